//! Linear arithmetic: Fourier–Motzkin elimination over exact rationals with strict and
//! non-strict bookkeeping, branching for `≠` and integers.

use super::interval::Interval;
use super::poly::{Poly, Rel};
use super::rational::{simplest_open, Rational};
use super::{spend, OrUnknown, Stop};
use std::collections::BTreeMap;

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
pub(super) fn linear(
    cons: &[(Poly, Rel)],
    bx: &[Interval],
    integer: &[bool],
    budget: &mut u64,
) -> Result<Vec<Rational>, Stop> {
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
