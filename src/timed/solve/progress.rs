//! The progress condition: the nested fixpoint (attractor ranks, `progress_ranks`), the removal
//! of trapped states, and the final zeno cut of moves that do not decrease the ranks. The
//! strategy-directed search's use of the ranks (steering its choices, marking what it left
//! unexplored) is in `directed`.

use super::space::{Class, Edge, EdgeId, Removal, State, StateId, StateSpace};
use super::{Search, Solver};
use std::collections::VecDeque;

/// The rank of a state that never joins (see `Solver::progress_ranks`).
pub(super) const UNRANKED: u32 = u32::MAX;
/// A count of wanted moves that no joining target brings down (see `Solver::progress_ranks`).
const BLOCKED: u32 = u32::MAX;

impl<S: Search> Solver<'_, '_, S> {
    /// Progress (5.1, made exact): a winning strategy must, besides staying safe, make the plans
    /// progress again and again: every cycle of its plays must take a plan transition. This is
    /// a Büchi condition on top of the safety game, solved as the nested fixpoint
    /// `νZ. μY. Pre(progress into Z, or anything into Y)`: `progress_ranks` is the inner least
    /// fixpoint over the surviving states (Z); states it leaves out can be kept from progress
    /// forever and are removed, the removal propagated, until nothing more is lost.
    ///
    /// In the strategy-directed search the ranks are optimistic (an untried alternative or an
    /// unexpanded state counts as progress, `Search::COUNTING`), so what they remove is lost in
    /// the whole game; `Search::steer` then moves each choice of the strategy onto a
    /// rank-decreasing alternative, exploring what that needs. When nothing is removed and the
    /// strategy needs nothing new, every cycle of it makes progress.
    ///
    /// One round: returns whether anything changed (removed, chosen anew or queued).
    pub(super) fn enforce_progress(&mut self) -> bool {
        let ranks = self.progress_ranks(S::COUNTING);
        self.charge_ranking();
        if self.remove_trapped(&ranks) {
            return true;
        }
        if S::steer(self, &ranks) {
            return true;
        }
        self.keep_rank_decreasing(ranks);
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

    /// Accounts one ranking of the space (`progress_ranks`, or a walk like it) as work: it reads
    /// every state and move once. A search that ranks often (steering) is bounded by the work
    /// budget like one that expands. Returns `false` when the search must stop.
    pub(super) fn charge_ranking(&mut self) -> bool {
        self.charge((self.space.states.len() + self.space.edges.len()) as u64)
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
    pub(super) fn decreases(&self, ranks: &[u32], s: StateId, alt: EdgeId) -> bool {
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

    /// The end of the search: in every winning state, the alternatives that do not decrease the
    /// rank and lie on a cycle without progress are cut (as zeno moves), so that whatever the
    /// program selects among the moves left, every cycle of its plays makes plan progress.
    /// (Moves that decrease the rank form no cycle; a move on no such cycle cannot close one; so
    /// moves that cannot hurt, like a request the thesis's programs make on the way, are kept.)
    /// The ranks are the search's final ones (`Search::final_ranks`).
    fn keep_rank_decreasing(&mut self, ranks: Vec<u32>) {
        let live = |st: &State| st.removal.is_none() && st.expanded;
        let ranks = &S::final_ranks(self, ranks);
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
            let mut options_cut = 0;
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
                    options_cut += u32::from(e.class == Class::Option);
                }
            }
            if wait_cut {
                self.space.states[s.index()].wait_viable = false;
            }
            S::after_cut(self, s, options_cut);
        }
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
