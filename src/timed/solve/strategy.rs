//! The strategy of the strategy-directed search (`directed`): the order in which a state's
//! alternatives are tried (towards the plans' goals; at a scan game's read, the guide's and
//! the delivery's), the choice of one, and the generation of deferred targets when their
//! move is tried.

use super::directed::Directed;
use super::expand::{guard_edge, Move};
use super::guide::Hint;
use super::space::{Class, Edge, EdgeId, Label, Removal, StateId, StateKind, NOT_DEFERRED};
use super::zeno::Vis;
use super::{Search, Solver};
use crate::timed::model::*;
use crate::timed::precompute::{SplitGame, SubLocId};
use crate::zone::Dbm;
use std::collections::VecDeque;

/// The target of a move not generated yet (a controller option or a delay, in a search that
/// defers them: `Search::deferred_targets`): the state's key, how its zeno memory is formed,
/// the request edge, and the guards checked before it.
pub(super) struct Deferred {
    pub(super) env: u32,
    pub(super) plan: u32,
    pub(super) zone: u32,
    pub(super) kind: StateKind,
    pub(super) vis: Vis,
    pub(super) request: Edge,
    pub(super) guards: Vec<MsgId>,
    /// The request returns to a plant state visited since the last plan progress.
    pub(super) repeats: bool,
}

impl Solver<'_, '_, Directed<'_>> {
    /// How far the plant state `env_id` is from the goals of the plans in `plan_id`: per plan,
    /// the fewest transitions before some sender can send a message that takes the plan to its
    /// next goal, summed over the plans.
    pub(super) fn goal_distance(&self, env_id: u32, plan_id: u32) -> u32 {
        let locations = self.locations_of(env_id);
        let mut total = 0u32;
        for (p, &sub) in self.space.plans.get(plan_id).iter().enumerate() {
            let nearest = self.search.plan_goals[p][sub.index()]
                .iter()
                .filter_map(|&m| {
                    let sender = (self.game.messages[m.index()].sender?).index();
                    self.search.send_distance[m.index()].get(locations[sender].index()).copied()
                })
                .min()
                .unwrap_or(u16::MAX);
            total += u32::from(nearest);
        }
        total
    }

    /// Where an alternative of a freshly expanded state goes in the order the strategy tries
    /// them (smallest first): forced moves, then what the guide's zero-time strategy does here
    /// (`hints`, scan games only), then options that make plan progress, then the others nearer
    /// the plans' goals first, options returning to a visited plant state after those, waiting
    /// last. In a scan game the decision at a read is a commitment whose effect comes later, so
    /// it is ordered by the request it commits (see `delivery_order`); there, committing nothing
    /// goes after the requests as near the goals, as waiting does.
    pub(super) fn try_order(&mut self, e: &Edge, hints: &[Hint]) -> (u8, u32, bool) {
        match e.class {
            Class::Forced => (0, 0, false),
            Class::Option if e.is_unexplored() => {
                let d = self.search.deferred[e.deferred as usize].as_ref().expect("a deferred target");
                let (env, plan, repeats) = (d.env, d.plan, d.repeats);
                let here = if e.progress {
                    2
                } else if repeats {
                    4
                } else {
                    3
                };
                let Label::Message { message } = e.label else { return (here, 0, false) };
                let Some(roles) = self.game.scan.as_ref() else {
                    return (here, self.goal_distance(env, plan), false);
                };
                if message == roles.idle {
                    // After the hinted requests: where the zero-time strategy both waits and
                    // requests (zones that meet the read's), the request is the one with a deadline.
                    if hints.contains(&Hint::Wait) {
                        return (1, 1, false);
                    }
                    return (here, self.goal_distance(env, plan), true);
                }
                match roles.commits.get(message.index()).copied().flatten() {
                    Some(request) if hints.contains(&Hint::Request(request)) => (1, 0, false),
                    Some(request) => self.delivery_order(env, plan, request),
                    None => (here, self.goal_distance(env, plan), false),
                }
            }
            Class::Option => (5, 0, false),
            Class::Wait => (6, 0, false),
            Class::Inert => (7, 0, false),
        }
    }

    /// The guide's decisions for a read whose alternatives are `edges` (none elsewhere).
    pub(super) fn guide_hints(&self, edges: &[Edge], env: &[SubLocId], plan: &[SubLocId], zone: &Dbm) -> Vec<Hint> {
        let (Some(guide), Some(roles)) = (self.search.guide, self.game.scan.as_ref()) else { return Vec::new() };
        let read = edges.iter().any(|e| e.class == Class::Option && e.label == Label::Message { message: roles.idle });
        if !read {
            return Vec::new();
        }
        guide.hints(self.split, env, plan, zone)
    }

    /// The order of committing `request` in a scan game, from the state `(env, plan)` it commits
    /// it into, by what its delivery does: the plant may deliver it at once, in the plant state
    /// the PLC has just read, so a delivery that violates an assertion or fails a plan makes the
    /// commitment lost (tried last, found lost in a step); otherwise it is ordered as the
    /// request itself would be in the zero-time game. Without this look-through every
    /// commitment looks alike (the plant has not moved yet) and the search tries them in the
    /// order of their declaration.
    fn delivery_order(&mut self, env: u32, plan: u32, request: MsgId) -> (u8, u32, bool) {
        let plant = self.space.envs.get(env).to_vec();
        let plans = self.space.plans.get(plan).to_vec();
        // The plant's side of the delivery: its units that take the request with it (the scan
        // automaton's own move does not matter here).
        let delivery =
            Move { kind: MessageKind::Uncontrollable, message: request, instant: false, env: plant.clone(), resets: 0 };
        let Some(moves) = self.synchronise(&plant, vec![delivery]) else { return (3, 0, false) };
        let (mut progress, mut lost, mut distance) = (false, false, u32::MAX);
        for m in &moves {
            let mut plans_after = plans.clone();
            for (p, sub) in plans_after.iter_mut().enumerate() {
                let next = self.split.plan_next[p][sub.index() * self.split.message_count + request.index()];
                if next != SubLocId::STAY {
                    progress = true;
                    *sub = next;
                }
            }
            let (env_after, plan_after) = self.intern_discrete(&m.env, &plans_after);
            lost |= self.env_violation[env_after as usize] != 0 || self.plan_failure[plan_after as usize] != 0;
            distance = distance.min(self.goal_distance(env_after, plan_after));
        }
        if distance == u32::MAX {
            // No unit can take it now (it would be refused): order by the state as it is.
            (3, self.goal_distance(env, plan), false)
        } else if lost {
            (4, distance, true)
        } else {
            (if progress { 2 } else { 3 }, distance, false)
        }
    }

    /// The `k`-th alternative of the expanded state `s` in the order the strategy tries them:
    /// an option edge, `EdgeId::WAIT`, or `None` when all are tried. Options are stored with
    /// those that make plan progress first, then by distance to the plans' goals. Waiting comes
    /// first where it costs nothing (no delay edge, so only the forced moves, needed anyway,
    /// follow it), else after every option (measured: fewest states on the examples).
    pub(super) fn alternative(&self, s: StateId, k: u32) -> Option<EdgeId> {
        let st = &self.space.states[s.index()];
        let (mut first_option, mut options, mut waits, mut forced) = (None, 0, 0, false);
        for id in st.out_ids() {
            let e = &self.space.edges[id.index()];
            match e.class {
                Class::Option => {
                    first_option.get_or_insert(id);
                    options += 1;
                }
                Class::Wait => waits += 1,
                Class::Forced => forced = true,
                Class::Inert => {}
            }
        }
        let wait_at = match (waits, forced) {
            (0, true) => Some(0),
            (0, false) => None,
            _ => Some(options),
        };
        let option = match wait_at {
            Some(w) if k == w => return Some(EdgeId::WAIT),
            Some(w) if k > w => k - 1,
            _ => k,
        };
        // The options are consecutive (see `expand`).
        match first_option {
            Some(first) if option < options => Some(EdgeId::from_raw(first.raw() + option)),
            _ => None,
        }
    }

    /// Picks the first alternative of `s`, from the `tried`-th on, that is not lost yet,
    /// generating an option's target when it is tried the first time, and queues what it needs.
    /// Without one, `s` is lost.
    pub(super) fn choose(&mut self, s: StateId) {
        loop {
            let k = self.space.states[s.index()].tried;
            match self.alternative(s, k) {
                None => {
                    let st = &mut self.space.states[s.index()];
                    st.choice = EdgeId::NONE;
                    let inert = st.out_ids().all(|id| self.space.edges[id.index()].class == Class::Inert);
                    self.remove(s, if inert { Removal::Deadlock } else { Removal::NoMove });
                    return;
                }
                Some(EdgeId::WAIT) => {
                    let out = self.space.states[s.index()].out_ids();
                    let waits: Vec<EdgeId> =
                        out.clone().filter(|&id| self.space.edges[id.index()].class == Class::Wait).collect();
                    for &id in &waits {
                        if self.space.edges[id.index()].is_unexplored() {
                            self.generate(id);
                        }
                    }
                    let st = &self.space.states[s.index()];
                    let viable = if waits.is_empty() {
                        st.wait_viable
                    } else {
                        st.wait_viable && waits.iter().all(|&id| self.space.is_live(&self.space.edges[id.index()]))
                    };
                    if viable {
                        self.space.states[s.index()].choice = EdgeId::WAIT;
                        for &id in &waits {
                            self.demand(self.space.edges[id.index()].to);
                        }
                        return;
                    }
                    self.space.states[s.index()].wait_viable = false;
                }
                Some(edge) => {
                    if self.space.edges[edge.index()].is_unexplored() {
                        self.generate(edge);
                    }
                    let e = self.space.edges[edge.index()];
                    if self.space.is_live(&e) {
                        self.space.states[s.index()].choice = edge;
                        self.demand(e.to);
                        return;
                    }
                }
            }
            self.space.states[s.index()].tried += 1;
        }
    }

    /// Generates the target of a deferred option (with its chain of guard states) and links the
    /// edge to it.
    pub(super) fn generate(&mut self, edge: EdgeId) {
        let index = std::mem::replace(&mut self.space.edges[edge.index()].deferred, NOT_DEFERRED);
        let Some(d) = self.search.deferred[index as usize].take() else { return };
        let from = self.space.edges[edge.index()].from;
        let (target, exact) = self.target(d.env, d.plan, d.zone, d.kind, d.vis);
        let first = if d.guards.is_empty() {
            self.space.edges[edge.index()].exact = exact;
            target
        } else {
            let st = self.space.states[from.index()].clone();
            let chain: Vec<StateId> = d.guards.iter().map(|_| self.add_guard_state(&st)).collect();
            for k in (0..chain.len()).rev() {
                let next = match chain.get(k + 1) {
                    Some(&next) => guard_edge(chain[k], next, d.guards[k + 1], d.request.instant),
                    None => Edge { from: chain[k], to: target, exact, ..d.request },
                };
                self.commit_edges(chain[k], vec![next]);
                Directed::decide(self, chain[k]);
            }
            chain[0]
        };
        let target_state = &mut self.space.states[first.index()];
        let e = &mut self.space.edges[edge.index()];
        e.to = first;
        e.next_in = target_state.first_in;
        target_state.first_in = edge;
    }
}

/// Per plan and sub-location: the messages that take the plan to a goal rather than to failure.
pub(super) fn plan_goals(split: &SplitGame) -> Vec<Vec<Vec<MsgId>>> {
    let messages = split.message_count;
    (0..split.units.len() - split.plant_count)
        .map(|p| {
            let unit = &split.units[split.plant_count + p];
            (0..unit.sublocs.len())
                .map(|sub| {
                    let next = &split.plan_next[p][sub * messages..(sub + 1) * messages];
                    (0..messages)
                        .filter(|&m| next[m] != SubLocId::STAY && !unit.sublocs[next[m].index()].failed)
                        .map(MsgId::new)
                        .collect()
                })
                .collect()
        })
        .collect()
}

/// For every message that is some plan's goal and has a sender, per location of the sender: the
/// fewest transitions before the message can be sent (1 where it is enabled), by a backward
/// breadth-first search over the sender's automaton (guards, clocks and synchronisation
/// ignored: a lower bound). Other messages get an empty table.
pub(super) fn send_distances(game: &Game, plan_goals: &[Vec<Vec<MsgId>>]) -> Vec<Vec<u16>> {
    let mut goal = vec![false; game.messages.len()];
    for &m in plan_goals.iter().flatten().flatten() {
        goal[m.index()] = true;
    }
    // Incoming edges per location, per automaton, built once for the automata that send a goal.
    let mut incoming: Vec<Option<Vec<Vec<LocId>>>> = vec![None; game.components.len()];
    game.messages
        .iter()
        .enumerate()
        .map(|(m, message)| {
            let Some(sender) = message.sender.filter(|_| goal[m]) else { return Vec::new() };
            let automaton = &game.components[sender.index()];
            let incoming = incoming[sender.index()].get_or_insert_with(|| {
                let mut lists = vec![Vec::new(); automaton.locations.len()];
                for e in &automaton.edges {
                    lists[e.to.index()].push(e.from);
                }
                lists
            });
            let mut distance = vec![u16::MAX; automaton.locations.len()];
            let mut queue = VecDeque::new();
            for e in &automaton.edges {
                if e.message.index() == m && e.kind != MessageKind::Synchronised && distance[e.from.index()] != 1 {
                    distance[e.from.index()] = 1;
                    queue.push_back(e.from);
                }
            }
            while let Some(loc) = queue.pop_front() {
                let d = distance[loc.index()].saturating_add(1);
                for &from in &incoming[loc.index()] {
                    if distance[from.index()] == u16::MAX {
                        distance[from.index()] = d;
                        queue.push_back(from);
                    }
                }
            }
            distance
        })
        .collect()
}
