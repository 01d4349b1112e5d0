//! Exact rationals (`i128`, checked arithmetic) and the simplest rational in an interval.

use std::cmp::Ordering;
use std::fmt;

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

    pub(super) fn signum(self) -> i128 {
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
pub(super) fn simplest_open(lo: Rational, hi: Rational) -> Option<Rational> {
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
pub(super) fn simplest_closed(lo: Rational, hi: Rational) -> Option<Rational> {
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ltl::theory::tests::r;

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
}
