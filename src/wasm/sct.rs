//! Supervisory control in the page: [`SctSession`] compiles a `.sct` project, draws its plant
//! models and specifications, synthesises the supervisors (Göbe 2019) and generates the runtime
//! framework for every PLC target.

use super::{diagnostics_error, to_js, unit_code, Progress, UnitCodeOptions};
use crate::diag::Diagnostic;
use crate::plc;
use crate::sct::export::{self, module_of};
use crate::sct::model::{Budget, Config, Method, Stop, DEFAULT_MAX_STATES};
use crate::sct::{self, compile_within, synthesize_within, Loaded, Outcome, SupervisorReport, Synthesis};
use serde::{Deserialize, Serialize};
use std::cell::OnceCell;
use wasm_bindgen::prelude::*;

/// Options of [`SctSession::new`] and [`SctSession::solve`]; every field is optional.
#[derive(Deserialize, Default)]
#[serde(rename_all = "camelCase", default)]
struct SctOptions {
    /// Product states one run may build (specification products and synthesis together).
    max_states: Option<usize>,
    /// `incremental` (the default) or `monolithic`.
    method: Option<String>,
    /// Use enforceable events to preempt uncontrollable ones (default true).
    preempt: Option<bool>,
    /// Minimise the supervisors (default true).
    minimize: Option<bool>,
    /// Compose all specifications into one supervisor `Composed` (5.8.5).
    compose: bool,
    /// Milliseconds between two progress calls (default 50).
    progress_ms: Option<f64>,
}

/// One supervisor of the synthesis report (its drawing comes from `supervisors()`).
#[derive(Serialize)]
struct SupervisorSummary<'a> {
    name: &'a str,
    module: &'a str,
    realizable: bool,
    states: usize,
    transitions: usize,
    prohibitions: usize,
    prohibited_events: &'a [String],
    enforced_events: &'a [String],
    plants_used: &'a [String],
    millis: f64,
}

#[derive(Serialize)]
struct SctSummary<'a> {
    method: &'static str,
    supervisors: Vec<SupervisorSummary<'a>>,
    /// Errors and warnings of synthesis (conflicts of 6.4.4, enforcement cycles, the warning of
    /// 6.4.2 when one supervisor enforces what another prohibits), located in the source.
    diagnostics: &'a [Diagnostic],
    /// `realizable`, `unrealizable` or `error` (`sct::Verdict`), or how the run stopped before
    /// deciding: `budget_exceeded` or `cancelled` (`search::Outcome::outcome_name`).
    verdict: &'static str,
    /// Why the run stopped before every specification was synthesised (`search::Stop`).
    stop: Option<&'a Stop>,
    /// Product states built.
    states_built: usize,
    ms: f64,
}

/// Progress of a synthesis: product states built so far.
#[derive(Serialize)]
struct SctProgress {
    built: usize,
}

/// A checked `.sct` project and, once synthesised, its supervisors.
#[wasm_bindgen]
pub struct SctSession {
    source: String,
    loaded: Loaded,
    warnings: Vec<Diagnostic>,
    reports: Option<Vec<SupervisorReport>>,
    /// The project with its specifications composed into one, when the last synthesis composed.
    composed: Option<Loaded>,
    /// Whether the last synthesis ran to its end without an input error: only then is there a
    /// framework to generate.
    complete: bool,
    /// The runtime framework with the default names and its map, for the cycle simulator: built
    /// on its first cycle after a solve.
    framework: OnceCell<Result<(plc::model::unit::Unit, plc::lower::sct::FrameworkMap), Vec<Diagnostic>>>,
}

/// The views of a cycle simulation: before the first cycle, then one per cycle.
#[derive(Serialize)]
struct CyclesView {
    initial: plc::lower::sct::framework_sim::CycleView,
    cycles: Vec<plc::lower::sct::framework_sim::CycleView>,
}

#[wasm_bindgen]
impl SctSession {
    /// Compiles `source`; throws `{ diagnostics: Diagnostic[] }` when it has errors.
    /// `options.maxStates` bounds the specification products the file writes.
    #[wasm_bindgen(constructor)]
    pub fn new(source: &str, options: JsValue) -> Result<SctSession, JsValue> {
        let opts: SctOptions = super::options(options)?;
        let mut go_on = |_: &_| true;
        let mut budget = Budget::new(opts.max_states.unwrap_or(DEFAULT_MAX_STATES), &mut go_on);
        let (loaded, diagnostics, _) = compile_within(source, &mut budget);
        match loaded {
            Some(loaded) if !diagnostics.iter().any(Diagnostic::is_error) => Ok(SctSession {
                source: source.to_string(),
                loaded,
                warnings: diagnostics,
                reports: None,
                composed: None,
                complete: false,
                framework: OnceCell::new(),
            }),
            _ => Err(diagnostics_error(&diagnostics)),
        }
    }

    /// The warnings of the compilation: `Diagnostic[]`.
    pub fn warnings(&self) -> Result<JsValue, JsValue> {
        to_js(&self.warnings)
    }

    /// The plant models and specifications as drawings, plants first:
    /// `{ name, module, kind, states, transitions, dot }[]`.
    pub fn models(&self) -> Result<JsValue, JsValue> {
        to_js(&export::models(&self.loaded.project))
    }

    /// Every event with its kind: `{ name, kind }[]`.
    pub fn events(&self) -> Result<JsValue, JsValue> {
        to_js(&self.loaded.project.events)
    }

    /// Synthesises one supervisor per specification. `options`: `{ maxStates?, method?,
    /// preempt?, minimize?, compose?, progressMs? }`; `progress(value, elapsedMs)` is called
    /// with `{ built }` while product states are built, and its `false` cancels.
    pub fn solve(&mut self, options: JsValue, progress: Option<js_sys::Function>) -> Result<JsValue, JsValue> {
        let opts: SctOptions = super::options(options)?;
        let method = match opts.method.as_deref() {
            None | Some("incremental") => Method::Incremental,
            Some("monolithic") => Method::Monolithic,
            Some(other) => {
                return Err(JsValue::from_str(&format!("unknown method `{other}` (incremental, monolithic)")))
            }
        };
        let cfg = Config::default()
            .method(method)
            .preempt(opts.preempt.unwrap_or(true))
            .minimize(opts.minimize.unwrap_or(true))
            .max_states(opts.max_states.unwrap_or(DEFAULT_MAX_STATES));
        let mut progress = Progress::new(progress, opts.progress_ms);
        let started = progress.elapsed();
        let clock = super::now_ms;
        let (synthesis, built) = {
            let mut report = |p: &sct::Progress| progress.report(|| SctProgress { built: p.states });
            let mut budget = Budget::new(cfg.max_states, &mut report);
            self.composed = None;
            if opts.compose {
                match self.loaded.composed("Composed", &mut budget) {
                    Ok(l) => self.composed = Some(l),
                    Err((_, error)) => {
                        let message = match error.stop() {
                            Some(Stop::Cancelled) => "cancelled while composing the specifications".to_string(),
                            _ => format!(
                                "composing the specifications spent the state budget of {} states",
                                cfg.max_states
                            ),
                        };
                        return Err(JsValue::from_str(&message));
                    }
                }
            }
            let loaded = self.composed.as_ref().unwrap_or(&self.loaded);
            (synthesize_within(&self.source, loaded, &cfg, Some(&clock), &mut budget), budget.built())
        };
        let (verdict, stop) = (synthesis.outcome_name(), synthesis.stop().cloned());
        let Synthesis { reports, diagnostics, .. } = synthesis;
        let ms = progress.elapsed() - started;
        progress.finish()?;
        let input_errors = diagnostics.iter().filter(|d| d.is_error()).count() > usize::from(stop.is_some());
        self.complete = stop.is_none() && !input_errors;
        let summary = SctSummary {
            method: if method == Method::Monolithic { "monolithic" } else { "incremental" },
            supervisors: reports.iter().map(summary_of).collect(),
            verdict,
            diagnostics: &diagnostics,
            stop: stop.as_ref(),
            states_built: built,
            ms,
        };
        let value = to_js(&summary);
        self.reports = Some(reports);
        self.framework = OnceCell::new();
        value
    }

    /// The synthesised supervisors as drawings: `{ name, module, kind, states, transitions,
    /// dot }[]`.
    pub fn supervisors(&self) -> Result<JsValue, JsValue> {
        let reports = self.reports()?;
        let project = &self.composed.as_ref().unwrap_or(&self.loaded).project;
        to_js(&reports.iter().map(|r| export::supervisor(project, &r.supervisor)).collect::<Vec<_>>())
    }

    /// The runtime framework (Göbe 2019, 6.3) for `target`, its program's names prefixed with
    /// `name` (`SyRF`), calling the existing controller function block `controller`:
    /// `{ target, extension, files, io, io_csv }`, or `null` when synthesis did not complete.
    /// Throws `{ diagnostics }` when the project's fragments do not fit the target.
    pub fn code(&self, target: &str, name: &str, controller: &str, options: JsValue) -> Result<JsValue, JsValue> {
        let reports = self.reports()?;
        if !self.complete {
            return Ok(JsValue::NULL);
        }
        let opts: UnitCodeOptions = super::options(options)?;
        let supervisors: Vec<_> = reports.iter().map(|r| &r.supervisor).collect();
        let framework = plc::lower::sct::FrameworkOptions {
            name: if name.is_empty() { "SyRF".into() } else { name.into() },
            controller: if controller.is_empty() { "Controller".into() } else { controller.into() },
        };
        let loaded = self.composed.as_ref().unwrap_or(&self.loaded);
        let unit = plc::lower::sct::lower(&self.source, loaded, &supervisors, &framework)
            .map_err(|diagnostics| diagnostics_error(&diagnostics))?;
        let plc_options =
            plc::Options { created_unix: opts.created_unix.unwrap_or(0.0).max(0.0) as u64, ..plc::Options::default() };
        to_js(&unit_code(&unit, target, &plc_options)?)
    }
}

#[wasm_bindgen]
impl SctSession {
    /// The stepper: the closed loop of plants and supervisors after firing `trace` (event
    /// names) from the initial states: `{ plants, supervisors, events: { name, kind, status,
    /// by? }[], trace }`, `status` one of `enabled`, `impossible`, `disabled`, `unexpected`,
    /// `enforced`, `not_enforced`. Throws the reason when an event of the trace cannot happen.
    pub fn step(&self, trace: JsValue) -> Result<JsValue, JsValue> {
        let trace: Vec<String> = super::options(trace)?;
        let reports = self.reports()?;
        let project = &self.composed.as_ref().unwrap_or(&self.loaded).project;
        let sups: Vec<_> = reports.iter().map(|r| &r.supervisor).collect();
        let view = crate::sct::stepper::step(project, &sups, &trace).map_err(|e| JsValue::from_str(&e))?;
        to_js(&view)
    }

    /// The runtime-cycle simulator: the generated framework run from a cold start through
    /// `cycles` (`{ elapsed_ms, inputs: { SYMBOL: value }, controller: { SYMBOL: value } }[]`)
    /// in the reference interpreter of the code model: `{ initial, cycles }`, each a
    /// `{ cycle, time_ms, signals, events, supervisors, timers }`. `null` when synthesis did
    /// not complete; throws `{ diagnostics }` when the framework cannot be generated.
    pub fn cycles(&self, cycles: JsValue) -> Result<JsValue, JsValue> {
        let cycles: Vec<plc::lower::sct::framework_sim::CycleInput> = super::options(cycles)?;
        let reports = self.reports()?;
        if !self.complete {
            return Ok(JsValue::NULL);
        }
        let loaded = self.composed.as_ref().unwrap_or(&self.loaded);
        let sups: Vec<_> = reports.iter().map(|r| &r.supervisor).collect();
        let built = self.framework.get_or_init(|| {
            plc::lower::sct::lower_mapped(&self.source, loaded, &sups, &plc::lower::sct::FrameworkOptions::default())
        });
        let (unit, map) = built.as_ref().map_err(|diagnostics| diagnostics_error(diagnostics))?;
        let project = &loaded.project;
        let initial =
            plc::lower::sct::framework_sim::initial(unit, map, project, &sups).map_err(|e| JsValue::from_str(&e))?;
        let cycles = plc::lower::sct::framework_sim::run(unit, map, project, &sups, &cycles)
            .map_err(|e| JsValue::from_str(&e))?;
        to_js(&CyclesView { initial, cycles })
    }
}

impl SctSession {
    fn reports(&self) -> Result<&[SupervisorReport], JsValue> {
        self.reports.as_deref().ok_or_else(|| JsValue::from_str("not synthesised yet: call solve() first"))
    }
}

fn summary_of(r: &SupervisorReport) -> SupervisorSummary<'_> {
    SupervisorSummary {
        name: &r.name,
        module: module_of(&r.name),
        realizable: r.realizable,
        states: r.states,
        transitions: r.transitions,
        prohibitions: r.prohibitions,
        prohibited_events: &r.prohibited_events,
        enforced_events: &r.enforced_events,
        plants_used: &r.plants_used,
        millis: r.millis,
    }
}

/// Options of [`import_model`].
#[derive(Deserialize, Default)]
#[serde(rename_all = "camelCase", default)]
struct ImportOptions {
    /// Read every state as marked instead of refusing unmarked states (`.sct` has no marking).
    ignore_marking: bool,
    /// The states the files may declare in all (default 250 000, as `plcsynth import`).
    max_states: Option<usize>,
}

/// A diagnostic of one of the imported files.
#[derive(Serialize)]
struct FileDiagnostic<'a> {
    file: &'a str,
    #[serde(flatten)]
    diagnostic: &'a Diagnostic,
    /// As `plcsynth import` prints it: `file:line:column`, the message, the source line with a
    /// caret under the place, the notes.
    rendered: String,
}

/// What an import that failed throws.
#[derive(Serialize)]
struct ImportFailure<'a> {
    ok: bool,
    diagnostics: Vec<FileDiagnostic<'a>>,
    /// Some error is an unmarked state: `ignoreMarking` would import the files.
    unmarked: bool,
    /// The files declare more states than the budget.
    over_budget: bool,
}

#[derive(Serialize)]
struct Imported {
    /// The project's name: the first file's, with `.sct` for its extension.
    name: String,
    text: String,
}

/// Converts other tools' models into an editable `.sct` project, as `plcsynth import` does
/// (`sct::interchange::import`): `files` are `{ name, bytes: Uint8Array, kind?: "plant" | "spec" }`,
/// either one Supremica module (`.wmod`; UTF-8, or the `windows-1252` Supremica writes) or
/// libFAUDES generators (`.gen`, each a plant unless `kind` says `spec`). Answers `{ name, text }`;
/// throws `{ ok: false, diagnostics, unmarked, over_budget }` (each diagnostic with the `file`
/// it is located in and its `rendered` text) when a file does not read or a component does not map.
#[wasm_bindgen(js_name = importModel)]
pub fn import_model(files: js_sys::Array, options: JsValue) -> Result<JsValue, JsValue> {
    use crate::diag::{render_plain, Diagnostics, Span};
    use crate::sct::classic::wmod::{decode, ComponentKind};
    use crate::sct::interchange::{import, is_wmod, Import, ImportFile, ToSct};
    let options: ImportOptions = super::options(options)?;
    let field = |file: &JsValue, key: &str| js_sys::Reflect::get(file, &JsValue::from_str(key));
    let mut names = Vec::new();
    let mut bytes = Vec::new();
    let mut kinds = Vec::new();
    for file in files.iter() {
        let name = field(&file, "name")?.as_string().ok_or("importModel: every file needs a `name`")?;
        let data = field(&file, "bytes")?;
        if !data.is_instance_of::<js_sys::Uint8Array>() {
            return Err(JsValue::from_str(&format!("importModel: `{name}` needs its `bytes` as a Uint8Array")));
        }
        kinds.push(match field(&file, "kind")?.as_string().as_deref() {
            None | Some("plant") => ComponentKind::Plant,
            Some("spec") => ComponentKind::Spec,
            Some(other) => {
                return Err(JsValue::from_str(&format!("importModel: unknown kind `{other}` (plant, spec)")))
            }
        });
        bytes.push(js_sys::Uint8Array::new(&data).to_vec());
        names.push(name);
    }
    if names.is_empty() {
        return Err(JsValue::from_str("importModel: no file"));
    }
    let fail = |errors: Vec<(usize, Diagnostic)>, texts: &[&str], unmarked: bool, over_budget: bool| {
        let diagnostics = errors
            .iter()
            .map(|(i, d)| FileDiagnostic {
                file: &names[*i],
                diagnostic: d,
                rendered: render_plain(&names[*i], texts[*i], std::slice::from_ref(d)),
            })
            .collect();
        let failure = ImportFailure { ok: false, diagnostics, unmarked, over_budget };
        to_js(&failure).unwrap_or_else(|e| e)
    };
    // A file that is neither kind, or not text: said at its start.
    let mut texts = Vec::new();
    for (i, (name, data)) in names.iter().zip(&bytes).enumerate() {
        let lower = name.to_ascii_lowercase();
        let problem = if !is_wmod(name) && !lower.ends_with(".gen") {
            Some(format!("`{name}` is neither a Supremica module (`.wmod`) nor a libFAUDES generator (`.gen`)"))
        } else if decode(data).is_none() {
            Some(format!("`{name}` is not UTF-8 text (and declares no windows-1252 or ISO-8859-1 encoding)"))
        } else {
            None
        };
        if let Some(message) = problem {
            let mut d = Diagnostics::new("");
            let item = d.error(Span::new(0, 0), message).clone();
            return Err(fail(vec![(i, item)], &vec![""; names.len()], false, false));
        }
        texts.push(decode(data).unwrap_or_default().into_owned());
    }
    let texts: Vec<&str> = texts.iter().map(String::as_str).collect();
    let inputs: Vec<ImportFile> = names
        .iter()
        .zip(&texts)
        .zip(&kinds)
        .map(|((name, text), kind)| ImportFile { name, text, kind: *kind })
        .collect();
    let settings = Import {
        by: "the plcsynth playground",
        to_sct: ToSct { ignore_marking: options.ignore_marking, switch: "Ignore marking" },
        max_states: options.max_states.unwrap_or(DEFAULT_MAX_STATES),
    };
    match import(&inputs, &settings) {
        Ok(text) => {
            let stem = std::path::Path::new(&names[0]).file_stem().and_then(|s| s.to_str()).unwrap_or("imported");
            to_js(&Imported { name: format!("{stem}.sct"), text })
        }
        Err(errors) => {
            let unmarked = errors.iter().any(|e| e.unmarked);
            let over_budget = errors.iter().any(|e| e.over_budget);
            let list = errors.into_iter().map(|e| (e.file, e.diagnostic)).collect();
            Err(fail(list, &texts, unmarked, over_budget))
        }
    }
}
