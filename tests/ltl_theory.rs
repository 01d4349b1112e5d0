//! The theory checker (`ltl::testing::theory`) under random constraint sets (proptest): 1–3 variables,
//! boxes with small rational bounds (sometimes integer, rarely empty), polynomials of degree
//! ≤ 3 with small coefficients, random relations and polarities. Every `Sat` witness lies in the
//! box and satisfies every literal under an evaluator of this file's own; every `Unsat` survives
//! a dense grid and random rational points; linear sets over the reals are never `Unknown`;
//! `Theory::check` agrees with `decide` and `minimal_unsat` returns an Unsat subset.

use plcsynth::ltl::testing::theory::{decide, Answer, Atom, Domain, NumVar, Poly, Rational, Rel, Theory};
use plcsynth::rng::Rng;
use proptest::prelude::*;
use proptest::strategy::ValueTree;
use proptest::test_runner::TestRunner;

/// A polynomial as this file sees it: (coefficient, exponent of each variable) terms.
type Terms = Vec<(i64, Vec<u32>)>;

#[derive(Clone, Debug)]
struct Problem {
    domains: Vec<Domain>,
    atoms: Vec<(Terms, Rel)>,
    polarities: Vec<bool>,
    seed: u64,
}

const RELS: [Rel; 6] = [Rel::Lt, Rel::Le, Rel::Gt, Rel::Ge, Rel::Eq, Rel::Ne];

fn rat(num: i64, den: i64) -> Rational {
    Rational::new(num.into(), den.into()).unwrap()
}

fn domain(integer: bool, allow_empty: bool) -> impl Strategy<Value = Domain> {
    let width = if allow_empty { -1i64..=8 } else { 0i64..=8 };
    (-6i64..=6, 1i64..=3, width, 1i64..=2, prop::bool::weighted(if integer { 0.25 } else { 0.0 })).prop_map(
        |(lo, lo_den, width, width_den, integer)| {
            let lo = rat(lo, lo_den);
            let hi = lo.checked_add(rat(width, width_den)).unwrap();
            Domain { lo, hi, integer }
        },
    )
}

/// A term of degree ≤ 3 (linear: ≤ 1) over n variables.
fn term(n: usize, linear: bool) -> impl Strategy<Value = (i64, Vec<u32>)> {
    let top = if linear { 1u32 } else { 3 };
    (-3i64..=3, prop::collection::vec(0..=top, n)).prop_map(move |(coef, mut exps)| {
        // Cap the total degree by lowering the later exponents.
        let mut left = top;
        for e in exps.iter_mut() {
            *e = (*e).min(left);
            left -= *e;
        }
        (if coef == 0 { 1 } else { coef }, exps)
    })
}

fn problem(linear: bool, integers: bool) -> impl Strategy<Value = Problem> {
    (1usize..=3, 1usize..=3).prop_flat_map(move |(n, count)| {
        let atom = (prop::collection::vec(term(n, linear), 1..=4), prop::sample::select(RELS.to_vec()));
        (
            prop::collection::vec(domain(integers, !linear), n),
            prop::collection::vec(atom, count),
            prop::collection::vec(any::<bool>(), count),
            any::<u64>(),
        )
            .prop_map(|(domains, atoms, polarities, seed)| Problem { domains, atoms, polarities, seed })
    })
}

fn to_poly(terms: &Terms) -> Poly {
    let mut poly = Poly::zero();
    for (coef, exps) in terms {
        let mut term = Poly::constant(Rational::from_i64(*coef));
        for (v, e) in exps.iter().enumerate() {
            term = term.mul(&Poly::var(NumVar(v as u32)).pow(*e).unwrap()).unwrap();
        }
        poly = poly.add(&term).unwrap();
    }
    poly
}

/// This file's own evaluation of a term list at a point, exactly (None on overflow).
fn value(terms: &Terms, point: &[Rational]) -> Option<Rational> {
    let mut sum = Rational::ZERO;
    for (coef, exps) in terms {
        let mut term = Rational::from_i64(*coef);
        for (x, e) in point.iter().zip(exps) {
            for _ in 0..*e {
                term = term.checked_mul(*x)?;
            }
        }
        sum = sum.checked_add(term)?;
    }
    Some(sum)
}

fn holds(rel: Rel, v: Rational) -> bool {
    let zero = Rational::ZERO;
    match rel {
        Rel::Lt => v < zero,
        Rel::Le => v <= zero,
        Rel::Gt => v > zero,
        Rel::Ge => v >= zero,
        Rel::Eq => v == zero,
        Rel::Ne => v != zero,
    }
}

/// Whether the point satisfies the literals; a witness with numbers too large for this file's
/// term-by-term evaluation (deep in a bisection) is evaluated on the canonical polynomial.
fn satisfies(p: &Problem, literals: &[usize], point: &[Rational]) -> bool {
    literals.iter().all(|&i| {
        let (terms, rel) = &p.atoms[i];
        let v = value(terms, point).or_else(|| to_poly(terms).eval(point)).expect("a value");
        holds(*rel, v) == p.polarities[i]
    })
}

fn in_box(domains: &[Domain], point: &[Rational]) -> bool {
    point.len() == domains.len()
        && point.iter().zip(domains).all(|(v, d)| d.lo <= *v && *v <= d.hi && (!d.integer || v.is_integer()))
}

/// Values to sample per variable: a grid of 17 (every integer of an integer domain) and
/// random rationals with denominators up to 60.
fn samples(domains: &[Domain], seed: u64) -> Vec<Vec<Rational>> {
    let mut rng = Rng::new(seed | 1);
    let mut axes: Vec<Vec<Rational>> = Vec::new();
    for d in domains {
        let mut values = Vec::new();
        if d.integer {
            let (lo, hi) = (d.lo.ceil(), d.hi.floor());
            values.extend((lo..=hi).map(Rational::from_int));
        } else if d.lo <= d.hi {
            let width = d.hi.checked_sub(d.lo).unwrap();
            for k in 0..=16 {
                values.push(d.lo.checked_add(width.checked_mul(rat(k, 16)).unwrap()).unwrap());
            }
        }
        axes.push(values);
    }
    let mut points: Vec<Vec<Rational>> = vec![Vec::new()];
    for axis in &axes {
        points = points.into_iter().flat_map(|p| axis.iter().map(move |v| [p.clone(), vec![*v]].concat())).collect();
    }
    if axes.iter().all(|a| !a.is_empty()) {
        for _ in 0..300 {
            let point = domains
                .iter()
                .zip(&axes)
                .map(|(d, axis)| {
                    if d.integer {
                        axis[rng.below(axis.len() as u64) as usize]
                    } else {
                        let den = 1 + rng.below(60) as i64;
                        let num = rng.below(den as u64 + 1) as i64;
                        let width = d.hi.checked_sub(d.lo).unwrap();
                        d.lo.checked_add(width.checked_mul(rat(num, den)).unwrap()).unwrap()
                    }
                })
                .collect();
            points.push(point);
        }
    }
    points
}

fn literals_of(p: &Problem, which: &[usize]) -> Vec<(Atom, bool)> {
    which.iter().map(|&i| (Atom { poly: to_poly(&p.atoms[i].0), rel: p.atoms[i].1 }, p.polarities[i])).collect()
}

/// Checks one answer on the literals `which` of the problem; returns it.
fn check_answer(p: &Problem, which: &[usize], answer: &Answer) -> Result<(), TestCaseError> {
    match answer {
        Answer::Sat(w) => {
            prop_assert!(in_box(&p.domains, w), "witness {:?} outside the box", w);
            prop_assert!(satisfies(p, which, w), "witness {:?} fails a literal", w);
        }
        Answer::Unsat => {
            for point in samples(&p.domains, p.seed) {
                prop_assert!(!satisfies(p, which, &point), "Unsat, but {:?} satisfies every literal", point);
            }
        }
        Answer::Unknown => {}
    }
    Ok(())
}

const BUDGET: u64 = 20_000;

fn all(p: &Problem) -> Vec<usize> {
    (0..p.atoms.len()).collect()
}

fn run(p: &Problem, which: &[usize], budget: u64) -> Answer {
    let mut budget = budget;
    decide(&literals_of(p, which), &p.domains, &mut budget)
}

proptest! {
    #![proptest_config(crate::common::proptest_config(400))]

    #[test]
    fn decide_is_sound(p in problem(false, true)) {
        let answer = run(&p, &all(&p), BUDGET);
        check_answer(&p, &all(&p), &answer)?;
    }

    #[test]
    fn linear_reals_are_decided(p in problem(true, false)) {
        let answer = run(&p, &all(&p), 200_000);
        prop_assert!(answer != Answer::Unknown, "Unknown on a linear set over the reals");
        check_answer(&p, &all(&p), &answer)?;
    }

    #[test]
    fn linear_integers_are_sound(p in problem(true, true)) {
        let answer = run(&p, &all(&p), BUDGET);
        check_answer(&p, &all(&p), &answer)?;
    }

    #[test]
    fn theory_agrees_with_decide(p in problem(false, true)) {
        let atoms: Vec<Atom> = p.atoms.iter().map(|(t, rel)| Atom { poly: to_poly(t), rel: *rel }).collect();
        let mut theory = Theory::new(atoms, p.domains.clone()).with_budget(BUDGET);
        let combination: Vec<(usize, bool)> = all(&p).into_iter().rev().map(|i| (i, p.polarities[i])).collect();
        let direct = run(&p, &all(&p), BUDGET);
        let first = theory.check(&combination);
        prop_assert_eq!(&first, &direct);
        let again = theory.check(&combination);
        prop_assert_eq!(&again, &direct);
        prop_assert_eq!((theory.queries(), theory.cached(), theory.computed()), (2, 1, 1));
        if first == Answer::Unsat {
            let core = theory.minimal_unsat(&combination);
            prop_assert!(core.iter().all(|l| combination.contains(l)), "core {:?} not in the query", core);
            prop_assert_eq!(theory.check(&core), Answer::Unsat);
            let which: Vec<usize> = core.iter().map(|&(i, _)| i).collect();
            let fresh = run(&p, &which, BUDGET * 4);
            prop_assert!(!matches!(fresh, Answer::Sat(_)), "the core {:?} is satisfiable: {:?}", core, fresh);
            check_answer(&p, &which, &Answer::Unsat)?;
        }
        prop_assert_eq!(theory.queries(), theory.cached() + theory.computed());
    }
}

/// The checks above can fail: the sampler finds points of satisfiable sets (so an `Unsat`
/// claimed for them would be caught), and the generated sets give every kind of answer.
#[test]
fn the_checks_have_teeth() {
    let mut runner = TestRunner::deterministic();
    let strategy = problem(false, true);
    let (mut sat, mut unsat, mut unknown, mut sampled) = (0, 0, 0, 0);
    for _ in 0..300 {
        let p = strategy.new_tree(&mut runner).unwrap().current();
        match run(&p, &all(&p), BUDGET) {
            Answer::Sat(_) => {
                sat += 1;
                if samples(&p.domains, p.seed).iter().any(|point| satisfies(&p, &all(&p), point)) {
                    sampled += 1;
                }
            }
            Answer::Unsat => unsat += 1,
            Answer::Unknown => unknown += 1,
        }
    }
    eprintln!("sat {sat}, unsat {unsat}, unknown {unknown}, sampled {sampled}");
    assert!(sat >= 60 && unsat >= 30, "sat {sat}, unsat {unsat}, unknown {unknown}");
    assert!(unknown * 10 <= sat + unsat, "too many Unknown: {unknown} of 300");
    // Most satisfiable sets have a sampled point too: a false Unsat there would be seen.
    assert!(sampled * 2 >= sat, "sampling found {sampled} of {sat} satisfiable sets");

    // A satisfiable set, claimed Unsat, fails the check.
    let p = Problem {
        domains: vec![Domain::real(rat(0, 1), rat(4, 1)), Domain::real(rat(0, 1), rat(4, 1))],
        atoms: vec![(vec![(1, vec![1, 0]), (1, vec![0, 1]), (-3, vec![0, 0])], Rel::Gt)],
        polarities: vec![true],
        seed: 7,
    };
    assert!(check_answer(&p, &[0], &Answer::Unsat).is_err());
    assert!(check_answer(&p, &[0], &Answer::Sat(vec![rat(1, 1), rat(1, 1)])).is_err());
    assert!(check_answer(&p, &[0], &Answer::Sat(vec![rat(2, 1), rat(2, 1)])).is_ok());
    assert!(check_answer(&p, &[0], &Answer::Sat(vec![rat(5, 1), rat(0, 1)])).is_err());
}
