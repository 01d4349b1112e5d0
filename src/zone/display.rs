//! Human-readable and serialised views of zones.

use std::fmt;

use serde::ser::{Serialize, SerializeStruct, Serializer};

use super::{Bound, Dbm};

/// One constraint `x_i - x_j ≺ c` of a zone (`x_0` is the constant 0).
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug)]
pub struct Constraint {
    /// Index of the positive clock.
    pub i: usize,
    /// Index of the negative clock.
    pub j: usize,
    /// The (finite) bound.
    pub bound: Bound,
}

impl Serialize for Constraint {
    /// `{"i": 1, "j": 0, "c": 4, "strict": false}` for `x1 - x0 ≤ 4`.
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let mut st = s.serialize_struct("Constraint", 4)?;
        st.serialize_field("i", &self.i)?;
        st.serialize_field("j", &self.j)?;
        st.serialize_field("c", &self.bound.constant())?;
        st.serialize_field("strict", &self.bound.is_strict())?;
        st.end()
    }
}

impl Dbm {
    /// A non-redundant set of constraints describing the zone, for display:
    /// trivial ones (`x ≥ 0`) and those implied by the others are left out,
    /// preferring to keep single-clock bounds over differences. An empty
    /// zone yields `[0 - 0 < 0]`, an unconstrained one yields nothing.
    /// O(dim⁵); not for the exploration loop.
    pub fn constraints(&self) -> Vec<Constraint> {
        let n = self.dim();
        if self.is_empty() {
            return vec![Constraint { i: 0, j: 0, bound: Bound::LT_ZERO }];
        }
        // What every zone knows without being told: x ≥ 0 and x - x ≤ 0.
        let base = Dbm::unconstrained(n);
        let mut kept: Vec<(usize, usize)> = Vec::new();
        for i in 0..n {
            for j in 0..n {
                if i != j && self.get(i, j) < base.get(i, j) {
                    kept.push((i, j));
                }
            }
        }
        // Try to drop differences first, then bounds of the highest clocks;
        // keep an edge only
        // if the others no longer imply the same canonical matrix. Dropping is
        // monotone, so no kept edge becomes redundant later.
        crate::sort::sort_by_key(&mut kept, |&(i, j)| (i == 0 || j == 0, std::cmp::Reverse(i.max(j)), i, j));
        let mut k = 0;
        let mut trial = base.clone();
        while k < kept.len() {
            trial.copy_from_slice(base.as_slice());
            for (idx, &(i, j)) in kept.iter().enumerate() {
                if idx != k {
                    trial.m_set(i, j, self.get(i, j));
                }
            }
            trial.close();
            if trial == *self {
                kept.remove(k);
            } else {
                k += 1;
            }
        }
        crate::sort::sort_by_key(&mut kept, |&(i, j)| (i != 0 && j != 0, i.max(j), i.min(j), i));
        kept.into_iter().map(|(i, j)| Constraint { i, j, bound: self.get(i, j) }).collect()
    }

    /// Displays the zone with `names[c]` for clock `c` (index 0 unused;
    /// missing names fall back to `x<c>`).
    pub fn display_with<'a>(&'a self, names: &'a [&'a str]) -> DisplayZone<'a> {
        DisplayZone { zone: self, names }
    }
}

/// A zone together with clock names, see [`Dbm::display_with`].
pub struct DisplayZone<'a> {
    zone: &'a Dbm,
    names: &'a [&'a str],
}

impl DisplayZone<'_> {
    fn name(&self, f: &mut fmt::Formatter<'_>, c: usize) -> fmt::Result {
        match self.names.get(c) {
            Some(s) if c > 0 => f.write_str(s),
            _ => write!(f, "x{c}"),
        }
    }
}

impl fmt::Display for DisplayZone<'_> {
    /// Conjunction such as `x1 ∈ [2,4] ∧ x2 - x1 < 3`; `true` for the
    /// unconstrained zone, `false` for the empty one.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let z = self.zone;
        if z.is_empty() {
            return f.write_str("false");
        }
        let cs = z.constraints();
        if cs.is_empty() {
            return f.write_str("true");
        }
        let find = |i: usize, j: usize| cs.iter().find(|c| c.i == i && c.j == j).map(|c| c.bound);
        let mut first = true;
        for c in &cs {
            // Each unordered pair is printed once, as an interval on
            // x_a - x_b with a the larger index (or the single clock).
            let (a, b) = if c.i > c.j { (c.i, c.j) } else { (c.j, c.i) };
            if (c.i, c.j) == (b, a) && find(a, b).is_some() {
                continue; // printed together with (a, b)
            }
            if !first {
                f.write_str(" ∧ ")?;
            }
            first = false;
            let upper = find(a, b);
            // x_b - x_a ≺ d means x_a - x_b ≻ -d.
            let mut lower = find(b, a);
            if b == 0 && lower.is_none() && upper == Some(Bound::LE_ZERO) {
                lower = Some(Bound::LE_ZERO); // the implicit x ≥ 0 makes x = 0
            }
            if b != 0 && upper.is_some_and(|u| u == Bound::LE_ZERO) && lower == upper {
                self.name(f, a)?;
                f.write_str(" = ")?;
                self.name(f, b)?;
                continue;
            }
            self.name(f, a)?;
            if b != 0 {
                f.write_str(" - ")?;
                self.name(f, b)?;
            }
            match (lower, upper) {
                (Some(l), Some(u)) if !l.is_strict() && !u.is_strict() && l.constant() == -u.constant() => {
                    write!(f, " = {}", u.constant())?
                }
                (Some(l), Some(u)) => write!(
                    f,
                    " ∈ {}{},{}{}",
                    if l.is_strict() { '(' } else { '[' },
                    -l.constant(),
                    u.constant(),
                    if u.is_strict() { ')' } else { ']' }
                )?,
                (Some(l), None) => write!(f, " {} {}", if l.is_strict() { ">" } else { "≥" }, -l.constant())?,
                (None, Some(u)) => write!(f, " {} {}", if u.is_strict() { "<" } else { "≤" }, u.constant())?,
                (None, None) => unreachable!("a listed constraint has a bound"),
            }
        }
        Ok(())
    }
}

impl fmt::Display for Dbm {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        self.display_with(&[]).fmt(f)
    }
}

impl Serialize for Dbm {
    /// `{"dim": 3, "empty": false, "constraints": [...], "text": "x1 ≤ 4"}`.
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let mut st = s.serialize_struct("Dbm", 4)?;
        st.serialize_field("dim", &self.dim())?;
        st.serialize_field("empty", &self.is_empty())?;
        let cs = if self.is_empty() { Vec::new() } else { self.constraints() };
        st.serialize_field("constraints", &cs)?;
        st.serialize_field("text", &self.to_string())?;
        st.end()
    }
}
