//! The structured form of a lowered controller: a [`Code`] step machine as a [`Unit`] of the one
//! code model, so that the structured printers and the interpreter [`crate::plc::model::exec`]
//! take it like any other unit.
//!
//! The function block keeps the step machine's interface (a BOOL input per input signal, a BOOL
//! output per output signal); its body clears the pulsed outputs (keeping their last write),
//! calls every timer with `IN := TRUE`, and runs the steps as a [`StepList`] on `step`. The
//! program calls the block and wires it: a signal bound to a symbol of the project is a
//! [`Signal`] of the unit; one bound to a direct address is a global of the unit at that address
//! ([`Location::Address`]), named after its message; an unbound one is a global the PLC tool
//! maps ([`Location::Mapped`]).

use crate::plc::lower::timed::machine::{Binding, Code, Effect, Statement, Step, Test};
use crate::plc::model::unit::{
    self, direct_addresses, BinOp, Expr, Location, Next, Place, Pou, PouKind, Signal, SignalKind, StepList, Stmt, Type,
    Unit, Var,
};

/// The position variable and the loop flag of the step list.
pub(crate) const POSITION: &str = "step";
const DONE: &str = "scan_done";

/// A step machine as a unit, and where the unit's program reads and writes each variable of the
/// code's interface.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Structured {
    pub unit: Unit,
    /// Per input of the code: the signal or global the program passes to the block.
    pub inputs: Vec<Place>,
    /// Per output of the code: the signal or global the program copies it to.
    pub outputs: Vec<Place>,
}

/// `code` as a unit: the function block and the program that wires it.
pub fn structured(code: &Code) -> Structured {
    let mut unit = Unit {
        name: code.name.clone(),
        header: code.header.clone(),
        gvl: code.gvl.clone(),
        constants: Vec::new(),
        globals: Vec::new(),
        signals: Vec::new(),
        pous: Vec::new(),
    };
    let wires = wiring(code, &mut unit);
    unit.pous.push(function_block(code));
    unit.pous.push(program(code, &wires));
    let outputs = wires[code.inputs.len()..].to_vec();
    let mut inputs = wires;
    inputs.truncate(code.inputs.len());
    Structured { unit, inputs, outputs }
}

/// Where the program reads an input or writes an output: a signal of the project, or a global.
fn wiring(code: &Code, unit: &mut Unit) -> Vec<Place> {
    let kinds: Vec<(SignalKind, char)> = code
        .variables()
        .map(|(_, d)| match d {
            crate::plc::lower::timed::machine::Direction::Input => (SignalKind::Input, 'I'),
            crate::plc::lower::timed::machine::Direction::Output => (SignalKind::Output, 'Q'),
        })
        .collect();
    // Addresses for the symbols, where a dialect cannot write them (STL), per area, after the
    // direct addresses the code uses.
    let fallback = |area: char| {
        let count = code.variables().zip(&kinds).filter(|(_, k)| k.1 == area).count();
        let mut free = direct_addresses(area, &vec![Type::Bool; count + 64]).into_iter().flatten();
        let used: Vec<String> = code
            .variables()
            .filter_map(|(v, _)| match &v.binding {
                Some(Binding::Address(a)) => Some(crate::plc::iec_address(a)),
                _ => None,
            })
            .collect();
        move || free.by_ref().find(|a| !used.contains(a)).unwrap_or_default()
    };
    let (mut input_address, mut output_address) = (fallback('I'), fallback('Q'));
    code.variables()
        .zip(kinds)
        .map(|((v, _), (kind, area))| {
            let global = |at: Location, unit: &mut Unit| {
                unit.globals.push(Var::new(v.symbol.clone(), Type::Bool, v.comment.clone()).at(at));
                Place::global(v.symbol.clone())
            };
            match &v.binding {
                None => global(Location::Mapped(kind), unit),
                Some(Binding::Address(a)) => global(Location::Address(crate::plc::iec_address(a)), unit),
                Some(binding @ (Binding::Symbol(symbol) | Binding::Quoted(symbol))) => {
                    // A Siemens tag keeps its quotes: it is written as it is.
                    let symbol =
                        if matches!(binding, Binding::Quoted(_)) { format!("\"{symbol}\"") } else { symbol.clone() };
                    let address = if area == 'I' { input_address() } else { output_address() };
                    let comment = v.comment.clone();
                    unit.signals.push(Signal { symbol, kind, ty: Type::Bool, address, comment });
                    Place::Signal(unit.signals.len() - 1)
                }
            }
        })
        .collect()
}

fn bool_var(name: &str, comment: &str) -> Var {
    Var::new(name, Type::Bool, comment)
}

fn function_block(code: &Code) -> Pou {
    let mut locals = vec![
        Var::new(POSITION, Type::Int, "program position").with_init(Expr::Int(0)),
        bool_var(DONE, "the scan has ended"),
    ];
    for out in &code.outputs {
        if let Some(last) = out.gap() {
            locals.push(bool_var(last, &format!("{} at the last output write", out.variable.symbol)));
        }
    }
    locals.extend(code.timers.iter().map(|t| Var::new(t.symbol.clone(), Type::Ton, t.comment.clone())));
    let mut body = Vec::new();
    if code.outputs.iter().any(|out| out.pulsed) {
        body.push(Stmt::Comment("Pulsed outputs are TRUE for one scan, with a FALSE scan between two pulses.".into()));
    }
    for out in code.outputs.iter().filter(|out| out.pulsed) {
        let symbol = &out.variable.symbol;
        if let Some(last) = out.gap() {
            body.push(Stmt::assign(Place::local(last), Expr::local(symbol)));
        }
        body.push(Stmt::assign(Place::local(symbol), Expr::Bool(false)));
    }
    if !code.timers.is_empty() {
        body.push(Stmt::Comment("Clocks run as timers; a restart calls the timer with IN := FALSE.".into()));
    }
    for t in 0..code.timers.len() {
        body.push(timer_call(code, t, true));
    }
    body.push(Stmt::Comment("One scan: run from the stored position until the program waits.".into()));
    let steps = code.steps.iter().enumerate().map(|(i, step)| step_of(code, i, step)).collect();
    body.push(Stmt::Steps(StepList { position: POSITION.into(), done: DONE.into(), steps }));
    Pou {
        kind: PouKind::FunctionBlock,
        name: code.name.clone(),
        comment: String::new(),
        inputs: code.inputs.iter().map(|v| bool_var(&v.symbol, &v.comment)).collect(),
        outputs: code.outputs.iter().map(|o| bool_var(&o.variable.symbol, &o.variable.comment)).collect(),
        locals,
        body,
    }
}

/// `t(IN := running, PT := preset)`: the scan's call (`running`) or a restart.
fn timer_call(code: &Code, t: usize, running: bool) -> Stmt {
    let timer = &code.timers[t];
    Stmt::CallInstance {
        instance: Place::local(timer.symbol.clone()),
        args: vec![("IN".into(), Expr::Bool(running)), ("PT".into(), Expr::Time(timer.preset_ms))],
    }
}

fn test_expr(code: &Code, test: &Test) -> Expr {
    match *test {
        Test::Input { input, negated } => {
            let read = Expr::local(code.inputs[input].symbol.clone());
            if negated {
                read.not()
            } else {
                read
            }
        }
        Test::Elapsed { timer, ms, strict } => Expr::binary(
            if strict { BinOp::Gt } else { BinOp::Ge },
            Expr::read(Place::local(code.timers[timer].symbol.clone()).member("ET")),
            Expr::Time(ms),
        ),
    }
}

/// Step `i` of `code`: where a transfer backwards ends the scan, the next scan resumes where the
/// chain of bare jumps from the target leads ([`Code::resume_at`]).
fn step_of(code: &Code, i: usize, step: &Step) -> unit::Step {
    let mut actions: Vec<Stmt> = Vec::new();
    let restarts: Vec<Stmt> = step.restarts.iter().map(|&t| timer_call(code, t, false)).collect();
    let transfer = |target: usize| {
        if target <= i && !step.back_in_scan {
            Next::Resume(code.resume_at(target))
        } else {
            Next::Continue(target)
        }
    };
    let (wait, when, next) = match step.statement {
        Statement::Wait { test } => (Some(test_expr(code, &test)), None, Next::Continue(i + 1)),
        Statement::Branch { test, target } => (None, Some(test_expr(code, &test)), transfer(target)),
        Statement::Act { output, effect, ends_scan } => {
            let out = &code.outputs[output];
            actions.push(Stmt::assign(Place::local(out.variable.symbol.clone()), Expr::Bool(effect != Effect::Reset)));
            // A pulse right after a pulse of the same output waits here for one scan.
            let wait = out.gap().filter(|_| effect == Effect::Pulse).map(|last| Expr::local(last).not());
            let next = if ends_scan { Next::Resume(code.resume_at(i + 1)) } else { Next::Continue(i + 1) };
            (wait, None, next)
        }
        Statement::Jump { target } => (None, None, transfer(target)),
    };
    actions.extend(restarts);
    unit::Step { comment: step.comment.clone(), wait, when, actions, next }
}

/// The program: calls the block with its inputs and copies its outputs out.
fn program(code: &Code, wires: &[Place]) -> Pou {
    let instance = Place::local(code.instance.clone());
    let args = code.inputs.iter().zip(wires).map(|(v, w)| (v.symbol.clone(), Expr::read(w.clone()))).collect();
    let mut body = vec![Stmt::CallInstance { instance: instance.clone(), args }];
    for (out, w) in code.outputs.iter().zip(&wires[code.inputs.len()..]) {
        let symbol = out.variable.symbol.clone();
        body.push(Stmt::assign(w.clone(), Expr::read(instance.clone().member(symbol))));
    }
    Pou {
        kind: PouKind::Program,
        name: code.program.clone(),
        comment: String::new(),
        inputs: Vec::new(),
        outputs: Vec::new(),
        locals: vec![Var::new(code.instance.clone(), Type::Instance(code.name.clone()), "the controller")],
        body,
    }
}
