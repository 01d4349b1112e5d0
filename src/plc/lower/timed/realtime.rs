//! Closed-loop checking in real time: a lowered timed controller ([`Code`], run as its unit)
//! scanned with a real
//! period against the plant automata of its [`Game`], in continuous time counted in
//! microseconds, with a plant that picks its timings adversarially within the specification.
//!
//! The PLC scans at `t_k = k · scan`: it latches the input image from the plant's state, runs
//! the code from its stored position (its unit's step list, [`crate::plc::model::unit::StepList`]), and writes
//! the output image at `t_k + e_k`, the execution time `e_k` in `[0, scan)` chosen by the
//! adversary. Outputs are physical signals: a request reaches the plant on a rising edge of its
//! output (a pulse repeated in the next scan stays TRUE and is no second request; a latched
//! output sends its `set` request on FALSE→TRUE and its `reset` request on TRUE→FALSE); the
//! edges of one write reach the plant in an order the adversary picks, since a real write
//! has none. Inputs are levels (docs/plc-code.md, "The I/O contract").
//!
//! The plant decides after every change of its state which reaction fires when: random times
//! within guards and invariants, the earliest and latest allowed instants, 1 µs after a scan
//! instant, 1 µs before one; it may also idle. A state guard keeps the spec's `dependson`: one
//! whose dependencies list only messages (the round table's colours) is drawn anew when one of
//! them occurs and holds its level in between; any other is drawn anew at every move, and one
//! that is FALSE turns TRUE within a scan period (the game assumes a guard holds when the
//! controller checks it). A stable guard turns TRUE between its messages only when the run
//! would otherwise stall (the plant can do nothing by itself and the controller has sent
//! nothing for two scans): there the game's assumption is all that lets the controller go on.
//! `instant` transitions
//! fire at once, before anything else. A run fails when an assertion is violated (checked after
//! every plant move and every request), a plan fails (a timeout clock beyond its bound, at the
//! microsecond), a request is refused, a request enters a guarded condition while the scan that
//! issued it read the guard FALSE, or the plans stop progressing while the controller keeps
//! running, or the controller stops (a scan that does not end). The controller is a
//! [`ScanController`]: [`UnitInterpreter`] runs the code's unit in the unit interpreter
//! ([`crate::plc::model::exec`]), as the printers write it; a test plugs in a PLC emulator. No
//! I/O, no clock: a run is a function of its seed.

use crate::plc::lower::timed::machine::{Code, Effect};
use crate::plc::lower::timed::{Structured, Wiring};
use crate::plc::model::exec::{Machine, Value};
use crate::plc::model::unit::{Place, PouKind, Stmt};
use crate::rng::Rng;
use crate::timed::model::{CompId, DependsOn, Game, MessageKind, MessageRole, MsgId};
use crate::timed::plant::{Move, Plant, Sensors, Violation};
use std::collections::VecDeque;
use std::fmt;

/// Plant reactions between two scans beyond which the plant is taken to be zeno (a cycle of
/// reactions without a time constraint would otherwise keep a run at one instant for ever).
const ZENO_REACTIONS: u64 = 100_000;

/// Scans without a request while the plant can do nothing by itself after which a run has
/// stalled, and a stable guard may turn TRUE between its dependency messages.
const STALLED_SCANS: u64 = 2;

/// The controller side of a run.
pub trait ScanController {
    /// One scan at `now_us` (microseconds since the run began) on the input image `inputs` (a
    /// level per input of the code); returns the output image (a level per output), which the
    /// run writes out at the end of the scan's execution time.
    fn scan(&mut self, now_us: u64, inputs: &[bool]) -> Vec<bool>;

    /// The stored program position after the last scan, for traces.
    fn position(&self) -> Option<usize> {
        None
    }

    /// Why the controller stopped, if it did (a scan that did not end): the run fails.
    fn fault(&self) -> Option<String> {
        None
    }
}

/// A controller's structured unit ([`crate::plc::lower::timed::structured`]) run by the unit
/// interpreter [`crate::plc::model::exec`]: the one model's semantics, scan by scan, as the
/// structured printers execute it. The interpreter's clock counts milliseconds: a scan at a
/// fraction of a millisecond sees the time of the millisecond it falls in. A unit the
/// interpreter refuses (a scan that does not end) stops the controller where it is, as a PLC's
/// watchdog would; [`UnitInterpreter::error`] tells why.
pub struct UnitInterpreter<'u> {
    structured: &'u Structured,
    machine: Machine<'u>,
    /// The instance of the block in the program, whose position [`ScanController::position`]
    /// reports.
    instance: Option<String>,
    now_ms: u64,
    error: Option<String>,
}

impl<'u> UnitInterpreter<'u> {
    /// The unit after a cold start.
    pub fn new(structured: &'u Structured) -> Result<UnitInterpreter<'u>, String> {
        let machine = Machine::new(&structured.unit).map_err(|e| e.0)?;
        let program = structured.unit.pous.iter().find(|p| p.kind == PouKind::Program);
        let instance = program.and_then(|p| {
            p.body.iter().find_map(|s| match s {
                Stmt::CallInstance { instance: Place::Local(name), .. } => Some(name.clone()),
                _ => None,
            })
        });
        Ok(UnitInterpreter { structured, machine, instance, now_ms: 0, error: None })
    }

    /// Why the interpreter stopped the controller, if it did.
    pub fn error(&self) -> Option<&str> {
        self.error.as_deref()
    }

    fn write(&mut self, place: &Place, level: bool) -> Result<(), String> {
        match place {
            Place::Signal(k) => {
                self.machine.set_signal(*k, Value::Bool(level));
                Ok(())
            }
            Place::Global(name) => self.machine.set_global(name, Value::Bool(level)).map_err(|e| e.0),
            other => Err(format!("the program wires {other:?}, neither a signal nor a global")),
        }
    }

    fn level(&self, place: &Place) -> bool {
        match place {
            Place::Signal(k) => self.machine.signal(*k).as_bool(),
            Place::Global(name) => self.machine.global(name).is_some_and(Value::as_bool),
            _ => false,
        }
    }
}

impl ScanController for UnitInterpreter<'_> {
    fn scan(&mut self, now_us: u64, inputs: &[bool]) -> Vec<bool> {
        let outputs = |me: &Self| me.structured.outputs.iter().map(|p| me.level(p)).collect();
        if self.error.is_some() {
            return outputs(self);
        }
        let now_ms = now_us / 1000;
        self.machine.advance(now_ms.saturating_sub(self.now_ms));
        self.now_ms = self.now_ms.max(now_ms);
        let mut result = Ok(());
        for (place, &level) in self.structured.inputs.iter().zip(inputs) {
            result = result.and_then(|()| self.write(place, level));
        }
        let mut no_controller =
            |_: &mut Machine<'_>| Err(crate::plc::model::exec::ExecError("no external controller".into()));
        if let Err(e) = result.and_then(|()| self.machine.cycle(&mut no_controller).map_err(|e| e.0)) {
            self.error = Some(e);
        }
        outputs(self)
    }

    fn fault(&self) -> Option<String> {
        self.error.clone()
    }

    fn position(&self) -> Option<usize> {
        let instance = self.instance.as_deref()?;
        self.machine.instance_value(instance, super::structured::POSITION).map(|v| v.as_int() as usize)
    }
}

/// The choices of one run.
#[derive(Clone, Debug)]
pub struct Config {
    /// The scan period, in µs.
    pub scan_us: u64,
    /// Scans per run.
    pub scans: u64,
    /// How many of the last events a report keeps.
    pub trace_lines: usize,
    /// No plan progress after this many requests, or this many scans with neither a request
    /// nor a plant reaction that could still happen, is a failure ([`Failure::NoProgress`]).
    pub patience: u64,
}

impl Default for Config {
    fn default() -> Config {
        Config { scan_us: 10_000, scans: 2000, trace_lines: 40, patience: 1000 }
    }
}

/// Why a run failed.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Failure {
    Assertion {
        text: String,
    },
    PlanFailed {
        plan: String,
    },
    /// A request the plant could not take when it arrived.
    RequestRefused {
        request: String,
        reason: String,
    },
    /// A request entered a guarded condition while the scan that issued it read its guard
    /// FALSE (or the code does not read the guard).
    GuardViolated {
        request: String,
        guard: String,
    },
    /// The plans stopped progressing while the controller kept running.
    NoProgress {
        reason: String,
    },
    /// The controller stopped: its scan did not end (a PLC's watchdog would stop it).
    ControllerStopped {
        reason: String,
    },
}

/// How a run ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stop {
    /// All scans ran.
    Scans,
    /// The plant could neither move nor let time pass (an invariant expired with no reaction
    /// enabled, or instant transitions without end), or reacted without end between two scans
    /// (a zeno plant): the specification's doing, not the controller's fault.
    Timelock,
    Failed,
}

/// Request latencies in scans. A request's latency is the number of scans from the input
/// change it reacted to — the last scan whose input image differed from the one before by a
/// change a plant reaction (or guard) made; the feedback of the controller's own requests does
/// not count — to the scan that issued it. Per plan cycle (from one plan progress to the next)
/// the latencies add up, a chain of requests reacting to the same change counting once, by its
/// last request: the scans the cycle waited for the controller. A round is a plan's way from
/// its initial location back to it (one production cycle); it adds up the latencies of its
/// plan cycles.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Latency {
    pub requests: u64,
    pub sum: u64,
    pub max: u64,
    /// Plan cycles closed, and the summed and the largest latency one of them added.
    pub cycles: u64,
    pub cycle_sum: u64,
    pub cycle_max: u64,
    /// Plan rounds closed, and the summed and the largest latency one of them added.
    pub rounds: u64,
    pub round_sum: u64,
    pub round_max: u64,
}

impl Latency {
    /// Mean scans per request.
    pub fn mean(&self) -> f64 {
        self.sum as f64 / self.requests.max(1) as f64
    }

    /// Mean scans of request latency per plan cycle.
    pub fn cycle_mean(&self) -> f64 {
        self.cycle_sum as f64 / self.cycles.max(1) as f64
    }

    /// Mean scans of request latency per plan round.
    pub fn round_mean(&self) -> f64 {
        self.round_sum as f64 / self.rounds.max(1) as f64
    }

    /// Adds another run's figures.
    pub fn merge(&mut self, other: &Latency) {
        self.requests += other.requests;
        self.sum += other.sum;
        self.max = self.max.max(other.max);
        self.cycles += other.cycles;
        self.cycle_sum += other.cycle_sum;
        self.cycle_max = self.cycle_max.max(other.cycle_max);
        self.rounds += other.rounds;
        self.round_sum += other.round_sum;
        self.round_max = self.round_max.max(other.round_max);
    }
}

/// What one run did.
#[derive(Clone, Debug)]
pub struct RunReport {
    pub seed: u64,
    pub stop: Stop,
    pub failure: Option<Failure>,
    /// Where the run ended (at the failure, if any), in µs.
    pub time_us: u64,
    pub scans: u64,
    pub requests: u64,
    pub reactions: u64,
    /// Plan progress events (plan cycles).
    pub progress: u64,
    pub latency: Latency,
    /// Scans that pulsed an output already TRUE from the scan before: the signal stays TRUE,
    /// so the plant sees one request where the code made two.
    pub repeated_pulses: u64,
    /// Times a stable guard (one that changes only on its `dependson` messages) turned TRUE
    /// between them, because the run had stalled: the game's assumption, not the spec's promise.
    pub assumed_guards: u64,
    /// A legend (the inputs' and outputs' names, the plant's manner in this run), then the last
    /// events: time in ms, the event, the inputs' levels and the outputs.
    pub trace: Vec<String>,
}

impl RunReport {
    /// What ended the run and when: the failure in its `Debug` form (the variant's name, which
    /// the CLI's and the playground's readers look for) at the run's end in ms, e.g.
    /// `PlanFailed { plan: "p" } at 495.000 ms`; `no failure (Scans) at …` when none.
    pub fn outcome(&self) -> String {
        let ms = self.time_us as f64 / 1000.0;
        match &self.failure {
            Some(f) => format!("{f:?} at {ms:.3} ms"),
            None => format!("no failure ({:?}) at {ms:.3} ms", self.stop),
        }
    }
}

/// [`RunReport::outcome`], then the trace, one event a line: the text every reader of a failed
/// run prints (the CLI, the tests; the playground shows the trace apart).
impl fmt::Display for RunReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.outcome())?;
        for line in &self.trace {
            write!(f, "\n{line}")?;
        }
        Ok(())
    }
}

/// When the plant lets a reaction fire within its window.
#[derive(Clone, Copy, Debug)]
enum Timing {
    Uniform,
    Earliest,
    Latest,
    AfterScan,
    BeforeScan,
}

const TIMINGS: [Timing; 5] = [Timing::Uniform, Timing::Earliest, Timing::Latest, Timing::AfterScan, Timing::BeforeScan];

/// How long a scan's execution takes.
#[derive(Clone, Copy, Debug)]
enum Execution {
    Random,
    Zero,
    /// 1 µs below the scan period.
    Longest,
    /// One of the three, anew each scan.
    Mixed,
}

/// What the plant has decided to do next.
#[derive(Clone, Debug)]
enum Next {
    React(Move),
    /// A FALSE guard turns TRUE; `stalled`: a stable guard between its dependency messages,
    /// because the run had stalled and only the game's assumption (a guard holds when the
    /// controller checks it) lets it go on.
    RaiseGuard {
        message: MsgId,
        stalled: bool,
    },
    /// Nothing until then; decide again.
    Idle,
    /// The invariants expire with no reaction enabled.
    Timelock,
}

/// A state guard's input and when the specification lets it change.
struct GuardInput {
    message: MsgId,
    /// `Some`: only when one of these messages occurs (`dependson` without `time`); `None`: at
    /// any time.
    changes_on: Option<Vec<MsgId>>,
}

impl GuardInput {
    fn of(game: &Game) -> Vec<GuardInput> {
        let guards =
            (0..game.messages.len()).map(MsgId::new).filter(|&m| game.messages[m.index()].role == MessageRole::Guard);
        guards
            .map(|message| {
                let on: Vec<DependsOn> = game
                    .dependencies
                    .iter()
                    .filter(|d| d.message == message)
                    .flat_map(|d| d.on.iter().copied())
                    .collect();
                let changes_on = (!on.is_empty() && !on.contains(&DependsOn::Time)).then(|| {
                    on.iter().filter_map(|d| if let DependsOn::Message(m) = d { Some(*m) } else { None }).collect()
                });
                GuardInput { message, changes_on }
            })
            .collect()
    }

    /// Whether the guard is drawn anew when `m` occurs.
    fn redrawn_by(&self, m: MsgId) -> bool {
        self.changes_on.as_ref().is_none_or(|on| on.contains(&m))
    }
}

struct Write {
    at: i64,
    outputs: Vec<bool>,
    image: Vec<bool>,
    scan: u64,
}

struct Run<'a> {
    game: &'a Game,
    code: &'a Code,
    wiring: &'a Wiring,
    config: &'a Config,
    plant: Plant<'a>,
    inputs: Sensors,
    guards: Vec<GuardInput>,
    rng: Rng,
    /// Per timing strategy: its weight in this run.
    timing: [u64; 5],
    execution: Execution,
    /// Longest idle time and stretch of an unbounded window, in µs.
    horizon: i64,
    now: i64,
    scan: i64,
    next_scan: i64,
    physical: Vec<bool>,
    write: Option<Write>,
    decided: Option<(i64, Next)>,
    /// Whether some reaction may still happen in the current state (set when deciding).
    plant_can_react: bool,
    last_image: Option<Vec<bool>>,
    /// The last scan whose image differed from the one before by a change a reaction made.
    last_change: u64,
    /// Some reaction changed an input's level since the last scan.
    reacted: bool,
    /// The trigger (`last_change`) and latency of the last request, and the latency the
    /// current plan cycle has added so far.
    episode: Option<(u64, u64)>,
    cycle_latency: u64,
    /// Per plan: the latency its current round has added so far.
    round_latency: Vec<u64>,
    requests_since_progress: u64,
    stalled_scans: u64,
    /// Plant reactions since the last scan: a plant that reacts without end between two scans
    /// (a cycle of reactions without a time constraint) stops the run.
    reactions_since_scan: u64,
    trace: VecDeque<String>,
    /// The first line of every trace: the names behind the bits of the trace's lines.
    legend: String,
    report: RunReport,
}

/// What [`check`] found: the totals over its runs, and the first failure with its report.
#[derive(Clone, Debug)]
pub struct CheckReport {
    pub runs: u64,
    pub scans: u64,
    pub requests: u64,
    /// Plan progress events over all runs.
    pub progress: u64,
    pub latency: Latency,
    /// Runs that ended in a timelock of the plant (the specification's, not a failure).
    pub timelocks: u64,
    pub failure: Option<RunReport>,
}

/// Runs the interpreter of `code` as `target` prints it against the plant of `game`, seeds
/// `0..runs` (each a different manner of the adversary: timings, execution times, orders),
/// `config.scans` scans each, and stops at the first failure. The gate of a compile at a
/// declared scan time: evidence over many adversarial runs, not a proof.
pub fn check(game: &Game, code: &Code, wiring: &Wiring, config: &Config, runs: u64) -> CheckReport {
    let mut report = CheckReport {
        runs: 0,
        scans: 0,
        requests: 0,
        progress: 0,
        latency: Latency::default(),
        timelocks: 0,
        failure: None,
    };
    let structured = super::structured(code);
    for seed in 0..runs {
        let mut controller = UnitInterpreter::new(&structured).expect("a lowered controller's unit starts");
        let r = run(game, code, wiring, &mut controller, config, seed);
        report.runs += 1;
        report.scans += r.scans;
        report.requests += r.requests;
        report.progress += r.progress;
        report.latency.merge(&r.latency);
        report.timelocks += u64::from(r.stop == Stop::Timelock);
        if r.failure.is_some() {
            report.failure = Some(r);
            break;
        }
    }
    report
}

/// Runs `controller`, whose code is `code` wired to `game` by `wiring`, against the plant of
/// `game` for `config.scans` scans of `config.scan_us`; `seed` decides every choice of the
/// plant.
pub fn run(
    game: &Game,
    code: &Code,
    wiring: &Wiring,
    controller: &mut dyn ScanController,
    config: &Config,
    seed: u64,
) -> RunReport {
    let unit_us = i64::try_from(game.timeunit_ms.saturating_mul(1000)).unwrap_or(i64::MAX);
    let scan = i64::try_from(config.scan_us.max(1)).unwrap_or(i64::MAX);
    let mut rng = Rng::new(seed);
    // This run's manner: even timings, or one that dominates; one kind of execution time.
    let mut timing = [1u64; 5];
    if rng.chance(60) {
        timing[rng.below(5) as usize] = 12;
    }
    let execution = [Execution::Random, Execution::Zero, Execution::Longest, Execution::Mixed][rng.below(4) as usize];
    let guards = GuardInput::of(game);
    let mut run = Run {
        game,
        code,
        wiring,
        config,
        plant: Plant::new(game, unit_us),
        inputs: Sensors::new(game, &wiring.inputs),
        guards,
        rng,
        timing,
        execution,
        horizon: unit_us.saturating_mul(2).max(scan.saturating_mul(10)),
        now: 0,
        scan,
        next_scan: 0,
        physical: vec![false; code.outputs.len()],
        write: None,
        decided: None,
        plant_can_react: true,
        last_image: None,
        last_change: 0,
        reacted: true,
        episode: None,
        cycle_latency: 0,
        round_latency: vec![0; game.plans.len()],
        requests_since_progress: 0,
        stalled_scans: 0,
        reactions_since_scan: 0,
        trace: VecDeque::new(),
        legend: format!(
            "inputs {}; outputs {}",
            code.inputs.iter().map(|v| v.symbol.as_str()).collect::<Vec<_>>().join(" "),
            code.outputs.iter().map(|o| o.variable.symbol.as_str()).collect::<Vec<_>>().join(" ")
        ),
        report: RunReport {
            seed,
            stop: Stop::Scans,
            failure: None,
            time_us: 0,
            scans: 0,
            requests: 0,
            reactions: 0,
            progress: 0,
            latency: Latency::default(),
            repeated_pulses: 0,
            assumed_guards: 0,
            trace: Vec::new(),
        },
    };
    for i in 0..run.guards.len() {
        let g = run.guards[i].message;
        run.inputs.holds[g.index()] = run.rng.chance(50);
    }
    run.legend += &format!(
        "; timing weights {:?} (uniform, earliest, latest, after a scan, before a scan); execution {:?}",
        run.timing, run.execution
    );
    let stop = run.go(controller);
    run.report.stop = stop;
    run.report.time_us = run.now as u64;
    run.report.trace = std::iter::once(run.legend).chain(run.trace).collect();
    run.report
}

impl Run<'_> {
    fn name(&self, m: MsgId) -> &str {
        &self.game.messages[m.index()].name
    }

    fn bits(v: &[bool]) -> String {
        v.iter().map(|&b| if b { '1' } else { '0' }).collect()
    }

    /// Adds a trace line: the time in ms, the event, the inputs' levels and the outputs.
    fn note(&mut self, event: String) {
        if self.config.trace_lines == 0 {
            return;
        }
        let line = format!(
            "{:>12.3} ms  {event}   [in {} out {}]",
            self.now as f64 / 1000.0,
            Self::bits(&self.inputs.image()),
            Self::bits(&self.physical)
        );
        if self.trace.len() == self.config.trace_lines {
            self.trace.pop_front();
        }
        self.trace.push_back(line);
    }

    fn describe(&self, m: &Move) -> String {
        let parts: Vec<String> = m
            .parts
            .iter()
            .map(|&(u, ei)| {
                let a = &self.game.components[u];
                let e = &a.edges[ei];
                format!("{} {} -> {}", a.name, a.locations[e.from.index()].name, a.locations[e.to.index()].name)
            })
            .collect();
        format!(
            "{}{} ({})",
            self.game.messages[m.message.index()].name,
            if m.instant { " instant" } else { "" },
            parts.join(", ")
        )
    }

    fn fail(&mut self, failure: Failure) -> Stop {
        self.note(format!("FAILURE: {failure:?}"));
        self.report.failure = Some(failure);
        Stop::Failed
    }

    fn violated(&mut self) -> Option<Stop> {
        let failure = match self.plant.violation()? {
            Violation::Assertion(k) => Failure::Assertion { text: self.game.assertions[k].text.clone() },
            Violation::Plan(k) => Failure::PlanFailed { plan: self.game.plans[k].name.clone() },
        };
        Some(self.fail(failure))
    }

    /// Applies a plant move (a reaction or a request) and what follows at once: the inputs, the
    /// plans, the instant transitions it enables; then checks the state.
    fn apply(&mut self, m: &Move, what: String) -> Option<Stop> {
        let before = self.inputs.image();
        let closing = self.closing(m.message);
        if self.plant.apply(m) {
            self.progressed(&closing);
        }
        self.inputs.moved(self.game, m.message, m.instant, m.parts.iter().map(|&(u, _)| CompId::new(u)));
        self.decided = None;
        self.stalled_scans = 0;
        self.note(what);
        self.redraw_guards(m.message);
        let request = self.game.messages[m.message.index()].role == MessageRole::Request;
        self.reacted |= !request && self.inputs.image() != before;
        self.violated().or_else(|| self.settle())
    }

    /// Draws anew the guards that message `m` may change: the stable ones that depend on it, and
    /// every other.
    fn redraw_guards(&mut self, m: MsgId) {
        for i in 0..self.guards.len() {
            if self.guards[i].redrawn_by(m) {
                let g = self.guards[i].message;
                self.inputs.holds[g.index()] = self.rng.chance(50);
            }
        }
    }

    /// Fires the instant transitions enabled now, one after the other (checking the state after
    /// each), until none is.
    fn settle(&mut self) -> Option<Stop> {
        for _ in 0..10_000 {
            let instants = self.plant.instant_moves(MessageKind::Uncontrollable);
            if instants.is_empty() {
                return None;
            }
            let m = instants[self.rng.below(instants.len() as u64) as usize].clone();
            let before = self.inputs.image();
            let closing = self.closing(m.message);
            if self.plant.apply(&m) {
                self.progressed(&closing);
            }
            self.inputs.moved(self.game, m.message, m.instant, m.parts.iter().map(|&(u, _)| CompId::new(u)));
            self.decided = None;
            self.report.reactions += 1;
            let line = format!("!{}", self.describe(&m));
            self.note(line);
            self.redraw_guards(m.message);
            self.reacted |= self.inputs.image() != before;
            if let Some(stop) = self.violated() {
                return Some(stop);
            }
        }
        self.note("instant transitions without end".into());
        Some(Stop::Timelock)
    }

    /// The plans whose round message `m` closes: it takes them back to their initial location.
    fn closing(&self, m: MsgId) -> Vec<usize> {
        let plans = self.game.plans.iter().enumerate();
        plans
            .filter(|(p, plan)| {
                let at = self.plant.plan_locs[*p];
                plan.edges.iter().find(|e| e.from == at && e.message == m).is_some_and(|e| e.to == plan.initial)
            })
            .map(|(p, _)| p)
            .collect()
    }

    /// A plan progressed: a plan step closes, and so does the round of every plan in `closing`.
    fn progressed(&mut self, closing: &[usize]) {
        self.report.progress += 1;
        self.requests_since_progress = 0;
        let l = &mut self.report.latency;
        l.cycles += 1;
        l.cycle_sum += self.cycle_latency;
        l.cycle_max = l.cycle_max.max(self.cycle_latency);
        self.cycle_latency = 0;
        for &p in closing {
            l.rounds += 1;
            l.round_sum += self.round_latency[p];
            l.round_max = l.round_max.max(self.round_latency[p]);
            self.round_latency[p] = 0;
        }
    }

    /// A delay within `lo..=hi` (from now) by this run's timing strategies.
    fn pick_time(&mut self, lo: i64, hi: Option<i64>) -> i64 {
        let hi = hi.unwrap_or(lo.saturating_add(self.horizon));
        let total: u64 = self.timing.iter().sum();
        let mut r = self.rng.below(total);
        let mut timing = Timing::Uniform;
        for (k, &w) in self.timing.iter().enumerate() {
            if r < w {
                timing = TIMINGS[k];
                break;
            }
            r -= w;
        }
        let uniform = |rng: &mut Rng| lo + rng.below((hi - lo + 1) as u64) as i64;
        // The scan instants after the window opens, shifted by `offset`: one of the first three.
        let near_scan = |rng: &mut Rng, offset: i64| -> Option<i64> {
            let from = self.now + lo - offset;
            let first = from.div_euclid(self.scan) + i64::from(from.rem_euclid(self.scan) != 0);
            let d = (first + rng.below(3) as i64) * self.scan + offset - self.now;
            (lo..=hi).contains(&d).then_some(d)
        };
        match timing {
            Timing::Uniform => uniform(&mut self.rng),
            Timing::Earliest => lo,
            Timing::Latest => hi,
            Timing::AfterScan => near_scan(&mut self.rng, 1).unwrap_or_else(|| uniform(&mut self.rng)),
            Timing::BeforeScan => near_scan(&mut self.rng, -1).unwrap_or_else(|| uniform(&mut self.rng)),
        }
    }

    /// The plant decides its next event in the current state.
    fn decide(&mut self) {
        let room = self.plant.room();
        let mut reactions = Vec::new();
        let mut instant: Option<(i64, Vec<Move>)> = None;
        for m in self.plant.candidates(&[MessageKind::Uncontrollable]) {
            let Some((lo, hi)) = self.plant.window(&m) else { continue };
            if m.instant {
                match &mut instant {
                    Some((at, ms)) if *at == lo => ms.push(m),
                    Some((at, _)) if *at < lo => {}
                    _ => instant = Some((lo, vec![m])),
                }
            } else {
                reactions.push((m, lo, hi));
            }
        }
        self.plant_can_react = !reactions.is_empty() || instant.is_some();
        // Options: each reaction, and idling while no invariant presses.
        let idle = room.is_none();
        let total = reactions.len() as u64 + u64::from(idle);
        let mut choice = if total == 0 {
            room.map(|r| (r, Next::Timelock))
        } else {
            let r = self.rng.below(total) as usize;
            if r < reactions.len() {
                let (m, lo, hi) = reactions.swap_remove(r);
                Some((self.pick_time(lo, hi), Next::React(m)))
            } else {
                Some((self.pick_time(1, Some(self.horizon.max(1))), Next::Idle))
            }
        };
        // A guard that is FALSE turns TRUE within a scan period (the game assumes a guard holds
        // when the controller needs it), unless the plant moves first; a stable one only when
        // the run has stalled.
        let stalled = !self.plant_can_react && self.stalled_scans >= STALLED_SCANS;
        let low: Vec<(MsgId, bool)> = self
            .guards
            .iter()
            .filter(|g| !self.inputs.holds[g.message.index()] && (g.changes_on.is_none() || stalled))
            .map(|g| (g.message, g.changes_on.is_some()))
            .collect();
        if !low.is_empty() {
            let (g, stable) = low[self.rng.below(low.len() as u64) as usize];
            let d = self.pick_time(1, Some(self.scan));
            if choice.as_ref().is_none_or(|&(at, _)| d < at) {
                choice = Some((d, Next::RaiseGuard { message: g, stalled: stable }));
            }
        }
        if let Some((at, ms)) = instant {
            if choice.as_ref().is_none_or(|&(d, _)| d >= at) {
                let m = ms[self.rng.below(ms.len() as u64) as usize].clone();
                choice = Some((at, Next::React(m)));
            }
        }
        self.decided = choice.map(|(d, p)| (self.now + d, p));
    }

    fn go(&mut self, controller: &mut dyn ScanController) -> Stop {
        // Instant transitions enabled initially fire before the first scan.
        if let Some(stop) = self.violated().or_else(|| self.settle()) {
            return stop;
        }
        loop {
            if self.report.scans >= self.config.scans && self.write.is_none() {
                return Stop::Scans;
            }
            if self.decided.is_none() {
                self.decide();
            }
            let t_controller = self.write.as_ref().map_or(self.next_scan, |w| w.at);
            let t_plant = self.decided.as_ref().map(|&(t, _)| t);
            let t_deadline = self.plant.plan_deadline().map(|d| self.now + d);
            let t = [Some(t_controller), t_plant, t_deadline].into_iter().flatten().min().unwrap_or(t_controller);
            self.plant.delay(t - self.now);
            self.now = t;
            if let Some(stop) = self.violated() {
                return stop;
            }
            if t_plant == Some(t) {
                if let Some(stop) = self.plant_event() {
                    return stop;
                }
            } else if t_controller == t {
                let stop = match self.write.take() {
                    Some(w) => self.output(w),
                    None => self.scan(controller),
                };
                if let Some(stop) = stop {
                    return stop;
                }
            }
        }
    }

    fn plant_event(&mut self) -> Option<Stop> {
        let (_, plan) = self.decided.take()?;
        match plan {
            Next::React(m) => {
                // The window was computed on this very state, so the move is enabled.
                debug_assert!(self.plant.enabled(&m), "{} not enabled at its chosen time", self.describe(&m));
                if !self.plant.enabled(&m) {
                    return None;
                }
                self.reactions_since_scan += 1;
                if self.reactions_since_scan > ZENO_REACTIONS {
                    self.note(format!("the plant reacts more than {ZENO_REACTIONS} times within one scan (zeno)"));
                    return Some(Stop::Timelock);
                }
                self.report.reactions += 1;
                let line = format!("!{}", self.describe(&m));
                self.apply(&m, line)
            }
            Next::RaiseGuard { message, stalled } => {
                let before = self.inputs.image();
                self.inputs.holds[message.index()] = true;
                self.reacted |= self.inputs.image() != before;
                self.report.assumed_guards += u64::from(stalled);
                let why = if stalled { " (stalled: the game assumes it holds when checked)" } else { "" };
                let line = format!("guard {} := 1{why}", self.name(message));
                self.note(line);
                None
            }
            Next::Idle => None,
            Next::Timelock => {
                self.note("the plant can neither move nor wait (an invariant expires)".into());
                Some(Stop::Timelock)
            }
        }
    }

    /// A scan instant: latch the inputs, run the controller, schedule the output write.
    fn scan(&mut self, controller: &mut dyn ScanController) -> Option<Stop> {
        self.reactions_since_scan = 0;
        let k = self.report.scans;
        let image = self.inputs.image();
        let changed = self.last_image.as_ref() != Some(&image);
        if changed && self.reacted {
            self.last_change = k;
        }
        self.reacted = false;
        let outputs = controller.scan(self.now as u64, &image);
        if let Some(reason) = controller.fault() {
            return Some(self.fail(Failure::ControllerStopped { reason }));
        }
        assert_eq!(outputs.len(), self.code.outputs.len(), "the controller writes one level per output");
        let execution = match self.execution {
            Execution::Mixed => [Execution::Random, Execution::Zero, Execution::Longest][self.rng.below(3) as usize],
            e => e,
        };
        let e = match execution {
            Execution::Zero => 0,
            Execution::Longest => self.scan - 1,
            _ => self.rng.below(self.scan as u64) as i64,
        };
        if changed || outputs != self.physical {
            let at = controller.position().map_or(String::new(), |p| format!(" -> step {p}"));
            self.note(format!("scan {k}: read {}{at}, writes {} at +{e} us", Self::bits(&image), Self::bits(&outputs)));
        }
        self.last_image = Some(image.clone());
        self.write = Some(Write { at: self.now + e, outputs, image, scan: k });
        self.report.scans += 1;
        self.next_scan += self.scan;
        if !self.plant_can_react {
            self.stalled_scans += 1;
            if self.stalled_scans == STALLED_SCANS && self.guards.iter().any(|g| g.changes_on.is_some()) {
                // Stalled: the plant decides again, now free to raise a stable guard.
                self.decided = None;
            }
            if self.stalled_scans >= self.config.patience {
                let reason =
                    format!("{} scans without a request while the plant can do nothing by itself", self.stalled_scans);
                return Some(self.fail(Failure::NoProgress { reason }));
            }
        }
        None
    }

    /// The end of a scan's execution: the output image is written; edges send requests.
    fn output(&mut self, w: Write) -> Option<Stop> {
        // The machine takes the edges of one write in an order of its choosing.
        let mut order: Vec<usize> = (0..w.outputs.len()).collect();
        for k in (1..order.len()).rev() {
            order.swap(k, self.rng.below(k as u64 + 1) as usize);
        }
        for k in order {
            if w.outputs[k] == self.physical[k] {
                if w.outputs[k] && self.code.outputs[k].pulsed {
                    self.report.repeated_pulses += 1;
                    let line = format!(
                        "{} pulsed again in scan {}: no rising edge, no request",
                        self.code.outputs[k].variable.symbol, w.scan
                    );
                    self.note(line);
                }
                continue;
            }
            self.physical[k] = w.outputs[k];
            let rising = w.outputs[k];
            let requests: Vec<MsgId> = self.wiring.outputs[k]
                .iter()
                .filter(|&&(_, e)| (e == Effect::Reset) != rising)
                .map(|&(m, _)| m)
                .collect();
            let Some(&first) = requests.first() else { continue };
            let moves: Vec<Move> = self
                .plant
                .moves(&[MessageKind::Controllable])
                .into_iter()
                .filter(|m| requests.contains(&m.message))
                .collect();
            if moves.is_empty() {
                let reason = self.refusal(first);
                let request = self.name(first).to_string();
                return Some(self.fail(Failure::RequestRefused { request, reason }));
            }
            let m = moves[self.rng.below(moves.len() as u64) as usize].clone();
            // Guards apply to requests that enter a guarded condition (4.2.1).
            let before = self.plant.locs.clone();
            let mut after = before.clone();
            for &(u, ei) in &m.parts {
                after[u] = self.game.components[u].edges[ei].to;
            }
            for rule in &self.game.guards {
                if rule.cond.eval(&before) || !rule.cond.eval(&after) {
                    continue;
                }
                let read = self
                    .wiring
                    .inputs
                    .iter()
                    .zip(&w.image)
                    .any(|(ms, &level)| ms.iter().any(|&(g, negated)| g == rule.message && level != negated));
                if !read {
                    let (request, guard) = (self.name(m.message).to_string(), self.name(rule.message).to_string());
                    return Some(self.fail(Failure::GuardViolated { request, guard }));
                }
            }
            let latency = w.scan - self.last_change;
            let l = &mut self.report.latency;
            l.requests += 1;
            l.sum += latency;
            l.max = l.max.max(latency);
            // A chain of requests reacting to one change adds its last request's latency.
            let added = match self.episode {
                Some((trigger, before)) if trigger == self.last_change => latency.saturating_sub(before),
                _ => latency,
            };
            self.cycle_latency += added;
            for r in &mut self.round_latency {
                *r += added;
            }
            self.episode = Some((self.last_change, latency));
            self.report.requests += 1;
            self.requests_since_progress += 1;
            let line = format!("?{} from scan {} (latency {latency})", self.describe(&m), w.scan);
            if let Some(stop) = self.apply(&m, line) {
                return Some(stop);
            }
            if self.requests_since_progress > self.config.patience {
                let reason = format!("{} requests since the last plan progress", self.requests_since_progress);
                return Some(self.fail(Failure::NoProgress { reason }));
            }
        }
        None
    }

    /// Why request `m` cannot be taken now.
    fn refusal(&self, m: MsgId) -> String {
        let game = self.game;
        let Some(s) = game.messages[m.index()].sender else { return "it has no sender".into() };
        let a = &game.components[s.index()];
        let here = &a.locations[self.plant.locs[s.index()].index()].name;
        let candidates = self.plant.candidates_of(MessageKind::Controllable, m);
        if !a.edges.iter().any(|e| e.message == m && e.from == self.plant.locs[s.index()]) {
            return format!("{} has no ?{} in {here}", a.name, self.name(m));
        }
        if candidates.is_empty() {
            let missing: Vec<String> = game.messages[m.index()]
                .synchronised
                .iter()
                .map(|&o| (&game.components[o.index()], self.plant.locs[o.index()]))
                .filter(|(b, at)| !b.edges.iter().any(|e| e.message == m && e.from == *at))
                .map(|(b, at)| format!("{} has no ${} in {}", b.name, self.name(m), b.locations[at.index()].name))
                .collect();
            return missing.join("; ");
        }
        let c = &candidates[0];
        for &(u, ei) in &c.parts {
            let e = &game.components[u].edges[ei];
            for ci in &e.guard {
                let v = self.plant.clocks[ci.clock.index()];
                if !self.plant.holds(&ci.interval, v) {
                    return format!(
                        "guard {} in {} of {} is false ({} = {:.3} units)",
                        game.clocks[ci.clock.index()].name,
                        ci.interval,
                        game.components[u].name,
                        game.clocks[ci.clock.index()].name,
                        v as f64 / self.plant.ticks as f64
                    );
                }
            }
        }
        "a target's invariant would not hold".into()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::plc::lower::timed::machine::{Effect, Output, Statement, Step, Test, Timer, Variable};

    /// `0: WAIT t >= 30 ms; 1: DO go (restart t); 2: GOTO 0` with one input and a pulsed output.
    fn code() -> Code {
        Code {
            name: "c".into(),
            program: "c_main".into(),
            instance: "ctrl".into(),
            gvl: "GVL_IO".into(),
            header: Vec::new(),
            inputs: vec![Variable::unbound("x")],
            outputs: vec![Output { variable: Variable::unbound("go"), pulsed: true, last: Some("last_go".into()) }],
            timers: vec![Timer { symbol: "t_x".into(), comment: String::new(), preset_ms: 40 }],
            steps: vec![
                Step::new(Statement::Wait { test: Test::Elapsed { timer: 0, ms: 30, strict: false } }, vec![]),
                Step::new(Statement::Act { output: 0, effect: Effect::Pulse, ends_scan: true }, vec![0]),
                Step::new(Statement::Jump { target: 0 }, vec![]),
            ],
        }
    }

    /// The output at each scan, every 10 ms, with the input FALSE.
    fn outputs(code: &Code, scans: u64) -> Vec<bool> {
        let structured = super::super::structured(code);
        let mut i = UnitInterpreter::new(&structured).unwrap();
        (0..scans).map(|k| i.scan(k * 10_000, &[false])[0]).collect()
    }

    #[test]
    fn a_timer_restarted_by_a_request_starts_with_the_next_scan() {
        // Started at scan 0, elapsed at scan 3 (30 ms); restarted there, running from scan 4,
        // elapsed at scan 7; the position after the request resolves through the jump.
        assert_eq!(outputs(&code(), 12).iter().positions(), vec![3, 7, 11]);
    }

    #[test]
    fn a_stored_backward_jump_costs_no_scan() {
        // Waiting for nothing, the code would pulse in every scan (the position after the
        // request resolves through `GOTO 0`), but a pulse right after a pulse waits a scan.
        let mut c = code();
        c.steps[0].statement = Statement::Wait { test: Test::Input { input: 0, negated: true } };
        assert_eq!(outputs(&c, 6).iter().positions(), vec![0, 2, 4]);
        // Without the memory of the last write the code pulses in every scan: one long TRUE, a
        // single request for the plant.
        c.outputs[0].last = None;
        assert_eq!(outputs(&c, 6).iter().positions(), vec![0, 1, 2, 3, 4, 5]);
    }

    #[test]
    fn a_request_that_goes_on_runs_the_next_test_in_its_scan() {
        // `go` goes on to wait for `x`: with `x` TRUE the wait passes in the same scan and the
        // jump back ends it; with `x` FALSE the scan ends at the wait.
        let mut c = code();
        c.steps[0].statement = Statement::Wait { test: Test::Elapsed { timer: 0, ms: 0, strict: false } };
        c.steps[1].statement = Statement::Act { output: 0, effect: Effect::Pulse, ends_scan: false };
        c.steps.insert(2, Step::new(Statement::Wait { test: Test::Input { input: 0, negated: false } }, vec![]));
        c.steps[3].statement = Statement::Jump { target: 0 };
        let structured = super::super::structured(&c);
        let mut i = UnitInterpreter::new(&structured).unwrap();
        assert_eq!(i.scan(0, &[true]), vec![true]);
        assert_eq!(i.position(), Some(0));
        let mut i = UnitInterpreter::new(&structured).unwrap();
        assert_eq!(i.scan(0, &[false]), vec![true]);
        assert_eq!(i.position(), Some(2));
    }

    #[test]
    fn a_pulse_after_a_pulse_waits_at_its_step_for_one_scan() {
        // Waiting for nothing: scan 1 reaches the request with `go` TRUE from scan 0 and stays
        // at step 1 without acting.
        let mut c = code();
        c.steps[0].statement = Statement::Wait { test: Test::Input { input: 0, negated: true } };
        let structured = super::super::structured(&c);
        let mut i = UnitInterpreter::new(&structured).unwrap();
        assert_eq!(i.scan(0, &[false]), vec![true]);
        assert_eq!(i.position(), Some(0));
        assert_eq!(i.scan(10_000, &[false]), vec![false]);
        assert_eq!(i.position(), Some(1));
        assert_eq!(i.scan(20_000, &[false]), vec![true]);
        assert_eq!(i.position(), Some(0));
    }

    #[test]
    fn a_scan_that_does_not_end_stops_the_controller() {
        // A jump back that goes on within its scan to itself: the watchdog's case.
        let mut c = code();
        c.steps[2].back_in_scan = true;
        c.steps[0].statement = Statement::Jump { target: 2 };
        let structured = super::super::structured(&c);
        let mut i = UnitInterpreter::new(&structured).unwrap();
        i.scan(0, &[false]);
        assert!(i.fault().is_some_and(|f| f.contains("watchdog")), "{:?}", i.fault());
    }

    trait Positions {
        fn positions(self) -> Vec<usize>;
    }

    impl<'a, I: Iterator<Item = &'a bool>> Positions for I {
        fn positions(self) -> Vec<usize> {
            self.enumerate().filter(|(_, &b)| b).map(|(k, _)| k).collect()
        }
    }
}
