//! A controller as a circuit: state bits (latches) with next-state functions, and per goal (the
//! GR(1) strategy's memory: which guarantee's justice it pursues) the outputs as Boolean
//! functions of the latches and the inputs. This is the form of a GR(1) controller whose table
//! would have a state per monitor valuation (2^n on an arbiter of n clients): the circuit
//! grows with the specification, the table with its state space.
//!
//! One step, as the function block runs it in a scan: the outputs of the current goal are
//! computed from the latches and the inputs; the goal advances (cyclically) when its
//! `reached` condition holds; then every latch takes its next value, computed from the
//! latches, inputs and outputs of this step, all at once.

use super::machine::{Cube, Machine, Row, StateId};
use super::spec::{SignalId, Spec};
use hashbrown::HashMap;

/// A Boolean function of a circuit's latches and the step's signals.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Logic {
    Const(bool),
    Signal(SignalId),
    Latch(usize),
    Not(Box<Logic>),
    And(Vec<Logic>),
    Or(Vec<Logic>),
}

impl Logic {
    pub fn negated(p: Logic) -> Logic {
        match p {
            Logic::Const(b) => Logic::Const(!b),
            Logic::Not(q) => *q,
            p => Logic::Not(Box::new(p)),
        }
    }

    pub fn and(parts: Vec<Logic>) -> Logic {
        Logic::junction(parts, true)
    }

    pub fn or(parts: Vec<Logic>) -> Logic {
        Logic::junction(parts, false)
    }

    fn junction(parts: Vec<Logic>, conjunction: bool) -> Logic {
        let mut kept = Vec::with_capacity(parts.len());
        for part in parts {
            match part {
                Logic::Const(b) if b == conjunction => {}
                Logic::Const(_) => return Logic::Const(!conjunction),
                part => kept.push(part),
            }
        }
        match kept.len() {
            0 => Logic::Const(conjunction),
            1 => kept.pop().expect("one part"),
            _ if conjunction => Logic::And(kept),
            _ => Logic::Or(kept),
        }
    }

    /// Its value under the latches' and signals' values.
    pub fn eval(&self, latch: &impl Fn(usize) -> bool, signal: &impl Fn(SignalId) -> bool) -> bool {
        match self {
            Logic::Const(b) => *b,
            Logic::Signal(s) => signal(*s),
            Logic::Latch(b) => latch(*b),
            Logic::Not(p) => !p.eval(latch, signal),
            Logic::And(ps) => ps.iter().all(|p| p.eval(latch, signal)),
            Logic::Or(ps) => ps.iter().any(|p| p.eval(latch, signal)),
        }
    }

    /// The latches it reads.
    pub fn latches(&self, out: &mut Vec<usize>) {
        match self {
            Logic::Const(_) | Logic::Signal(_) => {}
            Logic::Latch(b) => out.push(*b),
            Logic::Not(p) => p.latches(out),
            Logic::And(ps) | Logic::Or(ps) => ps.iter().for_each(|p| p.latches(out)),
        }
    }

    /// The same function with latch `b` renamed `rename[b]`.
    pub fn renamed(&self, rename: &[usize]) -> Logic {
        match self {
            Logic::Latch(b) => Logic::Latch(rename[*b]),
            Logic::Not(p) => Logic::Not(Box::new(p.renamed(rename))),
            Logic::And(ps) => Logic::And(ps.iter().map(|p| p.renamed(rename)).collect()),
            Logic::Or(ps) => Logic::Or(ps.iter().map(|p| p.renamed(rename)).collect()),
            p => p.clone(),
        }
    }

    /// `a AND NOT b OR c`, with the names given (for reports and tests).
    pub fn to_text(&self, latch: &dyn Fn(usize) -> String, signal: &dyn Fn(SignalId) -> String) -> String {
        match self {
            Logic::Const(b) => if *b { "TRUE" } else { "FALSE" }.to_string(),
            Logic::Signal(s) => signal(*s),
            Logic::Latch(b) => latch(*b),
            Logic::Not(p) => match **p {
                Logic::Signal(_) | Logic::Latch(_) | Logic::Const(_) => format!("NOT {}", p.to_text(latch, signal)),
                _ => format!("NOT ({})", p.to_text(latch, signal)),
            },
            Logic::And(ps) => ps
                .iter()
                .map(|p| match p {
                    Logic::Or(_) => format!("({})", p.to_text(latch, signal)),
                    _ => p.to_text(latch, signal),
                })
                .collect::<Vec<_>>()
                .join(" AND "),
            Logic::Or(ps) => ps.iter().map(|p| p.to_text(latch, signal)).collect::<Vec<_>>().join(" OR "),
        }
    }

    /// Operators and operands in all: what a reader has to read.
    pub fn size(&self) -> usize {
        match self {
            Logic::Const(_) | Logic::Signal(_) | Logic::Latch(_) => 1,
            Logic::Not(p) => 1 + p.size(),
            Logic::And(ps) | Logic::Or(ps) => ps.iter().map(Logic::size).sum::<usize>() + ps.len().saturating_sub(1),
        }
    }
}

/// A state bit of a circuit.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Latch {
    /// A name that says what it remembers (`open_3`, `r0_prev`), unique in the circuit.
    pub name: String,
    /// What it remembers, in words.
    pub comment: String,
    pub init: bool,
    /// Its value at the next step: a function of the latches, the inputs and the outputs of
    /// this step.
    pub next: Logic,
}

/// What the controller does while it pursues one guarantee's justice.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Goal {
    /// Which justice, in words.
    pub comment: String,
    /// Per written signal, its value: a function of the latches (and, unless the circuit moves
    /// first, the inputs).
    pub writes: Vec<Logic>,
    /// When the justice is met on this step, after which the next goal is pursued: a function
    /// of the latches and the inputs.
    pub reached: Logic,
}

/// A complete deterministic controller as a circuit (see the module's documentation).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Circuit {
    pub reads: Vec<SignalId>,
    pub writes: Vec<SignalId>,
    /// A Moore circuit: the outputs read no input of the same step.
    pub moves_first: bool,
    pub latches: Vec<Latch>,
    /// At least one; the first is pursued first.
    pub goals: Vec<Goal>,
}

/// Where a circuit is: its latches and the goal it pursues.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct CircuitState {
    pub latches: Vec<bool>,
    pub goal: usize,
}

impl Circuit {
    pub fn initial(&self) -> CircuitState {
        CircuitState { latches: self.latches.iter().map(|l| l.init).collect(), goal: 0 }
    }

    /// One step from `state` on the inputs `read` (by signal): the outputs, in the order of
    /// [`Circuit::writes`], and the state after the step.
    pub fn step(&self, state: &CircuitState, read: &dyn Fn(SignalId) -> bool) -> (Vec<bool>, CircuitState) {
        let goal = &self.goals[state.goal];
        let latch = |b: usize| state.latches[b];
        let writes: Vec<bool> = goal.writes.iter().map(|f| f.eval(&latch, &read)).collect();
        let reached = goal.reached.eval(&latch, &read);
        let signal = |s: SignalId| match self.writes.iter().position(|&w| w == s) {
            Some(i) => writes[i],
            None => read(s),
        };
        let latches = self.latches.iter().map(|l| l.next.eval(&latch, &signal)).collect();
        let goal = if reached { (state.goal + 1) % self.goals.len() } else { state.goal };
        (writes, CircuitState { latches, goal })
    }

    /// The outputs' and conditions' size in all ([`Logic::size`]).
    pub fn size(&self) -> usize {
        let goals = self.goals.iter().flat_map(|g| g.writes.iter().chain([&g.reached]));
        goals.chain(self.latches.iter().map(|l| &l.next)).map(Logic::size).sum()
    }

    /// The circuit as a table: a state per latch valuation and goal reached from the initial
    /// one, a row per valuation of the reads. `None` past `max_states` states, or with more
    /// than 16 reads (the rows enumerate them).
    pub fn to_machine(&self, max_states: usize) -> Option<Machine> {
        if self.reads.len() > 16 {
            return None;
        }
        let mut states = vec![self.initial()];
        let mut index: HashMap<CircuitState, u32> = HashMap::new();
        index.insert(self.initial(), 0);
        let mut table = Vec::new();
        let mut i = 0;
        while i < states.len() {
            let state = states[i].clone();
            let mut rows = Vec::new();
            for valuation in 0..1u64 << self.reads.len() {
                let read = |s: SignalId| {
                    let k = self.reads.iter().position(|&r| r == s).expect("a read signal");
                    valuation >> k & 1 == 1
                };
                let (writes, next) = self.step(&state, &read);
                let write = writes.iter().enumerate().filter(|(_, &w)| w).fold(0u64, |m, (k, _)| m | 1 << k);
                let next = *index.entry(next.clone()).or_insert_with(|| {
                    states.push(next);
                    states.len() as u32 - 1
                });
                if states.len() > max_states {
                    return None;
                }
                rows.push(Row {
                    read: Cube { care: (1 << self.reads.len()) - 1, value: valuation },
                    write,
                    next: StateId(next),
                });
            }
            table.push(rows);
            i += 1;
        }
        Some(Machine {
            reads: self.reads.clone(),
            writes: self.writes.clone(),
            moves_first: self.moves_first,
            init: StateId(0),
            states: table,
        })
    }

    /// The circuit as text: the latches with their next values, then per goal its outputs and
    /// when it is reached.
    pub fn render(&self, spec: &Spec) -> String {
        let latch = |b: usize| self.latches[b].name.clone();
        let signal = |s: SignalId| spec.name(s).to_string();
        let text = |f: &Logic| f.to_text(&latch, &signal);
        let mut out = String::new();
        for l in &self.latches {
            out.push_str(&format!(
                "latch {} (initially {}): {}\n  next = {}\n",
                l.name,
                l.init,
                l.comment,
                text(&l.next)
            ));
        }
        for (g, goal) in self.goals.iter().enumerate() {
            out.push_str(&format!("goal {g}: {}\n", goal.comment));
            for (&s, f) in self.writes.iter().zip(&goal.writes) {
                out.push_str(&format!("  {} = {}\n", spec.name(s), text(f)));
            }
            if self.goals.len() > 1 {
                out.push_str(&format!("  goal {} when {}\n", (g + 1) % self.goals.len(), text(&goal.reached)));
            }
        }
        out
    }

    /// The JSON form of `plcsynth ltl --json`: latches (name, init, next) and goals (writes,
    /// reached), each function as text over the signals' and latches' names.
    pub fn to_json(&self, spec: &Spec) -> serde_json::Value {
        let latch = |b: usize| self.latches[b].name.clone();
        let signal = |s: SignalId| spec.name(s).to_string();
        let text = |f: &Logic| f.to_text(&latch, &signal);
        let latches: Vec<serde_json::Value> = self
            .latches
            .iter()
            .map(|l| serde_json::json!({ "name": l.name, "comment": l.comment, "init": l.init, "next": text(&l.next) }))
            .collect();
        let goals: Vec<serde_json::Value> = self
            .goals
            .iter()
            .map(|g| {
                let writes: serde_json::Map<String, serde_json::Value> =
                    self.writes.iter().zip(&g.writes).map(|(&s, f)| (signal(s), text(f).into())).collect();
                serde_json::json!({ "comment": g.comment, "writes": writes, "reached": text(&g.reached) })
            })
            .collect();
        serde_json::json!({ "moves_first": self.moves_first, "latches": latches, "goals": goals })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A toggle: `g` is the latch, which flips whenever `r` holds; two goals alternate on `r`.
    fn toggle() -> Circuit {
        let (r, g) = (SignalId(0), SignalId(1));
        Circuit {
            reads: vec![r],
            writes: vec![g],
            moves_first: false,
            latches: vec![Latch {
                name: "t".into(),
                comment: String::new(),
                init: false,
                next: Logic::or(vec![
                    Logic::and(vec![Logic::Latch(0), Logic::negated(Logic::Signal(r))]),
                    Logic::and(vec![Logic::negated(Logic::Latch(0)), Logic::Signal(g)]),
                ]),
            }],
            goals: vec![
                Goal { comment: String::new(), writes: vec![Logic::Signal(r)], reached: Logic::Signal(r) },
                Goal { comment: String::new(), writes: vec![Logic::Const(false)], reached: Logic::Const(true) },
            ],
        }
    }

    #[test]
    fn a_step_reads_this_steps_outputs_and_advances_the_goal() {
        let c = toggle();
        let (w, s) = c.step(&c.initial(), &|_| true);
        assert_eq!(w, vec![true]);
        assert_eq!(s, CircuitState { latches: vec![true], goal: 1 });
        let (w, s) = c.step(&s, &|_| true);
        assert_eq!(w, vec![false]);
        assert_eq!(s, CircuitState { latches: vec![false], goal: 0 });
        let m = c.to_machine(100).expect("small");
        m.validate().expect("a complete deterministic machine");
        // (t, goal): (F, 0), (T, 1), (T, 0), (F, 1).
        assert_eq!(m.states.len(), 4);
        let text = c.latches[0].next.to_text(&|b| c.latches[b].name.clone(), &|s| format!("s{}", s.0));
        assert_eq!(text, "t AND NOT s0 OR NOT t AND s1");
    }
}
