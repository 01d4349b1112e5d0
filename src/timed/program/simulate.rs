//! Closed-loop checking: a controller program run against the plant it was made for.
//!
//! The plant is the specification's own automata (`crate::timed::plant`), with concrete
//! clock values in eighths of a time unit; the controller is an interpreter of the intermediate
//! program under the scan-cycle model of 6.3: after every plant step it runs, in zero time,
//! until it waits. The plant chooses at random among its enabled reactions and delays within
//! the guards and invariants; `instant` transitions fire before anything else, and the
//! controller does not act while one is enabled. Each plant event is received once: the test
//! that succeeds on it takes it. A run fails if an
//! assertion is violated, a plan fails, the program sends a request the plant cannot take, or
//! the controller stops waiting or stops making plan progress.
//!
//! [`Simulation`] is the same closed loop one step at a time, for the playground's simulator:
//! each step is a [`Choice`] (a plant move picked by the user, a delay, or a random plant step
//! as [`run`] takes them), and [`Simulation::view`] shows where it stands. [`run`] is a loop of
//! random steps over it. Without a program the simulation is *free*: nobody scans, and the
//! requests are offered as moves beside the reactions (the replay of an unrealizable spec's
//! counter-play, [`replay_line`], plays both sides).

use super::{Condition, Instruction, Program};
use crate::timed::model::{Game, Interval, LocId, MessageKind, MessageRole, MsgId};
use crate::timed::plant::{Move as PlantMove, Plant, Violation};
use crate::timed::precompute::SplitGame;
use crate::timed::solve::{EdgeId, EdgeKind, Label, StateId, StateSpace};
use crate::zone::{Bound, Dbm};
use serde::{Deserialize, Serialize};

/// Clock values are counted in `1 / TICKS` time units.
pub const TICKS: i64 = 8;

#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Failure {
    Assertion {
        text: String,
    },
    /// `timeout`: a timeout clock exceeded its bound; else a message the plan forbids occurred.
    PlanFailed {
        plan: String,
        timeout: bool,
    },
    RequestRefused {
        request: String,
    },
    ControllerLoops,
    NoProgress,
}

#[derive(Clone, Debug, Serialize)]
pub struct RunReport {
    pub steps: usize,
    pub progress: usize,
    pub requests: usize,
    /// Elapsed time in time units.
    pub time: f64,
    pub failure: Option<Failure>,
    /// The last steps before the failure, for diagnosis; empty when the run did not fail
    /// (formatting the trace of every passing run cost the random closed loops a tenth of their
    /// time).
    pub trace: Vec<String>,
}

pub use crate::rng::Rng;

/// How many of the last steps [`RunReport::trace`] keeps.
const TRACE_LINES: usize = 40;
/// Commands one scan runs before a zeno loop is cut (at its next request).
const ZENO_CUT: usize = 10_000;

/// What a step of the trace was.
#[derive(Clone, Debug)]
enum TraceLine {
    /// The controller's request (`DO (m)`).
    Request(MsgId),
    /// A plant message: `!` a reaction, `?` a request.
    Message {
        sigil: &'static str,
        message: MsgId,
    },
    Text(&'static str),
}

/// A step of the trace with the numbers it shows, formatted when the run ends.
#[derive(Clone, Debug)]
struct TraceEntry {
    line: TraceLine,
    ticks: i64,
    pc: usize,
    clocks: Vec<i64>,
    timers: Vec<i64>,
    plan_locs: Vec<LocId>,
}

/// One step of a [`Simulation`].
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Choice {
    /// The `index`-th move of [`Simulation::moves`].
    Move { index: usize },
    /// Let `ticks` pass, within what the invariants allow; the controller scans every tick and,
    /// when it acts, the delay ends there (the plant decides anew, as in [`run`]).
    Delay { ticks: i64 },
    /// One plant step at random, as [`run`] takes them.
    Random,
}

/// Who did what in a step of the trace.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Actor {
    Plant,
    Controller,
    Time,
    /// The simulation's verdict: a failure, or a plant that can neither move nor wait.
    Checker,
}

/// One line of the trace, as in a message sequence chart.
#[derive(Clone, Debug, Serialize)]
pub struct Event {
    /// When it happened (a delay: when it began), in time units.
    pub time: f64,
    pub actor: Actor,
    /// `reaction`, `request`, `delay`, `failure` or `stuck`.
    pub kind: &'static str,
    pub text: String,
    /// Some plan took a step with it.
    pub progress: bool,
    /// A delay's length in time units.
    pub duration: Option<f64>,
    /// The number of the step (1-based) that produced it (for a delay: that began it); 0 is
    /// the start.
    pub step: usize,
}

/// A move the simulation offers: a plant reaction, or, without a program, a request too.
#[derive(Clone, Debug, Serialize)]
pub struct MoveView {
    pub index: usize,
    /// `reaction` or `request`.
    pub kind: &'static str,
    pub message: String,
    pub instant: bool,
    /// `!press: button.released → pressing`, one `unit.from → to` per participating transition.
    pub text: String,
}

#[derive(Clone, Debug, Serialize)]
pub struct UnitLocation {
    pub unit: String,
    pub location: String,
}

/// Where a plan stands: its location, the `index`-th (0-based) of its `count` steps (the
/// locations other than the failed one, in declaration order).
#[derive(Clone, Debug, Serialize)]
pub struct PlanView {
    pub name: String,
    pub location: String,
    pub index: usize,
    pub count: usize,
    pub failed: bool,
}

#[derive(Clone, Debug, Serialize)]
pub struct ClockView {
    pub name: String,
    /// The plant's clock, in time units.
    pub value: f64,
    /// The controller's timer of the same clock (reset by its commands), with a program.
    pub timer: Option<f64>,
}

#[derive(Clone, Debug, Serialize)]
pub struct GuardView {
    pub name: String,
    pub value: bool,
}

/// Where a simulation stands, for the page.
#[derive(Clone, Debug, Serialize)]
pub struct SimView {
    /// `program` (the controller program runs after every plant step) or `free`.
    pub mode: &'static str,
    pub time: f64,
    /// Steps taken (choices applied).
    pub steps: usize,
    /// The program's current command (where it waits), with a program.
    pub pc: Option<usize>,
    pub locations: Vec<UnitLocation>,
    pub plans: Vec<PlanView>,
    pub clocks: Vec<ClockView>,
    /// The sensor conditions (guard messages), set at random before every plant step.
    pub guards: Vec<GuardView>,
    /// The requests the controller sent after the last plant step.
    pub sent: Vec<String>,
    pub requests: usize,
    /// Plan steps taken so far.
    pub progress: usize,
    pub moves: Vec<MoveView>,
    /// Whether time may pass now (no failure, no instant reaction due, room in the invariants).
    pub can_delay: bool,
    /// The longest delay the invariants allow, in time units; `null`: unbounded.
    pub max_delay: Option<f64>,
    pub failure: Option<Failure>,
    /// The failure in words.
    pub failure_text: Option<String>,
    /// The plant can neither move nor wait (an exceptional timeout: not the controller's fault).
    pub stuck: bool,
    pub events: Vec<Event>,
}

/// True if `ticks` has reached the interval's lower bound.
fn reached(i: &Interval, ticks: i64) -> bool {
    let lo = i.lower as i64 * TICKS;
    if i.lower_closed {
        ticks >= lo
    } else {
        ticks > lo
    }
}

/// The plant, the controller's timers (one per clock, in ticks) and the time.
#[derive(Clone)]
struct World<'g> {
    plant: Plant<'g>,
    timers: Vec<i64>,
    time: i64,
}

impl World<'_> {
    fn delay(&mut self, d: i64) {
        self.plant.delay(d);
        for t in self.timers.iter_mut().skip(1) {
            *t += d;
        }
        self.time += d;
    }

    fn failure(&self) -> Option<Failure> {
        let game = self.plant.game;
        self.plant.violation().map(|v| match v {
            Violation::Assertion(k) => Failure::Assertion { text: game.assertions[k].text.clone() },
            Violation::Plan(k) => Failure::PlanFailed {
                plan: game.plans[k].name.clone(),
                timeout: self.plant.plan_locs[k] != game.plans[k].failed,
            },
        })
    }
}

/// A closed-loop run, one step at a time: the plant, the controller program (if any) with its
/// position and timers, and the trace.
pub struct Simulation<'g> {
    w: World<'g>,
    program: Option<&'g Program>,
    observable: Vec<bool>,
    pos: Vec<u32>,
    pc: usize,
    pending: Option<MsgId>,
    guards: Vec<MsgId>,
    guard_values: Vec<bool>,
    rng: Rng,
    report: RunReport,
    /// The last steps, formatted into [`RunReport::trace`] when [`run`] ends.
    trace: std::collections::VecDeque<TraceEntry>,
    /// Per command, the stamp of the scan segment that last ran it (see `scan`).
    visited: Vec<u32>,
    stamp: u32,
    requests_since_progress: usize,
    /// Whether [`Simulation::events`] are kept ([`run`] only needs its short text trace).
    record: bool,
    events: Vec<Event>,
    /// The requests of the scan after the last plant step.
    sent: Vec<MsgId>,
    stuck: bool,
    steps: usize,
}

impl<'g> Simulation<'g> {
    /// A simulation from the initial state: the controller (with a `program`) has already run
    /// its first scan. `observable[m]` tells whether the controller sees plant message `m`
    /// (missing: it does); `seed` drives the random steps and the guard inputs.
    pub fn new(game: &'g Game, program: Option<&'g Program>, observable: &[bool], seed: u64) -> Simulation<'g> {
        Simulation::build(game, program, observable, seed, true)
    }

    fn build(
        game: &'g Game,
        program: Option<&'g Program>,
        observable: &[bool],
        seed: u64,
        record: bool,
    ) -> Simulation<'g> {
        let guards: Vec<MsgId> = (0..game.messages.len())
            .map(MsgId::new)
            .filter(|&m| game.messages[m.index()].role == MessageRole::Guard)
            .collect();
        // Guard messages are sensor conditions (4.2.1): the environment sets them at random, anew
        // before every plant step, for the controller's IF tests. The game treats a guard check as
        // the controller's option (5.3.4), i.e. it assumes the guard holds when the controller
        // needs it: a WAITUNTIL on a guard is therefore satisfied at once.
        let mut sim = Simulation {
            w: World { plant: Plant::new(game, TICKS), timers: vec![0; game.dim()], time: 0 },
            program,
            observable: observable.to_vec(),
            pos: program.map(Program::positions).unwrap_or_default(),
            pc: 0,
            pending: None,
            guard_values: vec![false; game.messages.len()],
            guards,
            rng: Rng::new(seed),
            report: RunReport { steps: 0, progress: 0, requests: 0, time: 0.0, failure: None, trace: Vec::new() },
            trace: std::collections::VecDeque::with_capacity(TRACE_LINES),
            visited: Vec::new(),
            stamp: 0,
            requests_since_progress: 0,
            record,
            events: Vec::new(),
            sent: Vec::new(),
            stuck: false,
            steps: 0,
        };
        if !sim.check() {
            sim.scan();
        }
        sim.note_failure();
        sim
    }

    /// The plant's current state.
    pub fn plant(&self) -> &Plant<'g> {
        &self.w.plant
    }

    pub fn failure(&self) -> Option<&Failure> {
        self.report.failure.as_ref()
    }

    /// True once a failure occurred or the plant got stuck: no step is possible any more.
    pub fn finished(&self) -> bool {
        self.report.failure.is_some() || self.stuck || (self.offered().is_empty() && self.w.plant.room() == Some(0))
    }

    fn game(&self) -> &'g Game {
        self.w.plant.game
    }

    /// Keeps the last [`TRACE_LINES`] steps for [`RunReport::trace`]: a snapshot of the numbers,
    /// formatted only when the run ends (a run may take millions of requests; formatting each
    /// step's clocks was most of its time).
    fn trace(&mut self, line: TraceLine) {
        let p = &self.w.plant;
        let entry = if self.trace.len() == TRACE_LINES {
            // The oldest entry's buffers take the new snapshot.
            let mut e = self.trace.pop_front().expect("the trace is full");
            e.clocks.clone_from(&p.clocks);
            e.timers.clone_from(&self.w.timers);
            e.plan_locs.clone_from(&p.plan_locs);
            TraceEntry { line, ticks: self.w.time, pc: self.pc, ..e }
        } else {
            TraceEntry {
                line,
                ticks: self.w.time,
                pc: self.pc,
                clocks: p.clocks.clone(),
                timers: self.w.timers.clone(),
                plan_locs: p.plan_locs.clone(),
            }
        };
        self.trace.push_back(entry);
    }

    /// The kept steps as text: `time: line   [pc; clock/timer …; plan location and clocks]`.
    fn trace_text(&self) -> Vec<String> {
        let game = self.game();
        let units = |ticks: i64| ticks as f64 / TICKS as f64;
        self.trace
            .iter()
            .map(|e| {
                let line = match &e.line {
                    TraceLine::Request(m) => format!("{:.3}: DO ({})", units(e.ticks), self.name(*m)),
                    TraceLine::Message { sigil, message } => {
                        format!("{:.3}: {sigil}{}", units(e.ticks), self.name(*message))
                    }
                    TraceLine::Text(text) => text.to_string(),
                };
                let plans: Vec<String> = game
                    .plans
                    .iter()
                    .enumerate()
                    .map(|(p, plan)| {
                        let clocks: Vec<String> = plan
                            .clocks
                            .iter()
                            .map(|&(c, _)| format!("{}={:.3}", game.clocks[c.index()].name, units(e.clocks[c.index()])))
                            .collect();
                        format!("{}.{} {}", plan.name, plan.locations[e.plan_locs[p].index()].name, clocks.join(" "))
                    })
                    .collect();
                let clocks: Vec<String> = (1..e.clocks.len())
                    .map(|c| format!("{}={:.3}/{:.3}", game.clocks[c].name, units(e.clocks[c]), units(e.timers[c])))
                    .collect();
                format!(
                    "{line}   [pc {}; clock/timer {}{}{}]",
                    e.pc,
                    clocks.join(" "),
                    if plans.is_empty() { "" } else { "; " },
                    plans.join("; ")
                )
            })
            .collect()
    }

    /// Adds a line to the trace of [`Simulation::view`].
    fn event(&mut self, actor: Actor, kind: &'static str, text: String, progress: bool) {
        if self.record {
            let time = self.w.time as f64 / TICKS as f64;
            self.events.push(Event { time, actor, kind, text, progress, duration: None, step: self.steps });
        }
    }

    /// One tick of time: extends the trace's last delay when nothing happened since (also
    /// across steps: consecutive delays read as one in the trace).
    fn tick(&mut self) {
        self.w.delay(1);
        if !self.record {
            return;
        }
        match self.events.last_mut() {
            Some(e) if e.kind == "delay" => {
                let d = e.duration.unwrap_or(0.0) + 1.0 / TICKS as f64;
                e.duration = Some(d);
                e.text = format!("time passes: {}", units(d));
            }
            _ => {
                let time = (self.w.time - 1) as f64 / TICKS as f64;
                let d = 1.0 / TICKS as f64;
                self.events.push(Event {
                    time,
                    actor: Actor::Time,
                    kind: "delay",
                    text: format!("time passes: {}", units(d)),
                    progress: false,
                    duration: Some(d),
                    step: self.steps,
                });
            }
        }
    }

    /// Records a failure in the trace once.
    fn note_failure(&mut self) {
        if !self.record {
            return;
        }
        if let Some(f) = &self.report.failure {
            if !self.events.iter().any(|e| e.kind == "failure") {
                let text = failure_text(f);
                self.event(Actor::Checker, "failure", text, false);
            }
        }
    }

    fn name(&self, m: MsgId) -> String {
        self.game().messages[m.index()].name.clone()
    }

    fn progressed(&mut self) {
        self.report.progress += 1;
        self.requests_since_progress = 0;
    }

    /// One scan: executes commands until the program waits. Returns whether it sent a request.
    /// Without a program nothing happens.
    fn scan(&mut self) -> bool {
        let Some(program) = self.program else { return false };
        let mut acted = false;
        let progress_before = self.report.progress;
        let mut executed = 0usize;
        // Whether the command run last was a request: the only place where a zeno loop is cut.
        let mut after_request = false;
        // A scan ends when control comes back to a command it already ran (a wait loop); it
        // then resumes at that command, the head of the loop, as the generated PLC code does.
        // Commands run in this scan (since its last request), by stamp: no set to clear.
        if self.visited.len() <= program.len() {
            self.visited = vec![0; program.len() + 1];
        }
        self.stamp = self.stamp.wrapping_add(1);
        if self.stamp == 0 {
            self.visited.fill(0);
            self.stamp = 1;
        }
        self.visited[self.pc.min(program.len())] = self.stamp;
        loop {
            executed += 1;
            if self.pc >= program.len() {
                self.report.failure = Some(Failure::ControllerLoops);
                return acted;
            }
            // Acting forever at one instant: a zeno controller. One that keeps making plan
            // progress is the specification's business (5.1; the PLC code spreads it over
            // scans); one that makes none is a failure. The cut comes right after a request, as
            // a PLC scan ends after writing its outputs, never between a test and the request it
            // guards (the plant could move in between). Without a request a scan ends within
            // the program's length (a wait loop), so this check ends every scan.
            if executed > ZENO_CUT && after_request {
                if self.report.progress == progress_before {
                    self.report.failure = Some(Failure::ControllerLoops);
                }
                return acted;
            }
            let c = program.commands[self.pc];
            after_request = matches!(c.instruction, Instruction::Do { .. });
            let truth = |sim: &Self, cond: &Condition| match cond {
                Condition::Message { message } => sim.pending == Some(*message) || sim.guard_values[(*message).index()],
                // `{c} WAIT k`: the timer has reached k (passed k when the bound is open), as the
                // PLC code tests it with `ET >= k`.
                Condition::Delay { clock, interval } => reached(interval, sim.w.timers[(*clock).index()]),
            };
            match c.instruction {
                Instruction::Do { .. } if !self.w.plant.instant_moves(MessageKind::Uncontrollable).is_empty() => {
                    return acted; // an instant reaction has priority: the controller acts after it
                }
                Instruction::Do { request } => {
                    let candidates = self.w.plant.moves_of(MessageKind::Controllable, request);
                    if candidates.is_empty() {
                        self.report.failure = Some(Failure::RequestRefused { request: self.name(request) });
                        return acted;
                    }
                    let k = self.rng.below(candidates.len() as u64) as usize;
                    let progress = self.w.plant.apply(&candidates[k]);
                    if progress {
                        self.progressed();
                    }
                    self.reset(c.resets);
                    self.report.requests += 1;
                    self.requests_since_progress += 1;
                    acted = true;
                    self.trace(TraceLine::Request(request));
                    if self.record {
                        let text = format!("?{} {}", self.name(request), self.move_text(&candidates[k]));
                        self.event(Actor::Controller, "request", text, progress);
                        self.sent.push(request);
                    }
                    self.stamp = self.stamp.wrapping_add(1);
                    if self.stamp == 0 {
                        self.visited.fill(0);
                        self.stamp = 1;
                    }
                    self.pc += 1;
                    if let Some(f) = self.w.failure() {
                        self.report.failure = Some(f);
                        return acted;
                    }
                }
                Instruction::Goto { target } => self.pc = self.pos[target.index()] as usize,
                Instruction::If { condition, target } => {
                    if truth(self, &condition) {
                        self.reset(c.resets);
                        self.consume(&condition);
                        self.pc = self.pos[target.index()] as usize;
                    } else {
                        self.pc += 1;
                    }
                }
                Instruction::WaitUntil { condition } => {
                    let awaited_guard =
                        matches!(condition, Condition::Message { message } if self.guards.contains(&message));
                    if awaited_guard || truth(self, &condition) {
                        self.reset(c.resets);
                        self.consume(&condition);
                        self.pc += 1;
                    } else {
                        return acted; // waits
                    }
                }
            }
            let at = self.pc.min(program.len());
            if std::mem::replace(&mut self.visited[at], self.stamp) == self.stamp {
                return acted; // a wait loop: back at a command of this scan without acting
            }
        }
    }

    fn reset(&mut self, resets: u64) {
        for (b, t) in self.w.timers.iter_mut().enumerate().skip(1) {
            if resets >> b & 1 == 1 {
                *t = 0;
            }
        }
    }

    /// An event is received once: a test that succeeds on it takes it.
    fn consume(&mut self, condition: &Condition) {
        if let Condition::Message { message } = condition {
            if self.pending == Some(*message) {
                self.pending = None;
            }
        }
    }

    fn check(&mut self) -> bool {
        if self.report.failure.is_none() {
            self.report.failure = self.w.failure();
        }
        if self.report.failure.is_none() && self.requests_since_progress > 1000 {
            self.report.failure = Some(Failure::NoProgress);
        }
        self.report.failure.is_some()
    }

    /// The enabled moves a step may take: the plant's reactions, and without a program the
    /// requests too (the caller plays the controller), in [`Plant::candidates`] order.
    fn candidates(&self) -> Vec<PlantMove> {
        if self.program.is_some() {
            self.w.plant.moves(&[MessageKind::Uncontrollable])
        } else {
            self.w.plant.moves(&[MessageKind::Controllable, MessageKind::Uncontrollable])
        }
    }

    fn is_reaction(&self, m: &PlantMove) -> bool {
        let (u, e) = m.parts[0];
        self.game().components[u].edges[e].kind == MessageKind::Uncontrollable
    }

    /// An instant reaction must be taken before anything else.
    fn is_urgent(&self, m: &PlantMove) -> bool {
        m.instant && self.is_reaction(m)
    }

    /// The moves a step may take now: the urgent ones when there are any, else every candidate.
    fn offered(&self) -> Vec<PlantMove> {
        if self.report.failure.is_some() || self.stuck {
            return Vec::new();
        }
        let all = self.candidates();
        if all.iter().any(|m| self.is_urgent(m)) {
            all.into_iter().filter(|m| self.is_urgent(m)).collect()
        } else {
            all
        }
    }

    /// The moves of [`Choice::Move`], by index.
    pub fn moves(&self) -> Vec<MoveView> {
        self.offered()
            .iter()
            .enumerate()
            .map(|(index, m)| {
                let reaction = self.is_reaction(m);
                MoveView {
                    index,
                    kind: if reaction { "reaction" } else { "request" },
                    message: self.name(m.message),
                    instant: m.instant,
                    text: format!("{}{} {}", if reaction { "!" } else { "?" }, self.name(m.message), self.move_text(m)),
                }
            })
            .collect()
    }

    /// `(button.released → pressing)`: the participating transitions.
    fn move_text(&self, m: &PlantMove) -> String {
        let game = self.game();
        let parts: Vec<String> = m
            .parts
            .iter()
            .map(|&(u, e)| {
                let a = &game.components[u];
                let edge = &a.edges[e];
                format!("{}.{} → {}", a.name, a.locations[edge.from.index()].name, a.locations[edge.to.index()].name)
            })
            .collect();
        format!("({})", parts.join(", "))
    }

    /// The longest delay now, in ticks: `None` when no time may pass, `Some(None)` unbounded.
    pub fn delay_room(&self) -> Option<Option<i64>> {
        if self.report.failure.is_some() || self.stuck || self.offered().iter().any(|m| self.is_urgent(m)) {
            return None;
        }
        match self.w.plant.room() {
            Some(0) => None,
            room => Some(room),
        }
    }

    /// Before every plant step: the last event is forgotten and the sensors are read anew.
    fn begin_step(&mut self) {
        self.pending = None;
        self.sent.clear();
        for i in 0..self.guards.len() {
            let g = self.guards[i];
            self.guard_values[g.index()] = self.rng.below(2) == 0;
        }
    }

    /// Takes a plant move (or, without a program, a request), then lets the controller scan.
    fn fire(&mut self, m: &PlantMove) {
        let progress = self.w.plant.apply(m);
        if progress {
            self.progressed();
        }
        let reaction = self.is_reaction(m);
        let sigil = if reaction { "!" } else { "?" };
        self.trace(TraceLine::Message { sigil, message: m.message });
        if self.record {
            let text = format!("{sigil}{} {}", self.name(m.message), self.move_text(m));
            let actor = if reaction { Actor::Plant } else { Actor::Controller };
            self.event(actor, if reaction { "reaction" } else { "request" }, text, progress);
        }
        if !reaction {
            self.report.requests += 1;
            self.requests_since_progress += 1;
        } else if self.observable.get(m.message.index()).copied().unwrap_or(true) {
            self.pending = Some(m.message);
        }
        if !self.check() {
            self.scan();
        }
    }

    /// One plant step: an urgent reaction, another reaction, or a delay during which the
    /// controller scans every tick. Returns false when the plant can neither move nor wait.
    fn plant_step(&mut self) -> bool {
        self.begin_step();
        let reactions = self.candidates();
        let urgent: Vec<usize> = (0..reactions.len()).filter(|&i| self.is_urgent(&reactions[i])).collect();
        let max = self.w.plant.room();
        let chosen = if !urgent.is_empty() {
            Some(urgent[self.rng.below(urgent.len() as u64) as usize])
        } else if !reactions.is_empty() && (max == Some(0) || self.rng.below(3) == 0) {
            Some(self.rng.below(reactions.len() as u64) as usize)
        } else {
            None
        };
        match chosen {
            Some(i) => self.fire(&reactions[i]),
            None => {
                let limit = max.unwrap_or(4 * TICKS).min(4 * TICKS);
                if limit == 0 {
                    self.trace(TraceLine::Text("the plant can neither move nor wait (timeout)"));
                    return false; // an exceptional timeout ends the run; not the controller's fault
                }
                let d = 1 + self.rng.below(limit as u64) as i64;
                for _ in 0..d {
                    self.tick();
                    if self.check() || self.scan() {
                        break; // the controller acted: the plant decides anew
                    }
                }
            }
        }
        true
    }

    /// Takes one step. An error (a move that is not offered, a delay the invariants forbid, a
    /// finished simulation) leaves the simulation as it was.
    pub fn apply(&mut self, choice: &Choice) -> Result<(), String> {
        if self.report.failure.is_some() || self.stuck {
            return Err("the simulation has ended: step back or reset".into());
        }
        match *choice {
            Choice::Random => {
                self.steps += 1;
                if !self.plant_step() {
                    self.stuck = true;
                    self.event(
                        Actor::Checker,
                        "stuck",
                        "the plant can neither move nor wait (a timeout)".into(),
                        false,
                    );
                }
                self.check();
            }
            Choice::Move { index } => {
                let offered = self.offered();
                let m = offered.get(index).ok_or_else(|| format!("no move {index}: {} offered", offered.len()))?;
                self.steps += 1;
                self.begin_step();
                self.fire(m);
            }
            Choice::Delay { ticks } => {
                let room = self.delay_room().ok_or("no time may pass now")?;
                if ticks < 1 {
                    return Err("a delay must be positive".into());
                }
                if let Some(r) = room.filter(|&r| ticks > r) {
                    return Err(format!("the invariants allow at most {} time units", units(r as f64 / TICKS as f64)));
                }
                self.steps += 1;
                self.begin_step();
                for _ in 0..ticks {
                    self.tick();
                    if self.check() || self.scan() {
                        break; // the controller acted (or something failed): the step ends here
                    }
                }
            }
        }
        self.note_failure();
        Ok(())
    }

    /// Where the simulation stands.
    pub fn view(&self) -> SimView {
        let game = self.game();
        let plant = &self.w.plant;
        let secs = |t: i64| t as f64 / TICKS as f64;
        let room = self.delay_room();
        let offered_empty = self.offered().is_empty();
        SimView {
            mode: if self.program.is_some() { "program" } else { "free" },
            time: secs(self.w.time),
            steps: self.steps,
            pc: self.program.map(|_| self.pc),
            locations: game
                .components
                .iter()
                .enumerate()
                .map(|(u, a)| UnitLocation {
                    unit: a.name.clone(),
                    location: a.locations[plant.locs[u].index()].name.clone(),
                })
                .collect(),
            plans: game
                .plans
                .iter()
                .enumerate()
                .map(|(p, plan)| {
                    let at = plant.plan_locs[p];
                    PlanView {
                        name: plan.name.clone(),
                        location: plan.locations[at.index()].name.clone(),
                        index: at.index().saturating_sub(usize::from(at > plan.failed)),
                        count: plan.locations.len() - 1,
                        failed: at == plan.failed,
                    }
                })
                .collect(),
            clocks: (1..game.clocks.len())
                .map(|c| ClockView {
                    name: game.clocks[c].name.clone(),
                    value: secs(plant.clocks[c]),
                    timer: self.program.map(|_| secs(self.w.timers[c])),
                })
                .collect(),
            guards: self
                .guards
                .iter()
                .map(|&g| GuardView { name: self.name(g), value: self.guard_values[g.index()] })
                .collect(),
            sent: self.sent.iter().map(|&m| self.name(m)).collect(),
            requests: self.report.requests,
            progress: self.report.progress,
            moves: self.moves(),
            can_delay: room.is_some(),
            max_delay: room.flatten().map(secs),
            failure: self.report.failure.clone(),
            failure_text: self.report.failure.as_ref().map(failure_text),
            stuck: self.stuck || (self.report.failure.is_none() && offered_empty && room.is_none()),
            events: self.events.clone(),
        }
    }
}

/// A number of time units, without trailing zeros: `1`, `0.375`.
fn units(v: f64) -> String {
    let text = format!("{v:.3}");
    text.trim_end_matches('0').trim_end_matches('.').to_string()
}

/// A failure in words.
pub fn failure_text(f: &Failure) -> String {
    match f {
        Failure::Assertion { text } => format!("assertion violated: {text}"),
        Failure::PlanFailed { plan, timeout: true } => format!("{plan} failed: a timeout clock exceeded its bound"),
        Failure::PlanFailed { plan, timeout: false } => format!("{plan} failed: a message it forbids occurred"),
        Failure::RequestRefused { request } => format!("request {request} refused: the plant cannot take it now"),
        Failure::ControllerLoops => "the controller loops at one instant without plan progress".into(),
        Failure::NoProgress => "no plan progress after 1000 requests".into(),
    }
}

/// Runs `program` against the plant of `game` for at most `steps` plant steps.
pub fn run(game: &Game, program: &Program, observable: &[bool], seed: u64, steps: usize) -> RunReport {
    let mut sim = Simulation::build(game, Some(program), observable, seed, false);
    for step in 0..steps {
        sim.report.steps = step;
        if sim.check() || !sim.plant_step() || sim.check() {
            break;
        }
    }
    sim.report.time = sim.w.time as f64 / TICKS as f64;
    if sim.report.failure.is_some() {
        sim.report.trace = sim.trace_text();
    }
    sim.report
}

/// The steps that play `line`, a path of edges of the explored `space` from its initial state
/// (a counter-play), on the concrete plant without a program (the caller plays the
/// controller): each message edge becomes the move of its message whose result lies in the
/// edge's target, each delay edge a delay into the middle of those that bring the clocks into
/// the target (none for waiting in the same locations; time in eighths, as in the simulation). Guard checks have
/// no concrete move and are skipped. Returns the steps that could be played and, if the line
/// could not be followed to its end, why.
///
/// A zone holds valuations from which the rest of the line is not possible (the shortest delay
/// into one state may put the clocks out of reach of the next one), so the targets are first
/// narrowed backwards along the line ([`feasible_sets`]) to the valuations from which the rest
/// of the line can still be played.
pub fn replay_line(
    game: &Game,
    split: &SplitGame,
    space: &StateSpace,
    line: &[EdgeId],
) -> (Vec<Choice>, Option<String>) {
    let mut sim = Simulation::build(game, None, &[], 0, false);
    let mut choices = Vec::new();
    let feasible = feasible_sets(split, space, line);
    if !sim.plant().is_in(split, space, space.initial) {
        return (choices, Some("the initial state of the plant is not the explored initial state".into()));
    }
    // Beyond the largest constant (of guards, invariants and plan bounds) every further delay
    // looks the same to the zones.
    let bounds = game.plans.iter().flat_map(|p| p.clocks.iter().map(|&(_, b)| b as i64));
    let largest = split.max_constant.iter().map(|&c| c as i64).chain(bounds).max().unwrap_or(0).max(0);
    let horizon = (largest + 2) * TICKS;
    // Only steps the simulation took are returned: the caller plays them again.
    let take = |sim: &mut Simulation, choice: Choice, choices: &mut Vec<Choice>| {
        let ok = sim.apply(&choice).is_ok();
        if ok {
            choices.push(choice);
        }
        ok
    };
    for (k, &id) in line.iter().enumerate() {
        let e = &space.edges[id.index()];
        let target = e.to;
        let in_target = |p: &Plant| {
            target == StateId::NONE
                || (p.is_in(split, space, target) && feasible[k + 1].contains_point(&p.clocks, p.ticks))
        };
        let limit = sim.delay_room().map_or(0, |room| room.unwrap_or(horizon).min(horizon));
        let stuck = |why: &str| {
            Some(format!(
                "move {} ({}) could not be played: {why}",
                k + 1,
                crate::timed::explain::describe_edge(game, split, e)
            ))
        };
        match (e.kind, e.label) {
            (EdgeKind::Guard, _) => continue,
            (EdgeKind::Timeout, _) => return (choices, stuck("it is a timeout, which leads to no state")),
            (EdgeKind::Delay, label) => {
                let fits: Vec<i64> = (0..=limit)
                    .filter(|&d| {
                        let mut p = sim.plant().clone();
                        p.delay(d);
                        in_target(&p)
                    })
                    .collect();
                let (Some(&lo), Some(&hi)) = (fits.first(), fits.last()) else {
                    return (choices, stuck("no delay brings the clocks into its target"));
                };
                // Waiting in the same locations takes no time of its own (the pieces' delays
                // do). A delay into a piece goes to the middle of its window, or half a unit
                // into an unbounded one: a point on the edge of a strict bound leaves the next
                // steps no room in eighths.
                let d = match label {
                    Label::Wait => lo,
                    _ if hi == limit => lo + ((hi - lo) / 2).min(TICKS / 2),
                    _ => lo + (hi - lo) / 2,
                };
                if d > 0 && !take(&mut sim, Choice::Delay { ticks: d }, &mut choices) {
                    return (choices, stuck("the delay was refused"));
                }
            }
            (_, Label::Message { message }) => {
                let reaction = e.kind == EdgeKind::Reaction;
                // The first delay (usually none) after which a move of this message lands in
                // the target: the concrete clocks may sit earlier in the zone than the move needs.
                let found = (0..=limit).find_map(|d| {
                    let mut p = sim.plant().clone();
                    p.delay(d);
                    let kinds = [if reaction { MessageKind::Uncontrollable } else { MessageKind::Controllable }];
                    p.moves(&kinds)
                        .into_iter()
                        .find(|m| {
                            let mut q = p.clone();
                            q.apply(m);
                            m.message == message && in_target(&q)
                        })
                        .map(|m| (d, m))
                });
                let Some((d, m)) = found else {
                    return (choices, stuck("no move of its message lands in its target"));
                };
                if d > 0 && !take(&mut sim, Choice::Delay { ticks: d }, &mut choices) {
                    return (choices, stuck("the delay before it was refused"));
                }
                let Some(index) = sim.offered().iter().position(|o| *o == m) else {
                    return (choices, stuck("an instant reaction must come first"));
                };
                if !take(&mut sim, Choice::Move { index }, &mut choices) {
                    return (choices, stuck("the move was refused"));
                }
            }
            _ => return (choices, stuck("it carries no message")),
        }
        if sim.failure().is_some() && k + 1 < line.len() {
            return (choices, Some(format!("the plant failed already after move {}", k + 1)));
        }
    }
    (choices, None)
}

/// For each state along `line` (the initial state, then each edge's target), the valuations of
/// its zone from which the rest of the line can be played: backwards from the last state, the
/// past of the next set for a delay edge, the valuations whose reset lands in it for a message
/// edge, the same set for a guard check. The sets are taken within each state's zone and pieces;
/// where a set would be empty (the zones' extrapolation), the state's zone stands in for it.
pub fn feasible_sets(split: &SplitGame, space: &StateSpace, line: &[EdgeId]) -> Vec<Dbm> {
    let mut states = vec![space.initial];
    states.extend(line.iter().map(|&e| space.edges[e.index()].to));
    let own = |s: StateId| -> Dbm {
        if s == StateId::NONE {
            return Dbm::unconstrained(space.dim);
        }
        let mut z = space.zone(s);
        let base = split.plant_count;
        let units =
            space.env(s).iter().enumerate().chain(space.plan(s).iter().enumerate().map(|(p, sub)| (base + p, sub)));
        for (u, &sub) in units {
            for &(c, piece) in &split.units[u].sublocs[sub.index()].pieces {
                let iv = &split.pieces[c.index()][piece as usize];
                let lower = if iv.lower_closed { Bound::le(-(iv.lower as i32)) } else { Bound::lt(-(iv.lower as i32)) };
                let upper = match iv.upper {
                    Some(u) if iv.upper_closed => Bound::le(u as i32),
                    Some(u) => Bound::lt(u as i32),
                    None => Bound::INFINITY,
                };
                z.constrain_interval(c.index(), lower, upper);
            }
        }
        z
    };
    let mut sets: Vec<Dbm> = states.iter().map(|&s| own(s)).collect();
    for k in (0..line.len()).rev() {
        let e = &space.edges[line[k].index()];
        let mut pre = sets[k + 1].clone();
        match e.kind {
            EdgeKind::Delay => pre.down(),
            EdgeKind::Request | EdgeKind::Reaction => {
                for c in 1..space.dim {
                    if e.resets >> c & 1 == 1 {
                        pre.constrain(c, 0, Bound::LE_ZERO);
                        pre.free(c);
                    }
                }
            }
            EdgeKind::Guard | EdgeKind::Timeout => {}
        }
        let mut narrowed = sets[k].clone();
        if e.to != StateId::NONE && narrowed.intersect(&pre) {
            sets[k] = narrowed;
        }
    }
    sets
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::timed::program::optimize::Context;

    fn lamp() -> (Game, Program) {
        let (game, _) = crate::timed::compile(include_str!("../../../examples/timed/lamp.tga")).unwrap();
        let synthesis = crate::timed::synthesize(&game, &Default::default(), &mut |_| true);
        let program = crate::timed::program::controller(&game, &synthesis).unwrap();
        (game, program)
    }

    fn message(game: &Game, name: &str) -> MsgId {
        MsgId::new(game.messages.iter().position(|m| m.name == name).unwrap())
    }

    /// The index of the offered move of `name`.
    fn pick(sim: &Simulation, name: &str) -> Choice {
        let moves = sim.moves();
        let m = moves.iter().find(|m| m.message == name).unwrap_or_else(|| panic!("{name} not in {moves:?}"));
        Choice::Move { index: m.index }
    }

    #[test]
    fn the_lamp_controller_follows_the_button_step_by_step() {
        let (game, program) = lamp();
        let observable = Context::from_game(&game).observable;
        let mut sim = Simulation::new(&game, Some(&program), &observable, 1);
        let view = sim.view();
        assert_eq!(view.mode, "program");
        assert_eq!(view.moves.iter().map(|m| m.message.as_str()).collect::<Vec<_>>(), ["press"]);
        assert_eq!((view.plans[0].index, view.plans[0].count), (0, 2), "waiting for the press, of two steps");
        let start_plan = view.plans[0].location.clone();
        // The user presses: the controller turns the lamp on in the same instant.
        sim.apply(&pick(&sim, "press")).unwrap();
        let view = sim.view();
        assert_eq!(view.sent, ["turn_on"]);
        assert!(view.locations.iter().any(|l| l.unit == "lamp" && l.location == "on"));
        assert_ne!(view.plans[0].location, start_plan, "the plan took its first step");
        assert_eq!(view.plans[0].index, 1);
        assert_eq!(view.progress, 1);
        // The button needs less than a time unit to settle: the invariant bounds the delay.
        assert_eq!(view.max_delay, Some(0.875));
        assert!(sim.apply(&Choice::Delay { ticks: 8 }).is_err(), "beyond the invariant");
        sim.apply(&Choice::Delay { ticks: 3 }).unwrap();
        assert_eq!(sim.view().time, 0.375);
        sim.apply(&pick(&sim, "press_settled")).unwrap();
        sim.apply(&pick(&sim, "release")).unwrap();
        let view = sim.view();
        assert_eq!(view.sent, ["turn_off"]);
        assert!(view.locations.iter().any(|l| l.unit == "lamp" && l.location == "off"));
        assert_eq!(view.progress, 2);
        assert!(view.failure.is_none());
        let kinds: Vec<&str> = view.events.iter().map(|e| e.kind).collect();
        assert_eq!(kinds, ["reaction", "request", "delay", "reaction", "reaction", "request"]);
        assert_eq!(view.events[2].duration, Some(0.375));
        assert!(view.events.iter().all(|e| e.step >= 1));
    }

    #[test]
    fn random_steps_are_the_runs_steps() {
        // `run` is a loop of random steps: the same seed gives the same run.
        let (game, program) = lamp();
        let observable = Context::from_game(&game).observable;
        for seed in 0..20 {
            let report = run(&game, &program, &observable, seed, 60);
            let mut sim = Simulation::new(&game, Some(&program), &observable, seed);
            for _ in 0..60 {
                if sim.apply(&Choice::Random).is_err() || sim.finished() {
                    break;
                }
            }
            assert_eq!(sim.view().time, report.time, "seed {seed}");
            assert_eq!(sim.view().progress, report.progress, "seed {seed}");
        }
    }

    #[test]
    fn a_wrong_program_fails_and_the_simulation_stops() {
        let (game, _) = lamp();
        let mut wrong = Program::new();
        let press = message(&game, "press");
        let off = message(&game, "turn_off");
        wrong.push(Instruction::WaitUntil { condition: Condition::Message { message: press } }, 0);
        wrong.push(Instruction::Do { request: off }, 0);
        let mut sim = Simulation::new(&game, Some(&wrong), &[], 0);
        sim.apply(&pick(&sim, "press")).unwrap();
        let view = sim.view();
        assert!(matches!(view.failure, Some(Failure::RequestRefused { .. })), "{:?}", view.failure);
        assert!(view.failure_text.unwrap().contains("turn_off"));
        assert!(view.moves.is_empty() && !view.can_delay);
        assert_eq!(view.events.last().unwrap().kind, "failure");
        assert!(sim.apply(&Choice::Random).is_err());
    }

    #[test]
    fn without_a_program_the_requests_are_moves() {
        let (game, _) = lamp();
        let mut sim = Simulation::new(&game, None, &[], 0);
        assert_eq!(sim.view().mode, "free");
        let mut names: Vec<String> = sim.moves().into_iter().map(|m| m.message).collect();
        crate::sort::sort(&mut names);
        assert_eq!(names, ["press", "turn_on"]);
        // Pressing without turning the lamp on: once the button has settled, an assertion fails.
        sim.apply(&pick(&sim, "press")).unwrap();
        sim.apply(&Choice::Delay { ticks: 1 }).unwrap();
        sim.apply(&pick(&sim, "press_settled")).unwrap();
        let view = sim.view();
        assert!(matches!(view.failure, Some(Failure::Assertion { .. })), "{:?}", view.failure);
        assert!(sim.finished());
    }

    #[test]
    fn the_concrete_state_lies_in_a_winning_state_along_a_run() {
        let (game, _) = crate::timed::compile(include_str!("../../../examples/timed/robot_arm.tga")).unwrap();
        let synthesis = crate::timed::synthesize(&game, &Default::default(), &mut |_| true);
        let program = crate::timed::program::controller(&game, &synthesis).unwrap();
        let observable = Context::from_game(&game).observable;
        let mut sim = Simulation::new(&game, Some(&program), &observable, 3);
        let space = &synthesis.solution.space;
        for step in 0..80 {
            let found = sim.plant().locate(&synthesis.split, space);
            assert!(
                found.first().is_some_and(|&s| space.is_winning(s)),
                "step {step}: {found:?} at {:?}",
                sim.view().locations
            );
            sim.apply(&Choice::Random).unwrap();
            assert!(sim.failure().is_none());
        }
    }
}
