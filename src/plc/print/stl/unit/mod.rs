//! Siemens S7 Statement List (AWL) of a structured [`Unit`], in the form awlsim and STEP 7
//! Classic sources accept.
//!
//! How the unit maps onto S7 blocks:
//! - The globals (BOOL, INT, DINT, TIME, REAL) live in one global data block, `DB first_db`, declared
//!   as a STRUCT with their initial values. Code addresses them absolutely (`DB1.DBW 2`), so the
//!   file needs no symbol table; the header lists each global with its address, for an HMI or a
//!   watch table ([`global_locations`] gives the same table to programs).
//! - STL has no named constants: every read of a constant is printed as its literal. The header
//!   keeps a table of the constants' names and values (event ids the user's controller needs).
//! - Functions become FCs numbered from `first_fc` in the unit's order: inputs as `VAR_INPUT`,
//!   the result as `RET_VAL` (the function's own name in its body), locals as `VAR_TEMP`. S7 leaves temporaries and `RET_VAL`
//!   undefined on entry, so every FC starts by setting its locals to their initial values and its
//!   result to the type's default, as IEC 61131-3 does. Arguments are copied into temporaries of
//!   the caller before `CALL` (S7 passes FC parameters by reference; IEC by value), and the
//!   result comes back through a temporary, so a function that writes a global passed to it sees
//!   what an IEC function would. (An FB copies its inputs into its instance at the call, so a
//!   variable of the formal's type is passed to it as it is.)
//! - Function blocks become FBs numbered from `first_fb`, the program last. Each instance (the
//!   program's, and every global or program-local instance of a timer or of a function block of
//!   the unit) gets its own instance data block numbered after the global data block; initial
//!   values of statics are written in the instance DB's `BEGIN` section (awlsim ignores
//!   initial values in an FB's declaration). `OB ob` calls the program's FB with its DB.
//! - Timers (`TON`) are instances of SFB 4. A global timer or one local to the program has its
//!   own instance DB (`CALL SFB 4, DB n`), and its members are read from the DB's fixed layout
//!   (`IN` 0.0, `PT` 2, `Q` 6.0, `ET` 8), so an HMI finds them. A timer local to a function
//!   block of the unit (which may have several instances) is a multi-instance (`t : SFB 4` in
//!   `VAR`); awlsim cannot address fields of a multi-instance (`#t.Q`), so its call copies `Q`
//!   and `ET` into statics `t_Q` and `t_ET` (`CALL #t (IN := …, PT := …, Q := #t_Q, ET :=
//!   #t_ET)`), which is what reading them means in IEC: outputs change only during a call.
//!   Instances of the unit's function blocks have their own DB too (globals and locals of the
//!   program); inside a function block [`check`] refuses them.
//! - An instance of a block type the unit does not define is the user's controller:
//!   `CALL FB controller_fb, DB controller_db`, with the arguments given. The user's project
//!   provides that FB and its DB; the header lists what the controller may call (the FCs and
//!   their parameters).
//! - Signals are addressed by their address (`IX0.1` → `I 0.1`, `IW4` → `IW 4`, `MD8` → `MD 8`);
//!   the address's size must suit the signal's type (bit for BOOL, word for INT, double word for
//!   DINT, TIME and REAL: `ID4` → `ID 4`).
//! - BOOL expressions run through the RLO: `A`/`O`/`X` with their negated forms for simple
//!   operands and nesting brackets (`A(` … `)`, `AN(` … `)`) for composite ones; a bracket
//!   deeper than six levels (S7 allows seven) is computed first into a temporary bit.
//!   Comparisons (`==I`, `<D`, …) load both sides into the accumulators and leave their result
//!   in the RLO, always as the first check of a bracket (a comparison replaces the RLO).
//!   Arithmetic works in 16 bits (`+I`, `MOD` as the remainder of `/I`) when both sides are INT,
//!   in 32 bits (`+D`, `MOD`) when one side is DINT or TIME (INT operands widened with `ITD`);
//!   an integer literal is INT when it fits in 16 bits. A right operand that is not a plain load
//!   is computed first into a temporary. INT results wrap at 16 bits, as the CPU's do; a
//!   division by zero gives 0, the divisor left in the accumulator (IEC leaves it undefined).
//! - REAL arithmetic and comparisons use the floating-point instructions (`+R -R *R /R`,
//!   `NEGR`, `==R <>R <R <=R >R >=R`) on 32-bit IEEE values held in double words; a literal is
//!   loaded in the S7 real format (`L 3.500000e+00`, with 7 significant digits, or 8 or 9 when
//!   the `f32` needs them to read back exactly). An operation, assignment or parameter that
//!   mixes REAL with an integer type is an error (IEC converts only explicitly).
//! - `IF`/`ELSIF`/`ELSE` jump with `JCN`/`JU` to labels `L000`, `L001`, … (four characters,
//!   unique per block); `CASE` uses a `JL` jump list after a range check when its labels are
//!   small non-negative integers with few gaps, and a chain of comparisons otherwise.
//! - Comments of the unit, its POUs, variables and statements are printed as `//` comments, and
//!   every statement is preceded by its Structured Text form.

mod check;
mod expr;
mod layout;
mod stmt;

pub use self::check::check;
pub use layout::{global_locations, instance_locations, program_locations, Location};

use crate::plc::model::unit::{Expr, Place, Pou, PouKind, RealLit, Type, Unit, Var};
use expr::{expr_text, signal_operand};
use layout::{blocks, Blocks, Owner};
use std::fmt::{self, Write};
use stmt::generate;

/// Block numbers of the printed STL.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct StlUnitOptions {
    /// The organisation block that calls the program (`OB 1`).
    pub ob: u16,
    /// The first FC number: the unit's functions are `FC first_fc`, `FC first_fc + 1`, … in order.
    pub first_fc: u16,
    /// The first FB number: the unit's function blocks, then the program.
    pub first_fb: u16,
    /// The global data block; instance DBs follow it.
    pub first_db: u16,
    /// The FB of the user's controller (an instance of a type the unit does not define).
    pub controller_fb: u16,
    /// The instance DB of the user's controller.
    pub controller_db: u16,
}

impl Default for StlUnitOptions {
    fn default() -> StlUnitOptions {
        StlUnitOptions { ob: 1, first_fc: 1, first_fb: 1, first_db: 1, controller_fb: 100, controller_db: 100 }
    }
}

/// Scalar types as STL handles them.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Ty {
    Bool,
    Int,
    Dint,
    Time,
    Real,
}

impl Ty {
    fn of(ty: &Type) -> Option<Ty> {
        match ty {
            Type::Bool => Some(Ty::Bool),
            Type::Int => Some(Ty::Int),
            Type::Dint => Some(Ty::Dint),
            Type::Time => Some(Ty::Time),
            Type::Real => Some(Ty::Real),
            _ => None,
        }
    }

    fn wide(self) -> bool {
        matches!(self, Ty::Dint | Ty::Time | Ty::Real)
    }

    fn name(self) -> &'static str {
        match self {
            Ty::Bool => "BOOL",
            Ty::Int => "INT",
            Ty::Dint => "DINT",
            Ty::Time => "TIME",
            Ty::Real => "REAL",
        }
    }
}

fn type_name(ty: &Type) -> String {
    match ty {
        Type::Bool => "BOOL".into(),
        Type::Int => "INT".into(),
        Type::Dint => "DINT".into(),
        Type::Time => "TIME".into(),
        Type::Real => "REAL".into(),
        Type::Ton => "TON".into(),
        Type::Instance(name) => name.clone(),
    }
}

/// A REAL literal in the S7 format (`3.500000e+00`, `-2.500000e-01`, `0.000000e+00`): seven
/// significant digits as STEP 7 writes them, or eight or nine when the `f32` needs them to read
/// back exactly.
fn real_literal(r: RealLit) -> String {
    let v = r.value();
    let text = (6..=8)
        .map(|p| format!("{v:.p$e}"))
        .find(|t| t.parse::<f32>().ok().map(f32::to_bits) == Some(v.to_bits()))
        .unwrap_or_else(|| format!("{v:.8e}"));
    let (mantissa, exponent) = text.split_once('e').expect("`{:e}` writes an exponent");
    let exponent: i32 = exponent.parse().expect("an integer exponent");
    let sign = if exponent < 0 { '-' } else { '+' };
    format!("{mantissa}e{sign}{:02}", exponent.unsigned_abs())
}

/// A valid STL variable name (as awlsim and STEP 7 check them).
fn valid_name(name: &str) -> bool {
    let mut chars = name.chars();
    chars.next().is_some_and(|c| c.is_ascii_alphabetic() || c == '_')
        && name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_')
        && !name.ends_with('_')
        && !name.contains("__")
        && name.len() <= 24
}

/// Four-character label number `n`: `L000` … `LZZZ`, then `M000` …
fn label(n: usize) -> String {
    const FIRST: &[u8] = b"LMNOPQRSTUVWXYZABCDEFGHIJK";
    const DIGITS: &[u8] = b"0123456789ABCDEFGHIJKLMNOPQRSTUVWXYZ";
    let per = 36 * 36 * 36;
    let mut s = String::new();
    s.push(FIRST[(n / per) % FIRST.len()] as char);
    let r = n % per;
    for d in [r / 1296, r / 36 % 36, r % 36] {
        s.push(DIGITS[d] as char);
    }
    s
}

const LABELS_MAX: usize = 26 * 36 * 36 * 36;

/// Bracket levels an expression may open; S7 nests seven.
const MAX_DEPTH: usize = 6;

/// Temporaries: bits, words, double words.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum TempKind {
    X,
    W,
    D,
}

impl TempKind {
    fn of(ty: Ty) -> TempKind {
        match ty {
            Ty::Bool => TempKind::X,
            Ty::Int => TempKind::W,
            _ => TempKind::D,
        }
    }

    fn index(self) -> usize {
        self as usize
    }
}

/// Integer literal fitting in an INT.
fn fits_int(n: i64) -> bool {
    (-32768..=32767).contains(&n)
}

/// Code generation of one POU.
struct Gen<'a> {
    unit: &'a Unit,
    options: &'a StlUnitOptions,
    blocks: &'a Blocks,
    pou: &'a Pou,
    code: String,
    labels: usize,
    temps: [usize; 3],
    max_temps: [usize; 3],
    temp_prefix: String,
    /// Code of BOOL subexpressions too deep to nest, to run before the expression.
    hoisted: Vec<String>,
    errors: Vec<String>,
}

impl<'a> Gen<'a> {
    fn new(unit: &'a Unit, options: &'a StlUnitOptions, blocks: &'a Blocks, pou: &'a Pou) -> Gen<'a> {
        let names: Vec<String> =
            pou.inputs.iter().chain(&pou.outputs).chain(&pou.locals).map(|v| v.name.to_ascii_lowercase()).collect();
        let mut temp_prefix = String::from("t");
        while names.iter().any(|n| n.starts_with(&temp_prefix) && n.len() > temp_prefix.len() + 1) {
            temp_prefix.insert(0, 'z');
        }
        Gen {
            unit,
            options,
            blocks,
            pou,
            code: String::new(),
            labels: 0,
            temps: [0; 3],
            max_temps: [0; 3],
            temp_prefix,
            hoisted: Vec::new(),
            errors: Vec::new(),
        }
    }

    fn error(&mut self, message: String) {
        let _ = writeln!(self.code, "// ERROR: {message}");
        self.errors.push(format!("{}: {message}", self.pou.name));
    }

    fn emit(&mut self, line: &str) {
        self.code.push('\t');
        self.code.push_str(line);
        self.code.push('\n');
    }

    fn comment(&mut self, text: &str) {
        for line in text.lines() {
            let _ = writeln!(self.code, "\t// {line}");
        }
    }

    fn new_label(&mut self) -> String {
        let l = label(self.labels);
        if self.labels == LABELS_MAX {
            self.error("more than 1213056 labels in one block".into());
        }
        self.labels += 1;
        l
    }

    fn place_label(&mut self, l: &str) {
        let _ = writeln!(self.code, "{l}:\tNOP\t0");
    }

    fn temp_name(&self, kind: TempKind, k: usize) -> String {
        let letter = match kind {
            TempKind::X => 'x',
            TempKind::W => 'w',
            TempKind::D => 'd',
        };
        format!("{}{letter}{k}", self.temp_prefix)
    }

    fn push_temp(&mut self, kind: TempKind) -> String {
        let i = kind.index();
        let k = self.temps[i];
        self.temps[i] += 1;
        self.max_temps[i] = self.max_temps[i].max(self.temps[i]);
        format!("#{}", self.temp_name(kind, k))
    }

    fn pop_temp(&mut self, kind: TempKind) {
        self.temps[kind.index()] -= 1;
    }

    fn is_function(&self) -> bool {
        matches!(self.pou.kind, PouKind::Function { .. })
    }

    fn local(&self, name: &str) -> Option<&'a Var> {
        self.pou.inputs.iter().chain(&self.pou.outputs).chain(&self.pou.locals).find(|v| v.name == name)
    }

    /// The declared type of a place.
    fn place_type(&self, place: &Place) -> Result<Type, String> {
        match place {
            Place::Global(name) => {
                self.unit.global(name).map(|v| v.ty.clone()).ok_or_else(|| format!("unknown global `{name}`"))
            }
            Place::Local(name) => {
                if let PouKind::Function { returns } = &self.pou.kind {
                    if *name == self.pou.name {
                        return returns.clone().ok_or_else(|| format!("function `{name}` has no result"));
                    }
                }
                self.local(name).map(|v| v.ty.clone()).ok_or_else(|| format!("unknown local `{name}`"))
            }
            Place::Signal(i) => {
                self.unit.signals.get(*i).map(|s| s.ty.clone()).ok_or_else(|| format!("unknown signal number {i}"))
            }
            Place::Member(inner, field) => match self.place_type(inner)? {
                Type::Ton => match field.to_ascii_uppercase().as_str() {
                    "IN" | "Q" => Ok(Type::Bool),
                    "PT" | "ET" => Ok(Type::Time),
                    _ => Err(format!("a TON has no member `{field}`")),
                },
                Type::Instance(ty) => match self.unit.pou(&ty) {
                    Some(fb) if fb.kind == PouKind::FunctionBlock => fb
                        .inputs
                        .iter()
                        .chain(&fb.outputs)
                        .find(|v| v.name == *field)
                        .map(|v| v.ty.clone())
                        .ok_or_else(|| format!("function block `{ty}` has no input or output `{field}`")),
                    _ => Err(format!(
                        "cannot read `{field}` of the controller instance: its layout is the user's (read the \
                         controller's outputs through signals)"
                    )),
                },
                other => Err(format!("`{}` is not a block instance", type_name(&other))),
            },
        }
    }

    /// The instance DB of an instance place (a global, or a local of the program).
    fn instance_db(&self, place: &Place) -> Option<u16> {
        let (owner, name) = match place {
            Place::Global(name) => (Owner::Global, name),
            Place::Local(name) if self.pou.kind == PouKind::Program => (Owner::Program, name),
            _ => return None,
        };
        self.blocks.instances.iter().find(|(o, n, _, _)| *o == owner && n == name).map(|x| x.3)
    }

    /// The timer local to this function block that `place` names (a multi-instance of SFB 4).
    fn block_timer(&self, place: &Place) -> Option<&'a str> {
        let Place::Local(name) = place else { return None };
        if self.pou.kind != PouKind::FunctionBlock {
            return None;
        }
        self.pou.locals.iter().find(|v| v.name == *name && v.ty == Type::Ton).map(|v| v.name.as_str())
    }

    /// The literal of a constant, when `place` names one.
    fn constant(&self, place: &Place) -> Option<Expr> {
        let Place::Global(name) = place else { return None };
        let c = self.unit.constants.iter().find(|v| v.name == *name)?;
        Some(c.init.clone().unwrap_or(match c.ty {
            Type::Bool => Expr::Bool(false),
            Type::Time => Expr::Time(0),
            Type::Real => Expr::Real(RealLit::new(0.0).expect("0.0 is finite")),
            _ => Expr::Int(0),
        }))
    }
}

/// The static that keeps output `field` of timer `timer` local to a function block.
fn shadow(timer: &str, field: &str) -> String {
    format!("{timer}_{field}")
}

/// `T#1D2H3M4S5MS`: a TIME literal in the units STEP 7 writes (each below its next unit).
fn time_literal(ms: i64) -> String {
    let sign = if ms < 0 { "-" } else { "" };
    let ms = ms.unsigned_abs();
    let parts = [
        (ms / 86_400_000, "D"),
        (ms / 3_600_000 % 24, "H"),
        (ms / 60_000 % 60, "M"),
        (ms / 1000 % 60, "S"),
        (ms % 1000, "MS"),
    ];
    let mut text = format!("T#{sign}");
    for (v, unit) in parts {
        if v > 0 {
            text.push_str(&format!("{v}{unit}"));
        }
    }
    if ms == 0 {
        text.push_str("0MS");
    }
    text
}

fn default_value(ty: Ty) -> Expr {
    match ty {
        Ty::Bool => Expr::Bool(false),
        Ty::Time => Expr::Time(0),
        Ty::Real => Expr::Real(RealLit::new(0.0).expect("0.0 is finite")),
        _ => Expr::Int(0),
    }
}

/// The literal of an initial value in a declaration or a DB's `BEGIN` section.
fn init_literal(var: &Var, constants: &Unit) -> Option<String> {
    let init = var.init.as_ref()?;
    let init = match init {
        Expr::Read(Place::Global(name)) => constants.constants.iter().find(|c| c.name == *name)?.init.as_ref()?,
        e => e,
    };
    Some(match (init, &var.ty) {
        (Expr::Bool(b), _) => (if *b { "TRUE" } else { "FALSE" }).into(),
        (Expr::Real(r), Type::Real) => real_literal(*r),
        (Expr::Int(n), Type::Int) => n.to_string(),
        (Expr::Int(n), Type::Dint) => format!("L#{n}"),
        (Expr::Int(n), Type::Time) => time_literal(*n),
        (Expr::Time(ms), _) => time_literal(i64::try_from(*ms).ok()?),
        _ => return None,
    })
}

fn declare(o: &mut impl Write, section: &str, vars: &[&Var], unit: &Unit) -> fmt::Result {
    if vars.is_empty() {
        return Ok(());
    }
    writeln!(o, "{section}")?;
    for v in vars {
        let ty = match &v.ty {
            Type::Ton => "SFB 4".to_string(),
            other => type_name(other),
        };
        let init = init_literal(v, unit).map(|l| format!(" := {l}")).unwrap_or_default();
        let comment = if v.comment.is_empty() { String::new() } else { format!("\t// {}", v.comment) };
        writeln!(o, "\t{} : {ty}{init};{comment}", v.name)?;
    }
    writeln!(o, "END_VAR")
}

fn params_text(pou: &Pou) -> String {
    pou.inputs.iter().map(|v| format!("{} : {}", v.name, type_name(&v.ty))).collect::<Vec<_>>().join(", ")
}

fn instance_db_text(o: &mut impl Write, db: u16, block: &str, what: &str, inits: &[(String, String)]) -> fmt::Result {
    writeln!(o, "// {what}\nDATA_BLOCK DB {db}\n\t{block}\nBEGIN")?;
    for (name, value) in inits {
        writeln!(o, "\t{name} := {value};")?;
    }
    writeln!(o, "END_DATA_BLOCK\n")
}

/// The header comment: blocks, globals with their addresses, constants, signals.
fn header(unit: &Unit, options: &StlUnitOptions, blocks: &Blocks, o: &mut String) -> fmt::Result {
    for line in &unit.header {
        writeln!(o, "// {line}")?;
    }
    writeln!(o, "// Unit {} as Siemens S7 STL (AWL).", unit.name)?;
    writeln!(o, "//\n// Blocks:")?;
    writeln!(o, "//   DB {:<6} {} (global data)", options.first_db, unit.gvl)?;
    for pou in &unit.pous {
        match &pou.kind {
            PouKind::Function { returns } => {
                let r = returns.as_ref().map_or("VOID".into(), type_name);
                writeln!(o, "//   FC {:<6} FUNCTION {}({}) : {r}", blocks.fc[&pou.name], pou.name, params_text(pou))?;
            }
            PouKind::FunctionBlock => {
                writeln!(o, "//   FB {:<6} FUNCTION_BLOCK {}({})", blocks.fb[&pou.name], pou.name, params_text(pou))?
            }
            PouKind::Program => writeln!(
                o,
                "//   FB {:<6} PROGRAM {}, instance DB {}, called from OB {}",
                blocks.fb[&pou.name], pou.name, blocks.program_db, options.ob
            )?,
        }
    }
    for (owner, name, ty, db) in &blocks.instances {
        let whose = match owner {
            Owner::Global => "global".to_string(),
            Owner::Program => format!("{} local", unit.pous.last().map_or("", |p| &p.name)),
        };
        let block = match ty {
            Type::Ton => "SFB 4 (TON)".to_string(),
            Type::Instance(t) => format!("FB {} ({t})", blocks.fb.get(t).copied().unwrap_or(0)),
            _ => String::new(),
        };
        writeln!(o, "//   DB {db:<6} {whose} {name}: instance of {block}")?;
    }
    let controller: Vec<&Var> = unit
        .globals
        .iter()
        .chain(unit.pous.iter().flat_map(|p| &p.locals))
        .filter(|v| matches!(&v.ty, Type::Instance(t) if unit.pou(t).is_none()))
        .collect();
    for v in &controller {
        writeln!(
            o,
            "//   FB {:<6} {} (the user's controller, instance DB {}, called as `{}`; not in this file)",
            options.controller_fb,
            type_name(&v.ty),
            options.controller_db,
            v.name
        )?;
    }
    writeln!(o, "//   OB {:<6} calls the program", options.ob)?;
    if !blocks.globals.is_empty() {
        writeln!(o, "//\n// Globals (DB {}):", options.first_db)?;
        for (loc, v) in blocks.globals.iter().zip(unit.globals.iter().filter(|v| Ty::of(&v.ty).is_some())) {
            writeln!(o, "//   {:<24} {:<5} {:<16} {}", loc.name, type_name(&loc.ty), loc.operand(), v.comment)?;
        }
    }
    let statics = program_locations(unit, options);
    if let (false, Some(program)) = (statics.is_empty(), unit.pous.last()) {
        writeln!(o, "//\n// Variables of the program {} (its instance DB {}):", program.name, blocks.program_db)?;
        let vars = program.inputs.iter().chain(&program.outputs).chain(&program.locals);
        for (loc, v) in statics.iter().zip(vars.filter(|v| Ty::of(&v.ty).is_some())) {
            writeln!(o, "//   {:<24} {:<5} {:<16} {}", loc.name, type_name(&loc.ty), loc.operand(), v.comment)?;
        }
    }
    if !unit.constants.is_empty() {
        writeln!(o, "//\n// Constants (STL has none; their values are written where they are read):")?;
        for c in &unit.constants {
            let value = c.init.as_ref().map_or_else(String::new, |e| expr_text(unit, e));
            writeln!(o, "//   {:<24} {:<5} {:<16} {}", c.name, type_name(&c.ty), value, c.comment)?;
        }
    }
    if !unit.signals.is_empty() {
        writeln!(o, "//\n// Signals:")?;
        for s in &unit.signals {
            let address =
                Ty::of(&s.ty).and_then(|t| signal_operand(&s.address, t).ok()).unwrap_or_else(|| s.address.clone());
            writeln!(o, "//   {:<10} {:<24} {:?} {}", address, s.symbol, s.kind, s.comment)?;
        }
    }
    Ok(())
}

/// Prints `unit` as S7 STL: a header with the block and address tables, the global DB, the
/// FCs, FBs with their instance DBs, and the OB that calls the program. Problems [`check`]
/// reports are printed as `// ERROR:` comments where they occur.
pub fn print(unit: &Unit, options: &StlUnitOptions, o: &mut impl Write) -> fmt::Result {
    let blocks = blocks(unit, options);
    let gens: Vec<Gen> = unit.pous.iter().map(|p| generate(unit, options, &blocks, p)).collect();
    let mut head = String::new();
    header(unit, options, &blocks, &mut head)?;
    for line in head.lines() {
        writeln!(o, "{}", line.trim_end())?;
    }
    writeln!(o)?;
    // The global data block.
    writeln!(o, "DATA_BLOCK DB {}\n\tSTRUCT", options.first_db)?;
    let scalars: Vec<&Var> = unit.globals.iter().filter(|v| Ty::of(&v.ty).is_some()).collect();
    for v in &scalars {
        let init = init_literal(v, unit).map(|l| format!(" := {l}")).unwrap_or_default();
        let comment = if v.comment.is_empty() { String::new() } else { format!("\t// {}", v.comment) };
        writeln!(o, "\t\t{} : {}{init};{comment}", v.name, type_name(&v.ty))?;
    }
    if scalars.is_empty() {
        writeln!(o, "\t\tunused : BOOL;")?;
    }
    writeln!(o, "\tEND_STRUCT;\nBEGIN\nEND_DATA_BLOCK\n")?;
    for (owner, name, ty, db) in &blocks.instances {
        if *ty == Type::Ton {
            let whose = if *owner == Owner::Global { "global" } else { "program local" };
            instance_db_text(o, *db, "SFB 4", &format!("timer {name} ({whose})"), &[])?;
        }
    }
    for (pou, g) in unit.pous.iter().zip(&gens) {
        if !pou.comment.is_empty() {
            for line in pou.comment.lines() {
                writeln!(o, "// {line}")?;
            }
        }
        let inputs: Vec<&Var> = pou.inputs.iter().collect();
        let outputs: Vec<&Var> = pou.outputs.iter().collect();
        let (statics, temps): (Vec<&Var>, Vec<&Var>) = match pou.kind {
            PouKind::Function { .. } => (Vec::new(), pou.locals.iter().collect()),
            PouKind::FunctionBlock => {
                (pou.locals.iter().filter(|v| !matches!(v.ty, Type::Instance(_))).collect(), Vec::new())
            }
            PouKind::Program => (pou.locals.iter().filter(|v| Ty::of(&v.ty).is_some()).collect(), Vec::new()),
        };
        let shadows: Vec<Var> = statics
            .iter()
            .filter(|v| v.ty == Type::Ton)
            .flat_map(|v| {
                [
                    Var::new(shadow(&v.name, "Q"), Type::Bool, format!("{}.Q, copied by its call", v.name)),
                    Var::new(shadow(&v.name, "ET"), Type::Time, format!("{}.ET, copied by its call", v.name)),
                ]
            })
            .collect();
        let statics: Vec<&Var> = statics.into_iter().chain(&shadows).collect();
        let generated: Vec<Var> = [TempKind::X, TempKind::W, TempKind::D]
            .into_iter()
            .flat_map(|k| {
                let ty = match k {
                    TempKind::X => Type::Bool,
                    TempKind::W => Type::Int,
                    TempKind::D => Type::Dint,
                };
                (0..g.max_temps[k.index()]).map(move |i| Var::new(g.temp_name(k, i), ty.clone(), ""))
            })
            .collect();
        let mut temps: Vec<&Var> = temps;
        let temps_without_init: Vec<Var> = temps.iter().map(|v| Var { init: None, ..(*v).clone() }).collect();
        temps = temps_without_init.iter().chain(&generated).collect();
        match &pou.kind {
            PouKind::Function { returns } => {
                let r = returns.as_ref().map_or("VOID".into(), type_name);
                writeln!(o, "FUNCTION FC {} : {r}\t// {}", blocks.fc[&pou.name], pou.name)?;
            }
            _ => writeln!(o, "FUNCTION_BLOCK FB {}\t// {}", blocks.fb[&pou.name], pou.name)?,
        }
        declare(o, "VAR_INPUT", &inputs, unit)?;
        declare(o, "VAR_OUTPUT", &outputs, unit)?;
        declare(o, "VAR", &statics, unit)?;
        declare(o, "VAR_TEMP", &temps, unit)?;
        writeln!(o, "BEGIN")?;
        o.write_str(&g.code)?;
        match pou.kind {
            PouKind::Function { .. } => writeln!(o, "END_FUNCTION\n")?,
            _ => writeln!(o, "END_FUNCTION_BLOCK\n")?,
        }
        // Instance DBs of this block, with the initial values of its statics.
        let inits: Vec<(String, String)> = pou
            .inputs
            .iter()
            .chain(&pou.outputs)
            .chain(&statics.iter().copied().cloned().collect::<Vec<_>>())
            .filter_map(|v| init_literal(v, unit).map(|l| (v.name.clone(), l)))
            .collect();
        if pou.kind == PouKind::FunctionBlock {
            for (owner, name, ty, db) in &blocks.instances {
                if *ty == Type::Instance(pou.name.clone()) {
                    let whose = if *owner == Owner::Global { "global" } else { "program local" };
                    let what = format!("instance {name} of {} ({whose})", pou.name);
                    instance_db_text(o, *db, &format!("FB {}", blocks.fb[&pou.name]), &what, &inits)?;
                }
            }
        }
        if pou.kind == PouKind::Program {
            let what = format!("instance of the program {}", pou.name);
            instance_db_text(o, blocks.program_db, &format!("FB {}", blocks.fb[&pou.name]), &what, &inits)?;
        }
    }
    if let Some(program) = unit.pous.last().filter(|p| p.kind == PouKind::Program) {
        writeln!(
            o,
            "ORGANIZATION_BLOCK OB {}\nBEGIN\n\tCALL\tFB {}, DB {}\t// {}\nEND_ORGANIZATION_BLOCK",
            options.ob, blocks.fb[&program.name], blocks.program_db, program.name
        )?;
    }
    Ok(())
}

/// [`print()`] into a string.
pub fn render(unit: &Unit, options: &StlUnitOptions) -> String {
    let mut text = String::new();
    print(unit, options, &mut text).expect("writing to a String cannot fail");
    text
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn labels_are_four_characters_and_unique() {
        assert_eq!(label(0), "L000");
        assert_eq!(label(35), "L00Z");
        assert_eq!(label(36), "L010");
        assert_eq!(label(46_656), "M000");
        let all: std::collections::HashSet<String> = (0..LABELS_MAX).step_by(997).map(label).collect();
        assert_eq!(all.len(), LABELS_MAX.div_ceil(997));
    }

    #[test]
    fn time_literals() {
        assert_eq!(time_literal(50), "T#50MS");
        assert_eq!(time_literal(1500), "T#1S500MS");
        assert_eq!(time_literal(3_600_000), "T#1H");
        assert_eq!(time_literal(90_061_001), "T#1D1H1M1S1MS");
        assert_eq!(time_literal(0), "T#0MS");
        assert_eq!(time_literal(-20), "T#-20MS");
    }

    #[test]
    fn real_literals_read_back_as_the_same_f32() {
        let lit = |x: f64| real_literal(RealLit::new(x).unwrap());
        assert_eq!(lit(3.5), "3.500000e+00");
        assert_eq!(lit(-0.25), "-2.500000e-01");
        assert_eq!(lit(0.0), "0.000000e+00");
        assert_eq!(lit(-0.0), "0.000000e+00");
        assert_eq!(lit(1e-3), "1.000000e-03");
        assert_eq!(lit(1e20), "1.000000e+20");
        assert_eq!(lit(0.1 + 0.2), "3.000000e-01");
        // 16777215 and 2^-126 need more than seven digits.
        assert_eq!(lit(16_777_215.0), "1.6777215e+07");
        for x in [f32::MAX, f32::MIN_POSITIVE, -f32::MAX, 1.0 / 3.0, 16_777_215.0, 0.1, 2.0e-38, 123_456.79] {
            let text = lit(f64::from(x));
            assert_eq!(text.parse::<f32>().unwrap().to_bits(), x.to_bits(), "{text}");
        }
        for k in 0..2000 {
            let x = f32::from_bits(0x0080_0000 + k * 1_064_437);
            let text = lit(f64::from(x));
            assert_eq!(text.parse::<f32>().unwrap().to_bits(), x.to_bits(), "{text}");
        }
    }

    #[test]
    fn names_stl_accepts() {
        assert!(valid_name("denials") && valid_name("_x") && valid_name("a_b_c"));
        assert!(!valid_name("a__b") && !valid_name("a_") && !valid_name("1a") && !valid_name(""));
        assert!(!valid_name("abcdefghijklmnopqrstuvwxy"));
    }
}
