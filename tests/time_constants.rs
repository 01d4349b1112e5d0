//! Time constants in generated PLC code: each target writes a delay exactly or refuses it with an
//! error located at the constant in the specification; nothing wraps or rounds.

use plcsynth::diag::Diagnostic;
use plcsynth::plc::{self, Target};
use plcsynth::timed::program;
use plcsynth::timed::{compile, solve::Config, synthesize};
use proptest::prelude::*;

/// A controller that must wait `bound` time units before its request: one threshold, one timer.
fn spec(timeunit: &str, bound: u32) -> String {
    format!(
        "timeunit {timeunit};\nplant {{\n  automaton A {{\n    clocks x;\n    nodes a, b;\n    \
         a -> b ?go {{ x in [{bound},inf) }} reset {{ x }};\n    b -> a ?back;\n  }}\n}}\n\
         plans {{ plan {{ waitfor go; waitfor back; }} }}\n"
    )
}

/// Line and column of the bound in [`spec`]: line 6, after `    a -> b ?go { x in [`.
const BOUND_AT: (u32, u32) = (6, 24);

/// The code for every target, from one synthesis.
fn generate_all(source: &str) -> Vec<(Target, Result<String, Vec<Diagnostic>>)> {
    let (game, _) = compile(source).expect("a valid specification");
    let synthesis = synthesize(&game, &Config::default(), &mut |_| true);
    let program = program::controller(&game, &synthesis).expect("realizable");
    Target::ALL.into_iter().map(|t| (t, plc::generate(&game, &program, t, "limits", source))).collect()
}

fn generate(source: &str, target: Target) -> Result<String, Vec<Diagnostic>> {
    generate_all(source).into_iter().find(|(t, _)| *t == target).unwrap().1
}

/// The one error of a refused constant, checked to sit at the bound.
fn refusal(source: &str, target: Target) -> Diagnostic {
    let diags = generate(source, target).expect_err("the constant does not fit");
    assert_eq!(diags.len(), 1, "{diags:#?}");
    let d = diags[0].clone();
    assert!(d.is_error());
    assert_eq!((d.line, d.column), BOUND_AT, "{d:#?}");
    assert!(d.message.ends_with(&format!("for target {}", target.name())), "{}", d.message);
    d
}

#[test]
fn a_wrapping_product_is_a_located_error_for_every_target() {
    // Issue 9: 16777215 × 16777216 h printed its value modulo 2^64 as `T#17185675780068212736MS`.
    let source = spec("16777216 h", 16_777_215);
    for target in Target::ALL {
        let d = refusal(&source, target);
        assert!(d.message.starts_with("time constant 16777215 (1013309855760384000000 ms) exceeds "), "{}", d.message);
        assert!(d.notes.iter().any(|n| n == "one time unit is 60397977600000 ms (`timeunit` at 1:1)"), "{:?}", d.notes);
    }
    let d = refusal(&source, Target::St);
    assert_eq!(
        d.message,
        "time constant 16777215 (1013309855760384000000 ms) exceeds IEC TIME (at most 2147483647 ms = \
         24d20h31m23s647ms) for target st"
    );
}

#[test]
fn constants_beyond_the_targets_time_types_are_refused() {
    // Issue 9: `T#16777215000MS` exceeds every 32-bit TIME.
    let source = spec("1 s", 16_777_215);
    for (target, type_name) in [
        (Target::St, "IEC TIME"),
        (Target::Il, "IEC TIME"),
        (Target::Plcopen, "IEC TIME"),
        (Target::Abb, "IEC TIME"),
        (Target::Scl, "S7 TIME"),
        (Target::Scl1500, "S7 TIME"),
        (Target::Codesys, "CODESYS/TwinCAT TIME"),
        (Target::Twincat, "CODESYS/TwinCAT TIME"),
        (Target::Stl, "S5TIME"),
    ] {
        let d = refusal(&source, target);
        assert!(
            d.message.starts_with(&format!("time constant 16777215 (16777215000 ms) exceeds {type_name} ")),
            "{}",
            d.message
        );
    }
    // Issue 9: `S5T#2H46M40S` exceeds S5TIME's 2h46m30s; IEC TIME holds it.
    let source = spec("1 s", 10_000);
    assert_eq!(
        refusal(&source, Target::Stl).message,
        "time constant 10000 (10000000 ms) exceeds S5TIME (at most 9990000 ms = 2h46m30s) for target stl"
    );
    assert!(generate(&source, Target::St).unwrap().contains("ET >= T#10000000MS"));
}

#[test]
fn the_largest_constants_that_fit_are_printed_exactly_and_one_more_is_refused() {
    // 32-bit signed TIME: the preset, one unit above the threshold, must fit. 128 ms × (16777214 + 1)
    // = 2^31 − 128 fits; 128 ms × (16777215 + 1) = 2^31 is one millisecond too many.
    let fits = spec("128ms", 16_777_214);
    let over = spec("128ms", 16_777_215);
    for target in [Target::St, Target::Il, Target::Plcopen, Target::Scl] {
        let code = generate(&fits, target).unwrap();
        assert!(code.contains("T#2147483392MS") && code.contains("PT := T#2147483520MS"), "{target:?}:\n{code}");
        let d = refusal(&over, target);
        assert!(
            d.message.starts_with(
                "time constant 16777215 (2147483520 ms) needs a timer preset one time unit above it, 2147483648 ms, \
                 which exceeds "
            ),
            "{}",
            d.message
        );
    }
    // CODESYS/TwinCAT: unsigned 32-bit. 257 ms × 16711935 = 2^32 − 1 exactly.
    let code = generate(&spec("257ms", 16_711_934), Target::Codesys).unwrap();
    assert!(code.contains("ET >= T#4294967038MS") && code.contains("PT := T#4294967295MS"), "{code}");
    let d = refusal(&spec("257ms", 16_711_935), Target::Codesys);
    assert!(
        d.message.contains("4294967552 ms, which exceeds CODESYS/TwinCAT TIME (at most 4294967295 ms"),
        "{}",
        d.message
    );
    // S5TIME: 999 × 10 s at most.
    let code = generate(&spec("10s", 999), Target::Stl).unwrap();
    assert!(code.contains("L\tS5T#2H46M30S"), "{code}");
    refusal(&spec("10s", 1000), Target::Stl);
}

#[test]
fn s5time_constants_must_be_exact() {
    for (timeunit, bound, literal) in [
        ("1ms", 10, "S5T#10MS"),
        ("100ms", 999, "S5T#1M39S900MS"),
        ("100ms", 1010, "S5T#1M41S"),
        ("1s", 999, "S5T#16M39S"),
    ] {
        let code = generate(&spec(timeunit, bound), Target::Stl).unwrap();
        assert!(code.contains(&format!("L\t{literal}\n")), "{timeunit} × {bound}:\n{code}");
    }
    // 5 ms is below S5TIME's 10 ms step; 100.1 s needs steps of 1 s.
    for (timeunit, bound, ms, rounded) in
        [("1ms", 5, 5, 0), ("100ms", 1001, 100_100, 100_000), ("1s", 1001, 1_001_000, 1_000_000)]
    {
        let d = refusal(&spec(timeunit, bound), Target::Stl);
        assert_eq!(
            d.message,
            format!("time constant {bound} ({ms} ms) is not exactly representable in S5TIME for target stl")
        );
        assert!(d.notes[0].ends_with(&format!("it would become {rounded} ms")), "{:?}", d.notes);
        // The other targets count milliseconds.
        assert!(generate(&spec(timeunit, bound), Target::St).unwrap().contains(&format!("ET >= T#{ms}MS")));
    }
}

/// An independent statement of the documented limits: the milliseconds a target accepts.
fn accepts(target: Target, threshold_ms: u128, unit_ms: u128) -> bool {
    let fits_32 = |max: u128| threshold_ms + unit_ms <= max;
    match target {
        Target::St | Target::Il | Target::Plcopen | Target::Abb | Target::Scl | Target::Scl1500 => {
            fits_32((1 << 31) - 1)
        }
        Target::Codesys | Target::Twincat => fits_32((1 << 32) - 1),
        Target::Stl => {
            [10, 100, 1000, 10_000].iter().any(|&step| threshold_ms % step == 0 && threshold_ms / step <= 999)
        }
    }
}

/// `S5T#…` written by hand: hours, minutes, seconds, milliseconds, zero parts left out.
fn s5_literal(ms: u128) -> String {
    let parts = [(ms / 3_600_000, "H"), (ms / 60_000 % 60, "M"), (ms / 1000 % 60, "S"), (ms % 1000, "MS")];
    let text: String = parts.iter().filter(|(v, _)| *v > 0).map(|(v, u)| format!("{v}{u}")).collect();
    format!("S5T#{text}")
}

proptest! {
    #![proptest_config(crate::common::proptest_config(256))]

    /// For any time unit and bound, every target prints the exact product or refuses it at the
    /// constant; it never prints a wrong number.
    #[test]
    fn printed_constants_are_exact_or_refused(
        value in prop_oneof![1u32..=1000, 1u32..=1 << 24],
        unit in prop::sample::select(vec![("ms", 1u128), ("s", 1000), ("min", 60_000), ("h", 3_600_000)]),
        bound in prop_oneof![1u32..=10_000, 1u32..=1 << 24],
        // Half the cases put the bound next to a limit: IEC TIME, CODESYS TIME or S5TIME.
        edge in prop::option::of(prop::sample::select(vec![(1u128 << 31) - 1, (1 << 32) - 1, 9_990_000])),
        delta in -2i64..=2,
    ) {
        let unit_ms = u128::from(value) * unit.1;
        let bound = match edge {
            Some(limit) => (limit / unit_ms) as i64 - 1 + delta,
            None => i64::from(bound),
        }
        .clamp(1, 1 << 24) as u32;
        let source = spec(&format!("{value}{}", unit.0), bound);
        let threshold = u128::from(bound) * unit_ms;
        for (target, result) in generate_all(&source) {
            match result {
                Ok(code) => {
                    prop_assert!(accepts(target, threshold, unit_ms), "{target:?} printed {threshold} ms:\n{code}");
                    if target == Target::Stl {
                        prop_assert!(code.contains(&format!("L\t{}\n", s5_literal(threshold))), "{code}");
                    } else {
                        let test = if target == Target::Il { "GE" } else { ">=" };
                        prop_assert!(code.contains(&format!("{test} T#{threshold}MS")), "{target:?}:\n{code}");
                        prop_assert!(code.contains(&format!("PT := T#{}MS", threshold + unit_ms)), "{target:?}:\n{code}");
                    }
                }
                Err(diags) => {
                    prop_assert!(!accepts(target, threshold, unit_ms), "{target:?} refused {threshold} ms: {diags:#?}");
                    prop_assert!(!diags.is_empty());
                    for d in &diags {
                        prop_assert_eq!((d.line, d.column), BOUND_AT);
                        prop_assert!(d.message.starts_with(&format!("time constant {bound} ({threshold} ms) ")), "{}", d.message);
                        prop_assert!(d.message.ends_with(&format!("for target {}", target.name())), "{}", d.message);
                    }
                }
            }
        }
    }
}

/// A strict lower bound (`x in (2,inf)`) must not be met at exactly 2 s: ST and IL compare
/// `ET > T#2000MS`; an S5TIME timer, which counts in steps, is preset to the next value, 2.01 s.
#[test]
fn strict_bounds_are_strict_on_every_target() {
    let source = spec("1s", 2).replace("[2,inf)", "(2,inf)");
    let code = |t: Target| generate(&source, t).expect("fits");
    assert!(code(Target::St).contains("ET > T#2000MS"), "{}", code(Target::St));
    let stl = code(Target::Stl);
    assert!(stl.contains("S5T#2S10MS") && !stl.contains("S5T#2S\n"), "{stl}");
    let closed = generate(&spec("1s", 2), Target::Stl).expect("fits");
    assert!(closed.contains("S5T#2S\n") && !closed.contains("S5T#2S10MS"), "{closed}");
}
