//! The exhaustive reference search: the thesis's algorithm 5 as it stands (Peter 2005, 5.3).
//! Every reachable state is queued when first reached and expanded in breadth-first order,
//! every move's target generated at once, and every expanded state decided eagerly by the local
//! rule of the module doc (`evaluate`), each state counting its surviving options; the reverse
//! removal (algorithm 6, in `removal`) then only counts down. The progress condition counts
//! only what was explored, and the search has no strategy to steer. Slower than the
//! strategy-directed search (`directed`), whose verdicts it checks: kept as the reference
//! (`Config::exhaustive`).

use super::progress::Counting;
use super::space::{Edge, EdgeId, Removal, StateId};
use super::strategy::Deferred;
use super::{Search, Solver};
use crate::timed::precompute::SubLocId;
use crate::zone::Dbm;
use std::collections::VecDeque;

/// The reference's own state: the breadth-first queue.
pub(super) struct Exhaustive {
    /// Every reachable state not expanded yet, in the order reached.
    queue: VecDeque<StateId>,
}

impl Exhaustive {
    pub(super) fn new() -> Exhaustive {
        Exhaustive { queue: VecDeque::new() }
    }
}

impl Search for Exhaustive {
    /// Only what was explored: the reference explores everything it decides on.
    const COUNTING: Counting = Counting::Explored;

    /// Breadth first (algorithm 5).
    fn next_state(&mut self) -> Option<StateId> {
        self.queue.pop_front()
    }

    /// Every reachable state is expanded.
    fn reached(&mut self, s: StateId) {
        self.queue.push_back(s);
    }

    /// Nothing to do: every state was queued when reached.
    fn need(_: &mut Solver<'_, '_, Self>, _: StateId) {}

    /// None: every target is generated with its move.
    fn deferred_targets(&mut self) -> Option<&mut Vec<Option<Deferred>>> {
        None
    }

    /// As found: the reference tries no alternative before another.
    fn order(
        _: &mut Solver<'_, '_, Self>,
        edges: Vec<Edge>,
        _: &[SubLocId],
        _: &[SubLocId],
        _: &Dbm,
    ) -> Option<Vec<Edge>> {
        Some(edges)
    }

    fn decide(solver: &mut Solver<'_, '_, Self>, s: StateId) {
        solver.evaluate(s);
    }

    fn after_expansion(_: &mut Solver<'_, '_, Self>) {}

    /// One option fewer (or no waiting): lost when neither is left.
    fn alternative_lost(solver: &mut Solver<'_, '_, Self>, x: StateId, alt: EdgeId) {
        let xs = &mut solver.space.states[x.index()];
        if alt != EdgeId::WAIT {
            xs.options_alive -= 1;
        }
        if xs.options_alive == 0 && !xs.wait_viable {
            solver.remove(x, Removal::NoMove);
        }
    }

    /// No strategy to steer, and nothing left to explore.
    fn steer(_: &mut Solver<'_, '_, Self>, _: &[u32]) -> bool {
        false
    }

    /// Those of the last round: everything was explored.
    fn final_ranks(_: &mut Solver<'_, '_, Self>, ranks: Vec<u32>) -> Vec<u32> {
        ranks
    }

    /// The cut options no longer count as surviving.
    fn after_cut(solver: &mut Solver<'_, '_, Self>, s: StateId, options_cut: u32) {
        solver.space.states[s.index()].options_alive -= options_cut;
    }

    fn finish(_: &mut Solver<'_, '_, Self>) {}

    fn heap_bytes(&self) -> usize {
        self.queue.capacity() * std::mem::size_of::<StateId>()
    }
}

impl Solver<'_, '_, Exhaustive> {
    /// Decides a freshly expanded state from its edges (the local rule of the module doc),
    /// counting its surviving options for the reverse removal.
    fn evaluate(&mut self, s: StateId) {
        let survey = self.survey(s);
        let st = &mut self.space.states[s.index()];
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
}
