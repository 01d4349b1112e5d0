//! Compositional synthesis (paper, section 3, "Synthesized Code"): the guarantees are split
//! into groups that share no output, each group is solved alone over its own signals, and
//! the controllers run side by side — one state machine per group in one function block, as
//! in the paper's appendix A.
//!
//! Groups: two guarantees are in one group when they write a common output (transitively);
//! an assumption that mentions outputs joins their groups and belongs to that group only; an
//! assumption on inputs alone goes to every group. A timer's start and expiry are one group.
//! Each group's controller then realises (its assumptions → its guarantees) on every play, and
//! its assumptions are among the specification's, so together they realise the whole
//! specification. The converse does not hold (an assumption can tie groups through inputs), so
//! a group that is not realizable alone proves nothing: the run falls back to the monolithic
//! game, and the split never changes a verdict.

use super::machine::{Cube, Machine, Row, StateId};
use super::spec::{Clause, Ltl, Predicate, Signal, SignalId, SignalKind, Spec, Timer};
use super::{refine, Config, Progress, Refinement, Stats, Stop, Synthesis, Verdict};
use crate::search::OnProgress;
use serde::Serialize;
use std::collections::{BTreeSet, HashMap};

/// One group of a compositional run, as reported.
#[derive(Clone, Debug, Serialize)]
pub struct Group {
    /// Indices into [`Spec::guarantees`].
    pub guarantees: Vec<usize>,
    /// The outputs it writes (global signal ids).
    pub outputs: Vec<SignalId>,
    /// The bound at which it was decided.
    pub k: u32,
    /// Its controller over the specification's signals; `None` in the report of a group that
    /// was not realizable alone.
    #[serde(skip)]
    pub controller: Option<Machine>,
    pub verdict: Verdict,
}

/// Union-find over signal indices.
struct Sets(Vec<usize>);

impl Sets {
    fn find(&mut self, mut x: usize) -> usize {
        while self.0[x] != x {
            self.0[x] = self.0[self.0[x]];
            x = self.0[x];
        }
        x
    }
    fn union(&mut self, a: usize, b: usize) {
        let (a, b) = (self.find(a), self.find(b));
        self.0[a] = b;
    }
}

/// The groups of `spec`'s guarantees (indices), by their outputs; one group when nothing
/// splits. A guarantee on inputs alone joins the first group.
pub(super) fn split(spec: &Spec) -> Vec<Vec<usize>> {
    let n = spec.signals.len();
    let is_output = |s: SignalId| spec.signal(s).kind == SignalKind::Output;
    let mut sets = Sets((0..n).collect());
    let link = |ids: &[SignalId], sets: &mut Sets| {
        for w in ids.windows(2) {
            sets.union(w[0].index(), w[1].index());
        }
    };
    for t in &spec.timers {
        sets.union(t.start.index(), t.expire.index());
    }
    for c in &spec.guarantees {
        let outs: Vec<SignalId> = c.formula.signals().into_iter().filter(|&s| is_output(s)).collect();
        link(&outs, &mut sets);
    }
    for c in &spec.assumptions {
        let all: Vec<SignalId> = c.formula.signals().into_iter().collect();
        if all.iter().any(|&s| is_output(s)) {
            link(&all, &mut sets);
        }
    }
    let mut by_root: Vec<(usize, Vec<usize>)> = Vec::new();
    let mut loose = Vec::new();
    for (i, c) in spec.guarantees.iter().enumerate() {
        match c.formula.signals().into_iter().find(|&s| is_output(s)) {
            Some(out) => {
                let root = sets.find(out.index());
                match by_root.iter_mut().find(|(r, _)| *r == root) {
                    Some((_, members)) => members.push(i),
                    None => by_root.push((root, vec![i])),
                }
            }
            None => loose.push(i),
        }
    }
    let mut groups: Vec<Vec<usize>> = by_root.into_iter().map(|(_, g)| g).collect();
    match groups.first_mut() {
        Some(first) => {
            first.extend(loose);
            crate::sort::sort(first);
        }
        None => groups.push(loose),
    }
    groups
}

/// The part of `spec` a group of guarantees needs: its guarantees, the assumptions on inputs
/// alone and those on its outputs, over the signals these mention (renumbered); with the map
/// from its signal ids to `spec`'s.
fn part(spec: &Spec, guarantees: &[usize]) -> (Spec, Vec<SignalId>) {
    let is_output = |s: SignalId| spec.signal(s).kind == SignalKind::Output;
    let mut outputs = BTreeSet::new();
    for &g in guarantees {
        outputs.extend(spec.guarantees[g].formula.signals().into_iter().filter(|&s| is_output(s)));
    }
    // Outputs tied to these by assumptions come along (split made them one group), to a fixpoint:
    // an assumption may name an output no guarantee writes, such as an unused timer's start.
    loop {
        let before = outputs.len();
        for c in &spec.assumptions {
            let m = c.formula.signals();
            if m.iter().any(|s| outputs.contains(s)) {
                outputs.extend(m.into_iter().filter(|&s| is_output(s)));
            }
        }
        if outputs.len() == before {
            break;
        }
    }
    let assumptions: Vec<&Clause> = spec
        .assumptions
        .iter()
        .filter(|c| {
            let m = c.formula.signals();
            m.iter().all(|&s| !is_output(s)) || m.iter().any(|s| outputs.contains(s))
        })
        .collect();
    let mut keep: BTreeSet<SignalId> = outputs.clone();
    for c in &assumptions {
        keep.extend(c.formula.signals());
    }
    for &g in guarantees {
        keep.extend(spec.guarantees[g].formula.signals());
    }
    // An output of another group never comes along: an input-only assumption may mention a
    // timer's expiry, and then this group sees it as a free input (no timer of its own).
    keep.retain(|&s| !is_output(s) || outputs.contains(&s));
    let global: Vec<SignalId> = keep.into_iter().collect();
    let local: HashMap<SignalId, SignalId> = global.iter().enumerate().map(|(i, &g)| (g, SignalId(i as u32))).collect();
    let map = |f: &Ltl| rename(f, &local);
    let sub = Spec {
        signals: global.iter().map(|&g| spec.signal(g).clone()).collect::<Vec<Signal>>(),
        assumptions: assumptions.iter().map(|c| Clause { formula: map(&c.formula), span: c.span }).collect(),
        guarantees: guarantees
            .iter()
            .map(|&g| Clause { formula: map(&spec.guarantees[g].formula), span: spec.guarantees[g].span })
            .collect(),
        semantics: spec.semantics,
        timers: spec
            .timers
            .iter()
            .filter(|t| local.contains_key(&t.start) && local.contains_key(&t.expire))
            .map(|t| Timer { start: local[&t.start], expire: local[&t.expire], ..t.clone() })
            .collect(),
        numeric: spec.numeric.clone(),
        predicates: spec
            .predicates
            .iter()
            .filter(|p| local.contains_key(&p.signal))
            .map(|p| Predicate { signal: local[&p.signal], ..p.clone() })
            .collect(),
        title: spec.title.clone(),
    };
    (sub, global)
}

fn rename(f: &Ltl, map: &HashMap<SignalId, SignalId>) -> Ltl {
    let r = |x: &Ltl| rename(x, map);
    let b = |x: &Ltl| Box::new(rename(x, map));
    match f {
        Ltl::True => Ltl::True,
        Ltl::False => Ltl::False,
        Ltl::Var(s) => Ltl::Var(map[s]),
        Ltl::Not(a) => Ltl::Not(b(a)),
        Ltl::Next(a) => Ltl::Next(b(a)),
        Ltl::Globally(a) => Ltl::Globally(b(a)),
        Ltl::Finally(a) => Ltl::Finally(b(a)),
        Ltl::And(xs) => Ltl::And(xs.iter().map(r).collect()),
        Ltl::Or(xs) => Ltl::Or(xs.iter().map(r).collect()),
        Ltl::Implies(x, y) => Ltl::Implies(b(x), b(y)),
        Ltl::Iff(x, y) => Ltl::Iff(b(x), b(y)),
        Ltl::Until(x, y) => Ltl::Until(b(x), b(y)),
        Ltl::Release(x, y) => Ltl::Release(b(x), b(y)),
        Ltl::WeakUntil(x, y) => Ltl::WeakUntil(b(x), b(y)),
    }
}

/// A machine of a part, its signals renamed to the whole specification's.
fn globalise(m: &Machine, global: &[SignalId]) -> Machine {
    let g = |ids: &[SignalId]| ids.iter().map(|s| global[s.index()]).collect();
    Machine { reads: g(&m.reads), writes: g(&m.writes), ..m.clone() }
}

/// The machines run side by side as one: states are tuples of the parts' states (those
/// reachable), reads and writes the unions (sorted by signal), a row per combination of the
/// parts' rows whose cubes agree.
pub fn product(machines: &[Machine]) -> Machine {
    let union = |f: fn(&Machine) -> &Vec<SignalId>| -> Vec<SignalId> {
        let mut ids: Vec<SignalId> = machines.iter().flat_map(|m| f(m).iter().copied()).collect();
        crate::sort::sort(&mut ids);
        ids.dedup();
        ids
    };
    let (reads, writes) = (union(|m| &m.reads), union(|m| &m.writes));
    let position = |ids: &[SignalId], s: SignalId| ids.iter().position(|&x| x == s).expect("in the union");
    // Each part's bit i moved to the union's position of its signal.
    let spread = |v: u64, own: &[SignalId], all: &[SignalId]| -> u64 {
        own.iter().enumerate().fold(0, |acc, (i, &s)| acc | (v >> i & 1) << position(all, s))
    };
    let init: Vec<StateId> = machines.iter().map(|m| m.init).collect();
    let mut index: HashMap<Vec<StateId>, StateId> = HashMap::from([(init.clone(), StateId(0))]);
    let mut tuples = vec![init];
    let mut states = Vec::new();
    let mut next_tuple = 0;
    while next_tuple < tuples.len() {
        let tuple = tuples[next_tuple].clone();
        next_tuple += 1;
        // Rows: the combinations of one row of each part whose read cubes are compatible.
        let mut combos: Vec<(Cube, u64, Vec<StateId>)> = vec![(Cube::ANY, 0, Vec::new())];
        for (m, &s) in machines.iter().zip(&tuple) {
            let mut grown = Vec::new();
            for (cube, write, nexts) in &combos {
                for row in &m.states[s.index()] {
                    let care = spread(row.read.care, &m.reads, &reads);
                    let value = spread(row.read.value, &m.reads, &reads);
                    let shared = care & cube.care;
                    if value & shared != cube.value & shared {
                        continue;
                    }
                    let cube = Cube { care: cube.care | care, value: cube.value | value };
                    let write = write | spread(row.write, &m.writes, &writes);
                    let mut nexts = nexts.clone();
                    nexts.push(row.next);
                    grown.push((cube, write, nexts));
                }
            }
            combos = grown;
        }
        let rows = combos
            .into_iter()
            .map(|(read, write, nexts)| {
                let fresh = StateId(index.len() as u32);
                let next = *index.entry(nexts.clone()).or_insert_with(|| {
                    tuples.push(nexts);
                    fresh
                });
                Row { read, write, next }
            })
            .collect();
        states.push(rows);
    }
    Machine { reads, writes, moves_first: machines.iter().all(|m| m.moves_first), init: StateId(0), states }
}

/// Most product states built for the report's combined controller.
const MAX_PRODUCT_STATES: usize = 100_000;

/// Solves each group alone; `Err(work spent)` when a group is not realizable alone (the
/// caller then solves the whole specification), when there is one group, or when the product
/// of the controllers would be too large to report.
pub(super) fn synthesize(
    spec: &Spec,
    groups: &[Vec<usize>],
    cfg: &Config,
    progress: &mut OnProgress<'_, Progress>,
) -> Result<Result<Synthesis, u64>, Stop> {
    if groups.len() < 2 {
        return Ok(Err(0));
    }
    let mut reported = Vec::new();
    let mut stats = Stats::default();
    let mut refinement = Refinement::default();
    let mut k = 0;
    for guarantees in groups {
        let (sub, global) = part(spec, guarantees);
        let left = Config { max_work: cfg.max_work.saturating_sub(stats.work), ..cfg.clone() };
        let outcome = refine::synthesize(&sub, &left, progress)?;
        stats.automaton_states += outcome.stats.automaton_states;
        stats.dual_automaton_states += outcome.stats.dual_automaton_states;
        stats.positions += outcome.stats.positions;
        stats.strategy_states_raw += outcome.stats.strategy_states_raw;
        stats.work += outcome.stats.work;
        let Some(controller) = outcome.controller.as_ref() else { return Ok(Err(stats.work)) };
        let to_global: HashMap<SignalId, SignalId> =
            global.iter().enumerate().map(|(i, &g)| (SignalId(i as u32), g)).collect();
        for learned in &outcome.refinement.learned {
            let ltl = rename(&learned.ltl, &to_global);
            if refinement.learned.iter().all(|l| l.ltl != ltl) {
                refinement.learned.push(refine::Learned { ltl, ..learned.clone() });
            }
        }
        refinement.rounds += outcome.refinement.rounds;
        k = k.max(outcome.k);
        let outputs = controller.writes.iter().map(|s| global[s.index()]).collect();
        reported.push(Group {
            guarantees: guarantees.clone(),
            outputs,
            k: outcome.k,
            controller: Some(globalise(controller, &global)),
            verdict: Verdict::Realizable,
        });
    }
    let machines: Vec<Machine> = reported.iter().filter_map(|g| g.controller.clone()).collect();
    let bound: usize = machines.iter().map(|m| m.states.len()).product();
    if bound > MAX_PRODUCT_STATES {
        return Ok(Err(stats.work));
    }
    Ok(Ok(Synthesis {
        verdict: Verdict::Realizable,
        k,
        controller: Some(product(&machines)),
        counter_strategy: None,
        circuit: None,
        stats,
        limit: None,
        refinement,
        groups: reported,
        split: groups.len(),
    }))
}
