//! Every structured target prints the code model's expressions through one printer per dialect
//! (`plc::print::st::unit`): random expressions with nested unary operators, every precedence
//! level and negative literals, printed by IEC ST, CODESYS, TwinCAT, SCL, SCL-1500, PLCopen and
//! ABB, are read back by the ST fragment parser (`plc::fragment`) as the same tree, and evaluate
//! to what the reference interpreter (`plc::model::exec`) computes for the source; blark parses
//! the printed units. A printer that drops parentheses (`NOT NOT a`, `--x`, `a - b - c` for
//! `a - (b - c)`) fails both ways.

use std::collections::HashMap;
use std::path::PathBuf;

use crate::common;
use plcsynth::plc::fragment::{self, ExprKind, UnOp};
use plcsynth::plc::model::exec::{Machine, Value};
use plcsynth::plc::model::unit::{BinOp, Expr, Place, Pou, PouKind, Stmt, Type, Unit, Var};
use plcsynth::plc::{render_unit_files, Options, Target};
use proptest::prelude::*;

/// The targets that print Structured Text (IL and STL have no expressions).
const STRUCTURED: [Target; 7] =
    [Target::St, Target::Codesys, Target::Twincat, Target::Scl, Target::Scl1500, Target::Plcopen, Target::Abb];

struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        // xorshift64*
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }
    fn range(&mut self, lo: i64, hi: i64) -> i64 {
        lo + (self.next() % (hi - lo + 1) as u64) as i64
    }
}

const BOOLS: [&str; 3] = ["b0", "b1", "b2"];
const INTS: [&str; 3] = ["n0", "n1", "n2"];
const REALS: [&str; 2] = ["r0", "r1"];

fn bool_expr(rng: &mut Rng, depth: u32) -> Expr {
    if depth == 0 || rng.below(5) == 0 {
        return match rng.below(6) {
            0 => Expr::Bool(rng.below(2) == 0),
            _ => Expr::global(BOOLS[rng.below(BOOLS.len())]),
        };
    }
    let d = depth - 1;
    let compare = [BinOp::Eq, BinOp::Ne, BinOp::Lt, BinOp::Le, BinOp::Gt, BinOp::Ge];
    match rng.below(10) {
        // Nested negations are what the printers got wrong: make them frequent.
        0 | 1 => bool_expr(rng, d).not(),
        2 => Expr::binary(BinOp::And, bool_expr(rng, d), bool_expr(rng, d)),
        3 => Expr::binary(BinOp::Or, bool_expr(rng, d), bool_expr(rng, d)),
        4 => Expr::binary(BinOp::Xor, bool_expr(rng, d), bool_expr(rng, d)),
        5 => Expr::binary([BinOp::Eq, BinOp::Ne][rng.below(2)], bool_expr(rng, d), bool_expr(rng, d)),
        6 | 7 => Expr::binary(compare[rng.below(6)], int_expr(rng, d), int_expr(rng, d)),
        _ => Expr::binary(compare[rng.below(6)], real_expr(rng, d), real_expr(rng, d)),
    }
}

fn int_expr(rng: &mut Rng, depth: u32) -> Expr {
    if depth == 0 || rng.below(4) == 0 {
        return match rng.below(3) {
            0 => Expr::Int(rng.range(-9, 9)),
            _ => Expr::global(INTS[rng.below(INTS.len())]),
        };
    }
    let d = depth - 1;
    match rng.below(8) {
        0 | 1 => int_expr(rng, d).neg(),
        2 => Expr::binary(BinOp::Add, int_expr(rng, d), int_expr(rng, d)),
        3 | 4 => Expr::binary(BinOp::Sub, int_expr(rng, d), int_expr(rng, d)),
        5 => Expr::binary(BinOp::Mul, int_expr(rng, d), int_expr(rng, d)),
        // A non-zero literal divisor: the source has no division by zero.
        _ => {
            let divisor = [-3, -2, 2, 3, 5][rng.below(5)];
            Expr::binary([BinOp::Div, BinOp::Mod][rng.below(2)], int_expr(rng, d), Expr::Int(divisor))
        }
    }
}

/// Multiples of 1/8: literals the printers write exactly.
fn real_expr(rng: &mut Rng, depth: u32) -> Expr {
    if depth == 0 || rng.below(4) == 0 {
        return match rng.below(3) {
            0 => Expr::real(rng.range(-40, 40) as f64 / 8.0).unwrap(),
            _ => Expr::global(REALS[rng.below(REALS.len())]),
        };
    }
    let d = depth - 1;
    match rng.below(6) {
        0 | 1 => real_expr(rng, d).neg(),
        2 => Expr::binary(BinOp::Add, real_expr(rng, d), real_expr(rng, d)),
        3 | 4 => Expr::binary(BinOp::Sub, real_expr(rng, d), real_expr(rng, d)),
        _ => Expr::binary(BinOp::Mul, real_expr(rng, d), real_expr(rng, d)),
    }
}

/// A unit whose program assigns `n` random expressions of each type to `bo{k}`, `no{k}`, `ro{k}`,
/// reading globals with random initial values.
fn random_unit(rng: &mut Rng, n: usize, depth: u32) -> Unit {
    let mut globals = Vec::new();
    for name in BOOLS {
        globals.push(Var::new(name, Type::Bool, "").with_init(Expr::Bool(rng.below(2) == 0)));
    }
    for name in INTS {
        globals.push(Var::new(name, Type::Int, "").with_init(Expr::Int(rng.range(-20, 20))));
    }
    for name in REALS {
        globals.push(Var::new(name, Type::Real, "").with_init(Expr::real(rng.range(-40, 40) as f64 / 8.0).unwrap()));
    }
    let mut body = Vec::new();
    for k in 0..n {
        for (prefix, ty) in [("bo", Type::Bool), ("no", Type::Dint), ("ro", Type::Real)] {
            let name = format!("{prefix}{k}");
            let e = match prefix {
                "bo" => bool_expr(rng, depth),
                "no" => int_expr(rng, depth),
                _ => real_expr(rng, depth),
            };
            globals.push(Var::new(&name, ty, ""));
            body.push(Stmt::assign(Place::global(name), e));
        }
    }
    let program = Pou {
        kind: PouKind::Program,
        name: "exprs_main".into(),
        comment: String::new(),
        inputs: vec![],
        outputs: vec![],
        locals: vec![],
        body,
    };
    Unit {
        name: "exprs".into(),
        header: vec![],
        gvl: "GVL".into(),
        constants: vec![],
        globals,
        signals: vec![],
        pous: vec![program],
    }
}

/// The text of `target`'s files for `unit`, with XML's CDATA brackets and character references
/// undone (PLCopen and TwinCAT carry the ST inside XML).
fn printed(unit: &Unit, target: Target) -> String {
    let files = render_unit_files(unit, target, &Options::default()).unwrap_or_else(|e| panic!("{target:?}: {e}"));
    let text: String = files.iter().map(|f| f.text.as_str()).collect::<Vec<_>>().join("\n");
    text.replace("<![CDATA[", "\n")
        .replace("]]>", "\n")
        .replace("&lt;", "<")
        .replace("&gt;", ">")
        .replace("&quot;", "\"")
        .replace("&apos;", "'")
        .replace("&amp;", "&")
}

/// The right-hand side of every assignment in `text`, by the assigned name's last component
/// (`GVL.bo3`, `"GVL".bo3` and `bo3` are all `bo3`).
fn assignments(text: &str) -> HashMap<String, String> {
    let mut out = HashMap::new();
    for line in text.lines() {
        let line = line.trim().replace('"', "");
        let Some((lhs, rhs)) = line.split_once(" := ") else { continue };
        let Some(rhs) = rhs.strip_suffix(';') else { continue };
        let name = lhs.rsplit('.').next().unwrap_or(lhs).trim();
        if name.len() > 2 && ["bo", "no", "ro"].contains(&&name[..2]) && name[2..].bytes().all(|b| b.is_ascii_digit()) {
            out.insert(name.to_string(), rhs.to_string());
        }
    }
    out
}

/// The tree of `-(tree)`: a literal's negation is a literal.
fn negated(tree: String) -> String {
    if let Ok(v) = tree.parse::<i64>() {
        (-v).to_string()
    } else if let (false, Ok(v)) = (tree.starts_with('('), tree.parse::<f32>()) {
        format!("{:?}", -v)
    } else {
        format!("(neg {tree})")
    }
}

/// A tree in one notation for both sides: a negated literal is the negative literal, since
/// `(-3)`, `-3` and `-(-(-3))` are the same value however a parser reads them.
fn source_tree(e: &Expr) -> String {
    match e {
        Expr::Bool(b) => b.to_string(),
        Expr::Int(v) => v.to_string(),
        Expr::Real(r) => format!("{:?}", r.value()),
        Expr::Neg(inner) => negated(source_tree(inner)),
        Expr::Not(inner) => format!("(not {})", source_tree(inner)),
        Expr::Read(Place::Global(name)) => name.clone(),
        Expr::Binary(op, a, b) => format!("({} {} {})", op.text(), source_tree(a), source_tree(b)),
        other => panic!("not generated: {other:?}"),
    }
}

fn parsed_tree(e: &fragment::Expr) -> String {
    match &e.kind {
        ExprKind::Bool(b) => b.to_string(),
        ExprKind::Int(text) => text.parse::<i64>().unwrap_or_else(|_| panic!("integer literal {text}")).to_string(),
        ExprKind::Real(text) => format!("{:?}", text.parse::<f32>().unwrap_or_else(|_| panic!("real literal {text}"))),
        ExprKind::Unary(UnOp::Neg, inner) => negated(parsed_tree(inner)),
        ExprKind::Unary(UnOp::Not, inner) => format!("(not {})", parsed_tree(inner)),
        ExprKind::Var(path) => path.last().unwrap().clone(),
        ExprKind::Binary(op, a, b) => format!("({} {} {})", op.text(), parsed_tree(a), parsed_tree(b)),
        other => panic!("printed code holds {other:?}"),
    }
}

/// The printed expression's value: integers exact but for 64-bit wrap-around (as the reference
/// interpreter computes them before a store), REALs in `f32`.
fn eval(e: &fragment::Expr, env: &HashMap<String, Value>) -> Value {
    match &e.kind {
        ExprKind::Bool(b) => Value::Bool(*b),
        ExprKind::Int(text) => Value::Int(text.parse().unwrap()),
        ExprKind::Real(text) => Value::Real(text.parse().unwrap()),
        ExprKind::Var(path) => env[path.last().unwrap()],
        ExprKind::Unary(UnOp::Not, a) => Value::Bool(!eval(a, env).as_bool()),
        ExprKind::Unary(UnOp::Neg, a) => match eval(a, env) {
            Value::Real(x) => Value::Real(-x),
            v => Value::Int(v.as_int().wrapping_neg()),
        },
        ExprKind::Binary(op, a, b) => {
            let (p, q) = (eval(a, env), eval(b, env));
            match (p, q) {
                (Value::Real(x), Value::Real(y)) => match op {
                    BinOp::Add => Value::Real(x + y),
                    BinOp::Sub => Value::Real(x - y),
                    BinOp::Mul => Value::Real(x * y),
                    BinOp::Eq => Value::Bool(x == y),
                    BinOp::Ne => Value::Bool(x != y),
                    BinOp::Lt => Value::Bool(x < y),
                    BinOp::Le => Value::Bool(x <= y),
                    BinOp::Gt => Value::Bool(x > y),
                    BinOp::Ge => Value::Bool(x >= y),
                    _ => panic!("{op:?} of REALs"),
                },
                (Value::Bool(x), Value::Bool(y)) => Value::Bool(match op {
                    BinOp::And => x && y,
                    BinOp::Or => x || y,
                    BinOp::Xor | BinOp::Ne => x != y,
                    BinOp::Eq => x == y,
                    _ => panic!("{op:?} of BOOLs"),
                }),
                _ => {
                    let (i, j) = (p.as_int(), q.as_int());
                    match op {
                        BinOp::Add => Value::Int(i.wrapping_add(j)),
                        BinOp::Sub => Value::Int(i.wrapping_sub(j)),
                        BinOp::Mul => Value::Int(i.wrapping_mul(j)),
                        BinOp::Div => Value::Int(i.wrapping_div(j)),
                        BinOp::Mod => Value::Int(i.wrapping_rem(j)),
                        BinOp::Eq => Value::Bool(i == j),
                        BinOp::Ne => Value::Bool(i != j),
                        BinOp::Lt => Value::Bool(i < j),
                        BinOp::Le => Value::Bool(i <= j),
                        BinOp::Gt => Value::Bool(i > j),
                        BinOp::Ge => Value::Bool(i >= j),
                        _ => panic!("{op:?} of integers"),
                    }
                }
            }
        }
        other => panic!("printed code holds {other:?}"),
    }
}

/// Prints `unit` through every structured target and checks each printed assignment against
/// the source: the same tree, and the reference interpreter's value.
fn check_unit(unit: &Unit) -> Result<(), String> {
    let mut machine = Machine::new(unit).map_err(|e| format!("{e:?}"))?;
    let mut env: HashMap<String, Value> = HashMap::new();
    for v in &unit.globals {
        env.insert(v.name.clone(), machine.global(&v.name).unwrap());
    }
    machine.cycle(&mut |_: &mut Machine<'_>| Ok(())).map_err(|e| format!("{e:?}"))?;
    for target in STRUCTURED {
        let text = printed(unit, target);
        let found = assignments(&text);
        for stmt in &unit.pous[0].body {
            let Stmt::Assign { target: Place::Global(name), value } = stmt else { unreachable!() };
            let rhs = found.get(name).ok_or_else(|| format!("{target:?}: no assignment to {name} in\n{text}"))?;
            // IEC 61131-3 allows one unary operator before an operand (our parser is lenient
            // and would read `NOT NOT a`; blark and TIA do not).
            if rhs.contains("NOT NOT") || rhs.contains("--") {
                return Err(format!("{target:?} prints two unary operators in a row: {name} := {rhs}"));
            }
            let parsed = fragment::parse_expr(rhs).map_err(|e| format!("{target:?}: `{rhs}` does not parse: {e:?}"))?;
            let (want, got) = (source_tree(value), parsed_tree(&parsed));
            if want != got {
                return Err(format!("{target:?} prints {name} := {rhs}\n  source tree  {want}\n  printed tree {got}"));
            }
            let expected = machine.global(name).unwrap();
            let value = eval(&parsed, &env);
            let equal = match (expected, value) {
                // Stored in a DINT: wrapped to 32 bits.
                (Value::Int(a), Value::Int(b)) => a == i64::from(b as i32),
                (Value::Real(a), Value::Real(b)) => a.to_bits() == b.to_bits() || (a == 0.0 && b == 0.0),
                (a, b) => a == b,
            };
            if !equal {
                return Err(format!("{target:?}: {name} := {rhs} is {value:?}, the interpreter says {expected:?}"));
            }
        }
    }
    Ok(())
}

proptest! {
    #![proptest_config(common::proptest_config(64))]

    /// Random expressions through every structured target: same tree, same value.
    #[test]
    fn every_structured_target_prints_expressions_that_read_back_and_evaluate_equal(seed in any::<u64>()) {
        let mut rng = Rng(seed | 1);
        let unit = random_unit(&mut rng, 6, 4);
        if let Err(e) = check_unit(&unit) {
            prop_assert!(false, "{}", e);
        }
    }
}

/// The shapes that went wrong once, each through every target.
#[test]
fn nested_unary_operators_and_negative_literals_keep_their_parentheses() {
    let b = || Expr::global("b0");
    let n = || Expr::global("n0");
    let r = || Expr::global("r0");
    let cases: Vec<(Type, Expr)> = vec![
        (Type::Bool, b().not().not()),
        (Type::Bool, b().not().not().not()),
        (Type::Bool, Expr::binary(BinOp::And, b(), b().not()).not()),
        (Type::Dint, n().neg().neg()),
        (Type::Dint, Expr::Int(-3).neg()),
        (Type::Dint, Expr::binary(BinOp::Sub, n(), Expr::binary(BinOp::Sub, n(), Expr::Int(-4)))),
        (Type::Dint, Expr::binary(BinOp::Mul, Expr::binary(BinOp::Add, n(), Expr::Int(1)).neg(), Expr::Int(-2))),
        (Type::Dint, Expr::binary(BinOp::Div, n(), Expr::binary(BinOp::Mod, Expr::Int(7), Expr::Int(-3)))),
        (Type::Real, r().neg().neg()),
        (Type::Real, Expr::binary(BinOp::Sub, Expr::real(-1.5).unwrap(), r().neg())),
        (Type::Bool, Expr::binary(BinOp::Lt, n().neg(), Expr::Int(-1)).not()),
        (Type::Bool, Expr::binary(BinOp::Eq, Expr::binary(BinOp::Eq, b(), b()), Expr::Bool(false))),
    ];
    let mut unit = random_unit(&mut Rng(1), 0, 0);
    for (k, (ty, e)) in cases.into_iter().enumerate() {
        let prefix = match ty {
            Type::Bool => "bo",
            Type::Real => "ro",
            _ => "no",
        };
        let name = format!("{prefix}{k}");
        unit.globals.push(Var::new(&name, ty, ""));
        unit.pous[0].body.push(Stmt::assign(Place::global(name), e));
    }
    check_unit(&unit).unwrap();
    // The fixed text, for the reader: IEC 61131-3 allows one unary operator before an operand.
    let st = printed(&unit, Target::St);
    assert!(st.contains(":= NOT (NOT GVL.b0);") || st.contains(":= NOT (NOT b0);"), "{st}");
    assert!(!st.contains("NOT NOT") && !st.contains("--"), "{st}");
}

/// blark parses the units the property test checks, printed as IEC ST, CODESYS ST and SCL.
#[test]
fn blark_parses_printed_random_expressions() {
    let python = common::venv_tool("python");
    let dir = common::root().join("target/plc-expressions");
    std::fs::create_dir_all(&dir).unwrap();
    let mut files: Vec<PathBuf> = Vec::new();
    for seed in 1..=4u64 {
        let unit = random_unit(&mut Rng(seed * 7919), 8, 4);
        for target in [Target::St, Target::Codesys, Target::Scl1500] {
            let mut text = printed(&unit, target);
            if target == Target::Scl1500 {
                text = common::scl_for_blark(&text);
            }
            let path = dir.join(format!("exprs-{seed}-{}.st", target.name()));
            std::fs::write(&path, text).unwrap();
            files.push(path);
        }
    }
    common::blark_all(&python, &common::root(), &files);
}
