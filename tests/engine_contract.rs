//! The one engine contract (ARCHITECTURE.md): every engine compiles a text into a checked
//! model, synthesises it with a `Config` and a progress callback, and ends with a result that
//! implements `search::Outcome`: a verdict that is a decision, or a `Stop`. One generic check
//! runs over all three, so an engine that drifts from the shape stops compiling here, and one
//! that names or stops differently fails.

use plcsynth::search::{Decision, Outcome, Resource, Stop};
use plcsynth::{ltl, sct, timed};
use std::path::PathBuf;

fn example(path: &str) -> String {
    let file = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("examples").join(path);
    std::fs::read_to_string(&file).unwrap_or_else(|e| panic!("{}: {e}", file.display()))
}

/// What every run is checked for, whatever the engine: the names the CLI and the page print
/// agree with the outcome, and the verdict's JSON is its name.
fn check_outcome<O: Outcome>(run: &O, expected: Result<&str, &Stop>) {
    match (run.outcome(), expected) {
        (Ok(verdict), Ok(name)) => {
            assert_eq!(verdict.name(), name);
            assert_eq!(run.outcome_name(), name);
            assert_eq!(serde_json::to_value(verdict).unwrap(), serde_json::json!(name));
            assert_eq!(run.verdict(), Some(verdict));
            assert!(run.stop().is_none());
        }
        (Err(stop), Err(want)) => {
            assert_eq!(stop, want);
            assert_eq!(run.outcome_name(), want.outcome_name());
            assert!(run.verdict().is_none());
        }
        (got, want) => panic!("the run ended with {got:?}, expected {want:?}"),
    }
}

/// A callback that lets `calls` reports through and cancels at the next.
fn cancel_after<P>(calls: usize) -> impl FnMut(&P) -> bool {
    let mut seen = 0;
    move |_| {
        seen += 1;
        seen <= calls
    }
}

#[test]
fn the_three_engines_decide_and_stop_alike() {
    // timed: the lamp is realizable; cancelled at the first report; a state budget of 1.
    let (game, _) = timed::compile(&example("timed/lamp.tga")).expect("a valid game");
    let config = timed::Config::default().progress_interval(1);
    check_outcome(&timed::synthesize(&game, &config, &mut |_| true), Ok("realizable"));
    check_outcome(&timed::synthesize(&game, &config, &mut cancel_after(0)), Err(&Stop::Cancelled));
    let tiny = timed::synthesize(&game, &config.clone().max_states(1), &mut |_| true);
    assert!(matches!(tiny.stop(), Some(Stop::Budget { resource: Resource::States, .. })), "{:?}", tiny.stop());
    assert_eq!(tiny.outcome_name(), "budget_exceeded");

    // sct: the tank with preemption is realizable; cancelled at the first report of a big line.
    let source = example("sct/tank_preemption.sct");
    let (loaded, _) = sct::compile(&source).expect("a valid project");
    check_outcome(&sct::synthesize(&source, &loaded, &sct::Config::default(), None, &mut |_| true), Ok("realizable"));
    let line = plcsynth::benchmarks::transfer::transfer_lines(4, 3, 2);
    let (big, _) = sct::compile(&line).expect("a valid line");
    let monolithic = sct::Config::default().method(sct::model::Method::Monolithic);
    let cancelled = sct::synthesize(&line, &big, &monolithic, None, &mut cancel_after(0));
    check_outcome(&cancelled, Err(&Stop::Cancelled));
    let tiny = sct::synthesize(&source, &loaded, &sct::Config::default().max_states(1), None, &mut |_| true);
    assert!(matches!(tiny.stop(), Some(Stop::Budget { resource: Resource::States, .. })), "{:?}", tiny.stop());

    // ltl: the muting example is realizable (some 1.7 M units of work, so the callback is
    // asked); cancelled at the first report; a work budget of 1.
    let (spec, _) = ltl::compile(&example("ltl/ex4_muting.ltl"), ltl::Format::G4ltl, &[]).expect("a valid spec");
    check_outcome(&ltl::synthesize(&spec, &ltl::Config::default(), &mut |_| true), Ok("realizable"));
    let cancelled = ltl::synthesize(&spec, &ltl::Config::default(), &mut cancel_after(0));
    check_outcome(&cancelled, Err(&Stop::Cancelled));
    let tiny = ltl::synthesize(&spec, &ltl::Config::default().max_work(1), &mut |_| true);
    assert!(matches!(tiny.stop(), Some(Stop::Budget { resource: Resource::Work, .. })), "{:?}", tiny.stop());
    assert_eq!(tiny.outcome_name(), "budget_exceeded");
}

#[test]
fn each_engine_refuses_bad_text_with_located_diagnostics_only() {
    let refused = [
        timed::compile("plant { automaton a { nodes x; x -> y ?m; } }").err(),
        sct::compile("spec S { state s { forbid nothing; } }").err(),
        ltl::compile("ALWAYS (a ->\nINPUT a\n", ltl::Format::G4ltl, &[]).err(),
    ];
    for (engine, diagnostics) in ["timed", "sct", "ltl"].iter().zip(refused) {
        let diagnostics = diagnostics.unwrap_or_else(|| panic!("{engine}: bad text was accepted"));
        assert!(diagnostics.iter().any(|d| d.is_error()), "{engine}: {diagnostics:?}");
        assert!(diagnostics.iter().all(|d| d.line >= 1 && d.column >= 1), "{engine}: {diagnostics:?}");
    }
}
