//! The neutral code model every printer reads: a function block with BOOL inputs and outputs,
//! timers, and a list of steps (statements over tests). It names no engine; a lowering (such as
//! [`super::lower_timed`]) builds it, and printers turn it into text.

/// Where a signal lives outside the block.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Binding {
    /// A direct IEC address such as `I0.0`, `QX1.3`, `MW10` (without the `%`).
    Address(String),
    /// A symbol of an existing project, possibly dotted (`GVL.lamp`).
    Symbol(String),
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
}

/// An output variable.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Output {
    pub variable: Variable,
    /// Pulsed outputs are cleared at the start of every scan.
    pub pulsed: bool,
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
    /// TRUE for this scan.
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
    /// Drive an output, then end the scan and continue at the next position.
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
        self.inputs.iter().chain(self.outputs.iter().map(|o| &o.variable)).any(|v| v.binding.is_some())
    }
}
