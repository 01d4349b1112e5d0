//! Stable sorting with one shared implementation, for the size of the page's WebAssembly.
//!
//! The standard library's stable sort (driftsort) is fast but large, and every call site's
//! element type and comparator instantiates all of it again: some 3 KB of wasm each. Here a
//! slice of at most [`SMALL`] elements is sorted by insertion (a few instructions per caller);
//! a longer one by sorting its indices once with the standard sort behind a `dyn` comparator,
//! which is instantiated once for the whole crate, and then permuting the slice in place.
//!
//! A stable sort's result is determined by the comparator alone (equal elements keep their
//! order), so these functions give exactly what `<[T]>::sort_by` and friends give. The crate
//! sorts through them only, `sort_unstable` included (ipnsort is as large again per type): its
//! call sites sort ids, integers and tuples of them, whose equal elements are identical, so the
//! order among equals cannot show there either.

use std::cmp::Ordering;

/// Slices up to this length are sorted by insertion.
const SMALL: usize = 16;

/// Sorts `v` stably by `compare`, like `<[T]>::sort_by`.
pub fn sort_by<T>(v: &mut [T], mut compare: impl FnMut(&T, &T) -> Ordering) {
    let n = v.len();
    if n <= SMALL {
        for i in 1..n {
            let mut j = i;
            while j > 0 && compare(&v[j - 1], &v[j]) == Ordering::Greater {
                v.swap(j - 1, j);
                j -= 1;
            }
        }
        return;
    }
    let order = {
        let v = &*v;
        stable_order(n, &mut |a, b| compare(&v[a], &v[b]))
    };
    permute(v, order);
}

/// Sorts `v` stably by the key `f`, like `<[T]>::sort_by_key` (the key is computed per
/// comparison).
pub fn sort_by_key<T, K: Ord>(v: &mut [T], mut f: impl FnMut(&T) -> K) {
    sort_by(v, |a, b| f(a).cmp(&f(b)));
}

/// Sorts `v` stably, like `<[T]>::sort`.
pub fn sort<T: Ord>(v: &mut [T]) {
    sort_by(v, T::cmp);
}

/// The positions `0..n` in stably sorted order: the one instance of the standard stable sort.
fn stable_order(n: usize, compare: &mut dyn FnMut(usize, usize) -> Ordering) -> Vec<usize> {
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by(|&a, &b| compare(a, b));
    order
}

/// Moves `v[order[i]]` to position `i` for every `i`, by swaps along the permutation's cycles.
fn permute<T>(v: &mut [T], mut order: Vec<usize>) {
    for start in 0..v.len() {
        // A position already in place (or already filled) has `order[j] == j`.
        let mut j = start;
        loop {
            let k = order[j];
            order[j] = j;
            if k == start {
                break;
            }
            v.swap(j, k);
            j = k;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn equals_the_standard_stable_sort() {
        let mut seed = 0x2545_f491_4f6c_dd1du64;
        for n in [0, 1, 2, 5, 16, 17, 40, 300, 2000] {
            for modulus in [1, 3, 50, 1 << 20] {
                let v: Vec<(u64, usize)> = (0..n)
                    .map(|i| {
                        seed ^= seed << 13;
                        seed ^= seed >> 7;
                        seed ^= seed << 17;
                        (seed % modulus, i)
                    })
                    .collect();
                let mut expected = v.clone();
                expected.sort_by_key(|p| p.0);
                let mut got = v.clone();
                sort_by_key(&mut got, |p| p.0);
                assert_eq!(got, expected, "n = {n}, keys mod {modulus}");
                let mut expected = v.clone();
                expected.sort_by_key(|p| std::cmp::Reverse(p.0));
                let mut got = v;
                sort_by(&mut got, |a, b| b.0.cmp(&a.0));
                assert_eq!(got, expected, "n = {n}, descending keys mod {modulus}");
            }
        }
    }

    #[test]
    fn sorts_owned_values() {
        let mut names: Vec<String> = ["b", "a", "c", "a"].iter().map(|s| s.repeat(20)).collect();
        let mut expected = names.clone();
        expected.sort();
        sort(&mut names);
        assert_eq!(names, expected);
        let mut long: Vec<String> = (0..100).rev().map(|i| format!("{:03}", i % 37)).collect();
        let mut expected = long.clone();
        expected.sort();
        sort(&mut long);
        assert_eq!(long, expected);
    }
}
