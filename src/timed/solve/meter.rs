//! Budgets and metering: the work and memory a search accounts, when it calls the progress
//! callback, why it stopped (`Halt`, then the shared [`Stop`]), and its statistics ([`Stats`]).

use super::space::{Edge, State, StateId, StateKind};
use super::{Config, Search, Solver};
use crate::search::{Charge, Resource, Stop};
use crate::timed::model::*;
use crate::timed::precompute::SplitTooLarge;
use serde::Serialize;

/// Work between two progress calls during long work on one state (a few milliseconds).
pub(crate) const PROGRESS_WORK: u64 = 1 << 20;

/// The fixed part of the work of one candidate successor (hashing, allocation, bookkeeping), in
/// units of one zone bound: measured, this makes a unit cost 10–20 ns whatever the game's shape.
pub(crate) const STEP_COST: u64 = 64;

/// Why a search ended before deciding, while it runs (cheap to test in the loop); it becomes
/// the shared [`Stop`] with its sentence when the search returns.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Halt {
    /// A budget of [`Config`]: states, memory or work.
    Budget(Resource),
    Cancelled,
}

impl Halt {
    /// The stop of a search that ended so under `options`, with the budget's limit in words that
    /// do not depend on the caller (the CLI and the page add how to raise it).
    pub(crate) fn stop(self, options: &Config) -> Stop {
        let resource = match self {
            Halt::Budget(resource) => resource,
            Halt::Cancelled => return Stop::Cancelled,
        };
        let message = match resource {
            Resource::States => format!("the search stored more than {} states", options.max_states),
            Resource::Memory => format!("the search needs more than {} of memory", mib(options.max_bytes)),
            Resource::Work | Resource::Size => format!(
                "the search did more than {} units of work (zone bounds and state entries computed)",
                options.max_work
            ),
        };
        Stop::budget(resource, message)
    }
}

/// The stop of a split that needed more memory or work than `options` allow; the location to
/// blame is `too_large.span`.
pub(crate) fn split_stop(too_large: &SplitTooLarge, options: &Config) -> Stop {
    let what = format!(
        "{} splits into {} sub-locations ({} clocks in use there)",
        too_large.place, too_large.sublocations, too_large.clocks
    );
    let message = match too_large.budget {
        Resource::Work => format!("{what}: more than {} units of work", options.max_work),
        _ => format!("{what}: more than {} of memory", mib(options.max_bytes)),
    };
    Stop::budget(too_large.budget, message)
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
    /// Of those, states lost on arrival by dominance (`Config::dominance`), not expanded.
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

impl<S: Search> Solver<'_, '_, S> {
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
            + self.search.heap_bytes()
            + self.zeno.nodes.capacity() * std::mem::size_of::<(u32, u32, u32)>()
            + self.env_locations.capacity() * std::mem::size_of::<LocId>()
            + (self.env_violation.capacity() + self.plan_failure.capacity()) * std::mem::size_of::<u32>()
            + (self.env_clocks.capacity() + self.plan_clocks.capacity() + self.env_guards.capacity())
                * std::mem::size_of::<u64>()
            + self.predicate_locations.as_ref().map_or(0, |(vectors, first_env)| {
                vectors.heap_bytes() + first_env.capacity() * std::mem::size_of::<u32>()
            })
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
            work: self.meter.used(),
        }
    }

    /// The budget the search has exceeded, if any.
    pub(super) fn exceeded(&self) -> Option<Resource> {
        if self.space.states.len() > self.options.max_states {
            Some(Resource::States)
        } else if self.bytes() > self.options.max_bytes {
            Some(Resource::Memory)
        } else if self.meter.exceeded() {
            Some(Resource::Work)
        } else {
            None
        }
    }

    /// Calls the progress callback; `false` if it cancels the run.
    pub(super) fn report(&mut self) -> bool {
        self.meter.reported();
        let stats = self.stats();
        (self.progress)(&stats)
    }

    /// Accounts `units` of work. Returns `false`, with the reason in `halt`, when the search must
    /// stop: a budget is exceeded or, at a progress call during long work, the caller cancels.
    pub(super) fn charge(&mut self, units: u64) -> bool {
        let charge = self.meter.charge(units);
        if self.halt.is_none() {
            match charge {
                Charge::Within => {}
                Charge::Exceeded => self.halt = Some(Halt::Budget(Resource::Work)),
                // During long work on one state: the other budgets too, then the caller.
                Charge::ReportDue => {
                    if let Some(budget) = self.exceeded() {
                        self.halt = Some(Halt::Budget(budget));
                    } else if !self.report() {
                        self.halt = Some(Halt::Cancelled);
                    }
                }
            }
        }
        self.halt.is_none()
    }
}
