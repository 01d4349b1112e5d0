//! Removal: the survey of an expanded state's edges that the local rule reads, and the
//! backward propagation of removed states (algorithm 6); how a lost alternative changes its
//! state is the search's (`Search::alternative_lost`).

use super::space::{Class, EdgeId, Label, Removal, StateId, NO_ZONE};
use super::zeno::Vis;
use super::{Search, Solver};

impl<S: Search> Solver<'_, '_, S> {
    /// One pass over the edges of an expanded state: what the local rule of the module doc needs.
    pub(super) fn survey(&self, s: StateId) -> Survey {
        let st = &self.space.states[s.index()];
        let mut survey = Survey { wait_ok: true, all_inert: true, ..Survey::default() };
        for id in st.out_ids() {
            let e = &self.space.edges[id.index()];
            let alive = e.to != StateId::NONE && self.space.states[e.to.index()].removal.is_none();
            survey.all_inert &= e.class == Class::Inert;
            match e.class {
                Class::Forced => {
                    survey.forced_any = true;
                    if !alive && survey.dead_forced.is_none() {
                        let removal =
                            if e.zeno { Removal::ZenoLoop { edge: id } } else { Removal::Forced { edge: id } };
                        survey.dead_forced = Some(removal);
                    }
                }
                Class::Option => survey.options_alive += u32::from(alive),
                Class::Wait => {
                    survey.wait_edges += 1;
                    // A delay not generated yet (strategy-directed search) is not lost yet.
                    survey.wait_ok &= alive || e.is_unexplored();
                }
                Class::Inert => {}
            }
        }
        survey
    }

    pub(super) fn remove(&mut self, s: StateId, reason: Removal) {
        let st = &mut self.space.states[s.index()];
        if st.removal.is_none() {
            st.removal = Some(reason);
            self.removed += 1;
            let key = (st.env, st.plan, st.kind);
            self.lost_queue.push(s);
            if self.losses.is_some() && self.monotone_loss(s, reason) {
                if self.monotone.len() <= s.index() {
                    self.monotone.resize(s.index() + 1, false);
                }
                self.monotone[s.index()] = true;
                if let Some(losses) = self.losses.as_mut() {
                    losses.entry(key).or_default().push(s);
                }
            }
            if self.covers.is_some() {
                self.retarget_covered(s);
            }
        }
    }

    /// Dominance: whether the loss of `s` (for `reason`) carries over to every state of its
    /// locations and kind whose zone includes its own, plan clocks higher: a violation, or
    /// reached from violations through plant reactions, lost requests and lost delays alone
    /// (the larger zone has the same moves, into larger zones). Not a loss for want of time
    /// passing (a deadlock, or no delay and no reaction: a larger zone may let time pass), on a
    /// cycle without progress, or through a move cut or never tried.
    fn monotone_loss(&self, s: StateId, reason: Removal) -> bool {
        let monotone = |t: StateId| {
            t != StateId::NONE
                && match self.space.states[t.index()].removal {
                    Some(Removal::Assertion { .. } | Removal::PlanFailed { .. } | Removal::Dominated { .. }) => true,
                    Some(_) => self.monotone.get(t.index()).copied().unwrap_or(false),
                    None => false,
                }
        };
        match reason {
            Removal::Assertion { .. } | Removal::PlanFailed { .. } => true,
            Removal::Forced { edge } => {
                let e = &self.space.edges[edge.index()];
                !e.zeno && monotone(e.to)
            }
            Removal::NoMove => {
                // Waiting fails for good if a delay leads to such a loss, or if an instant move
                // is enabled: that depends on the sub-locations alone (every piece of a clock is
                // a sub-location), so the larger zone cannot wait either.
                let (mut wait_lost, mut urgent) = (false, false);
                for (_, e) in self.space.out_edges(s) {
                    urgent |= e.instant;
                    match e.class {
                        Class::Option if e.zeno || !monotone(e.to) => return false,
                        Class::Wait if e.zeno => return false,
                        Class::Wait => wait_lost |= monotone(e.to),
                        _ => {}
                    }
                }
                wait_lost || urgent
            }
            _ => false,
        }
    }

    /// Algorithm 6: removes, backwards, every state that can no longer avoid a removed one.
    pub(super) fn propagate(&mut self) {
        loop {
            if let Some(edge) = self.lost_edges.pop() {
                let x = self.space.edges[edge.index()].from;
                let xs = &self.space.states[x.index()];
                if xs.removal.is_none() && xs.expanded {
                    self.lost_edge(x, edge);
                }
                continue;
            }
            let Some(y) = self.lost_queue.pop() else { break };
            let mut id = self.space.states[y.index()].first_in;
            while id != EdgeId::NONE {
                let edge_id = id;
                let e = self.space.edges[id.index()];
                id = e.next_in;
                let x = e.from;
                let xs = &self.space.states[x.index()];
                if xs.removal.is_some() || !xs.expanded || e.zeno {
                    continue; // a zeno edge was already discounted when it was cut
                }
                self.lost_edge(x, edge_id);
            }
        }
    }

    /// Move `edge` of the live state `x` leads to a removed state.
    fn lost_edge(&mut self, x: StateId, edge_id: EdgeId) {
        match self.space.edges[edge_id.index()].class {
            Class::Forced => self.remove(x, Removal::Forced { edge: edge_id }),
            Class::Option => self.option_lost(x, edge_id),
            Class::Wait => self.wait_lost(x),
            Class::Inert => {}
        }
    }

    /// Inclusion: the moves of live states that went to the removed state `y` because it
    /// included their own zones lose nothing by its loss. Each gets, at once (before anything
    /// reads the move as lost), the state of its own zone: not another cover, which a search
    /// near the largest scan time that works keeps losing too (two machines at 17 ms: 77 694
    /// states so, 323 444 and the budget when a move may hop from cover to cover).
    fn retarget_covered(&mut self, y: StateId) {
        let mut id = self.space.states[y.index()].first_in;
        let mut kept = EdgeId::NONE;
        while id != EdgeId::NONE {
            let edge_id = id;
            let e = self.space.edges[id.index()];
            id = e.next_in;
            if !e.is_covered() || e.zeno || self.space.states[e.from.index()].removal.is_some() {
                kept = edge_id;
                continue;
            }
            match kept {
                EdgeId::NONE => self.space.states[y.index()].first_in = e.next_in,
                k => self.space.edges[k.index()].next_in = e.next_in,
            }
            self.give_own_state(edge_id);
        }
    }

    /// Inclusion: gives the move `edge`, into a state that includes its zone, the state of its
    /// own zone, as the search without inclusion has it (see `remove_trapped`).
    pub(super) fn unfold(&mut self, edge_id: EdgeId) {
        let e = self.space.edges[edge_id.index()];
        let mut id = self.space.states[e.to.index()].first_in;
        let mut previous = EdgeId::NONE;
        while id != EdgeId::NONE && id != edge_id {
            previous = id;
            id = self.space.edges[id.index()].next_in;
        }
        match previous {
            EdgeId::NONE => self.space.states[e.to.index()].first_in = e.next_in,
            p => self.space.edges[p.index()].next_in = e.next_in,
        }
        self.give_own_state(edge_id);
    }

    /// Points the covered move `edge`, already out of its cover's in-list, at the state of its
    /// own zone (same locations and kind as the cover).
    fn give_own_state(&mut self, edge_id: EdgeId) {
        let e = self.space.edges[edge_id.index()];
        let cover = &self.space.states[e.to.index()];
        let (env, plan, kind) = (cover.env, cover.plan, cover.kind);
        let vis = self.move_vis(edge_id);
        let to = self.add_checked(env, plan, e.exact, kind, vis);
        self.relink(edge_id, to, NO_ZONE);
    }

    /// How the zeno memory of a move's own target is formed (as `expand` forms it).
    fn move_vis(&self, edge_id: EdgeId) -> Vis {
        let e = &self.space.edges[edge_id.index()];
        let from = self.space.states[e.from.index()].vis;
        if e.progress {
            Vis::Fresh
        } else if e.label == Label::Wait {
            Vis::Same(from)
        } else {
            Vis::Extend(from)
        }
    }

    /// Points the move `edge` (out of every in-list) at `to`, with `exact` as its own zone:
    /// a lost target makes the move lost (`lost_edges`, read by `propagate`); a live one is
    /// needed where the strategy relies on the move.
    fn relink(&mut self, edge_id: EdgeId, to: StateId, exact: u32) {
        let target = &mut self.space.states[to.index()];
        let target_lost = target.removal.is_some();
        let edge = &mut self.space.edges[edge_id.index()];
        edge.to = to;
        edge.exact = exact;
        edge.next_in = target.first_in;
        target.first_in = edge_id;
        let e = *edge;
        if target_lost {
            self.lost_edges.push(edge_id);
            return;
        }
        let xs = &self.space.states[e.from.index()];
        let needed = xs.expanded
            && match e.class {
                Class::Forced => true,
                Class::Option => xs.choice == edge_id,
                Class::Wait => xs.choice == EdgeId::WAIT,
                Class::Inert => false,
            };
        if needed {
            S::need(self, to);
        }
    }

    /// The option `edge` of the live state `x` leads to a removed state (or was cut).
    fn option_lost(&mut self, x: StateId, edge: EdgeId) {
        S::alternative_lost(self, x, edge);
    }

    /// Waiting in the live state `x` leads to a removed state (or was cut).
    fn wait_lost(&mut self, x: StateId) {
        let xs = &mut self.space.states[x.index()];
        if !xs.wait_viable {
            return;
        }
        xs.wait_viable = false;
        S::alternative_lost(self, x, EdgeId::WAIT);
    }
}

/// What one pass over a state's edges finds (`Solver::survey`).
#[derive(Default)]
pub(super) struct Survey {
    forced_any: bool,
    /// The removal a lost forced move causes (the first such move).
    pub(super) dead_forced: Option<Removal>,
    pub(super) options_alive: u32,
    wait_edges: u32,
    wait_ok: bool,
    /// No edge, or only timeouts.
    pub(super) all_inert: bool,
}

impl Survey {
    /// Waiting is possible if all its targets survive, or, without delays, if the plant must act.
    pub(super) fn wait_viable(&self) -> bool {
        if self.wait_edges > 0 {
            self.wait_ok
        } else {
            self.forced_any
        }
    }
}
