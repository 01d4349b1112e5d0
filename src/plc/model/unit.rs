//! The structured half of the neutral code model: program organisation units (functions,
//! function blocks, a program) over typed variables, with expressions, `IF` and `CASE` — what a
//! framework of cooperating blocks needs, where [`crate::plc::lower::timed::machine::Code`] is one step machine.
//! It names no engine: a lowering (such as `lower::sct`) builds a [`Unit`]; printers (`print::st::unit`
//! for the Structured Text dialects, PLCopen and TwinCAT, `print::stl::unit` for S7 AWL) turn it into
//! text.
//!
//! Three kinds of names meet here, and printers write each as its dialect wants:
//! - globals of the unit ([`Place::Global`]), kept in the unit's global variable list (IEC,
//!   CODESYS, TwinCAT) or its global data block (SCL, STL);
//! - locals and parameters of the POU being printed ([`Place::Local`]);
//! - signals of the user's project ([`Place::Signal`]): I/O symbols, direct addresses and
//!   controller variables, declared elsewhere, listed in [`Unit::signals`] with an address a
//!   printer may use when the dialect cannot write the symbol (STL).

pub use crate::plc::fragment::BinOp;

/// Elementary and block types the unit uses.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Type {
    Bool,
    /// 16-bit signed integer (`INT`).
    Int,
    /// 32-bit signed integer (`DINT`).
    Dint,
    /// 32-bit IEEE 754 floating point (`REAL`). No operation mixes it with an integer type:
    /// IEC 61131-3 converts only explicitly, and the model offers no conversion.
    Real,
    /// A duration (`TIME`).
    Time,
    /// An on-delay timer instance (`TON`; `TON_TIME` on S7-1200/1500, SFB 4 in STL).
    Ton,
    /// An instance of a function block the unit does not define (the user's controller).
    Instance(String),
}

/// A declared variable, parameter or constant.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Var {
    /// A valid identifier, unique case-insensitively in its scope.
    pub name: String,
    pub ty: Type,
    /// The initial value (a literal expression); the type's default when absent.
    pub init: Option<Expr>,
    /// Printed beside the declaration.
    pub comment: String,
    /// For a global: where it lives in the PLC's memory, if not in the global list's own.
    pub at: Option<Location>,
}

/// Where a global of the unit lives when it is wired to the process (see [`Var::at`]).
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Location {
    /// At a direct address (IEC form without `%`: `IX0.1`, `QX0.0`): the IEC dialects declare
    /// it `AT %IX0.1`; Siemens code names it as a PLC tag of the same name that the tag table
    /// defines at the address.
    Address(String),
    /// In the process image of `kind`, mapped by the PLC tool: TwinCAT declares it `AT %I*` /
    /// `AT %Q*` to be linked in its System Manager; the others leave it to the tool's mapping.
    Mapped(SignalKind),
}

impl Var {
    pub fn new(name: impl Into<String>, ty: Type, comment: impl Into<String>) -> Var {
        Var { name: name.into(), ty, init: None, comment: comment.into(), at: None }
    }

    /// The variable at `location`.
    pub fn at(mut self, location: Location) -> Var {
        self.at = Some(location);
        self
    }

    /// The direct address of a global at one.
    pub fn address(&self) -> Option<&str> {
        match &self.at {
            Some(Location::Address(a)) => Some(a),
            _ => None,
        }
    }

    pub fn with_init(mut self, init: Expr) -> Var {
        self.init = Some(init);
        self
    }
}

/// Which way a signal of the user's project flows, seen from the PLC program.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SignalKind {
    /// Read from the process image of inputs.
    Input,
    /// Written to the process image of outputs.
    Output,
    /// A variable of the controller (memory, `\var{}` of Göbe 2019, 6.3.1).
    Memory,
}

impl SignalKind {
    /// `input`, `output` or `variable`.
    pub fn name(self) -> &'static str {
        match self {
            SignalKind::Input => "input",
            SignalKind::Output => "output",
            SignalKind::Memory => "variable",
        }
    }
}

/// A signal of the user's project that the unit reads or writes but does not declare.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Signal {
    /// The name as the user's project writes it: a symbol (`Q_Inlet`, `GVL.lamp`), a Siemens
    /// tag with its quotes (`"Lamp On"`, for Siemens dialects only) or a direct address without
    /// `%` (`IX0.1`), see [`Signal::is_address`].
    pub symbol: String,
    pub kind: SignalKind,
    pub ty: Type,
    /// The address used where the dialect cannot write the symbol (IEC form without `%`:
    /// `IX0.1`, `QX0.0`, `MX20.3`, `IW4`).
    pub address: String,
    /// Printed in tables and signal lists (which events read or write it).
    pub comment: String,
}

impl Signal {
    /// Whether the signal is written in the source as a direct address.
    pub fn is_address(&self) -> bool {
        self.symbol == self.address
    }
}

/// Direct addresses (IEC form without `%`) for signals of the given types in one area
/// (`area` `'I'`, `'Q'` or `'M'`), in order: BOOLs packed into bits from byte 0 (`IX0.0`,
/// `IX0.1`, …), then the others on even bytes after the last bit's byte: INT as a word
/// (`IW2`), DINT, TIME and REAL as a double word (`ID4`). `None` for a type that has no
/// address (a timer or block instance).
pub fn direct_addresses(area: char, types: &[Type]) -> Vec<Option<String>> {
    let bits = types.iter().filter(|t| **t == Type::Bool).count();
    let mut bit = 0;
    let mut byte = bits.div_ceil(8).next_multiple_of(2);
    types
        .iter()
        .map(|t| {
            let (size, width) = match t {
                Type::Bool => {
                    let a = format!("{area}X{}.{}", bit / 8, bit % 8);
                    bit += 1;
                    return Some(a);
                }
                Type::Int => ('W', 2),
                Type::Dint | Type::Time | Type::Real => ('D', 4),
                Type::Ton | Type::Instance(_) => return None,
            };
            let a = format!("{area}{size}{byte}");
            byte += width;
            Some(a)
        })
        .collect()
}

/// Something that holds a value.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Place {
    /// Variable `name` of [`Unit::globals`] or [`Unit::constants`].
    Global(String),
    /// A parameter or local variable of the POU being printed (for a function, its own name is
    /// its result).
    Local(String),
    /// Signal number `n` of [`Unit::signals`].
    Signal(usize),
    /// An output of a block instance: `timer.Q`, `timer.ET`.
    Member(Box<Place>, String),
}

impl Place {
    pub fn global(name: impl Into<String>) -> Place {
        Place::Global(name.into())
    }

    pub fn local(name: impl Into<String>) -> Place {
        Place::Local(name.into())
    }

    pub fn member(self, field: impl Into<String>) -> Place {
        Place::Member(Box::new(self), field.into())
    }
}

/// A `REAL` literal: the 32-bit float the PLC holds, finite, with `-0.0` stored as `0.0`.
/// Equal and hashed by its bits.
#[derive(Clone, Copy, Debug)]
pub struct RealLit(f32);

impl RealLit {
    /// `x` rounded to the nearest `f32`; `None` when that is not finite (NaN, or beyond
    /// ±3.4028235E38), which no PLC source can write as a literal.
    pub fn new(x: f64) -> Option<RealLit> {
        let v = x as f32;
        v.is_finite().then_some(RealLit(if v == 0.0 { 0.0 } else { v }))
    }

    /// The value as the PLC holds it.
    pub fn value(self) -> f32 {
        self.0
    }

    /// The literal in Structured Text (every dialect): the shortest decimal that reads back as
    /// the same `f32`, always with a decimal point (`3.0`, `-0.25`, `1.0E-7`, `1.5E+20`).
    /// Magnitudes from 1E-4 below 1E7 are written without an exponent.
    pub fn iec_text(self) -> String {
        let v = self.0;
        let a = v.abs();
        if a == 0.0 || (1e-4..1e7).contains(&a) {
            let text = format!("{v}");
            if text.contains('.') {
                text
            } else {
                format!("{text}.0")
            }
        } else {
            // `{:e}` is the shortest round-trip form too: `1e-7`, `1.5e20`.
            let text = format!("{v:e}");
            let (mantissa, exponent) = text.split_once('e').expect("`{:e}` writes an exponent");
            let mantissa = if mantissa.contains('.') { mantissa.to_string() } else { format!("{mantissa}.0") };
            let exponent = exponent.strip_prefix('-').map_or_else(|| format!("+{exponent}"), |e| format!("-{e}"));
            format!("{mantissa}E{exponent}")
        }
    }
}

impl PartialEq for RealLit {
    fn eq(&self, other: &RealLit) -> bool {
        self.0.to_bits() == other.0.to_bits()
    }
}

impl Eq for RealLit {}

impl std::hash::Hash for RealLit {
    fn hash<H: std::hash::Hasher>(&self, state: &mut H) {
        self.0.to_bits().hash(state);
    }
}

/// An expression. Integer arithmetic is on `INT`/`DINT`, real arithmetic on `REAL` (never both
/// in one operation); comparisons yield `BOOL`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Expr {
    Bool(bool),
    Int(i64),
    /// A `REAL` literal ([`Expr::real`]).
    Real(RealLit),
    /// A duration in milliseconds.
    Time(u64),
    Read(Place),
    Not(Box<Expr>),
    Neg(Box<Expr>),
    Binary(BinOp, Box<Expr>, Box<Expr>),
}

impl Expr {
    pub fn read(place: Place) -> Expr {
        Expr::Read(place)
    }

    pub fn global(name: impl Into<String>) -> Expr {
        Expr::Read(Place::global(name))
    }

    /// A `REAL` literal of `x` rounded to `f32`; `None` when that is not finite.
    pub fn real(x: f64) -> Option<Expr> {
        RealLit::new(x).map(Expr::Real)
    }

    /// Arithmetic negation (`-x`).
    #[allow(clippy::should_implement_trait)]
    pub fn neg(self) -> Expr {
        Expr::Neg(Box::new(self))
    }

    pub fn local(name: impl Into<String>) -> Expr {
        Expr::Read(Place::local(name))
    }

    #[allow(clippy::should_implement_trait)]
    pub fn not(self) -> Expr {
        Expr::Not(Box::new(self))
    }

    pub fn binary(op: BinOp, a: Expr, b: Expr) -> Expr {
        Expr::Binary(op, Box::new(a), Box::new(b))
    }

    pub fn and(self, b: Expr) -> Expr {
        Expr::binary(BinOp::And, self, b)
    }

    pub fn or(self, b: Expr) -> Expr {
        Expr::binary(BinOp::Or, self, b)
    }

    pub fn eq(self, b: Expr) -> Expr {
        Expr::binary(BinOp::Eq, self, b)
    }

    pub fn ne(self, b: Expr) -> Expr {
        Expr::binary(BinOp::Ne, self, b)
    }
}

/// A statement.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Stmt {
    /// Printed as a comment line.
    Comment(String),
    Assign {
        target: Place,
        value: Expr,
    },
    /// `IF c1 THEN … ELSIF c2 THEN … ELSE … END_IF`; `arms` is never empty.
    If {
        arms: Vec<(Expr, Vec<Stmt>)>,
        otherwise: Vec<Stmt>,
    },
    /// `CASE selector OF l1, l2: … ELSE … END_CASE` over integer labels.
    Case {
        selector: Expr,
        arms: Vec<(Vec<i64>, Vec<Stmt>)>,
        otherwise: Vec<Stmt>,
    },
    /// A call of a function of the unit, its result (if it has one) stored in `result`.
    CallFunction {
        function: String,
        args: Vec<(String, Expr)>,
        result: Option<Place>,
    },
    /// A call of a block instance (a timer or the user's controller) with its inputs.
    CallInstance {
        instance: Place,
        args: Vec<(String, Expr)>,
    },
    /// A step list: sequential code that keeps its position between calls ([`StepList`]).
    Steps(StepList),
}

/// Sequential code that runs across scans, as a step machine (Peter 2005, 6.7.2): the position
/// is kept in a variable between calls; every call (one scan) enters at the stored position and
/// runs from step to step until a step ends the scan. The structured dialects print it as a
/// `CASE` over the position inside a `WHILE` loop; the jump-list dialects (IL, S7 STL) as a jump
/// table and labels.
///
/// What keeps a scan finite is the builder's promise: within one call, control moves forward
/// but for at most one backward [`Next::Continue`]. The interpreter stops a call that runs more
/// than `2 · steps + 2` steps, as a PLC's watchdog would.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct StepList {
    /// The `INT` local that holds the position between calls.
    pub position: String,
    /// The `BOOL` local the structured dialects loop on (`WHILE NOT done`).
    pub done: String,
    pub steps: Vec<Step>,
}

/// One step of a [`StepList`].
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Step {
    /// The source of the step, printed beside it.
    pub comment: String,
    /// While this is FALSE the scan ends at the step, which runs again in the next scan.
    pub wait: Option<Expr>,
    /// While this is FALSE the step does nothing and control goes on at the next step within
    /// the scan (a branch not taken).
    pub when: Option<Expr>,
    /// What the step does when it takes effect.
    pub actions: Vec<Stmt>,
    /// Where control goes after the actions.
    pub next: Next,
}

/// Where control goes after a step.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Next {
    /// On at step `k` within this scan; past the last step the scan ends and the next one
    /// starts at step 0.
    Continue(usize),
    /// The scan ends; the next one starts at step `k`.
    Resume(usize),
}

impl Stmt {
    pub fn assign(target: Place, value: Expr) -> Stmt {
        Stmt::Assign { target, value }
    }

    pub fn when(condition: Expr, then: Vec<Stmt>) -> Stmt {
        Stmt::If { arms: vec![(condition, then)], otherwise: Vec::new() }
    }
}

/// What kind of POU.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum PouKind {
    /// A function: no memory of its own; reads and writes the unit's globals; its result has
    /// the given type (`None`: no result, `VOID`).
    Function {
        returns: Option<Type>,
    },
    FunctionBlock,
    /// The program the task calls every cycle (an FB called from OB 1 on Siemens targets).
    Program,
}

/// A program organisation unit.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Pou {
    pub kind: PouKind,
    pub name: String,
    /// What it does, printed above it.
    pub comment: String,
    pub inputs: Vec<Var>,
    pub outputs: Vec<Var>,
    /// Static variables (function blocks and programs) or temporaries (functions).
    pub locals: Vec<Var>,
    pub body: Vec<Stmt>,
}

/// A compilation unit: everything the printers need for one generated framework.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Unit {
    /// The unit's name: file names and the global data block derive from it.
    pub name: String,
    /// Comment lines for the head of every file.
    pub header: Vec<String>,
    /// Name of the global variable list (IEC, CODESYS, TwinCAT) or data block (SCL, STL).
    pub gvl: String,
    /// Named constants (`VAR_GLOBAL CONSTANT`), each with an `init`.
    pub constants: Vec<Var>,
    /// Global variables.
    pub globals: Vec<Var>,
    pub signals: Vec<Signal>,
    /// In call order: a POU only calls POUs before it; the last is the program.
    pub pous: Vec<Pou>,
}

impl Unit {
    /// The global or constant named `name`.
    pub fn global(&self, name: &str) -> Option<&Var> {
        self.constants.iter().chain(&self.globals).find(|v| v.name == name)
    }

    /// The POU named `name`.
    pub fn pou(&self, name: &str) -> Option<&Pou> {
        self.pous.iter().find(|p| p.name == name)
    }

    /// The unit without named constants: every read of a constant replaced by its value
    /// (constants defined through other constants resolved first), for tools whose import
    /// takes no `VAR_GLOBAL CONSTANT` (the ABB target). The code does the same: a constant is
    /// never written, so reading its value in place of its name changes nothing.
    pub fn inline_constants(&self) -> Unit {
        let mut values: Vec<(String, Expr)> = Vec::new();
        for c in &self.constants {
            let value = c.init.clone().unwrap_or(Expr::Int(0));
            let value = substitute(&value, &values);
            values.push((c.name.clone(), value));
        }
        let var = |v: &Var| Var { init: v.init.as_ref().map(|e| substitute(e, &values)), ..v.clone() };
        Unit {
            constants: Vec::new(),
            globals: self.globals.iter().map(var).collect(),
            pous: self
                .pous
                .iter()
                .map(|p| Pou {
                    inputs: p.inputs.iter().map(var).collect(),
                    outputs: p.outputs.iter().map(var).collect(),
                    locals: p.locals.iter().map(var).collect(),
                    body: p.body.iter().map(|s| substitute_stmt(s, &values)).collect(),
                    ..p.clone()
                })
                .collect(),
            ..self.clone()
        }
    }
}

/// `e` with every read of a global named in `values` replaced by its value.
fn substitute(e: &Expr, values: &[(String, Expr)]) -> Expr {
    match e {
        Expr::Read(Place::Global(name)) => {
            values.iter().find(|(n, _)| n == name).map_or_else(|| e.clone(), |(_, v)| v.clone())
        }
        Expr::Not(a) => Expr::Not(Box::new(substitute(a, values))),
        Expr::Neg(a) => Expr::Neg(Box::new(substitute(a, values))),
        Expr::Binary(op, a, b) => Expr::Binary(*op, Box::new(substitute(a, values)), Box::new(substitute(b, values))),
        _ => e.clone(),
    }
}

fn substitute_stmt(s: &Stmt, values: &[(String, Expr)]) -> Stmt {
    let block = |list: &[Stmt]| list.iter().map(|s| substitute_stmt(s, values)).collect::<Vec<_>>();
    let args = |list: &[(String, Expr)]| list.iter().map(|(n, e)| (n.clone(), substitute(e, values))).collect();
    match s {
        Stmt::Comment(_) => s.clone(),
        Stmt::Assign { target, value } => Stmt::Assign { target: target.clone(), value: substitute(value, values) },
        Stmt::If { arms, otherwise } => Stmt::If {
            arms: arms.iter().map(|(c, body)| (substitute(c, values), block(body))).collect(),
            otherwise: block(otherwise),
        },
        Stmt::Case { selector, arms, otherwise } => Stmt::Case {
            selector: substitute(selector, values),
            arms: arms.iter().map(|(labels, body)| (labels.clone(), block(body))).collect(),
            otherwise: block(otherwise),
        },
        Stmt::CallFunction { function, args: a, result } => {
            Stmt::CallFunction { function: function.clone(), args: args(a), result: result.clone() }
        }
        Stmt::CallInstance { instance, args: a } => Stmt::CallInstance { instance: instance.clone(), args: args(a) },
        Stmt::Steps(list) => Stmt::Steps(StepList {
            steps: list
                .steps
                .iter()
                .map(|step| Step {
                    wait: step.wait.as_ref().map(|e| substitute(e, values)),
                    when: step.when.as_ref().map(|e| substitute(e, values)),
                    actions: block(&step.actions),
                    ..step.clone()
                })
                .collect(),
            ..list.clone()
        }),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn real_literals_are_the_shortest_iec_text_that_reads_back() {
        let text = |x: f64| RealLit::new(x).unwrap().iec_text();
        assert_eq!(text(3.0), "3.0");
        assert_eq!(text(3.5), "3.5");
        assert_eq!(text(-0.25), "-0.25");
        assert_eq!(text(-0.0), "0.0");
        assert_eq!(text(0.1), "0.1");
        assert_eq!(text(1e-3), "0.001");
        assert_eq!(text(1e-7), "1.0E-7");
        assert_eq!(text(1.5e20), "1.5E+20");
        assert_eq!(text(16_777_216.0), "1.6777216E+7");
        assert_eq!(text(1_234_567.0), "1234567.0");
        assert!(RealLit::new(1e39).is_none() && RealLit::new(f64::NAN).is_none());
        for k in 0..5000u32 {
            let x = f32::from_bits(0x0080_0000 + k * 425_775);
            if !x.is_finite() {
                continue;
            }
            let t = RealLit::new(f64::from(x)).unwrap().iec_text();
            assert!(t.contains('.'), "{t}");
            let mantissa = t.split('E').next().unwrap();
            assert!(mantissa.trim_start_matches('-').split('.').all(|d| !d.is_empty()), "{t}");
            assert_eq!(t.parse::<f32>().unwrap().to_bits(), x.to_bits(), "{t}");
        }
        assert_eq!(RealLit::new(0.1).unwrap(), RealLit::new(0.1f32 as f64).unwrap());
    }

    #[test]
    fn direct_addresses_pack_bits_then_words() {
        let got = direct_addresses('I', &[Type::Real, Type::Bool, Type::Int, Type::Bool, Type::Real, Type::Ton]);
        let want = [Some("ID2"), Some("IX0.0"), Some("IW6"), Some("IX0.1"), Some("ID8"), None];
        assert_eq!(got, want.map(|a| a.map(String::from)));
        let bits: Vec<Type> = (0..17).map(|_| Type::Bool).chain([Type::Real]).collect();
        assert_eq!(direct_addresses('Q', &bits)[16..], [Some("QX2.0".into()), Some("QD4".into())]);
    }
}
