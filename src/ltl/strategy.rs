//! From a won bounded game to a small finite-state strategy: extraction over the maximal
//! winning positions, minimisation by partition refinement, and rows written as few disjoint
//! cubes.
//!
//! A position below a winning position `h` (pointwise) is won by `h`'s moves: its runs are a
//! subset of `h`'s with counters no larger, and successors keep that order. So the machine's
//! states are maximal winning positions (an antichain, Filiot, Jin and Raskin), and a move
//! goes to a state above its successor, preferring one the machine already has.

use super::antichain::{below, Antichain};
use super::game::advance;
use super::machine::{Cube, Machine, Row, StateId};
use super::spec::SignalId;
use super::translate::Automaton;
use hashbrown::HashMap;

/// The winner's strategy read off the antichain of its maximal winning positions: machine
/// states are antichain elements; from element `h`, a move whose successor lies below an
/// element `g` goes to `g` (the same moves win from every position below `h`).
#[allow(clippy::too_many_arguments)] // the game's parts, as `antichain::solve` takes them
pub(super) fn extract_from_antichain(
    automaton: &Automaton,
    k: u32,
    winning: &Antichain,
    first: &[u64],
    second: &[u64],
    protagonist_first: bool,
    reads: &[SignalId],
    writes: &[SignalId],
) -> (usize, Machine) {
    let k = k as i8;
    let elements = &winning.elements;
    let mut init = vec![-1i8; automaton.states.len()];
    if !automaton.is_empty() {
        init[automaton.init as usize] = 0;
    }
    let start = winning.above(&init).expect("the initial position is winning");
    let mut members: Vec<usize> = vec![start];
    let mut next = vec![-1i8; automaton.states.len()];
    // The machine state for a successor: a member above it, else a new member above it.
    let target = |members: &mut Vec<usize>, succ: &[i8]| -> Option<u32> {
        if let Some(m) = members.iter().position(|&e| below(succ, &elements[e])) {
            return Some(m as u32);
        }
        let e = winning.above(succ)?;
        members.push(e);
        Some(members.len() as u32 - 1)
    };
    let mut table: Table = Vec::new();
    let mut i = 0;
    while i < members.len() {
        let h = elements[members[i]].clone();
        let mut moves: Vec<(u64, u32)> = Vec::new();
        if protagonist_first {
            // An own valuation after which every reply stays below the antichain, preferring the
            // one whose successors lie below states the machine has.
            let known = |a: usize, members: &[usize], next: &mut [i8]| -> Option<usize> {
                let mut count = 0;
                for &fb in second {
                    if !advance(automaton, k, &h, first[a] | fb, next) || !winning.contains(next) {
                        return None;
                    }
                    count += usize::from(members.iter().any(|&e| below(next, &elements[e])));
                }
                Some(count)
            };
            let a = by_fewest_set(first.len())
                .into_iter()
                .filter_map(|a| known(a, &members, &mut next).map(|c| (c, a)))
                .max_by_key(|&(c, a)| (c, std::cmp::Reverse(a.count_ones()), std::cmp::Reverse(a)))
                .map(|(_, a)| a)
                .expect("a winning position has a safe move");
            for &fb in second {
                assert!(advance(automaton, k, &h, first[a] | fb, &mut next), "checked above");
                let to = target(&mut members, &next).expect("checked above");
                moves.push((a as u64, to));
            }
        } else {
            for &fa in first {
                // A reply this state already gives, if it wins here too.
                let reused = moves.iter().copied().find(|&(b, to): &(u64, u32)| {
                    advance(automaton, k, &h, fa | second[b as usize], &mut next)
                        && below(&next, &elements[members[to as usize]])
                });
                if let Some(choice) = reused {
                    moves.push(choice);
                    continue;
                }
                let mut fresh = None;
                let mut chosen = None;
                for b in by_fewest_set(second.len()) {
                    if !advance(automaton, k, &h, fa | second[b], &mut next) {
                        continue;
                    }
                    if let Some(m) = members.iter().position(|&e| below(&next, &elements[e])) {
                        chosen = Some((b as u64, m as u32));
                        break;
                    }
                    if fresh.is_none() && winning.contains(&next) {
                        fresh = Some((b, next.clone()));
                    }
                }
                let choice = chosen.unwrap_or_else(|| {
                    let (b, succ) = fresh.expect("a winning position has a reply to every move");
                    (b as u64, target(&mut members, &succ).expect("winning"))
                });
                moves.push(choice);
            }
        }
        table.push(moves);
        i += 1;
    }
    (table.len(), machine_from_table(&table, reads, writes, protagonist_first))
}

/// The machine of a table of moves (per state and valuation of the reads: the value written
/// and the next state, state 0 initial), minimised, its rows written as few disjoint cubes.
pub(super) fn machine_from_table(table: &Table, reads: &[SignalId], writes: &[SignalId], moves_first: bool) -> Machine {
    let table = minimise(table);
    let states = table.iter().map(|moves| cover(moves, reads.len())).collect();
    let machine = Machine { reads: reads.to_vec(), writes: writes.to_vec(), moves_first, init: StateId(0), states };
    debug_assert_eq!(machine.validate(), Ok(()));
    machine
}

/// Per machine state and valuation of the read signals: the value written and the next state.
pub(super) type Table = Vec<Vec<(u64, u32)>>;

/// Valuations ordered as a PLC engineer would like ties broken: fewer signals set first.
fn by_fewest_set(count: usize) -> Vec<usize> {
    let mut order: Vec<usize> = (0..count).collect();
    crate::sort::sort_by_key(&mut order, |&v| (v.count_ones(), v));
    order
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
pub(super) fn members(width: usize, cube: Cube) -> impl Iterator<Item = usize> {
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
