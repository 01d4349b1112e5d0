//! The winner's machine from the solved diagram: one state per explicit position reached
//! under the strategy from the initial one (a position below one the machine has reuses that
//! one's moves, as in `strategy`), its moves chosen symbolically.
//!
//! At a position `p`, `good(p, letter)` (safe letters into the winning region) is a diagram
//! over the letter alone. A protagonist that moves second fixes its signals one at a time, in
//! the diagram's order, each as a function of what it reads: true only where false cannot be
//! completed to a good letter (so outputs stay off unless needed). One that moves first picks
//! one valuation of its signals that is good against every reply, false preferred the same way.
//! The successor bits with the writes substituted are then functions of the read signals
//! alone, and a decision on the read signals (splitting on the topmost one any of them still
//! reads) gives the rows as disjoint cubes, each with one write and one successor.

use super::diagram::{Bdd, Diagram, LevelSet};
use super::{Encoding, Game, Round};
use crate::ltl::antichain::below;
use crate::ltl::game::advance;
use crate::ltl::machine::{Cube, Machine};
use crate::ltl::symbolic::machine_from_rows;
use crate::ltl::{Resource, Stop, Work};
use hashbrown::HashMap;

/// A row before the machine: read cube, written value, next position (an index into the
/// members).
type Rows = Vec<(Cube, u64, u32)>;

/// The strategy from `init` (which the protagonist wins): its states before minimisation, the
/// positions visited, and the machine.
pub(super) fn strategy(
    d: &mut Diagram,
    enc: &Encoding,
    round: &Round,
    good: Bdd,
    game: &Game,
    init: &[i8],
    work: &mut Work,
) -> Result<(usize, usize, Machine), Stop> {
    let mut members: Vec<Vec<i8>> = vec![init.to_vec()];
    let mut member_of: HashMap<Vec<i8>, u32> = HashMap::new();
    member_of.insert(init.to_vec(), 0);
    let mut table: Vec<Rows> = Vec::new();
    let mut visited = 1;
    let sets = OwnSets::new(d, enc, game);
    // The positions below some member, over the position bits: a move into them adds no state.
    let mut known = below_cube(d, enc, init)?;
    let mut i = 0;
    while i < members.len() {
        let leaves = moves(d, enc, round, good, game, &sets, known, &members[i], work)?;
        let mut rows = Rows::new();
        for (read, write, next) in leaves {
            let state = match member_of.get(&next) {
                Some(&m) => m,
                None => {
                    visited += 1;
                    // A position below a member is won by that member's moves (fewer runs,
                    // counters no larger, and successors keep the order).
                    let above = members.iter().position(|m| below(&next, m));
                    let m = match above {
                        Some(m) => m,
                        None => {
                            let cube = below_cube(d, enc, &next)?;
                            known = d.or(known, cube, work)?;
                            members.push(next.clone());
                            members.len() - 1
                        }
                    } as u32;
                    member_of.insert(next, m);
                    m
                }
            };
            rows.push((read, write, state));
        }
        if members.len() > game.max_positions {
            return Err(Stop::budget(
                Resource::States,
                format!(
                    "the strategy at k = {} needs more than the {} positions left of the budget (--max-states)",
                    game.k, game.max_positions
                ),
            ));
        }
        table.push(rows);
        i += 1;
    }
    let raw = table.len();
    let machine = machine_from_rows(&table, game.reads, game.writes, game.protagonist_first);
    Ok((raw, visited, machine))
}

/// The level sets the moves quantify, made once per game so that the computed table serves
/// every position.
struct OwnSets {
    /// The second mover's signals.
    replies: LevelSet,
    /// Per own signal (ascending levels), the own signals below it.
    rest: Vec<LevelSet>,
    /// All own signals.
    own: LevelSet,
}

impl OwnSets {
    fn new(d: &mut Diagram, enc: &Encoding, game: &Game) -> OwnSets {
        let own = if game.protagonist_first { &enc.first } else { &enc.second };
        OwnSets {
            replies: d.level_set(enc.second.iter().copied()),
            rest: (0..own.len()).map(|i| d.level_set(own[i + 1..].iter().copied())).collect(),
            own: d.level_set(own.iter().copied()),
        }
    }
}

/// The protagonist's moves at `position`: (read cube, written value, successor position).
#[allow(clippy::too_many_arguments)]
fn moves(
    d: &mut Diagram,
    enc: &Encoding,
    round: &Round,
    good: Bdd,
    game: &Game,
    sets: &OwnSets,
    known: Bdd,
    position: &[i8],
    work: &mut Work,
) -> Result<Vec<(Cube, u64, Vec<i8>)>, Stop> {
    let values = enc.position_values(position);
    let mut options = d.restrict(good, &values, work)?;
    debug_assert_ne!(options, Bdd::FALSE, "a member is winning");
    let mut next = Vec::with_capacity(round.next.len());
    for &f in &round.next {
        next.push(d.restrict(f, &values, work)?);
    }
    if !game.protagonist_first {
        // Replying to a letter, prefer the moves into positions the strategy has already (or
        // below them): they add no state, and the machine stays small. Only an order among
        // good moves, so the strategy still wins.
        let into_known = d.compose(known, &enc.at_successors(&next), work)?;
        let preferred = d.and(options, into_known, work)?;
        let somewhere = d.quantify(preferred, &sets.own, true, work)?;
        options = d.ite(somewhere, preferred, options, work)?;
    }
    let level_of = |s: crate::ltl::SignalId| enc.signal_level[s.index()];
    // Per written signal: its value as a function of the read signals.
    let mut writes: Vec<Bdd> = vec![Bdd::FALSE; game.writes.len()];
    let mut by: Vec<Option<Bdd>> = vec![None; enc.levels()];
    let own = if game.protagonist_first { &enc.first } else { &enc.second };
    for (i, &level) in own.iter().enumerate() {
        let index = game.writes.iter().position(|&s| level_of(s) == level).expect("the protagonist's signal");
        let off = d.restrict_one(options, level, false, work)?;
        let on = d.restrict_one(options, level, true, work)?;
        let value = if game.protagonist_first {
            // One value for every reply: false if some completion of the remaining own signals
            // is good against every reply.
            let against_all = d.quantify(off, &sets.replies, false, work)?;
            let possible = d.quantify(against_all, &sets.rest[i], true, work)?;
            if possible == Bdd::FALSE {
                Bdd::TRUE
            } else {
                Bdd::FALSE
            }
        } else {
            // Where false can still be completed by the remaining own signals, false.
            let possible = d.quantify(off, &sets.rest[i], true, work)?;
            d.not(possible, work)?
        };
        options = d.ite(value, on, off, work)?;
        writes[index] = value;
        by[level as usize] = Some(value);
    }
    for f in &mut next {
        *f = d.compose(*f, &by, work)?;
    }
    // The decision on the read signals.
    let mut functions = writes.clone();
    functions.extend_from_slice(&next);
    let mut leaves = Vec::new();
    let mut fixed: Vec<(u32, bool)> = Vec::new();
    split(d, enc, game, position, &functions, &mut fixed, &mut leaves, work)?;
    Ok(leaves)
}

/// The leaves of the decision on the read signals below `fixed`: where every function is
/// constant, one row.
#[allow(clippy::too_many_arguments)]
fn split(
    d: &mut Diagram,
    enc: &Encoding,
    game: &Game,
    position: &[i8],
    functions: &[Bdd],
    fixed: &mut Vec<(u32, bool)>,
    leaves: &mut Vec<(Cube, u64, Vec<i8>)>,
    work: &mut Work,
) -> Result<(), Stop> {
    work.spend(1 + functions.len() as u64)?;
    let top = functions.iter().map(|&f| d.level(f)).min().unwrap_or(u32::MAX);
    if functions.iter().all(|f| f.is_constant()) {
        let writes = game.writes.len();
        let write = (0..writes).filter(|&i| functions[i] == Bdd::TRUE).fold(0u64, |m, i| m | 1 << i);
        let successor = enc.position(|bit| functions[writes + bit] == Bdd::TRUE);
        let mut read = Cube::ANY;
        for &(level, value) in fixed.iter() {
            let index = game.reads.iter().position(|s| enc.signal_level[s.index()] == level).expect("a read signal");
            read.care |= 1 << index;
            read.value |= u64::from(value) << index;
        }
        if cfg!(debug_assertions) {
            // The explicit round on one letter of the row agrees.
            let value_at = |level: u32| fixed.iter().any(|&(l, v)| l == level && v);
            let mut letter = enc.letter(value_at);
            for (i, s) in game.writes.iter().enumerate() {
                letter |= (write >> i & 1) << s.index();
            }
            let mut next = vec![0i8; position.len()];
            assert!(advance(game.automaton, game.k as i8, position, letter, &mut next), "a strategy's round is safe");
            assert_eq!(next, successor, "the symbolic successor is the explicit one");
        }
        leaves.push((read, write, successor));
        return Ok(());
    }
    for value in [false, true] {
        let cofactors: Vec<Bdd> = functions.iter().map(|&f| d.cofactor_at(f, top, value)).collect();
        fixed.push((top, value));
        split(d, enc, game, position, &cofactors, fixed, leaves, work)?;
        fixed.pop();
    }
    Ok(())
}

/// The positions at or below `position` (counters no larger), over the position bits: every
/// bit above a state's counter is clear.
fn below_cube(d: &mut Diagram, enc: &Encoding, position: &[i8]) -> Result<Bdd, Stop> {
    let mut literals = Vec::new();
    for (q, &c) in position.iter().enumerate() {
        for j in 0..enc.width {
            if i32::from(c) < j as i32 {
                literals.push((enc.bit(q, j), false));
            }
        }
    }
    d.cube(&literals)
}
