//! `plcsynth ltl` as a user runs it: verdicts and exit statuses, located diagnostics, the
//! counter-strategy tree, JSON, bounds and budgets, TLSF parameters, generated code.

use std::path::PathBuf;
use std::process::{Command, Output};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn plcsynth(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_plcsynth")).current_dir(root()).args(args).output().unwrap()
}

fn stdout(out: &Output) -> String {
    String::from_utf8_lossy(&out.stdout).into_owned()
}

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

#[test]
fn a_realizable_specification_prints_its_controller() {
    let out = plcsynth(&["ltl", "examples/ltl/arbiter.ltl"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let text = stdout(&out);
    assert!(text.starts_with("realizable at k = 0: a controller of"), "{text}");
    assert!(text.contains("s0: ") && text.contains("grant1"), "{text}");
}

#[test]
fn an_unrealizable_specification_prints_the_counter_strategy_as_a_tree() {
    let out = plcsynth(&["ltl", "examples/ltl/arbiter_same_scan.ltl"]);
    assert_eq!(out.status.code(), Some(1));
    let text = stdout(&out);
    assert!(text.contains("s0: the environment sets req1 & req2"), "{text}");
    assert!(text.contains("└─ whatever the controller answers → s0 again"), "{text}");
}

#[test]
fn bad_input_is_located_with_the_source_line() {
    let dir = root().join("target/ltl-cli");
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("bad.ltl");
    std::fs::write(&file, "ALWAYS (req -> grant\nINPUT req\nOUTPUT grant\nALWAYS typo\n").unwrap();
    let out = plcsynth(&["ltl", file.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    let text = stderr(&out);
    assert!(text.contains("bad.ltl:1:21: error: expected `)`"), "{text}");
    assert!(text.contains("bad.ltl:4:8: error: `typo` is not declared"), "{text}");
    assert!(text.contains("ALWAYS typo") && text.contains('^'), "{text}");
    let missing = plcsynth(&["ltl", "no/such/file.ltl"]);
    assert_eq!(missing.status.code(), Some(2));
}

#[test]
fn json_carries_the_machine_and_the_formula() {
    let out = plcsynth(&["ltl", "--json", "../shared/ltl/g4ltl/paper_appC_grant.g4ltl"]);
    assert_eq!(out.status.code(), Some(0));
    let doc: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(doc["verdict"], "realizable");
    assert_eq!(doc["ltl"], "G (req -> (grant || X grant)) && G (grant -> X !grant)");
    assert_eq!(doc["inputs"], serde_json::json!(["req"]));
    let states = doc["mealy"]["states"].as_object().unwrap();
    assert_eq!(states.len(), 2, "{doc}");
    let unreal = plcsynth(&["ltl", "--json", "examples/ltl/copy_moore.tlsf"]);
    assert_eq!(unreal.status.code(), Some(1));
    let doc: serde_json::Value = serde_json::from_slice(&unreal.stdout).unwrap();
    assert_eq!(doc["semantics"], "moore");
    assert_eq!(doc["counterstrategy"]["moves_first"], false);
    assert!(doc.get("mealy").is_none());
}

#[test]
fn bounds_and_budgets_give_unknown_with_exit_3() {
    let out = plcsynth(&["ltl", "--max-k", "0", "examples/ltl/mutex.tlsf"]);
    assert_eq!(out.status.code(), Some(3), "{}", stdout(&out));
    assert!(stdout(&out).contains("unknown at k = 0: neither player wins"), "{}", stdout(&out));
    let out = plcsynth(&["ltl", "--max-states", "10", "examples/ltl/mutex.tlsf"]);
    assert_eq!(out.status.code(), Some(3));
    assert!(stdout(&out).contains("--max-states"), "{}", stdout(&out));
    let out = plcsynth(&["ltl", "--max-work", "1000", "examples/ltl/mutex.tlsf"]);
    assert_eq!(out.status.code(), Some(3));
    assert!(
        stdout(&out).contains("--max-work") || stderr(&out).contains("--max-work"),
        "{}{}",
        stdout(&out),
        stderr(&out)
    );
}

#[test]
fn tlsf_parameters_are_set_from_the_command_line() {
    let two = plcsynth(&["ltl", "--json", "--param", "n=2", "examples/ltl/mutex.tlsf"]);
    assert_eq!(two.status.code(), Some(0));
    let doc: serde_json::Value = serde_json::from_slice(&two.stdout).unwrap();
    assert_eq!(doc["inputs"], serde_json::json!(["r_0", "r_1"]));
    let unknown = plcsynth(&["ltl", "--param", "m=2", "examples/ltl/mutex.tlsf"]);
    assert_eq!(unknown.status.code(), Some(2));
    assert!(stderr(&unknown).contains('m'), "{}", stderr(&unknown));
    let g4ltl = plcsynth(&["ltl", "--param", "n=2", "examples/ltl/arbiter.ltl"]);
    assert_eq!(g4ltl.status.code(), Some(2));
    assert!(stderr(&g4ltl).contains("TLSF"), "{}", stderr(&g4ltl));
    let malformed = plcsynth(&["ltl", "--param", "n", "examples/ltl/mutex.tlsf"]);
    assert_eq!(malformed.status.code(), Some(2));
}

#[test]
fn the_controller_is_written_as_plc_code() {
    let dir = root().join("target/ltl-cli");
    std::fs::create_dir_all(&dir).unwrap();
    let st = dir.join("arbiter.st");
    let table = dir.join("arbiter.csv");
    let out = plcsynth(&[
        "ltl",
        "examples/ltl/arbiter.ltl",
        "--target",
        "st",
        "-o",
        st.to_str().unwrap(),
        "--io-table",
        table.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let code = std::fs::read_to_string(&st).unwrap();
    assert!(code.contains("FUNCTION_BLOCK FB_Controller") && code.contains("CASE state OF"), "{code}");
    assert!(std::fs::read_to_string(&table).unwrap().contains("grant1"));
    let stl = plcsynth(&["ltl", "examples/ltl/arbiter.ltl", "--target", "stl"]);
    assert_eq!(stl.status.code(), Some(0));
    assert!(stdout(&stl).contains("FUNCTION_BLOCK"), "{}", stdout(&stl));
    let il = plcsynth(&["ltl", "examples/ltl/arbiter.ltl", "--target", "il"]);
    assert_eq!(il.status.code(), Some(2));
    let unreal = plcsynth(&["ltl", "examples/ltl/arbiter_same_scan.ltl", "--target", "st"]);
    assert_eq!(unreal.status.code(), Some(1));
    assert!(stderr(&unreal).contains("no code written"), "{}", stderr(&unreal));
}

#[test]
fn suggest_prints_assumptions_with_their_controllers_and_keeps_the_exit_status() {
    let out = plcsynth(&["ltl", "--suggest", "../shared/ltl/g4ltl/ptii_NumericalOriginal.g4ltl"]);
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    let text = stdout(&out);
    assert!(text.contains("longest play the counter-strategy forces: [0] req1 & req2"), "{text}");
    assert!(text.contains("1. ASSUME G !(req1 && req2)   (template G !(?a && ?b))"), "{text}");
    assert!(text.contains("   realizable at k = "), "{text}");
    let json = plcsynth(&["ltl", "--json", "--suggest", "examples/ltl/fair_grant_unfair_env.ltl"]);
    assert_eq!(json.status.code(), Some(1));
    let doc: serde_json::Value = serde_json::from_slice(&json.stdout).unwrap();
    assert_eq!(doc["verdict"], "unrealizable");
    let first = &doc["suggestions"][0];
    assert_eq!(first["assumptions"], serde_json::json!(["G F req"]));
    assert_eq!(first["template"], "G F ?a");
    assert!(first["mealy"]["states"].is_object() && first["k"].is_u64(), "{first}");
    assert!(doc.get("suggest_limit").is_none());
    // A realizable specification: nothing extra.
    let real = plcsynth(&["ltl", "--suggest", "examples/ltl/fair_grant.ltl"]);
    assert_eq!(real.status.code(), Some(0));
    assert!(!stdout(&real).contains("suggestion"), "{}", stdout(&real));
}

#[test]
fn suggest_max_reports_that_no_set_that_small_was_found() {
    let dir = root().join("target/ltl-cli");
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("two_faults.ltl");
    std::fs::write(
        &file,
        "ALWAYS (grant -> req)\nALWAYS (grant -> NEXT !grant)\nALWAYS EVENTUALLY grant\nALWAYS (r1 -> g1)\n\
         ALWAYS (r2 -> g2)\nALWAYS !(g1 && g2)\nINPUT req, r1, r2\nOUTPUT grant, g1, g2\n",
    )
    .unwrap();
    let out = plcsynth(&["ltl", "--suggest", "--suggest-max", "1", file.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    assert!(stdout(&out).contains("none: no set of at most 1 assumption found"), "{}", stdout(&out));
    let json = plcsynth(&["ltl", "--json", "--suggest", "--suggest-max", "1", file.to_str().unwrap()]);
    let doc: serde_json::Value = serde_json::from_slice(&json.stdout).unwrap();
    assert_eq!(doc["suggestions"], serde_json::json!([]));
    assert!(doc["suggest_limit"].as_str().unwrap().starts_with("no set of at most 1 assumption found"), "{doc}");
}

/// `bench ltl --scale` with no time to spend: every instance of the families is read with its
/// parameters and gets a row, each run is cancelled at its first progress report (the verdicts
/// themselves are tested in tests/ltl_examples.rs), and a decided one would have to agree with
/// SYNTCOMP's status.
#[test]
fn the_scale_table_has_a_row_per_instance_and_no_verdict_against_the_status() {
    let out = plcsynth(&["bench", "ltl", "--scale", "--scale-timeout", "0"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let text = stdout(&out);
    let rows: Vec<Vec<&str>> = text
        .lines()
        .filter(|l| l.starts_with("| ") && !l.starts_with("| SYNTCOMP"))
        .map(|l| l.trim_matches('|').split(" | ").map(str::trim).collect())
        .collect();
    assert_eq!(rows.len(), 24, "{text}");
    for row in &rows {
        assert_eq!(row.len(), 9, "{row:?}");
        let status = row[2];
        assert_eq!(status == "unrealizable", row[0].contains("_unreal"), "{row:?}");
        for verdict in [row[3], row[5], row[7]] {
            assert!(!verdict.contains("errors"), "{row:?}");
            if verdict.starts_with("realizable") || verdict.starts_with("unrealizable") {
                assert!(verdict.starts_with(&format!("{status} ")), "{row:?}");
            } else {
                let known = ["stopped after 0 s", "unknown (", "refused ("];
                assert!(known.iter().any(|k| verdict.starts_with(k)), "{row:?}");
            }
        }
    }
    assert!(text.contains("stopped after 0 s"), "{text}");
}

/// A specification wider than the explicit games' letter limit is refused with the way on: the
/// solvers that do not enumerate letters, the GR(1) game first where the specification is in
/// its fragment; that game then decides it and writes the circuit's code.
#[test]
fn too_many_signals_for_the_explicit_games_names_the_symbolic_solvers() {
    let arbiter = "../shared/ltl/tlsf/simple_arbiter/simple_arbiter.tlsf";
    let out = plcsynth(&["ltl", arbiter, "--param", "n=12"]);
    assert_ne!(out.status.code(), Some(0));
    let text = format!("{}{}", stdout(&out), stderr(&out));
    assert!(text.contains("24 signals") && text.contains("--solver symbolic"), "{text}");
    assert!(text.contains("GR(1) fragment, which `--solver gr1` decides"), "{text}");
    let out = plcsynth(&["ltl", arbiter, "--param", "n=12", "--solver", "gr1", "--target", "st"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let code = stdout(&out);
    assert!(code.contains("CASE goal OF") && code.contains("g_11 := open_12;"), "{code}");
    // Outside the fragment (a persistence guarantee) the hint is not given.
    let inputs: Vec<String> = (0..21).map(|i| format!("INPUT a{i}")).collect();
    let wide = std::env::temp_dir().join(format!("plcsynth-wide-{}.ltl", std::process::id()));
    std::fs::write(&wide, format!("{}\nOUTPUT o\nEVENTUALLY (ALWAYS (o <-> a0))\n", inputs.join("\n"))).unwrap();
    let out = plcsynth(&["ltl", wide.to_str().unwrap()]);
    let text = format!("{}{}", stdout(&out), stderr(&out));
    assert!(text.contains("22 signals") && !text.contains("GR(1) fragment"), "{text}");
}
