//! The LTL engine against other tools' verdicts and an independent model checker:
//! - every G4LTL specification of `../shared/ltl/g4ltl` gets G4LTL's verdict (its README's
//!   k = 3 column; the automatic door, which G4LTL cannot parse, the verdict its header claims);
//! - every TLSF benchmark of `../shared/ltl/tlsf` gets SYNTCOMP's status (the README's table, the
//!   `STATUS` comments, the `.csv` rows of small parameters);
//! - every example of `examples/ltl` gets its `// Expected:` verdict;
//! - every controller and counter-strategy found is checked by `tests/checkers/ltl_mc.py`,
//!   which translates the specification with Debian's `lbt` (no code shared with the engine)
//!   and searches the product for a violating play; a mutated controller must be caught;
//! - where `tests/checkers/ltl_gr1.py` finds the specification GR(1)-shaped, gr1py agrees;
//! - every synthesised controller becomes code for every structured target, and blark parses
//!   (xmllint validates) the code of three of them, one with a timer.

use crate::common;

use plcsynth::ltl::{self, Config, Format, Spec, Synthesis, Verdict};
use plcsynth::plc::{self, Target};
use std::path::{Path, PathBuf};
use std::process::Command;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn shared() -> PathBuf {
    root().join("../shared/ltl")
}

fn decide(path: &Path, params: &[(String, i64)]) -> (Spec, Synthesis) {
    let source = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let format = Format::of_path(path.to_str().unwrap());
    let (spec, _) = ltl::compile(&source, format, params).unwrap_or_else(|d| panic!("{}: {d:?}", path.display()));
    let outcome = ltl::synthesize(&spec, &Config::default(), &mut |_| true)
        .unwrap_or_else(|stop| panic!("{}: {stop}", path.display()));
    (spec, outcome)
}

fn verdict(name: &str) -> Verdict {
    match name {
        "realizable" => Verdict::Realizable,
        "unrealizable" => Verdict::Unrealizable,
        _ => panic!("unknown verdict `{name}`"),
    }
}

/// G4LTL's verdicts at k = 3 (`../shared/ltl/README.md`).
const G4LTL: &[(&str, &str)] = &[
    ("ptii_Arbitor", "realizable"),
    ("ptii_PriorityArbitor", "realizable"),
    ("ptii_ErrorHandling", "realizable"),
    ("ptii_HydraulicRamp", "realizable"),
    ("ptii_NumericalOriginal", "unrealizable"),
    ("ptii_NumericalRefined", "realizable"),
    ("ptii_AutomaticDoor", "realizable"), // G4LTL: unknown (cannot parse `<->`); its header says realizable
    ("sample", "realizable"),
    ("example1", "unrealizable"),
    ("example1_ass", "realizable"),
    ("example2", "unrealizable"),
    ("example3", "unrealizable"),
    ("example4", "realizable"),
    ("paper_appC_grant", "realizable"),
    ("paper_fig1_abstract", "unrealizable"),
    // G4LTL: realizable, under its timer antecedent `G (t1.start -> X F t1.expire)`, which
    // also promises an expiry to a controller that restarts the timer in every scan. With a
    // real timer (docs/ltl-language.md, "Timers") an `err` held forever restarts it forever,
    // and `light UNTIL t1.expire` cannot be met: `tests/ltl_timers.rs` shows it.
    ("paper_fig1_refined", "unrealizable"),
];

/// A specification file, its parameter overrides and its expected verdict.
type Case = (PathBuf, Vec<(String, i64)>, Verdict);

/// Every listed specification with its expected verdict and parameter overrides.
fn listed() -> Vec<Case> {
    let mut cases = Vec::new();
    let files: Vec<_> = std::fs::read_dir(shared().join("g4ltl")).unwrap().map(|e| e.unwrap().path()).collect();
    assert_eq!(files.len(), G4LTL.len(), "a G4LTL file without an expected verdict");
    for (name, expected) in G4LTL {
        cases.push((shared().join(format!("g4ltl/{name}.g4ltl")), Vec::new(), verdict(expected)));
    }
    let tlsf = shared().join("tlsf");
    let n = |v: i64| vec![("n".to_string(), v)];
    for (file, params, expected) in [
        ("simple_arbiter/simple_arbiter.tlsf", n(2), "realizable"),
        ("simple_arbiter/simple_arbiter.tlsf", n(3), "realizable"),
        ("simple_arbiter_unreal/simple_arbiter_unreal1.tlsf", vec![("n".into(), 2), ("u".into(), 1)], "unrealizable"),
        ("simple_arbiter_unreal/simple_arbiter_unreal2.tlsf", n(2), "unrealizable"),
        ("full_arbiter/full_arbiter.tlsf", n(2), "realizable"),
        ("full_arbiter/full_arbiter.tlsf", n(3), "realizable"),
        ("load_balancer/load_balancer.tlsf", n(3), "realizable"),
        ("prioritized_arbiter/prioritized_arbiter.tlsf", n(2), "realizable"),
        ("prioritized_arbiter_unreal/prioritized_arbiter_unreal2.tlsf", n(2), "unrealizable"),
        ("round_robin_arbiter/round_robin_arbiter.tlsf", n(2), "realizable"),
        ("load_balancer/load_balancer.tlsf", n(2), "realizable"),
        ("ltl2dba/ltl2dba_R.tlsf", n(2), "unrealizable"),
        ("ltl2dba/ltl2dba_C2_unreal.tlsf", n(2), "unrealizable"),
    ] {
        cases.push((tlsf.join(file), params, verdict(expected)));
    }
    // Non-parametric ltl2dba files state their status in a comment.
    let mut dba: Vec<_> = std::fs::read_dir(tlsf.join("ltl2dba")).unwrap().map(|e| e.unwrap().path()).collect();
    dba.sort();
    for path in dba {
        let text = std::fs::read_to_string(&path).unwrap();
        if let Some(status) = text.lines().find_map(|l| l.strip_prefix("//STATUS : ")) {
            cases.push((path, Vec::new(), verdict(status.trim())));
        }
    }
    // Rows of the parameter tables with one parameter up to 2 (the larger ones are benchmarks).
    let mut tables: Vec<_> = walk(&tlsf).into_iter().filter(|p| p.extension().is_some_and(|e| e == "csv")).collect();
    tables.sort();
    for table in tables {
        let text = std::fs::read_to_string(&table).unwrap();
        let mut lines = text.lines();
        let header: Vec<&str> = lines.next().unwrap().split(',').collect();
        if header != ["n", "refsize", "status"] {
            continue;
        }
        for line in lines {
            let fields: Vec<&str> = line.split(',').collect();
            let value: i64 = fields[0].parse().unwrap();
            if value <= 2 && fields[2] != "unknown" {
                cases.push((table.with_extension("tlsf"), n(value), verdict(fields[2])));
            }
        }
    }
    let mut examples: Vec<_> =
        std::fs::read_dir(root().join("examples/ltl")).unwrap().map(|e| e.unwrap().path()).collect();
    examples.sort();
    for path in examples {
        let text = std::fs::read_to_string(&path).unwrap();
        let expected = text
            .lines()
            .find_map(|l| l.strip_prefix("// Expected: "))
            .unwrap_or_else(|| panic!("{} has no `// Expected:` line", path.display()));
        assert!(text.lines().next().unwrap().starts_with("// "), "{} starts with its description", path.display());
        cases.push((path, Vec::new(), verdict(expected.trim())));
    }
    // A family listed by hand may also be a row of its table: decide it once, and the two
    // sources must agree on its verdict.
    let mut seen: Vec<Case> = Vec::new();
    for case in cases {
        match seen.iter().find(|c| c.0 == case.0 && c.1 == case.1) {
            Some(first) => assert_eq!(first.2, case.2, "{} is listed twice with two verdicts", label(&case.0, &case.1)),
            None => seen.push(case),
        }
    }
    seen
}

/// Every listed specification decided, once for all the tests of this file (the larger
/// instances take seconds).
fn decided() -> &'static [(Case, Spec, Synthesis)] {
    static DECIDED: std::sync::OnceLock<Vec<(Case, Spec, Synthesis)>> = std::sync::OnceLock::new();
    DECIDED.get_or_init(|| {
        listed()
            .into_iter()
            .map(|case| {
                let (spec, outcome) = decide(&case.0, &case.1);
                (case, spec, outcome)
            })
            .collect()
    })
}

fn walk(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            out.extend(walk(&path));
        } else {
            out.push(path);
        }
    }
    out
}

fn label(path: &Path, params: &[(String, i64)]) -> String {
    let params: Vec<String> = params.iter().map(|(k, v)| format!("{k}={v}")).collect();
    format!(
        "{}{}",
        path.file_name().unwrap().to_string_lossy(),
        if params.is_empty() { String::new() } else { format!(" ({})", params.join(", ")) }
    )
}

fn python() -> PathBuf {
    let path = root().join(".venv/bin/python");
    assert!(path.exists(), "{} is missing: run `bash scripts/python-checkers.sh` (make test does)", path.display());
    path
}

fn check_with(script: &str, json: &Path) -> (i32, String) {
    let out = Command::new(python())
        .arg(root().join("tests/checkers").join(script))
        .arg(json)
        .output()
        .unwrap_or_else(|e| panic!("cannot run {script}: {e}"));
    let text = format!("{}{}", String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
    (out.status.code().unwrap_or(-1), text)
}

/// Where the model check records that it confirmed a report: a file named by a 128-bit hash of
/// everything the check depends on, namely the checker's source, the `lbt` it runs (size and
/// modification time) and the report without the two members the checker never reads
/// (`stats`, `rounds`: counters and timings that differ between solvers finding one machine).
/// Only passes are recorded, so a failing document is checked (and fails) every time.
fn confirmed_marker(json: &Path) -> PathBuf {
    use std::hash::{Hash, Hasher};
    let mut report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(json).unwrap()).expect("a report the test wrote");
    let members = report.as_object_mut().expect("a report is a JSON object");
    members.remove("stats");
    members.remove("rounds");
    static CHECKER: std::sync::OnceLock<(Vec<u8>, u64, Option<std::time::SystemTime>)> = std::sync::OnceLock::new();
    let checker = CHECKER.get_or_init(|| {
        let lbt = Command::new("sh").args(["-c", "command -v lbt"]).output().unwrap().stdout;
        let lbt = std::fs::metadata(String::from_utf8_lossy(&lbt).trim())
            .unwrap_or_else(|e| panic!("lbt is needed for the model check: {e}"));
        (std::fs::read(root().join("tests/checkers/ltl_mc.py")).unwrap(), lbt.len(), lbt.modified().ok())
    });
    // DefaultHasher::new() has fixed keys: the same input hashes alike in every test process.
    let key: Vec<u64> = [0u8, 1]
        .iter()
        .map(|seed| {
            let mut hasher = std::collections::hash_map::DefaultHasher::new();
            (seed, checker, report.to_string()).hash(&mut hasher);
            hasher.finish()
        })
        .collect();
    let dir = root().join("target/ltl-mc-confirmed");
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(format!("{:016x}{:016x}", key[0], key[1]))
}

fn scratch() -> PathBuf {
    let dir = root().join("target/ltl-examples");
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// The checks of the decided listing, each on the one decision of [`decided`]: with a process
/// per test (cargo-nextest), five tests would decide the listing five times (about 7 s each).
/// They run side by side; every failing check is named, its panic printed above.
#[test]
fn the_decided_listing_passes_every_check() {
    let checks: [(&str, fn()); 5] = [
        (
            "every_listed_specification_gets_its_known_verdict_and_a_strategy_lbt_confirms",
            every_listed_specification_gets_its_known_verdict_and_a_strategy_lbt_confirms,
        ),
        (
            "the_bdd_solver_decides_the_listed_specifications_as_the_explicit_one",
            the_bdd_solver_decides_the_listed_specifications_as_the_explicit_one,
        ),
        ("gr1py_agrees_where_the_specification_is_gr1", gr1py_agrees_where_the_specification_is_gr1),
        ("synthesised_controllers_become_code_for_every_target", synthesised_controllers_become_code_for_every_target),
        ("compositional_and_monolithic_verdicts_agree", compositional_and_monolithic_verdicts_agree),
    ];
    decided();
    let failed: Vec<&str> = std::thread::scope(|s| {
        let running: Vec<_> = checks.iter().map(|&(name, check)| (name, s.spawn(check))).collect();
        running.into_iter().filter_map(|(name, check)| check.join().is_err().then_some(name)).collect()
    });
    assert!(failed.is_empty(), "checks of the decided listing that failed (their panics are above): {failed:?}");
}

fn every_listed_specification_gets_its_known_verdict_and_a_strategy_lbt_confirms() {
    let cases = decided();
    assert!(cases.len() >= 60, "{} cases", cases.len());
    let dir = scratch();
    let mut documents = Vec::new();
    for (i, ((path, params, expected), spec, outcome)) in cases.iter().enumerate() {
        let name = label(path, params);
        assert_eq!(outcome.verdict, *expected, "{name}: {}", ltl::summary(outcome));
        let machine = outcome.controller.as_ref().or(outcome.counter_strategy.as_ref()).expect("a strategy");
        machine.validate().unwrap_or_else(|e| panic!("{name}: {e}"));
        let json = dir.join(format!("{i}.json"));
        std::fs::write(&json, ltl::report_json(spec, outcome).to_string()).unwrap();
        documents.push((name, json));
    }
    model_check(&documents);
}

/// Runs `tests/checkers/ltl_mc.py` on every (name, report) document, two at a time (lbt and
/// Python start in about 50 ms each), and fails on the first strategy it does not confirm.
///
/// A document the checker has confirmed before is not checked again: the symbolic solver finds
/// the explicit solver's very machine for almost every listed specification, and the bdd
/// solver for a third of them, so the tests of this file would otherwise check the same
/// machines up to three times. See [`confirmed_marker`] for what a confirmation is tied to.
pub(crate) fn model_check(documents: &[(String, PathBuf)]) {
    let half = documents.len() / 2;
    let (first, second) = documents.split_at(half);
    let results: Vec<(String, i32, String)> = std::thread::scope(|s| {
        let run = |docs: &[(String, PathBuf)]| {
            docs.iter()
                .map(|(name, json)| {
                    let marker = confirmed_marker(json);
                    if marker.exists() {
                        return (name.clone(), 0, String::new());
                    }
                    let (code, text) = check_with("ltl_mc.py", json);
                    if code == 0 {
                        std::fs::write(&marker, json.display().to_string()).unwrap();
                    }
                    (name.clone(), code, text)
                })
                .collect::<Vec<_>>()
        };
        let a = s.spawn(move || run(first));
        let b = s.spawn(move || run(second));
        let mut all = a.join().unwrap();
        all.extend(b.join().unwrap());
        all
    });
    for (name, code, text) in results {
        assert_eq!(code, 0, "{name}: the independent model check does not confirm the strategy:\n{text}");
    }
}

/// The symbolic solver (`--solver symbolic`) on every listed specification: the known verdict,
/// and a strategy the model check confirms (`tests/ltl_random.rs` compares it with the explicit
/// solver position by position).
#[test]
fn the_symbolic_solver_decides_every_listed_specification() {
    let dir = scratch().join("symbolic");
    std::fs::create_dir_all(&dir).unwrap();
    let cfg = Config { solver: ltl::Solver::Symbolic, ..Config::default() };
    let mut documents = Vec::new();
    for (i, (path, params, expected)) in listed().into_iter().enumerate() {
        let name = label(&path, &params);
        let source = std::fs::read_to_string(&path).unwrap();
        let (spec, _) = ltl::compile(&source, Format::of_path(path.to_str().unwrap()), &params).unwrap();
        let outcome = ltl::synthesize(&spec, &cfg, &mut |_| true).unwrap_or_else(|stop| panic!("{name}: {stop}"));
        assert_eq!(outcome.verdict, expected, "{name}: {}", ltl::summary(&outcome));
        let machine = outcome.controller.as_ref().or(outcome.counter_strategy.as_ref()).expect("a strategy");
        machine.validate().unwrap_or_else(|e| panic!("{name}: {e}"));
        let json = dir.join(format!("{i}.json"));
        std::fs::write(&json, ltl::report_json(&spec, &outcome).to_string()).unwrap();
        documents.push((name, json));
    }
    model_check(&documents);
}

/// The bdd solver (`--solver bdd`) on every listed specification, within a smaller work
/// budget: where it decides, the verdict and the bound of the explicit solver (the reference)
/// and a strategy the model check confirms; where its diagrams outgrow the budget it says so
/// (unknown, with the limit), and those specifications are named here.
fn the_bdd_solver_decides_the_listed_specifications_as_the_explicit_one() {
    let dir = scratch().join("bdd");
    std::fs::create_dir_all(&dir).unwrap();
    let cfg = Config { solver: ltl::Solver::Bdd, max_work: 60_000_000, ..Config::default() };
    let mut documents = Vec::new();
    let mut beyond = Vec::new();
    for (i, ((path, params, expected), spec, explicit)) in decided().iter().enumerate() {
        let name = label(path, params);
        let outcome = match ltl::synthesize(spec, &cfg, &mut |_| true) {
            Ok(outcome) if outcome.verdict != Verdict::Unknown => outcome,
            Ok(outcome) => {
                let limit = outcome.limit.unwrap_or_default();
                assert!(limit.contains("BDD nodes") || limit.contains("--max-work"), "{name}: {limit}");
                beyond.push(name);
                continue;
            }
            Err(stop) => {
                assert!(matches!(stop, ltl::Stop::Budget { .. }), "{name}: {stop}");
                beyond.push(name);
                continue;
            }
        };
        assert_eq!(outcome.verdict, *expected, "{name}: {}", ltl::summary(&outcome));
        assert_eq!((outcome.verdict, outcome.k), (explicit.verdict, explicit.k), "{name}: bdd against explicit");
        let machine = outcome.controller.as_ref().or(outcome.counter_strategy.as_ref()).expect("a strategy");
        machine.validate().unwrap_or_else(|e| panic!("{name}: {e}"));
        let json = dir.join(format!("{i}.json"));
        std::fs::write(&json, ltl::report_json(spec, &outcome).to_string()).unwrap();
        documents.push((name, json));
    }
    eprintln!("bdd: {} decided as the explicit solver does; beyond its budget: {beyond:?}", documents.len());
    assert!(documents.len() * 4 >= decided().len() * 3, "only {} decided; beyond: {beyond:?}", documents.len());
    model_check(&documents);
}

/// The GR(1) game (`--solver gr1`) on every listed specification in its fragment: the known
/// verdict, and the controller (and the counter-strategy, when the bounded games found one)
/// confirmed by the model check. Outside the fragment it refuses, naming the conjunct.
#[test]
fn the_gr1_game_decides_the_listed_specifications_in_its_fragment() {
    let dir = scratch().join("gr1");
    std::fs::create_dir_all(&dir).unwrap();
    let cfg = Config { solver: ltl::Solver::Gr1, circuit: true, ..Config::default() };
    let (mut documents, mut outside) = (Vec::new(), Vec::new());
    let mut circuits = 0;
    for (i, (path, params, expected)) in listed().into_iter().enumerate() {
        let name = label(&path, &params);
        let source = std::fs::read_to_string(&path).unwrap();
        let (spec, _) = ltl::compile(&source, Format::of_path(path.to_str().unwrap()), &params).unwrap();
        let outcome = match ltl::synthesize(&spec, &cfg, &mut |_| true) {
            Ok(outcome) => outcome,
            Err(ltl::Stop::Budget { message, .. }) if message.contains("outside the GR(1) fragment") => {
                outside.push(name);
                continue;
            }
            Err(stop) => panic!("{name}: {stop}"),
        };
        assert_eq!(outcome.verdict, expected, "{name}: {}", ltl::summary(&outcome));
        if expected == Verdict::Realizable {
            assert!(outcome.controller.is_some(), "{name}: {}", ltl::summary(&outcome));
        }
        if let Some(machine) = outcome.controller.as_ref().or(outcome.counter_strategy.as_ref()) {
            machine.validate().unwrap_or_else(|e| panic!("{name}: {e}"));
            let json = dir.join(format!("{i}.json"));
            std::fs::write(&json, ltl::report_json(&spec, &outcome).to_string()).unwrap();
            documents.push((name.clone(), json));
        }
        // The same controller as a circuit, unfolded into its table for the model check.
        if expected == Verdict::Realizable {
            let circuit = outcome.circuit.as_ref().unwrap_or_else(|| panic!("{name}: no circuit: {:?}", outcome.limit));
            let table =
                circuit.to_machine(100_000).unwrap_or_else(|| panic!("{name}: the circuit's table is too large"));
            table.validate().unwrap_or_else(|e| panic!("{name}: the circuit's table: {e}"));
            let as_table = Synthesis { controller: Some(table), circuit: None, ..outcome.clone() };
            let json = dir.join(format!("{i}-circuit.json"));
            std::fs::write(&json, ltl::report_json(&spec, &as_table).to_string()).unwrap();
            documents.push((format!("{name} (circuit)"), json));
            circuits += 1;
        }
    }
    eprintln!(
        "gr1: {} strategies ({circuits} of them circuits) to check; outside the fragment: {outside:?}",
        documents.len()
    );
    assert!(
        documents.len() >= 30 + circuits && circuits >= 20,
        "only {} decided; outside: {outside:?}",
        documents.len()
    );
    model_check(&documents);
}

/// SYNTCOMP's families at the sizes of issue 29 (up to 24 signals), decided by the GR(1) game
/// with SYNTCOMP's status; the bounded games decide none of the larger ones within the default
/// budgets (`plcsynth bench ltl --scale` prints both).
#[test]
fn the_gr1_game_decides_the_families_at_syntcomp_sizes() {
    let tlsf = shared().join("tlsf");
    let cfg = Config { solver: ltl::Solver::Gr1, circuit: true, ..Config::default() };
    let n = |v: i64| vec![("n".to_string(), v)];

    for (file, params, expected) in [
        ("simple_arbiter/simple_arbiter.tlsf", n(8), Verdict::Realizable),
        ("simple_arbiter/simple_arbiter.tlsf", n(12), Verdict::Realizable),
        ("load_balancer/load_balancer.tlsf", n(10), Verdict::Realizable),
        ("simple_arbiter/simple_arbiter.tlsf", n(20), Verdict::Realizable),
        ("full_arbiter/full_arbiter.tlsf", n(4), Verdict::Realizable),
        ("full_arbiter/full_arbiter.tlsf", n(5), Verdict::Realizable),
        ("load_balancer/load_balancer.tlsf", n(4), Verdict::Realizable),
        ("load_balancer/load_balancer.tlsf", n(5), Verdict::Realizable),
        ("prioritized_arbiter/prioritized_arbiter.tlsf", n(4), Verdict::Realizable),
        ("round_robin_arbiter/round_robin_arbiter.tlsf", n(4), Verdict::Realizable),
        ("simple_arbiter_unreal/simple_arbiter_unreal2.tlsf", n(4), Verdict::Unrealizable),
        (
            "simple_arbiter_unreal/simple_arbiter_unreal1.tlsf",
            vec![("n".into(), 4), ("u".into(), 2)],
            Verdict::Unrealizable,
        ),
        ("prioritized_arbiter_unreal/prioritized_arbiter_unreal2.tlsf", n(4), Verdict::Unrealizable),
        (
            "prioritized_arbiter_unreal/prioritized_arbiter_unreal1.tlsf",
            vec![("n".into(), 3), ("u".into(), 4)],
            Verdict::Unrealizable,
        ),
    ] {
        let path = tlsf.join(file);
        let name = label(&path, &params);
        let source = std::fs::read_to_string(&path).unwrap();
        let (spec, _) = ltl::compile(&source, Format::Tlsf, &params).unwrap();
        let outcome = ltl::synthesize(&spec, &cfg, &mut |_| true).unwrap_or_else(|stop| panic!("{name}: {stop}"));
        assert_eq!(outcome.verdict, expected, "{name}: {}", ltl::summary(&outcome));
        if expected == Verdict::Realizable {
            let circuit = outcome.circuit.as_ref().unwrap_or_else(|| panic!("{name}: {}", ltl::summary(&outcome)));
            let kept = bounded_check(&spec, circuit, 60).unwrap_or_else(|e| panic!("{name}: the circuit: {e}"));
            assert!(kept > 0, "{name}: no play kept the assumptions");
            eprintln!("{name}: {}; {kept} of 60 plays kept the assumptions", ltl::summary(&outcome));
            // The table, where there is one, too (lbt takes only the small ones).
            if let Some(table) = &outcome.controller {
                let kept = bounded_check_table(&spec, table, 60).unwrap_or_else(|e| panic!("{name}: the table: {e}"));
                assert!(kept > 0, "{name}: no play kept the assumptions");
            }
        } else {
            // lbt's model check of these small counter-strategies runs for more than ten
            // minutes (its automaton of the specification at n = 4): the bounded check, with
            // the controller's outputs the pseudo-random side, and every play must violate.
            let counter = outcome.counter_strategy.as_ref().unwrap_or_else(|| panic!("{name}: no counter-strategy"));
            counter.validate().unwrap_or_else(|e| panic!("{name}: {e}"));
            let plays = bounded_check_counter(&spec, counter, 60).unwrap_or_else(|e| panic!("{name}: {e}"));
            eprintln!("{name}: {}; all {plays} plays violate it", ltl::summary(&outcome));
        }
    }
}

/// The bounded check fails controllers that break the specification: circuits that never
/// grant the first client or grant two clients at once, a table that never grants the first.
#[test]
fn a_mutated_controller_fails_the_bounded_check() {
    let path = shared().join("tlsf/simple_arbiter/simple_arbiter.tlsf");
    let source = std::fs::read_to_string(&path).unwrap();
    let (spec, _) = ltl::compile(&source, Format::Tlsf, &[("n".to_string(), 12)]).unwrap();
    let cfg = Config { solver: ltl::Solver::Gr1, circuit: true, ..Config::default() };
    let circuit = ltl::synthesize(&spec, &cfg, &mut |_| true).unwrap().circuit.expect("a circuit");
    assert_eq!(bounded_check(&spec, &circuit, 20), Ok(20));
    let mut starving = circuit.clone();
    for goal in &mut starving.goals {
        goal.writes[0] = ltl::Logic::Const(false);
    }
    let error = bounded_check(&spec, &starving, 20).unwrap_err();
    assert!(error.contains("violates"), "{error}");
    let mut greedy = circuit.clone();
    greedy.goals[0].writes[1] = greedy.goals[0].writes[0].clone();
    let error = bounded_check(&spec, &greedy, 20).unwrap_err();
    assert!(error.contains("violates"), "{error}");
    // A table (n = 6) that never grants the first client.
    let (spec, _) = ltl::compile(&source, Format::Tlsf, &[("n".to_string(), 6)]).unwrap();
    let table = ltl::synthesize(&spec, &cfg, &mut |_| true).unwrap().controller.expect("a table");
    assert_eq!(bounded_check_table(&spec, &table, 20), Ok(20));
    let mut starving = table.clone();
    for row in starving.states.iter_mut().flatten() {
        row.write &= !1;
    }
    let error = bounded_check_table(&spec, &starving, 20).unwrap_err();
    assert!(error.contains("violates"), "{error}");
}

/// A bounded check of a controller circuit against the specification's own semantics, for
/// circuits whose table is too large for the model check: `runs` environments, each a fixed
/// pseudo-random function from the circuit's state to the inputs (with its own bias towards
/// true), so that each closed loop is an ultimately periodic play; each such play must satisfy
/// the whole formula, evaluated on the lasso (`Play::satisfies`, no code shared with the
/// solver). Returns how many plays kept the assumptions (where the guarantees were at stake).
fn bounded_check(spec: &Spec, circuit: &ltl::Circuit, runs: u64) -> Result<usize, String> {
    let key = |state: &ltl::CircuitState| {
        state.latches.iter().fold(mix(state.goal as u64), |h, &b| mix(h ^ u64::from(b)) ^ h << 1)
    };
    let step = |state: &ltl::CircuitState, input: &dyn Fn(ltl::SignalId) -> bool| {
        let (writes, next) = circuit.step(state, input);
        (letter_of(&circuit.reads, &circuit.writes, input, &writes), next)
    };
    lasso_check(spec, circuit.initial(), key, step, runs, true)
}

/// The same bounded check of a controller table (for tables past lbt's reach).
fn bounded_check_table(spec: &Spec, machine: &ltl::Machine, runs: u64) -> Result<usize, String> {
    lasso_check(spec, machine.init, |s: &ltl::StateId| mix(u64::from(s.0)), table_step(machine), runs, true)
}

/// The bounded check of a counter-strategy: the controller's outputs are the pseudo-random
/// side, and every play must violate the specification. Returns the plays checked.
fn bounded_check_counter(spec: &Spec, machine: &ltl::Machine, runs: u64) -> Result<usize, String> {
    lasso_check(spec, machine.init, |s: &ltl::StateId| mix(u64::from(s.0)), table_step(machine), runs, false)
}

/// A machine's step as the bounded check takes it: the letter of the step and the next state.
fn table_step(
    machine: &ltl::Machine,
) -> impl Fn(&ltl::StateId, &dyn Fn(ltl::SignalId) -> bool) -> (u64, ltl::StateId) + '_ {
    move |state, input| {
        let valuation = machine.reads.iter().enumerate().fold(0u64, |v, (i, &s)| v | u64::from(input(s)) << i);
        let row = machine.row(*state, valuation);
        let writes: Vec<bool> = (0..machine.writes.len()).map(|j| row.write >> j & 1 == 1).collect();
        (letter_of(&machine.reads, &machine.writes, input, &writes), row.next)
    }
}

/// splitmix64's finaliser.
fn mix(mut x: u64) -> u64 {
    x = (x ^ (x >> 30)).wrapping_mul(0xbf58476d1ce4e5b9);
    x = (x ^ (x >> 27)).wrapping_mul(0x94d049bb133111eb);
    x ^ (x >> 31)
}

/// A step's letter: bit `s` signal `s`.
fn letter_of(
    reads: &[ltl::SignalId],
    writes: &[ltl::SignalId],
    input: &dyn Fn(ltl::SignalId) -> bool,
    written: &[bool],
) -> u64 {
    let read = reads.iter().fold(0u64, |l, &s| l | u64::from(input(s)) << s.0);
    writes.iter().zip(written).fold(read, |l, (&s, &w)| l | u64::from(w) << s.0)
}

/// Closes the loop of a deterministic strategy (`step` from `initial`) with `runs` opponents
/// that are fixed functions of the strategy's state (`key`), and checks that each lasso
/// satisfies the formula (`satisfy`; a counter-strategy's must violate it). Returns the plays
/// that kept the assumptions (a controller's) or the plays checked (a counter-strategy's).
fn lasso_check<S: Clone + Eq + std::hash::Hash>(
    spec: &Spec,
    initial: S,
    key: impl Fn(&S) -> u64,
    step: impl Fn(&S, &dyn Fn(ltl::SignalId) -> bool) -> (u64, S),
    runs: u64,
    satisfy: bool,
) -> Result<usize, String> {
    use std::collections::HashMap;
    let formula = spec.formula();
    let assumptions = ltl::Ltl::all(spec.assumptions.iter().map(|c| c.formula.clone()).collect());
    let mut kept = 0;
    let mut checked = 0;
    for run in 0..runs {
        // Per run and input, how often it is true (in 1/1000): some inputs held, some never
        // set, so that assumptions such as `G F idle` can be kept.
        let bias = |s: ltl::SignalId| [500, 0, 1000, 50, 950, 200][(mix(run << 8 | u64::from(s.0)) % 6) as usize];
        let mut seen: HashMap<S, usize> = HashMap::new();
        let mut state = initial.clone();
        let mut letters: Vec<u64> = Vec::new();
        let loop_start = loop {
            if let Some(&start) = seen.get(&state) {
                break Some(start);
            }
            if letters.len() >= 5_000 {
                break None;
            }
            seen.insert(state.clone(), letters.len());
            let here = mix(run ^ key(&state));
            let input = |s: ltl::SignalId| mix(here ^ u64::from(s.0).wrapping_mul(0x9e3779b97f4a7c15)) % 1000 < bias(s);
            let (letter, next) = step(&state, &input);
            letters.push(letter);
            state = next;
        };
        let Some(loop_start) = loop_start else { continue };
        let play = ltl::Play { states: Vec::new(), letters, loop_start };
        checked += 1;
        if play.satisfies(&formula) != satisfy {
            let what = if satisfy { "violates" } else { "satisfies" };
            return Err(format!("run {run}: the strategy's play {what} the specification: {}", play.describe(spec)));
        }
        kept += usize::from(!satisfy || play.satisfies(&assumptions));
    }
    if checked * 2 < runs as usize {
        return Err(format!("only {checked} of {runs} plays closed a loop within 5 000 steps"));
    }
    Ok(kept)
}

#[test]
fn a_mutated_controller_is_caught_by_the_model_check() {
    let dir = scratch();
    for file in ["paper_appC_grant", "ptii_Arbitor", "ptii_NumericalRefined"] {
        let (spec, outcome) = decide(&shared().join(format!("g4ltl/{file}.g4ltl")), &[]);
        let controller = outcome.controller.clone().expect("realizable");
        // Every single-bit change of a row's outputs; some are harmless (a don't-care), but
        // not all of them may be.
        let mut caught = 0;
        let mut tried = 0;
        for s in 0..controller.states.len() {
            for r in 0..controller.states[s].len() {
                for bit in 0..controller.writes.len() {
                    let mut mutant = controller.clone();
                    mutant.states[s][r].write ^= 1 << bit;
                    let mutated = Synthesis { controller: Some(mutant), ..outcome.clone() };
                    let json = dir.join(format!("mutant-{file}-{s}-{r}-{bit}.json"));
                    std::fs::write(&json, ltl::report_json(&spec, &mutated).to_string()).unwrap();
                    let (code, text) = check_with("ltl_mc.py", &json);
                    assert!(code == 0 || code == 1, "{file}: {text}");
                    tried += 1;
                    caught += usize::from(code == 1);
                }
            }
        }
        assert!(caught > 0, "{file}: none of {tried} mutants is caught");
    }
}

fn gr1py_agrees_where_the_specification_is_gr1() {
    let dir = scratch();
    let mut documents = Vec::new();
    for (i, (_, spec, outcome)) in decided().iter().enumerate() {
        let json = dir.join(format!("gr1-{i}.json"));
        std::fs::write(&json, ltl::report_json(spec, outcome).to_string()).unwrap();
        documents.push(json);
    }
    // One Python process for the whole listing (its start-up is most of a document's check).
    let out = Command::new(python())
        .arg(root().join("tests/checkers/ltl_gr1.py"))
        .arg("--each")
        .args(&documents)
        .output()
        .unwrap_or_else(|e| panic!("cannot run ltl_gr1.py: {e}"));
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "ltl_gr1.py --each failed:\n{stdout}{}", String::from_utf8_lossy(&out.stderr));
    let answers: Vec<serde_json::Value> =
        stdout.lines().map(|l| serde_json::from_str(l).expect("a line of JSON")).collect();
    assert_eq!(
        answers.len(),
        documents.len(),
        "ltl_gr1.py --each answered {} of {} documents",
        answers.len(),
        documents.len()
    );
    let mut compared = 0;
    for (((path, params, _), _, outcome), answer) in decided().iter().zip(&answers) {
        let text = |key: &str| answer[key].as_str().expect("the answer's texts").to_string();
        match answer["code"].as_i64() {
            Some(4) => continue, // not GR(1)-shaped, or outside the fragment where the games agree
            Some(0) => {
                let theirs = text("stdout");
                let ours = if outcome.verdict == Verdict::Realizable { "realizable" } else { "unrealizable" };
                assert_eq!(theirs.trim(), ours, "{}: gr1py disagrees", label(path, params));
                compared += 1;
            }
            _ => panic!("{}: ltl_gr1.py failed:\n{}{}", label(path, params), text("stdout"), text("stderr")),
        }
    }
    assert!(compared >= 6, "only {compared} listed specifications were compared with gr1py");
}

fn synthesised_controllers_become_code_for_every_target() {
    let dir = scratch();
    let options = plc::Options::default();
    let schema = root().join("../shared/schemas/tc6_xml_v201.xsd");
    // A timer, many states, Moore semantics, and predicates with two state machines.
    let checked = ["sample.g4ltl", "ptii_AutomaticDoor.g4ltl", "mutex.tlsf", "fig1.ltl"];
    let mut st_files = Vec::new();
    for ((path, params, _), spec, outcome) in decided() {
        let source = std::fs::read_to_string(path).unwrap();
        let name = label(path, params);
        let options_ltl = plc::lower::ltl::LowerOptions::default();
        let Some(unit) = plc::lower::ltl::lower_outcome(&source, spec, outcome, &options_ltl) else { continue };
        let unit = unit.unwrap_or_else(|d| panic!("{name}: {d:?}"));
        let file = path.file_name().unwrap().to_string_lossy().to_string();
        for target in Target::ALL {
            let files = plc::render_unit_files(&unit, target, &options);
            if target == Target::Il {
                assert!(files.is_err(), "{name}: Instruction List is refused");
                continue;
            }
            let files = files.unwrap_or_else(|e| panic!("{name}, {target}: {e}"));
            if !checked.contains(&file.as_str()) || !params.is_empty() {
                continue;
            }
            let text = &files[0].text;
            let stem = file.replace('.', "_");
            match target {
                Target::St | Target::Codesys => {
                    let out = dir.join(format!("{stem}_{target}.st"));
                    std::fs::write(&out, text).unwrap();
                    st_files.push(out);
                }
                Target::Scl | Target::Scl1500 => {
                    let out = dir.join(format!("{stem}_{target}.st"));
                    std::fs::write(&out, common::scl_for_blark(text)).unwrap();
                    st_files.push(out);
                }
                Target::Plcopen | Target::Abb => {
                    let out = dir.join(format!("{stem}_{target}.xml"));
                    std::fs::write(&out, text).unwrap();
                    let status = Command::new("xmllint").arg("--noout").arg("--schema").arg(&schema).arg(&out).output();
                    let status = status.expect("xmllint runs (bash scripts/python-checkers.sh installs it)");
                    assert!(status.status.success(), "{name}: {}", String::from_utf8_lossy(&status.stderr));
                }
                _ => {}
            }
        }
    }
    assert_eq!(st_files.len(), 4 * checked.len(), "each checked controller in four ST dialects");
    common::blark_all(&python(), &root(), &st_files);
}

/// The compositional split never changes a verdict: every listed specification whose
/// guarantees split into groups is decided again as a whole, with the same result; and every
/// compositional controller's groups write disjoint outputs.
fn compositional_and_monolithic_verdicts_agree() {
    let mut split = 0;
    for ((path, params, _), spec, outcome) in decided() {
        if outcome.split < 2 {
            continue;
        }
        split += 1;
        let cfg = Config { compositional: false, ..Config::default() };
        let whole = ltl::synthesize(spec, &cfg, &mut |_| true).unwrap();
        assert_eq!(whole.verdict, outcome.verdict, "{}", label(path, params));
        let mut written: Vec<_> = outcome.groups.iter().flat_map(|g| g.outputs.clone()).collect();
        let n = written.len();
        written.sort();
        written.dedup();
        assert_eq!(written.len(), n, "{}: groups share an output", label(path, params));
    }
    assert!(split >= 5, "only {split} listed specifications split into groups");
}
