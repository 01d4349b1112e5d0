//! Large projects stay linear: loading and synthesising many small independent modules cost
//! in proportion to the project. Resolving conditions once copied the state names of every
//! plant per automaton, and synthesis sized per-event tables and compared supervisors pairwise;
//! 5 500 modules took over a minute. At the size below a quadratic front end would take many
//! minutes; linear, it takes well under a second.

use plcsynth::sct::compile;
use plcsynth::sct::model::Config;
use plcsynth::sct::{synthesize, Synthesis};

/// `n` modules, each a tank whose overflow is preempted by an enforceable event, with a
/// specification that also refers to its plant's state in a condition.
fn tanks(n: usize) -> String {
    let mut s = String::new();
    for i in 0..n {
        s += &format!(
            "module M{i} {{
  event open : controllable;
  event alarm : uncontrollable;
  event overflow : uncontrollable;
  event closeNow : enforceable {{ on accept \"Q := FALSE;\"; }}
  plant P {{ alphabet open, alarm, overflow, closeNow;
    state A initial {{ open -> B; }} state B {{ alarm -> C; }} state C {{ overflow -> C; closeNow -> A; }} }}
  spec S {{ state S {{ forbid overflow; forbid open if [P.C]; }} }}
}}
"
        );
    }
    s
}

#[test]
fn twenty_thousand_independent_modules_are_synthesised() {
    let n = 20_000;
    let src = tanks(n);
    let (loaded, diags) = compile(&src).unwrap_or_else(|d| panic!("{d:?}"));
    assert!(diags.is_empty(), "{:?}", diags.first());
    assert_eq!((loaded.project.plants.len(), loaded.project.specs.len()), (n, n));
    let Synthesis { reports, diagnostics: diags, .. } =
        synthesize(&src, &loaded, &Config::default(), None, &mut |_| true);
    assert!(diags.is_empty(), "{:?}", diags.first());
    assert_eq!(reports.len(), n);
    for (i, r) in reports.iter().enumerate() {
        assert!(r.realizable, "{}", r.name);
        assert_eq!(r.enforced_events, [format!("M{i}.closeNow")]);
        assert_eq!(r.plants_used, [format!("M{i}.P")]);
    }
}
