//! G4LTL front end under random input (proptest), as the other front ends: damaged real
//! specifications, token soup and arbitrary text never panic; every diagnostic is located on
//! character boundaries and rendered; a rejected text has an error; an accepted one is
//! synthesised on a small budget and its strategy is well-formed. The check is the fuzz
//! target's (`fuzz/src/lib.rs`, `check_g4ltl`), so both run the same code.

#[allow(dead_code)] // the other targets' checks are used by tests/fuzz_regressions.rs
use crate::harness;

use proptest::prelude::*;
use std::path::PathBuf;

fn seeds() -> Vec<String> {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let mut texts = Vec::new();
    for dir in [root.join("../shared/ltl/g4ltl"), root.join("examples/ltl")] {
        let mut paths: Vec<_> = std::fs::read_dir(&dir).unwrap().map(|e| e.unwrap().path()).collect();
        paths.sort();
        for path in paths.into_iter().filter(|p| p.extension().is_some_and(|e| e != "tlsf")) {
            texts.push(std::fs::read_to_string(path).unwrap());
        }
    }
    assert!(texts.len() >= 20);
    texts
}

/// Pieces of the language and of its mistakes.
const FRAGMENTS: &[&str] = &[
    "(",
    ")",
    "!",
    "&&",
    "||",
    "->",
    "<->",
    "[]",
    "<>",
    "X ",
    "U ",
    "W ",
    "R ",
    "ALWAYS ",
    "EVENTUALLY ",
    "NEXT ",
    "UNTIL ",
    "ASSUME ",
    "INPUT ",
    "OUTPUT ",
    "TIMER t(5s)",
    "t.start",
    "t.expire",
    ",",
    "\n",
    "\r",
    "##",
    "!--",
    "//",
    "true",
    "false",
    "req1",
    "grant1",
    "zz",
    "1",
    "10ms",
    "\u{0}",
    "é",
    "\t",
    " ",
    "WHENEVER ",
    " THEN ",
    " FOR 2s",
    " UNTIL ",
    "x",
    ": REAL[0, 4]",
    "y: INT[-3, 3]",
    " + ",
    " - ",
    " * ",
    " / ",
    "^2",
    " > ",
    " <= ",
    " = ",
    " != ",
    "3.5",
    "1e3",
];

fn mutated() -> impl Strategy<Value = String> {
    let edits =
        prop::collection::vec((any::<prop::sample::Index>(), 0usize..12, prop::sample::select(FRAGMENTS)), 1..6);
    (any::<prop::sample::Index>(), edits).prop_map(|(seed, edits)| {
        let seeds = seeds();
        let mut text = seeds[seed.index(seeds.len())].clone();
        for (at, cut, fragment) in edits {
            let mut i = at.index(text.len() + 1);
            while !text.is_char_boundary(i) {
                i -= 1;
            }
            let mut j = (i + cut).min(text.len());
            while !text.is_char_boundary(j) {
                j -= 1;
            }
            text.replace_range(i..j, fragment);
        }
        text
    })
}

fn soup() -> impl Strategy<Value = String> {
    prop::collection::vec(prop::sample::select(FRAGMENTS), 0..60).prop_map(|parts| parts.concat())
}

proptest! {
    #![proptest_config(crate::common::proptest_config(256))]
    #[test]
    fn damaged_specifications_never_panic(source in mutated()) {
        harness::check_g4ltl(&source);
    }

    #[test]
    fn token_soup_never_panics(source in soup()) {
        harness::check_g4ltl(&source);
    }

    #[test]
    fn arbitrary_text_never_panics(source in "\\PC{0,200}") {
        harness::check_g4ltl(&source);
    }
}

/// The deep and long inputs of the other front ends' tests, on a stack as small as a wasm
/// worker's: refused with a located error, or accepted, never a stack overflow.
#[test]
fn deep_inputs_are_safe_on_a_small_stack() {
    let inputs = [
        format!("{}a{}\nINPUT a", "(".repeat(100_000), ")".repeat(100_000)),
        format!("{}a\nINPUT a", "! ".repeat(100_000)),
        format!("{}a\nINPUT a", "X ".repeat(100_000)),
        format!("{}a\nINPUT a", "a -> ".repeat(100_000)),
        format!("{}a\nINPUT a", "a U ".repeat(100_000)),
        format!("{}a\nINPUT a", "a <-> ".repeat(100_000)),
        format!("{}a\nINPUT a", "a && ".repeat(100_000)),
        format!("{}a\nINPUT a", "(a && ".repeat(1_000) + &")".repeat(1_000)),
    ];
    std::thread::Builder::new()
        .stack_size(1 << 20)
        .spawn(move || {
            for input in &inputs {
                harness::check_g4ltl(input);
            }
        })
        .unwrap()
        .join()
        .expect("no stack overflow");
}
