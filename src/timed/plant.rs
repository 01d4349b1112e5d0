//! The plant of a game on concrete clock values, for the closed-loop checkers: the
//! specification's own automata (not the solver's split game) with integer clock values, counted
//! in `ticks` per time unit, the plans watching the messages, and the assertions.
//! `program::simulate` drives it in eighths of a time unit with a scan after every plant step,
//! `plc::lower::timed::realtime` in microseconds against a PLC with a real scan period.

use super::model::{ClockId, CompId, Edge, Game, Interval, LocId, MessageKind, MessageRole, MsgId};
use super::precompute::SplitGame;
use super::solve::{StateId, StateKind, StateSpace};

/// One plant move: a sending transition and one `$` transition of every unit that
/// synchronises on its message (algorithm 3).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Move {
    pub message: MsgId,
    /// Some participating transition is `instant`.
    pub instant: bool,
    /// (unit, edge index) of every participating transition, the sender first.
    pub parts: Vec<(usize, usize)>,
}

/// How each input's level follows the plant (docs/plc-code.md, "The I/O contract"): the one
/// model of what a PLC reads, shared by the real-time checker and the scan program's
/// extraction, so that the code is built from the levels it will be tested on.
///
/// A reaction *holds* from its occurrence until its sender next takes part in a transition that
/// is not `instant` (a sensor of the state reached: an instant transition leaves no time to see
/// the location it leaves), and initially when an edge carrying it enters its sender's initial
/// location. A guard holds while the environment says so. An input whose messages are bound
/// with both polarities is a latch: a `Level` message sets it TRUE when it occurs, a `not`
/// message sets it FALSE; initially it is TRUE when one of its `Level` messages holds. Any
/// other input is TRUE while one of its messages holds, or, bound only with `not`, FALSE while
/// one holds.
#[derive(Clone, Debug)]
pub struct Sensors {
    /// Per input: its messages and whether each reads the signal negated (shared by clones,
    /// and left out of equality: clones of one set of sensors are compared).
    messages: std::sync::Arc<[Vec<(MsgId, bool)>]>,
    /// Per message: whether some input reads it (shared by clones, as `messages`).
    read: std::sync::Arc<[bool]>,
    /// Per input: the latch's value, for latches.
    latch: Vec<Option<bool>>,
    /// Per message: whether it holds.
    pub holds: Vec<bool>,
}

impl PartialEq for Sensors {
    fn eq(&self, other: &Sensors) -> bool {
        self.holds == other.holds && self.latch == other.latch
    }
}

impl Eq for Sensors {}

impl std::hash::Hash for Sensors {
    fn hash<H: std::hash::Hasher>(&self, state: &mut H) {
        self.holds.hash(state);
        self.latch.hash(state);
    }
}

impl Sensors {
    /// The levels at the start, for inputs wired to `inputs` (per input, its messages and
    /// whether each reads it negated).
    pub fn new(game: &Game, inputs: &[Vec<(MsgId, bool)>]) -> Sensors {
        let holds: Vec<bool> = (0..game.messages.len())
            .map(|m| match game.messages[m].sender {
                Some(s) if game.messages[m].role == MessageRole::Reaction => {
                    let a = &game.components[s.index()];
                    a.edges
                        .iter()
                        .any(|e| e.message.index() == m && e.kind != MessageKind::Synchronised && e.to == a.initial)
                }
                _ => false,
            })
            .collect();
        let latch = inputs
            .iter()
            .map(|ms| {
                let both = ms.iter().any(|&(_, n)| n) && ms.iter().any(|&(_, n)| !n);
                both.then(|| ms.iter().any(|&(m, n)| !n && holds[m.index()]))
            })
            .collect();
        let mut read = vec![false; holds.len()];
        for &(m, _) in inputs.iter().flatten() {
            read[m.index()] = true;
        }
        Sensors { messages: inputs.to_vec().into(), read: read.into(), latch, holds }
    }

    pub fn level(&self, input: usize) -> bool {
        match self.latch[input] {
            Some(v) => v,
            None => {
                let ms = &self.messages[input];
                let any = ms.iter().any(|&(m, _)| self.holds[m.index()]);
                if ms.iter().all(|&(_, n)| n) {
                    !any
                } else {
                    any
                }
            }
        }
    }

    /// Forgets whether messages no input reads hold: two memories that differ only there give
    /// the same levels now and later.
    pub fn forget_unread(&mut self) {
        for (h, &r) in self.holds.iter_mut().zip(self.read.iter()) {
            *h &= r;
        }
    }

    /// What the sensors remember of the plant's past, for ordering memories.
    pub fn memory(&self) -> (&[bool], &[Option<bool>]) {
        (&self.holds, &self.latch)
    }

    /// Every input's level.
    pub fn image(&self) -> Vec<bool> {
        (0..self.messages.len()).map(|i| self.level(i)).collect()
    }

    /// A plant move on `message` with the units `parts` happened: their reactions stop holding
    /// unless it is instant, its message holds and sets or clears its latches.
    pub fn moved(&mut self, game: &Game, message: MsgId, instant: bool, parts: impl Iterator<Item = CompId>) {
        // `game` may extend the game the sensors were made for (a scan game): messages beyond
        // it are read by no input.
        let known = self.holds.len();
        if !instant {
            for u in parts {
                for (k, msg) in game.messages.iter().enumerate().take(known) {
                    if msg.sender == Some(u) && msg.role == MessageRole::Reaction {
                        self.holds[k] = false;
                    }
                }
            }
        }
        if message.index() < known && game.messages[message.index()].role == MessageRole::Reaction {
            self.holds[message.index()] = true;
        }
        for (i, ms) in self.messages.iter().enumerate() {
            if let (Some(v), Some(&(_, negated))) = (&mut self.latch[i], ms.iter().find(|&&(k, _)| k == message)) {
                *v = !negated;
            }
        }
    }
}

/// What is wrong with a plant state.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Violation {
    /// `game.assertions[k]` does not hold.
    Assertion(usize),
    /// `game.plans[k]` is in its failed location or a timeout clock is beyond its bound.
    Plan(usize),
}

/// The plant's state: a location per unit and per plan, and every clock.
#[derive(Clone, Debug)]
pub struct Plant<'g> {
    pub game: &'g Game,
    /// Clock ticks per time unit.
    pub ticks: i64,
    pub locs: Vec<LocId>,
    pub plan_locs: Vec<LocId>,
    /// Indexed by clock; index 0 (the zones' reference clock) stays 0.
    pub clocks: Vec<i64>,
}

impl<'g> Plant<'g> {
    /// The initial state, every clock at 0.
    pub fn new(game: &'g Game, ticks: i64) -> Plant<'g> {
        Plant {
            game,
            ticks,
            locs: game.components.iter().map(|a| a.initial).collect(),
            plan_locs: game.plans.iter().map(|p| p.initial).collect(),
            clocks: vec![0; game.dim()],
        }
    }

    /// A constant of the specification in ticks (saturating: beyond any run).
    pub fn ticks_of(&self, units: u32) -> i64 {
        i64::from(units).saturating_mul(self.ticks)
    }

    /// Whether clock value `v` lies in `i`.
    pub fn holds(&self, i: &Interval, v: i64) -> bool {
        let above = if i.lower_closed { v >= self.ticks_of(i.lower) } else { v > self.ticks_of(i.lower) };
        let below = match i.upper {
            None => true,
            Some(u) if i.upper_closed => v <= self.ticks_of(u),
            Some(u) => v < self.ticks_of(u),
        };
        above && below
    }

    /// The delays `d` for which `v + d` lies in `i`, as a range `lo..=hi` (`hi` `None`:
    /// unbounded); `lo` may be negative.
    fn shift(&self, i: &Interval, v: i64) -> (i64, Option<i64>) {
        let lo = self.ticks_of(i.lower) - v + i64::from(!i.lower_closed);
        let hi = i.upper.map(|u| self.ticks_of(u) - v - i64::from(!i.upper_closed));
        (lo, hi)
    }

    fn guard_ok(&self, unit: usize, edge: usize) -> bool {
        let e = &self.game.components[unit].edges[edge];
        e.guard.iter().all(|ci| self.holds(&ci.interval, self.clocks[ci.clock.index()]))
    }

    /// Every move of the given kinds from the current locations, whatever the guards and clocks:
    /// each sending transition with each combination of `$` transitions of the units that
    /// synchronise on its message. A message nobody else synchronises on is one move.
    pub fn candidates(&self, kinds: &[MessageKind]) -> Vec<Move> {
        self.candidates_where(|e| kinds.contains(&e.kind))
    }

    /// [`Plant::candidates`] of one message (the closed loop's requests: most of a simulated
    /// scan's work, so only the sending transitions of that message are combined).
    pub fn candidates_of(&self, kind: MessageKind, message: MsgId) -> Vec<Move> {
        self.candidates_where(|e| e.kind == kind && e.message == message)
    }

    /// [`Plant::moves`] of one message (see [`Plant::candidates_of`]).
    pub fn moves_of(&self, kind: MessageKind, message: MsgId) -> Vec<Move> {
        self.candidates_of(kind, message).into_iter().filter(|m| self.enabled(m)).collect()
    }

    /// The enabled instant moves of `kind`, without building any move when no transition from
    /// the current locations is instant (the usual case).
    pub fn instant_moves(&self, kind: MessageKind) -> Vec<Move> {
        let any_instant = self
            .game
            .components
            .iter()
            .zip(&self.locs)
            .any(|(a, &at)| a.edges.iter().any(|e| e.instant && e.from == at));
        if !any_instant {
            return Vec::new();
        }
        self.moves(&[kind]).into_iter().filter(|m| m.instant).collect()
    }

    fn candidates_where(&self, sends: impl Fn(&Edge) -> bool) -> Vec<Move> {
        let mut out = Vec::new();
        for (u, a) in self.game.components.iter().enumerate() {
            for (ei, e) in a.edges.iter().enumerate() {
                if e.from != self.locs[u] || !sends(e) {
                    continue;
                }
                let mut combos: Vec<Vec<(usize, usize)>> = vec![vec![(u, ei)]];
                for &other in &self.game.messages[e.message.index()].synchronised {
                    let o = other.index();
                    let options: Vec<usize> = self.game.components[o]
                        .edges
                        .iter()
                        .enumerate()
                        .filter(|(_, oe)| {
                            oe.kind == MessageKind::Synchronised && oe.message == e.message && oe.from == self.locs[o]
                        })
                        .map(|(oi, _)| oi)
                        .collect();
                    combos = combos
                        .into_iter()
                        .flat_map(|c| options.iter().map(move |&oi| [c.clone(), vec![(o, oi)]].concat()))
                        .collect();
                }
                for parts in combos {
                    let instant = parts.iter().any(|&(pu, pe)| self.game.components[pu].edges[pe].instant);
                    out.push(Move { message: e.message, instant, parts });
                }
            }
        }
        out
    }

    /// Whether `m` may fire now: every guard holds and every target's invariant holds after the
    /// resets.
    pub fn enabled(&self, m: &Move) -> bool {
        m.parts.iter().all(|&(u, ei)| self.guard_ok(u, ei)) && self.targets_ok(&m.parts)
    }

    /// The moves of the given kinds enabled now, in the order of [`Plant::candidates`].
    pub fn moves(&self, kinds: &[MessageKind]) -> Vec<Move> {
        self.candidates(kinds).into_iter().filter(|m| self.enabled(m)).collect()
    }

    fn targets_ok(&self, parts: &[(usize, usize)]) -> bool {
        let mut clocks = self.clocks.clone();
        for &(u, ei) in parts {
            for &c in &self.game.components[u].edges[ei].resets {
                clocks[c.index()] = 0;
            }
        }
        parts.iter().all(|&(u, ei)| {
            let to = self.game.components[u].edges[ei].to;
            self.game.components[u].locations[to.index()]
                .invariant
                .iter()
                .all(|ci| self.holds(&ci.interval, clocks[ci.clock.index()]))
        })
    }

    /// The delays after which `m` may fire, as `lo..=hi` (`hi` `None`: any delay from `lo`
    /// on): its guards hold, its targets' invariants hold after its resets, and the current
    /// invariants still hold ([`Plant::room`]). `None` if there is no such delay.
    pub fn window(&self, m: &Move) -> Option<(i64, Option<i64>)> {
        let mut lo = 0i64;
        let mut hi = self.room();
        let mut meet = |(l, h): (i64, Option<i64>)| {
            lo = lo.max(l);
            hi = match (hi, h) {
                (Some(a), Some(b)) => Some(a.min(b)),
                (a, b) => a.or(b),
            };
        };
        let reset = |c: ClockId| m.parts.iter().any(|&(u, ei)| self.game.components[u].edges[ei].resets.contains(&c));
        for &(u, ei) in &m.parts {
            let e = &self.game.components[u].edges[ei];
            for ci in &e.guard {
                meet(self.shift(&ci.interval, self.clocks[ci.clock.index()]));
            }
            for ci in &self.game.components[u].locations[e.to.index()].invariant {
                if reset(ci.clock) {
                    if !self.holds(&ci.interval, 0) {
                        return None;
                    }
                } else {
                    meet(self.shift(&ci.interval, self.clocks[ci.clock.index()]));
                }
            }
        }
        match hi {
            Some(h) if h < lo => None,
            _ => Some((lo, hi)),
        }
    }

    /// Applies a move to the units and the plans; returns whether a plan made progress. A plan
    /// observes the move's message when an edge of its current location carries it.
    pub fn apply(&mut self, m: &Move) -> bool {
        for &(u, ei) in &m.parts {
            let e = &self.game.components[u].edges[ei];
            for &c in &e.resets {
                self.clocks[c.index()] = 0;
            }
            self.locs[u] = e.to;
        }
        let mut progress = false;
        for (p, plan) in self.game.plans.iter().enumerate() {
            if let Some(e) = plan.edges.iter().find(|e| e.from == self.plan_locs[p] && e.message == m.message) {
                for &c in &e.resets {
                    self.clocks[c.index()] = 0;
                }
                self.plan_locs[p] = e.to;
                progress = true;
            }
        }
        progress
    }

    /// The largest delay the current locations' invariants allow, if bounded.
    pub fn room(&self) -> Option<i64> {
        let mut best: Option<i64> = None;
        for (u, a) in self.game.components.iter().enumerate() {
            for ci in &a.locations[self.locs[u].index()].invariant {
                if let (_, Some(h)) = self.shift(&ci.interval, self.clocks[ci.clock.index()]) {
                    let r = h.max(0);
                    best = Some(best.map_or(r, |b| b.min(r)));
                }
            }
        }
        best
    }

    /// Lets `d` ticks pass.
    pub fn delay(&mut self, d: i64) {
        for c in self.clocks.iter_mut().skip(1) {
            *c += d;
        }
    }

    /// The first violated assertion, else the first failed plan.
    pub fn violation(&self) -> Option<Violation> {
        if let Some(k) = self.game.assertions.iter().position(|a| !a.holds.eval(&self.locs)) {
            return Some(Violation::Assertion(k));
        }
        self.game
            .plans
            .iter()
            .enumerate()
            .position(|(p, plan)| {
                self.plan_locs[p] == plan.failed
                    || plan.clocks.iter().any(|&(c, bound)| self.clocks[c.index()] > self.ticks_of(bound))
            })
            .map(Violation::Plan)
    }

    /// The delay after which some plan's timeout clock first exceeds its bound, if any.
    pub fn plan_deadline(&self) -> Option<i64> {
        self.game
            .plans
            .iter()
            .flat_map(|plan| plan.clocks.iter())
            .map(|&(c, bound)| (self.ticks_of(bound) + 1 - self.clocks[c.index()]).max(0))
            .min()
    }

    /// Whether this concrete state lies in the explored state `s`: the same location of every
    /// unit and plan, every clock in the piece of `s`'s sub-locations, and the clock valuation
    /// in `s`'s zone. The zone is exact in the pieces and extrapolated beyond the largest
    /// constants (a superset), so membership is what the solver decided about this point.
    pub fn is_in(&self, split: &SplitGame, space: &StateSpace, s: StateId) -> bool {
        let base = split.plant_count;
        let units = space.env(s).iter().enumerate().map(|(u, &sub)| (u, sub, self.locs[u]));
        let plans = space.plan(s).iter().enumerate().map(|(p, &sub)| (base + p, sub, self.plan_locs[p]));
        let located = units.chain(plans).all(|(u, sub, at)| {
            let sub = &split.units[u].sublocs[sub.index()];
            sub.location == at
                && sub
                    .pieces
                    .iter()
                    .all(|&(c, piece)| self.holds(&split.pieces[c.index()][piece as usize], self.clocks[c.index()]))
        });
        located && space.zone(s).contains_point(&self.clocks, self.ticks)
    }

    /// The explored states this concrete state lies in: winning ones first, then by kind
    /// (entry, interval, waiting, guard: where the controller decides first), then by id. A
    /// point lies in several states when the zeno memory or the kinds tell them apart.
    pub fn locate(&self, split: &SplitGame, space: &StateSpace) -> Vec<StateId> {
        let mut found: Vec<StateId> = space.state_ids().filter(|&s| self.is_in(split, space, s)).collect();
        let kind_order = |k: StateKind| match k {
            StateKind::Entry => 0,
            StateKind::Interval => 1,
            StateKind::Waiting => 2,
            StateKind::Guard => 3,
        };
        crate::sort::sort_by_key(&mut found, |&s| {
            let st = &space.states[s.index()];
            (st.removal.is_some(), kind_order(st.kind), s)
        });
        found
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::Rng;

    /// On random walks through examples with guards and invariants, a move is enabled exactly
    /// at the delays of its window: at both ends, and not just outside them.
    #[test]
    fn a_window_holds_exactly_the_delays_at_which_a_move_is_enabled() {
        for source in [
            include_str!("../../examples/timed/two_robots_14.tga"),
            include_str!("../../examples/timed/lamp.tga"),
            include_str!("../../examples/timed/hardware_xyz.tga"),
        ] {
            let (game, _) = crate::timed::compile(source).unwrap();
            let mut plant = Plant::new(&game, 1000);
            let mut rng = Rng::new(7);
            for _ in 0..300 {
                let kinds = [MessageKind::Controllable, MessageKind::Uncontrollable];
                let mut possible = Vec::new();
                for m in plant.candidates(&kinds) {
                    let at = |d: i64| {
                        let mut p = plant.clone();
                        p.delay(d);
                        p.enabled(&m)
                    };
                    match plant.window(&m) {
                        Some((lo, hi)) => {
                            assert!(at(lo) && (lo == 0 || !at(lo - 1)), "{m:?} at {lo}");
                            if let Some(hi) = hi {
                                assert!(at(hi), "{m:?} at {hi}");
                                assert!(!at(hi + 1) || plant.room() == Some(hi), "{m:?} after {hi}");
                            }
                            possible.push((m, lo, hi));
                        }
                        None => assert!((0..3000).step_by(7).all(|d| !at(d) || plant.room().is_some_and(|r| d > r))),
                    }
                }
                if possible.is_empty() {
                    break;
                }
                let (m, lo, hi) = possible.swap_remove(rng.below(possible.len() as u64) as usize);
                let d = lo + rng.below((hi.unwrap_or(lo + 2000) - lo + 1) as u64) as i64;
                plant.delay(d);
                plant.apply(&m);
            }
        }
    }
}
