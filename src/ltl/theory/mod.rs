//! The theory checker of the abstraction-refinement loop (Cheng et al. 2014, section 3):
//! arithmetic predicates on bounded numeric inputs are abstracted into Boolean inputs, and a
//! combination of predicate values used by a candidate counter-strategy is checked here for
//! satisfiability over the inputs' box. G4LTL-ST discharges these conditions with JBernstein;
//! this is a decision procedure of our own, exact where it answers.
//!
//! [`decide`] takes a conjunction of polynomial literals over a box of closed intervals:
//!
//! - *all atoms linear*: Fourier–Motzkin elimination over exact rationals with strict and
//!   non-strict bookkeeping (equalities are substituted first, the box bounds are constraints
//!   too), the witness built by back-substitution. `≠` is split lazily into `<` / `>` when a
//!   witness violates it, integer variables by branch and bound on a fractional witness value.
//!   Complete up to the budget and `i128` overflow.
//! - *otherwise*: interval branch and bound. Each polynomial is enclosed monomial by monomial
//!   with exact rational interval endpoints (so rounding cannot lie); a box where some literal
//!   is certainly false is discarded, one where all are certainly true yields a witness; else a
//!   candidate point (the box's simplest rational point, with equalities solved for a variable
//!   they are linear in) is tried, a box whose undecided literals are all linear goes to the
//!   linear procedure, and the rest is bisected on its widest variable, breadth first. The
//!   enclosure is tightened where the polynomial is monotone in a variable over the box
//!   (derivative enclosure of one sign: that variable held at the extremal endpoint). Equalities the
//!   candidates miss end in `Unknown` when the budget runs out, never in a guess.
//!
//! Every `Sat` witness is re-checked by exact evaluation of every literal and of the box before
//! it is returned; overflow or a failed check gives `Unknown`, never a wrong answer.
//! [`Theory`] memoises queries on fixed atoms and shrinks unsatisfiable combinations to the
//! small cores that become learned assumptions (`G !(p0 && p1)`).
//!
//! The parts: `rational` (exact rationals), `poly` (polynomials, relations, atoms), `linear`
//! (Fourier–Motzkin), `interval` (interval arithmetic, branch and bound), `memo` ([`Theory`]).
//! This file holds the domains, the answers and [`decide`].

mod interval;
mod linear;
mod memo;
mod poly;
mod rational;

pub use memo::{Theory, TheoryStats, DEFAULT_BUDGET};
pub use poly::{Atom, NumVar, Poly, PolyDisplay, Rel};
pub use rational::Rational;

use interval::{branch_and_bound, Interval};
use linear::linear;
use std::collections::{BTreeMap, BTreeSet, HashMap};

/// A variable's closed range [lo, hi]; `integer`: only the integers in it.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug)]
pub struct Domain {
    pub lo: Rational,
    pub hi: Rational,
    pub integer: bool,
}

impl Domain {
    pub fn real(lo: Rational, hi: Rational) -> Domain {
        Domain { lo, hi, integer: false }
    }

    pub fn integer(lo: i64, hi: i64) -> Domain {
        Domain { lo: Rational::from_i64(lo), hi: Rational::from_i64(hi), integer: true }
    }

    /// Whether the value lies in the domain.
    pub fn contains(&self, value: Rational) -> bool {
        self.lo <= value && value <= self.hi && (!self.integer || value.is_integer())
    }
}

/// The verdict on a conjunction of literals.
#[derive(Clone, PartialEq, Eq, Hash, Debug)]
pub enum Answer {
    /// A witness: one value per variable, inside its domain, satisfying every literal exactly
    /// (checked by exact rational evaluation before it is returned).
    Sat(Vec<Rational>),
    /// No point of the box satisfies the literals.
    Unsat,
    /// The budget ran out, an `i128` overflowed, or an equality was not met by any candidate.
    Unknown,
}

/// Why a computation stopped early: the branch is empty, or we cannot tell.
enum Stop {
    Unsat,
    Unknown,
}

trait OrUnknown<T> {
    fn or_unknown(self) -> Result<T, Stop>;
}

impl<T> OrUnknown<T> for Option<T> {
    fn or_unknown(self) -> Result<T, Stop> {
        self.ok_or(Stop::Unknown)
    }
}

/// Takes one unit of work; Unknown when none is left.
fn spend(budget: &mut u64, units: u64) -> Result<(), Stop> {
    if *budget < units.max(1) {
        *budget = 0;
        return Err(Stop::Unknown);
    }
    *budget -= units.max(1);
    Ok(())
}

/// Decides whether the conjunction of literals (atom, polarity: true = the atom holds, false =
/// its negation holds) has a solution in the box.
pub fn decide(literals: &[(Atom, bool)], domains: &[Domain], budget: &mut u64) -> Answer {
    // The box, integer domains shrunk to their integer hull.
    let mut bounds = Vec::with_capacity(domains.len());
    for d in domains {
        let (lo, hi) =
            if d.integer { (Rational::from_int(d.lo.ceil()), Rational::from_int(d.hi.floor())) } else { (d.lo, d.hi) };
        if lo > hi {
            return Answer::Unsat;
        }
        bounds.push((lo, hi));
    }
    // The variables in use, renumbered 0..m in order.
    let used: BTreeSet<NumVar> = literals.iter().flat_map(|(a, _)| a.poly.vars()).collect();
    if used.iter().any(|v| v.0 as usize >= domains.len()) {
        return Answer::Unknown;
    }
    let used: Vec<NumVar> = used.into_iter().collect();
    let map: HashMap<NumVar, NumVar> = used.iter().enumerate().map(|(i, &v)| (v, NumVar(i as u32))).collect();
    let local_box: Vec<Interval> =
        used.iter().map(|v| Interval { lo: bounds[v.0 as usize].0, hi: bounds[v.0 as usize].1 }).collect();
    let integer: Vec<bool> = used.iter().map(|v| domains[v.0 as usize].integer).collect();

    let outcome = constraints(literals, &map).and_then(|cons| {
        if cons.is_empty() {
            Ok(Vec::new())
        } else if cons.iter().all(|(p, _)| p.is_linear()) {
            linear(&cons, &local_box, &integer, budget)
        } else {
            branch_and_bound(&cons, local_box, &integer, budget)
        }
    });
    let local = match outcome {
        Ok(point) => point,
        Err(Stop::Unsat) => return Answer::Unsat,
        Err(Stop::Unknown) => return Answer::Unknown,
    };

    // The whole witness: unused variables at a simple point of their domain.
    let mut witness = Vec::with_capacity(domains.len());
    for (i, (lo, hi)) in bounds.iter().enumerate() {
        let value = match map.get(&NumVar(i as u32)) {
            Some(local_var) => local[local_var.0 as usize],
            None if domains[i].integer => *lo,
            None => match lo.checked_add(*hi).and_then(|s| s.checked_div(Rational::from_int(2))) {
                Some(mid) => mid,
                None => *lo,
            },
        };
        witness.push(value);
    }
    let inside = witness.iter().zip(domains).all(|(v, d)| d.contains(*v));
    let holds = literals.iter().all(|(atom, polarity)| atom.holds(&witness) == Some(*polarity));
    if inside && holds {
        Answer::Sat(witness)
    } else {
        Answer::Unknown
    }
}

/// The literals as `poly REL 0` over the local variables, each polynomial scaled to a leading
/// coefficient of ±1 and signed so that `p`/`-p` meet; literals on one polynomial are merged
/// into the set of signs they allow (an empty set is Unsat, a full one is dropped).
fn constraints(literals: &[(Atom, bool)], map: &HashMap<NumVar, NumVar>) -> Result<Vec<(Poly, Rel)>, Stop> {
    // Allowed signs of the polynomial's value: bit 0 negative, bit 1 zero, bit 2 positive.
    let mut signs: BTreeMap<Poly, u8> = BTreeMap::new();
    for (atom, polarity) in literals {
        let rel = if *polarity { atom.rel } else { atom.rel.negate() };
        let poly = atom.poly.rename(map).or_unknown()?;
        let (poly, rel) = match poly.terms.values().next_back().copied() {
            Some(lead) => {
                let scaled = poly.scale(Rational::ONE.checked_div(lead.abs().or_unknown()?).or_unknown()?);
                let scaled = scaled.or_unknown()?;
                if lead.signum() < 0 {
                    (scaled.neg().or_unknown()?, rel.mirror())
                } else {
                    (scaled, rel)
                }
            }
            None => (poly, rel),
        };
        let allowed = [Rel::Lt, Rel::Eq, Rel::Gt]
            .iter()
            .enumerate()
            .filter(|(_, sample)| {
                let value = match sample {
                    Rel::Lt => Rational::from_int(-1),
                    Rel::Eq => Rational::ZERO,
                    _ => Rational::ONE,
                };
                rel.holds(value)
            })
            .fold(0u8, |acc, (bit, _)| acc | (1 << bit));
        *signs.entry(poly).or_insert(0b111) &= allowed;
    }
    let mut out = Vec::new();
    for (poly, allowed) in signs {
        let rel = match allowed {
            0b000 => return Err(Stop::Unsat),
            0b001 => Rel::Lt,
            0b010 => Rel::Eq,
            0b100 => Rel::Gt,
            0b011 => Rel::Le,
            0b110 => Rel::Ge,
            0b101 => Rel::Ne,
            _ => continue,
        };
        if let Some(value) = poly.as_constant() {
            if rel.holds(value) {
                continue;
            }
            return Err(Stop::Unsat);
        }
        out.push((poly, rel));
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    pub(super) fn r(text: &str) -> Rational {
        Rational::parse_decimal(text).unwrap()
    }

    pub(super) fn x(i: u32) -> Poly {
        Poly::var(NumVar(i))
    }

    pub(super) fn k(text: &str) -> Poly {
        Poly::constant(r(text))
    }

    pub(super) fn atom(lhs: Poly, rel: Rel, rhs: Poly) -> Atom {
        Atom::new(lhs, rel, rhs).unwrap()
    }

    pub(super) fn real(lo: &str, hi: &str) -> Domain {
        Domain::real(r(lo), r(hi))
    }

    fn run(literals: &[(Atom, bool)], domains: &[Domain]) -> Answer {
        let mut budget = DEFAULT_BUDGET;
        let answer = decide(literals, domains, &mut budget);
        if let Answer::Sat(w) = &answer {
            assert_eq!(w.len(), domains.len());
            assert!(w.iter().zip(domains).all(|(v, d)| d.contains(*v)), "{w:?}");
            assert!(literals.iter().all(|(a, p)| a.holds(w) == Some(*p)), "{w:?}");
        }
        answer
    }

    pub(super) fn is_sat(answer: &Answer) -> bool {
        matches!(answer, Answer::Sat(_))
    }

    /// The paper's figure 1: `x + y > 3` and `x*x + y*y < 3.5` over [0, 4]².
    #[test]
    fn figure_one() {
        let line = atom(x(0).add(&x(1)).unwrap(), Rel::Gt, k("3"));
        let disc = atom(x(0).pow(2).unwrap().add(&x(1).pow(2).unwrap()).unwrap(), Rel::Lt, k("3.5"));
        let box2 = [real("0", "4"), real("0", "4")];
        assert_eq!(run(&[(line.clone(), true), (disc.clone(), true)], &box2), Answer::Unsat);
        assert!(is_sat(&run(&[(line.clone(), true)], &box2)));
        assert!(is_sat(&run(&[(disc.clone(), true)], &box2)));
        assert!(is_sat(&run(&[(line.clone(), true), (disc.clone(), false)], &box2)));
        assert!(is_sat(&run(&[(line.clone(), false), (disc.clone(), true)], &box2)));
        assert!(is_sat(&run(&[(line.clone(), false), (disc.clone(), false)], &box2)));

        let mut theory = Theory::new(vec![line, disc], box2.to_vec());
        assert_eq!(theory.check(&[(1, true), (0, true)]), Answer::Unsat);
        assert_eq!(theory.check(&[(0, true), (1, true)]), Answer::Unsat);
        assert_eq!((theory.queries(), theory.cached(), theory.computed()), (2, 1, 1));
        assert_eq!(theory.minimal_unsat(&[(0, true), (1, true)]), vec![(0, true), (1, true)]);
        assert!(is_sat(&theory.check(&[(0, true)])));
        assert_eq!(theory.stats().queries, theory.queries());
    }

    #[test]
    fn linear_single_point() {
        // x + y >= 2, x - y >= 0, x <= 1, y >= 1 → x = y = 1.
        let lits = [
            (atom(x(0).add(&x(1)).unwrap(), Rel::Ge, k("2")), true),
            (atom(x(0).sub(&x(1)).unwrap(), Rel::Ge, k("0")), true),
            (atom(x(0), Rel::Le, k("1")), true),
            (atom(x(1), Rel::Ge, k("1")), true),
        ];
        let domains = [real("-5", "5"), real("-5", "5")];
        assert_eq!(run(&lits, &domains), Answer::Sat(vec![r("1"), r("1")]));
        // The same through an equality and a box that pins the point.
        let lits = [(atom(x(0).add(&x(1)).unwrap(), Rel::Eq, k("2")), true), (atom(x(0), Rel::Ge, x(1)), true)];
        assert_eq!(run(&lits, &[real("0", "1"), real("1", "3")]), Answer::Sat(vec![r("1"), r("1")]));
    }

    #[test]
    fn strict_linear() {
        let domains = [real("0", "4"), real("0", "4")];
        let gt = atom(x(0), Rel::Gt, x(1));
        let lt = atom(x(0), Rel::Lt, x(1));
        assert_eq!(run(&[(gt.clone(), true), (lt.clone(), true)], &domains), Answer::Unsat);
        assert_eq!(
            run(&[(atom(x(0), Rel::Lt, k("1")), true), (atom(x(0), Rel::Gt, k("1")), true)], &domains),
            Answer::Unsat
        );
        // x < 1 and x >= 1 - 0: Unsat; x <= 1 and x >= 1: the point 1.
        assert_eq!(
            run(&[(atom(x(0), Rel::Lt, k("1")), true), (atom(x(0), Rel::Lt, k("1")), false)], &domains),
            Answer::Unsat
        );
        let point = run(&[(atom(x(0), Rel::Le, k("1")), true), (atom(x(0), Rel::Ge, k("1")), true)], &domains);
        assert!(matches!(point, Answer::Sat(w) if w[0] == r("1")));
        // A strict chain through the box: 0 <= x < y < z <= 4/1000.
        let domains3 = [real("0", "0.004"), real("0", "0.004"), real("0", "0.004")];
        let chain = [(lt.clone(), true), (atom(x(1), Rel::Lt, x(2)), true)];
        assert!(is_sat(&run(&chain, &domains3)));
        // x > y with y at the top of x's range: Unsat only because the box is closed.
        assert_eq!(run(&[(gt, true)], &[real("0", "1"), real("1", "2")]), Answer::Unsat);
        assert!(is_sat(&run(&[(lt, true)], &[real("0", "1"), real("1", "2")])));
    }

    #[test]
    fn not_equal() {
        let domains = [real("0", "4"), real("0", "4")];
        // x != y inside x + y = 0 over [0, 4]²: only (0, 0) is on the line, so Unsat.
        let sum_zero = atom(x(0).add(&x(1)).unwrap(), Rel::Eq, k("0"));
        let ne = atom(x(0), Rel::Ne, x(1));
        assert_eq!(run(&[(sum_zero.clone(), true), (ne.clone(), true)], &domains), Answer::Unsat);
        // On x + y = 2 it is Sat (the first witness x = y = 1 is split away).
        let sum_two = atom(x(0).add(&x(1)).unwrap(), Rel::Eq, k("2"));
        assert!(is_sat(&run(&[(sum_two.clone(), true), (ne.clone(), true)], &domains)));
        // Negated equality as Ne, and a nonlinear one.
        assert!(is_sat(&run(&[(sum_two, false), (ne.clone(), false)], &domains)));
        let square = atom(x(0).pow(2).unwrap(), Rel::Ne, k("0"));
        assert_eq!(run(&[(square.clone(), true)], &[real("0", "0"), real("0", "1")]), Answer::Unsat);
        assert!(is_sat(&run(&[(square, true)], &domains)));
    }

    #[test]
    fn integer_domains() {
        let domains = [Domain::integer(0, 10), Domain::integer(0, 10)];
        // 2x = 2y + 1 has no integer solution; over the reals it has many.
        let odd = atom(x(0).scale(r("2")).unwrap(), Rel::Eq, x(1).scale(r("2")).unwrap().add(&k("1")).unwrap());
        assert_eq!(run(&[(odd.clone(), true)], &domains), Answer::Unsat);
        assert!(is_sat(&run(&[(odd, true)], &[real("0", "10"), real("0", "10")])));
        // 3x + 5y = 7 → (4, -1) no; over [0, 10]: none either (7 - 5y ∈ {7, 2} not divisible by 3 → y=1 gives 2…)
        let three_five = atom(x(0).scale(r("3")).unwrap().add(&x(1).scale(r("5")).unwrap()).unwrap(), Rel::Eq, k("7"));
        assert_eq!(run(&[(three_five, true)], &domains), Answer::Unsat);
        let three_five = atom(x(0).scale(r("3")).unwrap().add(&x(1).scale(r("5")).unwrap()).unwrap(), Rel::Eq, k("11"));
        assert_eq!(run(&[(three_five, true)], &domains), Answer::Sat(vec![r("2"), r("1")]));
        // Nonlinear integers: x*y = 7 needs (1, 7) or (7, 1); x*x = 2 has none.
        let product = atom(x(0).mul(&x(1)).unwrap(), Rel::Eq, k("7"));
        assert!(is_sat(&run(&[(product, true)], &domains)));
        let root_two = atom(x(0).pow(2).unwrap(), Rel::Eq, k("2"));
        assert_eq!(run(&[(root_two, true)], &domains), Answer::Unsat);
        // No integer in the domain at all.
        assert_eq!(
            run(&[], &[Domain::real(r("0.2"), r("0.8")), Domain { integer: true, ..real("0.2", "0.8") }]),
            Answer::Unsat
        );
        assert_eq!(run(&[], &[Domain::integer(3, 5)]), Answer::Sat(vec![r("3")]));
    }

    #[test]
    fn edge_cases() {
        assert_eq!(run(&[], &[]), Answer::Sat(vec![]));
        assert_eq!(run(&[], &[real("0", "4")]), Answer::Sat(vec![r("2")]));
        assert_eq!(run(&[(atom(x(0), Rel::Gt, k("0")), true)], &[real("1", "0")]), Answer::Unsat);
        // A variable without a domain: Unknown, not a panic.
        assert_eq!(run(&[(atom(x(3), Rel::Gt, k("0")), true)], &[real("0", "1")]), Answer::Unknown);
        // Budget 0: Unknown once work is needed.
        let mut budget = 0;
        let lits = [(atom(x(0), Rel::Gt, k("0")), true)];
        assert_eq!(decide(&lits, &[real("0", "1")], &mut budget), Answer::Unknown);
        // A nonlinear equality with only irrational roots: x² = 2 is never met exactly.
        let mut budget = 2_000;
        let root_two = [(atom(x(0).pow(2).unwrap(), Rel::Eq, k("2")), true)];
        assert_eq!(decide(&root_two, &[real("0", "4")], &mut budget), Answer::Unknown);
        // Constants: decided without a box.
        assert_eq!(run(&[(atom(k("1"), Rel::Lt, k("2")), true)], &[]), Answer::Sat(vec![]));
        assert_eq!(run(&[(atom(k("1"), Rel::Lt, k("2")), false)], &[]), Answer::Unsat);
        // A polynomial and its contradiction, nonlinear: caught without bisection.
        let disc = atom(x(0).pow(2).unwrap().add(&x(1).pow(3).unwrap()).unwrap(), Rel::Le, k("1"));
        let mut budget = 1;
        let lits = [(disc.clone(), true), (disc.clone(), false)];
        assert_eq!(decide(&lits, &[real("-2", "2"), real("-2", "2")], &mut budget), Answer::Unsat);
        // Huge bounds: overflow becomes Unknown or an exact answer, never a panic.
        let huge = Domain::real(Rational::from_int(-i128::MAX), Rational::from_int(i128::MAX));
        let cube = [(atom(x(0).pow(3).unwrap().add(&x(1)).unwrap(), Rel::Eq, k("0.5")), true)];
        let mut budget = 1_000;
        let answer = decide(&cube, &[huge, huge], &mut budget);
        assert!(answer != Answer::Unsat, "{answer:?}");
    }
}
