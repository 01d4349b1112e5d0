//! PLC code checked by independent implementations: blark parses the Structured Text (plain,
//! CODESYS and SCL), xmllint validates PLCopen XML against the TC6 v2.01 schema, and awlsim loads
//! and runs the S7 STL. The checkers are installed by `scripts/python-checkers.sh` (`make test`
//! runs it); without them these tests fail and say so.

use plcsynth::plc::{self, Target};
use plcsynth::program;
use plcsynth::timed::{compile, solve::SolveOptions, synthesize};
use std::path::{Path, PathBuf};
use std::process::Command;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn venv_tool(name: &str) -> PathBuf {
    let path = root().join(".venv/bin").join(name);
    assert!(path.exists(), "{} is missing: run `bash scripts/python-checkers.sh` (make test does)", path.display());
    path
}

fn generate(example: &str, target: Target) -> String {
    let source = std::fs::read_to_string(root().join(format!("examples/timed/{example}.tga"))).unwrap();
    let (game, _) = compile(&source).unwrap();
    let s = synthesize(&game, &SolveOptions::default(), &mut |_| true);
    let p = program::controller(&game, &s).expect("realizable");
    plc::generate(&game, &p, target, example, &source).expect("the examples' constants fit every target")
}

/// A controller that waits `bound` units of `timeunit` before its request on `output`, compiled
/// for `target`.
fn generate_waiting(timeunit: &str, bound: u32, output: &str, target: Target) -> String {
    let source = format!(
        "timeunit {timeunit};\nplant {{ automaton A {{ clocks x; nodes a, b;\n  \
         a -> b ?go {{ x in [{bound},inf) }} reset {{ x }}; b -> a ?back; }} }}\n\
         plans {{ plan {{ waitfor go; waitfor back; }} }}\nio {{ go = {output}; }}\n"
    );
    let (game, _) = compile(&source).unwrap();
    let s = synthesize(&game, &SolveOptions::default(), &mut |_| true);
    let p = program::controller(&game, &s).expect("realizable");
    plc::generate(&game, &p, target, "waiting", &source).expect("the constant fits")
}

fn scratch(name: &str, text: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("plcsynth-plc-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

fn run(cmd: &mut Command) -> (bool, String) {
    let out = cmd.output().unwrap_or_else(|e| panic!("cannot run {cmd:?}: {e}"));
    (out.status.success(), format!("{}{}", String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr)))
}

const EXAMPLES: &[&str] =
    &["lamp", "gear_checking", "round_table_2", "two_robots_14", "robot_arm", "gripper_guard", "hardware_xyz"];

fn blark(path: &Path) {
    let (ok, out) = run(Command::new(venv_tool("blark")).arg("parse").arg(path));
    assert!(
        ok,
        "blark rejects {}:\n{}\n{}",
        path.display(),
        out.lines().rev().take(12).collect::<Vec<_>>().join("\n"),
        std::fs::read_to_string(path).unwrap()
    );
}

/// Checks `text`, the code of `example` for `target`, with the target's independent checker.
/// Every target needs an arm here, so a new target cannot go unchecked by accident.
fn check(target: Target, example: &str, text: &str) {
    match target {
        Target::St | Target::Codesys => blark(&scratch(&format!("{example}_{target}.st"), text)),
        Target::Scl => {
            // blark reads TwinCAT-style IEC ST; the TIA Portal source lines (block attribute,
            // VERSION and BEGIN) are Siemens-only and are removed before parsing. Everything
            // else is checked.
            assert!(text.contains("VERSION : 0.1\n") && text.contains("BEGIN\n"), "TIA source layout");
            let stripped: String = text
                .lines()
                .filter(|l| !(l.starts_with("{ S7_Optimized_Access") || l.starts_with("VERSION :") || *l == "BEGIN"))
                .map(|l| format!("{l}\n"))
                .collect();
            blark(&scratch(&format!("{example}_scl.st"), &stripped));
        }
        Target::Plcopen => {
            let schema = root().join("../shared/schemas/tc6_xml_v201.xsd");
            assert!(schema.exists(), "the PLCopen schema is expected at {}", schema.display());
            let path = scratch(&format!("{example}.xml"), text);
            let (ok, out) = run(Command::new("xmllint").arg("--noout").arg("--schema").arg(&schema).arg(&path));
            assert!(ok, "{example}: {out}");
        }
        Target::Stl => {
            let path = scratch(&format!("{example}.awl"), text);
            let (ok, out) =
                run(Command::new(venv_tool("python")).arg(root().join("tests/checkers/awl_run.py")).arg(&path));
            assert!(ok, "{example}: awlsim fails:\n{out}\n{text}");
        }
        // No IL implementation is installed: the IL has the ST's structure (ST is checked) and
        // the STL's control flow (run in awlsim).
        Target::Il => {}
    }
}

#[test]
fn every_target_passes_its_checker_on_every_example() {
    // One thread per target: the checkers are separate processes.
    std::thread::scope(|scope| {
        for target in Target::ALL {
            scope.spawn(move || {
                for example in EXAMPLES {
                    check(target, example, &generate(example, target));
                }
            });
        }
    });
}

#[test]
fn the_lamp_follows_the_button_cycle_by_cycle_in_awlsim() {
    let path = scratch("lamp_run.awl", &generate("lamp", Target::Stl));
    // Bit 0 of IB 124 is the button, bit 6 of QB 125 the lamp (the thesis's lookup table).
    let script = "I124=0 ?Q125; I124=1 ?Q125; I124=1 ?Q125; I124=0 ?Q125; I124=0 ?Q125; I124=1 ?Q125; I124=0 ?Q125";
    let (ok, out) =
        run(Command::new(venv_tool("python")).arg(root().join("tests/checkers/awl_run.py")).arg(&path).arg(script));
    assert!(ok, "{out}");
    let lamp: Vec<bool> = out.lines().map(|l| l.trim() == "Q125=64").collect();
    assert_eq!(lamp, [false, true, true, false, false, true, false], "{out}");
}

#[test]
fn the_lamp_in_stl_is_the_thesis_listing_with_a_cycle_end_after_each_request() {
    let text = generate("lamp", Target::Stl);
    let body: Vec<String> = text
        .lines()
        .skip_while(|l| !l.starts_with("BEGIN"))
        .filter(|l| !l.contains("NOP\t0\t//"))
        .map(|l| l.split_whitespace().collect::<Vec<_>>().join(" "))
        .collect();
    // Peter 2005, 6.7.2, with `L 1; T MB 0; JU end` after `S Q 125.6` (the cycle ends after a
    // request) and the out-of-range entry of the jump list restarting the program.
    let expected = [
        "BEGIN",
        "L MB 0",
        "JL ud",
        "JU aaaa",
        "JU aaac",
        "ud: L 0",
        "T MB 0",
        "JU aaaa",
        "aaaa: NOP 0 // WAITUNTIL (press)",
    ];
    assert_eq!(body[..8], expected[..8], "{text}");
    let joined = body.join("\n");
    for fragment in [
        "L 0\nT MB 0\nA I 124.0\nJCN end\nSET\nS Q 125.6\nL 1\nT MB 0\nJU end",
        "L 1\nT MB 0\nAN I 124.0\nJCN end\nSET\nR Q 125.6\nL 0\nT MB 0\nJU end",
        "end: NOP 0\nEND_ORGANIZATION_BLOCK",
    ] {
        assert!(joined.contains(fragment), "missing\n{fragment}\nin\n{joined}");
    }
}

#[test]
fn every_file_names_plcsynth_its_version_and_the_spec_hash() {
    let source = std::fs::read_to_string(root().join("examples/timed/lamp.tga")).unwrap();
    let hash = plc::source_hash(&source);
    for target in Target::ALL {
        let text = generate("lamp", target);
        assert!(
            text.lines().take(4).any(|l| l.contains(&format!("plcsynth {}", env!("CARGO_PKG_VERSION")))),
            "{target:?}"
        );
        assert!(text.contains(&hash), "{target:?}");
    }
}

#[test]
fn without_io_the_signals_are_named_after_the_messages() {
    let st = generate("gear_checking", Target::St);
    for name in ["loaded : BOOL", "reached_up : BOOL", "moveto_up : BOOL", "load : BOOL"] {
        assert!(st.contains(name), "{name} in\n{st}");
    }
    assert!(!st.contains("PROGRAM"), "no wiring program without bindings");
    let il = generate("gear_checking", Target::Il);
    assert!(il.contains("JMPC S0") && il.contains("ST step") && il.contains("RET"), "{il}");
}

#[test]
fn timers_restart_where_the_program_resets_a_clock() {
    let st = generate("two_robots_14", Target::St);
    // The robots' arms are timed: every clock the program reads is a TON restarted at its resets.
    assert!(st.contains(": TON;"), "{st}");
    assert!(st.contains("(IN := FALSE"), "{st}");
    assert!(st.contains(".ET >="), "{st}");
}

#[test]
fn the_largest_constants_of_each_target_pass_the_checkers() {
    // IEC TIME: threshold 2147483392 ms, preset 2^31 − 128 ms; CODESYS TIME: preset 2^32 − 1 ms.
    let st = generate_waiting("128ms", 16_777_214, "%Q65535.7", Target::St);
    assert!(st.contains("PT := T#2147483520MS") && st.contains("%QX65535.7"), "{st}");
    blark(&scratch("limit_st.st", &st));
    let codesys = generate_waiting("257ms", 16_711_934, "%Q65535.7", Target::Codesys);
    assert!(codesys.contains("PT := T#4294967295MS"), "{codesys}");
    blark(&scratch("limit_codesys.st", &codesys));
    let schema = root().join("../shared/schemas/tc6_xml_v201.xsd");
    let xml = scratch("limit.xml", &generate_waiting("128ms", 16_777_214, "%Q65535.7", Target::Plcopen));
    let (ok, out) = run(Command::new("xmllint").arg("--noout").arg("--schema").arg(&schema).arg(&xml));
    assert!(ok, "{out}");
    // S5TIME: 999 × 10 s; awlsim loads the literal and runs the block (its process image is
    // smaller than 64 KB, hence a low output byte).
    let stl = generate_waiting("10s", 999, "%Q12.7", Target::Stl);
    assert!(stl.contains("L\tS5T#2H46M30S") && stl.contains("Q 12.7"), "{stl}");
    let path = scratch("limit.awl", &stl);
    let (ok, out) = run(Command::new(venv_tool("python")).arg(root().join("tests/checkers/awl_run.py")).arg(&path));
    assert!(ok, "awlsim fails:\n{out}\n{stl}");
}
