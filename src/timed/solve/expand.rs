//! Expansion: successor generation of a state (discrete moves with `$` synchronisation, guard
//! chains, waiting and delay edges, timeouts), the interning of its discrete parts and zones,
//! and the scan automaton's arming in a scan game. Whether a move's target is generated at once
//! and how the new state is decided are the search's (`Search::deferred_targets`, `decide`).

use super::space::{
    Class, Edge, EdgeId, EdgeKind, Label, Removal, State, StateId, StateKind, StateSpace, NOT_DEFERRED, NO_ZONE,
};
use super::strategy::Deferred;
use super::zeno::Vis;
use super::{Search, Solver};
use crate::timed::model::*;
use crate::timed::precompute::{SplitGame, SubLocId};
use crate::zone::{includes_lowered, includes_only_lowered, Bound, Dbm};

/// One discrete move under construction.
pub(super) struct Move {
    pub(super) kind: MessageKind,
    pub(super) message: MsgId,
    pub(super) instant: bool,
    pub(super) env: Vec<SubLocId>,
    pub(super) resets: u64,
}

/// Where a delay arms the scan automaton of a scan game.
pub(super) struct ScanArm {
    unit: usize,
    quiet: SubLocId,
    /// `armed` with its clock at 0, and with its clock just above 0.
    armed_at_zero: SubLocId,
    armed_after_zero: SubLocId,
    clock: ClockId,
}

impl ScanArm {
    pub(super) fn new(game: &Game, split: &SplitGame) -> Option<ScanArm> {
        let roles = game.scan.as_ref()?;
        let unit = roles.plc.index();
        let sublocs = &split.units[unit].sublocs;
        let find = |loc: LocId, piece: Option<bool>| {
            let position = sublocs.iter().position(|sl| {
                sl.location == loc
                    && piece.is_none_or(|closed| {
                        sl.pieces.iter().any(|&(c, p)| {
                            let iv = split.pieces[c.index()][p as usize];
                            c == roles.clock && iv.lower == 0 && iv.lower_closed == closed
                        })
                    })
            });
            position.map(SubLocId::new)
        };
        Some(ScanArm {
            unit,
            quiet: find(roles.quiet, None)?,
            armed_at_zero: find(roles.armed, Some(true))?,
            armed_after_zero: find(roles.armed, Some(false))?,
            clock: roles.clock,
        })
    }
}

impl<S: Search> Solver<'_, '_, S> {
    // ----- discrete parts and zones ------------------------------------------------------------

    pub(super) fn intern_discrete(&mut self, env: &[SubLocId], plan: &[SubLocId]) -> (u32, u32) {
        let units = &self.split.units;
        let (env_id, new_env) = self.space.envs.intern(env);
        if new_env {
            let locs: Vec<LocId> = env.iter().enumerate().map(|(u, &s)| units[u].sublocs[s.index()].location).collect();
            self.env_locations.extend_from_slice(&locs);
            // In a scan game many env ids (the scan automaton's phases, the sensors' memory) agree
            // on the locations the assertions and guards read, and so on what they say:
            // evaluated once per such vector. (In a zero-time game few do, and the vectors would
            // only take memory.)
            let first = self.env_guards.len();
            let same_as = self.predicate_locations.as_mut().and_then(|(vectors, first_env)| {
                let key: Vec<LocId> = self.predicate_components.iter().map(|&c| locs[c]).collect();
                let (key_id, new_key) = vectors.intern(&key);
                if new_key {
                    first_env.push(env_id);
                    None
                } else {
                    Some(first_env[key_id as usize])
                }
            });
            match same_as {
                Some(same) => {
                    self.env_violation.push(self.env_violation[same as usize]);
                    let words = same as usize * self.guard_words..(same as usize + 1) * self.guard_words;
                    self.env_guards.extend_from_within(words);
                }
                None => {
                    let violated =
                        self.game.assertions.iter().position(|a| !a.holds.eval(&locs)).map_or(0, |i| i as u32 + 1);
                    self.env_violation.push(violated);
                    self.env_guards.resize(first + self.guard_words, 0);
                    for (i, g) in self.game.guards.iter().enumerate() {
                        if g.cond.eval(&locs) {
                            self.env_guards[first + i / 64] |= 1 << (i % 64);
                        }
                    }
                }
            }
            let mut clocks = 0u64;
            for (u, &s) in env.iter().enumerate() {
                for &(c, _) in &units[u].sublocs[s.index()].pieces {
                    clocks |= 1 << c.index();
                }
            }
            self.env_clocks.push(clocks);
        }
        let (plan_id, new_plan) = self.space.plans.intern(plan);
        if new_plan {
            let base = self.split.plant_count;
            let failed = plan
                .iter()
                .enumerate()
                .position(|(p, &s)| units[base + p].sublocs[s.index()].failed)
                .map_or(0, |i| i as u32 + 1);
            self.plan_failure.push(failed);
            let mut clocks = 0u64;
            for (p, &s) in plan.iter().enumerate() {
                for &(c, _) in &units[base + p].sublocs[s.index()].pieces {
                    clocks |= 1 << c.index();
                }
            }
            self.plan_clocks.push(clocks);
        }
        (env_id, plan_id)
    }

    /// The messages of the state guards a move from `before` to `after` (env ids) enters: those
    /// that hold after it and not before, in the order the specification lists them.
    fn entered_guards(&self, before: u32, after: u32) -> Vec<MsgId> {
        let words = self.guard_words;
        let (before, after) = (before as usize * words, after as usize * words);
        let mut entered = Vec::new();
        for w in 0..words {
            let mut bits = self.env_guards[after + w] & !self.env_guards[before + w];
            while bits != 0 {
                entered.push(self.game.guards[w * 64 + bits.trailing_zeros() as usize].message);
                bits &= bits - 1;
            }
        }
        entered
    }

    /// Extrapolates with the maximal constants of the clocks in use; unused clocks are freed
    /// (the clock usage reduction of 5.2.1).
    pub(super) fn normalise(&mut self, env_id: u32, plan_id: u32, zone: &mut Dbm) {
        let used = self.env_clocks[env_id as usize] | self.plan_clocks[plan_id as usize];
        for c in 1..self.dim {
            self.max_constants[c] = if used >> c & 1 == 1 { self.split.max_constant[c].max(0) } else { -1 };
        }
        zone.extrapolate_max(&self.max_constants);
    }

    /// Applies the upper bounds of every piece in use (time may not leave a sub-location).
    fn constrain_upper(&self, env: &[SubLocId], plan: &[SubLocId], zone: &mut Dbm) -> bool {
        let units = &self.split.units;
        let base = self.split.plant_count;
        for (u, &s) in env.iter().enumerate().chain(plan.iter().enumerate().map(|(p, s)| (base + p, s))) {
            for &(clock, piece) in &units[u].sublocs[s.index()].pieces {
                let iv = &self.split.pieces[clock.index()][piece as usize];
                if let Some(upper) = iv.upper {
                    let b = if iv.upper_closed { Bound::le(upper as i32) } else { Bound::lt(upper as i32) };
                    if !zone.constrain(clock.index(), 0, b) {
                        return false;
                    }
                }
            }
        }
        true
    }

    /// The zone after letting time pass as long as every piece in use allows.
    fn time_closure(&self, env: &[SubLocId], plan: &[SubLocId], zone: &Dbm) -> Option<Dbm> {
        let mut closed = zone.clone();
        closed.up();
        self.constrain_upper(env, plan, &mut closed).then_some(closed)
    }

    pub(super) fn is_closed(&self, env: &[SubLocId], plan: &[SubLocId], zone: &Dbm) -> bool {
        self.time_closure(env, plan, zone).is_some_and(|c| &c == zone)
    }

    pub(super) fn locations_of(&self, env_id: u32) -> &[LocId] {
        let w = self.split.plant_count;
        &self.env_locations[env_id as usize * w..env_id as usize * w + w]
    }

    /// Finds or adds the state. A new state violating an assertion or with a failed plan is
    /// stored as removed; any other new state is queued for expansion.
    pub(super) fn find_or_add(
        &mut self,
        env_id: u32,
        plan_id: u32,
        zone: &Dbm,
        kind: StateKind,
        vis: Vis,
    ) -> (StateId, bool) {
        let (zone_id, _) = self.space.zones.intern(zone.as_slice());
        self.add_interned(env_id, plan_id, zone_id, kind, vis)
    }

    /// [`Self::find_or_add`] with the zone interned. The search hears of a new state to expand
    /// (`Search::reached`).
    pub(super) fn add_interned(
        &mut self,
        env_id: u32,
        plan_id: u32,
        zone_id: u32,
        kind: StateKind,
        vis: Vis,
    ) -> (StateId, bool) {
        let key = (env_id, plan_id, zone_id, kind);
        if let Some(&id) = self.state_index.get(&key) {
            return (id, false);
        }
        let id = StateId::new(self.space.states.len());
        let vis = match vis {
            Vis::Fresh => self.zeno.singleton(env_id),
            Vis::Extend(parent) => self.zeno.insert(parent, env_id),
            Vis::Same(v) => v,
        };
        let removal = match (self.env_violation[env_id as usize], self.plan_failure[plan_id as usize]) {
            (0, 0) => None,
            (0, p) => Some(Removal::PlanFailed { plan: p - 1 }),
            (a, _) => Some(Removal::Assertion { rule: a - 1 }),
        };
        self.space.states.push(State::new(env_id, plan_id, zone_id, kind, removal, vis));
        self.state_index.insert(key, id);
        if self.covers.is_some() && removal.is_none() {
            let key = (env_id, plan_id, kind, self.kept_key(zone_id));
            if let Some(covers) = self.covers.as_mut() {
                covers.entry(key).or_default().push(id);
            }
        }
        if removal.is_some() {
            self.removed += 1;
        } else if kind != StateKind::Guard {
            self.search.reached(id);
        }
        (id, true)
    }

    /// Inclusion (see `Config::inclusion`): a surviving state of these locations and kind
    /// whose zone includes zone `zone_id` once its plan clocks may be lower (a plan clock only
    /// ever meets a deadline, so a lower one only helps the controller), the latest such first;
    /// lost states leave the lists as they are met.
    fn cover(&mut self, env_id: u32, plan_id: u32, zone_id: u32, kind: StateKind) -> Option<StateId> {
        let key = (env_id, plan_id, kind, self.kept_key(zone_id));
        let list = self.covers.as_mut()?.get_mut(&key)?;
        let states = &self.space.states;
        list.retain(|&s| states[s.index()].removal.is_none());
        let (dim, lowered) = (self.dim, self.deadline_clocks);
        let (found, compared) =
            latest_related(&self.space, list, zone_id, |cover, zone| includes_only_lowered(cover, zone, dim, lowered));
        self.charge(compared * (dim * dim) as u64);
        found
    }

    /// The hash of zone `zone_id`'s bounds between clocks other than the plans' (and the zero
    /// clock): equal for two zones one of which covers the other (`includes_only_lowered`).
    fn kept_key(&mut self, zone_id: u32) -> u64 {
        if let Some(&Some(known)) = self.kept_keys.get(zone_id as usize) {
            return known;
        }
        let (dim, lowered) = (self.dim, self.deadline_clocks & !1);
        let zone = self.space.zones.get(zone_id);
        // The multiply-rotate mix of rustc's FxHasher: a lookup key, not a defence against
        // chosen collisions, and cheap next to the comparisons it saves.
        let mut hash = 0u64;
        for i in (0..dim).filter(|i| lowered >> i & 1 == 0) {
            for j in (0..dim).filter(|j| lowered >> j & 1 == 0) {
                hash = (hash.rotate_left(5) ^ zone[i * dim + j].raw() as u64).wrapping_mul(0x51_7c_c1_b7_27_22_0a_95);
            }
        }
        if self.kept_keys.len() <= zone_id as usize {
            self.kept_keys.resize(zone_id as usize + 1, None);
        }
        self.kept_keys[zone_id as usize] = Some(hash);
        hash
    }

    /// [`Self::add_interned`], and a new state lost at once if a lost state dominates it (see
    /// `Config::dominance`).
    pub(super) fn add_checked(
        &mut self,
        env_id: u32,
        plan_id: u32,
        zone_id: u32,
        kind: StateKind,
        vis: Vis,
    ) -> StateId {
        let (id, new) = self.add_interned(env_id, plan_id, zone_id, kind, vis);
        if new && self.space.states[id.index()].removal.is_none() {
            if let Some(by) = self.dominating_loss(env_id, plan_id, zone_id, kind) {
                // Born lost, as a state that violates an assertion is: nothing points at it
                // yet, and whoever links a move to it reads the removal.
                self.space.states[id.index()].removal = Some(Removal::Dominated { by });
                self.removed += 1;
                self.dominated += 1;
            }
        }
        id
    }

    /// Dominance: a lost state of these locations and kind whose zone lies in zone `zone_id`
    /// once plan clocks may be lower there (were `zone_id` won, by inclusion so would that
    /// state be), the latest lost first.
    fn dominating_loss(&mut self, env_id: u32, plan_id: u32, zone_id: u32, kind: StateKind) -> Option<StateId> {
        let list = self.losses.as_ref()?.get(&(env_id, plan_id, kind))?;
        let (dim, lowered) = (self.dim, self.deadline_clocks);
        let (found, compared) =
            latest_related(&self.space, list, zone_id, |lost, zone| includes_lowered(zone, lost, dim, lowered));
        self.charge(compared * (dim * dim) as u64);
        found
    }

    /// The target of a move: state and, if it is a cover, the move's own zone (`Edge::exact`).
    pub(super) fn target(
        &mut self,
        env_id: u32,
        plan_id: u32,
        zone_id: u32,
        kind: StateKind,
        vis: Vis,
    ) -> (StateId, u32) {
        let own = self.state_index.get(&(env_id, plan_id, zone_id, kind)).copied();
        let to = match own.or_else(|| self.cover(env_id, plan_id, zone_id, kind)) {
            Some(to) => to,
            None => self.add_checked(env_id, plan_id, zone_id, kind, vis),
        };
        let exact = if self.space.states[to.index()].zone == zone_id { NO_ZONE } else { zone_id };
        (to, exact)
    }

    // ----- expansion -----------------------------------------------------------------------

    /// Collects the discrete moves enabled in `env`, resolving `$` synchronisation (algorithm 3):
    /// a sender's move needs one enabled `$` transition in every unit synchronising on the
    /// message; each combination is a move.
    fn collect_moves(&mut self, env: &[SubLocId], requests_allowed: bool) {
        self.moves.clear();
        let split = self.split;
        let units = &split.units;
        for (u, &s) in env.iter().enumerate() {
            for e in &units[u].sublocs[s.index()].edges {
                if e.kind == MessageKind::Synchronised || (e.kind == MessageKind::Controllable && !requests_allowed) {
                    continue;
                }
                let mut partial = vec![Move {
                    kind: e.kind,
                    message: e.message,
                    instant: e.instant,
                    env: env.to_vec(),
                    resets: clock_bits(&e.resets),
                }];
                partial[0].env[u] = e.target;
                let Some(partial) = self.synchronise(env, partial) else { return };
                self.moves.extend(partial);
            }
        }
        // Urgency: while an instant move is enabled, only instant moves are taken, and an instant
        // reaction goes before an instant request (the plant's urgent move happens first; the
        // controller decides after observing it), as the closed-loop checker runs them.
        if self.moves.iter().any(|m| m.instant) {
            let reaction_first = self.moves.iter().any(|m| m.instant && m.kind == MessageKind::Uncontrollable);
            self.moves.retain(|m| m.instant && !(reaction_first && m.kind == MessageKind::Controllable));
        }
    }

    /// `partial` (moves of one message's sender from `env`) completed with one enabled `$`
    /// transition in every unit synchronising on the message, each combination a move; `None`
    /// when the work this costs stops the search.
    pub(super) fn synchronise(&mut self, env: &[SubLocId], mut partial: Vec<Move>) -> Option<Vec<Move>> {
        let Some(message) = partial.first().map(|m| m.message) else { return Some(partial) };
        let split = self.split;
        for &other in &split.sync_units[message.index()] {
            let other = other.index();
            let options: Vec<_> = split.units[other].sublocs[env[other].index()]
                .edges
                .iter()
                .filter(|se| se.kind == MessageKind::Synchronised && se.message == message)
                .collect();
            let mut next = Vec::with_capacity(partial.len() * options.len());
            for m in &partial {
                for o in &options {
                    let mut env2 = m.env.clone();
                    env2[other] = o.target;
                    next.push(Move {
                        kind: m.kind,
                        message: m.message,
                        instant: m.instant || o.instant,
                        env: env2,
                        resets: m.resets | clock_bits(&o.resets),
                    });
                }
            }
            partial = next;
            // Synchronisation multiplies the moves: count them as work.
            if !self.charge(self.vector_cost * partial.len() as u64) {
                return None;
            }
        }
        Some(partial)
    }

    pub(super) fn expand(&mut self, s: StateId) {
        let st = self.space.states[s.index()].clone();
        let env = self.space.envs.get(st.env).to_vec();
        let plan = self.space.plans.get(st.plan).to_vec();
        let zone = Dbm::from_slice(self.dim, self.space.zones.get(st.zone));
        let requests_allowed = st.kind != StateKind::Waiting;
        self.collect_moves(&env, requests_allowed);
        if self.halt.is_some() {
            return;
        }
        let urgent = self.moves.iter().any(|m| m.instant);
        let moves = std::mem::take(&mut self.moves);
        self.pending_edges.clear();
        let mut guard_chains: Vec<(usize, Vec<MsgId>)> = Vec::new();
        for m in &moves {
            if !self.charge(self.successor_cost) {
                break;
            }
            // Plans observe the message (they never block it).
            let mut plan2 = plan.clone();
            let mut resets = m.resets;
            let mut progress = false;
            for (p, sub) in plan2.iter_mut().enumerate() {
                let slot = sub.index() * self.split.message_count + m.message.index();
                let next = self.split.plan_next[p][slot];
                if next != SubLocId::STAY {
                    // Reaching a goal is progress even when the plan loops to the same location.
                    progress = true;
                    resets |= self.split.plan_resets[p][slot];
                    *sub = next;
                }
            }
            let mut z = zone.clone();
            for c in 1..self.dim {
                if resets >> c & 1 == 1 {
                    z.reset(c);
                }
            }
            let (env_id, plan_id) = self.intern_discrete(&m.env, &plan2);
            self.normalise(env_id, plan_id, &mut z);
            let kind = if self.is_closed(&m.env, &plan2, &z) { StateKind::Interval } else { StateKind::Entry };
            let edge_kind = if m.kind == MessageKind::Controllable { EdgeKind::Request } else { EdgeKind::Reaction };
            let class = if m.kind == MessageKind::Controllable { Class::Option } else { Class::Forced };
            let label = Label::Message { message: m.message };
            // A move back to a plant state visited since the last progress (the thesis's zeno
            // memory, 5.1) is cut in a search with the memory; without it, the strategy-directed
            // search tries such a request last: it tends to close a cycle without progress.
            let repeats = !progress && self.visited(st.vis, env_id);
            let cut = repeats
                && self.memory
                && self.env_violation[env_id as usize] == 0
                && self.plan_failure[plan_id as usize] == 0;
            self.memory_cuts += usize::from(cut);
            let vis = if progress { Vis::Fresh } else { Vis::Extend(st.vis) };
            let mut edge = Edge {
                from: s,
                to: StateId::NONE,
                kind: edge_kind,
                label,
                resets,
                instant: m.instant,
                zeno: cut,
                progress,
                class,
                next_in: EdgeId::NONE,
                deferred: NOT_DEFERRED,
                exact: NO_ZONE,
            };
            if cut {
                // Leads nowhere (`Edge::target`).
                self.pending_edges.push(edge);
                continue;
            }
            let (zone_id, _) = self.space.zones.intern(z.as_slice());
            if m.kind != MessageKind::Controllable {
                (edge.to, edge.exact) = self.target(env_id, plan_id, zone_id, kind, vis);
                self.pending_edges.push(edge);
                continue;
            }
            let guards = self.entered_guards(st.env, env_id);
            // A search that defers targets generates an option's target only once it tries it.
            if let Some(deferred) = self.search.deferred_targets() {
                let first = match guards.first() {
                    Some(&g) => guard_edge(s, StateId::NONE, g, m.instant),
                    None => edge,
                };
                self.pending_edges.push(Edge { deferred: deferred.len() as u32, ..first });
                let (env, plan, zone) = (env_id, plan_id, zone_id);
                deferred.push(Some(Deferred { env, plan, zone, kind, vis, request: edge, guards, repeats }));
                continue;
            }
            (edge.to, edge.exact) = self.target(env_id, plan_id, zone_id, kind, vis);
            if !guards.is_empty() {
                guard_chains.push((self.pending_edges.len(), guards));
            }
            self.pending_edges.push(edge);
        }
        self.moves = moves;
        if self.halt.is_some() {
            return;
        }
        if !urgent {
            if st.kind == StateKind::Entry {
                if !self.charge(self.successor_cost) {
                    return;
                }
                if let Some(closed) = self.time_closure(&env, &plan, &zone) {
                    let mut closed = closed;
                    self.normalise(st.env, st.plan, &mut closed);
                    let edge = Edge {
                        from: s,
                        to: StateId::NONE,
                        kind: EdgeKind::Delay,
                        label: Label::Wait,
                        resets: 0,
                        instant: false,
                        zeno: false,
                        progress: false,
                        class: Class::Wait,
                        next_in: EdgeId::NONE,
                        deferred: NOT_DEFERRED,
                        exact: NO_ZONE,
                    };
                    self.add_wait_edge(edge, st.env, st.plan, &closed, StateKind::Waiting, Vis::Same(st.vis));
                }
            } else {
                self.delay_edges(s, &st, &env, &plan, &zone);
            }
        }
        // A budget or a cancellation stopped the work on `s` half-way: leave it unexpanded.
        if self.halt.is_some() {
            return;
        }

        // A guarded request becomes `s -%g1-> G1 -%g2-> … -?m-> target` (5.3.4). Guard states
        // are settled (and their removal propagated) before the edges of `s` exist, so that no
        // removal is counted twice.
        let mut own = std::mem::take(&mut self.pending_edges);
        for (index, guards) in guard_chains {
            let request = own[index];
            let chain: Vec<StateId> = guards.iter().map(|_| self.add_guard_state(&st)).collect();
            for k in (0..chain.len()).rev() {
                let edge = match chain.get(k + 1) {
                    Some(&next) => guard_edge(chain[k], next, guards[k + 1], request.instant),
                    None => Edge { from: chain[k], ..request },
                };
                self.commit_edges(chain[k], vec![edge]);
                S::decide(self, chain[k]);
                self.propagate();
            }
            own[index] = guard_edge(s, chain[0], guards[0], request.instant);
        }
        let Some(own) = S::order(self, own, &env, &plan, &zone) else { return };
        self.commit_edges(s, own);
        S::decide(self, s);
        self.propagate();
    }

    pub(super) fn add_guard_state(&mut self, st: &State) -> StateId {
        let id = StateId::new(self.space.states.len());
        self.space.states.push(State::new(st.env, st.plan, st.zone, StateKind::Guard, None, st.vis));
        id
    }

    /// Delay edges of a time-closed state (5.2.2). Time leaves the current box of pieces when
    /// the first clocks reach the end of their pieces; for every set `S` of clocks that can be
    /// the first to leave, together, there is one edge into the box where the clocks of `S`
    /// are in their next piece. Restricting the zone to the valuations whose first exit set is
    /// `S` keeps every successor immediate, so no intermediate state is skipped. Leaving a piece
    /// past a plant invariant is a timeout edge instead.
    fn delay_edges(&mut self, s: StateId, st: &State, env: &[SubLocId], plan: &[SubLocId], zone: &Dbm) {
        let plant_count = self.split.plant_count;
        let mut exits: Vec<Exit> = Vec::new();
        for u in 0..self.split.units.len() {
            let sub = if u < plant_count { env[u] } else { plan[u - plant_count] };
            let sl = &self.split.units[u].sublocs[sub.index()];
            for &(clock, piece) in &sl.pieces {
                let iv = self.split.pieces[clock.index()][piece as usize];
                let Some(upper) = iv.upper else { continue };
                exits.push(Exit {
                    unit: u,
                    clock,
                    upper: upper as i32,
                    closed: iv.upper_closed,
                    next_piece: piece + 1,
                });
            }
        }
        for r in 0..exits.len() {
            if !self.charge(self.successor_cost) {
                return;
            }
            let mut base = zone.clone();
            // Clocks before `r` are not in S: they leave strictly later than `r`.
            let feasible = (0..r).all(|c| later(&mut base, &exits[c], &exits[r]));
            if feasible {
                self.exit_sets(s, st, env, plan, &exits, r, r + 1, base, vec![r]);
            }
        }
    }

    /// Enumerates the exit sets with smallest member `r`, deciding clocks `k..` one by one.
    #[allow(clippy::too_many_arguments)]
    fn exit_sets(
        &mut self,
        s: StateId,
        st: &State,
        env: &[SubLocId],
        plan: &[SubLocId],
        exits: &[Exit],
        r: usize,
        k: usize,
        zone: Dbm,
        set: Vec<usize>,
    ) {
        // Up to two branches per clock: exponential in the clocks that may leave together.
        if zone.is_empty() || !self.charge(self.successor_cost) {
            return;
        }
        if k == exits.len() {
            self.delay_into(s, st, env, plan, exits, &set, zone);
            return;
        }
        // k leaves together with r.
        if exits[k].closed == exits[r].closed {
            let mut with = zone.clone();
            let d = exits[k].upper - exits[r].upper;
            let (ck, cr) = ((exits[k].clock).index(), (exits[r].clock).index());
            if with.constrain(ck, cr, Bound::le(d)) && with.constrain(cr, ck, Bound::le(-d)) {
                let mut set2 = set.clone();
                set2.push(k);
                self.exit_sets(s, st, env, plan, exits, r, k + 1, with, set2);
            }
        }
        // k leaves later.
        let mut without = zone;
        if later(&mut without, &exits[k], &exits[r]) {
            self.exit_sets(s, st, env, plan, exits, r, k + 1, without, set);
        }
    }

    #[allow(clippy::too_many_arguments)]
    fn delay_into(
        &mut self,
        s: StateId,
        st: &State,
        env: &[SubLocId],
        plan: &[SubLocId],
        exits: &[Exit],
        set: &[usize],
        mut zone: Dbm,
    ) {
        let plant_count = self.split.plant_count;
        // Several clocks of one unit may move on together: follow the unit's delay edges one
        // clock after the other, each from the sub-location the previous one led to (taking
        // each from the original sub-location would keep only the last clock's move).
        let mut env2 = env.to_vec();
        let mut plan2 = plan.to_vec();
        for &k in set {
            let e = &exits[k];
            let sub = if e.unit < plant_count { &mut env2[e.unit] } else { &mut plan2[e.unit - plant_count] };
            let from = &self.split.units[e.unit].sublocs[sub.index()];
            if let Some(d) = from.delays.iter().find(|d| d.clock == e.clock) {
                *sub = d.target;
                continue;
            }
            // The clock runs past its invariant (plant) or past the last piece it may have.
            if e.unit < plant_count {
                self.pending_edges.push(Edge {
                    from: s,
                    to: StateId::NONE,
                    kind: EdgeKind::Timeout,
                    label: Label::Overrun { clock: e.clock },
                    resets: 0,
                    instant: false,
                    zeno: false,
                    progress: false,
                    class: Class::Inert,
                    next_in: EdgeId::NONE,
                    deferred: NOT_DEFERRED,
                    exact: NO_ZONE,
                });
            }
            return;
        }
        // A scan game's PLC that saw no change at its last read notices this one (a timer
        // reaching its threshold) at its next read: its clock starts at the instant of the change.
        if let Some(arm) = &self.scan_arm {
            if env2[arm.unit] == arm.quiet && set.iter().any(|&k| exits[k].clock != arm.clock) {
                let first = &exits[set[0]];
                let c = first.clock.index();
                zone.up();
                if !(zone.constrain(c, 0, Bound::le(first.upper)) && zone.constrain(0, c, Bound::le(-first.upper))) {
                    return;
                }
                zone.reset(arm.clock.index());
                // The clock is 0 at the change: in the target it is still 0 if the piece entered
                // starts there, and above 0 if the piece starts just after it.
                env2[arm.unit] = if first.closed { arm.armed_after_zero } else { arm.armed_at_zero };
            }
        }
        zone.up();
        for &k in set {
            let e = &exits[k];
            let iv = self.split.pieces[e.clock.index()][e.next_piece as usize];
            let lower = if iv.lower_closed { Bound::le(-(iv.lower as i32)) } else { Bound::lt(-(iv.lower as i32)) };
            if !zone.constrain(0, e.clock.index(), lower) {
                return;
            }
        }
        if !self.constrain_upper(&env2, &plan2, &mut zone) {
            return;
        }
        let (env_id, plan_id) = self.intern_discrete(&env2, &plan2);
        self.normalise(env_id, plan_id, &mut zone);
        // Time moved some clock into its next piece: a new plant state for the zeno memory.
        let first = &exits[set[0]];
        let clocks = set.iter().fold(0u64, |bits, &k| bits | 1 << exits[k].clock.index());
        let edge = Edge {
            from: s,
            to: StateId::NONE,
            kind: EdgeKind::Delay,
            label: Label::Piece { clock: first.clock, piece: first.next_piece, clocks },
            resets: 0,
            instant: false,
            zeno: false,
            progress: false,
            class: Class::Wait,
            next_in: EdgeId::NONE,
            deferred: NOT_DEFERRED,
            exact: NO_ZONE,
        };
        self.add_wait_edge(edge, env_id, plan_id, &zone, StateKind::Interval, Vis::Extend(st.vis));
    }

    /// Adds a wait edge into the given state: generated at once, unless the search defers
    /// targets until it tries waiting (`Search::deferred_targets`).
    fn add_wait_edge(&mut self, edge: Edge, env: u32, plan: u32, zone: &Dbm, kind: StateKind, vis: Vis) {
        let (zone, _) = self.space.zones.intern(zone.as_slice());
        if let Some(deferred) = self.search.deferred_targets() {
            self.pending_edges.push(Edge { deferred: deferred.len() as u32, ..edge });
            deferred.push(Some(Deferred {
                env,
                plan,
                zone,
                kind,
                vis,
                request: edge,
                guards: Vec::new(),
                repeats: false,
            }));
        } else {
            let to = self.add_interned(env, plan, zone, kind, vis).0;
            self.pending_edges.push(Edge { to, ..edge });
        }
    }

    pub(super) fn commit_edges(&mut self, s: StateId, edges: Vec<Edge>) {
        let start = EdgeId::new(self.space.edges.len());
        for mut e in edges {
            let id = EdgeId::new(self.space.edges.len());
            e.from = s;
            if e.to != StateId::NONE {
                let target = &mut self.space.states[e.to.index()];
                e.next_in = target.first_in;
                target.first_in = id;
            }
            self.space.edges.push(e);
        }
        let st = &mut self.space.states[s.index()];
        st.out_start = start;
        st.out_end = EdgeId::new(self.space.edges.len());
        st.expanded = true;
        self.expanded += 1;
    }
}

/// The latest of `candidates` whose zone stands in `relation` to zone `zone_id` (the
/// candidate's matrix first), and how many were compared.
fn latest_related(
    space: &StateSpace,
    candidates: &[StateId],
    zone_id: u32,
    relation: impl Fn(&[Bound], &[Bound]) -> bool,
) -> (Option<StateId>, u64) {
    let zone = space.zones.get(zone_id);
    let mut compared = 0u64;
    let found = candidates.iter().rev().copied().find(|&s| {
        compared += 1;
        relation(space.zones.get(space.states[s.index()].zone), zone)
    });
    (found, compared)
}

/// A clock that time can move out of its current piece.
struct Exit {
    unit: usize,
    clock: ClockId,
    /// End of the current piece, and whether it belongs to the piece.
    upper: i32,
    closed: bool,
    next_piece: u16,
}

/// Constrains `zone` so that clock `c` leaves its piece strictly after clock `r` leaves its own.
/// A closed end `u` is left just after the clock reaches `u`, an open end exactly at `u`.
fn later(zone: &mut Dbm, c: &Exit, r: &Exit) -> bool {
    let d = c.upper - r.upper;
    let bound = if c.closed && !r.closed { Bound::le(d) } else { Bound::lt(d) };
    zone.constrain(c.clock.index(), r.clock.index(), bound)
}

pub(super) fn guard_edge(from: StateId, to: StateId, message: MsgId, instant: bool) -> Edge {
    Edge {
        from,
        to,
        kind: EdgeKind::Guard,
        label: Label::Message { message },
        resets: 0,
        instant,
        zeno: false,
        progress: false,
        class: Class::Option,
        next_in: EdgeId::NONE,
        deferred: NOT_DEFERRED,
        exact: NO_ZONE,
    }
}

fn clock_bits(clocks: &[ClockId]) -> u64 {
    clocks.iter().fold(0, |bits, &c| bits | 1 << c.index())
}
