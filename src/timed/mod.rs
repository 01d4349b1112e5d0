//! The timed-game engine (Peter 2005, chapters 2–5).
//!
//! Pipeline: [`parse`] (syntax, all diagnostics) → [`compile`] (semantic check, game model) →
//! [`precompute`] (clock usage, unique choice intervals) → [`solve`] (forward exploration with
//! reverse fail-state removal); [`synthesize`] runs the last two and explains a loss.
//!
//! ```
//! use plcsynth::timed::{compile, synthesize, solve::{SolveOptions, Verdict}};
//!
//! let source = "
//!     plant {
//!       automaton lamp { nodes off, on; off -> on ?turn_on; on -> off ?turn_off; }
//!       automaton button { nodes released, pressed;
//!                          released -> pressed !press; pressed -> released !release; }
//!     }
//!     assertions { never lamp.off and button.pressed; }
//!     plans { plan { waitfor press; waitfor release; } }";
//! let (game, _warnings) = compile(source).expect("a valid specification");
//! let result = synthesize(&game, &SolveOptions::default(), &mut |_stats| true);
//! // The controller can only react after the press: no controller exists.
//! assert_eq!(result.solution.verdict, Verdict::Unrealizable);
//! assert!(result.explanation.unwrap().render().contains("!press"));
//! ```

pub mod arena;
pub mod ast;
pub mod check;
pub mod explain;
pub mod export;
pub mod lexer;
pub mod model;
pub mod parser;
pub mod precompute;
pub mod solve;

use crate::diag::{Diagnostic, Diagnostics};

/// A parsed specification with every syntax diagnostic.
pub struct Parsed {
    pub spec: ast::Spec,
    pub diagnostics: Vec<Diagnostic>,
}

/// Parses a `.tga` source; never fails, never panics: problems are in `diagnostics`.
pub fn parse(source: &str) -> Parsed {
    let mut diags = Diagnostics::new(source);
    let spec = parser::parse(source, &mut diags);
    Parsed { spec, diagnostics: diags.items }
}

/// Parses and checks a `.tga` source. On success returns the game and the warnings; otherwise
/// every diagnostic (syntax errors first, then semantic ones when the syntax was sound enough).
pub fn compile(source: &str) -> Result<(model::Game, Vec<Diagnostic>), Vec<Diagnostic>> {
    let mut diags = Diagnostics::new(source);
    let spec = parser::parse(source, &mut diags);
    let game = check::check(&spec, &mut diags);
    match game {
        Some(game) if !diags.has_errors() => Ok((game, diags.items)),
        _ => Err(diags.items),
    }
}

/// A solved game: the split automata, the solver's result and, when the initial state is
/// lost, the explanation.
pub struct Synthesis {
    pub split: precompute::SplitGame,
    pub solution: solve::Solution,
    pub explanation: Option<explain::Explanation>,
}

/// Precomputes and solves a checked game within the budgets of `options`. A split that alone
/// exceeds them is refused: the verdict is [`solve::Verdict::BudgetExceeded`], the state space
/// is empty and the stop names the location to blame. `progress` is called during both.
pub fn synthesize(
    game: &model::Game,
    options: &solve::SolveOptions,
    progress: &mut dyn FnMut(&solve::Stats) -> bool,
) -> Synthesis {
    let split = match precompute::split(game, options, progress) {
        Ok(split) => split,
        Err(error) => {
            let (verdict, stats, stop) = match error {
                precompute::SplitError::TooLarge(t) => {
                    let stats = solve::Stats { bytes: t.bytes, work: t.work, ..solve::Stats::default() };
                    (solve::Verdict::BudgetExceeded, stats, Some(solve::BudgetStop::split(&t, options)))
                }
                precompute::SplitError::Cancelled => (solve::Verdict::Cancelled, solve::Stats::default(), None),
            };
            let space = solve::StateSpace::empty(game.dim(), game.components.len(), game.plans.len());
            let solution = solve::Solution { verdict, stats, space, stop };
            return Synthesis { split: precompute::unsplit(game), solution, explanation: None };
        }
    };
    let solution = solve::solve(game, &split, options, progress);
    let explanation = if solution.verdict == solve::Verdict::Unrealizable {
        explain::explain(game, &split, &solution.space, solution.space.initial)
    } else {
        None
    };
    Synthesis { split, solution, explanation }
}
