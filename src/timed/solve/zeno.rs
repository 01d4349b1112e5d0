//! The zeno memory (5.1): per search item, the persistent set of plant states visited since the
//! last plan progress, and how a new state's memory is formed.

use super::{Search, Solver};

/// The zeno memory (5.1): for every search item, the set of plant states (env ids) visited since
/// the last plan progress. The sets are persistent treaps sharing structure, so that adding a
/// state and testing membership cost O(log n) however long a path without progress grows (a
/// linked list made a 40 000-node chain quadratic).
pub(super) struct ZenoSets {
    /// (env id, left, right); a set is the id of its root node, the empty set `EMPTY`.
    pub(super) nodes: Vec<(u32, u32, u32)>,
}

impl ZenoSets {
    /// The empty set (no node).
    const EMPTY: u32 = u32::MAX;

    /// A fixed pseudo-random priority per key (a bijective integer mix), so that the treap's
    /// shape does not depend on the order of insertions.
    fn priority(env: u32) -> u32 {
        let mut x = env ^ 0x9e37_79b9;
        x ^= x >> 16;
        x = x.wrapping_mul(0x85eb_ca6b);
        x ^= x >> 13;
        x = x.wrapping_mul(0xc2b2_ae35);
        x ^ (x >> 16)
    }

    fn node(&mut self, env: u32, left: u32, right: u32) -> u32 {
        self.nodes.push((env, left, right));
        (self.nodes.len() - 1) as u32
    }

    pub(super) fn singleton(&mut self, env: u32) -> u32 {
        self.node(env, Self::EMPTY, Self::EMPTY)
    }

    fn contains(&self, mut set: u32, env: u32) -> bool {
        while set != Self::EMPTY {
            let (key, left, right) = self.nodes[set as usize];
            if env == key {
                return true;
            }
            set = if env < key { left } else { right };
        }
        false
    }

    /// `set` with `env` added; `set` itself if it already holds `env`.
    pub(super) fn insert(&mut self, set: u32, env: u32) -> u32 {
        if self.contains(set, env) {
            set
        } else {
            self.insert_new(set, env)
        }
    }

    /// Path-copying insertion of a key that is not in `set`.
    fn insert_new(&mut self, set: u32, env: u32) -> u32 {
        if set == Self::EMPTY {
            return self.singleton(env);
        }
        let (key, left, right) = self.nodes[set as usize];
        if Self::priority(env) > Self::priority(key) {
            let (l, r) = self.split(set, env);
            return self.node(env, l, r);
        }
        if env < key {
            let l = self.insert_new(left, env);
            self.node(key, l, right)
        } else {
            let r = self.insert_new(right, env);
            self.node(key, left, r)
        }
    }

    /// The keys of `set` below and above `env` (which it does not hold), as two new sets.
    fn split(&mut self, set: u32, env: u32) -> (u32, u32) {
        if set == Self::EMPTY {
            return (Self::EMPTY, Self::EMPTY);
        }
        let (key, left, right) = self.nodes[set as usize];
        if key < env {
            let (l, r) = self.split(right, env);
            (self.node(key, left, l), r)
        } else {
            let (l, r) = self.split(left, env);
            (l, self.node(key, r, right))
        }
    }
}

/// How the zeno memory of a new state is formed.
#[derive(Clone, Copy)]
pub(super) enum Vis {
    /// A plan progressed: remember only the new plant state.
    Fresh,
    /// No progress: remember the new plant state on top of `parent`'s memory.
    Extend(u32),
    /// Waiting or a guard check: the plant state is unchanged.
    Same(u32),
}

impl<S: Search> Solver<'_, '_, S> {
    /// True if the plant state `env_id` is in the zeno memory `vis`.
    pub(super) fn visited(&self, vis: u32, env_id: u32) -> bool {
        self.zeno.contains(vis, env_id)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::HashSet;

    #[test]
    fn zeno_sets_are_persistent_sets() {
        // A random tree of insertions: every version keeps exactly its own keys, whatever was
        // added to other versions later.
        let mut rng = crate::rng::Rng::new(9);
        let mut sets = ZenoSets { nodes: Vec::new() };
        let first = sets.singleton(5);
        let mut versions: Vec<(u32, HashSet<u32>)> = vec![(first, HashSet::from([5]))];
        for _ in 0..3000 {
            let (set, keys) = versions[rng.below(versions.len() as u64) as usize].clone();
            let key = rng.below(400) as u32;
            let grown = sets.insert(set, key);
            let mut grown_keys = keys.clone();
            assert_eq!(grown == set, !grown_keys.insert(key), "inserting a present key keeps the set");
            versions.push((grown, grown_keys));
        }
        for (set, keys) in &versions {
            for key in 0..400 {
                assert_eq!(sets.contains(*set, key), keys.contains(&key));
            }
        }
        assert!(!sets.contains(ZenoSets::EMPTY, 5));
    }
}
