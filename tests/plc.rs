//! PLC code checked by independent implementations: blark parses the Structured Text (plain,
//! CODESYS, both SCL dialects) and TwinCAT's `.TcPOU`/`.TcGVL` files (whose XML xmllint checks
//! for well-formedness), xmllint validates PLCopen XML against the TC6 v2.01 schema, and awlsim
//! loads and runs the S7 STL. The checkers are installed by `scripts/python-checkers.sh` (`make test`
//! runs it); without them these tests fail and say so.

use crate::common;

use plcsynth::diag::Diagnostic;
use plcsynth::plc::{self, Code, Options, OutputFile, Target};
use plcsynth::timed::program;
use plcsynth::timed::{compile, solve::Config, synthesize};
use std::path::{Path, PathBuf};
use std::process::Command;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

use common::{scl_for_blark, venv_tool};

fn example(name: &str) -> String {
    std::fs::read_to_string(root().join(format!("examples/timed/{name}.tga"))).unwrap()
}

/// The code model of `source` for `target`, or the diagnostics.
fn build(source: &str, name: &str, target: Target, options: &Options) -> Result<Code, Vec<Diagnostic>> {
    let (game, _) = compile(source).unwrap();
    let s = synthesize(&game, &Config::default(), &mut |_| true);
    let p = program::controller(&game, &s).expect("realizable");
    plc::build(&game, &p, target, name, source, options)
}

fn generate(example_name: &str, target: Target) -> String {
    let code = build(&example(example_name), example_name, target, &Options::default())
        .expect("the examples' constants fit every target");
    plc::render(&code, target, &Options::default())
}

fn files(example_name: &str, target: Target) -> Vec<OutputFile> {
    let code = build(&example(example_name), example_name, target, &Options::default()).expect("fits");
    plc::render_files(&code, target, &Options::default())
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
    let s = synthesize(&game, &Config::default(), &mut |_| true);
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
        Target::Scl | Target::Scl1500 => blark(&scratch(&format!("{example}_{target}.st"), &scl_for_blark(text))),
        Target::Twincat => {
            for file in files(example, Target::Twincat) {
                let path = scratch(&format!("{example}_{}", file.name), &file.text);
                let (ok, out) = run(Command::new("xmllint").arg("--noout").arg(&path));
                assert!(ok, "{}: not well-formed XML: {out}", file.name);
                // blark reads TwinCAT's files itself and parses the ST in their CDATA.
                blark(&path);
            }
        }
        Target::Plcopen | Target::Abb => {
            let schema = root().join("../shared/schemas/tc6_xml_v201.xsd");
            assert!(schema.exists(), "the PLCopen schema is expected at {}", schema.display());
            let path = scratch(&format!("{example}_{target}.xml"), text);
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

/// Every target's code of every example passes its independent checker (blark on CODESYS, SCL
/// and TwinCAT: of the sampled examples, unless `PLCSYNTH_ALL_DIALECTS=1`).
#[test]
fn every_target_passes_its_checker_on_every_example() {
    // blark costs about a second to start: its files (the ST dialects' and TwinCAT's) are parsed
    // at the end, by two processes (tests/checkers/blark_many.py) instead of one each. The other
    // checkers run per target, one thread each.
    let for_blark = std::sync::Mutex::new(Vec::new());
    // The ST dialects print one body (`print::st::unit`) and differ in their declarations and
    // timers: `make test` has blark parse CODESYS, both SCL dialects and TwinCAT's files (the IEC
    // ST body in XML) for the examples that show every construct (pulses and latches, timers),
    // IEC ST for all of them;
    // `make test-long` (`PLCSYNTH_ALL_DIALECTS=1`) every dialect of every example (blark parses
    // about 80 lines a second: the other dialects of the five other examples took 30 CPU-s).
    let all_dialects = std::env::var("PLCSYNTH_ALL_DIALECTS").is_ok_and(|v| v == "1");
    std::thread::scope(|scope| {
        for target in Target::ALL {
            let for_blark = &for_blark;
            scope.spawn(move || {
                for example in EXAMPLES {
                    let sampled = all_dialects || ["lamp", "hardware_xyz"].contains(example);
                    if matches!(target, Target::Codesys | Target::Scl | Target::Scl1500) && !sampled {
                        continue;
                    }
                    let text = generate(example, target);
                    let path = match target {
                        Target::St | Target::Codesys => scratch(&format!("{example}_{target}.st"), &text),
                        Target::Scl | Target::Scl1500 => {
                            scratch(&format!("{example}_{target}.st"), &scl_for_blark(&text))
                        }
                        // Well-formed XML here; blark reads the files and parses their ST below
                        // (the IEC ST body inside: of the sampled examples in `make test`).
                        Target::Twincat => {
                            for file in files(example, Target::Twincat) {
                                let path = scratch(&format!("{example}_{}", file.name), &file.text);
                                let (ok, out) = run(Command::new("xmllint").arg("--noout").arg(&path));
                                assert!(ok, "{}: not well-formed XML: {out}", file.name);
                                if sampled {
                                    for_blark.lock().unwrap().push(path);
                                }
                            }
                            continue;
                        }
                        _ => {
                            check(target, example, &text);
                            continue;
                        }
                    };
                    for_blark.lock().unwrap().push(path);
                }
            });
        }
    });
    common::blark_all(&venv_tool("python"), &root(), &for_blark.into_inner().unwrap());
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
    // The program wires the block to a global variable list that the PLC tool maps to its I/O:
    // unlocated in IEC and CODESYS, `AT %I*` / `AT %Q*` in TwinCAT.
    assert!(st.contains("PROGRAM gear_checking_main") && st.contains("VAR_GLOBAL\n    loaded : BOOL;"), "{st}");
    assert!(!st.contains('%'), "no address without bindings:\n{st}");
    let twincat = generate("gear_checking", Target::Twincat);
    assert!(twincat.contains("loaded AT %I* : BOOL;") && twincat.contains("load AT %Q* : BOOL;"), "{twincat}");
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

/// A spec whose messages are named like the block, the instance, internal variables, keywords
/// and each other up to case, with the io section `io`.
fn clash_spec(io: &str) -> String {
    format!(
        "plant {{ automaton A {{ nodes a, b, c, d;\n  a -> b ?Ctrl; b -> c !lamp; c -> d !step; d -> a ?TON; }} }}\n\
         plans {{ plan {{ waitfor Ctrl; waitfor TON; }} }}\n{io}"
    )
}

#[test]
fn variables_are_named_after_the_messages_and_addresses_appear_only_in_the_mapping() {
    let st = generate("lamp", Target::St);
    let (globals, rest) = st.split_once("FUNCTION_BLOCK lamp\n").unwrap();
    let (block, program) = rest.split_once("END_FUNCTION_BLOCK").unwrap();
    assert!(block.contains("press : BOOL; (* press, NOT release *)"), "{st}");
    assert!(block.contains("turn_on : BOOL; (* turn_on sets, turn_off resets *)"), "{st}");
    assert!(block.contains("IF NOT press THEN"), "{st}");
    assert!(!block.contains('%') && !st.contains("I124_0"), "no address in the block:\n{st}");
    // The located variables in the global variable list, the program reads and writes them.
    assert!(globals.contains("press AT %IX124.0 : BOOL;") && globals.contains("turn_on AT %QX125.6 : BOOL;"), "{st}");
    assert!(program.contains("ctrl(press := press);\nturn_on := ctrl.turn_on;"), "{st}");
    assert!(!program.contains('%'), "{st}");
    // CODESYS: the located variables in the global variable list, the program reads it.
    let codesys = generate("lamp", Target::Codesys);
    assert!(codesys.contains("{attribute 'qualified_only'}\nVAR_GLOBAL\n    press AT %IX124.0 : BOOL;"), "{codesys}");
    assert!(codesys.contains("ctrl(press := GVL_IO.press);\nGVL_IO.turn_on := ctrl.turn_on;"), "{codesys}");
    // SCL: PLC tags, never %I/%Q.
    for target in [Target::Scl, Target::Scl1500] {
        let scl = generate("lamp", target);
        assert!(!scl.contains('%'), "{target}:\n{scl}");
        assert!(scl.contains("ctrl(press := \"press\");\n\"turn_on\" := ctrl.turn_on;"), "{target}:\n{scl}");
    }
    let scl = generate("lamp", Target::Scl);
    assert!(!scl.contains("S7_Optimized_Access") && scl.contains(": TON;") || !scl.contains("t_"), "{scl}");
    let scl1500 = generate("gripper_guard", Target::Scl1500);
    assert!(scl1500.contains("{ S7_Optimized_Access := 'TRUE' }"), "{scl1500}");
}

#[test]
fn names_never_clash_with_keywords_the_block_its_instance_or_each_other() {
    let source = clash_spec("");
    let code = build(&source, "lamp", Target::St, &Options::default()).unwrap();
    let names: Vec<&str> = code.variables().map(|(v, _)| v.symbol.as_str()).collect();
    // `Ctrl` meets the instance `ctrl`, `step` the position variable, `TON` the timer type,
    // `lamp` the block (named after the file).
    for name in &names {
        for taken in ["ctrl", "step", "scan_done", "ton", "lamp", "lamp_main", "gvl_io"] {
            assert!(!name.eq_ignore_ascii_case(taken), "{name} in {names:?}");
        }
    }
    for name in ["Ctrl_2", "step_sig", "TON_sig", "lamp_2"] {
        assert!(names.contains(&name), "{name} in {names:?}");
    }
    let text = plc::render(&code, Target::St, &Options::default());
    blark(&scratch("clash.st", &text));
}

#[test]
fn a_quoted_tag_keeps_its_quotes_in_siemens_code_and_is_refused_located_elsewhere() {
    let source = clash_spec("io { Ctrl = \"Lamp On\"; lamp = \"lamp_ok\"; step = %I0.1; TON = %Q0.1; }\n");
    for target in [Target::Scl, Target::Scl1500] {
        let text = plc::render(&build(&source, "x", target, &Options::default()).unwrap(), target, &Options::default());
        assert!(text.contains("\"Lamp On\" := ctrl.Ctrl_2;"), "{target}:\n{text}");
        blark(&scratch(&format!("quoted_{target}.st"), &scl_for_blark(&text)));
    }
    let stl =
        plc::render(&build(&source, "x", Target::Stl, &Options::default()).unwrap(), Target::Stl, &Options::default());
    assert!(stl.contains("\"Lamp On\""), "{stl}");
    for target in [Target::St, Target::Codesys, Target::Twincat, Target::Il, Target::Plcopen] {
        let diags = build(&source, "x", target, &Options::default()).expect_err("not an IEC identifier");
        assert_eq!(diags.len(), 1, "{diags:#?}");
        let at = source.find("\"Lamp On\"").unwrap();
        let line = source[..at].lines().count() as u32;
        assert_eq!(diags[0].line, line, "{target}: {diags:#?}");
        assert!(diags[0].message.contains("\"Lamp On\"` is not an IEC identifier"), "{}", diags[0].message);
    }
    // `%I0.1` and `%IX0.1` are one signal.
    let source = clash_spec("io { lamp = %I0.1; step = not %IX0.1; }\n");
    let code = build(&source, "x", Target::St, &Options::default()).unwrap();
    assert_eq!(code.inputs.len(), 1, "{:?}", code.inputs);
    assert_eq!(code.inputs[0].comment, "lamp, NOT step");
    // A quoted name that is an identifier is taken as it is.
    let source = clash_spec("io { lamp = \"lamp_ok\"; }\n");
    let st =
        plc::render(&build(&source, "x", Target::St, &Options::default()).unwrap(), Target::St, &Options::default());
    assert!(st.contains("ctrl(lamp := lamp_ok"), "{st}");
    // A member of a data block: SCL quotes the block, the IEC dialects write it as it is.
    let source = clash_spec("io { lamp = GVL.lamp_on; }\n");
    for (target, call) in [(Target::Scl, "ctrl(lamp := \"GVL\".lamp_on"), (Target::St, "ctrl(lamp := GVL.lamp_on")] {
        let text = plc::render(&build(&source, "x", target, &Options::default()).unwrap(), target, &Options::default());
        assert!(text.contains(call), "{target}:\n{text}");
    }
}

#[test]
fn no_two_targets_print_the_same_bytes_and_every_file_has_the_provenance_header() {
    for name in ["lamp", "gear_checking"] {
        let texts: Vec<(Target, String)> = Target::ALL.into_iter().map(|t| (t, generate(name, t))).collect();
        for (i, (a, x)) in texts.iter().enumerate() {
            for (b, y) in &texts[i + 1..] {
                assert_ne!(x, y, "{name}: {a} and {b} print the same bytes");
            }
        }
        let hash = plc::source_hash(&example(name));
        for target in Target::ALL {
            for file in files(name, target) {
                assert!(file.text.contains(&hash), "{target} {}", file.name);
                assert!(file.name.starts_with(name) || file.name.starts_with("GVL_IO"), "{}", file.name);
            }
        }
    }
    let names: Vec<String> = files("lamp", Target::Twincat).into_iter().map(|f| f.name).collect();
    assert_eq!(names, ["lamp.TcPOU", "lamp_main.TcPOU", "GVL_IO.TcGVL"]);
    let names: Vec<String> = files("gear_checking", Target::Twincat).into_iter().map(|f| f.name).collect();
    assert_eq!(names, ["gear_checking.TcPOU", "gear_checking_main.TcPOU", "GVL_IO.TcGVL"]);
    let gvl = &files("gear_checking", Target::Twincat)[2].text;
    assert!(gvl.contains("loaded AT %I* : BOOL;") && gvl.contains("load AT %Q* : BOOL;"), "{gvl}");
}

#[test]
fn plcopen_holds_a_program_a_task_the_mapped_io_and_the_creation_time() {
    let options = Options { created_unix: 1_700_000_000, ..Options::default() };
    let code = build(&example("lamp"), "lamp", Target::Plcopen, &options).unwrap();
    let xml = plc::render(&code, Target::Plcopen, &options);
    for fragment in [
        "creationDateTime=\"2023-11-14T22:13:20\"",
        "<pou name=\"lamp_main\" pouType=\"program\">",
        "<task name=\"task_main\" interval=\"T#10ms\" priority=\"1\">",
        "<pouInstance name=\"lamp_main_instance\" typeName=\"lamp_main\"/>",
        "<variable name=\"press\" address=\"%IX124.0\">",
        "<variable name=\"turn_on\" address=\"%QX125.6\">",
        "ctrl(press := press);\nturn_on := ctrl.turn_on;",
    ] {
        assert!(xml.contains(fragment), "{fragment} in\n{xml}");
    }
    check(Target::Plcopen, "lamp_created", &xml);
}

/// The ABB dialect (Eclipse ESCET's conventions for ABB's Automation Builder) differs from plain
/// TC6 where named here, and both validate against the TC6 schema.
#[test]
fn abb_writes_the_task_interval_in_iso_8601_and_the_io_at_the_configuration() {
    let options = Options { created_unix: 1_700_000_000, ..Options::default() };
    let code = build(&example("lamp"), "lamp", Target::Abb, &options).unwrap();
    let abb = plc::render(&code, Target::Abb, &options);
    let plain = plc::render(&code, Target::Plcopen, &options);
    // The task's interval: an ISO 8601 duration, as CODESYS-based tools write it.
    assert!(abb.contains("<task name=\"task_main\" interval=\"PT0.010S\" priority=\"1\">"), "{abb}");
    assert!(plain.contains("interval=\"T#10ms\"") && !plain.contains("PT0.010S"), "{plain}");
    // The I/O: the configuration's global variables (after the resource), located at their
    // addresses; plain TC6 puts them in the resource.
    let at_configuration = "        </resource>\n        <globalVars name=\"GVL_IO\">\n";
    assert!(abb.contains(at_configuration), "{abb}");
    assert!(!plain.contains(at_configuration) && plain.contains("          <globalVars name=\"GVL_IO\">"), "{plain}");
    let configuration = &abb[abb.find("</resource>").unwrap()..];
    for variable in
        ["<variable name=\"press\" address=\"%IX124.0\">", "<variable name=\"turn_on\" address=\"%QX125.6\">"]
    {
        assert!(configuration.contains(variable), "{variable} in\n{abb}");
    }
    // The POUs are the same.
    let pous = |xml: &str| xml[xml.find("<pous>").unwrap()..xml.find("</pous>").unwrap()].to_string();
    assert_eq!(pous(&abb), pous(&plain));
    check(Target::Abb, "lamp_abb", &abb);
    check(Target::Plcopen, "lamp_plain", &plain);
}

/// A unit with named constants: ABB's file declares none and writes their values where they
/// are read; the values read are the same (the reference interpreter runs both units).
#[test]
fn abb_writes_constants_values_in_place_and_computes_the_same() {
    use plc::model::exec::{Machine, Value};
    use plc::model::unit::{BinOp, Expr, Place, Pou, PouKind, Stmt, Type, Unit, Var};
    let within = Expr::binary(
        BinOp::And,
        Expr::binary(BinOp::Gt, Expr::local("x"), Expr::global("LOW")),
        Expr::binary(BinOp::Le, Expr::local("x"), Expr::global("HIGH")),
    );
    let unit = Unit {
        name: "limits".into(),
        header: vec!["a unit with constants".into()],
        gvl: "GVL_LIMITS".into(),
        constants: vec![
            Var::new("LOW", Type::Int, "lower bound").with_init(Expr::Int(-3)),
            Var::new("HIGH", Type::Int, "upper bound").with_init(Expr::Int(7)),
        ],
        globals: vec![Var::new("count", Type::Int, "")],
        signals: Vec::new(),
        pous: vec![
            Pou {
                kind: PouKind::Function { returns: Some(Type::Bool) },
                name: "within".into(),
                comment: String::new(),
                inputs: vec![Var::new("x", Type::Int, "")],
                outputs: Vec::new(),
                locals: Vec::new(),
                body: vec![Stmt::assign(Place::local("within"), within)],
            },
            Pou {
                kind: PouKind::Program,
                name: "limits_main".into(),
                comment: String::new(),
                inputs: Vec::new(),
                outputs: Vec::new(),
                locals: Vec::new(),
                body: vec![Stmt::assign(
                    Place::global("count"),
                    Expr::binary(BinOp::Add, Expr::global("count"), Expr::global("HIGH")),
                )],
            },
        ],
    };
    let render = |target| plc::render_unit_files(&unit, target, &Options::default()).unwrap().remove(0).text;
    let (abb, plain) = (render(Target::Abb), render(Target::Plcopen));
    assert!(plain.contains("<globalVars name=\"GVL_LIMITS\" constant=\"true\">"), "{plain}");
    assert!(plain.contains("x > LOW AND x <= HIGH") && plain.contains("count := count + HIGH;"), "{plain}");
    assert!(!abb.contains("constant=\"true\"") && !abb.contains("LOW") && !abb.contains("HIGH"), "{abb}");
    assert!(abb.contains("x > (-3) AND x <= 7") && abb.contains("count := count + 7;"), "{abb}");
    check(Target::Abb, "limits_abb", &abb);
    check(Target::Plcopen, "limits_plain", &plain);
    let inlined = unit.inline_constants();
    assert!(inlined.constants.is_empty());
    let (mut a, mut b) = (Machine::new(&unit).unwrap(), Machine::new(&inlined).unwrap());
    for x in -6..12 {
        let args = [("x", Value::Int(x))];
        assert_eq!(a.call("within", &args).unwrap(), b.call("within", &args).unwrap(), "x = {x}");
        assert_eq!(a.call("within", &args).unwrap(), Value::Bool(-3 < x && x <= 7), "x = {x}");
    }
}

/// The CODESYS I/O mapping list: semicolon-separated, the globals qualified by their list (the
/// CODESYS target declares it `qualified_only`), a mapped one without an address.
#[test]
fn the_codesys_mapping_list_names_each_channel_s_variable() {
    let unit = |name: &str| {
        let code = build(&example(name), name, Target::Codesys, &Options::default()).unwrap();
        plc::lower::timed::structured(&code).unit
    };
    assert_eq!(
        plc::codesys_mapping_csv(&unit("lamp")),
        "Variable;Address;Type;Direction;Description\r\n\
         GVL_IO.press;%IX124.0;BOOL;input;press, NOT release\r\n\
         GVL_IO.turn_on;%QX125.6;BOOL;output;turn_on sets, turn_off resets\r\n"
    );
    let csv = plc::codesys_mapping_csv(&unit("gear_checking"));
    assert!(
        csv.contains("\r\nGVL_IO.loaded;;BOOL;input;loaded\r\n") && csv.contains("\r\nGVL_IO.load;;BOOL;output;"),
        "{csv}"
    );
    // The code the list belongs to declares what it names.
    let gvl = &files("lamp", Target::Codesys)[0].text;
    assert!(gvl.contains("{attribute 'qualified_only'}") && gvl.contains("press AT %IX124.0 : BOOL;"), "{gvl}");
}

#[test]
fn the_io_table_lists_every_signal_as_csv_and_as_a_siemens_symbol_table() {
    let unit = |name: &str| {
        let code = build(&example(name), name, Target::St, &Options::default()).unwrap();
        plc::lower::timed::structured(&code).unit
    };
    let code = unit("lamp");
    assert_eq!(
        plc::io_table_csv(&code),
        "address,type,symbol,direction,meaning\r\n%IX124.0,BOOL,press,input,\"press, NOT release\"\r\n\
         %QX125.6,BOOL,turn_on,output,\"turn_on sets, turn_off resets\"\r\n"
    );
    assert_eq!(
        plc::tag_table_sdf(&code),
        "\"press\",\"I 124.0\",\"BOOL\",\"press, NOT release\"\r\n\
         \"turn_on\",\"Q 125.6\",\"BOOL\",\"turn_on sets, turn_off resets\"\r\n"
    );
    // Without io, the block's own inputs and outputs, unbound.
    let code = unit("gear_checking");
    let csv = plc::io_table_csv(&code);
    assert!(
        csv.contains("\r\n,BOOL,loaded,input,loaded\r\n") && csv.contains(",BOOL,load,output,load pulses\r\n"),
        "{csv}"
    );
    assert_eq!(plc::tag_table_sdf(&code), "");
}

#[test]
fn stl_runs_in_awlsim_from_a_chosen_block_and_marker_byte() {
    let options = Options { fb: Some(7), marker_byte: 40, ..Options::default() };
    let code = build(&example("lamp"), "lamp", Target::Stl, &options).unwrap();
    let text = plc::render(&code, Target::Stl, &options);
    assert!(
        text.contains("FUNCTION_BLOCK FB 7") && text.contains("CALL\tFB 7, DB 7") && text.contains("L\tMB 40\n\tJL"),
        "{text}"
    );
    assert!(!text.contains("MB 0"), "{text}");
    let path = scratch("lamp_fb.awl", &text);
    let script = "I124=0 ?Q125; I124=1 ?Q125; I124=1 ?Q125; I124=0 ?Q125; I124=0 ?Q125; I124=1 ?Q125; I124=0 ?Q125";
    let (ok, out) =
        run(Command::new(venv_tool("python")).arg(root().join("tests/checkers/awl_run.py")).arg(&path).arg(script));
    assert!(ok, "{out}\n{text}");
    let lamp: Vec<bool> = out.lines().map(|l| l.trim() == "Q125=64").collect();
    assert_eq!(lamp, [false, true, true, false, false, true, false], "{out}");
    // The gear checking machine has no io: its signals are memory bits from byte 50 on.
    let options = Options { ob: 1, marker_byte: 40, ..Options::default() };
    let code = build(&example("gear_checking"), "gear_checking", Target::Stl, &options).unwrap();
    let text = plc::render(&code, Target::Stl, &options);
    assert!(text.contains("M 50.0") && !text.contains("M 10.0"), "{text}");
    check(Target::Stl, "gear_mb40", &text);
}

#[test]
fn stl_refuses_markers_on_user_bits_and_more_thresholds_than_timers_located() {
    let source = example("lamp").replace("turn_on = set %Q125.6;", "turn_on = set %M0.3;");
    let diags = build(&source, "lamp", Target::Stl, &Options::default()).expect_err("MB 0 holds the position");
    assert_eq!(diags.len(), 1, "{diags:#?}");
    let at = source.find("%M0.3").unwrap();
    assert_eq!(diags[0].line as usize, source[..at].lines().count(), "{diags:#?}");
    assert!(
        diags[0].message.contains("`turn_on` is bound to %M0.3, in MB 0, which holds the program position"),
        "{diags:#?}"
    );
    assert!(diags[0].notes.iter().any(|n| n.contains("--marker-byte")), "{diags:#?}");
    // Another marker byte clears it; the other targets do not care.
    assert!(build(&source, "lamp", Target::Stl, &Options { marker_byte: 1, ..Options::default() }).is_ok());
    assert!(build(&source, "lamp", Target::St, &Options::default()).is_ok());
    // Two robots compare several thresholds; a CPU with one timer cannot run them.
    let source = example("two_robots_14");
    let code = build(&source, "r", Target::Stl, &Options::default()).unwrap();
    let needed = plc::print::stl::s7_timers(&plc::lower::timed::structured(&code).unit).unwrap().len();
    assert!(needed >= 2, "{needed}");
    let diags =
        build(&source, "r", Target::Stl, &Options { cpu_timers: 1, ..Options::default() }).expect_err("one timer");
    assert_eq!(diags.len(), 1, "{diags:#?}");
    assert!(diags[0].message.contains("needs S7 timer T 2, but the CPU has 1 timers"), "{diags:#?}");
    assert!(
        diags[0].line > 1 && source.lines().nth(diags[0].line as usize - 1).unwrap().contains(" in "),
        "{diags:#?}"
    );
}
