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

mod minimize;
mod product;
mod supervisor;
mod synth;

pub use minimize::minimize_supervisor;
pub use product::{plant_compose, spec_product};
pub use supervisor::{SupState, Supervisor};
pub use synth::{dep_closure, step, synthesize, synthesize_known, synthesize_within, Knowledge};

use crate::graph::{Successors, View};
use crate::id::id_type;
use petgraph::visit::{Bfs, NodeFiltered};
use serde::Serialize;

use crate::search::OnProgress;
pub use crate::search::Stop;
use crate::search::{Charge, Meter, Resource};

id_type! {
    /// Event id: an index into [`Project::events`].
    #[derive(Serialize)]
    #[serde(transparent)]
    pub struct EventId;
}

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
        self.events[e.index()].kind
    }

    pub fn event_name(&self, e: EventId) -> &str {
        &self.events[e.index()].name
    }

    pub fn event(&self, name: &str) -> Option<EventId> {
        self.events.iter().position(|e| e.name == name).map(EventId::new)
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
            crate::sort::sort_by_key(v, |t| t.event);
        }
        for v in &mut prohib {
            crate::sort::sort_by_key(v, |p| p.event);
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
        // The new number of every kept state reachable from the initial one.
        let mut map = vec![None; self.num_states()];
        let mut order = Vec::new();
        let graph = NodeFiltered(View(self), |s: u32| keep[s as usize]);
        let mut bfs = Bfs::new(&graph, i);
        while let Some(s) = bfs.next(&graph) {
            map[s as usize] = Some(order.len() as u32);
            order.push(s);
        }
        for &s in &order {
            out.tuples.extend_from_slice(&self.tuples[s as usize * w..(s as usize + 1) * w]);
            out.trans.push(
                self.trans[s as usize]
                    .iter()
                    .filter(|t| t.cond != Cond::False)
                    .filter_map(|t| Some(STrans { dst: map[t.dst as usize]?, ..t.clone() }))
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
        crate::sort::sort(&mut v);
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

crate::search::setters!(Config { method: Method, preempt: bool, minimize: bool, max_states: usize });

impl Default for Config {
    fn default() -> Config {
        Config { method: Method::Incremental, preempt: true, minimize: true, max_states: DEFAULT_MAX_STATES }
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

impl SynthError {
    /// The stop behind a synthesis error, if it is one (a conflict is an input error).
    pub fn stop(&self) -> Option<Stop> {
        match self {
            SynthError::BudgetExceeded { max_states } => Some(Stop::budget(
                Resource::States,
                format!("the state budget of {max_states} product states is spent"),
            )),
            SynthError::Cancelled => Some(Stop::Cancelled),
            SynthError::Conflict(_) => None,
        }
    }
}

/// What bounds a run: a number of product states that may still be built (every state of every
/// specification product and application product counts, also of products later shrunk by
/// synthesis steps) and the caller's progress callback. The callback sees the number of states built so
/// far ([`Progress`]) and returns `false` to cancel. One budget can serve several specifications.
pub struct Budget<'a> {
    /// Product states built, against `max_states`, with a progress call every
    /// [`PROGRESS_INTERVAL`] states.
    states: Meter,
    progress: &'a mut OnProgress<'a, Progress>,
}

/// Progress of a run, passed to the callback; returning `false` cancels.
#[derive(Clone, Copy, Debug, Default, serde::Serialize)]
pub struct Progress {
    /// Product states built so far.
    pub states: usize,
}

impl<'a> Budget<'a> {
    pub fn new(max_states: usize, progress: &'a mut OnProgress<'a, Progress>) -> Budget<'a> {
        Budget { states: Meter::new(0, max_states as u64, PROGRESS_INTERVAL as u64), progress }
    }

    /// Product states built so far.
    pub fn built(&self) -> usize {
        self.states.used() as usize
    }

    /// The number of states the budget allows.
    pub fn max_states(&self) -> usize {
        self.states.limit() as usize
    }

    /// Accounts for one new product state.
    fn take_one(&mut self) -> Result<(), SynthError> {
        match self.states.charge(1) {
            Charge::Within => Ok(()),
            Charge::Exceeded => Err(SynthError::BudgetExceeded { max_states: self.max_states() }),
            Charge::ReportDue => {
                let progress = Progress { states: self.built() };
                if (self.progress)(&progress) {
                    Ok(())
                } else {
                    Err(SynthError::Cancelled)
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ev(name: &str, kind: EventKind) -> EventInfo {
        EventInfo { name: name.into(), kind }
    }

    fn t(src: u32, e: u32, dst: u32) -> Transition {
        Transition { src, event: EventId::from_raw(e), cond: Cond::True, dst, origin: NO_ORIGIN }
    }

    /// Figures 5.7 and 5.8: the tank. Events: 0 openInlet (c), 1 closeInlet (c),
    /// 2 levelAlarm (u), 3 overflow (u), 4 closeInlNow (f).
    fn tank(with_enforceable: bool) -> Project {
        use EventKind::*;
        let mut trans =
            vec![t(0, 0, 1), t(0, 1, 0), t(1, 1, 0), t(1, 0, 1), t(1, 2, 2), t(2, 3, 2), t(2, 1, 0), t(2, 0, 2)];
        let mut alphabet = vec![EventId::new(0), EventId::new(1), EventId::new(2), EventId::new(3)];
        if with_enforceable {
            trans.push(t(2, 4, 0));
            alphabet.push(EventId::new(4));
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
                prohib: vec![Prohibition { state: 0, event: EventId::new(3), cond: Cond::True, origin: NO_ORIGIN }],
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
            assert!(s.run(&[EventId::new(0)]).is_none(), "openInlet must be disabled initially");
            assert!(s.enforced_events().is_empty());
        }
    }

    #[test]
    fn tank_with_preemption_allows_open_and_enforces_closing() {
        let p = tank(true);
        for method in [Method::Incremental, Method::Monolithic] {
            let s = synthesize(&p, 0, &Config { method, ..Config::default() }).unwrap();
            let after = s.run(&[EventId::new(0), EventId::new(2)]).expect("openInlet, levelAlarm allowed");
            assert_eq!(s.states[after as usize].enforced, Some(EventId::new(4)));
            // closeInlet is not preempted: the controller may still close the inlet itself.
            assert!(s.run(&[EventId::new(0), EventId::new(2), EventId::new(1)]).is_some());
            assert_eq!(s.enforced_events(), vec![EventId::new(4)]);
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
            prohib: vec![Prohibition { state: 1, event: EventId::new(1), cond: Cond::True, origin: NO_ORIGIN }],
        };
        let t2 = Spec {
            name: "H2".into(),
            states: vec!["u".into(), "v".into()],
            init: 0,
            trans: vec![t(0, 2, 1)],
            prohib: vec![Prohibition { state: 1, event: EventId::new(0), cond: Cond::True, origin: NO_ORIGIN }],
        };
        let product = |max_states| spec_product("H", &t1, &t2, &mut Budget::new(max_states, &mut |_| true));
        let h = product(DEFAULT_MAX_STATES).unwrap();
        // The budget admits a product of exactly its size and no more.
        assert!(product(4).is_ok());
        assert!(matches!(product(3), Err(SynthError::BudgetExceeded { max_states: 3 })));
        // From (s,u): a -> (t,u), c -> (s,v); (s,v) forbids a; (t,u) forbids b, c -> (t,v).
        assert_eq!(h.states.len(), 4);
        let p = h.prohib.iter().map(|p| (h.states[p.state as usize].as_str(), p.event.raw())).collect::<Vec<_>>();
        assert!(
            p.contains(&("s|v", 0)) && p.contains(&("t|u", 1)) && p.contains(&("t|v", 1)) && p.contains(&("t|v", 0))
        );
        assert!(
            !h.trans.iter().any(|x| h.states[x.src as usize] == "s|v" && x.event == EventId::new(0)),
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
                    alphabet: vec![EventId::new(0)],
                    states: vec!["x".into()],
                    init: 0,
                    trans: vec![Transition { src: 0, event: EventId::new(0), cond, dst: 0, origin: NO_ORIGIN }],
                },
                Plant {
                    name: "B".into(),
                    alphabet: vec![EventId::new(1)],
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
        let a_moves: Vec<_> = g.trans.iter().filter(|t| t.event == EventId::new(0)).collect();
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
