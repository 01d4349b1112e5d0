//! The bounded games solved fully symbolically with binary decision diagrams (`--solver bdd`),
//! in the manner of Ehlers' Unbeast: positions and letters are both variables of one diagram,
//! and the safety game is the greatest fixpoint `W = νX. CPre(X)` computed on sets of
//! positions, never on one position at a time.
//!
//! **Positions.** A position of [`super::game`] maps each automaton state `q` to a counter
//! `c(q)` in `-1..=k`. Here it is a "thermometer" of `k + 1` bits per state:
//! `b[q][j] = (c(q) ≥ j)`, so `b[q][0]` says a run is in `q`. The counter of a successor is
//! the maximum over the enabled edges `e = (q, guard, q')` of `c(q) + acc(e)`, so a successor
//! bit is a plain disjunction, monotone in the position:
//! `b'[q'][0] = ∨ guard(e) ∧ b[q][0]` and `b'[q'][j] = ∨ guard(e) ∧ b[q][j - acc(e)]` (j ≥ 1).
//! The round is lost (`advance` returns `false`) when an enabled accepting edge leaves a state
//! whose counter is `k`, or an enabled edge enters a state that accepts every word.
//!
//! **Order of variables.** The bits of each automaton state together, `b[q][0]` to `b[q][k]`,
//! and the signals between the states, each near the states whose guards read it (`order`).
//! Two fixed orders were measured first and both blow up on a conjunction over clients: with
//! all counters above the letter, a diagram must remember every client's counter before it
//! reads a signal (simple_arbiter n = 6 passed 3.2 million nodes at k = 3); with the letter on
//! top, a set of positions became a decision tree over the letter (load_balancer n = 3 passed
//! 3.2 million nodes at k = 1). The quantifiers are applied to level sets wherever the levels
//! lie.
//!
//! **The fixpoint.** `CPre(X)` is `X` with every position bit replaced by its successor
//! function (one simultaneous substitution, no next-state variables), conjoined with the safe
//! letters, and the letter quantified in the turn order: `∀ first ∃ second` when the
//! protagonist moves second, `∃ first ∀ second` when it moves first. The iteration stops as
//! soon as the initial position drops out (the protagonist loses) or nothing changes.
//!
//! **Strategies** are read off per explicit position reached under the strategy (`extract`):
//! few, since a strategy commits to one move per position, and fewer as a reply prefers a move
//! into a position the strategy already has.
//!
//! The explicit solver stays the reference: the successor functions are checked against
//! [`super::game::advance`] here, and the verdicts and bounds in `tests/ltl_random.rs` and
//! `tests/ltl_examples.rs`.

pub(super) mod diagram;
mod extract;

use super::machine::Machine;
use super::spec::SignalId;
use super::translate::Automaton;
use super::{Resource, Stop, Work};
use diagram::{Bdd, Diagram};

/// BDD nodes a game may hold per position of `--max-states`: a node costs about 32 bytes with
/// its hash-table entry, a position of the explicit game a few hundred (its counter vector, its
/// index entry and a successor per letter), so the default budget stays within a few hundred MB.
pub(super) const NODES_PER_POSITION: usize = 16;

/// Most variables a game may have (position bits and signals): the diagram's operations recurse
/// once per level, and the WebAssembly stack is small.
const MAX_LEVELS: usize = 20_000;

/// One bounded game, as [`super::game`] describes it.
pub(super) struct Game<'a> {
    pub automaton: &'a Automaton,
    pub k: u32,
    /// The first mover's signals and the second's.
    pub first: &'a [SignalId],
    pub second: &'a [SignalId],
    pub protagonist_first: bool,
    /// The protagonist's opponent's signals and its own, for its strategy.
    pub reads: &'a [SignalId],
    pub writes: &'a [SignalId],
    /// Nodes the diagram may hold.
    pub max_nodes: usize,
    /// Positions the strategy extraction may visit.
    pub max_positions: usize,
}

/// The result of one game.
pub(super) struct Played {
    /// Positions the strategy extraction visited (none when the game is lost).
    pub positions: usize,
    /// The most nodes the diagram held.
    pub nodes: usize,
    /// The protagonist's strategy, with its number of states before minimisation, if it wins.
    pub strategy: Option<(usize, Machine)>,
}

/// Which variable sits at which level.
pub(super) struct Encoding {
    /// Per signal id, its level (`u32::MAX`: not in the game).
    signal_level: [u32; 64],
    /// The levels of the first mover's signals and the second's, each ascending.
    first: Vec<u32>,
    second: Vec<u32>,
    /// `bit_level[q * width + j]`: the level of `b[q][j]`.
    bit_level: Vec<u32>,
    /// Bits per automaton state: `k + 1`.
    width: u32,
    states: usize,
}

/// A unit of the variable order: an automaton state's counter bits (kept together, lowest
/// first) or one signal.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
enum Unit {
    State(usize),
    Signal(SignalId),
}

impl Encoding {
    pub(super) fn new(automaton: &Automaton, k: u32, first: &[SignalId], second: &[SignalId]) -> Encoding {
        let width = k + 1;
        let mut signal_level = [u32::MAX; 64];
        let mut bit_level = vec![0; automaton.states.len() * width as usize];
        let mut level = 0;
        for unit in order(automaton, first, second) {
            match unit {
                Unit::State(q) => {
                    for j in 0..width as usize {
                        bit_level[q * width as usize + j] = level;
                        level += 1;
                    }
                }
                Unit::Signal(s) => {
                    signal_level[s.index()] = level;
                    level += 1;
                }
            }
        }
        let levels_of = |signals: &[SignalId]| {
            let mut levels: Vec<u32> = signals.iter().map(|s| signal_level[s.index()]).collect();
            levels.sort_unstable();
            levels
        };
        Encoding {
            first: levels_of(first),
            second: levels_of(second),
            signal_level,
            bit_level,
            width,
            states: automaton.states.len(),
        }
    }

    fn levels(&self) -> usize {
        self.bit_level.len() + self.first.len() + self.second.len()
    }

    /// The level of `b[q][j]`.
    fn bit(&self, q: usize, j: u32) -> u32 {
        self.bit_level[q * self.width as usize + j as usize]
    }

    /// The substitution of every position bit by its successor function (`next`, indexed as
    /// `bit_level`), for [`Diagram::compose`].
    fn at_successors(&self, next: &[Bdd]) -> Vec<Option<Bdd>> {
        let mut by: Vec<Option<Bdd>> = vec![None; self.levels()];
        for (i, &f) in next.iter().enumerate() {
            by[self.bit_level[i] as usize] = Some(f);
        }
        by
    }

    /// The position bits of a counter vector, by level (the letter's levels free).
    fn position_values(&self, position: &[i8]) -> Vec<Option<bool>> {
        let mut values = vec![None; self.levels()];
        for (q, &c) in position.iter().enumerate() {
            for j in 0..self.width {
                values[self.bit(q, j) as usize] = Some(i32::from(c) >= j as i32);
            }
        }
        values
    }

    /// The counter vector whose bits `bit(q * (k + 1) + j)` gives (the highest set bit of each
    /// state).
    fn position(&self, bit: impl Fn(usize) -> bool) -> Vec<i8> {
        let width = self.width as usize;
        (0..self.states).map(|q| (0..width).rev().find(|&j| bit(q * width + j)).map_or(-1, |j| j as i8)).collect()
    }

    /// The signal mask of a letter whose levels `bit(level)` gives.
    fn letter(&self, bit: impl Fn(u32) -> bool) -> u64 {
        (0..64).filter(|&s| self.signal_level[s] != u32::MAX && bit(self.signal_level[s])).fold(0, |m, s| m | 1 << s)
    }
}

/// The variable order: what a successor bit or a lost round reads lies close together.
///
/// Each automaton state's successor bits read the guards of the edges into it and the bits of
/// their sources; a lost round reads the guard and the source of a losing edge. Those sets are
/// the hyperedges of a linear arrangement, improved by the FORCE heuristic (Aloul, Markov and
/// Sakallah 2003): each unit moves to the mean of the centres of its hyperedges, and the order
/// with the smallest total span is kept. For a conjunction over clients this puts each client's
/// signals beside its counters, where the fixed order (all counters above the letter) made the
/// diagrams remember every counter until the letter was read: exponential in the clients.
fn order(automaton: &Automaton, first: &[SignalId], second: &[SignalId]) -> Vec<Unit> {
    let signals: Vec<SignalId> = first.iter().chain(second).copied().collect();
    let n = automaton.states.len();
    // Units 0..n are the states, n.. the signals.
    let unit_of_signal = |s: u32| signals.iter().position(|x| x.0 == s).map(|i| n + i);
    let guard_units = |e: &super::translate::Edge| -> Vec<usize> {
        (0..64).filter(|&s| (e.pos | e.neg) >> s & 1 == 1).filter_map(unit_of_signal).collect()
    };
    // Per state, what its successor bits read; then per state, what its losing edges read (one
    // hyperedge for all of them: they are one disjunction, and a hyperedge per edge would pull
    // the signals of a many-edged guard, such as mutual exclusion, into one cluster).
    let mut edges: Vec<Vec<usize>> = vec![vec![]; 2 * n];
    for (q, state) in automaton.states.iter().enumerate() {
        for e in &state.edges {
            let to = e.to as usize;
            let slot = if automaton.states[to].universal { n + q } else { to };
            edges[slot].extend(guard_units(e));
            edges[slot].push(q);
            if slot == to {
                edges[slot].push(to);
            }
        }
    }
    for e in &mut edges {
        e.sort_unstable();
        e.dedup();
    }
    // The first arrangement: states in their order, each after the signals its successor bits
    // read.
    let units = n + signals.len();
    let mut arrangement: Vec<usize> = Vec::with_capacity(units);
    let mut placed = vec![false; units];
    for (q, reads) in edges.iter().take(n).enumerate() {
        for &u in reads {
            if u >= n && !placed[u] {
                placed[u] = true;
                arrangement.push(u);
            }
        }
        placed[q] = true;
        arrangement.push(q);
    }
    arrangement.extend((n..units).filter(|&u| !placed[u]));
    edges.retain(|e| e.len() > 1);
    // Where each unit stands in an arrangement.
    let places = |arrangement: &[usize]| -> Vec<u64> {
        let mut at = vec![0u64; units];
        for (i, &u) in arrangement.iter().enumerate() {
            at[u] = i as u64;
        }
        at
    };
    let span = |arrangement: &[usize]| -> u64 {
        let at = places(arrangement);
        edges
            .iter()
            .map(|e| {
                let (lo, hi) = e.iter().fold((u64::MAX, 0), |(lo, hi), &u| (lo.min(at[u]), hi.max(at[u])));
                hi - lo
            })
            .sum()
    };
    let mut best = (span(&arrangement), arrangement.clone());
    let mut stale = 0;
    for _ in 0..50 {
        // Positions and centres in 1/1024ths, integers: the same order natively and in wasm.
        let at = places(&arrangement);
        let mut sum = vec![0u64; units];
        let mut count = vec![0u64; units];
        for e in &edges {
            let centre = e.iter().map(|&u| at[u] << 10).sum::<u64>() / e.len() as u64;
            for &u in e {
                sum[u] += centre;
                count[u] += 1;
            }
        }
        let target: Vec<u64> = (0..units).map(|u| sum[u].checked_div(count[u]).unwrap_or(at[u] << 10)).collect();
        // Ties keep the current order.
        arrangement.sort_unstable_by_key(|&u| (target[u], at[u]));
        let cost = span(&arrangement);
        if cost < best.0 {
            best = (cost, arrangement.clone());
            stale = 0;
        } else {
            stale += 1;
            if stale == 5 {
                break;
            }
        }
    }
    best.1.into_iter().map(|u| if u < n { Unit::State(u) } else { Unit::Signal(signals[u - n]) }).collect()
}

/// One round as functions of the position and the letter.
pub(super) struct Round {
    /// `next[q * (k + 1) + j]`: the successor's bit `b'[q][j]`.
    next: Vec<Bdd>,
    /// The letters (with the positions) on which the protagonist loses the round.
    lost: Bdd,
}

/// Builds the successor functions and the lost rounds (see the module's documentation).
fn round(d: &mut Diagram, enc: &Encoding, automaton: &Automaton, work: &mut Work) -> Result<Round, Stop> {
    let width = enc.width;
    let mut next = vec![Bdd::FALSE; enc.states * width as usize];
    let mut lost = Bdd::FALSE;
    for (q, state) in automaton.states.iter().enumerate() {
        for e in &state.edges {
            let literals: Vec<(u32, bool)> = (0..64)
                .filter(|&s| (e.pos | e.neg) >> s & 1 == 1)
                .map(|s| (enc.signal_level[s], e.pos >> s & 1 == 1))
                .collect();
            let guard = d.cube(&literals)?;
            let acc = u32::from(e.accepting);
            for j in 0..width {
                let from = if j == 0 { 0 } else { j - acc };
                let here = d.literal(enc.bit(q, from), true)?;
                let term = d.and(guard, here, work)?;
                let slot = e.to as usize * width as usize + j as usize;
                next[slot] = d.or(next[slot], term, work)?;
            }
            // A counter past k, or a run in a state that accepts every word.
            let losing_from = if automaton.states[e.to as usize].universal {
                Some(0)
            } else if e.accepting {
                Some(width - 1)
            } else {
                None
            };
            if let Some(j) = losing_from {
                let here = d.literal(enc.bit(q, j), true)?;
                let term = d.and(guard, here, work)?;
                lost = d.or(lost, term, work)?;
            }
        }
    }
    Ok(Round { next, lost })
}

/// The initial position: a run in the initial state with counter 0 (none in an automaton that
/// accepts nothing).
fn initial(automaton: &Automaton) -> Vec<i8> {
    let mut init = vec![-1i8; automaton.states.len()];
    if !automaton.is_empty() {
        init[automaton.init as usize] = 0;
    }
    init
}

/// Solves `game`: the greatest fixpoint of the controllable predecessor, then, if the
/// protagonist wins, its strategy. A budget stop ends only this game.
pub(super) fn play(game: &Game, work: &mut Work) -> Result<Played, Stop> {
    let automaton = game.automaton;
    let enc = Encoding::new(automaton, game.k, game.first, game.second);
    if enc.levels() > MAX_LEVELS {
        return Err(Stop::budget(
            Resource::Size,
            format!(
                "the game at k = {} has {} variables ({} automaton states × {} counter bits), more than {MAX_LEVELS}",
                game.k,
                enc.levels(),
                enc.states,
                enc.width
            ),
        ));
    }
    let mut d = Diagram::new(game.max_nodes);
    let mut round = round(&mut d, &enc, automaton, work)?;
    let mut safe = d.not(round.lost, work)?;
    let init = initial(automaton);
    let init_values = enc.position_values(&init);
    let at_init = |level: u32| init_values.get(level as usize).copied().flatten().unwrap_or(false);
    // Only counter vectors are positions: a set bit `b[q][j]` has `b[q][j - 1]` set. The
    // successors of a position are positions, so the fixpoint may ignore the other bit vectors,
    // and leaving them out keeps the diagrams of the sets small.
    let mut valid = Bdd::TRUE;
    for q in 0..enc.states {
        for j in 1..enc.width {
            let (low, high) = (d.literal(enc.bit(q, j - 1), true)?, d.literal(enc.bit(q, j), false)?);
            let either = d.or(low, high, work)?;
            valid = d.and(valid, either, work)?;
        }
    }
    let mut winning = valid;
    let (first, second) = (d.level_set(enc.first.iter().copied()), d.level_set(enc.second.iter().copied()));
    let mut live = d.len();
    let good = loop {
        work.at.nodes = d.len();
        let moved = d.compose(winning, &enc.at_successors(&round.next), work)?;
        let good = d.and(safe, moved, work)?;
        let pre = if game.protagonist_first {
            let all_replies = d.quantify(good, &second, false, work)?;
            d.quantify(all_replies, &first, true, work)?
        } else {
            let some_reply = d.quantify(good, &second, true, work)?;
            d.quantify(some_reply, &first, false, work)?
        };
        let pre = d.and(pre, valid, work)?;
        if !d.eval(pre, at_init) {
            return Ok(Played { positions: 0, nodes: d.peak(), strategy: None });
        }
        if pre == winning {
            break good;
        }
        winning = pre;
        // Drop the garbage of finished iterations once it outweighs what is live.
        if d.len() > 2 * live + (1 << 16) {
            let mut roots: Vec<Bdd> = round.next.clone();
            roots.extend([valid, safe, round.lost, winning]);
            d.compact(&mut roots);
            winning = roots.pop().expect("pushed");
            round.lost = roots.pop().expect("pushed");
            safe = roots.pop().expect("pushed");
            valid = roots.pop().expect("pushed");
            round.next = roots;
            live = d.len();
        }
    };
    // The extraction builds diagrams of its own per position: start it without the fixpoint's
    // garbage, which may be most of the node budget.
    let mut roots: Vec<Bdd> = round.next.clone();
    roots.extend([round.lost, good]);
    d.compact(&mut roots);
    let good = roots.pop().expect("pushed");
    round.lost = roots.pop().expect("pushed");
    round.next = roots;
    let (raw, positions, machine) = extract::strategy(&mut d, &enc, &round, good, game, &init, work)?;
    Ok(Played { positions, nodes: d.peak(), strategy: Some((raw, machine)) })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ltl::game::advance;
    use crate::ltl::translate::{AutomatonState, Edge};
    use crate::ltl::Progress;
    use crate::rng::Rng;

    /// A random automaton over `signals` signals: a few states, random guards (cubes), marks
    /// and universal states.
    fn random_automaton(rng: &mut Rng, signals: u32) -> Automaton {
        let n = 1 + rng.below(5) as usize;
        let states = (0..n)
            .map(|_| {
                let edges = (0..rng.below(4))
                    .map(|_| {
                        let (mut pos, mut neg) = (0u64, 0u64);
                        for s in 0..signals {
                            match rng.below(3) {
                                0 => pos |= 1 << s,
                                1 => neg |= 1 << s,
                                _ => {}
                            }
                        }
                        Edge { pos, neg, to: rng.below(n as u64) as u32, accepting: rng.below(2) == 0 }
                    })
                    .collect();
                AutomatonState { label: String::new(), edges, universal: rng.below(8) == 0 }
            })
            .collect();
        Automaton { init: rng.below(n as u64) as u32, states }
    }

    /// The symbolic round agrees with `game::advance` on every position (reachable or not) and
    /// every letter: lost exactly when `advance` says so, else the successor's bits.
    #[test]
    fn the_symbolic_round_is_the_explicit_successor() {
        let mut rng = Rng::new(29);
        let mut progress = |_: &Progress| true;
        let mut work = Work::new(u64::MAX, &mut progress);
        let first = [SignalId(1), SignalId(0)];
        let second = [SignalId(2)];
        let mut compared = 0;
        for _ in 0..300 {
            let automaton = random_automaton(&mut rng, 3);
            let k = rng.below(3) as u32;
            let enc = Encoding::new(&automaton, k, &first, &second);
            let mut d = Diagram::new(100_000);
            let round = round(&mut d, &enc, &automaton, &mut work).unwrap();
            let n = automaton.states.len();
            let counters = (k as u64 + 2).pow(n as u32);
            for code in 0..counters {
                let position: Vec<i8> =
                    (0..n).map(|q| ((code / (k as u64 + 2).pow(q as u32)) % (k as u64 + 2)) as i8 - 1).collect();
                let values = enc.position_values(&position);
                for letter in 0..8u64 {
                    let at = |level: u32| {
                        if enc.first.contains(&level) || enc.second.contains(&level) {
                            let s = (0..3).find(|&s| enc.signal_level[s] == level).expect("a signal");
                            letter >> s & 1 == 1
                        } else {
                            values[level as usize].expect("a position bit")
                        }
                    };
                    let mut next = vec![0i8; n];
                    let safe = advance(&automaton, k as i8, &position, letter, &mut next);
                    assert_eq!(!d.eval(round.lost, at), safe, "{automaton:?} k = {k} at {position:?} on {letter}");
                    if safe {
                        let symbolic = enc.position(|bit| d.eval(round.next[bit], at));
                        assert_eq!(symbolic, next, "{automaton:?} k = {k} at {position:?} on {letter}");
                    }
                    compared += 1;
                }
            }
        }
        assert!(compared > 10_000, "{compared}");
    }
}
