//! The WebAssembly boundary of the playground: the only module that knows wasm-bindgen.
//!
//! Everything crosses as plain JS values made by serde-wasm-bindgen (JSON-compatible: `None`
//! becomes `null`). Shapes are documented in `docs/playground.md`. Engines stay free of I/O and
//! of the browser; this module only adapts their results. Nothing here reads a clock
//! (`std::time::Instant` panics on `wasm32-unknown-unknown`): the page measures time.

use crate::diag::Diagnostic;
use crate::plc::{self, Target};
use crate::program::{self, Program};
use crate::timed::explain::{describe_edge, describe_state, dump};
use crate::timed::export::{self, SpaceView, StateView, TransitionView};
use crate::timed::model::Game;
use crate::timed::solve::{BudgetStop, SolveOptions, StateId, Stats, Verdict};
use crate::timed::{self, Synthesis};
use serde::{Deserialize, Serialize};
use std::cell::OnceCell;
use std::collections::{HashMap, VecDeque};
use wasm_bindgen::prelude::*;

const NONE: u32 = u32::MAX;

fn to_js<T: Serialize + ?Sized>(value: &T) -> Result<JsValue, JsValue> {
    value.serialize(&serde_wasm_bindgen::Serializer::json_compatible()).map_err(|e| JsValue::from_str(&e.to_string()))
}

/// Installs the panic hook, so that a panic reaches the console with its message.
#[wasm_bindgen(start)]
pub fn start() {
    console_error_panic_hook::set_once();
}

/// The crate version, shown in the page footer.
#[wasm_bindgen]
pub fn version() -> String {
    env!("CARGO_PKG_VERSION").to_string()
}

/// Syntax diagnostics only: `Diagnostic[]`.
#[wasm_bindgen]
pub fn parse(source: &str) -> Result<JsValue, JsValue> {
    to_js(&timed::parse(source).diagnostics)
}

#[derive(Serialize)]
struct CheckResult<'a> {
    ok: bool,
    diagnostics: &'a [Diagnostic],
}

/// Syntax and semantic check: `{ ok, diagnostics }` (warnings included when `ok`).
#[wasm_bindgen]
pub fn check(source: &str) -> Result<JsValue, JsValue> {
    match timed::compile(source) {
        Ok((_, warnings)) => to_js(&CheckResult { ok: true, diagnostics: &warnings }),
        Err(errors) => to_js(&CheckResult { ok: false, diagnostics: &errors }),
    }
}

/// Options of [`Session::solve`]; every field is optional.
#[derive(Deserialize, Default)]
#[serde(rename_all = "camelCase", default)]
struct JsSolveOptions {
    max_states: Option<usize>,
    max_memory_mib: Option<usize>,
    max_work: Option<u64>,
    progress_interval: Option<usize>,
}

#[derive(Serialize)]
struct SolveSummary {
    verdict: Verdict,
    stats: Stats,
    /// Present when the verdict is `budget_exceeded`: which budget stopped the search.
    budget: Option<BudgetStop>,
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
    verdict: Verdict,
    stats: Stats,
    budget: Option<BudgetStop>,
    /// Why no PLC with this scan can do it, as text (the scan game's counter-play).
    explanation_text: Option<String>,
}

/// Runs of the real-time check of code at a declared scan time (each 2000 scans), as the CLI.
const CHECK_RUNS: u64 = 20;

/// A code target of the page's menu.
#[derive(Serialize)]
struct TargetInfo {
    /// `program` (the intermediate language) or a [`Target`] name.
    id: &'static str,
    label: &'static str,
    extension: &'static str,
    /// Whether the target writes several files (TwinCAT).
    multi_file: bool,
}

/// The code targets: the intermediate program first, then every PLC back end.
#[wasm_bindgen]
pub fn targets() -> Result<JsValue, JsValue> {
    let mut list = vec![TargetInfo {
        id: "program",
        label: "Intermediate program (thesis notation)",
        extension: "txt",
        multi_file: false,
    }];
    for target in Target::ALL {
        list.push(TargetInfo {
            id: target.name(),
            label: target.label(),
            extension: target.extension(),
            multi_file: target.multi_file(),
        });
    }
    to_js(&list)
}

#[derive(Serialize)]
struct GeneratedCode {
    target: String,
    extension: &'static str,
    /// The files, each `{ name, text }` (TwinCAT: three; the others one). The page shows them
    /// as one text, each after a line `==> NAME <==` when there are several.
    files: Vec<FileView>,
    /// The I/O table, `{ address, type, symbol, direction, meaning }[]` (empty for `program`).
    io: Vec<IoRowView>,
    /// The I/O table as CSV and as a Siemens SDF symbol table (empty for `program`).
    io_csv: String,
    io_sdf: String,
    /// At a declared scan time at which the specification is implementable: the real-time
    /// check of the code (`plc::realtime::check`); when it failed, `files` is empty.
    realtime: Option<RealtimeView>,
}

/// What the real-time check of generated code found.
#[derive(Clone, Serialize)]
struct RealtimeView {
    scan_ms: u64,
    runs: u64,
    scans_per_run: u64,
    /// The failure, with the seed of its run and the run's trace, or `null`.
    failure: Option<String>,
    trace: Vec<String>,
}

#[derive(Serialize)]
struct FileView {
    name: String,
    text: String,
}

#[derive(Serialize)]
struct IoRowView {
    address: String,
    #[serde(rename = "type")]
    data_type: &'static str,
    symbol: String,
    direction: &'static str,
    meaning: String,
}

/// What the winning strategy does in one of its states.
#[derive(Serialize)]
struct StrategyChoice {
    state: StateId,
    /// `request` or `wait`.
    choice: &'static str,
    /// For a request: its target state and its label (as in `TransitionView::label`).
    to: Option<StateId>,
    label: Option<String>,
}

/// One row of the state explorer.
#[derive(Serialize)]
struct StateRow {
    id: StateId,
    text: String,
    winning: bool,
    initial: bool,
}

#[derive(Serialize)]
struct StateSearch {
    /// How many states match (the rows are the first `limit` of them).
    total: usize,
    rows: Vec<StateRow>,
}

/// A compiled specification and, once solved, its synthesis.
#[wasm_bindgen]
pub struct Session {
    source: String,
    game: Game,
    warnings: Vec<Diagnostic>,
    synthesis: Option<Synthesis>,
    /// Predecessors of every state, built on the first `neighbourhood` query after a solve.
    incoming: OnceCell<Vec<Vec<StateId>>>,
    /// The optimised controller program, built on the first `program`/`code` call after a solve.
    program: OnceCell<Option<Program>>,
    /// The declared scan time, when the last solve found the specification implementable there:
    /// `code` then runs the code against the plant in real time first.
    implementable_at: Option<u64>,
    /// That check, once per semantics (IEC targets, STL), built on the first `code` call after
    /// a solve: the targets of one semantics run the same code.
    checked: [OnceCell<RealtimeView>; 2],
}

#[wasm_bindgen]
impl Session {
    /// Compiles `source`; throws `{ diagnostics: Diagnostic[] }` when it has errors.
    #[wasm_bindgen(constructor)]
    pub fn new(source: &str) -> Result<Session, JsValue> {
        match timed::compile(source) {
            Ok((game, warnings)) => Ok(Session {
                source: source.to_string(),
                game,
                warnings,
                synthesis: None,
                incoming: OnceCell::new(),
                program: OnceCell::new(),
                implementable_at: None,
                checked: Default::default(),
            }),
            Err(errors) => Err(to_js(&CheckResult { ok: false, diagnostics: &errors })?),
        }
    }

    /// The warnings of the compilation: `Diagnostic[]`.
    pub fn warnings(&self) -> Result<JsValue, JsValue> {
        to_js(&self.warnings)
    }

    /// Plant units and plans: `AutomatonView[]`.
    pub fn automata(&self) -> Result<JsValue, JsValue> {
        to_js(&export::automata(&self.game))
    }

    /// Solves the game. `options`: `{ maxStates?, maxMemoryMib?, maxWork?, progressInterval? }`;
    /// `progress`, if given, is called with `Stats` every `progressInterval` expansions (and
    /// during long work on one state), and a return value of `false` cancels the run. Returns
    /// `{ verdict, stats, budget, explanation_depth }`.
    pub fn solve(&mut self, options: JsValue, progress: Option<js_sys::Function>) -> Result<JsValue, JsValue> {
        let opts: JsSolveOptions = if options.is_undefined() || options.is_null() {
            JsSolveOptions::default()
        } else {
            serde_wasm_bindgen::from_value(options)
                .map_err(|e| JsValue::from_str(&format!("bad solve options: {e}")))?
        };
        let defaults = SolveOptions::default();
        let options = SolveOptions {
            max_states: opts.max_states.unwrap_or(defaults.max_states),
            max_bytes: opts.max_memory_mib.map_or(defaults.max_bytes, |mib| mib.saturating_mul(1 << 20)),
            max_work: opts.max_work.unwrap_or(defaults.max_work),
            progress_interval: opts.progress_interval.unwrap_or(defaults.progress_interval).max(1),
        };
        let mut callback_error = None;
        let mut report = |stats: &Stats| -> bool {
            let Some(f) = &progress else { return true };
            let value = match to_js(stats) {
                Ok(v) => v,
                Err(e) => {
                    callback_error = Some(e);
                    return false;
                }
            };
            match f.call1(&JsValue::NULL, &value) {
                Ok(answer) => answer.as_bool() != Some(false),
                Err(e) => {
                    callback_error = Some(e);
                    false
                }
            }
        };
        let synthesis = timed::synthesize(&self.game, &options, &mut report);
        let scan = match self.game.scan_ms {
            // A callback error cancels the run, so a realizable verdict means none occurred.
            Some((ms, _)) if synthesis.solution.verdict == Verdict::Realizable => {
                timed::synthesize_at_scan(&self.game, ms, &options, &mut report).ok().map(|r| ScanSummary {
                    scan_ms: ms,
                    verdict: r.synthesis.solution.verdict,
                    stats: r.synthesis.solution.stats,
                    budget: r.synthesis.solution.stop.clone(),
                    explanation_text: r.synthesis.explanation.as_ref().map(|e| e.render()),
                })
            }
            _ => None,
        };
        if let Some(e) = callback_error {
            return Err(e);
        }
        let summary = SolveSummary {
            verdict: synthesis.solution.verdict,
            stats: synthesis.solution.stats,
            budget: synthesis.solution.stop.clone(),
            explanation_depth: synthesis.explanation.as_ref().map(|e| e.depth),
            scan,
        };
        self.synthesis = Some(synthesis);
        self.incoming = OnceCell::new();
        self.program = OnceCell::new();
        self.checked = Default::default();
        self.implementable_at = summary.scan.as_ref().filter(|s| s.verdict == Verdict::Realizable).map(|s| s.scan_ms);
        to_js(&summary)
    }

    fn synthesis(&self) -> Result<&Synthesis, JsValue> {
        self.synthesis.as_ref().ok_or_else(|| JsValue::from_str("not solved yet: call solve() first"))
    }

    /// The explored space, at most `limit` states breadth-first from the initial one: `SpaceView`.
    pub fn space(&self, limit: usize) -> Result<JsValue, JsValue> {
        to_js(&export::space(&self.game, self.synthesis()?, limit))
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
        let s = self.synthesis()?;
        let space = &s.solution.space;
        let words: Vec<String> = query.split_whitespace().map(str::to_lowercase).collect();
        let mut total = 0;
        let mut rows = Vec::new();
        for id in 0..space.states.len() as StateId {
            let winning = space.is_winning(id);
            if (filter == "winning" && !winning) || (filter == "removed" && winning) {
                continue;
            }
            // Describing a state costs; without a query only the listed rows need it.
            let text = if words.is_empty() {
                None
            } else {
                let text = describe_state(&self.game, &s.split, space, id);
                let lower = format!("s{id} {}", text.to_lowercase());
                if !words.iter().all(|w| lower.contains(w.as_str())) {
                    continue;
                }
                Some(text)
            };
            total += 1;
            if rows.len() < limit {
                let text = text.unwrap_or_else(|| describe_state(&self.game, &s.split, space, id));
                rows.push(StateRow { id, text, winning, initial: id == space.initial });
            }
        }
        to_js(&StateSearch { total, rows })
    }

    /// The states within `k` steps of `state` (following edges both ways), at most `limit` of
    /// them, with the edges among them: a `SpaceView` whose `truncated` tells if `limit` cut it.
    pub fn neighbourhood(&self, state: StateId, k: u32, limit: usize) -> Result<JsValue, JsValue> {
        let s = self.synthesis()?;
        let space = &s.solution.space;
        let n = space.states.len();
        if state as usize >= n {
            return Err(JsValue::from_str(&format!("no state s{state}")));
        }
        let incoming = self.incoming.get_or_init(|| {
            let mut incoming = vec![Vec::new(); n];
            for e in &space.edges {
                if e.to != NONE {
                    incoming[e.to as usize].push(e.from);
                }
            }
            incoming
        });
        let mut dist: HashMap<StateId, u32> = HashMap::from([(state, 0)]);
        let mut order = vec![state];
        let mut queue = VecDeque::from([state]);
        let mut cut = false;
        'bfs: while let Some(x) = queue.pop_front() {
            let d = dist[&x];
            if d >= k {
                continue;
            }
            let succ = space.out_edges(x).map(|(_, e)| e.to).filter(|&t| t != NONE);
            let pred = incoming[x as usize].iter().copied();
            for y in succ.chain(pred).collect::<Vec<_>>() {
                if dist.contains_key(&y) {
                    continue;
                }
                if order.len() >= limit {
                    cut = true;
                    break 'bfs;
                }
                dist.insert(y, d + 1);
                order.push(y);
                queue.push_back(y);
            }
        }
        let states: Vec<StateView> = order.iter().map(|&x| self.state_view(s, x)).collect();
        let mut edges = Vec::new();
        for &x in &order {
            for (_, e) in space.out_edges(x) {
                if e.to != NONE && !dist.contains_key(&e.to) {
                    continue;
                }
                edges.push(TransitionView {
                    from: x,
                    to: (e.to != NONE).then_some(e.to),
                    kind: e.kind,
                    label: describe_edge(&self.game, &s.split, e),
                    zeno: e.zeno,
                    progress: e.progress,
                });
            }
        }
        to_js(&SpaceView {
            verdict: s.solution.verdict,
            initial: space.initial,
            clocks: self.game.clocks.iter().map(|c| c.name.clone()).collect(),
            units: s.split.units.iter().map(|u| u.name.clone()).collect(),
            states,
            edges,
            truncated: cut,
            total_states: n,
        })
    }

    /// The controller program in the thesis's notation, or `undefined` when the game is not
    /// realizable (no controller exists, or the run stopped before deciding).
    pub fn program(&self) -> Result<Option<String>, JsValue> {
        Ok(self.controller()?.map(|p| p.render(&self.game)))
    }

    /// The controller as code for `target` (an id from `targets()`), the function block named
    /// after `name`, PLCopen's creation time `created_unix` (seconds since 1970, from the page's
    /// clock): `{ target, extension, files, io, io_csv, io_sdf, realtime }`, or `null` when the
    /// game is not realizable. At a declared scan time where the game is implementable the code is
    /// first run against the plant (`realtime`); if a run fails, `files` is empty. Throws `{ ok: false, diagnostics }` when a time constant does not fit
    /// the target.
    pub fn code(&self, target: &str, name: &str, created_unix: Option<f64>) -> Result<JsValue, JsValue> {
        let Some(program) = self.controller()? else { return Ok(JsValue::NULL) };
        let plc_target: Option<Target> = match target {
            "program" => None,
            t => Some(t.parse().map_err(|e: plc::UnknownTarget| JsValue::from_str(&e.to_string()))?),
        };
        let options = plc::Options { created_unix: created_unix.unwrap_or(0.0).max(0.0) as u64, ..Default::default() };
        // The intermediate program is checked as ST; it needs the lowering only for the check.
        let lowered = if plc_target.is_some() || self.implementable_at.is_some() {
            let t = plc_target.unwrap_or(Target::St);
            match plc::lower_timed::build_wired(&self.game, program, t, name, &self.source, &options) {
                Ok(built) => Some(built),
                Err(errors) if plc_target.is_some() => {
                    return Err(to_js(&CheckResult { ok: false, diagnostics: &errors })?)
                }
                Err(_) => None,
            }
        } else {
            None
        };
        let realtime = match (self.implementable_at, &lowered) {
            (Some(ms), Some((code, wiring))) => {
                let check_target = plc_target.unwrap_or(Target::St);
                let cell = &self.checked[usize::from(check_target == Target::Stl)];
                Some(
                    cell.get_or_init(|| {
                        let config = plc::realtime::Config { scan_us: ms.saturating_mul(1000), ..Default::default() };
                        let report = plc::realtime::check(&self.game, code, wiring, check_target, &config, CHECK_RUNS);
                        RealtimeView {
                            scan_ms: ms,
                            runs: report.runs,
                            scans_per_run: config.scans,
                            failure: report.failure.as_ref().map(|r| {
                                format!(
                                    "{} (run {}, seed {}, at {:.3} ms)",
                                    r.failure.as_ref().map_or(String::new(), |f| format!("{f:?}")),
                                    report.runs,
                                    r.seed,
                                    r.time_us as f64 / 1000.0
                                )
                            }),
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
                let io = plc::io_table(&code)
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
                    io_csv: plc::io_table_csv(&code),
                    io_sdf: plc::tag_table_sdf(&code),
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
        let s = self.synthesis()?;
        if s.solution.verdict != Verdict::Realizable {
            return Ok(JsValue::NULL);
        }
        let space = &s.solution.space;
        let strategy = program::select::select(&self.game, space);
        let choices: Vec<StrategyChoice> = strategy
            .states
            .iter()
            .map(|&st| match strategy.choice[st as usize] {
                program::select::Choice::Request(e) => {
                    let edge = &space.edges[e as usize];
                    StrategyChoice {
                        state: st,
                        choice: "request",
                        to: Some(edge.to),
                        label: Some(describe_edge(&self.game, &s.split, edge)),
                    }
                }
                program::select::Choice::Wait => StrategyChoice { state: st, choice: "wait", to: None, label: None },
            })
            .collect();
        to_js(&choices)
    }

    /// One state: `StateView`.
    pub fn state(&self, state: StateId) -> Result<JsValue, JsValue> {
        let s = self.synthesis()?;
        if state as usize >= s.solution.space.states.len() {
            return Err(JsValue::from_str(&format!("no state s{state}")));
        }
        to_js(&self.state_view(s, state))
    }
}

impl Session {
    fn controller(&self) -> Result<Option<&Program>, JsValue> {
        let s = self.synthesis()?;
        Ok(self.program.get_or_init(|| program::controller(&self.game, s)).as_ref())
    }

    /// The same view of one state as `export::space` gives.
    fn state_view(&self, s: &Synthesis, id: StateId) -> StateView {
        export::state_view(&self.game, s, id)
    }
}
