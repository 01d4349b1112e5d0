//! The zero-time game's winning strategy read as a guide for the scan game's strategy-directed
//! search (`directed`).
//!
//! A scan game's controller decides at each read what to commit; the plant has not moved yet,
//! so the search's sense of direction (plan progress, distance to the goals) cannot tell the
//! commitments apart by their targets. Where the zero-time controller wins, what it does in a
//! plant state is usually what a PLC reading that plant state should commit: the search tries
//! that first. A guide only orders the alternatives: every one is still tried before a read is
//! given up, so the verdict is the same with or without it.

use super::space::{EdgeId, EdgeKind, Label, StateId, StateKind};
use super::Solution;
use crate::timed::model::{LocId, MsgId};
use crate::timed::precompute::{SplitGame, SubLocId};
use crate::zone::Dbm;

/// What the zero-time strategy does in a state.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Hint {
    Request(MsgId),
    Wait,
}

/// The decisions of a zero-time winning strategy, by plant and plan locations, each with the
/// future of the zone where it is taken (in the scan game's time units, see `scan::rescaled`).
pub struct ScanGuide {
    plant_count: usize,
    dim: usize,
    by_locations: hashbrown::HashMap<Vec<LocId>, Vec<(Dbm, Hint)>>,
}

impl ScanGuide {
    /// The guide of a solved zero-time game in the time units of the scan game (see
    /// `scan::rescaled`); `None` unless its controller wins.
    pub fn new(split: &SplitGame, solution: &Solution) -> Option<ScanGuide> {
        let space = &solution.space;
        if !space.is_winning(space.initial) {
            return None;
        }
        let mut by_locations: hashbrown::HashMap<Vec<LocId>, Vec<(Dbm, Hint)>> = hashbrown::HashMap::new();
        for s in space.winning_states() {
            let st = &space.states[s.index()];
            if st.kind == StateKind::Guard || st.kind == StateKind::Waiting {
                continue;
            }
            let Some(hint) = decision(space, s) else { continue };
            let mut zone = space.zone(s);
            // The PLC reads a change up to a scan after it happens: compare with the zone's future.
            zone.up();
            let key = locations(split, space.env(s), space.plan(s));
            let hints = by_locations.entry(key).or_default();
            if !hints.iter().any(|(z, h)| *h == hint && *z == zone) {
                hints.push((zone, hint));
            }
        }
        Some(ScanGuide { plant_count: split.plant_count, dim: space.dim, by_locations })
    }

    /// The decisions for a read of the scan game (split `split`) in sub-locations `env`, `plan`
    /// and zone `zone`: those whose zone meets the read's, else every decision taken in those
    /// locations.
    pub(super) fn hints(&self, split: &SplitGame, env: &[SubLocId], plan: &[SubLocId], zone: &Dbm) -> Vec<Hint> {
        let mut key = locations(split, &env[..self.plant_count], &[]);
        key.extend(
            plan.iter().enumerate().map(|(p, &s)| split.units[split.plant_count + p].sublocs[s.index()].location),
        );
        let Some(candidates) = self.by_locations.get(&key) else { return Vec::new() };
        // The read's zone without the scan clock (the last one).
        let read = project(zone, self.dim);
        let meeting: Vec<Hint> =
            candidates.iter().filter(|(z, _)| z.clone().intersect(&read)).map(|&(_, hint)| hint).collect();
        if meeting.is_empty() {
            candidates.iter().map(|&(_, hint)| hint).collect()
        } else {
            meeting
        }
    }
}

/// What the strategy does in the winning state `s`: its request (through any guard checks), or
/// waiting.
fn decision(space: &super::StateSpace, mut s: StateId) -> Option<Hint> {
    loop {
        let choice = space.states[s.index()].choice;
        if choice == EdgeId::WAIT {
            return Some(Hint::Wait);
        }
        if choice == EdgeId::NONE {
            return None;
        }
        let edge = space.edges[choice.index()];
        match (edge.kind, edge.label) {
            (EdgeKind::Request, Label::Message { message }) => return Some(Hint::Request(message)),
            (EdgeKind::Guard, _) if edge.to != StateId::NONE => s = edge.to,
            _ => return None,
        }
    }
}

/// The original locations of the plant units and plans.
fn locations(split: &SplitGame, env: &[SubLocId], plan: &[SubLocId]) -> Vec<LocId> {
    let plant = env.iter().enumerate().map(|(u, &s)| split.units[u].sublocs[s.index()].location);
    let plans = plan.iter().enumerate().map(|(p, &s)| split.units[split.plant_count + p].sublocs[s.index()].location);
    plant.chain(plans).collect()
}

/// `zone` restricted to its first `dim` indices (a canonical zone stays canonical).
fn project(zone: &Dbm, dim: usize) -> Dbm {
    let mut bounds = Vec::with_capacity(dim * dim);
    for i in 0..dim {
        for j in 0..dim {
            bounds.push(zone.get(i, j));
        }
    }
    Dbm::from_slice(dim, &bounds)
}
