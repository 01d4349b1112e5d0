//! LTL synthesis in the page: [`LtlSession`] compiles a G4LTL or TLSF text, decides it
//! (Cheng et al. 2014), draws the controller or the environment's counter-strategy as a Mealy
//! machine, suggests assumptions for an unrealizable specification and generates the controller
//! as a function block for every PLC target.

use super::{diagnostics_error, to_js, unit_code, Progress, UnitCodeOptions};
use crate::diag::Diagnostic;
use crate::ltl::{self, Config, Format, Outcome, Spec, Stop, SuggestConfig, Suggestions, Synthesis, Verdict};
use crate::plc;
use serde::{Deserialize, Serialize};
use wasm_bindgen::prelude::*;

/// The format of a document kind: `tlsf`, else G4LTL's lines.
pub(crate) fn format(kind: &str) -> Format {
    if kind == "tlsf" {
        Format::Tlsf
    } else {
        Format::G4ltl
    }
}

/// Options of [`LtlSession::solve`]; every field is optional.
#[derive(Deserialize, Default)]
#[serde(rename_all = "camelCase", default)]
struct LtlOptions {
    max_k: Option<u32>,
    max_states: Option<usize>,
    max_work: Option<u64>,
    /// `explicit` (the default), `antichain`, `symbolic`, `bdd` or `gr1` (`ltl::Solver::named`).
    solver: Option<String>,
    /// Solve the whole specification at once (default: groups of guarantees first).
    monolithic: bool,
    /// With the `gr1` solver: build the controller as a circuit, and its code from it.
    circuit: bool,
    /// Decide the Boolean abstraction only (no refinement from counter-strategies).
    no_refine: bool,
    /// After an unrealizable verdict, search assumptions that make it realizable.
    suggest: bool,
    /// With `suggest`: at most this many assumptions in one suggestion (default 3).
    suggest_max: Option<usize>,
    /// Milliseconds between two progress calls (default 50).
    progress_ms: Option<f64>,
}

/// One assumption suggestion: the assumptions to add (in the specification's notation) and the
/// controller they allow.
#[derive(Serialize)]
struct SuggestionView {
    assumptions: Vec<String>,
    template: String,
    k: u32,
    states: usize,
    rows: usize,
    machine_text: String,
}

#[derive(Serialize)]
struct SuggestionsView {
    found: Vec<SuggestionView>,
    /// The longest play the counter-strategy forces, in words.
    play: Option<String>,
    candidates: usize,
    tried: usize,
    /// When nothing was found: why the search stopped.
    limit: Option<String>,
}

/// A group of guarantees with its own outputs, solved alone (compositional synthesis).
#[derive(Serialize)]
struct GroupView {
    /// Guarantee numbers, from 1 in the order of the specification.
    guarantees: Vec<usize>,
    outputs: Vec<String>,
    k: u32,
    states: usize,
    verdict: Verdict,
}

#[derive(Serialize)]
struct LtlSummary {
    /// `realizable`, `unrealizable`, `unknown` (no player won up to the bound), or how the run
    /// stopped before deciding: `budget_exceeded` or `cancelled` (`search::Stop::outcome_name`).
    verdict: &'static str,
    /// Present when a budget or the caller stopped the run: the shared `search::Stop`.
    stop: Option<Stop>,
    /// The solver that decided it (`explicit`, `antichain`, `symbolic`, `bdd`).
    solver: &'static str,
    /// `realizable at k = 1: a controller of 2 states, 3 rows`.
    summary: String,
    /// What the page shows of the specification as decided (with what refinement learned).
    report: ReportView,
    /// The controller (realizable) or the environment's counter-strategy (unrealizable) as a
    /// Mealy-machine drawing, and as text (one line per row).
    machine_dot: Option<String>,
    machine_text: Option<String>,
    /// The counter-strategy unfolded as a tree (a plain sequence of inputs reads as a lasso).
    counter_tree: Option<String>,
    /// The controller as a circuit (`gr1` solver): its latches, then per goal the outputs.
    circuit_text: Option<String>,
    groups: Vec<GroupView>,
    suggestions: Option<SuggestionsView>,
    /// Why suggestions stopped early (a budget), if they did.
    suggest_stopped: Option<String>,
    ms: f64,
}

/// The specification as decided: the LTL text, the signals, the turn order, and the
/// assumptions refinement learned (`{ formula, reason }`). Typed rather than `report_json`'s
/// `serde_json::Value`, which would put a JSON tree library into the page's wasm.
#[derive(Serialize, Default)]
struct ReportView {
    ltl: String,
    inputs: Vec<String>,
    outputs: Vec<String>,
    semantics: Option<&'static str>,
    learned: Vec<LearnedView>,
    limit: Option<String>,
}

#[derive(Serialize)]
struct LearnedView {
    formula: String,
    reason: String,
}

#[derive(Serialize)]
struct Signals {
    inputs: Vec<String>,
    outputs: Vec<String>,
}

/// A checked LTL specification and, once decided, the outcome.
#[wasm_bindgen]
pub struct LtlSession {
    source: String,
    spec: Spec,
    warnings: Vec<Diagnostic>,
    outcome: Option<Synthesis>,
    /// Whether `solve` ran (an outcome-less run was stopped by a budget).
    solved: bool,
}

#[wasm_bindgen]
impl LtlSession {
    /// Compiles `source` of `kind` (`ltl` for G4LTL's lines, `tlsf`); throws
    /// `{ diagnostics: Diagnostic[] }` when it has errors.
    #[wasm_bindgen(constructor)]
    pub fn new(source: &str, kind: &str) -> Result<LtlSession, JsValue> {
        match ltl::compile(source, format(kind), &[]) {
            Ok((spec, warnings)) => {
                Ok(LtlSession { source: source.to_string(), spec, warnings, outcome: None, solved: false })
            }
            Err(errors) => Err(diagnostics_error(&errors)),
        }
    }

    /// The warnings of the compilation: `Diagnostic[]`.
    pub fn warnings(&self) -> Result<JsValue, JsValue> {
        to_js(&self.warnings)
    }

    /// The inputs and outputs: `{ inputs: string[], outputs: string[] }`.
    pub fn signals(&self) -> Result<JsValue, JsValue> {
        let names =
            |ids: Vec<ltl::SignalId>| ids.into_iter().map(|s| self.spec.name(s).to_string()).collect::<Vec<_>>();
        to_js(&Signals { inputs: names(self.spec.inputs()), outputs: names(self.spec.outputs()) })
    }

    /// Decides the specification. `options`: `{ maxK?, maxStates?, maxWork?, solver?,
    /// monolithic?, circuit?, noRefine?, suggest?, suggestMax?, progressMs? }`; `progress(value,
    /// elapsedMs)` is called with `ltl::Progress`, `{ k, positions, nodes, work }`, and its `false` cancels. A run that
    /// a budget or the callback stops has the verdict `budget_exceeded` or `cancelled` and its
    /// `stop`, as the other engines' sessions.
    pub fn solve(&mut self, options: JsValue, progress: Option<js_sys::Function>) -> Result<JsValue, JsValue> {
        let opts: LtlOptions = super::options(options)?;
        let defaults = Config::default();
        let solver = match opts.solver.as_deref() {
            None => ltl::Solver::default(),
            Some(name) => ltl::Solver::named(name).ok_or_else(|| {
                let names: Vec<&str> = ltl::Solver::ALL.iter().map(|s| s.name()).collect();
                JsValue::from_str(&format!("unknown solver `{name}` ({})", names.join(", ")))
            })?,
        };
        let cfg = Config::default()
            .max_k(opts.max_k.unwrap_or(defaults.max_k))
            .max_states(opts.max_states.unwrap_or(defaults.max_states))
            .max_work(opts.max_work.unwrap_or(defaults.max_work))
            .solver(solver)
            .compositional(!opts.monolithic)
            .refine(!opts.no_refine)
            .circuit(opts.circuit);
        let mut progress = Progress::new(progress, opts.progress_ms);
        let started = super::now_ms();
        let mut report = |p: &ltl::Progress| progress.report(|| *p);
        let run = ltl::synthesize(&self.spec, &cfg, &mut report);
        let verdict = run.outcome_name();
        let outcome = match run {
            Ok(outcome) => outcome,
            Err(stop) => {
                // No verdict and no machine: the budget or the caller ended the run first.
                progress.finish()?;
                self.outcome = None;
                self.solved = true;
                return to_js(&LtlSummary {
                    verdict,
                    solver: solver.name(),
                    summary: format!("no verdict: {stop}"),
                    report: ReportView { limit: Some(stop.to_string()), ..ReportView::default() },
                    stop: Some(stop),
                    machine_dot: None,
                    machine_text: None,
                    counter_tree: None,
                    circuit_text: None,
                    groups: Vec::new(),
                    suggestions: None,
                    suggest_stopped: None,
                    ms: progress_ms(started),
                });
            }
        };
        let (suggestions, suggest_stopped) = if opts.suggest && outcome.verdict == Verdict::Unrealizable {
            let scfg = SuggestConfig {
                max_assumptions: opts.suggest_max.unwrap_or(3).clamp(1, 10),
                ..SuggestConfig::default()
            };
            let mut report = |p: &ltl::Progress| progress.report(|| *p);
            match ltl::suggest(&self.spec, &outcome, &cfg, &scfg, &mut report) {
                Ok(s) => (Some(self.suggestions_view(&s)), None),
                Err(Stop::Cancelled) => {
                    progress.finish()?;
                    return Err(JsValue::from_str("cancelled"));
                }
                Err(Stop::Budget { message, .. }) => (None, Some(message)),
            }
        } else {
            (None, None)
        };
        let ms = progress_ms(started);
        progress.finish()?;
        let refined = ltl::refined(&self.spec, &outcome.refinement);
        let machine = outcome.controller.as_ref().or(outcome.counter_strategy.as_ref());
        let summary = LtlSummary {
            verdict,
            stop: None,
            solver: solver.name(),
            summary: ltl::summary(&outcome),
            report: self.report_view(&refined, &outcome),
            machine_dot: machine.map(|m| ltl::machine_dot(&refined, m)),
            machine_text: machine.map(|m| ltl::render_machine(&refined, m)),
            counter_tree: outcome.counter_strategy.as_ref().map(|m| ltl::render_tree(&refined, m)),
            circuit_text: outcome.circuit.as_ref().map(|c| c.render(&refined)),
            groups: if outcome.groups.len() > 1 {
                outcome
                    .groups
                    .iter()
                    .map(|g| GroupView {
                        guarantees: g.guarantees.iter().map(|i| i + 1).collect(),
                        outputs: g.outputs.iter().map(|&s| self.spec.name(s).to_string()).collect(),
                        k: g.k,
                        states: g.controller.as_ref().map_or(0, |m| m.states.len()),
                        verdict: g.verdict,
                    })
                    .collect()
            } else {
                Vec::new()
            },
            suggestions,
            suggest_stopped,
            ms,
        };
        self.outcome = Some(outcome);
        self.solved = true;
        to_js(&summary)
    }

    /// The controller as a function block for `target`, named `name` (default `FB_` and the
    /// TLSF title, or `FB_Controller`): `{ target, extension, files, io, io_csv }`, or `null`
    /// when there is no controller. Throws `{ diagnostics }` when the specification does not
    /// fit the target.
    pub fn code(&self, target: &str, name: &str, options: JsValue) -> Result<JsValue, JsValue> {
        if !self.solved {
            return Err(JsValue::from_str("not solved yet: call solve() first"));
        }
        let Some(outcome) = &self.outcome else { return Ok(JsValue::NULL) };
        let opts: UnitCodeOptions = super::options(options)?;
        let lower = plc::lower::ltl::LowerOptions { name: (!name.is_empty()).then(|| name.to_string()) };
        let Some(unit) = plc::lower::ltl::lower_outcome(&self.source, &self.spec, outcome, &lower) else {
            return Ok(JsValue::NULL);
        };
        let unit = unit.map_err(|diagnostics| diagnostics_error(&diagnostics))?;
        let plc_options =
            plc::Options { created_unix: opts.created_unix.unwrap_or(0.0).max(0.0) as u64, ..plc::Options::default() };
        to_js(&unit_code(&unit, target, &plc_options)?)
    }
}

/// Milliseconds since `started` on the page's clock.
fn progress_ms(started: f64) -> f64 {
    super::now_ms() - started
}

impl LtlSession {
    /// What the summary shows of `refined`, the specification with what refinement learned.
    fn report_view(&self, refined: &Spec, outcome: &Synthesis) -> ReportView {
        let names = |ids: Vec<ltl::SignalId>| ids.into_iter().map(|s| refined.name(s).to_string()).collect();
        ReportView {
            ltl: refined.formula_text(),
            inputs: names(refined.inputs()),
            outputs: names(refined.outputs()),
            semantics: Some(match refined.semantics {
                ltl::Semantics::Mealy => "mealy",
                ltl::Semantics::Moore => "moore",
            }),
            learned: outcome
                .refinement
                .learned
                .iter()
                .map(|l| LearnedView { formula: l.formula.clone(), reason: l.reason.clone() })
                .collect(),
            limit: outcome.limit.clone(),
        }
    }

    fn suggestions_view(&self, s: &Suggestions) -> SuggestionsView {
        SuggestionsView {
            found: s
                .found
                .iter()
                .map(|f| {
                    let m = f.controller();
                    SuggestionView {
                        assumptions: f.texts(),
                        template: f.templates.iter().map(|t| t.pattern()).collect::<Vec<_>>().join(" + "),
                        k: f.outcome.k,
                        states: m.states.len(),
                        rows: m.rows(),
                        machine_text: ltl::render_machine(&f.spec, m),
                    }
                })
                .collect(),
            play: s.play.as_ref().map(|p| p.describe(&self.spec)),
            candidates: s.candidates,
            tried: s.tried,
            limit: s.limit.clone(),
        }
    }
}
