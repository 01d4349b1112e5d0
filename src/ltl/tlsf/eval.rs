//! Evaluation of a parsed TLSF file: parameters, definitions and big operators become plain
//! numbers, sets and [`Ltl`] formulas over the declared signals.
//!
//! A hostile file must neither hang nor overflow the stack, so the evaluation is bounded three
//! ways, each reported as a located error: [`MAX_STEPS`] units of work in all (a node
//! evaluated, a formula node copied), [`MAX_CALL_DEPTH`] nested calls of definitions and
//! [`MAX_EVAL_NESTING`] nested evaluations, and no formula deeper than [`MAX_FORMULA_DEPTH`]
//! is ever built (each value carries its depth).

use super::parser::{BigOp, Binary, Binder, BoundedOp, Definition, Domain, Expr, ExprKind, Junction, Unary};
use crate::diag::{Diagnostics, Span};
use crate::ltl::spec::{Ltl, SignalId, MAX_FORMULA_DEPTH};
use std::collections::{BTreeSet, HashMap, HashSet};

/// Units of work one file may cost: far more than any benchmark needs (full_arbiter with
/// n = 100 takes about 10^5), little enough to stop in a second.
pub const MAX_STEPS: u64 = 1_000_000;
/// Nested calls of definitions: recursion that deep is unbounded, or builds a formula too deep
/// for the engine anyway.
pub const MAX_CALL_DEPTH: usize = 256;
/// Nested evaluations (of subexpressions and calls together), which is what uses the stack.
pub const MAX_EVAL_NESTING: usize = 1000;

/// A formula with its nesting depth and node count: the depth is checked as it grows, the
/// count is paid for whenever the formula is copied.
#[derive(Clone, Debug, PartialEq)]
pub struct Formula {
    pub ltl: Ltl,
    depth: usize,
    size: u64,
}

impl Formula {
    fn constant(value: bool) -> Formula {
        Formula { ltl: if value { Ltl::True } else { Ltl::False }, depth: 1, size: 1 }
    }

    pub fn signal(id: SignalId) -> Formula {
        Formula { ltl: Ltl::Var(id), depth: 1, size: 1 }
    }
}

/// A bus: `width` signals with consecutive ids from `first`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Bus {
    pub first: u32,
    pub width: u32,
}

#[derive(Clone, Debug, PartialEq)]
pub enum Value {
    Int(i64),
    /// Formulas, including the truth values that comparisons give.
    Formula(Formula),
    Set(BTreeSet<i64>),
    Bus(Bus),
}

/// What a global name stands for.
#[derive(Clone, Copy, Debug)]
pub enum Global<'a> {
    /// A parameter; `None` until its value is known.
    Parameter(Option<i64>),
    Definition(&'a Definition),
    Signal(SignalId),
    Bus(Bus),
}

/// The evaluation failed and the reason was reported (or the budget ran out earlier).
#[derive(Debug)]
pub struct Failed;

type EResult<T> = Result<T, Failed>;

pub struct Evaluator<'a, 'd, 's> {
    pub globals: HashMap<&'a str, Global<'a>>,
    diags: &'d mut Diagnostics<'s>,
    steps: u64,
    /// Whether the step budget ran out: then every later evaluation fails silently.
    exhausted: bool,
    /// Errors reported, so that a definition failing on every call is reported once.
    reported: HashSet<(Span, String)>,
    /// Bound variables and arguments; a call sees only its own (from `frame`).
    locals: Vec<(&'a str, Value)>,
    frame: usize,
    /// Where the calls in progress were made, innermost last.
    calls: Vec<Span>,
    nesting: usize,
    /// Signals are entered in `globals` only after the parameters and bus widths are known,
    /// which therefore cannot use them; these names make that error say so.
    declared_signals: HashSet<&'a str>,
}

impl<'a, 'd, 's> Evaluator<'a, 'd, 's> {
    pub fn new(
        globals: HashMap<&'a str, Global<'a>>,
        declared_signals: HashSet<&'a str>,
        diags: &'d mut Diagnostics<'s>,
    ) -> Self {
        Evaluator {
            globals,
            diags,
            steps: 0,
            exhausted: false,
            reported: HashSet::new(),
            locals: Vec::new(),
            frame: 0,
            calls: Vec::new(),
            nesting: 0,
            declared_signals,
        }
    }

    pub fn diags(&mut self) -> &mut Diagnostics<'s> {
        self.diags
    }

    /// Reports `message` at `span`, with the call site that led there, unless reported before.
    fn fail<T>(&mut self, span: Span, message: impl Into<String>) -> EResult<T> {
        let message = message.into();
        if !self.exhausted && self.reported.insert((span, message.clone())) {
            let call_site = self.calls.last().map(|c| self.diags.line_col(c.start as usize));
            let d = self.diags.error(span, message);
            if let Some((line, column)) = call_site {
                d.with_note(format!("in the call at {line}:{column}"));
            }
        }
        Err(Failed)
    }

    /// Pays `cost` units of work.
    fn charge(&mut self, cost: u64, span: Span) -> EResult<()> {
        if self.exhausted {
            return Err(Failed);
        }
        self.steps = self.steps.saturating_add(cost);
        if self.steps > MAX_STEPS {
            let result = self.fail(span, format!("evaluation takes more than {MAX_STEPS} steps"));
            self.exhausted = true;
            return result;
        }
        Ok(())
    }

    pub fn int(&mut self, e: &'a Expr) -> EResult<i64> {
        let v = self.eval(e)?;
        self.int_of(v, e.span)
    }

    pub fn formula(&mut self, e: &'a Expr) -> EResult<Formula> {
        let v = self.eval(e)?;
        self.formula_of(v, e.span)
    }

    fn int_of(&mut self, v: Value, span: Span) -> EResult<i64> {
        match v {
            Value::Int(n) => Ok(n),
            other => self.fail(span, format!("expected a number, found {}", describe(&other))),
        }
    }

    fn formula_of(&mut self, v: Value, span: Span) -> EResult<Formula> {
        match v {
            Value::Formula(f) => Ok(f),
            Value::Bus(_) => self.fail(span, "expected a formula, found a bus: index it, as in `r[i]`"),
            other => self.fail(span, format!("expected a formula, found {}", describe(&other))),
        }
    }

    fn set_of(&mut self, v: Value, span: Span) -> EResult<BTreeSet<i64>> {
        match v {
            Value::Set(s) => Ok(s),
            other => self.fail(span, format!("expected a set, found {}", describe(&other))),
        }
    }

    fn bool_of(&mut self, v: Value, span: Span) -> EResult<bool> {
        match v {
            Value::Formula(Formula { ltl: Ltl::True, .. }) => Ok(true),
            Value::Formula(Formula { ltl: Ltl::False, .. }) => Ok(false),
            other => self.fail(span, format!("expected a condition on numbers, found {}", describe(&other))),
        }
    }

    /// Evaluates `e`. Kept small: each arm calls out, so that the frame that recursion stacks
    /// up is this one's and not the sum of all arms'.
    pub fn eval(&mut self, e: &'a Expr) -> EResult<Value> {
        self.charge(1, e.span)?;
        if self.nesting >= MAX_EVAL_NESTING {
            return self.fail(e.span, format!("evaluation nests more than {MAX_EVAL_NESTING} levels deep"));
        }
        self.nesting += 1;
        let result = match &e.kind {
            ExprKind::Number(n) => Ok(Value::Int(*n)),
            ExprKind::True => Ok(Value::Formula(Formula::constant(true))),
            ExprKind::False => Ok(Value::Formula(Formula::constant(false))),
            ExprKind::Otherwise => self.fail(e.span, "`otherwise` stands only as the guard of a definition's case"),
            ExprKind::Name(name) => self.name(name, e.span),
            ExprKind::Index { bus, bus_span, index } => self.index(bus, *bus_span, index),
            ExprKind::Call { name, name_span, args } => self.call_expr(name, *name_span, args, e.span),
            ExprKind::Set(elements) => self.set(elements),
            ExprKind::Unary(op, operand) => self.unary(*op, operand, e.span),
            ExprKind::Binary(op, lhs, rhs) => self.binary(*op, lhs, rhs, e.span),
            ExprKind::Chain(junction, parts) => self.chain(*junction, parts, e.span),
            ExprKind::NextN { count, body } => self.next_n(count, body, e.span),
            ExprKind::Bounded { op, from, to, body } => self.bounded(*op, from, to, body, e.span),
            ExprKind::Big { op, binders, body } => self.big(*op, binders, body, e.span),
        };
        self.nesting -= 1;
        result
    }

    fn name(&mut self, name: &str, span: Span) -> EResult<Value> {
        if let Some(v) = self.local(name) {
            let v = v.clone();
            if let Value::Formula(f) = &v {
                self.charge(f.size, span)?;
            }
            return Ok(v);
        }
        match self.globals.get(name).copied() {
            Some(Global::Parameter(Some(n))) => Ok(Value::Int(n)),
            Some(Global::Parameter(None)) => {
                self.fail(span, format!("parameter `{name}` is used before its value is defined"))
            }
            Some(Global::Definition(d)) if d.params.is_empty() => self.call(d, Vec::new(), span),
            Some(Global::Definition(d)) => {
                self.fail(span, format!("`{name}` takes {} arguments: write `{name}(…)`", d.params.len()))
            }
            Some(Global::Signal(id)) => Ok(Value::Formula(Formula::signal(id))),
            Some(Global::Bus(bus)) => Ok(Value::Bus(bus)),
            None if self.declared_signals.contains(name) => {
                self.fail(span, format!("signal `{name}` cannot be used here: parameters and bus sizes are numbers"))
            }
            None => self.fail(span, format!("unknown name `{name}`")),
        }
    }

    fn local(&self, name: &str) -> Option<&Value> {
        self.locals[self.frame..].iter().rev().find(|(n, _)| *n == name).map(|(_, v)| v)
    }

    fn index(&mut self, bus: &str, bus_span: Span, index: &'a Expr) -> EResult<Value> {
        let found = match self.local(bus) {
            Some(Value::Bus(b)) => Some(*b),
            Some(_) => None,
            None => match self.globals.get(bus) {
                Some(Global::Bus(b)) => Some(*b),
                _ => None,
            },
        };
        let Some(b) = found else {
            return self.fail(bus_span, format!("`{bus}` is not a bus: only buses `{bus}[n]` are indexed"));
        };
        let i = self.int(index)?;
        if i < 0 || i >= i64::from(b.width) {
            return self.fail(index.span, format!("index {i} out of bounds: `{bus}` has signals 0 to {}", b.width - 1));
        }
        Ok(Value::Formula(Formula::signal(SignalId(b.first + i as u32))))
    }

    fn call_expr(&mut self, name: &str, name_span: Span, args: &'a [Expr], span: Span) -> EResult<Value> {
        let definition = match self.globals.get(name) {
            Some(Global::Definition(d)) => *d,
            _ => return self.fail(name_span, format!("`{name}` is not a function")),
        };
        if definition.params.len() != args.len() {
            let message = format!("`{name}` takes {} arguments, given {}", definition.params.len(), args.len());
            return self.fail(span, message);
        }
        let mut values = Vec::with_capacity(args.len());
        for a in args {
            values.push(self.eval(a)?);
        }
        self.call(definition, values, span)
    }

    /// Evaluates the first case of `definition` whose guard holds for `args`.
    fn call(&mut self, definition: &'a Definition, args: Vec<Value>, span: Span) -> EResult<Value> {
        if self.calls.len() >= MAX_CALL_DEPTH {
            let message = format!("recursion deeper than {MAX_CALL_DEPTH} calls (calling `{}`)", definition.name);
            return self.fail(span, message);
        }
        let outer_frame = std::mem::replace(&mut self.frame, self.locals.len());
        let shown_args: Vec<String> = args.iter().map(describe).collect();
        for ((name, _), value) in definition.params.iter().zip(args) {
            self.locals.push((name, value));
        }
        self.calls.push(span);
        let result = self.cases(definition, &shown_args, span);
        self.calls.pop();
        self.locals.truncate(self.frame);
        self.frame = outer_frame;
        result
    }

    fn cases(&mut self, definition: &'a Definition, shown_args: &[String], span: Span) -> EResult<Value> {
        for case in &definition.cases {
            let taken = match &case.guard {
                None => true,
                Some(Expr { kind: ExprKind::Otherwise, .. }) => true,
                Some(guard) => {
                    let v = self.eval(guard)?;
                    self.bool_of(v, guard.span)?
                }
            };
            if taken {
                return self.eval(&case.value);
            }
        }
        // Reported at the call, which the definition's author and the caller both can find.
        self.calls.pop();
        let message = format!("no case of `{}` applies to ({})", definition.name, shown_args.join(", "));
        let result = self.fail(span, message);
        self.calls.push(span);
        result
    }

    fn set(&mut self, elements: &'a [Expr]) -> EResult<Value> {
        let mut set = BTreeSet::new();
        for e in elements {
            set.insert(self.int(e)?);
        }
        Ok(Value::Set(set))
    }

    fn unary(&mut self, op: Unary, operand: &'a Expr, span: Span) -> EResult<Value> {
        let v = self.eval(operand)?;
        let make: fn(Ltl) -> Ltl = match op {
            Unary::Not => Ltl::not,
            Unary::Next => Ltl::next,
            Unary::Globally => Ltl::globally,
            Unary::Finally => Ltl::finally,
            Unary::SizeOf => {
                return match v {
                    Value::Bus(b) => Ok(Value::Int(i64::from(b.width))),
                    other => self.fail(operand.span, format!("`SIZEOF` takes a bus, found {}", describe(&other))),
                };
            }
            Unary::Size | Unary::Min | Unary::Max => {
                let set = self.set_of(v, operand.span)?;
                let n = match op {
                    Unary::Size => Some(set.len() as i64),
                    Unary::Min => set.first().copied(),
                    _ => set.last().copied(),
                };
                return match n {
                    Some(n) => Ok(Value::Int(n)),
                    None => self.fail(span, "`MIN` and `MAX` of the empty set are undefined"),
                };
            }
        };
        let f = self.formula_of(v, operand.span)?;
        Ok(Value::Formula(self.wrap(f, make, span)?))
    }

    /// `make(f)`, one level deeper than `f`.
    fn wrap(&mut self, f: Formula, make: fn(Ltl) -> Ltl, span: Span) -> EResult<Formula> {
        let depth = f.depth + 1;
        self.check_depth(depth, span)?;
        Ok(Formula { ltl: make(f.ltl), depth, size: f.size + 1 })
    }

    fn check_depth(&mut self, depth: usize, span: Span) -> EResult<()> {
        if depth > MAX_FORMULA_DEPTH {
            return self.fail(span, format!("formula nested deeper than {MAX_FORMULA_DEPTH} levels"));
        }
        Ok(())
    }

    fn binary(&mut self, op: Binary, lhs: &'a Expr, rhs: &'a Expr, span: Span) -> EResult<Value> {
        let a = self.eval(lhs)?;
        let b = self.eval(rhs)?;
        let temporal: fn(Ltl, Ltl) -> Ltl = match op {
            Binary::Mul | Binary::Div | Binary::Mod | Binary::Add | Binary::Sub => {
                let (x, y) = (self.int_of(a, lhs.span)?, self.int_of(b, rhs.span)?);
                return self.arithmetic(op, x, y, rhs.span, span).map(Value::Int);
            }
            Binary::Lt | Binary::Le | Binary::Gt | Binary::Ge => {
                let (x, y) = (self.int_of(a, lhs.span)?, self.int_of(b, rhs.span)?);
                let holds = match op {
                    Binary::Lt => x < y,
                    Binary::Le => x <= y,
                    Binary::Gt => x > y,
                    _ => x >= y,
                };
                return Ok(Value::Formula(Formula::constant(holds)));
            }
            Binary::Eq | Binary::Ne => {
                if std::mem::discriminant(&a) != std::mem::discriminant(&b) {
                    let message = format!("cannot compare {} with {}", describe(&a), describe(&b));
                    return self.fail(span, message);
                }
                return Ok(Value::Formula(Formula::constant((a == b) == (op == Binary::Eq))));
            }
            Binary::In => {
                let x = self.int_of(a, lhs.span)?;
                let set = self.set_of(b, rhs.span)?;
                return Ok(Value::Formula(Formula::constant(set.contains(&x))));
            }
            Binary::SetMinus | Binary::Cap | Binary::Cup => {
                let (x, y) = (self.set_of(a, lhs.span)?, self.set_of(b, rhs.span)?);
                self.charge((x.len() + y.len()) as u64, span)?;
                let mut set = BTreeSet::new();
                match op {
                    Binary::SetMinus => set.extend(x.difference(&y)),
                    Binary::Cap => set.extend(x.intersection(&y)),
                    _ => set.extend(x.union(&y)),
                }
                return Ok(Value::Set(set));
            }
            Binary::Implies => Ltl::implies,
            Binary::Iff => Ltl::iff,
            Binary::WeakUntil => Ltl::weak_until,
            Binary::Until => Ltl::until,
            Binary::Release => Ltl::release,
        };
        let (f, g) = (self.formula_of(a, lhs.span)?, self.formula_of(b, rhs.span)?);
        let depth = f.depth.max(g.depth) + 1;
        self.check_depth(depth, span)?;
        Ok(Value::Formula(Formula { ltl: temporal(f.ltl, g.ltl), depth, size: f.size + g.size + 1 }))
    }

    /// Integer arithmetic as SyfCo's (Haskell's `div` and `mod` round towards −∞), checked.
    fn arithmetic(&mut self, op: Binary, x: i64, y: i64, rhs: Span, span: Span) -> EResult<i64> {
        if matches!(op, Binary::Div | Binary::Mod) && y == 0 {
            return self.fail(rhs, "division by zero");
        }
        let result = match op {
            Binary::Add => x.checked_add(y),
            Binary::Sub => x.checked_sub(y),
            Binary::Mul => x.checked_mul(y),
            Binary::Div => x.checked_div(y).map(|q| if (x % y != 0) && ((x < 0) != (y < 0)) { q - 1 } else { q }),
            _ => x.checked_rem(y).map(|r| if r != 0 && ((r < 0) != (y < 0)) { r + y } else { r }),
        };
        match result {
            Some(n) => Ok(n),
            None => self.fail(span, "arithmetic overflow: the result does not fit in 64 bits"),
        }
    }

    fn chain(&mut self, junction: Junction, parts: &'a [Expr], span: Span) -> EResult<Value> {
        let mut formulas = Vec::with_capacity(parts.len());
        for p in parts {
            formulas.push(self.formula(p)?);
        }
        Ok(Value::Formula(self.junction(junction, formulas, span)?))
    }

    /// The conjunction or disjunction of `parts` (`true`/`false` when empty, the part itself
    /// when single).
    fn junction(&mut self, junction: Junction, parts: Vec<Formula>, span: Span) -> EResult<Formula> {
        let depth = match parts.len() {
            0 => 1,
            1 => parts[0].depth,
            _ => parts.iter().map(|f| f.depth).max().unwrap_or(0) + 1,
        };
        self.check_depth(depth, span)?;
        let size = parts.iter().map(|f| f.size).sum::<u64>() + 1;
        let ltls = parts.into_iter().map(|f| f.ltl).collect();
        let ltl = match junction {
            Junction::And => Ltl::all(ltls),
            Junction::Or => Ltl::any(ltls),
        };
        Ok(Formula { ltl, depth, size })
    }

    fn count(&mut self, e: &'a Expr, what: &str) -> EResult<usize> {
        let n = self.int(e)?;
        if n < 0 {
            return self.fail(e.span, format!("{what} must not be negative, found {n}"));
        }
        if n as u64 > MAX_FORMULA_DEPTH as u64 {
            return self.fail(e.span, format!("{what} {n} nests the formula deeper than {MAX_FORMULA_DEPTH} levels"));
        }
        Ok(n as usize)
    }

    /// `X[n] φ`: n nested `X`.
    fn next_n(&mut self, count: &'a Expr, body: &'a Expr, span: Span) -> EResult<Value> {
        let n = self.count(count, "the number of steps")?;
        let mut f = self.formula(body)?;
        for _ in 0..n {
            f = self.wrap(f, Ltl::next, span)?;
        }
        Ok(Value::Formula(f))
    }

    /// `F[a:b] φ` = `X^a (φ || X (φ || … X φ))` with b − a nested `X` inside, `G[a:b]` the same
    /// with `&&`; empty (`true`) when a > b, as SyfCo expands them.
    fn bounded(&mut self, op: BoundedOp, from: &'a Expr, to: &'a Expr, body: &'a Expr, span: Span) -> EResult<Value> {
        let a = self.count(from, "the lower bound")?;
        let b = self.count(to, "the upper bound")?;
        if a > b {
            return Ok(Value::Formula(Formula::constant(true)));
        }
        let f = self.formula(body)?;
        self.check_depth(f.depth + a + 2 * (b - a), span)?;
        self.charge(f.size.saturating_mul((b - a) as u64 + 1), span)?;
        let junction = if op == BoundedOp::Finally { Junction::Or } else { Junction::And };
        let mut expansion = f.clone();
        for _ in a..b {
            let later = self.wrap(expansion, Ltl::next, span)?;
            expansion = self.junction(junction, vec![f.clone(), later], span)?;
        }
        for _ in 0..a {
            expansion = self.wrap(expansion, Ltl::next, span)?;
        }
        Ok(Value::Formula(expansion))
    }

    fn big(&mut self, op: BigOp, binders: &'a [Binder], body: &'a Expr, span: Span) -> EResult<Value> {
        let mut values = Vec::new();
        self.bind_all(binders, body, &mut values)?;
        match op {
            BigOp::And | BigOp::Or => {
                let mut formulas = Vec::with_capacity(values.len());
                for v in values {
                    formulas.push(self.formula_of(v, body.span)?);
                }
                let junction = if op == BigOp::And { Junction::And } else { Junction::Or };
                Ok(Value::Formula(self.junction(junction, formulas, span)?))
            }
            BigOp::Sum | BigOp::Prod => {
                let mut total: i64 = if op == BigOp::Sum { 0 } else { 1 };
                for v in values {
                    let n = self.int_of(v, body.span)?;
                    let arithmetic = if op == BigOp::Sum { Binary::Add } else { Binary::Mul };
                    total = self.arithmetic(arithmetic, total, n, body.span, span)?;
                }
                Ok(Value::Int(total))
            }
        }
    }

    /// Evaluates `body` for every value of the first binder (ascending), binding the rest
    /// inside, and collects the results in `out`.
    fn bind_all(&mut self, binders: &'a [Binder], body: &'a Expr, out: &mut Vec<Value>) -> EResult<()> {
        let Some((binder, rest)) = binders.split_first() else {
            out.push(self.eval(body)?);
            return Ok(());
        };
        let domain: Box<dyn Iterator<Item = i64>> = match &binder.domain {
            Domain::Range { from, from_strict, to, to_strict } => {
                let lo = self.int(from)?.saturating_add(i64::from(*from_strict));
                let hi = self.int(to)?.saturating_sub(i64::from(*to_strict));
                Box::new(lo..=hi)
            }
            Domain::Set(set) => {
                let v = self.eval(set)?;
                Box::new(self.set_of(v, set.span)?.into_iter())
            }
        };
        for value in domain {
            self.charge(1, binder.span)?;
            self.locals.push((&binder.var, Value::Int(value)));
            let result = self.bind_all(rest, body, out);
            self.locals.pop();
            result?;
        }
        Ok(())
    }
}

/// A value as an error message names it.
fn describe(v: &Value) -> String {
    match v {
        Value::Int(n) => format!("the number {n}"),
        Value::Formula(Formula { ltl: Ltl::True, .. }) => "`true`".into(),
        Value::Formula(Formula { ltl: Ltl::False, .. }) => "`false`".into(),
        Value::Formula(_) => "a formula over signals".into(),
        Value::Set(_) => "a set".into(),
        Value::Bus(b) => format!("a bus of {} signals", b.width),
    }
}
