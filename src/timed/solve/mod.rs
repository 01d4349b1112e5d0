//! Solving the timed safety game (Peter 2005, 5.3). The reference (`exhaustive`) is the thesis's
//! on-the-fly forward exploration of the combined state space (algorithm 5, breadth first) with
//! incremental reverse removal of losing states (algorithm 6). The default search builds one
//! strategy instead: forced successors are always explored, the controller's alternatives one
//! at a time (`alternative` gives the order), the next only when the chosen one is lost, which
//! the reverse removal reports through the same in-edge lists (a local fixpoint computation in
//! the manner of Liu and Smolka, as UPPAAL TIGA's on-the-fly algorithm). Targets of untried
//! options and delays are not generated (`Edge::is_unexplored`).
//!
//! A state is a vector of sub-locations (one per plant unit and per plan) and a clock zone.
//! Its outgoing edges fall in three classes:
//! - *forced*: uncontrollable messages `!m`; if any leads to a removed state, so is this one;
//! - *options*: controller requests `?m` and state guards `%g`; removing one only removes
//!   the edge;
//! - *waiting*: letting time pass. An *entry* state (just reached by a message) has one wait
//!   edge to the same locations with the time-closed zone, where plant reactions may come at
//!   any moment; a time-closed state has one delay edge (D) per clock piece that time can reach
//!   next. Waiting is possible if all its targets survive, or, where time cannot reach another
//!   piece, if some forced move exists (the plant must act).
//!
//! A state survives while no forced edge leads to a removed state and either an option
//! survives or waiting is possible. This makes delays forced unless the controller has a
//! better move: where the thesis turns a delay into a failed state into a tolerated timeout,
//! a plan deadline could be missed; here it cannot. Timeout edges (T) past a plant invariant
//! remain tolerated exceptions (5.2.2).
//!
//! Zeno avoidance (5.1): every search item remembers the plant states visited since the last
//! plan progress; a message that returns to one of them without progress leads nowhere. That
//! memory depends on the path that found a state first, so after the search every remaining
//! cycle of the winning graph without plan progress is cut as well (`cut_zeno_cycles`).
//! Transitions marked `instant` are urgent: while one is enabled, no other transition and no
//! delay is possible; an instant reaction goes before an instant request.

use super::arena::SliceArena;
use super::model::*;
use super::precompute::{SplitGame, SplitTooLarge, SubLocId, STAY};
use crate::diag::Span;
use crate::zone::{Bound, Dbm};
use serde::Serialize;
use std::collections::VecDeque;

pub type StateId = u32;
pub type EdgeId = u32;

const NONE: u32 = u32::MAX;
/// The strategy's alternative of a state that lets time pass (or the plant move).
const WAIT: u32 = u32::MAX - 1;

/// Limits and switches of one solver run.
#[derive(Clone, Debug)]
pub struct SolveOptions {
    /// Stop with [`Verdict::BudgetExceeded`] once this many states are stored.
    pub max_states: usize,
    /// Stop once the split game and the state space take about this many heap bytes.
    pub max_bytes: usize,
    /// Stop once this much work is done (see [`Stats::work`]), the split included: bounds the
    /// time of a search whose states are few but expensive (many clocks, many exit orders).
    pub max_work: u64,
    /// How many expansions between two calls of the progress callback (it is also called
    /// during long work on one state).
    pub progress_interval: usize,
    /// Explore the whole reachable game before deciding (the thesis's algorithm 5, breadth
    /// first), instead of only the strategy being built. Slower; kept as the reference.
    pub exhaustive: bool,
    /// First search with the thesis's zeno memory (5.1), which cuts a move back to a plant state
    /// visited since the last plan progress: far fewer states, and what it finds is a correct
    /// strategy. Only where it finds none and did cut something does a second search, without
    /// the memory, decide. `false` searches without it at once (the exact reference).
    pub zeno_memory: bool,
}

/// Default state budget: the exhaustive reference stores 824 640 states for round table 8/8
/// (the strategy-directed search 286).
pub const DEFAULT_MAX_STATES: usize = 1_000_000;
/// Default memory budget, 512 MiB: the reference needs about 311 MiB for round table 8/8.
pub const DEFAULT_MAX_BYTES: usize = 512 << 20;
/// Default work budget: a few seconds of solving natively; round table 8/8 needs about 82 million.
pub const DEFAULT_MAX_WORK: u64 = 250_000_000;

/// Work between two progress calls during long work on one state (a few milliseconds).
pub(crate) const PROGRESS_WORK: u64 = 1 << 20;

/// The fixed part of the work of one candidate successor (hashing, allocation, bookkeeping), in
/// units of one zone bound: measured, this makes a unit cost 10–20 ns whatever the game's shape.
pub(crate) const STEP_COST: u64 = 64;

impl Default for SolveOptions {
    fn default() -> Self {
        SolveOptions {
            max_states: DEFAULT_MAX_STATES,
            max_bytes: DEFAULT_MAX_BYTES,
            max_work: DEFAULT_MAX_WORK,
            progress_interval: 4096,
            exhaustive: false,
            zeno_memory: true,
        }
    }
}

/// The budgets of a search ([`SolveOptions`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Budget {
    /// States stored.
    States,
    /// Approximate heap bytes of the split game and the state space.
    Memory,
    /// Work done (see [`Stats::work`]).
    Work,
}

impl Budget {
    /// The budget's name in messages: `state`, `memory` or `work`.
    pub fn name(self) -> &'static str {
        match self {
            Budget::States => "state",
            Budget::Memory => "memory",
            Budget::Work => "work",
        }
    }
}

/// Which budget stopped a search, and why, in words that do not depend on the caller (the CLI
/// and the page add how to raise it).
#[derive(Clone, Debug, Serialize)]
pub struct BudgetStop {
    pub budget: Budget,
    /// The limit of that budget: states, bytes or work units.
    pub limit: u64,
    pub message: String,
    /// The declaration to blame, when there is one (a node split into too many sub-locations).
    pub span: Option<Span>,
}

impl BudgetStop {
    /// The stop of a search that exceeded `budget` of `options`.
    pub fn search(budget: Budget, options: &SolveOptions) -> BudgetStop {
        let (limit, message) = match budget {
            Budget::States => {
                (options.max_states as u64, format!("the search stored more than {} states", options.max_states))
            }
            Budget::Memory => {
                (options.max_bytes as u64, format!("the search needs more than {} of memory", mib(options.max_bytes)))
            }
            Budget::Work => (
                options.max_work,
                format!(
                    "the search did more than {} units of work (zone bounds and state entries computed)",
                    options.max_work
                ),
            ),
        };
        BudgetStop { budget, limit, message, span: None }
    }

    /// The stop of a split that needed more memory or work than `options` allow.
    pub fn split(too_large: &SplitTooLarge, options: &SolveOptions) -> BudgetStop {
        let what = format!(
            "{} splits into {} sub-locations ({} clocks in use there)",
            too_large.place, too_large.sublocations, too_large.clocks
        );
        let (limit, message) = match too_large.budget {
            Budget::Memory | Budget::States => {
                (options.max_bytes as u64, format!("{what}: more than {} of memory", mib(options.max_bytes)))
            }
            Budget::Work => (options.max_work, format!("{what}: more than {} units of work", options.max_work)),
        };
        BudgetStop { budget: too_large.budget, limit, message, span: Some(too_large.span) }
    }
}

/// Bytes as MiB for messages.
fn mib(bytes: usize) -> String {
    format!("{} MiB", bytes.div_ceil(1 << 20))
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Verdict {
    Realizable,
    Unrealizable,
    BudgetExceeded,
    Cancelled,
}

#[derive(Clone, Copy, Debug, Default, Serialize)]
pub struct Stats {
    /// States stored (explored or found losing on arrival).
    pub visited: usize,
    /// States whose successors were generated.
    pub expanded: usize,
    /// Surviving states reachable from the initial state.
    pub winning: usize,
    /// States removed as losing.
    pub removed: usize,
    pub edges: usize,
    /// Distinct zones stored.
    pub zones: usize,
    /// Approximate heap bytes of the split game and the state space.
    pub bytes: usize,
    /// Work done, the split included: per candidate successor, one unit per zone bound and per
    /// state-vector entry computed plus a fixed 64 for the rest, so roughly proportional to time.
    pub work: u64,
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
enum Class {
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
    /// `NONE` for timeouts and for zeno repetitions.
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
    class: Class,
    next_in: EdgeId,
    /// A controller option whose target is not generated yet: its index in the solver's
    /// deferred targets (strategy-directed search); `NONE` once generated or in the reference.
    deferred: u32,
}

impl Edge {
    /// A controller option the strategy-directed search never needed to try: `to` is `NONE`.
    pub fn is_unexplored(&self) -> bool {
        self.deferred != NONE
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
    out_start: u32,
    out_end: u32,
    first_in: EdgeId,
    options_alive: u32,
    wait_viable: bool,
    vis: u32,
    /// Strategy-directed search: the alternative (option edge id, or `WAIT`) the strategy takes
    /// here, and how many alternatives were tried and lost before it.
    choice: u32,
    tried: u32,
}

impl State {
    fn new(env: u32, plan: u32, zone: u32, kind: StateKind, removal: Option<Removal>, vis: u32) -> State {
        State {
            env,
            plan,
            zone,
            kind,
            removal,
            expanded: false,
            out_start: 0,
            out_end: 0,
            first_in: NONE,
            options_alive: 0,
            wait_viable: false,
            vis,
            choice: NONE,
            tried: 0,
        }
    }
}

/// The explored game graph with the surviving (winning) and removed states.
pub struct StateSpace {
    pub dim: usize,
    pub states: Vec<State>,
    pub edges: Vec<Edge>,
    pub initial: StateId,
    envs: SliceArena<SubLocId>,
    plans: SliceArena<SubLocId>,
    zones: SliceArena<Bound>,
    plant_count: usize,
}

impl StateSpace {
    /// A space without states: what a search refused before it started leaves.
    pub fn empty(dim: usize, plant_count: usize, plan_count: usize) -> StateSpace {
        StateSpace {
            dim,
            states: Vec::new(),
            edges: Vec::new(),
            initial: 0,
            envs: SliceArena::new(plant_count),
            plans: SliceArena::new(plan_count),
            zones: SliceArena::new(dim * dim),
            plant_count,
        }
    }

    /// True if state `s` exists and was not removed.
    pub fn is_winning(&self, s: StateId) -> bool {
        self.states.get(s as usize).is_some_and(|st| st.removal.is_none())
    }

    /// True if the edge leads to a winning state and was not cut as a zeno loop.
    pub fn is_live(&self, e: &Edge) -> bool {
        e.to != NONE && !e.zeno && self.is_winning(e.to)
    }

    /// Sub-locations of the plant units in state `s`.
    pub fn env(&self, s: StateId) -> &[SubLocId] {
        self.envs.get(self.states[s as usize].env)
    }

    /// Sub-locations of the plans in state `s`.
    pub fn plan(&self, s: StateId) -> &[SubLocId] {
        self.plans.get(self.states[s as usize].plan)
    }

    pub fn zone(&self, s: StateId) -> Dbm {
        Dbm::from_slice(self.dim, self.zones.get(self.states[s as usize].zone))
    }

    pub fn out_edges(&self, s: StateId) -> impl Iterator<Item = (EdgeId, &Edge)> {
        let st = &self.states[s as usize];
        (st.out_start..st.out_end).map(move |e| (e, &self.edges[e as usize]))
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
        seen[self.initial as usize] = true;
        let mut queue = VecDeque::from([self.initial]);
        while let Some(s) = queue.pop_front() {
            order.push(s);
            for (_, e) in self.out_edges(s) {
                if e.to != NONE && !seen[e.to as usize] && self.is_winning(e.to) {
                    seen[e.to as usize] = true;
                    queue.push_back(e.to);
                }
            }
        }
        order
    }
}

/// The outcome of [`solve`].
pub struct Solution {
    pub verdict: Verdict,
    pub stats: Stats,
    pub space: StateSpace,
    /// With [`Verdict::BudgetExceeded`]: which budget stopped the search.
    pub stop: Option<BudgetStop>,
}

/// Solves the game within the budgets of `options` (the split's memory and work count). Calls
/// `progress` every `options.progress_interval` expansions, and during long work on one state,
/// with the statistics so far; returning `false` cancels the run.
pub fn solve(
    game: &Game,
    split: &SplitGame,
    options: &SolveOptions,
    progress: &mut dyn FnMut(&Stats) -> bool,
) -> Solution {
    let exact = SolveOptions { zeno_memory: false, ..options.clone() };
    let mut solver = Solver::new(game, split, options, progress);
    let mut verdict = solver.run();
    if verdict == Verdict::Unrealizable && solver.memory_cuts > 0 {
        // The memory's cuts may have cost the controller its strategy: decide exactly.
        let spent = solver.work;
        drop(solver);
        solver = Solver::new(game, split, &exact, progress);
        solver.work += spent;
        verdict = solver.run();
    }
    let mut stats = solver.stats();
    let stop = match solver.halt {
        Some(Halt::Budget(budget)) => Some(BudgetStop::search(budget, options)),
        _ => None,
    };
    let space = solver.space;
    if verdict == Verdict::Realizable || verdict == Verdict::Unrealizable {
        stats.winning = space.winning_states().len();
    }
    Solution { verdict, stats, space, stop }
}

/// Why a search ended before deciding.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Halt {
    Budget(Budget),
    Cancelled,
}

/// The zeno memory (5.1): for every search item, the set of plant states (env ids) visited since
/// the last plan progress. The sets are persistent treaps sharing structure, so that adding a
/// state and testing membership cost O(log n) however long a path without progress grows (a
/// linked list made a 40 000-node chain quadratic).
struct ZenoSets {
    /// (env id, left, right); a set is the id of its root node.
    nodes: Vec<(u32, u32, u32)>,
}

impl ZenoSets {
    /// A fixed pseudo-random priority per key (a bijective integer mix), so that the treap's
    /// shape does not depend on the order of insertions.
    fn priority(env: u32) -> u32 {
        let mut x = env ^ 0x9e37_79b9;
        x ^= x >> 16;
        x = x.wrapping_mul(0x85eb_ca6b);
        x ^= x >> 13;
        x = x.wrapping_mul(0xc2b2_ae35);
        x ^ (x >> 16)
    }

    fn node(&mut self, env: u32, left: u32, right: u32) -> u32 {
        self.nodes.push((env, left, right));
        (self.nodes.len() - 1) as u32
    }

    fn singleton(&mut self, env: u32) -> u32 {
        self.node(env, NONE, NONE)
    }

    fn contains(&self, mut set: u32, env: u32) -> bool {
        while set != NONE {
            let (key, left, right) = self.nodes[set as usize];
            if env == key {
                return true;
            }
            set = if env < key { left } else { right };
        }
        false
    }

    /// `set` with `env` added; `set` itself if it already holds `env`.
    fn insert(&mut self, set: u32, env: u32) -> u32 {
        if self.contains(set, env) {
            set
        } else {
            self.insert_new(set, env)
        }
    }

    /// Path-copying insertion of a key that is not in `set`.
    fn insert_new(&mut self, set: u32, env: u32) -> u32 {
        if set == NONE {
            return self.singleton(env);
        }
        let (key, left, right) = self.nodes[set as usize];
        if Self::priority(env) > Self::priority(key) {
            let (l, r) = self.split(set, env);
            return self.node(env, l, r);
        }
        if env < key {
            let l = self.insert_new(left, env);
            self.node(key, l, right)
        } else {
            let r = self.insert_new(right, env);
            self.node(key, left, r)
        }
    }

    /// The keys of `set` below and above `env` (which it does not hold), as two new sets.
    fn split(&mut self, set: u32, env: u32) -> (u32, u32) {
        if set == NONE {
            return (NONE, NONE);
        }
        let (key, left, right) = self.nodes[set as usize];
        if key < env {
            let (l, r) = self.split(right, env);
            (self.node(key, left, l), r)
        } else {
            let (l, r) = self.split(left, env);
            (l, self.node(key, r, right))
        }
    }
}

/// One discrete move under construction.
struct Move {
    kind: MessageKind,
    message: MsgId,
    instant: bool,
    env: Vec<SubLocId>,
    resets: u64,
}

/// The target of a controller option not generated yet (strategy-directed search): the state's
/// key, how its zeno memory is formed, the request edge, and the guards checked before it.
struct Deferred {
    env: u32,
    plan: u32,
    zone: u32,
    kind: StateKind,
    vis: Vis,
    request: Edge,
    guards: Vec<MsgId>,
    /// The request returns to a plant state visited since the last plan progress.
    repeats: bool,
}

/// How the zeno memory of a new state is formed.
#[derive(Clone, Copy)]
enum Vis {
    /// A plan progressed: remember only the new plant state.
    Fresh,
    /// No progress: remember the new plant state on top of `parent`'s memory.
    Extend(u32),
    /// Waiting or a guard check: the plant state is unchanged.
    Same(u32),
}

struct Solver<'g, 'p> {
    game: &'g Game,
    split: &'g SplitGame,
    options: &'g SolveOptions,
    progress: &'p mut dyn FnMut(&Stats) -> bool,
    space: StateSpace,
    state_index: hashbrown::HashMap<(u32, u32, u32, StateKind), StateId>,
    /// States to expand: all reachable ones in the reference (breadth first), those the strategy
    /// needs in the strategy-directed search (depth first).
    queue: VecDeque<StateId>,
    /// Strategy-directed search rather than the exhaustive reference.
    lazy: bool,
    /// Cut moves by the zeno memory (see `SolveOptions::zeno_memory`), and how many were cut.
    memory: bool,
    memory_cuts: usize,
    deferred: Vec<Option<Deferred>>,
    expansions: usize,
    /// Per message with a sender: per location of the sender, how many transitions it needs at
    /// least before it can send the message (`u16::MAX` if never); the search's sense of
    /// direction towards the plans' goals.
    send_distance: Vec<Vec<u16>>,
    /// Per plan and sub-location: the messages that take the plan to its next goal (not to
    /// failure).
    plan_goals: Vec<Vec<Vec<MsgId>>>,
    zeno: ZenoSets,
    /// Per env id: 1 + index of the first violated assertion, or 0.
    env_violation: Vec<u32>,
    /// Per plan vector id: 1 + index of the first failed plan, or 0.
    plan_failure: Vec<u32>,
    /// Per env id: the original locations of the plant units (for predicates), flat.
    env_locations: Vec<LocId>,
    /// Clocks used per env id and per plan vector id, as bit sets.
    env_clocks: Vec<u64>,
    plan_clocks: Vec<u64>,
    lost_queue: Vec<StateId>,
    /// Strategy-directed search: the number of states at which to look for cycles without
    /// progress next (see `explore`).
    next_progress_check: usize,
    dim: usize,
    max_constants: Vec<i32>,
    removed: usize,
    expanded: usize,
    moves: Vec<Move>,
    pending_edges: Vec<Edge>,
    /// Work done so far (the split's included), and when the next progress call is due.
    work: u64,
    next_progress: u64,
    /// The work of one candidate successor (a zone and a state vector), and of one candidate
    /// state vector alone.
    successor_cost: u64,
    vector_cost: u64,
    halt: Option<Halt>,
    /// In a scan game: the scan automaton's quiet and armed sub-locations (see `scan::ScanRoles`).
    scan_arm: Option<ScanArm>,
}

/// Where a delay arms the scan automaton of a scan game.
struct ScanArm {
    unit: usize,
    quiet: SubLocId,
    /// `armed` with its clock at 0, and with its clock just above 0.
    armed_at_zero: SubLocId,
    armed_after_zero: SubLocId,
    clock: ClockId,
}

impl ScanArm {
    fn new(game: &Game, split: &SplitGame) -> Option<ScanArm> {
        let roles = game.scan.as_ref()?;
        let unit = roles.plc as usize;
        let sublocs = &split.units[unit].sublocs;
        let find = |loc: LocId, piece: Option<bool>| {
            let position = sublocs.iter().position(|sl| {
                sl.location == loc
                    && piece.is_none_or(|closed| {
                        sl.pieces.iter().any(|&(c, p)| {
                            let iv = split.pieces[c as usize][p as usize];
                            c == roles.clock && iv.lower == 0 && iv.lower_closed == closed
                        })
                    })
            });
            position.map(|p| p as SubLocId)
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

impl<'g, 'p> Solver<'g, 'p> {
    fn new(
        game: &'g Game,
        split: &'g SplitGame,
        options: &'g SolveOptions,
        progress: &'p mut dyn FnMut(&Stats) -> bool,
    ) -> Solver<'g, 'p> {
        let dim = game.dim();
        let plant_count = split.plant_count;
        let goals = if options.exhaustive { Vec::new() } else { plan_goals(split) };
        Solver {
            game,
            split,
            options,
            progress,
            space: StateSpace::empty(dim, plant_count, split.units.len() - plant_count),
            state_index: hashbrown::HashMap::new(),
            queue: VecDeque::new(),
            lazy: !options.exhaustive,
            memory: options.zeno_memory,
            memory_cuts: 0,
            deferred: Vec::new(),
            expansions: 0,
            send_distance: if options.exhaustive { Vec::new() } else { send_distances(game, &goals) },
            plan_goals: goals,
            zeno: ZenoSets { nodes: Vec::new() },
            env_violation: Vec::new(),
            plan_failure: Vec::new(),
            env_locations: Vec::new(),
            env_clocks: Vec::new(),
            plan_clocks: Vec::new(),
            lost_queue: Vec::new(),
            next_progress_check: 16,
            dim,
            max_constants: vec![-1; dim],
            removed: 0,
            expanded: 0,
            moves: Vec::new(),
            pending_edges: Vec::new(),
            work: split.work,
            next_progress: split.work + PROGRESS_WORK,
            successor_cost: STEP_COST + (dim * dim + split.units.len()) as u64,
            vector_cost: STEP_COST + split.units.len() as u64,
            halt: None,
            scan_arm: ScanArm::new(game, split),
        }
    }

    /// Approximate heap bytes of the split game and the state space (capacities, so the figure
    /// grows in steps as vectors double).
    fn bytes(&self) -> usize {
        let s = &self.space;
        self.split.bytes
            + s.states.capacity() * std::mem::size_of::<State>()
            + s.edges.capacity() * std::mem::size_of::<Edge>()
            + s.envs.heap_bytes()
            + s.plans.heap_bytes()
            + s.zones.heap_bytes()
            + self.state_index.capacity() * (std::mem::size_of::<((u32, u32, u32, StateKind), StateId)>() + 1)
            + self.queue.capacity() * std::mem::size_of::<StateId>()
            + self.deferred.capacity() * std::mem::size_of::<Option<Deferred>>()
            + self.zeno.nodes.capacity() * std::mem::size_of::<(u32, u32, u32)>()
            + self.env_locations.capacity() * std::mem::size_of::<LocId>()
            + (self.env_violation.capacity() + self.plan_failure.capacity()) * std::mem::size_of::<u32>()
            + (self.env_clocks.capacity() + self.plan_clocks.capacity()) * std::mem::size_of::<u64>()
    }

    fn stats(&self) -> Stats {
        let s = &self.space;
        Stats {
            visited: s.states.len(),
            expanded: self.expanded,
            winning: 0,
            removed: self.removed,
            edges: s.edges.len(),
            zones: s.zones.len(),
            bytes: self.bytes(),
            work: self.work,
        }
    }

    /// The budget the search has exceeded, if any.
    fn exceeded(&self) -> Option<Budget> {
        if self.space.states.len() > self.options.max_states {
            Some(Budget::States)
        } else if self.bytes() > self.options.max_bytes {
            Some(Budget::Memory)
        } else if self.work > self.options.max_work {
            Some(Budget::Work)
        } else {
            None
        }
    }

    /// Calls the progress callback; `false` if it cancels the run.
    fn report(&mut self) -> bool {
        self.next_progress = self.work + PROGRESS_WORK;
        let stats = self.stats();
        (self.progress)(&stats)
    }

    /// Accounts `units` of work. Returns `false`, with the reason in `halt`, when the search must
    /// stop: a budget is exceeded or, at a progress call during long work, the caller cancels.
    fn charge(&mut self, units: u64) -> bool {
        self.work += units;
        if self.halt.is_none() && self.work > self.options.max_work {
            self.halt = Some(Halt::Budget(Budget::Work));
        }
        if self.halt.is_none() && self.work >= self.next_progress {
            if let Some(budget) = self.exceeded() {
                self.halt = Some(Halt::Budget(budget));
            } else if !self.report() {
                self.halt = Some(Halt::Cancelled);
            }
        }
        self.halt.is_none()
    }

    fn run(&mut self) -> Verdict {
        let plant_count = self.split.plant_count;
        let env: Vec<SubLocId> = self.split.units[..plant_count].iter().map(|u| u.initial).collect();
        let plan: Vec<SubLocId> = self.split.units[plant_count..].iter().map(|u| u.initial).collect();
        let mut zone = Dbm::zero(self.dim);
        let (env_id, plan_id) = self.intern_discrete(&env, &plan);
        self.normalise(env_id, plan_id, &mut zone);
        let kind = if self.is_closed(&env, &plan, &zone) { StateKind::Interval } else { StateKind::Entry };
        self.space.initial = self.find_or_add(env_id, plan_id, &zone, kind, Vis::Fresh).0;
        if self.lazy {
            self.demand(self.space.initial);
        }
        // Explore, then cut the zeno cycles of what survived; in the strategy-directed search a
        // cut can make a state choose again, which needs more exploration.
        let verdict = loop {
            if let Some(stop) = self.explore() {
                break stop;
            }
            if !self.enforce_progress() {
                break if self.space.is_winning(self.space.initial) {
                    Verdict::Realizable
                } else {
                    Verdict::Unrealizable
                };
            }
        };
        if self.lazy && matches!(verdict, Verdict::Realizable | Verdict::Unrealizable) {
            self.mark_unexplored();
        }
        verdict
    }

    /// Expands queued states until none is left (`None`), the initial state is lost, or a budget
    /// or the caller stops the search.
    fn explore(&mut self) -> Option<Verdict> {
        loop {
            if !self.space.is_winning(self.space.initial) {
                return Some(Verdict::Unrealizable);
            }
            // The reference goes breadth first (algorithm 5); the strategy-directed search
            // depth first, so that a chosen line of play is followed to its end before others.
            let next = if self.lazy { self.queue.pop_back() } else { self.queue.pop_front() };
            let s = next?;
            let st = &self.space.states[s as usize];
            if st.removal.is_some() || st.expanded {
                continue;
            }
            if let Some(budget) = self.exceeded() {
                self.halt = Some(Halt::Budget(budget));
                return Some(Verdict::BudgetExceeded);
            }
            self.expansions += 1;
            if self.options.progress_interval > 0
                && self.expansions % self.options.progress_interval == 0
                && !self.report()
            {
                self.halt = Some(Halt::Cancelled);
                return Some(Verdict::Cancelled);
            }
            self.expand(s);
            // Strategy-directed search: a cycle without progress is found as soon as it
            // closes, not when the whole strategy is explored, so that a doomed choice is given
            // up before much is explored below it. Checked when the space has grown by a quarter
            // since the last check (amortised linear).
            if self.lazy && self.space.states.len() >= self.next_progress_check {
                self.next_progress_check = self.space.states.len() + self.space.states.len() / 4 + 16;
                let ranks = self.progress_ranks(Counting::Optimistic);
                if !self.remove_trapped(&ranks) {
                    self.steer_by_ranks(&ranks);
                }
            }
            match self.halt {
                Some(Halt::Budget(_)) => return Some(Verdict::BudgetExceeded),
                Some(Halt::Cancelled) => return Some(Verdict::Cancelled),
                None => {}
            }
        }
    }

    /// Strategy-directed search: states that were created but never needed are marked, so that
    /// the surviving states are exactly those whose every continuation under the strategy was
    /// explored.
    fn mark_unexplored(&mut self) {
        for st in &mut self.space.states {
            if st.removal.is_none() && !st.expanded {
                st.removal = Some(Removal::Unexplored);
            }
        }
    }

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
    fn enforce_progress(&mut self) -> bool {
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
    fn remove_trapped(&mut self, ranks: &[u32]) -> bool {
        let n = self.space.states.len();
        let trapped: Vec<StateId> = (0..n as StateId)
            .filter(|&s| {
                let st = &self.space.states[s as usize];
                st.removal.is_none() && st.expanded && ranks[s as usize] == NONE
            })
            .collect();
        if !trapped.is_empty() {
            let mut in_trap = vec![false; n];
            for &s in &trapped {
                in_trap[s as usize] = true;
            }
            for &s in &trapped {
                // The plant keeps the plays from progress if one of its moves stays in the trap;
                // otherwise every alternative of the controller does, and they are cut.
                let stays = |e: &Edge| !e.progress && !e.zeno && e.to != NONE && in_trap[e.to as usize];
                let (start, end) = (self.space.states[s as usize].out_start, self.space.states[s as usize].out_end);
                let culprit = (start..end).find(|&id| {
                    self.space.edges[id as usize].class == Class::Forced && stays(&self.space.edges[id as usize])
                });
                match culprit {
                    Some(edge) => {
                        self.space.edges[edge as usize].zeno = true;
                        self.remove(s, Removal::ZenoLoop { edge });
                    }
                    None => {
                        for id in start..end {
                            let e = &mut self.space.edges[id as usize];
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
    /// `counting` is `Explored`, reach something untried), `NONE` if it never does. Along a
    /// move that makes no progress, a joining state relies only on states of lower rank.
    fn progress_ranks(&self, counting: Counting) -> Vec<u32> {
        let optimistic = counting != Counting::Explored;
        let strategy = counting == Counting::Strategy;
        let space = &self.space;
        let n = space.states.len();
        let mut rank = vec![NONE; n];
        // Per state: forced moves still waiting for their target, delays still waiting
        // (`NONE`: waiting cannot help), and whether some option is good.
        let mut forced_wanted = vec![0u32; n];
        let mut waits_wanted = vec![NONE; n];
        let mut option_good = vec![false; n];
        let mut queue = VecDeque::new();
        let joins = |f: u32, w: u32, o: bool| f == 0 && (o || w == 0);
        for s in 0..n as StateId {
            let st = &space.states[s as usize];
            if st.removal.is_some() {
                continue;
            }
            if !st.expanded {
                if optimistic {
                    rank[s as usize] = 0;
                    queue.push_back(s);
                }
                continue;
            }
            let (mut forced, mut forced_any, mut blocked) = (0u32, false, false);
            // Counting only the strategy's moves: its choice and the plant's.
            let waiting = !strategy || st.choice == WAIT;
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
                } else if e.to == NONE || space.states[e.to as usize].removal.is_some() {
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
                continue; // a lost forced move: the safety removal is on its way
            }
            let waits = if wait_blocked || (wait_edges == 0 && !forced_any) { NONE } else { waits };
            forced_wanted[s as usize] = forced;
            waits_wanted[s as usize] = waits;
            option_good[s as usize] = good;
            if joins(forced, waits, good) {
                rank[s as usize] = 0;
                queue.push_back(s);
            }
        }
        while let Some(y) = queue.pop_front() {
            let mut id = space.states[y as usize].first_in;
            while id != NONE {
                let edge_id = id;
                let e = &space.edges[id as usize];
                id = e.next_in;
                let x = e.from as usize;
                let xs = &space.states[x];
                if rank[x] != NONE || xs.removal.is_some() || !xs.expanded || e.zeno || e.progress {
                    continue;
                }
                if strategy && e.class == Class::Option && edge_id != xs.choice {
                    continue;
                }
                match e.class {
                    Class::Forced => forced_wanted[x] -= 1,
                    Class::Option => option_good[x] = true,
                    Class::Wait if waits_wanted[x] != NONE => waits_wanted[x] -= 1,
                    Class::Wait | Class::Inert => continue,
                }
                if joins(forced_wanted[x], waits_wanted[x], option_good[x]) {
                    rank[x] = rank[y as usize] + 1;
                    queue.push_back(x as StateId);
                }
            }
        }
        rank
    }

    /// Whether alternative `alt` (an option edge or `WAIT`) of `s` is good by `ranks`: every move
    /// it allows makes progress or reaches a lower rank (an untried move counts as good).
    fn decreases(&self, ranks: &[u32], s: StateId, alt: u32) -> bool {
        // States generated after the ranks were computed are unexpanded: optimistic rank 0.
        let rank = |t: StateId| ranks.get(t as usize).copied().unwrap_or(0);
        let own = rank(s);
        let good = |e: &Edge| {
            if e.zeno {
                return false;
            }
            if e.is_unexplored() {
                return true;
            }
            e.to != NONE && self.space.is_winning(e.to) && (e.progress || rank(e.to) < own)
        };
        if alt == WAIT {
            let st = &self.space.states[s as usize];
            st.wait_viable && self.space.out_edges(s).filter(|(_, e)| e.class == Class::Wait).all(|(_, e)| good(e))
        } else {
            good(&self.space.edges[alt as usize])
        }
    }

    /// Strategy-directed search, after a round that removed nothing: while the strategy lets
    /// some play cycle without progress (a state it reaches that its own moves do not rank),
    /// the first such state, from the initial state, whose choice does not decrease the
    /// (optimistic) rank of the whole explored game moves onto one that does, an explored one
    /// where possible. One switch at a time: leaving a cycle at one state mends it for the
    /// others. Returns whether anything changed (a choice, or something to explore).
    fn steer_by_ranks(&mut self, ranks: &[u32]) -> bool {
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
    fn first_unranked_switch(&self, ranks: &[u32], strategy: &[u32]) -> Option<(StateId, u32)> {
        let mut seen = vec![false; self.space.states.len()];
        let mut queue = VecDeque::from([self.space.initial]);
        seen[self.space.initial as usize] = true;
        while let Some(s) = queue.pop_front() {
            let st = &self.space.states[s as usize];
            if st.removal.is_some() || !st.expanded {
                continue;
            }
            // A guard state generated since `ranks` keeps its choice until the next round.
            if strategy[s as usize] == NONE
                && (s as usize) < ranks.len()
                && (st.choice == NONE || !self.decreases(ranks, s, st.choice))
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
                    Class::Wait => st.choice == WAIT,
                    Class::Inert => false,
                };
                if follows && e.to != NONE && !seen[e.to as usize] {
                    seen[e.to as usize] = true;
                    queue.push_back(e.to);
                }
            }
        }
        None
    }

    /// Whether taking alternative `alt` of `s` needs a target generated first.
    fn needs_generation(&self, s: StateId, alt: u32) -> bool {
        if alt == WAIT {
            self.space.out_edges(s).any(|(_, e)| e.class == Class::Wait && e.is_unexplored())
        } else {
            self.space.edges[alt as usize].is_unexplored()
        }
    }

    /// Makes `alt` the choice of `s`, generating its targets if needed and queuing them.
    fn take(&mut self, s: StateId, alt: u32) {
        let (start, end) = (self.space.states[s as usize].out_start, self.space.states[s as usize].out_end);
        let edges: Vec<EdgeId> = if alt == WAIT {
            (start..end).filter(|&id| self.space.edges[id as usize].class == Class::Wait).collect()
        } else {
            vec![alt]
        };
        for &id in &edges {
            if self.space.edges[id as usize].is_unexplored() {
                self.generate(id);
            }
        }
        self.space.states[s as usize].choice = alt;
        for &id in &edges {
            let to = self.space.edges[id as usize].to;
            if to != NONE {
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
        let final_ranks;
        let ranks = if self.lazy {
            final_ranks = self.progress_ranks(Counting::Explored);
            &final_ranks
        } else {
            ranks
        };
        let live = |st: &State| st.removal.is_none() && st.expanded;
        for (s, st) in self.space.states.iter_mut().enumerate() {
            if live(st) && ranks[s] == NONE {
                st.removal = Some(Removal::Unexplored);
            }
        }
        // Components of the winning states under their live moves without progress.
        let space = &self.space;
        let nodes: Vec<StateId> =
            (0..space.states.len() as StateId).filter(|&s| live(&space.states[s as usize])).collect();
        let mut index = vec![NONE; space.states.len()];
        let mut graph = petgraph::Graph::<(), ()>::with_capacity(nodes.len(), 0);
        for &s in &nodes {
            index[s as usize] = graph.add_node(()).index() as u32;
        }
        for &s in &nodes {
            for (_, e) in space.out_edges(s) {
                if !e.progress && !e.zeno && e.class != Class::Inert && e.to != NONE && index[e.to as usize] != NONE {
                    let (from, to) = (index[s as usize] as usize, index[e.to as usize] as usize);
                    graph.add_edge(petgraph::graph::NodeIndex::new(from), petgraph::graph::NodeIndex::new(to), ());
                }
            }
        }
        // Kosaraju: iterative, and a chain of moves without progress can be deeper than the stack.
        let mut component = vec![NONE; space.states.len()];
        for (c, scc) in petgraph::algo::kosaraju_scc(&graph).iter().enumerate() {
            for &i in scc {
                component[nodes[i.index()] as usize] = c as u32;
            }
        }
        drop(graph);
        let on_cycle = |space: &StateSpace, e: &Edge| {
            !e.progress
                && e.to != NONE
                && component[e.to as usize] != NONE
                && component[e.to as usize] == component[e.from as usize]
                && space.is_winning(e.to)
        };
        for s in nodes {
            let (start, end) = (self.space.states[s as usize].out_start, self.space.states[s as usize].out_end);
            let wait_cut = !self.decreases(ranks, s, WAIT)
                && (start..end).any(|id| {
                    let e = &self.space.edges[id as usize];
                    e.class == Class::Wait && !e.zeno && on_cycle(&self.space, e)
                });
            for id in start..end {
                let e = self.space.edges[id as usize];
                let cut = !e.zeno
                    && match e.class {
                        Class::Option => on_cycle(&self.space, &e) && !self.decreases(ranks, s, id),
                        Class::Wait => wait_cut,
                        _ => false,
                    };
                if cut {
                    self.space.edges[id as usize].zeno = true;
                    if e.class == Class::Option && !self.lazy {
                        self.space.states[s as usize].options_alive -= 1;
                    }
                }
            }
            if wait_cut {
                self.space.states[s as usize].wait_viable = false;
            }
            // The strategy's own choice may have been cut where another alternative gave the
            // state its rank: it moves there.
            let choice = self.space.states[s as usize].choice;
            let kept = |solver: &Self, alt: u32| {
                if alt == WAIT {
                    !wait_cut && solver.space.states[s as usize].wait_viable
                } else {
                    solver.space.is_live(&solver.space.edges[alt as usize])
                }
            };
            if self.lazy && choice != NONE && !kept(self, choice) {
                let mut k = 0;
                while let Some(alt) = self.alternative(s, k) {
                    k += 1;
                    if kept(self, alt) {
                        self.space.states[s as usize].choice = alt;
                        break;
                    }
                }
            }
        }
    }

    // ----- discrete parts and zones ------------------------------------------------------------

    fn intern_discrete(&mut self, env: &[SubLocId], plan: &[SubLocId]) -> (u32, u32) {
        let units = &self.split.units;
        let (env_id, new_env) = self.space.envs.intern(env);
        if new_env {
            let locs: Vec<LocId> =
                env.iter().enumerate().map(|(u, &s)| units[u].sublocs[s as usize].location).collect();
            self.env_locations.extend_from_slice(&locs);
            let violated = self.game.assertions.iter().position(|a| !a.holds.eval(&locs)).map_or(0, |i| i as u32 + 1);
            self.env_violation.push(violated);
            let mut clocks = 0u64;
            for (u, &s) in env.iter().enumerate() {
                for &(c, _) in &units[u].sublocs[s as usize].pieces {
                    clocks |= 1 << c;
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
                .position(|(p, &s)| units[base + p].sublocs[s as usize].failed)
                .map_or(0, |i| i as u32 + 1);
            self.plan_failure.push(failed);
            let mut clocks = 0u64;
            for (p, &s) in plan.iter().enumerate() {
                for &(c, _) in &units[base + p].sublocs[s as usize].pieces {
                    clocks |= 1 << c;
                }
            }
            self.plan_clocks.push(clocks);
        }
        (env_id, plan_id)
    }

    /// Extrapolates with the maximal constants of the clocks in use; unused clocks are freed
    /// (the clock usage reduction of 5.2.1).
    fn normalise(&mut self, env_id: u32, plan_id: u32, zone: &mut Dbm) {
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
            for &(clock, piece) in &units[u].sublocs[s as usize].pieces {
                let iv = &self.split.pieces[clock as usize][piece as usize];
                if let Some(upper) = iv.upper {
                    let b = if iv.upper_closed { Bound::le(upper as i32) } else { Bound::lt(upper as i32) };
                    if !zone.constrain(clock as usize, 0, b) {
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

    fn is_closed(&self, env: &[SubLocId], plan: &[SubLocId], zone: &Dbm) -> bool {
        self.time_closure(env, plan, zone).is_some_and(|c| &c == zone)
    }

    fn locations_of(&self, env_id: u32) -> &[LocId] {
        let w = self.split.plant_count;
        &self.env_locations[env_id as usize * w..env_id as usize * w + w]
    }

    /// Finds or adds the state. A new state violating an assertion or with a failed plan is
    /// stored as removed; any other new state is queued for expansion.
    fn find_or_add(&mut self, env_id: u32, plan_id: u32, zone: &Dbm, kind: StateKind, vis: Vis) -> (StateId, bool) {
        let (zone_id, _) = self.space.zones.intern(zone.as_slice());
        self.add_interned(env_id, plan_id, zone_id, kind, vis)
    }

    /// [`Self::find_or_add`] with the zone interned. Only the reference queues new states: the
    /// strategy-directed search expands what its strategy needs (`demand`).
    fn add_interned(&mut self, env_id: u32, plan_id: u32, zone_id: u32, kind: StateKind, vis: Vis) -> (StateId, bool) {
        let key = (env_id, plan_id, zone_id, kind);
        if let Some(&id) = self.state_index.get(&key) {
            return (id, false);
        }
        let id = self.space.states.len() as StateId;
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
        if removal.is_some() {
            self.removed += 1;
        } else if kind != StateKind::Guard && !self.lazy {
            self.queue.push_back(id);
        }
        (id, true)
    }

    /// True if the plant state `env_id` is in the zeno memory `vis`.
    fn visited(&self, vis: u32, env_id: u32) -> bool {
        self.zeno.contains(vis, env_id)
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
            for e in &units[u].sublocs[s as usize].edges {
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
                for &other in &split.sync_units[e.message as usize] {
                    let other = other as usize;
                    let options: Vec<_> = units[other].sublocs[env[other] as usize]
                        .edges
                        .iter()
                        .filter(|se| se.kind == MessageKind::Synchronised && se.message == e.message)
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
                        return;
                    }
                }
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

    fn expand(&mut self, s: StateId) {
        let st = self.space.states[s as usize].clone();
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
                let slot = *sub as usize * self.split.message_count + m.message as usize;
                let next = self.split.plan_next[p][slot];
                if next != STAY {
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
            // The strategy-directed search generates an option's target only once it tries it.
            let defer = self.lazy && m.kind == MessageKind::Controllable && !cut;
            let to = if cut || defer { NONE } else { self.find_or_add(env_id, plan_id, &z, kind, vis).0 };
            let edge = Edge {
                from: s,
                to,
                kind: edge_kind,
                label,
                resets,
                instant: m.instant,
                zeno: cut,
                progress,
                class,
                next_in: NONE,
                deferred: NONE,
            };
            if m.kind == MessageKind::Controllable && !cut {
                let before = self.locations_of(st.env).to_vec();
                let after = self.locations_of(env_id).to_vec();
                let guards: Vec<MsgId> = self
                    .game
                    .guards
                    .iter()
                    .filter(|g| g.cond.eval(&after) && !g.cond.eval(&before))
                    .map(|g| g.message)
                    .collect();
                if defer {
                    let (zone, _) = self.space.zones.intern(z.as_slice());
                    let first = match guards.first() {
                        Some(&g) => guard_edge(s, NONE, g, m.instant),
                        None => edge,
                    };
                    self.pending_edges.push(Edge { deferred: self.deferred.len() as u32, ..first });
                    let (env, plan) = (env_id, plan_id);
                    self.deferred.push(Some(Deferred { env, plan, zone, kind, vis, request: edge, guards, repeats }));
                    continue;
                }
                if !guards.is_empty() {
                    guard_chains.push((self.pending_edges.len(), guards));
                }
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
                        to: NONE,
                        kind: EdgeKind::Delay,
                        label: Label::Wait,
                        resets: 0,
                        instant: false,
                        zeno: false,
                        progress: false,
                        class: Class::Wait,
                        next_in: NONE,
                        deferred: NONE,
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
                self.evaluate(chain[k]);
                self.propagate();
            }
            own[index] = guard_edge(s, chain[0], guards[0], request.instant);
        }
        if self.lazy {
            // Alternatives in the order the strategy tries them (see `alternative`).
            // Among options: plan progress first, then the nearer to the plans' goals.
            let keys: Vec<(u8, u32)> = own
                .iter()
                .map(|e| match e.class {
                    Class::Forced => (0, 0),
                    Class::Option if e.is_unexplored() => {
                        let d = self.deferred[e.deferred as usize].as_ref().expect("a deferred target");
                        let order = if e.progress {
                            1
                        } else if d.repeats {
                            3
                        } else {
                            2
                        };
                        (order, self.goal_distance(d.env, d.plan))
                    }
                    Class::Option => (4, 0),
                    Class::Wait => (5, 0),
                    Class::Inert => (6, 0),
                })
                .collect();
            let mut order: Vec<usize> = (0..own.len()).collect();
            order.sort_by_key(|&i| keys[i]);
            let own: Vec<Edge> = order.into_iter().map(|i| own[i]).collect();
            self.commit_edges(s, own);
            self.evaluate_lazy(s);
        } else {
            self.commit_edges(s, own);
            self.evaluate(s);
        }
        self.propagate();
    }

    fn add_guard_state(&mut self, st: &State) -> StateId {
        let id = self.space.states.len() as StateId;
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
            let sl = &self.split.units[u].sublocs[sub as usize];
            for &(clock, piece) in &sl.pieces {
                let iv = self.split.pieces[clock as usize][piece as usize];
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
            let (ck, cr) = (exits[k].clock as usize, exits[r].clock as usize);
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
            let from = &self.split.units[e.unit].sublocs[*sub as usize];
            if let Some(d) = from.delays.iter().find(|d| d.clock == e.clock) {
                *sub = d.target;
                continue;
            }
            // The clock runs past its invariant (plant) or past the last piece it may have.
            if e.unit < plant_count {
                self.pending_edges.push(Edge {
                    from: s,
                    to: NONE,
                    kind: EdgeKind::Timeout,
                    label: Label::Overrun { clock: e.clock },
                    resets: 0,
                    instant: false,
                    zeno: false,
                    progress: false,
                    class: Class::Inert,
                    next_in: NONE,
                    deferred: NONE,
                });
            }
            return;
        }
        // A scan game's PLC that saw no change at its last read notices this one (a timer
        // reaching its threshold) at its next read: its clock starts at the instant of the change.
        if let Some(arm) = &self.scan_arm {
            if env2[arm.unit] == arm.quiet && set.iter().any(|&k| exits[k].clock != arm.clock) {
                let first = &exits[set[0]];
                let c = first.clock as usize;
                zone.up();
                if !(zone.constrain(c, 0, Bound::le(first.upper)) && zone.constrain(0, c, Bound::le(-first.upper))) {
                    return;
                }
                zone.reset(arm.clock as usize);
                // The clock is 0 at the change: in the target it is still 0 if the piece entered
                // starts there, and above 0 if the piece starts just after it.
                env2[arm.unit] = if first.closed { arm.armed_after_zero } else { arm.armed_at_zero };
            }
        }
        zone.up();
        for &k in set {
            let e = &exits[k];
            let iv = self.split.pieces[e.clock as usize][e.next_piece as usize];
            let lower = if iv.lower_closed { Bound::le(-(iv.lower as i32)) } else { Bound::lt(-(iv.lower as i32)) };
            if !zone.constrain(0, e.clock as usize, lower) {
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
        let clocks = set.iter().fold(0u64, |bits, &k| bits | 1 << exits[k].clock);
        let edge = Edge {
            from: s,
            to: NONE,
            kind: EdgeKind::Delay,
            label: Label::Piece { clock: first.clock, piece: first.next_piece, clocks },
            resets: 0,
            instant: false,
            zeno: false,
            progress: false,
            class: Class::Wait,
            next_in: NONE,
            deferred: NONE,
        };
        self.add_wait_edge(edge, env_id, plan_id, &zone, StateKind::Interval, Vis::Extend(st.vis));
    }

    /// Adds a wait edge into the given state: generated at once in the reference, deferred in the
    /// strategy-directed search until the strategy tries waiting.
    fn add_wait_edge(&mut self, edge: Edge, env: u32, plan: u32, zone: &Dbm, kind: StateKind, vis: Vis) {
        if self.lazy {
            let (zone, _) = self.space.zones.intern(zone.as_slice());
            self.pending_edges.push(Edge { deferred: self.deferred.len() as u32, ..edge });
            self.deferred.push(Some(Deferred {
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
            let to = self.find_or_add(env, plan, zone, kind, vis).0;
            self.pending_edges.push(Edge { to, ..edge });
        }
    }

    fn commit_edges(&mut self, s: StateId, edges: Vec<Edge>) {
        let start = self.space.edges.len() as EdgeId;
        for mut e in edges {
            let id = self.space.edges.len() as EdgeId;
            e.from = s;
            if e.to != NONE {
                let target = &mut self.space.states[e.to as usize];
                e.next_in = target.first_in;
                target.first_in = id;
            }
            self.space.edges.push(e);
        }
        let st = &mut self.space.states[s as usize];
        st.out_start = start;
        st.out_end = self.space.edges.len() as EdgeId;
        st.expanded = true;
        self.expanded += 1;
    }

    /// One pass over the edges of an expanded state: what the local rule of the module doc needs.
    fn survey(&self, s: StateId) -> Survey {
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
    fn evaluate(&mut self, s: StateId) {
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

    fn remove(&mut self, s: StateId, reason: Removal) {
        let st = &mut self.space.states[s as usize];
        if st.removal.is_none() {
            st.removal = Some(reason);
            self.removed += 1;
            self.lost_queue.push(s);
        }
    }

    /// Algorithm 6: removes, backwards, every state that can no longer avoid a removed one.
    fn propagate(&mut self) {
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

    // ----- strategy-directed search ----------------------------------------------------------

    /// How far the plant state `env_id` is from the goals of the plans in `plan_id`: per plan,
    /// the fewest transitions before some sender can send a message that takes the plan to its
    /// next goal, summed over the plans.
    fn goal_distance(&self, env_id: u32, plan_id: u32) -> u32 {
        let locations = self.locations_of(env_id);
        let mut total = 0u32;
        for (p, &sub) in self.space.plans.get(plan_id).iter().enumerate() {
            let nearest = self.plan_goals[p][sub as usize]
                .iter()
                .filter_map(|&m| {
                    let sender = self.game.messages[m as usize].sender? as usize;
                    self.send_distance[m as usize].get(locations[sender] as usize).copied()
                })
                .min()
                .unwrap_or(u16::MAX);
            total += u32::from(nearest);
        }
        total
    }

    /// Queues `s` for expansion if it still needs it.
    fn demand(&mut self, s: StateId) {
        let st = &self.space.states[s as usize];
        if st.removal.is_none() && !st.expanded {
            self.queue.push_back(s);
        }
    }

    /// Decides a freshly expanded state of the strategy-directed search: lost if a forced move
    /// is; otherwise its forced successors are needed and it chooses its first alternative.
    fn evaluate_lazy(&mut self, s: StateId) {
        let survey = self.survey(s);
        if let Some(removal) = survey.dead_forced {
            self.remove(s, removal);
            return;
        }
        self.space.states[s as usize].wait_viable = survey.wait_viable();
        let st = &self.space.states[s as usize];
        for id in st.out_start..st.out_end {
            let e = self.space.edges[id as usize];
            if e.class == Class::Forced {
                self.demand(e.to);
            }
        }
        self.choose(s);
    }

    /// The `k`-th alternative of the expanded state `s` in the order the strategy tries them:
    /// an option edge, `WAIT`, or `None` when all are tried. Options are stored with those that
    /// make plan progress first, then by distance to the plans' goals. Waiting comes first where
    /// it costs nothing (no delay edge, so only the forced moves, needed anyway, follow it), else
    /// after every option (measured: fewest states on the examples).
    fn alternative(&self, s: StateId, k: u32) -> Option<u32> {
        let st = &self.space.states[s as usize];
        let (mut first_option, mut options, mut waits, mut forced) = (NONE, 0, 0, false);
        for id in st.out_start..st.out_end {
            let e = &self.space.edges[id as usize];
            match e.class {
                Class::Option => {
                    first_option = first_option.min(id);
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
            Some(w) if k == w => return Some(WAIT),
            Some(w) if k > w => k - 1,
            _ => k,
        };
        (option < options).then(|| first_option + option)
    }

    /// Picks the first alternative of `s`, from the `tried`-th on, that is not lost yet,
    /// generating an option's target when it is tried the first time, and queues what it needs.
    /// Without one, `s` is lost.
    fn choose(&mut self, s: StateId) {
        loop {
            let k = self.space.states[s as usize].tried;
            match self.alternative(s, k) {
                None => {
                    let st = &mut self.space.states[s as usize];
                    st.choice = NONE;
                    let inert =
                        (st.out_start..st.out_end).all(|id| self.space.edges[id as usize].class == Class::Inert);
                    self.remove(s, if inert { Removal::Deadlock } else { Removal::NoMove });
                    return;
                }
                Some(WAIT) => {
                    let (start, end) = (self.space.states[s as usize].out_start, self.space.states[s as usize].out_end);
                    let waits: Vec<EdgeId> =
                        (start..end).filter(|&id| self.space.edges[id as usize].class == Class::Wait).collect();
                    for &id in &waits {
                        if self.space.edges[id as usize].is_unexplored() {
                            self.generate(id);
                        }
                    }
                    let st = &self.space.states[s as usize];
                    let viable = if waits.is_empty() {
                        st.wait_viable
                    } else {
                        st.wait_viable && waits.iter().all(|&id| self.space.is_live(&self.space.edges[id as usize]))
                    };
                    if viable {
                        self.space.states[s as usize].choice = WAIT;
                        for &id in &waits {
                            self.demand(self.space.edges[id as usize].to);
                        }
                        return;
                    }
                    self.space.states[s as usize].wait_viable = false;
                }
                Some(edge) => {
                    if self.space.edges[edge as usize].is_unexplored() {
                        self.generate(edge);
                    }
                    let e = self.space.edges[edge as usize];
                    if self.space.is_live(&e) {
                        self.space.states[s as usize].choice = edge;
                        self.demand(e.to);
                        return;
                    }
                }
            }
            self.space.states[s as usize].tried += 1;
        }
    }

    /// Generates the target of a deferred option (with its chain of guard states) and links the
    /// edge to it.
    fn generate(&mut self, edge: EdgeId) {
        let index = std::mem::replace(&mut self.space.edges[edge as usize].deferred, NONE);
        let Some(d) = self.deferred[index as usize].take() else { return };
        let from = self.space.edges[edge as usize].from;
        let target = self.add_interned(d.env, d.plan, d.zone, d.kind, d.vis).0;
        let first = if d.guards.is_empty() {
            target
        } else {
            let st = self.space.states[from as usize].clone();
            let chain: Vec<StateId> = d.guards.iter().map(|_| self.add_guard_state(&st)).collect();
            for k in (0..chain.len()).rev() {
                let next = match chain.get(k + 1) {
                    Some(&next) => guard_edge(chain[k], next, d.guards[k + 1], d.request.instant),
                    None => Edge { from: chain[k], to: target, ..d.request },
                };
                self.commit_edges(chain[k], vec![next]);
                self.evaluate_lazy(chain[k]);
            }
            chain[0]
        };
        let target_state = &mut self.space.states[first as usize];
        let e = &mut self.space.edges[edge as usize];
        e.to = first;
        e.next_in = target_state.first_in;
        target_state.first_in = edge;
    }
}

/// Per plan and sub-location: the messages that take the plan to a goal rather than to failure.
fn plan_goals(split: &SplitGame) -> Vec<Vec<Vec<MsgId>>> {
    let messages = split.message_count;
    (0..split.units.len() - split.plant_count)
        .map(|p| {
            let unit = &split.units[split.plant_count + p];
            (0..unit.sublocs.len())
                .map(|sub| {
                    let next = &split.plan_next[p][sub * messages..(sub + 1) * messages];
                    (0..messages)
                        .filter(|&m| next[m] != STAY && !unit.sublocs[next[m] as usize].failed)
                        .map(|m| m as MsgId)
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
fn send_distances(game: &Game, plan_goals: &[Vec<Vec<MsgId>>]) -> Vec<Vec<u16>> {
    let mut goal = vec![false; game.messages.len()];
    for &m in plan_goals.iter().flatten().flatten() {
        goal[m as usize] = true;
    }
    // Incoming edges per location, per automaton, built once for the automata that send a goal.
    let mut incoming: Vec<Option<Vec<Vec<LocId>>>> = vec![None; game.components.len()];
    game.messages
        .iter()
        .enumerate()
        .map(|(m, message)| {
            let Some(sender) = message.sender.filter(|_| goal[m]) else { return Vec::new() };
            let automaton = &game.components[sender as usize];
            let incoming = incoming[sender as usize].get_or_insert_with(|| {
                let mut lists = vec![Vec::new(); automaton.locations.len()];
                for e in &automaton.edges {
                    lists[e.to as usize].push(e.from);
                }
                lists
            });
            let mut distance = vec![u16::MAX; automaton.locations.len()];
            let mut queue = VecDeque::new();
            for e in &automaton.edges {
                if e.message as usize == m && e.kind != MessageKind::Synchronised && distance[e.from as usize] != 1 {
                    distance[e.from as usize] = 1;
                    queue.push_back(e.from);
                }
            }
            while let Some(loc) = queue.pop_front() {
                let d = distance[loc as usize].saturating_add(1);
                for &from in &incoming[loc as usize] {
                    if distance[from as usize] == u16::MAX {
                        distance[from as usize] = d;
                        queue.push_back(from);
                    }
                }
            }
            distance
        })
        .collect()
}

/// Which moves `Solver::progress_ranks` counts on.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Counting {
    /// Every explored move; nothing untried.
    Explored,
    /// Every explored move, and an untried alternative or an unexpanded state as progress.
    Optimistic,
    /// Only the strategy's choices and the plant's moves, untried ones as progress.
    Strategy,
}

/// What one pass over a state's edges finds (`Solver::survey`).
#[derive(Default)]
struct Survey {
    forced_any: bool,
    /// The removal a lost forced move causes (the first such move).
    dead_forced: Option<Removal>,
    options_alive: u32,
    wait_edges: u32,
    wait_ok: bool,
    /// No edge, or only timeouts.
    all_inert: bool,
}

impl Survey {
    /// Waiting is possible if all its targets survive, or, without delays, if the plant must act.
    fn wait_viable(&self) -> bool {
        if self.wait_edges > 0 {
            self.wait_ok
        } else {
            self.forced_any
        }
    }
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
    zone.constrain(c.clock as usize, r.clock as usize, bound)
}

fn guard_edge(from: StateId, to: StateId, message: MsgId, instant: bool) -> Edge {
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
        next_in: NONE,
        deferred: NONE,
    }
}

fn clock_bits(clocks: &[ClockId]) -> u64 {
    clocks.iter().fold(0, |bits, &c| bits | 1 << c)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::HashSet;

    #[test]
    fn zeno_sets_are_persistent_sets() {
        // A random tree of insertions: every version keeps exactly its own keys, whatever was
        // added to other versions later.
        let mut rng = crate::rng::Rng::new(9);
        let mut sets = ZenoSets { nodes: Vec::new() };
        let first = sets.singleton(5);
        let mut versions: Vec<(u32, HashSet<u32>)> = vec![(first, HashSet::from([5]))];
        for _ in 0..3000 {
            let (set, keys) = versions[rng.below(versions.len() as u64) as usize].clone();
            let key = rng.below(400) as u32;
            let grown = sets.insert(set, key);
            let mut grown_keys = keys.clone();
            assert_eq!(grown == set, !grown_keys.insert(key), "inserting a present key keeps the set");
            versions.push((grown, grown_keys));
        }
        for (set, keys) in &versions {
            for key in 0..400 {
                assert_eq!(sets.contains(*set, key), keys.contains(&key));
            }
        }
        assert!(!sets.contains(NONE, 5));
    }
}
