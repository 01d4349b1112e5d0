//! The symbolic solver (`--solver symbolic`) on specifications wider than its table
//! extraction (more than 12 signals), where the strategy is read off its decision diagram:
//! verdicts and bounds as the explicit solver's, on the same positions, and every controller and
//! counter-strategy confirmed twice — by the product search of `tests/ltl_random.rs` on our
//! automata and by `tests/checkers/ltl_mc.py` on lbt's. Mealy and Moore, both verdicts.

use crate::ltl_examples::model_check;
use crate::ltl_random::some_play_accepted;
use plcsynth::ltl::testing::translate;
use plcsynth::ltl::{self, Config, Format, Ltl, Solver, Verdict};
use std::path::PathBuf;

/// Seven requests and seven grants (14 signals), with the semantics and guarantees given.
fn spec(semantics: &str, guarantees: &str) -> String {
    format!(
        "INFO {{ TITLE: \"wide\" DESCRIPTION: \"\" SEMANTICS: {semantics} TARGET: {semantics} }}\n\
         GLOBAL {{ PARAMETERS {{ n = 7; }} }}\n\
         MAIN {{ INPUTS {{ r[n]; }} OUTPUTS {{ g[n]; }} GUARANTEES {{ {guarantees} }} }}\n"
    )
}

#[test]
fn wide_specifications_get_diagram_strategies_that_win() {
    let cases = [
        ("mealy_grants", spec("Mealy", "&&[0 <= i < n] G (r[i] -> F g[i]); G !(g[0] && g[1]);"), Verdict::Realizable),
        ("mealy_prophecy", spec("Mealy", "&&[0 <= i < n] G (g[i] <-> X r[i]);"), Verdict::Unrealizable),
        ("moore_next", spec("Moore", "&&[0 <= i < n] G (r[i] -> X g[i]);"), Verdict::Realizable),
        ("moore_same_step", spec("Moore", "&&[0 <= i < n] G (g[i] <-> r[i]);"), Verdict::Unrealizable),
    ];
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("target/ltl-symbolic");
    std::fs::create_dir_all(&dir).unwrap();
    let mut documents = Vec::new();
    for (name, source, expected) in cases {
        let (spec, _) = ltl::compile(&source, Format::Tlsf, &[]).unwrap_or_else(|d| panic!("{name}: {d:?}"));
        assert_eq!(spec.signals.len(), 14);
        let decide = |solver| {
            let cfg = Config { solver, ..Config::default() };
            ltl::synthesize(&spec, &cfg, &mut |_| true).unwrap_or_else(|stop| panic!("{name}: {stop}"))
        };
        let (symbolic, explicit) = (decide(Solver::Symbolic), decide(Solver::Explicit));
        let bdd = decide(Solver::Bdd);
        // The bdd solver decides as the explicit one does, or says its diagrams outgrew the budget.
        let bdd_decided = bdd.verdict != Verdict::Unknown;
        if bdd_decided {
            assert_eq!((bdd.verdict, bdd.k), (explicit.verdict, explicit.k), "{name}: bdd");
        } else {
            let limit = bdd.limit.as_deref().unwrap_or_default();
            assert!(limit.contains("BDD nodes") || limit.contains("--max-work"), "{name}: bdd: {limit}");
        }
        assert_eq!(symbolic.verdict, expected, "{name}: {}", ltl::summary(&symbolic));
        assert_eq!((symbolic.verdict, symbolic.k), (explicit.verdict, explicit.k), "{name}");
        assert_eq!(symbolic.stats.positions, explicit.stats.positions, "{name}");
        let names = |s: ltl::SignalId| spec.name(s).to_string();
        let formula = spec.formula();
        // A controller lets no play satisfy ¬φ; a counter-strategy lets none satisfy φ.
        let opposed = if expected == Verdict::Realizable { Ltl::not(formula.clone()) } else { formula.clone() };
        let automaton = translate(&opposed, &names, 100_000, u64::MAX).unwrap();
        let solved = [("symbolic", &symbolic), ("bdd", &bdd)];
        for (solver, outcome) in solved.into_iter().filter(|&(solver, _)| solver != "bdd" || bdd_decided) {
            let machine = outcome.controller.as_ref().or(outcome.counter_strategy.as_ref()).expect("a strategy");
            machine.validate().unwrap_or_else(|e| panic!("{name} {solver}: {e}"));
            let moves_first = (expected == Verdict::Realizable) == (spec.semantics == ltl::Semantics::Moore);
            assert_eq!(machine.moves_first, moves_first, "{name} {solver}");
            assert!(
                !some_play_accepted(machine, &automaton),
                "{name} {solver}: the strategy does not win:\n{machine:?}"
            );
            let json = dir.join(format!("{name}-{solver}.json"));
            std::fs::write(&json, ltl::report_json(&spec, outcome).to_string()).unwrap();
            documents.push((format!("{name} ({solver})"), json));
        }
    }
    model_check(&documents);
}

/// The solvers' names, as the page's menu and `--solver` write them, name each solver once.
#[test]
fn every_solver_is_found_by_its_name() {
    for solver in Solver::ALL {
        assert_eq!(Solver::named(solver.name()), Some(solver));
    }
    assert_eq!(Solver::named("bdd"), Some(Solver::Bdd));
    assert_eq!(Solver::named("unbeast"), None);
    assert_eq!(Solver::default(), Solver::Explicit, "the reference solver is the default");
}

/// The environment's automaton (of φ, a conjunction of responses under mutual exclusion) grows
/// with the number of clients where the controller's (of ¬φ) does not: when the first passes
/// the automaton budget, only the environment's game is given up, and the controller's still
/// decides (before, the run ended there: simple_arbiter n = 10 stopped in the translation).
#[test]
fn an_environment_automaton_over_budget_costs_only_the_environments_game() {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../shared/ltl/tlsf/simple_arbiter/simple_arbiter.tlsf");
    let source = std::fs::read_to_string(path).unwrap();
    let (spec, _) = ltl::compile(&source, Format::Tlsf, &[("n".to_string(), 4)]).unwrap();
    let decide = |cfg: &Config| ltl::synthesize(&spec, cfg, &mut |_| true);
    let full = decide(&Config::default()).unwrap();
    assert_eq!(full.verdict, Verdict::Realizable);
    let (against, towards) = (full.stats.automaton_states, full.stats.dual_automaton_states);
    assert!(towards > against, "the premise: {towards} states for φ, {against} for ¬φ");
    for solver in [Solver::Explicit, Solver::Bdd] {
        let narrow = Config { solver, max_automaton_states: against, ..Config::default() };
        let outcome = decide(&narrow).unwrap_or_else(|stop| panic!("{solver:?}: the run ended: {stop}"));
        assert_eq!((outcome.verdict, outcome.k), (full.verdict, full.k), "{solver:?}");
        assert!(outcome.controller.is_some(), "{solver:?}");
        assert_eq!(outcome.stats.dual_automaton_states, 0, "{solver:?}: no automaton for the environment");
    }
    // Both over the budget: the run ends, with the budget named.
    let neither = Config { max_automaton_states: 1, ..Config::default() };
    assert!(matches!(decide(&neither), Err(ltl::Stop::Budget { .. })));
}

/// The bdd solver builds no positions while it solves: its progress reports the diagram's
/// nodes instead (the page shows them as such), and the explicit solver's its positions.
#[test]
fn the_bdd_solver_reports_diagram_nodes_not_positions() {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../shared/ltl/tlsf/simple_arbiter/simple_arbiter.tlsf");
    let source = std::fs::read_to_string(path).unwrap();
    let (spec, _) = ltl::compile(&source, Format::Tlsf, &[("n".to_string(), 4)]).unwrap();
    for (solver, diagram) in [(Solver::Bdd, true), (Solver::Explicit, false)] {
        let mut reports = Vec::new();
        let cfg = Config { solver, ..Config::default() };
        let outcome = ltl::synthesize(&spec, &cfg, &mut |p| {
            reports.push((p.positions, p.nodes));
            true
        })
        .unwrap();
        assert_eq!(outcome.verdict, Verdict::Realizable);
        assert!(!reports.is_empty(), "{solver:?}: no progress reported");
        assert_eq!(reports.iter().any(|r| r.1 > 0), diagram, "{solver:?}: nodes {reports:?}");
        assert_eq!(reports.iter().any(|r| r.0 > 0), !diagram, "{solver:?}: positions {reports:?}");
    }
}

/// The bdd solver's strategy prefers, for each letter, a move into a position it already has:
/// its controllers for simple_arbiter stay within twice the explicit solver's states (without
/// the preference, n = 4 took 73 states where the explicit solver takes 25).
#[test]
fn bdd_controllers_stay_near_the_explicit_ones() {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../shared/ltl/tlsf/simple_arbiter/simple_arbiter.tlsf");
    let source = std::fs::read_to_string(path).unwrap();
    for n in [3, 4] {
        let (spec, _) = ltl::compile(&source, Format::Tlsf, &[("n".to_string(), n)]).unwrap();
        let states = |solver| {
            let cfg = Config { solver, ..Config::default() };
            let outcome = ltl::synthesize(&spec, &cfg, &mut |_| true).unwrap();
            assert_eq!(outcome.verdict, Verdict::Realizable, "n = {n}, {solver:?}");
            outcome.controller.expect("a controller").states.len()
        };
        let (explicit, bdd) = (states(Solver::Explicit), states(Solver::Bdd));
        assert!(bdd <= 2 * explicit, "n = {n}: bdd {bdd} states, explicit {explicit}");
    }
}
