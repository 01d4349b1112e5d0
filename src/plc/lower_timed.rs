//! Lowering of the timed engine's controller program (Peter 2005, chapter 6) to the code model:
//! the one module of `plc` that knows timed games. Messages become BOOL inputs and outputs (or
//! the signals of the `io` section), clocks read by delay conditions become timers, and each
//! command becomes one step.

use super::model::{Binding, Code, Effect, Output, Statement, Step, Test, Timer, Variable};
use super::{identifier, render, source_hash, Target};
use crate::diag::{Diagnostic, Diagnostics};
use crate::program::{Condition, Instruction, Program};
use crate::timed::model::{ClockId, Game, IoMode, IoTarget, MsgId};

/// The binding of an io target.
fn binding(target: &IoTarget) -> Binding {
    match target {
        IoTarget::Address { text, .. } => Binding::Address(text.clone()),
        IoTarget::Symbol { text, .. } => Binding::Symbol(text.clone()),
    }
}

/// Identifier for a bound signal: the symbol itself, or the address spelled as a name.
fn binding_ident(target: &IoTarget) -> String {
    match target {
        IoTarget::Address { text, .. } => identifier(&text.replace('.', "_")),
        IoTarget::Symbol { text, .. } => identifier(text),
    }
}

/// A variable being built and the messages it stands for, which become its comment.
struct Signal {
    variable: Variable,
    notes: Vec<String>,
}

impl Signal {
    fn note(&mut self, note: String) {
        if !self.notes.contains(&note) {
            self.notes.push(note);
        }
    }

    fn finish(mut self) -> Variable {
        self.variable.comment = self.notes.join(", ");
        self.variable
    }
}

/// Builds the code model of `program` for `target`. `name` names the function block; `source`
/// is the specification text of `game` (hashed into the header). A delay constant that the
/// target's time type cannot hold exactly (see [`Target::time_type`]) is an error located at
/// the constant in `source`; nothing is rounded or wrapped.
pub fn build(
    game: &Game,
    program: &Program,
    target: Target,
    name: &str,
    source: &str,
) -> Result<Code, Vec<Diagnostic>> {
    let mut diags = Diagnostics::new(source);
    let time = target.time_type();
    let io_of = |m: MsgId| game.io.iter().find(|b| b.message == m);
    let message_name = |m: MsgId| game.messages[m as usize].name.as_str();
    let mut inputs: Vec<Signal> = Vec::new();
    let mut outputs: Vec<(Signal, bool)> = Vec::new();
    let mut input_of = |m: MsgId| -> (usize, bool) {
        let (symbol, bound, negated) = match io_of(m) {
            Some(b) => (binding_ident(&b.target), Some(binding(&b.target)), b.mode == IoMode::Negated),
            None => (identifier(message_name(m)), None, false),
        };
        let index = inputs.iter().position(|i| i.variable.symbol == symbol).unwrap_or_else(|| {
            let variable = Variable { symbol, binding: bound, comment: String::new() };
            inputs.push(Signal { variable, notes: Vec::new() });
            inputs.len() - 1
        });
        inputs[index].note(format!("{}{}", if negated { "NOT " } else { "" }, message_name(m)));
        (index, negated)
    };
    let mut output_of = |m: MsgId| -> (usize, Effect) {
        let (symbol, bound, effect) = match io_of(m) {
            Some(b) => {
                let effect = match b.mode {
                    IoMode::Set => Effect::Set,
                    IoMode::Reset => Effect::Reset,
                    _ => Effect::Pulse,
                };
                (binding_ident(&b.target), Some(binding(&b.target)), effect)
            }
            None => (identifier(message_name(m)), None, Effect::Pulse),
        };
        let index = outputs.iter().position(|(o, _)| o.variable.symbol == symbol).unwrap_or_else(|| {
            let variable = Variable { symbol, binding: bound, comment: String::new() };
            outputs.push((Signal { variable, notes: Vec::new() }, effect == Effect::Pulse));
            outputs.len() - 1
        });
        let verb = match effect {
            Effect::Pulse => "pulses",
            Effect::Set => "sets",
            Effect::Reset => "resets",
        };
        outputs[index].0.note(format!("{} {verb}", message_name(m)));
        (index, effect)
    };
    // Constants are at most 2^24 and a time unit at most 2^24 h (about 6·10^13 ms): their
    // product is far within u128, so the check below sees the exact value.
    let unit = u128::from(game.timeunit_ms);
    // The clock of each timer and its largest threshold, in time units.
    let mut timers: Vec<(ClockId, u32)> = Vec::new();
    let mut timer_of = |c: ClockId, units: u32| -> usize {
        match timers.iter().position(|&(clock, _)| clock == c) {
            Some(i) => {
                timers[i].1 = timers[i].1.max(units);
                i
            }
            None => {
                timers.push((c, units));
                timers.len() - 1
            }
        }
    };
    let mut refused: Vec<(ClockId, u32)> = Vec::new();
    let pos = program.positions();
    let mut test = |cond: &Condition| -> Test {
        match *cond {
            Condition::Message { message } => {
                let (input, negated) = input_of(message);
                Test::Input { input, negated }
            }
            Condition::Delay { clock, interval } => {
                let ms = u128::from(interval.lower) * unit;
                let strict = !interval.lower_closed;
                // A strict bound on S5TIME becomes the next value above it, which must fit too.
                if let Some((why, notes)) = time.refusal(ms).or_else(|| time.refusal(time.preset_for(ms, strict))) {
                    if !refused.contains(&(clock, interval.lower)) {
                        refused.push((clock, interval.lower));
                        let message =
                            format!("time constant {} ({ms} ms) {why} for target {}", interval.lower, target.name());
                        report(&mut diags, game, clock, interval.lower, message, notes);
                    }
                }
                // Every accepted threshold fits in 32 bits; a refused one is never printed.
                let ms = u64::try_from(ms).unwrap_or(u64::MAX);
                Test::Elapsed { timer: timer_of(clock, interval.lower), ms, strict }
            }
        }
    };
    let texts = program.command_texts(game);
    let mut steps = Vec::new();
    for (c, comment) in program.commands.iter().zip(texts) {
        let statement = match c.instruction {
            Instruction::Do { request } => {
                let (output, effect) = output_of(request);
                Statement::Act { output, effect }
            }
            Instruction::WaitUntil { condition } => Statement::Wait { test: test(&condition) },
            Instruction::If { condition, target } => {
                Statement::Branch { test: test(&condition), target: pos[target as usize] as usize }
            }
            Instruction::Goto { target } => Statement::Jump { target: pos[target as usize] as usize },
        };
        // Timers are known only at the end; `restarts` holds the reset clocks until then.
        steps.push((Step { statement, restarts: Vec::new(), comment }, c.resets));
    }
    let mut code_timers = Vec::new();
    for &(clock, units) in &timers {
        let threshold = u128::from(units) * unit;
        let preset = time.preset_ms(threshold, unit);
        if time.refusal(threshold).is_none() {
            if let Some((why, notes)) = time.refusal(preset) {
                let message = format!(
                    "time constant {units} ({threshold} ms) needs a timer preset one time unit above it, \
                     {preset} ms, which {why} for target {}",
                    target.name()
                );
                report(&mut diags, game, clock, units, message, notes);
            }
        }
        let clock_ident = identifier(&game.clocks[clock as usize].name);
        code_timers.push(Timer {
            symbol: format!("t_{clock_ident}"),
            comment: format!("clock {clock_ident}"),
            preset_ms: u64::try_from(preset).unwrap_or(u64::MAX),
        });
    }
    if diags.has_errors() {
        return Err(diags.items);
    }
    let steps = steps
        .into_iter()
        .map(|(mut step, resets)| {
            step.restarts =
                timers.iter().enumerate().filter(|(_, &(clock, _))| resets >> clock & 1 == 1).map(|(i, _)| i).collect();
            step
        })
        .collect();
    let header = vec![
        format!("Generated by plcsynth {} from a timed-game specification.", env!("CARGO_PKG_VERSION")),
        format!("Specification hash (FNV-1a 64): {}", source_hash(source)),
        "Do not edit: change the specification and generate again.".to_string(),
    ];
    Ok(Code {
        name: identifier(name),
        header,
        inputs: inputs.into_iter().map(Signal::finish).collect(),
        outputs: outputs.into_iter().map(|(o, pulsed)| Output { variable: o.finish(), pulsed }).collect(),
        timers: code_timers,
        steps,
    })
}

/// Generates the code of `program` for `target`. `name` names the function block, `source` is
/// the specification text (hashed into the header, and the place diagnostics point into).
pub fn generate(
    game: &Game,
    program: &Program,
    target: Target,
    name: &str,
    source: &str,
) -> Result<String, Vec<Diagnostic>> {
    let code = build(game, program, target, name, source)?;
    Ok(render(&code, target))
}

/// Reports a delay constant the target cannot hold: at the constant, with the time unit that
/// scaled it.
fn report(diags: &mut Diagnostics, game: &Game, clock: ClockId, units: u32, message: String, notes: Vec<String>) {
    let unit_note = match game.timeunit_span {
        Some(span) => {
            let (line, column) = diags.line_col(span.start as usize);
            format!("one time unit is {} ms (`timeunit` at {line}:{column})", game.timeunit_ms)
        }
        None => format!("one time unit is {} ms (the default, `timeunit 1s;`)", game.timeunit_ms),
    };
    let span = crate::timed::constant_span(game, diags.source(), clock, units);
    let d = diags.error(span, message);
    for note in notes {
        d.with_note(note);
    }
    d.with_note(format!("clock `{}` is compared with it", game.clocks[clock as usize].name)).with_note(unit_note);
}
