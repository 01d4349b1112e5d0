//! The difference bound matrix and its operations.

use super::Bound;

const INF: Bound = Bound::INFINITY;
const LE0: Bound = Bound::LE_ZERO;

/// A clock zone as a difference bound matrix over `dim` indices; index 0 is
/// the reference clock (always 0) and `1..dim` are real clocks. Entry
/// `(i, j)` bounds `x_i - x_j`, stored row-major at `i * dim + j`.
///
/// Every operation expects and returns a canonical matrix (all entries are
/// tight), except [`Dbm::from_slice`] / [`Dbm::copy_from_slice`], whose input
/// the caller must [`Dbm::close`] unless it is already canonical. An empty
/// zone is stored in one normal form, so `==` and `Hash` are equality of the
/// sets of clock valuations.
///
/// ```
/// use plcsynth::zone::{Bound, Dbm};
///
/// // Two clocks, both start at 0; let time pass; guard 2 ≤ x1 ≤ 4.
/// let mut z = Dbm::zero(3);
/// z.up();
/// assert!(z.constrain_interval(1, Bound::le(-2), Bound::le(4)));
/// assert_eq!(z.to_string(), "x1 ∈ [2,4] ∧ x2 = x1");
/// z.reset(1);
/// assert!(z.contains_point(&[0, 0, 3], 1));
/// // x2 > 4 contradicts x2 ≤ 4.
/// assert!(!z.constrain(0, 2, Bound::lt(-4)));
/// assert!(z.is_empty());
/// ```
#[derive(Clone, PartialEq, Eq, Hash, Debug)]
pub struct Dbm {
    dim: usize,
    m: Box<[Bound]>,
}

/// Row `p` mutably and row `q` immutably (`p != q`), without copying.
#[inline(always)]
fn two_rows(m: &mut [Bound], n: usize, p: usize, q: usize) -> (&mut [Bound], &[Bound]) {
    debug_assert_ne!(p, q);
    if p < q {
        let (a, b) = m.split_at_mut(q * n);
        (&mut a[p * n..p * n + n], &b[..n])
    } else {
        let (a, b) = m.split_at_mut(p * n);
        (&mut b[..n], &a[q * n..q * n + n])
    }
}

/// `row[k] = min(row[k], via + other[k])` for every `k`: relaxation of one
/// row through one intermediate node. Kept branch-free so it vectorises.
#[inline(always)]
fn relax_row(row: &mut [Bound], via: Bound, other: &[Bound]) {
    for (x, &y) in row.iter_mut().zip(other) {
        let s = via.add(y);
        *x = if s < *x { s } else { *x };
    }
}

impl Dbm {
    /// The zone where every clock equals 0.
    pub fn zero(dim: usize) -> Dbm {
        assert!(dim >= 1, "a DBM needs the reference clock");
        Dbm { dim, m: vec![LE0; dim * dim].into_boxed_slice() }
    }

    /// The zone where every clock is `≥ 0` and nothing else is known.
    pub fn unconstrained(dim: usize) -> Dbm {
        assert!(dim >= 1, "a DBM needs the reference clock");
        let mut m = vec![INF; dim * dim].into_boxed_slice();
        for j in 0..dim {
            m[j] = LE0; // x_0 - x_j ≤ 0, i.e. x_j ≥ 0
            m[j * dim + j] = LE0;
        }
        Dbm { dim, m }
    }

    /// The empty zone in its normal form.
    pub fn empty(dim: usize) -> Dbm {
        assert!(dim >= 1, "a DBM needs the reference clock");
        Dbm { dim, m: vec![Bound::LT_ZERO; dim * dim].into_boxed_slice() }
    }

    /// Number of indices, reference clock included.
    #[inline]
    pub fn dim(&self) -> usize {
        self.dim
    }

    /// The bound on `x_i - x_j`.
    #[inline]
    pub fn get(&self, i: usize, j: usize) -> Bound {
        self.m[i * self.dim + j]
    }

    /// Sets one entry without restoring canonical form.
    #[inline]
    pub(super) fn m_set(&mut self, i: usize, j: usize, b: Bound) {
        self.m[i * self.dim + j] = b;
    }

    /// The raw row-major matrix, e.g. to store zones in an arena.
    #[inline]
    pub fn as_slice(&self) -> &[Bound] {
        &self.m
    }

    /// A zone from a row-major matrix of `dim * dim` bounds. The matrix is
    /// taken as is: call [`Dbm::close`] if it may not be canonical.
    pub fn from_slice(dim: usize, s: &[Bound]) -> Dbm {
        assert_eq!(s.len(), dim * dim, "matrix size does not match dim");
        Dbm { dim, m: s.into() }
    }

    /// Overwrites this zone with a matrix of the same dimension (no
    /// allocation).
    #[inline]
    pub fn copy_from_slice(&mut self, s: &[Bound]) {
        self.m.copy_from_slice(s);
    }

    /// True if no valuation satisfies the zone (canonical zones only).
    #[inline]
    pub fn is_empty(&self) -> bool {
        self.m[0] < LE0
    }

    /// Replaces the matrix by the normal form of the empty zone, so that all
    /// empty zones compare and hash equal.
    #[cold]
    fn mark_empty(&mut self) {
        self.m.fill(Bound::LT_ZERO);
    }

    /// Brings the matrix to canonical form (all-pairs shortest paths,
    /// Floyd–Warshall, O(dim³)). Returns false, leaving the zone marked
    /// empty, if the constraints are contradictory. Intermediate entries are
    /// sums along simple paths, so `dim · max|c|` must stay below 2^29.
    pub fn close(&mut self) -> bool {
        let n = self.dim;
        for i in 0..n {
            let d = &mut self.m[i * n + i];
            if *d < LE0 {
                self.mark_empty();
                return false;
            }
            *d = LE0;
        }
        for k in 0..n {
            for i in 0..n {
                // Row k cannot improve through itself unless a negative
                // cycle exists, which is caught on the row that closes it.
                if i == k {
                    continue;
                }
                let ik = self.m[i * n + k];
                if ik.is_infinity() {
                    continue;
                }
                let (ri, rk) = two_rows(&mut self.m, n, i, k);
                relax_row(ri, ik, rk);
                // Stop at the first negative cycle: continuing could only
                // push the constants further down towards overflow.
                if ri[i] < LE0 {
                    self.mark_empty();
                    return false;
                }
            }
        }
        true
    }

    /// Adds `x_i - x_j ≺ b` to a canonical zone and restores canonical form
    /// in O(dim²): only paths that use the new edge can become shorter.
    /// Returns false (and marks the zone empty) if the result is empty.
    pub fn constrain(&mut self, i: usize, j: usize, b: Bound) -> bool {
        let n = self.dim;
        if self.is_empty() {
            return false;
        }
        if b >= self.m[i * n + j] {
            return true; // already implied
        }
        // The new edge closes the cycle i → j → i; negative means empty.
        if b.add(self.m[j * n + i]) < LE0 {
            self.mark_empty();
            return false;
        }
        // New shortest p → q is min(old, p → i → j → q). Row j itself never
        // improves (that path contains the non-negative cycle j → i → j), so
        // it can be read while the other rows are updated in place; likewise
        // column i is stable. If p → i → j is not shorter than the old p → j,
        // the triangle inequality shows the whole row p is unchanged.
        for p in 0..n {
            if p == j {
                continue;
            }
            let pij = self.m[p * n + i].add(b);
            if pij >= self.m[p * n + j] {
                continue;
            }
            let (rp, rj) = two_rows(&mut self.m, n, p, j);
            relax_row(rp, pij, rj);
        }
        true
    }

    /// Adds `lower` as a bound on `x_0 - x_clock` (so `Bound::le(-3)` means
    /// `x ≥ 3`) and `upper` as a bound on `x_clock - x_0`. Returns false if
    /// the zone becomes empty.
    #[inline]
    pub fn constrain_interval(&mut self, clock: usize, lower: Bound, upper: Bound) -> bool {
        self.constrain(0, clock, lower) && self.constrain(clock, 0, upper)
    }

    /// Delay: every valuation reachable by letting time pass. O(dim); stays
    /// canonical because only upper bounds of clocks are dropped and all
    /// differences are preserved by a common delay.
    #[inline]
    pub fn up(&mut self) {
        if self.is_empty() {
            return;
        }
        let n = self.dim;
        for i in 1..n {
            self.m[i * n] = INF;
        }
    }

    /// Past: every valuation from which the zone can be reached by letting
    /// time pass. O(dim²); the result is canonical.
    pub fn down(&mut self) {
        if self.is_empty() {
            return;
        }
        let n = self.dim;
        // A clock can go back until it or another clock hits 0: its new
        // lower bound is the tightest x_i - x_j bound with x_i ≥ 0.
        for j in 1..n {
            let mut best = LE0;
            for i in 1..n {
                let b = self.m[i * n + j];
                if b < best {
                    best = b;
                }
            }
            self.m[j] = best;
        }
    }

    /// `x := 0`. O(dim); stays canonical since the clock now equals the
    /// reference clock, so it inherits row and column 0.
    #[inline]
    pub fn reset(&mut self, clock: usize) {
        debug_assert!(clock > 0 && clock < self.dim);
        if self.is_empty() {
            return;
        }
        let n = self.dim;
        self.m.copy_within(0..n, clock * n);
        for j in 0..n {
            self.m[j * n + clock] = self.m[j * n];
        }
        self.m[clock * n + clock] = LE0;
    }

    /// Forgets everything about `clock` except `clock ≥ 0` (used to make
    /// inactive clocks irrelevant). O(dim); stays canonical.
    #[inline]
    pub fn free(&mut self, clock: usize) {
        debug_assert!(clock > 0 && clock < self.dim);
        if self.is_empty() {
            return;
        }
        let n = self.dim;
        self.m[clock * n..clock * n + n].fill(INF);
        for j in 0..n {
            // The tightest bound on x_j - x is reached with x = 0.
            self.m[j * n + clock] = self.m[j * n];
        }
        self.m[clock * n + clock] = LE0;
    }

    /// Intersection with another zone of the same dimension; the result is
    /// canonical. Returns false if it is empty.
    pub fn intersect(&mut self, other: &Dbm) -> bool {
        assert_eq!(self.dim, other.dim, "dimension mismatch");
        if self.is_empty() {
            return false;
        }
        if other.is_empty() {
            self.mark_empty();
            return false;
        }
        let n = self.dim;
        let tighter = self.m.iter().zip(other.m.iter()).filter(|(a, b)| b < a).count();
        if tighter == 0 {
            return true;
        }
        if tighter <= n {
            // Few new constraints (the usual guard or invariant): add them
            // one by one at O(dim²) each instead of a cubic closure.
            for k in 0..n * n {
                let b = other.m[k];
                if b < self.m[k] && !self.constrain(k / n, k % n, b) {
                    return false;
                }
            }
            true
        } else {
            for (a, &b) in self.m.iter_mut().zip(other.m.iter()) {
                if b < *a {
                    *a = b;
                }
            }
            self.close()
        }
    }

    /// True if `other ⊆ self` (both canonical).
    #[inline]
    pub fn includes(&self, other: &Dbm) -> bool {
        debug_assert_eq!(self.dim, other.dim);
        if other.is_empty() {
            return true;
        }
        if self.is_empty() {
            return false;
        }
        // Branch-free within a row so it vectorises; early exit per row.
        let n = self.dim;
        other
            .m
            .chunks_exact(n)
            .zip(self.m.chunks_exact(n))
            .all(|(o, s)| o.iter().zip(s).fold(true, |ok, (a, b)| ok & (a <= b)))
    }

    /// True if every valuation of `other` is a valuation of `self` with some of the clocks in
    /// `lowered` (a bit set over the indices; bit 0 ignored) made smaller, each no lower than 0:
    /// `other ⊆ down(self)`, the closure of `self` downwards in those clocks (both canonical).
    ///
    /// The closure keeps every bound of `self` but those that bound a lowered clock from below
    /// (`x_i - x_p ≤ c`, `p` lowered); in canonical form these become `x_i - x_p ≤ (x_i - x_0
    /// bound)` and `x_p ≥ 0`, so the test is entry-wise like [`Dbm::includes`]. Where lowering a
    /// clock can only help (a deadline's clock, checked against upper bounds alone), `self`
    /// covers `other` for a game: whatever wins from `self` wins from `other`.
    ///
    /// ```
    /// use plcsynth::zone::{Bound, Dbm};
    ///
    /// // x1 = 0 and a deadline clock x2 at 5, or at 3.
    /// let at = |x2: i32| {
    ///     let mut z = Dbm::zero(3);
    ///     z.up();
    ///     assert!(z.constrain_interval(2, Bound::le(-x2), Bound::le(x2)));
    ///     z.reset(1);
    ///     z
    /// };
    /// let (late, early) = (at(5), at(3));
    /// assert!(!late.includes(&early));
    /// assert!(late.includes_lowered(&early, 0b100));
    /// assert!(!early.includes_lowered(&late, 0b100));
    /// assert!(!late.includes_lowered(&early, 0b010));
    /// ```
    pub fn includes_lowered(&self, other: &Dbm, lowered: u64) -> bool {
        debug_assert_eq!(self.dim, other.dim);
        if other.is_empty() {
            return true;
        }
        if self.is_empty() {
            return false;
        }
        includes_lowered(&self.m, &other.m, self.dim, lowered)
    }

    /// Classic k-normalisation (Extra_M): bounds above a clock's maximal
    /// constant become infinite, bounds below minus a clock's maximal
    /// constant become `< -max`. `max[c]` is the maximal constant compared
    /// with clock `c` (`max[0]` is ignored); a negative value marks an
    /// inactive clock, which is freed. The result is canonical and contains
    /// the original zone.
    // Matrix indices and per-clock constants share the index: plain loops read best.
    #[allow(clippy::needless_range_loop)]
    pub fn extrapolate_max(&mut self, max: &[i32]) {
        assert_eq!(max.len(), self.dim, "one constant per index expected");
        if self.is_empty() {
            return;
        }
        let n = self.dim;
        // Between active clocks the bounds beyond the constants are cut, which needs a closure
        // afterwards. Without a cut, freeing the inactive clocks keeps the zone canonical on its
        // own (the active clocks' part of a canonical zone is canonical, and a freed column is
        // column 0), so the cubic closure runs only after a cut.
        let mut cut = false;
        for i in 0..n {
            let mi = if i == 0 { 0 } else { max[i] };
            if mi < 0 {
                continue;
            }
            let upper_cut = Bound::le(mi);
            for j in 0..n {
                let mj = if j == 0 { 0 } else { max[j] };
                if i == j || mj < 0 {
                    continue;
                }
                let b = self.m[i * n + j];
                let nb = if b > upper_cut {
                    INF
                } else if b < Bound::lt(-mj) {
                    Bound::lt(-mj)
                } else {
                    b
                };
                if nb != b {
                    self.m[i * n + j] = nb;
                    cut = true;
                }
            }
        }
        let inactive = (1..n).filter(|&c| max[c] < 0);
        if !cut {
            inactive.for_each(|c| self.free(c));
            return;
        }
        // After a cut a freed column must come from the cut column 0: an inactive clock keeps
        // only `x ≥ 0`, and the closure restores its column.
        for c in inactive {
            for k in 0..n {
                if k != c {
                    self.m[c * n + k] = INF;
                    self.m[k * n + c] = if k == 0 { LE0 } else { INF };
                }
            }
        }
        self.close();
    }

    /// Extra_LU+ (Behrmann, Bouyer, Larsen, Pelánek 2004) with per-clock
    /// maximal lower-bound constants `lower[c]` and upper-bound constants
    /// `upper[c]` (index 0 ignored; negative means the clock is never
    /// compared that way). Coarser than [`Dbm::extrapolate_max`] with
    /// `max = max(lower, upper)`, still sound for reachability. The result
    /// is canonical and contains the original zone.
    // Matrix indices and per-clock constants share the index: plain loops read best.
    #[allow(clippy::needless_range_loop)]
    pub fn extrapolate_lu(&mut self, lower: &[i32], upper: &[i32]) {
        assert_eq!(lower.len(), self.dim, "one constant per index expected");
        assert_eq!(upper.len(), self.dim, "one constant per index expected");
        if self.is_empty() {
            return;
        }
        let n = self.dim;
        let mut changed = false;
        // Row 0 is rewritten last: the other rules read its original values.
        // All comparisons are on constants only, as in the paper.
        let above_upper = |m: &[Bound], j: usize| {
            // Every valuation has x_j > U(x_j) (value of -c_0j above U).
            upper[j] < 0 || m[j] < Bound::lt(-upper[j])
        };
        for i in 1..n {
            let li = lower[i];
            // Every valuation has x_i above L(x_i): no upper bound on x_i
            // (or on its differences) can be observed any more.
            let drop_row = li < 0 || self.m[i] < Bound::lt(-li);
            let cut = Bound::le(li.max(0));
            for j in 0..n {
                if i == j {
                    continue;
                }
                let b = self.m[i * n + j];
                if b.is_infinity() {
                    continue;
                }
                if drop_row || b > cut || (j != 0 && above_upper(&self.m, j)) {
                    self.m[i * n + j] = INF;
                    changed = true;
                }
            }
        }
        for j in 1..n {
            if above_upper(&self.m, j) {
                let nb = if upper[j] < 0 { LE0 } else { Bound::lt(-upper[j]) };
                if self.m[j] != nb {
                    self.m[j] = nb;
                    changed = true;
                }
            }
        }
        if changed {
            self.close();
        }
    }

    /// Exact membership test for the rational valuation `v / denominator`
    /// (`v[0]` must be 0).
    pub fn contains_point(&self, v: &[i64], denominator: i64) -> bool {
        debug_assert_eq!(v.len(), self.dim);
        debug_assert!(denominator > 0);
        if self.is_empty() {
            return false;
        }
        let n = self.dim;
        for i in 0..n {
            for j in 0..n {
                let b = self.m[i * n + j];
                if b.is_infinity() {
                    continue;
                }
                let diff = v[i] - v[j];
                let lim = b.constant() as i64 * denominator;
                if diff > lim || (diff == lim && b.is_strict()) {
                    return false;
                }
            }
        }
        true
    }

    /// Some valuation of the zone as integers over the returned common
    /// denominator (`dim`), or `None` if the zone is empty. Allocates; meant
    /// for explanations and tests, not for the exploration loop.
    pub fn sample_point(&self) -> Option<(Vec<i64>, i64)> {
        if self.is_empty() {
            return None;
        }
        let n = self.dim;
        // Scale every constant by `den` and tighten strict bounds by one:
        // the system becomes non-strict over the integers and keeps a
        // solution. A cycle of integer weight w ≥ 1 has at most n edges, so
        // its scaled weight w·n - (#strict) stays ≥ 0, and a zero-weight
        // cycle of a non-empty zone has no strict edge.
        let den = n as i64;
        let mut w: Vec<Option<i64>> = self
            .m
            .iter()
            .map(|&b| (!b.is_infinity()).then(|| b.constant() as i64 * den - i64::from(b.is_strict())))
            .collect();
        // The tightening breaks canonical form, so close again (in i64).
        for k in 0..n {
            for i in 0..n {
                for j in 0..n {
                    if let (Some(a), Some(b)) = (w[i * n + k], w[k * n + j]) {
                        match w[i * n + j] {
                            Some(c) if c <= a + b => {}
                            _ => w[i * n + j] = Some(a + b),
                        }
                    }
                }
            }
        }
        // On a closed system, giving each clock in turn its smallest value
        // consistent with the clocks already fixed never gets stuck.
        let mut v = vec![0i64; n];
        for k in 1..n {
            let mut lo = i64::MIN;
            for j in 0..k {
                if let Some(c) = w[j * n + k] {
                    lo = lo.max(v[j] - c);
                }
            }
            v[k] = lo;
        }
        debug_assert!(self.contains_point(&v, den));
        Some((v, den))
    }
}

/// [`includes_lowered`], and the two zones agree on every other clock: their projections
/// onto the clocks not in `lowered` (the sub-matrices of canonical zones) are equal, so they
/// differ only in how far the lowered clocks have run.
///
/// ```
/// use plcsynth::zone::{includes_lowered, includes_only_lowered, Bound, Dbm};
///
/// // A deadline clock x2 at 5 or at 3, x1 = 0; and x2 at 5 with x1 anywhere in [0, 1].
/// let at = |x2: i32, x1_max: i32| {
///     let mut z = Dbm::zero(3);
///     z.up();
///     assert!(z.constrain_interval(2, Bound::le(-x2), Bound::le(x2)));
///     z.reset(1);
///     z.up();
///     assert!(z.constrain_interval(1, Bound::le(0), Bound::le(x1_max)));
///     z
/// };
/// let (late, early, wide) = (at(5, 0), at(3, 0), at(5, 1));
/// assert!(includes_only_lowered(late.as_slice(), early.as_slice(), 3, 0b100));
/// assert!(includes_lowered(wide.as_slice(), early.as_slice(), 3, 0b100));
/// assert!(!includes_only_lowered(wide.as_slice(), early.as_slice(), 3, 0b100));
/// ```
pub fn includes_only_lowered(big: &[Bound], small: &[Bound], n: usize, lowered: u64) -> bool {
    let kept = |c: usize| c == 0 || lowered >> c & 1 == 0;
    includes_lowered(big, small, n, lowered)
        && (0..n).filter(|&i| kept(i)).all(|i| (0..n).filter(|&j| kept(j)).all(|j| big[i * n + j] == small[i * n + j]))
}

/// [`Dbm::includes_lowered`] on the matrices ([`Dbm::as_slice`]) of two canonical, non-empty
/// zones of dimension `n`: for callers that store zones as slices.
pub fn includes_lowered(big: &[Bound], small: &[Bound], n: usize, lowered: u64) -> bool {
    let lowered = lowered & !1;
    (0..n).all(|i| {
        let (b, s) = (&big[i * n..i * n + n], &small[i * n..i * n + n]);
        (0..n).all(|j| {
            let bound = if j == i || lowered >> j & 1 == 0 {
                b[j]
            } else if i == 0 {
                LE0 // x_j ≥ 0 is all that is left of its lower bounds
            } else {
                b[0] // x_i - x_j ≤ x_i, the tightest left once x_j may go down to 0
            };
            s[j] <= bound
        })
    })
}
