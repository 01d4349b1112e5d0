//! Deterministic monitors for the GR(1)-shaped conjuncts of a specification: each clause
//! becomes state bits with next-state functions, safety conditions on a step and justice
//! conditions (to hold infinitely often), all Boolean functions of the monitor's state and the
//! step's letter. The monitors are exact: a play satisfies a conjunct if and only if its
//! safety conditions hold at every step and its justice conditions infinitely often.
//!
//! **Shapes.** After negations are pushed to the atoms, a conjunct is `G body` or a `body`
//! due at step 0, where `body` is a disjunction of *lookahead propositions* (signals under at
//! most a bounded number of `X`) and at most one temporal obligation: `F q`, `a U b`, `a W b`,
//! `a R b` or `G q` with lookahead propositions as operands (several `F` disjuncts merge into
//! one: `F a ∨ F b = F (a ∨ b)`), or `G F q` alone. `X` over a temporal operator moves inward
//! (`X (a U b) = X a U X b`). So `G (r -> F g)`, `G ((g && G !r) -> F !g)` (`G (!g ∨ F r ∨ F !g)`),
//! `!F G (r && X !g)` (`G F (!r ∨ X g)`), `G (r -> X (a U b))` and `r R !g` are all in.
//!
//! **Lookahead** is handled by delay: a conjunct whose propositions look `D` steps ahead is
//! judged `D` steps late, about the step `τ = t - D`, from history bits that remember the
//! signals of the last `D` steps. A delay changes when a violation is seen, never whether
//! there is one, so the game's winner is the same. Age bits (`t ≥ k`) gate a conjunct until
//! its first judged step exists, and pick step 0 for the conjuncts due only then.
//!
//! **Obligations** share one "open" bit per conjunct: all obligations `a U b` opened and not
//! yet discharged ask the same of the future, so one bit says whether any is open.

use crate::ltl::spec::{Clause, Ltl, SignalId, Spec};

/// A Boolean function of the monitors' state bits (the circuit's latches) and the current
/// step's signals.
pub(super) use crate::ltl::circuit::Logic as Prop;

/// A state bit of the monitors.
#[derive(Clone, Debug)]
pub(super) struct Bit {
    /// An identifier that says what it holds (`r0_prev`, `open_2`).
    pub name: String,
    /// What it holds, in words.
    pub comment: String,
    pub init: bool,
    pub next: Prop,
}

/// One player's conditions: safety on every step, justice infinitely often.
#[derive(Clone, Debug, Default)]
pub(super) struct Conditions {
    pub safety: Vec<Prop>,
    pub justice: Vec<Prop>,
    /// Per justice, the conjunct it comes from.
    pub labels: Vec<String>,
}

/// The monitors of a whole specification: the environment's conditions are its assumptions',
/// the controller's its guarantees'. The signals each clause reads, in clause order, give the
/// solver its variable order.
#[derive(Clone, Debug)]
pub(super) struct Monitors {
    pub bits: Vec<Bit>,
    pub env: Conditions,
    pub sys: Conditions,
    /// Per clause (assumptions first), the signals it reads and the bits it made.
    pub groups: Vec<(Vec<SignalId>, Vec<usize>)>,
}

/// Why a specification is not in the fragment: the clause and what in it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(super) struct Outside {
    pub clause: Clause,
    pub reason: String,
}

/// The monitors of `spec`, or the first clause outside the fragment.
pub(super) fn monitors(spec: &Spec, justice: Justice) -> Result<Monitors, Outside> {
    let names = spec.signals.iter().map(|s| s.name.clone()).collect();
    let mut builder = Builder {
        bits: Vec::new(),
        history: Vec::new(),
        age: Vec::new(),
        groups: Vec::new(),
        justice,
        names,
        obligations: 0,
    };
    let mut env = Conditions::default();
    let mut sys = Conditions::default();
    for (clauses, side) in [(&spec.assumptions, &mut env), (&spec.guarantees, &mut sys)] {
        for clause in clauses.iter() {
            let mut conjuncts = Vec::new();
            conjuncts_of(&nnf(&clause.formula, false), &mut conjuncts);
            for conjunct in conjuncts {
                let shape = shape(&conjunct)
                    .map_err(|reason| Outside { clause: clause.clone(), reason: reason.to_string() })?;
                let text = conjunct.to_infix(&|s| spec.name(s).to_string());
                builder.compile(shape, &text, side);
            }
        }
    }
    Ok(Monitors { bits: builder.bits, env, sys, groups: builder.groups })
}

/// `f` (negated if `negated`) with negations on atoms only and no `->`, `<->`.
fn nnf(f: &Ltl, negated: bool) -> Ltl {
    let both = |a: &Ltl, b: &Ltl, neg: bool| (Box::new(nnf(a, neg)), Box::new(nnf(b, neg)));
    match f {
        Ltl::True | Ltl::False => {
            if (*f == Ltl::True) != negated {
                Ltl::True
            } else {
                Ltl::False
            }
        }
        Ltl::Var(_) => {
            if negated {
                Ltl::not(f.clone())
            } else {
                f.clone()
            }
        }
        Ltl::Not(a) => nnf(a, !negated),
        Ltl::And(parts) | Ltl::Or(parts) => {
            let parts = parts.iter().map(|p| nnf(p, negated)).collect();
            if matches!(f, Ltl::And(_)) != negated {
                Ltl::all(parts)
            } else {
                Ltl::any(parts)
            }
        }
        Ltl::Implies(a, b) => nnf(&Ltl::Or(vec![Ltl::not((**a).clone()), (**b).clone()]), negated),
        Ltl::Iff(a, b) => {
            let (a, b) = ((**a).clone(), (**b).clone());
            let same = Ltl::Or(vec![Ltl::And(vec![a.clone(), b.clone()]), Ltl::And(vec![Ltl::not(a), Ltl::not(b)])]);
            nnf(&same, negated)
        }
        Ltl::Next(a) => Ltl::next(nnf(a, negated)),
        Ltl::Globally(a) | Ltl::Finally(a) => {
            let a = nnf(a, negated);
            if matches!(f, Ltl::Globally(_)) != negated {
                Ltl::globally(a)
            } else {
                Ltl::finally(a)
            }
        }
        Ltl::Until(a, b) | Ltl::Release(a, b) => {
            let (a, b) = both(a, b, negated);
            if matches!(f, Ltl::Until(..)) != negated {
                Ltl::Until(a, b)
            } else {
                Ltl::Release(a, b)
            }
        }
        Ltl::WeakUntil(a, b) => {
            if negated {
                // !(a W b) = !b U (!a && !b)
                let (na, nb) = (nnf(a, true), nnf(b, true));
                Ltl::until(nb.clone(), Ltl::all(vec![na, nb]))
            } else {
                let (a, b) = both(a, b, false);
                Ltl::WeakUntil(a, b)
            }
        }
    }
}

/// The conjuncts of an NNF formula: `∧` split, `G` distributed over `∧`, `G G` merged, and
/// a disjunction over a conjunction with temporal parts distributed
/// (`p ∨ (q ∧ X (a W b))` is `(p ∨ q) ∧ (p ∨ X (a W b))`).
fn conjuncts_of(f: &Ltl, out: &mut Vec<Ltl>) {
    match f {
        Ltl::True => {}
        Ltl::And(parts) => parts.iter().for_each(|p| conjuncts_of(p, out)),
        Ltl::Globally(body) => match &**body {
            Ltl::Globally(_) | Ltl::True => conjuncts_of(body, out),
            body => match distributed(body) {
                Some(Ltl::And(parts)) => parts.iter().for_each(|p| conjuncts_of(&Ltl::globally(p.clone()), out)),
                _ => out.push(f.clone()),
            },
        },
        _ => match distributed(f) {
            Some(conjunction @ Ltl::And(_)) => conjuncts_of(&conjunction, out),
            _ => out.push(f.clone()),
        },
    }
}

/// `f` as a conjunction, where it is one or a disjunction with a temporal conjunction in it
/// (distributed one conjunction at a time, `X` moved over `∧`); `None` otherwise.
fn distributed(f: &Ltl) -> Option<Ltl> {
    match f {
        Ltl::And(_) => Some(f.clone()),
        Ltl::Next(a) if look(f, 0).is_none() => match distributed(a)? {
            Ltl::And(parts) => Some(Ltl::And(parts.into_iter().map(Ltl::next).collect())),
            _ => None,
        },
        Ltl::Or(parts) => {
            let (i, conjunction) = parts.iter().enumerate().find_map(|(i, p)| {
                if look(p, 0).is_some() {
                    return None;
                }
                match distributed(p)? {
                    Ltl::And(conjuncts) => Some((i, conjuncts)),
                    _ => None,
                }
            })?;
            let rest: Vec<Ltl> = parts.iter().enumerate().filter(|&(j, _)| j != i).map(|(_, p)| p.clone()).collect();
            Some(Ltl::And(
                conjunction.into_iter().map(|c| Ltl::any(rest.iter().cloned().chain([c]).collect())).collect(),
            ))
        }
        _ => None,
    }
}

/// A proposition about the letters from the judged step on: `Atom(s, j)` is signal `s` at
/// `τ + j`.
#[derive(Clone, Debug, PartialEq, Eq)]
enum Look {
    Const(bool),
    Atom(SignalId, u32, bool),
    And(Vec<Look>),
    Or(Vec<Look>),
}

impl Look {
    fn reach(&self) -> u32 {
        match self {
            Look::Const(_) => 0,
            Look::Atom(_, j, _) => *j,
            Look::And(ps) | Look::Or(ps) => ps.iter().map(Look::reach).max().unwrap_or(0),
        }
    }
}

/// The temporal part of a conjunct's body, over lookahead propositions.
#[derive(Clone, Debug, PartialEq, Eq)]
enum Temporal {
    /// `a U b` (`F q` is `true U q`).
    Until(Look, Look),
    /// `a W b`.
    WeakUntil(Look, Look),
    /// `a R b`: `b` up to and including the first `a` (`G q` is `false R q`).
    Release(Look, Look),
    /// `G F q`.
    InfinitelyOften(Look),
}

/// What a conjunct asks: `body` at step 0 only, or at every step.
struct Shape {
    always: bool,
    /// The disjunction of the body's propositions (`false`: none).
    otherwise: Look,
    temporal: Option<Temporal>,
}

/// The lookahead proposition `f` seen `shift` steps ahead, if it is one.
fn look(f: &Ltl, shift: u32) -> Option<Look> {
    Some(match f {
        Ltl::True => Look::Const(true),
        Ltl::False => Look::Const(false),
        Ltl::Var(s) => Look::Atom(*s, shift, true),
        Ltl::Not(a) => match &**a {
            Ltl::Var(s) => Look::Atom(*s, shift, false),
            _ => return None,
        },
        Ltl::And(parts) => Look::And(parts.iter().map(|p| look(p, shift)).collect::<Option<_>>()?),
        Ltl::Or(parts) => Look::Or(parts.iter().map(|p| look(p, shift)).collect::<Option<_>>()?),
        Ltl::Next(a) => look(a, shift + 1)?,
        _ => return None,
    })
}

/// The most `X` a lookahead proposition may nest: history bits cost one per signal and step.
const MAX_REACH: u32 = 64;

fn shape(f: &Ltl) -> Result<Shape, &'static str> {
    // Leading `X`s shift the whole conjunct (`X G φ` is `G φ` from step 1).
    let mut shift = 0;
    let mut f = f;
    while let Ltl::Next(inner) = f {
        if look(f, 0).is_some() {
            break;
        }
        shift += 1;
        f = inner;
    }
    let (always, body) = match f {
        Ltl::Globally(body) => match &**body {
            Ltl::Finally(q) => {
                let q = look(q, shift).ok_or("G F with a temporal operand")?;
                return checked(Shape {
                    always: false,
                    otherwise: Look::Const(false),
                    temporal: Some(Temporal::InfinitelyOften(q)),
                });
            }
            _ => (true, &**body),
        },
        _ => (false, f),
    };
    let mut otherwise = Vec::new();
    let mut eventually = Vec::new();
    // `G q` disjuncts: alone a `false R q`, beside `q U b` a weak until.
    let mut always_also = Vec::new();
    let mut temporal = None;
    let mut disjuncts = Vec::new();
    disjuncts_of(body, shift, &mut disjuncts);
    for (d, shift) in disjuncts {
        if let Some(p) = look(d, shift) {
            otherwise.push(p);
            continue;
        }
        let operand = |f: &Ltl| look(f, shift).ok_or("a temporal operator over a temporal operand");
        let found = match d {
            Ltl::Finally(q) => match &**q {
                Ltl::Globally(_) => return Err("F G (persistence) is not a GR(1) condition"),
                q => {
                    eventually.push(operand(q)?);
                    continue;
                }
            },
            Ltl::Until(a, b) => Temporal::Until(operand(a)?, operand(b)?),
            Ltl::WeakUntil(a, b) => Temporal::WeakUntil(operand(a)?, operand(b)?),
            Ltl::Release(a, b) => Temporal::Release(operand(a)?, operand(b)?),
            Ltl::Globally(q) => match &**q {
                Ltl::Finally(r) if !always => Temporal::InfinitelyOften(operand(r)?),
                q => {
                    always_also.push(operand(q)?);
                    continue;
                }
            },
            _ => return Err("a conjunction of temporal obligations inside a disjunction"),
        };
        if temporal.replace(found).is_some() {
            return Err("a disjunction of two temporal obligations");
        }
    }
    // `(a U b) ∨ G a` is `a W b` (how G4LTL writes a weak until).
    if let Some(Temporal::Until(a, b)) = &temporal {
        if let Some(i) = always_also.iter().position(|g| g == a) {
            always_also.remove(i);
            temporal = Some(Temporal::WeakUntil(a.clone(), b.clone()));
        }
    }
    if let Some(g) = always_also.pop() {
        if temporal.replace(Temporal::Release(Look::Const(false), g)).is_some() || !always_also.is_empty() {
            return Err("a disjunction of two temporal obligations");
        }
    }
    if !eventually.is_empty() {
        let q = Look::Or(eventually);
        if temporal.replace(Temporal::Until(Look::Const(true), q)).is_some() {
            return Err("a disjunction of two temporal obligations");
        }
    }
    let otherwise = Look::Or(otherwise);
    if matches!(temporal, Some(Temporal::InfinitelyOften(_))) && otherwise != Look::Or(Vec::new()) {
        return Err("G F q in a disjunction (not a GR(1) condition)");
    }
    checked(Shape { always, otherwise, temporal })
}

impl Shape {
    /// Its propositions: the alternative, then the obligation's operands.
    fn looks(&self) -> Vec<&Look> {
        let operands = match &self.temporal {
            Some(Temporal::Until(a, b) | Temporal::WeakUntil(a, b) | Temporal::Release(a, b)) => [Some(a), Some(b)],
            Some(Temporal::InfinitelyOften(q)) => [Some(q), None],
            None => [None, None],
        };
        [Some(&self.otherwise)].into_iter().chain(operands).flatten().collect()
    }
}

fn checked(shape: Shape) -> Result<Shape, &'static str> {
    let reach = shape.looks().into_iter().map(Look::reach).max().unwrap_or(0);
    if reach > MAX_REACH {
        return Err("more than 64 nested X");
    }
    Ok(shape)
}

/// The disjuncts of `f`, each with the `X` above it (`X (a ∨ b)` is `X a ∨ X b`; `X` over a
/// temporal operator moves into its operands).
fn disjuncts_of<'a>(f: &'a Ltl, shift: u32, out: &mut Vec<(&'a Ltl, u32)>) {
    match f {
        Ltl::Or(parts) => parts.iter().for_each(|p| disjuncts_of(p, shift, out)),
        Ltl::Next(a) if look(f, 0).is_none() => disjuncts_of(a, shift + 1, out),
        _ => out.push((f, shift)),
    }
}

/// When an obligation's justice is met: with nothing open before the step, or nothing left
/// open after it. Both are exact (`¬waiting` now is `¬open` next) and decide the same game;
/// they differ in the strategies read off: a controller pursuing `After` answers a request in
/// its own step (the arbiters' machines halve), one pursuing `Before` may count an idle step
/// (full_arbiter's are a third of the size).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Justice {
    Before,
    After,
}

struct Builder {
    justice: Justice,
    bits: Vec<Bit>,
    /// `(signal, k)`: the bit holding the signal's value `k ≥ 1` steps ago.
    history: Vec<((SignalId, u32), usize)>,
    /// `age[k - 1]`: the bit saying that at least `k` steps have passed.
    age: Vec<usize>,
    groups: Vec<(Vec<SignalId>, Vec<usize>)>,
    /// The signals' names, for the bits' names.
    names: Vec<String>,
    /// Open bits made so far.
    obligations: usize,
}

impl Builder {
    fn bit(&mut self, init: bool, next: Prop, name: String, comment: String) -> usize {
        self.bits.push(Bit { name, comment, init, next });
        self.bits.len() - 1
    }

    /// The signal's value `k` steps ago (`k = 0`: now).
    fn history(&mut self, s: SignalId, k: u32) -> Prop {
        if k == 0 {
            return Prop::Signal(s);
        }
        if let Some(&(_, b)) = self.history.iter().find(|(key, _)| *key == (s, k)) {
            return Prop::Latch(b);
        }
        let next = self.history(s, k - 1);
        let signal = &self.names[s.index()];
        let name = if k == 1 { format!("{signal}_prev") } else { format!("{signal}_prev{k}") };
        let comment = format!("{signal} {k} step{} ago", if k == 1 { "" } else { "s" });
        let b = self.bit(false, next, name, comment);
        self.history.push(((s, k), b));
        Prop::Latch(b)
    }

    /// Whether at least `k` steps have passed.
    fn age(&mut self, k: u32) -> Prop {
        if k == 0 {
            return Prop::Const(true);
        }
        while self.age.len() < k as usize {
            let k = self.age.len() + 1;
            let next = self.age(k as u32 - 1);
            let comment = format!("at least {k} step{} done", if k == 1 { "" } else { "s" });
            let b = self.bit(false, next, format!("after_{k}"), comment);
            self.age.push(b);
        }
        Prop::Latch(self.age[k as usize - 1])
    }

    /// A lookahead proposition judged `delay` steps late.
    fn late(&mut self, p: &Look, delay: u32) -> Prop {
        match p {
            Look::Const(b) => Prop::Const(*b),
            Look::Atom(s, j, positive) => {
                let value = self.history(*s, delay - j);
                if *positive {
                    value
                } else {
                    Prop::negated(value)
                }
            }
            Look::And(ps) => Prop::and(ps.iter().map(|p| self.late(p, delay)).collect()),
            Look::Or(ps) => Prop::or(ps.iter().map(|p| self.late(p, delay)).collect()),
        }
    }

    /// Adds the monitor of one conjunct (`text`, for the names of its bits).
    fn compile(&mut self, shape: Shape, text: &str, side: &mut Conditions) {
        let first_bit = self.bits.len();
        let looks = shape.looks();
        let delay = looks.iter().map(|p| p.reach()).max().unwrap_or(0);
        let mut signals = Vec::new();
        for p in &looks {
            atoms(p, &mut signals);
        }
        // Each once, in order of appearance.
        let mut once = Vec::with_capacity(signals.len());
        for s in signals {
            if !once.contains(&s) {
                once.push(s);
            }
        }
        let signals = once;
        // The judged step exists (always), or is step 0 (once).
        let active = if shape.always {
            self.age(delay)
        } else {
            let (from, to) = (self.age(delay), self.age(delay + 1));
            Prop::and(vec![from, Prop::negated(to)])
        };
        let otherwise = self.late(&shape.otherwise, delay);
        let trigger = Prop::and(vec![active.clone(), Prop::negated(otherwise)]);
        let strong = matches!(shape.temporal, Some(Temporal::Until(..)));
        match shape.temporal {
            None => side.safety.push(Prop::negated(trigger)),
            Some(Temporal::InfinitelyOften(q)) => {
                // Prefix-independent: judged from the first step that has one on.
                let from = self.age(delay);
                let q = self.late(&q, delay);
                side.justice.push(Prop::and(vec![from, q]));
                side.labels.push(text.to_string());
            }
            Some(Temporal::Until(a, b) | Temporal::WeakUntil(a, b)) => {
                let (a, b) = (self.late(&a, delay), self.late(&b, delay));
                let open = self.bits.len();
                let pending = Prop::or(vec![Prop::Latch(open), trigger]);
                // Pending and not discharged now: `a` must hold, and it stays open.
                let waiting = Prop::and(vec![pending, Prop::negated(b)]);
                let (name, comment) = self.open_bit(text);
                self.bit(false, waiting.clone(), name, comment);
                side.safety.push(Prop::or(vec![Prop::negated(waiting.clone()), a]));
                if strong {
                    side.labels.push(text.to_string());
                    side.justice.push(match self.justice {
                        Justice::Before => Prop::negated(Prop::Latch(open)),
                        Justice::After => Prop::negated(waiting),
                    });
                }
            }
            Some(Temporal::Release(a, b)) => {
                let (a, b) = (self.late(&a, delay), self.late(&b, delay));
                let open = self.bits.len();
                let pending = Prop::or(vec![Prop::Latch(open), trigger]);
                let (name, comment) = self.open_bit(text);
                self.bit(false, Prop::and(vec![pending.clone(), Prop::negated(a)]), name, comment);
                side.safety.push(Prop::or(vec![Prop::negated(pending), b]));
            }
        }
        self.groups.push((signals, (first_bit..self.bits.len()).collect()));
    }
}

impl Builder {
    /// The name and comment of the next obligation's open bit.
    fn open_bit(&mut self, conjunct: &str) -> (String, String) {
        self.obligations += 1;
        (format!("open_{}", self.obligations), format!("an obligation of {conjunct} is open"))
    }
}

fn atoms(p: &Look, out: &mut Vec<SignalId>) {
    match p {
        Look::Const(_) => {}
        Look::Atom(s, ..) => out.push(*s),
        Look::And(ps) | Look::Or(ps) => ps.iter().for_each(|p| atoms(p, out)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ltl::{compile, Format};
    use hashbrown::HashMap;

    fn of(source: &str) -> Result<Monitors, Outside> {
        let (spec, _) = compile(source, Format::G4ltl, &[]).expect("a valid specification");
        monitors(&spec, Justice::Before)
    }

    #[test]
    fn the_arbiter_patterns_are_in_the_fragment() {
        let m = of("INPUT r, idle\nOUTPUT g\nASSUME ALWAYS EVENTUALLY idle\n\
                    ALWAYS (r -> EVENTUALLY g)\nALWAYS ((g && ALWAYS !r) -> EVENTUALLY !g)\n\
                    ALWAYS (r -> NEXT (!g UNTIL idle))\n(r R !g)\nALWAYS !(g && idle)\n")
        .expect("in the fragment");
        assert_eq!(m.env.justice.len(), 1);
        // Two responses and one until carry justice; one each of bit "open".
        assert_eq!(m.sys.justice.len(), 3);
    }

    /// Runs the monitors of a one-guarantee spec along a lasso word: whether every safety
    /// condition holds at every step and every justice infinitely often.
    fn accepts(m: &Monitors, play: &crate::ltl::Play) -> bool {
        let mut state: Vec<bool> = m.bits.iter().map(|b| b.init).collect();
        let n = play.letters.len();
        let mut seen: HashMap<(Vec<bool>, usize), usize> = HashMap::new();
        let mut trace = Vec::new();
        let mut i = 0;
        // Run until a (state, position in the loop) repeats: from there the run is periodic.
        loop {
            if i >= play.loop_start {
                if let Some(&first) = seen.get(&(state.clone(), i)) {
                    let cycle = &trace[first..];
                    let safe = trace.iter().all(|&(ok, _): &(bool, Vec<bool>)| ok);
                    let fair = (0..m.sys.justice.len()).all(|j| cycle.iter().any(|(_, js)| js[j]));
                    return safe && fair;
                }
                seen.insert((state.clone(), i), trace.len());
            }
            let letter = play.letters[i];
            let signal = |s: SignalId| letter >> s.0 & 1 == 1;
            let bit = |b: usize| state[b];
            let ok = m.sys.safety.iter().all(|p| p.eval(&bit, &signal));
            let js = m.sys.justice.iter().map(|p| p.eval(&bit, &signal)).collect();
            trace.push((ok, js));
            state = m.bits.iter().map(|b| b.next.eval(&bit, &signal)).collect();
            i = if i + 1 < n { i + 1 } else { play.loop_start };
        }
    }

    fn prop_strategy() -> impl proptest::strategy::Strategy<Value = Ltl> {
        use proptest::prelude::*;
        let atom = (0..3u32, any::<bool>()).prop_map(|(s, positive)| {
            let v = Ltl::Var(SignalId(s));
            if positive {
                v
            } else {
                Ltl::not(v)
            }
        });
        atom.prop_recursive(3, 8, 2, |inner| {
            prop_oneof![
                (inner.clone(), inner.clone()).prop_map(|(a, b)| Ltl::And(vec![a, b])),
                (inner.clone(), inner.clone()).prop_map(|(a, b)| Ltl::Or(vec![a, b])),
                inner.prop_map(Ltl::next),
            ]
        })
    }

    /// Conjuncts of every shape the fragment takes, over lookahead propositions.
    fn fragment_strategy() -> impl proptest::strategy::Strategy<Value = Ltl> {
        use proptest::prelude::*;
        let p = prop_strategy;
        prop_oneof![
            p(),
            p().prop_map(Ltl::globally),
            p().prop_map(|q| Ltl::globally(Ltl::finally(q))),
            (p(), p()).prop_map(|(a, b)| Ltl::globally(Ltl::implies(a, Ltl::finally(b)))),
            (p(), p(), p()).prop_map(|(t, a, b)| Ltl::globally(Ltl::implies(t, Ltl::next(Ltl::until(a, b))))),
            (p(), p(), p()).prop_map(|(t, a, b)| Ltl::globally(Ltl::implies(t, Ltl::weak_until(a, b)))),
            (p(), p(), p()).prop_map(|(t, a, b)| Ltl::globally(Ltl::Or(vec![t, Ltl::release(a, b)]))),
            (p(), p()).prop_map(|(a, b)| Ltl::release(a, b)),
            (p(), p()).prop_map(|(a, b)| Ltl::until(a, b)),
            (p(), p(), p()).prop_map(|(a, g, f)| Ltl::globally(Ltl::implies(
                Ltl::And(vec![a, Ltl::globally(g)]),
                Ltl::finally(f)
            ))),
            (p(), p()).prop_map(|(a, b)| Ltl::not(Ltl::finally(Ltl::globally(Ltl::And(vec![a, b]))))),
            (p(), p()).prop_map(|(t, q)| Ltl::next(Ltl::globally(Ltl::implies(t, Ltl::globally(q))))),
            (p(), p(), p()).prop_map(|(t, a, b)| Ltl::globally(Ltl::implies(
                t,
                Ltl::Or(vec![Ltl::until(a.clone(), b), Ltl::globally(a)])
            ))),
            (p(), p(), p(), p()).prop_map(|(t, q, a, b)| Ltl::globally(Ltl::implies(
                t,
                Ltl::And(vec![q, Ltl::next(Ltl::weak_until(a, b))])
            ))),
            (p(), p(), p()).prop_map(|(t, q, r)| Ltl::implies(t, Ltl::And(vec![Ltl::finally(q), Ltl::globally(r)]))),
        ]
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(400))]
        /// A monitor accepts exactly the lasso words that satisfy its conjunct (the lasso
        /// semantics of `Play::satisfies`, which shares no code with the monitors).
        #[test]
        fn monitors_accept_exactly_the_words_of_their_conjunct(
            f in fragment_strategy(),
            letters in proptest::collection::vec(0u64..8, 1..7),
            start in 0usize..6,
        ) {
            let spec = Spec {
                signals: (0..3).map(|i| crate::ltl::Signal {
                    name: format!("s{i}"),
                    kind: crate::ltl::SignalKind::Output,
                    span: Default::default(),
                }).collect(),
                guarantees: vec![Clause { formula: f.clone(), span: Default::default() }],
                ..Spec::default()
            };
            let loop_start = start % letters.len();
            let play = crate::ltl::Play { states: Vec::new(), letters, loop_start };
            for justice in [Justice::Before, Justice::After] {
                let m = monitors(&spec, justice).expect("in the fragment");
                proptest::prop_assert_eq!(accepts(&m, &play), play.satisfies(&f), "{:?} {:?}", justice, f);
            }
        }
    }

    #[test]
    fn persistence_and_nested_eventualities_are_not() {
        for spec in [
            "INPUT r\nOUTPUT g\nEVENTUALLY ALWAYS g\n",
            "INPUT r\nOUTPUT g\nALWAYS (r -> EVENTUALLY (g && EVENTUALLY !g))\n",
        ] {
            assert!(of(spec).is_err(), "{spec}");
        }
    }
}
