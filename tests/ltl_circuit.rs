//! Controller circuits (`plcsynth ltl --solver gr1 --circuit`; docs/ltl-plc.md, "Circuits")
//! lowered by `plc::lower::ltl::lower_circuit` and run as a PLC runs them: the neutral code
//! model in `plc::model::exec` and the STL form in awlsim, scan by scan on random inputs, must
//! give every scan's outputs and goal as `Circuit::step` does; a corrupted latch update must be
//! caught. blark parses the Structured Text dialects and xmllint validates PLCopen. Whether the
//! circuits themselves are right is checked in `ltl_examples.rs` (lbt's model check of their
//! tables, and a bounded check of the large ones) and `ltl_random.rs`.

use crate::common;

use plcsynth::ltl::{self, Circuit, Config, Format, Spec};
use plcsynth::plc::lower::ltl::{self as lower_ltl, LowerOptions};
use plcsynth::plc::model::exec::{self as unit_exec, Value};
use plcsynth::plc::model::unit::{PouKind, SignalKind, Stmt, Unit};
use plcsynth::plc::{self, Target};
use plcsynth::rng::Rng;
use std::path::PathBuf;
use std::process::Command;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// A SYNTCOMP family at size `n`: its text, specification and controller circuit.
fn family(file: &str, n: i64) -> (String, Spec, Circuit) {
    let path = root().join("../shared/ltl/tlsf").join(file);
    let source = std::fs::read_to_string(&path).unwrap();
    let (spec, _) = ltl::compile(&source, Format::Tlsf, &[("n".to_string(), n)]).unwrap();
    let cfg = Config { solver: ltl::Solver::Gr1, circuit: true, ..Config::default() };
    let outcome = ltl::synthesize(&spec, &cfg, &mut |_| true).unwrap();
    let circuit = outcome.circuit.unwrap_or_else(|| panic!("{file} n={n}: {:?}", outcome.limit));
    (source, spec, circuit)
}

fn cases() -> Vec<(String, String, Spec, Circuit)> {
    [
        ("simple_arbiter/simple_arbiter.tlsf", 12),
        ("simple_arbiter/simple_arbiter.tlsf", 8),
        ("load_balancer/load_balancer.tlsf", 10),
        ("full_arbiter/full_arbiter.tlsf", 4),
        ("prioritized_arbiter/prioritized_arbiter.tlsf", 4),
        ("round_robin_arbiter/round_robin_arbiter.tlsf", 3),
    ]
    .into_iter()
    .map(|(file, n)| {
        let (source, spec, circuit) = family(file, n);
        let name = format!("{}_{n}", file.split('/').next().unwrap());
        (name, source, spec, circuit)
    })
    .collect()
}

/// Per scan: the outputs (bit `j` the `j`-th written signal) and the goal after the scan.
type Observed = (u64, usize);

/// `Circuit::step` on `inputs` (bit `j` the `j`-th read signal).
fn reference(circuit: &Circuit, inputs: &[u64]) -> Vec<Observed> {
    let mut state = circuit.initial();
    inputs
        .iter()
        .map(|&v| {
            let read = |s: ltl::SignalId| v >> circuit.reads.iter().position(|&r| r == s).unwrap() & 1 == 1;
            let (writes, next) = circuit.step(&state, &read);
            state = next;
            (writes.iter().enumerate().fold(0, |m, (j, &w)| m | u64::from(w) << j), state.goal)
        })
        .collect()
}

fn lower(name: &str, source: &str, spec: &Spec, circuit: &Circuit) -> Unit {
    lower_ltl::lower_circuit(source, spec, circuit, &LowerOptions::default())
        .unwrap_or_else(|e| panic!("{name}: {e:?}"))
}

/// The goal a scan leaves, read from the block (0 when the circuit has one goal).
fn goal_of(value: Option<i64>) -> usize {
    value.unwrap_or(0) as usize
}

/// The unit in the reference interpreter.
fn run_exec(unit: &Unit, inputs: &[u64]) -> Vec<Observed> {
    let fb = &unit.pous[0];
    let program = unit.pous.iter().find(|p| p.kind == PouKind::Program).unwrap();
    let instance = &program.locals[0].name;
    let mut plc = unit_exec::Machine::new(unit).unwrap();
    let input_signals: Vec<usize> =
        (0..unit.signals.len()).filter(|&k| unit.signals[k].kind == SignalKind::Input).collect();
    let has_goal = fb.locals.iter().any(|v| v.name == "goal");
    inputs
        .iter()
        .map(|&v| {
            for (j, &k) in input_signals.iter().enumerate() {
                plc.set_signal(k, Value::Bool(v >> j & 1 == 1));
            }
            plc.cycle(&mut |_| Ok(())).unwrap();
            let writes = fb
                .outputs
                .iter()
                .enumerate()
                .fold(0, |m, (j, o)| m | u64::from(plc.instance_value(instance, &o.name).unwrap().as_bool()) << j);
            let goal = has_goal.then(|| plc.instance_value(instance, "goal").unwrap().as_int());
            (writes, goal_of(goal))
        })
        .collect()
}

/// The STL form in awlsim: inputs as bytes `I0`, `I1`, …; per cycle the block's outputs and goal
/// read from its instance data block.
fn run_awlsim(name: &str, unit: &Unit, inputs: &[u64]) -> Vec<Observed> {
    let (path, locations, db, size) = common::awl_instance("plcsynth-ltl-circuit", name, unit);
    let fb = &unit.pous[0];
    let location = |var: &str| locations.iter().find(|l| l.name == var).unwrap_or_else(|| panic!("no {var}"));
    let bytes = fb.inputs.len().div_ceil(8);
    let script: Vec<String> = inputs
        .iter()
        .map(|v| {
            let set: Vec<String> = (0..bytes).map(|b| format!("I{b}={}", v >> (8 * b) & 0xff)).collect();
            format!("{} ?DB{db}:0:{size}", set.join(" "))
        })
        .collect();
    let text = common::run_checker("unit_run.py", &[path.as_os_str()], &script.join("\n"));
    assert_eq!(text.lines().count(), inputs.len(), "one line per cycle");
    let has_goal = fb.locals.iter().any(|v| v.name == "goal");
    text.lines()
        .map(|line| {
            let data = common::hex_bytes(line);
            let bit = |var: &str| {
                let l = location(var);
                data[l.byte as usize] >> l.bit & 1 == 1
            };
            let writes = fb.outputs.iter().enumerate().fold(0, |m, (j, o)| m | u64::from(bit(&o.name)) << j);
            let goal = has_goal.then(|| {
                let l = location("goal");
                i64::from(i16::from_be_bytes([data[l.byte as usize], data[l.byte as usize + 1]]))
            });
            (writes, goal_of(goal))
        })
        .collect()
}

/// Random inputs, each true with probability 1/3 (so that requests come and go).
fn random_inputs(rng: &mut Rng, width: usize, scans: usize) -> Vec<u64> {
    (0..scans).map(|_| (0..width).fold(0, |m, j| m | u64::from(rng.below(3) == 0) << j)).collect()
}

fn first_difference(expected: &[Observed], observed: &[Observed]) -> Option<(usize, Observed, Observed)> {
    expected.iter().zip(observed).enumerate().find(|(_, (e, o))| e != o).map(|(k, (e, o))| (k, *e, *o))
}

/// The block runs like the circuit in the interpreter (500 scans), for arbiters up to 24
/// signals, and in awlsim (200 cycles) where it has at most eight inputs; a block whose last
/// latch update is dropped is caught.
#[test]
fn the_circuits_block_runs_like_the_circuit_in_the_interpreter_and_awlsim() {
    let mut in_awlsim = 0;
    for (k, (name, source, spec, circuit)) in cases().into_iter().enumerate() {
        let unit = lower(&name, &source, &spec, &circuit);
        let mut rng = Rng::new(k as u64 + 29);
        let inputs = random_inputs(&mut rng, circuit.reads.len(), 500);
        let expected = reference(&circuit, &inputs);
        let goals: std::collections::BTreeSet<usize> = expected.iter().map(|&(_, g)| g).collect();
        assert!(goals.len() > 1 || circuit.goals.len() == 1, "{name}: the goal never moves");
        if let Some((scan, e, o)) = first_difference(&expected, &run_exec(&unit, &inputs)) {
            panic!("{name}, scan {scan}: the circuit gives {e:?}, the interpreter {o:?}");
        }
        // awlsim packs an FB's BOOL outputs right after more than eight BOOL inputs where the
        // STL printer (and the program's wiring) starts them at the next word: only blocks
        // of at most eight inputs run there.
        if circuit.reads.len() <= 8 {
            let cycles = &inputs[..200];
            if let Some((scan, e, o)) = first_difference(&expected[..200], &run_awlsim(&name, &unit, cycles)) {
                panic!("{name}, cycle {scan}: the circuit gives {e:?}, awlsim {o:?}");
            }
            in_awlsim += 1;
        }
        // A latch that keeps its initial value is a different circuit, and shows.
        let mut broken = unit.clone();
        let body = &mut broken.pous[0].body;
        let last = body.iter().rposition(|s| matches!(s, Stmt::Assign { .. })).expect("a latch update");
        body[last] = Stmt::Comment("dropped".into());
        assert!(first_difference(&expected, &run_exec(&broken, &inputs)).is_some(), "{name}: a dropped update passes");
    }
    assert!(in_awlsim >= 3, "only {in_awlsim} circuits ran in awlsim");
}

/// Every target's code of the circuits: blark parses the Structured Text dialects, xmllint
/// validates PLCopen against the TC6 schema.
#[test]
fn the_circuits_code_parses_and_validates() {
    let python = common::venv_tool("python");
    let schema = root().join("../shared/schemas/tc6_xml_v201.xsd");
    let mut st_files = Vec::new();
    for (name, source, spec, circuit) in cases() {
        let unit = lower(&name, &source, &spec, &circuit);
        for target in [Target::St, Target::Codesys, Target::Scl, Target::Plcopen] {
            let files = plc::render_unit_files(&unit, target, &plc::Options::default()).unwrap();
            let text = &files[0].text;
            let scratch = |file: &str, text: &str| common::scratch("plcsynth-ltl-circuit", file, text);
            match target {
                Target::Plcopen => {
                    let path = scratch(&format!("{name}.xml"), text);
                    common::check(
                        Command::new("xmllint").arg("--noout").arg("--schema").arg(&schema).arg(&path),
                        &path,
                    );
                }
                Target::Scl => st_files.push(scratch(&format!("{name}_{target}.st"), &common::scl_for_blark(text))),
                _ => st_files.push(scratch(&format!("{name}_{target}.st"), text)),
            }
        }
    }
    common::blark_all(&python, &root(), &st_files);
}

/// The block docs/ltl-plc.md shows ("Circuits") is the generated one.
#[test]
fn the_documented_circuit_is_the_generated_code() {
    let (source, spec, circuit) = family("simple_arbiter/simple_arbiter.tlsf", 3);
    let unit = lower("simple_arbiter_3", &source, &spec, &circuit);
    let text = &plc::render_unit_files(&unit, Target::St, &plc::Options::default()).unwrap()[0].text;
    let start = text.find("FUNCTION_BLOCK").unwrap();
    let end = text.find("END_FUNCTION_BLOCK").unwrap() + "END_FUNCTION_BLOCK".len();
    let doc = std::fs::read_to_string(root().join("docs/ltl-plc.md")).unwrap();
    assert!(doc.contains(&text[start..end]), "docs/ltl-plc.md shows another block than:\n{}", &text[start..end]);
}
