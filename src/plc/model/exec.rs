//! A reference interpreter of [`Unit`]s: runs the structured code model as a PLC would, cycle by
//! cycle, on a virtual clock. It is the semantics the printers must keep (their output is run in
//! an emulator and compared with it) and lets a lowering be checked against its engine without
//! any printer: what the lowering means is what this interpreter does.
//!
//! Integers are stored wrapped to their declared width (`INT` 16 bits, `DINT` 32 bits), as a PLC
//! stores them; arithmetic is exact in between, or, in [`Arithmetic::Accumulator`], wraps after
//! every operation as an S7 CPU's accumulator does. `REAL` values are `f32` and every operation is
//! computed in `f32` (as an S7 CPU does, so results agree bit for bit with awlsim), a subnormal
//! result flushed to 0.0 as S7 does; an operation that mixes `REAL` with an integer, or a store
//! of one into the other, is an error (IEC converts only explicitly). A `TON` is on-delay: `Q` rises once `IN` has been
//! TRUE for `PT` on the virtual clock (`ET` counts up to `PT`), and a call with `IN` FALSE
//! resets it. Function locals start from their defaults on every call; program and function
//! block locals keep their values. An instance of a function block the unit defines has its own
//! variables, runs the block's body when called and shows its inputs and outputs as members
//! (`ctrl.grant`); an instance of a block the unit does not define is the user's controller.
//! Division by zero and unknown names are errors, not panics.

use crate::plc::fragment::BinOp;
use crate::plc::model::unit::{Expr, Next, Place, Pou, PouKind, StepList, Stmt, Type, Unit, Var};
use hashbrown::HashMap;

/// A value of the model's elementary types.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Value {
    Bool(bool),
    Int(i64),
    Real(f32),
    /// Milliseconds.
    Time(i64),
}

impl Value {
    pub fn as_bool(self) -> bool {
        match self {
            Value::Bool(b) => b,
            Value::Int(v) | Value::Time(v) => v != 0,
            Value::Real(v) => v != 0.0,
        }
    }

    pub fn as_int(self) -> i64 {
        match self {
            Value::Bool(b) => i64::from(b),
            Value::Int(v) | Value::Time(v) => v,
            // Truncated; only for CASE selectors and presets, which a checked unit never makes REAL.
            Value::Real(v) => v as i64,
        }
    }

    /// The value as a REAL (an integer converted, as `set_signal` accepts it).
    pub fn as_real(self) -> f32 {
        match self {
            Value::Real(v) => v,
            other => other.as_int() as f32,
        }
    }

    /// The default value of `ty` (FALSE, 0, T#0s).
    pub fn default_of(ty: &Type) -> Value {
        match ty {
            Type::Bool => Value::Bool(false),
            Type::Time => Value::Time(0),
            Type::Real => Value::Real(0.0),
            _ => Value::Int(0),
        }
    }

    /// The value as stored in a variable of type `ty`: integers wrap to the type's width.
    fn stored_as(self, ty: &Type) -> Value {
        match ty {
            Type::Bool => Value::Bool(self.as_bool()),
            Type::Int => Value::Int(i64::from(self.as_int() as i16)),
            Type::Dint => Value::Int(i64::from(self.as_int() as i32)),
            Type::Time => Value::Time(i64::from(self.as_int() as i32)),
            Type::Real => Value::Real(self.as_real()),
            Type::Ton | Type::Instance(_) => self,
        }
    }
}

/// `v` stored into `name` of type `ty`, or an error when one of them is REAL and the other
/// is not (an integer and a REAL never convert implicitly).
fn convert(v: Value, ty: &Type, name: &str) -> Result<Value> {
    let scalar = matches!(ty, Type::Bool | Type::Int | Type::Dint | Type::Time | Type::Real);
    if scalar && matches!(v, Value::Real(_)) != (*ty == Type::Real) {
        let (to, from) = if *ty == Type::Real { ("REAL", "an integer or BOOL") } else { ("not REAL", "REAL") };
        return err(format!("`{name}` ({to}) gets a value of type {from}: IEC needs an explicit conversion"));
    }
    Ok(v.stored_as(ty))
}

/// Stores `v` into local `name` of `frame`.
fn set_local(frame: &mut Frame, name: &str, v: Value) -> Result<()> {
    match (frame.types.get(name), frame.values.get_mut(name)) {
        (Some(ty), Some(slot)) => {
            *slot = convert(v, ty, name)?;
            Ok(())
        }
        _ => err(format!("no local `{name}`")),
    }
}

/// A REAL result as an S7 CPU keeps it: a subnormal becomes 0.0.
fn s7_real(v: f32) -> Value {
    Value::Real(if v.is_subnormal() { 0.0 } else { v })
}

/// How integer operations treat the width of their operands.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Arithmetic {
    /// Exact in between, wrapped to the declared width only when stored.
    #[default]
    Exact,
    /// Every arithmetic operation (`+ - * / MOD`, negation) wraps its result at its operands'
    /// width, as an S7 CPU's accumulator instructions do and as the STL printer's code computes
    /// (`plc::print::stl::unit`): 16 bits when both sides are INT, 32 bits when one is DINT or
    /// TIME; an integer literal is INT when it fits in 16 bits.
    Accumulator,
}

/// The width an integer operation works in under [`Arithmetic::Accumulator`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
enum Width {
    W16,
    W32,
}

impl Width {
    fn of(ty: &Type) -> Width {
        if *ty == Type::Int {
            Width::W16
        } else {
            Width::W32
        }
    }

    fn wrap(self, v: i64) -> i64 {
        match self {
            Width::W16 => i64::from(v as i16),
            Width::W32 => i64::from(v as i32),
        }
    }
}

/// Why the interpreter stopped.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ExecError(pub String);

type Result<T> = std::result::Result<T, ExecError>;

fn err<T>(message: impl Into<String>) -> Result<T> {
    Err(ExecError(message.into()))
}

/// The state of one on-delay timer.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
struct Ton {
    input: bool,
    since_ms: u64,
    preset_ms: u64,
}

/// The variables of one running POU.
#[derive(Default)]
struct Frame {
    values: HashMap<String, Value>,
    types: HashMap<String, Type>,
    timers: HashMap<String, Ton>,
    /// Instances of the unit's function blocks, each with its own variables.
    instances: HashMap<String, Frame>,
}

impl Frame {
    fn declare(&mut self, v: &Var, initial: Option<Value>) {
        self.types.insert(v.name.clone(), v.ty.clone());
        match v.ty {
            Type::Ton => {
                self.timers.insert(v.name.clone(), Ton::default());
            }
            // Instances of the unit's blocks get their frame from `Machine::declare`.
            Type::Instance(_) => {}
            _ => {
                let value = initial.unwrap_or_else(|| Value::default_of(&v.ty)).stored_as(&v.ty);
                self.values.insert(v.name.clone(), value);
            }
        }
    }
}

/// What the user's controller does when the program calls it: it may read and write signals
/// and call the unit's functions through the machine.
pub type Controller<'c> = dyn FnMut(&mut Machine<'_>) -> Result<()> + 'c;

/// A PLC running a unit: globals, signals, the program's static variables and a virtual clock.
pub struct Machine<'u> {
    unit: &'u Unit,
    globals: Frame,
    signals: Vec<Value>,
    program: Frame,
    now_ms: u64,
    /// Calls made so far in the current cycle: a bound on runaway code.
    steps: u64,
    arithmetic: Arithmetic,
}

/// Statements one cycle may execute before it counts as a hang.
const MAX_STEPS_PER_CYCLE: u64 = 10_000_000;

impl<'u> Machine<'u> {
    /// The unit after a cold start: every variable at its initial value, signals at their
    /// defaults, the clock at 0.
    pub fn new(unit: &'u Unit) -> Result<Machine<'u>> {
        let mut m = Machine {
            unit,
            globals: Frame::default(),
            signals: unit.signals.iter().map(|s| Value::default_of(&s.ty)).collect(),
            program: Frame::default(),
            now_ms: 0,
            steps: 0,
            arithmetic: Arithmetic::Exact,
        };
        let mut globals = Frame::default();
        for v in unit.constants.iter().chain(&unit.globals) {
            m.declare(&mut globals, v, 0)?;
        }
        m.globals = globals;
        let program = m.program_pou()?;
        let mut frame = Frame::default();
        for v in program.inputs.iter().chain(&program.outputs).chain(&program.locals) {
            m.declare(&mut frame, v, 0)?;
        }
        m.program = frame;
        Ok(m)
    }

    /// Declares `v` in `frame` at its initial value; an instance of one of the unit's function
    /// blocks gets a frame of its own (`depth` counts the blocks declared around it, so that a
    /// block containing an instance of itself is an error rather than a stack overflow).
    fn declare(&self, frame: &mut Frame, v: &Var, depth: usize) -> Result<()> {
        let initial = match &v.init {
            Some(e) => Some(self.eval(e, &mut Frame::default())?),
            None => None,
        };
        frame.declare(v, initial);
        if let Some(block) = self.function_block(&v.ty) {
            if depth > self.unit.pous.len() {
                return err(format!("function block `{}` contains an instance of itself", block.name));
            }
            let mut own = Frame::default();
            for w in block.inputs.iter().chain(&block.outputs).chain(&block.locals) {
                self.declare(&mut own, w, depth + 1)?;
            }
            frame.instances.insert(v.name.clone(), own);
        }
        Ok(())
    }

    /// The function block of the unit that `ty` is an instance of.
    fn function_block(&self, ty: &Type) -> Option<&'u Pou> {
        match ty {
            Type::Instance(name) => self.unit.pou(name).filter(|p| p.kind == PouKind::FunctionBlock),
            _ => None,
        }
    }

    fn program_pou(&self) -> Result<&'u Pou> {
        match self.unit.pous.iter().find(|p| p.kind == PouKind::Program) {
            Some(p) => Ok(p),
            None => err("the unit has no program"),
        }
    }

    /// Lets `ms` pass on the virtual clock.
    pub fn advance(&mut self, ms: u64) {
        self.now_ms += ms;
    }

    pub fn signal(&self, k: usize) -> Value {
        self.signals[k]
    }

    /// Sets signal `k` (an input before a cycle, or an output the controller writes).
    pub fn set_signal(&mut self, k: usize, value: Value) {
        self.signals[k] = value.stored_as(&self.unit.signals[k].ty);
    }

    /// The value of global or constant `name`.
    pub fn global(&self, name: &str) -> Option<Value> {
        self.globals.values.get(name).copied()
    }

    /// Sets global `name` (an input the tool maps, before a cycle).
    pub fn set_global(&mut self, name: &str, value: Value) -> Result<()> {
        if self.unit.constants.iter().any(|c| c.name == name) {
            return err(format!("`{name}` is a constant"));
        }
        match (self.globals.types.get(name), self.globals.values.get_mut(name)) {
            (Some(ty), Some(slot)) => {
                *slot = convert(value, ty, name)?;
                Ok(())
            }
            _ => err(format!("no global `{name}`")),
        }
    }

    /// The value of the program's variable `name` (an input, output or static).
    pub fn program_value(&self, name: &str) -> Option<Value> {
        self.program.values.get(name).copied()
    }

    /// Sets how integer operations treat widths from now on ([`Arithmetic::Exact`] at first).
    pub fn set_arithmetic(&mut self, arithmetic: Arithmetic) {
        self.arithmetic = arithmetic;
    }

    /// The value of variable `field` (an input, output or static) of `instance`, an instance of
    /// one of the unit's function blocks declared in the program.
    pub fn instance_value(&self, instance: &str, field: &str) -> Option<Value> {
        self.program.instances.get(instance)?.values.get(field).copied()
    }

    /// One PLC cycle: runs the program; its call of the controller instance runs `controller`.
    pub fn cycle(&mut self, controller: &mut Controller<'_>) -> Result<()> {
        self.steps = 0;
        let program = self.program_pou()?;
        let mut frame = std::mem::take(&mut self.program);
        let result = self.stmts(&program.body, &mut frame, &mut Some(controller));
        self.program = frame;
        result
    }

    /// Calls function `name` of the unit with named arguments (as the controller does for an
    /// executed event) and returns its result (FALSE for a function without one).
    pub fn call(&mut self, name: &str, args: &[(&str, Value)]) -> Result<Value> {
        let Some(pou) = self.unit.pou(name) else { return err(format!("no function `{name}`")) };
        let PouKind::Function { returns } = &pou.kind else { return err(format!("`{name}` is not a function")) };
        let mut frame = Frame::default();
        for v in pou.inputs.iter().chain(&pou.outputs).chain(&pou.locals) {
            self.declare(&mut frame, v, 0)?;
        }
        let result_type = returns.clone().unwrap_or(Type::Bool);
        frame.declare(&Var::new(name, result_type, ""), None);
        for (param, value) in args {
            let Some(ty) = pou.inputs.iter().find(|v| v.name == *param).map(|v| v.ty.clone()) else {
                return err(format!("`{name}` has no input `{param}`"));
            };
            frame.values.insert(param.to_string(), convert(*value, &ty, param)?);
        }
        self.stmts(&pou.body, &mut frame, &mut None)?;
        Ok(frame.values[name])
    }

    fn tick(&mut self) -> Result<()> {
        self.steps += 1;
        if self.steps > MAX_STEPS_PER_CYCLE {
            return err("the cycle does not end (more than 10^7 statements)");
        }
        Ok(())
    }

    fn stmts(&mut self, list: &[Stmt], frame: &mut Frame, controller: &mut Option<&mut Controller<'_>>) -> Result<()> {
        for s in list {
            self.stmt(s, frame, controller)?;
        }
        Ok(())
    }

    fn stmt(&mut self, s: &Stmt, frame: &mut Frame, controller: &mut Option<&mut Controller<'_>>) -> Result<()> {
        self.tick()?;
        match s {
            Stmt::Comment(_) => Ok(()),
            Stmt::Assign { target, value } => {
                let v = self.eval(value, frame)?;
                self.store(target, v, frame)
            }
            Stmt::If { arms, otherwise } => {
                for (cond, body) in arms {
                    if self.eval(cond, frame)?.as_bool() {
                        return self.stmts(body, frame, controller);
                    }
                }
                self.stmts(otherwise, frame, controller)
            }
            Stmt::Case { selector, arms, otherwise } => {
                let v = self.eval(selector, frame)?.as_int();
                match arms.iter().find(|(labels, _)| labels.contains(&v)) {
                    Some((_, body)) => self.stmts(body, frame, controller),
                    None => self.stmts(otherwise, frame, controller),
                }
            }
            Stmt::CallFunction { function, args, result } => {
                let mut values = Vec::new();
                for (name, e) in args {
                    values.push((name.as_str(), self.eval(e, frame)?));
                }
                let v = self.call(function, &values)?;
                match result {
                    Some(place) => self.store(place, v, frame),
                    None => Ok(()),
                }
            }
            Stmt::CallInstance { instance, args } => {
                let Place::Local(name) = instance else { return err("only local instances can be called") };
                match frame.types.get(name) {
                    Some(Type::Ton) => {
                        let mut input = None;
                        let mut preset = None;
                        for (param, e) in args {
                            let v = self.eval(e, frame)?;
                            match param.as_str() {
                                "IN" => input = Some(v.as_bool()),
                                "PT" => preset = Some(v.as_int().max(0) as u64),
                                other => return err(format!("TON has no input `{other}`")),
                            }
                        }
                        let now = self.now_ms;
                        let Some(t) = frame.timers.get_mut(name) else { return err(format!("no timer `{name}`")) };
                        if let Some(p) = preset {
                            t.preset_ms = p;
                        }
                        if let Some(i) = input {
                            if i && !t.input {
                                t.since_ms = now;
                            }
                            t.input = i;
                        }
                        Ok(())
                    }
                    Some(ty @ Type::Instance(_)) if self.function_block(ty).is_some() => {
                        let block = self.function_block(ty).expect("just checked");
                        let mut values = Vec::with_capacity(args.len());
                        for (param, e) in args {
                            let Some(input) = block.inputs.iter().find(|v| v.name == *param) else {
                                return err(format!("`{}` has no input `{param}`", block.name));
                            };
                            values.push((param, convert(self.eval(e, frame)?, &input.ty, param)?));
                        }
                        let Some(own) = frame.instances.get_mut(name) else {
                            return err(format!("instance `{name}` has no variables"));
                        };
                        let mut own = std::mem::take(own);
                        for (param, value) in values {
                            if let Some(slot) = own.values.get_mut(param) {
                                *slot = value;
                            }
                        }
                        let result = self.stmts(&block.body, &mut own, &mut None);
                        if let Some(slot) = frame.instances.get_mut(name) {
                            *slot = own;
                        }
                        result
                    }
                    Some(Type::Instance(_)) => match controller.as_deref_mut() {
                        Some(c) => c(self),
                        None => err("the controller can only be called from the program"),
                    },
                    _ => err(format!("`{name}` is not an instance")),
                }
            }
            Stmt::Steps(list) => self.step_list(list, frame, controller),
        }
    }

    /// One scan of a step list: from the stored position until a step ends the scan (see
    /// [`StepList`]); a position outside the list restarts it at step 0 in the next scan.
    fn step_list(
        &mut self,
        list: &StepList,
        frame: &mut Frame,
        controller: &mut Option<&mut Controller<'_>>,
    ) -> Result<()> {
        let n = list.steps.len();
        let Some(at) = frame.values.get(&list.position) else { return err(format!("no local `{}`", list.position)) };
        let mut at = at.as_int();
        let mut budget = 2 * n + 2;
        let resume = loop {
            let Some(step) = usize::try_from(at).ok().and_then(|i| list.steps.get(i)) else { break 0 };
            if budget == 0 {
                return err(format!(
                    "the step list ran {} steps in one scan without ending it (a PLC's watchdog stops here)",
                    2 * n + 2
                ));
            }
            budget -= 1;
            self.tick()?;
            if let Some(wait) = &step.wait {
                if !self.eval(wait, frame)?.as_bool() {
                    break at as usize;
                }
            }
            if let Some(when) = &step.when {
                if !self.eval(when, frame)?.as_bool() {
                    at += 1;
                    continue;
                }
            }
            self.stmts(&step.actions, frame, controller)?;
            match step.next {
                Next::Continue(k) => at = k as i64,
                Next::Resume(k) => break k,
            }
        };
        set_local(frame, &list.position, Value::Int(resume as i64))?;
        set_local(frame, &list.done, Value::Bool(true))
    }

    fn store(&mut self, place: &Place, v: Value, frame: &mut Frame) -> Result<()> {
        match place {
            Place::Local(name) => set_local(frame, name, v),
            Place::Global(name) => self.set_global(name, v),
            Place::Signal(k) => {
                if *k >= self.signals.len() {
                    return err(format!("no signal {k}"));
                }
                let s = &self.unit.signals[*k];
                self.signals[*k] = convert(v, &s.ty, &s.symbol)?;
                Ok(())
            }
            Place::Member(..) => err("a timer's outputs cannot be written"),
        }
    }

    fn read(&self, place: &Place, frame: &Frame) -> Result<Value> {
        match place {
            Place::Local(name) => frame.values.get(name).copied().map_or_else(|| err(format!("no local `{name}`")), Ok),
            Place::Global(name) => self.global(name).map_or_else(|| err(format!("no global `{name}`")), Ok),
            Place::Signal(k) => self.signals.get(*k).copied().map_or_else(|| err(format!("no signal {k}")), Ok),
            Place::Member(base, field) => {
                let Place::Local(name) = base.as_ref() else { return err("only local instances have outputs") };
                if let Some(own) = frame.instances.get(name) {
                    return own
                        .values
                        .get(field)
                        .copied()
                        .map_or_else(|| err(format!("`{name}` has no `{field}`")), Ok);
                }
                let Some(t) = frame.timers.get(name) else { return err(format!("`{name}` is not an instance")) };
                let elapsed = if t.input { (self.now_ms - t.since_ms).min(t.preset_ms) } else { 0 };
                match field.as_str() {
                    "Q" => Ok(Value::Bool(t.input && self.now_ms - t.since_ms >= t.preset_ms)),
                    "ET" => Ok(Value::Time(elapsed as i64)),
                    other => err(format!("TON has no output `{other}`")),
                }
            }
        }
    }

    fn eval(&self, e: &Expr, frame: &mut Frame) -> Result<Value> {
        Ok(match e {
            Expr::Bool(b) => Value::Bool(*b),
            Expr::Int(v) => Value::Int(*v),
            Expr::Real(r) => Value::Real(r.value()),
            Expr::Time(ms) => Value::Time(*ms as i64),
            Expr::Read(p) => self.read(p, frame)?,
            Expr::Not(a) => match self.eval(a, frame)? {
                Value::Bool(b) => Value::Bool(!b),
                v => Value::Int(!v.as_int()),
            },
            Expr::Neg(a) => match self.eval(a, frame)? {
                Value::Real(v) => Value::Real(-v),
                v => Value::Int(self.wrap(e, v.as_int().wrapping_neg(), frame)),
            },
            Expr::Binary(op, a, b) => {
                let (x, y) = (self.eval(a, frame)?, self.eval(b, frame)?);
                match (x, y) {
                    (Value::Real(p), Value::Real(q)) => return real_binary(*op, p, q),
                    (Value::Real(_), _) | (_, Value::Real(_)) => {
                        return err(format!(
                            "`{}` of REAL and a value of another type: IEC needs an explicit conversion",
                            op.text()
                        ))
                    }
                    _ => {}
                }
                let bools = matches!((x, y), (Value::Bool(_), Value::Bool(_)));
                let (i, j) = (x.as_int(), y.as_int());
                match op {
                    BinOp::And if bools => Value::Bool(x.as_bool() && y.as_bool()),
                    BinOp::Or if bools => Value::Bool(x.as_bool() || y.as_bool()),
                    BinOp::Xor if bools => Value::Bool(x.as_bool() != y.as_bool()),
                    BinOp::And => Value::Int(i & j),
                    BinOp::Or => Value::Int(i | j),
                    BinOp::Xor => Value::Int(i ^ j),
                    BinOp::Eq => Value::Bool(i == j),
                    BinOp::Ne => Value::Bool(i != j),
                    BinOp::Lt => Value::Bool(i < j),
                    BinOp::Le => Value::Bool(i <= j),
                    BinOp::Gt => Value::Bool(i > j),
                    BinOp::Ge => Value::Bool(i >= j),
                    BinOp::Add => Value::Int(self.wrap(e, i.wrapping_add(j), frame)),
                    BinOp::Sub => Value::Int(self.wrap(e, i.wrapping_sub(j), frame)),
                    BinOp::Mul => Value::Int(self.wrap(e, i.wrapping_mul(j), frame)),
                    BinOp::Div | BinOp::Mod if j == 0 => return err("division by zero"),
                    // IEC truncates towards zero; MOD takes the sign of the dividend.
                    BinOp::Div => Value::Int(self.wrap(e, i.wrapping_div(j), frame)),
                    BinOp::Mod => Value::Int(self.wrap(e, i.wrapping_rem(j), frame)),
                }
            }
        })
    }

    /// `v`, the result of integer operation `e`, wrapped at the operation's width under
    /// [`Arithmetic::Accumulator`]; `v` itself when exact.
    fn wrap(&self, e: &Expr, v: i64, frame: &Frame) -> i64 {
        match self.arithmetic {
            Arithmetic::Exact => v,
            Arithmetic::Accumulator => self.width(e, frame).wrap(v),
        }
    }

    /// The width integer expression `e` is computed in under [`Arithmetic::Accumulator`].
    fn width(&self, e: &Expr, frame: &Frame) -> Width {
        match e {
            Expr::Int(v) if i16::try_from(*v).is_ok() => Width::W16,
            Expr::Read(p) => self.place_type(p, frame).map_or(Width::W32, |ty| Width::of(&ty)),
            Expr::Neg(a) => self.width(a, frame),
            Expr::Binary(_, a, b) => self.width(a, frame).max(self.width(b, frame)),
            _ => Width::W32,
        }
    }

    /// The declared type of `place`, when it has one.
    fn place_type(&self, place: &Place, frame: &Frame) -> Option<Type> {
        match place {
            Place::Local(name) => frame.types.get(name).cloned(),
            Place::Global(name) => self.globals.types.get(name).cloned(),
            Place::Signal(k) => self.unit.signals.get(*k).map(|s| s.ty.clone()),
            Place::Member(base, field) => {
                let Place::Local(name) = base.as_ref() else { return None };
                match frame.instances.get(name) {
                    Some(own) => own.types.get(field).cloned(),
                    None => frame.timers.contains_key(name).then_some(Type::Time),
                }
            }
        }
    }
}

/// `p op q` on REALs, computed in `f32`.
fn real_binary(op: BinOp, p: f32, q: f32) -> Result<Value> {
    Ok(match op {
        BinOp::Eq => Value::Bool(p == q),
        BinOp::Ne => Value::Bool(p != q),
        BinOp::Lt => Value::Bool(p < q),
        BinOp::Le => Value::Bool(p <= q),
        BinOp::Gt => Value::Bool(p > q),
        BinOp::Ge => Value::Bool(p >= q),
        BinOp::Add => s7_real(p + q),
        BinOp::Sub => s7_real(p - q),
        BinOp::Mul => s7_real(p * q),
        BinOp::Div if q == 0.0 => return err("division by zero"),
        BinOp::Div => s7_real(p / q),
        BinOp::And | BinOp::Or | BinOp::Xor | BinOp::Mod => {
            return err(format!("`{}` of REALs (only + - * / and comparisons)", op.text()))
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `n := (a * a) / 10` and `d := (a * big) / 10` with `a` INT 300, `big` DINT 300.
    fn unit() -> Unit {
        let square = |x: &str| Expr::binary(BinOp::Mul, Expr::global("a"), Expr::global(x));
        let program = Pou {
            kind: PouKind::Program,
            name: "main".into(),
            comment: String::new(),
            inputs: vec![],
            outputs: vec![],
            locals: vec![Var::new("d", Type::Dint, "")],
            body: vec![
                Stmt::assign(Place::global("n"), Expr::binary(BinOp::Div, square("a"), Expr::Int(10))),
                Stmt::assign(Place::local("d"), Expr::binary(BinOp::Div, square("big"), Expr::Int(10))),
            ],
        };
        Unit {
            name: "widths".into(),
            header: vec![],
            gvl: "GVL".into(),
            constants: vec![],
            globals: vec![
                Var::new("a", Type::Int, "").with_init(Expr::Int(300)),
                Var::new("big", Type::Dint, "").with_init(Expr::Int(300)),
                Var::new("n", Type::Int, ""),
            ],
            signals: vec![],
            pous: vec![program],
        }
    }

    #[test]
    fn accumulator_arithmetic_wraps_every_int_operation_and_exact_only_the_store() {
        let unit = unit();
        let mut controller = |_: &mut Machine<'_>| Ok(());
        let mut exact = Machine::new(&unit).unwrap();
        exact.cycle(&mut controller).unwrap();
        assert_eq!(exact.global("n"), Some(Value::Int(9000)));
        assert_eq!(exact.program_value("d"), Some(Value::Int(9000)));
        let mut cpu = Machine::new(&unit).unwrap();
        cpu.set_arithmetic(Arithmetic::Accumulator);
        cpu.cycle(&mut controller).unwrap();
        // 300 * 300 = 90000 wraps to 24464 in 16 bits; with a DINT it does not.
        assert_eq!(cpu.global("n"), Some(Value::Int(2446)));
        assert_eq!(cpu.program_value("d"), Some(Value::Int(9000)));
    }
}
