//! LTL to Büchi automata, our own (no Rust crate does it).
//!
//! 1. The formula is brought into negation normal form on a hash-consed arena, with the usual
//!    simplifications (constants absorbed, `&&`/`||` flattened, sorted and deduplicated,
//!    complementary literals, `X true`, `F F`, `G G`, …). `G a` is `false R a`, `F a` is
//!    `true U a`, `a W b` is `b R (a || b)`.
//! 2. A state is a conjunction of obligations (itself a formula of the arena). It is expanded
//!    into terms — a cube of literals that must hold now, the obligations for the next step, and
//!    the untils whose fulfilment this term defers — by the tableau rules
//!    `a U b = b || (a && X(a U b))` and `a R b = b && (a || X(a R b))`; a term implied by a
//!    weaker one of the same state is dropped (subsumption). This is the on-the-fly construction
//!    of Couvreur (1999) with transition-based generalised Büchi acceptance: a run is accepting
//!    iff, for every until, infinitely many of its transitions do not defer it.
//! 3. Degeneralisation with a level counter gives one acceptance condition on transitions; only
//!    the untils that some transition defers take a level.
//! 4. States that cannot reach an accepting cycle are removed (they can never help a run be
//!    accepting), and acceptance marks on transitions between strongly connected components are
//!    cleared (a run takes each of them at most once). The bounded games count accepting
//!    transitions, so fewer marks mean smaller games and smaller bounds.

use super::spec::{Ltl, SignalId};
use super::{Progress, Resource, Stop, Work};
use hashbrown::HashMap;
use petgraph::graph::DiGraph;
use std::rc::Rc;

/// One transition of an [`Automaton`]: enabled on letters (valuations of all signals, bit `i`
/// signal `i`) that contain `pos` and avoid `neg`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Edge {
    pub pos: u64,
    pub neg: u64,
    pub to: u32,
    pub accepting: bool,
}

impl Edge {
    pub fn enabled(&self, letter: u64) -> bool {
        letter & self.pos == self.pos && letter & self.neg == 0
    }
}

#[derive(Clone, Debug)]
pub struct AutomatonState {
    /// The obligations this state stands for, as infix text, with the degeneralisation level.
    pub label: String,
    pub edges: Vec<Edge>,
    /// Every word is accepted from here: a run that reaches this state is accepting, so a game
    /// position containing it is lost at once.
    pub universal: bool,
}

/// A nondeterministic Büchi automaton with acceptance on transitions.
#[derive(Clone, Debug)]
pub struct Automaton {
    pub init: u32,
    pub states: Vec<AutomatonState>,
}

impl Automaton {
    /// Whether the automaton accepts no word at all (its initial state was pruned away, which
    /// leaves a single state without edges).
    pub fn is_empty(&self) -> bool {
        self.states.len() == 1 && self.states[0].edges.is_empty() && !self.states[0].universal
    }
}

/// Translates `formula` into a Büchi automaton accepting exactly its models. States are named
/// with `name`. Stops when more than `max_states` states would be built, or past `max_work`
/// units of work (terms combined and compared).
pub fn translate(
    formula: &Ltl,
    name: &dyn Fn(SignalId) -> String,
    max_states: usize,
    max_work: u64,
) -> Result<Automaton, Stop> {
    translate_within(formula, name, max_states, &mut Work::new(max_work, &mut |_: &Progress| true))
}

/// [`translate`] drawing on a run's work budget.
pub(crate) fn translate_within(
    formula: &Ltl,
    name: &dyn Fn(SignalId) -> String,
    max_states: usize,
    work: &mut Work,
) -> Result<Automaton, Stop> {
    let mut arena = Arena::default();
    let root = arena.nnf(formula, false);
    let tgba = arena.explore(root, max_states, work)?;
    let tba = degeneralise(&tgba, max_states)?;
    Ok(prune(tba, &arena, name))
}

/// Index of a formula in the [`Arena`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
struct F(u32);

#[derive(Clone, Debug, PartialEq, Eq, Hash)]
enum Node {
    True,
    False,
    Lit(u32, bool),
    And(Vec<F>),
    Or(Vec<F>),
    Next(F),
    Until(F, F),
    Release(F, F),
}

/// One way to satisfy a state for one step.
#[derive(Clone, Debug, PartialEq, Eq)]
struct Term {
    pos: u64,
    neg: u64,
    /// Obligations for the next step, sorted and deduplicated.
    next: Vec<F>,
    /// Bit `i`: the `i`-th until is deferred by this term.
    pending: u64,
}

impl Term {
    const TRUE: Term = Term { pos: 0, neg: 0, next: Vec::new(), pending: 0 };

    fn and(&self, other: &Term) -> Option<Term> {
        let pos = self.pos | other.pos;
        let neg = self.neg | other.neg;
        if pos & neg != 0 {
            return None;
        }
        let mut next = self.next.clone();
        next.extend_from_slice(&other.next);
        crate::sort::sort(&mut next);
        next.dedup();
        Some(Term { pos, neg, next, pending: self.pending | other.pending })
    }

    /// Whether every step this term allows is also allowed by `self`, with no worse acceptance.
    fn subsumes(&self, other: &Term) -> bool {
        self.pos & !other.pos == 0
            && self.neg & !other.neg == 0
            && self.pending & !other.pending == 0
            && is_subset(&self.next, &other.next)
    }
}

fn is_subset(small: &[F], big: &[F]) -> bool {
    let mut j = 0;
    for x in small {
        while j < big.len() && big[j] < *x {
            j += 1;
        }
        if j == big.len() || big[j] != *x {
            return false;
        }
        j += 1;
    }
    true
}

/// Keeps the terms no other term subsumes (one of two equal terms).
fn minimise(terms: Vec<Term>, work: &mut Work) -> Result<Vec<Term>, Stop> {
    let mut kept: Vec<Term> = Vec::with_capacity(terms.len());
    for t in terms {
        work.spend(1 + kept.len() as u64)?;
        if kept.iter().any(|k| k.subsumes(&t)) {
            continue;
        }
        kept.retain(|k| !t.subsumes(k));
        kept.push(t);
    }
    Ok(kept)
}

/// Most untils one formula may hold: the deferral sets are one machine word.
const MAX_UNTILS: usize = 64;

#[derive(Default)]
struct Arena {
    nodes: Vec<Node>,
    ids: HashMap<Node, F>,
    /// Until nodes in order of creation; the position is the until's bit in `Term::pending`.
    untils: Vec<F>,
    expansions: HashMap<F, Rc<Vec<Term>>>,
    /// Set when more than [`MAX_UNTILS`] untils were built.
    too_many_untils: bool,
}

impl Arena {
    fn intern(&mut self, node: Node) -> F {
        if let Some(&f) = self.ids.get(&node) {
            return f;
        }
        let f = F(self.nodes.len() as u32);
        if matches!(node, Node::Until(..)) {
            if self.untils.len() == MAX_UNTILS {
                self.too_many_untils = true;
            } else {
                self.untils.push(f);
            }
        }
        self.nodes.push(node.clone());
        self.ids.insert(node, f);
        f
    }

    fn node(&self, f: F) -> &Node {
        &self.nodes[f.0 as usize]
    }

    fn t(&mut self) -> F {
        self.intern(Node::True)
    }

    fn f(&mut self) -> F {
        self.intern(Node::False)
    }

    /// Conjunction (`conjunction == true`) or disjunction of `parts`, flattened and simplified.
    fn junction(&mut self, conjunction: bool, parts: Vec<F>) -> F {
        let (unit, zero) = if conjunction { (Node::True, Node::False) } else { (Node::False, Node::True) };
        let mut flat = Vec::with_capacity(parts.len());
        for p in parts {
            match self.node(p) {
                n if *n == unit => {}
                n if *n == zero => return self.intern(zero),
                Node::And(xs) if conjunction => flat.extend_from_slice(xs),
                Node::Or(xs) if !conjunction => flat.extend_from_slice(xs),
                _ => flat.push(p),
            }
        }
        crate::sort::sort(&mut flat);
        flat.dedup();
        let complementary = flat.iter().any(|&a| {
            let Node::Lit(s, v) = *self.node(a) else { return false };
            self.ids.get(&Node::Lit(s, !v)).is_some_and(|b| flat.binary_search(b).is_ok())
        });
        if complementary {
            return self.intern(zero);
        }
        match flat.len() {
            0 => self.intern(unit),
            1 => flat[0],
            _ if conjunction => self.intern(Node::And(flat)),
            _ => self.intern(Node::Or(flat)),
        }
    }

    fn next(&mut self, a: F) -> F {
        match self.node(a) {
            Node::True | Node::False => a,
            _ => self.intern(Node::Next(a)),
        }
    }

    fn until(&mut self, a: F, b: F) -> F {
        match (self.node(a), self.node(b)) {
            (_, Node::True | Node::False) | (Node::False, _) => b,
            // F F b = F b
            (Node::True, Node::Until(x, _)) if *self.node(*x) == Node::True => b,
            _ => self.intern(Node::Until(a, b)),
        }
    }

    fn release(&mut self, a: F, b: F) -> F {
        match (self.node(a), self.node(b)) {
            (_, Node::True | Node::False) | (Node::True, _) => b,
            // G G b = G b
            (Node::False, Node::Release(x, _)) if *self.node(*x) == Node::False => b,
            _ => self.intern(Node::Release(a, b)),
        }
    }

    /// The negation normal form of `f` (of `!f` when `negated`).
    fn nnf(&mut self, f: &Ltl, negated: bool) -> F {
        match f {
            Ltl::True if negated => self.f(),
            Ltl::True => self.t(),
            Ltl::False if negated => self.t(),
            Ltl::False => self.f(),
            Ltl::Var(s) => self.intern(Node::Lit(s.0, !negated)),
            Ltl::Not(a) => self.nnf(a, !negated),
            Ltl::And(xs) | Ltl::Or(xs) => {
                let parts = xs.iter().map(|x| self.nnf(x, negated)).collect();
                self.junction(matches!(f, Ltl::And(_)) != negated, parts)
            }
            Ltl::Implies(a, b) => {
                let (a, b) = (self.nnf(a, !negated), self.nnf(b, negated));
                self.junction(negated, vec![a, b])
            }
            Ltl::Iff(a, b) => {
                // a <-> b is (a && b) || (!a && !b); its negation (a && !b) || (!a && b).
                let (pa, na) = (self.nnf(a, false), self.nnf(a, true));
                let (pb, nb) = (self.nnf(b, negated), self.nnf(b, !negated));
                let left = self.junction(true, vec![pa, pb]);
                let right = self.junction(true, vec![na, nb]);
                self.junction(false, vec![left, right])
            }
            Ltl::Next(a) => {
                let a = self.nnf(a, negated);
                self.next(a)
            }
            Ltl::Globally(a) | Ltl::Finally(a) => {
                let a = self.nnf(a, negated);
                if matches!(f, Ltl::Globally(_)) != negated {
                    let f = self.f();
                    self.release(f, a)
                } else {
                    let t = self.t();
                    self.until(t, a)
                }
            }
            Ltl::Until(a, b) | Ltl::Release(a, b) => {
                let (a, b) = (self.nnf(a, negated), self.nnf(b, negated));
                if matches!(f, Ltl::Until(..)) != negated {
                    self.until(a, b)
                } else {
                    self.release(a, b)
                }
            }
            Ltl::WeakUntil(a, b) => {
                if negated {
                    // !(a W b) = !b U (!a && !b)
                    let (na, nb) = (self.nnf(a, true), self.nnf(b, true));
                    let both = self.junction(true, vec![na, nb]);
                    self.until(nb, both)
                } else {
                    // a W b = b R (a || b)
                    let (a, b) = (self.nnf(a, false), self.nnf(b, false));
                    let either = self.junction(false, vec![a, b]);
                    self.release(b, either)
                }
            }
        }
    }

    /// The terms of `f`, memoised.
    fn expand(&mut self, f: F, work: &mut Work) -> Result<Rc<Vec<Term>>, Stop> {
        if let Some(terms) = self.expansions.get(&f) {
            return Ok(terms.clone());
        }
        let terms = match self.node(f).clone() {
            Node::True => vec![Term::TRUE],
            Node::False => Vec::new(),
            Node::Lit(s, true) => vec![Term { pos: 1 << s, ..Term::TRUE }],
            Node::Lit(s, false) => vec![Term { neg: 1 << s, ..Term::TRUE }],
            Node::And(xs) => {
                let mut acc = vec![Term::TRUE];
                for x in xs {
                    let terms = self.expand(x, work)?;
                    work.spend((acc.len() * terms.len()) as u64)?;
                    acc = minimise(product(&acc, &terms), work)?;
                    if acc.is_empty() {
                        break;
                    }
                }
                acc
            }
            Node::Or(xs) => {
                let mut acc = Vec::new();
                for x in xs {
                    acc.extend(self.expand(x, work)?.iter().cloned());
                }
                minimise(acc, work)?
            }
            Node::Next(a) => vec![Term { next: vec![a], ..Term::TRUE }],
            Node::Until(a, b) => {
                let bit = self.untils.iter().position(|&u| u == f).map_or(0, |i| 1u64 << i);
                let defer = Term { next: vec![f], pending: bit, ..Term::TRUE };
                let mut terms = self.expand(b, work)?.to_vec();
                terms.extend(product(&self.expand(a, work)?, &[defer]));
                minimise(terms, work)?
            }
            Node::Release(a, b) => {
                let keep = Term { next: vec![f], ..Term::TRUE };
                let now = self.expand(b, work)?;
                let later = self.expand(a, work)?;
                work.spend((now.len() * later.len()) as u64)?;
                let mut terms = product(&now, &later);
                terms.extend(product(&now, &[keep]));
                minimise(terms, work)?
            }
        };
        let terms = Rc::new(terms);
        self.expansions.insert(f, terms.clone());
        Ok(terms)
    }

    /// The generalised automaton reachable from `root`: states are conjunctions of obligations.
    fn explore(&mut self, root: F, max_states: usize, work: &mut Work) -> Result<Tgba, Stop> {
        let mut index: HashMap<F, u32> = HashMap::new();
        let mut states = vec![root];
        index.insert(root, 0);
        let mut edges = Vec::new();
        let mut i = 0;
        while i < states.len() {
            let terms = self.expand(states[i], work)?;
            if self.too_many_untils {
                return Err(Stop::budget(
                    Resource::Size,
                    format!(
                    "the formula has more than {MAX_UNTILS} until or eventually subformulas; split the specification"
                ),
                ));
            }
            let mut out = Vec::with_capacity(terms.len());
            for term in terms.iter() {
                let target = self.junction(true, term.next.clone());
                let to = *index.entry(target).or_insert_with(|| {
                    states.push(target);
                    states.len() as u32 - 1
                });
                out.push((term.pos, term.neg, to, term.pending));
            }
            if states.len() > max_states {
                return Err(automaton_budget(max_states));
            }
            edges.push(out);
            i += 1;
        }
        let deferred = edges.iter().flatten().fold(0, |acc, e| acc | e.3);
        Ok(Tgba { formulas: states, edges, deferred })
    }

    fn write(&self, f: F, name: &dyn Fn(SignalId) -> String, out: &mut String) {
        let group = |arena: &Arena, g: F, out: &mut String| {
            let atomic = matches!(arena.node(g), Node::True | Node::False | Node::Lit(..) | Node::Next(_));
            if !atomic {
                out.push('(');
            }
            arena.write(g, name, out);
            if !atomic {
                out.push(')');
            }
        };
        match self.node(f) {
            Node::True => out.push_str("true"),
            Node::False => out.push_str("false"),
            Node::Lit(s, v) => {
                if !v {
                    out.push('!');
                }
                out.push_str(&name(SignalId(*s)));
            }
            Node::And(xs) | Node::Or(xs) => {
                let op = if matches!(self.node(f), Node::And(_)) { " && " } else { " || " };
                for (i, &x) in xs.iter().enumerate() {
                    if i > 0 {
                        out.push_str(op);
                    }
                    group(self, x, out);
                }
            }
            Node::Next(a) => {
                out.push_str("X ");
                group(self, *a, out);
            }
            Node::Until(a, b) if *self.node(*a) == Node::True => {
                out.push_str("F ");
                group(self, *b, out);
            }
            Node::Release(a, b) if *self.node(*a) == Node::False => {
                out.push_str("G ");
                group(self, *b, out);
            }
            Node::Until(a, b) | Node::Release(a, b) => {
                group(self, *a, out);
                out.push_str(if matches!(self.node(f), Node::Until(..)) { " U " } else { " R " });
                group(self, *b, out);
            }
        }
    }
}

fn product(left: &[Term], right: &[Term]) -> Vec<Term> {
    left.iter().flat_map(|a| right.iter().filter_map(move |b| a.and(b))).collect()
}

fn automaton_budget(max_states: usize) -> Stop {
    Stop::budget(
        Resource::States,
        format!("the Büchi automaton needs more than {max_states} states (the automaton budget)"),
    )
}

/// The generalised automaton: per state its formula and edges `(pos, neg, to, deferred untils)`.
struct Tgba {
    formulas: Vec<F>,
    edges: Vec<Vec<(u64, u64, u32, u64)>>,
    /// The untils some edge defers: only these need a degeneralisation level.
    deferred: u64,
}

/// The degeneralised automaton before pruning: states `(tgba state, level)`.
struct Tba {
    /// The formula of each generalised state.
    formulas: Vec<F>,
    origin: Vec<(u32, u32)>,
    edges: Vec<Vec<Edge>>,
}

fn degeneralise(g: &Tgba, max_states: usize) -> Result<Tba, Stop> {
    let levels: Vec<u64> = (0..64).map(|i| 1u64 << i).filter(|bit| g.deferred & bit != 0).collect();
    let mut index: HashMap<(u32, u32), u32> = HashMap::new();
    let mut origin = vec![(0u32, 0u32)];
    index.insert((0, 0), 0);
    let mut edges = Vec::new();
    let mut i = 0;
    while i < origin.len() {
        let (q, level) = origin[i];
        let mut out = Vec::new();
        for &(pos, neg, to, pending) in &g.edges[q as usize] {
            // Advance past every level this edge satisfies (does not defer).
            let mut l = level as usize;
            while l < levels.len() && pending & levels[l] == 0 {
                l += 1;
            }
            let accepting = l == levels.len();
            let next_level = if accepting { 0 } else { l as u32 };
            let key = (to, next_level);
            let target = *index.entry(key).or_insert_with(|| {
                origin.push(key);
                origin.len() as u32 - 1
            });
            out.push(Edge { pos, neg, to: target, accepting });
        }
        if origin.len() > max_states {
            return Err(automaton_budget(max_states));
        }
        edges.push(out);
        i += 1;
    }
    Ok(Tba { formulas: g.formulas.clone(), origin, edges })
}

/// Removes states that reach no accepting cycle, clears marks between components, renumbers
/// from the initial state, and labels states.
fn prune(tba: Tba, arena: &Arena, name: &dyn Fn(SignalId) -> String) -> Automaton {
    let n = tba.edges.len();
    let mut graph = DiGraph::<(), bool>::with_capacity(n, 0);
    let nodes: Vec<_> = (0..n).map(|_| graph.add_node(())).collect();
    for (q, out) in tba.edges.iter().enumerate() {
        for e in out {
            graph.add_edge(nodes[q], nodes[e.to as usize], e.accepting);
        }
    }
    let mut component = vec![0usize; n];
    for (c, scc) in petgraph::algo::tarjan_scc(&graph).into_iter().enumerate() {
        for node in scc {
            component[node.index()] = c;
        }
    }
    // An accepting cycle exists through a component with an accepting edge inside it.
    let mut live = vec![false; n];
    for (q, out) in tba.edges.iter().enumerate() {
        if out.iter().any(|e| e.accepting && component[e.to as usize] == component[q]) {
            live[q] = true;
        }
    }
    // Backwards: a state that can reach a live state is live.
    let mut reversed: Vec<Vec<u32>> = vec![Vec::new(); n];
    for (q, out) in tba.edges.iter().enumerate() {
        for e in out {
            reversed[e.to as usize].push(q as u32);
        }
    }
    let mut stack: Vec<u32> = (0..n as u32).filter(|&q| live[q as usize]).collect();
    while let Some(q) = stack.pop() {
        for &p in &reversed[q as usize] {
            if !live[p as usize] {
                live[p as usize] = true;
                stack.push(p);
            }
        }
    }
    // Renumber the live states reachable from the initial one, in breadth-first order.
    let mut renumber: Vec<Option<u32>> = vec![None; n];
    let mut order = vec![0u32];
    renumber[0] = Some(0);
    let mut i = 0;
    while i < order.len() {
        let q = order[i] as usize;
        if live[q] {
            for e in &tba.edges[q] {
                let t = e.to as usize;
                if live[t] && renumber[t].is_none() {
                    renumber[t] = Some(order.len() as u32);
                    order.push(t as u32);
                }
            }
        }
        i += 1;
    }
    let states = order
        .iter()
        .map(|&q| {
            let q = q as usize;
            let edges: Vec<Edge> = if live[q] {
                tba.edges[q]
                    .iter()
                    .filter_map(|e| {
                        let to = renumber[e.to as usize]?;
                        let internal = component[e.to as usize] == component[q];
                        Some(Edge { to, accepting: e.accepting && internal, ..*e })
                    })
                    .collect()
            } else {
                Vec::new()
            };
            let me = renumber[q].expect("numbered");
            let universal = edges.iter().any(|e| e.pos == 0 && e.neg == 0 && e.to == me && e.accepting);
            let (formula, level) = tba.origin[q];
            let mut label = String::new();
            arena.write(tba.formulas[formula as usize], name, &mut label);
            if level > 0 {
                label.push_str(&format!(" [level {level}]"));
            }
            AutomatonState { label, edges, universal }
        })
        .collect();
    Automaton { init: 0, states }
}
