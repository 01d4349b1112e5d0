//! The budgets of the timed-game search (issue 9): states, memory and work, each stopping a
//! search that would otherwise run for minutes or exhaust memory, with the counters showing that
//! it stopped promptly; the progress callback is called during long work on one state; the
//! front end stays linear on long chains. Inputs are generated here.

use plcsynth::search::Outcome as _;
use plcsynth::timed::solve::{
    Config, Resource, Stats, Stop, Verdict, DEFAULT_MAX_BYTES, DEFAULT_MAX_STATES, DEFAULT_MAX_WORK,
};
use plcsynth::timed::{compile, synthesize, Synthesis};

/// One automaton with `n` clocks and one self-loop per clock: node `q` has every clock in use,
/// so the split makes 2^n sub-locations of it.
fn self_loops(n: usize) -> String {
    let clocks: Vec<String> = (0..n).map(|i| format!("c{i}")).collect();
    let mut s = format!("plant {{\n  automaton A {{\n    clocks {};\n    nodes q;\n", clocks.join(", "));
    for i in 0..n {
        s += &format!("    q -> q !t{i} {{c{i} in [1,inf)}} reset{{c{i}}};\n");
    }
    s + "  }\n}\n"
}

/// `n` independent two-node automata without clocks: 2^n plant states.
fn independent(n: usize) -> String {
    let mut s = String::from("plant {\n");
    for i in 0..n {
        s += &format!("  automaton A{i} {{ nodes a, b; a -> b ?x{i}; b -> a ?y{i}; }}\n");
    }
    s + "}\n"
}

/// `n` independent one-clock automata: zones of dimension n + 1.
fn one_clock_each(n: usize) -> String {
    let mut s = String::from("plant {\n");
    for i in 0..n {
        s += &format!(
            "  automaton A{i} {{ clocks c; nodes a {{c in [0,2]}}, b; a -> b !x{i} {{c in [1,2]}} reset{{c}}; b -> a ?y{i} reset{{c}}; }}\n"
        );
    }
    s + "}\n"
}

fn run(source: &str, options: &Config, progress: &mut dyn FnMut(&Stats) -> bool) -> Synthesis {
    let (game, _) = compile(source).unwrap_or_else(|d| panic!("{d:?}"));
    synthesize(&game, options, progress)
}

/// The largest work one candidate successor may add after the budget check: the search
/// stops right after the charge that exceeds the budget.
fn one_step(dim: u64, units: u64) -> u64 {
    64 + dim * dim + units
}

/// The budget and message of a search that a budget stopped; fails on anything else.
fn budget_stop(s: &Synthesis) -> (Resource, &str) {
    match &s.solution.outcome {
        Err(Stop::Budget { resource, message }) => (*resource, message),
        other => panic!("a budget stop, not {other:?}"),
    }
}

#[test]
fn a_node_with_too_many_clocks_is_refused_before_splitting() {
    let source = self_loops(22);
    let s = run(&source, &Config::default(), &mut |_| true);
    let (resource, message) = budget_stop(&s);
    assert_eq!(resource, Resource::Memory);
    assert!(message.contains(&format!("more than {} MiB", DEFAULT_MAX_BYTES >> 20)), "{message}");
    assert!(message.contains("node `q` of `A` splits into 4194304 sub-locations (22 clocks"), "{message}");
    let span = s.solution.blame.expect("located at the node");
    assert_eq!(&source[span.start as usize..span.end as usize], "q");
    assert!(source[..span.start as usize].ends_with("nodes "));
    // Refused from the sizes alone: nothing was built.
    assert_eq!(s.solution.stats.visited, 0);
    assert_eq!(s.solution.stats.bytes, 0);
    assert_eq!(s.solution.stats.work, 0);
}

#[test]
fn the_work_budget_stops_a_long_split() {
    let source = self_loops(22);
    let options = Config { max_bytes: 4 << 30, max_work: 2_000_000, ..Config::default() };
    let s = run(&source, &options, &mut |_| true);
    assert_eq!(budget_stop(&s).0, Resource::Work);
    assert!(s.solution.blame.is_some());
    let stats = s.solution.stats;
    assert!(stats.work > 2_000_000 && stats.work <= 2_000_000 + 1000, "{stats:?}");
    assert_eq!(stats.visited, 0);
}

#[test]
fn a_long_split_calls_the_progress_callback_which_can_cancel() {
    let source = self_loops(22);
    let options = Config { max_bytes: 4 << 30, progress_interval: usize::MAX, ..Config::default() };
    let mut calls = Vec::new();
    let s = run(&source, &options, &mut |stats| {
        calls.push(*stats);
        false
    });
    assert_eq!(s.solution.outcome, Err(Stop::Cancelled));
    assert_eq!(calls.len(), 1);
    assert_eq!(calls[0].visited, 0, "called before the first state exists");
    assert!(calls[0].work >= 1 << 20 && calls[0].work < 2 << 20, "{:?}", calls[0]);
}

#[test]
fn a_split_within_the_budgets_is_solved() {
    // 2^12 sub-locations: no plan, so every plant state repeats without progress.
    let s = run(&self_loops(12), &Config::default(), &mut |_| true);
    assert_eq!(s.solution.verdict(), Some(Verdict::Unrealizable));
    assert!(s.solution.stats.bytes > 4096 * 64, "the split counts: {:?}", s.solution.stats);
}

#[test]
fn many_independent_automata_stop_at_the_work_budget() {
    let options = Config { max_work: 5_000_000, ..Config::default() };
    let s = run(&independent(40), &options, &mut |_| true);
    let (resource, message) = budget_stop(&s);
    assert_eq!(resource, Resource::Work);
    assert!(message.contains("more than 5000000 units of work"), "{message}");
    assert_eq!(s.solution.blame, None, "no declaration is to blame for a search");
    let stats = s.solution.stats;
    assert!(stats.work > 5_000_000 && stats.work <= 5_000_000 + one_step(1, 40), "{stats:?}");
    assert!(stats.visited < DEFAULT_MAX_STATES);
}

#[test]
fn many_independent_automata_stop_at_the_memory_budget() {
    let options = Config { max_bytes: 16 << 20, ..Config::default() };
    let s = run(&one_clock_each(30), &options, &mut |_| true);
    let (resource, message) = budget_stop(&s);
    assert_eq!(resource, Resource::Memory);
    assert!(message.contains("more than 16 MiB"), "{message}");
    let stats = s.solution.stats;
    // Capacities double: one step past the budget at most.
    assert!(stats.bytes > 16 << 20 && stats.bytes < 40 << 20, "{stats:?}");
    assert!(stats.work < DEFAULT_MAX_WORK);
}

#[test]
fn the_default_budgets_stop_forty_independent_automata() {
    let s = run(&independent(40), &Config::default(), &mut |_| true);
    budget_stop(&s);
    let stats = s.solution.stats;
    assert!(stats.visited <= DEFAULT_MAX_STATES + 64, "{stats:?}");
    assert!(stats.bytes < 2 * DEFAULT_MAX_BYTES, "{stats:?}");
    assert!(stats.work <= DEFAULT_MAX_WORK + one_step(1, 40), "{stats:?}");
}

#[test]
fn the_search_reports_progress_by_work_too() {
    // Without calls by expansions, the work-based calls still come, and cancel.
    let options = Config { progress_interval: usize::MAX, ..Config::default() };
    let mut calls = Vec::new();
    let s = run(&one_clock_each(20), &options, &mut |stats| {
        calls.push(*stats);
        calls.len() < 3
    });
    assert_eq!(s.solution.outcome, Err(Stop::Cancelled));
    assert_eq!(calls.len(), 3);
    assert!(calls.windows(2).all(|w| w[1].work >= w[0].work + (1 << 20)), "{calls:?}");
    assert!(calls[0].visited > 0);
}

#[test]
fn a_state_budget_stop_says_so() {
    let s = run(&independent(20), &Config { max_states: 1000, ..Config::default() }, &mut |_| true);
    assert_eq!(budget_stop(&s), (Resource::States, "the search stored more than 1000 states"));
    assert!(s.solution.stats.visited > 1000 && s.solution.stats.visited < 1100);
}

/// Each node of a long chain is a new plant state on one path without plan progress. The zeno
/// memory of that path once was a linked list walked for every move: quadratic, minutes for
/// this chain; now it is a persistent set and the chain is solved at once.
#[test]
fn a_long_chain_is_solved_in_linear_time() {
    let n = 100_000;
    let mut source = String::from("plant {\n  automaton A {\n    nodes ");
    source += &(0..n).map(|i| format!("n{i}")).collect::<Vec<_>>().join(", ");
    source += ";\n";
    for i in 0..n - 1 {
        source += &format!("    n{i} -> n{} ?m{i};\n", i + 1);
    }
    source += "  }\n}\nplans { plan { waitfor m0; } }\n";
    let s = run(&source, &Config::default(), &mut |_| true);
    assert_eq!(s.solution.verdict(), Some(Verdict::Unrealizable));
    assert_eq!(s.solution.stats.expanded, n);
}

/// The strategy-directed search ranks the whole explored space again whenever it steers a
/// choice off a cycle without progress (`steer_by_ranks`), and those rankings count as work.
/// Random spec 94's zero-time game steers hundreds of times over 400 000 states: uncounted and
/// one switch per ranking, they took 7.5 minutes within the default budget (to "unrealizable");
/// counted, and with the switches taken in growing batches, the default work budget stops the
/// search after a few seconds (16 times the budget decides it, in 95 s).
#[test]
fn steering_counts_as_work_and_the_default_budget_stops_it() {
    let s = run(&crate::random_spec::spec(94), &Config::default(), &mut |_| true);
    let (resource, _) = budget_stop(&s);
    assert_eq!(resource, Resource::Work, "{:?}", s.solution.stats);
    assert!(s.solution.stats.visited < DEFAULT_MAX_STATES);
}
