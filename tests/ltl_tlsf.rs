//! The TLSF front end: every shared benchmark compiles, a few to hand-derived formulas;
//! parameter overrides; malformed input reported at line:column; random input never panics.

use plcsynth::diag::{render_plain, Diagnostic};
use plcsynth::ltl::{self, Format, Semantics, SignalKind, Spec};
use proptest::prelude::*;
use std::path::{Path, PathBuf};

fn shared_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/ltl/tlsf")
}

fn tlsf_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let mut entries: Vec<PathBuf> = std::fs::read_dir(dir).expect("readable dir").map(|e| e.unwrap().path()).collect();
    entries.sort();
    for path in entries {
        if path.is_dir() {
            tlsf_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "tlsf") {
            out.push(path);
        }
    }
}

fn shared(name: &str) -> String {
    std::fs::read_to_string(shared_dir().join(name)).expect("shared benchmark")
}

fn compile_tlsf(source: &str, overrides: &[(String, i64)]) -> Result<(Spec, Vec<Diagnostic>), Vec<Diagnostic>> {
    ltl::compile(source, Format::Tlsf, overrides)
}

fn compile_ok(source: &str, overrides: &[(String, i64)]) -> Spec {
    match compile_tlsf(source, overrides) {
        Ok((spec, _warnings)) => spec,
        Err(diags) => panic!("{}", render_plain("spec.tlsf", source, &diags)),
    }
}

fn names(spec: &Spec, kind: SignalKind) -> Vec<&str> {
    spec.signals.iter().filter(|s| s.kind == kind).map(|s| s.name.as_str()).collect()
}

fn errors(source: &str) -> Vec<Diagnostic> {
    match compile_tlsf(source, &[]) {
        Ok((spec, _)) => panic!("accepted: {}", spec.formula_text()),
        Err(diags) => diags.into_iter().filter(Diagnostic::is_error).collect(),
    }
}

/// Asserts an error containing `message` at `line:column`.
fn expect_at(errs: &[Diagnostic], line: u32, column: u32, message: &str) {
    assert!(
        errs.iter().any(|d| d.line == line && d.column == column && d.message.contains(message)),
        "no error `{message}` at {line}:{column}; got:\n{:#?}",
        errs.iter().map(|d| format!("{}:{} {}", d.line, d.column, d.message)).collect::<Vec<_>>()
    );
}

#[test]
fn every_shared_benchmark_compiles() {
    let mut files = Vec::new();
    tlsf_files(&shared_dir(), &mut files);
    assert!(files.len() >= 40, "found only {} files", files.len());
    for path in files {
        let source = std::fs::read_to_string(&path).unwrap();
        let spec = compile_ok(&source, &[]);
        assert!(!spec.guarantees.is_empty(), "{}: no guarantees", path.display());
        assert!(spec.title.is_some(), "{}: no title", path.display());
    }
}

#[test]
fn simple_arbiter_with_two_clients() {
    let spec = compile_ok(&shared("simple_arbiter/simple_arbiter.tlsf"), &[]);
    assert_eq!(spec.title.as_deref(), Some("Simple Arbiter"));
    assert_eq!(spec.semantics, Semantics::Mealy);
    assert_eq!(names(&spec, SignalKind::Input), ["r_0", "r_1"]);
    assert_eq!(names(&spec, SignalKind::Output), ["g_0", "g_1"]);
    // mutual_exclusion(g) = mone(g, 0, 1); m(0, 1) = 0, so mone is
    // (none(g,0,0) && mone(g,1,1)) || (mone(g,0,0) && none(g,1,1)) with none(g,t,t) = !g_t
    // and mone(g,t,t) = true (dropped from the conjunctions). The invariant is always-ed; the big
    // && splits into two clauses.
    assert_eq!(spec.formula_text(), "G (!g_0 || !g_1) && G (r_0 -> F g_0) && G (r_1 -> F g_1)");
    assert!(spec.assumptions.is_empty());
    assert_eq!(spec.guarantees.len(), 3);
}

#[test]
fn ltl2dba01_is_one_equivalence() {
    let spec = compile_ok(&shared("ltl2dba/ltl2dba01.tlsf"), &[]);
    assert_eq!(names(&spec, SignalKind::Input), ["p", "q", "r"]);
    assert_eq!(names(&spec, SignalKind::Output), ["acc"]);
    // `<->` binds looser than the prefix operators: (F …) <-> (G F acc).
    assert_eq!(spec.formula_text(), "F (q && X (p U r)) <-> G F acc");
}

#[test]
fn full_arbiter_with_two_clients() {
    let spec = compile_ok(&shared("full_arbiter/full_arbiter.tlsf"), &[]);
    // Invariants: per client i, `g && G !r -> F !g` (`&&` binds tighter than `->`) and the
    // grant-release rule, then the mutual exclusion as in the simple arbiter; each always-ed.
    // Guarantees: per client, `r R !g` and `G (r -> F g)`.
    let invariants = [
        "G ((g_0 && G !r_0) -> F !g_0)",
        "G ((g_0 && X (!r_0 && !g_0)) -> X (r_0 R !g_0))",
        "G ((g_1 && G !r_1) -> F !g_1)",
        "G ((g_1 && X (!r_1 && !g_1)) -> X (r_1 R !g_1))",
        "G (!g_0 || !g_1)",
    ];
    let guarantees = ["(r_0 R !g_0)", "G (r_0 -> F g_0)", "(r_1 R !g_1)", "G (r_1 -> F g_1)"];
    let expected: Vec<&str> = invariants.iter().chain(&guarantees).copied().collect();
    assert_eq!(spec.formula_text(), expected.join(" && "));
    assert_eq!(spec.guarantees.len(), 9);
}

#[test]
fn moore_semantics_is_read() {
    let spec = compile_ok(&shared("ltl2dba/ltl2dba19.tlsf"), &[]);
    assert_eq!(spec.semantics, Semantics::Moore);
}

#[test]
fn parameter_overrides_resize_buses() {
    let source = shared("simple_arbiter/simple_arbiter.tlsf");
    let spec = compile_ok(&source, &[("n".to_string(), 3)]);
    assert_eq!(names(&spec, SignalKind::Input), ["r_0", "r_1", "r_2"]);
    assert_eq!(names(&spec, SignalKind::Output), ["g_0", "g_1", "g_2"]);
    let spec = compile_ok(&shared("round_robin_arbiter/round_robin_arbiter.tlsf"), &[("n".to_string(), 3)]);
    assert_eq!(names(&spec, SignalKind::Input).len(), 3);

    let errs = compile_tlsf(&source, &[("k".to_string(), 3)]).unwrap_err();
    // Located at the PARAMETERS keyword (line 9, column 3) and naming the parameter.
    expect_at(&errs, 9, 3, "unknown parameter `k`");
    assert!(errs[0].notes.iter().any(|n| n.contains('n')), "{:?}", errs[0].notes);
    let errs = compile_tlsf(&shared("ltl2dba/ltl2dba01.tlsf"), &[("n".to_string(), 3)]).unwrap_err();
    expect_at(&errs, 1, 1, "unknown parameter `n`");
}

#[test]
fn later_parameters_see_earlier_ones_and_overrides() {
    let source = "GLOBAL { PARAMETERS { n = 2; m = n * 2 + 1; } }\n\
                  MAIN { INPUTS { a[m]; } OUTPUTS { b; } GUARANTEES { G (a[m - 1] -> b); } }";
    let spec = compile_ok(source, &[]);
    assert_eq!(names(&spec, SignalKind::Input).len(), 5);
    let spec = compile_ok(source, &[("n".to_string(), 1)]);
    assert_eq!(spec.formula_text(), "G (a_2 -> b)");
}

#[test]
fn bounded_operators_expand_into_next() {
    let source = "MAIN { INPUTS { a; } OUTPUTS { b; }\n\
                  GUARANTEES { X[2] a; F[1:2] b; G[0:1] a; F[2:1] b; } }";
    let spec = compile_ok(source, &[]);
    let texts: Vec<String> =
        spec.guarantees.iter().map(|c| c.formula.to_infix(&|s| spec.name(s).to_string())).collect();
    // F[a:b] φ = X^a (φ || X (… φ)): b - a nested X after a leading X^a; empty range: true.
    assert_eq!(texts, ["X X a", "X (b || X b)", "a", "X a", "true"]);
}

#[test]
fn sets_sums_and_several_binders() {
    let source = "GLOBAL { PARAMETERS { n = 3; }\n\
                  DEFINITIONS { s = {0, 2}; total = SUM[i IN s] i; pairs = &&[0 <= i < n, i < j < n] !(r[i] && r[j]); } }\n\
                  MAIN { INPUTS { r[n]; } OUTPUTS { g; }\n\
                  GUARANTEES { G (r[total] -> g); pairs; ||[i IN s CUP {1}] r[i]; r[MAX s] || r[SIZE s - 2]; } }";
    let spec = compile_ok(source, &[]);
    assert_eq!(
        spec.formula_text(),
        "G (r_2 -> g) && !(r_0 && r_1) && !(r_0 && r_2) && !(r_1 && r_2) && (r_0 || r_1 || r_2) && (r_2 || r_0)"
    );
}

#[test]
fn sections_combine_as_syfco_does() {
    let source = "MAIN { INPUTS { e; } OUTPUTS { s; }\n\
                  INITIALLY { e; } REQUIRE { X e; } ASSUME { F e; } ASSERT { s -> e; } GUARANTEE { G F s; } }";
    let spec = compile_ok(source, &[]);
    assert_eq!(spec.formula_text(), "(e && G X e && F e) -> (G (s -> e) && G F s)");
    assert_eq!(spec.assumptions.len(), 3);

    // With a PRESET and assumptions, SyfCo's PRESET does not depend on the assumptions.
    let source = "MAIN { INPUTS { e; } OUTPUTS { s; } PRESET { s; } ASSUME { F e; } GUARANTEE { G F s; } }";
    let spec = compile_ok(source, &[]);
    assert_eq!(spec.formula_text(), "s && (F e -> G F s)");

    let strict = "INFO { TITLE: \"t\" DESCRIPTION: \"d\" SEMANTICS: Strict, Moore TARGET: Moore }\n\
                  MAIN { INPUTS { e; } OUTPUTS { s; }\n\
                  INITIALLY { e; } REQUIRE { X e; } ASSUME { F e; } ASSERT { s -> e; } GUARANTEE { G F s; } }";
    let spec = compile_ok(strict, &[]);
    assert_eq!(spec.semantics, Semantics::Moore);
    assert!(spec.assumptions.is_empty());
    assert_eq!(spec.guarantees.len(), 1);
    assert_eq!(spec.formula_text(), "e -> (((s -> e) W !X e) && ((G X e && F e) -> G F s))");
}

#[test]
fn unknown_info_fields_warn() {
    let source = "INFO { TITLE: \"t\" COLOUR: blue SEMANTICS: Mealy,Strict }\nMAIN { INPUTS { a; } OUTPUTS { b; } GUARANTEES { b; } }";
    let (spec, warnings) = compile_tlsf(source, &[]).expect("accepted");
    assert_eq!(spec.title.as_deref(), Some("t"));
    assert!(warnings.iter().any(|w| !w.is_error() && w.message.contains("`COLOUR`") && w.column == 19), "{warnings:?}");
}

/// One malformed input, where its error is, and what the message says.
struct Bad {
    source: String,
    line: u32,
    column: u32,
    message: &'static str,
}

fn bad(source: impl Into<String>, line: u32, column: u32, message: &'static str) -> Bad {
    Bad { source: source.into(), line, column, message }
}

/// `MAIN` with inputs `a`, `b`, output `c` and the given guarantee, which starts at column 52.
fn guarantee(formula: &str) -> String {
    format!("MAIN {{ INPUTS {{ a; b; }} OUTPUTS {{ c; }} GUARANTEES {{{formula}; }} }}")
}

#[test]
fn malformed_inputs_are_located() {
    let deep = format!("{}a{}", "(".repeat(100), ")".repeat(100));
    let table = [
        bad("MAIN {\n  INPUTS { a; }\n  OUTPUTS { b; }\n", 1, 6, "unclosed `{`"),
        bad(
            "MAIN {\n  INPUTS { a; }\n  OUTPUTS { b; }\n  GUARANTEES { G (a -> F d); }\n}\n",
            4,
            26,
            "unknown name `d`",
        ),
        bad("GLOBAL { PARAMETERS { n = 2 +; } }\nMAIN { INPUTS { a; } }", 1, 30, "expected an expression, found `;`"),
        bad("GLOBAL { PARAMETERS { n = 4 / (2 - 2); } }\nMAIN { INPUTS { a[n]; } }", 1, 31, "division by zero"),
        bad(
            format!("GLOBAL {{ DEFINITIONS {{ f(i) = i > 0 : a  i < 0 : b; }} }}\n{}", guarantee(" f(0)")),
            2,
            53,
            "no case of `f` applies to (the number 0)",
        ),
        bad(
            format!("GLOBAL {{ DEFINITIONS {{ f(i) = f(i); }} }}\n{}", guarantee(" f(0)")),
            1,
            31,
            "recursion deeper than 256 calls",
        ),
        bad(guarantee(" X[1000000] a"), 1, 55, "nests the formula deeper than 200 levels"),
        bad(guarantee(&format!(" {deep}")), 1, 117, "nested more than 64 levels deep"),
        bad("MAIN {\0 INPUTS { a; } }", 1, 7, "unexpected character U+0000"),
        bad(
            "MAIN {\r\n  INPUTS { a; }\r\n  OUTPUTS { b; }\r\n  GUARANTEES { G d; }\r\n}\r\n",
            4,
            18,
            "unknown name `d`",
        ),
        bad(
            "INFO { TITLE: \"Ärger\" }\nMAIN { INPUTS { a; } OUTPUTS { b; } GUARANTEES { G é; } }",
            2,
            52,
            "unexpected character `é`",
        ),
        bad(guarantee(" G b[0]"), 1, 55, "`b` is not a bus"),
        bad("MAIN { INPUTS { r[2]; } OUTPUTS { b; } GUARANTEES { G r[2]; } }", 1, 57, "index 2 out of bounds"),
        bad("MAIN { INPUTS { a; } OUTPUTS { a; } }", 1, 32, "both as an input and as an output"),
        bad("MAIN { INPUTS { r[2]; r_1; } OUTPUTS { b; } }", 1, 23, "`r_1` clashes"),
        bad("MAIN { INPUTS { a b; } }", 1, 18, "expected `;` after this entry"),
        bad("INFO { SEMANTICS: Mealy, Moore }\nMAIN { INPUTS { a; } }", 1, 19, "one of `Mealy` and `Moore`"),
        bad(guarantee(" G (a -> grnt)"), 1, 61, "unknown name `grnt`"),
        bad(guarantee(" a U"), 1, 56, "expected an expression, found `;`"),
        bad(guarantee(" SIZEOF a"), 1, 60, "`SIZEOF` takes a bus"),
        bad("GLOBAL { PARAMETERS { n = 9223372036854775807 + 1; } }\nMAIN { INPUTS { a[n]; } }", 1, 27, "overflow"),
        bad("MAIN { INPUTS { a[0]; } }", 1, 19, "bus `a` has width 0"),
        bad("MAIN { INPUTS { a; } OUTPUTS { b; } GUARANTEES { a; } /* open", 1, 55, "unclosed comment"),
    ];
    for Bad { source, line, column, message } in &table {
        let errs = errors(source);
        expect_at(&errs, *line, *column, message);
        render_plain("bad.tlsf", source, &errs);
    }
}

#[test]
fn all_errors_of_a_file_are_reported_at_once() {
    let source = "INFO { SEMANTICS: Mealy }\nMAIN {\n  INPUTS { a; }\n  OUTPUTS { b; }\n  \
                  GUARANTEES {\n    G (a -> ) ;\n    F x;\n    b && (a || ;\n    G y;\n  }\n}\n";
    let errs = errors(source);
    expect_at(&errs, 6, 13, "expected an expression");
    expect_at(&errs, 7, 7, "unknown name `x`");
    expect_at(&errs, 8, 16, "expected an expression");
    expect_at(&errs, 9, 7, "unknown name `y`");
}

#[test]
fn hostile_evaluations_stop_with_an_error() {
    // Exponential work: each level doubles the formula.
    let blowup = format!(
        "GLOBAL {{ DEFINITIONS {{ f(k) = k == 0 : a  k > 0 : f(k - 1) || f(k - 1); }} }}\n{}",
        guarantee(" f(40)")
    );
    assert!(errors(&blowup).iter().any(|d| d.message.contains("more than 1000000 steps")));
    let range = guarantee(" &&[0 <= i < 1000000000000] a");
    assert!(errors(&range).iter().any(|d| d.message.contains("steps")));
    let deep =
        format!("GLOBAL {{ DEFINITIONS {{ f(k) = k == 0 : a  k > 0 : X f(k - 1); }} }}\n{}", guarantee(" f(220)"));
    assert!(errors(&deep).iter().any(|d| d.message.contains("deeper than 200 levels")));
}

#[test]
fn deep_recursion_fits_a_small_stack() {
    // A body 60 levels deep around the recursive call: the evaluation nesting bound stops it.
    let body = format!("{}f(i){}", "!(".repeat(60), ")".repeat(60));
    let source = format!("GLOBAL {{ DEFINITIONS {{ f(i) = {body}; }} }}\n{}", guarantee(" f(0)"));
    let deep_parens = guarantee(&format!(" {}a{}", "(".repeat(10_000), ")".repeat(10_000)));
    let worker = std::thread::Builder::new().stack_size(1 << 20).spawn(move || {
        let e = errors(&source);
        assert!(e.iter().any(|d| d.message.contains("levels deep")), "{e:?}");
        let e = errors(&deep_parens);
        assert!(e.iter().any(|d| d.message.contains("nested more than")), "{e:?}");
    });
    worker.unwrap().join().expect("no stack overflow");
}

/// Spans inside the source on character boundaries, lines and columns from 1.
fn assert_located(source: &str, diagnostics: &[Diagnostic]) {
    for d in diagnostics {
        let (start, end) = (d.span.start as usize, d.span.end as usize);
        assert!(start <= end && end <= source.len(), "span {start}..{end} outside: {}", d.message);
        assert!(source.is_char_boundary(start) && source.is_char_boundary(end), "span splits a char: {}", d.message);
        assert!(d.line >= 1 && d.column >= 1);
    }
}

fn check_any(source: &str) {
    match compile_tlsf(source, &[]) {
        Ok((_, warnings)) => {
            assert!(!warnings.iter().any(Diagnostic::is_error), "accepted with an error");
            assert_located(source, &warnings);
        }
        Err(diagnostics) => {
            assert!(diagnostics.iter().any(Diagnostic::is_error), "rejected without an error");
            assert_located(source, &diagnostics);
            render_plain("fuzz.tlsf", source, &diagnostics);
        }
    }
}

const SEEDS: &[&str] = &[
    "simple_arbiter/simple_arbiter.tlsf",
    "full_arbiter/full_arbiter.tlsf",
    "load_balancer/load_balancer.tlsf",
    "ltl2dba/ltl2dba_U1.tlsf",
    "ltl2dba/ltl2dba_alpha.tlsf",
    "prioritized_arbiter_unreal/prioritized_arbiter_unreal2.tlsf",
];

const FRAGMENTS: &[&str] = &[
    "{",
    "}",
    "(",
    ")",
    "[",
    "]",
    ";",
    ":",
    ",",
    "=",
    "&&",
    "||",
    "!",
    "->",
    "<->",
    "X",
    "G",
    "F",
    "U",
    "R",
    "W",
    "X[3]",
    "F[1:2]",
    "&&[0 <= i < n]",
    "i",
    "n",
    "0",
    "99999999999999999999",
    "/ 0",
    "SIZEOF",
    "r[",
    "mone(g,0,",
    "é",
    "\0",
    "\r\n",
    "/*",
    "\"",
    "MAIN",
    "GLOBAL",
    "INFO",
    "otherwise",
    "true",
    "f(i)",
    "{1, 2}",
    "IN",
];

/// A mutation of a shared benchmark: fragments inserted, ranges deleted.
fn mutated() -> impl Strategy<Value = String> {
    let edits =
        prop::collection::vec((any::<prop::sample::Index>(), 0usize..20, prop::sample::select(FRAGMENTS)), 1..6);
    (prop::sample::select(SEEDS), edits).prop_map(|(seed, edits)| {
        let mut text = shared(seed);
        for (at, delete, fragment) in edits {
            let mut start = at.index(text.len() + 1);
            while !text.is_char_boundary(start) {
                start -= 1;
            }
            let mut end = (start + delete).min(text.len());
            while !text.is_char_boundary(end) {
                end -= 1;
            }
            text.replace_range(start..end, fragment);
        }
        text
    })
}

proptest! {
    #![proptest_config(crate::common::proptest_config(256))]
    #[test]
    fn mutated_benchmarks_never_panic(source in mutated()) {
        check_any(&source);
    }

    #[test]
    fn fragment_soup_never_panics(parts in prop::collection::vec(prop::sample::select(FRAGMENTS), 0..60)) {
        check_any(&format!("MAIN {{ INPUTS {{ a; r[2]; }} OUTPUTS {{ g; }} GUARANTEES {{ {} }} }}", parts.join(" ")));
        check_any(&parts.join(" "));
    }

    #[test]
    fn arbitrary_text_never_panics(source in "\\PC{0,200}") {
        check_any(&source);
    }
}

#[test]
fn the_documentation_example_compiles() {
    let doc = std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/ltl-tlsf.md")).unwrap();
    let example = doc.split("```").nth(1).expect("a code block");
    let spec = compile_ok(example, &[]);
    assert_eq!(spec.formula_text(), "G (g_0 -> !g_1) && G (g_1 -> true) && G (r_0 -> F g_0) && G (r_1 -> F g_1)");
}
