//! The memoising front: [`Theory`] caches queries on fixed atoms, skips supersets of known
//! unsatisfiable cores and shrinks unsatisfiable combinations to minimal ones.

use super::poly::Atom;
use super::{decide, Answer, Domain};
use serde::Serialize;
use std::collections::HashMap;

/// The work one query may spend unless configured otherwise.
pub const DEFAULT_BUDGET: u64 = 200_000;

/// Counts for reports: queries answered from the cache (or a known unsatisfiable subset) and
/// queries computed by [`decide`].
#[derive(Clone, Copy, PartialEq, Eq, Debug, Default, Serialize)]
pub struct TheoryStats {
    pub queries: usize,
    pub cached: usize,
    pub computed: usize,
    /// Units of work the computed queries spent (boxes split, eliminations).
    pub work: u64,
}

/// Memoising front: the atoms (predicates) fixed once, queried many times with combinations.
#[derive(Clone, Debug)]
pub struct Theory {
    atoms: Vec<Atom>,
    domains: Vec<Domain>,
    budget: u64,
    cache: HashMap<Vec<(usize, bool)>, Answer>,
    /// Known unsatisfiable combinations, none a superset of another.
    unsat: Vec<Vec<(usize, bool)>>,
    stats: TheoryStats,
}

/// Sorted, without duplicates: the cache key.
fn sorted(combination: &[(usize, bool)]) -> Vec<(usize, bool)> {
    let mut key = combination.to_vec();
    crate::sort::sort(&mut key);
    key.dedup();
    key
}

/// Whether every element of the sorted `small` is in the sorted `large`.
fn is_subset(small: &[(usize, bool)], large: &[(usize, bool)]) -> bool {
    let mut rest = large.iter();
    small.iter().all(|x| rest.by_ref().any(|y| y == x))
}

impl Theory {
    pub fn new(atoms: Vec<Atom>, domains: Vec<Domain>) -> Theory {
        Theory {
            atoms,
            domains,
            budget: DEFAULT_BUDGET,
            cache: HashMap::new(),
            unsat: Vec::new(),
            stats: TheoryStats::default(),
        }
    }

    /// The work each computed query may spend (default [`DEFAULT_BUDGET`]).
    pub fn with_budget(mut self, budget: u64) -> Theory {
        self.budget = budget;
        self
    }

    /// Changes the work each computed query from now on may spend.
    pub fn set_budget(&mut self, budget: u64) {
        self.budget = budget;
    }

    pub fn atoms(&self) -> &[Atom] {
        &self.atoms
    }

    pub fn domains(&self) -> &[Domain] {
        &self.domains
    }

    /// combination: (atom index, polarity) pairs; memoised on the sorted combination; a query on
    /// a superset of a known Unsat combination is Unsat without work. An atom index out of range
    /// gives Unknown.
    pub fn check(&mut self, combination: &[(usize, bool)]) -> Answer {
        self.stats.queries += 1;
        let key = sorted(combination);
        if let Some(answer) = self.cache.get(&key) {
            self.stats.cached += 1;
            return answer.clone();
        }
        if self.unsat.iter().any(|core| is_subset(core, &key)) {
            self.stats.cached += 1;
            return Answer::Unsat;
        }
        self.stats.computed += 1;
        let answer = if key.windows(2).any(|w| w[0].0 == w[1].0) {
            Answer::Unsat // an atom with both polarities
        } else if key.iter().any(|&(i, _)| i >= self.atoms.len()) {
            Answer::Unknown
        } else {
            let literals: Vec<(Atom, bool)> = key.iter().map(|&(i, p)| (self.atoms[i].clone(), p)).collect();
            let mut budget = self.budget;
            let answer = decide(&literals, &self.domains, &mut budget);
            self.stats.work += self.budget - budget;
            answer
        };
        if answer == Answer::Unsat {
            self.unsat.retain(|core| !is_subset(&key, core));
            self.unsat.push(key.clone());
        }
        self.cache.insert(key, answer.clone());
        answer
    }

    /// A smallest-found unsatisfiable sub-combination (literals dropped greedily while the rest
    /// stays Unsat), sorted — the learned assumption is its negation, e.g. `G !(p0 && p1)`.
    /// Meant for Unsat combinations: any other (Sat or Unknown) comes back unchanged (sorted);
    /// callers must learn only from combinations `check` answered Unsat.
    pub fn minimal_unsat(&mut self, combination: &[(usize, bool)]) -> Vec<(usize, bool)> {
        let key = sorted(combination);
        if self.check(&key) != Answer::Unsat {
            return key;
        }
        let mut core = self
            .unsat
            .iter()
            .filter(|core| is_subset(core, &key))
            .min_by_key(|core| core.len())
            .cloned()
            .unwrap_or(key);
        let mut i = 0;
        while i < core.len() {
            let mut smaller = core.clone();
            smaller.remove(i);
            if self.check(&smaller) == Answer::Unsat {
                core = smaller;
            } else {
                i += 1;
            }
        }
        core
    }

    /// How many queries were asked (`check`, including those `minimal_unsat` makes).
    pub fn queries(&self) -> usize {
        self.stats.queries
    }

    /// How many were answered from the cache or a known unsatisfiable subset.
    pub fn cached(&self) -> usize {
        self.stats.cached
    }

    /// How many were computed.
    pub fn computed(&self) -> usize {
        self.stats.computed
    }

    pub fn stats(&self) -> TheoryStats {
        self.stats
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ltl::theory::tests::{atom, is_sat, k, real, x};
    use crate::ltl::theory::Rel;

    #[test]
    fn theory_memo_and_cores() {
        let domains = vec![real("0", "4"), real("0", "4")];
        let atoms = vec![
            atom(x(0), Rel::Gt, k("3")),                 // 0
            atom(x(0), Rel::Lt, k("1")),                 // 1
            atom(x(1).pow(2).unwrap(), Rel::Gt, k("1")), // 2
            atom(x(0), Rel::Gt, k("5")),                 // 3: alone Unsat in the box
        ];
        let mut theory = Theory::new(atoms, domains).with_budget(50_000);
        assert_eq!(theory.check(&[(0, true), (1, true), (2, true)]), Answer::Unsat);
        assert_eq!(theory.minimal_unsat(&[(0, true), (1, true), (2, true)]), vec![(0, true), (1, true)]);
        let before = theory.computed();
        assert_eq!(theory.check(&[(2, false), (0, true), (1, true)]), Answer::Unsat);
        assert_eq!(theory.computed(), before, "a superset of a known core costs nothing");
        assert_eq!(theory.minimal_unsat(&[(2, true), (3, true), (0, false)]), vec![(3, true)]);
        assert_eq!(theory.check(&[(2, true), (2, false)]), Answer::Unsat);
        assert_eq!(theory.check(&[(9, true)]), Answer::Unknown);
        assert!(is_sat(&theory.check(&[(0, true), (2, true)])));
        assert_eq!(theory.minimal_unsat(&[(0, true), (2, true)]), vec![(0, true), (2, true)]);
        assert_eq!(theory.queries(), theory.cached() + theory.computed());
    }
}
