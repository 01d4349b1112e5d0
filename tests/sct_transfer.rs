//! The transfer-line family (Göbe 2019, 7.5): generated projects load, incremental and
//! monolithic synthesis agree on every supervisor's behaviour, and the example file matches
//! the generator.

use plcsynth::benchmarks::transfer::transfer_lines;
use plcsynth::sct::compile;
use plcsynth::sct::model::{synthesize, Config, Method};

#[test]
fn example_file_is_the_generated_2x2_line() {
    let text =
        std::fs::read_to_string(format!("{}/examples/sct/transfer_line_2x2.sct", env!("CARGO_MANIFEST_DIR"))).unwrap();
    let body: String =
        text.lines().skip_while(|l| l.starts_with("//") && !l.contains("(generated)")).collect::<Vec<_>>().join("\n");
    assert_eq!(body.trim(), transfer_lines(2, 2, 2).trim());
}

#[test]
fn sizes_and_counts_follow_the_thesis_structure() {
    for (k, m) in [(2, 2), (3, 2), (2, 4)] {
        let (l, d) = compile(&transfer_lines(k, m, 2)).unwrap_or_else(|e| panic!("{e:?}"));
        assert!(d.iter().all(|d| !d.is_error()), "{d:?}");
        let p = l.project;
        assert_eq!(p.plants.len(), k * (m + 1));
        assert_eq!(p.specs.len(), k * m + k - 1);
    }
}

fn possible(p: &plcsynth::sct::model::Project, w: &[plcsynth::sct::model::EventId]) -> bool {
    p.plants.iter().all(|g| {
        let mut s = g.init;
        for e in w {
            if g.alphabet.contains(e) {
                match g.trans.iter().find(|t| t.src == s && t.event == *e) {
                    Some(t) => s = t.dst,
                    None => return false,
                }
            }
        }
        true
    })
}

#[test]
fn incremental_equals_monolithic_on_small_lines() {
    let (l, _) = compile(&transfer_lines(2, 2, 2)).unwrap_or_else(|d| panic!("{d:?}"));
    let p = l.project;
    for i in 0..p.specs.len() {
        let inc = synthesize(&p, i, &Config { method: Method::Incremental, ..Config::default() }).unwrap();
        let mono = synthesize(&p, i, &Config { method: Method::Monolithic, ..Config::default() }).unwrap();
        assert!(inc.realizable() && mono.realizable());
        // Same behaviour: both minimal supervisors disable the same words of length <= 6.
        let events: Vec<_> = (0..p.events.len()).map(plcsynth::sct::model::EventId::new).collect();
        let mut frontier = vec![Vec::new()];
        for _ in 0..6 {
            let mut next = Vec::new();
            for w in &frontier {
                for &e in &events {
                    let mut w2: Vec<_> = w.clone();
                    w2.push(e);
                    // Compare on physically possible words only: where plants rule a word out,
                    // supervisors may differ without consequence.
                    if !possible(&p, &w2) {
                        continue;
                    }
                    let (a, b) = (inc.run(&w2).is_some(), mono.run(&w2).is_some());
                    assert_eq!(
                        a,
                        b,
                        "spec {} word {:?}",
                        p.specs[i].name,
                        w2.iter().map(|e| p.event_name(*e)).collect::<Vec<_>>()
                    );
                    if a && next.len() < 3000 {
                        next.push(w2);
                    }
                }
            }
            frontier = next;
        }
        // Incremental synthesis never needs more plants than monolithic.
        assert!(inc.plants_used.len() <= mono.plants_used.len());
    }
}

#[test]
fn incremental_synthesis_only_applies_the_plants_it_needs() {
    let (l, _) = compile(&transfer_lines(2, 2, 2)).unwrap_or_else(|d| panic!("{d:?}"));
    let p = l.project;
    let cfg = Config { method: Method::Incremental, ..Config::default() };
    let used = |name: &str| {
        let i = p.specs.iter().position(|s| s.name == name).unwrap();
        synthesize(&p, i, &cfg).unwrap().plants_used
    };
    // B1_1 overflows on M1's finish and TU's reject: only those two plants matter.
    assert_eq!(used("B1_1"), vec!["TL1.M1.P".to_string(), "TL1.TU.P".to_string()]);
    // B1_2 overflows on M2's finish only.
    assert_eq!(used("B1_2"), vec!["TL1.M2.P".to_string()]);
    // TB1 overflows on TL1's accept.
    assert_eq!(used("TB1"), vec!["TL1.TU.P".to_string()]);
}

#[test]
fn extended_line_ignores_the_shared_sensor() {
    let (l, d) = compile(&plcsynth::benchmarks::transfer::extended_line(3)).unwrap_or_else(|e| panic!("{e:?}"));
    assert!(d.iter().all(|d| !d.is_error()), "{d:?}");
    let p = l.project;
    assert_eq!((p.plants.len(), p.specs.len()), (12, 4));
    let cfg = Config::default();
    let mut dep_all = false;
    for i in 0..p.specs.len() {
        let s = synthesize(&p, i, &cfg).unwrap();
        assert!(s.realizable());
        assert!(!s.plants_used.iter().any(|n| n == "Sensor"), "{:?}", s.plants_used);
        let dep = plcsynth::sct::model::dep_closure(&p, i);
        assert!(s.plants_used.len() <= dep.len());
        dep_all |= dep.len() == p.plants.len() - 2; // all but the abstract M1 and the TU
    }
    assert!(dep_all, "the shared sensor should pull every extended plant into some Dep closure");
}

/// Monolithic synthesis on many plants grows exponentially: it stops at the state budget
/// instead of exhausting memory, and the progress callback can cancel it.
#[test]
fn state_budget_and_cancellation_stop_monolithic_synthesis() {
    use plcsynth::sct::model::{synthesize_within, Budget, SynthError};
    let (l, _) = compile(&transfer_lines(4, 3, 2)).unwrap_or_else(|d| panic!("{d:?}"));
    let p = l.project;
    let mono = Config { method: Method::Monolithic, max_states: 20_000, ..Config::default() };
    match synthesize(&p, 0, &mono) {
        Err(SynthError::BudgetExceeded { max_states }) => assert_eq!(max_states, 20_000),
        other => panic!("expected the budget to stop synthesis, got {other:?}"),
    }
    // The same specification is cheap incrementally.
    let inc = Config { method: Method::Incremental, max_states: 20_000, ..Config::default() };
    assert!(synthesize(&p, 0, &inc).unwrap().realizable());

    let mut calls = 0;
    let mut cancel_at_second = |p: &plcsynth::sct::Progress| {
        calls += 1;
        assert!(p.states > 0);
        calls < 2
    };
    let mut budget = Budget::new(usize::MAX, &mut cancel_at_second);
    assert!(matches!(
        synthesize_within(&p, 0, &Config { method: Method::Monolithic, ..Config::default() }, &mut budget),
        Err(SynthError::Cancelled)
    ));
    assert!(budget.built() > 4096, "cancelled after {} states", budget.built());
}

/// The budget counts every product state, the initial ones included: a product of exactly
/// the budget's size fits, one state less does not.
#[test]
fn state_budget_admits_exactly_its_size() {
    use plcsynth::sct::model::SynthError;
    let src = "event go : controllable;\nevent done : uncontrollable;\nevent more : controllable;\n\
               plant P { alphabet go, done, more; state A initial { go -> B; } state B { done -> C; } state C { more -> A; } }\n\
               spec H { state S { forbid more; } }";
    let (l, d) = compile(src).unwrap_or_else(|e| panic!("{e:?}"));
    assert!(d.is_empty(), "{d:?}");
    let p = l.project;
    // Monolithic synthesis applies the plant: one spec state times three plant states.
    let cfg = |max_states| Config { method: Method::Monolithic, max_states, ..Config::default() };
    assert!(synthesize(&p, 0, &cfg(3)).is_ok());
    assert!(matches!(synthesize(&p, 0, &cfg(2)), Err(SynthError::BudgetExceeded { max_states: 2 })));
}

/// Cancelling a whole report keeps the supervisors finished so far and says where it stopped.
#[test]
fn cancelling_a_report_stops_with_a_located_error() {
    let src = transfer_lines(4, 3, 2);
    let (l, _) = compile(&src).unwrap_or_else(|d| panic!("{d:?}"));
    let cfg = Config { method: Method::Monolithic, ..Config::default() };
    let synthesis = plcsynth::sct::synthesize(&src, &l, &cfg, None, &mut |p| p.states < 10_000);
    assert_eq!(synthesis.outcome, Err(plcsynth::search::Stop::Cancelled));
    let (reports, diags) = (synthesis.reports, synthesis.diagnostics);
    assert!(reports.len() < l.project.specs.len());
    let errors: Vec<_> = diags.iter().filter(|d| d.is_error()).collect();
    assert_eq!(errors.len(), 1, "{diags:?}");
    assert!(errors[0].message.starts_with("synthesis cancelled while synthesising `"), "{}", errors[0].message);
}
