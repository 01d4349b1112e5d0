//! `plc::lower_ltl` checked against the machines it lowers: random controllers (Mealy and
//! Moore, with and without a timer) built directly as `ltl::Machine` values are lowered to a
//! `Unit`, which `plc::unit_exec` runs scan by scan on random inputs and a virtual clock; every
//! scan's outputs and state must be the machine's step (`Machine::row`, `first_write`), with the
//! timer's expiry computed from when the controller started it. A corrupted branch must be
//! caught. The printed code goes to the independent tools: blark parses the Structured Text
//! dialects, xmllint validates PLCopen against the TC6 schema, and awlsim runs the STL form
//! cycle by cycle against the same reference. The checkers come from
//! `scripts/python-checkers.sh` (run when missing).

mod common;

use plcsynth::diag::Span;
use plcsynth::ltl::{Cube, Machine, Row, Semantics, Signal, SignalId, SignalKind, Spec, StateId, Timer};
use plcsynth::plc::lower_ltl::{self, LowerOptions};
use plcsynth::plc::unit::{Expr, Place, PouKind, Stmt, Unit};
use plcsynth::plc::unit_exec::{self, Value};
use plcsynth::plc::{self, unit_stl, Target};
use plcsynth::rng::Rng;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

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
        (0..unit.signals.len()).filter(|&k| unit.signals[k].kind == plc::unit::SignalKind::Input).collect();
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
            .filter(|&k| unit.signals[k].kind == plc::unit::SignalKind::Output)
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
