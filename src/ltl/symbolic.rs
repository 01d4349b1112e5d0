//! The bounded game with symbolic letters: no step enumerates the 2^n valuations of the
//! signals.
//!
//! A position's successor depends on the letter only through which automaton edges it enables,
//! and an edge's guard is a cube. So each position's successor function is built as a reduced
//! ordered decision diagram over the signals whose terminals are successor positions (or a lost
//! round), splitting only on signals that some still undecided guard names. The first mover's
//! signals are ordered above the second mover's, so a path from a root reads as the round is
//! played: the first mover's choices, then the second's. One diagram is shared by all positions
//! (hash-consed nodes), and the game is solved on it: a node of the protagonist's signal is lost
//! when both its branches are, a node of the opponent's when either is, a terminal when its
//! position's root is. The strategy reads rows off the diagram: the opponent's branches become
//! the read cubes, a winning branch of each protagonist node the written value.
//!
//! The explicit solver ([`super::game`]) stays the reference; `tests/ltl_symbolic.rs` compares
//! the two.

use super::antichain::{below, Antichain};
use super::machine::{Cube, Machine, Row, StateId};
use super::spec::SignalId;
use super::strategy::{machine_from_table, members, Table};
use super::translate::{Automaton, Edge};
use super::{Stop, Work};
use hashbrown::HashMap;

/// The terminal of a lost round.
const LOST: u32 = u32::MAX;

/// Up to this many read signals a strategy's rows go through a table of every valuation
/// (4 096 entries per state), for the explicit solver's minimisation and cover.
const TABLE_READS: usize = 12;

/// A node of the shared diagram.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
enum Node {
    /// The round ends in this position ([`LOST`]: the protagonist loses it).
    Leaf(u32),
    /// `lo` when the signal is false, `hi` when it is true.
    Split { signal: u8, lo: u32, hi: u32 },
}

/// An explored game with symbolic letters.
pub(super) struct SymbolicGame {
    nodes: Vec<Node>,
    index: HashMap<Node, u32>,
    /// Counter vectors, position 0 initial.
    positions: Vec<Box<[i8]>>,
    /// The diagram of each position's successors.
    roots: Vec<u32>,
    /// Per signal id: whether the protagonist sets it.
    protagonist_owns: u64,
    /// Per node, after [`SymbolicGame::solve`]: whether the protagonist loses there.
    lost: Vec<bool>,
}

/// Why an exploration stopped.
pub(super) enum Halt {
    OverBudget,
    Stopped(Stop),
}

/// An edge of a live run, with what taking it does.
#[derive(Clone, Copy)]
struct Move {
    pos: u64,
    neg: u64,
    to: u32,
    count: i8,
    /// Taking it loses the round (a counter past `k`, or a universal state).
    loses: bool,
}

impl SymbolicGame {
    /// Explores every position reachable from the initial one, each with its successor
    /// diagram; `first` are the first mover's signals (ordered above `second`'s).
    pub(super) fn explore(
        automaton: &Automaton,
        k: u32,
        first: &[SignalId],
        second: &[SignalId],
        protagonist_first: bool,
        budget: usize,
        work: &mut Work,
    ) -> Result<SymbolicGame, Halt> {
        let mask = |signals: &[SignalId]| signals.iter().fold(0u64, |m, s| m | 1 << s.0);
        let order: Vec<u8> = first.iter().chain(second).map(|s| s.0 as u8).collect();
        let protagonist_owns = if protagonist_first { mask(first) } else { mask(second) };
        let n = automaton.states.len();
        let mut init = vec![-1i8; n].into_boxed_slice();
        if !automaton.is_empty() {
            init[automaton.init as usize] = 0;
        }
        let mut game = SymbolicGame {
            nodes: vec![Node::Leaf(LOST)],
            index: HashMap::new(),
            positions: vec![init.clone()],
            roots: Vec::new(),
            protagonist_owns,
            lost: Vec::new(),
        };
        game.index.insert(Node::Leaf(LOST), 0);
        let mut position_index: HashMap<Box<[i8]>, u32> = HashMap::new();
        position_index.insert(init, 0);
        let mut p = 0;
        while p < game.positions.len() {
            work.at.positions = game.positions.len();
            if game.positions.len() > budget {
                return Err(Halt::OverBudget);
            }
            let position = game.positions[p].clone();
            let moves: Vec<Move> = position
                .iter()
                .enumerate()
                .filter(|(_, &c)| c >= 0)
                .flat_map(|(q, &c)| {
                    automaton.states[q].edges.iter().map(move |e: &Edge| {
                        let count = c + i8::from(e.accepting);
                        Move {
                            pos: e.pos,
                            neg: e.neg,
                            to: e.to,
                            count,
                            loses: count > k as i8 || automaton.states[e.to as usize].universal,
                        }
                    })
                })
                .collect();
            let live: Vec<u32> = (0..moves.len() as u32).collect();
            let mut builder = Builder {
                game: &mut game,
                moves: &moves,
                memo: HashMap::new(),
                index: &mut position_index,
                order: &order,
                n,
                work,
            };
            let root = builder.build(&live, 0, 0, 0).map_err(Halt::Stopped)?;
            game.roots.push(root);
            p += 1;
        }
        Ok(game)
    }

    pub(super) fn positions(&self) -> usize {
        self.positions.len()
    }

    /// Marks the nodes (and so the positions) the protagonist loses: the least fixpoint, by
    /// counting per node the branches that must be lost before it is.
    pub(super) fn solve(&mut self) {
        let n = self.nodes.len();
        let mut need = vec![0u8; n];
        let mut preds: Vec<Vec<u32>> = vec![Vec::new(); n];
        let mut lost = vec![false; n];
        let mut stack = Vec::new();
        for (i, node) in self.nodes.iter().enumerate() {
            match *node {
                Node::Leaf(LOST) => {
                    lost[i] = true;
                    stack.push(i as u32);
                }
                Node::Leaf(p) => {
                    need[i] = 1;
                    preds[self.roots[p as usize] as usize].push(i as u32);
                }
                Node::Split { signal, lo, hi } => {
                    need[i] = if self.protagonist_owns >> signal & 1 == 1 { 2 } else { 1 };
                    preds[lo as usize].push(i as u32);
                    preds[hi as usize].push(i as u32);
                }
            }
        }
        while let Some(x) = stack.pop() {
            for &y in &preds[x as usize] {
                let y = y as usize;
                if lost[y] {
                    continue;
                }
                need[y] -= 1;
                if need[y] == 0 {
                    lost[y] = true;
                    stack.push(y as u32);
                }
            }
        }
        self.lost = lost;
    }

    /// The maximal winning positions explored (after [`SymbolicGame::solve`]): the winning
    /// region is closed downwards, so these describe it.
    pub(super) fn maximal_winning(&self) -> Antichain {
        let mut set = Antichain::default();
        for (p, position) in self.positions.iter().enumerate() {
            if !self.lost[self.roots[p] as usize] {
                set.insert(position.clone());
            }
        }
        set
    }

    /// Whether the protagonist wins from the initial position (after [`SymbolicGame::solve`]).
    pub(super) fn won(&self) -> bool {
        !self.lost[self.roots[0] as usize]
    }

    /// The protagonist's strategy from the initial position (which it must win): a machine
    /// state per position reached that lies below none the machine already has (whose moves
    /// then serve), its rows read off the diagram, then states with the same rows merged. Returns the number of states before merging and the machine.
    pub(super) fn strategy(
        &self,
        reads: &[SignalId],
        writes: &[SignalId],
        protagonist_first: bool,
    ) -> (usize, Machine) {
        let bit_of = |signals: &[SignalId]| {
            let mut at = [u8::MAX; 64];
            for (i, s) in signals.iter().enumerate() {
                at[s.0 as usize] = i as u8;
            }
            at
        };
        let (read_bit, write_bit) = (bit_of(reads), bit_of(writes));
        let mut state_of: HashMap<u32, u32> = HashMap::new();
        let mut order = vec![0u32];
        state_of.insert(0, 0);
        let mut table: Vec<Vec<(Cube, u64, u32)>> = Vec::new();
        let mut i = 0;
        while i < order.len() {
            let p = order[i];
            let mut rows = Vec::new();
            self.rows(self.roots[p as usize], Cube::ANY, 0, &read_bit, &write_bit, &mut rows);
            let rows = rows
                .into_iter()
                .map(|(read, write, to)| {
                    if let Some(&state) = state_of.get(&to) {
                        return (read, write, state);
                    }
                    // A position below one the machine already has is won by that one's moves
                    // (fewer runs, counters no larger, and successors keep the order).
                    let to_position = &self.positions[to as usize];
                    let above = order.iter().position(|&q| below(to_position, &self.positions[q as usize]));
                    let state = above.map_or_else(
                        || {
                            order.push(to);
                            order.len() as u32 - 1
                        },
                        |m| m as u32,
                    );
                    state_of.insert(to, state);
                    (read, write, state)
                })
                .collect();
            table.push(rows);
            i += 1;
        }
        (table.len(), machine_from_rows(&table, reads, writes, protagonist_first))
    }

    /// The rows below `node`: every branch of the opponent's signals, a winning branch of the
    /// protagonist's (false preferred: fewer outputs set), as (read cube, written value, next
    /// position). The protagonist's nodes above the opponent's (it moves first) pick one value
    /// for all rows, as a Moore machine must.
    #[allow(clippy::too_many_arguments)]
    fn rows(
        &self,
        node: u32,
        read: Cube,
        write: u64,
        read_bit: &[u8; 64],
        write_bit: &[u8; 64],
        out: &mut Vec<(Cube, u64, u32)>,
    ) {
        match self.nodes[node as usize] {
            Node::Leaf(p) => {
                debug_assert_ne!(p, LOST, "a winning strategy never loses a round");
                out.push((read, write, p));
            }
            Node::Split { signal, lo, hi } if self.protagonist_owns >> signal & 1 == 1 => {
                let (branch, set) = if !self.lost[lo as usize] { (lo, 0) } else { (hi, 1) };
                debug_assert!(!self.lost[branch as usize]);
                let bit = write_bit[signal as usize];
                self.rows(branch, read, write | set << bit, read_bit, write_bit, out);
            }
            Node::Split { signal, lo, hi } => {
                let bit = 1u64 << read_bit[signal as usize];
                let low = Cube { care: read.care | bit, value: read.value };
                let high = Cube { care: read.care | bit, value: read.value | bit };
                self.rows(lo, low, write, read_bit, write_bit, out);
                self.rows(hi, high, write, read_bit, write_bit, out);
            }
        }
    }
}

/// Flags a move index in a memo key as enabled.
const ENABLED: u32 = 1 << 31;

/// Builds one position's diagram.
struct Builder<'a, 'w> {
    game: &'a mut SymbolicGame,
    /// The position's moves, and the nodes built for each set of moves still possible.
    moves: &'a [Move],
    memo: HashMap<Vec<u32>, u32>,
    index: &'a mut HashMap<Box<[i8]>, u32>,
    /// Signal ids, the first mover's first.
    order: &'a [u8],
    /// Automaton states.
    n: usize,
    work: &'a mut Work<'w>,
}

impl Builder<'_, '_> {
    /// The node of the moves left undecided under the partial valuation (`pos` true, `neg`
    /// false), splitting on signals from `order[from..]`.
    fn build(&mut self, live: &[u32], pos: u64, neg: u64, from: usize) -> Result<u32, Stop> {
        self.work.spend(1 + live.len() as u64)?;
        // The moves still possible, in index order, those already enabled flagged: with the
        // next signal to split on, they decide the node (every literal on an earlier signal of
        // the order is decided), so paths that agree on them share it.
        let mut key: Vec<u32> = Vec::with_capacity(live.len() + 1);
        let mut named = 0u64;
        for &i in live {
            let m = self.moves[i as usize];
            if m.pos & neg != 0 || m.neg & pos != 0 {
                continue;
            }
            if m.pos & !pos == 0 && m.neg & !neg == 0 {
                if m.loses {
                    return Ok(self.node(Node::Leaf(LOST)));
                }
                key.push(i | ENABLED);
            } else {
                named |= (m.pos | m.neg) & !(pos | neg);
                key.push(i);
            }
        }
        let at = self.order[from..].iter().position(|&s| named >> s & 1 == 1).map(|step| from + step);
        key.push(at.map_or(u32::MAX, |at| at as u32));
        if let Some(&node) = self.memo.get(&key) {
            return Ok(node);
        }
        let node = match at {
            // Every move is decided (`named` is empty only when no move is open).
            None => {
                let mut next = vec![-1i8; self.n];
                for &i in key.iter().filter(|&&i| i != u32::MAX && i & ENABLED != 0) {
                    let m = self.moves[(i & !ENABLED) as usize];
                    let slot = &mut next[m.to as usize];
                    *slot = (*slot).max(m.count);
                }
                let id = match self.index.get(next.as_slice()) {
                    Some(&id) => id,
                    None => {
                        let position: Box<[i8]> = next.into_boxed_slice();
                        let id = self.game.positions.len() as u32;
                        self.game.positions.push(position.clone());
                        self.index.insert(position, id);
                        id
                    }
                };
                self.node(Node::Leaf(id))
            }
            Some(at) => {
                let signal = self.order[at];
                let bit = 1u64 << signal;
                let live: Vec<u32> = key[..key.len() - 1].iter().map(|&i| i & !ENABLED).collect();
                let lo = self.build(&live, pos, neg | bit, at + 1)?;
                let hi = self.build(&live, pos | bit, neg, at + 1)?;
                if lo == hi {
                    lo
                } else {
                    self.node(Node::Split { signal, lo, hi })
                }
            }
        };
        self.memo.insert(key, node);
        Ok(node)
    }

    fn node(&mut self, node: Node) -> u32 {
        if let Some(&id) = self.game.index.get(&node) {
            return id;
        }
        let id = self.game.nodes.len() as u32;
        self.game.nodes.push(node);
        self.game.index.insert(node, id);
        id
    }
}

/// The machine of a strategy given as rows per state (read cube, written value, next state;
/// state 0 initial). Up to [`TABLE_READS`] read signals the rows go through a table per
/// valuation, minimised and covered as the explicit solver's strategies are (fewer states and
/// rows than the diagram's cubes); beyond, states with equal rows are merged.
pub(super) fn machine_from_rows(
    table: &[Vec<(Cube, u64, u32)>],
    reads: &[SignalId],
    writes: &[SignalId],
    moves_first: bool,
) -> Machine {
    if reads.len() <= TABLE_READS {
        let explicit: Table = table
            .iter()
            .map(|rows| {
                let mut moves = vec![(0, 0); 1 << reads.len()];
                for &(read, write, next) in rows {
                    for v in members(reads.len(), read) {
                        moves[v] = (write, next);
                    }
                }
                moves
            })
            .collect();
        return machine_from_table(&explicit, reads, writes, moves_first);
    }
    let machine =
        Machine { reads: reads.to_vec(), writes: writes.to_vec(), moves_first, init: StateId(0), states: merge(table) };
    debug_assert_eq!(machine.validate(), Ok(()));
    machine
}

/// Merges machine states whose rows agree (same cubes and writes, next states in the same
/// class), refining until stable; states numbered breadth-first from the initial one.
fn merge(table: &[Vec<(Cube, u64, u32)>]) -> Vec<Vec<Row>> {
    let n = table.len();
    let number = |keys: Vec<Vec<(u64, u64, u64, u32)>>| -> Vec<u32> {
        let mut ids: HashMap<Vec<(u64, u64, u64, u32)>, u32> = HashMap::new();
        keys.into_iter()
            .map(|k| {
                let next = ids.len() as u32;
                *ids.entry(k).or_insert(next)
            })
            .collect()
    };
    let mut block =
        number(table.iter().map(|rows| rows.iter().map(|r| (r.0.care, r.0.value, r.1, 0)).collect()).collect());
    let mut count = block.iter().max().map_or(0, |&b| b + 1);
    loop {
        let refined = number(
            table
                .iter()
                .enumerate()
                .map(|(s, rows)| {
                    let mut key: Vec<(u64, u64, u64, u32)> =
                        rows.iter().map(|r| (r.0.care, r.0.value, r.1, block[r.2 as usize])).collect();
                    key.push((u64::MAX, u64::MAX, u64::MAX, block[s]));
                    key
                })
                .collect(),
        );
        let refined_count = refined.iter().max().map_or(0, |&b| b + 1);
        block = refined;
        if refined_count == count {
            break;
        }
        count = refined_count;
    }
    let mut representative: Vec<Option<usize>> = vec![None; count as usize];
    for (s, &b) in block.iter().enumerate().take(n) {
        representative[b as usize].get_or_insert(s);
    }
    let mut id: Vec<Option<u32>> = vec![None; count as usize];
    let mut order = vec![block[0]];
    id[block[0] as usize] = Some(0);
    let mut i = 0;
    while i < order.len() {
        let s = representative[order[i] as usize].expect("a block has a state");
        for r in &table[s] {
            let b = block[r.2 as usize] as usize;
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
            table[s]
                .iter()
                .map(|r| Row {
                    read: r.0,
                    write: r.1,
                    next: StateId(id[block[r.2 as usize] as usize].expect("reachable")),
                })
                .collect()
        })
        .collect()
}
