//! What the engines' searches share: why a search ended without deciding.
//!
//! Every search meters what it builds against the budgets of its engine's `Config` and asks the
//! caller's progress callback now and then; the callback's `false` cancels. A run that ends so
//! returns a [`Stop`], never a verdict, so that verdicts hold only decisions. The supervisory
//! control and LTL engines return this type; the timed engine still folds its stops into its
//! verdict (`timed::solve::Verdict::BudgetExceeded`, `Cancelled`) and is next to move.

use serde::Serialize;
use std::fmt;

/// The budget that ran out.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Resource {
    /// States or game positions built (`max_states`).
    States,
    /// Units of work, about proportional to time (`max_work`).
    Work,
    /// A size the representation cannot hold (signals of a letter, say), whatever the budgets.
    Size,
}

/// Why a search ended before deciding.
#[derive(Clone, Debug, PartialEq, Eq)]
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

    /// Its name in the JSON forms and the page: `budget` or `cancelled`.
    pub fn name(&self) -> &'static str {
        match self {
            Stop::Budget { .. } => "budget",
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_stop_says_what_stopped_it() {
        let stop = Stop::budget(Resource::Work, "the run needs more than 10 units of work (--max-work)");
        assert_eq!(stop.to_string(), "the run needs more than 10 units of work (--max-work)");
        assert_eq!(stop.name(), "budget");
        assert_eq!(Stop::Cancelled.to_string(), "cancelled");
        assert_eq!(serde_json::to_string(&Resource::States).unwrap(), "\"states\"");
    }
}
