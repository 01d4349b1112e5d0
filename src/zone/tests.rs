//! Unit tests on hand-computed zones and property tests against brute-force
//! evaluation on rational sample points.

#![allow(clippy::needless_range_loop)]

use super::*;
use proptest::prelude::*;
use std::collections::hash_map::DefaultHasher;
use std::collections::HashSet;
use std::hash::{Hash, Hasher};

fn le(c: i32) -> Bound {
    Bound::le(c)
}
fn lt(c: i32) -> Bound {
    Bound::lt(c)
}

/// Checks the triangle inequality on every triple (canonical form).
fn is_canonical(z: &Dbm) -> bool {
    if z.is_empty() {
        return *z == Dbm::empty(z.dim());
    }
    let n = z.dim();
    (0..n).all(|i| z.get(i, i) == Bound::LE_ZERO)
        && (0..n).all(|i| (0..n).all(|j| (0..n).all(|k| z.get(i, j) <= z.get(i, k).add(z.get(k, j)))))
}

fn hash_of(z: &Dbm) -> u64 {
    let mut h = DefaultHasher::new();
    z.hash(&mut h);
    h.finish()
}

// ---------------------------------------------------------------- bounds

#[test]
fn bound_encoding_and_order() {
    assert_eq!(le(3).raw(), 7);
    assert_eq!(lt(3).raw(), 6);
    assert_eq!(le(-2).constant(), -2);
    assert!(lt(-2).is_strict() && !le(-2).is_strict());
    assert!(lt(3) < le(3) && le(3) < lt(4) && lt(4) < Bound::INFINITY);
    assert!(Bound::LT_ZERO < Bound::LE_ZERO);
    assert_eq!(Bound::from_raw(le(5).raw()), le(5));
    assert!(Bound::INFINITY.is_infinity() && !le(5).is_infinity());
}

#[test]
fn bound_addition() {
    assert_eq!(le(3).add(le(2)), le(5));
    assert_eq!(le(3).add(lt(2)), lt(5));
    assert_eq!(lt(3).add(lt(-3)), Bound::LT_ZERO);
    assert_eq!(le(1).add(le(-1)), Bound::LE_ZERO);
    assert_eq!(Bound::INFINITY.add(le(-5)), Bound::INFINITY);
    assert_eq!(lt(-5).add(Bound::INFINITY), Bound::INFINITY);
    assert_eq!(Bound::INFINITY.add(Bound::INFINITY), Bound::INFINITY);
    let big = Bound::MAX_CONSTANT;
    assert_eq!(le(big).add(le(big)).constant(), 2 * big);
    // Sums may leave the range of constructible bounds (±MAX_CONSTANT) but stay exact.
    let sum = lt(-big).add(le(-big));
    assert_eq!((sum.constant(), sum.is_strict()), (-2 * big, true));
}

#[test]
fn bound_complement() {
    // not (x ≤ 3) is x > 3, i.e. -x < -3.
    assert_eq!(le(3).negate_complement(), lt(-3));
    // not (x < 3) is x ≥ 3, i.e. -x ≤ -3.
    assert_eq!(lt(3).negate_complement(), le(-3));
    assert_eq!(le(3).negate_complement().negate_complement(), le(3));
}

// ------------------------------------------------------- hand-made zones

#[test]
fn zero_and_unconstrained() {
    let z = Dbm::zero(3);
    assert!(z.contains_point(&[0, 0, 0], 1));
    assert!(!z.contains_point(&[0, 1, 0], 4));
    let u = Dbm::unconstrained(3);
    assert!(u.contains_point(&[0, 100, 3], 1));
    assert!(u.includes(&z) && !z.includes(&u));
    assert!(is_canonical(&z) && is_canonical(&u));
    assert_eq!(u.to_string(), "true");
}

#[test]
fn strictness_decides_emptiness() {
    let mut z = Dbm::unconstrained(2);
    assert!(z.constrain(1, 0, lt(3))); // x < 3
    assert!(!z.constrain(0, 1, le(-3))); // x ≥ 3
    assert!(z.is_empty());
    assert_eq!(z, Dbm::empty(2));

    let mut z = Dbm::unconstrained(2);
    assert!(z.constrain_interval(1, le(-3), le(3))); // x = 3
    assert!(z.contains_point(&[0, 3], 1));
    assert!(!z.contains_point(&[0, 11], 4));
    assert_eq!(z.to_string(), "x1 = 3");

    // x > 3 ∧ x ≤ 3
    let mut z = Dbm::unconstrained(2);
    assert!(z.constrain(0, 1, lt(-3)));
    assert!(!z.constrain(1, 0, le(3)));
    assert_eq!(z.to_string(), "false");
}

#[test]
fn close_propagates_strictness() {
    // x1 < 3, x2 - x1 ≤ 2, given unclosed.
    let mut m = Dbm::unconstrained(3).as_slice().to_vec();
    m[3] = lt(3); // (1,0)
    m[2 * 3 + 1] = le(2); // (2,1)
    let mut z = Dbm::from_slice(3, &m);
    assert!(z.close());
    assert_eq!(z.get(2, 0), lt(5));
    assert!(is_canonical(&z));

    // x1 ≤ 3 ∧ x1 - x2 ≥ 1 ∧ x2 - ... contradiction through a cycle.
    m[1] = le(-4); // x1 ≥ 4
    let mut z = Dbm::from_slice(3, &m);
    assert!(!z.close());
    assert!(z.is_empty());
    assert_eq!(z, Dbm::empty(3));
}

#[test]
fn up_down_reset_free() {
    let mut z = Dbm::zero(3);
    z.up();
    assert!(is_canonical(&z));
    assert_eq!(z.get(1, 0), Bound::INFINITY);
    assert_eq!(z.get(1, 2), Bound::LE_ZERO);
    assert_eq!(z.to_string(), "x2 = x1");
    assert!(z.constrain_interval(1, le(-2), le(4)));
    z.reset(1); // x1 = 0, x2 ∈ [2,4]
    assert!(is_canonical(&z));
    assert_eq!(z.get(2, 0), le(4));
    assert_eq!(z.get(0, 2), le(-2));
    assert_eq!(z.get(2, 1), le(4));
    assert_eq!(z.get(1, 2), le(-2));
    assert_eq!(z.to_string(), "x1 = 0 ∧ x2 ∈ [2,4]");
    z.up(); // x2 - x1 ∈ [2,4]
    assert_eq!(z.to_string(), "x2 - x1 ∈ [2,4]");
    assert!(z.constrain(1, 0, lt(1))); // x1 < 1
    assert_eq!(z.to_string(), "x1 < 1 ∧ x2 - x1 ∈ [2,4]");
    let before = z.clone();
    z.down(); // the past: x1 ≥ 0, x2 ≥ 2 - no, x2 - x1 ∈ [2,4] keeps x2 ≥ 2
    assert!(is_canonical(&z));
    assert_eq!(z.get(0, 2), le(-2));
    assert_eq!(z.get(0, 1), Bound::LE_ZERO);
    assert!(z.includes(&before));
    z.free(2);
    assert!(is_canonical(&z));
    assert_eq!(z.to_string(), "x1 < 1");
}

#[test]
fn intersect_and_includes() {
    let mut a = Dbm::unconstrained(3);
    a.constrain_interval(1, le(-1), le(5));
    let mut b = Dbm::unconstrained(3);
    b.constrain_interval(1, lt(-4), Bound::INFINITY);
    b.constrain(2, 1, le(0)); // x2 ≤ x1
    let mut c = a.clone();
    assert!(c.intersect(&b));
    assert!(is_canonical(&c));
    assert_eq!(c.to_string(), "x1 ∈ (4,5] ∧ x2 - x1 ≤ 0");
    assert!(a.includes(&c) && b.includes(&c));
    assert!(!c.includes(&a));
    let mut d = Dbm::unconstrained(3);
    d.constrain(1, 0, le(4));
    assert!(!d.intersect(&c));
    assert!(d.is_empty());
    assert!(a.includes(&d) && !d.includes(&a));
}

#[test]
fn extrapolation_by_hand() {
    // x1 ∈ [7,9], x2 = 0 with max = 5 for x1, 3 for x2: x1 > 5.
    let mut z = Dbm::unconstrained(3);
    z.constrain_interval(1, le(-7), le(9));
    z.constrain_interval(2, le(0), le(0));
    let mut e = z.clone();
    e.extrapolate_max(&[0, 5, 3]);
    assert!(is_canonical(&e));
    assert_eq!(e.to_string(), "x1 > 5 ∧ x2 = 0");
    // An inactive clock is freed.
    let mut f = z.clone();
    f.extrapolate_max(&[0, 10, -1]);
    assert_eq!(f.to_string(), "x1 ∈ [7,9]");
    // A cut and a freed clock together: x2's column comes from the cut column 0 (x1 - x2 is
    // unbounded once x1 > 5 forgets its upper bound), not from column 0 before the cut.
    let mut h = z.clone();
    h.extrapolate_max(&[0, 5, -1]);
    assert!(is_canonical(&h));
    assert_eq!(h.to_string(), "x1 > 5");
    assert_eq!(h.get(1, 2), Bound::INFINITY);
    // LU: x1 has no lower-bound guard above 2 and upper-bound guards up to 8:
    // every valuation has x1 > L, so its upper bounds go; x1 ≥ 7 stays.
    let mut g = z.clone();
    g.extrapolate_lu(&[0, 2, 0], &[0, 8, 0]);
    assert!(is_canonical(&g));
    assert_eq!(g.to_string(), "x1 ≥ 7 ∧ x2 = 0");
}

#[test]
fn display_and_serialise() {
    let mut z = Dbm::unconstrained(3);
    z.constrain_interval(1, le(-2), le(4));
    z.constrain(2, 1, lt(3));
    assert_eq!(z.to_string(), "x1 ∈ [2,4] ∧ x2 - x1 < 3");
    assert_eq!(z.display_with(&["", "timer", "t2"]).to_string(), "timer ∈ [2,4] ∧ t2 - timer < 3");
    let json = serde_json::to_value(&z).unwrap();
    assert_eq!(json["dim"], 3);
    assert_eq!(json["empty"], false);
    assert_eq!(json["text"], "x1 ∈ [2,4] ∧ x2 - x1 < 3");
    assert_eq!(json["constraints"].as_array().unwrap().len(), 3);
    // x0 - x1 ≤ -2, i.e. x1 ≥ 2.
    assert_eq!(json["constraints"][0]["i"], 0);
    assert_eq!(json["constraints"][0]["c"], -2);
    assert_eq!(json["constraints"][0]["strict"], false);
    let e = serde_json::to_value(Dbm::empty(3)).unwrap();
    assert_eq!(e["empty"], true);
    assert_eq!(e["text"], "false");
}

#[test]
fn sample_point_respects_strict_bounds() {
    let mut z = Dbm::unconstrained(4);
    z.constrain(0, 1, lt(0)); // x1 > 0
    z.constrain(2, 1, lt(0)); // x2 < x1
    z.constrain(0, 2, lt(0)); // x2 > 0
    z.constrain(1, 0, le(1)); // x1 ≤ 1
    z.constrain(3, 2, lt(0)); // x3 < x2
    z.constrain(0, 3, lt(0)); // x3 > 0
    let (v, den) = z.sample_point().unwrap();
    assert!(z.contains_point(&v, den));
    assert!(Dbm::empty(4).sample_point().is_none());
}

// -------------------------------------------------------------- property

/// One step in building a random zone.
#[derive(Clone, Debug)]
enum Op {
    /// `x_i - x_j ≺ c` on indices taken modulo dim.
    Constrain(usize, usize, i32, bool),
    Up,
    Reset(usize),
    Free(usize),
}

fn op() -> impl Strategy<Value = Op> {
    prop_oneof![
        // Single-clock guards, the common case.
        (1..4usize, any::<bool>(), 0..=8i32, any::<bool>()).prop_map(|(x, upper, c, s)| {
            if upper {
                Op::Constrain(x, 0, c, s)
            } else {
                Op::Constrain(0, x, -c, s)
            }
        }),
        (1..4usize, 1..4usize, -8..=8i32, any::<bool>()).prop_map(|(i, j, c, s)| Op::Constrain(i, j, c, s)),
        Just(Op::Up),
        Just(Op::Up),
        (1..4usize).prop_map(Op::Reset),
        (1..4usize).prop_map(Op::Free),
    ]
}

fn build(dim: usize, from_zero: bool, ops: &[Op]) -> Dbm {
    let mut z = if from_zero { Dbm::zero(dim) } else { Dbm::unconstrained(dim) };
    if dim == 1 {
        return z;
    }
    let clock = |x: usize| 1 + (x - 1) % (dim - 1);
    for o in ops {
        match *o {
            Op::Constrain(i, j, c, s) => {
                let (i, j) = (if i == 0 { 0 } else { clock(i) }, if j == 0 { 0 } else { clock(j) });
                if i != j {
                    z.constrain(i, j, Bound::new(c, s));
                }
            }
            Op::Up => z.up(),
            Op::Reset(x) => z.reset(clock(x)),
            Op::Free(x) => z.free(clock(x)),
        }
    }
    z
}

fn zone_of_dim(dim: usize) -> impl Strategy<Value = Dbm> {
    (any::<bool>(), prop::collection::vec(op(), 0..8)).prop_map(move |(z, ops)| build(dim, z, &ops))
}

fn zone() -> impl Strategy<Value = Dbm> {
    (1..=4usize).prop_flat_map(zone_of_dim)
}

fn two_zones() -> impl Strategy<Value = (Dbm, Dbm)> {
    (1..=4usize).prop_flat_map(|d| (zone_of_dim(d), zone_of_dim(d)))
}

/// Grid step is 1/`DEN`; the box is [0, `BOX`]^clocks.
const DEN: i64 = 4;
const BOX: i64 = 12;

/// Calls `f` on every grid point of the box (`v[0] = 0`, units of 1/DEN).
///
/// Why this grid is fine enough for the zones here (at most 3 real clocks,
/// integer constants): scale all constants by `dim` (≤ 4) and turn each
/// strict bound `< c` into `≤ c - 1/dim`. A cycle of integer weight w ≥ 1
/// has at most `dim` edges, so its weight stays ≥ 0; zero-weight cycles of a
/// non-empty zone have no strict edge. The tightened system therefore still
/// has solutions, one with all coordinates multiples of 1/dim (shortest-path
/// distances), which lie on the 1/4 grid. So a zone inside the box is empty
/// iff no grid point lies in it.
fn for_each_point(dim: usize, mut f: impl FnMut(&[i64])) {
    let mut v = vec![0i64; dim];
    loop {
        f(&v);
        let mut k = 1;
        loop {
            if k >= dim {
                return;
            }
            if v[k] < BOX * DEN {
                v[k] += 1;
                break;
            }
            v[k] = 0;
            k += 1;
        }
    }
}

fn satisfies(v: &[i64], den: i64, i: usize, j: usize, b: Bound) -> bool {
    if b.is_infinity() {
        return true;
    }
    let d = v[i] - v[j];
    let lim = b.constant() as i64 * den;
    d < lim || (d == lim && !b.is_strict())
}

/// Some value s ≥ 0 (in units of 1/(2·DEN)) with `v[x := s]` in `z`, if one
/// exists. The feasible values form an interval whose finite endpoints are
/// `v_j ± c` for entries of `z` involving `x`: multiples of 1/DEN. A
/// non-degenerate interval between such endpoints is at least 1/DEN long,
/// so an endpoint or an endpoint ± 1/(2·DEN) lies in it.
fn exists_value_for(z: &Dbm, v: &[i64], x: usize) -> bool {
    let n = z.dim();
    let mut w: Vec<i64> = v.iter().map(|&a| 2 * a).collect();
    let mut cands = vec![0i64];
    for j in 0..n {
        if j == x {
            continue;
        }
        for b in [z.get(x, j), z.get(j, x)] {
            if !b.is_infinity() {
                let c = b.constant() as i64 * 2 * DEN;
                cands.extend([w[j] + c, w[j] - c]);
            }
        }
    }
    let all: Vec<i64> = cands.iter().flat_map(|&e| [e - 1, e, e + 1]).filter(|&s| s >= 0).collect();
    all.into_iter().any(|s| {
        w[x] = s;
        z.contains_point(&w, 2 * DEN)
    })
}

/// Some delay t ≥ 0 with `v - t` in `z`; same endpoint argument as above,
/// the endpoints being `v_i - c_i0` and `v_i + c_0i`.
fn exists_delay_back(z: &Dbm, v: &[i64]) -> bool {
    let n = z.dim();
    let w: Vec<i64> = v.iter().map(|&a| 2 * a).collect();
    let mut cands = vec![0i64];
    for i in 1..n {
        for (b, sign) in [(z.get(i, 0), -1), (z.get(0, i), 1)] {
            if !b.is_infinity() {
                cands.push(w[i] + sign * b.constant() as i64 * 2 * DEN);
            }
        }
    }
    let min_v = w[1..].iter().copied().min().unwrap_or(0);
    let mut u = w.clone();
    cands.iter().flat_map(|&e| [e - 1, e, e + 1]).filter(|&t| t >= 0 && t <= min_v).any(|t| {
        for k in 1..n {
            u[k] = w[k] - t;
        }
        z.contains_point(&u, 2 * DEN)
    })
}

/// Some delay t ≥ 0 with `v + t` in `z`; endpoints `c_i0 - v_i` and
/// `-c_0i - v_i`, as above.
fn exists_delay_forward(z: &Dbm, v: &[i64]) -> bool {
    let n = z.dim();
    let w: Vec<i64> = v.iter().map(|&a| 2 * a).collect();
    let mut cands = vec![0i64];
    for i in 1..n {
        for (b, sign) in [(z.get(i, 0), 1), (z.get(0, i), -1)] {
            if !b.is_infinity() {
                cands.push(sign * b.constant() as i64 * 2 * DEN - w[i]);
            }
        }
    }
    let mut u = w.clone();
    cands.iter().flat_map(|&e| [e - 1, e, e + 1]).filter(|&t| t >= 0).any(|t| {
        for k in 1..n {
            u[k] = w[k] + t;
        }
        z.contains_point(&u, 2 * DEN)
    })
}

fn random_matrix() -> impl Strategy<Value = (usize, Vec<Option<(i32, bool)>>)> {
    (1..=4usize).prop_flat_map(|d| {
        (Just(d), prop::collection::vec(prop::option::weighted(0.6, (-8..=8i32, any::<bool>())), d * d))
    })
}

/// As `tests/common`'s `proptest_config`: `base` cases times `PLCSYNTH_PROPTEST_SCALE`.
fn proptest_config(base: u32) -> ProptestConfig {
    let scale = std::env::var("PLCSYNTH_PROPTEST_SCALE").ok().and_then(|v| v.parse::<u32>().ok()).unwrap_or(1).max(1);
    ProptestConfig::with_cases(base.saturating_mul(scale))
}

proptest! {
    #![proptest_config(proptest_config(200))]

    #[test]
    fn closure_keeps_points_and_is_canonical((dim, entries) in random_matrix()) {
        let mut m = Dbm::unconstrained(dim).as_slice().to_vec();
        for i in 0..dim {
            for j in 0..dim {
                if i == j { continue; }
                if let Some((c, s)) = entries[i * dim + j] {
                    let b = Bound::new(c, s);
                    // Keep clocks non-negative and below 8, inside the box.
                    let cap = if i == 0 { Bound::LE_ZERO } else if j == 0 { le(8) } else { Bound::INFINITY };
                    m[i * dim + j] = b.min(cap);
                }
            }
        }
        for i in 1..dim { m[i * dim] = m[i * dim].min(le(8)); }
        let raw = Dbm::from_slice(dim, &m);
        let mut z = raw.clone();
        let nonempty = z.close();
        prop_assert_eq!(nonempty, !z.is_empty());
        prop_assert!(is_canonical(&z));
        let mut again = z.clone();
        again.close();
        prop_assert_eq!(&again, &z);
        let mut any = false;
        for_each_point(dim, |v| {
            let a = raw.contains_point(v, DEN);
            any |= a;
            assert_eq!(a, z.contains_point(v, DEN), "point {v:?}");
        });
        prop_assert_eq!(any, nonempty);
    }

    #[test]
    fn constrain_is_conjunction(z in zone(), i in 0..4usize, j in 0..4usize, c in -8..=8i32, s in any::<bool>()) {
        let (i, j) = (i % z.dim(), j % z.dim());
        let b = Bound::new(c, s);
        let mut y = z.clone();
        let ok = y.constrain(i, j, b);
        prop_assert_eq!(ok, !y.is_empty());
        prop_assert!(is_canonical(&y));
        for_each_point(z.dim(), |v| {
            assert_eq!(y.contains_point(v, DEN), z.contains_point(v, DEN) && satisfies(v, DEN, i, j, b));
        });
    }

    #[test]
    fn emptiness_is_exact(z in zone()) {
        prop_assert!(is_canonical(&z));
        let mut boxed = z.clone();
        for x in 1..z.dim() {
            boxed.constrain(x, 0, le(BOX as i32));
        }
        let mut any = false;
        for_each_point(z.dim(), |v| any |= z.contains_point(v, DEN));
        prop_assert_eq!(any, !boxed.is_empty());
        if let Some((v, den)) = z.sample_point() {
            prop_assert!(z.contains_point(&v, den));
        } else {
            prop_assert!(z.is_empty());
        }
    }

    #[test]
    fn includes_lowered_is_inclusion_in_the_downward_closure((a, b) in two_zones(), lowered in 0..16u64) {
        // Inside the box, so that the grid decides (see `for_each_point`).
        let boxed = |z: &Dbm| {
            let mut z = z.clone();
            for c in 1..z.dim() {
                z.constrain(c, 0, le(BOX as i32));
            }
            z
        };
        let (a, b) = (boxed(&a), boxed(&b));
        let n = a.dim();
        let lowered = lowered & ((1 << n) - 1);
        // `a` in units of 1/DEN, where every grid point is an integer point.
        let scaled = {
            let m: Vec<Bound> = a
                .as_slice()
                .iter()
                .map(|b| if b.is_infinity() { *b } else { Bound::new(b.constant() * DEN as i32, b.is_strict()) })
                .collect();
            Dbm::from_slice(n, &m)
        };
        // v ∈ down(a): some u ∈ a equals v but for lowered clocks, where it is at least v.
        let in_closure = |v: &[i64]| {
            let mut u = scaled.clone();
            (1..n).all(|c| {
                let x = v[c] as i32;
                let lower = u.constrain(0, c, le(-x));
                lower && (lowered >> c & 1 == 1 || u.constrain(c, 0, le(x)))
            })
        };
        let mut expected = true;
        for_each_point(n, |v| expected &= !b.contains_point(v, DEN) || in_closure(v));
        prop_assert_eq!(a.includes_lowered(&b, lowered), expected);
        prop_assert_eq!(a.includes_lowered(&b, 0), a.includes(&b));
    }

    #[test]
    fn up_is_delay(z in zone()) {
        let mut y = z.clone();
        y.up();
        prop_assert!(is_canonical(&y));
        prop_assert!(y.includes(&z));
        for_each_point(z.dim(), |v| {
            assert_eq!(y.contains_point(v, DEN), exists_delay_back(&z, v), "point {v:?}");
        });
    }

    #[test]
    fn down_is_past(z in zone()) {
        let mut y = z.clone();
        y.down();
        prop_assert!(is_canonical(&y));
        prop_assert!(y.includes(&z));
        for_each_point(z.dim(), |v| {
            assert_eq!(y.contains_point(v, DEN), exists_delay_forward(&z, v), "point {v:?}");
        });
    }

    #[test]
    fn reset_and_free_are_projections(z in zone(), x in 1..4usize) {
        prop_assume!(z.dim() > 1);
        let x = 1 + (x - 1) % (z.dim() - 1);
        let mut r = z.clone();
        r.reset(x);
        let mut f = z.clone();
        f.free(x);
        prop_assert!(is_canonical(&r));
        prop_assert!(is_canonical(&f));
        prop_assert!(f.includes(&r));
        for_each_point(z.dim(), |v| {
            let ex = exists_value_for(&z, v, x);
            assert_eq!(f.contains_point(v, DEN), ex, "free, point {v:?}");
            assert_eq!(r.contains_point(v, DEN), v[x] == 0 && ex, "reset, point {v:?}");
        });
    }

    #[test]
    fn intersect_and_includes_match_points((a, b) in two_zones()) {
        let mut c = a.clone();
        let ok = c.intersect(&b);
        prop_assert_eq!(ok, !c.is_empty());
        prop_assert!(is_canonical(&c));
        prop_assert!(a.includes(&c) && b.includes(&c));
        let a_in_b = b.includes(&a);
        let mut witness_outside = false;
        for_each_point(a.dim(), |v| {
            let (ia, ib) = (a.contains_point(v, DEN), b.contains_point(v, DEN));
            assert_eq!(c.contains_point(v, DEN), ia && ib);
            if a_in_b { assert!(!ia || ib, "includes but {v:?} is outside"); }
            witness_outside |= ia && !ib;
        });
        prop_assert!(!(witness_outside && a_in_b));
        // Inclusion is exact for canonical zones: a ⊆ b iff a ∩ b = a.
        prop_assert_eq!(a_in_b, c == a);
    }

    #[test]
    fn same_points_same_value_and_hash(z in zone()) {
        // Rebuild from the displayed constraints: same set, so equal.
        let mut r = Dbm::unconstrained(z.dim());
        for c in z.constraints() {
            r.constrain(c.i, c.j, c.bound);
        }
        prop_assert_eq!(&r, &z);
        prop_assert_eq!(hash_of(&r), hash_of(&z));
        // z ∩ up(z) = z, computed along another path.
        let mut u = z.clone();
        u.up();
        u.intersect(&z);
        prop_assert_eq!(&u, &z);
        prop_assert_eq!(hash_of(&u), hash_of(&z));
        // Every listed constraint is needed.
        let cs = z.constraints();
        if !z.is_empty() {
            for skip in 0..cs.len() {
                let mut r = Dbm::unconstrained(z.dim());
                for (k, c) in cs.iter().enumerate() {
                    if k != skip { r.constrain(c.i, c.j, c.bound); }
                }
                prop_assert_ne!(&r, &z);
            }
        }
    }

    #[test]
    fn extrapolate_max_sound(z in zone(), max in prop::collection::vec(-1..=8i32, 4)) {
        let n = z.dim();
        let max = &max[..n];
        let mut e = z.clone();
        e.extrapolate_max(max);
        prop_assert!(is_canonical(&e));
        prop_assert!(e.includes(&z));
        // Reference: z with its inactive clocks forgotten.
        let mut f = z.clone();
        for (x, &m) in max.iter().enumerate().skip(1) {
            if m < 0 { f.free(x); }
        }
        prop_assert!(e.includes(&f));
        for_each_point(n, |v| {
            let small = (1..n).all(|c| max[c] < 0 || v[c] <= max[c] as i64 * DEN);
            if small {
                assert_eq!(e.contains_point(v, DEN), f.contains_point(v, DEN), "point {v:?}");
            }
        });
    }

    /// The extrapolation frees inactive clocks without a closure and closes only after a cut:
    /// the zone is the one of the textbook form, every bound cut or freed and then one closure.
    #[test]
    fn extrapolate_max_is_the_textbook_closure(z in zone(), max in prop::collection::vec(-1..=8i32, 4)) {
        let n = z.dim();
        let max = &max[..n];
        let mut e = z.clone();
        e.extrapolate_max(max);
        if !z.is_empty() {
            let mut m: Vec<Bound> = z.as_slice().to_vec();
            for i in 0..n {
                let mi = if i == 0 { 0 } else { max[i] };
                for j in (0..n).filter(|&j| j != i) {
                    let mj = if j == 0 { 0 } else { max[j] };
                    let b = m[i * n + j];
                    m[i * n + j] = if mi < 0 || mj < 0 {
                        if i == 0 { Bound::le(0) } else { Bound::INFINITY }
                    } else if b > Bound::le(mi.max(0)) {
                        Bound::INFINITY
                    } else if b < Bound::lt(-mj) {
                        Bound::lt(-mj)
                    } else {
                        b
                    };
                }
            }
            let mut textbook = Dbm::from_slice(n, &m);
            textbook.close();
            prop_assert_eq!(e.as_slice(), textbook.as_slice());
        }
    }

    #[test]
    fn extrapolate_lu_sound(z in zone(), l in prop::collection::vec(-1..=8i32, 4), u in prop::collection::vec(-1..=8i32, 4)) {
        let n = z.dim();
        let (l, u) = (&l[..n], &u[..n]);
        let mut e = z.clone();
        e.extrapolate_lu(l, u);
        prop_assert!(is_canonical(&e));
        prop_assert!(e.includes(&z));
        // LU+ is coarser than Extra_M with M = max(L, U).
        let m: Vec<i32> = l.iter().zip(u).map(|(&a, &b)| a.max(b)).collect();
        let mut em = z.clone();
        em.extrapolate_max(&m);
        prop_assert!(e.includes(&em));
        if l.iter().chain(u).skip(1).all(|&c| c >= 0) {
            for_each_point(n, |v| {
                let small = (1..n).all(|c| v[c] <= l[c].min(u[c]) as i64 * DEN);
                if small {
                    assert_eq!(e.contains_point(v, DEN), z.contains_point(v, DEN), "point {v:?}");
                }
            });
        }
    }
}

// ------------------------------------------------------ zone-graph finiteness

/// Explores a small cyclic timed automaton over clocks x (1) and y (2):
/// `l0 --x ≥ 1, x := 0--> l1`, `l1 --x ≥ 1, x := 0--> l1` (y keeps growing),
/// `l1 --y ≥ 2 ∧ x ≤ 3, y := 0--> l0`, invariant `x ≤ 5` in l1. Returns the
/// number of symbolic states, or `None` past `cap`.
fn explore(extrapolate: impl Fn(&mut Dbm), cap: usize) -> Option<usize> {
    type Edge = (usize, usize, Vec<(usize, Bound, Bound)>, usize);
    let edges: Vec<Edge> = vec![
        (0, 1, vec![(1, le(-1), Bound::INFINITY)], 1),
        (1, 1, vec![(1, le(-1), Bound::INFINITY)], 1),
        (1, 0, vec![(2, le(-2), Bound::INFINITY), (1, Bound::LE_ZERO, le(3))], 2),
    ];
    let invariant = |loc: usize, z: &mut Dbm| loc != 1 || z.constrain(1, 0, le(5));
    let mut seen: HashSet<(usize, Dbm)> = HashSet::new();
    let mut start = Dbm::zero(3);
    start.up();
    let mut stack = vec![(0usize, start)];
    while let Some((loc, z)) = stack.pop() {
        if !seen.insert((loc, z.clone())) {
            continue;
        }
        if seen.len() > cap {
            return None;
        }
        for (from, to, guard, reset) in &edges {
            if *from != loc {
                continue;
            }
            let mut s = z.clone();
            if !guard.iter().all(|&(x, lo, hi)| s.constrain_interval(x, lo, hi)) {
                continue;
            }
            s.reset(*reset);
            s.up();
            if !invariant(*to, &mut s) {
                continue;
            }
            extrapolate(&mut s);
            stack.push((*to, s));
        }
    }
    Some(seen.len())
}

#[test]
fn zone_graph_is_finite_with_extrapolation() {
    // Without extrapolation the self-loop keeps producing new zones.
    assert_eq!(explore(|_| {}, 500), None);
    let m = explore(|z| z.extrapolate_max(&[0, 5, 2]), 500).expect("finite with Extra_M");
    assert!(m <= 20, "{m} zones");
    let lu = explore(|z| z.extrapolate_lu(&[0, 1, 2], &[0, 5, -1]), 500).expect("finite with Extra_LU+");
    assert!(lu <= m, "LU+ {lu} vs M {m}");
}
