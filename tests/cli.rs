//! The CLI as a user runs it: exit statuses, JSON output, rendered diagnostics.

use std::process::Command;

fn plcsynth(args: &[&str]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_plcsynth"))
        .args(args)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .unwrap();
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn solve_exit_status_follows_the_verdict() {
    assert_eq!(plcsynth(&["solve", "examples/timed/lamp.tga"]).0, 0);
    let (code, out, _) = plcsynth(&["solve", "examples/timed/lamp_naive.tga"]);
    assert_eq!(code, 1);
    assert!(
        out.contains("unrealizable") && out.contains("why the initial state is lost") && out.contains("!press"),
        "{out}"
    );
    let (code, out, err) = plcsynth(&["solve", "examples/timed/round_table_8.tga", "--max-states", "500"]);
    assert_eq!(code, 3);
    assert!(out.contains("budget exceeded after"), "{out}");
    assert!(err.contains("budget exceeded: the search stored more than 500 states"), "{err}");
    assert!(err.contains("this is the state budget; raise it with --max-states N"), "{err}");
}

#[test]
fn every_budget_stop_exits_3_and_names_its_flag() {
    let dir = std::env::temp_dir().join(format!("plcsynth-cli-budget-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    // One node with 22 clocks in use splits into 2^22 sub-locations: refused at the node.
    let clocks: Vec<String> = (0..22).map(|i| format!("c{i}")).collect();
    let loops: String = (0..22).map(|i| format!("    q -> q !t{i} {{c{i} in [1,inf)}} reset{{c{i}}};\n")).collect();
    let file = dir.join("clocks.tga");
    std::fs::write(
        &file,
        format!("plant {{\n  automaton A {{\n    clocks {};\n    nodes q;\n{loops}  }}\n}}\n", clocks.join(", ")),
    )
    .unwrap();
    let path = file.to_str().unwrap();
    for command in ["solve", "compile"] {
        let (code, _, err) = plcsynth(&[command, path]);
        assert_eq!(code, 3, "{command}: {err}");
        assert!(err.contains("clocks.tga:4:11: error: budget exceeded: node `q` of `A` splits into 4194304"), "{err}");
        assert!(err.contains("4 |     nodes q;"), "{err}");
        assert!(err.contains("raise it with --max-memory MIB"), "{err}");
    }
    let (code, out, err) = plcsynth(&["solve", path, "--max-memory", "4096", "--max-work", "1000000", "--json"]);
    assert_eq!(code, 3, "{err}");
    let v: serde_json::Value = serde_json::from_str(out.trim()).unwrap();
    assert_eq!(v["verdict"], "budget_exceeded");
    assert_eq!(v["budget"]["budget"], "work");
    assert_eq!(v["budget"]["limit"], 1_000_000);
    assert!(err.contains("raise it with --max-work N"), "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn solve_json_has_the_documented_fields() {
    let (code, out, _) = plcsynth(&["solve", "examples/timed/gear_checking.tga", "--json"]);
    assert_eq!(code, 0);
    let v: serde_json::Value = serde_json::from_str(out.trim()).unwrap();
    assert_eq!(v["realizable"], true);
    assert_eq!(v["verdict"], "realizable");
    for field in ["visited", "winning", "removed", "millis"] {
        assert!(v[field].is_number(), "{field} in {v}");
    }
    assert!(v["winning"].as_u64().unwrap() > 0 && v["visited"].as_u64() >= v["winning"].as_u64());
}

#[test]
fn bad_input_exits_2_with_a_located_diagnostic() {
    let dir = std::env::temp_dir().join(format!("plcsynth-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("bad.tga");
    std::fs::write(&file, "plant {\n  automaton A { nodes q; q -> r ?a; }\n}\n").unwrap();
    let (code, _, err) = plcsynth(&["solve", file.to_str().unwrap()]);
    assert_eq!(code, 2);
    assert!(err.contains("bad.tga:2:31: error: unknown node `r` in `A`"), "{err}");
    assert!(err.contains("2 |   automaton A { nodes q; q -> r ?a; }"), "{err}");
    let (code, _, err) = plcsynth(&["solve", "no/such/file.tga"]);
    assert_eq!(code, 2);
    assert!(err.contains("cannot read"), "{err}");
}

#[test]
fn states_flag_lists_removal_reasons() {
    let (_, out, _) = plcsynth(&["solve", "examples/timed/lamp.tga", "--states"]);
    assert!(out.contains("[removed (assertion violated: never lamp.on and button.released)]"), "{out}");
    assert!(out.contains("zeno"), "{out}");
}

#[test]
fn compile_writes_every_target_and_refuses_unrealizable_specs() {
    let dir = std::env::temp_dir().join(format!("plcsynth-compile-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let (code, out, _) = plcsynth(&["compile", "examples/timed/lamp.tga"]);
    assert_eq!(code, 0);
    assert_eq!(
        out,
        "0 : WAITUNTIL (press);\n1 : DO (turn_on);\n2 : WAITUNTIL (release);\n3 : DO (turn_off);\n4 : GOTO 0;\n"
    );
    for (target, marker) in [
        ("st", "FUNCTION_BLOCK lamp"),
        ("scl", "VERSION : 0.1"),
        ("codesys", "AT %IX124.0"),
        ("il", "JMPCN END_SCAN"),
        ("stl", "JL\tud"),
        ("plcopen", "tc6_0201"),
    ] {
        let file = dir.join(format!("lamp.{target}"));
        let (code, _, err) =
            plcsynth(&["compile", "examples/timed/lamp.tga", "--target", target, "-o", file.to_str().unwrap()]);
        assert_eq!(code, 0, "{target}: {err}");
        let text = std::fs::read_to_string(&file).unwrap();
        assert!(text.contains(marker), "{target}:\n{text}");
    }
    let file = dir.join("naive.st");
    let (code, _, err) =
        plcsynth(&["compile", "examples/timed/lamp_naive.tga", "--target", "st", "-o", file.to_str().unwrap()]);
    assert_eq!(code, 1);
    assert!(err.contains("unrealizable; nothing written") && err.contains("!press"), "{err}");
    assert!(!file.exists());
}
