//! The abstraction-refinement loop of the LTL engine (Cheng et al., section 3): timers learned
//! from counter-strategies, arithmetic predicates checked by the theory, and the compositional
//! split, each against what it must mean.
//! - the paper's figure 1 (`examples/ltl/fig1.ltl`) is unrealizable over the Boolean
//!   abstraction and realizable once `G !(p0 && p1)` is learned; the heating pair likewise, and
//!   an overlapping pair stays unrealizable with a witness that satisfies its predicates;
//! - random predicate specifications: every learned exclusion is truly unsatisfiable (a dense
//!   sampling of the box, evaluated exactly with rationals of this file, finds no point) and
//!   every witness satisfies its combination exactly;
//! - the timer model: a timer restarted in every scan never expires (unrealizable, where the
//!   paper's antecedent would make it realizable), and the shared reconstruction of figure 1
//!   with `light UNTIL t1.expire` is unrealizable for that reason and realizable with `W`.

use plcsynth::ltl::{self, Clause, Config, Format, Ltl, NumExpr, Relation, Spec, Verdict};
use std::path::PathBuf;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn compile(source: &str) -> Spec {
    ltl::compile(source, Format::G4ltl, &[]).unwrap_or_else(|d| panic!("{d:?}")).0
}

fn decide(spec: &Spec, cfg: &Config) -> ltl::Synthesis {
    ltl::synthesize(spec, cfg, &mut |_| true).unwrap_or_else(|s| panic!("{s}"))
}

fn example(name: &str) -> Spec {
    compile(&std::fs::read_to_string(root().join("examples/ltl").join(name)).unwrap())
}

#[test]
fn figure_one_is_realizable_only_with_the_learned_exclusion() {
    let spec = example("fig1.ltl");
    let abstract_only = decide(&spec, &Config { refine: false, ..Config::default() });
    assert_eq!(abstract_only.verdict, Verdict::Unrealizable);
    let refined = decide(&spec, &Config::default());
    assert_eq!(refined.verdict, Verdict::Realizable, "{:?}", refined.limit);
    let learned: Vec<&str> = refined.refinement.learned.iter().map(|l| l.formula.as_str()).collect();
    assert!(learned.contains(&"G !(p0 && p1)"), "{learned:?}");
    // Two groups, as the paper's appendix A: the grants, and the lamp with its timer.
    assert_eq!(refined.groups.len(), 2);
    // The same verdict monolithically.
    let whole = decide(&spec, &Config { compositional: false, ..Config::default() });
    assert_eq!(whole.verdict, Verdict::Realizable);
    assert!(whole.groups.is_empty());
}

#[test]
fn the_heating_pair_is_decided_by_the_theory() {
    let refined = decide(&example("heating.ltl"), &Config::default());
    assert_eq!(refined.verdict, Verdict::Realizable);
    assert_eq!(refined.refinement.learned.len(), 1);
    assert_eq!(refined.refinement.learned[0].formula, "G !(p0 && p1)");
    // Ptolemy's numerical demo pair: the Boolean original is unrealizable, and the refined twin's
    // hand-written assumption is the one learned here (p0, p1 for req1, req2).
    let demo = |name: &str| compile(&std::fs::read_to_string(root().join("../shared/ltl/g4ltl").join(name)).unwrap());
    let original = demo("ptii_NumericalOriginal.g4ltl");
    assert_eq!(decide(&original, &Config::default()).verdict, Verdict::Unrealizable);
    let twin = demo("ptii_NumericalRefined.g4ltl");
    let written = twin.assumptions[0].formula.to_infix(&|s| twin.name(s).to_string());
    assert_eq!(written, refined.refinement.learned[0].formula.replace("p0", "req1").replace("p1", "req2"));
    assert_eq!(decide(&twin, &Config::default()).verdict, Verdict::Realizable);
    let spec = example("heating_overlap.ltl");
    let overlap = decide(&spec, &Config::default());
    assert_eq!(overlap.verdict, Verdict::Unrealizable);
    assert!(overlap.refinement.learned.is_empty());
    let both = overlap.refinement.witnesses.iter().find(|w| w.combination == "p0 && p1").expect("a witness for both");
    let temp = rational(&both.values[0].1);
    assert!(holds(&spec, 0, &[temp]) && holds(&spec, 1, &[temp]), "{both:?}");
}

/// An exact rational of this test, independent of the engine's: (numerator, denominator > 0).
type Q = (i128, i128);

fn rational(text: &str) -> Q {
    match text.split_once('/') {
        Some((n, d)) => (n.parse().unwrap(), d.parse().unwrap()),
        None => (text.parse().unwrap(), 1),
    }
}

fn decimal(text: &str) -> Q {
    let (int, frac) = text.split_once('.').unwrap_or((text, ""));
    let den = 10i128.pow(frac.len() as u32);
    let sign = if int.starts_with('-') { -1 } else { 1 };
    let whole: i128 = int.trim_start_matches('-').parse().unwrap_or(0);
    let part: i128 = if frac.is_empty() { 0 } else { frac.parse().unwrap() };
    (sign * (whole * den + part), den)
}

fn norm((n, d): Q) -> Q {
    fn gcd(a: i128, b: i128) -> i128 {
        if b == 0 {
            a.abs()
        } else {
            gcd(b, a % b)
        }
    }
    let g = gcd(n, d).max(1);
    let s = if d < 0 { -1 } else { 1 };
    (s * n / g, s * d / g)
}

fn eval(e: &NumExpr, at: &[Q]) -> Q {
    let (add, mul) = (|a: Q, b: Q| norm((a.0 * b.1 + b.0 * a.1, a.1 * b.1)), |a: Q, b: Q| norm((a.0 * b.0, a.1 * b.1)));
    match e {
        NumExpr::Const(t) => norm(decimal(t)),
        NumExpr::Var(v) => at[v.0 as usize],
        NumExpr::Neg(a) => {
            let x = eval(a, at);
            (-x.0, x.1)
        }
        NumExpr::Add(a, b) => add(eval(a, at), eval(b, at)),
        NumExpr::Sub(a, b) => {
            let y = eval(b, at);
            add(eval(a, at), (-y.0, y.1))
        }
        NumExpr::Mul(a, b) => mul(eval(a, at), eval(b, at)),
        NumExpr::Div(a, b) => {
            let y = eval(b, at);
            mul(eval(a, at), norm((y.1, y.0)))
        }
        NumExpr::Pow(a, n) => (0..*n).fold((1, 1), |acc, _| mul(acc, eval(a, at))),
    }
}

/// Whether predicate `i` of `spec` holds at the point `at` (one value per numeric input).
fn holds(spec: &Spec, i: usize, at: &[Q]) -> bool {
    let p = &spec.predicates[i];
    let (l, r) = (eval(&p.lhs, at), eval(&p.rhs, at));
    let (a, b) = (l.0 * r.1, r.0 * l.1); // denominators are positive
    match p.relation {
        Relation::Lt => a < b,
        Relation::Le => a <= b,
        Relation::Gt => a > b,
        Relation::Ge => a >= b,
        Relation::Eq => a == b,
        Relation::Ne => a != b,
    }
}

/// A small deterministic generator (the tests must not depend on a crate's stream).
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }
    fn below(&mut self, n: u64) -> u64 {
        self.next() % n
    }
}

/// A random polynomial over x (and y) with small integer coefficients.
fn random_poly(rng: &mut Rng, vars: &[&str]) -> String {
    let terms = 1 + rng.below(3);
    let mut parts = Vec::new();
    for _ in 0..terms {
        let c = 1 + rng.below(3);
        let v = vars[rng.below(vars.len() as u64) as usize];
        parts.push(match rng.below(3) {
            0 => format!("{c} * {v}"),
            1 => format!("{v} * {v}"),
            _ => format!("{c} * {v} * {}", vars[rng.below(vars.len() as u64) as usize]),
        });
    }
    parts.join(" + ")
}

#[test]
fn learned_exclusions_are_unsatisfiable_and_witnesses_hold() {
    let mut rng = Rng(0x5eed_1234_abcd_0001);
    let (mut learned_total, mut witnessed_total, mut cases) = (0, 0, 0);
    for case in 0..60 {
        let vars: &[&str] = if case % 2 == 0 { &["x"] } else { &["x", "y"] };
        let rel = |rng: &mut Rng| ["<", "<=", ">", ">="][rng.below(4) as usize];
        let bound = |rng: &mut Rng| rng.below(12);
        let p0 = format!("{} {} {}", random_poly(&mut rng, vars), rel(&mut rng), bound(&mut rng));
        let p1 = format!("{} {} {}", random_poly(&mut rng, vars), rel(&mut rng), bound(&mut rng));
        let decl: Vec<String> = vars.iter().map(|v| format!("{v}: REAL[0, 2]")).collect();
        let source = format!(
            "ALWAYS (({p0}) -> NEXT a)\nALWAYS (({p1}) -> NEXT b)\nALWAYS !(a && b)\nINPUT {}\nOUTPUT a, b\n",
            decl.join(", ")
        );
        let spec = compile(&source);
        if spec.predicates.len() < 2 {
            continue; // both predicates the same text
        }
        cases += 1;
        let outcome = decide(&spec, &Config::default());
        let refined = ltl::refined(&spec, &outcome.refinement);
        // A dense grid over the box, exact.
        let steps = 40i128;
        let grid: Vec<Vec<Q>> = if vars.len() == 1 {
            (0..=steps).map(|i| vec![norm((2 * i, steps))]).collect()
        } else {
            (0..=steps)
                .flat_map(|i| (0..=steps).map(move |j| vec![norm((2 * i, steps)), norm((2 * j, steps))]))
                .collect()
        };
        for learned in &outcome.refinement.learned {
            learned_total += 1;
            // `G !(l1 && l2 …)` over predicate signals.
            let Ltl::Globally(inner) = &learned.ltl else { panic!("{}", learned.formula) };
            let Ltl::Not(core) = &**inner else { panic!("{}", learned.formula) };
            let literals: Vec<(usize, bool)> = match &**core {
                Ltl::And(xs) => xs.iter().map(|x| literal(&spec, x)).collect(),
                x => vec![literal(&spec, x)],
            };
            for point in &grid {
                let all = literals.iter().all(|&(i, on)| holds(&spec, i, point) == on);
                assert!(!all, "{source}: learned {} but {point:?} satisfies it", learned.formula);
            }
        }
        for w in &outcome.refinement.witnesses {
            witnessed_total += 1;
            let point: Vec<Q> = w.values.iter().map(|(_, v)| rational(v)).collect();
            for part in w.combination.split(" && ") {
                let (on, name) = match part.strip_prefix('!') {
                    Some(n) => (false, n),
                    None => (true, part),
                };
                let i = spec.predicates.iter().position(|p| spec.name(p.signal) == name).unwrap();
                assert_eq!(holds(&spec, i, &point), on, "{source}: witness {w:?}");
            }
        }
        // The verdict follows: realizable exactly when the predicates never hold together.
        let together = grid.iter().any(|p| holds(&spec, 0, p) && holds(&spec, 1, p));
        if !together {
            assert_eq!(outcome.verdict, Verdict::Realizable, "{source}: {:?}", refined.formula_text());
        }
        if outcome.verdict == Verdict::Realizable {
            assert!(!together, "{source}: realizable, but both predicates hold at a grid point");
        }
    }
    assert!(cases >= 40, "only {cases} cases");
    assert!(learned_total >= 10 && witnessed_total >= 10, "learned {learned_total}, witnessed {witnessed_total}");
}

fn literal(spec: &Spec, f: &Ltl) -> (usize, bool) {
    let (on, v) = match f {
        Ltl::Not(v) => (false, &**v),
        v => (true, v),
    };
    let Ltl::Var(s) = v else { panic!("not a literal") };
    (spec.predicates.iter().position(|p| p.signal == *s).expect("a predicate"), on)
}

#[test]
fn a_timer_restarted_in_every_scan_never_expires() {
    let spec = example("restart_forever.ltl");
    let outcome = decide(&spec, &Config::default());
    assert_eq!(outcome.verdict, Verdict::Unrealizable);
    // Under the paper's antecedent G (t.start -> X F t.expire) and the fact that a start
    // resets the timer, a controller wins vacuously: restarting in every scan, it leaves the
    // environment no way to keep the assumption.
    let mut paper = ltl::refined(&spec, &outcome.refinement);
    let t = &spec.timers[0];
    let (s, e) = (Ltl::Var(t.start), Ltl::Var(t.expire));
    paper.assumptions[0] = Clause {
        formula: Ltl::globally(Ltl::implies(s.clone(), Ltl::next(Ltl::finally(e.clone())))),
        span: Default::default(),
    };
    paper
        .assumptions
        .push(Clause { formula: Ltl::globally(Ltl::implies(s, Ltl::next(Ltl::not(e)))), span: Default::default() });
    let vacuous = decide(&paper, &Config { refine: false, ..Config::default() });
    assert_eq!(vacuous.verdict, Verdict::Realizable);
}

#[test]
fn the_shared_figure_one_needs_a_weak_until_with_a_real_timer() {
    let path = root().join("../shared/ltl/g4ltl/paper_fig1_refined.g4ltl");
    let source = std::fs::read_to_string(path).unwrap();
    let outcome = decide(&compile(&source), &Config::default());
    assert_eq!(outcome.verdict, Verdict::Unrealizable);
    // The counter-strategy holds `err` forever: every scan restarts the timer.
    let weak = source.replace("(light UNTIL t1.expire)", "(light W t1.expire)");
    assert_ne!(weak, source);
    assert_eq!(decide(&compile(&weak), &Config::default()).verdict, Verdict::Realizable);
}

#[test]
fn patterns_expand_to_their_encodings() {
    let spec = compile("WHENEVER a THEN b FOR 10s\nINPUT a\nOUTPUT b\n");
    assert_eq!(spec.timers[0].name, "w1");
    assert_eq!(spec.timers[0].preset_ms, 10_000);
    assert_eq!(
        spec.formula_text(),
        "G (w1.start -> X F (w1.expire || w1.start)) -> G (a -> (b && w1.start && X (b W w1.expire)))"
    );
    let spec = compile("WHENEVER a FOR 2s THEN b\nINPUT a\nOUTPUT b\n");
    assert!(spec.guarantees[0]
        .formula
        .to_infix(&|s| spec.name(s).to_string())
        .contains("G ((a && w1.expire && !w1.start) -> b)"));
    let spec = compile("WHENEVER a THEN b UNTIL c FOR 500ms\nINPUT a, c\nOUTPUT b\nTIMER w1(1s)\n");
    assert_eq!(spec.timers[1].name, "w2", "a declared timer's name is not reused");
    let text = spec.guarantees[0].formula.to_infix(&|s| spec.name(s).to_string());
    assert!(text.contains("G (a -> (b W (c && w2.expire && !w2.start)))"), "{text}");
    for (bad, message) in [
        ("WHENEVER a THEN b\nINPUT a\nOUTPUT b", "needs `FOR`"),
        ("WHENEVER a FOR 2s b\nINPUT a\nOUTPUT b", "needs `THEN`"),
        ("WHENEVER a THEN b FOR 0s\nINPUT a\nOUTPUT b", "longer than 0"),
        ("WHENEVER a THEN b FOR 2 parsecs\nINPUT a\nOUTPUT b", "after the duration"),
        ("WHENEVER THEN b FOR 2s\nINPUT a\nOUTPUT b", "expected the condition"),
    ] {
        let diags = ltl::compile(bad, Format::G4ltl, &[]).expect_err(bad);
        assert!(diags.iter().any(|d| d.message.contains(message)), "{bad}: {diags:?}");
    }
}

#[test]
fn numeric_inputs_are_checked_with_located_errors() {
    for (bad, line, column, message) in [
        ("G (x > 3 -> o)\nINPUT x: REAL[4, 0]\nOUTPUT o", 2, 10, "above the upper bound"),
        ("G (x > 3 -> o)\nINPUT x: INT[0, 2.5]\nOUTPUT o", 2, 10, "whole numbers"),
        ("G (x -> o)\nINPUT x: REAL[0, 1]\nOUTPUT o", 1, 4, "is a number"),
        ("G (b > 1 -> o)\nINPUT b\nOUTPUT o", 1, 4, "Boolean signal"),
        ("G (x / x > 1 -> o)\nINPUT x: REAL[1, 2]\nOUTPUT o", 1, 8, "division by a number"),
        ("G (x + 1 -> o)\nINPUT x: REAL[0, 1]\nOUTPUT o", 1, 4, "not a formula"),
        ("G (x > 1)\nINPUT x: REAL[0, 1]\nOUTPUT o: REAL[0, 1]", 3, 11, "only inputs"),
        ("G (x^99 > 1 -> o)\nINPUT x: REAL[0, 1]\nOUTPUT o", 1, 6, "exponents"),
    ] {
        let diags = ltl::compile(bad, Format::G4ltl, &[]).expect_err(bad);
        let d = diags.iter().find(|d| d.message.contains(message)).unwrap_or_else(|| panic!("{bad}: {diags:?}"));
        assert_eq!((d.line, d.column), (line, column), "{bad}: {}", d.message);
    }
}
