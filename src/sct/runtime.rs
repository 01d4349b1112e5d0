//! The reference executor of the runtime framework (Göbe 2019, 5.1.3.2 and 6.3): synthesised
//! supervisors stepped cycle by cycle, as the generated PLC code steps them. It decides which
//! events occur, which are denied and which are enforced; it knows nothing of triggers and
//! signals (which events were detected is its input) nor of actions (resets and code are what
//! the caller does with its report). The generated code is checked against it, and the
//! playground steps it.
//!
//! One cycle, in the order of 6.3.4:
//! 1. timers advance by the cycle's elapsed time; a timer reaching its duration raises its
//!    timeout (an uncontrollable event);
//! 2. uncontrollable events — due timeouts first, then the detected ones in the order given —
//!    are tracked by every supervisor; they happened, so none is denied, but one that a
//!    supervisor's current state prohibits breaks the plant contract and is reported;
//! 3. the controller runs: each event it executes is checked by all supervisors and answered
//!    at once ([`Runtime::execute`]);
//! 4. the controllable events detected after the controller ran are checked the same way;
//! 5. enforcement: every supervisor whose current state enforces an event executes it, and
//!    goes on while its new state enforces another (a cascade, within the cycle). So an
//!    enforcement happens only if the controller's own reaction did not already leave the
//!    state. Supervisors do not track events enforced by others (6.4.2): another supervisor
//!    takes an enforced event only where it enforces that event itself; one that prohibits it
//!    is reported as a conflict (the event is executed: it preempts a hazard).
//!
//! An accepted controllable event is a commit (5.1.3.2): no supervisor changes state unless all
//! accept it; a denied event changes nothing. Every event that occurs (accepted, uncontrollable,
//! timeout or enforced) starts the timers it starts and stops those it stops. The thesis puts
//! uncontrollable detection after the controller in 5.1.3.2 and before it in 6.3.4; the
//! framework follows 6.3.4, because those events happened before the controller ran and it
//! reacts to them.

use super::check::TimerInfo;
use super::model::{EventId, EventKind, Project, Supervisor};
use serde::Serialize;

/// Why a set of supervisors cannot run.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum RuntimeError {
    /// The supervisor is void: its specification is unrealizable.
    Unrealizable { supervisor: String },
    /// A timer names an event the project does not know.
    UnknownTimerEvent { timer: String, event: String },
}

/// What happened to one event in a cycle.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum EventOutcome {
    /// It occurred and every supervisor tracked it.
    Accepted,
    /// Supervisor number `supervisor` prohibits it in its current state; nothing changed.
    Denied { supervisor: usize },
    /// An uncontrollable event that supervisor number `supervisor` prohibits in its current
    /// state: it happened anyway (the plant models said it could not); that supervisor keeps
    /// its state, the others track it.
    Unexpected { supervisor: usize },
    /// Enforced by supervisor number `by`.
    Enforced { by: usize },
    /// Enforced by supervisor `by`, although supervisor `prohibited_by` prohibits it (6.4.2).
    EnforcedDespite { by: usize, prohibited_by: usize },
}

/// One event of a cycle and its outcome, in the order the framework handled them.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub struct Step {
    pub event: EventId,
    pub outcome: EventOutcome,
}

/// The report of one cycle.
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize)]
pub struct CycleReport {
    pub steps: Vec<Step>,
}

impl CycleReport {
    /// Events that occurred this cycle, in order (denied ones excluded).
    pub fn occurred(&self) -> impl Iterator<Item = EventId> + '_ {
        self.steps.iter().filter(|s| !matches!(s.outcome, EventOutcome::Denied { .. })).map(|s| s.event)
    }

    /// Events denied this cycle, with the supervisor that denied each.
    pub fn denied(&self) -> impl Iterator<Item = (EventId, usize)> + '_ {
        self.steps.iter().filter_map(|s| match s.outcome {
            EventOutcome::Denied { supervisor } => Some((s.event, supervisor)),
            _ => None,
        })
    }

    /// Events enforced this cycle, in order.
    pub fn enforced(&self) -> impl Iterator<Item = EventId> + '_ {
        self.steps
            .iter()
            .filter(|s| matches!(s.outcome, EventOutcome::Enforced { .. } | EventOutcome::EnforcedDespite { .. }))
            .map(|s| s.event)
    }
}

/// The inputs of one cycle for [`Runtime::cycle`].
#[derive(Clone, Debug, Default)]
pub struct CycleInput {
    /// Time since the previous cycle, in milliseconds.
    pub elapsed_ms: u64,
    /// Uncontrollable events detected at the start of the cycle.
    pub uncontrollable: Vec<EventId>,
    /// Controllable events the controller executes, in its order.
    pub executed: Vec<EventId>,
    /// Controllable events detected after the controller ran.
    pub detected: Vec<EventId>,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum TimerState {
    Idle,
    Running {
        elapsed_ms: u64,
    },
    /// Reached its duration; a start event starts it anew, a stop event resets it.
    Expired,
}

struct Timer {
    duration_ms: u64,
    start: EventId,
    stop: Vec<EventId>,
    timeout: EventId,
    state: TimerState,
}

/// Supervisors running on a PLC: their current states and the timers.
pub struct Runtime<'a> {
    project: &'a Project,
    supervisors: Vec<&'a Supervisor>,
    states: Vec<u32>,
    timers: Vec<Timer>,
    /// The report of the cycle in progress.
    report: CycleReport,
}

impl<'a> Runtime<'a> {
    /// All supervisors in their initial states, all timers idle.
    pub fn new(
        project: &'a Project,
        supervisors: &[&'a Supervisor],
        timers: &[TimerInfo],
    ) -> Result<Runtime<'a>, RuntimeError> {
        let mut states = Vec::with_capacity(supervisors.len());
        for s in supervisors {
            states.push(s.init.ok_or_else(|| RuntimeError::Unrealizable { supervisor: s.name.clone() })?);
        }
        let event = |timer: &TimerInfo, name: &str| {
            project
                .event(name)
                .ok_or_else(|| RuntimeError::UnknownTimerEvent { timer: timer.name.clone(), event: name.to_string() })
        };
        let mut running = Vec::with_capacity(timers.len());
        for t in timers {
            running.push(Timer {
                duration_ms: t.duration_ms,
                start: event(t, &t.start)?,
                stop: t.stop.iter().map(|s| event(t, s)).collect::<Result<_, _>>()?,
                timeout: event(t, &t.timeout)?,
                state: TimerState::Idle,
            });
        }
        Ok(Runtime {
            project,
            supervisors: supervisors.to_vec(),
            states,
            timers: running,
            report: CycleReport::default(),
        })
    }

    /// The current state of every supervisor.
    pub fn states(&self) -> &[u32] {
        &self.states
    }

    /// The first supervisor that prohibits `e` in its current state, if any.
    pub fn prohibited_by(&self, e: EventId) -> Option<usize> {
        Supervisor::first_prohibiting(&self.supervisors, &self.states, e)
    }

    /// Supervisor `k`'s successor on `e` (an event without a transition loops).
    fn successor(&self, k: usize, e: EventId) -> u32 {
        self.supervisors[k].successor(self.states[k], e)
    }

    /// `e` occurred: every supervisor but `skip` tracks it, and the timers react.
    fn occur(&mut self, e: EventId, skip: Option<usize>) {
        for k in 0..self.supervisors.len() {
            if Some(k) != skip {
                self.states[k] = self.successor(k, e);
            }
        }
        self.timers_react(e);
    }

    /// A stop event resets its timers; a start event starts its timers unless they run (a TON
    /// whose input is already on).
    fn timers_react(&mut self, e: EventId) {
        for t in &mut self.timers {
            if t.stop.contains(&e) {
                t.state = TimerState::Idle;
            }
            if t.start == e && !matches!(t.state, TimerState::Running { .. }) {
                t.state = TimerState::Running { elapsed_ms: 0 };
            }
        }
    }

    /// Steps 1 and 2 of a cycle: the timers advance by `elapsed_ms`, then the due timeouts
    /// and the detected uncontrollable events occur.
    pub fn begin_cycle(&mut self, elapsed_ms: u64, uncontrollable: &[EventId]) {
        self.report = CycleReport::default();
        let mut due = Vec::new();
        for t in &mut self.timers {
            if let TimerState::Running { elapsed_ms: e } = t.state {
                let e = e.saturating_add(elapsed_ms);
                t.state = if e >= t.duration_ms {
                    due.push(t.timeout);
                    TimerState::Expired
                } else {
                    TimerState::Running { elapsed_ms: e }
                };
            }
        }
        for e in due.into_iter().chain(uncontrollable.iter().copied()) {
            let outcome = match self.prohibited_by(e) {
                Some(k) => {
                    self.occur(e, Some(k));
                    EventOutcome::Unexpected { supervisor: k }
                }
                None => {
                    self.occur(e, None);
                    EventOutcome::Accepted
                }
            };
            self.report.steps.push(Step { event: e, outcome });
        }
    }

    /// A controllable event the controller executes (step 3) or the framework detected after
    /// it (step 4): accepted and tracked by all supervisors unless one prohibits it. Returns
    /// whether it was accepted.
    pub fn execute(&mut self, e: EventId) -> bool {
        debug_assert_eq!(self.project.kind(e), EventKind::Controllable, "only controllable events are checked");
        let outcome = match self.prohibited_by(e) {
            Some(k) => EventOutcome::Denied { supervisor: k },
            None => {
                self.occur(e, None);
                EventOutcome::Accepted
            }
        };
        self.report.steps.push(Step { event: e, outcome });
        outcome == EventOutcome::Accepted
    }

    /// Step 5, enforcement, and the end of the cycle: returns its report.
    pub fn end_cycle(&mut self) -> CycleReport {
        for k in 0..self.supervisors.len() {
            // A cascade ends where no event is enforced; a cycle of enforcements is refused at
            // synthesis (5.5.5), and the bound keeps a hand-made one from hanging the PLC.
            for _ in 0..self.supervisors[k].states.len() {
                let Some(f) = self.supervisors[k].states[self.states[k] as usize].enforced else { break };
                let prohibited_by = self.prohibited_by(f);
                // Others take `f` only where they enforce it themselves (6.4.2).
                let also: Vec<usize> = (0..self.supervisors.len())
                    .filter(|&j| j != k && self.supervisors[j].states[self.states[j] as usize].enforced == Some(f))
                    .collect();
                let before = self.states[k];
                self.states[k] = self.successor(k, f);
                for j in also {
                    self.states[j] = self.successor(j, f);
                }
                self.timers_react(f);
                let outcome = match prohibited_by {
                    Some(j) => EventOutcome::EnforcedDespite { by: k, prohibited_by: j },
                    None => EventOutcome::Enforced { by: k },
                };
                self.report.steps.push(Step { event: f, outcome });
                if self.states[k] == before {
                    break; // enforced without leaving the state: once per cycle
                }
            }
        }
        std::mem::take(&mut self.report)
    }

    /// One whole cycle: [`begin_cycle`](Self::begin_cycle), the executed then the detected
    /// controllable events, [`end_cycle`](Self::end_cycle).
    pub fn cycle(&mut self, input: &CycleInput) -> CycleReport {
        self.begin_cycle(input.elapsed_ms, &input.uncontrollable);
        for &e in input.executed.iter().chain(&input.detected) {
            self.execute(e);
        }
        self.end_cycle()
    }
}
