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
    let (code, out, err) = plcsynth(&["solve", "examples/timed/round_table_8.tga", "--max-states", "100"]);
    assert_eq!(code, 3);
    assert!(out.contains("budget exceeded after"), "{out}");
    assert!(err.contains("budget exceeded: the search stored more than 100 states"), "{err}");
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
    assert_eq!(v["stop"]["stop"], "budget");
    assert_eq!(v["stop"]["resource"], "work");
    assert!(v["stop"]["message"].as_str().unwrap().contains("more than 1000000 units of work"), "{v}");
    let blame = &v["blame"];
    let blamed = &std::fs::read_to_string(&file).unwrap()
        [blame["start"].as_u64().unwrap() as usize..blame["end"].as_u64().unwrap() as usize];
    assert_eq!(blamed, "q", "the node to blame");
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
    // The reference explores every option, the lost ones included.
    let (_, out, _) = plcsynth(&["solve", "examples/timed/lamp.tga", "--states", "--exhaustive"]);
    assert!(out.contains("[removed (assertion violated: never lamp.on and button.released)]"), "{out}");
    assert!(out.contains("zeno"), "{out}");
    // The strategy-directed search leaves the options its strategy does not need untried.
    let (_, out, _) = plcsynth(&["solve", "examples/timed/lamp.tga", "--states"]);
    assert!(out.contains("?turn_on -> not explored"), "{out}");
    assert!(!out.contains("[removed"), "{out}");
}

#[test]
fn no_zeno_memory_searches_exactly_at_once() {
    // The thesis's memory makes the gear checking machine's search small (thesis: 1 660 states);
    // without it the same verdict needs more states.
    let visited = |extra: &[&str]| {
        let mut args = vec!["solve", "examples/timed/gear_checking.tga", "--json"];
        args.extend_from_slice(extra);
        let (code, out, err) = plcsynth(&args);
        assert_eq!(code, 0, "{err}");
        let json: serde_json::Value = serde_json::from_str(&out).unwrap();
        assert_eq!(json["verdict"], "realizable");
        json["visited"].as_u64().unwrap()
    };
    let (with, without) = (visited(&[]), visited(&["--no-zeno-memory"]));
    assert!(with <= 1660 && without > with, "with the memory {with} states, without {without}");
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
        ("scl-1500", "S7_Optimized_Access := 'TRUE'"),
        ("codesys", "AT %IX124.0"),
        ("il", "JMPCN END_SCAN"),
        ("stl", "JL\tud"),
        ("plcopen", "tc6_0201"),
        ("abb", "interval=\"PT0.010S\""),
    ] {
        let file = dir.join(format!("lamp.{target}"));
        let (code, _, err) =
            plcsynth(&["compile", "examples/timed/lamp.tga", "--target", target, "-o", file.to_str().unwrap()]);
        assert_eq!(code, 0, "{target}: {err}");
        let text = std::fs::read_to_string(&file).unwrap();
        assert!(text.contains(marker), "{target}:\n{text}");
    }
    // TwinCAT writes a directory of files; to standard output each file follows a `==>` line.
    let tc = dir.join("twincat");
    let (code, _, err) =
        plcsynth(&["compile", "examples/timed/lamp.tga", "--target", "twincat", "-o", tc.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    let mut names: Vec<String> =
        std::fs::read_dir(&tc).unwrap().map(|e| e.unwrap().file_name().into_string().unwrap()).collect();
    names.sort();
    assert_eq!(names, ["GVL_IO.TcGVL", "lamp.TcPOU", "lamp_main.TcPOU"]);
    let (_, out, _) = plcsynth(&["compile", "examples/timed/lamp.tga", "--target", "twincat"]);
    assert!(out.starts_with("==> lamp.TcPOU <==\n<?xml") && out.contains("\n==> GVL_IO.TcGVL <==\n"), "{out}");
    let file = dir.join("naive.st");
    let (code, _, err) =
        plcsynth(&["compile", "examples/timed/lamp_naive.tga", "--target", "st", "-o", file.to_str().unwrap()]);
    assert_eq!(code, 1);
    assert!(err.contains("unrealizable; nothing written") && err.contains("!press"), "{err}");
    assert!(!file.exists());
}

#[test]
fn compile_refuses_time_constants_and_addresses_the_target_cannot_hold() {
    let dir = std::env::temp_dir().join(format!("plcsynth-limits-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let spec = |timeunit: &str, bound: u32, io: &str| {
        format!(
            "timeunit {timeunit};\nplant {{\n  automaton A {{ clocks x; nodes a, b;\n    \
             a -> b ?go {{ x in [{bound},inf) }} reset {{ x }}; b -> a ?back; }}\n}}\n\
             plans {{ plan {{ waitfor go; waitfor back; }} }}\n{io}"
        )
    };
    let write = |name: &str, text: &str| {
        let path = dir.join(name);
        std::fs::write(&path, text).unwrap();
        path.to_str().unwrap().to_string()
    };
    // Issue 9, section 2: a product beyond 2^64 used to print its remainder.
    let wrap = write("wrap.tga", &spec("16777216 h", 16_777_215, ""));
    for target in ["st", "il", "scl"] {
        let out_file = dir.join(format!("wrap.{target}"));
        let (code, out, err) = plcsynth(&["compile", &wrap, "--target", target, "-o", out_file.to_str().unwrap()]);
        assert_eq!(code, 2, "{target}: {err}");
        assert!(out.is_empty() && !out_file.exists(), "{target}: nothing is written");
        assert!(
            err.contains(&format!(
                "wrap.tga:4:24: error: time constant 16777215 (1013309855760384000000 ms) exceeds {} TIME (at most \
                 2147483647 ms = 24d20h31m23s647ms) for target {target}",
                if target == "scl" { "S7" } else { "IEC" }
            )),
            "{err}"
        );
        assert!(
            err.contains("4 |     a -> b ?go { x in [16777215,inf) }") && err.contains("(`timeunit` at 1:1)"),
            "{err}"
        );
        assert!(!err.contains("T#17185675780068212736MS"), "{err}");
    }
    // 16777215 s does not fit a 32-bit TIME; 10000 s does, but not S5TIME.
    let (code, _, err) = plcsynth(&["compile", &write("time.tga", &spec("1s", 16_777_215, "")), "--target", "st"]);
    assert_eq!(code, 2);
    assert!(err.contains("time.tga:4:24: error: time constant 16777215 (16777215000 ms) exceeds IEC TIME"), "{err}");
    let s5 = write("s5.tga", &spec("1s", 10_000, ""));
    let (code, _, err) = plcsynth(&["compile", &s5, "--target", "stl"]);
    assert_eq!(code, 2);
    assert!(
        err.contains("s5.tga:4:24: error: time constant 10000 (10000000 ms) exceeds S5TIME (at most 9990000 ms = 2h46m30s) for target stl"),
        "{err}"
    );
    let (code, out, _) = plcsynth(&["compile", &s5, "--target", "st"]);
    assert_eq!(code, 0);
    assert!(out.contains("ET >= T#10000000MS"), "{out}");
    // io addresses are range-checked by every command.
    let io = write("io.tga", &spec("1s", 1, "io { go = %QX99999999999999999999.9; }\n"));
    for command in ["solve", "compile"] {
        let (code, _, err) = plcsynth(&[command, &io]);
        assert_eq!(code, 2, "{command}");
        assert!(err.contains("io.tga:7:14: error: byte number 99999999999999999999 is out of range"), "{err}");
        assert!(err.contains("io.tga:7:35: error: bit number 9 is out of range"), "{err}");
    }
}

/// A specification that stops time is solved, and the warning says where, on stderr.
#[test]
fn solve_warns_where_time_cannot_pass() {
    let dir = std::env::temp_dir().join(format!("plcsynth-cli-timelock-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let f = dir.join("zeno.tga");
    std::fs::write(
        &f,
        "plant {\n  automaton m {\n    nodes a, b;\n    a -> b ?x instant;\n    b -> a ?y instant;\n  }\n}\nplans { plan { waitfor x; waitfor y; } }\n",
    )
    .unwrap();
    let (code, out, err) = plcsynth(&["solve", f.to_str().unwrap()]);
    assert_eq!(code, 0, "{out}{err}");
    assert!(out.contains("realizable"), "{out}");
    assert!(
        err.contains("zeno.tga:4:5: warning: time cannot pass in the cycle `a -> b ?x`, `b -> a ?y` of `m`"),
        "{err}"
    );
    assert!(err.contains("4 |     a -> b ?x instant;"), "{err}");
}

#[test]
fn compile_writes_the_io_table_and_takes_the_stl_and_plcopen_options() {
    let dir = std::env::temp_dir().join(format!("plcsynth-io-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let csv = dir.join("lamp_io.csv");
    let sdf = dir.join("lamp_tags.sdf");
    let (code, _, err) =
        plcsynth(&["compile", "examples/timed/lamp.tga", "--target", "st", "--io-table", csv.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    let table = std::fs::read_to_string(&csv).unwrap();
    assert!(table.starts_with("address,type,symbol,direction,meaning\r\n%IX124.0,BOOL,press,input,"), "{table}");
    let (code, _, err) =
        plcsynth(&["compile", "examples/timed/lamp.tga", "--target", "scl-1500", "--io-table", sdf.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    assert!(std::fs::read_to_string(&sdf).unwrap().starts_with("\"press\",\"I 124.0\",\"BOOL\","));
    // The CODESYS mapping list, by --io-format whatever the file's name.
    let mapping = dir.join("lamp_mapping.csv");
    let (code, _, err) = plcsynth(&[
        "compile",
        "examples/timed/lamp.tga",
        "--target",
        "codesys",
        "--io-table",
        mapping.to_str().unwrap(),
        "--io-format",
        "codesys",
    ]);
    assert_eq!(code, 0, "{err}");
    let table = std::fs::read_to_string(&mapping).unwrap();
    assert!(
        table.starts_with("Variable;Address;Type;Direction;Description\r\nGVL_IO.press;%IX124.0;BOOL;input;"),
        "{table}"
    );
    let (code, _, err) = plcsynth(&["compile", "examples/timed/lamp.tga", "--target", "st", "--io-format", "codesys"]);
    assert_eq!(code, 2, "--io-format needs --io-table: {err}");
    // STL: block numbers and marker byte; refused for other targets.
    let (code, out, err) = plcsynth(&[
        "compile",
        "examples/timed/lamp.tga",
        "--target",
        "stl",
        "--ob",
        "1",
        "--fb",
        "12",
        "--marker-byte",
        "30",
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(
        out.contains("FUNCTION_BLOCK FB 12") && out.contains("\tL\tMB 30\n") && out.contains("ORGANIZATION_BLOCK OB 1")
    );
    let (code, out, err) = plcsynth(&["compile", "examples/timed/lamp.tga", "--target", "st", "--marker-byte", "3"]);
    assert_eq!((code, out.as_str()), (2, ""), "{err}");
    assert!(err.contains("--marker-byte applies to --target stl only"), "{err}");
    let (code, _, err) = plcsynth(&["compile", "examples/timed/lamp.tga", "--target", "stl", "--fb", "0"]);
    assert_eq!(code, 2, "there is no FB 0: {err}");
    // A clash with a user marker is located in the specification.
    let spec = dir.join("marker.tga");
    let source = std::fs::read_to_string("examples/timed/lamp.tga").unwrap().replace("set %Q125.6", "set %M30.1");
    std::fs::write(&spec, &source).unwrap();
    let (code, _, err) = plcsynth(&["compile", spec.to_str().unwrap(), "--target", "stl", "--marker-byte", "30"]);
    assert_eq!(code, 2, "{err}");
    let at = source.find("%M30.1").unwrap();
    let line = source[..at].lines().count();
    assert!(
        err.contains(&format!("marker.tga:{line}:")) && err.contains("in MB 30, which holds the program position"),
        "{err}"
    );
    // PLCopen: the creation time from SOURCE_DATE_EPOCH.
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_plcsynth"))
        .args(["compile", "examples/timed/lamp.tga", "--target", "plcopen"])
        .env("SOURCE_DATE_EPOCH", "1700000000")
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .unwrap();
    let xml = String::from_utf8_lossy(&out.stdout);
    assert!(xml.contains("creationDateTime=\"2023-11-14T22:13:20\""), "{xml}");
    // Without it, the current time (not the epoch).
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_plcsynth"))
        .args(["compile", "examples/timed/lamp.tga", "--target", "plcopen"])
        .env_remove("SOURCE_DATE_EPOCH")
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .unwrap();
    let xml = String::from_utf8_lossy(&out.stdout);
    assert!(xml.contains("creationDateTime=\"20") && !xml.contains("1970-01-01"), "{xml}");
}

#[test]
fn a_scan_time_turns_the_verdict_into_implementability() {
    // Without a scan time the verdict says what it assumes.
    let (code, out, _) = plcsynth(&["solve", "examples/timed/lamp.tga"]);
    assert_eq!(code, 0);
    assert!(out.contains("realizable") && out.contains("reacts in zero time"), "{out}");
    // The thesis's lamp is realizable only with zero latency: exit 1, with the counter-play.
    let (code, out, _) = plcsynth(&["solve", "examples/timed/lamp.tga", "--scan", "10ms"]);
    assert_eq!(code, 1, "{out}");
    assert!(out.contains("not implementable at 10 ms (realizable with a zero-time controller)"), "{out}");
    assert!(out.contains("scan time: not implementable at any scan time tried, down to 1 ms"), "{out}");
    assert!(out.contains("why a PLC with a 10 ms scan cannot do it") && out.contains("!press_settled"), "{out}");
    // The example that declares `scan 10 ms;` is implementable, with its bound.
    let (code, out, _) = plcsynth(&["solve", "examples/timed/lamp_scan.tga"]);
    assert_eq!(code, 0, "{out}");
    assert!(out.contains("implementable at 10 ms") && out.contains("implementable at 14 ms, not at 15 ms"), "{out}");
    // The flag overrides the declaration.
    let (code, out, _) = plcsynth(&["solve", "examples/timed/lamp_scan.tga", "--scan", "0.02s"]);
    assert_eq!(code, 1, "{out}");
    assert!(out.contains("not implementable at 20 ms"), "{out}");
    let (code, out, _) = plcsynth(&["solve", "examples/timed/lamp_scan.tga", "--json"]);
    assert_eq!(code, 0);
    let v: serde_json::Value = serde_json::from_str(out.trim()).unwrap();
    assert_eq!(v["semantics"], "zero-time controller");
    assert_eq!(v["scan"]["scan_ms"], 10);
    assert_eq!(v["scan"]["implementable"], true);
    assert_eq!(v["scan"]["bound"]["works"], 14);
    assert_eq!(v["scan"]["bound"]["fails"], 15);
    // Unrealizable stays unrealizable, said as such.
    let (code, out, _) = plcsynth(&["solve", "examples/timed/lamp_naive.tga", "--scan", "10ms"]);
    assert_eq!(code, 1);
    assert!(out.contains("unrealizable (even with a zero-time controller)"), "{out}");
    // A bad duration is refused by the argument parser.
    for bad in ["0ms", "1.5ms", "fast"] {
        let (code, _, err) = plcsynth(&["solve", "examples/timed/lamp.tga", "--scan", bad]);
        assert_eq!(code, 2, "{bad}: {err}");
        assert!(err.contains("--scan"), "{bad}: {err}");
    }
}

#[test]
fn compile_at_a_scan_time_writes_nothing_for_a_controller_no_plc_can_run() {
    let (code, out, err) = plcsynth(&["compile", "examples/timed/lamp.tga", "--target", "st", "--scan", "10ms"]);
    assert_eq!(code, 1, "{out}");
    assert!(out.is_empty(), "{out}");
    assert!(err.contains("not implementable at 10 ms; nothing written") && err.contains("!press_settled"), "{err}");
    let (code, out, err) = plcsynth(&["compile", "examples/timed/lamp_scan.tga", "--target", "st"]);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("FUNCTION_BLOCK"), "{out}");
    // At a scan time the code is run against the plant before it is written.
    assert!(err.contains("checked at 10 ms: 20 runs of 2000 scans") && err.contains("no failure"), "{err}");
}

#[test]
fn compile_at_a_scan_time_refuses_code_that_fails_in_real_time() {
    // The watchdog's scan strategy decides by how long it has waited, which no input shows: its
    // code follows the zero-time strategy with its scans' latency, and at 250 ms (implementable)
    // it sends `stop` in a scan in which the run ended by itself.
    let args = ["compile", "tests/fixtures/timed/watchdog.tga", "--target", "stl", "--scan", "250ms"];
    let (code, out, err) = plcsynth(&args);
    assert_eq!(code, 1, "{err}");
    assert!(out.is_empty(), "{out}");
    assert!(err.contains("code from the zero-time strategy") && err.contains("which the PLC does not read"), "{err}");
    assert!(err.contains("the generated code fails at 250 ms in real-time run"), "{err}");
    assert!(err.contains("RequestRefused") && err.contains("scan "), "{err}");
    // The check can be skipped.
    let (code, out, _) = plcsynth(&[&args[..], &["--check-runs", "0"]].concat());
    assert_eq!(code, 0);
    assert!(out.contains("ORGANIZATION_BLOCK"), "{out}");
    // gripper_guard has a state guard: its code follows the scan strategy and waits for the
    // guard before the guarded request. The game assumes the guard holds when checked; the
    // checker lets it come up to a scan late, which at 500 ms costs a plan its bound (run 8),
    // and the note says so. At 100 ms it holds.
    let (code, _, err) = plcsynth(&["compile", "examples/timed/gripper_guard.tga", "--scan", "500ms"]);
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("code from the scan strategy at 500 ms") && err.contains("fails at 500 ms"), "{err}");
    assert!(err.contains("assumes that a state guard holds whenever the code checks it"), "{err}");
    let args = ["compile", "examples/timed/gripper_guard.tga", "--scan", "100ms", "--target", "program"];
    let (code, out, err) = plcsynth(&args);
    assert_eq!(code, 0, "{err}");
    assert!(err.contains("code from the scan strategy at 100 ms") && err.contains("checked at 100 ms"), "{err}");
    assert!(out.contains("WAITUNTIL (gear_is_present);\n") && out.contains("DO (moveto_closed)"), "{out}");
}

#[test]
fn compile_at_a_scan_time_follows_the_scan_strategy() {
    // hardware_xyz is implementable up to 500 ms (tests/timed_scan.rs); the code of its
    // zero-time strategy missed a plan bound at 495 ms, the scan strategy's holds.
    let args = ["compile", "examples/timed/hardware_xyz.tga", "--target", "stl", "--scan", "495ms"];
    let (code, out, err) = plcsynth(&args);
    assert_eq!(code, 0, "{err}");
    assert!(err.contains("code from the scan strategy at 495 ms") && err.contains("one decision per scan"), "{err}");
    assert!(err.contains("checked at 495 ms: 20 runs of 2000 scans") && err.contains("no failure"), "{err}");
    assert!(out.contains("ORGANIZATION_BLOCK"), "{out}");
    // The intermediate program at a scan time is the scan strategy's: dispatch, then decide.
    let (code, out, err) = plcsynth(&["compile", "examples/timed/lamp_scan.tga", "--check-runs", "0"]);
    assert_eq!(code, 0, "{err}");
    assert!(out.starts_with(" 0 : GOTO ") && out.contains("IF (press) THEN GOTO"), "{out}");
    assert!(out.contains("DO (turn_on)") && out.contains("DO (turn_off)"), "{out}");
}
