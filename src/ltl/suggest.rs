//! Assumption suggestions for unrealizable specifications (Cheng et al. 2014, section 4).
//!
//! An unrealizable specification often becomes realizable once the environment is restricted a
//! little. From the environment's counter-strategy, [`suggest`]
//! 1. takes a **longest play** it forces before a state repeats: the counter-strategy is
//!    unfolded from its initial state over every answer of the controller, and the longest
//!    simple path that closes into a lasso is kept (a bounded depth-first search) — the scenario
//!    where the controller resists longest;
//! 2. instantiates **templates** ([`Template`]) whose meta-variables range over the inputs the
//!    specification mentions (and their negations; one template also over outputs), and keeps a
//!    candidate only if it could defeat the counter-strategy: the longest play violates it (the
//!    paper's generalisation), or, tried after those, some other play of the counter-strategy
//!    does (a product of the counter-strategy with the Büchi automaton of the candidate's
//!    negation). A candidate every play satisfies cannot help: the counter-strategy still wins.
//!    A candidate unsatisfiable together with the existing assumptions is dropped (the
//!    environment could never meet it, and the controller would win vacuously);
//! 3. **re-synthesises** with each candidate added as an assumption, each attempt on a share of
//!    the run's work budget, and reports those that make the specification realizable, ranked.
//!    If none does, the best-ranked candidate that changed the counter-strategy is kept and the
//!    search goes on from the new counter-strategy, up to [`SuggestConfig::max_assumptions`]
//!    assumptions in all.
//!
//! Ranking: fewer added assumptions first; then weaker templates ([`Template::ALL`] is in order,
//! weakest first); then the smaller controller (states, then rows); then the smaller bound k.

use super::machine::{Machine, StateId};
use super::spec::{Clause, Ltl, Semantics, SignalId, SignalKind, Spec};
use super::translate::translate;
use super::{synthesize, Config, Progress, Stop, Synthesis, Verdict};
use crate::diag::Span;
use crate::search::OnProgress;
use petgraph::graph::{DiGraph, NodeIndex};
use serde_json::{json, Value};
use std::collections::{HashMap, HashSet};

/// Budgets of [`suggest`].
#[derive(Clone, Debug)]
pub struct SuggestConfig {
    /// Assumptions added at most (one set); past it the search stops and says so.
    pub max_assumptions: usize,
    /// Re-syntheses tried at most, over all rounds.
    pub max_candidates_tried: usize,
    /// Each re-synthesis may spend `Config::max_work / attempt_share` units of work.
    pub attempt_share: u64,
    /// Units of work of all re-syntheses together; `None`: twice `Config::max_work`.
    pub max_work: Option<u64>,
    /// Steps of the depth-first search for the longest play.
    pub max_path_steps: usize,
}

impl Default for SuggestConfig {
    fn default() -> SuggestConfig {
        SuggestConfig {
            max_assumptions: 3,
            max_candidates_tried: 400,
            attempt_share: 10,
            max_work: None,
            max_path_steps: 100_000,
        }
    }
}

/// The assumption templates, weakest (least restrictive for the environment) first. `?a`, `?b`
/// are literals of inputs (an input or its negation), `?o` an output.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Template {
    /// `G F ?a`: ?a holds infinitely often (fairness; Lily's `G F !req`).
    Fairness,
    /// `G (?a -> F ?b)`: every ?a is followed by a ?b, now or later (response).
    Response,
    /// `F G ?a`: from some step on, ?a holds for ever (stabilisation).
    Stabilisation,
    /// `G (?a -> X (!?a U ?b))`: after an ?a, no further ?a until a ?b, which comes.
    Separation,
    /// `G (?o -> X !?a)`: once the controller answers ?o, the environment withdraws ?a
    /// (Lily-style: a request is dropped after its grant).
    Withdrawal,
    /// `G ((?a && !?o) -> X ?a)`: ?a persists until the controller answers ?o (Lily-style
    /// `G (req && !grant -> X req)`).
    Persistence,
    /// `G (?a -> X !?a)`: no two successive ?a (the paper's example: no successive arrivals).
    NoRepetition,
    /// `G (?a -> X ?b)`: every ?a is followed by a ?b at the next step.
    NextStep,
    /// `G !(?a && ?b)`: never ?a and ?b in the same step (mutual exclusion).
    Exclusion,
    /// `G ?a`: ?a always (an input fixed for ever; the strongest).
    Invariant,
}

impl Template {
    /// Every template, weakest first: the ranking's order.
    pub const ALL: [Template; 10] = [
        Template::Fairness,
        Template::Response,
        Template::Stabilisation,
        Template::Separation,
        Template::Withdrawal,
        Template::Persistence,
        Template::NoRepetition,
        Template::NextStep,
        Template::Exclusion,
        Template::Invariant,
    ];

    /// The template as written with its meta-variables.
    pub fn pattern(self) -> &'static str {
        match self {
            Template::Fairness => "G F ?a",
            Template::Response => "G (?a -> F ?b)",
            Template::Stabilisation => "F G ?a",
            Template::Separation => "G (?a -> X (!?a U ?b))",
            Template::Withdrawal => "G (?o -> X !?a)",
            Template::Persistence => "G ((?a && !?o) -> X ?a)",
            Template::NoRepetition => "G (?a -> X !?a)",
            Template::NextStep => "G (?a -> X ?b)",
            Template::Exclusion => "G !(?a && ?b)",
            Template::Invariant => "G ?a",
        }
    }

    /// Position in [`Template::ALL`]: smaller is weaker.
    pub fn rank(self) -> usize {
        Template::ALL.iter().position(|&t| t == self).expect("listed")
    }
}

/// A play of the counter-strategy as a lasso: `letters[i]` is the valuation of all signals at
/// step i (bit `s` signal `s`; inputs as the counter-strategy writes them, outputs as the
/// controller answered on this path, unconstrained outputs false); after the last step the play
/// goes on at step `loop_start`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Play {
    pub states: Vec<StateId>,
    pub letters: Vec<u64>,
    pub loop_start: usize,
}

impl Play {
    /// `[0] req1 & req2 → [1] !req1 & req2 → back to [1]`: the inputs at each step.
    pub fn describe(&self, spec: &Spec) -> String {
        let inputs = spec.inputs();
        let mut parts: Vec<String> = self
            .letters
            .iter()
            .enumerate()
            .map(|(i, &letter)| {
                let lits: Vec<String> = inputs
                    .iter()
                    .map(|&s| format!("{}{}", if letter >> s.0 & 1 == 1 { "" } else { "!" }, spec.name(s)))
                    .collect();
                format!("[{i}] {}", if lits.is_empty() { "-".to_string() } else { lits.join(" & ") })
            })
            .collect();
        parts.push(format!("back to [{}]", self.loop_start));
        parts.join(" → ")
    }

    /// Whether the lasso word satisfies `f` (the fixpoint semantics on an ultimately periodic
    /// word).
    pub fn satisfies(&self, f: &Ltl) -> bool {
        self.letters.is_empty() || self.eval(f)[0]
    }

    fn eval(&self, f: &Ltl) -> Vec<bool> {
        let n = self.letters.len();
        let succ = |i: usize| if i + 1 < n { i + 1 } else { self.loop_start };
        // Least (`least`) or greatest fixpoint of v = now || (keep && v[succ]).
        let fix = |now: &[bool], keep: &[bool], least: bool| {
            let mut v = vec![!least; n];
            for _ in 0..=n {
                let next: Vec<bool> = (0..n).map(|i| now[i] || (keep[i] && v[succ(i)])).collect();
                if next == v {
                    break;
                }
                v = next;
            }
            v
        };
        match f {
            Ltl::True => vec![true; n],
            Ltl::False => vec![false; n],
            Ltl::Var(s) => self.letters.iter().map(|l| l >> s.0 & 1 == 1).collect(),
            Ltl::Not(a) => self.eval(a).into_iter().map(|b| !b).collect(),
            Ltl::And(xs) => {
                xs.iter().fold(vec![true; n], |acc, x| acc.iter().zip(self.eval(x)).map(|(a, b)| *a && b).collect())
            }
            Ltl::Or(xs) => {
                xs.iter().fold(vec![false; n], |acc, x| acc.iter().zip(self.eval(x)).map(|(a, b)| *a || b).collect())
            }
            Ltl::Implies(a, b) => self.eval(a).into_iter().zip(self.eval(b)).map(|(a, b)| !a || b).collect(),
            Ltl::Iff(a, b) => self.eval(a).into_iter().zip(self.eval(b)).map(|(a, b)| a == b).collect(),
            Ltl::Next(a) => {
                let v = self.eval(a);
                (0..n).map(|i| v[succ(i)]).collect()
            }
            Ltl::Finally(a) => fix(&self.eval(a), &vec![true; n], true),
            Ltl::Globally(a) => {
                // G a = !F !a
                let na: Vec<bool> = self.eval(a).into_iter().map(|b| !b).collect();
                fix(&na, &vec![true; n], true).into_iter().map(|b| !b).collect()
            }
            Ltl::Until(a, b) => fix(&self.eval(b), &self.eval(a), true),
            Ltl::WeakUntil(a, b) => fix(&self.eval(b), &self.eval(a), false),
            Ltl::Release(a, b) => {
                // a R b = !(!a U !b)
                let na: Vec<bool> = self.eval(a).into_iter().map(|x| !x).collect();
                let nb: Vec<bool> = self.eval(b).into_iter().map(|x| !x).collect();
                fix(&nb, &na, true).into_iter().map(|x| !x).collect()
            }
        }
    }
}

/// One set of added assumptions that makes the specification realizable.
#[derive(Clone, Debug)]
pub struct Suggestion {
    /// The added assumptions, in the order they were found.
    pub added: Vec<Ltl>,
    /// The template each came from.
    pub templates: Vec<Template>,
    /// The specification with them added (`ASSUME` clauses at the end of the assumptions).
    pub spec: Spec,
    /// Its realizable outcome: the controller they allow.
    pub outcome: Synthesis,
}

impl Suggestion {
    /// The controller of the extended specification.
    pub fn controller(&self) -> &Machine {
        self.outcome.controller.as_ref().expect("a suggestion is realizable")
    }

    /// The added assumptions as infix text.
    pub fn texts(&self) -> Vec<String> {
        self.added.iter().map(|f| f.to_infix(&|s| self.spec.name(s).to_string())).collect()
    }

    fn key(&self) -> (usize, Vec<usize>, usize, usize, u32) {
        let mut ranks: Vec<usize> = self.templates.iter().map(|t| t.rank()).collect();
        crate::sort::sort_by(&mut ranks, |a, b| b.cmp(a)); // the strongest template counts first
        let m = self.controller();
        (self.added.len(), ranks, m.states.len(), m.rows(), self.outcome.k)
    }
}

/// The result of [`suggest`].
#[derive(Clone, Debug, Default)]
pub struct Suggestions {
    /// The suggestions found, best first ([`suggest`]'s ranking); all of one size.
    pub found: Vec<Suggestion>,
    /// The longest play of the original counter-strategy.
    pub play: Option<Play>,
    /// Candidates that passed the filters in the first round.
    pub candidates: usize,
    /// Re-syntheses run.
    pub tried: usize,
    /// Candidates that made the specification realizable only vacuously: the environment
    /// cannot meet the extended assumptions against every controller (not reported).
    pub vacuous: usize,
    /// When nothing was found: why the search stopped.
    pub limit: Option<String>,
}

impl Suggestions {
    /// `[{"assumptions", "templates", "template", "ltl", "k", "states", "rows", "mealy"}, …]`.
    pub fn to_json(&self) -> Value {
        Value::Array(
            self.found
                .iter()
                .map(|s| {
                    let patterns: Vec<&str> = s.templates.iter().map(|t| t.pattern()).collect();
                    let m = s.controller();
                    json!({
                        "assumptions": s.texts(),
                        "templates": patterns,
                        "template": patterns.join(" + "),
                        "ltl": s.spec.formula_text(),
                        "k": s.outcome.k,
                        "states": m.states.len(),
                        "rows": m.rows(),
                        "mealy": m.to_json(&s.spec),
                    })
                })
                .collect(),
        )
    }
}

/// A literal: a signal, positive or negated.
type Lit = (SignalId, bool);

fn lit(l: Lit) -> Ltl {
    if l.1 {
        Ltl::Var(l.0)
    } else {
        Ltl::not(Ltl::Var(l.0))
    }
}

fn neg(l: Lit) -> Lit {
    (l.0, !l.1)
}

/// Every instance of every template over the literals of `inputs` and the `outputs`.
fn instances(inputs: &[SignalId], outputs: &[SignalId]) -> Vec<(Ltl, Template)> {
    let lits: Vec<Lit> = inputs.iter().flat_map(|&s| [(s, true), (s, false)]).collect();
    let mut out = Vec::new();
    for t in Template::ALL {
        match t {
            Template::Fairness | Template::Stabilisation | Template::NoRepetition | Template::Invariant => {
                for &a in &lits {
                    let f = match t {
                        Template::Fairness => Ltl::globally(Ltl::finally(lit(a))),
                        Template::Stabilisation => Ltl::finally(Ltl::globally(lit(a))),
                        Template::NoRepetition => Ltl::globally(Ltl::implies(lit(a), Ltl::next(lit(neg(a))))),
                        _ => Ltl::globally(lit(a)),
                    };
                    out.push((f, t));
                }
            }
            Template::Response | Template::Separation | Template::NextStep => {
                for &a in &lits {
                    for &b in &lits {
                        let same = a.0 == b.0;
                        // G (a -> F !a) says a does not stay for ever; the other templates need
                        // two signals (with one, they repeat NoRepetition or say nothing).
                        if same && !(t == Template::Response && b == neg(a)) {
                            continue;
                        }
                        let f = match t {
                            Template::Response => Ltl::implies(lit(a), Ltl::finally(lit(b))),
                            Template::Separation => Ltl::implies(lit(a), Ltl::next(Ltl::until(lit(neg(a)), lit(b)))),
                            _ => Ltl::implies(lit(a), Ltl::next(lit(b))),
                        };
                        out.push((Ltl::globally(f), t));
                    }
                }
            }
            Template::Exclusion => {
                for (i, &a) in lits.iter().enumerate() {
                    for &b in &lits[i + 1..] {
                        if a.0 != b.0 {
                            out.push((Ltl::globally(Ltl::not(Ltl::And(vec![lit(a), lit(b)]))), t));
                        }
                    }
                }
            }
            Template::Withdrawal | Template::Persistence => {
                for &o in outputs {
                    for &a in &lits {
                        let f = if t == Template::Withdrawal {
                            Ltl::implies(Ltl::Var(o), Ltl::next(lit(neg(a))))
                        } else {
                            Ltl::implies(Ltl::And(vec![lit(a), Ltl::not(Ltl::Var(o))]), Ltl::next(lit(a)))
                        };
                        out.push((Ltl::globally(f), t));
                    }
                }
            }
        }
    }
    out
}

/// The valuation of all signals at one step of the counter-strategy: the inputs it writes,
/// and the outputs' cube of the row taken as (bits that must be 1, bits that must be 0).
fn step_letter(m: &Machine, state: StateId, row: usize) -> (u64, u64, u64) {
    let r = &m.states[state.index()][row];
    let written = if m.moves_first { m.first_write(state) } else { r.write };
    let mut inputs = 0u64;
    for (j, &s) in m.writes.iter().enumerate() {
        if written >> j & 1 == 1 {
            inputs |= 1 << s.0;
        }
    }
    let (mut one, mut zero) = (0u64, 0u64);
    for (j, &s) in m.reads.iter().enumerate() {
        if r.read.care >> j & 1 == 1 {
            if r.read.value >> j & 1 == 1 {
                one |= 1 << s.0;
            } else {
                zero |= 1 << s.0;
            }
        }
    }
    (inputs, one, zero)
}

/// A longest simple path of the counter-strategy from its initial state over the controller's
/// answers, closed into a lasso; at most `max_steps` steps of search (then the longest so far).
pub fn longest_play(m: &Machine, max_steps: usize) -> Play {
    let mut on_path = vec![false; m.states.len()];
    let mut path = vec![m.init];
    let mut next_row = vec![0usize];
    on_path[m.init.index()] = true;
    let mut best: Option<(Vec<StateId>, Vec<usize>, usize)> = None;
    let mut steps = 0usize;
    while let Some(&s) = path.last() {
        steps += 1;
        if steps > max_steps && best.is_some() {
            break;
        }
        let i = *next_row.last().expect("one per state on the path");
        let rows = &m.states[s.index()];
        if i < rows.len() {
            *next_row.last_mut().expect("nonempty") += 1;
            let t = rows[i].next;
            if !on_path[t.index()] {
                on_path[t.index()] = true;
                path.push(t);
                next_row.push(0);
            } else if best.as_ref().is_none_or(|b| path.len() > b.0.len()) {
                let mut taken: Vec<usize> = next_row[..next_row.len() - 1].iter().map(|r| r - 1).collect();
                taken.push(i);
                let loop_start = path.iter().position(|&p| p == t).expect("on the path");
                best = Some((path.clone(), taken, loop_start));
            }
        } else {
            on_path[s.index()] = false;
            path.pop();
            next_row.pop();
        }
    }
    let (states, rows, loop_start) = best.expect("a complete machine has a cycle");
    let letters = states.iter().zip(&rows).map(|(&s, &r)| {
        let (inputs, one, _) = step_letter(m, s, r);
        inputs | one
    });
    Play { letters: letters.collect(), states, loop_start }
}

/// Whether some play of the counter-strategy `m` (against any controller) violates `f`: the
/// product of `m` with the Büchi automaton of `!f` has a reachable accepting cycle. A
/// translation past its budget counts as "yes" (the candidate is kept).
fn some_play_violates(spec: &Spec, m: &Machine, f: &Ltl, cfg: &Config) -> bool {
    let name = |s: SignalId| spec.name(s).to_string();
    let Ok(aut) = translate(&Ltl::not(f.clone()), &name, cfg.max_automaton_states.min(2_000), 2_000_000) else {
        return true;
    };
    if aut.is_empty() {
        return false;
    }
    let mut graph: DiGraph<(), bool> = DiGraph::new();
    let mut index: HashMap<(StateId, u32), NodeIndex> = HashMap::new();
    let start = (m.init, aut.init);
    index.insert(start, graph.add_node(()));
    let mut todo = vec![start];
    while let Some((s, q)) = todo.pop() {
        let from = index[&(s, q)];
        for (r, row) in m.states[s.index()].iter().enumerate() {
            let (inputs, one, zero) = step_letter(m, s, r);
            let written: u64 = m.writes.iter().map(|w| 1u64 << w.0).sum();
            for e in &aut.states[q as usize].edges {
                let ok =
                    (e.pos & written) & !inputs == 0 && e.neg & inputs == 0 && e.pos & zero == 0 && e.neg & one == 0;
                if !ok {
                    continue;
                }
                let key = (row.next, e.to);
                let to = *index.entry(key).or_insert_with(|| {
                    todo.push(key);
                    graph.add_node(())
                });
                graph.add_edge(from, to, e.accepting);
            }
        }
    }
    for scc in petgraph::algo::tarjan_scc(&graph) {
        let members: HashSet<NodeIndex> = scc.iter().copied().collect();
        for &n in &scc {
            for e in graph.edges(n) {
                use petgraph::visit::EdgeRef;
                if *e.weight() && members.contains(&e.target()) {
                    return true;
                }
            }
        }
    }
    false
}

/// Whether `f` is satisfiable: its Büchi automaton accepts some word. A translation past its
/// budget counts as satisfiable.
fn satisfiable(spec: &Spec, f: &Ltl, cfg: &Config) -> bool {
    let name = |s: SignalId| spec.name(s).to_string();
    translate(f, &name, cfg.max_automaton_states, cfg.max_work / 20).map_or(true, |a| !a.is_empty())
}

/// The environment's side of `spec`'s assumptions: a specification whose controller is the
/// environment (inputs and outputs swapped), whose guarantees are the assumptions, with the
/// turn order swapped too (under Mealy semantics the environment moves first, so it is a Moore
/// machine here). Realizable exactly when the environment can meet the assumptions whatever
/// the controller does; otherwise a controller of `A -> G` may win by breaking `A`.
fn environment_side(spec: &Spec) -> Spec {
    let mut signals = spec.signals.clone();
    for s in &mut signals {
        s.kind = match s.kind {
            SignalKind::Input => SignalKind::Output,
            SignalKind::Output => SignalKind::Input,
        };
    }
    let semantics = match spec.semantics {
        Semantics::Mealy => Semantics::Moore,
        Semantics::Moore => Semantics::Mealy,
    };
    Spec { signals, assumptions: Vec::new(), guarantees: spec.assumptions.clone(), semantics, ..Spec::default() }
}

fn extended(spec: &Spec, added: &[Ltl]) -> Spec {
    let mut s = spec.clone();
    s.assumptions.extend(added.iter().map(|f| Clause { formula: f.clone(), span: Span::default() }));
    s
}

/// The candidates against the counter-strategy `m` of `spec`, filtered and in the order they
/// are tried: those the longest play violates first, each group by template, weakest first.
fn candidates(spec: &Spec, m: &Machine, play: &Play, cfg: &Config) -> Vec<(Ltl, Template)> {
    let used: HashSet<SignalId> =
        spec.assumptions.iter().chain(&spec.guarantees).flat_map(|c| c.formula.signals()).collect();
    // An input no formula mentions cannot matter: the environment can fix it, and nothing
    // the controller could learn from it would help.
    let inputs: Vec<SignalId> = spec.inputs().into_iter().filter(|s| used.contains(s)).collect();
    let outputs: Vec<SignalId> = spec.outputs().into_iter().filter(|s| used.contains(s)).collect();
    let existing: HashSet<&Ltl> = spec.assumptions.iter().map(|c| &c.formula).collect();
    let assumption = spec.assumption();
    let (mut first, mut second) = (Vec::new(), Vec::new());
    for (f, t) in instances(&inputs, &outputs) {
        if existing.contains(&f) {
            continue;
        }
        let on_longest = !play.satisfies(&f);
        if !on_longest && !some_play_violates(spec, m, &f, cfg) {
            continue;
        }
        if !satisfiable(spec, &Ltl::all(vec![assumption.clone(), f.clone()]), cfg) {
            continue;
        }
        if on_longest {
            first.push((f, t));
        } else {
            second.push((f, t));
        }
    }
    first.extend(second);
    first
}

/// Searches assumptions that make the unrealizable `spec` (with `outcome`, its verdict)
/// realizable: see the module documentation. For any other verdict, nothing is searched.
/// Stops only when `progress` cancels; budgets end the search with [`Suggestions::limit`].
pub fn suggest(
    spec: &Spec,
    outcome: &Synthesis,
    cfg: &Config,
    scfg: &SuggestConfig,
    progress: &mut OnProgress<'_, Progress>,
) -> Result<Suggestions, Stop> {
    let mut result = Suggestions::default();
    let Some(first_counter) = outcome.counter_strategy.clone() else {
        return Ok(result);
    };
    if outcome.verdict != Verdict::Unrealizable {
        return Ok(result);
    }
    let total = scfg.max_work.unwrap_or(cfg.max_work.saturating_mul(2));
    let share = (cfg.max_work / scfg.attempt_share.max(1)).max(1);
    let mut used = 0u64;
    // One re-synthesis: its outcome, or None when it ran out of its share.
    let attempt =
        |s: &Spec, used: &mut u64, progress: &mut OnProgress<'_, Progress>| -> Result<Option<Synthesis>, Stop> {
            let budget = share.min(total.saturating_sub(*used));
            let run = Config { max_work: budget, ..cfg.clone() };
            match synthesize(s, &run, progress) {
                Ok(o) => {
                    *used += o.stats.work;
                    Ok(Some(o))
                }
                Err(Stop::Cancelled) => Err(Stop::Cancelled),
                Err(Stop::Budget { .. }) => {
                    *used += budget;
                    Ok(None)
                }
            }
        };
    let mut chosen: Vec<(Ltl, Template)> = Vec::new();
    let mut counter = first_counter;
    'rounds: loop {
        let base = extended(spec, &chosen.iter().map(|c| c.0.clone()).collect::<Vec<_>>());
        let play = longest_play(&counter, scfg.max_path_steps);
        let cands = candidates(&base, &counter, &play, cfg);
        if result.play.is_none() {
            result.play = Some(play);
            result.candidates = cands.len();
        }
        let mut fallback: Option<(Ltl, Template, Machine)> = None;
        for (f, t) in cands {
            if result.tried >= scfg.max_candidates_tried {
                if result.found.is_empty() {
                    result.limit = Some(format!(
                        "no suggestion within {} re-syntheses (--suggest-max bounds the assumptions, not the attempts)",
                        scfg.max_candidates_tried
                    ));
                }
                break 'rounds;
            }
            if used >= total {
                if result.found.is_empty() {
                    result.limit = Some(format!("the suggestions' budget of {total} units of work ran out"));
                }
                break 'rounds;
            }
            result.tried += 1;
            let mut added: Vec<Ltl> = chosen.iter().map(|c| c.0.clone()).collect();
            added.push(f.clone());
            let ext = extended(spec, &added);
            let Some(o) = attempt(&ext, &mut used, progress)? else { continue };
            match o.verdict {
                // A verdict without its machine (a gr1 run past its table) suggests nothing.
                Verdict::Realizable if o.controller.is_some() => {
                    // Not vacuous: the environment can meet the extended assumptions.
                    let meets = attempt(&environment_side(&ext), &mut used, progress)?;
                    if meets.is_none_or(|m| m.verdict != Verdict::Realizable) {
                        result.vacuous += 1;
                        continue;
                    }
                    let mut templates: Vec<Template> = chosen.iter().map(|c| c.1).collect();
                    templates.push(t);
                    result.found.push(Suggestion { added, templates, spec: ext, outcome: o });
                }
                Verdict::Unrealizable if fallback.is_none() && o.counter_strategy.as_ref() != Some(&counter) => {
                    if let Some(other) = o.counter_strategy {
                        fallback = Some((f, t, other));
                    }
                }
                _ => {}
            }
        }
        if !result.found.is_empty() {
            break;
        }
        if chosen.len() + 1 >= scfg.max_assumptions {
            result.limit = Some(format!(
                "no set of at most {} assumption{} found ({} re-syntheses)",
                scfg.max_assumptions,
                if scfg.max_assumptions == 1 { "" } else { "s" },
                result.tried
            ));
            break;
        }
        match fallback {
            Some((f, t, m)) => {
                chosen.push((f, t));
                counter = m;
            }
            None => {
                result.limit = Some(format!(
                    "no candidate changes the counter-strategy's behaviour ({} re-syntheses, {} assumption{} added)",
                    result.tried,
                    chosen.len(),
                    if chosen.len() == 1 { "" } else { "s" }
                ));
                break;
            }
        }
    }
    // A set found in a later round may not need the assumptions kept in earlier ones.
    for s in &mut result.found {
        let mut i = 0;
        while s.added.len() > 1 && i + 1 < s.added.len() {
            let mut fewer = s.added.clone();
            fewer.remove(i);
            let ext = extended(spec, &fewer);
            match attempt(&ext, &mut used, progress)? {
                Some(o) if o.verdict == Verdict::Realizable => {
                    s.added = fewer;
                    s.templates.remove(i);
                    s.spec = ext;
                    s.outcome = o;
                }
                _ => i += 1,
            }
        }
    }
    crate::sort::sort_by_key(&mut result.found, |s| s.key());
    let mut seen = HashSet::new();
    result.found.retain(|s| seen.insert(s.added.clone()));
    Ok(result)
}
