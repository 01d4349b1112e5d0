//! The jump-list view of a unit, which Instruction List and S7 STL print in the layout of Peter
//! 2005, 6.7.2: one function block that runs a [`StepList`] over BOOL inputs and outputs and
//! on-delay timers, and a program that calls it once per scan and wires it. [`StepBlock::of`]
//! reads that shape from a [`Unit`] or says why the unit does not have it.
//!
//! The block's body before its step list may clear pulsed outputs (`out := FALSE`, after
//! keeping the value of the last write, `last := out`) and call its timers with `IN := TRUE`;
//! the steps test inputs, those memories and a timer's `ET` against a constant, drive outputs
//! to a constant and restart timers (`IN := FALSE`).

use crate::plc::model::unit::{BinOp, Expr, Location, Next, Place, Pou, PouKind, StepList, Stmt, Type, Unit, Var};

/// Where the program wires a variable of the block.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(in crate::plc) enum Wire<'u> {
    /// A global of the unit at a direct address (IEC form without `%`), and its name.
    Address { name: &'u str, address: &'u str },
    /// A symbol of the project (a signal of the unit), as the project writes it.
    Symbol(&'u str),
    /// A global the PLC tool maps, or nothing: the block's own interface.
    Unbound,
}

/// A bit a step tests.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(in crate::plc) enum Bit {
    Input(usize),
    /// The value output `k` had at the last output write.
    Last(usize),
}

/// A condition of a step.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(in crate::plc) enum Cond {
    Bit {
        bit: Bit,
        negated: bool,
    },
    /// Timer `timer` has run at least `ms` (more than `ms` when `strict`).
    Elapsed {
        timer: usize,
        ms: u64,
        strict: bool,
    },
}

/// What a step does.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(in crate::plc) enum Action {
    Drive { output: usize, value: bool },
    Restart { timer: usize },
}

/// How the jump-list dialects write a drive of an output: a pulsed output (cleared at the
/// start of every scan) is assigned its level; a latched one is set or reset.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(in crate::plc) enum Drive {
    Assign(bool),
    Set,
    Reset,
}

/// One step, decoded.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(in crate::plc) struct StepView<'u> {
    pub comment: &'u str,
    pub wait: Option<Cond>,
    pub when: Option<Cond>,
    pub actions: Vec<Action>,
    pub next: Next,
}

/// A timer of the block.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(in crate::plc) struct TimerView<'u> {
    pub var: &'u Var,
    /// The preset of its call at the start of every scan.
    pub preset_ms: u64,
}

/// A unit in the jump-list shape.
#[derive(Clone, Debug)]
pub(in crate::plc) struct StepBlock<'u> {
    pub unit: &'u Unit,
    pub block: &'u Pou,
    pub program: &'u Pou,
    pub instance: &'u str,
    /// Per input, then per output of the block: where the program wires it.
    pub wires: Vec<Wire<'u>>,
    /// Per output: cleared at the start of every scan.
    pub pulsed: Vec<bool>,
    /// Per output: the local that keeps its value at the last output write.
    pub last: Vec<Option<&'u str>>,
    pub timers: Vec<TimerView<'u>>,
    pub list: &'u StepList,
    pub steps: Vec<StepView<'u>>,
}

impl<'u> StepBlock<'u> {
    /// The jump-list view of `unit`, or why it has not that shape.
    pub fn of(unit: &'u Unit) -> Result<StepBlock<'u>, String> {
        let [block, program] = unit.pous.as_slice() else {
            return Err("the jump-list form takes one function block and the program that calls it".into());
        };
        if block.kind != PouKind::FunctionBlock || program.kind != PouKind::Program {
            return Err("the jump-list form takes one function block and the program that calls it".into());
        }
        let bools = block.inputs.iter().chain(&block.outputs).all(|v| v.ty == Type::Bool);
        if !bools {
            return Err("the jump-list form takes BOOL inputs and outputs only".into());
        }
        let input = |name: &str| block.inputs.iter().position(|v| v.name == name);
        let output = |name: &str| block.outputs.iter().position(|v| v.name == name);
        let timer_var = |name: &str| block.locals.iter().find(|v| v.name == name && v.ty == Type::Ton);
        let mut pulsed = vec![false; block.outputs.len()];
        let mut last: Vec<Option<&str>> = vec![None; block.outputs.len()];
        let mut timers: Vec<TimerView> = Vec::new();
        let mut list = None;
        for s in &block.body {
            match s {
                Stmt::Comment(_) => {}
                _ if list.is_some() => return Err("the jump-list form ends its block with the step list".into()),
                Stmt::Assign { target: Place::Local(t), value: Expr::Read(Place::Local(o)) } if output(o).is_some() => {
                    last[output(o).expect("just checked")] = Some(t.as_str());
                }
                Stmt::Assign { target: Place::Local(o), value: Expr::Bool(false) } if output(o).is_some() => {
                    pulsed[output(o).expect("just checked")] = true;
                }
                Stmt::CallInstance { instance: Place::Local(t), args } if timer_var(t).is_some() => {
                    let preset = match args.as_slice() {
                        [(i, Expr::Bool(true)), (p, Expr::Time(ms))] if i == "IN" && p == "PT" => *ms,
                        _ => return Err(format!("timer `{t}` is called other than with IN := TRUE and a preset")),
                    };
                    timers.push(TimerView { var: timer_var(t).expect("just checked"), preset_ms: preset });
                }
                Stmt::Steps(l) => list = Some(l),
                other => return Err(format!("the jump-list form cannot hold {other:?} before the step list")),
            }
        }
        let Some(list) = list else { return Err("the block has no step list".into()) };
        let timer = |name: &str| timers.iter().position(|t| t.var.name == name);
        let bit = |name: &str| {
            input(name).map(Bit::Input).or_else(|| last.iter().position(|l| *l == Some(name)).map(Bit::Last))
        };
        let cond = |e: &Expr| -> Result<Cond, String> {
            let (e, negated) = match e {
                Expr::Not(inner) => (inner.as_ref(), true),
                e => (e, false),
            };
            match e {
                Expr::Read(Place::Local(n)) if bit(n).is_some() => {
                    Ok(Cond::Bit { bit: bit(n).expect("just checked"), negated })
                }
                Expr::Binary(op @ (BinOp::Ge | BinOp::Gt), a, b) if !negated => match (a.as_ref(), b.as_ref()) {
                    (Expr::Read(Place::Member(t, f)), Expr::Time(ms)) if f == "ET" => match t.as_ref() {
                        Place::Local(t) if timer(t).is_some() => Ok(Cond::Elapsed {
                            timer: timer(t).expect("just checked"),
                            ms: *ms,
                            strict: *op == BinOp::Gt,
                        }),
                        _ => Err(format!("the jump-list form tests the ET of its timers only: {e:?}")),
                    },
                    _ => Err(format!("the jump-list form compares a timer's ET with a constant only: {e:?}")),
                },
                _ => Err(format!("the jump-list form tests inputs and timers only: {e:?}")),
            }
        };
        let action = |s: &Stmt| -> Result<Action, String> {
            match s {
                Stmt::Assign { target: Place::Local(o), value: Expr::Bool(value) } if output(o).is_some() => {
                    Ok(Action::Drive { output: output(o).expect("just checked"), value: *value })
                }
                Stmt::CallInstance { instance: Place::Local(t), args }
                    if timer(t).is_some() && args.iter().any(|(p, v)| p == "IN" && *v == Expr::Bool(false)) =>
                {
                    Ok(Action::Restart { timer: timer(t).expect("just checked") })
                }
                other => Err(format!("the jump-list form drives outputs and restarts timers only: {other:?}")),
            }
        };
        let mut steps = Vec::new();
        for s in &list.steps {
            let actions = s.actions.iter().filter(|a| !matches!(a, Stmt::Comment(_))).map(action);
            steps.push(StepView {
                comment: &s.comment,
                wait: s.wait.as_ref().map(cond).transpose()?,
                when: s.when.as_ref().map(cond).transpose()?,
                actions: actions.collect::<Result<_, _>>()?,
                next: s.next,
            });
        }
        let (instance, wires) = wiring(unit, block, program)?;
        Ok(StepBlock { unit, block, program, instance, wires, pulsed, last, timers, list, steps })
    }

    /// How an [`Action::Drive`] of `output` to `value` is written.
    pub fn drive(&self, output: usize, value: bool) -> Drive {
        match (self.pulsed[output], value) {
            (true, level) => Drive::Assign(level),
            (false, true) => Drive::Set,
            (false, false) => Drive::Reset,
        }
    }

    /// The names of the block's inputs, then of its outputs.
    pub fn variables(&self) -> impl Iterator<Item = &'u Var> {
        self.block.inputs.iter().chain(&self.block.outputs)
    }

    /// For every step, whether some transfer other than falling through reaches it.
    pub fn jumped_to(&self) -> Vec<bool> {
        let n = self.steps.len();
        let mut v = vec![false; n];
        for (i, s) in self.steps.iter().enumerate() {
            if let Next::Continue(k) = s.next {
                if k < n && (k != i + 1 || s.when.is_some()) {
                    v[k] = true;
                }
            }
        }
        v
    }

    /// Steps where a scan may start: step 0, every step that waits, and where a scan that
    /// ends resumes.
    pub fn resume_points(&self) -> Vec<bool> {
        let mut resume = vec![false; self.steps.len().max(1)];
        resume[0] = true;
        for (i, s) in self.steps.iter().enumerate() {
            if s.wait.is_some() {
                resume[i] = true;
            }
            if let Next::Resume(k) = s.next {
                if k < resume.len() {
                    resume[k] = true;
                }
            }
        }
        resume
    }
}

/// The instance the program calls and where it wires each variable of the block.
fn wiring<'u>(unit: &'u Unit, block: &'u Pou, program: &'u Pou) -> Result<(&'u str, Vec<Wire<'u>>), String> {
    let wire = |place: &'u Place| -> Result<Wire<'u>, String> {
        match place {
            Place::Signal(k) => unit.signals.get(*k).map(|s| Wire::Symbol(&s.symbol)).ok_or("no such signal".into()),
            Place::Global(name) => match unit.globals.iter().find(|g| &g.name == name).and_then(|g| g.at.as_ref()) {
                Some(Location::Address(address)) => Ok(Wire::Address { name, address }),
                Some(Location::Mapped(_)) => Ok(Wire::Unbound),
                None => Err(format!("the program wires `{name}`, a global not on the process image")),
            },
            other => Err(format!("the program wires {other:?}")),
        }
    };
    let mut wires = vec![Wire::Unbound; block.inputs.len() + block.outputs.len()];
    let mut instance = None;
    for s in &program.body {
        match s {
            Stmt::Comment(_) => {}
            Stmt::CallInstance { instance: Place::Local(name), args } if instance.is_none() => {
                let declared =
                    program.locals.iter().any(|v| &v.name == name && v.ty == Type::Instance(block.name.clone()));
                if !declared {
                    return Err(format!("the program calls `{name}`, not an instance of `{}`", block.name));
                }
                instance = Some(name.as_str());
                for (param, value) in args {
                    let Some(k) = block.inputs.iter().position(|v| &v.name == param) else {
                        return Err(format!("`{}` has no input `{param}`", block.name));
                    };
                    match value {
                        Expr::Read(place) => wires[k] = wire(place)?,
                        Expr::Bool(false) => {}
                        other => return Err(format!("the program passes {other:?} to `{param}`")),
                    }
                }
            }
            Stmt::Assign { target, value: Expr::Read(Place::Member(base, field)) }
                if instance.is_some() && **base == Place::local(instance.unwrap_or_default()) =>
            {
                let Some(k) = block.outputs.iter().position(|v| &v.name == field) else {
                    return Err(format!("`{}` has no output `{field}`", block.name));
                };
                wires[block.inputs.len() + k] = wire(target)?;
            }
            other => {
                return Err(format!(
                    "the jump-list form's program only calls the block and copies its outputs: {other:?}"
                ))
            }
        }
    }
    let instance = instance.ok_or_else(|| format!("the program does not call `{}`", block.name))?;
    Ok((instance, wires))
}
