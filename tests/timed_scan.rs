//! Timed games at a PLC's scan time (`src/timed/scan.rs`): the verdicts that follow from the
//! examples' numbers, the bound search, the construction, and the syntax.

use plcsynth::search::Outcome as _;
use plcsynth::timed::model::{MessageKind, MessageRole};
use plcsynth::timed::solve::{Config, Verdict};
use plcsynth::timed::testing::scan_game;
use plcsynth::timed::{compile, scan_bound, synthesize, synthesize_at_scan};
use std::path::PathBuf;

fn source(path: &str) -> String {
    std::fs::read_to_string(PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(path)).unwrap()
}

fn game(path: &str) -> plcsynth::timed::model::Game {
    compile(&source(path)).unwrap_or_else(|d| panic!("{path}: {d:?}")).0
}

fn verdict_at(path: &str, scan_ms: u64) -> Verdict {
    let result = synthesize_at_scan(&game(path), scan_ms, &Config::default(), &mut |_| true).unwrap();
    result.synthesis.solution.verdict().expect("decided within the default budgets")
}

/// The thesis's lamp needs a zero-time controller: after `press` the button may settle at any
/// moment of the next unit, before any PLC has read the press. The counter-play shows it: the
/// PLC reads, the plant presses and settles inside the scan.
#[test]
fn the_thesis_lamp_is_realizable_but_not_implementable_at_10_ms() {
    let g = game("examples/timed/lamp.tga");
    assert_eq!(synthesize(&g, &Config::default(), &mut |_| true).solution.verdict(), Some(Verdict::Realizable));
    let result = synthesize_at_scan(&g, 10, &Config::default(), &mut |_| true).unwrap();
    assert_eq!(result.synthesis.solution.verdict(), Some(Verdict::Unrealizable));
    let text = result.synthesis.explanation.expect("a counter-play").render();
    assert!(text.contains("plc.read") && text.contains("?scan:idle"), "{text}");
    assert!(text.contains("!press_settled") && text.contains("never lamp.off and button.pressed"), "{text}");
    // No scan time helps: the bound search finds none down to 1 ms.
    let bound = scan_bound(&g, 10, false, &Config::default(), &mut |_| true);
    assert_eq!((bound.works, bound.fails, bound.stopped), (None, Some(1), false));
}

/// The lamp whose button settles no sooner than 30 ms: a change is read at most one scan `T`
/// late and the output takes effect within the next scan, so `2T < 30 ms` works (a strict
/// bound, since the settle may come at exactly 30 ms, at the same instant as the output).
/// Every scan time from 1 to 14 ms works and none from 15 to 20 ms, so the bound search's
/// neighbours are the true bound here.
#[test]
fn the_lamp_with_a_settle_time_is_implementable_exactly_below_15_ms() {
    let path = "examples/timed/lamp_scan.tga";
    assert_eq!(game(path).scan_ms.map(|(ms, _)| ms), Some(10));
    for ms in 1..=20 {
        let expected = if ms < 15 { Verdict::Realizable } else { Verdict::Unrealizable };
        assert_eq!(verdict_at(path, ms), expected, "at {ms} ms");
    }
    let bound = scan_bound(&game(path), 10, true, &Config::default(), &mut |_| true);
    assert_eq!((bound.works, bound.fails), (Some(14), Some(15)));
}

/// The hardware unit of 4.1.2: X→Y takes at most 4 s and Y→Z at most 4 s, and the plan allows
/// 10 s. Each of the two requests may take effect up to two scans after the change it answers,
/// so the slack of 2 s allows `4T ≤ 2 s`: 500 ms works and 501 ms does not.
#[test]
fn the_hardware_unit_is_implementable_up_to_half_a_second() {
    let g = game("examples/timed/hardware_xyz.tga");
    let bound = scan_bound(&g, 10, true, &Config::default(), &mut |_| true);
    assert_eq!((bound.works, bound.fails), (Some(500), Some(501)));
    assert_eq!(verdict_at("examples/timed/hardware_xyz.tga", 500), Verdict::Realizable);
    assert_eq!(verdict_at("examples/timed/hardware_xyz.tga", 501), Verdict::Unrealizable);
}

/// Two robots and a 14 s cycle that the first workpiece needs in full (4 + 6 + 4 s): any
/// latency misses the deadline. (The scan game needs more than the default work budget here.)
#[test]
fn two_robots_without_slack_are_not_implementable() {
    let options = Config { max_work: 3_000_000_000, max_states: 5_000_000, ..Config::default() };
    let result = synthesize_at_scan(&game("examples/timed/two_robots_14.tga"), 10, &options, &mut |_| true).unwrap();
    assert_eq!(result.synthesis.solution.verdict(), Some(Verdict::Unrealizable));
}

/// Dominance (a new state lost at once when a lost state of its locations lies in its zone,
/// plan clocks lowered): the same verdicts with fewer states, and the explanation of a loss
/// still ends in violations, through the states that dominate. The largest scan time of two
/// robots 22 s is decided exactly within the default budgets (without dominance the bound
/// search stops at a budget between 1320 and 1420 ms).
#[test]
fn dominance_decides_losses_with_fewer_states_and_explains_them() {
    use plcsynth::timed::explain::{Outcome, Step};
    fn leaves_are_failures(step: &Step, via_dominance: &mut bool) -> bool {
        match &step.outcome {
            Outcome::Violation { .. } | Outcome::Truncated => true,
            Outcome::Forced { next } => {
                *via_dominance |= next.event.as_deref().is_some_and(|e| e.starts_with("lost as s"));
                leaves_are_failures(next, via_dominance)
            }
            Outcome::Choices { branches } => {
                !branches.is_empty() && branches.iter().all(|b| leaves_are_failures(b, via_dominance))
            }
        }
    }
    let mut dominated_on_a_path = false;
    for (path, ms) in [("examples/timed/two_robots_14.tga", 10), ("examples/timed/two_robots_13.tga", 10)] {
        let g = game(path);
        let with = synthesize_at_scan(&g, ms, &Config::default(), &mut |_| true).unwrap().synthesis;
        let without_options = Config { dominance: false, ..Config::default() };
        let without = synthesize_at_scan(&g, ms, &without_options, &mut |_| true).unwrap().synthesis;
        assert_eq!(with.solution.verdict(), Some(Verdict::Unrealizable), "{path}");
        assert_eq!(without.solution.verdict(), Some(Verdict::Unrealizable), "{path}");
        assert!(with.solution.stats.dominated > 0 && without.solution.stats.dominated == 0, "{path}");
        assert!(with.solution.stats.visited < without.solution.stats.visited, "{path}");
        let explanation = with.explanation.expect("an explanation");
        assert!(leaves_are_failures(&explanation.root, &mut dominated_on_a_path), "{path}: {}", explanation.render());
    }
    assert!(dominated_on_a_path, "some explanation passes through a state lost by dominance");
    let bound = scan_bound(&game("examples/timed/two_robots_22.tga"), 10, true, &Config::default(), &mut |_| true);
    assert_eq!((bound.works, bound.fails, bound.stopped), (Some(1333), Some(1334), false));
}

/// Specifications without time constants look the same at every time scale.
#[test]
fn an_untimed_specification_has_one_verdict_for_every_scan_time() {
    let g = game("examples/timed/round_table_1.tga");
    assert_eq!(verdict_at("examples/timed/round_table_1.tga", 10), Verdict::Realizable);
    assert!(scan_bound(&g, 10, true, &Config::default(), &mut |_| true).scale_free);
}

/// Finding V1 (docs/fuzzing.md): a controller that makes plan progress forever at one instant
/// wins the zero-time game (the thesis accepts it, 5.1), but not on a PLC, where `c` leaves
/// `[0,0]` before the request arrives.
#[test]
fn progress_at_one_instant_is_not_implementable() {
    let path = "tests/fixtures/fuzz/handed_over/v1_progress_at_one_instant.tga";
    let g = game(path);
    assert_eq!(synthesize(&g, &Config::default(), &mut |_| true).solution.verdict(), Some(Verdict::Realizable));
    for ms in [1, 10, 1000] {
        assert_eq!(verdict_at(path, ms), Verdict::Unrealizable, "at {ms} ms");
    }
}

/// A scan controller is a zero-time controller that waits: what is unrealizable stays so.
#[test]
fn unrealizable_examples_are_not_implementable() {
    assert_eq!(verdict_at("examples/timed/lamp_naive.tga", 10), Verdict::Unrealizable);
    assert_eq!(verdict_at("examples/timed/two_robots_13.tga", 1000), Verdict::Unrealizable);
}

/// The construction on the lamp: constants scaled to 10 ms steps, the plant's requests taken
/// with the PLC's outputs, a refusal for each request where the lamp cannot take it, and the
/// scan automaton.
#[test]
fn the_scan_game_of_the_lamp() {
    let g = game("examples/timed/lamp.tga");
    let s = scan_game(&g, 10).unwrap();
    let roles = s.scan.as_ref().unwrap();
    assert_eq!((s.timeunit_ms, roles.scale, roles.period), (10, 100, 1));
    let button = &s.components[(s.component_id("button").unwrap()).index()];
    let settle = button.edges.iter().find(|e| s.messages[e.message.index()].name == "press_settled").unwrap();
    assert_eq!(settle.guard[0].interval.to_string(), "(0,100)");
    let lamp = &s.components[(s.component_id("lamp").unwrap()).index()];
    for request in ["turn_on", "turn_off"] {
        let m = s.message_id(request).unwrap();
        assert_eq!(s.messages[m.index()].sender, Some(roles.plc));
        assert!(lamp.edges.iter().filter(|e| e.message == m).all(|e| e.kind == MessageKind::Synchronised));
        // Taken in one location, refused in the other.
        let targets: Vec<&str> =
            lamp.edges.iter().filter(|e| e.message == m).map(|e| lamp.locations[e.to.index()].name.as_str()).collect();
        assert_eq!(targets.len(), 2, "{request}: {targets:?}");
        assert!(targets.contains(&"refused"), "{request}: {targets:?}");
        let commit = s.message_id(&format!("scan:{request}")).unwrap();
        assert_eq!(roles.commits[commit.index()], Some(m));
        assert_eq!(s.messages[commit.index()].role, MessageRole::Request);
    }
    let plc = &s.components[roles.plc.index()];
    let names: Vec<&str> = plc.locations.iter().map(|l| l.name.as_str()).collect();
    assert_eq!(names, ["read", "quiet", "armed", "scheduled", "out_turn_on", "out_turn_off"]);
    // Every reaction is seen by the PLC.
    for reaction in ["press", "press_settled", "release", "release_settled"] {
        let m = s.message_id(reaction).unwrap();
        assert!(s.messages[m.index()].synchronised.contains(&roles.plc), "{reaction}");
    }
    assert!(s.assertions.iter().any(|a| a.text.starts_with("never lamp.refused")));
}

#[test]
fn a_scan_finer_than_the_constants_allow_is_refused() {
    // 2^24 time units of 1 h at a 1 ms scan: far beyond the limit.
    let src = "timeunit 1h; plant { automaton a { clocks c; nodes p {c in [0,16777215]}, q; p -> q !go; } }";
    let g = compile(src).unwrap().0;
    let err = scan_game(&g, 1).map(|_| ()).unwrap_err();
    assert!(err.to_string().contains("beyond the limit"), "{err}");
}

#[test]
fn the_scan_time_is_declared_once_with_a_unit() {
    let base = "plant { automaton a { nodes p, q; p -> q !go; } } plans { plan { waitfor go; } }";
    assert_eq!(compile(&format!("scan 10 ms; {base}")).unwrap().0.scan_ms.map(|(ms, _)| ms), Some(10));
    assert_eq!(compile(&format!("scan 2s; {base}")).unwrap().0.scan_ms.map(|(ms, _)| ms), Some(2000));
    assert_eq!(compile(base).unwrap().0.scan_ms, None);
    let messages = |src: &str| -> Vec<String> {
        compile(src)
            .err()
            .unwrap_or_default()
            .into_iter()
            .map(|d| format!("{}:{} {}", d.line, d.column, d.message))
            .collect()
    };
    assert_eq!(messages(&format!("scan 10 ms;\nscan 20 ms; {base}")), ["2:1 the scan time is declared twice"]);
    assert_eq!(messages(&format!("scan 0 ms; {base}")), ["1:6 the scan time must be longer than zero"]);
    assert_eq!(messages(&format!("scan 10 weeks; {base}")), ["1:9 unknown time unit `weeks`"]);
    assert_eq!(messages(&format!("scan 10; {base}")).len(), 1);
}

/// A pulsed output is TRUE for the scan of its request; pulsed in the next scan again, it stays
/// TRUE and the plant sees one rising edge. Here every `go` must reach the plant within 25 ms of
/// the last: with a scan between two pulses, a request committed at read `k` arrives by
/// `(k+1)T` and the next one, committed at read `k+2`, by `(k+3)T`, so `3T ≤ 25 ms`: 8 ms works,
/// 9 ms does not (pulses in consecutive scans would allow `2T ≤ 25`, 12 ms).
#[test]
fn a_pulsed_request_needs_a_scan_without_it_before_the_next() {
    let src = "timeunit 1ms;\nplant { automaton a { nodes p, q; p -> q ?go; q -> p !back instant; } }\n\
               plans { plan { clocks t 25; reset t; waitfor go; } }\n";
    let g = compile(src).unwrap().0;
    let s = scan_game(&g, 10).unwrap();
    let plc = &s.components[(s.scan.as_ref().unwrap().plc).index()];
    assert!(plc.locations.iter().any(|l| l.name == "read_after_go"), "{:?}", plc.locations);
    let bound = scan_bound(&g, 10, false, &Config::default(), &mut |_| true);
    assert_eq!((bound.works, bound.fails), (Some(8), Some(9)));
}

/// Covers are looked up among the zones that agree with the new one outside the plans' clocks
/// (the only zones a cover may differ from it in), not among every zone of its locations: two
/// machines' bound at 16 ms, where most zones differ in the plant's clocks, is decided within
/// the default budgets (it passed the work budget while the lookup compared every zone). The
/// search without inclusion, which stores every zone, agrees at 16 ms (1.3 M states with
/// `--no-inclusion` and raised budgets: measured, too slow for this test).
#[test]
fn two_machines_is_bounded_exactly_within_the_default_budgets() {
    let g = game("examples/timed/two_machines.tga");
    let bound = scan_bound(&g, 10, true, &Config::default(), &mut |_| true);
    assert_eq!((bound.works, bound.fails, bound.stopped), (Some(16), Some(17), false));
    let at_16 = synthesize_at_scan(&g, 16, &Config::default(), &mut |_| true).unwrap().synthesis;
    assert_eq!(at_16.solution.verdict(), Some(Verdict::Realizable));
    assert!(at_16.solution.stats.visited < 100_000, "{} states", at_16.solution.stats.visited);
}
