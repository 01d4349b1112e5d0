//! Bad `.sct` input: every problem is reported with line:column and a readable message, all
//! at once where possible, and nothing panics.

use plcsynth::diag::{render_plain, Diagnostic};
use plcsynth::sct::compile;
use plcsynth::sct::model::Config;
use plcsynth::sct::{synthesize, Synthesis};
use proptest::prelude::*;

fn errors(src: &str) -> Vec<Diagnostic> {
    match compile(src) {
        Ok((l, _)) => {
            let Synthesis { diagnostics, .. } = synthesize(src, &l, &Config::default(), None, &mut |_| true);
            diagnostics.into_iter().filter(|d| d.is_error()).collect()
        }
        Err(diags) => {
            let errs: Vec<Diagnostic> = diags.into_iter().filter(|d| d.is_error()).collect();
            assert!(!errs.is_empty(), "a project refused without an error");
            errs
        }
    }
}

/// Asserts an error containing `msg` at `line:col`.
fn expect_at(errs: &[Diagnostic], line: u32, col: u32, msg: &str) {
    assert!(
        errs.iter().any(|d| d.line == line && d.column == col && d.message.contains(msg)),
        "no error `{msg}` at {line}:{col}; got:\n{:#?}",
        errs.iter().map(|d| format!("{}:{} {}", d.line, d.column, d.message)).collect::<Vec<_>>()
    );
}

#[test]
fn unknown_names_are_located() {
    let src = "event a : controllable;\nplant P {\n  alphabet a, b;\n  state s { a -> t; }\n}\nspec H { state s { forbid c; } }\n";
    let e = errors(src);
    expect_at(&e, 3, 15, "unknown event `b`");
    expect_at(&e, 4, 18, "unknown state `t`");
    expect_at(&e, 6, 27, "`c`");
    assert_eq!(e.len(), 3, "all three reported at once");
}

#[test]
fn ambiguous_relative_names_are_reported_with_candidates() {
    let src = "module A {\n  event x : uncontrollable;\n  module B {\n    event x : uncontrollable;\n    module C { spec H { state s { forbid x; } } }\n  }\n}\n";
    let e = errors(src);
    expect_at(&e, 5, 42, "ambiguous name `x`");
    let d = e.iter().find(|d| d.message.contains("ambiguous")).unwrap();
    assert!(
        d.notes.iter().any(|n| n.contains("A.B.x")) && d.notes.iter().any(|n| n.contains("`A.x`")),
        "{:?}",
        d.notes
    );
}

#[test]
fn absolute_names_win_over_relative_ones() {
    let src = "module A { event x : uncontrollable; module A { event x : controllable; spec H { state s { forbid A.x; } } } }\n";
    let (l, _) = compile(src).unwrap_or_else(|diags| panic!("{diags:?}"));
    let p = &l.project.specs[0].prohib[0];
    assert_eq!(l.project.event_name(p.event), "A.x");
}

#[test]
fn unbound_binding_events_name_the_instance() {
    let src = "template plant V {\n  bind op, cl;\n  alphabet op, cl;\n  state c { op -> o; }\n  state o { cl -> c; }\n}\nmodule Y { event op : controllable;\n  instance b : V;\n}\n";
    let e = errors(src);
    expect_at(&e, 8, 12, "binding event `cl` of template `V` is not bound");
}

#[test]
fn conditions_over_unknown_states() {
    let src = "event j : uncontrollable;\nplant H { alphabet j; state off { j -> off; } }\nplant J { alphabet j; state s { j -> s if [H.warm or Q.x]; } }\n";
    let e = errors(src);
    expect_at(&e, 3, 44, "plant `H` has no state `warm`");
    expect_at(&e, 3, 54, "unknown plant `Q`");
}

#[test]
fn overlapping_conditional_transitions_report_both_locations() {
    let src = "event a : controllable;\nevent u : uncontrollable;\nplant G { alphabet a; state g0 { a -> g1; } state g1 { a -> g0; } }\nspec H {\n  state s {\n    u -> t if [G.g0];\n    u -> s if [G.g0 or G.g1];\n  }\n  state t { forbid u; }\n}\n";
    let e = errors(src);
    let d =
        e.iter().find(|d| d.message.contains("two transitions on `u` can both be taken")).expect("conflict reported");
    assert_eq!((d.line, d.column), (6, 5));
    assert!(d.notes.iter().any(|n| n.contains("7:5")), "{:?}", d.notes);
}

#[test]
fn unconditional_duplicate_transitions() {
    let src = "event a : controllable;\nspec H { state s { a -> s; a -> t; } state t; }\n";
    let e = errors(src);
    expect_at(&e, 2, 28, "two unconditional transitions on `a`");
}

#[test]
fn enforcement_cycles_are_errors() {
    let src = "event u : uncontrollable;\nevent f1 : enforceable { on accept \"x := 1;\"; }\nevent f2 : enforceable { on accept \"x := 0;\"; }\nplant P {\n  alphabet u, f1, f2;\n  state A { u -> A; f1 -> B; }\n  state B { u -> B; f2 -> A; }\n}\nspec H { state s { forbid u; } }\n";
    let e = errors(src);
    let d = e.iter().find(|d| d.message.contains("enforces a cycle")).expect("cycle reported");
    assert_eq!(d.line, 6);
}

#[test]
fn event_declaration_rules() {
    let src = "event f : enforceable { detect rising \"x\"; }\nevent u : uncontrollable { executed; }\nevent c : sometimes;\n";
    let e = errors(src);
    expect_at(&e, 1, 7, "needs `on accept");
    expect_at(&e, 1, 25, "cannot be detected");
    expect_at(&e, 2, 28, "cannot be executed");
    expect_at(&e, 3, 11, "unknown event type `sometimes`");
}

#[test]
fn syntax_errors_are_all_reported() {
    let src = "plant P {\n  alphabet a\n  state s { a -> ; }\n}\nspec H { state s { forbid ; } }\n$\n";
    let e = errors(src);
    assert!(e.len() >= 3, "{e:?}");
    expect_at(&e, 3, 3, "expected `;`");
    expect_at(&e, 5, 27, "expected an event to forbid");
    // Recovery resumes at `state`, so the plant keeps its state and no follow-up error appears.
    assert!(!e.iter().any(|d| d.message.contains("has no states")), "{e:?}");
    expect_at(&e, 6, 1, "unexpected character `$`");
    let text = render_plain("bad.sct", src, &e);
    assert!(text.contains("bad.sct:5:27: error:"), "{text}");
}

#[test]
fn plants_need_alphabets_and_specs_must_not_have_one() {
    let src = "event a : controllable;\nplant P { state s { a -> s; } }\nspec H { alphabet a; state s; }\n";
    let e = errors(src);
    expect_at(&e, 2, 7, "needs an `alphabet`");
    expect_at(&e, 3, 10, "cannot have an alphabet");
}

const TOKENS: &[&str] = &[
    "module",
    "event",
    "plant",
    "spec",
    "template",
    "instance",
    "state",
    "initial",
    "forbid",
    "alphabet",
    "selfloops",
    "impossible",
    "bind",
    "namespace",
    "timer",
    "duration",
    "start",
    "stop",
    "if",
    "and",
    "or",
    "not",
    "a",
    "b",
    "X",
    "X.a",
    "{",
    "}",
    "[",
    "]",
    "(",
    ")",
    ";",
    ":",
    ",",
    ".",
    "->",
    "=",
    "controllable",
    "uncontrollable",
    "enforceable",
    "\"s\"",
    "15s",
    "detect",
    "rising",
    "on",
    "accept",
    "denial",
    "reset",
    "executed",
    "\n",
];

proptest! {
    #![proptest_config(crate::common::proptest_config(400))]

    #[test]
    fn never_panics_on_random_bytes(bytes in proptest::collection::vec(any::<u8>(), 0..300)) {
        let src = String::from_utf8_lossy(&bytes);
        let _ = errors(&src);
    }

    #[test]
    fn never_panics_on_random_token_soup(idx in proptest::collection::vec(0..TOKENS.len(), 0..120)) {
        let src: Vec<&str> = idx.iter().map(|&i| TOKENS[i]).collect();
        let src = src.join(" ");
        let _ = errors(&src);
    }
}

fn example_sources() -> Vec<String> {
    let dir = format!("{}/examples/sct", env!("CARGO_MANIFEST_DIR"));
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .filter_map(|e| e.ok())
        .filter(|e| e.path().extension().is_some_and(|x| x == "sct"))
        .map(|e| std::fs::read_to_string(e.path()).unwrap())
        .collect();
    v.sort();
    v
}

proptest! {
    #![proptest_config(crate::common::proptest_config(300))]

    /// Mutated examples (a span deleted, a token inserted, a span duplicated) exercise the
    /// resolver and synthesis on almost-valid input: never a panic, and a failed load always
    /// comes with an error.
    #[test]
    fn never_panics_on_mutated_examples(which in 0usize..64, ops in proptest::collection::vec((0u8..3, 0usize..10_000, 0usize..40, 0..TOKENS.len()), 1..4)) {
        let sources = example_sources();
        let mut src = sources[which % sources.len()].clone();
        for (op, at, len, tok) in ops {
            let mut at = at % (src.len() + 1);
            while !src.is_char_boundary(at) { at -= 1; }
            let mut end = (at + len).min(src.len());
            while !src.is_char_boundary(end) { end -= 1; }
            match op {
                0 => src.replace_range(at..end, ""),
                1 => src.insert_str(at, &format!(" {} ", TOKENS[tok])),
                _ => { let piece = src[at..end].to_string(); src.insert_str(end, &piece); }
            }
        }
        if let Err(diags) = compile(&src) {
            prop_assert!(diags.iter().any(|d| d.is_error()));
        }
        let _ = errors(&src);
    }
}

#[test]
fn namespace_bindings_inherit_from_modules_and_can_be_overridden() {
    let src = "template spec Mutex {\n  namespace local { op, cl }\n  namespace remote { op }\n  state idle initial { local.op -> busy; }\n  state busy { forbid remote.op; local.cl -> idle; }\n}\nmodule A { event op : controllable; event cl : controllable; }\nmodule B { event op : controllable; event open : controllable; }\ninstance M : Mutex { local = A; remote = B; remote.op = B.open; }\n";
    let (l, _) = compile(src).unwrap_or_else(|diags| panic!("{diags:?}"));
    let spec = &l.project.specs[0];
    assert_eq!(spec.name, "M");
    let forbidden: Vec<&str> = spec.prohib.iter().map(|p| l.project.event_name(p.event)).collect();
    assert_eq!(forbidden, vec!["B.open"], "the override replaces the inherited B.op");
    let moves: Vec<&str> = spec.trans.iter().map(|t| l.project.event_name(t.event)).collect();
    assert_eq!(moves, vec!["A.op", "A.cl"]);
}

#[test]
fn namespace_module_missing_an_event_is_an_unbound_binding() {
    let src = "template spec Mutex {\n  namespace local { op, cl }\n  state idle { forbid local.cl; }\n}\nmodule A { event op : controllable; }\ninstance M : Mutex { local = A; }\nevent x : controllable;\ninstance N : Mutex { lokal = A; }\n";
    let e = errors(src);
    expect_at(&e, 6, 10, "binding event `local.cl` is not bound: module `A` has no event `cl`");
    expect_at(&e, 8, 22, "template `Mutex` has no binding event or namespace `lokal`");
}

#[test]
fn timers_need_a_duration_and_a_start_event() {
    let src = "event go : controllable;\ntimer T { stop go; }\ntimer U { duration 1m 30s; start nothing; }\n";
    let e = errors(src);
    expect_at(&e, 2, 7, "timer `T` has no `duration`");
    expect_at(&e, 2, 7, "timer `T` has no `start` event");
    expect_at(&e, 3, 34, "unknown event `nothing`");
}

fn on_small_stack<T: Send + 'static>(f: impl FnOnce() -> T + Send + 'static) -> T {
    std::thread::Builder::new().stack_size(1 << 20).spawn(f).unwrap().join().expect("no stack overflow, no panic")
}

#[test]
fn deeply_nested_modules_get_a_located_error() {
    let src = format!("{}event e;{}", "module M {\n".repeat(5_000), "}".repeat(5_000));
    let errs = on_small_stack(move || errors(&src).iter().map(|d| (d.line, d.message.clone())).collect::<Vec<_>>());
    assert_eq!(errs.first().map(|e| e.0), Some(65), "{errs:?}");
    assert!(errs[0].1.contains("nested too deeply"), "{errs:?}");
}

#[test]
fn long_condition_chains_resolve_on_a_small_stack() {
    let chain = vec!["P.a"; 50_000].join(" or ");
    let src = format!(
        "event go : controllable; event stop : controllable;\nplant P {{ alphabet go, stop; state a initial {{ go -> b; }} state b {{ stop -> a; }} }}\n\
         spec S {{ state s {{ go -> s if [{chain}]; stop -> s; }} }}\n"
    );
    let errs = on_small_stack(move || errors(&src).iter().map(|d| d.message.clone()).collect::<Vec<_>>());
    assert_eq!(errs, Vec::<String>::new());
}

#[test]
fn an_error_at_the_end_of_a_file_ending_in_cr_renders() {
    let src = "module\r";
    let (Ok((_, diags)) | Err(diags)) = compile(src);
    let text = plcsynth::diag::render_plain("a.sct", src, &diags);
    assert!(text.starts_with("a.sct:1:"), "{text}");
}

/// Triggers and actions are Structured Text: a mistake in one is located inside its string
/// (escapes counted), all of them at once; `\var{…}` and `\last{…}` pass through the string.
#[test]
fn mistakes_in_triggers_and_actions_are_located_inside_the_string() {
    let src = "event a : controllable { detect rising \"Q_A AND\"; on denial \"Q_A = FALSE;\"; }\n\
               event b : controllable { detect edge \"x > \\\"y\"; reset on denial \"Q_B + 1\"; }\n\
               event c : controllable { detect cyclic \"\\var{Ctrl.busy} AND NOT \\last{%IX0.1}\"; on accept \"IF go THEN Q := TRUE; END_IF;\"; }\n\
               plant P { alphabet a, b, c; state s { a -> s; b -> s; c -> s; } }\n";
    let e = errors(src);
    expect_at(&e, 1, 48, "in the trigger: expected an operand");
    expect_at(&e, 1, 66, "in the code: expected `:=`, found `=`");
    // `\"` counts as one character of the fragment and two of the source.
    expect_at(&e, 2, 43, "in the trigger: unexpected character `\"`");
    expect_at(&e, 2, 66, "in `reset on denial`: expected a variable or an address to reset");
    assert_eq!(e.len(), 4, "{e:#?}");
    let rendered = render_plain("t.sct", src, &e);
    assert!(rendered.contains("triggers and actions are Structured Text"), "{rendered}");
}
