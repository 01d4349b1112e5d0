//! Budgets and metering: the work and memory a search accounts, when it calls the progress
//! callback, why it stopped ([`Budget`], [`BudgetStop`], `Halt`), and its statistics ([`Stats`]).

use super::space::{Edge, State, StateId, StateKind};
use super::strategy::Deferred;
use super::{SolveOptions, Solver};
use crate::diag::Span;
use crate::timed::model::*;
use crate::timed::precompute::SplitTooLarge;
use serde::Serialize;

/// Work between two progress calls during long work on one state (a few milliseconds).
pub(crate) const PROGRESS_WORK: u64 = 1 << 20;

/// The fixed part of the work of one candidate successor (hashing, allocation, bookkeeping), in
/// units of one zone bound: measured, this makes a unit cost 10–20 ns whatever the game's shape.
pub(crate) const STEP_COST: u64 = 64;

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
    /// Of those, states lost on arrival by dominance (`SolveOptions::dominance`), not expanded.
    pub dominated: usize,
    pub edges: usize,
    /// Distinct zones stored.
    pub zones: usize,
    /// Approximate heap bytes of the split game and the state space.
    pub bytes: usize,
    /// Work done, the split included: per candidate successor, one unit per zone bound and per
    /// state-vector entry computed plus a fixed 64 for the rest, so roughly proportional to time.
    pub work: u64,
}

/// Why a search ended before deciding.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Halt {
    Budget(Budget),
    Cancelled,
}

impl Solver<'_, '_> {
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

    pub(super) fn stats(&self) -> Stats {
        let s = &self.space;
        Stats {
            visited: s.states.len(),
            expanded: self.expanded,
            winning: 0,
            removed: self.removed,
            dominated: self.dominated,
            edges: s.edges.len(),
            zones: s.zones.len(),
            bytes: self.bytes(),
            work: self.work,
        }
    }

    /// The budget the search has exceeded, if any.
    pub(super) fn exceeded(&self) -> Option<Budget> {
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
    pub(super) fn report(&mut self) -> bool {
        self.next_progress = self.work + PROGRESS_WORK;
        let stats = self.stats();
        (self.progress)(&stats)
    }

    /// Accounts `units` of work. Returns `false`, with the reason in `halt`, when the search must
    /// stop: a budget is exceeded or, at a progress call during long work, the caller cancels.
    pub(super) fn charge(&mut self, units: u64) -> bool {
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
}
