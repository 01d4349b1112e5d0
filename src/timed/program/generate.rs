//! Intermediate code generation (Peter 2005, 6.5, algorithm 10).
//!
//! Every strategy state becomes a command block entered at its first command. The block first
//! checks the plant's reactions and the state guards (`IF … THEN GOTO`), since the controller
//! must react before it acts; then it sends the chosen request (`DO`) and jumps to the
//! successor, or, when it waits, checks the delays and loops (`GOTO` its own entry). A state
//! reached by a message that waits continues unconditionally in its time-closed state.
//!
//! Several clocks may reach the ends of their pieces at the same instant; the solver then has
//! one delay edge per set of clocks that can move on together. Such a set is tested as a chain
//! of single-clock tests, larger sets first, each falling through to the next candidate when a
//! clock has not got there yet.

use super::select::{Choice, Strategy};
use super::{CmdId, Condition, Instruction, Program};
use crate::timed::model::{ClockId, ClockOwner, Game};
use crate::timed::precompute::SplitGame;
use crate::timed::solve::{EdgeKind, Label, StateId, StateKind, StateSpace};

/// A generated program with, for every command, the state whose block it belongs to.
pub struct Generated {
    pub program: Program,
    pub origin: Vec<StateId>,
}

/// The delay conditions meaning "every clock of `clocks` has entered the piece it has in state
/// `to`".
fn delay_conditions(game: &Game, split: &SplitGame, space: &StateSpace, to: StateId, clocks: u64) -> Vec<Condition> {
    let mut out = Vec::new();
    for clock in (1..64usize).filter(|c| clocks >> c & 1 == 1).map(ClockId::new) {
        let (unit, sub) = match game.clocks[clock.index()].owner {
            ClockOwner::Component(u) => (u.index(), space.env(to)[u.index()]),
            ClockOwner::Plan(p) => (split.plant_count + p as usize, space.plan(to)[p as usize]),
            ClockOwner::Reference => continue,
        };
        if let Some(&(_, piece)) = split.units[unit].sublocs[sub.index()].pieces.iter().find(|(c, _)| *c == clock) {
            out.push(Condition::Delay { clock, interval: split.pieces[clock.index()][piece as usize] });
        }
    }
    out
}

/// Algorithm 10 over the strategy states (initial state first, so its entry is label 0).
pub fn generate(game: &Game, split: &SplitGame, space: &StateSpace, strategy: &Strategy) -> Generated {
    let mut program = Program::new();
    let mut entry = vec![CmdId::NONE; space.states.len()];
    for &s in &strategy.states {
        entry[s.index()] = program.fresh_id();
    }
    let mut origin = Vec::new();
    for &s in &strategy.states {
        let choice = strategy.choice[s.index()];
        // (id, instruction, resets); the first command takes the state's entry id.
        let mut block: Vec<(Option<CmdId>, Instruction, u64)> = Vec::new();
        for (_, e) in space.out_edges(s) {
            if !space.is_live(e) {
                continue;
            }
            if let (EdgeKind::Reaction | EdgeKind::Guard, Label::Message { message }) = (e.kind, e.label) {
                block.push((
                    None,
                    Instruction::If { condition: Condition::Message { message }, target: entry[e.to.index()] },
                    e.resets,
                ));
            }
        }
        match choice {
            Choice::Request(id) => {
                let e = &space.edges[id.index()];
                if let Label::Message { message } = e.label {
                    block.push((None, Instruction::Do { request: message }, e.resets));
                }
                block.push((None, Instruction::Goto { target: entry[e.to.index()] }, 0));
            }
            Choice::Wait => {
                let mut continued = None;
                let mut delays: Vec<(Vec<Condition>, StateId)> = Vec::new();
                for (_, e) in space.out_edges(s) {
                    if e.kind != EdgeKind::Delay || !space.is_live(e) {
                        continue;
                    }
                    match e.label {
                        Label::Wait => continued = Some(e.to),
                        Label::Piece { clocks, .. } => {
                            delays.push((delay_conditions(game, split, space, e.to, clocks), e.to))
                        }
                        _ => {}
                    }
                }
                match continued {
                    Some(to) => block.push((None, Instruction::Goto { target: entry[to.index()] }, 0)),
                    None => {
                        crate::sort::sort_by_key(&mut delays, |(conds, _)| std::cmp::Reverse(conds.len()));
                        let heads: Vec<CmdId> = delays.iter().map(|_| program.fresh_id()).collect();
                        let waiting = program.fresh_id();
                        for (k, (conds, to)) in delays.iter().enumerate() {
                            let next = heads.get(k + 1).copied().unwrap_or(waiting);
                            let mut id = Some(heads[k]);
                            for (j, &condition) in conds.iter().enumerate() {
                                let last = j + 1 == conds.len();
                                let target = if last { entry[to.index()] } else { program.fresh_id() };
                                block.push((id, Instruction::If { condition, target }, 0));
                                if conds.len() > 1 {
                                    block.push((None, Instruction::Goto { target: next }, 0));
                                }
                                id = (!last).then_some(target);
                            }
                        }
                        block.push((Some(waiting), Instruction::Goto { target: entry[s.index()] }, 0));
                    }
                }
            }
        }
        debug_assert!(space.states[s.index()].kind != StateKind::Guard || matches!(choice, Choice::Request(_)));
        for (k, (id, instruction, resets)) in block.into_iter().enumerate() {
            let id = if k == 0 { entry[s.index()] } else { id.unwrap_or_else(|| program.fresh_id()) };
            program.push_with_id(id, instruction, resets);
            origin.push(s);
        }
    }
    Generated { program, origin }
}
