//! The strategy-directed search, the default: it builds one strategy rather than deciding the
//! whole game (see the module doc of `solve`). States are expanded depth first, and only those
//! the strategy needs (`demand`: the initial state, the targets of the plant's moves and of the
//! strategy's choices), so that a chosen line of play is followed to its end before others.
//! The targets of the controller's options and of delays are generated only when the strategy
//! tries them (`Search::deferred_targets`, `generate`). A freshly expanded state is decided
//! lazily: lost if a forced move is, else it chooses its first alternative (`choose`, in
//! `strategy`), the next only when the chosen one is lost. The progress condition is checked
//! as the space grows, with optimistic ranks that steer the choices (`steer_by_ranks`); at the
//! end the states no strategy needed, and those relying on them, are marked
//! `Removal::Unexplored`. What the reference does instead is in `exhaustive`. Inclusion and
//! dominance, the scan-game reductions only this search uses (`uses_inclusion`), stay in the
//! core, where states are created and lost.

use super::guide::ScanGuide;
use super::progress::{Counting, UNRANKED};
use super::space::{Class, Edge, EdgeId, Removal, State, StateId};
use super::strategy::{plan_goals, send_distances, Deferred};
use super::{Search, Solver};
use crate::timed::model::*;
use crate::timed::precompute::{SplitGame, SubLocId};
use crate::zone::Dbm;
use std::collections::VecDeque;

/// The strategy-directed search's own state.
pub(super) struct Directed<'g> {
    /// States the strategy needs expanded, the last needed on top (depth first).
    stack: Vec<StateId>,
    /// The targets of moves not tried yet, by `Edge::deferred`; taken when generated.
    pub(super) deferred: Vec<Option<Deferred>>,
    /// Per message with a sender: per location of the sender, how many transitions it needs at
    /// least before it can send the message (`u16::MAX` if never); the search's sense of
    /// direction towards the plans' goals.
    pub(super) send_distance: Vec<Vec<u16>>,
    /// Per plan and sub-location: the messages that take the plan to its next goal (not to
    /// failure).
    pub(super) plan_goals: Vec<Vec<Vec<MsgId>>>,
    /// The number of states at which to look for cycles without progress next (see
    /// `after_expansion`).
    next_progress_check: usize,
    /// In a scan game: the zero-time strategy that orders the commitments at a read.
    pub(super) guide: Option<&'g ScanGuide>,
    /// Switches `steer_by_ranks` has made so far, over all its calls.
    switches: usize,
}

impl<'g> Directed<'g> {
    pub(super) fn new(game: &Game, split: &SplitGame, guide: Option<&'g ScanGuide>) -> Directed<'g> {
        let goals = plan_goals(split);
        Directed {
            stack: Vec::new(),
            deferred: Vec::new(),
            send_distance: send_distances(game, &goals),
            plan_goals: goals,
            next_progress_check: 16,
            guide,
            switches: 0,
        }
    }
}

impl Search for Directed<'_> {
    /// Optimistic: an untried alternative or an unexpanded state counts as progress, so what the
    /// ranks remove is lost in the whole game.
    const COUNTING: Counting = Counting::Optimistic;

    /// Depth first: the state needed last.
    fn next_state(&mut self) -> Option<StateId> {
        self.stack.pop()
    }

    /// Not queued: only what the strategy needs is expanded (`need`).
    fn reached(&mut self, _: StateId) {}

    fn need(solver: &mut Solver<'_, '_, Self>, s: StateId) {
        solver.demand(s);
    }

    fn deferred_targets(&mut self) -> Option<&mut Vec<Option<Deferred>>> {
        Some(&mut self.deferred)
    }

    /// In the order the strategy tries them (see `alternative`): among options, plan progress
    /// first, then the nearer to the plans' goals (`try_order`).
    fn order(
        solver: &mut Solver<'_, '_, Self>,
        edges: Vec<Edge>,
        env: &[SubLocId],
        plan: &[SubLocId],
        zone: &Dbm,
    ) -> Option<Vec<Edge>> {
        let hints = solver.guide_hints(&edges, env, plan, zone);
        let keys: Vec<(u8, u32, bool)> = edges.iter().map(|e| solver.try_order(e, &hints)).collect();
        if solver.halt.is_some() {
            return None;
        }
        let mut order: Vec<usize> = (0..edges.len()).collect();
        crate::sort::sort_by_key(&mut order, |&i| keys[i]);
        Some(order.into_iter().map(|i| edges[i]).collect())
    }

    /// Lost if a forced move is; otherwise its forced successors are needed and it chooses its
    /// first alternative.
    fn decide(solver: &mut Solver<'_, '_, Self>, s: StateId) {
        let survey = solver.survey(s);
        if let Some(removal) = survey.dead_forced {
            solver.remove(s, removal);
            return;
        }
        solver.space.states[s.index()].wait_viable = survey.wait_viable();
        let st = &solver.space.states[s.index()];
        for id in st.out_ids() {
            let e = solver.space.edges[id.index()];
            if e.class == Class::Forced {
                solver.demand(e.to);
            }
        }
        solver.choose(s);
    }

    /// A cycle without progress is found as soon as it closes, not when the whole strategy is
    /// explored, so that a doomed choice is given up before much is explored below it. Checked
    /// when the space has grown by a quarter since the last check (amortised linear).
    fn after_expansion(solver: &mut Solver<'_, '_, Self>) {
        let states = solver.space.states.len();
        if states >= solver.search.next_progress_check {
            solver.search.next_progress_check = states + states / 4 + 16;
            let ranks = solver.progress_ranks(Counting::Optimistic);
            if solver.charge_ranking() && !solver.remove_trapped(&ranks) {
                solver.steer_by_ranks(&ranks);
            }
        }
    }

    /// If it was the choice, the next alternative not lost yet (`choose` moves on from `tried`,
    /// past every alternative lost, this one among them: the choice is not always the
    /// `tried`-th, `steer_by_ranks` may have moved it).
    fn alternative_lost(solver: &mut Solver<'_, '_, Self>, x: StateId, alt: EdgeId) {
        if solver.space.states[x.index()].choice == alt {
            solver.choose(x);
        }
    }

    fn steer(solver: &mut Solver<'_, '_, Self>, ranks: &[u32]) -> bool {
        solver.steer_by_ranks(ranks)
    }

    /// The greatest fixpoint over what was explored: a state left out is marked unexplored,
    /// with the survivors that rely on it (`unexplored_closure`); that can leave out a state
    /// whose rank rested on a move with progress into one (progress counts into surviving
    /// states only), so until nothing changes. The strategy's own states are never left out:
    /// its moves rank them.
    fn final_ranks(solver: &mut Solver<'_, '_, Self>, _optimistic: Vec<u32>) -> Vec<u32> {
        let live = |st: &State| st.removal.is_none() && st.expanded;
        loop {
            let ranks = solver.progress_ranks(Counting::Explored);
            let mut marked = Vec::new();
            for (s, st) in solver.space.states.iter_mut().enumerate() {
                if live(st) && ranks[s] == UNRANKED {
                    st.removal = Some(Removal::Unexplored);
                    marked.push(StateId::new(s));
                }
            }
            if marked.is_empty() {
                return ranks;
            }
            solver.unexplored_closure(marked);
        }
    }

    /// The strategy's own choice may have been cut where another alternative gave the state its
    /// rank: it moves there.
    fn after_cut(solver: &mut Solver<'_, '_, Self>, s: StateId, _options_cut: u32) {
        let choice = solver.space.states[s.index()].choice;
        let kept = |solver: &Solver<'_, '_, Self>, alt: EdgeId| {
            if alt == EdgeId::WAIT {
                solver.space.states[s.index()].wait_viable
            } else {
                solver.space.is_live(&solver.space.edges[alt.index()])
            }
        };
        if choice != EdgeId::NONE && !kept(solver, choice) {
            let mut k = 0;
            while let Some(alt) = solver.alternative(s, k) {
                k += 1;
                if kept(solver, alt) {
                    solver.space.states[s.index()].choice = alt;
                    break;
                }
            }
        }
    }

    /// States created but never needed are marked, so that the surviving states are exactly
    /// those whose every continuation under the strategy was explored.
    fn finish(solver: &mut Solver<'_, '_, Self>) {
        for st in &mut solver.space.states {
            if st.removal.is_none() && !st.expanded {
                st.removal = Some(Removal::Unexplored);
            }
        }
    }

    fn heap_bytes(&self) -> usize {
        self.stack.capacity() * std::mem::size_of::<StateId>()
            + self.deferred.capacity() * std::mem::size_of::<Option<Deferred>>()
    }
}

impl Solver<'_, '_, Directed<'_>> {
    /// Queues `s` for expansion if it still needs it.
    pub(super) fn demand(&mut self, s: StateId) {
        let st = &self.space.states[s.index()];
        if st.removal.is_none() && !st.expanded {
            self.search.stack.push(s);
        }
    }

    /// After a round of the progress condition that removed nothing: while the strategy lets
    /// some play cycle without progress (a state it reaches that its own moves do not rank),
    /// the first such state, from the initial state, whose choice does not decrease the
    /// (optimistic) rank of the whole explored game moves onto one that does, an explored one
    /// where possible. Returns whether anything changed (a choice, or something to explore).
    ///
    /// Leaving a cycle at one state often mends it for the others, so a search's first switch
    /// is made alone. But each round ranks the whole strategy again, so the rounds then take the first
    /// 1, 2, 4, 8, ... such states at once, and at least a quarter as many as the search has
    /// switched in all its calls so far: a game that needs hundreds of switches (a random
    /// specification's scan game needed 500 over 126 000 states, and six minutes when it took
    /// them one at a time) takes a logarithmic number of rounds instead of one per switch.
    fn steer_by_ranks(&mut self, ranks: &[u32]) -> bool {
        let mut changed = false;
        let mut switched = 0;
        // Each switch is onto a decreasing choice, so a state switches once; the bound only
        // guards against what generating targets may change on the way (the next round sees it).
        for _ in 0..ranks.len() {
            let strategy = self.progress_ranks(Counting::Strategy);
            let batch = switched.max(self.search.switches / 4).max(1);
            let switches = self.unranked_switches(ranks, &strategy, batch);
            if !self.charge_ranking() || switches.is_empty() {
                break;
            }
            for (s, alt) in switches {
                self.take(s, alt);
                switched += 1;
                self.search.switches += 1;
            }
            changed = true;
        }
        changed || !self.search.stack.is_empty()
    }

    /// For `steer_by_ranks`: walking the strategy breadth first from the initial state, the
    /// first `limit` states it reaches that `strategy` leaves unranked and whose choice does
    /// not decrease `ranks`, each with the alternative to take instead.
    fn unranked_switches(&self, ranks: &[u32], strategy: &[u32], limit: usize) -> Vec<(StateId, EdgeId)> {
        let mut switches = Vec::new();
        let mut seen = vec![false; self.space.states.len()];
        let mut queue = VecDeque::from([self.space.initial]);
        seen[self.space.initial.index()] = true;
        while let Some(s) = queue.pop_front() {
            let st = &self.space.states[s.index()];
            if st.removal.is_some() || !st.expanded {
                continue;
            }
            // A guard state generated since `ranks` keeps its choice until the next round.
            if strategy[s.index()] == UNRANKED
                && s.index() < ranks.len()
                && (st.choice == EdgeId::NONE || !self.decreases(ranks, s, st.choice))
            {
                let mut untried = None;
                let mut explored = None;
                let mut k = 0;
                while let Some(alt) = self.alternative(s, k) {
                    k += 1;
                    if !self.decreases(ranks, s, alt) {
                        continue;
                    }
                    if !self.needs_generation(s, alt) {
                        explored = Some(alt);
                        break;
                    }
                    untried.get_or_insert(alt);
                }
                if let Some(alt) = explored.or(untried) {
                    switches.push((s, alt));
                    if switches.len() == limit {
                        return switches;
                    }
                }
            }
            for (id, e) in self.space.out_edges(s) {
                let follows = match e.class {
                    Class::Forced => true,
                    Class::Option => id == st.choice,
                    Class::Wait => st.choice == EdgeId::WAIT,
                    Class::Inert => false,
                };
                if follows && e.to != StateId::NONE && !seen[e.to.index()] {
                    seen[e.to.index()] = true;
                    queue.push_back(e.to);
                }
            }
        }
        switches
    }

    /// Whether taking alternative `alt` of `s` needs a target generated first.
    fn needs_generation(&self, s: StateId, alt: EdgeId) -> bool {
        if alt == EdgeId::WAIT {
            self.space.out_edges(s).any(|(_, e)| e.class == Class::Wait && e.is_unexplored())
        } else {
            self.space.edges[alt.index()].is_unexplored()
        }
    }

    /// Makes `alt` the choice of `s`, generating its targets if needed and queuing them.
    fn take(&mut self, s: StateId, alt: EdgeId) {
        let out = self.space.states[s.index()].out_ids();
        let edges: Vec<EdgeId> = if alt == EdgeId::WAIT {
            out.clone().filter(|&id| self.space.edges[id.index()].class == Class::Wait).collect()
        } else {
            vec![alt]
        };
        for &id in &edges {
            if self.space.edges[id.index()].is_unexplored() {
                self.generate(id);
            }
        }
        self.space.states[s.index()].choice = alt;
        for &id in &edges {
            let to = self.space.edges[id.index()].to;
            if to != StateId::NONE {
                self.demand(to);
            }
        }
    }

    /// A surviving state that relies on a state just marked
    /// unexplored is not decided either, so it is marked too, backwards from `marked`: a plant
    /// reaction into one, or no request into a survivor and no waiting whose delays all survive.
    /// (Plan progress gives a state its rank whatever the move's target, so a ranked state off
    /// the strategy can lead into an unranked one.)
    fn unexplored_closure(&mut self, mut marked: Vec<StateId>) {
        while let Some(y) = marked.pop() {
            let mut id = self.space.states[y.index()].first_in;
            while id != EdgeId::NONE {
                let x = self.space.edges[id.index()].from;
                id = self.space.edges[id.index()].next_in;
                let xs = &self.space.states[x.index()];
                if xs.removal.is_none() && xs.expanded && !self.decided(x) {
                    self.space.states[x.index()].removal = Some(Removal::Unexplored);
                    marked.push(x);
                }
            }
        }
    }

    /// Whether the surviving state `s` keeps its plant reactions among the survivors and has a
    /// request into a survivor or can wait among them.
    fn decided(&self, s: StateId) -> bool {
        let space = &self.space;
        let (mut option, mut delays, mut delays_live, mut reaction) = (false, false, true, false);
        for (_, e) in space.out_edges(s) {
            match e.class {
                Class::Forced => {
                    if !space.is_live(e) {
                        return false;
                    }
                    reaction = true;
                }
                Class::Option => option |= space.is_live(e),
                Class::Wait => {
                    delays = true;
                    delays_live &= space.is_live(e);
                }
                Class::Inert => {}
            }
        }
        option || if delays { delays_live } else { reaction }
    }
}
