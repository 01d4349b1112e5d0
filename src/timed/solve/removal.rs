//! Removal: the local rule that decides an expanded state, and the backward propagation of
//! removed states (algorithm 6).

use super::space::{Class, EdgeId, Removal, StateId};
use super::{Solver, NONE, WAIT};

impl Solver<'_, '_> {
    /// One pass over the edges of an expanded state: what the local rule of the module doc needs.
    pub(super) fn survey(&self, s: StateId) -> Survey {
        let st = &self.space.states[s as usize];
        let mut survey = Survey { wait_ok: true, all_inert: true, ..Survey::default() };
        for id in st.out_start..st.out_end {
            let e = &self.space.edges[id as usize];
            let alive = e.to != NONE && self.space.states[e.to as usize].removal.is_none();
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

    /// Decides a freshly expanded state from its edges (the local rule of the module doc).
    pub(super) fn evaluate(&mut self, s: StateId) {
        let survey = self.survey(s);
        let st = &mut self.space.states[s as usize];
        st.options_alive = survey.options_alive;
        st.wait_viable = survey.wait_viable();
        let removal = match survey.dead_forced {
            Some(removal) => Some(removal),
            None if survey.options_alive == 0 && !st.wait_viable => {
                Some(if survey.all_inert { Removal::Deadlock } else { Removal::NoMove })
            }
            None => None,
        };
        if let Some(r) = removal {
            self.remove(s, r);
        }
    }

    pub(super) fn remove(&mut self, s: StateId, reason: Removal) {
        let st = &mut self.space.states[s as usize];
        if st.removal.is_none() {
            st.removal = Some(reason);
            self.removed += 1;
            self.lost_queue.push(s);
        }
    }

    /// Algorithm 6: removes, backwards, every state that can no longer avoid a removed one.
    pub(super) fn propagate(&mut self) {
        while let Some(y) = self.lost_queue.pop() {
            let mut id = self.space.states[y as usize].first_in;
            while id != NONE {
                let edge_id = id;
                let e = self.space.edges[id as usize];
                id = e.next_in;
                let x = e.from;
                let xs = &self.space.states[x as usize];
                if xs.removal.is_some() || !xs.expanded || e.zeno {
                    continue; // a zeno edge was already discounted when it was cut
                }
                match e.class {
                    Class::Forced => self.remove(x, Removal::Forced { edge: edge_id }),
                    Class::Option => self.option_lost(x, edge_id),
                    Class::Wait => self.wait_lost(x),
                    Class::Inert => {}
                }
            }
        }
    }

    /// The option `edge` of the live state `x` leads to a removed state (or was cut).
    fn option_lost(&mut self, x: StateId, edge: EdgeId) {
        let xs = &mut self.space.states[x as usize];
        if self.lazy {
            // `choose` moves on from `tried`, past every alternative lost (this one among them:
            // the choice is not always the `tried`-th, `steer_by_ranks` may have moved it).
            if xs.choice == edge {
                self.choose(x);
            }
        } else {
            xs.options_alive -= 1;
            if xs.options_alive == 0 && !xs.wait_viable {
                self.remove(x, Removal::NoMove);
            }
        }
    }

    /// Waiting in the live state `x` leads to a removed state (or was cut).
    fn wait_lost(&mut self, x: StateId) {
        let xs = &mut self.space.states[x as usize];
        if !xs.wait_viable {
            return;
        }
        xs.wait_viable = false;
        if self.lazy {
            if xs.choice == WAIT {
                self.choose(x);
            }
        } else if xs.options_alive == 0 {
            self.remove(x, Removal::NoMove);
        }
    }
}

/// What one pass over a state's edges finds (`Solver::survey`).
#[derive(Default)]
pub(super) struct Survey {
    forced_any: bool,
    /// The removal a lost forced move causes (the first such move).
    pub(super) dead_forced: Option<Removal>,
    options_alive: u32,
    wait_edges: u32,
    wait_ok: bool,
    /// No edge, or only timeouts.
    all_inert: bool,
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
