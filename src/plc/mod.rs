//! PLC back ends: one small code model built from an intermediate program, and printers for
//! IEC 61131-3 Structured Text (plain, CODESYS, Siemens SCL), Instruction List, Siemens S7 STL
//! (AWL, Peter 2005, 6.7.2) and PLCopen TC6 XML.
//!
//! All targets share the execution scheme of 6.7.2: the program position is kept in a step
//! variable; every call (one PLC scan) jumps to the stored position and runs until the program
//! waits. A scan ends when a wait condition is false, when the program jumps backwards (so no
//! loop can run within one scan), and after every request (so that outputs are written and
//! inputs are read again before the next test). Inputs are levels read once per scan; a request
//! either pulses its output for one scan or sets/resets a latched output (the `io` section).
//! Clocks read by delay conditions are IEC `TON` timers (S7 timers in STL), restarted where the
//! program resets the clock.

pub mod il;
pub mod plcopen;
pub mod st;
pub mod stl;

use crate::program::{Condition, Instruction, Program};
use crate::timed::ast::{IoMode, IoTarget};
use crate::timed::model::{ClockId, Game, MsgId};
use serde::Serialize;

/// The output formats.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Target {
    /// IEC 61131-3 Structured Text.
    St,
    /// Siemens SCL for S7-1200/1500 (TIA Portal source file).
    Scl,
    /// CODESYS / TwinCAT Structured Text.
    Codesys,
    /// IEC 61131-3 Instruction List.
    Il,
    /// Siemens S7 Statement List (AWL), as in the thesis.
    Stl,
    /// PLCopen TC6 XML v2.01 project holding the ST function block.
    Plcopen,
}

impl Target {
    pub const ALL: [Target; 6] = [Target::St, Target::Scl, Target::Codesys, Target::Il, Target::Stl, Target::Plcopen];

    /// File extension for downloads.
    pub fn extension(self) -> &'static str {
        match self {
            Target::St | Target::Codesys => "st",
            Target::Scl => "scl",
            Target::Il => "il",
            Target::Stl => "awl",
            Target::Plcopen => "xml",
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            Target::St => "st",
            Target::Scl => "scl",
            Target::Codesys => "codesys",
            Target::Il => "il",
            Target::Stl => "stl",
            Target::Plcopen => "plcopen",
        }
    }
}

/// An input signal: a physical input, a project symbol, or (without `io`) a BOOL input named
/// after the message.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Input {
    /// Identifier of the function block input.
    pub ident: String,
    pub binding: Option<IoTarget>,
    /// The messages read from it (`!press`, `not: release`), for comments.
    pub notes: Vec<String>,
}

/// An output signal.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Output {
    pub ident: String,
    pub binding: Option<IoTarget>,
    /// Pulsed outputs are cleared at the start of every scan.
    pub pulsed: bool,
    /// The requests driving it, for comments.
    pub notes: Vec<String>,
}

/// A timer standing for one clock.
#[derive(Clone, Debug)]
pub struct Timer {
    pub clock: ClockId,
    pub ident: String,
    /// Largest threshold compared, in milliseconds (the timer's preset is above it).
    pub max_ms: u64,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Test {
    /// Input `input` is TRUE (or FALSE when `negated`).
    Input { input: usize, negated: bool },
    /// Timer `timer` has run at least `ms` (more than `ms` when `strict`).
    Elapsed { timer: usize, ms: u64, strict: bool },
}

/// What a request does to its output.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Effect {
    Pulse,
    Set,
    Reset,
}

/// One program position.
#[derive(Clone, Debug)]
pub enum Step {
    /// Wait until `test` holds, then continue at the next position.
    Wait { test: Test },
    /// If `test` holds, continue at `target`, else at the next position.
    Branch { test: Test, target: usize },
    /// Drive an output, then end the scan and continue at the next position.
    Act { output: usize, effect: Effect },
    /// Continue at `target`.
    Jump { target: usize },
}

/// The code model: everything the printers need.
#[derive(Clone, Debug)]
pub struct Code {
    /// Identifier of the function block.
    pub name: String,
    /// Comment lines for the head of every file.
    pub header: Vec<String>,
    pub inputs: Vec<Input>,
    pub outputs: Vec<Output>,
    pub timers: Vec<Timer>,
    pub steps: Vec<Step>,
    /// The intermediate command of each step, for comments.
    pub comments: Vec<String>,
    /// Timers restarted when each step takes effect.
    pub restarts: Vec<Vec<usize>>,
    /// Milliseconds per clock unit.
    pub timeunit_ms: u64,
}

impl Code {
    /// For every step, whether some jump or branch targets it (printers that label only jump
    /// targets use it).
    pub fn jumped_to(&self) -> Vec<bool> {
        let mut v = vec![false; self.steps.len()];
        for s in &self.steps {
            if let Step::Branch { target, .. } | Step::Jump { target } = s {
                if *target < v.len() {
                    v[*target] = true;
                }
            }
        }
        v
    }
}

/// A stable 64-bit FNV-1a hash, printed in headers to tie generated code to its source.
pub fn source_hash(source: &str) -> String {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for b in source.bytes() {
        h ^= b as u64;
        h = h.wrapping_mul(0x0100_0000_01b3);
    }
    format!("{h:016x}")
}

/// Reserved words of IEC 61131-3 and common dialects that may not name a variable.
const KEYWORDS: &[&str] = &[
    "ABS",
    "ACTION",
    "AND",
    "ARRAY",
    "AT",
    "BOOL",
    "BY",
    "BYTE",
    "CASE",
    "CONFIGURATION",
    "CONSTANT",
    "DATE",
    "DINT",
    "DO",
    "DT",
    "DWORD",
    "ELSE",
    "ELSIF",
    "END",
    "EN",
    "ENO",
    "EXIT",
    "FALSE",
    "FOR",
    "FUNCTION",
    "IF",
    "IN",
    "INT",
    "MOD",
    "NOT",
    "OF",
    "ON",
    "OR",
    "PROGRAM",
    "PT",
    "Q",
    "ET",
    "R",
    "S",
    "REAL",
    "REPEAT",
    "RETURN",
    "STEP",
    "STRING",
    "STRUCT",
    "THEN",
    "TIME",
    "TO",
    "TON",
    "TRUE",
    "TYPE",
    "UNTIL",
    "VAR",
    "WHILE",
    "WORD",
    "XOR",
    "BEGIN",
    "REGION",
    "METHOD",
    "INTERFACE",
    "CLASS",
    "TASK",
    "RESOURCE",
];

/// A valid, non-reserved IEC identifier derived from `name` (no double or trailing underscores).
pub fn identifier(name: &str) -> String {
    let mut out = String::new();
    for ch in name.chars() {
        let ch = if ch.is_ascii_alphanumeric() { ch } else { '_' };
        if ch == '_' && (out.is_empty() || out.ends_with('_')) {
            continue;
        }
        out.push(ch);
    }
    while out.ends_with('_') {
        out.pop();
    }
    if out.is_empty() || out.starts_with(|c: char| c.is_ascii_digit()) {
        out.insert_str(0, "x_");
    }
    if KEYWORDS.iter().any(|k| k.eq_ignore_ascii_case(&out)) {
        out.push_str("_sig");
    }
    out
}

/// Identifier for a bound signal: the symbol itself, or the address spelled as a name.
fn binding_ident(target: &IoTarget) -> String {
    match target {
        IoTarget::Address { text, .. } => identifier(&text.replace('.', "_")),
        IoTarget::Symbol { text, .. } => identifier(text),
    }
}

/// Builds the code model of `program`. `name` names the function block.
pub fn build(game: &Game, program: &Program, name: &str, source: &str) -> Code {
    let binding = |m: MsgId| game.io.iter().find(|b| b.message == m);
    let mut inputs: Vec<Input> = Vec::new();
    let mut outputs: Vec<Output> = Vec::new();
    let mut timers: Vec<Timer> = Vec::new();
    let mut input_of = |m: MsgId| -> (usize, bool) {
        let (ident, bind, negated) = match binding(m) {
            Some(b) => (binding_ident(&b.target), Some(b.target.clone()), b.mode == IoMode::Negated),
            None => (identifier(&game.messages[m as usize].name), None, false),
        };
        let index = inputs.iter().position(|i| i.ident == ident).unwrap_or_else(|| {
            inputs.push(Input { ident, binding: bind, notes: Vec::new() });
            inputs.len() - 1
        });
        let note = format!("{}{}", if negated { "NOT " } else { "" }, game.messages[m as usize].name);
        if !inputs[index].notes.contains(&note) {
            inputs[index].notes.push(note);
        }
        (index, negated)
    };
    let mut output_of = |m: MsgId| -> (usize, Effect) {
        let (ident, bind, effect) = match binding(m) {
            Some(b) => {
                let effect = match b.mode {
                    IoMode::Set => Effect::Set,
                    IoMode::Reset => Effect::Reset,
                    _ => Effect::Pulse,
                };
                (binding_ident(&b.target), Some(b.target.clone()), effect)
            }
            None => (identifier(&game.messages[m as usize].name), None, Effect::Pulse),
        };
        let index = outputs.iter().position(|o| o.ident == ident).unwrap_or_else(|| {
            outputs.push(Output { ident, binding: bind, pulsed: effect == Effect::Pulse, notes: Vec::new() });
            outputs.len() - 1
        });
        let verb = match effect {
            Effect::Pulse => "pulses",
            Effect::Set => "sets",
            Effect::Reset => "resets",
        };
        let note = format!("{} {verb}", game.messages[m as usize].name);
        if !outputs[index].notes.contains(&note) {
            outputs[index].notes.push(note);
        }
        (index, effect)
    };
    let unit = game.timeunit_ms;
    let mut timer_of = |c: ClockId, ms: u64| -> usize {
        let ident = format!("t_{}", identifier(&game.clocks[c as usize].name));
        match timers.iter().position(|t| t.clock == c) {
            Some(i) => {
                timers[i].max_ms = timers[i].max_ms.max(ms);
                i
            }
            None => {
                timers.push(Timer { clock: c, ident, max_ms: ms });
                timers.len() - 1
            }
        }
    };
    let pos = program.positions();
    let mut test = |cond: &Condition| -> Test {
        match *cond {
            Condition::Message { message } => {
                let (input, negated) = input_of(message);
                Test::Input { input, negated }
            }
            Condition::Delay { clock, interval } => {
                let ms = interval.lower as u64 * unit;
                Test::Elapsed { timer: timer_of(clock, ms), ms, strict: !interval.lower_closed }
            }
        }
    };
    let rendered = program.render(game);
    let lines: Vec<&str> = rendered.lines().collect();
    let mut steps = Vec::new();
    let mut comments = Vec::new();
    let mut restarts_by_clock = Vec::new();
    for (i, c) in program.commands.iter().enumerate() {
        let step = match c.instruction {
            Instruction::Do { request } => {
                let (output, effect) = output_of(request);
                Step::Act { output, effect }
            }
            Instruction::WaitUntil { condition } => Step::Wait { test: test(&condition) },
            Instruction::If { condition, target } => {
                Step::Branch { test: test(&condition), target: pos[target as usize] as usize }
            }
            Instruction::Goto { target } => Step::Jump { target: pos[target as usize] as usize },
        };
        steps.push(step);
        comments.push(
            lines
                .get(i)
                .map(|l| l.split_once(" : ").map_or(*l, |(_, r)| r).trim_end_matches(';').to_string())
                .unwrap_or_default(),
        );
        restarts_by_clock.push(c.resets);
    }
    // Timers are known only now; map each step's clock resets to timer indices.
    let restarts = restarts_by_clock
        .iter()
        .map(|&bits| timers.iter().enumerate().filter(|(_, t)| bits >> t.clock & 1 == 1).map(|(i, _)| i).collect())
        .collect();
    let header = vec![
        format!("Generated by plcsynth {} from a timed-game specification.", env!("CARGO_PKG_VERSION")),
        format!("Specification hash (FNV-1a 64): {}", source_hash(source)),
        "Do not edit: change the specification and generate again.".to_string(),
    ];
    Code { name: identifier(name), header, inputs, outputs, timers, steps, comments, restarts, timeunit_ms: unit }
}

/// Generates the code of `program` for `target`. `name` names the function block, `source` is
/// the specification text (hashed into the header).
pub fn generate(game: &Game, program: &Program, target: Target, name: &str, source: &str) -> String {
    let code = build(game, program, name, source);
    match target {
        Target::St => st::print(&code, st::Dialect::Iec),
        Target::Codesys => st::print(&code, st::Dialect::Codesys),
        Target::Scl => st::print(&code, st::Dialect::Scl),
        Target::Il => il::print(&code),
        Target::Stl => stl::print(&code),
        Target::Plcopen => plcopen::print(&code),
    }
}

/// `T#…` literal for a duration.
pub fn time_literal(ms: u64) -> String {
    format!("T#{ms}MS")
}

/// An address in IEC notation (`IX0.0`, `QX1.3`, `MW10`; without `%`): a bit address gets the
/// `X` size prefix that IEC and CODESYS require.
pub fn iec_address(text: &str) -> String {
    let mut chars = text.chars();
    let area = chars.next().unwrap_or('I');
    let rest: String = chars.collect();
    let has_size = rest.starts_with(['X', 'B', 'W', 'D', 'L']);
    if !has_size && rest.contains('.') {
        format!("{area}X{rest}")
    } else {
        format!("{area}{rest}")
    }
}

/// An address in Siemens notation (`I0.0`, `Q1.3`, `MW10`): the bit size prefix `X` is dropped.
pub fn siemens_address(text: &str) -> String {
    let mut chars = text.chars();
    let area = chars.next().unwrap_or('I');
    let rest: String = chars.collect();
    match rest.strip_prefix('X') {
        Some(bit) => format!("{area}{bit}"),
        None => format!("{area}{rest}"),
    }
}

/// The preset of a timer: above its largest threshold, so every comparison can still become true.
pub fn preset_literal(code: &Code, timer: usize) -> String {
    time_literal(code.timers[timer].max_ms + code.timeunit_ms)
}
