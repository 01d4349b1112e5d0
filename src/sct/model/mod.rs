//! The SynTACS automaton model of Göbe (2019), chapter 5.8: specifications with prohibitions,
//! plant models with alphabets, conditional transitions, and synthesis automata.
//!
//! A *specification* has no alphabet: an event with neither a transition nor a prohibition in
//! the current state leaves the state unchanged; a prohibited event is illegal there. A *plant
//! model* has an alphabet and obeys the plant contract: an alphabet event without a transition
//! is physically impossible in that state. A *synthesis automaton* (definition 18) joins both:
//! transitions, prohibitions and a plant alphabet of the events it has full knowledge of.
//!
//! Conditions (5.7, 5.8.4) are propositional formulas over plant states; they are refined
//! three-valuedly while composing and disappear once every referenced plant is part of the
//! synthesis automaton.

use crate::graph::{Successors, View};
use petgraph::visit::{Bfs, NodeFiltered};
use serde::Serialize;

/// Event id: an index into [`Project::events`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize)]
pub struct EventId(pub u32);

/// Event types of 5.3.2.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum EventKind {
    Controllable,
    Uncontrollable,
    Enforceable,
}

/// A project-wide event.
#[derive(Clone, Debug, Serialize)]
pub struct EventInfo {
    /// Fully qualified name, e.g. `Tank.levelAlarm`.
    pub name: String,
    pub kind: EventKind,
}

/// A condition over plant states (definition 23).
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Cond {
    True,
    False,
    /// Plant `plant` is in state `state`.
    State {
        plant: u32,
        state: u32,
    },
    Not(Box<Cond>),
    And(Box<Cond>, Box<Cond>),
    Or(Box<Cond>, Box<Cond>),
}

/// Three-valued truth: `False < Maybe < True`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Truth {
    False,
    Maybe,
    True,
}

impl Cond {
    pub fn is_true(&self) -> bool {
        matches!(self, Cond::True)
    }

    /// Conjunction with constant folding.
    pub fn and(self, other: Cond) -> Cond {
        match (self, other) {
            (Cond::False, _) | (_, Cond::False) => Cond::False,
            (Cond::True, c) | (c, Cond::True) => c,
            (a, b) => Cond::And(Box::new(a), Box::new(b)),
        }
    }

    /// Disjunction with constant folding.
    pub fn or(self, other: Cond) -> Cond {
        match (self, other) {
            (Cond::True, _) | (_, Cond::True) => Cond::True,
            (Cond::False, c) | (c, Cond::False) => c,
            (a, b) => Cond::Or(Box::new(a), Box::new(b)),
        }
    }

    /// Negation with constant folding.
    pub fn negate(self) -> Cond {
        match self {
            Cond::True => Cond::False,
            Cond::False => Cond::True,
            Cond::Not(c) => *c,
            c => Cond::Not(Box::new(c)),
        }
    }

    /// Evaluation on a state whose known plant components are given by `lookup(plant)`
    /// (definition 25): an atom is true if its plant is known and in that state, false if the
    /// plant is known and elsewhere, maybe if the plant is unknown.
    pub fn eval(&self, lookup: &impl Fn(u32) -> Option<u32>) -> Truth {
        match self {
            Cond::True => Truth::True,
            Cond::False => Truth::False,
            Cond::State { plant, state } => match lookup(*plant) {
                Some(s) if s == *state => Truth::True,
                Some(_) => Truth::False,
                None => Truth::Maybe,
            },
            Cond::Not(c) => match c.eval(lookup) {
                Truth::True => Truth::False,
                Truth::False => Truth::True,
                Truth::Maybe => Truth::Maybe,
            },
            Cond::And(a, b) => a.eval(lookup).min(b.eval(lookup)),
            Cond::Or(a, b) => a.eval(lookup).max(b.eval(lookup)),
        }
    }

    /// Refinement (definition 25): decided subformulas become constants.
    pub fn refine(&self, lookup: &impl Fn(u32) -> Option<u32>) -> Cond {
        match self.eval(lookup) {
            Truth::True => Cond::True,
            Truth::False => Cond::False,
            Truth::Maybe => match self {
                Cond::Not(c) => c.refine(lookup).negate(),
                Cond::And(a, b) => a.refine(lookup).and(b.refine(lookup)),
                Cond::Or(a, b) => a.refine(lookup).or(b.refine(lookup)),
                c => c.clone(),
            },
        }
    }

    /// Plants referenced by the formula.
    pub fn plants(&self, out: &mut Vec<u32>) {
        match self {
            Cond::State { plant, .. } => out.push(*plant),
            Cond::Not(c) => c.plants(out),
            Cond::And(a, b) | Cond::Or(a, b) => {
                a.plants(out);
                b.plants(out);
            }
            _ => {}
        }
    }
}

/// Sentinel for "no source location".
pub const NO_ORIGIN: u32 = u32::MAX;

/// A transition of a user automaton.
#[derive(Clone, Debug)]
pub struct Transition {
    pub src: u32,
    pub event: EventId,
    pub cond: Cond,
    pub dst: u32,
    /// Index into the front end's table of source locations, or [`NO_ORIGIN`].
    pub origin: u32,
}

/// A prohibition of a specification.
#[derive(Clone, Debug)]
pub struct Prohibition {
    pub state: u32,
    pub event: EventId,
    pub cond: Cond,
    pub origin: u32,
}

/// A plant model (definition 13, with conditional transitions).
#[derive(Clone, Debug)]
pub struct Plant {
    pub name: String,
    pub alphabet: Vec<EventId>,
    pub states: Vec<String>,
    pub init: u32,
    pub trans: Vec<Transition>,
}

/// A specification (definition 2, with conditions).
#[derive(Clone, Debug)]
pub struct Spec {
    pub name: String,
    pub states: Vec<String>,
    pub init: u32,
    pub trans: Vec<Transition>,
    pub prohib: Vec<Prohibition>,
}

/// Everything synthesis needs: events, plants and specifications.
#[derive(Clone, Debug, Default)]
pub struct Project {
    pub events: Vec<EventInfo>,
    pub plants: Vec<Plant>,
    pub specs: Vec<Spec>,
}

impl Project {
    pub fn kind(&self, e: EventId) -> EventKind {
        self.events[e.0 as usize].kind
    }

    pub fn event_name(&self, e: EventId) -> &str {
        &self.events[e.0 as usize].name
    }

    pub fn event(&self, name: &str) -> Option<EventId> {
        self.events.iter().position(|e| e.name == name).map(|i| EventId(i as u32))
    }
}

/// A transition of a synthesis automaton. `origin` keeps up to two user transitions it came from.
#[derive(Clone, Debug)]
pub struct STrans {
    pub event: EventId,
    pub cond: Cond,
    pub dst: u32,
    pub origin: [u32; 2],
}

/// A prohibition of a synthesis automaton.
#[derive(Clone, Debug)]
pub struct SProhib {
    pub event: EventId,
    pub cond: Cond,
    pub origin: u32,
}

/// A (preemptive) synthesis automaton (definitions 18 and 28). States are tuples of the
/// specification state and the states of the plants applied so far.
#[derive(Clone, Debug)]
pub struct SynthAut {
    /// Plants applied so far, in application order.
    pub plants: Vec<u32>,
    /// `tuples[s * (1 + plants.len()) ..]`: the spec state, then one state per applied plant.
    pub tuples: Vec<u32>,
    /// The plant alphabet: the events of the applied plants, sorted (a set per automaton, not a
    /// mask over all events, so that many small specifications stay linear).
    pub plant_alphabet: Vec<EventId>,
    pub init: Option<u32>,
    /// Transitions per state (sorted by event).
    pub trans: Vec<Vec<STrans>>,
    /// Prohibitions per state (sorted by event).
    pub prohib: Vec<Vec<SProhib>>,
    /// The enforced event per state (γ).
    pub enforced: Vec<Option<EventId>>,
}

impl SynthAut {
    pub fn num_states(&self) -> usize {
        self.trans.len()
    }

    pub fn num_transitions(&self) -> usize {
        self.trans.iter().map(Vec::len).sum()
    }

    pub fn width(&self) -> usize {
        1 + self.plants.len()
    }

    pub fn tuple(&self, s: u32) -> &[u32] {
        let w = self.width();
        &self.tuples[s as usize * w..(s as usize + 1) * w]
    }

    /// A specification as a synthesis automaton with an empty plant alphabet (lemma 8).
    pub fn from_spec(spec: &Spec) -> SynthAut {
        let n = spec.states.len();
        let mut trans = vec![Vec::new(); n];
        let mut prohib = vec![Vec::new(); n];
        for t in &spec.trans {
            trans[t.src as usize].push(STrans {
                event: t.event,
                cond: t.cond.clone(),
                dst: t.dst,
                origin: [t.origin, NO_ORIGIN],
            });
        }
        for p in &spec.prohib {
            prohib[p.state as usize].push(SProhib { event: p.event, cond: p.cond.clone(), origin: p.origin });
        }
        for v in &mut trans {
            v.sort_by_key(|t| t.event);
        }
        for v in &mut prohib {
            v.sort_by_key(|p| p.event);
        }
        let a = SynthAut {
            plants: Vec::new(),
            tuples: (0..n as u32).collect(),
            plant_alphabet: Vec::new(),
            init: Some(spec.init),
            trans,
            prohib,
            enforced: vec![None; n],
        };
        a.accessible()
    }

    /// The reachable part, renumbered in breadth-first order from the initial state. Only
    /// transitions whose condition is not false count.
    pub fn accessible(&self) -> SynthAut {
        let keep = vec![true; self.num_states()];
        self.restrict(&keep)
    }

    /// Keeps the states in `keep` that are reachable through kept states; transitions into
    /// dropped states are dropped (callers turn them into prohibitions first if needed).
    pub fn restrict(&self, keep: &[bool]) -> SynthAut {
        let w = self.width();
        let mut out = SynthAut {
            plants: self.plants.clone(),
            tuples: Vec::new(),
            plant_alphabet: self.plant_alphabet.clone(),
            init: None,
            trans: Vec::new(),
            prohib: Vec::new(),
            enforced: Vec::new(),
        };
        let Some(i) = self.init.filter(|&i| keep[i as usize]) else { return out };
        let mut map = vec![u32::MAX; self.num_states()];
        let mut order = Vec::new();
        let graph = NodeFiltered(View(self), |s: u32| keep[s as usize]);
        let mut bfs = Bfs::new(&graph, i);
        while let Some(s) = bfs.next(&graph) {
            map[s as usize] = order.len() as u32;
            order.push(s);
        }
        for &s in &order {
            out.tuples.extend_from_slice(&self.tuples[s as usize * w..(s as usize + 1) * w]);
            out.trans.push(
                self.trans[s as usize]
                    .iter()
                    .filter(|t| map[t.dst as usize] != u32::MAX && t.cond != Cond::False)
                    .map(|t| STrans { dst: map[t.dst as usize], ..t.clone() })
                    .collect(),
            );
            out.prohib.push(self.prohib[s as usize].iter().filter(|p| p.cond != Cond::False).cloned().collect());
            out.enforced.push(self.enforced[s as usize]);
        }
        out.init = Some(0);
        out
    }

    /// Plants referenced by conditions that are still unresolved.
    pub fn unresolved_plants(&self) -> Vec<u32> {
        let mut v = Vec::new();
        for ts in &self.trans {
            for t in ts {
                t.cond.plants(&mut v);
            }
        }
        for ps in &self.prohib {
            for p in ps {
                p.cond.plants(&mut v);
            }
        }
        v.sort_unstable();
        v.dedup();
        v
    }
}

/// The transitions whose condition is not false.
impl Successors for SynthAut {
    type Iter<'a> = std::iter::FilterMap<std::slice::Iter<'a, STrans>, fn(&STrans) -> Option<u32>>;
    fn node_bound(&self) -> usize {
        self.num_states()
    }
    fn successors(&self, s: u32) -> Self::Iter<'_> {
        self.trans[s as usize].iter().filter_map(|t| (t.cond != Cond::False).then_some(t.dst))
    }
}

/// Two transitions on one event leave one state and both conditions hold (6.4.4).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Conflict {
    pub event: EventId,
    /// Source locations of the user transitions involved (deduplicated, may be empty).
    pub origins: Vec<u32>,
    /// Human-readable state, e.g. `(S1, Heater.on)`.
    pub state: String,
}

fn state_label(project: &Project, spec: &Spec, a: &SynthAut, s: u32) -> String {
    let t = a.tuple(s);
    let mut parts = vec![spec.states[t[0] as usize].clone()];
    for (i, &p) in a.plants.iter().enumerate() {
        let plant = &project.plants[p as usize];
        parts.push(format!("{}.{}", plant.name, plant.states[t[i + 1] as usize]));
    }
    format!("({})", parts.join(", "))
}

/// Plant composition `G1 || G2` (definitions 17 and 26): synchronous on shared events, the
/// conditions of each operand refined on the other's state (conditions naming `g1` or `g2`
/// are decided, those naming other plants remain). Only the accessible part is built.
pub fn plant_compose(project: &Project, g1: u32, g2: u32) -> Plant {
    let (a, b) = (&project.plants[g1 as usize], &project.plants[g2 as usize]);
    let n = project.events.len();
    let mut in_a = vec![false; n];
    let mut in_b = vec![false; n];
    a.alphabet.iter().for_each(|e| in_a[e.0 as usize] = true);
    b.alphabet.iter().for_each(|e| in_b[e.0 as usize] = true);
    fn out_of(p: &Plant) -> Vec<Vec<&Transition>> {
        let mut v: Vec<Vec<&Transition>> = vec![Vec::new(); p.states.len()];
        p.trans.iter().for_each(|t| v[t.src as usize].push(t));
        v
    }
    let (ta, tb) = (out_of(a), out_of(b));
    let mut alphabet: Vec<EventId> = a.alphabet.iter().chain(&b.alphabet).copied().collect();
    alphabet.sort_unstable();
    alphabet.dedup();
    let mut out =
        Plant { name: format!("{}||{}", a.name, b.name), alphabet, states: Vec::new(), init: 0, trans: Vec::new() };
    let mut index: hashbrown::HashMap<(u32, u32), u32> = hashbrown::HashMap::new();
    let mut pairs = vec![(a.init, b.init)];
    index.insert((a.init, b.init), 0);
    let mut k = 0;
    while k < pairs.len() {
        let (q1, q2) = pairs[k];
        out.states.push(format!("{}|{}", a.states[q1 as usize], b.states[q2 as usize]));
        let lookup = |p: u32| {
            if p == g1 {
                Some(q1)
            } else if p == g2 {
                Some(q2)
            } else {
                None
            }
        };
        let mut moves: Vec<(EventId, Cond, (u32, u32), u32)> = Vec::new();
        for x in &ta[q1 as usize] {
            if !in_b[x.event.0 as usize] {
                moves.push((x.event, x.cond.refine(&lookup), (x.dst, q2), x.origin));
            } else {
                for y in tb[q2 as usize].iter().filter(|y| y.event == x.event) {
                    moves.push((x.event, x.cond.refine(&lookup).and(y.cond.refine(&lookup)), (x.dst, y.dst), x.origin));
                }
            }
        }
        for y in &tb[q2 as usize] {
            if !in_a[y.event.0 as usize] {
                moves.push((y.event, y.cond.refine(&lookup), (q1, y.dst), y.origin));
            }
        }
        push_moves(&mut out.trans, &mut index, &mut pairs, k as u32, moves);
        k += 1;
    }
    out
}

/// Adds the transitions of a product state: each move whose condition can hold goes to the
/// pair it names, numbered on first sight (shared by the plant and specification products).
fn push_moves(
    trans: &mut Vec<Transition>,
    index: &mut hashbrown::HashMap<(u32, u32), u32>,
    pairs: &mut Vec<(u32, u32)>,
    src: u32,
    moves: Vec<(EventId, Cond, (u32, u32), u32)>,
) {
    for (event, cond, pair, origin) in moves {
        if cond == Cond::False {
            continue;
        }
        let next = pairs.len() as u32;
        let dst = *index.entry(pair).or_insert_with(|| {
            pairs.push(pair);
            next
        });
        trans.push(Transition { src, event, cond, dst, origin });
    }
}

/// Specification product `H1 | H2` (definition 6, with conditions): prohibits everything
/// either operand prohibits; an event moves the operands that have a transition for it, and
/// an operand without one stays unless it prohibits the event. Only the accessible part is
/// built. Conditions of competing transitions are combined as in the application product.
/// Every product state is drawn from `budget`.
pub fn spec_product(name: &str, a: &Spec, b: &Spec, budget: &mut Budget) -> Result<Spec, SynthError> {
    fn by_state(h: &Spec) -> (Vec<Vec<&Transition>>, Vec<Vec<&Prohibition>>) {
        let mut t: Vec<Vec<&Transition>> = vec![Vec::new(); h.states.len()];
        let mut p: Vec<Vec<&Prohibition>> = vec![Vec::new(); h.states.len()];
        for x in &h.trans {
            t[x.src as usize].push(x);
        }
        for x in &h.prohib {
            p[x.state as usize].push(x);
        }
        (t, p)
    }
    if a.states.is_empty() || b.states.is_empty() {
        return Ok(Spec { name: name.to_string(), states: Vec::new(), init: 0, trans: Vec::new(), prohib: Vec::new() });
    }
    let (ta, pa) = by_state(a);
    let (tb, pb) = by_state(b);
    let mut index: hashbrown::HashMap<(u32, u32), u32> = hashbrown::HashMap::new();
    let mut pairs = vec![(a.init, b.init)];
    index.insert((a.init, b.init), 0);
    budget.take_one()?;
    let mut out = Spec { name: name.to_string(), states: Vec::new(), init: 0, trans: Vec::new(), prohib: Vec::new() };
    let any = |cs: &mut dyn Iterator<Item = &Cond>| cs.fold(Cond::False, |acc, c| acc.or(c.clone()));
    let mut k = 0;
    while k < pairs.len() {
        let (q1, q2) = pairs[k];
        out.states.push(format!("{}|{}", a.states[q1 as usize], b.states[q2 as usize]));
        let mut evs: Vec<EventId> = ta[q1 as usize]
            .iter()
            .map(|t| t.event)
            .chain(tb[q2 as usize].iter().map(|t| t.event))
            .chain(pa[q1 as usize].iter().map(|p| p.event))
            .chain(pb[q2 as usize].iter().map(|p| p.event))
            .collect();
        evs.sort_unstable();
        evs.dedup();
        let mut moves: Vec<(EventId, Cond, (u32, u32), u32)> = Vec::new();
        for e in evs {
            let t1: Vec<&&Transition> = ta[q1 as usize].iter().filter(|t| t.event == e).collect();
            let t2: Vec<&&Transition> = tb[q2 as usize].iter().filter(|t| t.event == e).collect();
            let p1 = any(&mut pa[q1 as usize].iter().filter(|p| p.event == e).map(|p| &p.cond));
            let p2 = any(&mut pb[q2 as usize].iter().filter(|p| p.event == e).map(|p| &p.cond));
            let c1 = any(&mut t1.iter().map(|t| &t.cond));
            let c2 = any(&mut t2.iter().map(|t| &t.cond));
            for x in &t1 {
                for y in &t2 {
                    moves.push((e, x.cond.clone().and(y.cond.clone()), (x.dst, y.dst), x.origin));
                }
                moves.push((
                    e,
                    x.cond.clone().and(c2.clone().negate()).and(p2.clone().negate()),
                    (x.dst, q2),
                    x.origin,
                ));
            }
            for y in &t2 {
                moves.push((
                    e,
                    y.cond.clone().and(c1.clone().negate()).and(p1.clone().negate()),
                    (q1, y.dst),
                    y.origin,
                ));
            }
            for p in pa[q1 as usize].iter().chain(pb[q2 as usize].iter()).filter(|p| p.event == e) {
                out.prohib.push(Prohibition { state: k as u32, ..(*p).clone() });
            }
        }
        let known = pairs.len();
        push_moves(&mut out.trans, &mut index, &mut pairs, k as u32, moves);
        for _ in known..pairs.len() {
            budget.take_one()?;
        }
        k += 1;
    }
    Ok(out)
}

/// A transition under construction: event, condition, target pair, origins.
type NewTrans = (EventId, Cond, (u32, u32), [u32; 2]);

/// Application product `C @ G` (definitions 20, 27 and 32): applies the knowledge of plant
/// `g` to the synthesis automaton `c`. Conflicting transitions that both become unconditional
/// are reported.
fn apply(project: &Project, spec: &Spec, c: &SynthAut, g_id: u32, budget: &mut Budget) -> Result<SynthAut, SynthError> {
    let g = &project.plants[g_id as usize];
    let mut g_alphabet = g.alphabet.clone();
    g_alphabet.sort_unstable();
    g_alphabet.dedup();
    let in_g = |e: EventId| g_alphabet.binary_search(&e).is_ok();
    let in_c = |e: EventId| c.plant_alphabet.binary_search(&e).is_ok();
    let mut plant_alphabet: Vec<EventId> = c.plant_alphabet.iter().chain(&g_alphabet).copied().collect();
    plant_alphabet.sort_unstable();
    plant_alphabet.dedup();
    // Plant transitions per state, sorted by event.
    let mut g_out: Vec<Vec<&Transition>> = vec![Vec::new(); g.states.len()];
    for t in &g.trans {
        g_out[t.src as usize].push(t);
    }
    for v in &mut g_out {
        v.sort_by_key(|t| t.event);
    }
    let mut plants = c.plants.clone();
    plants.push(g_id);
    let w_old = c.width();
    let mut out = SynthAut {
        plants,
        tuples: Vec::new(),
        plant_alphabet,
        init: None,
        trans: Vec::new(),
        prohib: Vec::new(),
        enforced: Vec::new(),
    };
    let Some(ci) = c.init else { return Ok(out) };
    budget.take_one()?;
    let mut index: hashbrown::HashMap<(u32, u32), u32> = hashbrown::HashMap::new();
    let mut pairs: Vec<(u32, u32)> = vec![(ci, g.init)];
    index.insert((ci, g.init), 0);
    let mut k = 0;
    let mut new_trans: Vec<NewTrans> = Vec::new();
    while k < pairs.len() {
        let (qc, qg) = pairs[k];
        let ctuple = &c.tuples[qc as usize * w_old..(qc as usize + 1) * w_old];
        let lookup = |p: u32| -> Option<u32> {
            if p == g_id {
                return Some(qg);
            }
            c.plants.iter().position(|&x| x == p).map(|i| ctuple[i + 1])
        };
        new_trans.clear();
        let mut new_prohib: Vec<SProhib> = Vec::new();
        let gts = &g_out[qg as usize];
        let g_for = |e: EventId| {
            let lo = gts.partition_point(|t| t.event < e);
            let hi = gts.partition_point(|t| t.event <= e);
            &gts[lo..hi]
        };
        let gamma = c.enforced[qc as usize];
        for tc in &c.trans[qc as usize] {
            let e = tc.event;
            if !in_g(e) {
                let cond = tc.cond.refine(&lookup);
                if cond != Cond::False {
                    new_trans.push((e, cond, (tc.dst, qg), tc.origin));
                }
            } else {
                for tg in g_for(e) {
                    let cond = tc.cond.refine(&lookup).and(tg.cond.refine(&lookup));
                    if cond != Cond::False {
                        let o0 = if tc.origin[0] != NO_ORIGIN { tc.origin[0] } else { tc.origin[1] };
                        new_trans.push((e, cond, (tc.dst, tg.dst), [o0, tg.origin]));
                    }
                }
            }
        }
        for p in &c.prohib[qc as usize] {
            let e = p.event;
            if !in_g(e) {
                let cond = p.cond.refine(&lookup);
                if cond != Cond::False {
                    new_prohib.push(SProhib { event: e, cond, origin: p.origin });
                }
            } else {
                // Kept only where the plant considers the event possible.
                let mut any = Cond::False;
                for tg in g_for(e) {
                    let cond = p.cond.refine(&lookup).and(tg.cond.refine(&lookup));
                    any = any.or(cond);
                }
                if any != Cond::False {
                    new_prohib.push(SProhib { event: e, cond: any, origin: p.origin });
                }
            }
        }
        // Plant moves while the synthesis automaton stays (it has no knowledge of the event).
        for tg in gts.iter() {
            let e = tg.event;
            if in_c(e) {
                continue;
            }
            if let Some(f) = gamma {
                // Preempted events (definition 30) cannot occur here.
                if f != e && project.kind(e) != EventKind::Controllable {
                    continue;
                }
            }
            let mut cond = tg.cond.refine(&lookup);
            for tc in c.trans[qc as usize].iter().filter(|t| t.event == e) {
                cond = cond.and(tc.cond.refine(&lookup).negate());
            }
            for p in c.prohib[qc as usize].iter().filter(|p| p.event == e) {
                cond = cond.and(p.cond.refine(&lookup).negate());
            }
            if cond != Cond::False {
                new_trans.push((e, cond, (qc, tg.dst), [NO_ORIGIN, tg.origin]));
            }
        }
        // Prohibitions dominate: a transition on an unconditionally prohibited event is dropped.
        new_trans.retain(|(e, _, _, _)| !new_prohib.iter().any(|p| p.event == *e && p.cond.is_true()));
        new_trans.sort_by_key(|t| (t.0, t.2));
        new_trans.dedup_by(|b, a| a.0 == b.0 && a.2 == b.2 && a.1.is_true() && b.1.is_true());
        // Determinism: two unconditional transitions on one event.
        for w in new_trans.windows(2) {
            if w[0].0 == w[1].0 && w[0].1.is_true() && w[1].1.is_true() && w[0].2 != w[1].2 {
                let mut origins: Vec<u32> =
                    w[0].3.iter().chain(w[1].3.iter()).copied().filter(|&o| o != NO_ORIGIN).collect();
                origins.sort_unstable();
                origins.dedup();
                let mut tup: Vec<u32> = ctuple.to_vec();
                tup.push(qg);
                let tmp = SynthAut {
                    plants: out.plants.clone(),
                    tuples: tup,
                    plant_alphabet: Vec::new(),
                    init: None,
                    trans: vec![Vec::new()],
                    prohib: vec![Vec::new()],
                    enforced: vec![None],
                };
                return Err(SynthError::Conflict(Conflict {
                    event: w[0].0,
                    origins,
                    state: state_label(project, spec, &tmp, 0),
                }));
            }
        }
        new_prohib.sort_by_key(|p| p.event);
        let mut row = Vec::with_capacity(new_trans.len());
        for (e, cond, pair, origin) in new_trans.drain(..) {
            let id = match index.entry(pair) {
                hashbrown::hash_map::Entry::Occupied(o) => *o.get(),
                hashbrown::hash_map::Entry::Vacant(v) => {
                    budget.take_one()?;
                    pairs.push(pair);
                    *v.insert(pairs.len() as u32 - 1)
                }
            };
            row.push(STrans { event: e, cond, dst: id, origin });
        }
        out.tuples.extend_from_slice(ctuple);
        out.tuples.push(qg);
        out.trans.push(row);
        out.prohib.push(new_prohib);
        // γ survives if the plant can do the enforced event here (definition 32).
        let keep_gamma = gamma.filter(|f| !in_g(*f) || !g_for(*f).is_empty());
        out.enforced.push(keep_gamma);
        k += 1;
    }
    out.init = Some(0);
    Ok(out)
}

/// Is a prohibition "uncontrollable" for synthesis? Unresolved conditions count as true
/// (conservative, 5.7.3).
fn has_uncontrollable_prohibition(project: &Project, a: &SynthAut, s: usize) -> bool {
    a.prohib[s].iter().any(|p| project.kind(p.event) == EventKind::Uncontrollable && p.cond != Cond::False)
}

/// One synthesis step: `sys` (definition 21) or, with `preempt`, `sysp` (definition 36).
/// Returns the new automaton and whether anything changed.
pub fn step(project: &Project, a: &SynthAut, preempt: bool) -> (SynthAut, bool) {
    let n = a.num_states();
    let critical: Vec<bool> = (0..n).map(|s| has_uncontrollable_prohibition(project, a, s)).collect();
    let is_enf = |e: EventId| project.kind(e) == EventKind::Enforceable;
    // Q': the largest set where every critical state has an enforceable way into Q'.
    let mut alive = vec![true; n];
    if preempt {
        // Greatest fixpoint: repeatedly drop critical states without a live enforceable exit.
        let mut preds: Vec<Vec<u32>> = vec![Vec::new(); n];
        for s in 0..n {
            for t in &a.trans[s] {
                if is_enf(t.event) && t.cond.is_true() {
                    preds[t.dst as usize].push(s as u32);
                }
            }
        }
        let exits = |s: usize, alive: &[bool]| {
            a.trans[s].iter().any(|t| is_enf(t.event) && t.cond.is_true() && alive[t.dst as usize])
        };
        let mut work: Vec<u32> =
            (0..n as u32).filter(|&s| critical[s as usize] && !exits(s as usize, &alive)).collect();
        for &s in &work {
            alive[s as usize] = false;
        }
        while let Some(s) = work.pop() {
            for &p in &preds[s as usize] {
                if alive[p as usize] && critical[p as usize] && !exits(p as usize, &alive) {
                    alive[p as usize] = false;
                    work.push(p);
                }
            }
        }
    } else {
        for s in 0..n {
            if critical[s] {
                alive[s] = false;
            }
        }
    }
    let mut changed = alive.iter().any(|x| !x);
    let mut b = a.clone();
    for s in 0..n {
        if !alive[s] {
            continue;
        }
        // γ' (definition 36): keep a still valid choice, else choose the smallest event.
        if preempt && critical[s] {
            let valid = a.enforced[s]
                .filter(|f| a.trans[s].iter().any(|t| t.event == *f && t.cond.is_true() && alive[t.dst as usize]));
            let g = valid.or_else(|| {
                a.trans[s]
                    .iter()
                    .find(|t| is_enf(t.event) && t.cond.is_true() && alive[t.dst as usize])
                    .map(|t| t.event)
            });
            if g != a.enforced[s] {
                changed = true;
            }
            b.enforced[s] = g;
        } else if let Some(f) = a.enforced[s] {
            if !a.trans[s].iter().any(|t| t.event == f && alive[t.dst as usize]) {
                b.enforced[s] = None;
                changed = true;
            }
        }
        // Transitions into removed states become prohibitions of their event.
        let mut newp: Vec<SProhib> = Vec::new();
        b.trans[s].retain(|t| {
            if alive[t.dst as usize] {
                true
            } else {
                newp.push(SProhib { event: t.event, cond: Cond::True, origin: t.origin[0] });
                false
            }
        });
        if !newp.is_empty() {
            for p in newp {
                if let Some(q) = b.prohib[s].iter_mut().find(|q| q.event == p.event) {
                    q.cond = Cond::True;
                } else {
                    b.prohib[s].push(p);
                }
            }
            b.prohib[s].sort_by_key(|p| p.event);
        }
    }
    if !changed {
        return (b, false);
    }
    let out = b.restrict(&alive);
    (out, true)
}

/// Synthesis method.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Method {
    /// Apply every plant, then iterate synthesis steps to the fixpoint (5.8.2).
    Monolithic,
    /// Apply plants lazily, only where an uncontrollable prohibition would isolate a state (5.8.3).
    Incremental,
}

/// Synthesis options.
#[derive(Clone, Copy, Debug)]
pub struct Config {
    pub method: Method,
    /// Use enforceable events to preempt uncontrollable ones (5.5, 5.8.5).
    pub preempt: bool,
    /// Minimise the result (5.4.4).
    pub minimize: bool,
    /// Stop with [`SynthError::BudgetExceeded`] once more than this many product states have
    /// been built (monolithic synthesis on many plants grows exponentially). [`synthesize`]
    /// gives each specification this budget; a report over a whole project shares one among all.
    pub max_states: usize,
}

/// The default state budget of a run ([`Config`], [`super::compile`], `supervise
/// --max-states`): product states cost 0.5–1.5 KB and a few microseconds each, so a run stops
/// within about a second and a few hundred MB.
pub const DEFAULT_MAX_STATES: usize = 250_000;

/// How many new states a product builds between two calls of the progress callback.
const PROGRESS_INTERVAL: usize = 4096;

impl Default for Config {
    fn default() -> Config {
        Config { method: Method::Incremental, preempt: true, minimize: true, max_states: DEFAULT_MAX_STATES }
    }
}

/// A synthesised supervisor (definition 7, with the enforcement map of 5.8.5).
#[derive(Clone, Debug, Serialize)]
pub struct Supervisor {
    pub name: String,
    /// `None` if the specification is unrealizable (void supervisor).
    pub init: Option<u32>,
    pub states: Vec<SupState>,
    /// Plants that were applied, in order.
    pub plants_used: Vec<String>,
}

/// One supervisor state: its label, explicit transitions, prohibited and enforced events.
#[derive(Clone, Debug, Serialize)]
pub struct SupState {
    pub label: String,
    pub transitions: Vec<(EventId, u32)>,
    pub prohibited: Vec<EventId>,
    pub enforced: Option<EventId>,
    /// Source locations of the enforced transition (for cycle reports).
    #[serde(skip)]
    pub enforced_origin: Vec<u32>,
}

impl SupState {
    /// The explicit transition on `e`, if any.
    pub fn next(&self, e: EventId) -> Option<u32> {
        self.transitions.iter().find(|(x, _)| *x == e).map(|&(_, t)| t)
    }

    /// Whether this state prohibits `e`.
    pub fn prohibits(&self, e: EventId) -> bool {
        self.prohibited.contains(&e)
    }
}

impl Supervisor {
    /// The successor of `state` on `e`: its transition on `e`, else `state` itself (an event
    /// without a transition loops).
    pub fn successor(&self, state: u32, e: EventId) -> u32 {
        self.states[state as usize].next(e).unwrap_or(state)
    }

    /// Whether `state` prohibits `e`.
    pub fn prohibits(&self, state: u32, e: EventId) -> bool {
        self.states[state as usize].prohibits(e)
    }

    /// The first of `supervisors`, each in its state of `states`, that prohibits `e`.
    pub fn first_prohibiting(supervisors: &[&Supervisor], states: &[u32], e: EventId) -> Option<usize> {
        (0..supervisors.len()).find(|&k| supervisors[k].prohibits(states[k], e))
    }

    pub fn realizable(&self) -> bool {
        self.init.is_some()
    }

    pub fn num_transitions(&self) -> usize {
        self.states.iter().map(|s| s.transitions.len()).sum()
    }

    pub fn num_prohibitions(&self) -> usize {
        self.states.iter().map(|s| s.prohibited.len()).sum()
    }

    /// Events enforced somewhere, sorted and deduplicated.
    pub fn enforced_events(&self) -> Vec<EventId> {
        let mut v: Vec<EventId> = self.states.iter().filter_map(|s| s.enforced).collect();
        v.sort_unstable();
        v.dedup();
        v
    }

    /// Events prohibited somewhere, sorted and deduplicated.
    pub fn prohibited_events(&self) -> Vec<EventId> {
        let mut v: Vec<EventId> = self.states.iter().flat_map(|s| s.prohibited.iter().copied()).collect();
        v.sort_unstable();
        v.dedup();
        v
    }

    /// The supervisor's state after a word (implicit self-loops for events without a
    /// transition); `None` if a prohibited event occurs or the supervisor is void.
    pub fn run(&self, word: &[EventId]) -> Option<u32> {
        let mut s = self.init?;
        for &e in word {
            if self.prohibits(s, e) {
                return None;
            }
            s = self.successor(s, e);
        }
        Some(s)
    }

    /// A cycle of enforced transitions (5.5.5), as the list of states on it.
    ///
    /// Kept by hand rather than petgraph's `depth_first_search`: every state has at most one
    /// enforced successor, so the search is a walk along it, and the walk is a loop where
    /// petgraph's search recurses once per state on a path (a long enforced chain would exhaust
    /// the stack, in the browser first).
    pub fn enforcement_cycle(&self) -> Option<Vec<u32>> {
        let n = self.states.len();
        let next = |s: usize| -> Option<usize> {
            let f = self.states[s].enforced?;
            self.states[s].next(f).map(|t| t as usize)
        };
        let mut color = vec![0u8; n];
        for start in 0..n {
            let mut path = Vec::new();
            let mut s = start;
            loop {
                if color[s] == 2 {
                    break;
                }
                if color[s] == 1 {
                    let i = path.iter().position(|&x| x == s).unwrap_or(0);
                    return Some(path[i..].iter().map(|&x| x as u32).collect());
                }
                color[s] = 1;
                path.push(s);
                match next(s) {
                    Some(t) => s = t,
                    None => break,
                }
            }
            for p in path {
                color[p] = 2;
            }
        }
        None
    }
}

/// Errors of synthesis for one specification.
#[derive(Clone, Debug)]
pub enum SynthError {
    Conflict(Conflict),
    /// The run built more product states than its budget allows.
    BudgetExceeded {
        max_states: usize,
    },
    /// The progress callback asked to stop.
    Cancelled,
}

/// Why a run stopped before its end.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stop {
    /// More product states than the budget allows.
    BudgetExceeded { max_states: usize },
    /// The progress callback asked to stop.
    Cancelled,
}

impl Stop {
    /// The stop behind a synthesis error, if it is one (a conflict is an input error).
    pub fn of(error: &SynthError) -> Option<Stop> {
        match error {
            SynthError::BudgetExceeded { max_states } => Some(Stop::BudgetExceeded { max_states: *max_states }),
            SynthError::Cancelled => Some(Stop::Cancelled),
            SynthError::Conflict(_) => None,
        }
    }
}

/// What bounds a run: a number of product states that may still be built (every state of every
/// specification product and application product counts, also of products later shrunk by
/// synthesis steps) and the caller's progress callback. The callback sees the number of states built so
/// far and returns `false` to cancel. One budget can serve several specifications.
pub struct Budget<'a> {
    max_states: usize,
    built: usize,
    progress: &'a mut dyn FnMut(usize) -> bool,
}

impl<'a> Budget<'a> {
    pub fn new(max_states: usize, progress: &'a mut dyn FnMut(usize) -> bool) -> Budget<'a> {
        Budget { max_states, built: 0, progress }
    }

    /// Product states built so far.
    pub fn built(&self) -> usize {
        self.built
    }

    /// The number of states the budget allows.
    pub fn max_states(&self) -> usize {
        self.max_states
    }

    /// Accounts for one new product state.
    fn take_one(&mut self) -> Result<(), SynthError> {
        self.built += 1;
        if self.built > self.max_states {
            return Err(SynthError::BudgetExceeded { max_states: self.max_states });
        }
        if self.built % PROGRESS_INTERVAL == 0 && !(self.progress)(self.built) {
            return Err(SynthError::Cancelled);
        }
        Ok(())
    }
}

/// Synthesises the supervisor for specification `spec_id` within `cfg.max_states`.
pub fn synthesize(project: &Project, spec_id: usize, cfg: &Config) -> Result<Supervisor, SynthError> {
    synthesize_within(project, spec_id, cfg, &mut Budget::new(cfg.max_states, &mut |_| true))
}

/// [`synthesize`] drawing on a caller's budget (which may be shared by several
/// specifications and carries the progress callback); `cfg.max_states` is not consulted.
pub fn synthesize_within(
    project: &Project,
    spec_id: usize,
    cfg: &Config,
    budget: &mut Budget,
) -> Result<Supervisor, SynthError> {
    synthesize_known(project, &Knowledge::new(project), spec_id, cfg, budget)
}

/// Which plants know each event (have it in their alphabet): what incremental synthesis looks
/// up. Built once per run, as it is as large as the project.
pub struct Knowledge {
    knows: Vec<Vec<u32>>,
}

impl Knowledge {
    pub fn new(project: &Project) -> Knowledge {
        let mut knows: Vec<Vec<u32>> = vec![Vec::new(); project.events.len()];
        for (i, p) in project.plants.iter().enumerate() {
            for e in &p.alphabet {
                knows[e.0 as usize].push(i as u32);
            }
        }
        Knowledge { knows }
    }
}

/// [`synthesize_within`] with the project's [`Knowledge`] built by the caller: the work for one
/// specification then depends on its own size and the plants it needs, not on the project's.
pub fn synthesize_known(
    project: &Project,
    knowledge: &Knowledge,
    spec_id: usize,
    cfg: &Config,
    budget: &mut Budget,
) -> Result<Supervisor, SynthError> {
    let spec = &project.specs[spec_id];
    let mut c = SynthAut::from_spec(spec);
    let mut applied: hashbrown::HashSet<u32> = hashbrown::HashSet::new();
    let remaining = |applied: &hashbrown::HashSet<u32>, g: u32| !applied.contains(&g);
    let knows = &knowledge.knows;
    match cfg.method {
        Method::Monolithic => {
            for g in 0..project.plants.len() as u32 {
                c = apply(project, spec, &c, g, budget)?;
            }
            loop {
                let (next, changed) = step(project, &c, cfg.preempt);
                c = next;
                if !changed || c.init.is_none() {
                    break;
                }
            }
        }
        Method::Incremental => loop {
            // Gather plants until none is relevant: those knowing an uncontrollable prohibited
            // event (lemma 18), those knowing an enforceable event offered where preemption may
            // be needed (so that preemption rests on full knowledge, 5.8.5), and those that
            // conditions still refer to (5.7.3).
            loop {
                let mut gather: Vec<u32> =
                    c.unresolved_plants().into_iter().filter(|&p| remaining(&applied, p)).collect();
                for s in 0..c.num_states() {
                    if !has_uncontrollable_prohibition(project, &c, s) {
                        continue;
                    }
                    for p in &c.prohib[s] {
                        if project.kind(p.event) == EventKind::Uncontrollable {
                            gather.extend(knows[p.event.0 as usize].iter().filter(|&&g| remaining(&applied, g)));
                        }
                    }
                    if cfg.preempt {
                        for t in &c.trans[s] {
                            if project.kind(t.event) == EventKind::Enforceable {
                                gather.extend(knows[t.event.0 as usize].iter().filter(|&&g| remaining(&applied, g)));
                            }
                        }
                    }
                }
                gather.sort_unstable();
                gather.dedup();
                if gather.is_empty() {
                    break;
                }
                for g in gather {
                    applied.insert(g);
                    c = apply(project, spec, &c, g, budget)?;
                }
            }
            let (next, changed) = step(project, &c, cfg.preempt);
            c = next;
            if !changed || c.init.is_none() {
                break;
            }
        },
    }
    Ok(to_supervisor(project, spec, &c, cfg))
}

/// The plants Åkesson et al.'s modular criterion would compose with a specification (the
/// `Dep` closure of 5.8.3): start from the uncontrollable events the specification mentions,
/// add every plant sharing one of them, then those plants' uncontrollable events, until
/// nothing changes. Incremental synthesis usually needs far fewer; used for comparison.
pub fn dep_closure(project: &Project, spec_id: usize) -> Vec<u32> {
    let spec = &project.specs[spec_id];
    let n = project.events.len();
    let mut events = vec![false; n];
    for e in spec.trans.iter().map(|t| t.event).chain(spec.prohib.iter().map(|p| p.event)) {
        if project.kind(e) == EventKind::Uncontrollable {
            events[e.0 as usize] = true;
        }
    }
    let mut taken = vec![false; project.plants.len()];
    loop {
        let mut changed = false;
        for (i, g) in project.plants.iter().enumerate() {
            if !taken[i] && g.alphabet.iter().any(|e| events[e.0 as usize]) {
                taken[i] = true;
                changed = true;
                for e in &g.alphabet {
                    if project.kind(*e) == EventKind::Uncontrollable {
                        events[e.0 as usize] = true;
                    }
                }
            }
        }
        if !changed {
            break;
        }
    }
    (0..project.plants.len() as u32).filter(|&i| taken[i as usize]).collect()
}

/// Converts a synthesis fixpoint into a supervisor: drops the plant alphabet, explicit
/// self-loops (they mean the same as no transition), preempted prohibitions in enforcing
/// states and enforceable transitions that are not enforced (6.4.2); then minimises.
fn to_supervisor(project: &Project, spec: &Spec, c: &SynthAut, cfg: &Config) -> Supervisor {
    let mut sup = Supervisor {
        name: spec.name.clone(),
        init: c.init,
        states: Vec::new(),
        plants_used: c.plants.iter().map(|&p| project.plants[p as usize].name.clone()).collect(),
    };
    if c.init.is_none() {
        return sup;
    }
    for s in 0..c.num_states() {
        let gamma = c.enforced[s];
        let transitions: Vec<(EventId, u32)> = c.trans[s]
            .iter()
            .filter(|t| t.dst as usize != s)
            .filter(|t| project.kind(t.event) != EventKind::Enforceable || Some(t.event) == gamma)
            .map(|t| (t.event, t.dst))
            .collect();
        let prohibited: Vec<EventId> = c.prohib[s]
            .iter()
            .filter(|p| gamma.is_none() || project.kind(p.event) != EventKind::Uncontrollable)
            .map(|p| p.event)
            .collect();
        let enforced_origin = gamma
            .and_then(|f| c.trans[s].iter().find(|t| t.event == f))
            .map(|t| t.origin.iter().copied().filter(|&o| o != NO_ORIGIN).collect())
            .unwrap_or_default();
        sup.states.push(SupState {
            label: state_label(project, spec, c, s as u32),
            transitions,
            prohibited,
            enforced: gamma,
            enforced_origin,
        });
    }
    if cfg.minimize {
        sup = minimize_supervisor(&sup);
    }
    sup
}

/// Minimisation (5.4.4): states are equivalent if they prohibit and enforce the same events and
/// their transitions lead to equivalent states, where a missing transition means "stay". The
/// supervisor is read as a complete automaton over the events it mentions (prohibited events
/// lead to a sink) and refined with Hopcroft's algorithm.
pub fn minimize_supervisor(sup: &Supervisor) -> Supervisor {
    let Some(init) = sup.init else { return sup.clone() };
    let n = sup.states.len();
    let mut events: Vec<EventId> = sup
        .states
        .iter()
        .flat_map(|s| s.transitions.iter().map(|t| t.0).chain(s.prohibited.iter().copied()).chain(s.enforced))
        .collect();
    events.sort_unstable();
    events.dedup();
    let k = events.len();
    let sink = n as u32;
    let mut delta = vec![0u32; (n + 1) * k];
    for (s, st) in sup.states.iter().enumerate() {
        for (a, e) in events.iter().enumerate() {
            delta[s * k + a] = if st.prohibits(*e) { sink } else { st.next(*e).unwrap_or(s as u32) };
        }
    }
    for a in 0..k {
        delta[n * k + a] = sink;
    }
    let mut keys: hashbrown::HashMap<(Vec<EventId>, Option<EventId>), u64> = hashbrown::HashMap::new();
    let mut key: Vec<u64> = sup
        .states
        .iter()
        .map(|s| {
            let mut p = s.prohibited.clone();
            p.sort_unstable();
            let next = keys.len() as u64;
            *keys.entry((p, s.enforced)).or_insert(next)
        })
        .collect();
    key.push(u64::MAX);
    let class = super::partition::coarsest_partition(n + 1, k, &delta, &key);
    let count = class.iter().copied().max().map_or(0, |c| c as usize + 1);
    // Build the quotient from the initial state.
    let mut renum = vec![u32::MAX; count];
    let mut reps: Vec<usize> = vec![init as usize];
    renum[class[init as usize] as usize] = 0;
    let mut states = Vec::new();
    let mut k = 0;
    while k < reps.len() {
        let s = reps[k];
        let st = &sup.states[s];
        let mut transitions = Vec::new();
        for &(e, t) in &st.transitions {
            let c = class[t as usize] as usize;
            if class[t as usize] == class[s] {
                continue;
            }
            if renum[c] == u32::MAX {
                renum[c] = reps.len() as u32;
                reps.push(t as usize);
            }
            transitions.push((e, renum[c]));
        }
        states.push(SupState { transitions, ..st.clone() });
        k += 1;
    }
    Supervisor { name: sup.name.clone(), init: Some(0), states, plants_used: sup.plants_used.clone() }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ev(name: &str, kind: EventKind) -> EventInfo {
        EventInfo { name: name.into(), kind }
    }

    fn t(src: u32, e: u32, dst: u32) -> Transition {
        Transition { src, event: EventId(e), cond: Cond::True, dst, origin: NO_ORIGIN }
    }

    /// Figures 5.7 and 5.8: the tank. Events: 0 openInlet (c), 1 closeInlet (c),
    /// 2 levelAlarm (u), 3 overflow (u), 4 closeInlNow (f).
    fn tank(with_enforceable: bool) -> Project {
        use EventKind::*;
        let mut trans =
            vec![t(0, 0, 1), t(0, 1, 0), t(1, 1, 0), t(1, 0, 1), t(1, 2, 2), t(2, 3, 2), t(2, 1, 0), t(2, 0, 2)];
        let mut alphabet = vec![EventId(0), EventId(1), EventId(2), EventId(3)];
        if with_enforceable {
            trans.push(t(2, 4, 0));
            alphabet.push(EventId(4));
        }
        Project {
            events: vec![
                ev("openInlet", Controllable),
                ev("closeInlet", Controllable),
                ev("levelAlarm", Uncontrollable),
                ev("overflow", Uncontrollable),
                ev("closeInlNow", Enforceable),
            ],
            plants: vec![Plant {
                name: "Tank".into(),
                alphabet,
                states: vec!["A".into(), "B".into(), "C".into()],
                init: 0,
                trans,
            }],
            specs: vec![Spec {
                name: "NoOverflow".into(),
                states: vec!["S".into()],
                init: 0,
                trans: vec![],
                prohib: vec![Prohibition { state: 0, event: EventId(3), cond: Cond::True, origin: NO_ORIGIN }],
            }],
        }
    }

    #[test]
    fn tank_without_preemption_disables_open_inlet() {
        let p = tank(false);
        for method in [Method::Incremental, Method::Monolithic] {
            let s = synthesize(&p, 0, &Config { method, ..Config::default() }).unwrap();
            assert!(s.realizable());
            assert_eq!(s.run(&[]), Some(0));
            assert!(s.run(&[EventId(0)]).is_none(), "openInlet must be disabled initially");
            assert!(s.enforced_events().is_empty());
        }
    }

    #[test]
    fn tank_with_preemption_allows_open_and_enforces_closing() {
        let p = tank(true);
        for method in [Method::Incremental, Method::Monolithic] {
            let s = synthesize(&p, 0, &Config { method, ..Config::default() }).unwrap();
            let after = s.run(&[EventId(0), EventId(2)]).expect("openInlet, levelAlarm allowed");
            assert_eq!(s.states[after as usize].enforced, Some(EventId(4)));
            // closeInlet is not preempted: the controller may still close the inlet itself.
            assert!(s.run(&[EventId(0), EventId(2), EventId(1)]).is_some());
            assert_eq!(s.enforced_events(), vec![EventId(4)]);
            assert!(s.prohibited_events().iter().all(|e| p.kind(*e) != EventKind::Uncontrollable));
        }
    }

    #[test]
    fn spec_product_unites_prohibitions_and_moves_independently() {
        // H1: s -a-> t, t forbids b.  H2: forbids a in its initial state after c.
        let t1 = Spec {
            name: "H1".into(),
            states: vec!["s".into(), "t".into()],
            init: 0,
            trans: vec![t(0, 0, 1)],
            prohib: vec![Prohibition { state: 1, event: EventId(1), cond: Cond::True, origin: NO_ORIGIN }],
        };
        let t2 = Spec {
            name: "H2".into(),
            states: vec!["u".into(), "v".into()],
            init: 0,
            trans: vec![t(0, 2, 1)],
            prohib: vec![Prohibition { state: 1, event: EventId(0), cond: Cond::True, origin: NO_ORIGIN }],
        };
        let product = |max_states| spec_product("H", &t1, &t2, &mut Budget::new(max_states, &mut |_| true));
        let h = product(DEFAULT_MAX_STATES).unwrap();
        // The budget admits a product of exactly its size and no more.
        assert!(product(4).is_ok());
        assert!(matches!(product(3), Err(SynthError::BudgetExceeded { max_states: 3 })));
        // From (s,u): a -> (t,u), c -> (s,v); (s,v) forbids a; (t,u) forbids b, c -> (t,v).
        assert_eq!(h.states.len(), 4);
        let p = h.prohib.iter().map(|p| (h.states[p.state as usize].as_str(), p.event.0)).collect::<Vec<_>>();
        assert!(
            p.contains(&("s|v", 0)) && p.contains(&("t|u", 1)) && p.contains(&("t|v", 1)) && p.contains(&("t|v", 0))
        );
        assert!(
            !h.trans.iter().any(|x| h.states[x.src as usize] == "s|v" && x.event == EventId(0)),
            "prohibition dominates"
        );
    }

    #[test]
    fn plant_composition_resolves_conditions_on_each_other() {
        use EventKind::*;
        // A: a-loop only while B is in v, and only while C (not composed) is in state 0.
        let cond = Cond::State { plant: 1, state: 0 }.and(Cond::State { plant: 2, state: 0 });
        let p = Project {
            events: vec![ev("a", Controllable), ev("c", Uncontrollable)],
            plants: vec![
                Plant {
                    name: "A".into(),
                    alphabet: vec![EventId(0)],
                    states: vec!["x".into()],
                    init: 0,
                    trans: vec![Transition { src: 0, event: EventId(0), cond, dst: 0, origin: NO_ORIGIN }],
                },
                Plant {
                    name: "B".into(),
                    alphabet: vec![EventId(1)],
                    states: vec!["v".into(), "w".into()],
                    init: 0,
                    trans: vec![t(0, 1, 1)],
                },
                Plant { name: "C".into(), alphabet: vec![], states: vec!["0".into()], init: 0, trans: vec![] },
            ],
            specs: vec![],
        };
        let g = plant_compose(&p, 0, 1);
        assert_eq!(g.states, vec!["x|v".to_string(), "x|w".to_string()]);
        let a_moves: Vec<_> = g.trans.iter().filter(|t| t.event == EventId(0)).collect();
        assert_eq!(a_moves.len(), 1, "the a-loop survives only in x|v");
        assert_eq!(a_moves[0].src, 0);
        assert_eq!(a_moves[0].cond, Cond::State { plant: 2, state: 0 }, "the condition on C remains");
    }

    #[test]
    fn conditions_refine_three_valued() {
        let c = Cond::State { plant: 0, state: 1 }.and(Cond::State { plant: 1, state: 0 }.negate());
        assert_eq!(c.eval(&|p| (p == 0).then_some(1)), Truth::Maybe);
        assert_eq!(c.eval(&|p| (p == 0).then_some(0)), Truth::False);
        assert_eq!(c.refine(&|p| (p == 0).then_some(1)), Cond::State { plant: 1, state: 0 }.negate());
        assert_eq!(c.eval(&|p| Some(if p == 0 { 1 } else { 2 })), Truth::True);
    }
}
