//! The abstraction-refinement loop (paper, section 3 and figure 2): the Boolean abstraction
//! of timers (and of arithmetic predicates, see [`super::theory`]) over-approximates what the
//! environment can do. When the environment wins the abstract game, its counter-strategy is
//! checked against what a real timer (or the theory) allows; what it used but cannot happen is
//! excluded by a new assumption, and the game is played again. The loop ends with a controller,
//! with a counter-strategy that only does what is possible (a genuine one), or at a budget.
//!
//! The timer model. A start in a scan restarts the timer (the code gives `IN` a rising edge at
//! the end of that scan, `docs/ltl-plc.md`), and `expire` is the timer's `Q` read at the start
//! of a scan. So a real timer behaves as follows, whatever the scan time (assuming only that
//! the preset is longer than a scan):
//!
//! - *expires unless restarted* (always assumed): `G (s -> X F (e || s))`. The paper's
//!   antecedent `G (s -> X F e)` is stronger and unsound: a controller that starts the timer in
//!   every scan makes it false, and so wins any specification vacuously once a restart is
//!   known to delay the expiry;
//! - *no expiry before the first start*: `!e W (s && !e)`;
//! - *a start resets*: `G (s -> X !e)` (the scan after a start reads the timer running);
//! - *an expiry lasts until the next start*: `G ((e && !s) -> X e)`.
//!
//! The last three are learned: added when a counter-strategy breaks them. Together they are
//! satisfiable by the environment against every controller (an expiry two scans after a start
//! that was not repeated), so the refined assumptions never make a specification vacuous.

use super::game;
use super::machine::{Machine, StateId};
use super::spec::{Clause, Ltl, NumExpr, NumberKind, SignalId, Spec, Timer};
use super::theory::{Answer, Atom, Domain, NumVar, Poly, Rational, Theory, TheoryStats, DEFAULT_BUDGET};
use super::{Config, Progress, Stop, Synthesis, Verdict};
use crate::diag::Span;
use crate::search::OnProgress;
use serde::Serialize;
use std::collections::{BTreeSet, HashSet};

/// Rounds of the loop before it gives up (each adds at least one assumption).
const MAX_ROUNDS: u32 = 64;

/// Units of the run's work ([`Config::max_work`]) one unit of the theory checker costs: a box
/// split or an elimination takes about 10 µs, a game unit a few ns (measured on this project's
/// machine with a tangency the checker cannot settle, `tests/fixtures/fuzz/ltl/l2_…`).
const THEORY_UNIT_COST: u64 = 4_000;

/// An assumption the loop added, and why.
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
pub struct Learned {
    /// The assumption as infix text over the signal names.
    pub formula: String,
    /// What the counter-strategy did that cannot happen.
    pub reason: String,
    #[serde(skip)]
    pub ltl: Ltl,
    /// What it came from in the source (the timer's or the predicate's declaration).
    #[serde(skip)]
    pub span: Span,
}

/// What the refinement loop did in one run.
#[derive(Clone, Debug, Default, Serialize)]
pub struct Refinement {
    /// The assumptions added, in order.
    pub learned: Vec<Learned>,
    /// Games solved (1 when nothing was learned).
    pub rounds: u32,
    /// For a genuine counter-strategy over predicates: a valuation of the numeric inputs for
    /// each combination of predicate values it uses.
    pub witnesses: Vec<Witness>,
    /// Queries of the theory checker, and how many the memo answered.
    pub theory: Option<TheoryStats>,
}

/// Numeric inputs that make a combination of predicate values true.
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
pub struct Witness {
    /// The combination, as `p0 && !p1`.
    pub combination: String,
    /// Each numeric input's value (exact, `7/2` or `3`).
    pub values: Vec<(String, String)>,
}

/// The theory of a specification's predicates: one atom per predicate, one domain per
/// numeric input. `None` when there are no predicates; an atom that cannot be built (its
/// rational arithmetic overflows) is `None`, and combinations using it are never decided.
struct PredicateTheory {
    theory: Theory,
    /// The predicate of atom `i` (index into `Spec::predicates`), for atoms that exist.
    atoms: Vec<usize>,
}

fn poly(e: &NumExpr) -> Option<Poly> {
    Some(match e {
        NumExpr::Const(text) => Poly::constant(Rational::parse_decimal(text)?),
        NumExpr::Var(v) => Poly::var(NumVar(v.0)),
        NumExpr::Neg(a) => poly(a)?.neg()?,
        NumExpr::Add(a, b) => poly(a)?.add(&poly(b)?)?,
        NumExpr::Sub(a, b) => poly(a)?.sub(&poly(b)?)?,
        NumExpr::Mul(a, b) => poly(a)?.mul(&poly(b)?)?,
        NumExpr::Div(a, b) => {
            let divisor = poly(b)?.as_constant()?;
            poly(a)?.scale(Rational::ONE.checked_div(divisor)?)?
        }
        NumExpr::Pow(a, n) => poly(a)?.pow(*n)?,
    })
}

impl PredicateTheory {
    fn new(spec: &Spec) -> Option<PredicateTheory> {
        if spec.predicates.is_empty() {
            return None;
        }
        let mut atoms = Vec::new();
        let mut built = Vec::new();
        for (i, p) in spec.predicates.iter().enumerate() {
            if let Some(atom) = poly(&p.lhs).zip(poly(&p.rhs)).and_then(|(l, r)| Atom::new(l, p.relation, r)) {
                atoms.push(atom);
                built.push(i);
            }
        }
        let domains = spec
            .numeric
            .iter()
            .map(|n| Domain {
                // The front end checked that the bounds parse exactly.
                lo: Rational::parse_decimal(&n.lo).unwrap_or(Rational::ZERO),
                hi: Rational::parse_decimal(&n.hi).unwrap_or(Rational::ZERO),
                integer: n.kind == NumberKind::Int,
            })
            .collect();
        Some(PredicateTheory { theory: Theory::new(atoms, domains), atoms: built })
    }
}

/// What the theory says of the predicate combinations a counter-strategy uses.
#[derive(Default)]
struct TheoryVerdict {
    /// Unsatisfiable cores, as (predicate index, value) literals.
    cores: Vec<Vec<(usize, bool)>>,
    witnesses: Vec<Witness>,
    /// Combinations neither proved nor refuted.
    undecided: Vec<String>,
}

fn combination_text(spec: &Spec, literals: &[(usize, bool)]) -> String {
    let parts: Vec<String> = literals
        .iter()
        .map(|&(i, on)| format!("{}{}", if on { "" } else { "!" }, spec.name(spec.predicates[i].signal)))
        .collect();
    parts.join(" && ")
}

/// Decides the combinations `plays` uses, spending at most `left` units of the theory
/// checker in all (a combination left over is undecided).
fn check_combinations(spec: &Spec, pt: &mut PredicateTheory, plays: &Plays, left: &mut u64) -> TheoryVerdict {
    let mut combos: BTreeSet<Vec<(usize, bool)>> = BTreeSet::new();
    for &letter in &plays.letters {
        combos.insert(spec.predicates.iter().enumerate().map(|(i, p)| (i, letter >> p.signal.0 & 1 == 1)).collect());
    }
    let mut out = TheoryVerdict::default();
    for combo in combos {
        // The query in atom numbering; predicates without an atom make it undecidable.
        let query: Option<Vec<(usize, bool)>> =
            combo.iter().map(|&(i, on)| pt.atoms.iter().position(|&a| a == i).map(|a| (a, on))).collect();
        let Some(query) = query else {
            out.undecided.push(combination_text(spec, &combo));
            continue;
        };
        let before = pt.theory.stats().work;
        pt.theory.set_budget((*left).min(DEFAULT_BUDGET));
        let answer = if *left == 0 { Answer::Unknown } else { pt.theory.check(&query) };
        let answer = match answer {
            Answer::Unsat => {
                let core = pt.theory.minimal_unsat(&query);
                *left = left.saturating_sub(pt.theory.stats().work - before);
                (Answer::Unsat, core)
            }
            other => {
                *left = left.saturating_sub(pt.theory.stats().work - before);
                (other, Vec::new())
            }
        };
        match answer {
            // An empty core would exclude every letter: never learned (the bounds are checked
            // non-empty, so it cannot come from a sound checker).
            (Answer::Unsat, core) if core.is_empty() => out.undecided.push(combination_text(spec, &combo)),
            (Answer::Unsat, core) => {
                let core: Vec<(usize, bool)> = core.into_iter().map(|(a, on)| (pt.atoms[a], on)).collect();
                if !out.cores.contains(&core) {
                    out.cores.push(core);
                }
            }
            (Answer::Sat(values), _) => out.witnesses.push(Witness {
                combination: combination_text(spec, &combo),
                values: spec.numeric.iter().zip(values).map(|(n, v)| (n.name.clone(), v.to_string())).collect(),
            }),
            (Answer::Unknown, _) => out.undecided.push(combination_text(spec, &combo)),
        }
    }
    out
}

/// The timer facts that can be learned, in the order they are checked.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
enum TimerFact {
    NoExpiryBeforeStart,
    StartResets,
    ExpiryLasts,
}

impl TimerFact {
    const ALL: [TimerFact; 3] = [TimerFact::NoExpiryBeforeStart, TimerFact::StartResets, TimerFact::ExpiryLasts];

    fn formula(self, t: &Timer) -> Ltl {
        let (s, e) = (Ltl::Var(t.start), Ltl::Var(t.expire));
        match self {
            TimerFact::NoExpiryBeforeStart => Ltl::weak_until(Ltl::not(e.clone()), Ltl::And(vec![s, Ltl::not(e)])),
            TimerFact::StartResets => Ltl::globally(Ltl::implies(s, Ltl::next(Ltl::not(e)))),
            TimerFact::ExpiryLasts => Ltl::globally(Ltl::implies(Ltl::And(vec![e.clone(), Ltl::not(s)]), Ltl::next(e))),
        }
    }

    fn reason(self, t: &Timer) -> String {
        let n = &t.name;
        match self {
            TimerFact::NoExpiryBeforeStart => format!("the counter-strategy reported `{n}.expire` before any start"),
            TimerFact::StartResets => {
                format!("the counter-strategy reported `{n}.expire` in the scan right after a start of `{n}`")
            }
            TimerFact::ExpiryLasts => {
                format!("the counter-strategy withdrew `{n}.expire` without a start of `{n}` in between")
            }
        }
    }
}

/// The assumption every timer gets from the start: it expires some scans after a start
/// unless it is started again first.
pub(super) fn timer_liveness(t: &Timer) -> Ltl {
    let (s, e) = (Ltl::Var(t.start), Ltl::Var(t.expire));
    Ltl::globally(Ltl::implies(s.clone(), Ltl::next(Ltl::finally(Ltl::Or(vec![e, s])))))
}

/// One letter of a play of a machine: the valuation of every signal (bit = signal id).
type Letter = u64;

/// The letters a machine's plays can show, with every answer of the other player, and the
/// pairs of consecutive letters.
struct Plays {
    steps: HashSet<(Letter, Letter)>,
    letters: BTreeSet<Letter>,
}

/// All letters of `machine`'s plays (the other player answering anything), and the pairs of
/// consecutive ones.
fn plays(machine: &Machine) -> Plays {
    let n = machine.reads.len();
    let moves: Vec<Vec<(Letter, StateId)>> = (0..machine.states.len() as u32)
        .map(|s| {
            (0..1u64 << n)
                .map(|read| {
                    let row = machine.row(StateId(s), read);
                    (letter(machine, read, row.write), row.next)
                })
                .collect()
        })
        .collect();
    let mut reachable = vec![false; machine.states.len()];
    let mut stack = vec![machine.init];
    while let Some(s) = stack.pop() {
        if !std::mem::replace(&mut reachable[s.index()], true) {
            stack.extend(moves[s.index()].iter().map(|&(_, next)| next));
        }
    }
    let mut out = Plays { steps: HashSet::new(), letters: BTreeSet::new() };
    for s in (0..machine.states.len()).filter(|&s| reachable[s]) {
        for &(a, next) in &moves[s] {
            out.letters.insert(a);
            out.steps.extend(moves[next.index()].iter().map(|&(b, _)| (a, b)));
        }
    }
    out
}

/// The letter of a step in which `machine` reads `read` and writes `write`.
fn letter(machine: &Machine, read: u64, write: u64) -> Letter {
    let bits = |ids: &[SignalId], v: u64| ids.iter().enumerate().fold(0u64, |m, (i, s)| m | (v >> i & 1) << s.0);
    bits(&machine.reads, read) | bits(&machine.writes, write)
}

/// Whether some play shows `fact` broken for `t`.
fn breaks(fact: TimerFact, t: &Timer, plays: &Plays, machine: &Machine) -> bool {
    let on = |letter: Letter, s: SignalId| letter >> s.0 & 1 == 1;
    match fact {
        TimerFact::StartResets => plays.steps.iter().any(|&(a, b)| on(a, t.start) && on(b, t.expire)),
        TimerFact::ExpiryLasts => {
            plays.steps.iter().any(|&(a, b)| on(a, t.expire) && !on(a, t.start) && !on(b, t.expire))
        }
        TimerFact::NoExpiryBeforeStart => expiry_before_start(t, machine),
    }
}

/// Whether a play reports `t.expire` at or before the timer's first start (a search over the
/// machine's states while no start has been seen).
fn expiry_before_start(t: &Timer, machine: &Machine) -> bool {
    let n = machine.reads.len();
    let mut seen = vec![false; machine.states.len()];
    let mut stack = vec![machine.init];
    while let Some(s) = stack.pop() {
        if std::mem::replace(&mut seen[s.index()], true) {
            continue;
        }
        for read in 0..1u64 << n {
            let row = machine.row(s, read);
            let letter = letter(machine, read, row.write);
            if letter >> t.expire.0 & 1 == 1 {
                return true;
            }
            if letter >> t.start.0 & 1 == 0 {
                stack.push(row.next);
            }
        }
    }
    false
}

/// Decides `spec` with the refinement loop around the bounded games.
pub(super) fn synthesize(
    spec: &Spec,
    cfg: &Config,
    progress: &mut OnProgress<'_, Progress>,
) -> Result<Synthesis, Stop> {
    let mut current = spec.clone();
    let mut refinement = Refinement::default();
    let mut known: HashSet<(usize, TimerFact)> = HashSet::new();
    let mut used_work = 0u64;
    let mut theory = PredicateTheory::new(spec);
    loop {
        refinement.rounds += 1;
        let round_cfg = Config { max_work: cfg.max_work.saturating_sub(used_work), ..cfg.clone() };
        let mut outcome = game::synthesize(&current, &round_cfg, progress)?;
        used_work += outcome.stats.work;
        outcome.stats.work = used_work;
        let (mut new, mut verdict) = (Vec::new(), TheoryVerdict::default());
        if !cfg.refine {
            outcome.refinement = refinement;
            return Ok(outcome);
        }
        if let (Verdict::Unrealizable, Some(counter)) = (&outcome.verdict, &outcome.counter_strategy) {
            let plays = plays(counter);
            for (k, t) in current.timers.iter().enumerate() {
                for fact in TimerFact::ALL {
                    if !known.contains(&(k, fact)) && breaks(fact, t, &plays, counter) {
                        new.push((k, fact));
                    }
                }
            }
            if let Some(pt) = theory.as_mut() {
                let mut left = cfg.max_work.saturating_sub(used_work) / THEORY_UNIT_COST;
                let before = left;
                verdict = check_combinations(&current, pt, &plays, &mut left);
                used_work += (before - left) * THEORY_UNIT_COST;
                outcome.stats.work = used_work;
            }
        }
        refinement.theory = theory.as_ref().map(|pt| pt.theory.stats());
        if new.is_empty() && verdict.cores.is_empty() {
            if !verdict.undecided.is_empty() {
                outcome.verdict = Verdict::Unknown;
                outcome.counter_strategy = None;
                outcome.limit = Some(format!(
                    "the theory checker could not decide whether {} can happen (predicates that touch without crossing, a nonlinear equality, or the work budget: --max-work)",
                    verdict.undecided.join(", ")
                ));
            } else {
                refinement.witnesses = verdict.witnesses;
            }
            outcome.refinement = refinement;
            return Ok(outcome);
        }
        if refinement.rounds >= MAX_ROUNDS {
            outcome.verdict = Verdict::Unknown;
            outcome.counter_strategy = None;
            outcome.limit = Some(format!("the refinement loop learned assumptions for {MAX_ROUNDS} rounds"));
            outcome.refinement = refinement;
            return Ok(outcome);
        }
        for (k, fact) in new {
            known.insert((k, fact));
            let t = &current.timers[k];
            let ltl = fact.formula(t);
            let formula = ltl.to_infix(&|s| current.name(s).to_string());
            let learned = Learned { formula, reason: fact.reason(t), ltl, span: t.span };
            current.assumptions.push(Clause { formula: learned.ltl.clone(), span: learned.span });
            refinement.learned.push(learned);
        }
        for core in verdict.cores {
            let literal = |&(i, on): &(usize, bool)| {
                let v = Ltl::Var(current.predicates[i].signal);
                if on {
                    v
                } else {
                    Ltl::not(v)
                }
            };
            let ltl = Ltl::globally(Ltl::not(Ltl::all(core.iter().map(literal).collect())));
            let formula = ltl.to_infix(&|s| current.name(s).to_string());
            let texts: Vec<String> = core
                .iter()
                .map(|&(i, on)| {
                    let p = &current.predicates[i];
                    let text = current.predicate_text(p);
                    if on {
                        format!("{} ({text})", current.name(p.signal))
                    } else {
                        format!("!{} (not {text})", current.name(p.signal))
                    }
                })
                .collect();
            let inputs: Vec<&str> = current.numeric.iter().map(|n| n.name.as_str()).collect();
            let reason = format!(
                "the counter-strategy used {}, which no value of {} in its range satisfies",
                texts.join(" and "),
                inputs.join(", ")
            );
            let span = current.predicates[core[0].0].span;
            current.assumptions.push(Clause { formula: ltl.clone(), span });
            refinement.learned.push(Learned { formula, reason, ltl, span });
        }
    }
}

/// `spec` with the assumptions a run learned: the specification its controller or
/// counter-strategy is for.
pub fn refined(spec: &Spec, refinement: &Refinement) -> Spec {
    let mut out = spec.clone();
    out.assumptions.extend(refinement.learned.iter().map(|l| Clause { formula: l.ltl.clone(), span: l.span }));
    out
}
