//! Assumption suggestions (paper, section 4) on the paper-like cases: every suggestion's
//! controller is model-checked against the *extended* specification by
//! `tests/checkers/ltl_mc.py` (Debian's lbt, no code shared with the engine), and every added
//! assumption matters (without any one of them the specification is unrealizable again).

use crate::common;

use plcsynth::ltl::{self, Config, Format, Ltl, Spec, SuggestConfig, Suggestions, Synthesis, Template, Verdict};
use std::path::{Path, PathBuf};
use std::process::Command;

fn shared(name: &str) -> PathBuf {
    common::root().join("../shared/ltl/g4ltl").join(name)
}

fn example(name: &str) -> PathBuf {
    common::root().join("examples/ltl").join(name)
}

fn compile(source: &str) -> Spec {
    ltl::compile(source, Format::G4ltl, &[]).unwrap_or_else(|d| panic!("{d:?}")).0
}

fn decide(spec: &Spec) -> Synthesis {
    ltl::synthesize(spec, &Config::default(), &mut |_| true).expect("within budget")
}

fn load(path: &Path) -> Spec {
    compile(&std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display())))
}

fn suggest_with(spec: &Spec, scfg: &SuggestConfig) -> Suggestions {
    let outcome = decide(spec);
    assert_eq!(outcome.verdict, Verdict::Unrealizable);
    ltl::suggest(spec, &outcome, &Config::default(), scfg, &mut |_| true).expect("not cancelled")
}

fn texts(s: &Suggestions) -> Vec<String> {
    s.found.iter().map(|f| f.texts().join(" ; ")).collect()
}

/// Every suggestion: its controller model-checked against the extended specification, and
/// each added assumption needed.
fn confirm(label: &str, spec: &Spec, s: &Suggestions) {
    let python = common::root().join(".venv/bin/python");
    assert!(python.exists(), "run `bash scripts/python-checkers.sh` first");
    for (i, found) in s.found.iter().enumerate() {
        found.controller().validate().unwrap();
        assert_eq!(found.spec.assumptions.len(), spec.assumptions.len() + found.added.len());
        let json = common::scratch(
            "ltl-suggest",
            &format!("{label}-{i}.json"),
            &ltl::report_json(&found.spec, &found.outcome).to_string(),
        );
        let out =
            Command::new(&python).arg(common::root().join("tests/checkers/ltl_mc.py")).arg(&json).output().unwrap();
        assert!(
            out.status.success(),
            "{label}: suggestion {:?} not confirmed:\n{}{}",
            found.texts(),
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr)
        );
        for drop in 0..found.added.len() {
            let mut fewer = spec.clone();
            for (j, f) in found.added.iter().enumerate() {
                if j != drop {
                    fewer.assumptions.push(ltl::Clause { formula: f.clone(), span: Default::default() });
                }
            }
            assert_eq!(
                decide(&fewer).verdict,
                Verdict::Unrealizable,
                "{label}: {:?} does not need #{drop}",
                found.texts()
            );
        }
    }
}

#[test]
fn the_numerical_arbiter_gets_the_assumption_of_its_refined_twin() {
    let spec = load(&shared("ptii_NumericalOriginal.g4ltl"));
    let s = suggest_with(&spec, &SuggestConfig::default());
    assert!(!s.found.is_empty(), "{:?}", s.limit);
    assert_eq!(texts(&s)[0], "G !(req1 && req2)", "{:?}", texts(&s));
    assert_eq!(s.found[0].templates, [Template::Exclusion]);
    // The refined twin's ASSUME is the same formula, and its verdict the same.
    let refined = load(&shared("ptii_NumericalRefined.g4ltl"));
    assert_eq!(refined.assumptions[0].formula, s.found[0].added[0]);
    assert_eq!(decide(&refined).verdict, Verdict::Realizable);
    confirm("numerical", &spec, &s);
}

#[test]
fn example1_and_the_same_scan_arbiter_get_mutual_exclusion() {
    for path in [shared("example1.g4ltl"), example("arbiter_same_scan.ltl")] {
        let spec = load(&path);
        let s = suggest_with(&spec, &SuggestConfig::default());
        assert_eq!(
            texts(&s).first().map(String::as_str),
            Some("G !(req1 && req2)"),
            "{}: {:?}",
            path.display(),
            texts(&s)
        );
        // example1_ass.g4ltl states it as `ALWAYS (req1 -> !req2)`: the same words.
        confirm(path.file_stem().unwrap().to_str().unwrap(), &spec, &s);
    }
}

#[test]
fn examples_2_and_3_get_suggestions_a_model_checker_confirms() {
    for name in ["example2.g4ltl", "example3.g4ltl"] {
        let spec = load(&shared(name));
        let s = suggest_with(&spec, &SuggestConfig::default());
        assert!(!s.found.is_empty(), "{name}: {:?}", s.limit);
        confirm(name, &spec, &s);
    }
}

#[test]
fn an_unfair_environment_gets_a_fairness_assumption_first() {
    let spec = load(&example("fair_grant_unfair_env.ltl"));
    let s = suggest_with(&spec, &SuggestConfig::default());
    assert_eq!(texts(&s).first().map(String::as_str), Some("G F req"), "{:?}", texts(&s));
    assert_eq!(s.found[0].templates, [Template::Fairness]);
    confirm("fair", &spec, &s);
}

#[test]
fn a_candidate_the_counter_strategy_already_satisfies_is_not_proposed() {
    // The counter-strategy of the same-scan arbiter raises both requests at every step: it
    // satisfies `G F req1`, `F G req1`, `G req1` and `G (req1 -> X req2)`, which therefore
    // cannot defeat it and are never tried.
    let spec = load(&example("arbiter_same_scan.ltl"));
    let outcome = decide(&spec);
    let play = ltl::testing::longest_play(outcome.counter_strategy.as_ref().unwrap(), 1000);
    let req1 = Ltl::Var(spec.signal_id("req1").unwrap());
    let req2 = Ltl::Var(spec.signal_id("req2").unwrap());
    let satisfied = [
        Ltl::globally(Ltl::finally(req1.clone())),
        Ltl::finally(Ltl::globally(req1.clone())),
        Ltl::globally(req1.clone()),
        Ltl::globally(Ltl::implies(req1.clone(), Ltl::next(req2.clone()))),
    ];
    for f in &satisfied {
        assert!(play.satisfies(f), "{}", play.describe(&spec));
    }
    let scfg = SuggestConfig { max_candidates_tried: 1000, ..SuggestConfig::default() };
    let s = ltl::suggest(&spec, &outcome, &Config::default(), &scfg, &mut |_| true).unwrap();
    for found in &s.found {
        for f in &satisfied {
            assert!(!found.added.contains(f), "{:?}", found.texts());
        }
    }
    // Only candidates some play violates were re-synthesised.
    assert!(s.tried <= s.candidates && s.candidates > 0);
    assert!(!play.satisfies(&Ltl::globally(Ltl::not(Ltl::And(vec![req1, req2])))));
}

/// Two independent faults: an environment that never requests (needs `G F req`) and two
/// clients that request in the same scan (needs `G !(r1 && r2)`).
const TWO_FAULTS: &str = "ALWAYS (grant -> req)\nALWAYS (grant -> NEXT !grant)\nALWAYS EVENTUALLY grant\n\
                          ALWAYS (r1 -> g1)\nALWAYS (r2 -> g2)\nALWAYS !(g1 && g2)\n\
                          INPUT req, r1, r2\nOUTPUT grant, g1, g2\n";

#[test]
fn two_faults_need_two_assumptions_and_the_limit_is_reported() {
    let spec = compile(TWO_FAULTS);
    let one = suggest_with(&spec, &SuggestConfig { max_assumptions: 1, ..SuggestConfig::default() });
    assert!(one.found.is_empty(), "{:?}", texts(&one));
    assert_eq!(
        one.limit.as_deref().map(|l| l.starts_with("no set of at most 1 assumption found")),
        Some(true),
        "{:?}",
        one.limit
    );
    let two = suggest_with(&spec, &SuggestConfig { max_assumptions: 2, ..SuggestConfig::default() });
    assert!(!two.found.is_empty(), "{:?}", two.limit);
    assert!(two.found.iter().all(|f| f.added.len() == 2), "{:?}", texts(&two));
    confirm("two-faults", &spec, &two);
}

#[test]
fn no_assumption_over_the_inputs_helps_an_impossible_guarantee() {
    let spec =
        compile("ALWAYS (req -> grant)\nEVENTUALLY (grant && NEXT !grant && NEXT grant)\nINPUT req\nOUTPUT grant\n");
    let s = suggest_with(&spec, &SuggestConfig { max_assumptions: 2, ..SuggestConfig::default() });
    assert!(s.found.is_empty(), "{:?}", texts(&s));
    assert!(s.limit.is_some());
}

#[test]
fn a_realizable_specification_gets_no_search() {
    let spec = load(&shared("ptii_NumericalRefined.g4ltl"));
    let outcome = decide(&spec);
    let s = ltl::suggest(&spec, &outcome, &Config::default(), &SuggestConfig::default(), &mut |_| true).unwrap();
    assert!(s.found.is_empty() && s.tried == 0 && s.limit.is_none());
}

#[test]
fn cancelling_stops_the_search() {
    let spec = compile(TWO_FAULTS);
    let outcome = decide(&spec);
    let r = ltl::suggest(&spec, &outcome, &Config::default(), &SuggestConfig::default(), &mut |_| false);
    // Small attempts may never reach a progress report; a cancelled one must say so.
    if let Err(stop) = r {
        assert_eq!(stop, ltl::Stop::Cancelled);
    }
}
