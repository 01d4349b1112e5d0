//! Synthesis of every specification of a loaded project, with the per-supervisor report
//! (states, transitions, prohibitions, enforced events, time) and its JSON form.
//!
//! Problems found during synthesis become located diagnostics: conflicting conditional
//! transitions (6.4.4) with both locations, cycles of enforced transitions (5.5.5), and a warning
//! when one supervisor enforces an event another one prohibits (6.4.2).

use super::check::Loaded;
use super::model::{self, Budget, Config, EventId, Knowledge, Method, Stop, SynthError};
use crate::diag::{Diagnostic, Diagnostics, Span};
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

/// The outcome of synthesising a project, decided here once for the CLI and the page.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Verdict {
    /// Every specification has a supervisor with a non-empty behaviour.
    Realizable,
    /// Some specification's supervisor is empty: its initial state is lost.
    Unrealizable,
    /// The state budget stopped the run before every specification was synthesised.
    BudgetExceeded,
    /// The progress callback cancelled the run.
    Cancelled,
    /// Synthesis found errors in the project (conflicts, enforcement cycles).
    Error,
}

impl Verdict {
    /// The verdict of a run of [`synthesize_all_within`] from what it returned: a stop decides
    /// first (its own error diagnostic is not an input error), then any error, then whether
    /// every supervisor is realizable.
    pub fn of(reports: &[SupervisorReport], diagnostics: &[Diagnostic], stop: Option<&Stop>) -> Verdict {
        match stop {
            Some(Stop::Cancelled) => Verdict::Cancelled,
            Some(Stop::Budget { .. }) => Verdict::BudgetExceeded,
            None if diagnostics.iter().any(Diagnostic::is_error) => Verdict::Error,
            None if reports.iter().all(|r| r.realizable) => Verdict::Realizable,
            None => Verdict::Unrealizable,
        }
    }
}

/// Synthesises one supervisor per specification. Timing uses `now` (milliseconds) so that
/// the engine stays free of clocks on targets without one; pass `None` to skip timing.
/// All specifications share one budget of `cfg.max_states` product states; once it is spent,
/// the remaining specifications get an error diagnostic instead of a report.
pub fn synthesize_all(
    src: &str,
    loaded: &Loaded,
    cfg: &Config,
    now: Option<&dyn Fn() -> f64>,
) -> (Vec<SupervisorReport>, Vec<Diagnostic>) {
    synthesize_all_with_progress(src, loaded, cfg, now, &mut |_| true)
}

/// [`synthesize_all`] with a progress callback, called every few thousand product states
/// with the number built so far; returning `false` cancels the run (the reports finished so
/// far are returned, with an error diagnostic).
pub fn synthesize_all_with_progress(
    src: &str,
    loaded: &Loaded,
    cfg: &Config,
    now: Option<&dyn Fn() -> f64>,
    progress: &mut dyn FnMut(usize) -> bool,
) -> (Vec<SupervisorReport>, Vec<Diagnostic>) {
    let (reports, diagnostics, _) =
        synthesize_all_within(src, loaded, cfg, now, &mut Budget::new(cfg.max_states, progress));
    (reports, diagnostics)
}

/// [`synthesize_all`] drawing on the run's `budget` (which the specification products of the
/// run may have drawn on already; `cfg.max_states` is not consulted). The third value is set
/// when the budget or a cancellation stopped the run: its error diagnostic is not an input
/// error.
pub fn synthesize_all_within(
    src: &str,
    loaded: &Loaded,
    cfg: &Config,
    now: Option<&dyn Fn() -> f64>,
    budget: &mut Budget,
) -> (Vec<SupervisorReport>, Vec<Diagnostic>, Option<Stop>) {
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
            spans.sort_by_key(|s| s.start);
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
    (out, diags.items, stop)
}
