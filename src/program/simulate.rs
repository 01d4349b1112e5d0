//! Closed-loop checking: a controller program run against the plant it was made for.
//!
//! The plant is the specification's own automata ([`crate::timed::plant`]), with concrete
//! clock values in eighths of a time unit; the controller is an interpreter of the intermediate
//! program under the scan-cycle model of 6.3: after every plant step it runs, in zero time,
//! until it waits. The plant chooses at random among its enabled reactions and delays within
//! the guards and invariants; `instant` transitions fire before anything else, and the
//! controller does not act while one is enabled. Each plant event is received once: the test
//! that succeeds on it takes it. A run fails if an
//! assertion is violated, a plan fails, the program sends a request the plant cannot take, or
//! the controller stops waiting or stops making plan progress.

use super::{Condition, Instruction, Program};
use crate::timed::model::{Game, Interval, MessageKind, MessageRole, MsgId};
use crate::timed::plant::{Move as PlantMove, Plant, Violation};
use serde::Serialize;

/// Clock values are counted in `1 / TICKS` time units.
pub const TICKS: i64 = 8;

#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Failure {
    Assertion { text: String },
    PlanFailed { plan: String },
    RequestRefused { request: String },
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
    /// The last steps, for diagnosis.
    pub trace: Vec<String>,
}

pub use crate::rng::Rng;

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
            Violation::Plan(k) => Failure::PlanFailed { plan: game.plans[k].name.clone() },
        })
    }
}

/// The state of one closed-loop run.
struct Run<'g, 'p> {
    w: World<'g>,
    program: &'p Program,
    pos: Vec<u32>,
    pc: usize,
    pending: Option<MsgId>,
    guards: Vec<MsgId>,
    guard_values: Vec<bool>,
    rng: Rng,
    report: RunReport,
    requests_since_progress: usize,
}

impl Run<'_, '_> {
    fn trace(&mut self, line: String) {
        let plans: Vec<String> = self
            .w
            .plant
            .game
            .plans
            .iter()
            .enumerate()
            .map(|(p, plan)| {
                let clocks: Vec<String> = plan
                    .clocks
                    .iter()
                    .map(|&(c, _)| {
                        format!(
                            "{}={:.3}",
                            self.w.plant.game.clocks[c as usize].name,
                            self.w.plant.clocks[c as usize] as f64 / TICKS as f64
                        )
                    })
                    .collect();
                format!(
                    "{}.{} {}",
                    plan.name,
                    plan.locations[self.w.plant.plan_locs[p] as usize].name,
                    clocks.join(" ")
                )
            })
            .collect();
        let clocks: Vec<String> = (1..self.w.plant.clocks.len())
            .map(|c| {
                format!(
                    "{}={:.3}/{:.3}",
                    self.w.plant.game.clocks[c].name,
                    self.w.plant.clocks[c] as f64 / TICKS as f64,
                    self.w.timers[c] as f64 / TICKS as f64
                )
            })
            .collect();
        let line = format!(
            "{line}   [pc {}; clock/timer {}{}{}]",
            self.pc,
            clocks.join(" "),
            if plans.is_empty() { "" } else { "; " },
            plans.join("; ")
        );
        self.report.trace.push(line);
        if self.report.trace.len() > 40 {
            self.report.trace.remove(0);
        }
    }

    fn name(&self, m: MsgId) -> String {
        self.w.plant.game.messages[m as usize].name.clone()
    }

    fn progressed(&mut self) {
        self.report.progress += 1;
        self.requests_since_progress = 0;
    }

    /// One scan: executes commands until the program waits. Returns whether it sent a request.
    fn scan(&mut self) -> bool {
        let mut acted = false;
        let progress_before = self.report.progress;
        let mut executed = 0usize;
        // A scan ends when control comes back to a command it already ran (a wait loop); it
        // then resumes at that command, the head of the loop, as the generated PLC code does.
        let mut seen = std::collections::HashSet::from([self.pc]);
        loop {
            executed += 1;
            if self.pc >= self.program.len() {
                self.report.failure = Some(Failure::ControllerLoops);
                return acted;
            }
            if executed > 10_000 {
                // Acting forever at one instant: a zeno controller. One that keeps making plan
                // progress is the specification's business (5.1; the PLC code spreads it over
                // scans); one that makes none is a failure.
                if self.report.progress == progress_before {
                    self.report.failure = Some(Failure::ControllerLoops);
                }
                return acted;
            }
            let c = self.program.commands[self.pc];
            let truth = |run: &Self, cond: &Condition| match cond {
                Condition::Message { message } => run.pending == Some(*message) || run.guard_values[*message as usize],
                // `{c} WAIT k`: the timer has reached k (passed k when the bound is open), as the
                // PLC code tests it with `ET >= k`.
                Condition::Delay { clock, interval } => reached(interval, run.w.timers[*clock as usize]),
            };
            match c.instruction {
                Instruction::Do { .. }
                    if self.w.plant.moves(&[MessageKind::Uncontrollable]).iter().any(|m| m.instant) =>
                {
                    return acted; // an instant reaction has priority: the controller acts after it
                }
                Instruction::Do { request } => {
                    let candidates: Vec<PlantMove> = self
                        .w
                        .plant
                        .moves(&[MessageKind::Controllable])
                        .into_iter()
                        .filter(|m| m.message == request)
                        .collect();
                    if candidates.is_empty() {
                        self.report.failure = Some(Failure::RequestRefused { request: self.name(request) });
                        return acted;
                    }
                    let k = self.rng.below(candidates.len() as u64) as usize;
                    if self.w.plant.apply(&candidates[k]) {
                        self.progressed();
                    }
                    self.reset(c.resets);
                    self.report.requests += 1;
                    self.requests_since_progress += 1;
                    acted = true;
                    let line = format!("{:.3}: DO ({})", self.w.time as f64 / TICKS as f64, self.name(request));
                    self.trace(line);
                    seen.clear();
                    self.pc += 1;
                    if let Some(f) = self.w.failure() {
                        self.report.failure = Some(f);
                        return acted;
                    }
                }
                Instruction::Goto { target } => self.pc = self.pos[target as usize] as usize,
                Instruction::If { condition, target } => {
                    if truth(self, &condition) {
                        self.reset(c.resets);
                        self.consume(&condition);
                        self.pc = self.pos[target as usize] as usize;
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
            if !seen.insert(self.pc) {
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

    /// One plant step: an urgent reaction, another reaction, or a delay during which the
    /// controller scans every tick. Returns false when the plant can neither move nor wait.
    fn plant_step(&mut self, observable: &[bool]) -> bool {
        self.pending = None;
        for i in 0..self.guards.len() {
            let g = self.guards[i];
            self.guard_values[g as usize] = self.rng.below(2) == 0;
        }
        let reactions = self.w.plant.moves(&[MessageKind::Uncontrollable]);
        let urgent: Vec<usize> = (0..reactions.len()).filter(|&i| reactions[i].instant).collect();
        let max = self.w.plant.room();
        let chosen = if !urgent.is_empty() {
            Some(urgent[self.rng.below(urgent.len() as u64) as usize])
        } else if !reactions.is_empty() && (max == Some(0) || self.rng.below(3) == 0) {
            Some(self.rng.below(reactions.len() as u64) as usize)
        } else {
            None
        };
        match chosen {
            Some(i) => {
                let m = &reactions[i];
                if self.w.plant.apply(m) {
                    self.progressed();
                }
                let line = format!("{:.3}: !{}", self.w.time as f64 / TICKS as f64, self.name(m.message));
                self.trace(line);
                if observable.get(m.message as usize).copied().unwrap_or(true) {
                    self.pending = Some(m.message);
                }
                if !self.check() {
                    self.scan();
                }
            }
            None => {
                let limit = max.unwrap_or(4 * TICKS).min(4 * TICKS);
                if limit == 0 {
                    self.trace("the plant can neither move nor wait (timeout)".into());
                    return false; // an exceptional timeout ends the run; not the controller's fault
                }
                let d = 1 + self.rng.below(limit as u64) as i64;
                for _ in 0..d {
                    self.w.delay(1);
                    if self.check() || self.scan() {
                        break; // the controller acted: the plant decides anew
                    }
                }
            }
        }
        true
    }
}

/// Runs `program` against the plant of `game` for at most `steps` plant steps.
pub fn run(game: &Game, program: &Program, observable: &[bool], seed: u64, steps: usize) -> RunReport {
    let guards: Vec<MsgId> =
        (0..game.messages.len() as MsgId).filter(|&m| game.messages[m as usize].role == MessageRole::Guard).collect();
    // Guard messages are sensor conditions (4.2.1): the environment sets them at random, anew
    // before every plant step, for the controller's IF tests. The game treats a guard check as
    // the controller's option (5.3.4), i.e. it assumes the guard holds when the controller
    // needs it: a WAITUNTIL on a guard is therefore satisfied at once.
    let mut run = Run {
        w: World { plant: Plant::new(game, TICKS), timers: vec![0; game.dim()], time: 0 },
        program,
        pos: program.positions(),
        pc: 0,
        pending: None,
        guard_values: vec![false; game.messages.len()],
        guards,
        rng: Rng::new(seed),
        report: RunReport { steps: 0, progress: 0, requests: 0, time: 0.0, failure: None, trace: Vec::new() },
        requests_since_progress: 0,
    };
    if !run.check() {
        run.scan();
    }
    for step in 0..steps {
        run.report.steps = step;
        if run.check() || !run.plant_step(observable) || run.check() {
            break;
        }
    }
    run.report.time = run.w.time as f64 / TICKS as f64;
    run.report
}
