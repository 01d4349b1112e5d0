//! From a won bounded game to a small finite-state strategy: extraction over the winning
//! positions with reuse of dominating positions, minimisation by partition refinement, and
//! rows written as few disjoint cubes.
//!
//! Reuse: a position dominated pointwise by a winning position `h` is won by `h`'s strategy
//! (its runs are a subset of `h`'s with counters no larger, and the successors keep that
//! order), so the extraction jumps to an existing machine state `h` whenever one dominates
//! the successor. This is the antichain argument of Filiot, Jin and Raskin; it keeps the
//! machine near the maximal winning positions it needs instead of every position it meets.

use super::game::{Game, LOST};
use super::machine::{Cube, Machine, Row, StateId};
use super::spec::SignalId;
use hashbrown::HashMap;

/// The winner's strategy in `game` from the initial position, which must be winning: states
/// before minimisation, and the minimised machine reading `reads` and writing `writes`.
pub(super) fn extract(game: &Game, reads: &[SignalId], writes: &[SignalId]) -> (usize, Machine) {
    let table = choose(game);
    let raw = table.len();
    let table = minimise(&table);
    let states = table.iter().map(|moves| cover(moves, reads.len())).collect();
    let machine = Machine {
        reads: reads.to_vec(),
        writes: writes.to_vec(),
        moves_first: game.protagonist_first,
        init: StateId(0),
        states,
    };
    debug_assert_eq!(machine.validate(), Ok(()));
    (raw, machine)
}

/// Per machine state and valuation of the read signals: the value written and the next state.
type Table = Vec<Vec<(u64, u32)>>;

/// Valuations ordered as a PLC engineer would like ties broken: fewer signals set first.
fn by_fewest_set(count: usize) -> Vec<usize> {
    let mut order: Vec<usize> = (0..count).collect();
    order.sort_by_key(|&v| (v.count_ones(), v));
    order
}

fn choose(game: &Game) -> Table {
    let positions = &game.positions;
    let dominates =
        |h: u32, q: u32| positions[q as usize].iter().zip(positions[h as usize].iter()).all(|(x, y)| x <= y);
    let winning = |q: u32| q != LOST && !game.lost[q as usize];
    let (l1, l2) = (game.first.len(), game.second.len());
    let mut members: Vec<u32> = vec![0];
    let mut table: Table = Vec::new();
    let mut i = 0;
    // The machine state standing for successor `q`: an existing one that dominates it, if any.
    fn existing(members: &[u32], q: u32, dominates: &dyn Fn(u32, u32) -> bool) -> Option<u32> {
        members.iter().position(|&h| dominates(h, q)).map(|m| m as u32)
    }
    fn add(members: &mut Vec<u32>, q: u32) -> u32 {
        members.push(q);
        members.len() as u32 - 1
    }
    while i < members.len() {
        let p = members[i];
        let mut moves = Vec::new();
        if game.protagonist_first {
            // Write first: a valuation after which every reply stays winning, preferring the
            // one whose successors the machine already has.
            let safe = by_fewest_set(l1).into_iter().filter(|&a| (0..l2).all(|b| winning(game.successor(p, a, b))));
            let a = safe
                .max_by_key(|&a| {
                    let known = (0..l2).filter(|&b| existing(&members, game.successor(p, a, b), &dominates).is_some());
                    (known.count(), std::cmp::Reverse(a.count_ones()), std::cmp::Reverse(a))
                })
                .expect("a winning position has a safe move");
            for b in 0..l2 {
                let q = game.successor(p, a, b);
                let next = existing(&members, q, &dominates).unwrap_or_else(|| add(&mut members, q));
                moves.push((a as u64, next));
            }
        } else {
            // Read first: for each valuation, a reply that stays winning — one this state
            // already gives for another valuation if it fits (fewer rows), else one into a known
            // state, else a new state.
            for a in 0..l1 {
                let reused = moves.iter().copied().find(|&(b, next): &(u64, u32)| {
                    let q = game.successor(p, a, b as usize);
                    winning(q) && dominates(members[next as usize], q)
                });
                if let Some(choice) = reused {
                    moves.push(choice);
                    continue;
                }
                let replies: Vec<usize> =
                    by_fewest_set(l2).into_iter().filter(|&b| winning(game.successor(p, a, b))).collect();
                let known = replies
                    .iter()
                    .find_map(|&b| existing(&members, game.successor(p, a, b), &dominates).map(|m| (b, m)));
                let (b, next) = known.unwrap_or_else(|| {
                    let b = *replies.first().expect("a winning position has a reply to every move");
                    (b, add(&mut members, game.successor(p, a, b)))
                });
                moves.push((b as u64, next));
            }
        }
        table.push(moves);
        i += 1;
    }
    table
}

/// The smallest machine with the same behaviour (Moore's partition refinement on writes and
/// next states), states numbered breadth-first from the initial one.
fn minimise(table: &Table) -> Table {
    let n = table.len();
    let mut block: Vec<u32> = number(table.iter().map(|moves| moves.iter().map(|m| m.0).collect::<Vec<_>>()));
    let mut count = block.iter().max().map_or(0, |&b| b + 1);
    loop {
        let refined = number((0..n).map(|s| {
            let succ: Vec<(u64, u32)> = table[s].iter().map(|&(w, t)| (w, block[t as usize])).collect();
            (block[s], succ)
        }));
        let refined_count = refined.iter().max().map_or(0, |&b| b + 1);
        block = refined;
        if refined_count == count {
            break;
        }
        count = refined_count;
    }
    // Breadth-first renumbering of the blocks from the initial state's.
    let mut representative: Vec<Option<usize>> = vec![None; count as usize];
    for (s, &b) in block.iter().enumerate() {
        representative[b as usize].get_or_insert(s);
    }
    let mut id: Vec<Option<u32>> = vec![None; count as usize];
    let mut order = vec![block[0]];
    id[block[0] as usize] = Some(0);
    let mut i = 0;
    while i < order.len() {
        let s = representative[order[i] as usize].expect("a block has a state");
        for &(_, t) in &table[s] {
            let b = block[t as usize] as usize;
            if id[b].is_none() {
                id[b] = Some(order.len() as u32);
                order.push(b as u32);
            }
        }
        i += 1;
    }
    order
        .iter()
        .map(|&b| {
            let s = representative[b as usize].expect("a block has a state");
            table[s].iter().map(|&(w, t)| (w, id[block[t as usize] as usize].expect("reachable"))).collect()
        })
        .collect()
}

/// Numbers distinct keys in order of first appearance.
fn number<K: std::hash::Hash + Eq>(keys: impl Iterator<Item = K>) -> Vec<u32> {
    let mut ids: HashMap<K, u32> = HashMap::new();
    keys.map(|k| {
        let next = ids.len() as u32;
        *ids.entry(k).or_insert(next)
    })
    .collect()
}

/// Disjoint cubes covering every valuation of `width` read signals, one per group of
/// valuations with the same write and next state: a decision on the read signals, splitting
/// each time on the signal that leaves the fewest distinct groups on its two sides, then
/// sibling cubes that differ in one signal merged.
fn cover(moves: &[(u64, u32)], width: usize) -> Vec<Row> {
    let mut rows = Vec::new();
    split(moves, width, Cube::ANY, &mut rows);
    loop {
        let mut merged = false;
        'pairs: for i in 0..rows.len() {
            for j in i + 1..rows.len() {
                let (a, b) = (rows[i], rows[j]);
                let differ = a.read.value ^ b.read.value;
                if a.write == b.write && a.next == b.next && a.read.care == b.read.care && differ.count_ones() == 1 {
                    rows[i].read = Cube { care: a.read.care & !differ, value: a.read.value & !differ };
                    rows.remove(j);
                    merged = true;
                    break 'pairs;
                }
            }
        }
        if !merged {
            return rows;
        }
    }
}

/// The valuations of `width` signals inside `cube`.
fn members(width: usize, cube: Cube) -> impl Iterator<Item = usize> {
    let free = ((1u64 << width) - 1) & !cube.care;
    let mut sub = Some(free);
    std::iter::from_fn(move || {
        let current = sub?;
        sub = (current != 0).then(|| (current - 1) & free);
        Some((cube.value | current) as usize)
    })
}

fn distinct(moves: &[(u64, u32)], width: usize, cube: Cube) -> usize {
    let mut seen: Vec<(u64, u32)> = Vec::new();
    for v in members(width, cube) {
        if !seen.contains(&moves[v]) {
            seen.push(moves[v]);
        }
    }
    seen.len()
}

fn split(moves: &[(u64, u32)], width: usize, cube: Cube, rows: &mut Vec<Row>) {
    let first = moves[cube.value as usize];
    if members(width, cube).all(|v| moves[v] == first) {
        rows.push(Row { read: cube, write: first.0, next: StateId(first.1) });
        return;
    }
    let halves = |bit: u64| {
        (Cube { care: cube.care | bit, value: cube.value }, Cube { care: cube.care | bit, value: cube.value | bit })
    };
    let bit = (0..width)
        .map(|i| 1u64 << i)
        .filter(|bit| cube.care & bit == 0)
        .min_by_key(|&bit| {
            let (low, high) = halves(bit);
            distinct(moves, width, low) + distinct(moves, width, high)
        })
        .expect("a cube that is not uniform has a free signal");
    let (low, high) = halves(bit);
    split(moves, width, low, rows);
    split(moves, width, high, rows);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cover_merges_and_stays_disjoint() {
        // Two read signals; write 1 exactly when the first is set, next state always 0.
        let moves = vec![(0, 0), (1, 0), (0, 0), (1, 0)];
        let rows = cover(&moves, 2);
        assert_eq!(rows.len(), 2, "{rows:?}");
        assert!(rows.iter().all(|r| r.read.care == 1));
        let uniform = cover(&[(3, 1); 8], 3);
        assert_eq!(uniform, vec![Row { read: Cube::ANY, write: 3, next: StateId(1) }]);
    }

    #[test]
    fn minimise_merges_equivalent_states() {
        // States 0 and 1 behave alike (write the valuation, go to the other); 2 is unreachable.
        let table: Table = vec![vec![(0, 1), (1, 1)], vec![(0, 0), (1, 0)], vec![(1, 2), (1, 2)]];
        assert_eq!(minimise(&table), vec![vec![(0, 0), (1, 0)]]);
    }
}
