//! The progress condition: the nested fixpoint (attractor ranks, `progress_ranks`), the removal
//! of trapped states, steering the strategy by ranks, and the final zeno cut of moves that do
//! not decrease the ranks.

use super::space::{Class, Edge, EdgeId, Removal, State, StateId, StateSpace};
use super::Solver;

/// The rank of a state that never joins (see `Solver::progress_ranks`).
const UNRANKED: u32 = u32::MAX;
/// A count of wanted moves that no joining target brings down (see `Solver::progress_ranks`).
const BLOCKED: u32 = u32::MAX;
use std::collections::VecDeque;

impl Solver<'_, '_> {
    /// Progress (5.1, made exact): a winning strategy must, besides staying safe, make the plans
    /// progress again and again: every cycle of its plays must take a plan transition. This is
    /// a Büchi condition on top of the safety game, solved as the nested fixpoint
    /// `νZ. μY. Pre(progress into Z, or anything into Y)`: `progress_ranks` is the inner least
    /// fixpoint over the surviving states (Z); states it leaves out can be kept from progress
    /// forever and are removed, the removal propagated, until nothing more is lost.
    ///
    /// In the strategy-directed search the ranks are optimistic (an untried alternative or an
    /// unexpanded state counts as progress), so what they remove is lost in the whole game;
    /// `steer_by_ranks` then moves each choice of the strategy onto a rank-decreasing
    /// alternative, exploring what that needs. When nothing is removed and the strategy needs
    /// nothing new, every cycle of it makes progress.
    ///
    /// One round: returns whether anything changed (removed, chosen anew or queued).
    pub(super) fn enforce_progress(&mut self) -> bool {
        let ranks = self.progress_ranks(if self.lazy { Counting::Optimistic } else { Counting::Explored });
        if self.remove_trapped(&ranks) {
            return true;
        }
        if self.lazy && self.steer_by_ranks(&ranks) {
            return true;
        }
        self.keep_rank_decreasing(&ranks);
        false
    }

    /// Removes the surviving expanded states `ranks` leaves out (the plant, or the controller's
    /// own moves, keep their plays from progress) and propagates; returns whether there were any.
    pub(super) fn remove_trapped(&mut self, ranks: &[u32]) -> bool {
        let n = self.space.states.len();
        let trapped: Vec<StateId> = (0..n)
            .map(StateId::new)
            .filter(|&s| {
                let st = &self.space.states[s.index()];
                st.removal.is_none() && st.expanded && ranks[s.index()] == UNRANKED
            })
            .collect();
        if !trapped.is_empty() {
            let mut in_trap = vec![false; n];
            for &s in &trapped {
                in_trap[s.index()] = true;
            }
            // Inclusion: a cycle may close only because a move went to a state including its
            // zone (an earlier state of the same play, say), where the play itself moves on.
            // Such moves get their own states first; only a trap without them is removed. Each
            // move is unfolded once, so this ends.
            if self.covers.is_some() {
                let folded: Vec<EdgeId> = trapped
                    .iter()
                    .flat_map(|&s| self.space.out_edges(s))
                    .filter(|(_, e)| {
                        e.is_covered() && !e.progress && !e.zeno && in_trap.get(e.to.index()).copied().unwrap_or(false)
                    })
                    .map(|(id, _)| id)
                    .collect();
                if !folded.is_empty() {
                    for edge in folded {
                        self.unfold(edge);
                    }
                    self.propagate();
                    return true;
                }
            }
            for &s in &trapped {
                // The plant keeps the plays from progress if one of its moves stays in the trap;
                // otherwise every alternative of the controller does, and they are cut.
                // (A state added meanwhile, for a move whose cover was trapped, is not in the trap.)
                let stays = |e: &Edge| {
                    !e.progress
                        && !e.zeno
                        && e.to != StateId::NONE
                        && in_trap.get(e.to.index()).copied().unwrap_or(false)
                };
                let out = self.space.states[s.index()].out_ids();
                let culprit = out.clone().find(|&id| {
                    self.space.edges[id.index()].class == Class::Forced && stays(&self.space.edges[id.index()])
                });
                match culprit {
                    Some(edge) => {
                        self.space.edges[edge.index()].zeno = true;
                        self.remove(s, Removal::ZenoLoop { edge });
                    }
                    None => {
                        for id in out.clone() {
                            let e = &mut self.space.edges[id.index()];
                            if matches!(e.class, Class::Option | Class::Wait) && stays(e) {
                                e.zeno = true;
                            }
                        }
                        self.remove(s, Removal::NoMove);
                    }
                }
            }
            self.propagate();
            return true;
        }
        false
    }

    /// The inner fixpoint of `enforce_progress`: per surviving expanded state, the round in
    /// which it joined the states from which the controller can force plan progress (or, unless
    /// `counting` is `Explored`, reach something untried), [`UNRANKED`] if it never does. Along a
    /// move that makes no progress, a joining state relies only on states of lower rank.
    pub(super) fn progress_ranks(&self, counting: Counting) -> Vec<u32> {
        let optimistic = counting != Counting::Explored;
        let strategy = counting == Counting::Strategy;
        let space = &self.space;
        let n = space.states.len();
        let mut rank = vec![UNRANKED; n];
        // Per state: forced moves still waiting for their target (`BLOCKED`: a forced move is
        // lost), delays still waiting (`BLOCKED`: waiting cannot help), and whether some option
        // is good.
        let mut forced_wanted = vec![0u32; n];
        let mut waits_wanted = vec![BLOCKED; n];
        let mut option_good = vec![false; n];
        let mut queue = VecDeque::new();
        let joins = |f: u32, w: u32, o: bool| f == 0 && (o || w == 0);
        for s in (0..n).map(StateId::new) {
            let st = &space.states[s.index()];
            if st.removal.is_some() {
                continue;
            }
            if !st.expanded {
                if optimistic {
                    rank[s.index()] = 0;
                    queue.push_back(s);
                }
                continue;
            }
            let (mut forced, mut forced_any, mut blocked) = (0u32, false, false);
            // Counting only the strategy's moves: its choice and the plant's.
            let waiting = !strategy || st.choice == EdgeId::WAIT;
            let (mut waits, mut wait_edges, mut wait_blocked) = (0u32, 0u32, !st.wait_viable || !waiting);
            let mut good = false;
            for (id, e) in space.out_edges(s) {
                if strategy && e.class == Class::Option && id != st.choice {
                    continue;
                }
                // Good at once, never (lost or cut), or once its target joins.
                let status = if e.zeno || e.class == Class::Inert {
                    None
                } else if e.is_unexplored() {
                    optimistic.then_some(true)
                } else if e.to == StateId::NONE
                    || space.states[e.to.index()].removal.is_some()
                    || (!optimistic && !space.states[e.to.index()].expanded)
                {
                    // Counting only what was explored, an unexpanded target is not known to
                    // survive (the strategy-directed search marks it unexplored at the end).
                    None
                } else {
                    Some(e.progress)
                };
                match e.class {
                    Class::Forced => {
                        forced_any = true;
                        match status {
                            None => blocked = true,
                            Some(false) => forced += 1,
                            Some(true) => {}
                        }
                    }
                    Class::Option => good |= status == Some(true),
                    Class::Wait => {
                        wait_edges += 1;
                        match status {
                            None => wait_blocked = true,
                            Some(false) => waits += 1,
                            Some(true) => {}
                        }
                    }
                    Class::Inert => {}
                }
            }
            if blocked {
                // A lost forced move: the safety removal is on its way (or, counting only what
                // was explored, the state is left out); never counted down.
                forced_wanted[s.index()] = BLOCKED;
                continue;
            }
            let waits = if wait_blocked || (wait_edges == 0 && !forced_any) { BLOCKED } else { waits };
            forced_wanted[s.index()] = forced;
            waits_wanted[s.index()] = waits;
            option_good[s.index()] = good;
            if joins(forced, waits, good) {
                rank[s.index()] = 0;
                queue.push_back(s);
            }
        }
        while let Some(y) = queue.pop_front() {
            let mut id = space.states[y.index()].first_in;
            while id != EdgeId::NONE {
                let edge_id = id;
                let e = &space.edges[id.index()];
                id = e.next_in;
                let x = e.from.index();
                let xs = &space.states[x];
                if rank[x] != UNRANKED || xs.removal.is_some() || !xs.expanded || e.zeno || e.progress {
                    continue;
                }
                if strategy && e.class == Class::Option && edge_id != xs.choice {
                    continue;
                }
                match e.class {
                    Class::Forced if forced_wanted[x] != BLOCKED => forced_wanted[x] -= 1,
                    Class::Option => option_good[x] = true,
                    Class::Wait if waits_wanted[x] != BLOCKED => waits_wanted[x] -= 1,
                    Class::Forced | Class::Wait | Class::Inert => continue,
                }
                if joins(forced_wanted[x], waits_wanted[x], option_good[x]) {
                    rank[x] = rank[y.index()] + 1;
                    queue.push_back(StateId::new(x));
                }
            }
        }
        rank
    }

    /// Whether alternative `alt` (an option edge or `EdgeId::WAIT`) of `s` is good by `ranks`:
    /// every move it allows makes progress or reaches a lower rank (an untried move counts as
    /// good).
    fn decreases(&self, ranks: &[u32], s: StateId, alt: EdgeId) -> bool {
        // States generated after the ranks were computed are unexpanded: optimistic rank 0.
        let rank = |t: StateId| ranks.get(t.index()).copied().unwrap_or(0);
        let own = rank(s);
        let good = |e: &Edge| {
            if e.zeno {
                return false;
            }
            if e.is_unexplored() {
                return true;
            }
            e.to != StateId::NONE && self.space.is_winning(e.to) && (e.progress || rank(e.to) < own)
        };
        if alt == EdgeId::WAIT {
            let st = &self.space.states[s.index()];
            st.wait_viable && self.space.out_edges(s).filter(|(_, e)| e.class == Class::Wait).all(|(_, e)| good(e))
        } else {
            good(&self.space.edges[alt.index()])
        }
    }

    /// Strategy-directed search, after a round that removed nothing: while the strategy lets
    /// some play cycle without progress (a state it reaches that its own moves do not rank),
    /// the first such state, from the initial state, whose choice does not decrease the
    /// (optimistic) rank of the whole explored game moves onto one that does, an explored one
    /// where possible. One switch at a time: leaving a cycle at one state mends it for the
    /// others. Returns whether anything changed (a choice, or something to explore).
    pub(super) fn steer_by_ranks(&mut self, ranks: &[u32]) -> bool {
        let mut changed = false;
        // Each switch is onto a decreasing choice, so a state switches once; the bound only
        // guards against what generating targets may change on the way (the next round sees it).
        for _ in 0..ranks.len() {
            let strategy = self.progress_ranks(Counting::Strategy);
            let Some((s, alt)) = self.first_unranked_switch(ranks, &strategy) else { break };
            self.take(s, alt);
            changed = true;
        }
        changed || !self.queue.is_empty()
    }

    /// For `steer_by_ranks`: walking the strategy breadth first from the initial state, the
    /// first state it reaches that `strategy` leaves unranked and whose choice does not
    /// decrease `ranks`, with the alternative to take instead.
    fn first_unranked_switch(&self, ranks: &[u32], strategy: &[u32]) -> Option<(StateId, EdgeId)> {
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
                let mut k = 0;
                while let Some(alt) = self.alternative(s, k) {
                    k += 1;
                    if !self.decreases(ranks, s, alt) {
                        continue;
                    }
                    if !self.needs_generation(s, alt) {
                        return Some((s, alt));
                    }
                    untried.get_or_insert(alt);
                }
                if let Some(alt) = untried {
                    return Some((s, alt));
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
        None
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

    /// The end of the search: in every winning state, the alternatives that do not decrease the
    /// rank and lie on a cycle without progress are cut (as zeno moves), so that whatever the
    /// program selects among the moves left, every cycle of its plays makes plan progress.
    /// (Moves that decrease the rank form no cycle; a move on no such cycle cannot close one; so
    /// moves that cannot hurt, like a request the thesis's programs make on the way, are kept.)
    /// In the strategy-directed search, surviving states outside the ranks (needed by no
    /// strategy, and not decided) are marked unexplored.
    fn keep_rank_decreasing(&mut self, ranks: &[u32]) {
        let live = |st: &State| st.removal.is_none() && st.expanded;
        let final_ranks;
        let ranks = if self.lazy {
            // The greatest fixpoint over what was explored: a state left out is marked
            // unexplored, with the survivors that rely on it (`unexplored_closure`); that can
            // leave out a state whose rank rested on a move with progress into one (progress
            // counts into surviving states only), so until nothing changes. The strategy's own
            // states are never left out: its moves rank them.
            final_ranks = loop {
                let ranks = self.progress_ranks(Counting::Explored);
                let mut marked = Vec::new();
                for (s, st) in self.space.states.iter_mut().enumerate() {
                    if live(st) && ranks[s] == UNRANKED {
                        st.removal = Some(Removal::Unexplored);
                        marked.push(StateId::new(s));
                    }
                }
                if marked.is_empty() {
                    break ranks;
                }
                self.unexplored_closure(marked);
            };
            &final_ranks
        } else {
            ranks
        };
        // Components of the winning states under their live moves without progress.
        let space = &self.space;
        let nodes: Vec<StateId> = space.state_ids().filter(|&s| live(&space.states[s.index()])).collect();
        let mut index = vec![None; space.states.len()];
        let mut graph = petgraph::Graph::<(), ()>::with_capacity(nodes.len(), 0);
        for &s in &nodes {
            index[s.index()] = Some(graph.add_node(()));
        }
        for &s in &nodes {
            for (_, e) in space.out_edges(s) {
                if e.progress || e.zeno || e.class == Class::Inert || e.to == StateId::NONE {
                    continue;
                }
                if let (Some(from), Some(to)) = (index[s.index()], index[e.to.index()]) {
                    graph.add_edge(from, to, ());
                }
            }
        }
        // Kosaraju: iterative, and a chain of moves without progress can be deeper than the stack.
        let mut component = vec![None; space.states.len()];
        for (c, scc) in petgraph::algo::kosaraju_scc(&graph).iter().enumerate() {
            for &i in scc {
                component[nodes[i.index()].index()] = Some(c);
            }
        }
        drop(graph);
        let on_cycle = |space: &StateSpace, e: &Edge| {
            !e.progress
                && e.to != StateId::NONE
                && component[e.to.index()].is_some()
                && component[e.to.index()] == component[e.from.index()]
                && space.is_winning(e.to)
        };
        for s in nodes {
            let out = self.space.states[s.index()].out_ids();
            let wait_cut = !self.decreases(ranks, s, EdgeId::WAIT)
                && out.clone().any(|id| {
                    let e = &self.space.edges[id.index()];
                    e.class == Class::Wait && !e.zeno && on_cycle(&self.space, e)
                });
            for id in out.clone() {
                let e = self.space.edges[id.index()];
                let cut = !e.zeno
                    && match e.class {
                        Class::Option => on_cycle(&self.space, &e) && !self.decreases(ranks, s, id),
                        Class::Wait => wait_cut,
                        _ => false,
                    };
                if cut {
                    self.space.edges[id.index()].zeno = true;
                    if e.class == Class::Option && !self.lazy {
                        self.space.states[s.index()].options_alive -= 1;
                    }
                }
            }
            if wait_cut {
                self.space.states[s.index()].wait_viable = false;
            }
            // The strategy's own choice may have been cut where another alternative gave the
            // state its rank: it moves there.
            let choice = self.space.states[s.index()].choice;
            let kept = |solver: &Self, alt: EdgeId| {
                if alt == EdgeId::WAIT {
                    !wait_cut && solver.space.states[s.index()].wait_viable
                } else {
                    solver.space.is_live(&solver.space.edges[alt.index()])
                }
            };
            if self.lazy && choice != EdgeId::NONE && !kept(self, choice) {
                let mut k = 0;
                while let Some(alt) = self.alternative(s, k) {
                    k += 1;
                    if kept(self, alt) {
                        self.space.states[s.index()].choice = alt;
                        break;
                    }
                }
            }
        }
    }
}

impl Solver<'_, '_> {
    /// Strategy-directed search: a surviving state that relies on a state just marked
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

/// Which moves `Solver::progress_ranks` counts on.
#[derive(Clone, Copy, PartialEq, Eq)]
pub(super) enum Counting {
    /// Every explored move; nothing untried.
    Explored,
    /// Every explored move, and an untried alternative or an unexpanded state as progress.
    Optimistic,
    /// Only the strategy's choices and the plant's moves, untried ones as progress.
    Strategy,
}
