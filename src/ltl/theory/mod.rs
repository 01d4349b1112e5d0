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

use serde::Serialize;
use std::cmp::Ordering;
use std::collections::{BTreeMap, BTreeSet, HashMap, VecDeque};
use std::fmt;

// ------------------------------------------------------------------------------------------
// Rational

/// Exact rational number (i128 numerator/denominator, normalised, den > 0); arithmetic is
/// checked: overflow gives None (callers turn it into an Unknown answer, never a wrong one).
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug)]
pub struct Rational {
    num: i128,
    den: i128,
}

fn gcd(mut a: u128, mut b: u128) -> u128 {
    while b != 0 {
        (a, b) = (b, a % b);
    }
    a
}

impl Rational {
    pub const ZERO: Rational = Rational { num: 0, den: 1 };
    pub const ONE: Rational = Rational { num: 1, den: 1 };

    /// `num / den` normalised; None when `den` is 0 or the sign cannot be moved.
    pub fn new(num: i128, den: i128) -> Option<Rational> {
        if den == 0 {
            return None;
        }
        let (num, den) = if den < 0 { (num.checked_neg()?, den.checked_neg()?) } else { (num, den) };
        // den > 0 here, so the gcd is at most den and fits in i128.
        let g = gcd(num.unsigned_abs(), den.unsigned_abs()) as i128;
        Some(Rational { num: num / g, den: den / g })
    }

    pub fn from_int(n: i128) -> Rational {
        Rational { num: n, den: 1 }
    }

    pub fn from_i64(n: i64) -> Rational {
        Rational::from_int(n as i128)
    }

    pub fn numer(self) -> i128 {
        self.num
    }

    pub fn denom(self) -> i128 {
        self.den
    }

    pub fn is_integer(self) -> bool {
        self.den == 1
    }

    /// The largest integer not above the value.
    pub fn floor(self) -> i128 {
        self.num.div_euclid(self.den)
    }

    /// The smallest integer not below the value.
    pub fn ceil(self) -> i128 {
        // A remainder means den > 1, so the floor is far from i128::MAX.
        self.floor() + i128::from(self.num.rem_euclid(self.den) != 0)
    }

    /// A decimal literal: optional sign, digits with an optional point, optional exponent
    /// (`3.5`, `-0.25`, `1e3`, `.5`, `2.5E-2`). None on malformed text or overflow.
    pub fn parse_decimal(text: &str) -> Option<Rational> {
        let text = text.trim();
        let (negative, rest) = match text.as_bytes().first()? {
            b'-' => (true, &text[1..]),
            b'+' => (false, &text[1..]),
            _ => (false, text),
        };
        let (mantissa, exponent) = match rest.find(['e', 'E']) {
            Some(at) => (&rest[..at], Some(&rest[at + 1..])),
            None => (rest, None),
        };
        let (whole, fraction) = match mantissa.find('.') {
            Some(at) => (&mantissa[..at], &mantissa[at + 1..]),
            None => (mantissa, ""),
        };
        if whole.is_empty() && fraction.is_empty() {
            return None;
        }
        let mut num: i128 = 0;
        let mut den: i128 = 1;
        for (digits, scale) in [(whole, false), (fraction, true)] {
            for byte in digits.bytes() {
                if !byte.is_ascii_digit() {
                    return None;
                }
                num = num.checked_mul(10)?.checked_add(i128::from(byte - b'0'))?;
                if scale {
                    den = den.checked_mul(10)?;
                }
            }
        }
        if let Some(exponent) = exponent {
            let (minus, digits) = match exponent.as_bytes().first()? {
                b'-' => (true, &exponent[1..]),
                b'+' => (false, &exponent[1..]),
                _ => (false, exponent),
            };
            if digits.is_empty() || digits.len() > 3 || !digits.bytes().all(|b| b.is_ascii_digit()) {
                return None;
            }
            let e: u32 = digits.parse().ok()?;
            let power = 10i128.checked_pow(e)?;
            if minus {
                den = den.checked_mul(power)?;
            } else {
                num = num.checked_mul(power)?;
            }
        }
        let value = Rational::new(num, den)?;
        if negative {
            value.checked_neg()
        } else {
            Some(value)
        }
    }

    pub fn to_f64(self) -> f64 {
        self.num as f64 / self.den as f64
    }

    pub fn checked_neg(self) -> Option<Rational> {
        Some(Rational { num: self.num.checked_neg()?, den: self.den })
    }

    pub fn checked_add(self, other: Rational) -> Option<Rational> {
        let g = gcd(self.den as u128, other.den as u128) as i128;
        let (b, d) = (self.den / g, other.den / g);
        let num = self.num.checked_mul(d)?.checked_add(other.num.checked_mul(b)?)?;
        Rational::new(num, b.checked_mul(other.den)?)
    }

    pub fn checked_sub(self, other: Rational) -> Option<Rational> {
        self.checked_add(other.checked_neg()?)
    }

    pub fn checked_mul(self, other: Rational) -> Option<Rational> {
        let g1 = gcd(self.num.unsigned_abs(), other.den as u128) as i128;
        let g2 = gcd(other.num.unsigned_abs(), self.den as u128) as i128;
        let num = (self.num / g1).checked_mul(other.num / g2)?;
        Rational::new(num, (self.den / g2).checked_mul(other.den / g1)?)
    }

    pub fn checked_div(self, other: Rational) -> Option<Rational> {
        self.checked_mul(Rational::new(other.den, other.num)?)
    }

    pub fn checked_pow(self, exponent: u32) -> Option<Rational> {
        Some(Rational { num: self.num.checked_pow(exponent)?, den: self.den.checked_pow(exponent)? })
    }

    pub fn abs(self) -> Option<Rational> {
        if self.num < 0 {
            self.checked_neg()
        } else {
            Some(self)
        }
    }

    fn signum(self) -> i128 {
        self.num.signum()
    }
}

impl From<i64> for Rational {
    fn from(n: i64) -> Rational {
        Rational::from_i64(n)
    }
}

impl Ord for Rational {
    /// Exact without overflow: cross multiplication when it fits, else a comparison of the
    /// continued-fraction expansions (Euclid's steps on both fractions at once).
    fn cmp(&self, other: &Rational) -> Ordering {
        let (mut a, mut b, mut c, mut d) = (self.num, self.den, other.num, other.den);
        loop {
            if let (Some(x), Some(y)) = (a.checked_mul(d), c.checked_mul(b)) {
                return x.cmp(&y);
            }
            let (qa, ra) = (a.div_euclid(b), a.rem_euclid(b));
            let (qc, rc) = (c.div_euclid(d), c.rem_euclid(d));
            let order = match (qa.cmp(&qc), ra == 0, rc == 0) {
                (Ordering::Equal, true, true) => Ordering::Equal,
                (Ordering::Equal, true, false) => Ordering::Less,
                (Ordering::Equal, false, true) => Ordering::Greater,
                (Ordering::Equal, false, false) => {
                    // ra/b against rc/d, both in (0, 1): as d/rc against b/ra (reciprocals).
                    (a, b, c, d) = (d, rc, b, ra);
                    continue;
                }
                (order, _, _) => order,
            };
            return order;
        }
    }
}

impl PartialOrd for Rational {
    fn partial_cmp(&self, other: &Rational) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

impl fmt::Display for Rational {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.den == 1 {
            write!(f, "{}", self.num)
        } else {
            write!(f, "{}/{}", self.num, self.den)
        }
    }
}

/// The simplest rational (smallest denominator, then smallest magnitude) strictly between
/// `lo < hi`: small witnesses and split points keep later arithmetic far from overflow.
fn simplest_open(lo: Rational, hi: Rational) -> Option<Rational> {
    if lo >= hi {
        return None;
    }
    if lo < Rational::ZERO && hi > Rational::ZERO {
        return Some(Rational::ZERO);
    }
    if hi <= Rational::ZERO {
        return simplest_open(hi.checked_neg()?, lo.checked_neg()?)?.checked_neg();
    }
    simplest_above(lo, Some(hi), 0)
}

/// Simplest rational in the open interval (lo, hi) with 0 <= lo (hi None: unbounded).
fn simplest_above(lo: Rational, hi: Option<Rational>, depth: u32) -> Option<Rational> {
    if depth > 256 {
        return None;
    }
    let whole = lo.floor();
    let next = Rational::from_int(whole.checked_add(1)?);
    if hi.is_none_or(|h| next < h) {
        return Some(next);
    }
    let hi = hi?;
    let base = Rational::from_int(whole);
    let (l, h) = (lo.checked_sub(base)?, hi.checked_sub(base)?);
    // x = base + 1/y with y in (1/h, 1/l); h is in (0, 1].
    let upper = if l == Rational::ZERO { None } else { Some(Rational::ONE.checked_div(l)?) };
    let y = simplest_above(Rational::ONE.checked_div(h)?, upper, depth + 1)?;
    base.checked_add(Rational::ONE.checked_div(y)?)
}

/// Simplest rational in the closed interval [lo, hi] (an integer when one is inside).
fn simplest_closed(lo: Rational, hi: Rational) -> Option<Rational> {
    if lo > hi {
        return None;
    }
    if lo == hi {
        return Some(lo);
    }
    if lo <= Rational::ZERO && hi >= Rational::ZERO {
        return Some(Rational::ZERO);
    }
    if lo > Rational::ZERO && Rational::from_int(lo.ceil()) <= hi {
        return Some(Rational::from_int(lo.ceil()));
    }
    if hi < Rational::ZERO && Rational::from_int(hi.floor()) >= lo {
        return Some(Rational::from_int(hi.floor()));
    }
    simplest_open(lo, hi)
}

// ------------------------------------------------------------------------------------------
// Polynomials and atoms

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
    terms: BTreeMap<Monomial, Rational>,
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
        Poly { terms: BTreeMap::from([(vec![(v, 1)], Rational::ONE)]) }
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

    fn degree_in(&self, v: NumVar) -> u32 {
        self.terms.keys().flat_map(|m| m.iter().filter(|&&(w, _)| w == v).map(|&(_, e)| e)).max().unwrap_or(0)
    }

    /// The variables that occur, sorted.
    pub fn vars(&self) -> Vec<NumVar> {
        let set: BTreeSet<NumVar> = self.terms.keys().flat_map(|m| m.iter().map(|&(v, _)| v)).collect();
        set.into_iter().collect()
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
    fn range(&self, bx: &[Interval]) -> Option<Interval> {
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

    fn rename(&self, map: &HashMap<NumVar, NumVar>) -> Option<Poly> {
        let mut terms = BTreeMap::new();
        for (m, c) in &self.terms {
            let mut renamed: Monomial = m.iter().map(|&(v, e)| Some((*map.get(&v)?, e))).collect::<Option<_>>()?;
            renamed.sort();
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
    let mut exponents: BTreeMap<NumVar, u32> = a.iter().copied().collect();
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
        terms.sort_by(|(a, _), (b, _)| graded_lex(a, b));
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

// ------------------------------------------------------------------------------------------
// Intervals

#[derive(Clone, Copy, Debug)]
struct Interval {
    lo: Rational,
    hi: Rational,
}

impl Interval {
    fn point(r: Rational) -> Interval {
        Interval { lo: r, hi: r }
    }

    fn add(self, other: Interval) -> Option<Interval> {
        Some(Interval { lo: self.lo.checked_add(other.lo)?, hi: self.hi.checked_add(other.hi)? })
    }

    fn mul(self, other: Interval) -> Option<Interval> {
        let products = [
            self.lo.checked_mul(other.lo)?,
            self.lo.checked_mul(other.hi)?,
            self.hi.checked_mul(other.lo)?,
            self.hi.checked_mul(other.hi)?,
        ];
        Some(Interval { lo: *products.iter().min()?, hi: *products.iter().max()? })
    }

    /// The exact range of `x^e` (tighter than repeated multiplication for even powers).
    fn pow(self, e: u32) -> Option<Interval> {
        let (a, b) = (self.lo.checked_pow(e)?, self.hi.checked_pow(e)?);
        Some(if e % 2 == 1 || self.lo >= Rational::ZERO {
            Interval { lo: a, hi: b }
        } else if self.hi <= Rational::ZERO {
            Interval { lo: b, hi: a }
        } else {
            Interval { lo: Rational::ZERO, hi: a.max(b) }
        })
    }

    /// Whether `x REL 0` for every x of the interval (Some(true)), for none (Some(false)).
    fn decides(self, rel: Rel) -> Option<bool> {
        let zero = Rational::ZERO;
        let (lo, hi) = (self.lo, self.hi);
        match rel {
            Rel::Lt if hi < zero => Some(true),
            Rel::Lt if lo >= zero => Some(false),
            Rel::Le if hi <= zero => Some(true),
            Rel::Le if lo > zero => Some(false),
            Rel::Gt if lo > zero => Some(true),
            Rel::Gt if hi <= zero => Some(false),
            Rel::Ge if lo >= zero => Some(true),
            Rel::Ge if hi < zero => Some(false),
            Rel::Eq | Rel::Ne if lo == zero && hi == zero => Some(rel == Rel::Eq),
            Rel::Eq | Rel::Ne if lo > zero || hi < zero => Some(rel == Rel::Ne),
            _ => None,
        }
    }
}

// ------------------------------------------------------------------------------------------
// decide

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

// ------------------------------------------------------------------------------------------
// Linear arithmetic: Fourier–Motzkin with branching for ≠ and integers

#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Debug)]
enum Kind {
    /// `a·x + c > 0`
    Gt,
    /// `a·x + c >= 0`
    Ge,
    /// `a·x + c = 0`
    Eq,
}

/// A linear constraint `a·x + c (kind) 0` over the local variables.
#[derive(Clone, PartialEq, Eq, Debug)]
struct Lin {
    a: Vec<Rational>,
    c: Rational,
    kind: Kind,
}

impl Lin {
    fn from_poly(poly: &Poly, m: usize, kind: Kind) -> Result<Lin, Stop> {
        let mut a = vec![Rational::ZERO; m];
        let mut c = Rational::ZERO;
        for (mono, coef) in &poly.terms {
            match mono.as_slice() {
                [] => c = *coef,
                [(v, 1)] => *a.get_mut(v.0 as usize).or_unknown()? = *coef,
                _ => return Err(Stop::Unknown),
            }
        }
        Ok(Lin { a, c, kind })
    }

    fn negated(&self, kind: Kind) -> Result<Lin, Stop> {
        let a = self.a.iter().map(|x| x.checked_neg()).collect::<Option<_>>().or_unknown()?;
        Ok(Lin { a, c: self.c.checked_neg().or_unknown()?, kind })
    }

    fn value(&self, point: &[Rational]) -> Result<Rational, Stop> {
        let mut sum = self.c;
        for (a, x) in self.a.iter().zip(point) {
            sum = sum.checked_add(a.checked_mul(*x).or_unknown()?).or_unknown()?;
        }
        Ok(sum)
    }

    /// `self·f + other·g`
    fn combine(&self, f: Rational, other: &Lin, g: Rational, kind: Kind) -> Result<Lin, Stop> {
        let term = |x: Rational, y: Rational| x.checked_mul(f)?.checked_add(y.checked_mul(g)?);
        let a = self.a.iter().zip(&other.a).map(|(x, y)| term(*x, *y)).collect::<Option<_>>().or_unknown()?;
        Ok(Lin { a, c: term(self.c, other.c).or_unknown()?, kind })
    }
}

/// The box bounds `x - lo >= 0`, `hi - x >= 0` as constraints.
fn box_constraints(bx: &[Interval]) -> Result<Vec<Lin>, Stop> {
    let m = bx.len();
    let mut out = Vec::with_capacity(2 * m);
    for (i, iv) in bx.iter().enumerate() {
        let mut a = vec![Rational::ZERO; m];
        a[i] = Rational::ONE;
        out.push(Lin { a: a.clone(), c: iv.lo.checked_neg().or_unknown()?, kind: Kind::Ge });
        a[i] = Rational::from_int(-1);
        out.push(Lin { a, c: iv.hi, kind: Kind::Ge });
    }
    Ok(out)
}

/// Linear literals over a box: Fourier–Motzkin at each node, `≠` split into `<`/`>` when the
/// witness violates it, an integer variable with a fractional value split at that value.
fn linear(cons: &[(Poly, Rel)], bx: &[Interval], integer: &[bool], budget: &mut u64) -> Result<Vec<Rational>, Stop> {
    let m = bx.len();
    let mut base = Vec::new();
    let mut nes = Vec::new();
    for (poly, rel) in cons {
        let lin = Lin::from_poly(poly, m, Kind::Ge)?;
        match rel {
            Rel::Gt => base.push(Lin { kind: Kind::Gt, ..lin }),
            Rel::Ge => base.push(lin),
            Rel::Lt => base.push(lin.negated(Kind::Gt)?),
            Rel::Le => base.push(lin.negated(Kind::Ge)?),
            Rel::Eq => base.push(Lin { kind: Kind::Eq, ..lin }),
            Rel::Ne => nes.push(lin),
        }
    }
    let mut stack: Vec<(Vec<Interval>, Vec<Lin>)> = vec![(bx.to_vec(), Vec::new())];
    let mut incomplete = false;
    while let Some((node_box, extra)) = stack.pop() {
        spend(budget, 1)?;
        let mut system = base.clone();
        system.extend(extra.iter().cloned());
        system.extend(box_constraints(&node_box)?);
        let point = match fourier_motzkin(system, &node_box, integer, budget) {
            Ok(point) => point,
            Err(Stop::Unsat) => continue,
            Err(Stop::Unknown) if *budget == 0 => return Err(Stop::Unknown),
            Err(Stop::Unknown) => {
                incomplete = true;
                continue;
            }
        };
        let mut violated = None;
        let mut overflow = false;
        for ne in &nes {
            match ne.value(&point) {
                Ok(v) if v == Rational::ZERO => {
                    violated = Some(ne);
                    break;
                }
                Ok(_) => {}
                Err(_) => {
                    overflow = true;
                    break;
                }
            }
        }
        if overflow {
            incomplete = true;
            continue;
        }
        if let Some(ne) = violated {
            let mut above = extra.clone();
            above.push(Lin { kind: Kind::Gt, ..ne.clone() });
            let mut below = extra;
            below.push(ne.negated(Kind::Gt)?);
            stack.push((node_box.clone(), above));
            stack.push((node_box, below));
            continue;
        }
        if let Some(i) = (0..m).find(|&i| integer[i] && !point[i].is_integer()) {
            let split = point[i].floor();
            let mut low = node_box.clone();
            low[i].hi = Rational::from_int(split);
            let mut high = node_box;
            high[i].lo = Rational::from_int(split.checked_add(1).or_unknown()?);
            for side in [high, low] {
                if side[i].lo <= side[i].hi {
                    stack.push((side, extra.clone()));
                }
            }
            continue;
        }
        return Ok(point);
    }
    Err(if incomplete { Stop::Unknown } else { Stop::Unsat })
}

/// Scales a constraint so that its first nonzero coefficient is ±1 (1 for equalities); a
/// constant constraint is checked (Unsat) or dropped (None).
fn normalise(lin: Lin) -> Result<Option<Lin>, Stop> {
    let Some(lead) = lin.a.iter().copied().find(|x| *x != Rational::ZERO) else {
        let holds = match lin.kind {
            Kind::Gt => lin.c > Rational::ZERO,
            Kind::Ge => lin.c >= Rational::ZERO,
            Kind::Eq => lin.c == Rational::ZERO,
        };
        return if holds { Ok(None) } else { Err(Stop::Unsat) };
    };
    let factor = if lin.kind == Kind::Eq { lead } else { lead.abs().or_unknown()? };
    if factor == Rational::ONE {
        return Ok(Some(lin));
    }
    let inverse = Rational::ONE.checked_div(factor).or_unknown()?;
    let zero = Lin { a: vec![Rational::ZERO; lin.a.len()], c: Rational::ZERO, kind: lin.kind };
    Ok(Some(lin.combine(inverse, &zero, Rational::ZERO, lin.kind)?))
}

/// Normalises, drops constants and keeps the tightest of parallel inequalities.
fn simplify(system: Vec<Lin>) -> Result<Vec<Lin>, Stop> {
    let mut ineqs: BTreeMap<Vec<Rational>, (Rational, Kind)> = BTreeMap::new();
    let mut eqs: BTreeMap<Vec<Rational>, Rational> = BTreeMap::new();
    for lin in system {
        let Some(lin) = normalise(lin)? else { continue };
        if lin.kind == Kind::Eq {
            match eqs.get(&lin.a) {
                Some(c) if *c != lin.c => return Err(Stop::Unsat),
                Some(_) => {}
                None => {
                    eqs.insert(lin.a, lin.c);
                }
            }
            continue;
        }
        // a·x + c ⋈ 0: a smaller c is tighter; at equal c strict is tighter.
        let entry = ineqs.entry(lin.a).or_insert((lin.c, lin.kind));
        if lin.c < entry.0 || (lin.c == entry.0 && lin.kind == Kind::Gt) {
            *entry = (lin.c, lin.kind);
        }
    }
    let mut out: Vec<Lin> = eqs.into_iter().map(|(a, c)| Lin { a, c, kind: Kind::Eq }).collect();
    out.extend(ineqs.into_iter().map(|(a, (c, kind))| Lin { a, c, kind }));
    Ok(out)
}

/// One elimination, kept for back-substitution.
enum Step {
    /// The variable was solved from this equality.
    Solve(usize, Lin),
    /// The variable was eliminated; these constraints bounded it.
    Eliminate(usize, Vec<Lin>),
}

/// Decides a system of linear constraints (which includes the box bounds) exactly; the
/// witness by back-substitution, preferring integers (and small denominators) in each range.
fn fourier_motzkin(
    system: Vec<Lin>,
    bx: &[Interval],
    integer: &[bool],
    budget: &mut u64,
) -> Result<Vec<Rational>, Stop> {
    let m = bx.len();
    let mut system = simplify(system)?;
    let mut steps = Vec::new();
    loop {
        if let Some(at) = system.iter().position(|l| l.kind == Kind::Eq) {
            spend(budget, system.len() as u64)?;
            let eq = system.swap_remove(at);
            let j = (0..m).rev().find(|&j| eq.a[j] != Rational::ZERO).or_unknown()?;
            let mut next = Vec::with_capacity(system.len());
            for lin in system {
                if lin.a[j] == Rational::ZERO {
                    next.push(lin);
                } else {
                    let factor = lin.a[j].checked_div(eq.a[j]).and_then(|f| f.checked_neg()).or_unknown()?;
                    let mut combined = lin.combine(Rational::ONE, &eq, factor, lin.kind)?;
                    combined.a[j] = Rational::ZERO; // exact already; kept explicit
                    next.push(combined);
                }
            }
            steps.push(Step::Solve(j, eq));
            system = simplify(next)?;
            continue;
        }
        // The variable whose elimination makes the fewest new constraints.
        let mut best: Option<(usize, usize)> = None;
        for j in 0..m {
            let pos = system.iter().filter(|l| l.a[j] > Rational::ZERO).count();
            let neg = system.iter().filter(|l| l.a[j] < Rational::ZERO).count();
            if pos + neg > 0 && best.is_none_or(|(_, cost)| pos * neg < cost) {
                best = Some((j, pos * neg));
            }
        }
        let Some((j, cost)) = best else { break };
        spend(budget, cost as u64)?;
        let (bounding, rest): (Vec<Lin>, Vec<Lin>) = system.into_iter().partition(|l| l.a[j] != Rational::ZERO);
        let mut next = rest;
        for lower in bounding.iter().filter(|l| l.a[j] > Rational::ZERO) {
            for upper in bounding.iter().filter(|l| l.a[j] < Rational::ZERO) {
                let kind = if lower.kind == Kind::Gt || upper.kind == Kind::Gt { Kind::Gt } else { Kind::Ge };
                let f = upper.a[j].checked_neg().or_unknown()?;
                let mut combined = lower.combine(f, upper, lower.a[j], kind)?;
                combined.a[j] = Rational::ZERO;
                next.push(combined);
            }
        }
        steps.push(Step::Eliminate(j, bounding));
        system = simplify(next)?;
    }

    // Back-substitution, last elimination first.
    let mut point: Vec<Option<Rational>> = vec![None; m];
    let value_at = |point: &[Option<Rational>], i: usize| point[i].unwrap_or(bx[i].lo);
    let rest_value = |lin: &Lin, j: usize, point: &[Option<Rational>]| -> Result<Rational, Stop> {
        let mut sum = lin.c;
        for i in (0..m).filter(|&i| i != j && lin.a[i] != Rational::ZERO) {
            sum = sum.checked_add(lin.a[i].checked_mul(value_at(point, i)).or_unknown()?).or_unknown()?;
        }
        Ok(sum)
    };
    for step in steps.iter().rev() {
        match step {
            Step::Solve(j, eq) => {
                let r = rest_value(eq, *j, &point)?;
                point[*j] = Some(r.checked_neg().and_then(|r| r.checked_div(eq.a[*j])).or_unknown()?);
            }
            Step::Eliminate(j, bounding) => {
                let mut lower: Option<(Rational, bool)> = None;
                let mut upper: Option<(Rational, bool)> = None;
                for lin in bounding {
                    let r = rest_value(lin, *j, &point)?;
                    let bound = r.checked_neg().and_then(|r| r.checked_div(lin.a[*j])).or_unknown()?;
                    let strict = lin.kind == Kind::Gt;
                    if lin.a[*j] > Rational::ZERO {
                        if lower.is_none_or(|(b, s)| bound > b || (bound == b && strict && !s)) {
                            lower = Some((bound, strict));
                        }
                    } else if upper.is_none_or(|(b, s)| bound < b || (bound == b && strict && !s)) {
                        upper = Some((bound, strict));
                    }
                }
                let lower = lower.unwrap_or((bx[*j].lo, false));
                let upper = upper.unwrap_or((bx[*j].hi, false));
                point[*j] = Some(pick(lower, upper, integer[*j]).or_unknown()?);
            }
        }
    }
    Ok((0..m).map(|i| value_at(&point, i)).collect())
}

/// A value between two bounds (value, strict): an integer when one fits, else the simplest.
fn pick(lower: (Rational, bool), upper: (Rational, bool), prefer_integer: bool) -> Option<Rational> {
    let ((lo, lo_strict), (hi, hi_strict)) = (lower, upper);
    if lo == hi {
        return (!lo_strict && !hi_strict).then_some(lo);
    }
    let inner = simplest_open(lo, hi)?;
    if inner.is_integer() || !prefer_integer {
        return Some(inner);
    }
    [(lo, lo_strict), (hi, hi_strict)]
        .iter()
        .find(|(b, strict)| !strict && b.is_integer())
        .map(|(b, _)| *b)
        .or(Some(inner))
}

// ------------------------------------------------------------------------------------------
// Interval branch and bound

/// A point of the box to try: its simplest point, then each undecided equality solved for a
/// variable it is linear in (the others held), so that equalities can be met exactly.
fn candidate(cons: &[(Poly, Rel)], live: &[usize], bx: &[Interval], integer: &[bool]) -> Option<Vec<Rational>> {
    let mut point: Vec<Rational> = bx.iter().map(|iv| simplest_closed(iv.lo, iv.hi)).collect::<Option<_>>()?;
    let satisfied =
        |point: &[Rational]| live.iter().all(|&i| cons[i].0.eval(point).is_some_and(|v| cons[i].1.holds(v)));
    if satisfied(&point) {
        return Some(point);
    }
    let mut fixed = vec![false; bx.len()];
    for &i in live.iter().filter(|&&i| cons[i].1 == Rel::Eq) {
        let poly = &cons[i].0;
        for v in poly.vars() {
            let k = v.0 as usize;
            if fixed[k] || poly.degree_in(v) != 1 {
                continue;
            }
            // poly = A·v + B with the other variables held.
            let mut at = point.clone();
            at[k] = Rational::ZERO;
            let b = poly.eval(&at)?;
            at[k] = Rational::ONE;
            let a = poly.eval(&at)?.checked_sub(b)?;
            if a == Rational::ZERO {
                continue;
            }
            let value = b.checked_neg()?.checked_div(a)?;
            if bx[k].lo <= value && value <= bx[k].hi && (!integer[k] || value.is_integer()) {
                point[k] = value;
                fixed[k] = true;
                break;
            }
        }
    }
    satisfied(&point).then_some(point)
}

/// Waiting boxes beyond which branch and bound goes depth first.
const MAX_FRONTIER: usize = 4096;

/// The range enclosure, tightened by monotonicity: a variable in which the polynomial is
/// monotone over the whole box (its derivative's enclosure has one sign) is held at the
/// endpoint that gives the minimum (maximum) for the lower (upper) bound. This settles
/// literals whose zero set touches the box's boundary, where the plain enclosure never does.
fn refined_range(poly: &Poly, derivatives: &[(usize, Poly)], bx: &[Interval]) -> Option<Interval> {
    let plain = poly.range(bx)?;
    let (mut low, mut high) = (bx.to_vec(), bx.to_vec());
    let mut monotone = false;
    for (k, derivative) in derivatives {
        let Some(slope) = derivative.range(bx) else { continue };
        let (lo, hi) = (Interval::point(bx[*k].lo), Interval::point(bx[*k].hi));
        if slope.lo >= Rational::ZERO {
            (low[*k], high[*k]) = (lo, hi);
        } else if slope.hi <= Rational::ZERO {
            (low[*k], high[*k]) = (hi, lo);
        } else {
            continue;
        }
        monotone = true;
    }
    if !monotone {
        return Some(plain);
    }
    let lo = poly.range(&low).map_or(plain.lo, |r| r.lo.max(plain.lo));
    let hi = poly.range(&high).map_or(plain.hi, |r| r.hi.min(plain.hi));
    Some(Interval { lo, hi })
}

/// Boxes are processed breadth first (up to [`MAX_FRONTIER`] waiting), so that a degenerate
/// corner cannot swallow the budget before the rest of the box has been looked at.
fn branch_and_bound(
    cons: &[(Poly, Rel)],
    bx: Vec<Interval>,
    integer: &[bool],
    budget: &mut u64,
) -> Result<Vec<Rational>, Stop> {
    let mut derivatives: Vec<Vec<(usize, Poly)>> = Vec::with_capacity(cons.len());
    for (poly, _) in cons {
        let vars = poly.vars();
        let d = vars.iter().map(|&v| Some((v.0 as usize, poly.derivative(v)?))).collect::<Option<_>>();
        derivatives.push(d.or_unknown()?);
    }
    let mut queue: VecDeque<(Vec<Interval>, Vec<usize>)> = VecDeque::from([(bx, (0..cons.len()).collect())]);
    let mut incomplete = false;
    // Depth first once the frontier is large, which bounds its memory.
    'boxes: while let Some((bx, live)) = if queue.len() > MAX_FRONTIER { queue.pop_back() } else { queue.pop_front() } {
        spend(budget, 1)?;
        let mut undecided = Vec::with_capacity(live.len());
        for &i in &live {
            let Some(range) = refined_range(&cons[i].0, &derivatives[i], &bx) else {
                incomplete = true; // overflow: this box is given up
                continue 'boxes;
            };
            match range.decides(cons[i].1) {
                Some(true) => {}
                Some(false) => continue 'boxes,
                None => undecided.push(i),
            }
        }
        if let Some(point) = candidate(cons, &undecided, &bx, integer) {
            return Ok(point);
        }
        if undecided.iter().all(|&i| cons[i].0.is_linear()) {
            let live: Vec<(Poly, Rel)> = undecided.iter().map(|&i| cons[i].clone()).collect();
            match linear(&live, &bx, integer, budget) {
                Ok(point) => return Ok(point),
                Err(Stop::Unsat) => continue,
                Err(Stop::Unknown) if *budget == 0 => return Err(Stop::Unknown),
                Err(Stop::Unknown) => {
                    incomplete = true;
                    continue;
                }
            }
        }
        // Bisect the widest variable of the undecided literals.
        let mut widest: Option<(usize, Rational)> = None;
        for &i in &undecided {
            for v in cons[i].0.vars() {
                let k = v.0 as usize;
                let Some(width) = bx[k].hi.checked_sub(bx[k].lo) else {
                    incomplete = true;
                    continue 'boxes;
                };
                if width > Rational::ZERO && widest.is_none_or(|(_, w)| width > w) {
                    widest = Some((k, width));
                }
            }
        }
        let Some((k, width)) = widest else {
            incomplete = true; // a point box is always decided; kept for safety
            continue;
        };
        let (low, high) = if integer[k] {
            let mid = bx[k].lo.checked_add(bx[k].hi).and_then(|s| s.checked_div(Rational::from_int(2)));
            let Some(mid) = mid.map(|m| m.floor()) else {
                incomplete = true;
                continue;
            };
            let Some(next) = mid.checked_add(1) else {
                incomplete = true;
                continue;
            };
            (Rational::from_int(mid), Rational::from_int(next))
        } else {
            let quarter = width.checked_div(Rational::from_int(4));
            let split = quarter.and_then(|q| simplest_open(bx[k].lo.checked_add(q)?, bx[k].hi.checked_sub(q)?));
            let Some(split) = split else {
                incomplete = true;
                continue;
            };
            (split, split)
        };
        let mut left = bx.clone();
        left[k].hi = low;
        let mut right = bx;
        right[k].lo = high;
        queue.push_back((left, undecided.clone()));
        queue.push_back((right, undecided));
    }
    Err(if incomplete { Stop::Unknown } else { Stop::Unsat })
}

// ------------------------------------------------------------------------------------------
// Theory: the memoising front

/// The work one query may spend unless configured otherwise.
pub const DEFAULT_BUDGET: u64 = 200_000;

/// Counts for reports: queries answered from the cache (or a known unsatisfiable subset) and
/// queries computed by [`decide`].
#[derive(Clone, Copy, PartialEq, Eq, Debug, Default, Serialize)]
pub struct TheoryStats {
    pub queries: usize,
    pub cached: usize,
    pub computed: usize,
    /// Units of work the computed queries spent (boxes split, eliminations).
    pub work: u64,
}

/// Memoising front: the atoms (predicates) fixed once, queried many times with combinations.
#[derive(Clone, Debug)]
pub struct Theory {
    atoms: Vec<Atom>,
    domains: Vec<Domain>,
    budget: u64,
    cache: HashMap<Vec<(usize, bool)>, Answer>,
    /// Known unsatisfiable combinations, none a superset of another.
    unsat: Vec<Vec<(usize, bool)>>,
    stats: TheoryStats,
}

/// Sorted, without duplicates: the cache key.
fn sorted(combination: &[(usize, bool)]) -> Vec<(usize, bool)> {
    let mut key = combination.to_vec();
    key.sort_unstable();
    key.dedup();
    key
}

/// Whether every element of the sorted `small` is in the sorted `large`.
fn is_subset(small: &[(usize, bool)], large: &[(usize, bool)]) -> bool {
    let mut rest = large.iter();
    small.iter().all(|x| rest.by_ref().any(|y| y == x))
}

impl Theory {
    pub fn new(atoms: Vec<Atom>, domains: Vec<Domain>) -> Theory {
        Theory {
            atoms,
            domains,
            budget: DEFAULT_BUDGET,
            cache: HashMap::new(),
            unsat: Vec::new(),
            stats: TheoryStats::default(),
        }
    }

    /// The work each computed query may spend (default [`DEFAULT_BUDGET`]).
    pub fn with_budget(mut self, budget: u64) -> Theory {
        self.budget = budget;
        self
    }

    /// Changes the work each computed query from now on may spend.
    pub fn set_budget(&mut self, budget: u64) {
        self.budget = budget;
    }

    pub fn atoms(&self) -> &[Atom] {
        &self.atoms
    }

    pub fn domains(&self) -> &[Domain] {
        &self.domains
    }

    /// combination: (atom index, polarity) pairs; memoised on the sorted combination; a query on
    /// a superset of a known Unsat combination is Unsat without work. An atom index out of range
    /// gives Unknown.
    pub fn check(&mut self, combination: &[(usize, bool)]) -> Answer {
        self.stats.queries += 1;
        let key = sorted(combination);
        if let Some(answer) = self.cache.get(&key) {
            self.stats.cached += 1;
            return answer.clone();
        }
        if self.unsat.iter().any(|core| is_subset(core, &key)) {
            self.stats.cached += 1;
            return Answer::Unsat;
        }
        self.stats.computed += 1;
        let answer = if key.windows(2).any(|w| w[0].0 == w[1].0) {
            Answer::Unsat // an atom with both polarities
        } else if key.iter().any(|&(i, _)| i >= self.atoms.len()) {
            Answer::Unknown
        } else {
            let literals: Vec<(Atom, bool)> = key.iter().map(|&(i, p)| (self.atoms[i].clone(), p)).collect();
            let mut budget = self.budget;
            let answer = decide(&literals, &self.domains, &mut budget);
            self.stats.work += self.budget - budget;
            answer
        };
        if answer == Answer::Unsat {
            self.unsat.retain(|core| !is_subset(&key, core));
            self.unsat.push(key.clone());
        }
        self.cache.insert(key, answer.clone());
        answer
    }

    /// A smallest-found unsatisfiable sub-combination (literals dropped greedily while the rest
    /// stays Unsat), sorted — the learned assumption is its negation, e.g. `G !(p0 && p1)`.
    /// Meant for Unsat combinations: any other (Sat or Unknown) comes back unchanged (sorted);
    /// callers must learn only from combinations `check` answered Unsat.
    pub fn minimal_unsat(&mut self, combination: &[(usize, bool)]) -> Vec<(usize, bool)> {
        let key = sorted(combination);
        if self.check(&key) != Answer::Unsat {
            return key;
        }
        let mut core = self
            .unsat
            .iter()
            .filter(|core| is_subset(core, &key))
            .min_by_key(|core| core.len())
            .cloned()
            .unwrap_or(key);
        let mut i = 0;
        while i < core.len() {
            let mut smaller = core.clone();
            smaller.remove(i);
            if self.check(&smaller) == Answer::Unsat {
                core = smaller;
            } else {
                i += 1;
            }
        }
        core
    }

    /// How many queries were asked (`check`, including those `minimal_unsat` makes).
    pub fn queries(&self) -> usize {
        self.stats.queries
    }

    /// How many were answered from the cache or a known unsatisfiable subset.
    pub fn cached(&self) -> usize {
        self.stats.cached
    }

    /// How many were computed.
    pub fn computed(&self) -> usize {
        self.stats.computed
    }

    pub fn stats(&self) -> TheoryStats {
        self.stats
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn r(text: &str) -> Rational {
        Rational::parse_decimal(text).unwrap()
    }

    fn x(i: u32) -> Poly {
        Poly::var(NumVar(i))
    }

    fn k(text: &str) -> Poly {
        Poly::constant(r(text))
    }

    fn atom(lhs: Poly, rel: Rel, rhs: Poly) -> Atom {
        Atom::new(lhs, rel, rhs).unwrap()
    }

    fn real(lo: &str, hi: &str) -> Domain {
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

    fn is_sat(answer: &Answer) -> bool {
        matches!(answer, Answer::Sat(_))
    }

    #[test]
    fn rationals() {
        assert_eq!(r("3.5").to_string(), "7/2");
        assert_eq!(r("-0.25").to_string(), "-1/4");
        assert_eq!(r("1e3").to_string(), "1000");
        assert_eq!(r("2.5E-2").to_string(), "1/40");
        assert_eq!(r(".5"), Rational::new(1, 2).unwrap());
        for bad in ["", "-", ".", "1..2", "e3", "1e", "1e-", "x", "1e99999", "1/2"] {
            assert_eq!(Rational::parse_decimal(bad), None, "{bad}");
        }
        assert_eq!(Rational::new(6, -4).unwrap().to_string(), "-3/2");
        assert_eq!(Rational::new(1, 0), None);
        let big = Rational::from_int(i128::MAX);
        assert_eq!(big.checked_add(Rational::ONE), None);
        assert_eq!(big.checked_mul(Rational::from_int(2)), None);
        assert_eq!(Rational::from_int(i128::MIN).checked_neg(), None);
        // Comparison past the range of cross multiplication.
        let a = Rational::new(i128::MAX, i128::MAX - 1).unwrap();
        let b = Rational::new(i128::MAX - 1, i128::MAX - 2).unwrap();
        assert!(a < b);
        assert_eq!((b.cmp(&a), a.cmp(&a.clone())), (Ordering::Greater, Ordering::Equal));
        let c = Rational::new(i128::MAX - 2, 3).unwrap();
        assert!(c < big && Rational::new(-i128::MAX, 7).unwrap() < c);
        assert_eq!(r("-3.5").floor(), -4);
        assert_eq!(r("-3.5").ceil(), -3);
        assert_eq!(r("3").ceil(), 3);
        assert!((r("0.1").to_f64() - 0.1).abs() < 1e-15);
    }

    #[test]
    fn simplest_points() {
        assert_eq!(simplest_open(r("0.3"), r("0.4")), Some(Rational::new(1, 3).unwrap()));
        assert_eq!(simplest_open(r("-0.4"), r("-0.3")), Some(Rational::new(-1, 3).unwrap()));
        assert_eq!(simplest_open(r("1"), r("3")), Some(r("2")));
        assert_eq!(simplest_open(r("-1"), r("3")), Some(Rational::ZERO));
        assert_eq!(simplest_open(r("1"), r("2")), Some(r("1.5")));
        assert_eq!(simplest_open(r("1"), r("1")), None);
        assert_eq!(simplest_closed(r("1"), r("2")), Some(r("1")));
        assert_eq!(simplest_closed(r("0.25"), r("0.75")), Some(r("0.5")));
    }

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

    #[test]
    fn theory_memo_and_cores() {
        let domains = vec![real("0", "4"), real("0", "4")];
        let atoms = vec![
            atom(x(0), Rel::Gt, k("3")),                 // 0
            atom(x(0), Rel::Lt, k("1")),                 // 1
            atom(x(1).pow(2).unwrap(), Rel::Gt, k("1")), // 2
            atom(x(0), Rel::Gt, k("5")),                 // 3: alone Unsat in the box
        ];
        let mut theory = Theory::new(atoms, domains).with_budget(50_000);
        assert_eq!(theory.check(&[(0, true), (1, true), (2, true)]), Answer::Unsat);
        assert_eq!(theory.minimal_unsat(&[(0, true), (1, true), (2, true)]), vec![(0, true), (1, true)]);
        let before = theory.computed();
        assert_eq!(theory.check(&[(2, false), (0, true), (1, true)]), Answer::Unsat);
        assert_eq!(theory.computed(), before, "a superset of a known core costs nothing");
        assert_eq!(theory.minimal_unsat(&[(2, true), (3, true), (0, false)]), vec![(3, true)]);
        assert_eq!(theory.check(&[(2, true), (2, false)]), Answer::Unsat);
        assert_eq!(theory.check(&[(9, true)]), Answer::Unknown);
        assert!(is_sat(&theory.check(&[(0, true), (2, true)])));
        assert_eq!(theory.minimal_unsat(&[(0, true), (2, true)]), vec![(0, true), (2, true)]);
        assert_eq!(theory.queries(), theory.cached() + theory.computed());
    }
}
