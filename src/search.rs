//! What the engines' searches share: the progress callback, the meter, why a search ended
//! without deciding, and the outcome of a run.
//!
//! The engine contract (ARCHITECTURE.md, "One engine contract"): each engine's `mod.rs` offers
//! `compile` (text → checked model, see [`crate::diag::Checked`]), a `Config` with builder
//! methods (`setters!`), and `synthesize(model, &Config, progress) -> Synthesis`, where the
//! progress callback is an [`OnProgress`] of the engine's `Progress` and the `Synthesis`
//! implements [`Outcome`]: a [`Decision`] of the engine or a [`Stop`].
//!
//! Every search meters what it builds against the budgets of its engine's `Config` and asks the
//! caller's progress callback now and then; the callback's `false` cancels. A run that ends so
//! returns a [`Stop`], never a verdict, so that verdicts hold only decisions. All three engines
//! stop with this type; the CLI's JSON and the page print it in one shape (`{"stop": "budget",
//! "resource": "work", "message": ...}`) and name the end of a run by [`Stop::outcome_name`]
//! where a decision would have been.

use serde::Serialize;
use std::fmt;

/// The budget that ran out.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Resource {
    /// States or game positions built (`max_states`).
    States,
    /// Approximate heap bytes (`max_bytes`).
    Memory,
    /// Units of work, about proportional to time (`max_work`).
    Work,
    /// A size the representation cannot hold (signals of a letter, say), whatever the budgets.
    Size,
}

impl Resource {
    /// Its name in messages: `state`, `memory`, `work` or `size`.
    pub fn name(self) -> &'static str {
        match self {
            Resource::States => "state",
            Resource::Memory => "memory",
            Resource::Work => "work",
            Resource::Size => "size",
        }
    }
}

/// Why a search ended before deciding.
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
#[serde(tag = "stop", rename_all = "snake_case")]
pub enum Stop {
    /// A budget ran out: which one, and a sentence naming it and how to raise it.
    Budget { resource: Resource, message: String },
    /// The progress callback returned `false`.
    Cancelled,
}

impl Stop {
    /// A budget stop.
    pub fn budget(resource: Resource, message: impl Into<String>) -> Stop {
        Stop::Budget { resource, message: message.into() }
    }

    /// How the run ended, in the words where a decision's name would stand (`realizable`, ...):
    /// `budget_exceeded` or `cancelled`.
    pub fn outcome_name(&self) -> &'static str {
        match self {
            Stop::Budget { .. } => "budget_exceeded",
            Stop::Cancelled => "cancelled",
        }
    }
}

impl fmt::Display for Stop {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Stop::Budget { message, .. } => f.write_str(message),
            Stop::Cancelled => f.write_str("cancelled"),
        }
    }
}

/// The progress callback of a search: called now and then with what the search has built so
/// far (the engine's `Progress`); returning `false` cancels the run, which then ends with
/// [`Stop::Cancelled`].
pub type OnProgress<'a, P> = dyn FnMut(&P) -> bool + 'a;

/// An engine's verdict: a decision only (a run that did not decide ends with a [`Stop`]). Its
/// name is its JSON form (each verdict serialises through it, so there is one list of names).
pub trait Decision: Copy + Eq + fmt::Debug + Serialize {
    /// Its name in the CLI's JSON and the page: `realizable`, `unrealizable`, ...
    fn name(self) -> &'static str;
}

/// How a run of an engine's `synthesize` ended: its decision or why there is none. The CLI and
/// the page read the three engines' results through it alike. A timed or SCT `Synthesis`
/// holds its outcome beside what the search built (a stopped search's states and reports are
/// shown too); an LTL run that stops has nothing to show, so `ltl::synthesize` returns
/// `Result<Synthesis, Stop>`, which implements it.
pub trait Outcome {
    type Verdict: Decision;

    /// The decision, or why the run ended without one.
    fn outcome(&self) -> Result<Self::Verdict, &Stop>;

    /// The decision, if the run reached one.
    fn verdict(&self) -> Option<Self::Verdict> {
        self.outcome().ok()
    }

    /// Why the run stopped before deciding, if it did.
    fn stop(&self) -> Option<&Stop> {
        self.outcome().err()
    }

    /// How the run ended, in the CLI's JSON and the page: the verdict's name, or
    /// `budget_exceeded` or `cancelled`.
    fn outcome_name(&self) -> &'static str {
        match self.outcome() {
            Ok(verdict) => verdict.name(),
            Err(stop) => stop.outcome_name(),
        }
    }
}

/// Counts what a search spends (units of work, or states built) against its budget and says
/// when the caller's progress callback is due: the one meter of the three engines. It calls no
/// callback itself, since each engine tells its own what it has built; it decides when.
#[derive(Clone, Debug)]
pub struct Meter {
    used: u64,
    limit: u64,
    /// Units between two progress calls, and when the next one is due.
    interval: u64,
    next_report: u64,
}

/// What a charge to a [`Meter`] found.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Charge {
    /// Within the budget, no progress call due.
    Within,
    /// Within the budget, and the progress callback is due (the meter counts it as made).
    ReportDue,
    /// Past the budget: the search stops.
    Exceeded,
}

impl Meter {
    /// A meter with `used` units already spent (an earlier phase's), `limit` in all, and a
    /// progress call every `interval` units.
    pub fn new(used: u64, limit: u64, interval: u64) -> Meter {
        Meter { used, limit, interval, next_report: used.saturating_add(interval) }
    }

    /// Spends `units`.
    pub fn charge(&mut self, units: u64) -> Charge {
        self.used = self.used.saturating_add(units);
        if self.used > self.limit {
            Charge::Exceeded
        } else if self.used >= self.next_report {
            self.reported();
            Charge::ReportDue
        } else {
            Charge::Within
        }
    }

    /// Records a progress call made for another reason (a search that also reports every so
    /// many expansions), so that the next is due an interval later.
    pub fn reported(&mut self) {
        self.next_report = self.used.saturating_add(self.interval);
    }

    pub fn used(&self) -> u64 {
        self.used
    }

    pub fn limit(&self) -> u64 {
        self.limit
    }

    /// Units left before the budget ends the search.
    pub fn remaining(&self) -> u64 {
        self.limit.saturating_sub(self.used)
    }

    /// Whether more than the budget is spent.
    pub fn exceeded(&self) -> bool {
        self.used > self.limit
    }

    /// Sets the budget (a share of the run's for optional work, restored after it).
    pub fn set_limit(&mut self, limit: u64) {
        self.limit = limit;
    }
}

/// Builder methods for the public fields of an engine's `Config`: each takes the config and
/// returns it with one field set (as regex-automata's configs), so that a caller writes
/// `Config::default().max_states(1000).exhaustive(true)` and keeps the defaults of the rest.
macro_rules! setters {
    ($config:ty { $($field:ident: $ty:ty),* $(,)? }) => {
        impl $config {
            $(
                #[doc = concat!("Sets `", stringify!($field), "` (the field's documentation says what it does).")]
                #[must_use]
                pub fn $field(mut self, $field: $ty) -> Self {
                    self.$field = $field;
                    self
                }
            )*
        }
    };
}

pub(crate) use setters;

/// Makes a verdict enum a [`Decision`] with the names given, and serialises it by them: the
/// one place a verdict's names are written.
macro_rules! decision {
    ($verdict:ty { $($variant:ident => $name:literal),* $(,)? }) => {
        impl $crate::search::Decision for $verdict {
            fn name(self) -> &'static str {
                match self {
                    $(<$verdict>::$variant => $name,)*
                }
            }
        }

        impl serde::Serialize for $verdict {
            fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
                serializer.serialize_str($crate::search::Decision::name(*self))
            }
        }
    };
}

pub(crate) use decision;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_stop_says_what_stopped_it() {
        let stop = Stop::budget(Resource::Work, "the run needs more than 10 units of work (--max-work)");
        assert_eq!(stop.to_string(), "the run needs more than 10 units of work (--max-work)");
        assert_eq!(Stop::Cancelled.to_string(), "cancelled");
        assert_eq!(serde_json::to_string(&Resource::States).unwrap(), "\"states\"");
        assert_eq!(
            serde_json::to_value(&stop).unwrap(),
            serde_json::json!({"stop": "budget", "resource": "work",
                               "message": "the run needs more than 10 units of work (--max-work)"})
        );
        assert_eq!(serde_json::to_value(Stop::Cancelled).unwrap(), serde_json::json!({"stop": "cancelled"}));
        assert_eq!((stop.outcome_name(), Stop::Cancelled.outcome_name()), ("budget_exceeded", "cancelled"));
    }

    #[test]
    fn a_meter_stops_past_its_limit_and_reports_every_interval() {
        let mut meter = Meter::new(0, 10, 4);
        assert_eq!(meter.charge(3), Charge::Within);
        assert_eq!(meter.charge(1), Charge::ReportDue);
        assert_eq!(meter.charge(3), Charge::Within, "the next report is due at 8");
        meter.reported();
        assert_eq!(meter.charge(3), Charge::Within, "a report at 7 moves the next to 11");
        assert_eq!((meter.used(), meter.remaining()), (10, 0));
        assert_eq!(meter.charge(1), Charge::Exceeded);
        assert!(meter.exceeded());
        let mut earlier = Meter::new(100, 200, 50);
        assert_eq!(earlier.charge(49), Charge::Within, "the interval counts from what was spent");
        assert_eq!(earlier.charge(1), Charge::ReportDue);
    }
}
