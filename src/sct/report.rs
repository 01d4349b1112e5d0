//! Synthesis of every specification of a loaded project, with the per-supervisor report
//! (states, transitions, prohibitions, enforced events, time) and its JSON form.
//!
//! Problems found during synthesis become located diagnostics: conflicting conditional
//! transitions (6.4.4) with both locations, cycles of enforced transitions (5.5.5), and a warning
//! when one supervisor enforces an event another one prohibits (6.4.2).

use super::check::Loaded;
use super::model::{self, Budget, Config, EventId, Knowledge, Method, Progress, Stop, SynthError};
use crate::diag::{Diagnostic, Diagnostics, Span};
use crate::search::{OnProgress, Outcome};
use serde::Serialize;

/// One supervisor transition in the JSON form.
#[derive(Clone, Debug, Serialize)]
pub struct JsonTransition {
    pub event: String,
    pub target: u32,
}

/// One supervisor state in the JSON form.
#[derive(Clone, Debug, Serialize)]
pub struct JsonState {
    pub label: String,
    pub transitions: Vec<JsonTransition>,
    pub prohibited: Vec<String>,
    pub enforced: Option<String>,
}

/// The report for one specification's supervisor.
#[derive(Clone, Debug, Serialize)]
pub struct SupervisorReport {
    pub name: String,
    pub realizable: bool,
    pub states: usize,
    pub transitions: usize,
    pub prohibitions: usize,
    pub prohibited_events: Vec<String>,
    pub enforced_events: Vec<String>,
    pub plants_used: Vec<String>,
    pub millis: f64,
    pub initial: Option<u32>,
    pub automaton: Vec<JsonState>,
    /// The supervisor itself, for callers that continue working with it.
    #[serde(skip)]
    pub supervisor: model::Supervisor,
}

/// What synthesis decided of a project. A run that a budget or the caller stopped has no
/// verdict: its [`Synthesis::outcome`] is the [`Stop`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Verdict {
    /// Every specification has a supervisor with a non-empty behaviour.
    Realizable,
    /// Some specification's supervisor is empty: its initial state is lost.
    Unrealizable,
    /// Synthesis found errors in the project (conflicts, enforcement cycles).
    Error,
}

crate::search::decision!(Verdict { Realizable => "realizable", Unrealizable => "unrealizable", Error => "error" });

/// A run of [`synthesize`]: the verdict (or the stop), a report per specification synthesised
/// (a stopped run keeps those finished before it), and the diagnostics synthesis found.
pub struct Synthesis {
    pub outcome: Result<Verdict, Stop>,
    pub reports: Vec<SupervisorReport>,
    /// Conflicts and enforcement cycles (errors), unrealizable specifications and supervisors
    /// that disagree (warnings), and where a stop ended the run (an error that is not an input
    /// error).
    pub diagnostics: Vec<Diagnostic>,
}

impl Outcome for Synthesis {
    type Verdict = Verdict;

    fn outcome(&self) -> Result<Verdict, &Stop> {
        self.outcome.as_ref().copied()
    }
}

/// Synthesises one supervisor per specification. Timing uses `now` (milliseconds) so that
/// the engine stays free of clocks on targets without one; pass `None` to skip timing.
/// All specifications share one budget of `cfg.max_states` product states; once it is spent,
/// the remaining specifications get an error diagnostic instead of a report. `progress` is
/// called every few thousand product states; its `false` cancels the run.
pub fn synthesize(
    src: &str,
    loaded: &Loaded,
    cfg: &Config,
    now: Option<&dyn Fn() -> f64>,
    progress: &mut OnProgress<'_, Progress>,
) -> Synthesis {
    synthesize_within(src, loaded, cfg, now, &mut Budget::new(cfg.max_states, progress))
}

/// [`synthesize`] drawing on the run's `budget`, which the specification products written in
/// the file drew on already ([`super::compile_within`]); `cfg.max_states` is not consulted.
pub fn synthesize_within(
    src: &str,
    loaded: &Loaded,
    cfg: &Config,
    now: Option<&dyn Fn() -> f64>,
    budget: &mut Budget,
) -> Synthesis {
    let mut stop = None;
    let mut diags = Diagnostics::new(src);
    let p = &loaded.project;
    let knowledge = Knowledge::new(p);
    let name = |e: EventId| p.event_name(e).to_string();
    let mut out = Vec::new();
    // The specification of each report (a specification with an error has none).
    let mut spec_of: Vec<usize> = Vec::new();
    for (i, spec) in p.specs.iter().enumerate() {
        let t0 = now.map(|f| f());
        let sup = match model::synthesize_known(p, &knowledge, i, cfg, budget) {
            Ok(s) => s,
            Err(error @ SynthError::BudgetExceeded { max_states }) => {
                stop = error.stop();
                let rest: Vec<&str> = p.specs[i + 1..].iter().map(|s| s.name.as_str()).collect();
                let d = diags.error(
                    loaded.spec_spans[i],
                    format!("synthesis stopped at `{}`: more than {max_states} product states built", spec.name),
                );
                match rest.len() {
                    0 => {}
                    1..=5 => {
                        d.with_note(format!("not synthesised either: {}", rest.join(", ")));
                    }
                    n => {
                        d.with_note(format!("not synthesised either: {} and {} more", rest[..4].join(", "), n - 4));
                    }
                }
                d.with_note(if cfg.method == Method::Monolithic {
                    "incremental synthesis applies only the plants it needs; or raise the state budget"
                } else {
                    "raise the state budget to synthesise it"
                });
                break;
            }
            Err(SynthError::Cancelled) => {
                stop = SynthError::Cancelled.stop();
                diags.error(loaded.spec_spans[i], format!("synthesis cancelled while synthesising `{}`", spec.name));
                break;
            }
            Err(SynthError::Conflict(c)) => {
                let spans: Vec<Span> =
                    c.origins.iter().filter_map(|&o| loaded.origins.get(o as usize).copied()).collect();
                let at = spans.first().copied().unwrap_or(loaded.spec_spans[i]);
                let locs: Vec<String> = spans
                    .iter()
                    .skip(1)
                    .map(|s| {
                        let (l, c) = diags.line_col(s.start as usize);
                        format!("the other transition is at {l}:{c}")
                    })
                    .collect();
                let d = diags.error(
                    at,
                    format!(
                        "two transitions on `{}` can both be taken in state {} (while synthesising `{}`)",
                        name(c.event),
                        c.state,
                        spec.name
                    ),
                );
                for l in locs {
                    d.with_note(l);
                }
                d.with_note("make the conditions mutually exclusive");
                continue;
            }
        };
        let millis = match (t0, now) {
            (Some(a), Some(f)) => f() - a,
            _ => 0.0,
        };
        if let Some(cycle) = sup.enforcement_cycle() {
            let mut spans: Vec<Span> = cycle
                .iter()
                .flat_map(|&s| sup.states[s as usize].enforced_origin.iter().copied())
                .filter_map(|o| loaded.origins.get(o as usize).copied())
                .collect();
            crate::sort::sort_by_key(&mut spans, |s| s.start);
            spans.dedup();
            let at = spans.first().copied().unwrap_or(loaded.spec_spans[i]);
            let evs: Vec<String> = cycle.iter().filter_map(|&s| sup.states[s as usize].enforced).map(name).collect();
            let d = diags.error(
                at,
                format!(
                    "supervisor `{}` enforces a cycle of events ({}) that would never end",
                    spec.name,
                    evs.join(" -> ")
                ),
            );
            d.with_note(
                "enforced events are executed in the same PLC cycle; break the cycle in the plant models (5.5.5)",
            );
        }
        let automaton = sup
            .states
            .iter()
            .map(|s| JsonState {
                label: s.label.clone(),
                transitions: s.transitions.iter().map(|&(e, t)| JsonTransition { event: name(e), target: t }).collect(),
                prohibited: s.prohibited.iter().map(|&e| name(e)).collect(),
                enforced: s.enforced.map(name),
            })
            .collect();
        spec_of.push(i);
        out.push(SupervisorReport {
            name: spec.name.clone(),
            realizable: sup.realizable(),
            states: sup.states.len(),
            transitions: sup.num_transitions(),
            prohibitions: sup.num_prohibitions(),
            prohibited_events: sup.prohibited_events().into_iter().map(name).collect(),
            enforced_events: sup.enforced_events().into_iter().map(name).collect(),
            plants_used: sup.plants_used.clone(),
            millis,
            initial: sup.init,
            automaton,
            supervisor: sup,
        });
    }
    // 6.4.2: supervisors do not synchronise on enforced events. Indexed by event, so that many
    // supervisors are not compared pairwise.
    let mut prohibiting: hashbrown::HashMap<String, Vec<usize>> = hashbrown::HashMap::new();
    for (j, b) in out.iter().enumerate() {
        for e in &b.prohibited_events {
            prohibiting.entry(e.clone()).or_default().push(j);
        }
    }
    for (i, a) in out.iter().enumerate() {
        for e in &a.enforced_events {
            for &j in prohibiting.get(e).into_iter().flatten() {
                let b = &out[j];
                if i != j {
                    let at = loaded.spec_spans[spec_of[j]];
                    diags
                        .warning(at, format!("`{}` prohibits `{e}`, which supervisor `{}` enforces", b.name, a.name))
                        .with_note("compose the two specifications into one to resolve the conflict (6.4.2)");
                }
            }
        }
    }
    for (r, &k) in out.iter().zip(&spec_of) {
        if !r.realizable {
            diags.warning(
                loaded.spec_spans[k],
                format!(
                    "specification `{}` is unrealizable: no safe supervisor exists with the given plant models",
                    r.name
                ),
            );
        }
    }
    // A stop decides first (its own error diagnostic is not an input error), then any error,
    // then whether every supervisor is realizable.
    let outcome = match stop {
        Some(stop) => Err(stop),
        None if diags.has_errors() => Ok(Verdict::Error),
        None if out.iter().all(|r| r.realizable) => Ok(Verdict::Realizable),
        None => Ok(Verdict::Unrealizable),
    };
    Synthesis { outcome, reports: out, diagnostics: diags.items }
}
