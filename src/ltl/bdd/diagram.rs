//! A small package of reduced ordered binary decision diagrams: one shared node table
//! (hash-consed, so equal functions are equal ids), a lossy computed table, and the operations
//! the bounded games need — conjunction, disjunction, negation, if-then-else, quantification
//! of a set of levels, simultaneous substitution (vector composition) and cofactors.
//!
//! Every operation draws on the run's [`Work`] (a unit per recursive step, charged in batches)
//! and stops with a [`Stop`] when the node table would pass its cap, so a large game ends as a
//! budget stop, never as an out-of-memory abort, and a cancellation is honoured within an
//! operation. Nodes are never freed during an operation; [`Diagram::compact`] keeps only what
//! given roots reach, between the fixpoint's iterations.

use crate::ltl::{Resource, Stop, Work};
use hashbrown::HashMap;

/// A function: an index into the node table. Equal functions have equal ids.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub(crate) struct Bdd(u32);

impl Bdd {
    pub(crate) const FALSE: Bdd = Bdd(0);
    pub(crate) const TRUE: Bdd = Bdd(1);

    pub(crate) fn is_constant(self) -> bool {
        self.0 < 2
    }

    /// Its index in the node table (for keys of tables outside the diagram).
    pub(crate) fn index(self) -> u32 {
        self.0
    }
}

/// The level of the terminals: below every variable.
const TERMINAL: u32 = u32::MAX;

/// A decision on the variable at `level` (smaller levels nearer the root).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
struct Node {
    level: u32,
    lo: Bdd,
    hi: Bdd,
}

/// Operations remembered in the computed table.
#[derive(Clone, Copy, PartialEq, Eq)]
#[repr(u32)]
enum Op {
    Empty = 0,
    And,
    Or,
    Not,
    Ite,
    Exists,
    ForAll,
}

#[derive(Clone, Copy)]
struct Entry {
    op: Op,
    a: u32,
    b: u32,
    c: u32,
    result: Bdd,
}

const EMPTY: Entry = Entry { op: Op::Empty, a: 0, b: 0, c: 0, result: Bdd::FALSE };

/// Entries of the computed table (a power of two): 20 bytes each, 5 MB.
const CACHE_SIZE: usize = 1 << 18;

/// Recursive steps charged to the run's work at once.
const BATCH: u64 = 1024;

/// Units of work one recursive step costs. `--max-work` is about proportional to time across
/// the solvers: a step (a unique-table lookup in a table of millions of nodes, a computed-table
/// probe) takes 100–200 ns in the release build where the explicit solver spends 2–4 ns per
/// unit, so with one unit per step the default budget let a bdd run go on for minutes
/// (load_balancer n = 3) instead of the few seconds it stands for.
const UNITS_PER_STEP: u64 = 32;

/// The node table and the computed table.
pub(crate) struct Diagram {
    nodes: Vec<Node>,
    unique: HashMap<Node, Bdd>,
    cache: Vec<Entry>,
    /// The most nodes the table may hold.
    max_nodes: usize,
    /// The largest the table has been.
    peak: usize,
    /// Steps not yet charged to the run's work.
    steps: u64,
    /// Level sets made so far (their ids key the computed table).
    sets: u32,
}

/// Variables to quantify, by level: made by [`Diagram::level_set`], whose id names it in the
/// computed table.
pub(crate) struct LevelSet {
    id: u32,
    /// Per level up to the deepest member, whether it is one.
    member: Vec<bool>,
}

impl Diagram {
    pub(crate) fn new(max_nodes: usize) -> Diagram {
        let terminal = |value| Node { level: TERMINAL, lo: value, hi: value };
        Diagram {
            nodes: vec![terminal(Bdd::FALSE), terminal(Bdd::TRUE)],
            unique: HashMap::new(),
            cache: vec![EMPTY; CACHE_SIZE],
            max_nodes: max_nodes.max(2),
            peak: 2,
            steps: 0,
            sets: 0,
        }
    }

    /// Nodes in the table now (terminals included).
    pub(crate) fn len(&self) -> usize {
        self.nodes.len()
    }

    /// The largest the table has been.
    pub(crate) fn peak(&self) -> usize {
        self.peak
    }

    pub(crate) fn level(&self, f: Bdd) -> u32 {
        self.nodes[f.0 as usize].level
    }

    /// `f` with the variable at `level` (which no variable of `f` lies above) set to `value`:
    /// one step of a decision read top-down.
    pub(crate) fn cofactor_at(&self, f: Bdd, level: u32, value: bool) -> Bdd {
        let (lo, hi) = self.cofactors_at(f, level);
        if value {
            hi
        } else {
            lo
        }
    }

    /// The two cofactors of `f` on the variable at `level` (which no variable of `f` lies above).
    fn cofactors_at(&self, f: Bdd, level: u32) -> (Bdd, Bdd) {
        let node = self.nodes[f.0 as usize];
        if node.level == level {
            (node.lo, node.hi)
        } else {
            (f, f)
        }
    }

    fn tick(&mut self, work: &mut Work) -> Result<(), Stop> {
        self.steps += 1;
        if self.steps == BATCH {
            self.steps = 0;
            work.spend(BATCH * UNITS_PER_STEP)?;
        }
        Ok(())
    }

    /// The node deciding `level` between `lo` and `hi`, shared if it exists.
    fn make(&mut self, level: u32, lo: Bdd, hi: Bdd) -> Result<Bdd, Stop> {
        if lo == hi {
            return Ok(lo);
        }
        let node = Node { level, lo, hi };
        if let Some(&f) = self.unique.get(&node) {
            return Ok(f);
        }
        if self.nodes.len() >= self.max_nodes {
            return Err(Stop::budget(
                Resource::States,
                format!("the game needs more than {} BDD nodes (--max-states)", self.max_nodes),
            ));
        }
        let f = Bdd(self.nodes.len() as u32);
        self.nodes.push(node);
        self.unique.insert(node, f);
        self.peak = self.peak.max(self.nodes.len());
        Ok(f)
    }

    /// The variable at `level`, or its negation.
    pub(crate) fn literal(&mut self, level: u32, positive: bool) -> Result<Bdd, Stop> {
        if positive {
            self.make(level, Bdd::FALSE, Bdd::TRUE)
        } else {
            self.make(level, Bdd::TRUE, Bdd::FALSE)
        }
    }

    /// The conjunction of literals (level, value), in any order.
    pub(crate) fn cube(&mut self, literals: &[(u32, bool)]) -> Result<Bdd, Stop> {
        let mut sorted = literals.to_vec();
        crate::sort::sort_by_key(&mut sorted, |&(level, _)| std::cmp::Reverse(level));
        let mut f = Bdd::TRUE;
        for (level, value) in sorted {
            f = if value { self.make(level, Bdd::FALSE, f)? } else { self.make(level, f, Bdd::FALSE)? };
        }
        Ok(f)
    }

    fn slot(op: Op, a: u32, b: u32, c: u32) -> usize {
        let h = (op as u32 as u64)
            .wrapping_mul(0x9E37_79B9_7F4A_7C15)
            .wrapping_add(a as u64)
            .wrapping_mul(0x9E37_79B9_7F4A_7C15)
            .wrapping_add(b as u64)
            .wrapping_mul(0x9E37_79B9_7F4A_7C15)
            .wrapping_add(c as u64)
            .wrapping_mul(0x9E37_79B9_7F4A_7C15);
        (h >> 40) as usize & (CACHE_SIZE - 1)
    }

    fn cached(&self, op: Op, a: u32, b: u32, c: u32) -> Option<Bdd> {
        let e = self.cache[Self::slot(op, a, b, c)];
        (e.op == op && e.a == a && e.b == b && e.c == c).then_some(e.result)
    }

    fn remember(&mut self, op: Op, a: u32, b: u32, c: u32, result: Bdd) {
        self.cache[Self::slot(op, a, b, c)] = Entry { op, a, b, c, result };
    }

    pub(crate) fn not(&mut self, f: Bdd, work: &mut Work) -> Result<Bdd, Stop> {
        if f.is_constant() {
            return Ok(Bdd(1 - f.0));
        }
        if let Some(r) = self.cached(Op::Not, f.0, 0, 0) {
            return Ok(r);
        }
        self.tick(work)?;
        let Node { level, lo, hi } = self.nodes[f.0 as usize];
        let (lo, hi) = (self.not(lo, work)?, self.not(hi, work)?);
        let r = self.make(level, lo, hi)?;
        self.remember(Op::Not, f.0, 0, 0, r);
        Ok(r)
    }

    pub(crate) fn and(&mut self, f: Bdd, g: Bdd, work: &mut Work) -> Result<Bdd, Stop> {
        self.apply(Op::And, f, g, work)
    }

    pub(crate) fn or(&mut self, f: Bdd, g: Bdd, work: &mut Work) -> Result<Bdd, Stop> {
        self.apply(Op::Or, f, g, work)
    }

    fn apply(&mut self, op: Op, f: Bdd, g: Bdd, work: &mut Work) -> Result<Bdd, Stop> {
        // The absorbing element, the neutral one, idempotence.
        let (absorbing, neutral) = if op == Op::And { (Bdd::FALSE, Bdd::TRUE) } else { (Bdd::TRUE, Bdd::FALSE) };
        if f == absorbing || g == absorbing {
            return Ok(absorbing);
        }
        if f == neutral || f == g {
            return Ok(g);
        }
        if g == neutral {
            return Ok(f);
        }
        // Commutative: one order of the operands in the table.
        let (f, g) = if f < g { (f, g) } else { (g, f) };
        if let Some(r) = self.cached(op, f.0, g.0, 0) {
            return Ok(r);
        }
        self.tick(work)?;
        let level = self.level(f).min(self.level(g));
        let (f0, f1) = self.cofactors_at(f, level);
        let (g0, g1) = self.cofactors_at(g, level);
        let lo = self.apply(op, f0, g0, work)?;
        let hi = self.apply(op, f1, g1, work)?;
        let r = self.make(level, lo, hi)?;
        self.remember(op, f.0, g.0, 0, r);
        Ok(r)
    }

    /// `if f then g else h`.
    pub(crate) fn ite(&mut self, f: Bdd, g: Bdd, h: Bdd, work: &mut Work) -> Result<Bdd, Stop> {
        if f == Bdd::TRUE || g == h {
            return Ok(g);
        }
        if f == Bdd::FALSE {
            return Ok(h);
        }
        if g == Bdd::TRUE && h == Bdd::FALSE {
            return Ok(f);
        }
        if g == Bdd::FALSE && h == Bdd::TRUE {
            return self.not(f, work);
        }
        if h == Bdd::FALSE {
            return self.and(f, g, work);
        }
        if g == Bdd::TRUE {
            return self.or(f, h, work);
        }
        if let Some(r) = self.cached(Op::Ite, f.0, g.0, h.0) {
            return Ok(r);
        }
        self.tick(work)?;
        let level = self.level(f).min(self.level(g)).min(self.level(h));
        let (f0, f1) = self.cofactors_at(f, level);
        let (g0, g1) = self.cofactors_at(g, level);
        let (h0, h1) = self.cofactors_at(h, level);
        let lo = self.ite(f0, g0, h0, work)?;
        let hi = self.ite(f1, g1, h1, work)?;
        let r = self.make(level, lo, hi)?;
        self.remember(Op::Ite, f.0, g.0, h.0, r);
        Ok(r)
    }

    /// The set of the variables at `levels`, for [`Diagram::quantify`].
    pub(crate) fn level_set(&mut self, levels: impl IntoIterator<Item = u32>) -> LevelSet {
        self.sets += 1;
        let mut member = Vec::new();
        for level in levels {
            let l = level as usize;
            if member.len() <= l {
                member.resize(l + 1, false);
            }
            member[l] = true;
        }
        LevelSet { id: self.sets, member }
    }

    /// `∃ set. f` (or `∀` when `!exists`) for the variables of `set`, wherever they lie in the
    /// order.
    pub(crate) fn quantify(&mut self, f: Bdd, set: &LevelSet, exists: bool, work: &mut Work) -> Result<Bdd, Stop> {
        let level = self.level(f);
        if level as usize >= set.member.len() {
            return Ok(f);
        }
        let op = if exists { Op::Exists } else { Op::ForAll };
        if let Some(r) = self.cached(op, f.0, set.id, 0) {
            return Ok(r);
        }
        self.tick(work)?;
        let Node { lo, hi, .. } = self.nodes[f.0 as usize];
        let lo = self.quantify(lo, set, exists, work)?;
        let r = if !set.member[level as usize] {
            let hi = self.quantify(hi, set, exists, work)?;
            self.make(level, lo, hi)?
        } else if lo == Bdd::TRUE && exists || lo == Bdd::FALSE && !exists {
            // The other branch cannot change the result.
            lo
        } else {
            let hi = self.quantify(hi, set, exists, work)?;
            if exists {
                self.or(lo, hi, work)?
            } else {
                self.and(lo, hi, work)?
            }
        };
        self.remember(op, f.0, set.id, 0, r);
        Ok(r)
    }

    /// `f` with every variable at level `l` replaced by `by[l]` at once (a variable past the
    /// end of `by`, or with `None`, stays itself).
    pub(crate) fn compose(&mut self, f: Bdd, by: &[Option<Bdd>], work: &mut Work) -> Result<Bdd, Stop> {
        let mut memo = HashMap::new();
        self.compose_memo(f, by, &mut memo, work)
    }

    fn compose_memo(
        &mut self,
        f: Bdd,
        by: &[Option<Bdd>],
        memo: &mut HashMap<Bdd, Bdd>,
        work: &mut Work,
    ) -> Result<Bdd, Stop> {
        if f.is_constant() {
            return Ok(f);
        }
        if let Some(&r) = memo.get(&f) {
            return Ok(r);
        }
        self.tick(work)?;
        let Node { level, lo, hi } = self.nodes[f.0 as usize];
        let lo = self.compose_memo(lo, by, memo, work)?;
        let hi = self.compose_memo(hi, by, memo, work)?;
        let choice = match by.get(level as usize).copied().flatten() {
            Some(g) => g,
            None => self.literal(level, true)?,
        };
        let r = self.ite(choice, hi, lo, work)?;
        memo.insert(f, r);
        Ok(r)
    }

    /// `f` with the variables at the levels `values` gives fixed (`values[l]`; past the end or
    /// `None`: free).
    pub(crate) fn restrict(&mut self, f: Bdd, values: &[Option<bool>], work: &mut Work) -> Result<Bdd, Stop> {
        let mut memo = HashMap::new();
        self.restrict_memo(f, values, &mut memo, work)
    }

    fn restrict_memo(
        &mut self,
        f: Bdd,
        values: &[Option<bool>],
        memo: &mut HashMap<Bdd, Bdd>,
        work: &mut Work,
    ) -> Result<Bdd, Stop> {
        if f.is_constant() {
            return Ok(f);
        }
        if let Some(&r) = memo.get(&f) {
            return Ok(r);
        }
        self.tick(work)?;
        let Node { level, lo, hi } = self.nodes[f.0 as usize];
        let r = match values.get(level as usize).copied().flatten() {
            Some(false) => self.restrict_memo(lo, values, memo, work)?,
            Some(true) => self.restrict_memo(hi, values, memo, work)?,
            None => {
                let lo = self.restrict_memo(lo, values, memo, work)?;
                let hi = self.restrict_memo(hi, values, memo, work)?;
                self.make(level, lo, hi)?
            }
        };
        memo.insert(f, r);
        Ok(r)
    }

    /// `f` with the variable at `level` fixed to `value`.
    pub(crate) fn restrict_one(&mut self, f: Bdd, level: u32, value: bool, work: &mut Work) -> Result<Bdd, Stop> {
        let mut values = vec![None; level as usize + 1];
        values[level as usize] = Some(value);
        self.restrict(f, &values, work)
    }

    /// The value of `f` under a total assignment (`value(level)`).
    pub(crate) fn eval(&self, mut f: Bdd, value: impl Fn(u32) -> bool) -> bool {
        while !f.is_constant() {
            let node = self.nodes[f.0 as usize];
            f = if value(node.level) { node.hi } else { node.lo };
        }
        f == Bdd::TRUE
    }

    /// Keeps only the nodes `roots` reach (renumbered, `roots` updated in place) and forgets the
    /// computed table: the garbage of finished iterations goes.
    pub(crate) fn compact(&mut self, roots: &mut [Bdd]) {
        let mut keep = vec![false; self.nodes.len()];
        keep[0] = true;
        keep[1] = true;
        let mut stack: Vec<Bdd> = roots.to_vec();
        while let Some(f) = stack.pop() {
            if keep[f.0 as usize] {
                continue;
            }
            keep[f.0 as usize] = true;
            let node = self.nodes[f.0 as usize];
            stack.push(node.lo);
            stack.push(node.hi);
        }
        // A node's children were made before it, so one pass in id order renumbers children
        // first.
        let mut id = vec![u32::MAX; self.nodes.len()];
        let mut nodes = Vec::with_capacity(keep.iter().filter(|&&k| k).count());
        self.unique.clear();
        for (old, node) in self.nodes.iter().enumerate() {
            if !keep[old] {
                continue;
            }
            let new = Bdd(nodes.len() as u32);
            id[old] = new.0;
            let node = if old < 2 {
                *node
            } else {
                Node { level: node.level, lo: Bdd(id[node.lo.0 as usize]), hi: Bdd(id[node.hi.0 as usize]) }
            };
            if old >= 2 {
                self.unique.insert(node, new);
            }
            nodes.push(node);
        }
        self.nodes = nodes;
        for root in roots {
            *root = Bdd(id[root.0 as usize]);
        }
        self.cache.fill(EMPTY);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ltl::Progress;

    /// Every operation against its truth table on four variables.
    #[test]
    fn operations_match_their_truth_tables() {
        let mut progress = |_: &Progress| true;
        let mut work = Work::new(u64::MAX, &mut progress);
        let mut d = Diagram::new(10_000);
        let x: Vec<Bdd> = (0..4).map(|l| d.literal(l, true).unwrap()).collect();
        let a = d.and(x[0], x[2], &mut work).unwrap();
        let not_x1 = d.not(x[1], &mut work).unwrap();
        let b = d.or(a, not_x1, &mut work).unwrap();
        let c = d.ite(x[3], b, x[1], &mut work).unwrap();
        let truth = |v: u32, l: u32| v >> l & 1 == 1;
        for v in 0..16 {
            let expected_b = truth(v, 0) && truth(v, 2) || !truth(v, 1);
            assert_eq!(d.eval(b, |l| truth(v, l)), expected_b);
            let expected_c = if truth(v, 3) { expected_b } else { truth(v, 1) };
            assert_eq!(d.eval(c, |l| truth(v, l)), expected_c);
        }
        // ∃ x0 x1. c and ∀ x0 x1. c, against enumeration.
        let top = d.level_set(0..2);
        let some = d.quantify(c, &top, true, &mut work).unwrap();
        let all = d.quantify(c, &top, false, &mut work).unwrap();
        for v in 0..16u32 {
            let values: Vec<bool> = (0..4).map(|w| d.eval(c, |l| truth((v & !3) | w, l))).collect();
            assert_eq!(d.eval(some, |l| truth(v, l)), values.iter().any(|&b| b));
            assert_eq!(d.eval(all, |l| truth(v, l)), values.iter().all(|&b| b));
        }
        // ∃ x0 x3. c: a set with a gap, quantified in one pass.
        let apart = d.level_set([3, 0]);
        let some = d.quantify(c, &apart, true, &mut work).unwrap();
        for v in 0..16u32 {
            let any = (0..4).any(|w| d.eval(c, |l| truth((v & 0b0110) | (w & 1) | (w >> 1) << 3, l)));
            assert_eq!(d.eval(some, |l| truth(v, l)), any);
        }
        // c[x3 := x0 ∧ x2, x1 := ¬x1] at once.
        let mut by = vec![None; 4];
        by[3] = Some(a);
        by[1] = Some(not_x1);
        let composed = d.compose(c, &by, &mut work).unwrap();
        for v in 0..16u32 {
            let mut u = v & !(1 << 3 | 1 << 1);
            u |= u32::from(truth(v, 0) && truth(v, 2)) << 3 | u32::from(!truth(v, 1)) << 1;
            assert_eq!(d.eval(composed, |l| truth(v, l)), d.eval(c, |l| truth(u, l)), "{v}");
        }
        // Canonical: the same function built another way is the same id, also after compaction.
        let again = d.ite(not_x1, Bdd::TRUE, a, &mut work).unwrap();
        assert_eq!(again, b);
        let mut roots = [b, c, composed];
        d.compact(&mut roots);
        let x0 = d.literal(0, true).unwrap();
        let x2 = d.literal(2, true).unwrap();
        let a = d.and(x0, x2, &mut work).unwrap();
        let x1 = d.literal(1, true).unwrap();
        let not_x1 = d.not(x1, &mut work).unwrap();
        assert_eq!(d.or(a, not_x1, &mut work).unwrap(), roots[0]);
    }

    #[test]
    fn the_node_cap_stops_with_a_budget() {
        let mut progress = |_: &Progress| true;
        let mut work = Work::new(u64::MAX, &mut progress);
        let mut d = Diagram::new(20);
        // x0 <-> x10, x1 <-> x11, …: exponential in this order.
        let mut f = Bdd::TRUE;
        let result = (0..10).try_for_each(|i| {
            let a = d.literal(i, true)?;
            let b = d.literal(i + 10, true)?;
            let not_b = d.not(b, &mut work)?;
            let same = d.ite(a, b, not_b, &mut work)?;
            f = d.and(f, same, &mut work)?;
            Ok(())
        });
        assert!(matches!(result, Err(Stop::Budget { resource: Resource::States, .. })), "{result:?}");
    }
}
