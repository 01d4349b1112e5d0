//! The `supervise`, `supcon` and `bench sct` commands, run as a user would.

use std::process::Command;

fn plcsynth(args: &[&str]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_plcsynth"))
        .args(args)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .unwrap();
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into(),
        String::from_utf8_lossy(&out.stderr).into(),
    )
}

#[test]
fn supervise_prints_one_line_per_supervisor() {
    let (code, out, err) = plcsynth(&["supervise", "examples/sct/tank_preemption.sct"]);
    assert_eq!(code, 0, "{err}");
    let line = out.lines().find(|l| l.starts_with("Safety.NoOverflow")).expect(&out);
    assert!(line.contains("yes") && line.contains("Tank.closeInlNow"), "{line}");
}

#[test]
fn supervise_json_serialises_supervisors() {
    let (code, out, err) =
        plcsynth(&["supervise", "examples/sct/transfer_line_2x2.sct", "--method", "monolithic", "--json"]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["method"], "monolithic");
    let sups = v["supervisors"].as_array().unwrap();
    assert_eq!(sups.len(), 5);
    for s in sups {
        assert_eq!(s["realizable"], true);
        assert_eq!(s["automaton"].as_array().unwrap().len() as u64, s["states"].as_u64().unwrap());
        assert!(s["millis"].as_f64().unwrap() >= 0.0);
    }
}

#[test]
fn supervise_bad_input_exits_2_with_located_diagnostics() {
    let dir = std::env::temp_dir().join(format!("plcsynth-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let f = dir.join("bad.sct");
    std::fs::write(&f, "event a : controllable;\nspec H { state s { forbid b; } }\n").unwrap();
    let (code, _, err) = plcsynth(&["supervise", f.to_str().unwrap()]);
    assert_eq!(code, 2);
    assert!(err.contains("bad.sct:2:27: error: unknown event `b`"), "{err}");
    assert!(err.contains("2 | spec H { state s { forbid b; } }"), "{err}");
    let (code, _, err) = plcsynth(&["supervise", dir.join("missing.sct").to_str().unwrap()]);
    assert_eq!(code, 2, "{err}");
}

#[test]
fn supcon_reads_and_writes_gen_files() {
    let dir = std::env::temp_dir().join(format!("plcsynth-cli-gen-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let (plant, spec, ev) = plcsynth::benchmarks::textbook::transfer_line(3, 1);
    use plcsynth::sct::classic::gen::write_gen;
    std::fs::write(dir.join("p.gen"), write_gen(&plant, &ev, "TL")).unwrap();
    std::fs::write(dir.join("s.gen"), write_gen(&spec, &ev, "BUF")).unwrap();
    let out = dir.join("sup.gen");
    let (code, stdout, err) = plcsynth(&[
        "supcon",
        dir.join("p.gen").to_str().unwrap(),
        dir.join("s.gen").to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(stdout.starts_with("SupCon: 28 states, 65 transitions"), "{stdout}");
    let mut ev2 = plcsynth::sct::classic::Events::new();
    let sup = plcsynth::sct::classic::gen::read_gen(&std::fs::read_to_string(&out).unwrap(), &mut ev2).unwrap();
    assert_eq!((sup.num_states(), sup.num_transitions()), (28, 65));
    std::fs::write(
        dir.join("bad.gen"),
        "<Generator> <Alphabet> a </Alphabet> <States> 1 </States>\n<TransRel> 1 zz 1 </TransRel> </Generator>",
    )
    .unwrap();
    let (code, _, err) =
        plcsynth(&["supcon", dir.join("bad.gen").to_str().unwrap(), dir.join("s.gen").to_str().unwrap()]);
    assert_eq!(code, 2);
    assert!(err.contains("bad.gen:2:14: error: event `zz` is not in the alphabet"), "{err}");
}

/// Files as libFAUDES writes them (empty sections self-closing) are read; a nondeterministic
/// generator and a specification over unknown events get located, readable errors.
#[test]
fn supcon_reads_libfaudes_empty_sections_and_locates_errors() {
    let dir = std::env::temp_dir().join(format!("plcsynth-cli-gen-forms-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let write = |name: &str, text: &str| {
        let p = dir.join(name);
        std::fs::write(&p, text).unwrap();
        p.to_str().unwrap().to_string()
    };
    let plant = write(
        "plant.gen",
        "<Generator name=\"plant\" ftype=\"System\">\n<Alphabet>\nstart +C+ done\n</Alphabet>\n<States>\nidle busy\n</States>\n<TransRel>\nidle start busy\nbusy done idle\n</TransRel>\n<InitStates>\nidle\n</InitStates>\n<MarkedStates/>\n</Generator>\n",
    );
    let spec = write(
        "spec.gen",
        "<Generator name=\"spec\">\n<Alphabet>\nstart done\n</Alphabet>\n<States>\n1\n</States>\n<TransRel/>\n<InitStates>\n1\n</InitStates>\n<MarkedStates>\n1\n</MarkedStates>\n</Generator>\n",
    );
    let (code, out, err) = plcsynth(&["supcon", &plant, &spec]);
    assert_eq!(code, 0, "{err}");
    assert!(out.starts_with("SupCon: 0 states, 0 transitions"), "{out}");
    let (code, out, err) = plcsynth(&["supcon", &plant, &spec, "--closed"]);
    assert_eq!(code, 0, "{err}");
    assert!(out.starts_with("SupConClosed: 1 states, 0 transitions"), "{out}");

    let nondeterministic = write(
        "nondet.gen",
        "<Generator>\n<Alphabet> a </Alphabet>\n<States> 3 4 7 </States>\n<TransRel>\n3 a 4\n3 a 7\n</TransRel>\n</Generator>\n",
    );
    let (code, _, err) = plcsynth(&["supcon", &nondeterministic, &spec]);
    assert_eq!(code, 2);
    assert!(
        err.contains("nondet.gen:6:1: error: state `3` has two transitions on event `a` (to `4` and `7`)"),
        "{err}"
    );
    assert!(err.contains("= note: SupCon needs deterministic generators"), "{err}");
    assert!(!err.contains("EventId") && !err.contains("Nondeterministic {"), "{err}");

    let unknown = write(
        "unknown.gen",
        "<Generator>\n<Alphabet>\nstart\n  jam   reset\n</Alphabet>\n<States> 1 </States>\n<TransRel/>\n</Generator>\n",
    );
    let (code, _, err) = plcsynth(&["supcon", &plant, &unknown]);
    assert_eq!(code, 2);
    assert!(
        err.contains("unknown.gen:4:3: error: the specification uses events the plant does not know: `jam`, `reset`"),
        "{err}"
    );
    assert!(err.contains("4 |   jam   reset"), "{err}");
    assert!(err.contains("has the events `start`, `done`") || err.contains("has the events `done`, `start`"), "{err}");
}

/// `supcon` has a state budget: a file declaring more states than `--max-states` (a short
/// `<Consecutive>` range, finding G1 of docs/fuzzing.md) and a product past it both stop with
/// exit status 3 and say how to go on.
#[test]
fn supcon_stops_at_its_state_budget() {
    let dir = std::env::temp_dir().join(format!("plcsynth-cli-gen-budget-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let write = |name: &str, text: &str| {
        let p = dir.join(name);
        std::fs::write(&p, text).unwrap();
        p.to_str().unwrap().to_string()
    };
    let bomb = write(
        "bomb.gen",
        "<Generator>\n<Alphabet> a </Alphabet>\n<States>\n<Consecutive> 1 10000000 </Consecutive>\n</States>\n<InitStates> 1 </InitStates>\n</Generator>\n",
    );
    // A cycle of `n` states over `event`, with self-loops on `others` in every state.
    let cycle = |name: &str, event: &str, others: &[&str], n: usize| {
        let mut trans = String::new();
        for k in 1..=n {
            trans += &format!("{k} {event} {}\n", k % n + 1);
            for o in others {
                trans += &format!("{k} {o} {k}\n");
            }
        }
        let alphabet: String =
            std::iter::once(event).chain(others.iter().copied()).map(|e| format!("{e} +C+ ")).collect();
        write(
            name,
            &format!("<Generator>\n<Alphabet> {alphabet}</Alphabet>\n<States> <Consecutive> 1 {n} </Consecutive> </States>\n<TransRel>\n{trans}</TransRel>\n<InitStates> 1 </InitStates>\n<MarkedStates> 1 </MarkedStates>\n</Generator>\n"),
        )
    };
    let (code, _, err) = plcsynth(&["supcon", &bomb, &bomb]);
    assert_eq!(code, 3, "{err}");
    assert!(
        err.contains("bomb.gen:4:1: error: the generator declares more than 250000 states, the state budget"),
        "{err}"
    );
    assert!(err.contains("--max-states"), "{err}");
    // A plant cycling on `a` that allows `b` anywhere, and a specification cycling on `b`:
    // a product of 100 x 100 states.
    let (plant, b) = (cycle("a.gen", "a", &["b"], 100), cycle("b.gen", "b", &[], 100));
    let (code, out, err) = plcsynth(&["supcon", &plant, &b, "--max-states", "9999"]);
    assert_eq!(code, 3, "{out}{err}");
    assert!(err.contains("has more than 9999 states") && err.contains("--max-states"), "{err}");
    let (code, out, err) = plcsynth(&["supcon", &plant, &b, "--max-states", "10000"]);
    assert_eq!(code, 0, "{err}");
    assert!(out.starts_with("SupCon: 10000 states"), "{out}");
}

#[test]
fn bench_sct_prints_thesis_figures_beside_ours() {
    let (code, out, err) = plcsynth(&["bench", "sct", "--runs", "1", "--no-faudes"]);
    assert_eq!(code, 0, "{err}");
    let row = out.lines().find(|l| l.starts_with("2 x 2 ")).expect(&out);
    assert!(row.contains("164") && row.contains("38"), "{row}");
    assert!(out.contains("50 x 4"), "{out}");
}

/// `--compose` synthesises one supervisor for the product of all specifications: on the
/// enforcement conflict of 6.4.2 it gives what the explicit product `spec Safety = ...` gives,
/// and the warning about the conflict goes away.
#[test]
fn supervise_compose_resolves_the_enforcement_conflict() {
    let dir = std::env::temp_dir().join(format!("plcsynth-cli-compose-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let src =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/examples/sct/enforcement_conflict.sct")).unwrap();
    let product_line = "spec Safety = NoOverflow | PumpProtection;";
    assert!(src.contains(product_line));
    let f = dir.join("separate.sct");
    std::fs::write(&f, src.replace(product_line, "")).unwrap();
    let f = f.to_str().unwrap();

    let (code, out, err) = plcsynth(&["supervise", f]);
    assert_eq!(code, 0, "{err}");
    assert!(err.contains("`PumpProtection` prohibits `closeInlNow`, which supervisor `NoOverflow` enforces"), "{err}");
    assert!(out.contains("2 supervisors"), "{out}");

    let (code, composed, err) = plcsynth(&["supervise", f, "--compose", "--json"]);
    assert_eq!(code, 0, "{err}");
    assert!(!err.contains("warning"), "{err}");
    let (code, explicit, err) = plcsynth(&["supervise", "examples/sct/enforcement_conflict.sct", "--json"]);
    assert_eq!(code, 0, "{err}");
    let (a, b): (serde_json::Value, serde_json::Value) =
        (serde_json::from_str(&composed).unwrap(), serde_json::from_str(&explicit).unwrap());
    let (a, b) = (&a["supervisors"], &b["supervisors"]);
    assert_eq!(a.as_array().unwrap().len(), 1);
    assert_eq!(a[0]["name"], "Composed");
    for key in ["states", "transitions", "prohibitions", "enforced_events", "prohibited_events", "automaton"] {
        assert_eq!(a[0][key], b[0][key], "{key}");
    }
    assert_eq!(a[0]["enforced_events"], serde_json::json!(["closeInlNow"]));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn supervise_reports_an_exhausted_state_budget_with_exit_status_3() {
    let (code, out, err) =
        plcsynth(&["supervise", "examples/sct/transfer_line_2x2.sct", "--method", "monolithic", "--max-states", "100"]);
    assert_eq!(code, 3, "{out}{err}");
    assert!(err.contains("error: synthesis stopped at `B1_1`: more than 100 product states built"), "{err}");
    assert!(err.contains("not synthesised either: B1_2, TB1, B2_1, B2_2"), "{err}");
    assert!(err.contains("raise it with --max-states N"), "{err}");
    // Incremental synthesis of the same file fits easily.
    let (code, _, err) = plcsynth(&["supervise", "examples/sct/transfer_line_2x2.sct", "--max-states", "100"]);
    assert_eq!(code, 0, "{err}");
    let (code, _, err) = plcsynth(&["supervise", "examples/sct/three_tanks.sct", "--compose", "--max-states", "10"]);
    assert_eq!(code, 3, "{err}");
    assert!(err.contains("three_tanks.sct:"), "located: {err}");
    assert!(err.contains("error: composing the 10 specifications spent the state budget at `"), "{err}");
    assert!(err.contains("raise it with --max-states N"), "{err}");
}

/// `n` independent two-state specifications, each forbidding its event after it: 2^n states
/// in their product.
fn independent_specs(n: usize) -> String {
    let mut s = String::new();
    for i in 0..n {
        s += &format!(
            "event e{i} : controllable;\nspec S{i} {{ state a initial {{ e{i} -> b; }} state b {{ forbid e{i}; }} }}\n"
        );
    }
    s
}

#[test]
fn products_written_in_the_file_and_compose_obey_the_state_budget() {
    let dir = std::env::temp_dir().join(format!("plcsynth-cli-products-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let names: Vec<String> = (0..12).map(|i| format!("S{i}")).collect();
    let file = dir.join("product.sct");
    std::fs::write(&file, format!("{}spec All = {};\n", independent_specs(12), names.join(" | "))).unwrap();
    let path = file.to_str().unwrap();
    // 2^12 = 4096 states in the product; its intermediate products count too.
    let (code, _, err) = plcsynth(&["supervise", path, "--max-states", "5000"]);
    assert_eq!(code, 3, "{err}");
    assert!(err.contains("product.sct:25:6: error: building the product `All` spent the state budget"), "{err}");
    assert!(err.contains("raise it with --max-states N"), "{err}");
    let (code, out, err) = plcsynth(&["supervise", path, "--max-states", "20000"]);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("All ") && out.contains("1 supervisors"), "{out}");
    // --compose draws on the same budget as the synthesis after it.
    let file = dir.join("forty.sct");
    std::fs::write(&file, independent_specs(40)).unwrap();
    let (code, _, err) = plcsynth(&["supervise", file.to_str().unwrap(), "--compose"]);
    assert_eq!(code, 3, "{err}");
    assert!(err.contains("error: composing the 40 specifications spent the state budget at `S"), "{err}");
    // An input error keeps exit status 2 even when the budget stops the run too.
    let file = dir.join("conflict.sct");
    std::fs::write(
        &file,
        "event a : controllable;\nevent b : uncontrollable;\nplant P { alphabet a, b; state p initial { a -> p; b -> q; } state q { b -> q; } }\n\
         plant Q { alphabet b; state x initial { b -> y; } state y { b -> x; } }\n\
         spec C { state s initial { a -> t if [P.p]; a -> u if [Q.x]; forbid b; } state t; state u; }\n\
         spec D { state s initial { forbid b; } }\n",
    )
    .unwrap();
    let (code, _, err) =
        plcsynth(&["supervise", file.to_str().unwrap(), "--method", "monolithic", "--max-states", "6"]);
    assert!(err.contains("two transitions on `a`"), "{err}");
    assert!(err.contains("synthesis stopped at `D`"), "{err}");
    assert_eq!(code, 2, "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn supervise_writes_the_runtime_framework_for_every_target() {
    let dir = std::env::temp_dir().join(format!("plcsynth-supervise-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for target in ["st", "codesys", "scl", "scl-1500", "plcopen", "abb", "stl"] {
        let path = dir.join(format!("tank.{target}"));
        let table = dir.join(format!("tank_{target}.csv"));
        let (code, out, err) = plcsynth(&[
            "supervise",
            "examples/sct/tank_timer.sct",
            "--target",
            target,
            "-o",
            path.to_str().unwrap(),
            "--io-table",
            table.to_str().unwrap(),
            "--controller",
            "TankControl",
        ]);
        assert_eq!(code, 0, "{target}: {err}");
        assert!(out.is_empty(), "{target}: the code goes to the file");
        let text = std::fs::read_to_string(&path).unwrap();
        assert!(text.contains("Specification hash (FNV-1a 64): ") && text.contains("TankControl"), "{target}");
        let csv = std::fs::read_to_string(&table).unwrap();
        assert!(csv.starts_with("address,type,symbol,direction,events\r\n"), "{csv}");
        assert!(csv.contains("%IX0.0,BOOL,I_LevelHigh,input,levelAlarm\r\n"), "{csv}");
        assert!(csv.contains(",INT,EV_T_timeout,constant,"), "{csv}");
    }
    // The signal table as the CODESYS mapping list: the user's symbols at their addresses.
    let table = dir.join("tank_mapping.csv");
    let (code, _, err) = plcsynth(&[
        "supervise",
        "examples/sct/tank_timer.sct",
        "--target",
        "codesys",
        "--io-table",
        table.to_str().unwrap(),
        "--io-format",
        "codesys",
    ]);
    assert_eq!(code, 0, "{err}");
    let csv = std::fs::read_to_string(&table).unwrap();
    assert!(csv.starts_with("Variable;Address;Type;Direction;Description\r\n"), "{csv}");
    assert!(csv.contains("\r\nI_LevelHigh;%IX0.0;BOOL;input;levelAlarm\r\n"), "{csv}");
    // TwinCAT: a directory with a file per POU and the global variable list.
    let tc = dir.join("tank_tc");
    let (code, _, err) =
        plcsynth(&["supervise", "examples/sct/tank_timer.sct", "--target", "twincat", "-o", tc.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    let mut names: Vec<String> =
        std::fs::read_dir(&tc).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
    names.sort();
    assert!(
        names.contains(&"SyRF_Main.TcPOU".to_string()) && names.contains(&"SyRF_Data.TcGVL".to_string()),
        "{names:?}"
    );
    // Without -o the code goes to standard output; the report is not printed.
    let (code, out, _) = plcsynth(&["supervise", "examples/sct/crane.sct", "--target", "st", "--name", "Crane"]);
    assert_eq!(code, 0);
    assert!(out.contains("PROGRAM Crane_Main") && out.contains("FUNCTION Crane_Execute : BOOL"), "{out}");
    assert!(!out.contains("realizable"), "{out}");
    let (code, out, _) = plcsynth(&["supervise", "examples/sct/crane.sct", "--target", "stl", "--controller-fb", "10"]);
    assert_eq!(code, 0);
    assert!(out.contains("CALL FB 10, DB 10") || out.contains("CALL\tFB 10, DB 10"), "{out}");
}

#[test]
fn supervise_refuses_what_cannot_run_and_writes_nothing() {
    let dir = std::env::temp_dir().join(format!("plcsynth-supervise-refused-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let spec = dir.join("virtual.sct");
    std::fs::write(
        &spec,
        "event go : controllable;\nevent stop : controllable { detect falling \"Q\"; }\n\
         plant P { alphabet go, stop; state A initial { go -> B; } state B { stop -> A; } }\n\
         spec S { state X { go -> Y; } state Y { forbid go; stop -> X; } }\n",
    )
    .unwrap();
    let out_path = dir.join("out.st");
    let (code, _, err) =
        plcsynth(&["supervise", spec.to_str().unwrap(), "--target", "st", "-o", out_path.to_str().unwrap()]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains(":1:7: error: supervisor `S` changes state on the virtual event `go`"), "{err}");
    assert!(err.contains("1 | event go : controllable;") && err.contains("nothing written"), "{err}");
    assert!(!out_path.exists());
    // Instruction List is refused with a reason; options of the framework need a target.
    let (code, _, err) = plcsynth(&["supervise", "examples/sct/tank_timer.sct", "--target", "il"]);
    assert_eq!(code, 2);
    assert!(err.contains("Instruction List"), "{err}");
    let (code, _, err) = plcsynth(&["supervise", "examples/sct/tank_timer.sct", "-o", "x.st"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("--target"), "{err}");
}
