//! Packed difference bounds `x_i - x_j ≺ c`.

use std::fmt;

/// A bound `x_i - x_j ≺ c` with `≺ ∈ {<, ≤}`, packed into one `i32` as
/// `(c << 1) | 1` for `≤` and `c << 1` for `<`; [`Bound::INFINITY`] is
/// `i32::MAX` and stands for `< ∞`.
///
/// The packing makes the natural integer order the order of bounds by
/// tightness: `(c, <)` < `(c, ≤)` < `(c + 1, <)` < … < `∞`. Constants must
/// stay within `±2^28` so that the sum of two bounds cannot overflow.
#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Debug)]
pub struct Bound(i32);

impl Bound {
    /// No constraint: `< ∞`.
    pub const INFINITY: Bound = Bound(i32::MAX);
    /// `≤ 0`, the diagonal of every non-empty canonical zone.
    pub const LE_ZERO: Bound = Bound(1);
    /// `< 0`.
    pub const LT_ZERO: Bound = Bound(0);
    /// Largest constant magnitude the packing supports safely.
    pub const MAX_CONSTANT: i32 = 1 << 28;

    /// The non-strict bound `≤ c`.
    #[inline(always)]
    pub const fn le(c: i32) -> Bound {
        debug_assert!(c >= -Self::MAX_CONSTANT && c <= Self::MAX_CONSTANT);
        Bound((c << 1) | 1)
    }

    /// The strict bound `< c`.
    #[inline(always)]
    pub const fn lt(c: i32) -> Bound {
        debug_assert!(c >= -Self::MAX_CONSTANT && c <= Self::MAX_CONSTANT);
        Bound(c << 1)
    }

    /// `≤ c` if `strict` is false, `< c` otherwise.
    #[inline(always)]
    pub const fn new(c: i32, strict: bool) -> Bound {
        if strict {
            Bound::lt(c)
        } else {
            Bound::le(c)
        }
    }

    /// The constant `c` (meaningless for infinity).
    #[inline(always)]
    pub const fn constant(self) -> i32 {
        self.0 >> 1
    }

    /// True for `<` (infinity counts as strict).
    #[inline(always)]
    pub const fn is_strict(self) -> bool {
        self.0 & 1 == 0
    }

    /// True for the absent bound `< ∞`.
    #[inline(always)]
    pub const fn is_infinity(self) -> bool {
        self.0 == i32::MAX
    }

    /// Sum of two bounds, the weight of a two-edge path: `(a, ≺1) + (b, ≺2) =
    /// (a + b, ≤ iff both are ≤)`; anything plus infinity is infinity.
    #[inline(always)]
    #[allow(clippy::should_implement_trait)]
    pub fn add(self, other: Bound) -> Bound {
        // Clearing both strictness bits leaves an even sum; the combined bit is
        // set only when both were `≤`. The wrapping add may produce garbage
        // when an operand is infinite, but that value is then discarded by a
        // select the compiler turns into a conditional move.
        let sum = (self.0 & !1).wrapping_add(other.0 & !1) | (self.0 & other.0 & 1);
        if self.0 == i32::MAX || other.0 == i32::MAX {
            Bound::INFINITY
        } else {
            Bound(sum)
        }
    }

    /// The packed representation.
    #[inline(always)]
    pub const fn raw(self) -> i32 {
        self.0
    }

    /// Rebuilds a bound from [`Bound::raw`].
    #[inline(always)]
    pub const fn from_raw(r: i32) -> Bound {
        Bound(r)
    }

    /// The bound of the complementary constraint: `¬(x ≺ c)` is
    /// `-x ≺' -c` with the strictness flipped (`¬(x ≤ c)` is `-x < -c`).
    /// Infinity has no complement and is returned unchanged.
    #[inline(always)]
    pub fn negate_complement(self) -> Bound {
        if self.is_infinity() {
            self
        } else {
            // -(2c + s) = -2c - s; flipping s gives -2c + (1 - s) = 1 - raw.
            Bound(1 - self.0)
        }
    }
}

impl fmt::Display for Bound {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.is_infinity() {
            f.write_str("<∞")
        } else if self.is_strict() {
            write!(f, "<{}", self.constant())
        } else {
            write!(f, "≤{}", self.constant())
        }
    }
}
