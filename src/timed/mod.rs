//! The timed-game engine (Peter 2005, chapters 2–6).
//!
//! Pipeline: [`parse`] (syntax, all diagnostics) → [`compile`] (semantic check, game model) →
//! `precompute` (clock usage, unique choice intervals) → [`solve`] (forward exploration with
//! reverse fail-state removal); [`synthesize`] runs the last two with a [`Config`] and explains
//! a loss ([`explain`]); [`program`] turns a winning strategy into the intermediate controller
//! program (chapter 6), which `plc::lower::timed` lowers to PLC code. At a PLC's scan time,
//! [`synthesize_at_scan`] solves the scan game (`scan`) and [`scan_bound`] finds the longest
//! scan time that works. [`export`] holds the JSON views of a game and a solved space.
//! `precompute`, `scan` and `plant` (the plant the real-time checker runs) are the engine's;
//! `testing` (hidden) gives the tests what they check of them.
//!
//! ```
//! use plcsynth::timed::{compile, synthesize, Config, Outcome, Verdict};
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
//! let result = synthesize(&game, &Config::default(), &mut |_stats| true);
//! // The controller can only react after the press: no controller exists.
//! assert_eq!(result.verdict(), Some(Verdict::Unrealizable));
//! assert!(result.explanation.unwrap().render().contains("!press"));
//! ```

mod arena;
mod ast;
mod check;
pub mod explain;
pub mod export;
mod lexer;
pub mod model;
mod parser;
pub(crate) mod plant;
mod precompute;
pub mod program;
mod scan;
pub mod solve;
mod timelock;

use crate::diag::{Checked, Diagnostic, Diagnostics, Span};
use crate::search::OnProgress;
use lexer::{tokenize, Tok};

// The engine contract (see `crate::search`): `compile` → `synthesize` with a `Config` →
// a `Synthesis`, whose `Outcome` is a `Verdict` or a `Stop`; progress reports the `Stats`.
pub use crate::search::{Outcome, Stop};
pub use solve::{Config, Stats, Verdict};
// The types of the machinery that the front door's results carry: the split automata of a
// `Synthesis` and why a scan game cannot be built. (`plant`, the plant the real-time checker
// runs, is the crate's.)
pub use precompute::SplitGame;
pub use scan::ScanError;

/// Internals for the integration tests and the fuzz harness; not part of the API.
#[doc(hidden)]
pub mod testing {
    pub use super::precompute::SubLocId;
    pub use super::scan::scan_game;
}

/// A parsed specification with every syntax diagnostic.
pub struct Parsed {
    /// The syntax tree: internal to the engine ([`compile`] checks it into a game).
    #[allow(dead_code)]
    pub(crate) spec: ast::Spec,
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
pub fn compile(source: &str) -> Checked<model::Game> {
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

impl Outcome for Synthesis {
    type Verdict = Verdict;

    fn outcome(&self) -> Result<Verdict, &Stop> {
        self.solution.outcome()
    }
}

/// Precomputes and solves a checked game within the budgets of `options`. A split that alone
/// exceeds them is refused: the outcome is a budget [`solve::Stop`], the state space
/// is empty and the stop names the location to blame. `progress` is called during both.
pub fn synthesize(
    game: &model::Game,
    options: &solve::Config,
    progress: &mut OnProgress<'_, solve::Stats>,
) -> Synthesis {
    synthesize_guided(game, None, options, progress)
}

/// [`synthesize`] with the search of a scan game guided by a zero-time strategy.
fn synthesize_guided(
    game: &model::Game,
    guide: Option<&solve::ScanGuide>,
    options: &solve::Config,
    progress: &mut OnProgress<'_, solve::Stats>,
) -> Synthesis {
    let split = match precompute::split(game, options, progress) {
        Ok(split) => split,
        Err(error) => {
            let (stop, stats, blame) = match error {
                precompute::SplitError::TooLarge(t) => {
                    let stats = solve::Stats { bytes: t.bytes, work: t.work, ..solve::Stats::default() };
                    (solve::split_stop(&t, options), stats, Some(t.span))
                }
                precompute::SplitError::Cancelled => (solve::Stop::Cancelled, solve::Stats::default(), None),
            };
            let space = solve::StateSpace::empty(game.dim(), game.components.len(), game.plans.len());
            let solution = solve::Solution { outcome: Err(stop), stats, space, blame };
            return Synthesis { split: precompute::unsplit(game), solution, explanation: None };
        }
    };
    let solution = solve::solve_guided(game, &split, options, guide, progress);
    let explanation = if solution.verdict() == Some(solve::Verdict::Unrealizable) {
        explain::explain(game, &split, &solution.space, solution.space.initial)
    } else {
        None
    };
    Synthesis { split, solution, explanation }
}

/// A verdict at a PLC scan time: the scan game (see `scan`) and its solution.
pub struct ScanSynthesis {
    pub scan_ms: u64,
    pub game: model::Game,
    pub synthesis: Synthesis,
    /// The options it was solved with.
    pub options: solve::Config,
}

impl ScanSynthesis {
    /// Whether some move of the solution goes to a state that includes its zone rather than
    /// to its own (inclusion, see [`solve::Config::inclusion`]).
    pub fn has_covers(&self) -> bool {
        self.synthesis.solution.space.edges.iter().any(|e| e.is_covered())
    }

    /// The same scan game solved with every zone its own state (no inclusion), if this
    /// solution has covers: the strategy a PLC's code can follow read by read, where a cover's
    /// decisions, made for a larger zone, tell apart states the PLC's inputs do not. `None` if
    /// this solution has no covers (it is exact already) or the scan game cannot be built.
    pub fn exact(&self, game: &model::Game, progress: &mut OnProgress<'_, solve::Stats>) -> Option<ScanSynthesis> {
        if !self.has_covers() {
            return None;
        }
        let options = solve::Config { inclusion: false, ..self.options.clone() };
        synthesize_at_scan(game, self.scan_ms, &options, progress).ok()
    }

    /// The same scan game solved by the exhaustive search (within the same budgets): the whole
    /// winning region, where every decision's consequences are explored, not only the
    /// strategy's. `None` if the scan game cannot be built.
    pub fn exhaustive(&self, game: &model::Game, progress: &mut OnProgress<'_, solve::Stats>) -> Option<ScanSynthesis> {
        let options = solve::Config { exhaustive: true, ..self.options.clone() };
        synthesize_at_scan(game, self.scan_ms, &options, progress).ok()
    }
}

/// Solves the scan game of `game` at `scan_ms`: realizable means implementable on a PLC with
/// that cycle time. The strategy-directed search is guided by a zero-time strategy (see
/// [`scan_guide`]); the verdict does not depend on the guide, only the work to reach it.
pub fn synthesize_at_scan(
    game: &model::Game,
    scan_ms: u64,
    options: &solve::Config,
    progress: &mut OnProgress<'_, solve::Stats>,
) -> Result<ScanSynthesis, scan::ScanError> {
    let scan_game = scan::scan_game(game, scan_ms)?;
    let guide = if options.exhaustive { None } else { scan_guide(game, scan_ms, options, progress) };
    let synthesis = synthesize_guided(&scan_game, guide.as_ref(), options, progress);
    Ok(ScanSynthesis { scan_ms, game: scan_game, synthesis, options: options.clone() })
}

/// The zero-time strategy that guides the search of the scan game at `scan_ms`, or `None` if
/// the zero-time controller does not win. A PLC reacts up to a scan or two late at every step,
/// so a zero-time strategy that meets a plan's deadline with nothing to spare leads the scan
/// search into a long dead end; the guide is the strategy of the zero-time game (in the scan
/// game's time units) with every plan deadline shortened by a spare, the largest of half the
/// shortest deadline, a quarter, and so on, that keeps it realizable (within a factor of two of
/// the most time a strategy can spare).
///
/// The spares are searched by bisection, after the game without a spare (which decides whether
/// there is a guide at all). Proving a tightened game lost explores every alternative, where a
/// win is found along one strategy, so a tightened game gets [`GUIDE_BUDGET_FACTOR`] times the
/// states and work of the game without a spare, and one that needs more counts as lost: the
/// guide may then spare less than it could, and only the work to reach the verdict changes,
/// never the verdict.
pub fn scan_guide(
    game: &model::Game,
    scan_ms: u64,
    options: &solve::Config,
    progress: &mut OnProgress<'_, solve::Stats>,
) -> Option<solve::ScanGuide> {
    let base = scan::rescaled(game, scan_ms).ok()?;
    let shortest = base.plans.iter().flat_map(|p| p.clocks.iter().map(|&(_, bound)| bound)).min().unwrap_or(0);
    let loose = synthesize(&base, options, progress);
    if !loose.solution.is_realizable() {
        return None;
    }
    // The spares, largest first: half the shortest deadline, a quarter, ..., 1.
    let spares: Vec<_> = std::iter::successors(Some(shortest / 2), |&s| Some(s / 2)).take_while(|&s| s > 0).collect();
    let stats = &loose.solution.stats;
    let capped = solve::Config {
        max_states: options.max_states.min(stats.visited.saturating_mul(GUIDE_BUDGET_FACTOR).max(1)),
        max_work: options.max_work.min(stats.work.saturating_mul(GUIDE_BUDGET_FACTOR as u64).max(1)),
        ..options.clone()
    };
    // The first spare that wins lies in `lo..=hi` (`hi = spares.len()`: none does, only 0).
    let (mut lo, mut hi) = (0, spares.len());
    let mut best = loose;
    while lo < hi {
        let mid = (lo + hi) / 2;
        let mut tight = base.clone();
        for (_, bound) in tight.plans.iter_mut().flat_map(|p| p.clocks.iter_mut()) {
            *bound -= spares[mid];
        }
        let synthesis = synthesize(&tight, &capped, progress);
        if synthesis.solution.outcome == Err(solve::Stop::Cancelled) {
            return None;
        }
        if synthesis.solution.is_realizable() {
            best = synthesis;
            hi = mid;
        } else {
            lo = mid + 1;
        }
    }
    solve::ScanGuide::new(&best.split, &best.solution)
}

/// How many times the states and the work of the zero-time game without a spare a tightened
/// game of [`scan_guide`] may take.
const GUIDE_BUDGET_FACTOR: usize = 2;

/// The scan times around a verdict: the longest found to work and the shortest found not to.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
pub struct ScanBound {
    /// Implementable at this scan time (milliseconds).
    pub works: Option<u64>,
    /// Not implementable at this scan time.
    pub fails: Option<u64>,
    /// A probe between `works` and `fails` (or above `works`, when nothing failed) hit a budget
    /// or was cancelled: the times between are open.
    pub stopped: bool,
    /// The specification has no time constants: scaling time maps the runs at one scan time
    /// onto the runs at any other, so the verdict is the same at every scan time.
    pub scale_free: bool,
}

impl ScanBound {
    /// The bound in words, as `solve` and the playground print it (`None` if nothing was found).
    pub fn text(&self) -> Option<String> {
        if self.scale_free {
            return Some("the same at every scan time (the specification has no time constants)".into());
        }
        let text = match (self.works, self.fails) {
            (Some(w), Some(f)) => format!("implementable at {w} ms, not at {f} ms"),
            (None, Some(f)) => format!("not implementable at any scan time tried, down to 1 ms (fails at {f} ms)"),
            (Some(w), None) => format!("implementable up to at least {w} ms (the longest tried)"),
            (None, None) => return None,
        };
        Some(match (self.stopped, self.works, self.fails) {
            (false, ..) => text,
            (true, Some(_), Some(_)) => format!("{text}; between them the search stopped at a budget"),
            (true, ..) => format!("{text}; the search stopped at a budget"),
        })
    }
}

/// Searches the scan times around `scan_ms`, where the verdict was `implementable`: below it by
/// bisection when it fails, above it by doubling (up to four times the longest constant of the
/// specification) and then bisection when it works. Implementability need not be monotone in
/// the scan time, so the answer is two neighbouring times that were solved, not a proof about
/// the times between: "works at `works`, fails at `fails`".
///
/// A scan time with few common divisors with the time unit makes a large game (1301 ms in
/// seconds is 1301 units of a millisecond), so the bisection probes round times first (the
/// multiple of the largest step in the middle half of the interval: 30, then 35, then 36 between
/// 20 and 40) and ends at neighbours only where those decide. A probe that stops at a budget is
/// passed over: doubling goes on above it, and the bisection probes the wider of the gaps below
/// the lowest and above the highest of them, up to [`UNDECIDED_PROBES`]; the pair found stays a
/// decided one.
pub fn scan_bound(
    game: &model::Game,
    scan_ms: u64,
    implementable: bool,
    options: &solve::Config,
    progress: &mut OnProgress<'_, solve::Stats>,
) -> ScanBound {
    let mut bound = ScanBound::default();
    // `None`: stopped at a budget or cancelled (or no scan game at that time).
    let mut verdict_at = |ms: u64| -> Option<bool> {
        let result = synthesize_at_scan(game, ms, options, progress).ok()?;
        Some(result.synthesis.solution.verdict()? == solve::Verdict::Realizable)
    };
    let longest = game
        .components
        .iter()
        .flat_map(|c| {
            let guards = c.edges.iter().flat_map(|e| &e.guard);
            guards.chain(c.locations.iter().flat_map(|l| &l.invariant))
        })
        .map(|ci| ci.interval.upper.unwrap_or(ci.interval.lower))
        .chain(game.plans.iter().flat_map(|p| p.clocks.iter().map(|&(_, b)| b)))
        .max()
        .unwrap_or(0);
    if longest == 0 {
        bound.scale_free = true;
        return bound;
    }
    // Probes that stopped at a budget: the bisection probes below the lowest of them or above
    // the highest, in the wider of the two gaps.
    let mut undecided: Vec<u64> = Vec::new();
    let (mut lo, mut hi) = if implementable {
        let cap = (u64::from(longest) * game.timeunit_ms).max(scan_ms).saturating_mul(4);
        let (mut works, mut next) = (scan_ms, scan_ms.saturating_mul(2));
        loop {
            if next > cap {
                bound.works = Some(works);
                bound.stopped = !undecided.is_empty();
                return bound;
            }
            match verdict_at(next) {
                Some(true) => works = next,
                Some(false) => break (works, next),
                None => undecided.push(next),
            }
            next = next.saturating_mul(2);
        }
    } else {
        (0, scan_ms)
    };
    while undecided.len() < UNDECIDED_PROBES {
        let between = || undecided.iter().copied().filter(|&u| lo < u && u < hi);
        let (lowest, highest) = (between().min().unwrap_or(hi), between().max().unwrap_or(lo));
        let probe = if hi - highest > lowest - lo {
            round_probe(highest, hi).or_else(|| round_probe(lo, lowest))
        } else {
            round_probe(lo, lowest).or_else(|| round_probe(highest, hi))
        };
        let Some(mid) = probe else { break };
        match verdict_at(mid) {
            Some(true) => lo = mid,
            Some(false) => hi = mid,
            None => undecided.push(mid),
        }
    }
    bound.works = (lo > 0).then_some(lo);
    bound.fails = Some(hi);
    // A probe that stopped between the pair leaves the times between them open.
    bound.stopped = undecided.iter().any(|&u| lo < u && u < hi);
    bound
}

/// Probes that stop at a budget one bound search passes over before it settles for the pair
/// it has (each costs a whole budget).
pub const UNDECIDED_PROBES: usize = 3;

/// The next probe of a bisection of the open interval `(lo, hi)` of milliseconds: the multiple
/// of the largest round step (1000, 500, 200, 100, 50, 20, 10, 5, 2, 1 ms) that lies in the
/// middle half of the interval, nearest its middle; `None` once the ends are neighbours.
fn round_probe(lo: u64, hi: u64) -> Option<u64> {
    if hi <= lo + 1 {
        return None;
    }
    let (quarter_lo, quarter_hi) = (lo + (hi - lo) / 4, hi - (hi - lo) / 4);
    let middle = lo + (hi - lo) / 2;
    for step in [1000, 500, 200, 100, 50, 20, 10, 5, 2] {
        let below = middle / step * step;
        let candidates = [below, below + step].into_iter().filter(|&m| m > lo && m < hi);
        let inside = candidates.filter(|&m| m >= quarter_lo && m <= quarter_hi);
        if let Some(m) = inside.min_by_key(|&m| m.abs_diff(middle)) {
            return Some(m);
        }
    }
    Some(middle)
}

/// Where constant `value` of `clock` is written in `source`, the text `game` was compiled from:
/// the number in the first guard or invariant of the clock that has it as a bound, or the bound
/// of a plan's timeout clock. Falls back to the whole interval (an operator's implicit `(0,1)` is
/// not written) or the clock's declaration. Back ends locate constants they cannot hold with it.
pub fn constant_span(game: &model::Game, source: &str, clock: model::ClockId, value: u32) -> Span {
    // The numbers written in `span`, in order, with their spans.
    let numbers = |span: Span| -> Vec<(u32, Span)> {
        let Some(text) = source.get(span.range()) else { return Vec::new() };
        tokenize(text)
            .into_iter()
            .filter(|t| t.tok == Tok::Int)
            .filter_map(|t| {
                let value = text[t.span.range()].parse().ok()?;
                Some((value, Span::new((span.start + t.span.start) as usize, (span.start + t.span.end) as usize)))
            })
            .collect()
    };
    let intervals = game
        .components
        .iter()
        .flat_map(|a| a.locations.iter().flat_map(|l| &l.invariant).chain(a.edges.iter().flat_map(|e| &e.guard)));
    for ci in intervals.filter(|ci| ci.clock == clock) {
        let interval = ci.interval;
        if interval.lower == value || interval.upper == Some(value) {
            return numbers(interval.span).into_iter().find(|&(v, _)| v == value).map_or(interval.span, |(_, s)| s);
        }
    }
    let declared = game.clocks[clock.index()].span;
    // A plan's timeout clock is declared as `name bound`.
    numbers(declared).into_iter().rfind(|&(v, _)| v == value).map_or(declared, |(_, s)| s)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_bound_says_where_the_search_stopped() {
        let bound = |works, fails, stopped| ScanBound { works, fails, stopped, scale_free: false }.text();
        assert_eq!(bound(Some(35), Some(36), false).unwrap(), "implementable at 35 ms, not at 36 ms");
        assert_eq!(
            bound(Some(15), Some(20), true).unwrap(),
            "implementable at 15 ms, not at 20 ms; between them the search stopped at a budget"
        );
        assert_eq!(
            bound(Some(20), None, true).unwrap(),
            "implementable up to at least 20 ms (the longest tried); the search stopped at a budget"
        );
        assert_eq!(bound(None, None, true), None);
    }

    #[test]
    fn bisection_probes_round_times_first() {
        let probes = |mut lo: u64, hi: u64| {
            let mut out = Vec::new();
            while let Some(m) = round_probe(lo, hi) {
                out.push(m);
                lo = m;
            }
            out
        };
        // Between 20 and 40 ms, with every probe found to work.
        assert_eq!(probes(20, 40), [30, 35, 36, 38, 39]);
        assert_eq!(round_probe(1300, 1462), Some(1400));
        assert_eq!(round_probe(0, 10), Some(5));
        assert_eq!(round_probe(14, 15), None);
        // Every probe lies strictly inside, and the ends meet.
        for lo in 0..60 {
            for hi in lo + 2..80 {
                let m = round_probe(lo, hi).unwrap();
                assert!(lo < m && m < hi, "{lo} {hi} {m}");
            }
        }
    }

    /// The text at each span [`constant_span`] finds for `(clock, value)`.
    fn located(source: &str, clock: &str, value: u32) -> String {
        let (game, _) = crate::timed::compile(source).expect("a valid specification");
        let id =
            crate::timed::model::ClockId::new(game.clocks.iter().position(|c| c.name == clock).expect("the clock"));
        let span = constant_span(&game, source, id, value);
        let (line, column) = Diagnostics::new(source).line_col(span.start as usize);
        format!("{line}:{column} {}", &source[span.range()])
    }

    #[test]
    fn constants_are_found_where_they_are_written() {
        let source = "plant {\n  hardware H { states a, b; a -> b takes [2, /* up to */ 4]; }\n  \
                      operator O { states p, q; p -> q; }\n  \
                      automaton A { clocks x; nodes u { x in [0,0030] }, v; u -> v ?go { x in (7,inf) }; v -> u ?back; }\n}\n\
                      plans { plan { clocks t 4000; waitfor go; } }\n";
        assert_eq!(located(source, "H.moving", 2), "2:43 2");
        assert_eq!(located(source, "H.moving", 4), "2:58 4");
        assert_eq!(located(source, "A.x", 30), "4:45 0030");
        assert_eq!(located(source, "A.x", 7), "4:76 7");
        assert_eq!(located(source, "plan1.t", 4000), "6:25 4000");
        // An operator's reaction within (0,1) is not written: the move is.
        assert_eq!(located(source, "O.moving", 1), "3:29 p -> q;");
    }
}
