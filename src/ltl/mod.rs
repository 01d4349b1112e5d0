//! The LTL synthesis engine (Cheng et al. 2014, G4LTL-ST; appendix C).
//!
//! Pipeline: [`compile`] checks a text — G4LTL's `.ltl` lines (`g4ltl`) or SYNTCOMP's TLSF
//! (`tlsf`), by [`Format`] — into a [`Spec`] with every diagnostic located → [`synthesize`]
//! translates the specification and its negation into Büchi automata of our own
//! (`translate`), plays the bounded co-Büchi safety games of both players for k = 0, 1, …
//! (`game`) and returns a [`Synthesis`] (or the [`Stop`] that ended it): the verdict with the winner's finite-state strategy
//! ([`Machine`]), minimised. The views of an outcome ([`report_json`], [`render_machine`],
//! [`render_tree`], [`machine_dot`], [`summary`]), assumption suggestions for an unrealizable
//! specification ([`suggest`]) and G4LTL's own syntax ([`to_g4ltl`]) are the rest of the front
//! door; `testing` holds the internals the tests check. The engine does no I/O and never
//! reads the clock.
//!
//! ```
//! use plcsynth::ltl::{compile, synthesize, Config, Format, Verdict};
//! let source = "ALWAYS (req -> (grant || NEXT grant))\nALWAYS (grant -> NEXT !grant)\n\
//!               INPUT req\nOUTPUT grant\n";
//! let (spec, _warnings) = compile(source, Format::G4ltl, &[]).expect("a valid specification");
//! let outcome = synthesize(&spec, &Config::default(), &mut |_| true).expect("within budget");
//! assert_eq!(outcome.verdict, Verdict::Realizable);
//! assert!(outcome.controller.is_some());
//! ```

mod antichain;
mod bdd;
mod circuit;
mod compose;
mod export;
mod g4ltl;
mod game;
mod gr1;
mod machine;
mod refine;
mod spec;
mod strategy;
mod suggest;
mod symbolic;
mod theory;
mod tlsf;
mod to_g4ltl;
mod translate;

// The checked specification and its parts.
pub use spec::{
    Clause, Ltl, NumExpr, NumberKind, NumericId, NumericInput, Predicate, Relation, Semantics, Signal, SignalId,
    SignalKind, Spec, Timer,
};
// The strategies, for the views and the PLC lowering.
pub use circuit::{Circuit, CircuitState, Goal, Latch, Logic};
pub use machine::{Cube, Machine, Row, StateId};
// The parts of an outcome: the assumptions refinement learned, the groups of a compositional run.
pub use compose::Group;
pub use refine::{refined, Learned, Refinement};
// The views of an outcome.
pub use export::{machine_dot, render_machine, render_tree, report_json, summary};
// Assumption suggestions for an unrealizable specification.
pub use suggest::{suggest, Play, SuggestConfig, Suggestion, Suggestions, Template};
// A specification in G4LTL's own syntax (`ltl --to-g4ltl`).
pub use to_g4ltl::to_g4ltl;

use g4ltl::compile_g4ltl;
use tlsf::compile_tlsf;

/// Internals for the integration tests and the fuzz harness; not part of the API.
#[doc(hidden)]
pub mod testing {
    pub use super::spec::MAX_FORMULA_DEPTH;
    pub use super::suggest::longest_play;
    // The Büchi automata of `synthesize`'s first step, with the types of their fields.
    pub use super::translate::{translate, Automaton, AutomatonState, Edge};

    /// The theory checker of `refine`: polynomial literals over boxes.
    pub mod theory {
        pub use super::super::theory::*;
    }
}

use serde::Serialize;

/// The two input languages.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// G4LTL's line format (`.ltl`, `.g4ltl`).
    G4ltl,
    /// SYNTCOMP's Temporal Logic Synthesis Format (`.tlsf`).
    Tlsf,
}

impl Format {
    /// The format a file name's extension names: `.tlsf` is TLSF, anything else G4LTL's.
    pub fn of_path(path: &str) -> Format {
        if path.to_ascii_lowercase().ends_with(".tlsf") {
            Format::Tlsf
        } else {
            Format::G4ltl
        }
    }
}

/// Checks `source` in `format`; TLSF `PARAMETERS` may be overridden by name (`--param n=3`).
/// On success the specification and the warnings, otherwise every diagnostic.
pub fn compile(
    source: &str,
    format: Format,
    overrides: &[(String, i64)],
) -> Result<(Spec, Vec<crate::diag::Diagnostic>), Vec<crate::diag::Diagnostic>> {
    match format {
        Format::G4ltl => compile_g4ltl(source),
        Format::Tlsf => compile_tlsf(source, overrides),
    }
}

/// Budgets of one synthesis run.
#[derive(Clone, Debug)]
pub struct Config {
    /// The largest bound k of the co-Büchi counters tried; k grows from 0.
    pub max_k: u32,
    /// Game positions (counter vectors) built in all games of the run together; the `bdd`
    /// solver holds each game's diagram to `max_states × 16` nodes.
    pub max_states: usize,
    /// States of each Büchi automaton built by the translation.
    pub max_automaton_states: usize,
    /// Letters (valuations of all signals) a game may enumerate per position: the explicit
    /// game costs 2^(inputs + outputs) per position.
    pub max_signals: usize,
    /// How the bounded games are solved.
    pub solver: Solver,
    /// Units of work of the whole run (tableau terms combined and compared in the
    /// translation, automaton edges followed in the games): about proportional to time, so
    /// that no input keeps a caller waiting, however small its state counts.
    pub max_work: u64,
    /// Solve groups of guarantees with disjoint outputs alone first (`compose`); the verdict
    /// is the same either way.
    pub compositional: bool,
    /// Refine the abstraction of timers and predicates from counter-strategies (`refine`);
    /// without it the verdict is that of the Boolean abstraction.
    pub refine: bool,
    /// A GR(1) run builds its controller as a [`Circuit`] even when the table fits (which it
    /// builds too): the PLC code is then the circuit's, and the specification is solved as a
    /// whole (the groups of a compositional run would each have their own).
    pub circuit: bool,
}

/// The solvers of the bounded games; they decide the same games (the tests compare them). The
/// explicit and antichain solvers hand the winner's maximal winning positions to one strategy
/// extraction; the symbolic one reads its strategy off its own diagram.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Solver {
    /// Every position reachable from the initial one explored, the game solved backwards by
    /// counting: the faster on the listed specifications.
    #[default]
    Explicit,
    /// The greatest fixpoint on antichains of maximal winning positions (Filiot, Jin and Raskin):
    /// no position below them is enumerated, but meets of antichains can grow.
    Antichain,
    /// Letters as decision diagrams over the signals (`symbolic`): every position reachable
    /// from the initial one explored as the explicit solver does, but a position's successors
    /// split only on the signals its runs' guards name, so no step enumerates 2^n letters.
    Symbolic,
    /// Positions and letters both as binary decision diagrams (`bdd`, Ehlers' Unbeast): the
    /// game solved as a greatest fixpoint on sets of positions, so no position is enumerated
    /// but those a strategy visits. For games whose counters make too many positions.
    Bdd,
    /// GR(1) games over deterministic monitors of the conjuncts (`gr1`): no counter bound,
    /// positions and letters as decision diagrams. Only for specifications whose conjuncts
    /// are invariants, responses, `U`/`W`/`R` obligations and `G F` conditions; decides those
    /// outright, at SYNTCOMP's arbiter sizes.
    Gr1,
}

impl Solver {
    /// Every solver, in the order the CLI and the page list them.
    pub const ALL: [Solver; 5] = [Solver::Explicit, Solver::Antichain, Solver::Symbolic, Solver::Bdd, Solver::Gr1];

    /// Its name on the command line (`--solver`) and in the page.
    pub fn name(self) -> &'static str {
        match self {
            Solver::Explicit => "explicit",
            Solver::Antichain => "antichain",
            Solver::Symbolic => "symbolic",
            Solver::Bdd => "bdd",
            Solver::Gr1 => "gr1",
        }
    }

    /// The solver named `name`.
    pub fn named(name: &str) -> Option<Solver> {
        Solver::ALL.into_iter().find(|s| s.name() == name)
    }
}

/// The default work budget: a few seconds natively.
pub const DEFAULT_MAX_WORK: u64 = 1_500_000_000;

/// The work a run has spent against [`Config::max_work`], with the caller's progress callback
/// asked every 2^16 units (its `false` cancels): the shared [`crate::search::Meter`] and the
/// callback.
pub(crate) struct Work<'a> {
    meter: Meter,
    /// The run's budget (the meter's limit is lower inside [`Work::capped`]).
    budget: u64,
    progress: &'a mut OnProgress<'a, Progress>,
    /// What the callback is told besides the work.
    pub(crate) at: Progress,
}

impl<'a> Work<'a> {
    pub(crate) fn new(limit: u64, progress: &'a mut OnProgress<'a, Progress>) -> Work<'a> {
        Work { meter: Meter::new(0, limit, 1 << 16), budget: limit, progress, at: Progress::default() }
    }

    /// Spends `units`; stops the run past the budget or when the callback cancels.
    pub(crate) fn spend(&mut self, units: u64) -> Result<(), Stop> {
        match self.meter.charge(units) {
            Charge::Within => Ok(()),
            Charge::Exceeded => Err(Stop::budget(
                Resource::Work,
                if self.meter.limit() < self.budget {
                    format!(
                        "it would pass {} units of work, the end of its share (--max-work {} for the whole run)",
                        self.meter.limit(),
                        self.budget
                    )
                } else {
                    format!("the run needs more than {} units of work (--max-work)", self.budget)
                },
            )),
            Charge::ReportDue => {
                self.at.work = self.meter.used();
                if (self.progress)(&self.at) {
                    Ok(())
                } else {
                    Err(Stop::Cancelled)
                }
            }
        }
    }

    pub(crate) fn used(&self) -> u64 {
        self.meter.used()
    }

    /// Units left before the budget ends the run.
    pub(crate) fn remaining(&self) -> u64 {
        self.meter.remaining()
    }

    /// Runs `f` with at most `units` more to spend (within the run's budget), then restores
    /// the run's budget: for optional work whose running out is not the run's end.
    pub(crate) fn capped<T>(&mut self, units: u64, f: impl FnOnce(&mut Work) -> T) -> T {
        let limit = self.meter.limit();
        self.meter.set_limit(limit.min(self.meter.used().saturating_add(units)));
        let result = f(self);
        self.meter.set_limit(limit);
        result
    }
}

/// The default bound of the co-Büchi counters: enough for every example and every listed
/// benchmark (most need 1–3).
pub const DEFAULT_MAX_K: u32 = 8;
/// The default budget of game positions: a run stops within seconds and a few hundred MB.
pub const DEFAULT_MAX_STATES: usize = 200_000;

crate::search::setters!(Config {
    max_k: u32,
    max_states: usize,
    max_automaton_states: usize,
    max_signals: usize,
    solver: Solver,
    max_work: u64,
    compositional: bool,
    refine: bool,
    circuit: bool,
});

impl Default for Config {
    fn default() -> Config {
        Config {
            max_k: DEFAULT_MAX_K,
            max_states: DEFAULT_MAX_STATES,
            max_automaton_states: 20_000,
            max_signals: 20,
            max_work: DEFAULT_MAX_WORK,
            solver: Solver::Explicit,
            compositional: true,
            refine: true,
            circuit: false,
        }
    }
}

/// What a run decided. Bounded synthesis answers `Unknown` when neither player wins a game up
/// to the bound: a result of the games played, not a stop (a budget or a cancellation ends the
/// run with a [`Stop`] instead).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Verdict {
    /// A controller exists (and is returned).
    Realizable,
    /// The environment has a strategy that defeats every controller (returned).
    Unrealizable,
    /// Neither player won a game up to [`Config::max_k`].
    Unknown,
}

crate::search::decision!(Verdict { Realizable => "realizable", Unrealizable => "unrealizable", Unknown => "unknown" });

/// A run of [`synthesize`] ends with a [`Synthesis`] or a [`Stop`]: a stopped run has no
/// strategy to show.
impl Outcome for Result<Synthesis, Stop> {
    type Verdict = Verdict;

    fn outcome(&self) -> Result<Verdict, &Stop> {
        self.as_ref().map(|synthesis| synthesis.verdict)
    }
}

/// Progress of a run, passed to the callback; returning `false` cancels.
#[derive(Clone, Copy, Debug, Default, Serialize)]
pub struct Progress {
    /// The bound being tried.
    pub k: u32,
    /// Game positions built so far in this run (the explicit and symbolic solvers).
    pub positions: usize,
    /// Nodes the current game's decision diagram holds (the bdd solver, which builds no
    /// positions while it solves).
    pub nodes: usize,
    /// Work spent so far ([`Config::max_work`]).
    pub work: u64,
}

/// Sizes and counts of one run, for reports and benchmarks.
#[derive(Clone, Debug, Default, Serialize)]
pub struct Stats {
    /// States of the Büchi automaton of the negated specification (the controller's game).
    pub automaton_states: usize,
    /// States of the Büchi automaton of the specification (the environment's game).
    pub dual_automaton_states: usize,
    /// Game positions built in all games (explicit solver), antichain elements of the
    /// winning sets (antichain solver), or positions its strategies visited (bdd solver).
    pub positions: usize,
    /// States of the strategy before minimisation.
    pub strategy_states_raw: usize,
    /// The most nodes one game's decision diagram held (`bdd` solver; 0 for the others).
    pub bdd_nodes: usize,
    /// Work spent ([`Config::max_work`]).
    pub work: u64,
    /// Decided as a GR(1) game (`--solver gr1`): no bound k, and the automaton counts are 0.
    pub gr1: bool,
    /// State bits of the GR(1) game's monitors.
    pub monitor_bits: usize,
}

/// The result of [`synthesize`].
#[derive(Clone, Debug)]
pub struct Synthesis {
    pub verdict: Verdict,
    /// The bound at which the verdict was reached (the last one tried when unknown).
    pub k: u32,
    /// The controller: reads the inputs, writes the outputs. `Some` exactly when realizable,
    /// except after a GR(1) game whose strategy outgrew its table (then [`Synthesis::limit`]
    /// says so).
    pub controller: Option<Machine>,
    /// The environment's counter-strategy: reads the outputs, writes the inputs. `Some` exactly
    /// when unrealizable, with the same exception as the controller's.
    pub counter_strategy: Option<Machine>,
    /// The controller as a circuit (a GR(1) run only): built when its table would pass the
    /// budget, or when [`Config::circuit`] asks for it.
    pub circuit: Option<Circuit>,
    pub stats: Stats,
    /// For an unknown verdict: which bound or budget ended the run, and the flag that raises it;
    /// for a decided one without its machine, why it is missing.
    pub limit: Option<String>,
    /// The assumptions the refinement loop learned: the controller or counter-strategy is one
    /// of the specification with them ([`refined`]).
    pub refinement: Refinement,
    /// The groups of a compositional run, each with its controller (empty when the
    /// specification was solved as a whole).
    pub groups: Vec<Group>,
    /// How many groups the guarantees split into (1: nothing to split). More than 1 with no
    /// [`Synthesis::groups`]: a group was not realizable alone, and the whole decided.
    pub split: usize,
}

use crate::search::{Charge, Meter, OnProgress};
/// Why a run stopped without a verdict, and how a run ended: the shared [`crate::search`] types.
pub use crate::search::{Outcome, Resource, Stop};

/// Decides `spec`: for k = 0, 1, …, [`Config::max_k`] plays the controller's bounded game on
/// the automaton of the negated specification, then the environment's on the automaton of the
/// specification, and stops at the first that is won. A counter-strategy that uses timer
/// behaviour no real timer shows is excluded by a learned assumption and the games are played
/// again (`refine`).
///
/// With [`Config::compositional`], groups of guarantees that share no output are solved alone
/// first; when every group is realizable their controllers run side by side
/// ([`Synthesis::groups`]), otherwise the whole specification is solved.
pub fn synthesize(spec: &Spec, cfg: &Config, progress: &mut OnProgress<'_, Progress>) -> Result<Synthesis, Stop> {
    let groups = compose::split(spec);
    let split = groups.len();
    let mut spent = 0;
    // A circuit is one controller: the groups' circuits are not run side by side.
    let circuit = cfg.solver == Solver::Gr1 && cfg.circuit;
    if cfg.compositional && split > 1 && !circuit {
        let mut tried = Config { max_work: cfg.max_work / 2, ..cfg.clone() };
        tried.max_states = cfg.max_states / 2;
        match compose::synthesize(spec, &groups, &tried, progress) {
            Ok(Ok(outcome)) => return Ok(outcome),
            Ok(Err(work)) => spent = work,
            Err(Stop::Budget { .. }) => spent = tried.max_work,
            Err(Stop::Cancelled) => return Err(Stop::Cancelled),
        }
    }
    // A game may overshoot its share by its last step, and the theory by its last query.
    let whole = Config { max_work: cfg.max_work.saturating_sub(spent), ..cfg.clone() };
    let mut outcome = refine::synthesize(spec, &whole, progress)?;
    outcome.split = split;
    Ok(outcome)
}
