//! Inputs found by the fuzzers (`fuzz/`, `docs/fuzzing.md`), replayed through the same checks
//! that found them: `fuzz/src/lib.rs` is included here as a module. Each file in
//! `tests/fixtures/fuzz/<target>/` is one minimised input; `verdict/` holds the generated
//! specification as `.tga` text rather than the fuzzer's bytes, so that it can be read.

use crate::harness;

use plcsynth::rng::Rng;
use plcsynth::timed::solve::Verdict;
use std::path::PathBuf;

/// The saved inputs of one target, sorted by name, as (file name, text read lossily).
fn inputs(target: &str) -> Vec<(String, String)> {
    files(&format!("tests/fixtures/fuzz/{target}"))
}

/// The files of a directory of the repository, sorted by name, as (file name, text).
fn files(relative: &str) -> Vec<(String, String)> {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(relative);
    let mut out: Vec<(String, String)> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.unwrap().path())
        .filter(|p| p.is_file())
        .map(|p| {
            let name = p.file_name().unwrap().to_string_lossy().into_owned();
            (name, String::from_utf8_lossy(&std::fs::read(&p).unwrap()).into_owned())
        })
        .collect();
    out.sort();
    out
}

/// `make fuzz` starts from these inputs, so they must pass the checks themselves.
#[test]
fn the_seed_inputs_pass_the_fuzz_checks() {
    type Check = fn(&str);
    let checks: [(&str, Check); 5] = [
        ("examples/timed", harness::check_tga),
        ("examples/sct", harness::check_sct),
        ("fuzz/seeds/gen", harness::check_gen),
        ("fuzz/seeds/wmod", harness::check_wmod),
        ("../shared/ltl/g4ltl", harness::check_g4ltl),
    ];
    for (dir, check) in checks {
        let seeds = files(dir);
        assert!(!seeds.is_empty(), "no seeds in {dir}");
        for (name, text) in seeds {
            eprintln!("{dir}/{name}");
            check(&text);
        }
    }
}

/// Inputs that made a parser target fail (a crash or a timeout), replayed through its check.
/// `gen/consecutive_range_with_fraction_timeout.gen`: `<Consecutive> 2 6310354.555` declared six
/// million states past the fuzz check's old textual skip (a fraction); the reader's state budget
/// now refuses it at once. `wmod/text_starting_with_a_multibyte_character.wmod`: the error for
/// stray text took one byte of its first character, splitting `é` (found by the `wmod` target).
/// `wmod/renamed_name_with_a_line_break.wmod`: a renamed name with a line break ended the
/// comment listing it, so the imported project did not load.
#[test]
fn saved_parser_inputs_pass_their_checks() {
    type Check = fn(&str);
    let checks: [(&str, Check); 6] = [
        ("tga", harness::check_tga),
        ("sct", harness::check_sct),
        ("gen", harness::check_gen),
        ("wmod", harness::check_wmod),
        ("tlsf", harness::check_tlsf),
        ("ltl", harness::check_g4ltl),
    ];
    let mut replayed = 0;
    for (target, check) in checks {
        let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/fuzz").join(target);
        if !dir.exists() {
            continue;
        }
        for (name, text) in inputs(target) {
            eprintln!("{target}/{name}");
            check(&text);
            replayed += 1;
        }
    }
    assert!(replayed > 0, "no saved parser inputs");
}

/// Finding T1: every token of a long line of garbage was a diagnostic, each costing a scan of
/// the line and a copy of it when rendered; 200 KB on one line took two minutes, 6 GB of
/// memory and printed 6 GB. Now at most `MAX_DIAGNOSTICS` (and one more error) are kept and a
/// long line is shown cut around the caret.
#[test]
fn a_long_line_of_errors_gives_a_short_report() {
    let source = format!("plant {{ automaton a {{ nodes q; {}}} }}", "q -> q ?; ".repeat(20_000));
    let Err(diagnostics) = plcsynth::timed::compile(&source) else { panic!("every transition lacks its message") };
    assert!(diagnostics.len() <= plcsynth::diag::MAX_DIAGNOSTICS + 1, "{} diagnostics", diagnostics.len());
    let text = plcsynth::diag::render_plain("long.tga", &source, &diagnostics);
    assert!(text.len() < 100_000, "{} bytes of diagnostics", text.len());
    harness::check_tga(&source);
}

#[test]
fn saved_verdict_specs_pass_the_whole_pipeline() {
    for (name, source) in inputs("verdict") {
        eprintln!("{name}");
        for seed in 0..20 {
            assert!(harness::check_verdict(&source, seed, true).is_some(), "{name} no longer compiles");
        }
    }
}

/// Finding G1: a 100-byte `.gen` file declares ten million states with one `<Consecutive>`
/// range (it took `plcsynth supcon` 19 s and 880 MB). The reader's state budget refuses it,
/// located at the range, before building any state, and says it is a budget stop.
#[test]
fn a_tiny_gen_file_cannot_declare_millions_of_states() {
    let text = "<Generator>\n<Alphabet> a </Alphabet>\n<States>\n<Consecutive> 1 10000000 </Consecutive>\n\
                </States>\n<InitStates> 1 </InitStates>\n</Generator>\n";
    let mut events = plcsynth::sct::classic::Events::new();
    let err = match plcsynth::sct::classic::gen::read_gen_file(text, &mut events) {
        Ok(g) => panic!("read {} states", g.automaton.num_states()),
        Err(e) => e,
    };
    assert!(err.over_budget, "{err:?}");
    let d = err.diagnostic(text);
    assert_eq!((d.line, d.column), (4, 1), "{d:?}");
    assert!(d.message.contains("more than 250000 states"), "{}", d.message);
    // The budget is exact: 1000 states are read within 1000, refused within 999.
    let small = text.replace("10000000", "1000");
    let g = plcsynth::sct::classic::gen::read_gen_file_within(&small, &mut events, 1000).unwrap();
    assert_eq!(g.automaton.num_states(), 1000);
    assert!(plcsynth::sct::classic::gen::read_gen_file_within(&small, &mut events, 999).is_err_and(|e| e.over_budget));
}

/// The verdict target is only as good as its generator: the specifications must compile, and
/// both verdicts must occur.
#[test]
fn generated_timed_specs_are_well_formed_and_both_verdicts_occur() {
    let mut rng = Rng::new(9);
    let (mut realizable, mut unrealizable) = (0, 0);
    for _ in 0..300 {
        let bytes: Vec<u8> = (0..rng.below(120)).map(|_| rng.below(256) as u8).collect();
        let source = harness::timed_spec(&bytes);
        if let Err(d) = plcsynth::timed::compile(&source) {
            panic!("{}\n{source}", plcsynth::diag::render_plain("generated.tga", &source, &d));
        }
        match harness::check_verdict(&source, 1, true) {
            Some(Ok(Verdict::Realizable)) => realizable += 1,
            Some(Ok(Verdict::Unrealizable)) => unrealizable += 1,
            _ => {}
        }
    }
    assert!(realizable >= 30 && unrealizable >= 30, "{realizable} realizable, {unrealizable} unrealizable");
}
