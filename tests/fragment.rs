//! Structured Text fragments (`plc::fragment`): what is printed parses back to the same tree,
//! and blark, an independent IEC 61131-3 parser, accepts what is printed.

use plcsynth::diag::Span;
use plcsynth::plc::fragment::{parse_expr, parse_statements, BinOp, Expr, ExprKind, Stmt, UnOp};
use plcsynth::rng::Rng;
use proptest::prelude::*;
use std::path::PathBuf;
use std::process::Command;

const OPS: [BinOp; 14] = [
    BinOp::Or,
    BinOp::Xor,
    BinOp::And,
    BinOp::Eq,
    BinOp::Ne,
    BinOp::Lt,
    BinOp::Le,
    BinOp::Gt,
    BinOp::Ge,
    BinOp::Add,
    BinOp::Sub,
    BinOp::Mul,
    BinOp::Div,
    BinOp::Mod,
];

fn node(kind: ExprKind) -> Expr {
    Expr { kind, span: Span::new(0, 0) }
}

/// A random expression of at most `depth` levels; `macros` allows `\var{}` and `\last{}`.
fn random_expr(rng: &mut Rng, depth: u32, macros: bool) -> Expr {
    if depth == 0 || rng.below(4) == 0 {
        let leaves = if macros { 9 } else { 7 };
        return node(match rng.below(leaves) {
            0 => ExprKind::Bool(rng.below(2) == 0),
            1 => ExprKind::Int(["0", "42", "16#FF", "2#1010"][rng.below(4) as usize].to_string()),
            2 => ExprKind::Real("1.5".into()),
            3 => ExprKind::Time(["T#1s500ms", "T#10MS", "TIME#2m"][rng.below(3) as usize].to_string()),
            4 => ExprKind::Address(["%IX0.1", "%QX4.0", "%MW10"][rng.below(3) as usize].to_string()),
            5 => ExprKind::Var(vec!["T1".into(), "ET".into()]),
            6 => ExprKind::Var(vec![["a", "level", "Q_Inlet"][rng.below(3) as usize].to_string()]),
            7 => ExprKind::ControllerVar("Ctrl.busy".into()),
            _ => ExprKind::Last("%IX0.1".into()),
        });
    }
    if rng.below(5) == 0 {
        let op = if rng.below(2) == 0 { UnOp::Not } else { UnOp::Neg };
        return node(ExprKind::Unary(op, Box::new(random_expr(rng, depth - 1, macros))));
    }
    let op = OPS[rng.below(OPS.len() as u64) as usize];
    node(ExprKind::Binary(
        op,
        Box::new(random_expr(rng, depth - 1, macros)),
        Box::new(random_expr(rng, depth - 1, macros)),
    ))
}

/// The tree without its spans.
fn strip(e: &Expr) -> Expr {
    node(match &e.kind {
        ExprKind::Unary(op, a) => ExprKind::Unary(*op, Box::new(strip(a))),
        ExprKind::Binary(op, a, b) => ExprKind::Binary(*op, Box::new(strip(a)), Box::new(strip(b))),
        other => other.clone(),
    })
}

proptest! {
    #![proptest_config(crate::common::proptest_config(512))]

    /// Printing inserts exactly the parentheses the precedences need: the printed text parses
    /// back to the same tree (spans aside), and printing that again gives the same text.
    #[test]
    fn printed_expressions_parse_back_to_the_same_tree(seed in any::<u64>()) {
        let e = random_expr(&mut Rng::new(seed), 6, true);
        let text = e.to_string();
        let back = parse_expr(&text).unwrap_or_else(|err| panic!("{text}: {err:?}"));
        prop_assert_eq!(strip(&back), strip(&e), "{}", text);
        prop_assert_eq!(back.to_string(), text.clone());
        // A span covers the text of its node.
        prop_assert_eq!((back.span.start as usize, back.span.end as usize), (0, text.len()));
    }
}

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// 120 random expressions, each printed once through the statement parser (as action code is),
/// alternately as an assignment's value and as an `IF`'s condition, into one program: blark
/// parses all of it. (blark reads these nested expressions at under 1 kB a second: each is
/// printed once.)
#[test]
fn blark_parses_printed_fragments() {
    let blark = root().join(".venv/bin/blark");
    assert!(blark.exists(), "{} is missing: run `bash scripts/python-checkers.sh` (make test does)", blark.display());
    let mut rng = Rng::new(7);
    let mut body = String::new();
    for k in 0..120 {
        let e = random_expr(&mut rng, 4, false);
        let text = if k % 2 == 0 {
            format!("x{k} := {e};")
        } else {
            format!("IF {e} THEN x{k} := 1; ELSE y := NOT b; END_IF;")
        };
        let stmts = parse_statements(&text).unwrap_or_else(|err| panic!("{text}: {err:?}"));
        body += &stmts.iter().map(Stmt::to_string).collect::<String>();
    }
    let program = format!("PROGRAM fragments\nVAR\n    b : BOOL;\nEND_VAR\n{body}END_PROGRAM\n");
    let dir = root().join("target/fragment-check");
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("fragments.st");
    std::fs::write(&path, &program).unwrap();
    let out = Command::new(&blark).arg("parse").arg(&path).output().expect("blark runs");
    assert!(
        out.status.success(),
        "blark rejects {}:\n{}{}",
        path.display(),
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
}
