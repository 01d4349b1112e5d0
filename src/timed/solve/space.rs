//! The explored game graph: states, edges and their classes, why a state was removed, and the
//! accessors the rest of the crate reads a solved space with.

use crate::id::id_type;
use crate::timed::arena::SliceArena;
use crate::timed::model::*;
use crate::timed::precompute::SubLocId;
use crate::zone::{Bound, Dbm};
use serde::Serialize;
use std::collections::VecDeque;

id_type! {
    /// A state: an index into [`StateSpace::states`].
    #[derive(Serialize)]
    #[serde(transparent)]
    pub struct StateId;
}

impl StateId {
    /// No state: the target of a timeout or a zeno repetition, which lead nowhere.
    pub const NONE: StateId = StateId::from_raw(u32::MAX);
}

id_type! {
    /// An edge: an index into [`StateSpace::edges`].
    #[derive(Serialize)]
    #[serde(transparent)]
    pub struct EdgeId;
}

impl EdgeId {
    /// No edge: the end of an in-edge list, and the choice of a state that has none.
    pub const NONE: EdgeId = EdgeId::from_raw(u32::MAX);
    /// The choice of a state whose strategy lets time pass (or the plant move): no one edge,
    /// but stored where the chosen option's id goes.
    pub(super) const WAIT: EdgeId = EdgeId::from_raw(u32::MAX - 1);
}

/// What kind of move an edge is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum EdgeKind {
    /// `?m`: a controller request.
    Request,
    /// `!m`: a plant reaction.
    Reaction,
    /// `%g`: a state guard checked before a request.
    Guard,
    /// Time passes: to the time-closed state, or into the next piece of a clock.
    Delay,
    /// Time passes beyond a plant invariant: the exceptional timeout of 5.2.2.
    Timeout,
}

impl EdgeKind {
    pub fn sigil(self) -> &'static str {
        match self {
            EdgeKind::Request => "?",
            EdgeKind::Reaction => "!",
            EdgeKind::Guard => "%",
            EdgeKind::Delay => "D",
            EdgeKind::Timeout => "T",
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Class {
    Forced,
    Option,
    Wait,
    Inert,
}

/// What an edge carries.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(tag = "kind", rename_all = "lowercase")]
pub enum Label {
    Message {
        message: MsgId,
    },
    /// Waiting in the current locations.
    Wait,
    /// Time passes until `clock` enters piece `piece`; `clocks` (a bit set) holds every clock
    /// that enters its next piece at the same instant, `clock` included.
    Piece {
        clock: ClockId,
        piece: u16,
        clocks: u64,
    },
    /// Time passes beyond the invariant on `clock`.
    Overrun {
        clock: ClockId,
    },
}

#[derive(Clone, Copy, Debug)]
pub struct Edge {
    pub from: StateId,
    /// [`StateId::NONE`] for timeouts and for zeno repetitions (see [`Edge::target`]).
    pub to: StateId,
    pub kind: EdgeKind,
    pub label: Label,
    /// Clocks reset by the move, as a bit set over clock ids.
    pub resets: u64,
    pub instant: bool,
    /// The move returns to a plant state visited since the last plan progress.
    pub zeno: bool,
    /// Some plan reached a goal (took a transition) with this move.
    pub progress: bool,
    pub(super) class: Class,
    pub(super) next_in: EdgeId,
    /// A move whose target is not generated yet: its index in the search's deferred targets
    /// (`Search::deferred_targets`, strategy-directed search); [`NOT_DEFERRED`] once generated
    /// or in the reference.
    pub(super) deferred: u32,
    /// Inclusion (scan games): `to` is a state whose zone includes the move's own target zone,
    /// this one (interned); [`NO_ZONE`] when `to` is the move's own target. Should `to` be lost,
    /// the move is given the state of its own zone (`Solver::retarget_covered`).
    pub(super) exact: u32,
}

/// [`Edge::deferred`] of a move whose target is generated (or never was deferred).
pub(super) const NOT_DEFERRED: u32 = u32::MAX;
/// [`Edge::exact`] of a move whose target has the move's own zone (no interned zone is meant).
pub(super) const NO_ZONE: u32 = u32::MAX;

impl Edge {
    /// The state the move leads to; `None` for a timeout or a zeno repetition.
    #[inline]
    pub fn target(&self) -> Option<StateId> {
        (self.to != StateId::NONE).then_some(self.to)
    }

    /// A controller option or delay the strategy-directed search never needed to try: `to` is
    /// [`StateId::NONE`].
    pub fn is_unexplored(&self) -> bool {
        self.deferred != NOT_DEFERRED
    }

    /// A move whose target is a state that includes its own zone (inclusion, see
    /// `Config::inclusion`; the zone is [`StateSpace::own_zone`]).
    pub fn is_covered(&self) -> bool {
        self.exact != NO_ZONE
    }
}

/// Why a state was removed.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Removal {
    /// The state violates assertion number `rule`.
    Assertion { rule: u32 },
    /// Plan number `plan` has failed (forbidden message or timeout).
    PlanFailed { plan: u32 },
    /// Nothing can happen any more: no move and no time can pass usefully.
    Deadlock,
    /// A forced move (plant reaction or passing time) leads to a removed state.
    Forced { edge: EdgeId },
    /// A plant reaction returns to a plant state visited since the last plan progress.
    ZenoLoop { edge: EdgeId },
    /// Every controller move leads to a removed state and waiting is not possible.
    NoMove,
    /// Not lost, but never explored: the strategy found does not pass through this state, so
    /// nothing is known about what follows it (strategy-directed search only).
    Unexplored,
    /// Lost on arrival because state `by`, of the same locations and kind, is lost and its zone
    /// lies in this one's once plan clocks may be lower there (dominance, the dual of
    /// inclusion: see `Config::dominance`). Not expanded.
    Dominated { by: StateId },
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum StateKind {
    /// Reached by a message: the controller may act at once.
    Entry,
    /// Time-closed: reached by waiting; only the plant and time move.
    Waiting,
    /// Time-closed and reached by a delay: the controller may act, or wait further.
    Interval,
    /// The intermediate state of a state guard (5.3.4).
    Guard,
}

impl StateKind {
    /// The name the JSON views use.
    pub fn name(self) -> &'static str {
        match self {
            StateKind::Entry => "entry",
            StateKind::Waiting => "waiting",
            StateKind::Interval => "interval",
            StateKind::Guard => "guard",
        }
    }
}

#[derive(Clone, Debug)]
pub struct State {
    pub env: u32,
    pub plan: u32,
    pub zone: u32,
    pub kind: StateKind,
    pub removal: Option<Removal>,
    pub expanded: bool,
    /// The outgoing edges, `out_start..out_end` in [`StateSpace::edges`].
    pub(super) out_start: EdgeId,
    pub(super) out_end: EdgeId,
    /// The first incoming edge; the list goes on through [`Edge::next_in`].
    pub(super) first_in: EdgeId,
    /// Exhaustive reference: how many options lead to surviving states (the strategy-directed
    /// search keeps its choice instead).
    pub(super) options_alive: u32,
    pub(super) wait_viable: bool,
    pub(super) vis: u32,
    /// Strategy-directed search: the alternative (option edge id, or [`EdgeId::WAIT`]) the
    /// strategy takes here, and how many alternatives were tried and lost before it.
    pub(super) choice: EdgeId,
    pub(super) tried: u32,
}

impl State {
    pub(super) fn new(env: u32, plan: u32, zone: u32, kind: StateKind, removal: Option<Removal>, vis: u32) -> State {
        State {
            env,
            plan,
            zone,
            kind,
            removal,
            expanded: false,
            out_start: EdgeId::new(0),
            out_end: EdgeId::new(0),
            first_in: EdgeId::NONE,
            options_alive: 0,
            wait_viable: false,
            vis,
            choice: EdgeId::NONE,
            tried: 0,
        }
    }

    /// The ids of the outgoing edges.
    #[inline]
    pub(super) fn out_ids(&self) -> impl Iterator<Item = EdgeId> + Clone {
        (self.out_start.raw()..self.out_end.raw()).map(EdgeId::from_raw)
    }
}

/// The explored game graph with the surviving (winning) and removed states.
pub struct StateSpace {
    pub dim: usize,
    pub states: Vec<State>,
    pub edges: Vec<Edge>,
    pub initial: StateId,
    pub(super) envs: SliceArena<SubLocId>,
    pub(super) plans: SliceArena<SubLocId>,
    pub(super) zones: SliceArena<Bound>,
    pub(super) plant_count: usize,
}

impl StateSpace {
    /// A space without states: what a search refused before it started leaves.
    pub fn empty(dim: usize, plant_count: usize, plan_count: usize) -> StateSpace {
        StateSpace {
            dim,
            states: Vec::new(),
            edges: Vec::new(),
            initial: StateId::new(0),
            envs: SliceArena::new(plant_count),
            plans: SliceArena::new(plan_count),
            zones: SliceArena::new(dim * dim),
            plant_count,
        }
    }

    /// True if state `s` exists and was not removed.
    pub fn is_winning(&self, s: StateId) -> bool {
        self.states.get(s.index()).is_some_and(|st| st.removal.is_none())
    }

    /// True if the edge leads to a winning state and was not cut as a zeno loop.
    pub fn is_live(&self, e: &Edge) -> bool {
        e.to != StateId::NONE && !e.zeno && self.is_winning(e.to)
    }

    /// The ids of all states, in order.
    pub fn state_ids(&self) -> impl Iterator<Item = StateId> {
        (0..self.states.len()).map(StateId::new)
    }

    /// Sub-locations of the plant units in state `s`.
    pub fn env(&self, s: StateId) -> &[SubLocId] {
        self.envs.get(self.states[s.index()].env)
    }

    /// Sub-locations of the plans in state `s`.
    pub fn plan(&self, s: StateId) -> &[SubLocId] {
        self.plans.get(self.states[s.index()].plan)
    }

    pub fn zone(&self, s: StateId) -> Dbm {
        Dbm::from_slice(self.dim, self.zones.get(self.states[s.index()].zone))
    }

    /// The zone move `e` itself leads to, where its target is a state whose zone includes it
    /// (inclusion, see `Config::inclusion`); `None` where the target's zone is the move's.
    pub fn own_zone(&self, e: &Edge) -> Option<Dbm> {
        e.is_covered().then(|| Dbm::from_slice(self.dim, self.zones.get(e.exact)))
    }

    pub fn out_edges(&self, s: StateId) -> impl Iterator<Item = (EdgeId, &Edge)> {
        self.states[s.index()].out_ids().map(move |e| (e, &self.edges[e.index()]))
    }

    pub fn plant_count(&self) -> usize {
        self.plant_count
    }

    /// Surviving states reachable from the initial state through surviving states.
    pub fn winning_states(&self) -> Vec<StateId> {
        let mut seen = vec![false; self.states.len()];
        let mut order = Vec::new();
        if !self.is_winning(self.initial) {
            return order;
        }
        seen[self.initial.index()] = true;
        let mut queue = VecDeque::from([self.initial]);
        while let Some(s) = queue.pop_front() {
            order.push(s);
            for t in self.out_edges(s).filter_map(|(_, e)| e.target()) {
                if !seen[t.index()] && self.is_winning(t) {
                    seen[t.index()] = true;
                    queue.push_back(t);
                }
            }
        }
        order
    }
}
