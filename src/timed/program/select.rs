//! Request selection (Peter 2005, 6.4, algorithms 8 and 9): in each winning state, keep the one
//! controller decision that reaches the next plan goal soonest.
//!
//! As in algorithm 10, the controller sends a request whenever one survives; it waits only when
//! none does (or none can still reach a goal). Among the requests it picks the one with the
//! fewest moves to the nearest move that makes a plan progress (algorithm 9), computed for all
//! states at once by a backward breadth-first search over the winning space. Ties are broken
//! deterministically by the request's message name, then by the edge's position.

use crate::timed::model::Game;
use crate::timed::solve::{EdgeId, EdgeKind, StateId, StateKind, StateSpace};
use serde::Serialize;
use std::collections::VecDeque;

/// The controller's decision in one state.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(tag = "kind", content = "edge", rename_all = "lowercase")]
pub enum Choice {
    /// Send this request.
    Request(EdgeId),
    /// Let time pass (waiting for reactions, delays or guards).
    Wait,
}

/// A deterministic strategy: one decision per reachable winning state.
#[derive(Clone, Debug, Serialize)]
pub struct Strategy {
    /// Reachable strategy states in breadth-first order; the initial state first.
    pub states: Vec<StateId>,
    /// Decision per state id (meaningful for the states in `states`).
    pub choice: Vec<Choice>,
}

/// Moves from each winning state to the nearest plan progress, along winning states.
pub fn goal_distances(space: &StateSpace) -> Vec<u32> {
    let n = space.states.len();
    let mut dist = vec![u32::MAX; n];
    let mut preds: Vec<Vec<StateId>> = vec![Vec::new(); n];
    let mut queue = VecDeque::new();
    for s in space.state_ids() {
        if !space.is_winning(s) {
            continue;
        }
        for (_, e) in space.out_edges(s) {
            if !space.is_live(e) {
                continue;
            }
            if e.progress && dist[s.index()] == u32::MAX {
                dist[s.index()] = 1;
                queue.push_back(s);
            }
            preds[e.to.index()].push(s);
        }
    }
    while let Some(y) = queue.pop_front() {
        for &x in &preds[y.index()] {
            if dist[x.index()] == u32::MAX {
                dist[x.index()] = dist[y.index()] + 1;
                queue.push_back(x);
            }
        }
    }
    dist
}

/// Moves from taking edge `e` to the nearest plan progress (`u32::MAX`: none known).
pub(crate) fn edge_distance(space: &StateSpace, dist: &[u32], e: EdgeId) -> u32 {
    let edge = &space.edges[e.index()];
    if edge.progress {
        1
    } else {
        // An unexplored wait edge (strategy-directed search) leads nowhere known.
        dist.get(edge.to.index()).map_or(u32::MAX, |d| d.saturating_add(1))
    }
}

/// Edges by which the state lets time pass: its wait edge or its delays.
pub fn wait_edges(space: &StateSpace, s: StateId) -> impl Iterator<Item = EdgeId> + '_ {
    space.out_edges(s).filter(|(_, e)| e.kind == EdgeKind::Delay).map(|(id, _)| id)
}

/// Algorithm 8: the decision in every reachable winning state.
pub fn select(game: &Game, space: &StateSpace) -> Strategy {
    let n = space.states.len();
    let dist = goal_distances(space);
    let mut choice = vec![Choice::Wait; n];
    let mut seen = vec![false; n];
    let mut states = Vec::new();
    if !space.is_winning(space.initial) {
        return Strategy { states, choice };
    }
    let mut queue = VecDeque::from([space.initial]);
    seen[space.initial.index()] = true;
    while let Some(s) = queue.pop_front() {
        states.push(s);
        let waits: Vec<EdgeId> = wait_edges(space, s).collect();
        let wait_viable = !waits.is_empty() && waits.iter().all(|&e| space.is_live(&space.edges[e.index()]));
        let wait_distance = waits.iter().map(|&e| edge_distance(space, &dist, e)).min().filter(|_| wait_viable);
        let mut best: Option<(u32, u8, &str, EdgeId)> = None;
        for (id, e) in space.out_edges(s) {
            if e.kind != EdgeKind::Request || !space.is_live(e) {
                continue;
            }
            let name = match e.label {
                crate::timed::solve::Label::Message { message } => game.messages[message.index()].name.as_str(),
                _ => "",
            };
            let key = (edge_distance(space, &dist, id), 0u8, name, id);
            if best.is_none_or(|b| key < b) {
                best = Some(key);
            }
        }
        // As in algorithm 10, a surviving request is always preferred to waiting; waiting is
        // chosen only when no request can still reach a goal.
        if best.is_some_and(|b| b.0 == u32::MAX) && wait_distance.is_some() {
            best = None;
        }
        if let Some((_, _, _, id)) = best {
            choice[s.index()] = Choice::Request(id);
        }
        // A guard state's only move is its request.
        if space.states[s.index()].kind == StateKind::Guard {
            if let Some((id, _)) = space.out_edges(s).next() {
                choice[s.index()] = Choice::Request(id);
            }
        }
        for t in strategy_successors(space, s, choice[s.index()]) {
            if !seen[t.index()] {
                seen[t.index()] = true;
                queue.push_back(t);
            }
        }
    }
    Strategy { states, choice }
}

/// The successors of a state under the strategy: reactions and guard checks always (the
/// controller observes them first), then the chosen request, or the ways time can pass.
pub fn strategy_successors(space: &StateSpace, s: StateId, choice: Choice) -> Vec<StateId> {
    let mut out = Vec::new();
    for (id, e) in space.out_edges(s) {
        if !space.is_live(e) {
            continue;
        }
        let taken = match e.kind {
            EdgeKind::Reaction | EdgeKind::Guard => true,
            EdgeKind::Request => choice == Choice::Request(id),
            EdgeKind::Delay => choice == Choice::Wait,
            EdgeKind::Timeout => false,
        };
        if taken {
            out.push(e.to);
        }
    }
    out
}
