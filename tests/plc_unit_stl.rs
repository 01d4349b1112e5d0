//! `plc::print::stl::unit` checked by running its output in awlsim (an independent S7 implementation):
//! random units (Boolean logic, INT/DINT arithmetic, REAL arithmetic and comparisons, nested IF,
//! dense and sparse CASE, function calls) against the crate's reference interpreter
//! `plc::model::exec`, cycle by cycle on random inputs; TON timers in real time; a controller FB
//! written in STL that calls one of the unit's FCs. awlsim comes from `scripts/python-checkers.sh` (`make test` runs it);
//! without it these tests fail and say so.

use crate::common;

use plcsynth::plc::model::exec::{Arithmetic, ExecError, Machine, Value};
use plcsynth::plc::model::unit::{BinOp, Expr, Place, Pou, PouKind, Signal, SignalKind, Stmt, Type, Unit, Var};
use plcsynth::plc::print::stl::unit::{self as unit_stl, Location, StlUnitOptions};

/// Runs `awl` in awlsim with one script line per cycle; the reads of each cycle, as bytes.
fn awlsim(name: &str, awl: &str, script: &[String]) -> Vec<Vec<Vec<u8>>> {
    let dir = std::env::temp_dir().join(format!("plcsynth-unit-stl-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(format!("{name}.awl"));
    std::fs::write(&path, awl).unwrap();
    let text = common::run_checker("unit_run.py", &[&path], &script.join("\n"));
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines.len(), script.len(), "one line per cycle:\n{text}");
    lines.iter().map(|l| l.split_whitespace().map(common::hex_bytes).collect()).collect()
}

// ---------------------------------------------------------------------------------------------
// The reference: the crate's interpreter `plc::model::exec`, in its accumulator arithmetic
// (every INT operation wraps at 16 bits, DINT at 32, as the CPU's and the printed code's do),
// its signals read from and written to process images at their addresses. Its REAL operations
// are computed in `f32` (as an S7 CPU does; awlsim rounds each result to `f32`), so REAL results
// and comparisons are compared exactly, bit for bit. The random units keep REAL values within
// ±1E4 between statements and expressions three deep, so no NaN, infinity or subnormal arises
// (awlsim saturates an overflow at ±3.4E38 where IEEE gives infinity).

/// A deliberate error of the reference, to show that the comparison finds one: the reference
/// runs the unit rewritten so.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Mutation {
    None,
    /// MOD as the Euclidean remainder (never negative).
    EuclidMod,
    /// XOR as OR.
    XorAsOr,
    /// REAL `a / b` as `a * (1.0 / b)`: rounded to `f32` twice.
    RealDivByReciprocal,
}

/// `unit` with `mutation` applied to every expression of its POUs.
fn mutated(unit: &Unit, mutation: Mutation) -> Unit {
    let mut unit = unit.clone();
    for pou in &mut unit.pous {
        mutate_stmts(&mut pou.body, mutation);
    }
    unit
}

fn mutate_stmts(body: &mut [Stmt], m: Mutation) {
    for s in body {
        match s {
            Stmt::Comment(_) => {}
            Stmt::Assign { value, .. } => *value = mutate(value, m),
            Stmt::If { arms, otherwise } => {
                for (cond, body) in arms {
                    *cond = mutate(cond, m);
                    mutate_stmts(body, m);
                }
                mutate_stmts(otherwise, m);
            }
            Stmt::Case { selector, arms, otherwise } => {
                *selector = mutate(selector, m);
                for (_, body) in arms {
                    mutate_stmts(body, m);
                }
                mutate_stmts(otherwise, m);
            }
            Stmt::CallFunction { args, .. } | Stmt::CallInstance { args, .. } => {
                for (_, e) in args {
                    *e = mutate(e, m);
                }
            }
            Stmt::Steps(list) => {
                for step in &mut list.steps {
                    for e in step.wait.iter_mut().chain(&mut step.when) {
                        *e = mutate(e, m);
                    }
                    mutate_stmts(&mut step.actions, m);
                }
            }
        }
    }
}

/// Whether divisor `e` of a random unit is REAL: its REAL divisors are a literal or
/// `v * v + 1.0`, its integer ones hold no REAL literal.
fn real_divisor(e: &Expr) -> bool {
    match e {
        Expr::Real(_) => true,
        Expr::Neg(a) => real_divisor(a),
        Expr::Binary(_, a, b) => real_divisor(a) || real_divisor(b),
        _ => false,
    }
}

fn mutate(e: &Expr, m: Mutation) -> Expr {
    match e {
        Expr::Not(a) => Expr::Not(Box::new(mutate(a, m))),
        Expr::Neg(a) => Expr::Neg(Box::new(mutate(a, m))),
        Expr::Binary(op, a, b) => {
            let (a, b) = (mutate(a, m), mutate(b, m));
            match (op, m) {
                (BinOp::Xor, Mutation::XorAsOr) => Expr::binary(BinOp::Or, a, b),
                (BinOp::Mod, Mutation::EuclidMod) => {
                    // ((a MOD b) + |b|) MOD |b|, |b| of a literal; the random units' other
                    // divisors, (x MOD 7) + 8, are positive.
                    let d = match b {
                        Expr::Int(v) => Expr::Int(v.abs()),
                        other => other,
                    };
                    let rem = Expr::binary(BinOp::Mod, a, d.clone());
                    Expr::binary(BinOp::Mod, Expr::binary(BinOp::Add, rem, d.clone()), d)
                }
                (BinOp::Div, Mutation::RealDivByReciprocal) if real_divisor(&b) => {
                    Expr::binary(BinOp::Mul, a, Expr::binary(BinOp::Div, Expr::real(1.0).unwrap(), b))
                }
                _ => Expr::binary(*op, a, b),
            }
        }
        other => other.clone(),
    }
}

fn image_address(address: &str) -> (char, usize, Option<u8>, usize) {
    // IX0.1, QW2, ID6, MX1.0: area, byte, bit, width in bytes.
    let area = address.chars().next().unwrap();
    let rest = &address[1..];
    let (size, number) = match rest.chars().next().unwrap() {
        c @ ('X' | 'B' | 'W' | 'D') => (c, &rest[1..]),
        _ => ('X', rest),
    };
    match size {
        'X' => {
            let (b, x) = number.split_once('.').unwrap();
            (area, b.parse().unwrap(), Some(x.parse().unwrap()), 0)
        }
        'B' => (area, number.parse().unwrap(), None, 1),
        'W' => (area, number.parse().unwrap(), None, 2),
        _ => (area, number.parse().unwrap(), None, 4),
    }
}

/// The bytes of `v` in a variable of type `ty` other than BOOL, big-endian as S7 keeps them:
/// two for INT, four for DINT and TIME, the `f32`'s bits for REAL.
fn value_bytes(v: Value, ty: &Type) -> Vec<u8> {
    match ty {
        Type::Int => (v.as_int() as i16).to_be_bytes().to_vec(),
        Type::Real => v.as_real().to_bits().to_be_bytes().to_vec(),
        _ => (v.as_int() as i32).to_be_bytes().to_vec(),
    }
}

/// The value of type `ty` (not BOOL) held in `bytes`, big-endian.
fn bytes_value(bytes: &[u8], ty: &Type) -> Value {
    match ty {
        Type::Int => Value::Int(i64::from(i16::from_be_bytes(bytes.try_into().unwrap()))),
        Type::Real => Value::Real(f32::from_bits(u32::from_be_bytes(bytes.try_into().unwrap()))),
        Type::Time => Value::Time(i64::from(i32::from_be_bytes(bytes.try_into().unwrap()))),
        _ => Value::Int(i64::from(i32::from_be_bytes(bytes.try_into().unwrap()))),
    }
}

/// The variables at `locations` as the data block holding them: `size` bytes.
fn data_block(locations: &[Location], size: usize, value: impl Fn(&str) -> Value) -> Vec<u8> {
    let mut db = vec![0u8; size];
    for l in locations {
        let (v, b) = (value(&l.name), l.byte as usize);
        match l.ty {
            Type::Bool => db[b] |= u8::from(v.as_bool()) << l.bit,
            _ => {
                let bytes = value_bytes(v, &l.ty);
                db[b..b + bytes.len()].copy_from_slice(&bytes);
            }
        }
    }
    db
}

/// The reference PLC: the interpreter with its process images.
struct Reference<'u> {
    unit: &'u Unit,
    machine: Machine<'u>,
}

impl<'u> Reference<'u> {
    fn new(unit: &'u Unit) -> Reference<'u> {
        let mut machine = Machine::new(unit).unwrap();
        machine.set_arithmetic(Arithmetic::Accumulator);
        Reference { unit, machine }
    }

    /// One cycle on the input image `inputs`.
    fn cycle(&mut self, inputs: &[u8]) {
        for (k, s) in self.unit.signals.iter().enumerate() {
            let (area, byte, bit, width) = image_address(&s.address);
            if area != 'I' {
                continue;
            }
            let v = match bit {
                Some(x) => Value::Bool(inputs[byte] >> x & 1 == 1),
                None => bytes_value(&inputs[byte..byte + width], &s.ty),
            };
            self.machine.set_signal(k, v);
        }
        let mut controller = |_: &mut Machine<'_>| Err(ExecError("the random units call no controller".into()));
        if let Err(e) = self.machine.cycle(&mut controller) {
            panic!("{}: the reference stops: {e:?}", self.unit.name);
        }
    }

    /// The first `size` bytes of process image `area` (`Q` or `M`) after the cycle.
    fn image(&self, area: char, size: usize) -> Vec<u8> {
        let mut image = vec![0u8; size];
        for (k, s) in self.unit.signals.iter().enumerate() {
            let (a, byte, bit, _) = image_address(&s.address);
            if a != area {
                continue;
            }
            let v = self.machine.signal(k);
            match bit {
                Some(x) => image[byte] |= u8::from(v.as_bool()) << x,
                None => {
                    let bytes = value_bytes(v, &s.ty);
                    image[byte..byte + bytes.len()].copy_from_slice(&bytes);
                }
            }
        }
        image
    }

    /// The global data block as bytes, laid out as the printer says.
    fn global_db(&self, options: &StlUnitOptions) -> Vec<u8> {
        let locations = unit_stl::global_locations(self.unit, options);
        let size = locations.iter().map(|l| l.byte as usize + 4).max().unwrap_or(0);
        data_block(&locations, size, |name| self.machine.global(name).unwrap())
    }
}

// ---------------------------------------------------------------------------------------------
// Random units.

/// The crate's generator, with the helpers these tests use.
struct Rng(plcsynth::rng::Rng);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0.next_u64()
    }

    fn below(&mut self, n: usize) -> usize {
        self.0.below(n as u64) as usize
    }

    fn range(&mut self, lo: i64, hi: i64) -> i64 {
        lo + self.0.below((hi - lo + 1) as u64) as i64
    }

    fn chance(&mut self, percent: u64) -> bool {
        self.0.chance(percent)
    }
}

fn signal(symbol: &str, kind: SignalKind, ty: Type, address: &str) -> Signal {
    Signal { symbol: symbol.into(), kind, ty, address: address.into(), comment: format!("{symbol} at {address}") }
}

// Signal numbers of the random units.
const BOOL_INPUTS: std::ops::Range<usize> = 0..8; // I 0.0 … I 0.7
const INT_INPUTS: [usize; 2] = [8, 9]; // IW 2, IW 4
const DINT_INPUT: usize = 10; // ID 6
const BOOL_OUTPUTS: std::ops::Range<usize> = 11..15; // Q 0.0 … Q 0.3
const INT_OUTPUT: usize = 15; // QW 2
const BOOL_MEMORY: usize = 16; // M 1.0
const INT_MEMORY: usize = 17; // MW 4
const REAL_INPUTS: [usize; 2] = [18, 19]; // ID 10, ID 14
const REAL_OUTPUT: usize = 20; // QD 4
const REAL_MEMORY: usize = 21; // MD 8

fn signals() -> Vec<Signal> {
    let mut s = Vec::new();
    for k in 0..8 {
        s.push(signal(&format!("in{k}"), SignalKind::Input, Type::Bool, &format!("IX0.{k}")));
    }
    s.push(signal("level", SignalKind::Input, Type::Int, "IW2"));
    s.push(signal("speed", SignalKind::Input, Type::Int, "IW4"));
    s.push(signal("count", SignalKind::Input, Type::Dint, "ID6"));
    for k in 0..4 {
        s.push(signal(&format!("out{k}"), SignalKind::Output, Type::Bool, &format!("QX0.{k}")));
    }
    s.push(signal("setpoint", SignalKind::Output, Type::Int, "QW2"));
    s.push(signal("flag", SignalKind::Memory, Type::Bool, "MX1.0"));
    s.push(signal("word", SignalKind::Memory, Type::Int, "MW4"));
    s.push(signal("x", SignalKind::Input, Type::Real, "ID10"));
    s.push(signal("y", SignalKind::Input, Type::Real, "ID14"));
    s.push(signal("valve", SignalKind::Output, Type::Real, "QD4"));
    s.push(signal("gain", SignalKind::Memory, Type::Real, "MD8"));
    s
}

/// What a random expression may read: the scope's names of each type.
struct Scope {
    bools: Vec<Place>,
    ints: Vec<Place>,
    dints: Vec<Place>,
    reals: Vec<Place>,
}

fn program_scope() -> Scope {
    let mut bools: Vec<Place> = BOOL_INPUTS.map(Place::Signal).collect();
    bools.extend(["b0", "b1", "b2", "b3", "K_ON"].map(Place::global));
    bools.push(Place::Signal(BOOL_MEMORY));
    bools.push(Place::Signal(11));
    bools.push(Place::local("pb"));
    let mut ints: Vec<Place> = INT_INPUTS.map(Place::Signal).to_vec();
    ints.extend(["n0", "n1", "n2", "n3", "state", "K_STEP"].map(Place::global));
    ints.push(Place::Signal(INT_MEMORY));
    ints.push(Place::local("pn"));
    let dints = vec![Place::Signal(DINT_INPUT), Place::global("d0"), Place::global("d1"), Place::global("K_BIG")];
    let mut reals: Vec<Place> = REAL_INPUTS.map(Place::Signal).to_vec();
    reals.extend([REAL_OUTPUT, REAL_MEMORY].map(Place::Signal));
    reals.extend(["r0", "r1", "r2", "K_HALF"].map(Place::global));
    reals.push(Place::local("pr"));
    Scope { bools, ints, dints, reals }
}

fn pick(rng: &mut Rng, places: &[Place]) -> Place {
    places[rng.below(places.len())].clone()
}

fn bool_expr(rng: &mut Rng, scope: &Scope, depth: usize) -> Expr {
    let leaf = depth == 0 || rng.chance(25);
    if leaf {
        return match rng.below(10) {
            0 => Expr::Bool(rng.chance(50)),
            _ => Expr::Read(pick(rng, &scope.bools)),
        };
    }
    let d = depth - 1;
    match rng.below(11) {
        9 | 10 => {
            let ops = [BinOp::Eq, BinOp::Ne, BinOp::Lt, BinOp::Le, BinOp::Gt, BinOp::Ge];
            let a = real_expr(rng, scope, d.min(2));
            // Now and then the same value on both sides, or a literal both can hold exactly.
            let b = match rng.below(6) {
                0 => a.clone(),
                1 => Expr::real(rng.range(-8, 8) as f64 * 0.5).unwrap(),
                _ => real_expr(rng, scope, d.min(2)),
            };
            Expr::binary(ops[rng.below(6)], a, b)
        }
        0 => bool_expr(rng, scope, d).not(),
        1 | 2 => bool_expr(rng, scope, d).and(bool_expr(rng, scope, d)),
        3 | 4 => bool_expr(rng, scope, d).or(bool_expr(rng, scope, d)),
        5 => Expr::binary(BinOp::Xor, bool_expr(rng, scope, d), bool_expr(rng, scope, d)),
        6 => Expr::binary(
            if rng.chance(50) { BinOp::Eq } else { BinOp::Ne },
            bool_expr(rng, scope, d),
            bool_expr(rng, scope, d),
        ),
        _ => {
            let ops = [BinOp::Eq, BinOp::Ne, BinOp::Lt, BinOp::Le, BinOp::Gt, BinOp::Ge];
            let wide = rng.chance(30);
            Expr::binary(ops[rng.below(6)], int_expr(rng, scope, d, wide), int_expr(rng, scope, d, false))
        }
    }
}

/// A REAL literal: a multiple of 1/8 (exact in `f32`) or of 1/10 (rounded).
fn real_literal(rng: &mut Rng) -> Expr {
    let x = if rng.chance(50) { rng.range(-400, 400) as f64 / 8.0 } else { rng.range(-500, 500) as f64 / 10.0 };
    Expr::real(x).unwrap()
}

/// A REAL expression over operands within ±1E4: at most eight factors (below 1E32), divisors
/// at least 1 (a literal, or `v * v + 1.0`).
fn real_expr(rng: &mut Rng, scope: &Scope, depth: usize) -> Expr {
    if depth == 0 || rng.chance(25) {
        return match rng.below(3) {
            0 => real_literal(rng),
            _ => Expr::Read(pick(rng, &scope.reals)),
        };
    }
    let d = depth - 1;
    match rng.below(9) {
        0 => real_expr(rng, scope, d).neg(),
        1 | 2 => Expr::binary(BinOp::Add, real_expr(rng, scope, d), real_expr(rng, scope, d)),
        3 | 4 => Expr::binary(BinOp::Sub, real_expr(rng, scope, d), real_expr(rng, scope, d)),
        5 | 6 => Expr::binary(BinOp::Mul, real_expr(rng, scope, d), real_expr(rng, scope, d)),
        _ => {
            let divisor = if rng.chance(50) {
                Expr::real(rng.range(1, 40) as f64 / 4.0 * if rng.chance(50) { 1.0 } else { -1.0 }).unwrap()
            } else {
                let v = Expr::Read(pick(rng, &scope.reals));
                Expr::binary(BinOp::Add, Expr::binary(BinOp::Mul, v.clone(), v), Expr::real(1.0).unwrap())
            };
            Expr::binary(BinOp::Div, real_expr(rng, scope, d), divisor)
        }
    }
}

/// `target := e` when `e` is within ±1E4, else a literal: REAL values stay bounded.
fn real_assign(rng: &mut Rng, scope: &Scope, target: Place) -> Stmt {
    let e = real_expr(rng, scope, 3);
    let bound = Expr::real(1e4).unwrap();
    let inside = Expr::binary(BinOp::Lt, e.clone(), bound.clone()).and(Expr::binary(BinOp::Gt, e.clone(), bound.neg()));
    Stmt::If {
        arms: vec![(inside, vec![Stmt::assign(target.clone(), e)])],
        otherwise: vec![Stmt::assign(target, real_literal(rng))],
    }
}

fn targets_real() -> Vec<Place> {
    vec![
        Place::global("r0"),
        Place::global("r1"),
        Place::global("r2"),
        Place::Signal(REAL_OUTPUT),
        Place::Signal(REAL_MEMORY),
        Place::local("pr"),
    ]
}

/// An INT expression, or DINT when `wide`.
fn int_expr(rng: &mut Rng, scope: &Scope, depth: usize, wide: bool) -> Expr {
    if depth == 0 || rng.chance(30) {
        return match rng.below(8) {
            0 | 1 => Expr::Int(rng.range(-60, 60)),
            2 if wide => Expr::Int(rng.range(40_000, 90_000) * if rng.chance(50) { 1 } else { -1 }),
            3 if wide => Expr::Read(pick(rng, &scope.dints)),
            _ => Expr::Read(pick(rng, &scope.ints)),
        };
    }
    let d = depth - 1;
    match rng.below(8) {
        0 => Expr::Neg(Box::new(int_expr(rng, scope, d, wide))),
        1 | 2 => Expr::binary(BinOp::Add, int_expr(rng, scope, d, wide), {
            let w = wide && rng.chance(50);
            int_expr(rng, scope, d, w)
        }),
        3 => Expr::binary(
            BinOp::Sub,
            {
                let w = wide && rng.chance(50);
                int_expr(rng, scope, d, w)
            },
            int_expr(rng, scope, d, wide),
        ),
        4 => Expr::binary(BinOp::Mul, int_expr(rng, scope, d, wide), int_expr(rng, scope, d, false)),
        _ => {
            // A divisor that is never zero: a literal, or (x MOD 7) + 8.
            let divisor = if rng.chance(50) {
                Expr::Int(rng.range(1, 9) * if rng.chance(50) { 1 } else { -1 })
            } else {
                Expr::binary(
                    BinOp::Add,
                    Expr::binary(
                        BinOp::Mod,
                        {
                            let w = wide && rng.chance(50);
                            int_expr(rng, scope, d, w)
                        },
                        Expr::Int(7),
                    ),
                    Expr::Int(8),
                )
            };
            let op = if rng.chance(50) { BinOp::Div } else { BinOp::Mod };
            Expr::binary(op, int_expr(rng, scope, d, wide), divisor)
        }
    }
}

fn targets_bool() -> Vec<Place> {
    let mut t: Vec<Place> = ["b0", "b1", "b2", "b3"].map(Place::global).to_vec();
    t.extend(BOOL_OUTPUTS.map(Place::Signal));
    t.push(Place::Signal(BOOL_MEMORY));
    t.push(Place::local("pb"));
    t
}

fn targets_int() -> Vec<Place> {
    vec![
        Place::global("n0"),
        Place::global("n1"),
        Place::global("n2"),
        Place::Signal(INT_OUTPUT),
        Place::Signal(INT_MEMORY),
        Place::local("pn"),
    ]
}

fn statement(rng: &mut Rng, scope: &Scope, depth: usize) -> Stmt {
    let choice = if depth == 0 { rng.below(4) } else { rng.below(12) };
    match choice {
        10 | 11 => {
            let target = pick(rng, &targets_real());
            real_assign(rng, scope, target)
        }
        0 | 1 => Stmt::assign(pick(rng, &targets_bool()), bool_expr(rng, scope, 4)),
        2 => Stmt::assign(pick(rng, &targets_int()), int_expr(rng, scope, 3, false)),
        3 => {
            let target = if rng.chance(50) { Place::global("d0") } else { Place::global("d1") };
            Stmt::assign(target, int_expr(rng, scope, 3, true))
        }
        4 | 5 => {
            let arms =
                (0..1 + rng.below(3)).map(|_| (bool_expr(rng, scope, 3), block(rng, scope, depth - 1))).collect();
            let otherwise = if rng.chance(60) { block(rng, scope, depth - 1) } else { Vec::new() };
            Stmt::If { arms, otherwise }
        }
        6 | 7 => {
            let dense = rng.chance(50);
            let mut labels: Vec<i64> = if dense {
                (0..8).filter(|_| rng.chance(70)).collect()
            } else {
                (0..6).map(|_| rng.range(-40, 40) * 5).collect()
            };
            labels.dedup();
            let mut arms = Vec::new();
            while !labels.is_empty() {
                let take = (1 + rng.below(2)).min(labels.len());
                let these: Vec<i64> = labels.drain(..take).collect();
                if arms.iter().any(|(ls, _): &(Vec<i64>, Vec<Stmt>)| these.iter().any(|l| ls.contains(l))) {
                    continue;
                }
                arms.push((these, block(rng, scope, depth - 1)));
            }
            let selector = if dense {
                Expr::binary(
                    BinOp::Mod,
                    {
                        let w = rng.chance(30);
                        int_expr(rng, scope, 1, w)
                    },
                    Expr::Int(9),
                )
            } else {
                int_expr(rng, scope, 2, false)
            };
            let otherwise = if rng.chance(70) { block(rng, scope, depth - 1) } else { Vec::new() };
            Stmt::Case { selector, arms, otherwise }
        }
        _ => call(rng, scope),
    }
}

fn call(rng: &mut Rng, scope: &Scope) -> Stmt {
    match rng.below(5) {
        3 => Stmt::CallFunction {
            function: "norm2".into(),
            args: vec![("a".into(), real_expr(rng, scope, 2)), ("b".into(), real_expr(rng, scope, 2))],
            result: Some(pick(rng, &targets_real())),
        },
        4 => Stmt::CallFunction {
            function: "inside".into(),
            args: vec![
                ("px".into(), Expr::Read(pick(rng, &scope.reals))),
                ("py".into(), real_expr(rng, scope, 1)),
                ("r".into(), real_literal(rng)),
            ],
            result: Some(pick(rng, &targets_bool())),
        },
        0 => Stmt::CallFunction {
            function: "scale".into(),
            args: vec![("a".into(), int_expr(rng, scope, 2, false)), ("up".into(), bool_expr(rng, scope, 2))],
            result: Some(pick(rng, &targets_int())),
        },
        1 => Stmt::CallFunction {
            function: "above".into(),
            args: vec![("x".into(), int_expr(rng, scope, 2, true)), ("y".into(), int_expr(rng, scope, 1, false))],
            result: Some(pick(rng, &targets_bool())),
        },
        _ => Stmt::CallFunction {
            function: "nudge".into(),
            args: vec![("v".into(), int_expr(rng, scope, 2, false))],
            result: None,
        },
    }
}

fn block(rng: &mut Rng, scope: &Scope, depth: usize) -> Vec<Stmt> {
    (0..1 + rng.below(3)).map(|_| statement(rng, scope, depth)).collect()
}

/// Functions of the random units: results, locals with initial values, globals written.
fn functions() -> Vec<Pou> {
    let a = || Expr::local("a");
    let scale = Pou {
        kind: PouKind::Function { returns: Some(Type::Int) },
        name: "scale".into(),
        comment: "a times 3 minus the step, or a MOD 5; counts calls with up in n3".into(),
        inputs: vec![Var::new("a", Type::Int, "value"), Var::new("up", Type::Bool, "direction")],
        outputs: vec![],
        locals: vec![Var::new("acc", Type::Int, "starts at 4 on every call").with_init(Expr::Int(4))],
        body: vec![
            Stmt::If {
                arms: vec![(
                    Expr::local("up"),
                    vec![
                        Stmt::assign(
                            Place::local("scale"),
                            Expr::binary(
                                BinOp::Sub,
                                Expr::binary(BinOp::Mul, a(), Expr::Int(3)),
                                Expr::global("K_STEP"),
                            ),
                        ),
                        Stmt::assign(Place::global("n3"), Expr::binary(BinOp::Add, Expr::global("n3"), Expr::Int(1))),
                    ],
                )],
                otherwise: vec![Stmt::assign(Place::local("scale"), Expr::binary(BinOp::Mod, a(), Expr::Int(5)))],
            },
            Stmt::assign(Place::local("acc"), Expr::binary(BinOp::Add, Expr::local("acc"), a())),
            Stmt::assign(Place::local("scale"), Expr::binary(BinOp::Add, Expr::local("scale"), Expr::local("acc"))),
        ],
    };
    let above = Pou {
        kind: PouKind::Function { returns: Some(Type::Bool) },
        name: "above".into(),
        comment: "x > y; toggles b3".into(),
        inputs: vec![Var::new("x", Type::Dint, ""), Var::new("y", Type::Int, "")],
        outputs: vec![],
        locals: vec![],
        body: vec![
            Stmt::assign(Place::local("above"), Expr::binary(BinOp::Gt, Expr::local("x"), Expr::local("y"))),
            Stmt::assign(Place::global("b3"), Expr::global("b3").not()),
        ],
    };
    let nudge = Pou {
        kind: PouKind::Function { returns: None },
        name: "nudge".into(),
        comment: "n2 := v - n2".into(),
        inputs: vec![Var::new("v", Type::Int, "")],
        outputs: vec![],
        locals: vec![],
        body: vec![Stmt::assign(Place::global("n2"), Expr::binary(BinOp::Sub, Expr::local("v"), Expr::global("n2")))],
    };
    let (ra, rb) = (|| Expr::local("a"), || Expr::local("b"));
    let square = |e: Expr| Expr::binary(BinOp::Mul, e.clone(), e);
    let norm2 = Pou {
        kind: PouKind::Function { returns: Some(Type::Real) },
        name: "norm2".into(),
        comment: "a*a + b*b + acc, at most 1E4; acc starts at 0.5 on every call and counts in r2".into(),
        inputs: vec![Var::new("a", Type::Real, ""), Var::new("b", Type::Real, "")],
        outputs: vec![],
        locals: vec![Var::new("acc", Type::Real, "").with_init(Expr::real(0.5).unwrap())],
        body: vec![
            Stmt::assign(
                Place::local("norm2"),
                Expr::binary(BinOp::Add, Expr::binary(BinOp::Add, square(ra()), square(rb())), Expr::local("acc")),
            ),
            Stmt::when(
                Expr::binary(BinOp::Gt, Expr::local("norm2"), Expr::real(1e4).unwrap()),
                vec![Stmt::assign(Place::local("norm2"), Expr::real(1e4).unwrap())],
            ),
            Stmt::assign(Place::local("acc"), Expr::binary(BinOp::Mul, Expr::local("acc"), Expr::local("norm2"))),
            Stmt::when(
                Expr::binary(BinOp::Lt, Expr::global("r2"), Expr::real(9000.0).unwrap()),
                vec![Stmt::assign(
                    Place::global("r2"),
                    Expr::binary(BinOp::Add, Expr::global("r2"), Expr::global("K_HALF")),
                )],
            ),
        ],
    };
    let inside = Pou {
        kind: PouKind::Function { returns: Some(Type::Bool) },
        name: "inside".into(),
        comment: "px*px + py*py < r*r (the point within radius r)".into(),
        inputs: vec![Var::new("px", Type::Real, ""), Var::new("py", Type::Real, ""), Var::new("r", Type::Real, "")],
        outputs: vec![],
        locals: vec![],
        body: vec![Stmt::assign(
            Place::local("inside"),
            Expr::binary(
                BinOp::Lt,
                Expr::binary(BinOp::Add, square(Expr::local("px")), square(Expr::local("py"))),
                square(Expr::local("r")),
            ),
        )],
    };
    vec![scale, above, nudge, norm2, inside]
}

/// A big state machine: CASE over `state` with `arms` arms (labels 0, `step`, 2·`step`, …).
fn big_case(rng: &mut Rng, arms: i64, step: i64) -> Stmt {
    let arms: Vec<(Vec<i64>, Vec<Stmt>)> = (0..arms)
        .map(|k| {
            let next = Expr::binary(
                BinOp::Mod,
                Expr::binary(
                    BinOp::Add,
                    Expr::binary(BinOp::Mul, Expr::global("state"), Expr::Int(rng.range(2, 9))),
                    Expr::Read(Place::Signal(INT_INPUTS[0])),
                ),
                Expr::Int(arms * step + 3),
            );
            (
                vec![k * step],
                vec![Stmt::assign(Place::global("state"), next), Stmt::assign(Place::global("n1"), Expr::Int(k))],
            )
        })
        .collect();
    Stmt::Case {
        selector: Expr::global("state"),
        arms,
        otherwise: vec![
            Stmt::Comment("unknown state".into()),
            Stmt::assign(
                Place::global("state"),
                Expr::binary(
                    BinOp::Add,
                    Expr::binary(BinOp::Mod, Expr::global("state"), Expr::Int(step * 3)),
                    Expr::Int(step * 3),
                ),
            ),
        ],
    }
}

/// A BOOL expression nested `levels` deep (deeper than S7's seven brackets).
fn deep_expr(rng: &mut Rng, scope: &Scope, levels: usize) -> Expr {
    let mut e = bool_expr(rng, scope, 1);
    for k in 0..levels {
        let leaf = Expr::Read(pick(rng, &scope.bools));
        let other = if k % 3 == 0 { bool_expr(rng, scope, 2) } else { Expr::Read(pick(rng, &scope.bools)) };
        e = match k % 4 {
            0 => e.or(leaf).and(other),
            1 => e.and(leaf).or(other.not()),
            2 => Expr::binary(BinOp::Xor, e.or(leaf), other),
            _ => e.and(leaf).not().or(other),
        };
    }
    e
}

fn random_unit(seed: u64) -> Unit {
    let mut rng = Rng(plcsynth::rng::Rng::new(seed));
    let scope = program_scope();
    let mut globals = Vec::new();
    for k in 0..4 {
        globals.push(Var::new(format!("b{k}"), Type::Bool, "").with_init(Expr::Bool(rng.chance(50))));
    }
    for k in 0..4 {
        globals.push(Var::new(format!("n{k}"), Type::Int, "").with_init(Expr::Int(rng.range(-300, 300))));
    }
    globals.push(Var::new("state", Type::Int, "supervisor state").with_init(Expr::Int(rng.range(0, 20))));
    globals.push(Var::new("d0", Type::Dint, "").with_init(Expr::Int(rng.range(-100_000, 100_000))));
    globals.push(Var::new("d1", Type::Dint, "").with_init(Expr::Int(7)));
    globals.push(Var::new("r0", Type::Real, "").with_init(real_literal(&mut rng)));
    globals.push(Var::new("r1", Type::Real, "").with_init(Expr::real(-0.1).unwrap()));
    globals.push(Var::new("r2", Type::Real, "counts norm2 calls by halves"));
    let constants = vec![
        Var::new("K_ON", Type::Bool, "").with_init(Expr::Bool(true)),
        Var::new("K_STEP", Type::Int, "event id").with_init(Expr::Int(7)),
        Var::new("K_BIG", Type::Dint, "").with_init(Expr::Int(123_456)),
        Var::new("K_HALF", Type::Real, "").with_init(Expr::real(0.5).unwrap()),
    ];
    let mut body: Vec<Stmt> = (0..14).map(|_| statement(&mut rng, &scope, 3)).collect();
    body.insert(0, Stmt::Comment("random statements\nover two lines".into()));
    body.push(Stmt::assign(Place::global("b0"), deep_expr(&mut rng, &scope, 16)));
    body.push(Stmt::assign(Place::Signal(BOOL_OUTPUTS.start + 1), deep_expr(&mut rng, &scope, 12)));
    body.push(big_case(&mut rng, 200, 1));
    body.push(big_case(&mut rng, 300, 3));
    let program = Pou {
        kind: PouKind::Program,
        name: "main".into(),
        comment: "random program".into(),
        inputs: vec![],
        outputs: vec![],
        locals: vec![
            Var::new("pb", Type::Bool, "a static BOOL").with_init(Expr::Bool(true)),
            Var::new("pn", Type::Int, "a static INT").with_init(Expr::Int(-3)),
            Var::new("pr", Type::Real, "a static REAL").with_init(Expr::real(2.5).unwrap()),
        ],
        body,
    };
    let mut pous = functions();
    pous.push(program);
    Unit {
        name: format!("random{seed}"),
        header: vec![format!("random unit {seed}")],
        gvl: "GVL".into(),
        constants,
        globals,
        signals: signals(),
        pous,
    }
}

/// Runs `unit` in awlsim and in the reference on the same random inputs; the reference's
/// mismatches with each mutation (`Mutation::None` must have none).
fn compare(unit: &Unit, seed: u64, cycles: usize, mutations: &[Mutation]) -> Vec<(Mutation, Option<String>)> {
    let options = StlUnitOptions::default();
    assert_eq!(unit_stl::check(unit, &options), Vec::<String>::new());
    let awl = unit_stl::render(unit, &options);
    let db_size = Reference::new(unit).global_db(&options).len();
    // The program's statics, where the header says they are.
    let program = unit_stl::program_locations(unit, &options);
    let program_size = program.iter().map(|l| l.byte + if l.ty == Type::Real { 4 } else { 2 }).max().unwrap();
    let mut rng = Rng(plcsynth::rng::Rng::new(seed ^ 0x5eed));
    let inputs: Vec<Vec<u8>> = (0..cycles)
        .map(|_| {
            let mut bytes = vec![0u8; 18];
            bytes[0] = rng.next() as u8;
            // Levels and counts in ranges that also make products overflow now and then.
            let level = rng.range(-400, 400) as i16;
            let speed = if rng.chance(20) { rng.range(-32768, 32767) } else { rng.range(-50, 50) } as i16;
            let count = rng.range(-200_000, 200_000) as i32;
            bytes[2..4].copy_from_slice(&level.to_be_bytes());
            bytes[4..6].copy_from_slice(&speed.to_be_bytes());
            bytes[6..10].copy_from_slice(&count.to_be_bytes());
            // REALs within ±100, in thousandths (mostly inexact in binary); now and then equal.
            let x = rng.range(-100_000, 100_000) as f32 / 1000.0;
            let y = if rng.chance(15) { x } else { rng.range(-100_000, 100_000) as f32 / 1000.0 };
            bytes[10..14].copy_from_slice(&x.to_be_bytes());
            bytes[14..18].copy_from_slice(&y.to_be_bytes());
            bytes
        })
        .collect();
    let script: Vec<String> = inputs
        .iter()
        .map(|bytes| {
            let mut line: Vec<String> = bytes.iter().enumerate().map(|(i, b)| format!("I{i}={b}")).collect();
            line.push(format!("?DB{}:0:{db_size}", options.first_db));
            line.push(format!("?DB{}:0:{program_size}", program[0].db));
            line.push("?Q0:8".into());
            line.push("?M0:12".into());
            line.join(" ")
        })
        .collect();
    let trace = awlsim(&unit.name, &awl, &script);
    mutations
        .iter()
        .map(|&mutation| {
            let unit = mutated(unit, mutation);
            let mut m = Reference::new(&unit);
            for (k, bytes) in inputs.iter().enumerate() {
                m.cycle(bytes);
                let statics =
                    data_block(&program, program_size as usize, |name| m.machine.program_value(name).unwrap());
                let expected = [m.global_db(&options), statics, m.image('Q', 8), m.image('M', 12)];
                if trace[k] != expected {
                    let globals: Vec<(&str, Value)> = unit
                        .globals
                        .iter()
                        .filter_map(|v| Some((v.name.as_str(), m.machine.global(&v.name)?)))
                        .collect();
                    return (
                        mutation,
                        Some(format!(
                            "cycle {k}: awlsim {:02x?}, reference {expected:02x?}\nglobals {globals:?}",
                            trace[k]
                        )),
                    );
                }
            }
            (mutation, None)
        })
        .collect()
}

#[test]
fn random_units_run_in_awlsim_as_the_reference_says() {
    // One awlsim process per unit, side by side (awlsim starts in about a second).
    let failures: Vec<String> = std::thread::scope(|s| {
        let runs: Vec<_> = (1..=3u64)
            .map(|seed| {
                s.spawn(move || {
                    let unit = random_unit(seed);
                    let mutations = if seed == 1 {
                        vec![Mutation::None, Mutation::EuclidMod, Mutation::XorAsOr, Mutation::RealDivByReciprocal]
                    } else {
                        vec![Mutation::None]
                    };
                    let mut failures = Vec::new();
                    for (mutation, mismatch) in compare(&unit, seed, 150, &mutations) {
                        match (mutation, mismatch) {
                            (Mutation::None, None) => {}
                            (Mutation::None, Some(m)) => failures.push(format!("seed {seed}: {m}")),
                            // The comparison must notice a wrong reference.
                            (other, None) => {
                                failures.push(format!("seed {seed}: the mutation {other:?} went unnoticed"))
                            }
                            _ => {}
                        }
                    }
                    failures
                })
            })
            .collect();
        runs.into_iter().flat_map(|r| r.join().unwrap()).collect()
    });
    assert!(failures.is_empty(), "{}", failures.join("\n\n"));
}

/// A unit with timers (a global one and one local to the program), a function block of its own,
/// a function, and the user's controller, which calls that function from STL written here.
fn timer_unit() -> Unit {
    let start = 0;
    let req = 1;
    let level = 2;
    let signals = vec![
        signal("start", SignalKind::Input, Type::Bool, "IX0.0"),
        signal("req", SignalKind::Input, Type::Bool, "IX0.1"),
        signal("level", SignalKind::Input, Type::Int, "IW2"),
        signal("q1", SignalKind::Output, Type::Bool, "QX0.0"),
        signal("q2", SignalKind::Output, Type::Bool, "QX0.1"),
    ];
    let edges = Pou {
        kind: PouKind::FunctionBlock,
        name: "edges".into(),
        comment: "counts rising edges of inc from 100 on".into(),
        inputs: vec![Var::new("inc", Type::Bool, "")],
        outputs: vec![Var::new("n", Type::Int, "edges so far")],
        locals: vec![Var::new("prev", Type::Bool, ""), Var::new("seen", Type::Int, "").with_init(Expr::Int(100))],
        body: vec![
            Stmt::when(
                Expr::local("inc").and(Expr::local("prev").not()),
                vec![Stmt::assign(Place::local("seen"), Expr::binary(BinOp::Add, Expr::local("seen"), Expr::Int(1)))],
            ),
            Stmt::assign(Place::local("prev"), Expr::local("inc")),
            Stmt::assign(Place::local("n"), Expr::local("seen")),
        ],
    };
    let delay = Pou {
        kind: PouKind::FunctionBlock,
        name: "delay".into(),
        comment: "go delayed by 50 ms, through a timer of its own (a multi-instance)".into(),
        inputs: vec![Var::new("go", Type::Bool, "")],
        outputs: vec![Var::new("done", Type::Bool, ""), Var::new("waited", Type::Time, "")],
        locals: vec![Var::new("t", Type::Ton, "")],
        body: vec![
            Stmt::CallInstance {
                instance: Place::local("t"),
                args: vec![("IN".into(), Expr::local("go")), ("PT".into(), Expr::Time(50))],
            },
            Stmt::assign(Place::local("done"), Expr::read(Place::local("t").member("Q"))),
            Stmt::assign(Place::local("waited"), Expr::read(Place::local("t").member("ET"))),
        ],
    };
    let twice = Pou {
        kind: PouKind::Function { returns: Some(Type::Int) },
        name: "twice".into(),
        comment: "x * 2 + bias, for the controller".into(),
        inputs: vec![Var::new("x", Type::Int, "")],
        outputs: vec![],
        locals: vec![],
        body: vec![Stmt::assign(
            Place::local("twice"),
            Expr::binary(BinOp::Add, Expr::binary(BinOp::Mul, Expr::local("x"), Expr::Int(2)), Expr::global("bias")),
        )],
    };
    let t1 = || Place::global("t1");
    let t2 = || Place::local("t2");
    let program = Pou {
        kind: PouKind::Program,
        name: "main".into(),
        comment: String::new(),
        inputs: vec![],
        outputs: vec![],
        locals: vec![
            Var::new("t2", Type::Ton, "slow timer"),
            Var::new("ctrl", Type::Instance("Controller".into()), "the user's controller"),
        ],
        body: vec![
            Stmt::CallInstance {
                instance: t1(),
                args: vec![("IN".into(), Expr::Read(Place::Signal(start))), ("PT".into(), Expr::global("FAST"))],
            },
            Stmt::assign(Place::Signal(3), Expr::read(t1().member("Q"))),
            Stmt::assign(Place::global("et1"), Expr::read(t1().member("ET"))),
            Stmt::assign(
                Place::global("fast_done"),
                Expr::binary(BinOp::Ge, Expr::read(t1().member("ET")), Expr::Time(50)),
            ),
            Stmt::CallInstance {
                instance: t2(),
                args: vec![
                    ("IN".into(), Expr::Read(Place::Signal(start)).and(Expr::Bool(true))),
                    ("PT".into(), Expr::Time(1000)),
                ],
            },
            Stmt::assign(Place::Signal(4), Expr::read(t2().member("Q"))),
            Stmt::CallInstance {
                instance: Place::global("cnt"),
                args: vec![("inc".into(), Expr::Read(Place::Signal(req)))],
            },
            Stmt::assign(Place::global("edges_seen"), Expr::read(Place::global("cnt").member("n"))),
            Stmt::CallInstance {
                instance: Place::global("d1"),
                args: vec![("go".into(), Expr::Read(Place::Signal(start)))],
            },
            Stmt::CallInstance {
                instance: Place::global("d2"),
                args: vec![("go".into(), Expr::Read(Place::Signal(start)).not())],
            },
            Stmt::assign(Place::global("d1_done"), Expr::read(Place::global("d1").member("done"))),
            Stmt::assign(Place::global("d2_done"), Expr::read(Place::global("d2").member("done"))),
            Stmt::assign(Place::global("d1_waited"), Expr::read(Place::global("d1").member("waited"))),
            Stmt::CallInstance {
                instance: Place::local("ctrl"),
                args: vec![("req".into(), Expr::Read(Place::Signal(req)))],
            },
            Stmt::assign(
                Place::global("level_seen"),
                Expr::binary(BinOp::Add, Expr::Read(Place::Signal(level)), Expr::Int(0)),
            ),
        ],
    };
    Unit {
        name: "timers".into(),
        header: vec!["timers, a block of the unit and the user's controller".into()],
        gvl: "Supervisor".into(),
        constants: vec![Var::new("FAST", Type::Time, "").with_init(Expr::Time(50))],
        globals: vec![
            Var::new("t1", Type::Ton, "fast timer"),
            Var::new("et1", Type::Time, ""),
            Var::new("fast_done", Type::Bool, ""),
            Var::new("bias", Type::Int, "").with_init(Expr::Int(5)),
            Var::new("cnt", Type::Instance("edges".into()), ""),
            Var::new("edges_seen", Type::Int, ""),
            Var::new("level_seen", Type::Int, ""),
            Var::new("d1", Type::Instance("delay".into()), ""),
            Var::new("d2", Type::Instance("delay".into()), ""),
            Var::new("d1_done", Type::Bool, ""),
            Var::new("d2_done", Type::Bool, ""),
            Var::new("d1_waited", Type::Time, ""),
        ],
        signals,
        pous: vec![edges, delay, twice, program],
    }
}

/// The user's controller: calls the unit's FC 1 (`twice`) with IW 2, stores the result in MW 10
/// and copies its input `req` to Q 0.2.
const CONTROLLER: &str = "
FUNCTION_BLOCK FB 100
VAR_INPUT
	req : BOOL;
END_VAR
VAR_TEMP
	r : INT;
END_VAR
BEGIN
	CALL FC 1 (x := IW 2, RET_VAL := #r)
	L	#r
	T	MW 10
	A	#req
	=	Q 0.2
END_FUNCTION_BLOCK

DATA_BLOCK DB 100
	FB 100
BEGIN
END_DATA_BLOCK
";

#[test]
fn timers_blocks_and_the_controller_run_in_awlsim() {
    let unit = timer_unit();
    let options = StlUnitOptions::default();
    assert_eq!(unit_stl::check(&unit, &options), Vec::<String>::new());
    let awl = unit_stl::render(&unit, &options);
    for line in [
        "//   FC 1      FUNCTION twice(x : INT) : INT",
        "\tCALL\t#t (IN := #go, PT := T#50MS, Q := #t_Q, ET := #t_ET)",
        "//   DB 2      global t1: instance of SFB 4 (TON)",
        "//   DB 3      global cnt: instance of FB 1 (edges)",
        "//   FB 3      PROGRAM main, instance DB 7, called from OB 1",
        "//   DB 4      global d1: instance of FB 2 (delay)",
        "//   DB 6      main local t2: instance of SFB 4 (TON)",
        "//   FB 100    Controller (the user's controller, instance DB 100, called as `ctrl`; not in this file)",
        "//   FAST                     TIME  T#50MS",
    ] {
        assert!(awl.contains(line), "{line}\n{awl}");
    }
    let locations = unit_stl::global_locations(&unit, &options);
    let at = |name: &str| locations.iter().find(|l| l.name == name).unwrap().clone();
    let size = locations.iter().map(|l| l.byte + 4).max().unwrap();
    let program = format!("{awl}\n{CONTROLLER}");
    // Cycle by cycle: inputs (bit 0 start, bit 1 req; IW 2), a sleep before the cycle.
    let cycles: [(u8, i16, u32); 12] = [
        (0b00, 21, 0),
        (0b11, 21, 0),
        (0b01, 21, 150),
        (0b01, 21, 20),
        (0b01, -8, 20),
        (0b11, -8, 20),
        (0b01, -8, 20),
        (0b01, -8, 1000),
        (0b01, -8, 0),
        (0b10, 300, 0),
        (0b00, 300, 100),
        (0b10, 300, 0),
    ];
    let script: Vec<String> = cycles
        .iter()
        .map(|&(bits, level, sleep)| {
            let [hi, lo] = level.to_be_bytes();
            format!("S{sleep} I0={bits} I2={hi} I3={lo} ?DB1:0:{size} ?Q0:1 ?M10:2")
        })
        .collect();
    let trace = awlsim("timers", &program, &script);
    let int = |db: &[u8], name: &str| {
        let b = at(name).byte as usize;
        i64::from(i16::from_be_bytes([db[b], db[b + 1]]))
    };
    let dint = |db: &[u8], name: &str| {
        let b = at(name).byte as usize;
        i64::from(i32::from_be_bytes(db[b..b + 4].try_into().unwrap()))
    };
    let bit = |db: &[u8], name: &str| db[at(name).byte as usize] >> at(name).bit & 1 == 1;
    for (k, (&(bits, level, _), reads)) in cycles.iter().zip(&trace).enumerate() {
        let (db, q, mw) = (&reads[0], reads[1][0], i16::from_be_bytes([reads[2][0], reads[2][1]]));
        let start = bits & 1 == 1;
        // The controller calls FC 1 (twice) with IW 2: 2 * level + bias.
        assert_eq!(i64::from(mw), 2 * i64::from(level) + 5, "cycle {k}: MW 10");
        assert_eq!(q >> 2 & 1, bits >> 1 & 1, "cycle {k}: the controller copies req to Q 0.2");
        assert_eq!(int(db, "level_seen"), i64::from(level), "cycle {k}");
        assert_eq!(int(db, "bias"), 5);
        // Rising edges of req: cycles 1, 5, 9, 11 (the FB's count starts at 100).
        let edges = 100 + [1, 5, 9, 11].iter().filter(|&&c| c <= k).count() as i64;
        assert_eq!(int(db, "edges_seen"), edges, "cycle {k}: edges");
        // The fast timer (50 ms): off before start and after; on from the cycle after 150 ms,
        // and it stays on (with ET at its preset) while IN stays on.
        let fast = (2..=8).contains(&k);
        assert_eq!(q & 1 == 1, fast, "cycle {k}: t1.Q");
        assert_eq!(bit(db, "fast_done"), fast, "cycle {k}: t1.ET >= 50 ms");
        if fast {
            assert_eq!(dint(db, "et1"), 50, "cycle {k}: t1.ET stays at PT");
        }
        if !start {
            assert_eq!(dint(db, "et1"), 0, "cycle {k}: t1.ET");
        }
        // The slow timer (1 s): on only after the long sleep (cycles 2 to 6 are well below 1 s).
        let slow = (7..=8).contains(&k);
        assert_eq!(q >> 1 & 1 == 1, slow, "cycle {k}: t2.Q");
        // Two instances of a function block with a timer of its own: d1 follows start as t1
        // does, d2 follows NOT start (on for the 100 ms before cycle 10).
        assert_eq!(bit(db, "d1_done"), fast, "cycle {k}: d1.done");
        assert_eq!(bit(db, "d2_done"), (10..=11).contains(&k), "cycle {k}: d2.done");
        if fast {
            assert_eq!(dint(db, "d1_waited"), 50, "cycle {k}: d1.waited");
        }
    }
}

#[test]
fn what_stl_cannot_express_is_reported_not_printed_wrongly() {
    let mut unit = timer_unit();
    // A timer inside a function block (it would need a multi-instance), a name STL refuses,
    // a member of the controller, a second external block type, a DB clash.
    unit.pous[0].locals.push(Var::new("inner", Type::Instance("edges".into()), ""));
    unit.pous[0].locals.push(Var::new("t", Type::Ton, ""));
    unit.pous[0].locals.push(Var::new("t_ET", Type::Int, ""));
    unit.globals.push(Var::new("a_name_longer_than_twenty_four", Type::Bool, ""));
    unit.globals.push(Var::new("other", Type::Instance("Other".into()), ""));
    let program = unit.pous.last_mut().unwrap();
    program.body.push(Stmt::assign(Place::Signal(3), Expr::read(Place::local("ctrl").member("busy"))));
    program.body.push(Stmt::assign(Place::global("bias"), Expr::Bool(true)));
    program.body.push(Stmt::assign(Place::global("FAST"), Expr::Time(3)));
    program.body.push(Stmt::CallFunction { function: "missing".into(), args: vec![], result: None });
    program.body.push(Stmt::assign(Place::Signal(3), Expr::read(Place::Signal(2))));
    unit.globals.push(Var::new("too_big", Type::Int, "").with_init(Expr::Int(40_000)));
    let options = StlUnitOptions { controller_db: 3, ..StlUnitOptions::default() };
    let errors = unit_stl::check(&unit, &options);
    for part in [
        "`inner` of type edges in a function block",
        "timer `t` keeps its ET in `t_ET`, which is not a free STL name",
        "global `a_name_longer_than_twenty_four` is not an STL name",
        "several external block types",
        "cannot read `busy` of the controller instance",
        "`bias` of type INT gets a value of type BOOL",
        "constant `FAST` cannot be written",
        "the controller's DB 3 is also a data block of the unit",
        "`missing` is not a function of the unit",
        "`q1` of type BOOL gets a value of type INT",
        "the initial value of `too_big` is not a literal of type INT",
    ] {
        assert!(errors.iter().any(|e| e.contains(part)), "no error with {part:?} in {errors:#?}");
    }
    // Printing still works and marks the places.
    let text = unit_stl::render(&unit, &options);
    assert!(text.contains("// ERROR: "), "{text}");
}

#[test]
fn broken_units_get_errors_and_never_a_panic() {
    let options = StlUnitOptions::default();
    let empty = Unit {
        name: "empty".into(),
        header: vec![],
        gvl: "GVL".into(),
        constants: vec![],
        globals: vec![],
        signals: vec![],
        pous: vec![],
    };
    assert!(!unit_stl::check(&empty, &options).is_empty());
    assert!(unit_stl::render(&empty, &options).contains("DATA_BLOCK DB 1"));
    let bad_places = [
        Place::Signal(999),
        Place::local("nope"),
        Place::global("nope"),
        Place::global("bias").member("Q"),
        Place::global("FAST"),
        Place::local("ctrl").member("ET"),
        Place::Signal(INT_INPUTS[0]).member("x"),
    ];
    let bad_exprs = [
        Expr::Int(1 << 40),
        Expr::Time(u64::MAX),
        Expr::Bool(true).not().and(Expr::Int(3)),
        Expr::Neg(Box::new(Expr::Bool(false))),
        Expr::binary(BinOp::Lt, Expr::Bool(true), Expr::Int(2)),
        Expr::binary(BinOp::Add, Expr::global("fast_done"), Expr::Int(2)),
        Expr::binary(BinOp::And, Expr::global("bias"), Expr::Int(2)),
        Expr::Int(5).not(),
    ];
    let mut k = 0;
    for place in &bad_places {
        for value in bad_exprs.iter().chain([&Expr::global("bias"), &Expr::global("fast_done")]) {
            let mut unit = timer_unit();
            let body = &mut unit.pous.last_mut().unwrap().body;
            let stmt = match k % 5 {
                0 => Stmt::assign(place.clone(), value.clone()),
                1 => Stmt::when(value.clone(), vec![Stmt::assign(place.clone(), Expr::Bool(true))]),
                2 => Stmt::Case { selector: value.clone(), arms: vec![(vec![1, 1 << 40], vec![])], otherwise: vec![] },
                3 => Stmt::CallInstance { instance: place.clone(), args: vec![("IN".into(), value.clone())] },
                _ => Stmt::CallFunction {
                    function: "twice".into(),
                    args: vec![("x".into(), value.clone()), ("zz".into(), Expr::Bool(true))],
                    result: Some(place.clone()),
                },
            };
            body.insert(k % (body.len() + 1), stmt);
            k += 1;
            let errors = unit_stl::check(&unit, &options);
            assert!(!errors.is_empty(), "no error for {place:?} and {value:?}");
            assert!(unit_stl::render(&unit, &options).contains("// ERROR: "));
        }
    }
}
