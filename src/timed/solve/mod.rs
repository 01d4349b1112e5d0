//! Solving the timed safety game (Peter 2005, 5.3). Two searches share one core. The reference
//! (`exhaustive`) is the thesis's on-the-fly forward exploration of the combined state space
//! (algorithm 5, breadth first) with incremental reverse removal of losing states (algorithm 6).
//! The default search (`directed`) builds one strategy instead: forced successors are always
//! explored, the controller's alternatives one at a time (`alternative` gives the order), the
//! next only when the chosen one is lost, which the reverse removal reports through the same
//! in-edge lists (a local fixpoint computation in the manner of Liu and Smolka, as UPPAAL
//! TIGA's on-the-fly algorithm). Targets of untried options and delays are not generated
//! (`Edge::is_unexplored`).
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
//! cycle of the winning graph without plan progress is cut as well (`keep_rank_decreasing`, in
//! `progress`).
//! Transitions marked `instant` are urgent: while one is enabled, no other transition and no
//! delay is possible; an instant reaction goes before an instant request.
//!
//! The parts. The core, which both searches run: `space` (states, edges, removals: what a
//! solved space holds), `meter` (budgets, work, progress calls, statistics), `expand`
//! (successor generation, discrete parts and zones), `removal` (what the local rule reads,
//! and backward propagation), `progress` (the nested fixpoint, its ranks and the zeno cut),
//! `zeno` (the zeno memory). The searches, behind the `Search` trait the core asks where they
//! part: `exhaustive` (the reference: breadth first, every reachable state, decided eagerly)
//! and `directed` (the strategy-directed search: depth first, what the strategy needs,
//! decided lazily, steered by the ranks), with `strategy` (its order of alternatives and its
//! choice) and `guide` (a zero-time strategy as a scan game's first choices). This file holds
//! the options, the entry point, the `Search` trait and the search loop.

mod directed;
mod exhaustive;
mod expand;
mod guide;
mod meter;
mod progress;
mod removal;
mod space;
mod strategy;
mod zeno;

use crate::search::OnProgress;
pub use crate::search::{Outcome, Resource, Stop};
pub use guide::ScanGuide;
pub use meter::Stats;
pub(crate) use meter::{split_stop, Halt, PROGRESS_WORK, STEP_COST};
pub use space::{Edge, EdgeId, EdgeKind, Label, Removal, State, StateId, StateKind, StateSpace};

use super::arena::SliceArena;
use super::model::*;
use super::precompute::{SplitGame, SubLocId};
use crate::search::Meter;
use crate::zone::Dbm;
use directed::Directed;
use exhaustive::Exhaustive;
use expand::{Move, ScanArm};
use progress::Counting;
use strategy::Deferred;
use zeno::{Vis, ZenoSets};

/// Limits and switches of one solver run.
#[derive(Clone, Debug)]
pub struct Config {
    /// Stop with a [`Stop::Budget`] once this many states are stored.
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
    /// Scan games, strategy-directed search: a move into a zone that a surviving state of the
    /// same locations includes, its plan clocks allowed to be lower there, goes to that state
    /// (a plan clock only meets deadlines, so whatever the strategy does from the larger zone
    /// it can do from the smaller one); should that state be lost, the move gets a state of its
    /// own. Far fewer states where the scan's phase splits zones. This search gets a quarter of
    /// every budget; if it stops there, the search without inclusion runs with the rest.
    /// `false` stores every zone as its own state at once.
    pub inclusion: bool,
    /// Scan games, strategy-directed search: a new state is lost at once when a lost state of
    /// the same locations and kind has a zone that lies in the new one's, plan clocks allowed
    /// to be lower there (`Removal::Dominated`): the dual of inclusion (were the new state won,
    /// so would be the lost one). Loss proofs then do not explore again, zone by zone, what
    /// lower plan clocks already lost. `false` explores every new state.
    pub dominance: bool,
}

/// Default state budget: the exhaustive reference stores 824 640 states for round table 8/8
/// (the strategy-directed search 286).
pub const DEFAULT_MAX_STATES: usize = 1_000_000;
/// Default memory budget, 512 MiB: the reference needs about 311 MiB for round table 8/8.
pub const DEFAULT_MAX_BYTES: usize = 512 << 20;
/// Default work budget: about three seconds of solving natively; round table 8/8 needs about
/// 82 million, the scan game of gear checking at 36 ms, which is not implementable, 327 million.
pub const DEFAULT_MAX_WORK: u64 = 500_000_000;

crate::search::setters!(Config {
    max_states: usize,
    max_bytes: usize,
    max_work: u64,
    progress_interval: usize,
    exhaustive: bool,
    zeno_memory: bool,
    inclusion: bool,
    dominance: bool,
});

impl Default for Config {
    fn default() -> Self {
        Config {
            max_states: DEFAULT_MAX_STATES,
            max_bytes: DEFAULT_MAX_BYTES,
            max_work: DEFAULT_MAX_WORK,
            progress_interval: 4096,
            exhaustive: false,
            zeno_memory: true,
            inclusion: true,
            dominance: true,
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Verdict {
    /// The controller has a strategy that keeps every assertion and meets every plan.
    Realizable,
    /// The plant has a strategy that defeats every controller.
    Unrealizable,
}

crate::search::decision!(Verdict { Realizable => "realizable", Unrealizable => "unrealizable" });

/// The outcome of [`solve`]: the decision or why there is none, and what the search built
/// either way (the page shows the states and statistics of a stopped search too).
pub struct Solution {
    pub outcome: Result<Verdict, Stop>,
    pub stats: Stats,
    pub space: StateSpace,
    /// With a budget stop of the split: the declaration to blame (the node or step that splits
    /// into too many sub-locations).
    pub blame: Option<crate::diag::Span>,
}

impl Outcome for Solution {
    type Verdict = Verdict;

    fn outcome(&self) -> Result<Verdict, &Stop> {
        self.outcome.as_ref().copied()
    }
}

impl Solution {
    /// Whether the controller wins.
    pub fn is_realizable(&self) -> bool {
        self.outcome == Ok(Verdict::Realizable)
    }
}

/// Solves the game within the budgets of `options` (the split's memory and work count). Calls
/// `progress` every `options.progress_interval` expansions, and during long work on one state,
/// with the statistics so far; returning `false` cancels the run.
pub fn solve(game: &Game, split: &SplitGame, options: &Config, progress: &mut OnProgress<'_, Stats>) -> Solution {
    solve_guided(game, split, options, None, progress)
}

/// [`solve`] for a scan game, whose strategy-directed search tries first at each read what the
/// zero-time strategy `guide` does there (see [`ScanGuide`]); the verdict does not depend on it.
pub fn solve_guided(
    game: &Game,
    split: &SplitGame,
    options: &Config,
    guide: Option<&ScanGuide>,
    progress: &mut OnProgress<'_, Stats>,
) -> Solution {
    if !uses_inclusion(game, options) {
        return solve_pass(game, split, options, guide, progress, split.work);
    }
    // Inclusion decides most scan games with a fraction of the states, but where covers keep
    // being lost (a scan time just past the largest that works) it can cost more than storing
    // every zone: it gets a quarter of every budget, then the search without it the rest.
    let share = Config {
        max_states: options.max_states / INCLUSION_SHARE,
        max_bytes: options.max_bytes / INCLUSION_SHARE,
        max_work: options.max_work / INCLUSION_SHARE as u64,
        ..options.clone()
    };
    let first = solve_pass(game, split, &share, guide, progress, split.work);
    if !matches!(first.outcome, Err(Stop::Budget { .. })) {
        return first;
    }
    let exact = Config { inclusion: false, ..options.clone() };
    solve_pass(game, split, &exact, guide, progress, first.stats.work)
}

/// Whether a search of `game` with `options` uses inclusion: scan games, strategy-directed.
/// The plant components whose location some assertion or state guard reads, in order.
fn predicate_components(game: &Game) -> Vec<usize> {
    let mut read = vec![false; game.components.len()];
    for pred in game.assertions.iter().map(|a| &a.holds).chain(game.guards.iter().map(|g| &g.cond)) {
        pred.mark_components(&mut read);
    }
    read.iter().enumerate().filter(|&(_, &r)| r).map(|(c, _)| c).collect()
}

fn uses_inclusion(game: &Game, options: &Config) -> bool {
    options.inclusion && !options.exhaustive && game.scan.is_some()
}

/// Whether a search of `game` with `options` uses dominance: scan games, strategy-directed.
fn uses_dominance(game: &Game, options: &Config) -> bool {
    options.dominance && !options.exhaustive && game.scan.is_some()
}

/// The part of each budget the search with inclusion gets before the search without it runs
/// (see [`solve_guided`]).
const INCLUSION_SHARE: usize = 4;

/// One search within the budgets of `options`, `spent` work (the split's and any earlier
/// search's) already counted against them.
fn solve_pass(
    game: &Game,
    split: &SplitGame,
    options: &Config,
    guide: Option<&ScanGuide>,
    progress: &mut OnProgress<'_, Stats>,
    spent: u64,
) -> Solution {
    if options.exhaustive {
        search_pass(game, split, options, progress, spent, Exhaustive::new)
    } else {
        search_pass(game, split, options, progress, spent, || Directed::new(game, split, guide))
    }
}

/// [`solve_pass`] with the search `new_search` makes (a fresh one for the second search).
fn search_pass<S: Search>(
    game: &Game,
    split: &SplitGame,
    options: &Config,
    progress: &mut OnProgress<'_, Stats>,
    spent: u64,
    new_search: impl Fn() -> S,
) -> Solution {
    let exact = Config { zeno_memory: false, ..options.clone() };
    let mut solver = Solver::new(game, split, options, new_search(), progress, spent);
    let mut verdict = solver.run();
    if verdict == Ok(Verdict::Unrealizable) && solver.memory_cuts > 0 {
        // The memory's cuts may have cost the controller its strategy: decide exactly.
        let spent = solver.meter.used();
        drop(solver);
        solver = Solver::new(game, split, &exact, new_search(), progress, spent);
        verdict = solver.run();
    }
    let mut stats = solver.stats();
    let space = solver.space;
    if verdict.is_ok() {
        stats.winning = space.winning_states().len();
    }
    Solution { outcome: verdict.map_err(|halt| halt.stop(options)), stats, space, blame: None }
}

/// What the two searches do differently, asked by the core (expansion, removal, the progress
/// condition) where they part: which states are expanded and in what order, whether a move's
/// target is generated when the move is found or when the search tries it, how a freshly
/// expanded state is decided, and what the loss of one of its alternatives changes.
/// [`Exhaustive`] is the thesis's reference, [`Directed`] the default; the solver is generic
/// over the search, so each question is a direct call, settled when the solver is compiled.
trait Search: Sized {
    /// What `progress_ranks` counts on while the search runs (`enforce_progress`).
    const COUNTING: Counting;

    /// The next queued state to expand; `None` when nothing is left.
    fn next_state(&mut self) -> Option<StateId>;

    /// The new state `s` (not removed, not a guard state) was just stored.
    fn reached(&mut self, s: StateId);

    /// The strategy relies on the state `s` (the initial state, or a move it takes).
    fn need(solver: &mut Solver<'_, '_, Self>, s: StateId);

    /// Where the targets of moves not tried yet are kept until the search tries them
    /// (`Edge::deferred` indexes it); `None` if every target is generated when the move is.
    fn deferred_targets(&mut self) -> Option<&mut Vec<Option<Deferred>>>;

    /// The alternatives of a freshly expanded state in `env`, `plan` and `zone` in the order
    /// they are stored; `None` if a budget or the caller stopped the work.
    fn order(
        solver: &mut Solver<'_, '_, Self>,
        edges: Vec<Edge>,
        env: &[SubLocId],
        plan: &[SubLocId],
        zone: &Dbm,
    ) -> Option<Vec<Edge>>;

    /// Decides the freshly expanded state `s`, its edges committed (removes it if it is lost).
    fn decide(solver: &mut Solver<'_, '_, Self>, s: StateId);

    /// After each expansion (and its propagation).
    fn after_expansion(solver: &mut Solver<'_, '_, Self>);

    /// An alternative of the live expanded state `x` leads to a removed state or was cut: the
    /// option edge `alt`, or waiting (`EdgeId::WAIT`, `wait_viable` already cleared).
    fn alternative_lost(solver: &mut Solver<'_, '_, Self>, x: StateId, alt: EdgeId);

    /// After a round of the progress condition that removed nothing, `ranks` its ranks:
    /// whether the search changed its strategy or has more to explore.
    fn steer(solver: &mut Solver<'_, '_, Self>, ranks: &[u32]) -> bool;

    /// The ranks the final zeno cut goes by, from those of the last round.
    fn final_ranks(solver: &mut Solver<'_, '_, Self>, ranks: Vec<u32>) -> Vec<u32>;

    /// The final cut took `options_cut` options of the winning state `s` (and perhaps waiting).
    fn after_cut(solver: &mut Solver<'_, '_, Self>, s: StateId, options_cut: u32);

    /// The search reached its verdict.
    fn finish(solver: &mut Solver<'_, '_, Self>);

    /// Heap bytes of the search's own tables (see `Solver::bytes`).
    fn heap_bytes(&self) -> usize;
}

/// Locations, kind and the hash of the zone without the plans' clocks (see `Solver::covers`).
type CoverKey = (u32, u32, StateKind, u64);

/// One search of the game: the core's tables, and the search `S` (see [`Search`]).
struct Solver<'g, 'p, S> {
    game: &'g Game,
    split: &'g SplitGame,
    options: &'g Config,
    progress: &'p mut OnProgress<'p, Stats>,
    space: StateSpace,
    state_index: hashbrown::HashMap<(u32, u32, u32, StateKind), StateId>,
    /// Inclusion (see `Config::inclusion`), when on: the states per discrete part, kind
    /// and [`Solver::kept_key`] of the zone. A cover's zone agrees with the zone it takes on
    /// every clock but the plans', so only states of the same key can cover one another, and a
    /// lookup compares a handful of zones, not every zone of the locations.
    covers: Option<hashbrown::HashMap<CoverKey, Vec<StateId>>>,
    /// Per interned zone, its key once computed (zones recur in many states).
    kept_keys: Vec<Option<u64>>,
    /// Dominance (see `Config::dominance`), when on: the lost states per discrete part
    /// and kind.
    losses: Option<hashbrown::HashMap<(u32, u32, StateKind), Vec<StateId>>>,
    /// States lost on arrival by dominance.
    dominated: usize,
    /// Dominance: per state, whether its loss carries over to larger zones (`monotone_loss`).
    monotone: Vec<bool>,
    /// The plans' clocks (a bit per zone index): checked only against deadlines, so a state
    /// with them higher covers one with them lower (inclusion).
    deadline_clocks: u64,
    /// The search: its queue of states to expand, and what only it keeps.
    search: S,
    /// Cut moves by the zeno memory (see `Config::zeno_memory`), and how many were cut.
    memory: bool,
    memory_cuts: usize,
    expansions: usize,
    zeno: ZenoSets,
    /// Per env id: 1 + index of the first violated assertion, or 0.
    env_violation: Vec<u32>,
    /// Per plan vector id: 1 + index of the first failed plan, or 0.
    plan_failure: Vec<u32>,
    /// Per env id: the original locations of the plant units (for predicates), flat.
    env_locations: Vec<LocId>,
    /// Per env id: which state guards (4.2.1) hold there, a bit per guard, `guard_words` words
    /// per env id. A request enters a guard where it holds after and not before: evaluated once
    /// per env id rather than twice per controllable move.
    env_guards: Vec<u64>,
    guard_words: usize,
    /// In a scan game: the vectors of the locations of the `predicate_components` met, and per
    /// vector the first env id with it (whose assertion and guard entries the others copy).
    predicate_locations: Option<(SliceArena<LocId>, Vec<u32>)>,
    /// The plant components whose location some assertion or guard reads.
    predicate_components: Vec<usize>,
    /// Clocks used per env id and per plan vector id, as bit sets.
    env_clocks: Vec<u64>,
    plan_clocks: Vec<u64>,
    lost_queue: Vec<StateId>,
    /// Moves given a lost target in place of a lost cover (`retarget_covered`), to propagate.
    lost_edges: Vec<EdgeId>,
    dim: usize,
    max_constants: Vec<i32>,
    removed: usize,
    expanded: usize,
    moves: Vec<Move>,
    pending_edges: Vec<Edge>,
    /// Work done so far (the split's and earlier searches' included), and when the next progress
    /// call is due.
    meter: Meter,
    /// The work of one candidate successor (a zone and a state vector), and of one candidate
    /// state vector alone.
    successor_cost: u64,
    vector_cost: u64,
    halt: Option<Halt>,
    /// In a scan game: the scan automaton's quiet and armed sub-locations (see `scan::ScanRoles`).
    scan_arm: Option<ScanArm>,
}

impl<'g, 'p, S: Search> Solver<'g, 'p, S> {
    fn new(
        game: &'g Game,
        split: &'g SplitGame,
        options: &'g Config,
        search: S,
        progress: &'p mut OnProgress<'p, Stats>,
        spent: u64,
    ) -> Solver<'g, 'p, S> {
        let dim = game.dim();
        let plant_count = split.plant_count;
        let scan_arm = ScanArm::new(game, split);
        let predicate_components = predicate_components(game);
        Solver {
            game,
            split,
            options,
            progress,
            space: StateSpace::empty(dim, plant_count, split.units.len() - plant_count),
            state_index: hashbrown::HashMap::new(),
            covers: uses_inclusion(game, options).then(hashbrown::HashMap::new),
            kept_keys: Vec::new(),
            losses: uses_dominance(game, options).then(hashbrown::HashMap::new),
            dominated: 0,
            monotone: Vec::new(),
            deadline_clocks: game.plans.iter().flat_map(|p| &p.clocks).fold(0, |bits, &(c, _)| bits | 1 << c.index()),
            search,
            memory: options.zeno_memory,
            memory_cuts: 0,
            expansions: 0,
            zeno: ZenoSets { nodes: Vec::new() },
            env_violation: Vec::new(),
            plan_failure: Vec::new(),
            env_locations: Vec::new(),
            env_guards: Vec::new(),
            guard_words: game.guards.len().div_ceil(64),
            predicate_locations: scan_arm.is_some().then(|| (SliceArena::new(predicate_components.len()), Vec::new())),
            predicate_components,
            env_clocks: Vec::new(),
            plan_clocks: Vec::new(),
            lost_queue: Vec::new(),
            lost_edges: Vec::new(),
            dim,
            max_constants: vec![-1; dim],
            removed: 0,
            expanded: 0,
            moves: Vec::new(),
            pending_edges: Vec::new(),
            meter: Meter::new(spent, options.max_work, PROGRESS_WORK),
            successor_cost: STEP_COST + (dim * dim + split.units.len()) as u64,
            vector_cost: STEP_COST + split.units.len() as u64,
            halt: None,
            scan_arm,
        }
    }

    fn run(&mut self) -> Result<Verdict, Halt> {
        let plant_count = self.split.plant_count;
        let env: Vec<SubLocId> = self.split.units[..plant_count].iter().map(|u| u.initial).collect();
        let plan: Vec<SubLocId> = self.split.units[plant_count..].iter().map(|u| u.initial).collect();
        let mut zone = Dbm::zero(self.dim);
        let (env_id, plan_id) = self.intern_discrete(&env, &plan);
        self.normalise(env_id, plan_id, &mut zone);
        let kind = if self.is_closed(&env, &plan, &zone) { StateKind::Interval } else { StateKind::Entry };
        self.space.initial = self.find_or_add(env_id, plan_id, &zone, kind, Vis::Fresh).0;
        S::need(self, self.space.initial);
        // Explore, then cut the zeno cycles of what survived; in the strategy-directed search a
        // cut can make a state choose again, which needs more exploration.
        let verdict = loop {
            if let Some(lost) = self.explore()? {
                break lost;
            }
            let settled = !self.enforce_progress();
            // Steering charges its rankings as work (`steer_by_ranks`): a budget may end it.
            if let Some(halt) = self.halt {
                return Err(halt);
            }
            if settled {
                break if self.space.is_winning(self.space.initial) {
                    Verdict::Realizable
                } else {
                    Verdict::Unrealizable
                };
            }
        };
        S::finish(self);
        Ok(verdict)
    }

    /// Expands queued states until none is left (`Ok(None)`) or the initial state is lost
    /// (`Ok(Some(Unrealizable))`), unless a budget or the caller stops the search first.
    fn explore(&mut self) -> Result<Option<Verdict>, Halt> {
        loop {
            if !self.space.is_winning(self.space.initial) {
                return Ok(Some(Verdict::Unrealizable));
            }
            let Some(s) = self.search.next_state() else { return Ok(None) };
            let st = &self.space.states[s.index()];
            if st.removal.is_some() || st.expanded {
                continue;
            }
            if let Some(budget) = self.exceeded() {
                self.halt = Some(Halt::Budget(budget));
                return Err(Halt::Budget(budget));
            }
            self.expansions += 1;
            if self.options.progress_interval > 0
                && self.expansions % self.options.progress_interval == 0
                && !self.report()
            {
                self.halt = Some(Halt::Cancelled);
                return Err(Halt::Cancelled);
            }
            self.expand(s);
            S::after_expansion(self);
            if let Some(halt) = self.halt {
                return Err(halt);
            }
        }
    }
}
