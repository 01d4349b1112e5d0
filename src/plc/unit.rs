//! The structured half of the neutral code model: program organisation units (functions,
//! function blocks, a program) over typed variables, with expressions, `IF` and `CASE` — what a
//! framework of cooperating blocks needs, where [`super::model::Code`] is one step machine.
//! It names no engine: a lowering (such as `lower_sct`) builds a [`Unit`]; printers (`unit_st`
//! for the Structured Text dialects, PLCopen and TwinCAT, `unit_stl` for S7 AWL) turn it into
//! text.
//!
//! Three kinds of names meet here, and printers write each as its dialect wants:
//! - globals of the unit ([`Place::Global`]), kept in the unit's global variable list (IEC,
//!   CODESYS, TwinCAT) or its global data block (SCL, STL);
//! - locals and parameters of the POU being printed ([`Place::Local`]);
//! - signals of the user's project ([`Place::Signal`]): I/O symbols, direct addresses and
//!   controller variables, declared elsewhere, listed in [`Unit::signals`] with an address a
//!   printer may use when the dialect cannot write the symbol (STL).

pub use super::fragment::BinOp;

/// Elementary and block types the unit uses.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Type {
    Bool,
    /// 16-bit signed integer (`INT`).
    Int,
    /// 32-bit signed integer (`DINT`).
    Dint,
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
}

impl Var {
    pub fn new(name: impl Into<String>, ty: Type, comment: impl Into<String>) -> Var {
        Var { name: name.into(), ty, init: None, comment: comment.into() }
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

/// A signal of the user's project that the unit reads or writes but does not declare.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Signal {
    /// The name as the user's project writes it: a symbol (`Q_Inlet`, `GVL.lamp`) or a direct
    /// address without `%` (`IX0.1`), see [`Signal::is_address`].
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

/// An expression. Integer arithmetic is on `INT`/`DINT`; comparisons yield `BOOL`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Expr {
    Bool(bool),
    Int(i64),
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
}
