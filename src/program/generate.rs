//! Intermediate code generation (Peter 2005, 6.5, algorithm 10).
//!
//! Every strategy state becomes a command block entered at its first command. The block first
//! checks the plant's reactions and the state guards (`IF … THEN GOTO`), since the controller
//! must react before it acts; then it sends the chosen request (`DO`) and jumps to the
//! successor, or, when it waits, checks the delays and loops (`GOTO` its own entry). A state
//! reached by a message that waits continues unconditionally in its time-closed state.

use super::select::{Choice, Strategy};
use super::{Condition, Instruction, Program};
use crate::timed::model::Game;
use crate::timed::precompute::SplitGame;
use crate::timed::solve::{EdgeKind, Label, StateId, StateKind, StateSpace};

/// A generated program with, for every command, the state whose block it belongs to.
pub struct Generated {
    pub program: Program,
    pub origin: Vec<StateId>,
}

/// Algorithm 10 over the strategy states (initial state first, so its entry is label 0).
pub fn generate(_game: &Game, split: &SplitGame, space: &StateSpace, strategy: &Strategy) -> Generated {
    let mut program = Program::new();
    let mut entry = vec![u32::MAX; space.states.len()];
    for &s in &strategy.states {
        entry[s as usize] = program.fresh_id();
    }
    let mut origin = Vec::new();
    for &s in &strategy.states {
        let choice = strategy.choice[s as usize];
        let mut block: Vec<(Instruction, u64)> = Vec::new();
        let alive = |to: StateId| to != u32::MAX && space.is_winning(to);
        for (_, e) in space.out_edges(s) {
            if !alive(e.to) {
                continue;
            }
            if let (EdgeKind::Reaction | EdgeKind::Guard, Label::Message { message }) = (e.kind, e.label) {
                block.push((Instruction::If { condition: Condition::Message { message }, target: entry[e.to as usize] }, e.resets));
            }
        }
        match choice {
            Choice::Request(id) => {
                let e = &space.edges[id as usize];
                if let Label::Message { message } = e.label {
                    block.push((Instruction::Do { request: message }, e.resets));
                }
                block.push((Instruction::Goto { target: entry[e.to as usize] }, 0));
            }
            Choice::Wait => {
                let mut continued = false;
                for (_, e) in space.out_edges(s) {
                    if e.kind != EdgeKind::Delay || !alive(e.to) {
                        continue;
                    }
                    match e.label {
                        Label::Wait => {
                            block.push((Instruction::Goto { target: entry[e.to as usize] }, 0));
                            continued = true;
                        }
                        Label::Piece { clock, piece } => {
                            let interval = split.pieces[clock as usize][piece as usize];
                            block.push((Instruction::If { condition: Condition::Delay { clock, interval }, target: entry[e.to as usize] }, 0));
                        }
                        _ => {}
                    }
                }
                if !continued {
                    block.push((Instruction::Goto { target: entry[s as usize] }, 0));
                }
            }
        }
        debug_assert!(space.states[s as usize].kind != StateKind::Guard || matches!(choice, Choice::Request(_)));
        for (k, (instruction, resets)) in block.into_iter().enumerate() {
            if k == 0 {
                program.push_with_id(entry[s as usize], instruction, resets);
            } else {
                program.push(instruction, resets);
            }
            origin.push(s);
        }
    }
    Generated { program, origin }
}
