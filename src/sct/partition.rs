//! Hopcroft's partition refinement for complete deterministic automata, O(k·n·log n).
//!
//! Used by both minimisations (classic automata and supervisors). Callers complete their
//! partial automata with an explicit sink state and give every state an initial key; states
//! with different keys are never merged.

/// Coarsest partition of `0..n` compatible with `key` and with the complete transition table
/// `delta` (`delta[s * k + a]` is the successor of `s` on the `a`-th event). Returns the block
/// of every state; block numbers are dense but otherwise arbitrary.
pub fn coarsest_partition(n: usize, k: usize, delta: &[u32], key: &[u64]) -> Vec<u32> {
    debug_assert_eq!(delta.len(), n * k);
    if n == 0 {
        return Vec::new();
    }
    // Inverse transitions, CSR over (event, target).
    let mut inv_off = vec![0u32; n * k + 1];
    for s in 0..n {
        for a in 0..k {
            inv_off[a * n + delta[s * k + a] as usize + 1] += 1;
        }
    }
    for i in 0..n * k {
        inv_off[i + 1] += inv_off[i];
    }
    let mut fill = inv_off.clone();
    let mut inv = vec![0u32; n * k];
    for s in 0..n {
        for a in 0..k {
            let slot = a * n + delta[s * k + a] as usize;
            inv[fill[slot] as usize] = s as u32;
            fill[slot] += 1;
        }
    }
    // Refinable partition: `elems` is a permutation, each block a contiguous range of it.
    let mut elems: Vec<u32> = (0..n as u32).collect();
    crate::sort::sort_by_key(&mut elems, |&s| key[s as usize]);
    let mut loc = vec![0u32; n];
    let mut block = vec![0u32; n];
    let mut start: Vec<u32> = Vec::new();
    let mut end: Vec<u32> = Vec::new();
    for (i, &s) in elems.iter().enumerate() {
        if i == 0 || key[elems[i - 1] as usize] != key[s as usize] {
            start.push(i as u32);
            end.push(i as u32);
        }
        let b = start.len() - 1;
        end[b] = i as u32 + 1;
        block[s as usize] = b as u32;
        loc[s as usize] = i as u32;
    }
    let mut marked = vec![0u32; start.len()];
    let mut in_work: Vec<bool> = vec![true; start.len() * k];
    let mut work: Vec<(u32, u32)> = (0..start.len() as u32).flat_map(|b| (0..k as u32).map(move |a| (b, a))).collect();
    let mut splitter: Vec<u32> = Vec::new();
    let mut touched: Vec<u32> = Vec::new();
    while let Some((b, a)) = work.pop() {
        in_work[b as usize * k + a as usize] = false;
        splitter.clear();
        for i in start[b as usize]..end[b as usize] {
            let t = elems[i as usize] as usize;
            let slot = a as usize * n + t;
            splitter.extend_from_slice(&inv[inv_off[slot] as usize..inv_off[slot + 1] as usize]);
        }
        touched.clear();
        for &s in &splitter {
            let y = block[s as usize] as usize;
            let pos = loc[s as usize];
            let front = start[y] + marked[y];
            if pos < front {
                continue; // already marked
            }
            // Swap s to the front (marked) region of its block.
            let other = elems[front as usize];
            elems.swap(pos as usize, front as usize);
            loc[other as usize] = pos;
            loc[s as usize] = front;
            if marked[y] == 0 {
                touched.push(y as u32);
            }
            marked[y] += 1;
        }
        for &y in &touched {
            let y = y as usize;
            let m = marked[y];
            marked[y] = 0;
            if m == end[y] - start[y] {
                continue;
            }
            // Split: the marked front part becomes a new block z.
            let z = start.len();
            start.push(start[y]);
            end.push(start[y] + m);
            marked.push(0);
            start[y] += m;
            for i in start[z]..end[z] {
                block[elems[i as usize] as usize] = z as u32;
            }
            in_work.resize(start.len() * k, false);
            let (size_y, size_z) = (end[y] - start[y], end[z] - start[z]);
            for c in 0..k {
                if in_work[y * k + c] {
                    in_work[z * k + c] = true;
                    work.push((z as u32, c as u32));
                } else {
                    let pick = if size_z <= size_y { z } else { y };
                    in_work[pick * k + c] = true;
                    work.push((pick as u32, c as u32));
                }
            }
        }
    }
    block
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn separates_by_key_and_by_successors() {
        // 0 -> 1 -> 2 -> 2 on one event; only 2 has key 1: three blocks.
        let p = coarsest_partition(3, 1, &[1, 2, 2], &[0, 0, 1]);
        assert!(p[0] != p[1] && p[1] != p[2] && p[0] != p[2]);
        // A cycle of four with alternating keys collapses to two blocks.
        let p = coarsest_partition(4, 1, &[1, 2, 3, 0], &[0, 1, 0, 1]);
        assert_eq!(p[0], p[2]);
        assert_eq!(p[1], p[3]);
        assert_ne!(p[0], p[1]);
    }

    #[test]
    fn long_chains_are_fully_distinguished() {
        let n = 20_000;
        let delta: Vec<u32> = (0..n as u32).map(|s| (s + 1).min(n as u32 - 1)).collect();
        let mut key = vec![0u64; n];
        key[n - 1] = 1;
        let p = coarsest_partition(n, 1, &delta, &key);
        let mut q = p.clone();
        q.sort_unstable();
        q.dedup();
        assert_eq!(q.len(), n);
    }
}
