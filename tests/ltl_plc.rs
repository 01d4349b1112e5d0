//! `plc::lower::ltl` checked against the machines it lowers: random controllers (Mealy and
//! Moore, with and without a timer) built directly as `ltl::Machine` values are lowered to a
//! `Unit`, which `plc::model::exec` runs scan by scan on random inputs and a virtual clock; every
//! scan's outputs and state must be the machine's step (`Machine::row`, `first_write`), with the
//! timer's expiry computed from when the controller started it. A corrupted branch must be
//! caught. The printed code goes to the independent tools: blark parses the Structured Text
//! dialects, xmllint validates PLCopen against the TC6 schema, and awlsim runs the STL form
//! cycle by cycle against the same reference. The checkers come from
//! `scripts/python-checkers.sh` (run when missing).

use crate::common;

use plcsynth::diag::Span;
use plcsynth::ltl::{Cube, Machine, Row, Semantics, Signal, SignalId, SignalKind, Spec, StateId, Timer};
use plcsynth::plc::lower::ltl::{self as lower_ltl, LowerOptions};
use plcsynth::plc::model::exec::{self as unit_exec, Value};
use plcsynth::plc::model::unit::{Expr, Place, PouKind, Stmt, Unit};
use plcsynth::plc::{self, print::stl::unit as unit_stl, Target};
use plcsynth::rng::Rng;
use std::path::PathBuf;
use std::process::Command;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// Names that must become legal, distinct PLC identifiers: dots, spaces, keywords, names the
/// lowering itself would like to use, names equal but for case.
const INPUT_NAMES: &[&str] = &["req", "door.open", "state", "END_IF", "Sensor 2", "S_0", "ctrl", "x"];
const OUTPUT_NAMES: &[&str] = &["grant", "lamp.on", "REQ_2", "t1_Q", "q", "Grant", "fb_controller", "valve"];

/// A controller and its specification.
struct Case {
    spec: Spec,
    machine: Machine,
    /// The timer's preset, when the specification has one.
    preset_ms: Option<u64>,
}

fn signal(name: &str, kind: SignalKind) -> Signal {
    Signal { name: name.to_string(), kind, span: Span::default() }
}

fn pick<'a>(rng: &mut Rng, pool: &[&'a str], n: usize) -> Vec<&'a str> {
    let mut left: Vec<&str> = pool.to_vec();
    (0..n).map(|_| left.remove(rng.below(left.len() as u64) as usize)).collect()
}

/// A random partition of the valuations of `free` (a mask of read variables) below `cube`.
fn partition(rng: &mut Rng, cube: Cube, free: u64, out: &mut Vec<Cube>) {
    if free == 0 || rng.chance(30) {
        out.push(cube);
        return;
    }
    let bits: Vec<u64> = (0..64).map(|i| 1u64 << i).filter(|b| free & b != 0).collect();
    let bit = bits[rng.below(bits.len() as u64) as usize];
    for value in [0, bit] {
        partition(rng, Cube { care: cube.care | bit, value: cube.value | value }, free & !bit, out);
    }
}

/// A random controller: 1–6 states, 0–4 inputs, 1–4 outputs, Mealy or Moore, perhaps a timer
/// (presets from `presets`).
fn random_case(seed: u64, presets: &[u64]) -> Case {
    let mut rng = Rng::new(seed);
    let states = 1 + rng.below(6) as usize;
    let (n_inputs, n_outputs) = (rng.below(5) as usize, 1 + rng.below(4) as usize);
    let inputs = pick(&mut rng, INPUT_NAMES, n_inputs);
    let outputs = pick(&mut rng, OUTPUT_NAMES, n_outputs);
    let moore = rng.chance(40);
    let timed = rng.chance(40);
    let mut spec = Spec {
        semantics: if moore { Semantics::Moore } else { Semantics::Mealy },
        title: rng.chance(50).then(|| "Demo line".to_string()),
        ..Spec::default()
    };
    let mut reads = Vec::new();
    let mut writes = Vec::new();
    for name in inputs {
        reads.push(SignalId(spec.signals.len() as u32));
        spec.signals.push(signal(name, SignalKind::Input));
    }
    for name in outputs {
        writes.push(SignalId(spec.signals.len() as u32));
        spec.signals.push(signal(name, SignalKind::Output));
    }
    let mut preset_ms = None;
    if timed {
        let name = if rng.chance(50) { "t1" } else { "pump.delay" };
        let start = SignalId(spec.signals.len() as u32);
        spec.signals.push(signal(&format!("{name}.start"), SignalKind::Output));
        let expire = SignalId(spec.signals.len() as u32);
        spec.signals.push(signal(&format!("{name}.expire"), SignalKind::Input));
        let preset = presets[rng.below(presets.len() as u64) as usize];
        preset_ms = Some(preset);
        spec.timers.push(Timer { name: name.into(), preset_ms: preset, start, expire, span: Span::default() });
        let at = rng.below(reads.len() as u64 + 1) as usize;
        reads.insert(at, expire);
        let at = rng.below(writes.len() as u64 + 1) as usize;
        writes.insert(at, start);
    }
    let all_reads = if reads.is_empty() { 0 } else { (1u64 << reads.len()) - 1 };
    let write = |rng: &mut Rng| rng.below(1 << writes.len());
    let machine_states = (0..states)
        .map(|_| {
            let mut cubes = Vec::new();
            partition(&mut rng, Cube::ANY, all_reads, &mut cubes);
            let state_write = write(&mut rng);
            cubes
                .into_iter()
                .map(|read| Row {
                    read,
                    write: if moore { state_write } else { write(&mut rng) },
                    next: StateId(rng.below(states as u64) as u32),
                })
                .collect()
        })
        .collect();
    let init = StateId(rng.below(states as u64) as u32);
    let machine = Machine { reads, writes, moves_first: moore, init, states: machine_states };
    machine.validate().expect("a valid machine");
    Case { spec, machine, preset_ms }
}

fn lower(case: &Case) -> Unit {
    lower_ltl::lower("", &case.spec, &case.machine, &LowerOptions::default()).expect("a controller lowers")
}

/// One scan of the environment: the time that passes before it and the inputs of the
/// project (the reads that are not the timer's expiry), as bits.
#[derive(Clone, Copy, Debug)]
struct Scan {
    dt: u64,
    inputs: u64,
}

/// What one scan shows: the block's outputs (in the machine's write order) and its state.
#[derive(Clone, Debug, PartialEq, Eq)]
struct Observed {
    writes: u64,
    state: u32,
}

fn expire_index(case: &Case) -> Option<usize> {
    let t = case.spec.timers.first()?;
    case.machine.reads.iter().position(|&s| s == t.expire)
}

fn start_index(case: &Case) -> Option<usize> {
    let t = case.spec.timers.first()?;
    case.machine.writes.iter().position(|&s| s == t.start)
}

/// The machine's own steps on `scans`, its timer modelled as a TON: expired once the preset has
/// passed since the last scan that started it (a start counts from the next scan's reads on).
/// Also the number of scans that read the timer expired.
fn reference(case: &Case, scans: &[Scan]) -> (Vec<Observed>, usize) {
    let m = &case.machine;
    let expire = expire_index(case);
    let start = start_index(case);
    let (mut state, mut now, mut started) = (m.init, 0u64, None::<u64>);
    let mut out = Vec::new();
    let mut expired = 0;
    for scan in scans {
        now += scan.dt;
        // The project's inputs fill the reads in order, skipping the timer's expiry.
        let mut valuation = 0u64;
        let mut next_input = 0;
        for i in 0..m.reads.len() {
            let bit = if Some(i) == expire {
                let bit = started.is_some_and(|t| now - t >= case.preset_ms.unwrap());
                expired += usize::from(bit);
                bit
            } else {
                next_input += 1;
                scan.inputs >> (next_input - 1) & 1 == 1
            };
            valuation |= u64::from(bit) << i;
        }
        let row = m.row(state, valuation);
        let writes = if m.moves_first { m.first_write(state) } else { row.write };
        if start.is_some_and(|j| writes >> j & 1 == 1) {
            started = Some(now);
        }
        state = row.next;
        out.push(Observed { writes, state: state.0 });
    }
    (out, expired)
}

fn random_scans(rng: &mut Rng, case: &Case, n: usize, steps: &[u64]) -> Vec<Scan> {
    let inputs = case.machine.reads.len() - usize::from(expire_index(case).is_some());
    (0..n).map(|_| Scan { dt: steps[rng.below(steps.len() as u64) as usize], inputs: rng.below(1 << inputs) }).collect()
}

/// The unit in the reference interpreter: per scan the block's outputs (read from the instance)
/// and state; the program's output signals must equal the block's outputs.
fn run_exec(unit: &Unit, scans: &[Scan]) -> Vec<Observed> {
    let fb = &unit.pous[0];
    let program = unit.pous.iter().find(|p| p.kind == PouKind::Program).unwrap();
    let instance = &program.locals[0].name;
    let state = &fb.locals[0].name;
    let mut plc = unit_exec::Machine::new(unit).unwrap();
    let input_signals: Vec<usize> =
        (0..unit.signals.len()).filter(|&k| unit.signals[k].kind == plc::model::unit::SignalKind::Input).collect();
    let mut out = Vec::new();
    for scan in scans {
        plc.advance(scan.dt);
        for (j, &k) in input_signals.iter().enumerate() {
            plc.set_signal(k, Value::Bool(scan.inputs >> j & 1 == 1));
        }
        plc.cycle(&mut |_| Ok(())).unwrap();
        let mut writes = 0;
        for (j, v) in fb.outputs.iter().enumerate() {
            let value = plc.instance_value(instance, &v.name).unwrap().as_bool();
            writes |= u64::from(value) << j;
        }
        // The program copies every output but the timer's start to a signal, in order.
        let wired: Vec<bool> = (0..unit.signals.len())
            .filter(|&k| unit.signals[k].kind == plc::model::unit::SignalKind::Output)
            .map(|k| plc.signal(k).as_bool())
            .collect();
        let expected: Vec<bool> = fb
            .outputs
            .iter()
            .enumerate()
            .filter(|(_, v)| !v.comment.contains("starts timer"))
            .map(|(j, _)| writes >> j & 1 == 1)
            .collect();
        assert_eq!(wired, expected, "the program wires the block's outputs");
        out.push(Observed { writes, state: plc.instance_value(instance, state).unwrap().as_int() as u32 });
    }
    out
}

/// The first scan where `observed` differs from `expected`.
fn first_difference(expected: &[Observed], observed: &[Observed]) -> Option<(usize, Observed, Observed)> {
    expected.iter().zip(observed).enumerate().find(|(_, (e, o))| e != o).map(|(k, (e, o))| (k, e.clone(), o.clone()))
}

/// Flips every output a branch of the initial state assigns: the first scan goes through one
/// of its paths, each of which assigns every output.
fn corrupt_initial_branch(unit: &mut Unit, init: StateId) {
    fn flip(stmts: &mut [Stmt]) {
        for s in stmts {
            match s {
                Stmt::Assign { target: Place::Local(_), value: Expr::Bool(b) } => *b = !*b,
                Stmt::If { arms, otherwise } => {
                    arms.iter_mut().for_each(|(_, body)| flip(body));
                    flip(otherwise);
                }
                _ => {}
            }
        }
    }
    let body = &mut unit.pous[0].body;
    let Some(Stmt::Case { arms, .. }) = body.iter_mut().find(|s| matches!(s, Stmt::Case { .. })) else {
        panic!("the block has a CASE")
    };
    let (_, branch) = arms.iter_mut().find(|(labels, _)| labels.contains(&i64::from(init.0))).unwrap();
    flip(branch);
}

/// Steps in ms between scans for the interpreter: exact timer boundaries included.
fn exec_steps(preset: Option<u64>) -> Vec<u64> {
    let p = preset.unwrap_or(10);
    vec![0, 1, 2, p - 1, p, p + 1, 3]
}

#[test]
fn lowered_machines_step_like_the_machine_and_a_corrupted_branch_is_caught() {
    let mut counts = [0usize; 4]; // Mealy, Moore, timed, runs that read the timer expired
    for seed in 0..400 {
        let case = random_case(seed, &[1, 2, 5, 10, 25]);
        let unit = lower(&case);
        let mut rng = Rng::new(seed ^ 0x5eed);
        let scans = random_scans(&mut rng, &case, 200, &exec_steps(case.preset_ms));
        let (expected, expired) = reference(&case, &scans);
        let observed = run_exec(&unit, &scans);
        if let Some((scan, e, o)) = first_difference(&expected, &observed) {
            panic!(
                "seed {seed}, scan {scan}: expected {e:?}, the unit gives {o:?}\n{:?}\n{}",
                case.machine,
                plc::render_unit_files(&unit, Target::St, &plc::Options::default()).unwrap()[0].text
            );
        }
        counts[usize::from(case.machine.moves_first)] += 1;
        if case.preset_ms.is_some() {
            counts[2] += 1;
            counts[3] += usize::from(expired > 0);
        }
        let mut corrupted = unit.clone();
        corrupt_initial_branch(&mut corrupted, case.machine.init);
        let observed = run_exec(&corrupted, &scans[..1]);
        assert!(
            first_difference(&expected[..1], &observed).is_some(),
            "seed {seed}: a corrupted branch of the initial state goes unnoticed"
        );
    }
    assert!(
        counts[0] > 100 && counts[1] > 100 && counts[2] > 100 && counts[3] > 50,
        "a spread of machines: {counts:?}"
    );
}

/// The example of `docs/ltl-plc.md`: a lamp that a button switches on for 5 s (timer `t1`);
/// pressing it again while on starts the 5 s again.
fn lamp_example() -> Case {
    let mut spec = Spec { title: Some("Lamp".into()), ..Spec::default() };
    for (name, kind) in [
        ("button", SignalKind::Input),
        ("lamp", SignalKind::Output),
        ("t1.start", SignalKind::Output),
        ("t1.expire", SignalKind::Input),
    ] {
        spec.signals.push(signal(name, kind));
    }
    spec.timers.push(Timer {
        name: "t1".into(),
        preset_ms: 5000,
        start: SignalId(2),
        expire: SignalId(3),
        span: Span::default(),
    });
    // reads: button (bit 0), t1.expire (bit 1); writes: lamp (bit 0), t1.start (bit 1)
    let row = |care, value, write, next| Row { read: Cube { care, value }, write, next: StateId(next) };
    let machine = Machine {
        reads: vec![SignalId(0), SignalId(3)],
        writes: vec![SignalId(1), SignalId(2)],
        moves_first: false,
        init: StateId(0),
        states: vec![
            // off: the button switches the lamp on and starts t1
            vec![row(0b01, 0b01, 0b11, 1), row(0b01, 0b00, 0b00, 0)],
            // on: the button starts t1 again; t1 expired switches off
            vec![row(0b01, 0b01, 0b11, 1), row(0b11, 0b10, 0b00, 0), row(0b11, 0b00, 0b01, 1)],
        ],
    };
    machine.validate().unwrap();
    Case { spec, machine, preset_ms: Some(5000) }
}

/// docs/ltl-plc.md shows the example's generated Structured Text: it must be what the lowering
/// prints.
#[test]
fn the_documented_example_is_the_generated_code() {
    let unit = lower(&lamp_example());
    let text = &plc::render_unit_files(&unit, Target::St, &plc::Options::default()).unwrap()[0].text;
    let doc = std::fs::read_to_string(root().join("docs/ltl-plc.md")).unwrap();
    assert!(doc.contains(text.as_str()), "docs/ltl-plc.md should show the generated code:\n{text}");
}

// ---------------------------------------------------------------------------------------------
// The printed code and the independent tools.

use common::{check, venv_tool};

fn scratch(name: &str, text: &str) -> PathBuf {
    common::scratch("plcsynth-ltl-plc", name, text)
}

/// The first random case (from `seed` on) that `wanted` accepts.
fn find_case(seed: u64, presets: &[u64], wanted: impl Fn(&Case) -> bool) -> (u64, Case) {
    (seed..).map(|s| (s, random_case(s, presets))).find(|(_, c)| wanted(c)).unwrap()
}

/// Machines that show every construct: the documented example (a timer started in a Mealy
/// machine, ELSIF chains), a Moore machine with a timer and tricky names, a Mealy machine of
/// four inputs without a timer.
fn representative(presets: &[u64]) -> Vec<(String, Case)> {
    let inputs = |c: &Case| c.machine.reads.len();
    let (moore, moore_case) = find_case(0, presets, |c| {
        c.machine.moves_first && c.preset_ms.is_some() && inputs(c) >= 3 && c.machine.states.len() >= 3
    });
    let (mealy, mealy_case) = find_case(0, presets, |c| {
        !c.machine.moves_first && c.preset_ms.is_none() && inputs(c) == 4 && c.machine.states.len() >= 4
    });
    vec![
        ("lamp".to_string(), lamp_example()),
        (format!("moore_timer_{moore}"), moore_case),
        (format!("mealy_{mealy}"), mealy_case),
    ]
}

/// Every target of a few machines: blark parses the Structured Text dialects (SCL as blark reads
/// it), xmllint validates PLCopen against the TC6 schema and TwinCAT's files as XML; Instruction
/// List is refused with the reason.
#[test]
fn every_target_parses_or_validates() {
    let python = venv_tool("python");
    let schema = root().join("../shared/schemas/tc6_xml_v201.xsd");
    assert!(schema.exists(), "the PLCopen schema is expected at {}", schema.display());
    let options = plc::Options::default();
    let mut st_files = Vec::new();
    for (name, case) in representative(&[5000]) {
        let unit = lower(&case);
        for target in Target::ALL {
            let files = plc::render_unit_files(&unit, target, &options);
            let files = match (target, files) {
                (Target::Il, Err(reason)) => {
                    assert!(reason.contains("Instruction List"), "{reason}");
                    continue;
                }
                (_, files) => files.unwrap_or_else(|e| panic!("{name}, {target}: {e}")),
            };
            let text = &files[0].text;
            match target {
                Target::St | Target::Codesys => st_files.push(scratch(&format!("{name}_{target}.st"), text)),
                Target::Scl | Target::Scl1500 => {
                    st_files.push(scratch(&format!("{name}_{target}.st"), &common::scl_for_blark(text)))
                }
                Target::Twincat => {
                    assert_eq!(files.len(), unit.pous.len() + 1, "a .TcPOU per POU and the constants' .TcGVL");
                    for f in &files {
                        let path = scratch(&format!("{name}_{}", f.name), &f.text);
                        check(Command::new("xmllint").arg("--noout").arg(&path), &path);
                    }
                }
                Target::Plcopen | Target::Abb => {
                    if target == Target::Abb {
                        assert!(!text.contains("constant=\"true\""), "{name}: ABB declares no constants");
                    }
                    let path = scratch(&format!("{name}_{target}.xml"), text);
                    check(Command::new("xmllint").arg("--noout").arg("--schema").arg(&schema).arg(&path), &path);
                }
                Target::Stl => {
                    let stl = plc::unit_stl_options(&options);
                    assert_eq!(unit_stl::check(&unit, &stl), Vec::<String>::new(), "{name}");
                }
                Target::Il => unreachable!("refused above"),
            }
        }
    }
    common::blark_all(&python, &root(), &st_files);
}

/// The STL form of `case` run in awlsim on `scans` (a virtual clock advanced by each scan's
/// `dt`): per cycle the block's outputs and state read from its instance DB.
fn run_awlsim(name: &str, unit: &Unit, scans: &[Scan]) -> Vec<Observed> {
    let (path, locations, db, size) = common::awl_instance("plcsynth-ltl-plc", name, unit);
    let fb = &unit.pous[0];
    let location = |var: &str| locations.iter().find(|l| l.name == var).unwrap_or_else(|| panic!("no {var}"));
    let script: Vec<String> =
        scans.iter().map(|s| format!("T{} I0={} ?DB{db}:0:{size} ?Q0:1", s.dt, s.inputs)).collect();
    let text = common::run_checker("unit_run.py", &[path.as_os_str(), "--virtual-time".as_ref()], &script.join("\n"));
    assert_eq!(text.lines().count(), scans.len(), "one line per cycle");
    let wired: Vec<usize> =
        (0..fb.outputs.len()).filter(|&j| !fb.outputs[j].comment.contains("starts timer")).collect();
    text.lines()
        .map(|line| {
            let parts: Vec<Vec<u8>> = line.split(' ').map(common::hex_bytes).collect();
            let (data, q) = (&parts[0], parts[1][0]);
            let bit = |var: &str| {
                let l = location(var);
                data[l.byte as usize] >> l.bit & 1 == 1
            };
            let mut writes = 0;
            for (j, v) in fb.outputs.iter().enumerate() {
                writes |= u64::from(bit(&v.name)) << j;
            }
            for (k, &j) in wired.iter().enumerate() {
                assert_eq!(
                    q >> k & 1 == 1,
                    writes >> j & 1 == 1,
                    "{name}: output {} is wired to Q 0.{k}",
                    fb.outputs[j].name
                );
            }
            let l = location(&fb.locals[0].name);
            let state = i16::from_be_bytes([data[l.byte as usize], data[l.byte as usize + 1]]);
            Observed { writes, state: state as u32 }
        })
        .collect()
}

/// The STL form runs in awlsim (an S7 emulator, SFB 4 timers on a virtual clock) like the
/// machine: the representative machines and more random ones, 200 cycles each. Scans are 0,
/// 300 or 600 ms apart and presets 500, 700 or 1 100 ms, so no expiry falls on the instant the
/// emulator's floating-point clock could round either way.
#[test]
fn the_stl_form_runs_in_awlsim_like_the_machine() {
    let presets = [500, 700, 1100];
    let mut cases = representative(&presets);
    cases[0].1.spec.timers[0].preset_ms = 1100;
    cases[0].1.preset_ms = Some(1100);
    for seed in 1000..1006 {
        cases.push((format!("random_{seed}"), random_case(seed, &presets)));
    }
    let mut expired = 0;
    for (k, (name, case)) in cases.iter().enumerate() {
        let unit = lower(case);
        let mut rng = Rng::new(k as u64);
        let scans = random_scans(&mut rng, case, 200, &[0, 300, 600]);
        let (expected, seen) = reference(case, &scans);
        expired += seen;
        let observed = run_awlsim(name, &unit, &scans);
        if let Some((scan, e, o)) = first_difference(&expected, &observed) {
            panic!("{name}, scan {scan}: expected {e:?}, awlsim gives {o:?}");
        }
    }
    assert!(expired > 0, "a timer expired in the emulator");
}

/// The environment's counter-strategy (it reads the outputs and writes the inputs) is not a
/// controller: lowering it is an error located at the signal.
#[test]
fn a_counter_strategy_is_refused_at_the_signal() {
    let source = "INPUT req\nOUTPUT grant\n";
    let mut spec = Spec::default();
    spec.signals.push(Signal { name: "req".into(), kind: SignalKind::Input, span: Span::new(6, 9) });
    spec.signals.push(Signal { name: "grant".into(), kind: SignalKind::Output, span: Span::new(17, 22) });
    let counter = Machine {
        reads: vec![SignalId(1)],
        writes: vec![SignalId(0)],
        moves_first: false,
        init: StateId(0),
        states: vec![vec![Row { read: Cube::ANY, write: 1, next: StateId(0) }]],
    };
    let errors = lower_ltl::lower(source, &spec, &counter, &LowerOptions::default()).unwrap_err();
    let text = plcsynth::diag::render_plain("spec.ltl", source, &errors);
    assert!(text.contains("spec.ltl:2:8: error: the machine reads `grant`, which is not its input"), "{text}");
    assert!(text.contains("spec.ltl:1:7: error: the machine writes `req`, which is not its output"), "{text}");
}
