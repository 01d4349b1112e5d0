//! The neutral code model every printer reads: a function block with BOOL inputs and outputs,
//! timers, and a list of steps (statements over tests). It names no engine; a lowering (such as
//! [`super::lower_timed`]) builds it, and printers turn it into text.

use crate::diag::Span;

/// Where a signal lives outside the block.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Binding {
    /// A direct IEC address such as `I0.0`, `QX1.3`, `MX10.2` (without the `%`).
    Address(String),
    /// A symbol of an existing project, possibly dotted (`GVL.lamp`).
    Symbol(String),
    /// A Siemens tag name written in quotes (`"Lamp On"`), printed with its quotes.
    Quoted(String),
}

impl Binding {
    /// The binding as Siemens code writes it: `%I0.0`, `GVL.lamp`, `"Lamp On"`.
    pub fn siemens_text(&self) -> String {
        match self {
            Binding::Address(text) => format!("%{}", super::siemens_address(text)),
            Binding::Symbol(text) => text.clone(),
            Binding::Quoted(text) => format!("\"{text}\""),
        }
    }

    /// The binding as IEC code writes it: `%IX0.0`, `GVL.lamp`, `"Lamp On"` (a quoted name is
    /// only accepted by the lowering for Siemens targets, see `Target::quotes_tags`).
    pub fn iec_text(&self) -> String {
        match self {
            Binding::Address(text) => format!("%{}", super::iec_address(text)),
            Binding::Symbol(text) => text.clone(),
            Binding::Quoted(text) => format!("\"{text}\""),
        }
    }
}

/// Which way a signal flows, seen from the PLC program.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Direction {
    Input,
    Output,
}

/// A BOOL variable of the block's interface.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Variable {
    /// A valid IEC identifier (see [`super::identifier`]).
    pub symbol: String,
    /// The signal it is wired to, if any; unbound variables are the block's own inputs/outputs.
    pub binding: Option<Binding>,
    /// What the variable stands for, printed beside its declaration.
    pub comment: String,
    /// Where the binding is written in the source, for diagnostics about it.
    pub span: Option<Span>,
}

/// An output variable.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Output {
    pub variable: Variable,
    /// Pulsed outputs are cleared at the start of every scan.
    pub pulsed: bool,
    /// For a pulsed output: a BOOL of the block that holds the output's value at the last
    /// output write, captured at the start of every scan before the clear. A pulse while it is
    /// TRUE (the output was pulsed in the previous scan) does not act: the step ends the scan
    /// and pulses in the next one, so the machine sees a FALSE write, and a rising edge, for
    /// every pulse. The lowering gives every pulsed output one; without it (`None`) two pulses
    /// in consecutive scans keep the output TRUE and are one request for the machine.
    pub last: Option<String>,
}

impl Output {
    /// The memory of the last write, if the output is pulsed and has one.
    pub fn gap(&self) -> Option<&str> {
        self.last.as_deref().filter(|_| self.pulsed)
    }
}

/// An on-delay timer (`TON`), running while the block runs and restarted by steps.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Timer {
    pub symbol: String,
    /// What it measures, printed beside its declaration.
    pub comment: String,
    /// The preset: above the largest threshold compared (see [`super::TimeType`]).
    pub preset_ms: u64,
}

/// A condition a step tests.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Test {
    /// Input `input` is TRUE (or FALSE when `negated`).
    Input { input: usize, negated: bool },
    /// Timer `timer` has run at least `ms` (more than `ms` when `strict`).
    Elapsed { timer: usize, ms: u64, strict: bool },
}

/// What a step does to its output.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Effect {
    /// TRUE for this scan (one scan later if the output was TRUE in the previous one).
    Pulse,
    Set,
    Reset,
}

/// What one program position does.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Statement {
    /// Wait until `test` holds, then continue at the next position.
    Wait { test: Test },
    /// If `test` holds, continue at `target`, else at the next position.
    Branch { test: Test, target: usize },
    /// Drive an output, then end the scan and continue at the next position. A pulse of an
    /// output that was TRUE at the last write (see [`Output::last`]) only ends the scan and
    /// stays at this position.
    Act { output: usize, effect: Effect },
    /// Continue at `target`.
    Jump { target: usize },
}

/// One program position.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Step {
    pub statement: Statement,
    /// Timers restarted when the step takes effect (its test holds, or it acts or jumps).
    pub restarts: Vec<usize>,
    /// The source of the step (an intermediate command), printed beside it.
    pub comment: String,
}

/// A function block: everything the printers need.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Code {
    /// Identifier of the function block.
    pub name: String,
    /// Identifier of the program (or wrapper block) that instantiates and wires the block.
    pub program: String,
    /// Identifier of the block's instance inside [`Code::program`].
    pub instance: String,
    /// Identifier of the global variable list of the I/O (CODESYS, TwinCAT).
    pub gvl: String,
    /// Comment lines for the head of every file.
    pub header: Vec<String>,
    pub inputs: Vec<Variable>,
    pub outputs: Vec<Output>,
    pub timers: Vec<Timer>,
    pub steps: Vec<Step>,
}

impl Code {
    /// For every step, whether some jump or branch targets it (printers that label only jump
    /// targets use it).
    pub fn jumped_to(&self) -> Vec<bool> {
        let mut v = vec![false; self.steps.len()];
        for s in &self.steps {
            if let Statement::Branch { target, .. } | Statement::Jump { target } = s.statement {
                if target < v.len() {
                    v[target] = true;
                }
            }
        }
        v
    }

    /// Whether any variable is wired to a signal outside the block.
    pub fn has_bindings(&self) -> bool {
        self.variables().any(|(v, _)| v.binding.is_some())
    }

    /// Every interface variable with its direction: inputs first, then outputs.
    pub fn variables(&self) -> impl Iterator<Item = (&Variable, Direction)> {
        let inputs = self.inputs.iter().map(|v| (v, Direction::Input));
        inputs.chain(self.outputs.iter().map(|o| (&o.variable, Direction::Output)))
    }
}
