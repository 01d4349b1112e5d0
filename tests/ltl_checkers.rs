//! The independent checkers for the LTL engine, checked on hand-made documents before they judge
//! the engine: `tests/checkers/ltl_mc.py` (a model checker built on Debian's `lbt`) must accept
//! every correct controller and counter-strategy in `tests/fixtures/ltl`, reject every mutated one
//! with a lasso, refuse the malformed ones, and agree with brute force on random machines
//! (`ltl_mc_selftest.py`); `tests/checkers/ltl_gr1.py` must give gr1py's verdict on the GR(1)
//! specifications and refuse the others. The tools are installed by `scripts/python-checkers.sh`
//! (`make test` runs it); without them these tests fail and say what to install.

use std::io::Write;
use std::path::PathBuf;
use std::process::{Command, Output, Stdio};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn python() -> PathBuf {
    let path = root().join(".venv/bin/python");
    assert!(path.exists(), "{} is missing: run `bash scripts/python-checkers.sh` (make test does)", path.display());
    path
}

/// Fails, naming the package, unless Debian's `lbt` runs and translates `G p0`.
fn require_lbt() {
    let child = Command::new("lbt").stdin(Stdio::piped()).stdout(Stdio::piped()).stderr(Stdio::piped()).spawn();
    let mut child = child.unwrap_or_else(|e| {
        panic!("lbt is missing ({e}): `apt-get install -y lbt` (bash scripts/python-checkers.sh does it as root)")
    });
    child.stdin.take().unwrap().write_all(b"G p0\n").unwrap();
    let out = child.wait_with_output().unwrap();
    assert!(out.status.success() && !out.stdout.is_empty(), "lbt does not work: {out:?}");
}

fn require_gr1py() {
    let path = root().join(".venv/bin/gr1py");
    assert!(
        path.exists(),
        "{} is missing: `.venv/bin/pip install gr1py` (bash scripts/python-checkers.sh)",
        path.display()
    );
}

fn checker(script: &str, args: &[&str]) -> Output {
    Command::new(python())
        .arg(root().join("tests/checkers").join(script))
        .args(args)
        .output()
        .unwrap_or_else(|e| panic!("cannot run {script}: {e}"))
}

fn fixture(name: &str) -> String {
    root().join("tests/fixtures/ltl").join(name).to_str().unwrap().to_string()
}

fn text(out: &Output) -> String {
    format!("{}{}", String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr))
}

/// Every fixture with the exit code ltl_mc.py must give it: 0 right, 1 wrong (a lasso), 2 malformed.
/// Each was reasoned out by hand; the name says what it is.
const MC: &[(&str, i32)] = &[
    // G (req -> (grant || X grant)) && G (grant -> X !grant), Mealy
    ("reqgrant_ok.json", 0),
    ("reqgrant_bad_brief_example.json", 1), // a request right after a grant is never granted
    ("reqgrant_bad_flipped_output.json", 1),
    ("reqgrant_bad_next_state.json", 1),
    ("reqgrant_moore_ok.json", 0), // alternating grants, whatever the requests
    // !grant && G (req -> X grant) && G (!req -> X !grant): grant is the last step's request
    ("delay_moore_ok.json", 0),
    ("delay_moore_bad_init.json", 1),
    ("delay_mealy_bad_instant.json", 1),
    // G (grant <-> X req) is unrealizable under Mealy semantics: the environment negates grant
    ("echo_unrealizable_counter_ok.json", 0),
    ("echo_unrealizable_counter_bad.json", 1),
    // G (req <-> grant): unrealizable under Moore, realizable under Mealy
    ("copy_moore_counter_ok.json", 0),
    ("copy_moore_counter_bad.json", 1),
    ("copy_mealy_ok.json", 0),
    // assumptions: G F r -> G F g, and G F r -> (G F g && G (g -> r))
    ("assume_gfr_gfg_ok.json", 0),
    ("assume_gfr_gfg_moore_ok.json", 0),
    ("assume_gfr_gfg_bad_never.json", 1),
    ("assume_gfr_gfg_bad_phase.json", 1),
    ("assume_two_guarantees_ok.json", 0), // violates G F g only where G F r fails
    ("assume_two_guarantees_bad_always.json", 1),
    // the GR(1) fixtures carry machines too
    ("gr1_alternating_ok.json", 0),
    ("gr1_alternating_bad_instant.json", 1),
    ("gr1_liveness_counter_ok.json", 0),
    ("gr1_liveness_counter_bad.json", 1),
    ("gr1_not_response.json", 0),
    ("gr1_not_strict.json", 0),
    // six request/grant pairs, dotted names: lbt crashes (SIGSEGV) on the whole formula, so these
    // go through the split
    ("wide_always_grant_ok.json", 0),
    ("wide_bad_one_never_granted.json", 1),
    ("wide_counter_ok.json", 0),
    ("wide_counter_bad_breaks_assumption.json", 1), // granting forever starves G F t0.req
    ("malformed_overlapping_rows.json", 2),
    ("malformed_moore_counter_as_mealy.json", 2),
];

/// What ltl_gr1.py must print for every Mealy fixture with a meaningful verdict.
const GR1: &[(&str, &str)] = &[
    ("reqgrant_ok.json", "realizable"),
    ("echo_unrealizable_counter_ok.json", "unrealizable"),
    ("copy_mealy_ok.json", "realizable"),
    ("assume_gfr_gfg_ok.json", "realizable"),
    ("assume_two_guarantees_ok.json", "realizable"),
    ("gr1_alternating_ok.json", "realizable"),
    ("gr1_liveness_counter_ok.json", "unrealizable"),
    ("gr1_not_response.json", "not-gr1"),      // G (req -> F grant)
    ("gr1_not_strict.json", "not-gr1"),        // gr1py's strict game says unrealizable, the implication is realizable
    ("copy_moore_counter_ok.json", "not-gr1"), // Moore
];

#[test]
fn every_fixture_is_listed_once() {
    let mut on_disk: Vec<String> = std::fs::read_dir(root().join("tests/fixtures/ltl"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".json"))
        .collect();
    on_disk.sort();
    let mut listed: Vec<String> = MC.iter().map(|(n, _)| n.to_string()).collect();
    listed.sort();
    assert_eq!(on_disk, listed);
}

#[test]
fn ltl_mc_accepts_the_right_machines_and_gives_a_lasso_against_the_wrong_ones() {
    require_lbt();
    let mut failures = Vec::new();
    for &(name, expected) in MC {
        for mode in [&[][..], &["--split"][..]] {
            let path = fixture(name);
            let out = checker("ltl_mc.py", &[mode, &[path.as_str()]].concat());
            let code = out.status.code();
            let output = text(&out);
            let lasso = output.contains("prefix:") && output.contains("cycle (repeated forever):");
            let right = code == Some(expected)
                && match expected {
                    0 => String::from_utf8_lossy(&out.stdout).trim() == "ok",
                    1 => lasso,
                    _ => output.contains("malformed"),
                };
            if !right {
                failures.push(format!("{name} {mode:?}: exit {code:?}, expected {expected}\n{output}"));
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn ltl_mc_agrees_with_brute_force_on_random_machines() {
    require_lbt();
    // 60 random machines in `make test` (about 12 CPU-s), 600 in `make test-long`.
    let random_specs: u64 = std::env::var("PLCSYNTH_RANDOM_SPECS").ok().and_then(|v| v.parse().ok()).unwrap_or(400);
    let machines = (random_specs / 400).max(1) * 60;
    let out = checker("ltl_mc_selftest.py", &[&machines.to_string(), "1"]);
    assert!(out.status.success(), "{}", text(&out));
}

#[test]
fn ltl_gr1_gives_gr1pys_verdict_on_gr1_specs_and_refuses_the_others() {
    require_gr1py();
    let mut failures = Vec::new();
    for &(name, expected) in GR1 {
        let out = checker("ltl_gr1.py", &[fixture(name).as_str()]);
        let printed = String::from_utf8_lossy(&out.stdout).trim().to_string();
        let code = if expected == "not-gr1" { 4 } else { 0 };
        if printed != expected || out.status.code() != Some(code) {
            failures.push(format!(
                "{name}: exit {:?}, expected {expected} (exit {code})\n{}",
                out.status.code(),
                text(&out)
            ));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn the_gr1_table_agrees_with_the_verdicts_the_fixtures_carry() {
    for &(name, expected) in GR1 {
        let doc = std::fs::read_to_string(fixture(name)).unwrap();
        let claims_unrealizable = doc.contains("\"verdict\": \"unrealizable\"");
        match expected {
            "realizable" => assert!(!claims_unrealizable, "{name}"),
            "unrealizable" => assert!(claims_unrealizable, "{name}"),
            _ => {}
        }
    }
}
