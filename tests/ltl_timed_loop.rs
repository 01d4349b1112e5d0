//! The timed controllers in a closed loop: every specification with a timer among
//! `examples/ltl/*.ltl`, G4LTL's `sample.g4ltl` and a specification with the `UNTIL` pattern is
//! synthesised, lowered (`plc::lower::ltl::lower_outcome`), printed as S7 STL and run in awlsim
//! (SFB 4 timers on a virtual clock, `tests/checkers/timed_run.py`) for hundreds of cycles with
//! random inputs held for random stretches and random scan times scaled to the timer's preset.
//! From each run a timestamped trace (inputs, outputs, the timers' `Q` read from the instance
//! DB by awlsim's own field names) is checked by code that shares nothing with the engine's
//! automata:
//!
//! a. *the code is the machine*: the abstract [`Machine`] fed the same abstract inputs
//!    (predicates computed in `f32` from the REAL inputs, each timer's expiry from the virtual
//!    clock) writes what awlsim wrote, scan by scan; the DB's `Q` agrees with that expiry;
//! b. *the timer model* of `src/ltl/refine.rs` holds on the observed expiries;
//! c. *the specification* with its learned assumptions holds on the finite prefix: a
//!    three-valued evaluation (Kleene, `Unknown` past the end) that reports only definite
//!    violations; runs that break an assumption are counted and say nothing;
//! d. *the real-time meaning* of each `WHENEVER` pattern holds on the timestamps.
//!
//! Mutants must be caught: a shortened and a lengthened preset, a flipped output, and G4LTL-ST's
//! own start `t1(IN := 0, PT := …)` (appendix A), with which awlsim's TON never sets `Q`.

use crate::common;

use common::root;
use plcsynth::ltl::{self, Config, Format, Ltl, Machine, NumExpr, Relation, SignalId, Spec, Verdict};
use plcsynth::plc::model::unit::{Expr, Place, PouKind, Stmt, Type, Unit};
use plcsynth::plc::{self, lower::ltl as lower_ltl, Target};
use plcsynth::rng::Rng;

/// A specification with the `UNTIL` pattern (no example has one).
const UNTIL_SPEC: &str = "// A valve opened on request stays open until the level switch has been on for 500 ms.
WHENEVER req THEN valve UNTIL full FOR 500ms

INPUT req, full
OUTPUT valve
";

/// Examples that must be realizable and run (others with a timer run when realizable).
const REQUIRED: &[&str] = &[
    "fig1",
    "ex2_discrepancy",
    "ex3_safety_request",
    "ex4_muting",
    "ex5_conveyor_alarm",
    "jam_alarm",
    "sample",
    "until",
];

/// Specifications whose controllers meet their patterns' obligations on random inputs (ex4's
/// controller may keep `error` on and never mute; `sample` has no pattern).
const EXERCISED: &[&str] =
    &["fig1", "ex2_discrepancy", "ex3_safety_request", "ex5_conveyor_alarm", "jam_alarm", "until"];

/// One specification, synthesised and lowered.
struct Case {
    name: String,
    source: String,
    spec: Spec,
    /// The specification with the learned assumptions.
    refined: Spec,
    /// The controller (the product of the groups' machines in a compositional run).
    machine: Machine,
    unit: Unit,
    /// Inputs that may rise only while a timer is idle (never started, or expired): what
    /// `sample.g4ltl`'s assumption `req1 -> X (!req1 U t1.expire)` asks of the environment.
    gated: Vec<(SignalId, usize)>,
}

fn load(name: &str, source: String) -> Result<Case, String> {
    let (spec, _) = ltl::compile(&source, Format::G4ltl, &[]).map_err(|d| format!("{name}: {d:?}"))?;
    let outcome = ltl::synthesize(&spec, &Config::default(), &mut |_| true).map_err(|e| format!("{name}: {e}"))?;
    if outcome.verdict != Verdict::Realizable {
        return Err(format!("{name}: {:?} ({})", outcome.verdict, outcome.limit.clone().unwrap_or_default()));
    }
    let machine = outcome.controller.clone().expect("a realizable run has a controller");
    // A compositional run is lowered one state machine per group, as `plcsynth ltl --target`
    // does; the checks compare it with the product of the groups' machines.
    let unit = lower_ltl::lower_outcome(&source, &spec, &outcome, &Default::default())
        .expect("a controller")
        .map_err(|d| format!("{name}: lowering fails: {d:?}"))?;
    let refined = ltl::refined(&spec, &outcome.refinement);
    let mut gated = Vec::new();
    if name == "sample" {
        let req1 = spec.signal_id("req1").unwrap();
        gated.push((req1, spec.timers.iter().position(|t| t.name == "t1").unwrap()));
    }
    Ok(Case { name: name.to_string(), source, spec, refined, machine, unit, gated })
}

/// Where the block finds each of its inputs, and what its outputs and timers are.
struct Io {
    /// The program's input signals in the block's order: the spec's signal or numeric input,
    /// and the address (byte, bit) — REAL inputs are 4 bytes from `byte`.
    inputs: Vec<(Input, usize, u8)>,
    /// The block's outputs: field name and signal.
    outputs: Vec<(String, SignalId)>,
    /// Per timer of the spec (in order): its instance in the block.
    timers: Vec<String>,
}

#[derive(Clone, Copy, Debug)]
enum Input {
    Bool(SignalId),
    Real(usize),
}

fn io(case: &Case) -> Io {
    let fb = &case.unit.pous[0];
    let spec = &case.spec;
    let signals: Vec<&plc::model::unit::Signal> =
        case.unit.signals.iter().filter(|s| s.kind == plc::model::unit::SignalKind::Input).collect();
    assert_eq!(signals.len(), fb.inputs.len(), "{}: one program input per block input", case.name);
    let inputs = fb
        .inputs
        .iter()
        .zip(&signals)
        .map(|(var, signal)| {
            let name = var.comment.trim_start_matches("input ");
            let name = name.split(" in [").next().unwrap();
            let input = match spec.numeric.iter().position(|n| n.name == name) {
                Some(k) => {
                    assert_eq!(var.ty, Type::Real, "{}: {name} is REAL", case.name);
                    Input::Real(k)
                }
                None => Input::Bool(spec.signal_id(name).unwrap_or_else(|| panic!("{}: input {name}", case.name))),
            };
            let a = &signal.address;
            let (byte, bit) = if let Some(rest) = a.strip_prefix("IX") {
                let (byte, bit) = rest.split_once('.').unwrap();
                (byte.parse().unwrap(), bit.parse().unwrap())
            } else if let Some(rest) = a.strip_prefix("ID") {
                (rest.parse().unwrap(), 0)
            } else {
                panic!("{}: address {a}", case.name)
            };
            (input, byte, bit)
        })
        .collect();
    let outputs = fb
        .outputs
        .iter()
        .map(|var| {
            let c = &var.comment;
            let name = c.strip_prefix("output ").unwrap_or_else(|| c.split(": TRUE in a scan").next().unwrap());
            (var.name.clone(), spec.signal_id(name).unwrap_or_else(|| panic!("{}: output {name}", case.name)))
        })
        .collect();
    let timers = spec
        .timers
        .iter()
        .map(|t| {
            let comment = format!("timer {} (", t.name);
            fb.locals
                .iter()
                .find(|v| v.ty == Type::Ton && v.comment.starts_with(&comment))
                .unwrap_or_else(|| panic!("{}: timer {}", case.name, t.name))
                .name
                .clone()
        })
        .collect();
    Io { inputs, outputs, timers }
}

/// One scan of a run as the test drives it.
#[derive(Clone, Debug)]
struct Drive {
    dt: u64,
    /// Boolean inputs by signal index.
    bools: Vec<bool>,
    /// REAL inputs by numeric index.
    reals: Vec<f32>,
}

/// One scan as observed: the virtual time, what was driven, what the block wrote, and each
/// timer's `Q` and `ET` as its statics hold them after the scan.
#[derive(Clone, Debug)]
struct Scan {
    now: u64,
    drive: Drive,
    /// Outputs by signal index (only the written ones are meaningful).
    outputs: Vec<bool>,
    q: Vec<bool>,
    et: Vec<i64>,
}

/// Scan times in ms: multiples of a step that divides no preset, so that no sum of scan times
/// lands exactly on a preset (awlsim's clock is a float), at most an eighth of the shortest
/// preset on average a sixteenth.
fn scan_times(spec: &Spec) -> (u64, u64) {
    let presets: Vec<u64> = spec.timers.iter().map(|t| t.preset_ms).collect();
    let step = [7u64, 11, 13, 17, 19, 23].into_iter().find(|s| presets.iter().all(|p| p % s != 0)).unwrap();
    let shortest = presets.iter().copied().min().unwrap_or(1000);
    (step, (shortest / (8 * step)).max(2))
}

/// The predicate's truth value in `f32`, evaluated as the generated code does (left to right,
/// a power as repeated products).
fn num(e: &NumExpr, reals: &dyn Fn(usize) -> f32) -> f32 {
    match e {
        NumExpr::Const(text) => text.parse::<f64>().unwrap() as f32,
        NumExpr::Var(v) => reals(v.0 as usize),
        NumExpr::Neg(a) => -num(a, reals),
        NumExpr::Add(a, b) => num(a, reals) + num(b, reals),
        NumExpr::Sub(a, b) => num(a, reals) - num(b, reals),
        NumExpr::Mul(a, b) => num(a, reals) * num(b, reals),
        NumExpr::Div(a, b) => num(a, reals) / num(b, reals),
        NumExpr::Pow(a, n) => {
            let x = num(a, reals);
            if *n == 0 {
                1.0
            } else {
                (1..*n).fold(x, |acc, _| acc * x)
            }
        }
    }
}

fn relation(r: Relation, a: f32, b: f32) -> bool {
    match r {
        Relation::Lt => a < b,
        Relation::Le => a <= b,
        Relation::Gt => a > b,
        Relation::Ge => a >= b,
        Relation::Eq => a == b,
        Relation::Ne => a != b,
    }
}

/// The timer model on the virtual clock: per timer the time of the last scan that started it.
/// `expire` in a scan at `now`: started at all, and the preset has passed since.
#[derive(Clone)]
struct Timers {
    presets: Vec<u64>,
    started: Vec<Option<u64>>,
}

impl Timers {
    fn new(spec: &Spec) -> Timers {
        Timers { presets: spec.timers.iter().map(|t| t.preset_ms).collect(), started: vec![None; spec.timers.len()] }
    }
    fn expired(&self, k: usize, now: u64) -> bool {
        self.started[k].is_some_and(|t| now - t >= self.presets[k])
    }
}

/// Every signal's abstract value in one scan: inputs as driven, predicates in `f32`, expiries
/// from the timer model, outputs as observed (or as the machine wrote them).
fn abstract_valuation(spec: &Spec, drive: &Drive, timers: &Timers, now: u64, outputs: &[bool]) -> Vec<bool> {
    let mut v = vec![false; spec.signals.len()];
    for (i, s) in spec.signals.iter().enumerate() {
        if s.kind == ltl::SignalKind::Output {
            v[i] = outputs[i];
        } else {
            v[i] = drive.bools[i];
        }
    }
    for p in &spec.predicates {
        let reals = |k: usize| drive.reals[k];
        v[p.signal.index()] = relation(p.relation, num(&p.lhs, &reals), num(&p.rhs, &reals));
    }
    for (k, t) in spec.timers.iter().enumerate() {
        v[t.expire.index()] = timers.expired(k, now);
    }
    v
}

/// The machine's step on a full valuation: the written signals' values.
fn step(m: &Machine, state: &mut ltl::StateId, v: &[bool]) -> u64 {
    let valuation = m.reads.iter().enumerate().fold(0u64, |acc, (i, s)| acc | u64::from(v[s.index()]) << i);
    let row = m.row(*state, valuation);
    let write = if m.moves_first { m.first_write(*state) } else { row.write };
    *state = row.next;
    write
}

/// Random inputs for `n` scans: each Boolean input and each REAL input keeps its value for
/// 1–40 scans; scan times from [`scan_times`]. Gated inputs (see [`Case::gated`]) are only
/// true while their timer is idle, which the generator knows by running the machine.
fn drives(case: &Case, rng: &mut Rng, n: usize) -> Vec<Drive> {
    let spec = &case.spec;
    let (step_ms, max_k) = scan_times(spec);
    let mut hold = vec![0u64; spec.signals.len() + spec.numeric.len()];
    let mut bools = vec![false; spec.signals.len()];
    let mut reals = vec![0f32; spec.numeric.len()];
    let mut timers = Timers::new(spec);
    let mut state = case.machine.init;
    let mut now = 0;
    let mut out = Vec::new();
    for _ in 0..n {
        let dt = step_ms * (1 + rng.below(max_k));
        now += dt;
        for (i, s) in spec.signals.iter().enumerate() {
            if s.kind != ltl::SignalKind::Input || spec.predicate_of(SignalId(i as u32)).is_some() {
                continue;
            }
            if spec.timers.iter().any(|t| t.expire.index() == i) {
                continue;
            }
            if hold[i] == 0 {
                bools[i] = rng.chance(50);
                hold[i] = 1 + rng.below(40);
            }
            hold[i] -= 1;
        }
        for (k, input) in spec.numeric.iter().enumerate() {
            let h = spec.signals.len() + k;
            if hold[h] == 0 {
                let (lo, hi) = (input.lo.parse::<f64>().unwrap(), input.hi.parse::<f64>().unwrap());
                reals[k] = if rng.chance(50) {
                    // On a grid of quarters, to meet predicates' boundaries exactly.
                    let steps = ((hi - lo) * 4.0) as u64;
                    (lo + rng.below(steps + 1) as f64 / 4.0) as f32
                } else {
                    (lo + (hi - lo) * (rng.below(1 << 24) as f64 / f64::from(1 << 24))) as f32
                };
                hold[h] = 1 + rng.below(40);
            }
            hold[h] -= 1;
        }
        let mut drive = Drive { dt, bools: bools.clone(), reals: reals.clone() };
        for &(signal, timer) in &case.gated {
            let idle = timers.started[timer].is_none() || timers.expired(timer, now);
            drive.bools[signal.index()] &= idle;
        }
        // The machine's answer, to know when it starts the timers.
        let v = abstract_valuation(spec, &drive, &timers, now, &vec![false; spec.signals.len()]);
        let write = step(&case.machine, &mut state, &v);
        for (k, t) in spec.timers.iter().enumerate() {
            if let Some(j) = case.machine.writes.iter().position(|&s| s == t.start) {
                if write >> j & 1 == 1 {
                    timers.started[k] = Some(now);
                }
            }
        }
        out.push(drive);
    }
    out
}

/// Runs `unit` (of `case`) in awlsim on `drives`: the trace.
fn run(case: &Case, unit: &Unit, drives: &[Drive], tag: &str) -> Vec<Scan> {
    let io = io(case);
    let text = &plc::render_unit_files(unit, Target::Stl, &plc::Options::default()).unwrap()[0].text;
    let path = common::scratch("ltl-timed-loop", &format!("{}_{tag}.awl", case.name), text);
    let options = plc::unit_stl_options(&plc::Options::default());
    let program = unit.pous.iter().find(|p| p.kind == PouKind::Program).unwrap();
    let db = plc::print::stl::unit::instance_locations(unit, &options, &program.locals[0].name)[0].db;
    let mut fields: Vec<String> = io.outputs.iter().map(|(name, _)| name.clone()).collect();
    for t in &io.timers {
        fields.push(format!("{t}_Q"));
        fields.push(format!("{t}_ET"));
    }
    let bytes = io.inputs.iter().map(|&(i, byte, _)| byte + if matches!(i, Input::Real(_)) { 4 } else { 1 }).max();
    let script: Vec<String> = drives
        .iter()
        .map(|d| {
            let mut image = vec![0u8; bytes.unwrap_or(0)];
            for &(input, byte, bit) in &io.inputs {
                match input {
                    Input::Bool(s) => image[byte] |= u8::from(d.bools[s.index()]) << bit,
                    Input::Real(k) => image[byte..byte + 4].copy_from_slice(&d.reals[k].to_be_bytes()),
                }
            }
            let mut line = format!("T{}", d.dt);
            for (b, v) in image.iter().enumerate() {
                line.push_str(&format!(" I{b}={v}"));
            }
            line
        })
        .collect();
    let mut args = vec![path.clone().into_os_string(), db.to_string().into()];
    args.extend(fields.iter().map(Into::into));
    let text = common::run_checker("timed_run.py", &args, &script.join("\n"));
    assert_eq!(text.lines().count(), drives.len(), "{}: one line per cycle", case.name);
    let wired: Vec<SignalId> =
        io.outputs.iter().map(|&(_, s)| s).filter(|s| case.spec.timers.iter().all(|t| t.start != *s)).collect();
    let mut now = 0;
    text.lines()
        .zip(drives)
        .map(|(line, d)| {
            now += d.dt;
            let words: Vec<&str> = line.split(' ').collect();
            let value = |k: usize| words[k].parse::<i64>().unwrap();
            let mut outputs = vec![false; case.spec.signals.len()];
            for (k, (_, s)) in io.outputs.iter().enumerate() {
                outputs[s.index()] = value(k) == 1;
            }
            let n = io.outputs.len();
            let q = (0..io.timers.len()).map(|k| value(n + 2 * k) == 1).collect();
            let et = (0..io.timers.len()).map(|k| value(n + 2 * k + 1)).collect();
            // The program copies the block's outputs (not the timers' starts) to Q 0.0, 0.1, …
            let qbyte = u16::from_str_radix(words.last().unwrap().trim_start_matches("Q="), 16).unwrap();
            let qbyte = qbyte.rotate_left(8);
            for (k, s) in wired.iter().enumerate() {
                assert_eq!(qbyte >> k & 1 == 1, outputs[s.index()], "{}: output {} is wired", case.name, k);
            }
            Scan { now, drive: d.clone(), outputs, q, et }
        })
        .collect()
}

/// Three-valued truth on a finite prefix: `Unknown` where the future beyond it decides.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Tri {
    False,
    Unknown,
    True,
}

impl Tri {
    fn of(b: bool) -> Tri {
        if b {
            Tri::True
        } else {
            Tri::False
        }
    }
    fn not(self) -> Tri {
        match self {
            Tri::False => Tri::True,
            Tri::Unknown => Tri::Unknown,
            Tri::True => Tri::False,
        }
    }
    fn and(self, o: Tri) -> Tri {
        self.min(o)
    }
    fn or(self, o: Tri) -> Tri {
        self.max(o)
    }
    fn min(self, o: Tri) -> Tri {
        if self == Tri::False || o == Tri::False {
            Tri::False
        } else if self == Tri::Unknown || o == Tri::Unknown {
            Tri::Unknown
        } else {
            Tri::True
        }
    }
    fn max(self, o: Tri) -> Tri {
        self.not().min(o.not()).not()
    }
}

/// `f`'s value at every position of `trace` (valuations per scan) and one past its end, where
/// everything temporal is `Unknown`: each subformula once, backwards, so linear in the trace.
/// Sound for violations: Kleene logic is monotone, so `False` holds on every extension.
fn eval(f: &Ltl, trace: &[Vec<bool>]) -> Vec<Tri> {
    let n = trace.len();
    let mut out = vec![Tri::Unknown; n + 1];
    let backwards = |out: &mut Vec<Tri>, step: &dyn Fn(usize, Tri) -> Tri| {
        for i in (0..n).rev() {
            out[i] = step(i, out[i + 1]);
        }
    };
    match f {
        Ltl::True => (0..n).for_each(|i| out[i] = Tri::True),
        Ltl::False => (0..n).for_each(|i| out[i] = Tri::False),
        Ltl::Var(s) => (0..n).for_each(|i| out[i] = Tri::of(trace[i][s.index()])),
        Ltl::Not(a) => {
            let a = eval(a, trace);
            (0..n).for_each(|i| out[i] = a[i].not());
        }
        Ltl::And(xs) | Ltl::Or(xs) => {
            let conj = matches!(f, Ltl::And(_));
            (0..n).for_each(|i| out[i] = Tri::of(conj));
            for x in xs {
                let x = eval(x, trace);
                (0..n).for_each(|i| out[i] = if conj { out[i].and(x[i]) } else { out[i].or(x[i]) });
            }
        }
        Ltl::Implies(a, b) => {
            let (a, b) = (eval(a, trace), eval(b, trace));
            (0..n).for_each(|i| out[i] = a[i].not().or(b[i]));
        }
        Ltl::Iff(a, b) => {
            let (a, b) = (eval(a, trace), eval(b, trace));
            (0..n).for_each(|i| out[i] = a[i].and(b[i]).or(a[i].not().and(b[i].not())));
        }
        Ltl::Next(a) => {
            let a = eval(a, trace);
            (0..n).for_each(|i| out[i] = a[i + 1]);
        }
        Ltl::Globally(a) => {
            let a = eval(a, trace);
            backwards(&mut out, &|i, later| a[i].and(later));
        }
        Ltl::Finally(a) => {
            let a = eval(a, trace);
            backwards(&mut out, &|i, later| a[i].or(later));
        }
        // a U b = b || (a && X (a U b)); a W b likewise with an Unknown end; a R b = b && (a || X (a R b)).
        Ltl::Until(a, b) | Ltl::WeakUntil(a, b) => {
            let (a, b) = (eval(a, trace), eval(b, trace));
            backwards(&mut out, &|i, later| b[i].or(a[i].and(later)));
        }
        Ltl::Release(a, b) => {
            let (a, b) = (eval(a, trace), eval(b, trace));
            backwards(&mut out, &|i, later| b[i].and(a[i].or(later)));
        }
    }
    out
}

/// The first scan where a formula is definitely broken: for `G x`, the first scan where `x`
/// is `False`; otherwise scan 0.
fn first_break(f: &Ltl, trace: &[Vec<bool>]) -> Option<usize> {
    if eval(f, trace)[0] != Tri::False {
        return None;
    }
    Some(match f {
        Ltl::Globally(x) => eval(x, trace).iter().position(|&t| t == Tri::False).unwrap(),
        _ => 0,
    })
}

/// A table-1 pattern as written on a `WHENEVER` line, its conditions as formulas of a small
/// specification of their own (same declarations), evaluated by signal name.
struct Pattern {
    line: String,
    kind: Kind,
    preset_ms: u64,
    spec: Spec,
    a: Ltl,
    b: Ltl,
    c: Option<Ltl>,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    /// `WHENEVER a THEN b FOR T`
    HoldFor,
    /// `WHENEVER a FOR T THEN b`
    After,
    /// `WHENEVER a THEN b UNTIL c FOR T`
    UntilHeld,
}

fn duration(text: &str) -> u64 {
    let text = text.trim();
    if let Some(ms) = text.strip_suffix("ms") {
        ms.trim().parse().unwrap()
    } else if let Some(s) = text.strip_suffix('s') {
        (s.trim().parse::<f64>().unwrap() * 1000.0).round() as u64
    } else {
        panic!("duration {text}")
    }
}

fn patterns(source: &str) -> Vec<Pattern> {
    let declarations: String = source
        .lines()
        .filter(|l| ["INPUT", "OUTPUT", "TIMER"].iter().any(|k| l.trim_start().starts_with(k)))
        .map(|l| format!("{l}\n"))
        .collect();
    let mut out = Vec::new();
    for line in source.lines().map(str::trim).filter(|l| l.starts_with("WHENEVER ")) {
        let rest = &line["WHENEVER ".len()..];
        let (kind, a, b, c, t) = match (rest.find(" THEN "), rest.find(" FOR ")) {
            (Some(then), Some(for_)) if for_ < then => {
                (Kind::After, &rest[..for_], &rest[then + 6..], None, &rest[for_ + 5..then])
            }
            (Some(then), Some(for_)) => {
                let b = &rest[then + 6..for_];
                match b.find(" UNTIL ") {
                    Some(u) => (Kind::UntilHeld, &rest[..then], &b[..u], Some(&b[u + 7..]), &rest[for_ + 5..]),
                    None => (Kind::HoldFor, &rest[..then], b, None, &rest[for_ + 5..]),
                }
            }
            _ => panic!("pattern {line}"),
        };
        let mut text = declarations.clone();
        for x in [Some(a), Some(b), c].into_iter().flatten() {
            text.push_str(&format!("ALWAYS ({x})\n"));
        }
        let (spec, _) = ltl::compile(&text, Format::G4ltl, &[]).unwrap_or_else(|d| panic!("{text}: {d:?}"));
        let mut conditions = spec.guarantees.iter().map(|g| match &g.formula {
            Ltl::Globally(x) => (**x).clone(),
            other => panic!("{other:?}"),
        });
        let (a, b) = (conditions.next().unwrap(), conditions.next().unwrap());
        let c = conditions.next();
        out.push(Pattern { line: line.to_string(), kind, preset_ms: duration(t), spec, a, b, c });
    }
    out
}

/// A pattern condition in one scan: signals by name, predicates in `f32`.
fn holds(p: &Pattern, f: &Ltl, case: &Spec, scan: &Scan) -> bool {
    let value = |s: SignalId| -> bool {
        if let Some(pred) = p.spec.predicate_of(s) {
            let reals = |k: usize| {
                let name = &p.spec.numeric[k].name;
                scan.drive.reals[case.numeric.iter().position(|n| &n.name == name).unwrap()]
            };
            return relation(pred.relation, num(&pred.lhs, &reals), num(&pred.rhs, &reals));
        }
        let id = case.signal_id(p.spec.name(s)).unwrap();
        match case.signal(id).kind {
            ltl::SignalKind::Input => scan.drive.bools[id.index()],
            ltl::SignalKind::Output => scan.outputs[id.index()],
        }
    };
    let trace = vec![p.spec.signals.iter().enumerate().map(|(i, _)| value(SignalId(i as u32))).collect()];
    eval(f, &trace)[0] == Tri::True
}

/// What a run showed.
#[derive(Default, Debug, Clone)]
struct Report {
    scans: usize,
    virtual_ms: u64,
    /// Scans that read a timer expired (model), per timer.
    expired: Vec<usize>,
    /// Scans whose DB `Q` (not overwritten by a restart) was TRUE, per timer.
    q_seen: Vec<usize>,
    /// Scans where a pattern's real-time obligation was in force (beyond the trigger itself).
    obligations: usize,
    /// The assumption broken on this trace, if one is.
    assumption_broken: Option<String>,
}

/// a. The machine fed the trace's abstract inputs writes what awlsim wrote (the first scan
/// where it does not is the error); then the DB's `Q` must agree with the timer model wherever
/// the scan did not restart the timer, and be reset where it did.
fn check_machine(case: &Case, trace: &[Scan]) -> Result<Vec<Vec<bool>>, String> {
    let spec = &case.spec;
    let m = &case.machine;
    let mut timers = Timers::new(spec);
    let mut state = m.init;
    let mut valuations = Vec::new();
    let mut timer_error = None;
    for (n, scan) in trace.iter().enumerate() {
        let v = abstract_valuation(spec, &scan.drive, &timers, scan.now, &scan.outputs);
        let write = step(m, &mut state, &v);
        for (j, s) in m.writes.iter().enumerate() {
            if (write >> j & 1 == 1) != scan.outputs[s.index()] {
                let shown: Vec<String> =
                    m.reads.iter().map(|&r| format!("{}={}", spec.name(r), u8::from(v[r.index()]))).collect();
                return Err(format!(
                    "{}, scan {n} (t = {} ms): the machine writes {} = {}, awlsim {} (reads {})",
                    case.name,
                    scan.now,
                    spec.name(*s),
                    write >> j & 1 == 1,
                    scan.outputs[s.index()],
                    shown.join(" ")
                ));
            }
        }
        for (k, t) in spec.timers.iter().enumerate() {
            let started = scan.outputs[t.start.index()];
            let expired = v[t.expire.index()];
            if timer_error.is_none() && !started && scan.q[k] != expired {
                timer_error = Some(format!(
                    "{}, scan {n} (t = {} ms): timer {} has Q = {} in the DB (ET {} ms), the model says {expired}",
                    case.name, scan.now, t.name, scan.q[k], scan.et[k]
                ));
            }
            if timer_error.is_none() && started && (scan.q[k] || scan.et[k] != 0) {
                timer_error =
                    Some(format!("{}, scan {n}: timer {} restarted, but Q or ET not reset", case.name, t.name));
            }
            if started {
                timers.started[k] = Some(scan.now);
            }
        }
        valuations.push(v);
    }
    timer_error.map_or(Ok(valuations), Err)
}

/// b. The timer model of `refine` on the DB's `Q` (the expiry a scan read, wherever the scan
/// did not restart the timer and so overwrite it): no expiry before the first start, none in
/// the scan after a start, an expiry lasts until the next start, and one comes once the preset
/// has passed without a restart.
fn check_timer_model(case: &Case, trace: &[Scan]) -> Result<(), String> {
    for (k, t) in case.spec.timers.iter().enumerate() {
        let start = |n: usize| trace[n].outputs[t.start.index()];
        let seen = |n: usize| (!start(n)).then_some(trace[n].q[k]);
        let mut last_start: Option<usize> = None;
        for n in 0..trace.len() {
            let fail = |what: &str| Err(format!("{}, timer {}, scan {n}: {what}", case.name, t.name));
            match (last_start, seen(n)) {
                (None, Some(true)) => return fail("expired before the first start"),
                (Some(l), Some(true)) if l + 1 == n => return fail("expired in the scan after a start"),
                (Some(l), Some(false)) if trace[n].now - trace[l].now >= t.preset_ms => {
                    return fail("no expiry though the preset has passed without a restart")
                }
                _ => {}
            }
            if n > 0 && !start(n - 1) && seen(n - 1) == Some(true) && seen(n) == Some(false) {
                return fail("an expiry ended without a start");
            }
            if start(n) {
                last_start = Some(n);
            }
        }
    }
    Ok(())
}

/// c. Every assumption and guarantee of the refined specification on the abstract trace. An
/// assumption broken makes the run say nothing about the guarantees (reported).
fn check_spec(case: &Case, valuations: &[Vec<bool>]) -> Result<Option<String>, String> {
    let name = |s: SignalId| case.refined.name(s).to_string();
    for a in &case.refined.assumptions {
        if let Some(n) = first_break(&a.formula, valuations) {
            return Ok(Some(format!("{} (scan {n})", a.formula.to_infix(&name))));
        }
    }
    for g in &case.refined.guarantees {
        if let Some(n) = first_break(&g.formula, valuations) {
            return Err(format!("{}: guarantee {} broken at scan {n}", case.name, g.formula.to_infix(&name)));
        }
    }
    Ok(None)
}

/// d. The patterns' real-time meaning on the timestamps; the number of scans with an
/// obligation in force (beyond the trigger's own scan).
///
/// - `a THEN b FOR T`: in every scan less than T after the last scan with `a`, `b`;
/// - `a FOR T THEN b`: in every scan where `a` has held in every scan since the scan it rose
///   in, and that scan is at least T ago, `b` (the TON started at the rise and is read at the
///   start of a scan: it sees the time between the two scans);
/// - `a THEN b UNTIL c FOR T`: from a scan with `a` on, `b` in every scan until one where `c`
///   has held (as above) for T.
fn check_patterns(case: &Case, trace: &[Scan]) -> Result<usize, String> {
    let mut obligations = 0;
    for p in patterns(&case.source) {
        let at = |f: &Ltl, scan: &Scan| holds(&p, f, &case.spec, scan);
        let mut last_a: Option<u64> = None;
        let mut rise: Option<u64> = None;
        let mut active = false;
        for (n, scan) in trace.iter().enumerate() {
            let now = scan.now;
            let a = at(&p.a, scan);
            let b = at(&p.b, scan);
            let (required, trigger) = match p.kind {
                Kind::HoldFor => {
                    if a {
                        last_a = Some(now);
                    }
                    (last_a.is_some_and(|t| now - t < p.preset_ms), a)
                }
                Kind::After => {
                    rise = if a { rise.or(Some(now)) } else { None };
                    (rise.is_some_and(|t| now - t >= p.preset_ms), false)
                }
                Kind::UntilHeld => {
                    let c = at(p.c.as_ref().unwrap(), scan);
                    rise = if c { rise.or(Some(now)) } else { None };
                    let held = rise.is_some_and(|t| now - t >= p.preset_ms);
                    active = !held && (a || active);
                    (active, a)
                }
            };
            if required && !trigger {
                obligations += 1;
            }
            if required && !b {
                return Err(format!(
                    "{}: `{}` broken at scan {n} (t = {now} ms): last trigger at {:?} ms, rise at {:?} ms",
                    case.name, p.line, last_a, rise
                ));
            }
        }
    }
    Ok(obligations)
}

/// All four checks of one run.
fn check_all(case: &Case, trace: &[Scan]) -> Result<Report, String> {
    let valuations = check_machine(case, trace)?;
    check_timer_model(case, trace)?;
    let assumption_broken = check_spec(case, &valuations)?;
    let obligations = check_patterns(case, trace)?;
    let timers = &case.spec.timers;
    Ok(Report {
        scans: trace.len(),
        virtual_ms: trace.last().map_or(0, |s| s.now),
        expired: (0..timers.len()).map(|k| valuations.iter().filter(|v| v[timers[k].expire.index()]).count()).collect(),
        q_seen: (0..timers.len()).map(|k| trace.iter().filter(|s| s.q[k]).count()).collect(),
        obligations,
        assumption_broken,
    })
}

/// The specifications: every example with a timer, G4LTL's sample, the `UNTIL` one.
fn sources() -> Vec<(String, String)> {
    let mut out = Vec::new();
    let mut paths: Vec<_> = std::fs::read_dir(root().join("examples/ltl"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "ltl"))
        .collect();
    paths.sort();
    for path in paths {
        let text = std::fs::read_to_string(&path).unwrap();
        if text.lines().any(|l| {
            let l = l.trim_start();
            !l.starts_with("//") && (l.contains("TIMER") || l.contains("WHENEVER"))
        }) {
            out.push((path.file_stem().unwrap().to_string_lossy().into_owned(), text));
        }
    }
    let sample = root().join("../shared/ltl/g4ltl/sample.g4ltl");
    out.push(("sample".into(), std::fs::read_to_string(sample).unwrap()));
    out.push(("until".into(), UNTIL_SPEC.to_string()));
    out
}

const RUNS: u64 = 4;
const CYCLES: usize = 600;

/// Every timed controller in the loop: the four checks pass on every run, every timer expires
/// and every pattern's obligations are exercised, most runs keep the assumptions.
#[test]
fn timed_controllers_in_a_closed_loop_keep_their_specifications() {
    let started = std::time::Instant::now();
    let sources = sources();
    let results: Vec<(String, Result<Vec<Report>, String>)> = std::thread::scope(|scope| {
        let chunks: Vec<Vec<&(String, String)>> = (0..2).map(|h| sources.iter().skip(h).step_by(2).collect()).collect();
        let handles: Vec<_> = chunks
            .into_iter()
            .map(|chunk| {
                scope.spawn(move || {
                    chunk
                        .into_iter()
                        .map(|(name, text)| {
                            let result = load(name, text.clone()).map(|case| {
                                (0..RUNS)
                                    .map(|r| {
                                        let mut rng = Rng::new(0x71_3ed + r * 7919 + name.len() as u64);
                                        let d = drives(&case, &mut rng, CYCLES);
                                        let trace = run(&case, &case.unit, &d, &format!("run{r}"));
                                        check_all(&case, &trace).unwrap_or_else(|e| panic!("run {r}: {e}"))
                                    })
                                    .collect()
                            });
                            (name.clone(), result)
                        })
                        .collect::<Vec<_>>()
                })
            })
            .collect();
        handles.into_iter().flat_map(|h| h.join().unwrap()).collect()
    });
    let mut ran = 0;
    for (name, result) in &results {
        match result {
            Err(why) => {
                assert!(!REQUIRED.contains(&name.as_str()), "{why}");
                println!("{name:20} not run: {why}");
            }
            Ok(reports) => {
                ran += 1;
                let cycles: usize = reports.iter().map(|r| r.scans).sum();
                let virtual_ms: u64 = reports.iter().map(|r| r.virtual_ms).sum();
                let timers = reports[0].expired.len();
                let expired: Vec<usize> = (0..timers).map(|k| reports.iter().map(|r| r.expired[k]).sum()).collect();
                let q_seen: Vec<usize> = (0..timers).map(|k| reports.iter().map(|r| r.q_seen[k]).sum()).collect();
                let obligations: usize = reports.iter().map(|r| r.obligations).sum();
                let broken: Vec<&String> = reports.iter().filter_map(|r| r.assumption_broken.as_ref()).collect();
                println!(
                    "{name:20} {} runs, {cycles} cycles, {:.1} s virtual, scans with a timer expired {expired:?} \
                     (DB Q TRUE after the scan {q_seen:?}), {obligations} scans under a pattern's obligation, \
                     {} runs broke an assumption{}",
                    reports.len(),
                    virtual_ms as f64 / 1000.0,
                    broken.len(),
                    broken.first().map_or(String::new(), |b| format!(" (e.g. {b})"))
                );
                assert!(expired.iter().all(|&e| e > 0), "{name}: every timer expired in some run");
                assert!(2 * broken.len() < reports.len(), "{name}: most runs keep the assumptions");
                if EXERCISED.contains(&name.as_str()) {
                    assert!(obligations > 0, "{name}: the patterns' obligations were exercised");
                }
            }
        }
    }
    assert!(ran >= REQUIRED.len());
    println!("closed loop: {ran} specifications in {:.1} s", started.elapsed().as_secs_f64());
}

/// The block's calls of timer `instance`, everywhere in its body.
fn timer_calls<'a>(stmts: &'a mut [Stmt], instance: &str, out: &mut Vec<&'a mut Vec<(String, Expr)>>) {
    for s in stmts {
        match s {
            Stmt::CallInstance { instance: Place::Local(i), args } if i == instance => out.push(args),
            Stmt::If { arms, otherwise } => {
                for (_, body) in arms {
                    timer_calls(body, instance, out);
                }
                timer_calls(otherwise, instance, out);
            }
            Stmt::Case { arms, otherwise, .. } => {
                for (_, body) in arms {
                    timer_calls(body, instance, out);
                }
                timer_calls(otherwise, instance, out);
            }
            _ => {}
        }
    }
}

/// `case`'s unit with timer `k`'s preset `PT` set to `ms` in every call.
fn with_preset(case: &Case, k: usize, ms: u64) -> Unit {
    let mut unit = case.unit.clone();
    let instance = io(case).timers[k].clone();
    let mut calls = Vec::new();
    timer_calls(&mut unit.pous[0].body, &instance, &mut calls);
    let mut changed = 0;
    for args in calls {
        for (name, value) in args.iter_mut() {
            if name == "PT" {
                assert_eq!(*value, Expr::Time(case.spec.timers[k].preset_ms));
                *value = Expr::Time(ms);
                changed += 1;
            }
        }
    }
    assert_eq!(changed, 2, "{}: PT at the scan's start and at the restart", case.name);
    unit
}

fn case(name: &str) -> Case {
    let (_, text) = sources().into_iter().find(|(n, _)| n == name).unwrap();
    load(name, text).unwrap()
}

/// A run of `case` (seed `seed`) with `unit`: the drives and the trace.
fn mutant_run(case: &Case, unit: &Unit, seed: u64, tag: &str) -> Vec<Scan> {
    let d = drives(case, &mut Rng::new(seed), CYCLES);
    run(case, unit, &d, tag)
}

/// Mutated code must be caught: a preset shortened (fig1's light goes out early: a. and d.),
/// one lengthened (the jam alarm sounds late: a. and d.), one output flipped in one branch (a.).
#[test]
fn mutated_controllers_are_caught() {
    let fig1 = case("fig1");
    assert!(check_all(&fig1, &mutant_run(&fig1, &fig1.unit, 1, "plain")).is_ok());
    let short = mutant_run(&fig1, &with_preset(&fig1, 0, 5000), 1, "short");
    let a = check_machine(&fig1, &short).unwrap_err();
    assert!(a.contains("the machine writes"), "{a}");
    let d = check_patterns(&fig1, &short).unwrap_err();
    println!("fig1, preset 10 s -> 5 s:\n  a. {a}\n  d. {d}");

    let jam = case("jam_alarm");
    let long = mutant_run(&jam, &with_preset(&jam, 0, 4000), 2, "long");
    let a = check_machine(&jam, &long).unwrap_err();
    assert!(a.contains("the machine writes"), "{a}");
    let d = check_patterns(&jam, &long).unwrap_err();
    println!("jam_alarm, preset 2 s -> 4 s:\n  a. {a}\n  d. {d}");

    // ex5: in the initial state's branch, the first constant written to an output flips.
    let ex5 = case("ex5_conveyor_alarm");
    let mut unit = ex5.unit.clone();
    let init = i64::from(ex5.machine.init.0);
    let flipped = {
        let Some(Stmt::Case { arms, .. }) = unit.pous[0].body.iter_mut().find(|s| matches!(s, Stmt::Case { .. }))
        else {
            panic!("a CASE")
        };
        let (_, branch) = arms.iter_mut().find(|(labels, _)| labels.contains(&init)).unwrap();
        fn flip(stmts: &mut [Stmt]) -> Option<String> {
            for s in stmts {
                match s {
                    Stmt::Assign { target: Place::Local(name), value: Expr::Bool(b) } if name != "state" => {
                        *b = !*b;
                        return Some(name.clone());
                    }
                    Stmt::If { arms, .. } => {
                        if let Some(n) = flip(&mut arms[0].1) {
                            return Some(n);
                        }
                    }
                    _ => {}
                }
            }
            None
        }
        flip(branch).unwrap()
    };
    let trace = mutant_run(&ex5, &unit, 3, "flip");
    let a = check_machine(&ex5, &trace).unwrap_err();
    let rest = check_machine(&ex5, &trace).err().map(|_| {
        // The checks c. and d. on the abstract trace of the observed run.
        let mut timers = Timers::new(&ex5.spec);
        let valuations: Vec<Vec<bool>> = trace
            .iter()
            .map(|scan| {
                let v = abstract_valuation(&ex5.spec, &scan.drive, &timers, scan.now, &scan.outputs);
                for (k, t) in ex5.spec.timers.iter().enumerate() {
                    if scan.outputs[t.start.index()] {
                        timers.started[k] = Some(scan.now);
                    }
                }
                v
            })
            .collect();
        (check_spec(&ex5, &valuations), check_patterns(&ex5, &trace))
    });
    println!("ex5, {flipped} flipped in the initial state's branch:\n  a. {a}\n  c., d.: {rest:?}");
}

/// G4LTL-ST starts a timer with `t1(IN := 0, PT := …)` (appendix A). In awlsim a TON called
/// only with `IN := FALSE` never sets `Q`: the jam alarm with that start never sounds, though
/// the barrier stays blocked for far longer than 2 s; with the generated rising edge it does.
#[test]
fn g4ltl_st_start_never_sets_q() {
    let jam = case("jam_alarm");
    let instance = io(&jam).timers[0].clone();
    let mut unit = jam.unit.clone();
    let body = &mut unit.pous[0].body;
    let restart = body
        .iter()
        .position(|s| matches!(s, Stmt::If { arms, .. } if matches!(&arms[0].1[..], [Stmt::CallInstance { .. }, Stmt::CallInstance { .. }])))
        .expect("the restart after the CASE");
    let Stmt::If { arms, .. } = &mut body[restart] else { unreachable!() };
    arms[0].1 = vec![Stmt::CallInstance {
        instance: Place::local(&instance),
        args: vec![("IN".into(), Expr::Bool(false)), ("PT".into(), Expr::Time(2000))],
    }];
    let plain = mutant_run(&jam, &jam.unit, 4, "edge");
    let g4ltl = mutant_run(&jam, &unit, 4, "g4ltl");
    assert!(plain.iter().any(|s| s.q[0]), "the generated start sets Q");
    assert!(g4ltl.iter().all(|s| !s.q[0] && s.et[0] == 0), "IN := FALSE alone never sets Q nor runs ET");
    let longest = {
        let blocked = jam.spec.signal_id("blocked").unwrap();
        let (mut best, mut since) = (0, None);
        for s in &g4ltl {
            since = if s.drive.bools[blocked.index()] { since.or(Some(s.now)) } else { None };
            best = best.max(since.map_or(0, |t| s.now - t));
        }
        best
    };
    assert!(longest > 2000);
    let d = check_patterns(&jam, &g4ltl).unwrap_err();
    let a = check_machine(&jam, &g4ltl).unwrap_err();
    println!("G4LTL-ST's start (IN := FALSE only): Q never TRUE; blocked up to {longest} ms\n  a. {a}\n  d. {d}");
}

/// Every compositional run's groups lower to one block of state machines (`sample.g4ltl` once
/// gave its timer's start to every group that read the expiry: three groups wrote it).
#[test]
fn groups_of_a_compositional_run_lower() {
    for (name, text) in sources() {
        let (spec, _) = ltl::compile(&text, Format::G4ltl, &[]).unwrap();
        let outcome = ltl::synthesize(&spec, &Config::default(), &mut |_| true).unwrap();
        if let Some(lowered) = lower_ltl::lower_outcome(&text, &spec, &outcome, &Default::default()) {
            assert!(lowered.is_ok(), "{name}: {:?}", lowered.err());
        }
    }
}

/// The checks themselves have teeth: the finite-trace evaluator reports a broken safety part
/// and leaves open obligations open; the timer-model check rejects an expiry before the first
/// start and one that ends without a restart.
#[test]
fn the_finite_trace_checks_have_teeth() {
    let (a, b) = (Ltl::Var(SignalId(0)), Ltl::Var(SignalId(1)));
    let trace = |rows: &[[bool; 2]]| rows.iter().map(|r| r.to_vec()).collect::<Vec<_>>();
    let response = Ltl::globally(Ltl::implies(a.clone(), Ltl::next(b.clone())));
    assert_eq!(first_break(&response, &trace(&[[false, false], [true, false], [false, false]])), Some(1));
    assert_eq!(first_break(&response, &trace(&[[false, false], [true, false]])), None, "X b open at the end");
    let eventually = Ltl::globally(Ltl::implies(a.clone(), Ltl::finally(b.clone())));
    assert_eq!(eval(&eventually, &trace(&[[true, false], [false, false]]))[0], Tri::Unknown);
    let until = Ltl::until(a.clone(), b.clone());
    assert_eq!(eval(&until, &trace(&[[true, false], [false, false]]))[0], Tri::False);
    assert_eq!(eval(&until, &trace(&[[true, false], [true, false]]))[0], Tri::Unknown);
    assert_eq!(eval(&Ltl::weak_until(a.clone(), b.clone()), &trace(&[[true, false], [false, true]]))[0], Tri::True);
    assert_eq!(eval(&Ltl::release(a, b), &trace(&[[false, true], [false, false]]))[0], Tri::False);

    let jam = case("jam_alarm");
    let plain = mutant_run(&jam, &jam.unit, 8, "teeth");
    assert!(check_timer_model(&jam, &plain).is_ok());
    let start = jam.spec.timers[0].start.index();
    let first = plain.iter().position(|s| s.outputs[start]).unwrap();
    assert!(first > 0, "this run starts the timer after scan 0");
    let mut early = plain.clone();
    early[first - 1].q[0] = true;
    assert!(check_timer_model(&jam, &early).unwrap_err().contains("before the first start"));
    let mut dropped = plain.clone();
    let n = (1..dropped.len())
        .find(|&n| dropped[n - 1].q[0] && !dropped[n - 1].outputs[start] && !dropped[n].outputs[start])
        .expect("an expiry that lasts a scan");
    dropped[n].q[0] = false;
    assert!(check_timer_model(&jam, &dropped).is_err());
    assert!(check_machine(&jam, &dropped).is_err(), "the DB's Q against the model");
}
