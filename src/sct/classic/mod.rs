//! Classic Ramadge–Wonham automata: marked states, synchronous product, trim, supremal
//! controllable (closed) sublanguage, the supremal controllable nonblocking supervisor (SupCon)
//! and state minimisation.
//!
//! Events live in one [`Events`] table shared by every automaton of a problem; an automaton
//! stores its alphabet as a sorted list of [`ClassicEventId`]s and its transitions in a compressed
//! sparse-row table sorted by (source, event), so that the transitions leaving a state are one
//! contiguous slice and a product can merge two such slices in one pass.

mod file_error;
pub mod gen;
pub mod wmod;

use crate::graph::{flags, Successors, View};
use crate::id::id_type;
pub use file_error::FileError;
use hashbrown::HashMap;
use petgraph::visit::{Dfs, NodeFiltered, Visitable};

id_type! {
    /// A compact event id: an index into [`Events`]. Not the SynTACS model's
    /// [`crate::sct::model::EventId`]; `sct::interchange` converts between the two.
    pub struct ClassicEventId;
}

id_type! {
    /// A compact state id: an index into an automaton's states.
    pub struct StateId;
}

/// The event universe of a problem: names, and which events are controllable.
#[derive(Clone, Debug, Default)]
pub struct Events {
    names: Vec<String>,
    controllable: Vec<bool>,
    index: HashMap<String, ClassicEventId>,
}

impl Events {
    pub fn new() -> Events {
        Events::default()
    }

    /// The id of `name`, inserting it with the given controllability if it is new. An existing
    /// event keeps its controllability; use [`Events::set_controllable`] to change it.
    pub fn intern(&mut self, name: &str, controllable: bool) -> ClassicEventId {
        if let Some(&id) = self.index.get(name) {
            return id;
        }
        let id = ClassicEventId::new(self.names.len());
        self.names.push(name.to_string());
        self.controllable.push(controllable);
        self.index.insert(name.to_string(), id);
        id
    }

    pub fn get(&self, name: &str) -> Option<ClassicEventId> {
        self.index.get(name).copied()
    }

    pub fn name(&self, e: ClassicEventId) -> &str {
        &self.names[e.index()]
    }

    pub fn is_controllable(&self, e: ClassicEventId) -> bool {
        self.controllable[e.index()]
    }

    pub fn set_controllable(&mut self, e: ClassicEventId, c: bool) {
        self.controllable[e.index()] = c;
    }

    pub fn len(&self) -> usize {
        self.names.len()
    }

    pub fn is_empty(&self) -> bool {
        self.names.is_empty()
    }
}

/// One transition in the CSR table: the event and the target state.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub struct Edge {
    pub event: ClassicEventId,
    pub target: StateId,
}

/// A deterministic finite automaton with marked states (a "generator" in DES terms).
#[derive(Clone, Debug)]
pub struct Automaton {
    alphabet: Vec<ClassicEventId>,
    init: Option<StateId>,
    marked: Vec<bool>,
    offsets: Vec<u32>,
    edges: Vec<Edge>,
    names: Vec<String>,
}

/// Error from [`AutomatonBuilder::build`].
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum BuildError {
    /// Two transitions leave one state on one event towards different targets.
    Nondeterministic { state: StateId, event: ClassicEventId },
    /// A transition uses an event outside the alphabet.
    EventNotInAlphabet { event: ClassicEventId },
    /// A transition or the initial state names a state that does not exist.
    BadState { state: StateId },
}

/// Collects states and transitions in any order and builds the sorted table.
#[derive(Clone, Debug, Default)]
pub struct AutomatonBuilder {
    alphabet: Vec<ClassicEventId>,
    init: Option<StateId>,
    marked: Vec<bool>,
    names: Vec<String>,
    trans: Vec<(StateId, ClassicEventId, StateId)>,
}

impl AutomatonBuilder {
    pub fn new() -> AutomatonBuilder {
        AutomatonBuilder::default()
    }

    pub fn add_event(&mut self, e: ClassicEventId) {
        self.alphabet.push(e);
    }

    /// Adds a state and returns its id.
    pub fn add_state(&mut self, name: impl Into<String>, marked: bool) -> StateId {
        self.names.push(name.into());
        self.marked.push(marked);
        StateId::new(self.marked.len() - 1)
    }

    pub fn set_init(&mut self, s: StateId) {
        self.init = Some(s);
    }

    pub fn set_marked(&mut self, s: StateId, m: bool) {
        self.marked[s.index()] = m;
    }

    pub fn add_transition(&mut self, from: StateId, e: ClassicEventId, to: StateId) {
        self.trans.push((from, e, to));
    }

    pub fn num_states(&self) -> usize {
        self.marked.len()
    }

    pub fn build(mut self) -> Result<Automaton, BuildError> {
        crate::sort::sort(&mut self.alphabet);
        self.alphabet.dedup();
        let n = self.marked.len();
        if let Some(i) = self.init {
            if i.index() >= n {
                return Err(BuildError::BadState { state: i });
            }
        }
        crate::sort::sort(&mut self.trans);
        self.trans.dedup();
        let mut offsets = vec![0u32; n + 1];
        let mut edges = Vec::with_capacity(self.trans.len());
        for w in self.trans.windows(2) {
            if w[0].0 == w[1].0 && w[0].1 == w[1].1 {
                return Err(BuildError::Nondeterministic { state: w[0].0, event: w[0].1 });
            }
        }
        for &(s, e, t) in &self.trans {
            if s.index() >= n || t.index() >= n {
                return Err(BuildError::BadState { state: s.max(t) });
            }
            if self.alphabet.binary_search(&e).is_err() {
                return Err(BuildError::EventNotInAlphabet { event: e });
            }
            offsets[s.index() + 1] += 1;
            edges.push(Edge { event: e, target: t });
        }
        for i in 0..n {
            offsets[i + 1] += offsets[i];
        }
        Ok(Automaton {
            alphabet: self.alphabet,
            init: if n == 0 { None } else { self.init },
            marked: self.marked,
            offsets,
            edges,
            names: self.names,
        })
    }
}

impl Automaton {
    /// The automaton with no states (the empty language), over `alphabet`.
    pub fn empty(mut alphabet: Vec<ClassicEventId>) -> Automaton {
        crate::sort::sort(&mut alphabet);
        alphabet.dedup();
        Automaton { alphabet, init: None, marked: Vec::new(), offsets: vec![0], edges: Vec::new(), names: Vec::new() }
    }

    pub fn alphabet(&self) -> &[ClassicEventId] {
        &self.alphabet
    }

    pub fn init(&self) -> Option<StateId> {
        self.init
    }

    pub fn num_states(&self) -> usize {
        self.marked.len()
    }

    /// The state ids, in order.
    pub fn states(&self) -> impl Iterator<Item = StateId> + Clone + use<> {
        (0..self.num_states()).map(StateId::new)
    }

    pub fn num_transitions(&self) -> usize {
        self.edges.len()
    }

    pub fn is_marked(&self, s: StateId) -> bool {
        self.marked[s.index()]
    }

    pub fn state_name(&self, s: StateId) -> &str {
        &self.names[s.index()]
    }

    /// The transitions leaving `s`, sorted by event.
    pub fn edges(&self, s: StateId) -> &[Edge] {
        &self.edges[self.offsets[s.index()] as usize..self.offsets[s.index() + 1] as usize]
    }

    /// The successor of `s` on `e`, if defined.
    pub fn step(&self, s: StateId, e: ClassicEventId) -> Option<StateId> {
        let out = self.edges(s);
        out.binary_search_by(|x| x.event.cmp(&e)).ok().map(|i| out[i].target)
    }

    pub fn has_event(&self, e: ClassicEventId) -> bool {
        self.alphabet.binary_search(&e).is_ok()
    }

    /// Runs a word from the initial state; `None` if it leaves the generated language.
    pub fn run(&self, word: &[ClassicEventId]) -> Option<StateId> {
        let mut s = self.init?;
        for &e in word {
            s = self.step(s, e)?;
        }
        Some(s)
    }

    /// Membership bitmap of the alphabet over an event universe of `n` events.
    fn alphabet_mask(&self, n: usize) -> Vec<bool> {
        let mut m = vec![false; n];
        for e in &self.alphabet {
            if e.index() < n {
                m[e.index()] = true;
            }
        }
        m
    }

    /// A copy with every state marked (so that the marked language equals the generated one).
    pub fn with_all_marked(&self) -> Automaton {
        let mut a = self.clone();
        a.marked.iter_mut().for_each(|m| *m = true);
        a
    }

    /// The same language over a larger alphabet: every event of `extra` not yet in the
    /// alphabet is added with a self-loop in every state (libFAUDES wants equal alphabets).
    pub fn with_selfloops(&self, extra: &[ClassicEventId]) -> Automaton {
        let new: Vec<ClassicEventId> = extra.iter().copied().filter(|e| !self.has_event(*e)).collect();
        let mut b = AutomatonBuilder::new();
        for &e in self.alphabet.iter().chain(&new) {
            b.add_event(e);
        }
        for s in 0..self.num_states() {
            b.add_state(self.names[s].clone(), self.marked[s]);
            let s = StateId::new(s);
            for e in self.edges(s) {
                b.add_transition(s, e.event, e.target);
            }
            for &e in &new {
                b.add_transition(s, e, s);
            }
        }
        if let Some(i) = self.init {
            b.set_init(i);
        }
        b.build().expect("adding self-loops on new events keeps determinism")
    }

    /// Keeps the states for which `keep` holds, renumbered in order; transitions into dropped
    /// states are dropped. The initial state is dropped too if `keep` rejects it.
    pub fn restrict(&self, keep: &[bool]) -> Automaton {
        let n = self.num_states();
        let mut map: Vec<Option<StateId>> = vec![None; n];
        let mut next = 0usize;
        for s in 0..n {
            if keep[s] {
                map[s] = Some(StateId::new(next));
                next += 1;
            }
        }
        let mut offsets = Vec::with_capacity(next + 1);
        offsets.push(0u32);
        let mut edges = Vec::new();
        let mut marked = Vec::with_capacity(next);
        let mut names = Vec::with_capacity(next);
        for (s, _) in keep.iter().enumerate().take(n).filter(|(_, k)| **k) {
            for e in self.edges(StateId::new(s)) {
                if let Some(t) = map[e.target.index()] {
                    edges.push(Edge { event: e.event, target: t });
                }
            }
            offsets.push(edges.len() as u32);
            marked.push(self.marked[s]);
            names.push(self.names[s].clone());
        }
        let init = self.init.and_then(|i| map[i.index()]);
        if init.is_none() {
            return Automaton::empty(self.alphabet.clone());
        }
        Automaton { alphabet: self.alphabet.clone(), init, marked, offsets, edges, names }
    }

    /// States reachable from the initial state.
    pub fn reachable(&self) -> Vec<bool> {
        let graph = View(self);
        let mut dfs = Dfs::from_parts(self.init.into_iter().map(StateId::raw).collect(), graph.visit_map());
        while dfs.next(graph).is_some() {}
        flags(&dfs.discovered, self.num_states())
    }

    /// States from which a marked state can be reached.
    pub fn coreachable(&self) -> Vec<bool> {
        let all = vec![true; self.num_states()];
        let rev = Reverse::new(self, |_| true);
        coreachable_within(self, &rev, &all)
    }

    /// The accessible part.
    pub fn accessible(&self) -> Automaton {
        self.restrict(&self.reachable())
    }

    /// The accessible and coaccessible part.
    pub fn trim(&self) -> Automaton {
        let r = self.reachable();
        let c = self.coreachable();
        let keep: Vec<bool> = r.iter().zip(&c).map(|(a, b)| *a && *b).collect();
        self.restrict(&keep)
    }

    /// True if every reachable state can reach a marked state.
    pub fn is_nonblocking(&self) -> bool {
        let r = self.reachable();
        let c = self.coreachable();
        r.iter().zip(&c).all(|(a, b)| !*a || *b)
    }
}

/// Reverse adjacency (CSR) over the edges accepted by a filter.
struct Reverse {
    offsets: Vec<u32>,
    sources: Vec<StateId>,
}

impl Reverse {
    fn new(a: &Automaton, mut filter: impl FnMut(ClassicEventId) -> bool) -> Reverse {
        let n = a.num_states();
        let mut offsets = vec![0u32; n + 1];
        for e in &a.edges {
            if filter(e.event) {
                offsets[e.target.index() + 1] += 1;
            }
        }
        for i in 0..n {
            offsets[i + 1] += offsets[i];
        }
        let mut fill = offsets.clone();
        let mut sources = vec![StateId::new(0); offsets[n] as usize];
        for s in 0..n {
            for e in a.edges(StateId::new(s)) {
                if filter(e.event) {
                    sources[fill[e.target.index()] as usize] = StateId::new(s);
                    fill[e.target.index()] += 1;
                }
            }
        }
        Reverse { offsets, sources }
    }

    fn preds(&self, s: StateId) -> &[StateId] {
        &self.sources[self.offsets[s.index()] as usize..self.offsets[s.index() + 1] as usize]
    }
}

/// States among `alive` that reach a marked alive state through alive states only.
fn coreachable_within(a: &Automaton, rev: &Reverse, alive: &[bool]) -> Vec<bool> {
    let graph = NodeFiltered(View(rev), |s: u32| alive[s as usize]);
    let marked = (0..a.num_states()).filter(|&s| alive[s] && a.marked[s]).map(|s| s as u32);
    let mut dfs = Dfs::from_parts(marked.collect(), graph.visit_map());
    while dfs.next(&graph).is_some() {}
    flags(&dfs.discovered, a.num_states())
}

impl Successors for Automaton {
    type Iter<'a> = std::iter::Map<std::slice::Iter<'a, Edge>, fn(&Edge) -> u32>;
    fn node_bound(&self) -> usize {
        self.num_states()
    }
    fn successors(&self, s: u32) -> Self::Iter<'_> {
        self.edges(StateId::from_raw(s)).iter().map(|e| e.target.raw())
    }
}

/// The reversed automaton: successors are the sources of the accepted edges into a state.
impl Successors for Reverse {
    type Iter<'a> = std::iter::Map<std::slice::Iter<'a, StateId>, fn(&StateId) -> u32>;
    fn node_bound(&self) -> usize {
        self.offsets.len() - 1
    }
    fn successors(&self, s: u32) -> Self::Iter<'_> {
        self.preds(StateId::from_raw(s)).iter().map(|s| s.raw())
    }
}

/// A synchronous product together with the pair of component states behind each state.
pub struct Product {
    pub automaton: Automaton,
    pub pairs: Vec<(StateId, StateId)>,
}

/// Synchronous (parallel) product `a || b`: shared events synchronise, the others interleave.
/// Only the accessible part is built. `n_events` is the size of the event universe.
pub fn product(a: &Automaton, b: &Automaton, n_events: usize) -> Product {
    match product_within(a, b, n_events, usize::MAX) {
        Ok(p) => p,
        Err(_) => unreachable!("an unbounded product cannot exceed its budget"),
    }
}

/// [`product`] building at most `max_states` states; past that, `Err(max_states)`.
pub fn product_within(a: &Automaton, b: &Automaton, n_events: usize, max_states: usize) -> Result<Product, usize> {
    let in_a = a.alphabet_mask(n_events);
    let in_b = b.alphabet_mask(n_events);
    let mut alphabet: Vec<ClassicEventId> = a.alphabet.iter().chain(&b.alphabet).copied().collect();
    crate::sort::sort(&mut alphabet);
    alphabet.dedup();
    let (Some(ia), Some(ib)) = (a.init, b.init) else {
        return Ok(Product { automaton: Automaton::empty(alphabet), pairs: Vec::new() });
    };
    let mut index: HashMap<(StateId, StateId), StateId> = HashMap::new();
    let mut pairs = vec![(ia, ib)];
    index.insert((ia, ib), StateId::new(0));
    let mut offsets = vec![0u32];
    let mut edges: Vec<Edge> = Vec::new();
    let mut out: Vec<(ClassicEventId, StateId, StateId)> = Vec::new();
    let mut k = 0usize;
    while k < pairs.len() {
        let (sa, sb) = pairs[k];
        out.clear();
        let (ea, eb) = (a.edges(sa), b.edges(sb));
        let (mut i, mut j) = (0, 0);
        while i < ea.len() || j < eb.len() {
            let ev_a = ea.get(i).map(|e| e.event);
            let ev_b = eb.get(j).map(|e| e.event);
            match (ev_a, ev_b) {
                (Some(x), Some(y)) if x == y => {
                    out.push((x, ea[i].target, eb[j].target));
                    i += 1;
                    j += 1;
                }
                (Some(x), y) if y.is_none_or(|y| x < y) => {
                    if !in_b[x.index()] {
                        out.push((x, ea[i].target, sb));
                    }
                    i += 1;
                }
                (_, Some(y)) => {
                    if !in_a[y.index()] {
                        out.push((y, sa, eb[j].target));
                    }
                    j += 1;
                }
                _ => unreachable!("loop condition guarantees one side"),
            }
        }
        for &(e, ta, tb) in &out {
            let next = StateId::new(pairs.len());
            let t = *index.entry((ta, tb)).or_insert_with(|| {
                pairs.push((ta, tb));
                next
            });
            edges.push(Edge { event: e, target: t });
        }
        if pairs.len() > max_states {
            return Err(max_states);
        }
        offsets.push(edges.len() as u32);
        k += 1;
    }
    let marked = pairs.iter().map(|&(x, y)| a.marked[x.index()] && b.marked[y.index()]).collect();
    let names = pairs.iter().map(|&(x, y)| format!("{}|{}", a.names[x.index()], b.names[y.index()])).collect();
    Ok(Product { automaton: Automaton { alphabet, init: Some(StateId::new(0)), marked, offsets, edges, names }, pairs })
}

/// Error of the supervisor computations.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum SupConError {
    /// The specification uses events the plant does not know.
    SpecEventsOutsidePlant(Vec<ClassicEventId>),
    /// `plant || spec` has more than `max_states` states.
    BudgetExceeded { max_states: usize },
}

/// Supremal controllable sublanguage of `L(plant || spec)` with respect to `L(plant)`, the
/// closed-loop behaviour of the maximally permissive supervisor, with (`nonblocking = true`,
/// SupCon) or without (SupConClosed) the requirement that every reachable state can still reach
/// a state marked in both plant and specification.
pub fn supcon(
    plant: &Automaton,
    spec: &Automaton,
    events: &Events,
    nonblocking: bool,
) -> Result<Automaton, SupConError> {
    supcon_within(plant, spec, events, nonblocking, usize::MAX)
}

/// [`supcon`] with a state budget: `plant || spec` may have at most `max_states` states.
pub fn supcon_within(
    plant: &Automaton,
    spec: &Automaton,
    events: &Events,
    nonblocking: bool,
    max_states: usize,
) -> Result<Automaton, SupConError> {
    let outside: Vec<ClassicEventId> = spec.alphabet.iter().copied().filter(|e| !plant.has_event(*e)).collect();
    if !outside.is_empty() {
        return Err(SupConError::SpecEventsOutsidePlant(outside));
    }
    let n_events = events.len().max(plant.alphabet.last().map_or(0, |e| e.index() + 1));
    let prod = product_within(plant, spec, n_events, max_states)
        .map_err(|max_states| SupConError::BudgetExceeded { max_states })?;
    let p = &prod.automaton;
    let n = p.num_states();
    let in_spec = spec.alphabet_mask(n_events);
    let controllable = |e: ClassicEventId| e.index() < events.len() && events.is_controllable(e);
    // Initially bad: the plant can do an uncontrollable spec event that the product refuses.
    let mut alive = vec![true; n];
    let mut work: Vec<StateId> = Vec::new();
    for (s, &(g, _)) in prod.pairs.iter().enumerate() {
        let pe = p.edges(StateId::new(s));
        for e in plant.edges(g) {
            if controllable(e.event) || !in_spec[e.event.index()] {
                continue;
            }
            if pe.binary_search_by(|x| x.event.cmp(&e.event)).is_err() {
                alive[s] = false;
                work.push(StateId::new(s));
                break;
            }
        }
    }
    let rev_u = Reverse::new(p, |e| !controllable(e));
    let rev_all = if nonblocking { Some(Reverse::new(p, |_| true)) } else { None };
    loop {
        // Propagate badness backwards over uncontrollable transitions. Kept by hand: the search
        // kills states in `alive` as it reaches them, which a petgraph search filtered by
        // `alive` cannot do while it borrows it (it would need a copy of its visit map per
        // round of SupCon's loop).
        while let Some(s) = work.pop() {
            for &q in rev_u.preds(s) {
                if alive[q.index()] {
                    alive[q.index()] = false;
                    work.push(q);
                }
            }
        }
        let Some(rev) = &rev_all else { break };
        let co = coreachable_within(p, rev, &alive);
        for s in 0..n {
            if alive[s] && !co[s] {
                alive[s] = false;
                work.push(StateId::new(s));
            }
        }
        if work.is_empty() {
            break;
        }
    }
    Ok(p.restrict(&alive).accessible())
}

/// True if `L(sup)` is controllable with respect to `L(plant)`: after every word of the
/// supervised language, every uncontrollable event the plant can do is still possible.
/// `sup` must be defined over the plant's alphabet (a sublanguage of the plant).
pub fn is_controllable(plant: &Automaton, sup: &Automaton, events: &Events) -> bool {
    let n_events = events.len();
    let prod = product(plant, sup, n_events);
    let in_sup = sup.alphabet_mask(n_events);
    let p = &prod.automaton;
    (0..p.num_states()).all(|s| {
        let (g, _) = prod.pairs[s];
        plant.edges(g).iter().all(|e| {
            events.is_controllable(e.event) || !in_sup[e.event.index()] || p.step(StateId::new(s), e.event).is_some()
        })
    })
}

/// Minimal deterministic automaton with the same generated and marked languages (states are
/// first trimmed to the accessible part). `key` gives an extra initial distinction per state
/// (e.g. prohibitions of a supervisor); states with different keys are never merged.
///
/// The reachable part is completed with a sink state (for missing transitions) and refined
/// with Hopcroft's algorithm (`sct::partition`). Returns the quotient and, for every
/// original state, its quotient state (`None` for unreachable ones).
pub fn minimize_with_key(a: &Automaton, key: &[u64]) -> (Automaton, Vec<Option<StateId>>) {
    let reach = a.reachable();
    let n = a.num_states();
    let states: Vec<StateId> = (0..n).filter(|&s| reach[s]).map(StateId::new).collect();
    if states.is_empty() {
        return (Automaton::empty(a.alphabet.clone()), vec![None; n]);
    }
    let m = states.len();
    // Positions among the reachable states; every edge of a reachable state leads to one.
    let mut local = vec![0u32; n];
    for (i, &s) in states.iter().enumerate() {
        local[s.index()] = i as u32;
    }
    let k = a.alphabet.len();
    let sink = m as u32;
    let mut delta = vec![sink; (m + 1) * k];
    for (i, &s) in states.iter().enumerate() {
        for e in a.edges(s) {
            let ai = a.alphabet.binary_search(&e.event).expect("edge events are in the alphabet");
            delta[i * k + ai] = local[e.target.index()];
        }
    }
    // Keys: (marked, user key) made dense; the sink gets a key of its own.
    let mut dense: HashMap<(bool, u64), u64> = HashMap::new();
    let mut keys = Vec::with_capacity(m + 1);
    for &s in &states {
        let kk = (a.marked[s.index()], key.get(s.index()).copied().unwrap_or(0));
        let next = dense.len() as u64;
        keys.push(*dense.entry(kk).or_insert(next));
    }
    keys.push(u64::MAX);
    let blocks = crate::sct::partition::coarsest_partition(m + 1, k, &delta, &keys);
    let count = blocks.iter().copied().max().map_or(0, |b| b as usize + 1);
    let mut class: Vec<Option<u32>> = vec![None; n];
    for (i, &s) in states.iter().enumerate() {
        class[s.index()] = Some(blocks[i]);
    }
    let class_of = |s: StateId| class[s.index()].expect("reachable") as usize;
    // Build the quotient, numbering classes in order of first visit from the initial state.
    let mut renum: Vec<Option<StateId>> = vec![None; count];
    let mut rep: Vec<StateId> = Vec::new();
    let init = a.init.expect("non-empty");
    let mut b = AutomatonBuilder::new();
    for &e in &a.alphabet {
        b.add_event(e);
    }
    renum[class_of(init)] = Some(StateId::new(0));
    rep.push(init);
    b.add_state(a.names[init.index()].clone(), a.marked[init.index()]);
    let mut k = 0;
    while k < rep.len() {
        let s = rep[k];
        for e in a.edges(s) {
            let c = class_of(e.target);
            let t = match renum[c] {
                Some(t) => t,
                None => {
                    let t = StateId::new(rep.len());
                    renum[c] = Some(t);
                    rep.push(e.target);
                    b.add_state(a.names[e.target.index()].clone(), a.marked[e.target.index()]);
                    t
                }
            };
            b.add_transition(StateId::new(k), e.event, t);
        }
        k += 1;
    }
    b.set_init(StateId::new(0));
    let map: Vec<Option<StateId>> = class.iter().map(|&c| c.and_then(|c| renum[c as usize])).collect();
    (b.build().expect("quotient of a deterministic automaton is deterministic"), map)
}

/// Minimal automaton with the same generated and marked languages.
pub fn minimize(a: &Automaton) -> Automaton {
    minimize_with_key(a, &[]).0
}

/// True if both automata generate and mark the same languages (compared on minimal forms
/// by a synchronous walk).
pub fn language_equal(a: &Automaton, b: &Automaton) -> bool {
    let (Some(ia), Some(ib)) = (a.init, b.init) else { return a.init.is_none() && b.init.is_none() };
    let mut seen: HashMap<(StateId, StateId), ()> = HashMap::new();
    let mut stack = vec![(ia, ib)];
    seen.insert((ia, ib), ());
    while let Some((x, y)) = stack.pop() {
        if a.marked[x.index()] != b.marked[y.index()] {
            return false;
        }
        let (ex, ey) = (a.edges(x), b.edges(y));
        if ex.len() != ey.len() {
            return false;
        }
        for (p, q) in ex.iter().zip(ey) {
            if p.event != q.event {
                return false;
            }
            if seen.insert((p.target, q.target), ()).is_none() {
                stack.push((p.target, q.target));
            }
        }
    }
    true
}

#[cfg(test)]
mod tests {
    use super::*;

    fn machine(ev: &mut Events, start: &str, done: &str) -> Automaton {
        let s = ev.intern(start, true);
        let d = ev.intern(done, false);
        let mut b = AutomatonBuilder::new();
        b.add_event(s);
        b.add_event(d);
        let i = b.add_state("I", true);
        let w = b.add_state("W", false);
        b.add_transition(i, s, w);
        b.add_transition(w, d, i);
        b.set_init(i);
        b.build().unwrap()
    }

    #[test]
    fn product_interleaves_private_events_and_syncs_shared() {
        let mut ev = Events::new();
        let m1 = machine(&mut ev, "a1", "b1");
        let m2 = machine(&mut ev, "a2", "b2");
        let p = product(&m1, &m2, ev.len()).automaton;
        assert_eq!((p.num_states(), p.num_transitions()), (4, 8));
        let shared = machine(&mut ev, "a1", "b2");
        let q = product(&m1, &shared, ev.len()).automaton;
        // a1 synchronises, b1 and b2 are private.
        assert!(q.run(&[ev.get("a1").unwrap(), ev.get("b1").unwrap(), ev.get("b2").unwrap()]).is_some());
        assert!(q.run(&[ev.get("a1").unwrap(), ev.get("a1").unwrap()]).is_none());
    }

    #[test]
    fn nondeterminism_is_rejected() {
        let mut ev = Events::new();
        let a = ev.intern("a", true);
        let mut b = AutomatonBuilder::new();
        b.add_event(a);
        let s = b.add_state("s", true);
        let t = b.add_state("t", true);
        b.add_transition(s, a, s);
        b.add_transition(s, a, t);
        b.set_init(s);
        assert_eq!(b.build().unwrap_err(), BuildError::Nondeterministic { state: s, event: a });
    }

    #[test]
    fn minimize_merges_equivalent_states() {
        let mut ev = Events::new();
        let a = ev.intern("a", true);
        let mut b = AutomatonBuilder::new();
        b.add_event(a);
        let s: Vec<_> = (0..4).map(|i| b.add_state(format!("s{i}"), i % 2 == 0)).collect();
        for i in 0..4 {
            b.add_transition(s[i], a, s[(i + 1) % 4]);
        }
        b.set_init(s[0]);
        let m = minimize(&b.build().unwrap());
        assert_eq!((m.num_states(), m.num_transitions()), (2, 2));
    }
}
