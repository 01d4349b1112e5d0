//! Polynomials over the numeric variables (exact rational coefficients, graded lexicographic
//! terms), relations and atoms: the polynomial literals the theory decides.

use super::interval::Interval;
use super::rational::Rational;
use serde::Serialize;
use std::cmp::Ordering;
use std::collections::{BTreeMap, HashMap};
use std::fmt;

/// Index of a numeric variable (the caller's numbering, 0..n).
#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Debug, Serialize)]
pub struct NumVar(pub u32);

/// A product of variable powers, sorted by variable, exponents positive; empty is the constant.
type Monomial = Vec<(NumVar, u32)>;

/// Products with more terms than this are refused (None), a guard against `pow` blow-up.
const MAX_TERMS: usize = 4096;

/// A polynomial with rational coefficients over NumVars (sparse: monomial -> coefficient,
/// canonical so equal polynomials compare equal).
#[derive(Clone, PartialEq, Eq, PartialOrd, Ord, Hash, Debug, Default)]
pub struct Poly {
    pub(super) terms: BTreeMap<Monomial, Rational>,
}

impl Poly {
    pub fn zero() -> Poly {
        Poly::default()
    }

    pub fn constant(r: Rational) -> Poly {
        let mut terms = BTreeMap::new();
        if r != Rational::ZERO {
            terms.insert(Vec::new(), r);
        }
        Poly { terms }
    }

    pub fn var(v: NumVar) -> Poly {
        let mut terms = BTreeMap::new();
        terms.insert(vec![(v, 1)], Rational::ONE);
        Poly { terms }
    }

    /// The terms as (monomial: sorted (variable, exponent) pairs, coefficient), none zero.
    pub fn terms(&self) -> impl Iterator<Item = (&[(NumVar, u32)], Rational)> + '_ {
        self.terms.iter().map(|(m, c)| (m.as_slice(), *c))
    }

    pub fn is_zero(&self) -> bool {
        self.terms.is_empty()
    }

    /// The value of a constant polynomial.
    pub fn as_constant(&self) -> Option<Rational> {
        match self.terms.len() {
            0 => Some(Rational::ZERO),
            1 => self.terms.get(&Vec::new()).copied(),
            _ => None,
        }
    }

    pub fn add(&self, other: &Poly) -> Option<Poly> {
        let mut terms = self.terms.clone();
        for (m, c) in &other.terms {
            add_term(&mut terms, m.clone(), *c)?;
        }
        Some(Poly { terms })
    }

    pub fn neg(&self) -> Option<Poly> {
        let mut terms = BTreeMap::new();
        for (m, c) in &self.terms {
            terms.insert(m.clone(), c.checked_neg()?);
        }
        Some(Poly { terms })
    }

    pub fn sub(&self, other: &Poly) -> Option<Poly> {
        self.add(&other.neg()?)
    }

    pub fn scale(&self, factor: Rational) -> Option<Poly> {
        let mut terms = BTreeMap::new();
        if factor != Rational::ZERO {
            for (m, c) in &self.terms {
                terms.insert(m.clone(), c.checked_mul(factor)?);
            }
        }
        Some(Poly { terms })
    }

    /// None on overflow or when the product would have more than a few thousand terms.
    pub fn mul(&self, other: &Poly) -> Option<Poly> {
        if self.terms.len().saturating_mul(other.terms.len()) > MAX_TERMS * 4 {
            return None;
        }
        let mut terms = BTreeMap::new();
        for (m1, c1) in &self.terms {
            for (m2, c2) in &other.terms {
                add_term(&mut terms, mul_monomial(m1, m2)?, c1.checked_mul(*c2)?)?;
            }
        }
        if terms.len() > MAX_TERMS {
            return None;
        }
        Some(Poly { terms })
    }

    pub fn pow(&self, exponent: u32) -> Option<Poly> {
        let mut result = Poly::constant(Rational::ONE);
        let mut base = self.clone();
        let mut e = exponent;
        while e > 0 {
            if e & 1 == 1 {
                result = result.mul(&base)?;
            }
            e >>= 1;
            if e > 0 {
                base = base.mul(&base)?;
            }
        }
        Some(result)
    }

    /// Total degree (0 for constants and the zero polynomial).
    pub fn degree(&self) -> u32 {
        self.terms.keys().map(|m| m.iter().map(|&(_, e)| e).fold(0u32, u32::saturating_add)).max().unwrap_or(0)
    }

    pub fn is_linear(&self) -> bool {
        self.degree() <= 1
    }

    pub(super) fn degree_in(&self, v: NumVar) -> u32 {
        self.terms.keys().flat_map(|m| m.iter().filter(|&&(w, _)| w == v).map(|&(_, e)| e)).max().unwrap_or(0)
    }

    /// The variables that occur, sorted.
    pub fn vars(&self) -> Vec<NumVar> {
        let mut vars: Vec<NumVar> = self.terms.keys().flat_map(|m| m.iter().map(|&(v, _)| v)).collect();
        crate::sort::sort(&mut vars);
        vars.dedup();
        vars
    }

    /// Floating-point value (NaN when a variable has no value): for display and heuristics only.
    pub fn eval_f64(&self, values: &[f64]) -> f64 {
        self.terms
            .iter()
            .map(|(m, c)| {
                m.iter().fold(c.to_f64(), |acc, &(v, e)| {
                    acc * values.get(v.0 as usize).copied().unwrap_or(f64::NAN).powi(e.min(i32::MAX as u32) as i32)
                })
            })
            .sum()
    }

    /// Exact value; None on overflow or when a variable has no value.
    pub fn eval(&self, values: &[Rational]) -> Option<Rational> {
        let mut sum = Rational::ZERO;
        for (m, c) in &self.terms {
            let mut term = *c;
            for &(v, e) in m {
                term = term.checked_mul(values.get(v.0 as usize)?.checked_pow(e)?)?;
            }
            sum = sum.checked_add(term)?;
        }
        Some(sum)
    }

    /// An enclosure of the polynomial's range over the box (indexed by variable).
    pub(super) fn range(&self, bx: &[Interval]) -> Option<Interval> {
        let mut sum = Interval::point(Rational::ZERO);
        for (m, c) in &self.terms {
            let mut term = Interval::point(*c);
            for &(v, e) in m {
                term = term.mul(bx.get(v.0 as usize)?.pow(e)?)?;
            }
            sum = sum.add(term)?;
        }
        Some(sum)
    }

    /// The partial derivative in `v`.
    pub fn derivative(&self, v: NumVar) -> Option<Poly> {
        let mut terms = BTreeMap::new();
        for (m, c) in &self.terms {
            let Some(at) = m.iter().position(|&(w, _)| w == v) else { continue };
            let e = m[at].1;
            let mut reduced = m.clone();
            if e == 1 {
                reduced.remove(at);
            } else {
                reduced[at].1 = e - 1;
            }
            add_term(&mut terms, reduced, c.checked_mul(Rational::from_int(i128::from(e)))?)?;
        }
        Some(Poly { terms })
    }

    pub(super) fn rename(&self, map: &HashMap<NumVar, NumVar>) -> Option<Poly> {
        let mut terms = BTreeMap::new();
        for (m, c) in &self.terms {
            let mut renamed: Monomial = m.iter().map(|&(v, e)| Some((*map.get(&v)?, e))).collect::<Option<_>>()?;
            crate::sort::sort(&mut renamed);
            terms.insert(renamed, *c);
        }
        Some(Poly { terms })
    }

    /// Printed with the given variable names, highest degree first (`3*x*y^2 - 1/2*x + 7`).
    pub fn display<F: Fn(NumVar) -> String>(&self, name: F) -> PolyDisplay<'_, F> {
        PolyDisplay { poly: self, name }
    }
}

fn add_term(terms: &mut BTreeMap<Monomial, Rational>, m: Monomial, c: Rational) -> Option<()> {
    let sum = match terms.get(&m) {
        Some(old) => old.checked_add(c)?,
        None => c,
    };
    if sum == Rational::ZERO {
        terms.remove(&m);
    } else {
        terms.insert(m, sum);
    }
    Some(())
}

fn mul_monomial(a: &Monomial, b: &Monomial) -> Option<Monomial> {
    let mut exponents: BTreeMap<NumVar, u32> = BTreeMap::new();
    exponents.extend(a.iter().copied());
    for &(v, e) in b {
        let slot = exponents.entry(v).or_insert(0);
        *slot = slot.checked_add(e)?;
    }
    Some(exponents.into_iter().collect())
}

/// Higher total degree first, then the higher power of the first variable where they differ.
fn graded_lex(a: &Monomial, b: &Monomial) -> Ordering {
    let degree = |m: &Monomial| m.iter().map(|&(_, e)| u64::from(e)).sum::<u64>();
    degree(b).cmp(&degree(a)).then_with(|| {
        let (mut i, mut j) = (a.iter().peekable(), b.iter().peekable());
        loop {
            match (i.peek(), j.peek()) {
                (None, None) => return Ordering::Equal,
                (Some(_), None) => return Ordering::Less,
                (None, Some(_)) => return Ordering::Greater,
                (Some(&&(va, ea)), Some(&&(vb, eb))) => match va.cmp(&vb) {
                    Ordering::Less => return Ordering::Less,
                    Ordering::Greater => return Ordering::Greater,
                    Ordering::Equal if ea != eb => return eb.cmp(&ea),
                    Ordering::Equal => {
                        i.next();
                        j.next();
                    }
                },
            }
        }
    })
}

/// [`Poly::display`]'s printer.
pub struct PolyDisplay<'a, F> {
    poly: &'a Poly,
    name: F,
}

impl<F: Fn(NumVar) -> String> fmt::Display for PolyDisplay<'_, F> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let mut terms: Vec<(&Monomial, &Rational)> = self.poly.terms.iter().collect();
        if terms.is_empty() {
            return write!(f, "0");
        }
        crate::sort::sort_by(&mut terms, |(a, _), (b, _)| graded_lex(a, b));
        for (i, (m, c)) in terms.into_iter().enumerate() {
            let negative = c.signum() < 0;
            let magnitude = if negative { c.checked_neg().unwrap_or(*c) } else { *c };
            match (i, negative) {
                (0, true) => write!(f, "-")?,
                (0, false) => {}
                (_, true) => write!(f, " - ")?,
                (_, false) => write!(f, " + ")?,
            }
            let mut first = true;
            if magnitude != Rational::ONE || m.is_empty() {
                write!(f, "{magnitude}")?;
                first = false;
            }
            for &(v, e) in m {
                if !first {
                    write!(f, "*")?;
                }
                first = false;
                write!(f, "{}", (self.name)(v))?;
                if e > 1 {
                    write!(f, "^{e}")?;
                }
            }
        }
        Ok(())
    }
}

impl fmt::Display for Poly {
    /// Variables printed as `x0`, `x1`, …
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.display(|v| format!("x{}", v.0)))
    }
}

/// How a polynomial compares with 0.
#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Debug, Serialize)]
pub enum Rel {
    Lt,
    Le,
    Gt,
    Ge,
    Eq,
    Ne,
}

impl Rel {
    /// The relation of the negated atom.
    pub fn negate(self) -> Rel {
        match self {
            Rel::Lt => Rel::Ge,
            Rel::Le => Rel::Gt,
            Rel::Gt => Rel::Le,
            Rel::Ge => Rel::Lt,
            Rel::Eq => Rel::Ne,
            Rel::Ne => Rel::Eq,
        }
    }

    /// The relation after both sides are multiplied by -1.
    pub fn mirror(self) -> Rel {
        match self {
            Rel::Lt => Rel::Gt,
            Rel::Le => Rel::Ge,
            Rel::Gt => Rel::Lt,
            Rel::Ge => Rel::Le,
            other => other,
        }
    }

    /// Whether `value REL 0`.
    pub fn holds(self, value: Rational) -> bool {
        let order = value.cmp(&Rational::ZERO);
        match self {
            Rel::Lt => order == Ordering::Less,
            Rel::Le => order != Ordering::Greater,
            Rel::Gt => order == Ordering::Greater,
            Rel::Ge => order != Ordering::Less,
            Rel::Eq => order == Ordering::Equal,
            Rel::Ne => order != Ordering::Equal,
        }
    }

    pub fn symbol(self) -> &'static str {
        match self {
            Rel::Lt => "<",
            Rel::Le => "<=",
            Rel::Gt => ">",
            Rel::Ge => ">=",
            Rel::Eq => "=",
            Rel::Ne => "!=",
        }
    }
}

/// `poly REL 0`
#[derive(Clone, PartialEq, Eq, PartialOrd, Ord, Hash, Debug)]
pub struct Atom {
    pub poly: Poly,
    pub rel: Rel,
}

impl Atom {
    /// `lhs REL rhs` as `lhs - rhs REL 0`; None on overflow.
    pub fn new(lhs: Poly, rel: Rel, rhs: Poly) -> Option<Atom> {
        Some(Atom { poly: lhs.sub(&rhs)?, rel })
    }

    /// Whether the atom holds at the point (exactly); None on overflow or a missing value.
    pub fn holds(&self, values: &[Rational]) -> Option<bool> {
        Some(self.rel.holds(self.poly.eval(values)?))
    }
}

impl fmt::Display for Atom {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} {} 0", self.poly, self.rel.symbol())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ltl::theory::tests::{atom, k, r, x};

    #[test]
    fn polynomials() {
        let p = x(0).add(&x(1)).unwrap().pow(2).unwrap();
        assert_eq!(p.to_string(), "x0^2 + 2*x0*x1 + x1^2");
        assert_eq!(p.degree(), 2);
        assert!(!p.is_linear());
        let q = x(0).mul(&x(0)).unwrap().add(&x(1).scale(r("2")).unwrap().mul(&x(0)).unwrap()).unwrap();
        let q = q.add(&x(1).mul(&x(1)).unwrap()).unwrap();
        assert_eq!(p, q);
        assert_eq!(p.sub(&q).unwrap(), Poly::zero());
        assert_eq!(p.vars(), vec![NumVar(0), NumVar(1)]);
        assert_eq!(p.eval(&[r("1"), r("2")]), Some(r("9")));
        assert_eq!(p.eval(&[r("1")]), None);
        assert_eq!(p.eval_f64(&[1.0, 2.0]), 9.0);
        let names = |v: NumVar| ["x", "y"][v.0 as usize].to_string();
        let a = atom(x(0).mul(&x(0)).unwrap().add(&x(1).mul(&x(1)).unwrap()).unwrap(), Rel::Lt, k("3.5"));
        assert_eq!(format!("{}", a.poly.display(names)), "x^2 + y^2 - 7/2");
        assert_eq!(a.to_string(), "x0^2 + x1^2 - 7/2 < 0");
        assert_eq!(x(0).neg().unwrap().sub(&k("0.5")).unwrap().to_string(), "-x0 - 1/2");
        assert_eq!(x(0).add(&x(1)).unwrap().pow(200), None); // too many terms, not a hang
    }
}
