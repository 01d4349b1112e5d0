//! The checked specification every LTL front end produces: declared signals, assumptions and
//! guarantees as formulas over them, the turn order, and (for G4LTL) timers.
//!
//! Both input languages (G4LTL's `.ltl` lines and SYNTCOMP's TLSF) end here, so the synthesis
//! knows nothing of either syntax.

use crate::diag::Span;
use serde::Serialize;

/// Index of a signal in [`Spec::signals`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize)]
pub struct SignalId(pub u32);

impl SignalId {
    pub fn index(self) -> usize {
        self.0 as usize
    }
}

/// Who sets a signal: the environment (an input of the controller) or the controller.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum SignalKind {
    Input,
    Output,
}

#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
pub struct Signal {
    pub name: String,
    pub kind: SignalKind,
    /// Where it was declared.
    pub span: Span,
}

/// The turn order within one step.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Semantics {
    /// The environment sets the inputs first, then the controller answers with outputs in the
    /// same step (a PLC scan: read inputs, compute, write outputs). G4LTL's semantics.
    #[default]
    Mealy,
    /// The controller sets the outputs first, before it sees the step's inputs (TLSF's
    /// `SEMANTICS: Moore`): outputs depend only on the inputs of earlier steps.
    Moore,
}

/// A G4LTL timer `TIMER t1(10s)`: the controller starts it with the output `t1.start`, the
/// environment reports its expiry with the input `t1.expire` (paper, section 2).
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
pub struct Timer {
    pub name: String,
    /// The preset time in milliseconds.
    pub preset_ms: u64,
    pub start: SignalId,
    pub expire: SignalId,
    pub span: Span,
}

/// The type of a numeric input.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum NumberKind {
    /// IEC `REAL`.
    Real,
    /// IEC `INT` (the bounds must be integers).
    Int,
}

/// A bounded numeric input, `INPUT x: REAL[0, 4]` (paper, section 3): the environment sets it;
/// formulas only compare it in [`Predicate`]s.
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
pub struct NumericInput {
    pub name: String,
    pub kind: NumberKind,
    /// The bounds as written (decimal literals, exact).
    pub lo: String,
    pub hi: String,
    pub span: Span,
}

/// Index of a numeric input in [`Spec::numeric`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize)]
pub struct NumericId(pub u32);

/// A polynomial expression over numeric inputs, as written.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub enum NumExpr {
    /// A decimal literal as written (`3`, `3.5`, `1.0e-3`).
    Const(String),
    Var(NumericId),
    Neg(Box<NumExpr>),
    Add(Box<NumExpr>, Box<NumExpr>),
    Sub(Box<NumExpr>, Box<NumExpr>),
    Mul(Box<NumExpr>, Box<NumExpr>),
    /// Division by a constant only (the checker makes sure): the result stays a polynomial.
    Div(Box<NumExpr>, Box<NumExpr>),
    Pow(Box<NumExpr>, u32),
}

/// A comparison of a [`Predicate`]: the theory checker's relations.
pub use super::theory::Rel as Relation;

/// An arithmetic predicate on the numeric inputs, abstracted into the Boolean input `signal`
/// (paper, section 3): the controller reads its truth value, computed once per scan.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Predicate {
    pub signal: SignalId,
    pub lhs: NumExpr,
    pub relation: Relation,
    pub rhs: NumExpr,
    /// Where it was first written.
    pub span: Span,
}

impl NumExpr {
    /// Infix text with the inputs' names, fully parenthesised where precedence could matter.
    pub fn to_text(&self, name: &dyn Fn(NumericId) -> String) -> String {
        let operand = |e: &NumExpr| match e {
            NumExpr::Const(_) | NumExpr::Var(_) | NumExpr::Pow(..) => e.to_text(name),
            _ => format!("({})", e.to_text(name)),
        };
        match self {
            NumExpr::Const(text) => text.clone(),
            NumExpr::Var(v) => name(*v),
            NumExpr::Neg(a) => format!("-{}", operand(a)),
            NumExpr::Add(a, b) => format!("{} + {}", a.to_text(name), operand_sum(b, name)),
            NumExpr::Sub(a, b) => format!("{} - {}", a.to_text(name), operand(b)),
            NumExpr::Mul(a, b) => format!("{} * {}", operand(a), operand(b)),
            NumExpr::Div(a, b) => format!("{} / {}", operand(a), operand(b)),
            NumExpr::Pow(a, n) => match **a {
                NumExpr::Const(_) | NumExpr::Var(_) => format!("{}^{n}", a.to_text(name)),
                _ => format!("({})^{n}", a.to_text(name)),
            },
        }
    }
}

/// The right operand of `+`: a product or power needs no parentheses.
fn operand_sum(e: &NumExpr, name: &dyn Fn(NumericId) -> String) -> String {
    match e {
        NumExpr::Add(..) | NumExpr::Sub(..) | NumExpr::Neg(_) => format!("({})", e.to_text(name)),
        _ => e.to_text(name),
    }
}

/// An LTL formula over the signals of one [`Spec`]. `W` (weak until) and `R` (release) are
/// kept as written; the translation brings everything into negation normal form.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub enum Ltl {
    True,
    False,
    Var(SignalId),
    Not(Box<Ltl>),
    And(Vec<Ltl>),
    Or(Vec<Ltl>),
    Implies(Box<Ltl>, Box<Ltl>),
    Iff(Box<Ltl>, Box<Ltl>),
    Next(Box<Ltl>),
    Globally(Box<Ltl>),
    Finally(Box<Ltl>),
    Until(Box<Ltl>, Box<Ltl>),
    Release(Box<Ltl>, Box<Ltl>),
    WeakUntil(Box<Ltl>, Box<Ltl>),
}

/// Deepest formula the engine accepts. The translation recurses on the formula, and the page
/// runs it in a worker with a 1 MiB stack; parsers report a deeper formula as a located error.
pub const MAX_FORMULA_DEPTH: usize = 200;

impl Ltl {
    #[allow(clippy::should_implement_trait)] // a constructor, as `plc::model::unit::Expr::not`
    pub fn not(f: Ltl) -> Ltl {
        Ltl::Not(Box::new(f))
    }
    pub fn next(f: Ltl) -> Ltl {
        Ltl::Next(Box::new(f))
    }
    pub fn globally(f: Ltl) -> Ltl {
        Ltl::Globally(Box::new(f))
    }
    pub fn finally(f: Ltl) -> Ltl {
        Ltl::Finally(Box::new(f))
    }
    pub fn implies(a: Ltl, b: Ltl) -> Ltl {
        Ltl::Implies(Box::new(a), Box::new(b))
    }
    pub fn iff(a: Ltl, b: Ltl) -> Ltl {
        Ltl::Iff(Box::new(a), Box::new(b))
    }
    pub fn until(a: Ltl, b: Ltl) -> Ltl {
        Ltl::Until(Box::new(a), Box::new(b))
    }
    pub fn release(a: Ltl, b: Ltl) -> Ltl {
        Ltl::Release(Box::new(a), Box::new(b))
    }
    pub fn weak_until(a: Ltl, b: Ltl) -> Ltl {
        Ltl::WeakUntil(Box::new(a), Box::new(b))
    }

    /// The conjunction of `parts` without its `true` parts (`false` if one is `false`): `true`
    /// when nothing is left, the part itself when one is.
    pub fn all(parts: Vec<Ltl>) -> Ltl {
        Ltl::junction(parts, true)
    }

    /// The disjunction of `parts` without its `false` parts (`true` if one is `true`): `false`
    /// when nothing is left, the part itself when one is.
    pub fn any(parts: Vec<Ltl>) -> Ltl {
        Ltl::junction(parts, false)
    }

    fn junction(parts: Vec<Ltl>, conjunction: bool) -> Ltl {
        let (unit, zero) = if conjunction { (Ltl::True, Ltl::False) } else { (Ltl::False, Ltl::True) };
        let mut kept: Vec<Ltl> = Vec::with_capacity(parts.len());
        for part in parts {
            if part == zero {
                return zero;
            }
            if part != unit {
                kept.push(part);
            }
        }
        match kept.len() {
            0 => unit,
            1 => kept.pop().expect("one part"),
            _ if conjunction => Ltl::And(kept),
            _ => Ltl::Or(kept),
        }
    }

    /// Nesting depth (an atom is 1). Iterative, so that it is safe on any formula.
    pub fn depth(&self) -> usize {
        let mut deepest = 0;
        let mut stack = vec![(self, 1usize)];
        while let Some((f, d)) = stack.pop() {
            deepest = deepest.max(d);
            match f {
                Ltl::True | Ltl::False | Ltl::Var(_) => {}
                Ltl::Not(a) | Ltl::Next(a) | Ltl::Globally(a) | Ltl::Finally(a) => stack.push((a, d + 1)),
                Ltl::And(xs) | Ltl::Or(xs) => stack.extend(xs.iter().map(|x| (x, d + 1))),
                Ltl::Implies(a, b) | Ltl::Iff(a, b) | Ltl::Until(a, b) | Ltl::Release(a, b) | Ltl::WeakUntil(a, b) => {
                    stack.push((a, d + 1));
                    stack.push((b, d + 1));
                }
            }
        }
        deepest
    }

    /// The signals the formula mentions. Iterative, so that it is safe on any formula.
    pub fn signals(&self) -> std::collections::BTreeSet<SignalId> {
        let mut out = std::collections::BTreeSet::new();
        let mut stack = vec![self];
        while let Some(f) = stack.pop() {
            match f {
                Ltl::True | Ltl::False => {}
                Ltl::Var(s) => {
                    out.insert(*s);
                }
                Ltl::Not(a) | Ltl::Next(a) | Ltl::Globally(a) | Ltl::Finally(a) => stack.push(a),
                Ltl::And(xs) | Ltl::Or(xs) => stack.extend(xs.iter()),
                Ltl::Implies(a, b) | Ltl::Iff(a, b) | Ltl::Until(a, b) | Ltl::Release(a, b) | Ltl::WeakUntil(a, b) => {
                    stack.push(a);
                    stack.push(b);
                }
            }
        }
        out
    }

    /// Infix text over signal names: `G F X U R W ! && || -> <->`, `true`, `false`. Every
    /// operand that is not an atom or a unary application is parenthesised, so the text needs no
    /// precedence table to be read back.
    pub fn to_infix(&self, name: &dyn Fn(SignalId) -> String) -> String {
        self.written(&Notation::INFIX, name)
    }

    /// The formula in `notation`, parenthesised as [`Ltl::to_infix`] is.
    pub(crate) fn written(&self, notation: &Notation, name: &dyn Fn(SignalId) -> String) -> String {
        let mut out = String::new();
        write_infix(self, notation, name, &mut out);
        out
    }
}

/// The operator words of an infix notation that [`Ltl::written`] varies (`X`, `U`, `W`, `!`,
/// `&&`, `||` and `->` are the same in every notation it writes).
pub(crate) struct Notation {
    pub globally: &'static str,
    pub finally: &'static str,
    pub release: &'static str,
    /// `None`: the notation has no equivalence, so `a <-> b` is written `(a -> b) && (b -> a)`.
    pub iff: Option<&'static str>,
}

impl Notation {
    /// Ours ([`Ltl::to_infix`]).
    pub const INFIX: Notation = Notation { globally: "G ", finally: "F ", release: " R ", iff: Some(" <-> ") };
}

fn is_tight(f: &Ltl) -> bool {
    matches!(f, Ltl::True | Ltl::False | Ltl::Var(_) | Ltl::Not(_) | Ltl::Next(_) | Ltl::Globally(_) | Ltl::Finally(_))
        || matches!(f, Ltl::And(xs) | Ltl::Or(xs) if xs.len() < 2)
}

fn write_operand(f: &Ltl, n: &Notation, name: &dyn Fn(SignalId) -> String, out: &mut String) {
    if is_tight(f) {
        write_infix(f, n, name, out);
    } else {
        out.push('(');
        write_infix(f, n, name, out);
        out.push(')');
    }
}

fn write_infix(f: &Ltl, n: &Notation, name: &dyn Fn(SignalId) -> String, out: &mut String) {
    match f {
        Ltl::True => out.push_str("true"),
        Ltl::False => out.push_str("false"),
        Ltl::Var(s) => out.push_str(&name(*s)),
        Ltl::Not(a) => {
            out.push('!');
            write_operand(a, n, name, out);
        }
        Ltl::Next(a) | Ltl::Globally(a) | Ltl::Finally(a) => {
            out.push_str(match f {
                Ltl::Next(_) => "X ",
                Ltl::Globally(_) => n.globally,
                _ => n.finally,
            });
            write_operand(a, n, name, out);
        }
        Ltl::And(xs) | Ltl::Or(xs) => {
            let (op, unit) = if matches!(f, Ltl::And(_)) { (" && ", "true") } else { (" || ", "false") };
            if xs.is_empty() {
                out.push_str(unit);
            }
            for (i, x) in xs.iter().enumerate() {
                if i > 0 {
                    out.push_str(op);
                }
                write_operand(x, n, name, out);
            }
        }
        // Both implications (the operands are written twice).
        Ltl::Iff(a, b) if n.iff.is_none() => {
            let both =
                Ltl::And(vec![Ltl::implies((**a).clone(), (**b).clone()), Ltl::implies((**b).clone(), (**a).clone())]);
            write_infix(&both, n, name, out);
        }
        Ltl::Implies(a, b) | Ltl::Iff(a, b) | Ltl::Until(a, b) | Ltl::Release(a, b) | Ltl::WeakUntil(a, b) => {
            write_operand(a, n, name, out);
            out.push_str(match f {
                Ltl::Implies(..) => " -> ",
                Ltl::Iff(..) => n.iff.unwrap_or(" <-> "),
                Ltl::Until(..) => " U ",
                Ltl::Release(..) => n.release,
                _ => " W ",
            });
            write_operand(b, n, name, out);
        }
    }
}

/// One formula of the specification with where it was written (a G4LTL line, a TLSF
/// section entry).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Clause {
    pub formula: Ltl,
    pub span: Span,
}

/// A checked LTL specification: `(∧ assumptions) -> (∧ guarantees)` over the signals.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Spec {
    /// Inputs and outputs in declaration order; [`SignalId`] indexes this list.
    pub signals: Vec<Signal>,
    pub assumptions: Vec<Clause>,
    pub guarantees: Vec<Clause>,
    pub semantics: Semantics,
    pub timers: Vec<Timer>,
    /// Bounded numeric inputs (G4LTL-ST's `INPUT x: REAL[0, 4]`).
    pub numeric: Vec<NumericInput>,
    /// The arithmetic predicates, each abstracted into a Boolean input.
    pub predicates: Vec<Predicate>,
    /// A title for reports and generated code (TLSF `TITLE`), if the source gave one.
    pub title: Option<String>,
}

impl Spec {
    pub fn signal(&self, id: SignalId) -> &Signal {
        &self.signals[id.index()]
    }

    pub fn name(&self, id: SignalId) -> &str {
        &self.signals[id.index()].name
    }

    pub fn signal_id(&self, name: &str) -> Option<SignalId> {
        self.signals.iter().position(|s| s.name == name).map(|i| SignalId(i as u32))
    }

    /// The inputs, in declaration order.
    pub fn inputs(&self) -> Vec<SignalId> {
        self.of_kind(SignalKind::Input)
    }

    /// The outputs, in declaration order.
    pub fn outputs(&self) -> Vec<SignalId> {
        self.of_kind(SignalKind::Output)
    }

    fn of_kind(&self, kind: SignalKind) -> Vec<SignalId> {
        (0..self.signals.len() as u32).map(SignalId).filter(|&s| self.signal(s).kind == kind).collect()
    }

    /// A predicate's text over the numeric inputs' names, `x + y > 3`.
    pub fn predicate_text(&self, p: &Predicate) -> String {
        let name = |v: NumericId| self.numeric[v.0 as usize].name.clone();
        format!("{} {} {}", p.lhs.to_text(&name), p.relation.symbol(), p.rhs.to_text(&name))
    }

    /// The predicate abstracted into `signal`, if it is one.
    pub fn predicate_of(&self, signal: SignalId) -> Option<&Predicate> {
        self.predicates.iter().find(|p| p.signal == signal)
    }

    /// The conjunction of the assumptions (`true` if there are none).
    pub fn assumption(&self) -> Ltl {
        Ltl::all(self.assumptions.iter().map(|c| c.formula.clone()).collect())
    }

    /// The conjunction of the guarantees (`true` if there are none).
    pub fn guarantee(&self) -> Ltl {
        Ltl::all(self.guarantees.iter().map(|c| c.formula.clone()).collect())
    }

    /// The whole specification as one formula: `A -> G`, or just `G` without assumptions.
    pub fn formula(&self) -> Ltl {
        if self.assumptions.is_empty() {
            self.guarantee()
        } else {
            Ltl::implies(self.assumption(), self.guarantee())
        }
    }

    /// [`Spec::formula`] as infix text over the signal names.
    pub fn formula_text(&self) -> String {
        self.formula().to_infix(&|s| self.name(s).to_string())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn infix_parenthesises_binary_operands_only() {
        let a = Ltl::Var(SignalId(0));
        let b = Ltl::Var(SignalId(1));
        let f = Ltl::globally(Ltl::implies(a.clone(), Ltl::finally(Ltl::until(a.clone(), Ltl::not(b.clone())))));
        let names = ["req", "grant"];
        assert_eq!(f.to_infix(&|s| names[s.index()].to_string()), "G (req -> F (req U !grant))");
        let g = Ltl::And(vec![Ltl::Or(vec![a.clone(), b.clone()]), Ltl::next(b)]);
        assert_eq!(g.to_infix(&|s| names[s.index()].to_string()), "(req || grant) && X grant");
        assert_eq!(g.depth(), 3);
    }
}
