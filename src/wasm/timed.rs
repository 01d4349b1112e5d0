//! The timed-game engine in the page: [`TimedSession`] compiles a `.tga` text, solves the game
//! and answers the state explorer's and the code pane's queries.

use super::{diagnostics_error, plc_target, to_js, FileView, GeneratedCode, IoRowView, Progress};
use crate::diag::Diagnostic;
use crate::plc::{self, Target};
use crate::search::Outcome;
use crate::timed::explain::{self as explain, dump, CounterPlay};
use crate::timed::export::{self, StateView};
use crate::timed::model::Game;
use crate::timed::program::simulate::{self, Choice, SimView, Simulation};
use crate::timed::program::{self, Program};
use crate::timed::solve::{Config, StateId, Stats, Stop, Verdict};
use crate::timed::{self, Synthesis};
use serde::{Deserialize, Serialize};
use std::cell::OnceCell;
use wasm_bindgen::prelude::*;

/// Options of [`TimedSession::solve`]; every field is optional.
#[derive(Deserialize, Default)]
#[serde(rename_all = "camelCase", default)]
struct JsSolveOptions {
    max_states: Option<usize>,
    max_memory_mib: Option<usize>,
    max_work: Option<u64>,
    progress_interval: Option<usize>,
    /// Milliseconds between two progress calls (default 50).
    progress_ms: Option<f64>,
    /// Explore the whole reachable game (the reference) instead of only the strategy.
    exhaustive: bool,
}

#[derive(Serialize)]
struct SolveSummary {
    /// `realizable`, `unrealizable`, `budget_exceeded` or `cancelled`
    /// (`search::Outcome::outcome_name`).
    verdict: &'static str,
    stats: Stats,
    /// Present when the search stopped before deciding: the shared `search::Stop`.
    stop: Option<Stop>,
    /// With a budget stop of the split: the node or plan step to blame.
    blame: Option<crate::diag::Span>,
    /// Present when the verdict is `unrealizable`.
    explanation_depth: Option<u32>,
    /// Present when the specification declares a scan time and is realizable: the verdict on
    /// a PLC with that cycle (`timed::synthesize_at_scan`).
    scan: Option<ScanSummary>,
}

#[derive(Serialize)]
struct ScanSummary {
    scan_ms: u64,
    /// `realizable` here means implementable at `scan_ms`.
    verdict: &'static str,
    stats: Stats,
    stop: Option<Stop>,
    /// Why no PLC with this scan can do it, as text (the scan game's counter-play).
    explanation_text: Option<String>,
    /// The scan times around the verdict (`timed::scan_bound`), once it is decided.
    bound: Option<timed::ScanBound>,
    /// The same in words, as the CLI's `solve` prints it.
    bound_text: Option<String>,
    /// Where the code comes from when implementable: the scan strategy (one decision per scan)
    /// or, where the PLC's inputs do not tell it enough, the zero-time strategy and why.
    code_from: Option<String>,
}

/// Runs of the real-time check of code at a declared scan time (each 2000 scans), as the CLI.
const CHECK_RUNS: u64 = 20;

/// What the real-time check of generated code found.
#[derive(Clone, Serialize)]
pub(crate) struct RealtimeView {
    scan_ms: u64,
    runs: u64,
    scans_per_run: u64,
    /// The failure ([`plc::lower::timed::realtime::RunReport::outcome`]: what and when) with its
    /// run and seed, or `null`; the failed run's trace apart.
    failure: Option<String>,
    /// Why the code can fail although the scan game is won ([`plc::lower::timed::Pacing::failure_reason`]).
    why: Option<&'static str>,
    trace: Vec<String>,
}

/// The simulator's script: how it started and every step since. The simulation is rebuilt from
/// it on every call (it is deterministic from its seed, and a step takes microseconds), so the
/// session keeps no borrowed state and stepping back is dropping the last step.
struct SimScript {
    seed: u64,
    /// Without the controller program: the user (or the replay) picks the requests too.
    free: bool,
    choices: Vec<Choice>,
    replay: Option<ReplayView>,
}

/// Steps kept at most (a step back per step).
const SIM_STEPS: usize = 20_000;

/// The counter-play a free simulation replays.
#[derive(Clone, Serialize)]
struct ReplayView {
    /// The symbolic line (`CounterPlay`).
    line: CounterPlay,
    /// Concrete steps it became.
    steps: usize,
    /// Why the line could not be followed to its end, if it could not.
    stopped: Option<String>,
}

/// What every simulator method returns.
#[derive(Serialize)]
struct SimState<'a> {
    #[serde(flatten)]
    view: SimView,
    /// Steps that `simBack` can take back.
    history: usize,
    seed: u64,
    replay: Option<&'a ReplayView>,
    /// The program's commands, as in `program()` (`simStart` and `simReplay` only; `null`
    /// without a program).
    listing: Option<Vec<String>>,
}

/// A compiled specification and, once solved, its synthesis.
#[wasm_bindgen]
pub struct TimedSession {
    source: String,
    game: Game,
    warnings: Vec<Diagnostic>,
    synthesis: Option<Synthesis>,
    /// Predecessors of every state, built on the first `neighbourhood` query after a solve.
    incoming: OnceCell<Vec<Vec<StateId>>>,
    /// The optimised controller program, built on the first `program`/`code` call after a solve.
    program: OnceCell<Option<Program>>,
    /// The strategy's choice in every state it reaches, built on first use after a solve.
    strategy: OnceCell<Option<Vec<export::StrategyChoice>>>,
    /// The declared scan time, when the last solve found the specification implementable there:
    /// `code` then runs the code against the plant in real time first.
    implementable_at: Option<u64>,
    /// The program of the scan strategy at that scan time, where there is one
    /// (`plc::lower::timed::scan_program`); the code follows it, one decision per scan.
    scan_program: Option<Program>,
    /// That check, once per semantics (IEC targets, STL), built on the first `code` call after
    /// a solve: the targets of one semantics run the same code.
    checked: [OnceCell<RealtimeView>; 2],
    /// The simulator, once started after a solve.
    sim: Option<SimScript>,
}

#[wasm_bindgen]
impl TimedSession {
    /// Compiles `source`; throws `{ diagnostics: Diagnostic[] }` when it has errors.
    #[wasm_bindgen(constructor)]
    pub fn new(source: &str) -> Result<TimedSession, JsValue> {
        match timed::compile(source) {
            Ok((game, warnings)) => Ok(TimedSession {
                source: source.to_string(),
                game,
                warnings,
                synthesis: None,
                incoming: OnceCell::new(),
                program: OnceCell::new(),
                strategy: OnceCell::new(),
                implementable_at: None,
                scan_program: None,
                checked: Default::default(),
                sim: None,
            }),
            Err(errors) => Err(diagnostics_error(&errors)),
        }
    }

    /// The warnings of the compilation: `Diagnostic[]`.
    pub fn warnings(&self) -> Result<JsValue, JsValue> {
        to_js(&self.warnings)
    }

    /// Plant units and plans: `AutomatonView[]`, each with `dot`, its drawing.
    pub fn automata(&self) -> Result<JsValue, JsValue> {
        /// A component with its drawing.
        #[derive(Serialize)]
        struct Drawn {
            #[serde(flatten)]
            view: export::AutomatonView,
            dot: String,
        }
        let drawn: Vec<Drawn> = export::automata(&self.game)
            .into_iter()
            .map(|view| {
                let dot = view.dot();
                Drawn { view, dot }
            })
            .collect();
        to_js(&drawn)
    }

    /// Solves the game. `options`: `{ maxStates?, maxMemoryMib?, maxWork?, progressInterval? }`;
    /// `progress`, if given, is called with `Stats` every `progressInterval` expansions (and
    /// during long work on one state), and a return value of `false` cancels the run. Returns
    /// `{ verdict, stats, stop, explanation_depth, scan }`.
    pub fn solve(&mut self, options: JsValue, progress: Option<js_sys::Function>) -> Result<JsValue, JsValue> {
        let opts: JsSolveOptions = super::options(options)?;
        let defaults = Config::default();
        let options = Config::default()
            .max_states(opts.max_states.unwrap_or(defaults.max_states))
            .max_bytes(opts.max_memory_mib.map_or(defaults.max_bytes, |mib| mib.saturating_mul(1 << 20)))
            .max_work(opts.max_work.unwrap_or(defaults.max_work))
            .progress_interval(opts.progress_interval.unwrap_or(defaults.progress_interval).max(1))
            .exhaustive(opts.exhaustive);
        let mut progress = Progress::new(progress, opts.progress_ms);
        let mut report = |stats: &Stats| progress.report(|| *stats);
        let synthesis = timed::synthesize(&self.game, &options, &mut report);
        let mut scan_program = None;
        let mut implementable_at = None;
        let scan = match self.game.scan_ms {
            // A callback error cancels the run, so a realizable verdict means none occurred.
            Some((ms, _)) if synthesis.solution.is_realizable() => {
                timed::synthesize_at_scan(&self.game, ms, &options, &mut report).ok().map(|r| {
                    let verdict = r.synthesis.verdict();
                    implementable_at = r.synthesis.solution.is_realizable().then_some(ms);
                    let code_from = (verdict == Some(Verdict::Realizable)).then(|| {
                        // The page's cancel button stops the extraction too.
                        let stats = r.synthesis.solution.stats;
                        match plc::lower::timed::scan_program(&self.game, &r, &mut |_| report(&stats)) {
                            Ok(p) => {
                                let text = format!("the scan strategy: {} nodes, one decision per scan", p.nodes.len());
                                scan_program = Some(p.program());
                                text
                            }
                            Err(why) => format!("the zero-time strategy, checked in real time: {why}"),
                        }
                    });
                    // How slow a PLC may be: the neighbouring scan times solved, as the CLI's
                    // `solve` prints them (each within the same budgets).
                    let bound = verdict.map(|verdict| {
                        timed::scan_bound(&self.game, ms, verdict == Verdict::Realizable, &options, &mut report)
                    });
                    ScanSummary {
                        scan_ms: ms,
                        verdict: r.synthesis.outcome_name(),
                        stats: r.synthesis.solution.stats,
                        stop: r.synthesis.solution.stop().cloned(),
                        explanation_text: r.synthesis.explanation.as_ref().map(|e| e.render()),
                        bound_text: bound.and_then(|b| b.text()),
                        bound,
                        code_from,
                    }
                })
            }
            _ => None,
        };
        progress.finish()?;
        let summary = SolveSummary {
            verdict: synthesis.outcome_name(),
            stats: synthesis.solution.stats,
            stop: synthesis.solution.stop().cloned(),
            blame: synthesis.solution.blame,
            explanation_depth: synthesis.explanation.as_ref().map(|e| e.depth),
            scan,
        };
        self.synthesis = Some(synthesis);
        self.incoming = OnceCell::new();
        self.program = OnceCell::new();
        self.strategy = OnceCell::new();
        self.checked = Default::default();
        self.sim = None;
        self.implementable_at = implementable_at;
        self.scan_program = scan_program;
        to_js(&summary)
    }

    fn synthesis(&self) -> Result<&Synthesis, JsValue> {
        self.synthesis.as_ref().ok_or_else(|| JsValue::from_str("not solved yet: call solve() first"))
    }

    /// The explored space, at most `limit` states breadth-first from the initial one: `SpaceView`.
    pub fn space(&self, limit: usize) -> Result<JsValue, JsValue> {
        let view = export::space(&self.game, self.synthesis()?, limit);
        to_js(&self.drawn(view, None)?)
    }

    /// Why the initial state is lost, as a tree: `Explanation | null`.
    pub fn explanation(&self) -> Result<JsValue, JsValue> {
        to_js(&self.synthesis()?.explanation)
    }

    /// The explanation as indented text, or `undefined` when there is none.
    #[wasm_bindgen(js_name = explanationText)]
    pub fn explanation_text(&self) -> Result<Option<String>, JsValue> {
        Ok(self.synthesis()?.explanation.as_ref().map(|e| e.render()))
    }

    /// The whole explored state space as text, one line per state and per edge.
    pub fn dump(&self) -> Result<String, JsValue> {
        let s = self.synthesis()?;
        Ok(dump(&self.game, &s.split, &s.solution.space))
    }

    /// Searches the states whose description contains every word of `query` (case-insensitive).
    /// `filter`: `all`, `winning` or `removed`. Returns `{ total, rows: StateRow[] }` with at
    /// most `limit` rows, in state order.
    pub fn states(&self, query: &str, filter: &str, limit: usize) -> Result<JsValue, JsValue> {
        to_js(&export::search_states(&self.game, self.synthesis()?, query, filter, limit))
    }

    /// The states within `k` steps of `state` (following edges both ways), at most `limit` of
    /// them, with the edges among them: a `SpaceView` whose `truncated` tells if `limit` cut it.
    /// (State ids cross to JavaScript as plain numbers.)
    pub fn neighbourhood(&self, state: u32, k: u32, limit: usize) -> Result<JsValue, JsValue> {
        let state = StateId::from_raw(state);
        let s = self.synthesis()?;
        let incoming = self.incoming.get_or_init(|| export::incoming(s));
        match export::neighbourhood(&self.game, s, incoming, state, k, limit) {
            Some(view) => to_js(&self.drawn(view, Some(state))?),
            None => Err(JsValue::from_str(&format!("no state s{state}"))),
        }
    }

    /// The controller program in the thesis's notation, or `undefined` when the game is not
    /// realizable (no controller exists, or the run stopped before deciding).
    pub fn program(&self) -> Result<Option<String>, JsValue> {
        Ok(self.controller()?.map(|p| p.render(&self.game)))
    }

    /// The controller as code for `target` (an id from `targets()`), the function block named
    /// after `name`, PLCopen's creation time `created_unix` (seconds since 1970, from the page's
    /// clock): `{ target, extension, files, io, io_csv, io_sdf, io_codesys, realtime }`, or `null` when the
    /// game is not realizable. At a declared scan time where the game is implementable the code is
    /// first run against the plant (`realtime`); if a run fails, `files` is empty. Throws `{ ok: false, diagnostics }` when a time constant does not fit
    /// the target.
    pub fn code(&self, target: &str, name: &str, created_unix: Option<f64>) -> Result<JsValue, JsValue> {
        let Some(zero_time) = self.controller()? else { return Ok(JsValue::NULL) };
        let (program, pacing) = match &self.scan_program {
            Some(p) => (p, plc::lower::timed::Pacing::ScanByScan),
            None => (zero_time, plc::lower::timed::Pacing::Chained),
        };
        let plc_target: Option<Target> = match target {
            "program" => None,
            t => Some(plc_target(t)?),
        };
        let options = plc::Options { created_unix: created_unix.unwrap_or(0.0).max(0.0) as u64, ..Default::default() };
        // The intermediate program is checked as ST; it needs the lowering only for the check.
        let lowered = if plc_target.is_some() || self.implementable_at.is_some() {
            let t = plc_target.unwrap_or(Target::St);
            match plc::lower::timed::build_paced(&self.game, program, pacing, t, name, &self.source, &options) {
                Ok(built) => Some(built),
                Err(errors) if plc_target.is_some() => return Err(diagnostics_error(&errors)),
                Err(errors) => {
                    // The intermediate program itself is still shown; say why it went unchecked.
                    let why = errors.first().map_or(String::new(), |d| d.message.clone());
                    web_sys::console::warn_1(&format!("the real-time check of the program was skipped: {why}").into());
                    None
                }
            }
        } else {
            None
        };
        let realtime = match (self.implementable_at, &lowered) {
            (Some(ms), Some((code, wiring))) => {
                // The STL code tests its thresholds at their S5TIME presets: checked apart.
                let cell = &self.checked[usize::from(plc_target == Some(Target::Stl))];
                Some(
                    cell.get_or_init(|| {
                        let config = plc::lower::timed::realtime::Config {
                            scan_us: ms.saturating_mul(1000),
                            ..Default::default()
                        };
                        let report = plc::lower::timed::realtime::check(&self.game, code, wiring, &config, CHECK_RUNS);
                        RealtimeView {
                            scan_ms: ms,
                            runs: report.runs,
                            scans_per_run: config.scans,
                            failure: report
                                .failure
                                .as_ref()
                                .map(|r| format!("{} (run {}, seed {})", r.outcome(), report.runs, r.seed)),
                            why: report.failure.is_some().then(|| pacing.failure_reason(&self.game)),
                            trace: report.failure.map(|r| r.trace).unwrap_or_default(),
                        }
                    })
                    .clone(),
                )
            }
            _ => None,
        };
        let failed = realtime.as_ref().is_some_and(|r| r.failure.is_some());
        let generated = match (plc_target, lowered) {
            (Some(t), Some((code, _))) => {
                let files: Vec<FileView> = if failed {
                    Vec::new()
                } else {
                    plc::render_files(&code, t, &options)
                        .into_iter()
                        .map(|f| FileView { name: f.name, text: f.text })
                        .collect()
                };
                let unit = plc::lower::timed::structured(&code).unit;
                let io = plc::io_table(&unit)
                    .into_iter()
                    .map(|r| IoRowView {
                        address: r.address,
                        data_type: r.data_type,
                        symbol: r.symbol,
                        direction: r.direction.name(),
                        meaning: r.meaning,
                    })
                    .collect();
                GeneratedCode {
                    target: target.to_string(),
                    extension: t.extension(),
                    files,
                    io,
                    io_csv: plc::io_table_csv(&unit),
                    io_sdf: plc::tag_table_sdf(&unit),
                    io_codesys: plc::codesys_mapping_csv(&unit),
                    realtime,
                }
            }
            _ => {
                let files = if failed {
                    Vec::new()
                } else {
                    vec![FileView { name: format!("{name}.txt"), text: program.render(&self.game) }]
                };
                GeneratedCode {
                    target: target.to_string(),
                    extension: "txt",
                    files,
                    io: Vec::new(),
                    io_csv: String::new(),
                    io_sdf: String::new(),
                    io_codesys: String::new(),
                    realtime,
                }
            }
        };
        to_js(&generated)
    }

    /// The strategy the controller program follows (request selection, Peter 2005, 6.3): for
    /// each state it reaches, the request it makes or `wait`. `{ state, choice, to, label }[]`,
    /// initial state first, or `null` when the game is not realizable.
    pub fn strategy(&self) -> Result<JsValue, JsValue> {
        to_js(self.strategy_choices()?)
    }

    /// The plant's winning line against the controller that holds out longest, for an
    /// unrealizable spec: `CounterPlay | null`.
    #[wasm_bindgen(js_name = counterPlay)]
    pub fn counter_play(&self) -> Result<JsValue, JsValue> {
        let s = self.synthesis()?;
        to_js(&explain::counter_play(&self.game, &s.split, &s.solution.space))
    }

    /// Starts the simulator from the initial state: the controller program against the plant
    /// when there is one (and `options.free` is not set), else free (the user picks requests
    /// too). `seed` drives the random steps and the sensor inputs. Returns `SimState` with the
    /// program's `listing`.
    #[wasm_bindgen(js_name = simStart)]
    pub fn sim_start(&mut self, seed: f64, options: JsValue) -> Result<JsValue, JsValue> {
        #[derive(Deserialize, Default)]
        #[serde(default)]
        struct Options {
            free: bool,
        }
        let opts: Options = super::options(options)?;
        let free = opts.free || self.controller()?.is_none();
        self.sim = Some(SimScript { seed: seed.max(0.0) as u64, free, choices: Vec::new(), replay: None });
        self.sim_result(true, |_| Ok(Vec::new()))
    }

    /// Replays the counter-play (`counterPlay()`) in a free simulation: the steps are taken and
    /// can be stepped back. `SimState` with `replay` set; throws without a counter-play.
    #[wasm_bindgen(js_name = simReplay)]
    pub fn sim_replay(&mut self) -> Result<JsValue, JsValue> {
        let s = self.synthesis()?;
        let line = explain::counter_play(&self.game, &s.split, &s.solution.space)
            .ok_or_else(|| JsValue::from_str("no counter-play: the spec is not unrealizable"))?;
        let edges: Vec<_> = line.moves.iter().map(|m| m.edge).collect();
        let (choices, stopped) = simulate::replay_line(&self.game, &s.split, &s.solution.space, &edges);
        let replay = ReplayView { line, steps: choices.len(), stopped };
        self.sim = Some(SimScript { seed: 0, free: true, choices, replay: Some(replay) });
        self.sim_result(true, |_| Ok(Vec::new()))
    }

    /// Where the simulator stands: `SimState`.
    #[wasm_bindgen(js_name = simState)]
    pub fn sim_state(&self) -> Result<JsValue, JsValue> {
        let view = self.simulation()?.view();
        self.state_of(view, false)
    }

    /// Takes the `index`-th move of `SimState.moves`: `SimState`.
    #[wasm_bindgen(js_name = simStep)]
    pub fn sim_step(&mut self, index: usize) -> Result<JsValue, JsValue> {
        self.sim_result(false, |sim| sim.apply(&Choice::Move { index }).map(|_| vec![Choice::Move { index }]))
    }

    /// Lets `units` time units pass (rounded to eighths, within `max_delay`); the controller
    /// scans all along and the delay ends where it acts. `SimState`.
    #[wasm_bindgen(js_name = simDelay)]
    pub fn sim_delay(&mut self, units: f64) -> Result<JsValue, JsValue> {
        if !units.is_finite() {
            return Err(JsValue::from_str("a delay must be a number"));
        }
        let ticks = (units * simulate::TICKS as f64).round() as i64;
        self.sim_result(false, |sim| sim.apply(&Choice::Delay { ticks }).map(|_| vec![Choice::Delay { ticks }]))
    }

    /// Takes up to `n` random plant steps (as the closed-loop check does), stopping at a
    /// failure: `SimState`.
    #[wasm_bindgen(js_name = simRandom)]
    pub fn sim_random(&mut self, n: usize) -> Result<JsValue, JsValue> {
        self.sim_result(false, |sim| {
            let mut taken = Vec::new();
            for _ in 0..n.min(SIM_STEPS) {
                if sim.finished() {
                    break;
                }
                sim.apply(&Choice::Random)?;
                taken.push(Choice::Random);
            }
            Ok(taken)
        })
    }

    /// Takes back the last step: `SimState`.
    #[wasm_bindgen(js_name = simBack)]
    pub fn sim_back(&mut self) -> Result<JsValue, JsValue> {
        let script = self.sim.as_mut().ok_or_else(not_started)?;
        script.choices.pop();
        let view = self.simulation()?.view();
        self.state_of(view, false)
    }

    /// The explored states the simulation's concrete state lies in (locations, pieces and
    /// zone): `StateId[]`, winning ones first.
    #[wasm_bindgen(js_name = simLocate)]
    pub fn sim_locate(&self) -> Result<JsValue, JsValue> {
        let s = self.synthesis()?;
        let sim = self.simulation()?;
        to_js(&sim.plant().locate(&s.split, &s.solution.space))
    }

    /// One state: `StateView`.
    pub fn state(&self, state: u32) -> Result<JsValue, JsValue> {
        let state = StateId::from_raw(state);
        let s = self.synthesis()?;
        if state.index() >= s.solution.space.states.len() {
            return Err(JsValue::from_str(&format!("no state s{state}")));
        }
        to_js(&self.state_view(s, state))
    }
}

fn not_started() -> JsValue {
    JsValue::from_str("the simulator has not started: call simStart() first")
}

/// A view of the state space with its drawing.
#[derive(Serialize)]
struct DrawnSpace {
    #[serde(flatten)]
    view: export::SpaceView,
    dot: String,
}

impl TimedSession {
    /// The strategy's choices (built once per solve), or `None` without a controller.
    fn strategy_choices(&self) -> Result<&Option<Vec<export::StrategyChoice>>, JsValue> {
        let s = self.synthesis()?;
        Ok(self.strategy.get_or_init(|| export::strategy(&self.game, s)))
    }

    /// `view` with its drawing, the strategy's requests marked and `selected` highlighted.
    fn drawn(&self, view: export::SpaceView, selected: Option<StateId>) -> Result<DrawnSpace, JsValue> {
        let dot = export::space_dot(&view, selected, self.strategy_choices()?.as_deref());
        Ok(DrawnSpace { view, dot })
    }

    /// The simulation the script describes, rebuilt from its start.
    fn simulation(&self) -> Result<Simulation<'_>, JsValue> {
        let script = self.sim.as_ref().ok_or_else(not_started)?;
        let program = if script.free { None } else { self.controller()? };
        let observable = program::optimize::Context::from_game(&self.game).observable;
        let mut sim = Simulation::new(&self.game, program, &observable, script.seed);
        for c in &script.choices {
            sim.apply(c).map_err(|e| JsValue::from_str(&format!("the simulator's script does not replay: {e}")))?;
        }
        Ok(sim)
    }

    fn state_of(&self, view: SimView, listing: bool) -> Result<JsValue, JsValue> {
        let script = self.sim.as_ref().ok_or_else(not_started)?;
        let listing = match (listing, script.free) {
            (true, false) => self.controller()?.map(|p| p.command_texts(&self.game)),
            _ => None,
        };
        to_js(&SimState {
            view,
            history: script.choices.len(),
            seed: script.seed,
            replay: script.replay.as_ref(),
            listing,
        })
    }

    /// Rebuilds the simulation, takes the steps `step` takes (an error leaves the script as it
    /// was), records them and returns the new `SimState`.
    fn sim_result(
        &mut self,
        listing: bool,
        step: impl FnOnce(&mut Simulation) -> Result<Vec<Choice>, String>,
    ) -> Result<JsValue, JsValue> {
        let (taken, view) = {
            let mut sim = self.simulation()?;
            let taken = step(&mut sim).map_err(|e| JsValue::from_str(&e))?;
            (taken, sim.view())
        };
        let script = self.sim.as_mut().ok_or_else(not_started)?;
        if script.choices.len() + taken.len() > SIM_STEPS {
            return Err(JsValue::from_str(&format!("the simulator keeps at most {SIM_STEPS} steps: reset it")));
        }
        script.choices.extend(taken);
        self.state_of(view, listing)
    }

    fn controller(&self) -> Result<Option<&Program>, JsValue> {
        let s = self.synthesis()?;
        Ok(self.program.get_or_init(|| program::controller(&self.game, s)).as_ref())
    }

    /// The same view of one state as `export::space` gives.
    fn state_view(&self, s: &Synthesis, id: StateId) -> StateView {
        export::state_view(&self.game, s, id)
    }
}
