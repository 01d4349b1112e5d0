//! The `.tga` language: the thesis listings, located diagnostics, robustness.

use plcsynth::diag::render_plain;
use plcsynth::search::Outcome as _;
use plcsynth::timed::model::LocId;
use plcsynth::timed::{compile, parse};

fn fixture(name: &str) -> String {
    std::fs::read_to_string(format!("{}/tests/fixtures/thesis/{name}", env!("CARGO_MANIFEST_DIR"))).unwrap()
}

fn syntax_errors(src: &str) -> Vec<String> {
    parse(src)
        .diagnostics
        .iter()
        .filter(|d| d.is_error())
        .map(|d| format!("{}:{}: {}", d.line, d.column, d.message))
        .collect()
}

#[test]
fn thesis_listings_parse_verbatim() {
    for name in [
        "round_table_appendix_a.tga",
        "robot_arm_4_1_4.tga",
        "robot_arm_4_1_4_bare.tga",
        "gripper_4_2_1.tga",
        "plan_4_2_2.tga",
    ] {
        let src = fixture(name);
        assert_eq!(syntax_errors(&src), Vec::<String>::new(), "{name}");
    }
}

#[test]
fn thesis_listings_with_a_plant_check() {
    for name in ["round_table_appendix_a.tga", "robot_arm_4_1_4.tga", "robot_arm_4_1_4_bare.tga", "gripper_4_2_1.tga"] {
        let src = fixture(name);
        if let Err(d) = compile(&src) {
            panic!("{name}:\n{}", render_plain(name, &src, &d));
        }
    }
}

/// Compiles `src` and returns the errors as `line:col: message`.
fn errors(src: &str) -> Vec<String> {
    match compile(src) {
        Ok(_) => Vec::new(),
        Err(d) => {
            d.iter().filter(|d| d.is_error()).map(|d| format!("{}:{}: {}", d.line, d.column, d.message)).collect()
        }
    }
}

/// Asserts an error at the `occurrence`-th (1-based) appearance of `at` in `src` whose message
/// contains `fragment`; the expected line and column are derived from the source text.
fn assert_error_at(src: &str, at: &str, occurrence: usize, fragment: &str) {
    let offset = src.match_indices(at).nth(occurrence - 1).unwrap_or_else(|| panic!("{at:?} not in source")).0;
    let line = src[..offset].matches('\n').count() + 1;
    let col = src[..offset].rsplit('\n').next().unwrap().chars().count() + 1;
    let errs = errors(src);
    assert!(
        errs.iter().any(|e| e.starts_with(&format!("{line}:{col}: ")) && e.contains(fragment)),
        "expected an error at {line}:{col} ({at:?}) containing {fragment:?}, got {errs:#?}"
    );
}

fn assert_error(src: &str, at: &str, fragment: &str) {
    assert_error_at(src, at, 1, fragment)
}

const PLAN: &str = "plans { plan { waitfor a; } }\n";

#[test]
fn lexical_errors_are_located() {
    assert_error("plant { automaton A { nodes q; q -> q ?a; } }\n#\n", "#", "unexpected character `#`");
    assert_error("plant { } /* never closed\n", "/*", "block comment is never closed");
}

#[test]
fn syntax_errors_are_located_and_all_reported() {
    let src = "plant {\n  automaton A {\n    nodes q0, q1;\n    q0 -> q1 a;\n    q1 -> q0 ?b {c in [1,2}\n  }\n}\n";
    assert_error(src, "a;", "expected a message type");
    assert_error(src, "}\n  }", "`]` or `)`");
    assert_error(
        "plant { automaton A { nodes q; } }\nassertions { never A.q and ; }\n",
        "; }\n",
        "expected a condition",
    );
    assert_error("timeunit 5 parsecs;\n", "parsecs", "unknown time unit `parsecs`");
    assert_error("plant { automaton A { clocks c; nodes q{c in [0,inf]}; } }\n", "]}", "must end with `)`");
}

#[test]
fn semantic_errors_are_located() {
    let unit = "plant { automaton A { clocks c; nodes q0, q1; q0 -> q1 ?a; q1 -> q0 !b; } }\n";
    // Unknown unit, node, wildcard.
    assert_error(&format!("{unit}assertions {{ never B.q0; }}\n{PLAN}"), "B.q0", "unknown unit `B`");
    assert_error(&format!("{unit}assertions {{ never A.q9; }}\n{PLAN}"), "q9", "unknown node `q9` in unit `A`");
    assert_error(&format!("{unit}assertions {{ never A.z*; }}\n{PLAN}"), "z*", "no node of `A` starts with `z`");
    // Unknown node in a transition, unknown clock, clock of another component.
    assert_error("plant { automaton A { nodes q0; q0 -> q7 ?a; } }\n", "q7", "unknown node `q7` in `A`");
    assert_error("plant { automaton A { nodes q0{d in [0,1]}; } }\n", "d in", "unknown clock `d` in `A`");
    let other =
        "plant {\n automaton A { clocks c; nodes q0; }\n automaton B { nodes r0; r0 -> r0 ?m {c in [1,2]}; }\n}\n";
    assert_error(other, "c in", "unknown clock `c` in `B`");
    let d = compile(other).unwrap_err();
    assert!(d.iter().any(|d| d.notes.iter().any(|n| n.contains("`A.c` belongs to another unit"))), "{d:#?}");
    // Duplicate names.
    assert_error(
        "plant { automaton A { nodes q; } automaton A { nodes r; } }\n",
        "A { nodes r",
        "a unit named `A` is already declared",
    );
    assert_error("plant { automaton A { nodes q, q; } }\n", "q;", "node `q` is declared twice");
    assert_error("plant { automaton A { clocks c, c; nodes q; } }\n", "c;", "clock `c` is declared twice");
    // Empty interval.
    assert_error(
        "plant { automaton A { clocks c; nodes q{c in [5,2]}; } }\n",
        "[5,2]",
        "lower bound 5 exceeds its upper bound 2",
    );
    assert_error("plant { hardware H { states a, b; a -> b takes [3,3); } }\n", "[3,3)", "is empty");
    // Synchronised message nobody sends.
    assert_error(
        "plant { automaton A { nodes q; q -> q $ghost; } }\n",
        "ghost",
        "synchronised message `ghost` is never sent",
    );
    // The same ?/! message in two components (3.3).
    assert_error_at(
        "plant { automaton A { nodes q; q -> q ?m; } automaton B { nodes r; r -> r ?m; } }\n",
        "m;",
        2,
        "message `m` is already sent by unit `A`",
    );
    // Plans: undefined label, unknown message, reserved label, plan without waitfor, unknown clock.
    assert_error(
        &format!("{unit}plans {{ plan {{ waitfor a -> nowhere; }} }}\n"),
        "nowhere",
        "undefined label `nowhere`",
    );
    assert_error(&format!("{unit}plans {{ plan {{ waitfor zz; }} }}\n"), "zz", "no unit sends the message `zz`");
    assert_error(
        &format!("{unit}plans {{ plan {{ failed: waitfor a; }} }}\n"),
        "failed:",
        "`failed` is the plan's fail location",
    );
    assert_error(&format!("{unit}plans {{ plan {{ clocks t 5; reset t; }} }}\n"), "plan {", "no `waitfor` command");
    assert_error(&format!("{unit}plans {{ plan {{ reset u; waitfor a; }} }}\n"), "u;", "unknown timeout clock `u`");
    // io entry for an unknown message, and a double mapping.
    assert_error(&format!("{unit}{PLAN}io {{ aa = %I0.0; }}\n"), "aa =", "io entry for unknown message `aa`");
    assert_error(&format!("{unit}{PLAN}io {{ a = %Q0.0; a = %Q0.1; }}\n"), "a = %Q0.1", "`a` is mapped twice");
    // io addresses: one bit, byte 0 to 65535, bit 0 to 7; errors point at the offending part.
    let io = |entries: &str| format!("{unit}{PLAN}io {{ {entries} }}\n");
    assert_error(
        &io("a = %QX99999999999999999999.9;"),
        "99999999999999999999",
        "byte number 99999999999999999999 is out of range",
    );
    assert_error(&io("a = %QX99999999999999999999.9;"), "9;", "bit number 9 is out of range");
    assert_error(&io("a = %Q65536.0;"), "65536", "byte number 65536 is out of range");
    assert_error(&io("b = %IX3.8;"), "8;", "bit number 8 is out of range");
    assert_error(&io("b = %I3.99999999999;"), "99999999999", "bit number 99999999999 is out of range");
    assert_error(&io("a = %QW4;"), "%QW4", "`%QW4` is a word address, but an io signal is one bit");
    assert_error(&io("b = %IB2;"), "%IB2", "`%IB2` is a byte address");
    assert_error(&io("b = %MD8;"), "%MD8", "`%MD8` is a double word address");
    assert_error(&io("b = %IL8;"), "%IL8", "`%IL8` is a long word address");
    assert_error(&io("b = %IX7;"), "%IX7", "`%IX7` has no bit number");
    assert_error(&io("b = %I7;"), "%I7", "`%I7` has no bit number");
    for fine in ["a = %Q65535.7; b = %I0.0;", "a = %QX0.0; b = %MX65535.7;", "a = set %M1.2; b = not %IX0.0;"] {
        assert_eq!(errors(&io(fine)), Vec::<String>::new(), "{fine}");
    }
    // Hardware: unknown state, missing duration; operator with a duration.
    assert_error("plant { hardware H { states a, b; a -> c takes [1,2]; } }\n", "c takes", "unknown state `c` in `H`");
    assert_error("plant { hardware H { states a, b; a -> b; } }\n", "a -> b;", "a hardware move needs its duration");
    assert_error(
        "plant { operator O { states a, b; a <-> b takes [1,2]; } }\n",
        "[1,2]",
        "operator moves take no duration",
    );
}

#[test]
fn all_errors_of_a_file_are_reported_at_once() {
    let src = "plant {\n  automaton A { nodes q; q -> r ?a; }\n  automaton A { nodes s; }\n}\nassertions { never X.q; }\nplans { plan { waitfor nothing; } }\n";
    assert!(errors(src).len() >= 4, "{:#?}", errors(src));
    assert_error(src, "r ?a", "unknown node `r`");
    assert_error_at(src, "A {", 2, "already declared");
    assert_error(src, "X.q", "unknown unit `X`");
    assert_error(src, "nothing", "no unit sends the message `nothing`");
}

#[test]
fn did_you_mean_for_near_misses() {
    let src = "plant { automaton lamp { nodes off, on; off -> on ?turn_on; } }\nplans { plan { waitfor turn_onn; } }\n";
    let d = compile(src).unwrap_err();
    assert!(d.iter().any(|d| d.notes.iter().any(|n| n == "did you mean `turn_on`?")), "{d:#?}");
}

#[test]
fn rendered_diagnostics_show_the_line_and_a_caret() {
    let src = "plant { automaton A { nodes q0; q0 -> q7 ?a; } }\n";
    let d = compile(src).unwrap_err();
    let text = render_plain("x.tga", src, &d);
    assert!(text.contains("x.tga:1:39: error: unknown node `q7` in `A`"), "{text}");
    assert!(text.contains("1 | plant { automaton A { nodes q0; q0 -> q7 ?a; } }"), "{text}");
    assert!(text.contains("  |                                       ^^"), "{text}");
}

#[test]
fn hardware_expands_as_in_4_3_2() {
    let (game, _) =
        compile("plant { hardware H { states X, Y; X -> Y takes [2,4]; } }\nplans { plan { waitfor reached_Y; } }\n")
            .unwrap();
    let h = &game.components[0];
    let names: Vec<&str> = h.locations.iter().map(|l| l.name.as_str()).collect();
    assert_eq!(names, ["X", "Y", "moving_X_Y"]);
    assert_eq!(h.clocks.len(), 1);
    assert_eq!(h.locations[2].invariant[0].interval.to_string(), "[0,4]");
    let msg = |e: &plcsynth::timed::model::Edge| game.messages[e.message.index()].name.clone();
    assert_eq!(msg(&h.edges[0]), "moveto_Y");
    assert_eq!(h.edges[0].kind.sigil(), '?');
    assert_eq!(h.edges[0].resets, h.clocks);
    assert_eq!(msg(&h.edges[1]), "reached_Y");
    assert_eq!(h.edges[1].kind.sigil(), '!');
    assert_eq!(h.edges[1].guard[0].interval.to_string(), "[2,inf)");
}

#[test]
fn operator_expands_as_in_4_3_3() {
    let (game, _) = compile("plant { operator button { states released, pressed; released <-> pressed; } }\nplans { plan { waitfor reached_pressed; } }\n").unwrap();
    let b = &game.components[0];
    let names: Vec<&str> = b.locations.iter().map(|l| l.name.as_str()).collect();
    assert_eq!(names, ["released", "pressed", "moving_released_pressed", "moving_pressed_released"]);
    assert_eq!(game.messages[(b.edges[0].message).index()].name, "occurred_pressed");
    assert_eq!(b.edges[0].kind.sigil(), '!');
    assert_eq!(b.edges[1].guard[0].interval.to_string(), "(0,inf)");
    assert_eq!(b.locations[2].invariant[0].interval.to_string(), "[0,1)");
}

#[test]
fn plans_compile_with_algorithm_4() {
    let src = "plant { automaton A { nodes q; q -> q !a; q -> q !b; q -> q !c; } }\nplans { plan { clocks t 15; L1: reset t; waitfor a, b -> failed, c -> L1; waitfor b; } }\n";
    let (game, _) = compile(src).unwrap();
    let p = &game.plans[0];
    let names: Vec<&str> = p.locations.iter().map(|l| l.name.as_str()).collect();
    assert_eq!(names, ["waitfor1", "waitfor2", "failed"]);
    let t = p.clocks[0].0;
    let edge = |m: &str| {
        p.edges.iter().find(|e| game.messages[e.message.index()].name == m && e.from == LocId::new(0)).unwrap()
    };
    assert_eq!(edge("a").to, LocId::new(1));
    assert!(edge("a").resets.is_empty());
    assert_eq!(edge("b").to, p.failed);
    // `c -> L1` passes the reset command and comes back to the first waitfor.
    assert_eq!(edge("c").to, LocId::new(0));
    assert_eq!(edge("c").resets, vec![t]);
    // After the last command the plan wraps around through the reset.
    let last = p.edges.iter().find(|e| e.from == LocId::new(1)).unwrap();
    assert_eq!((last.to, last.resets.clone()), (LocId::new(0), vec![t]));
}

mod robustness {
    use super::*;
    use proptest::prelude::*;

    const WORDS: &[&str] = &[
        "plant",
        "automaton",
        "hardware",
        "operator",
        "clocks",
        "nodes",
        "states",
        "takes",
        "reset",
        "instant",
        "in",
        "inf",
        "and",
        "or",
        "not",
        "never",
        "always",
        "onlyif",
        "assertions",
        "dependencies",
        "dependson",
        "time",
        "guards",
        "guardedby",
        "plans",
        "plan",
        "waitfor",
        "failed",
        "timeunit",
        "io",
        "ms",
        "{",
        "}",
        "(",
        ")",
        "[",
        "]",
        ",",
        ";",
        ":",
        ".",
        "*",
        "?",
        "!",
        "$",
        "=",
        "->",
        "<-",
        "<->",
        "A",
        "q",
        "c",
        "x",
        "0",
        "1",
        "5",
        "%I0.0",
        "\"s\"",
        "/*",
        "*/",
        "//",
        "\n",
    ];

    proptest! {
        #![proptest_config(crate::common::proptest_config(300))]

        #[test]
        fn arbitrary_bytes_never_panic(bytes in proptest::collection::vec(any::<u8>(), 0..400)) {
            let src = String::from_utf8_lossy(&bytes);
            let _ = parse(&src);
            let _ = compile(&src);
        }

        #[test]
        fn token_soup_never_panics(tokens in proptest::collection::vec(proptest::sample::select(WORDS), 0..120)) {
            let src = tokens.join(" ");
            let _ = compile(&src);
        }

        /// Damaging an example anywhere never panics; what still compiles also solves.
        #[test]
        fn damaged_examples_never_panic(which in 0usize..4, at in 0usize..2000, cut in 0usize..12, insert in proptest::sample::select(WORDS)) {
            let names = ["lamp.tga", "gear_checking.tga", "round_table_2.tga", "two_robots_14.tga"];
            let path = format!("{}/examples/timed/{}", env!("CARGO_MANIFEST_DIR"), names[which]);
            let mut src = std::fs::read_to_string(path).unwrap();
            let mut at = at.min(src.len());
            while !src.is_char_boundary(at) { at -= 1; }
            let mut end = (at + cut).min(src.len());
            while !src.is_char_boundary(end) { end -= 1; }
            src.replace_range(at..end, insert);
            if let Ok((game, _)) = compile(&src) {
                let options = plcsynth::timed::solve::Config { max_states: 20_000, ..Default::default() };
                let _ = plcsynth::timed::synthesize(&game, &options, &mut |_| true);
            }
        }
    }
}

#[test]
fn too_many_clocks_is_an_error_not_a_crash() {
    let mut src = String::from("plant {\n");
    for i in 0..70 {
        src.push_str(&format!("  hardware h{i} {{ states a{i}, b{i}; a{i} -> b{i} takes [1,2]; }}\n"));
    }
    src.push_str("}\nplans { plan { waitfor reached_b0; } }\n");
    let errs = errors(&src);
    assert!(errs.iter().any(|e| e.contains("70 clocks; at most 63")), "{errs:#?}");
}

#[test]
fn every_example_in_the_language_reference_parses() {
    let doc = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/docs/timed-language.md")).unwrap();
    let blocks: Vec<&str> = doc.split("```tga\n").skip(1).map(|b| b.split("```").next().unwrap()).collect();
    assert!(blocks.len() >= 8, "found {} tga blocks", blocks.len());
    for block in blocks {
        // Fragments of a plant body are wrapped so that they form a specification.
        let src = if block.trim_start().starts_with("hardware") || block.trim_start().starts_with("operator") {
            format!("plant {{\n{block}}}\n")
        } else {
            block.to_string()
        };
        assert_eq!(syntax_errors(&src), Vec::<String>::new(), "{block}");
    }
}

/// Runs `f` on a thread with a 1 MiB stack, the size a wasm worker gets, so that recursion
/// which only native stacks survive fails here.
fn on_small_stack<T: Send + 'static>(f: impl FnOnce() -> T + Send + 'static) -> T {
    std::thread::Builder::new().stack_size(1 << 20).spawn(f).unwrap().join().expect("no stack overflow, no panic")
}

const LAMP_PLANT: &str = "plant { automaton lamp { nodes off, on; off -> on ?turn_on; on -> off ?turn_off; } }\n";

#[test]
fn deeply_nested_conditions_get_a_located_error() {
    for (what, cond) in [
        ("parentheses", format!("{}lamp.on{}", "(".repeat(100_000), ")".repeat(100_000))),
        ("not", format!("{}lamp.on", "not ".repeat(100_000))),
    ] {
        let src = format!("{LAMP_PLANT}assertions {{ never {cond}; }}\n");
        let errs = on_small_stack(move || errors(&src));
        assert!(
            !errs.is_empty() && errs[0].starts_with("2:") && errs[0].contains("nested too deeply"),
            "{what}: {errs:?}"
        );
    }
    // 64 levels are fine.
    let src = format!("{LAMP_PLANT}assertions {{ never {}lamp.on{}; }}\n", "(not ".repeat(32), ")".repeat(32));
    assert_eq!(on_small_stack(move || errors(&src)), Vec::<String>::new());
}

#[test]
fn long_and_or_chains_are_flat() {
    // A chain of 100 000 operands is one wide node: it checks, solves and drops on a small stack,
    // and means what the short form means.
    let chain = vec!["lamp.on"; 100_000].join(" and ");
    let long = format!("{LAMP_PLANT}assertions {{ never {chain} or lamp.off and lamp.on; }}\n");
    let short = format!("{LAMP_PLANT}assertions {{ never lamp.on; }}\n");
    let solve = |src: String| {
        on_small_stack(move || {
            let (game, _) = compile(&src).map_err(|d| format!("{d:?}")).unwrap();
            let result = plcsynth::timed::synthesize(&game, &Default::default(), &mut |_| true);
            (result.solution.verdict(), result.solution.space.states.len())
        })
    };
    assert_eq!(solve(long), solve(short));
}

#[test]
fn render_of_an_error_at_the_end_of_a_file_ending_in_cr() {
    let src = "dependencies\r";
    let d = compile(src).expect_err("an error");
    let text = render_plain("a.tga", src, &d);
    assert!(text.contains("a.tga:1:"), "{text}");
}

/// The warnings of a valid specification as `line:col: message`.
fn warnings(src: &str) -> Vec<String> {
    let (_, w) = compile(src).unwrap_or_else(|d| panic!("{}", render_plain("spec.tga", src, &d)));
    w.iter().map(|d| format!("{}:{}: {}", d.line, d.column, d.message)).collect()
}

fn verdict(src: &str) -> plcsynth::timed::solve::Verdict {
    let (game, _) = compile(src).unwrap();
    plcsynth::timed::synthesize(&game, &Default::default(), &mut |_| true).solution.verdict().expect("decided")
}

/// `automaton m { … }` with a two-goal plan on `x` and `y`.
fn unit_m(body: &str) -> String {
    format!("plant {{\n  automaton m {{\n    clocks c;\n{body}  }}\n}}\nplans {{ plan {{ waitfor x; waitfor y; }} }}\n")
}

/// Where a unit stops time, the verdict rests on zero-time behaviour: warned, located, with
/// the reason and a pointer to the language reference.
#[test]
fn warns_where_time_cannot_pass() {
    use plcsynth::timed::solve::Verdict;
    // The initial state violates its invariant; the controller "wins" by acting at time 0 forever.
    let src = unit_m("    nodes a {c in [1,2]}, b {c in [1,2]};\n    a -> b ?x;\n    b -> a ?y;\n");
    assert_eq!(
        warnings(&src),
        ["4:19: time cannot pass in the initial state: node `a` of `m` requires `c in [1,2]`, but clocks start at 0"]
    );
    assert_eq!(verdict(&src), Verdict::Realizable);
    let (_, w) = compile(&src).unwrap();
    assert!(w[0].notes.iter().any(|n| n.contains("\"Where time cannot pass\" in docs/timed-language.md")), "{w:?}");

    // A cycle of instant requests, each round reaching a plan goal: realizable at one instant.
    let src = unit_m("    nodes a, b;\n    a -> b ?x instant;\n    b -> a ?y instant;\n");
    assert_eq!(warnings(&src), ["5:5: time cannot pass in the cycle `a -> b ?x`, `b -> a ?y` of `m`"]);
    assert_eq!(verdict(&src), Verdict::Realizable);
    let (_, w) = compile(&src).unwrap();
    assert!(w[0].notes[0].starts_with("instant transitions are urgent"), "{w:?}");
    // An instant reaction looping on itself.
    let src = unit_m("    nodes a, b;\n    a -> b ?x;\n    b -> b !y instant;\n");
    assert_eq!(warnings(&src), ["6:5: time cannot pass in the cycle `b -> b !y` of `m`"]);

    // Nodes that let no time pass, on a cycle whose clock is never reset.
    let src = unit_m("    nodes a {c in [0,0]}, b {c in [0,0]};\n    a -> b ?x;\n    b -> a ?y;\n");
    let w = warnings(&src);
    assert_eq!(w, ["5:5: time cannot pass in the cycle `a -> b ?x`, `b -> a ?y` of `m`"]);
    assert_eq!(verdict(&src), Verdict::Realizable);

    // A node that lets no time pass and cannot be left at that value.
    let src = unit_m("    nodes a, b {c in [2,2]};\n    a -> b ?x;\n    b -> a ?y {c in [3,inf)};\n");
    assert_eq!(
        warnings(&src),
        ["4:22: time cannot pass in node `b` of `m` (`c in [2,2]`), and no transition can leave it there"]
    );
    let src = unit_m("    nodes a, b {c in [0,0]};\n    a -> b ?x reset{c};\n    b -> b ?y {c in (0,inf)};\n");
    assert_eq!(
        warnings(&src),
        ["4:22: time cannot pass in node `b` of `m` (`c in [0,0]`), and no transition can leave it there"]
    );
}

/// No warning where time can pass: invariants that hold at 0, cycles whose guards need time
/// (after a reset, or between bounds), nodes that let no time pass but can be left, and `$`
/// transitions, which wait for a partner.
#[test]
fn no_time_warning_where_time_can_pass() {
    for body in [
        "    nodes a {c in [0,5]}, b;\n    a -> b ?x;\n    b -> a ?y reset{c};\n",
        "    nodes a, b;\n    a -> b ?x {c in [1,1]} reset{c} instant;\n    b -> a ?y instant;\n",
        "    nodes a, b;\n    a -> b ?x {c in [0,1]} instant;\n    b -> a ?y {c in [2,3]} instant;\n",
        "    nodes a, b;\n    a -> b ?x instant;\n    b -> a ?y;\n",
        "    nodes a, b {c in [0,0]};\n    a -> b ?x reset{c};\n    b -> a !y;\n",
        "    nodes a {c in [0,0]}, b;\n    a -> b ?x;\n    b -> a ?y reset{c};\n",
        "    nodes i, a {c in [3,3]}, b {c in [3,3]};\n    i -> a ?x;\n    a -> b ?x reset{c};\n    b -> a ?y;\n",
    ] {
        let src = unit_m(body);
        assert_eq!(warnings(&src), Vec::<String>::new(), "{body}");
    }
    let sync = "plant {\n  automaton m { nodes a, b; a -> b $x instant; b -> a $y instant; }\n  automaton n { nodes p; p -> p ?x; p -> p ?y; }\n}\nplans { plan { waitfor x; waitfor y; } }\n";
    assert_eq!(warnings(sync), Vec::<String>::new());
    let hardware = "plant { hardware h { states open, closed; open <-> closed takes [0,0]; } }\nplans { plan { waitfor reached_open; } }\n";
    assert_eq!(warnings(hardware), Vec::<String>::new());
}

/// The thesis's listings stop time nowhere.
#[test]
fn thesis_listings_have_no_time_warning() {
    for name in ["round_table_appendix_a.tga", "robot_arm_4_1_4.tga", "robot_arm_4_1_4_bare.tga", "gripper_4_2_1.tga"] {
        let w = warnings(&fixture(name));
        assert!(w.iter().all(|m| !m.contains("time cannot pass")), "{name}: {w:?}");
    }
}
