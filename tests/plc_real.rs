//! REAL values through every printer: a unit shaped like G4LTL-ST's real-valued specifications
//! (appendix A: `VAR_INPUT x: REAL; y: REAL; END_VAR`, predicates `p0 := x + y > 3.0;`
//! `p1 := x*x + y*y < 3.5;` evaluated once per scan). blark parses the Structured Text
//! dialects, xmllint validates PLCopen against the TC6 schema (and TwinCAT's files as XML),
//! Instruction List is refused, and awlsim runs the STL form over a grid of (x, y) whose
//! results must equal `f32` evaluation in Rust bit for bit, as must `plc::model::exec`'s.

use crate::common;

use common::{check, venv_tool};
use plcsynth::plc::model::exec::{Machine, Value};
use plcsynth::plc::model::unit::{
    direct_addresses, BinOp, Expr, Place, Pou, PouKind, Signal, SignalKind, Stmt, Type, Unit, Var,
};
use plcsynth::plc::{self, print::stl::unit as unit_stl, Target};
use std::path::PathBuf;
use std::process::Command;

fn root() -> PathBuf {
    common::root()
}

fn scratch(name: &str, text: &str) -> PathBuf {
    common::scratch("plcsynth-real", name, text)
}

fn real(x: f64) -> Expr {
    Expr::real(x).unwrap()
}

fn bin(op: BinOp, a: Expr, b: Expr) -> Expr {
    Expr::binary(op, a, b)
}

/// The block `Predicates` (x, y → p0, p1, the sum of squares, a scaled difference), a program
/// wiring it to `ID0`, `ID4` and `QX0.0`, `QX0.1`, `QD2`, `QD6`, a REAL constant and a REAL
/// global with a negative initial value.
fn predicates_unit() -> Unit {
    let (x, y) = (|| Expr::local("x"), || Expr::local("y"));
    let square = |e: Expr| bin(BinOp::Mul, e.clone(), e);
    let fb = Pou {
        kind: PouKind::FunctionBlock,
        name: "Predicates".into(),
        comment: "the predicates of a specification over real inputs, once per scan".into(),
        inputs: vec![Var::new("x", Type::Real, ""), Var::new("y", Type::Real, "")],
        outputs: vec![
            Var::new("p0", Type::Bool, "x + y > 3.0"),
            Var::new("p1", Type::Bool, "x*x + y*y < 3.5"),
            Var::new("r2", Type::Real, "x*x + y*y"),
            Var::new("scaled", Type::Real, "(x - offset) * 1.0E-3 / -0.25"),
        ],
        locals: vec![],
        body: vec![
            Stmt::assign(Place::local("p0"), bin(BinOp::Gt, bin(BinOp::Add, x(), y()), real(3.0))),
            Stmt::assign(Place::local("r2"), bin(BinOp::Add, square(x()), square(y()))),
            Stmt::assign(
                Place::local("p1"),
                bin(BinOp::Lt, bin(BinOp::Add, square(x()), square(y())), Expr::global("LIMIT")),
            ),
            Stmt::assign(
                Place::local("scaled"),
                bin(BinOp::Div, bin(BinOp::Mul, bin(BinOp::Sub, x(), Expr::global("offset")), real(1e-3)), real(-0.25)),
            ),
        ],
    };
    let inputs = direct_addresses('I', &[Type::Real, Type::Real]);
    let outputs = direct_addresses('Q', &[Type::Bool, Type::Bool, Type::Real, Type::Real]);
    assert_eq!(inputs, [Some("ID0".into()), Some("ID4".into())]);
    assert_eq!(outputs[2..], [Some("QD2".into()), Some("QD6".into())]);
    let mut signals = Vec::new();
    for (name, a) in ["x", "y"].iter().zip(&inputs) {
        let address = a.clone().unwrap();
        signals.push(Signal {
            symbol: address.clone(),
            kind: SignalKind::Input,
            ty: Type::Real,
            address,
            comment: name.to_string(),
        });
    }
    let outs = [("p0", Type::Bool), ("p1", Type::Bool), ("r2", Type::Real), ("scaled", Type::Real)];
    for ((name, ty), a) in outs.iter().zip(&outputs) {
        let address = a.clone().unwrap();
        signals.push(Signal {
            symbol: address.clone(),
            kind: SignalKind::Output,
            ty: ty.clone(),
            address,
            comment: name.to_string(),
        });
    }
    let instance = || Place::local("pred");
    let mut body = vec![Stmt::CallInstance {
        instance: instance(),
        args: vec![("x".into(), Expr::Read(Place::Signal(0))), ("y".into(), Expr::Read(Place::Signal(1)))],
    }];
    for (k, (name, _)) in outs.iter().enumerate() {
        body.push(Stmt::assign(Place::Signal(2 + k), Expr::read(instance().member(*name))));
    }
    let program = Pou {
        kind: PouKind::Program,
        name: "Main".into(),
        comment: "Predicates on the PLC's inputs and outputs".into(),
        inputs: vec![],
        outputs: vec![],
        locals: vec![Var::new("pred", Type::Instance("Predicates".into()), "")],
        body,
    };
    Unit {
        name: "predicates".into(),
        header: vec!["REAL inputs and polynomial predicates".into()],
        gvl: "Spec".into(),
        constants: vec![Var::new("LIMIT", Type::Real, "the radius squared").with_init(real(3.5))],
        globals: vec![Var::new("offset", Type::Real, "").with_init(real(-0.25))],
        signals,
        pous: vec![fb, program],
    }
}

/// What the PLC must compute, in `f32`.
fn expected(x: f32, y: f32) -> (bool, bool, f32, f32) {
    let r2 = x * x + y * y;
    (x + y > 3.0, r2 < 3.5, r2, (x - -0.25) * 1e-3f32 / -0.25)
}

/// The grid: steps of 0.25 in [-2, 2.5], and points on and next to both boundaries (x + y = 3,
/// x² + y² = 3.5), where rounding decides.
fn grid() -> Vec<(f32, f32)> {
    let mut points = Vec::new();
    for i in -8..=10 {
        for j in -8..=10 {
            if (i + j) % 3 == 0 {
                points.push((i as f32 * 0.25, j as f32 * 0.25));
            }
        }
    }
    let edge = (1.75f32).sqrt();
    for (x, y) in [(1.5f32, 1.5f32), (1.0, 2.0), (0.1, 2.9), (edge, edge), (-edge, edge), (0.5, 3.25f32.sqrt())] {
        for dx in [-1i32, 0, 1] {
            let nudge = |v: f32, d: i32| f32::from_bits((v.to_bits() as i32 + d) as u32);
            points.push((nudge(x, dx), y));
            points.push((x, nudge(y, -dx)));
        }
    }
    points.push((-1e-3, 3.0));
    points.push((1e3, -997.0));
    assert!(points.iter().all(|(x, y)| x.is_normal() && y.is_normal() || *x == 0.0 || *y == 0.0));
    points
}

#[test]
fn the_st_forms_declare_reals_and_write_literals_every_dialect_reads() {
    let unit = predicates_unit();
    let text = &plc::render_unit_files(&unit, Target::St, &plc::Options::default()).unwrap()[0].text;
    for line in [
        "    x : REAL;",
        "    LIMIT : REAL := 3.5;",
        "    offset : REAL := -0.25;",
        "p0 := x + y > 3.0;",
        "p1 := x * x + y * y < LIMIT;",
        "scaled := (x - offset) * 0.001 / (-0.25);",
        "%QD2 := pred.r2;",
    ] {
        assert!(text.contains(line), "{line}\n{text}");
    }
    let scl = &plc::render_unit_files(&unit, Target::Scl, &plc::Options::default()).unwrap()[0].text;
    assert!(scl.contains("    LIMIT := 3.5;") && scl.contains("\"Spec\".offset"), "{scl}");
}

#[test]
fn every_target_parses_validates_or_refuses() {
    let python = venv_tool("python");
    let schema = root().join("../shared/schemas/tc6_xml_v201.xsd");
    assert!(schema.exists(), "the PLCopen schema is expected at {}", schema.display());
    let mut unit = predicates_unit();
    // Literals at the edges of the decimal form: exponents both ways, negative operands.
    unit.pous[0].body.push(Stmt::assign(
        Place::local("scaled"),
        bin(BinOp::Add, bin(BinOp::Mul, Expr::local("x"), real(1e-7)), bin(BinOp::Sub, real(1.5e20), real(-3.0e-38))),
    ));
    unit.pous[0].body.push(Stmt::assign(Place::local("scaled"), Expr::local("scaled").neg()));
    let options = plc::Options::default();
    let mut st_files = Vec::new();
    for target in Target::ALL {
        let files = match (target, plc::render_unit_files(&unit, target, &options)) {
            (Target::Il, Err(reason)) => {
                assert!(reason.contains("Instruction List"), "{reason}");
                continue;
            }
            (_, files) => files.unwrap_or_else(|e| panic!("{target}: {e}")),
        };
        let text = &files[0].text;
        match target {
            Target::St | Target::Codesys => {
                assert!(text.contains("1.0E-7") && text.contains("1.5E+20") && text.contains("(-3.0E-38)"), "{text}");
                st_files.push(scratch(&format!("predicates_{target}.st"), text))
            }
            Target::Scl | Target::Scl1500 => {
                st_files.push(scratch(&format!("predicates_{target}.st"), &common::scl_for_blark(text)))
            }
            Target::Twincat => {
                for f in &files {
                    let path = scratch(&format!("predicates_{}", f.name), &f.text);
                    check(Command::new("xmllint").arg("--noout").arg(&path), &path);
                }
            }
            Target::Plcopen | Target::Abb => {
                assert!(text.contains("<REAL/>") && text.contains("<simpleValue value=\"-0.25\"/>"), "{text}");
                let path = scratch(&format!("predicates_{target}.xml"), text);
                check(Command::new("xmllint").arg("--noout").arg("--schema").arg(&schema).arg(&path), &path);
            }
            Target::Stl => {
                for part in ["L\t1.500000e+20", "L\t-3.000000e-38", "NEGR", "x : REAL;", "L\t1.000000e-07"] {
                    assert!(text.contains(part), "{part}\n{text}");
                }
            }
            Target::Il => unreachable!("refused above"),
        }
    }
    common::blark_all(&python, &root(), &st_files);
}

/// Runs the STL form over the grid in awlsim: per cycle the output bytes.
fn awlsim(unit: &Unit, points: &[(f32, f32)]) -> Vec<Vec<u8>> {
    let options = plc::unit_stl_options(&plc::Options::default());
    assert_eq!(unit_stl::check(unit, &options), Vec::<String>::new());
    let text = &plc::render_unit_files(unit, Target::Stl, &plc::Options::default()).unwrap()[0].text;
    for part in
        ["(x := ID 0, y := ID 4)", "+R", "*R", "/R", ">R", "<R", "T\tQD 2", "L\t3.000000e+00", "L\t3.500000e+00"]
    {
        assert!(text.contains(part), "{part}\n{text}");
    }
    let path = scratch("predicates.awl", text);
    let script: Vec<String> = points
        .iter()
        .map(|(x, y)| {
            let bytes: Vec<u8> = x.to_be_bytes().into_iter().chain(y.to_be_bytes()).collect();
            let words: Vec<String> = bytes.iter().enumerate().map(|(i, b)| format!("I{i}={b}")).collect();
            format!("{} ?Q0:10", words.join(" "))
        })
        .collect();
    let text = common::run_checker("unit_run.py", &[&path], &script.join("\n"));
    assert_eq!(text.lines().count(), points.len(), "one line per cycle");
    text.lines().map(common::hex_bytes).collect()
}

#[test]
fn awlsim_and_unit_exec_compute_the_predicates_as_f32_does() {
    let unit = predicates_unit();
    let points = grid();
    let trace = awlsim(&unit, &points);
    let mut machine = Machine::new(&unit).unwrap();
    let (mut p0s, mut p1s) = (0, 0);
    for (k, (&(x, y), q)) in points.iter().zip(&trace).enumerate() {
        let (p0, p1, r2, scaled) = expected(x, y);
        p0s += usize::from(p0);
        p1s += usize::from(p1);
        let dword = |b: usize| f32::from_be_bytes(q[b..b + 4].try_into().unwrap());
        let got = (q[0] & 1 == 1, q[0] >> 1 & 1 == 1, dword(2), dword(6));
        assert_eq!(got.0, p0, "cycle {k}: p0 at x = {x:e}, y = {y:e}");
        assert_eq!(got.1, p1, "cycle {k}: p1 at x = {x:e}, y = {y:e}");
        assert_eq!(got.2.to_bits(), r2.to_bits(), "cycle {k}: r2 at x = {x:e}, y = {y:e}: {} vs {r2}", got.2);
        assert_eq!(got.3.to_bits(), scaled.to_bits(), "cycle {k}: scaled at x = {x:e}, y = {y:e}");
        machine.set_signal(0, Value::Real(x));
        machine.set_signal(1, Value::Real(y));
        machine.cycle(&mut |_| Ok(())).unwrap();
        let exec = [machine.signal(2), machine.signal(3), machine.signal(4), machine.signal(5)];
        assert_eq!(
            exec,
            [Value::Bool(p0), Value::Bool(p1), Value::Real(r2), Value::Real(scaled)],
            "unit_exec, cycle {k}"
        );
    }
    // The grid reaches both sides of both predicates.
    assert!(p0s > 10 && p0s < points.len() - 10, "{p0s} of {}", points.len());
    assert!(p1s > 10 && p1s < points.len() - 10, "{p1s} of {}", points.len());
}

#[test]
fn reals_and_integers_never_mix_implicitly() {
    let options = plc::unit_stl_options(&plc::Options::default());
    let cases = [
        (bin(BinOp::Add, Expr::local("x"), Expr::Int(3)), "`+` of REAL and INT: IEC needs an explicit conversion"),
        (bin(BinOp::Gt, Expr::Int(3), Expr::local("y")), "`>` of INT and REAL: IEC needs an explicit conversion"),
        (bin(BinOp::Mod, Expr::local("x"), real(2.0)), "MOD of REAL values"),
    ];
    for (value, message) in cases {
        let mut unit = predicates_unit();
        let target = if message.contains('>') { "p0" } else { "r2" };
        unit.pous[0].body.push(Stmt::assign(Place::local(target), value.clone()));
        let errors = unit_stl::check(&unit, &options);
        assert!(errors.iter().any(|e| e.contains(message)), "{message}: {errors:#?}");
        let mut m = Machine::new(&unit).unwrap();
        let e = m.cycle(&mut |_| Ok(())).unwrap_err();
        assert!(e.0.contains("REAL"), "{e:?}");
    }
    // An integer stored into a REAL, a REAL into an INT, an INT literal as a REAL argument.
    let mut unit = predicates_unit();
    unit.globals.push(Var::new("count", Type::Int, ""));
    unit.pous[0].body.push(Stmt::assign(Place::local("r2"), Expr::Int(1)));
    let errors = unit_stl::check(&unit, &options);
    assert!(errors.iter().any(|e| e.contains("`r2` of type REAL gets a value of type INT")), "{errors:#?}");
    assert!(Machine::new(&unit).unwrap().cycle(&mut |_| Ok(())).unwrap_err().0.contains("explicit conversion"));
    let mut unit = predicates_unit();
    unit.globals.push(Var::new("count", Type::Int, ""));
    unit.pous[1].body.push(Stmt::assign(Place::global("count"), Expr::read(Place::Signal(0))));
    let errors = unit_stl::check(&unit, &options);
    assert!(errors.iter().any(|e| e.contains("`count` of type INT gets a value of type REAL")), "{errors:#?}");
    let mut unit = predicates_unit();
    let Stmt::CallInstance { args, .. } = &mut unit.pous[1].body[0] else { panic!() };
    args[0].1 = Expr::Int(2);
    let errors = unit_stl::check(&unit, &options);
    assert!(errors.iter().any(|e| e.contains("2 of type INT passed as a REAL")), "{errors:#?}");
    assert!(Machine::new(&unit).unwrap().cycle(&mut |_| Ok(())).unwrap_err().0.contains("explicit conversion"));
    // A REAL initial value must be a REAL literal; a REAL signal needs a double word.
    let mut unit = predicates_unit();
    unit.globals.push(Var::new("bad", Type::Real, "").with_init(Expr::Int(3)));
    unit.signals[0].address = "IW0".into();
    unit.signals[0].symbol = "IW0".into();
    let errors = unit_stl::check(&unit, &options);
    assert!(
        errors.iter().any(|e| e.contains("the initial value of `bad` is not a literal of type REAL")),
        "{errors:#?}"
    );
    assert!(errors.iter().any(|e| e.contains("`IW0` is not an I, Q or M address of a REAL")), "{errors:#?}");
}
