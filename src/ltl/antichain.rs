//! The bounded game solved on antichains (Filiot, Jin and Raskin 2009, as in Acacia+): the
//! protagonist's winning positions are closed downwards (fewer runs with smaller counters are
//! never worse), so the greatest fixpoint `W = Safe ∩ CPre(W)` is kept as the antichain of its
//! maximal positions, and no position below them is ever enumerated.
//!
//! For one letter σ and a target position g, the largest position whose successor on σ lies
//! below g is computed directly: `f(q) = min(k, min over σ-edges q → q' of g(q') − acc)`, and
//! `−1` (q must hold no run) when that is negative. The controllable predecessor is then a
//! union over the protagonist's choices and a meet (pointwise minimum) over the opponent's, on
//! antichains.
//!
//! `game::Game` solves the same game by exploring positions explicitly — faster on the listed
//! specifications, so it is the default — and hands its maximal winning positions to the same
//! strategy extraction as an antichain; `Config::solver` picks, and the tests compare the two.

use super::translate::Automaton;
use super::{Resource, Stop, Work};

/// A downward-closed set of positions, kept as its maximal elements.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub(super) struct Antichain {
    pub elements: Vec<Box<[i8]>>,
}

/// The positions' order: `a` is at least as good for the protagonist as `b` (every run of `a`
/// is a run of `b`, with a counter no larger).
pub(super) fn below(a: &[i8], b: &[i8]) -> bool {
    a.iter().zip(b).all(|(x, y)| x <= y)
}

impl Antichain {
    /// Whether `position` lies in the set.
    pub fn contains(&self, position: &[i8]) -> bool {
        self.elements.iter().any(|e| below(position, e))
    }

    /// An element of the antichain above `position`, if any (its index).
    pub fn above(&self, position: &[i8]) -> Option<usize> {
        self.elements.iter().position(|e| below(position, e))
    }

    pub fn insert(&mut self, x: Box<[i8]>) {
        if self.contains(&x) {
            return;
        }
        self.elements.retain(|e| !below(e, &x));
        self.elements.push(x);
    }

    /// The intersection of two downward-closed sets: pairwise minima, maximal ones kept.
    fn meet(&self, other: &Antichain, work: &mut Work) -> Result<Antichain, Stop> {
        let mut out = Antichain::default();
        for a in &self.elements {
            for b in &other.elements {
                work.spend(1 + out.elements.len() as u64)?;
                out.insert(a.iter().zip(b.iter()).map(|(x, y)| *x.min(y)).collect());
            }
        }
        Ok(out)
    }

    /// Same set (the elements in any order).
    fn same(&self, other: &Antichain) -> bool {
        self.elements.len() == other.elements.len() && self.elements.iter().all(|e| other.elements.contains(e))
    }
}

/// The largest position whose successor on `letter` lies below `target`.
fn predecessor(automaton: &Automaton, k: i8, target: &[i8], letter: u64) -> Box<[i8]> {
    automaton
        .states
        .iter()
        .map(|state| {
            let mut bound = k;
            for e in state.edges.iter().filter(|e| e.enabled(letter)) {
                let allowed = if automaton.states[e.to as usize].universal { -1 } else { target[e.to as usize] };
                bound = bound.min(allowed - i8::from(e.accepting));
            }
            bound.max(-1)
        })
        .collect()
}

/// The antichain of the protagonist's winning positions for bound `k`, where the first mover
/// picks a valuation from `first` and then the second from `second` (signal masks), and the
/// protagonist is the first mover when `protagonist_first`.
pub(super) fn solve(
    automaton: &Automaton,
    k: u32,
    first: &[u64],
    second: &[u64],
    protagonist_first: bool,
    max_elements: usize,
    work: &mut Work,
) -> Result<Antichain, Stop> {
    let k = k as i8;
    let top: Box<[i8]> = automaton.states.iter().map(|s| if s.universal { -1 } else { k }).collect();
    let mut winning = Antichain { elements: vec![top] };
    loop {
        // The positions from which the protagonist can force the next position into `winning`.
        let reach = |letter: u64, work: &mut Work| -> Result<Antichain, Stop> {
            let mut set = Antichain::default();
            for g in &winning.elements {
                work.spend(1 + automaton.states.len() as u64 + set.elements.len() as u64)?;
                set.insert(predecessor(automaton, k, g, letter));
            }
            Ok(set)
        };
        let mut cpre = Antichain::default();
        if protagonist_first {
            // Some own valuation against which every reply stays inside.
            for &a in first {
                let mut all: Option<Antichain> = None;
                for &b in second {
                    let set = reach(a | b, work)?;
                    all = Some(match all {
                        None => set,
                        Some(acc) => acc.meet(&set, work)?,
                    });
                }
                for e in all.map(|s| s.elements).unwrap_or_default() {
                    cpre.insert(e);
                }
            }
        } else {
            // For every valuation of the opponent, some own reply.
            let mut all: Option<Antichain> = None;
            for &a in first {
                let mut some = Antichain::default();
                for &b in second {
                    for e in reach(a | b, work)?.elements {
                        some.insert(e);
                    }
                }
                all = Some(match all {
                    None => some,
                    Some(acc) => acc.meet(&some, work)?,
                });
                if all.as_ref().is_some_and(|s| s.elements.is_empty()) {
                    break;
                }
            }
            cpre = all.unwrap_or_default();
        }
        let next = winning.meet(&cpre, work)?;
        if next.elements.len() > max_elements {
            return Err(Stop::budget(
                Resource::States,
                super::game::position_budget(k as u32, max_elements, max_elements),
            ));
        }
        if next.same(&winning) {
            return Ok(winning);
        }
        winning = next;
    }
}
