//! Interval arithmetic with exact rational endpoints and the interval branch and bound for
//! literals that are not all linear.

use super::linear::linear;
use super::poly::{Poly, Rel};
use super::rational::{simplest_closed, simplest_open, Rational};
use super::{spend, OrUnknown, Stop};
use std::collections::VecDeque;

#[derive(Clone, Copy, Debug)]
pub(super) struct Interval {
    pub(super) lo: Rational,
    pub(super) hi: Rational,
}

impl Interval {
    pub(super) fn point(r: Rational) -> Interval {
        Interval { lo: r, hi: r }
    }

    pub(super) fn add(self, other: Interval) -> Option<Interval> {
        Some(Interval { lo: self.lo.checked_add(other.lo)?, hi: self.hi.checked_add(other.hi)? })
    }

    pub(super) fn mul(self, other: Interval) -> Option<Interval> {
        let products = [
            self.lo.checked_mul(other.lo)?,
            self.lo.checked_mul(other.hi)?,
            self.hi.checked_mul(other.lo)?,
            self.hi.checked_mul(other.hi)?,
        ];
        Some(Interval { lo: *products.iter().min()?, hi: *products.iter().max()? })
    }

    /// The exact range of `x^e` (tighter than repeated multiplication for even powers).
    pub(super) fn pow(self, e: u32) -> Option<Interval> {
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
pub(super) fn branch_and_bound(
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
