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

use crate::plc::model::unit::{BinOp, Expr, Place, Pou, PouKind, RealLit, Stmt, Type, Unit, Var};
use crate::plc::siemens_address;
use std::collections::HashMap;
use std::fmt::{self, Write};

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

/// Where a global variable lives in the global data block.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Location {
    pub name: String,
    pub ty: Type,
    pub db: u16,
    pub byte: u32,
    /// The bit of a BOOL (0 for other types).
    pub bit: u8,
}

impl Location {
    /// The absolute STL operand: `DB1.DBX 0.3`, `DB1.DBW 2`, `DB1.DBD 4`.
    pub fn operand(&self) -> String {
        match self.ty {
            Type::Bool => format!("DB{}.DBX {}.{}", self.db, self.byte, self.bit),
            Type::Int => format!("DB{}.DBW {}", self.db, self.byte),
            _ => format!("DB{}.DBD {}", self.db, self.byte),
        }
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

/// Byte and bit of each variable of `sections`, laid out as S7 does (BOOLs packed into bytes,
/// other types on even bytes, every section on an even byte), and the total size in bytes.
fn layout(sections: &[&[Var]]) -> (Vec<(u32, u8)>, u32) {
    let mut bits: u32 = 0;
    let mut out = Vec::new();
    let align = |bits: u32| bits.div_ceil(16) * 16;
    for section in sections {
        bits = align(bits);
        for v in section.iter() {
            match v.ty {
                Type::Bool => {
                    out.push((bits / 8, (bits % 8) as u8));
                    bits += 1;
                }
                Type::Int => {
                    bits = align(bits);
                    out.push((bits / 8, 0));
                    bits += 16;
                }
                _ => {
                    bits = align(bits);
                    out.push((bits / 8, 0));
                    bits += 32;
                }
            }
        }
    }
    (out, align(bits) / 8)
}

/// The globals of `unit` in the global data block, in declaration order. Timers and block
/// instances are not in it (each has its own instance DB, listed in the header).
pub fn global_locations(unit: &Unit, options: &StlUnitOptions) -> Vec<Location> {
    let scalars: Vec<Var> = unit.globals.iter().filter(|v| Ty::of(&v.ty).is_some()).cloned().collect();
    let (places, _) = layout(&[&scalars]);
    scalars
        .iter()
        .zip(places)
        .map(|(v, (byte, bit))| Location { name: v.name.clone(), ty: v.ty.clone(), db: options.first_db, byte, bit })
        .collect()
}

/// The program's inputs, outputs and statics (BOOL, INT, DINT, TIME, REAL) in its instance DB: a
/// supervisor's state kept by the program is found there. Empty when the unit has no program.
pub fn program_locations(unit: &Unit, options: &StlUnitOptions) -> Vec<Location> {
    let Some(program) = unit.pous.last().filter(|p| p.kind == PouKind::Program) else { return Vec::new() };
    let db = blocks(unit, options).program_db;
    let scalars = |vars: &[Var]| -> Vec<Var> { vars.iter().filter(|v| Ty::of(&v.ty).is_some()).cloned().collect() };
    let sections = [scalars(&program.inputs), scalars(&program.outputs), scalars(&program.locals)];
    let (places, _) = layout(&[&sections[0], &sections[1], &sections[2]]);
    sections
        .iter()
        .flatten()
        .zip(places)
        .map(|(v, (byte, bit))| Location { name: v.name.clone(), ty: v.ty.clone(), db, byte, bit })
        .collect()
}

/// The inputs, outputs and statics (BOOL, INT, DINT, TIME, REAL) of `instance` — a global or a local
/// of the program that is an instance of one of the unit's function blocks — in its instance
/// DB: what a watch table or a test reads. Statics declared after a timer are not listed (a
/// multi-instance of SFB 4 has a layout of its own). Empty when there is no such instance.
pub fn instance_locations(unit: &Unit, options: &StlUnitOptions, instance: &str) -> Vec<Location> {
    let blocks = blocks(unit, options);
    let Some((_, _, Type::Instance(name), db)) = blocks.instances.iter().find(|(_, n, _, _)| n == instance) else {
        return Vec::new();
    };
    let Some(fb) = unit.pou(name) else { return Vec::new() };
    // Statics after a timer's multi-instance (SFB 4 has a layout of its own) are left out.
    let scalars = |vars: &[Var]| -> Vec<Var> { vars.iter().filter(|v| Ty::of(&v.ty).is_some()).cloned().collect() };
    let statics: Vec<Var> = fb.locals.iter().take_while(|v| Ty::of(&v.ty).is_some()).cloned().collect();
    let sections = [scalars(&fb.inputs), scalars(&fb.outputs), statics];
    let (places, _) = layout(&[&sections[0], &sections[1], &sections[2]]);
    sections
        .iter()
        .flatten()
        .zip(places)
        .map(|(v, (byte, bit))| Location { name: v.name.clone(), ty: v.ty.clone(), db: *db, byte, bit })
        .collect()
}

/// Where an instance lives: a global or a local of the program.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
enum Owner {
    Global,
    Program,
}

/// The blocks of the printed unit.
struct Blocks {
    fc: HashMap<String, u16>,
    fb: HashMap<String, u16>,
    /// Instance DBs of timers and of the unit's function blocks: (owner, name) → (DB, type).
    instances: Vec<(Owner, String, Type, u16)>,
    program_db: u16,
    globals: Vec<Location>,
}

fn blocks(unit: &Unit, options: &StlUnitOptions) -> Blocks {
    let mut fc = HashMap::new();
    let mut fb = HashMap::new();
    let (mut next_fc, mut next_fb) = (options.first_fc, options.first_fb);
    for pou in &unit.pous {
        match pou.kind {
            PouKind::Function { .. } => {
                fc.insert(pou.name.clone(), next_fc);
                next_fc = next_fc.saturating_add(1);
            }
            _ => {
                fb.insert(pou.name.clone(), next_fb);
                next_fb = next_fb.saturating_add(1);
            }
        }
    }
    let mut next_db = options.first_db.saturating_add(1);
    let mut instances = Vec::new();
    let own_db = |ty: &Type| match ty {
        Type::Ton => true,
        Type::Instance(name) => unit.pou(name).is_some_and(|p| matches!(p.kind, PouKind::FunctionBlock)),
        _ => false,
    };
    for v in &unit.globals {
        if own_db(&v.ty) {
            instances.push((Owner::Global, v.name.clone(), v.ty.clone(), next_db));
            next_db = next_db.saturating_add(1);
        }
    }
    if let Some(program) = unit.pous.last().filter(|p| p.kind == PouKind::Program) {
        for v in &program.locals {
            if own_db(&v.ty) {
                instances.push((Owner::Program, v.name.clone(), v.ty.clone(), next_db));
                next_db = next_db.saturating_add(1);
            }
        }
    }
    Blocks { fc, fb, instances, program_db: next_db, globals: global_locations(unit, options) }
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

    /// The STL operand of a scalar place.
    fn operand(&mut self, place: &Place) -> Result<String, String> {
        let ty = self.place_type(place)?;
        let scalar = Ty::of(&ty)
            .ok_or_else(|| format!("`{}` is not a BOOL, INT, DINT, TIME or REAL", place_text(self.unit, place)))?;
        match place {
            Place::Global(name) => {
                if self.unit.constants.iter().any(|c| c.name == *name) {
                    return Err(format!("constant `{name}` cannot be written"));
                }
                let loc = self.blocks.globals.iter().find(|l| l.name == *name).expect("a scalar global has a place");
                Ok(loc.operand())
            }
            Place::Local(name) => {
                if self.is_function() && *name == self.pou.name {
                    Ok("#RET_VAL".into())
                } else {
                    Ok(format!("#{name}"))
                }
            }
            Place::Signal(i) => signal_operand(&self.unit.signals[*i].address, scalar),
            Place::Member(inner, field) => {
                if let Some(timer) = self.block_timer(inner) {
                    // awlsim cannot read `#t.Q`: the call copies Q and ET into statics.
                    let field = field.to_ascii_uppercase();
                    return match field.as_str() {
                        "Q" | "ET" => Ok(format!("#{}", shadow(timer, &field))),
                        _ => Err(format!(
                            "`{timer}.{field}` of a timer in a function block (STL keeps only its Q and ET)"
                        )),
                    };
                }
                let db = self.instance_db(inner).ok_or_else(|| {
                    format!(
                        "`{}` is an instance inside a function or function block; STL reads members only of \
                         instances with their own DB (globals or locals of the program)",
                        place_text(self.unit, inner)
                    )
                })?;
                let field = field.to_ascii_uppercase();
                match self.place_type(inner)? {
                    Type::Ton => Ok(match field.as_str() {
                        "IN" => format!("DB{db}.DBX 0.0"),
                        "PT" => format!("DB{db}.DBD 2"),
                        "Q" => format!("DB{db}.DBX 6.0"),
                        _ => format!("DB{db}.DBD 8"),
                    }),
                    Type::Instance(fb_name) => {
                        let fb = self.unit.pou(&fb_name).expect("checked by place_type");
                        let (places, _) = layout(&[&fb.inputs, &fb.outputs, &fb.locals]);
                        let k = fb
                            .inputs
                            .iter()
                            .chain(&fb.outputs)
                            .chain(&fb.locals)
                            .position(|v| v.name.eq_ignore_ascii_case(&field))
                            .expect("checked by place_type");
                        let (byte, bit) = places[k];
                        Ok(match scalar {
                            Ty::Bool => format!("DB{db}.DBX {byte}.{bit}"),
                            Ty::Int => format!("DB{db}.DBW {byte}"),
                            _ => format!("DB{db}.DBD {byte}"),
                        })
                    }
                    _ => unreachable!("place_type accepts members of instances only"),
                }
            }
        }
    }

    /// The type of an expression; an integer literal is INT when it fits.
    fn ty(&self, e: &Expr) -> Result<Ty, String> {
        match e {
            Expr::Bool(_) => Ok(Ty::Bool),
            Expr::Int(n) => Ok(if fits_int(*n) { Ty::Int } else { Ty::Dint }),
            Expr::Real(_) => Ok(Ty::Real),
            Expr::Time(_) => Ok(Ty::Time),
            Expr::Read(p) => {
                let ty = self.place_type(p)?;
                Ty::of(&ty)
                    .ok_or_else(|| format!("`{}` of type {} is not a value", place_text(self.unit, p), type_name(&ty)))
            }
            Expr::Not(x) => match self.ty(x)? {
                Ty::Bool => Ok(Ty::Bool),
                t => Err(format!("NOT of {} (bitwise NOT is not printed in STL)", t.name())),
            },
            Expr::Neg(x) => match self.ty(x)? {
                Ty::Bool => Err("negation of a BOOL".into()),
                t => Ok(t),
            },
            Expr::Binary(op, a, b) => {
                let (ta, tb) = (self.ty(a)?, self.ty(b)?);
                if (ta == Ty::Real) != (tb == Ty::Real) && ta != Ty::Bool && tb != Ty::Bool {
                    return Err(format!(
                        "`{}` of {} and {}: IEC needs an explicit conversion between REAL and integers",
                        op.text(),
                        ta.name(),
                        tb.name()
                    ));
                }
                if ta == Ty::Real && matches!(op, BinOp::Mod) {
                    return Err("MOD of REAL values".into());
                }
                match op {
                    BinOp::And | BinOp::Or | BinOp::Xor => {
                        if ta == Ty::Bool && tb == Ty::Bool {
                            Ok(Ty::Bool)
                        } else {
                            Err(format!(
                                "{} of {} and {} (bitwise logic is not printed in STL)",
                                op.text(),
                                ta.name(),
                                tb.name()
                            ))
                        }
                    }
                    BinOp::Eq | BinOp::Ne => {
                        if (ta == Ty::Bool) != (tb == Ty::Bool) {
                            Err(format!("comparison of {} and {}", ta.name(), tb.name()))
                        } else {
                            Ok(Ty::Bool)
                        }
                    }
                    BinOp::Lt | BinOp::Le | BinOp::Gt | BinOp::Ge => {
                        if ta == Ty::Bool || tb == Ty::Bool {
                            Err(format!("ordering comparison of {} and {}", ta.name(), tb.name()))
                        } else {
                            Ok(Ty::Bool)
                        }
                    }
                    _ => {
                        if ta == Ty::Bool || tb == Ty::Bool {
                            Err(format!("arithmetic on {} and {}", ta.name(), tb.name()))
                        } else {
                            Ok(numeric(ta, tb))
                        }
                    }
                }
            }
        }
    }

    /// A BOOL operand read directly (`A op`), or `None` when the expression needs code.
    fn bit_operand(&mut self, e: &Expr) -> Option<String> {
        let Expr::Read(p) = e else { return None };
        if self.constant(p).is_some() {
            return None;
        }
        self.operand(p).ok()
    }

    /// Code that leaves BOOL `e` in the RLO, starting a new logic string (first check).
    fn bool_fresh(&mut self, e: &Expr, depth: usize) {
        match e {
            Expr::Bool(b) => self.emit(if *b { "SET" } else { "CLR" }),
            Expr::Read(p) => {
                if let Some(c) = self.constant(p) {
                    return self.bool_fresh(&c, depth);
                }
                match self.operand(p) {
                    Ok(op) => self.emit(&format!("A\t{op}")),
                    Err(m) => self.error(m),
                }
            }
            Expr::Not(x) => match self.bit_operand(x) {
                Some(op) => self.emit(&format!("AN\t{op}")),
                None => {
                    self.bool_fresh(x, depth);
                    self.emit("NOT");
                }
            },
            Expr::Binary(op @ (BinOp::And | BinOp::Or | BinOp::Xor), _, _) => {
                let letter = match op {
                    BinOp::And => "A",
                    BinOp::Or => "O",
                    _ => "X",
                };
                let mut terms = Vec::new();
                flatten(*op, e, &mut terms);
                for t in terms {
                    self.bool_term(letter, t, false, depth);
                }
            }
            Expr::Binary(op @ (BinOp::Eq | BinOp::Ne), a, b) if self.ty(a) == Ok(Ty::Bool) => {
                self.bool_term("A", a, false, depth);
                self.bool_term(if *op == BinOp::Eq { "XN" } else { "X" }, b, false, depth);
            }
            Expr::Binary(op, a, b) if is_comparison(*op) => self.compare(*op, a, b),
            other => match self.ty(other) {
                Err(m) => self.error(m),
                Ok(t) => self.error(format!("a {} expression where a BOOL is needed", t.name())),
            },
        }
    }

    /// Combines `e` with the RLO by `letter` (`A`, `O`, `X`; negated with `N`).
    fn bool_term(&mut self, letter: &str, e: &Expr, negate: bool, depth: usize) {
        if let Expr::Not(x) = e {
            return self.bool_term(letter, x, !negate, depth);
        }
        let letter = match (letter, negate) {
            ("XN", true) => "X".to_string(),
            (l, true) => format!("{l}N"),
            (l, false) => l.to_string(),
        };
        if let Some(op) = self.bit_operand(e) {
            return self.emit(&format!("{letter}\t{op}"));
        }
        if depth + 1 >= MAX_DEPTH {
            // Too deep for the nesting stack: compute it first into a temporary bit.
            let saved = std::mem::take(&mut self.code);
            let tmp = self.push_temp(TempKind::X);
            self.bool_fresh(e, 0);
            self.emit(&format!("=\t{tmp}"));
            let hoisted = std::mem::replace(&mut self.code, saved);
            self.hoisted.push(hoisted);
            self.emit(&format!("{letter}\t{tmp}"));
            return;
        }
        self.emit(&format!("{letter}("));
        self.bool_fresh(e, depth + 1);
        self.emit(")");
    }
}

fn flatten<'e>(op: BinOp, e: &'e Expr, out: &mut Vec<&'e Expr>) {
    match e {
        Expr::Binary(o, a, b) if *o == op => {
            flatten(op, a, out);
            flatten(op, b, out);
        }
        _ => out.push(e),
    }
}

/// Whether a value of type `value` cannot be stored into a `target` (BOOL only into BOOL, REAL
/// only into REAL; integers of any width into each other).
fn incompatible(value: Ty, target: Ty) -> bool {
    (value == Ty::Bool) != (target == Ty::Bool) || (value == Ty::Real) != (target == Ty::Real)
}

fn is_comparison(op: BinOp) -> bool {
    matches!(op, BinOp::Eq | BinOp::Ne | BinOp::Lt | BinOp::Le | BinOp::Gt | BinOp::Ge)
}

/// The type arithmetic on `a` and `b` has.
fn numeric(a: Ty, b: Ty) -> Ty {
    if a == Ty::Real || b == Ty::Real {
        Ty::Real
    } else if a == Ty::Time || b == Ty::Time {
        Ty::Time
    } else if a == Ty::Dint || b == Ty::Dint {
        Ty::Dint
    } else {
        Ty::Int
    }
}

/// The STL operand of a signal address (IEC form without `%`) read as `ty`.
fn signal_operand(address: &str, ty: Ty) -> Result<String, String> {
    let a = siemens_address(address);
    let bad = || format!("`{address}` is not an I, Q or M address of a {}", ty.name());
    let split = a.find(|c: char| c.is_ascii_digit()).ok_or_else(bad)?;
    let (area, number) = a.split_at(split);
    let (mem, size) = match area {
        "I" | "Q" | "M" => (area, ""),
        "IB" | "QB" | "MB" | "IW" | "QW" | "MW" | "ID" | "QD" | "MD" => area.split_at(1),
        _ => return Err(bad()),
    };
    let _ = mem;
    let ok = match ty {
        Ty::Bool => {
            size.is_empty()
                && number
                    .split_once('.')
                    .is_some_and(|(b, x)| b.parse::<u32>().is_ok() && x.parse::<u8>().is_ok_and(|x| x < 8))
        }
        Ty::Int => size == "W" && number.parse::<u32>().is_ok(),
        Ty::Dint | Ty::Time | Ty::Real => size == "D" && number.parse::<u32>().is_ok(),
    };
    if ok {
        Ok(format!("{area} {number}"))
    } else {
        Err(bad())
    }
}

/// Structured Text of a place, for comments.
fn place_text(unit: &Unit, place: &Place) -> String {
    match place {
        Place::Global(n) | Place::Local(n) => n.clone(),
        Place::Signal(i) => unit.signals.get(*i).map_or_else(|| format!("signal{i}"), |s| s.symbol.clone()),
        Place::Member(inner, f) => format!("{}.{f}", place_text(unit, inner)),
    }
}

/// Structured Text of an expression, for comments.
fn expr_text(unit: &Unit, e: &Expr) -> String {
    fn go(unit: &Unit, e: &Expr, out: &mut String) -> u8 {
        match e {
            Expr::Bool(b) => out.push_str(if *b { "TRUE" } else { "FALSE" }),
            Expr::Int(n) => out.push_str(&n.to_string()),
            Expr::Real(r) => out.push_str(&r.iec_text()),
            Expr::Time(ms) => out.push_str(&time_literal(i64::try_from(*ms).unwrap_or(i64::MAX))),
            Expr::Read(p) => out.push_str(&place_text(unit, p)),
            Expr::Not(x) | Expr::Neg(x) => {
                out.push_str(if matches!(e, Expr::Not(_)) { "NOT " } else { "-" });
                let mut inner = String::new();
                if go(unit, x, &mut inner) < 8 {
                    out.push_str(&format!("({inner})"));
                } else {
                    out.push_str(&inner);
                }
                return 8;
            }
            Expr::Binary(op, a, b) => {
                let p = op.precedence();
                for (k, x) in [a, b].into_iter().enumerate() {
                    let mut inner = String::new();
                    let q = go(unit, x, &mut inner);
                    let negative = match x.as_ref() {
                        Expr::Int(n) => *n < 0,
                        Expr::Real(r) => r.value() < 0.0,
                        _ => false,
                    };
                    if q < p || (k == 1 && q == p) || negative {
                        out.push_str(&format!("({inner})"));
                    } else {
                        out.push_str(&inner);
                    }
                    if k == 0 {
                        out.push_str(&format!(" {} ", op.text()));
                    }
                }
                return p;
            }
        }
        9
    }
    let mut out = String::new();
    go(unit, e, &mut out);
    out
}

impl Gen<'_> {
    /// Code that leaves BOOL `e` in the RLO, with the subexpressions too deep to nest computed
    /// first into temporary bits.
    fn bool_value(&mut self, e: &Expr) {
        let bits = self.temps[TempKind::X.index()];
        let saved_hoisted = std::mem::take(&mut self.hoisted);
        let saved = std::mem::take(&mut self.code);
        self.bool_fresh(e, 0);
        let main = std::mem::replace(&mut self.code, saved);
        for h in std::mem::replace(&mut self.hoisted, saved_hoisted) {
            self.code.push_str(&h);
        }
        self.code.push_str(&main);
        self.temps[TempKind::X.index()] = bits;
    }

    /// An integer or time literal as loaded into a 16-bit (`wide == false`) or 32-bit accumulator.
    fn number_literal(&mut self, e: &Expr, ty: Ty) -> Option<String> {
        match (e, ty) {
            (Expr::Real(r), Ty::Real) => Some(real_literal(*r)),
            (Expr::Real(_), _) | (_, Ty::Real) => {
                self.error(format!("{} where a {} is needed", expr_text(self.unit, e), ty.name()));
                Some("0".into())
            }
            (Expr::Int(n), Ty::Int) => {
                if fits_int(*n) {
                    Some(n.to_string())
                } else {
                    self.error(format!("{n} does not fit in an INT"));
                    Some("0".into())
                }
            }
            (Expr::Int(n), Ty::Dint) => {
                if i32::try_from(*n).is_err() {
                    self.error(format!("{n} does not fit in a DINT"));
                }
                Some(format!("L#{}", *n as i32))
            }
            (Expr::Int(n), _) => Some(self.time(*n)),
            (Expr::Time(ms), _) => Some(self.time(i64::try_from(*ms).unwrap_or(i64::MAX))),
            _ => None,
        }
    }

    /// A TIME literal, or an error beyond the range of TIME (±24 days).
    fn time(&mut self, ms: i64) -> String {
        if i32::try_from(ms).is_err() {
            self.error(format!("{ms} ms is beyond the range of TIME (T#24D20H31M23S647MS)"));
        }
        time_literal(ms)
    }

    /// Whether `e` loads with one `L` (and perhaps `ITD`).
    fn simple_load(&self, e: &Expr) -> bool {
        match e {
            Expr::Int(_) | Expr::Real(_) | Expr::Time(_) => true,
            Expr::Read(p) => self.constant(p).is_some() || Ty::of(&self.place_type(p).unwrap_or(Type::Ton)).is_some(),
            _ => false,
        }
    }

    /// Code that leaves numeric `e` in ACCU1, as 16 bits for `ty` INT and 32 bits otherwise.
    fn load(&mut self, e: &Expr, ty: Ty) {
        let own = match self.ty(e) {
            Ok(Ty::Bool) => return self.error("a BOOL expression where a number is needed".into()),
            Ok(t) => t,
            Err(m) => return self.error(m),
        };
        let widen = !own.wide() && ty.wide();
        match e {
            Expr::Int(_) | Expr::Real(_) | Expr::Time(_) => {
                let lit = self.number_literal(e, if widen { ty } else { own }).unwrap_or_default();
                return self.emit(&format!("L\t{lit}"));
            }
            Expr::Read(p) => {
                if let Some(c) = self.constant(p) {
                    let lit = self.number_literal(&c, ty).unwrap_or_default();
                    return self.emit(&format!("L\t{lit}"));
                }
                match self.operand(p) {
                    Ok(op) => self.emit(&format!("L\t{op}")),
                    Err(m) => return self.error(m),
                }
            }
            Expr::Neg(x) => {
                self.load(x, own);
                self.emit(match own {
                    Ty::Real => "NEGR",
                    t if t.wide() => "NEGD",
                    _ => "NEGI",
                });
            }
            Expr::Binary(op, a, b) => {
                self.load_pair(a, b, own);
                let s = match own {
                    Ty::Real => "R",
                    t if t.wide() => "D",
                    _ => "I",
                };
                match op {
                    BinOp::Add => self.emit(&format!("+{s}")),
                    BinOp::Sub => self.emit(&format!("-{s}")),
                    BinOp::Mul => self.emit(&format!("*{s}")),
                    BinOp::Div => self.emit(&format!("/{s}")),
                    BinOp::Mod if own.wide() => self.emit("MOD"),
                    BinOp::Mod => {
                        // The remainder of /I is in the high word.
                        self.emit("/I");
                        self.emit("SRD\t16");
                    }
                    _ => return self.error(format!("{} where a number is needed", op.text())),
                }
            }
            Expr::Bool(_) | Expr::Not(_) => unreachable!("typed BOOL above"),
        }
        if widen {
            self.emit("ITD");
        }
    }

    /// `a` into ACCU2 and `b` into ACCU1, both as `ty`.
    fn load_pair(&mut self, a: &Expr, b: &Expr, ty: Ty) {
        if self.simple_load(b) {
            self.load(a, ty);
            self.load(b, ty);
        } else {
            let kind = TempKind::of(ty);
            let tmp = self.push_temp(kind);
            self.load(b, ty);
            self.emit(&format!("T\t{tmp}"));
            self.load(a, ty);
            self.emit(&format!("L\t{tmp}"));
            self.pop_temp(kind);
        }
    }

    /// A comparison of numbers, its result in the RLO.
    fn compare(&mut self, op: BinOp, a: &Expr, b: &Expr) {
        let ty = match (self.ty(a), self.ty(b)) {
            (Ok(x), Ok(y)) if (x == Ty::Real) != (y == Ty::Real) && x != Ty::Bool && y != Ty::Bool => {
                return self.error(format!(
                    "`{}` of {} and {}: IEC needs an explicit conversion between REAL and integers",
                    op.text(),
                    x.name(),
                    y.name()
                ))
            }
            (Ok(x), Ok(y)) => numeric(x, y),
            (Err(m), _) | (_, Err(m)) => return self.error(m),
        };
        self.load_pair(a, b, ty);
        let cmp = match op {
            BinOp::Eq => "==",
            BinOp::Ne => "<>",
            BinOp::Lt => "<",
            BinOp::Le => "<=",
            BinOp::Gt => ">",
            _ => ">=",
        };
        self.emit(&format!(
            "{cmp}{}",
            match ty {
                Ty::Real => "R",
                t if t.wide() => "D",
                _ => "I",
            }
        ));
    }

    /// Stores `value` into the operand `op` of type `ty`.
    fn store(&mut self, value: &Expr, ty: Ty, op: &str) {
        if ty == Ty::Bool {
            self.bool_value(value);
            self.emit(&format!("=\t{op}"));
        } else {
            // A DINT value stored into an INT keeps its low word, as the CPU does.
            let vty = self.ty(value).unwrap_or(ty);
            self.load(value, if vty.wide() && !ty.wide() { vty } else { ty });
            self.emit(&format!("T\t{op}"));
        }
    }

    /// An actual parameter of type `ty`: a literal, or a temporary holding the value (the
    /// temporary stays allocated until the caller pops it). Returns the text and the temporary's
    /// kind.
    fn argument(&mut self, value: &Expr, ty: Ty) -> (String, Option<TempKind>) {
        let value = match value {
            Expr::Read(p) => self.constant(p).unwrap_or_else(|| value.clone()),
            _ => value.clone(),
        };
        if let Ok(vt) = self.ty(&value) {
            if (vt == Ty::Real) != (ty == Ty::Real) {
                self.error(format!(
                    "{} of type {} passed as a {}: IEC needs an explicit conversion between REAL and integers",
                    expr_text(self.unit, &value),
                    vt.name(),
                    ty.name()
                ));
            }
        }
        match (&value, ty) {
            (Expr::Bool(b), Ty::Bool) => return ((if *b { "TRUE" } else { "FALSE" }).into(), None),
            (Expr::Int(_) | Expr::Time(_), Ty::Int | Ty::Dint | Ty::Time) => {
                if let Some(lit) = self.number_literal(&value, ty) {
                    return (lit, None);
                }
            }
            _ => {}
        }
        let kind = TempKind::of(ty);
        let tmp = self.push_temp(kind);
        self.store(&value, ty, &tmp);
        (tmp, Some(kind))
    }

    fn statements(&mut self, body: &[Stmt]) {
        for s in body {
            self.statement(s);
        }
    }

    fn statement(&mut self, s: &Stmt) {
        let unit = self.unit;
        match s {
            Stmt::Comment(text) => self.comment(text),
            Stmt::Assign { target, value } => {
                self.comment(&format!("{} := {};", place_text(unit, target), expr_text(unit, value)));
                let ty = match self.place_type(target) {
                    Ok(t) => t,
                    Err(m) => return self.error(m),
                };
                let Some(ty) = Ty::of(&ty) else {
                    return self.error(format!("cannot assign to `{}`", place_text(unit, target)));
                };
                match self.ty(value) {
                    Ok(vt) if incompatible(vt, ty) => {
                        return self.error(format!(
                            "`{}` of type {} gets a value of type {}",
                            place_text(unit, target),
                            ty.name(),
                            vt.name()
                        ))
                    }
                    Err(m) => return self.error(m),
                    _ => {}
                }
                match self.operand(target) {
                    Ok(op) => self.store(value, ty, &op),
                    Err(m) => self.error(m),
                }
            }
            Stmt::If { arms, otherwise } => {
                let end = self.new_label();
                for (k, (cond, body)) in arms.iter().enumerate() {
                    let word = if k == 0 { "IF" } else { "ELSIF" };
                    self.comment(&format!("{word} {} THEN", expr_text(unit, cond)));
                    let next = self.new_label();
                    self.bool_value(cond);
                    self.emit(&format!("JCN\t{next}"));
                    self.statements(body);
                    self.emit(&format!("JU\t{end}"));
                    self.place_label(&next);
                }
                if !otherwise.is_empty() {
                    self.comment("ELSE");
                    self.statements(otherwise);
                }
                self.comment("END_IF");
                self.place_label(&end);
            }
            Stmt::Case { selector, arms, otherwise } => self.case(selector, arms, otherwise),
            Stmt::CallFunction { function, args, result } => self.call_function(function, args, result.as_ref()),
            Stmt::CallInstance { instance, args } => self.call_instance(instance, args),
        }
    }

    fn case(&mut self, selector: &Expr, arms: &[(Vec<i64>, Vec<Stmt>)], otherwise: &[Stmt]) {
        let unit = self.unit;
        self.comment(&format!("CASE {} OF", expr_text(unit, selector)));
        let ty = match self.ty(selector) {
            Ok(Ty::Bool) => return self.error("CASE over a BOOL".into()),
            Ok(Ty::Real) => return self.error("CASE over a REAL".into()),
            Ok(t) => t,
            Err(m) => return self.error(m),
        };
        let end = self.new_label();
        let other = self.new_label();
        let arm_labels: Vec<String> = arms.iter().map(|_| self.new_label()).collect();
        let all: Vec<i64> = arms.iter().flat_map(|(ls, _)| ls.iter().copied()).collect();
        let max = all.iter().copied().max().unwrap_or(0);
        let dense =
            !all.is_empty() && all.iter().all(|&l| (0..=254).contains(&l)) && (max as usize) < 2 * all.len() + 8;
        // The selector: a place loaded directly, or a temporary.
        let kind = TempKind::of(ty);
        let (sel, temp) = match selector {
            Expr::Read(p) if self.constant(p).is_none() && self.ty(selector) == Ok(ty) => match self.operand(p) {
                Ok(op) => (op, false),
                Err(m) => return self.error(m),
            },
            _ => {
                let tmp = self.push_temp(kind);
                self.load(selector, ty);
                self.emit(&format!("T\t{tmp}"));
                (tmp, true)
            }
        };
        let (s, lit): (&str, fn(i64) -> String) = if ty.wide() {
            ("D", |n| if n as i32 as i64 == n { format!("L#{n}") } else { "L#0".into() })
        } else {
            ("I", |n| n.to_string())
        };
        let out_of_range: Vec<i64> =
            all.iter().copied().filter(|&n| if ty.wide() { n as i32 as i64 != n } else { !fits_int(n) }).collect();
        if !out_of_range.is_empty() {
            self.error(format!("CASE labels {out_of_range:?} do not fit the selector's type {}", ty.name()));
        }
        if dense {
            self.emit(&format!("L\t{sel}"));
            self.emit(&format!("L\t{}", lit(0)));
            self.emit(&format!("<{s}"));
            self.emit(&format!("JC\t{other}"));
            self.emit(&format!("L\t{sel}"));
            self.emit(&format!("L\t{}", lit(max)));
            self.emit(&format!(">{s}"));
            self.emit(&format!("JC\t{other}"));
            self.emit(&format!("L\t{sel}"));
            let list_end = self.new_label();
            self.emit(&format!("JL\t{list_end}"));
            for value in 0..=max {
                let target = arms.iter().position(|(ls, _)| ls.contains(&value)).map_or(&other, |k| &arm_labels[k]);
                let line = format!("JU\t{target}");
                self.emit(&line);
            }
            let _ = writeln!(self.code, "{list_end}:\tJU\t{other}");
        } else {
            for (k, (labels, _)) in arms.iter().enumerate() {
                for &l in labels {
                    self.emit(&format!("L\t{sel}"));
                    self.emit(&format!("L\t{}", lit(l)));
                    self.emit(&format!("=={s}"));
                    let line = format!("JC\t{}", arm_labels[k]);
                    self.emit(&line);
                }
            }
            self.emit(&format!("JU\t{other}"));
        }
        if temp {
            self.pop_temp(kind);
        }
        for (k, (labels, body)) in arms.iter().enumerate() {
            let text: Vec<String> = labels.iter().map(|l| l.to_string()).collect();
            let _ = writeln!(self.code, "{}:\tNOP\t0\t// {}:", arm_labels[k], text.join(", "));
            self.statements(body);
            self.emit(&format!("JU\t{end}"));
        }
        let _ = writeln!(self.code, "{other}:\tNOP\t0\t// ELSE");
        self.statements(otherwise);
        self.comment("END_CASE");
        self.place_label(&end);
    }

    fn args_text(&self, args: &[(String, Expr)]) -> String {
        args.iter().map(|(n, e)| format!("{n} := {}", expr_text(self.unit, e))).collect::<Vec<_>>().join(", ")
    }

    fn call_function(&mut self, function: &str, args: &[(String, Expr)], result: Option<&Place>) {
        let unit = self.unit;
        let target = result.map(|p| format!("{} := ", place_text(unit, p))).unwrap_or_default();
        self.comment(&format!("{target}{function}({});", self.args_text(args)));
        let Some(f) = unit.pou(function).filter(|p| matches!(p.kind, PouKind::Function { .. })) else {
            return self.error(format!("`{function}` is not a function of the unit"));
        };
        let fc = self.blocks.fc[function];
        for (name, _) in args {
            if !f.inputs.iter().any(|v| v.name == *name) {
                self.error(format!("function `{function}` has no input `{name}`"));
            }
        }
        let saved = self.temps;
        let mut params = Vec::new();
        for p in &f.inputs {
            let Some(ty) = Ty::of(&p.ty) else {
                self.error(format!("input `{}` of `{function}` is not a BOOL, INT, DINT, TIME or REAL", p.name));
                continue;
            };
            let value = args
                .iter()
                .find(|(n, _)| *n == p.name)
                .map(|(_, e)| e.clone())
                .or_else(|| p.init.clone())
                .unwrap_or_else(|| default_value(ty));
            let (text, _) = self.argument(&value, ty);
            params.push(format!("{} := {text}", p.name));
        }
        let returns = match &f.kind {
            PouKind::Function { returns } => returns.as_ref().and_then(Ty::of),
            _ => None,
        };
        let mut copy_back = None;
        if let Some(rt) = returns {
            let kind = TempKind::of(rt);
            let tmp = self.push_temp(kind);
            params.push(format!("RET_VAL := {tmp}"));
            copy_back = Some((tmp, rt));
        } else if result.is_some() {
            self.error(format!("function `{function}` has no result to store"));
        }
        let list = if params.is_empty() { String::new() } else { format!(" ({})", params.join(", ")) };
        self.emit(&format!("CALL\tFC {fc}{list}"));
        if let (Some((tmp, rt)), Some(place)) = (copy_back, result) {
            let ty = self.place_type(place).ok().as_ref().and_then(Ty::of);
            match (ty, self.operand(place)) {
                (Some(ty), Ok(op)) if !incompatible(rt, ty) => {
                    if ty == Ty::Bool {
                        self.emit(&format!("A\t{tmp}"));
                        self.emit(&format!("=\t{op}"));
                    } else {
                        self.emit(&format!("L\t{tmp}"));
                        if ty.wide() && !rt.wide() {
                            self.emit("ITD");
                        }
                        self.emit(&format!("T\t{op}"));
                    }
                }
                (_, Err(m)) => self.error(m),
                _ => self.error(format!("the result of `{function}` does not fit `{}`", place_text(unit, place))),
            }
        }
        self.temps = saved;
    }

    fn call_instance(&mut self, instance: &Place, args: &[(String, Expr)]) {
        let unit = self.unit;
        self.comment(&format!("{}({});", place_text(unit, instance), self.args_text(args)));
        let ty = match self.place_type(instance) {
            Ok(t) => t,
            Err(m) => return self.error(m),
        };
        let saved = self.temps;
        let mut outputs = String::new();
        // The formal parameters and their types, and the block called.
        let (block, formals): (String, Vec<(String, Option<Ty>)>) = match &ty {
            Type::Ton if self.block_timer(instance).is_some() => {
                let timer = self.block_timer(instance).unwrap_or_default();
                outputs = format!(", Q := #{}, ET := #{}", shadow(timer, "Q"), shadow(timer, "ET"));
                (format!("#{timer}"), vec![("IN".into(), Some(Ty::Bool)), ("PT".into(), Some(Ty::Time))])
            }
            Type::Ton => {
                let Some(db) = self.instance_db(instance) else {
                    return self.error(format!(
                        "timer `{}` is local to a function or function block: STL needs a DB of its own for it \
                         (make it a global or a local of the program)",
                        place_text(unit, instance)
                    ));
                };
                (format!("SFB 4, DB {db}"), vec![("IN".into(), Some(Ty::Bool)), ("PT".into(), Some(Ty::Time))])
            }
            Type::Instance(name) => match unit.pou(name) {
                Some(fb) if fb.kind == PouKind::FunctionBlock => {
                    let Some(db) = self.instance_db(instance) else {
                        return self.error(format!(
                            "instance `{}` is local to a function or function block: STL needs a DB of its own \
                             for it (make it a global or a local of the program)",
                            place_text(unit, instance)
                        ));
                    };
                    (
                        format!("FB {}, DB {db}", self.blocks.fb[name]),
                        fb.inputs.iter().map(|v| (v.name.clone(), Ty::of(&v.ty))).collect(),
                    )
                }
                Some(_) => return self.error(format!("`{name}` is not a function block")),
                None => {
                    let formals = args.iter().map(|(n, e)| (n.clone(), self.ty(e).ok())).collect();
                    (format!("FB {}, DB {}", self.options.controller_fb, self.options.controller_db), formals)
                }
            },
            other => {
                return self.error(format!(
                    "`{}` of type {} cannot be called",
                    place_text(unit, instance),
                    type_name(other)
                ))
            }
        };
        let mut params = Vec::new();
        for (name, value) in args {
            let Some((formal, ty)) = formals.iter().find(|(f, _)| f.eq_ignore_ascii_case(name)) else {
                self.error(format!("`{}` has no input `{name}`", place_text(unit, instance)));
                continue;
            };
            let Some(ty) = *ty else {
                self.error(format!("input `{name}` of `{}` has no STL value type", place_text(unit, instance)));
                continue;
            };
            // An FB copies its inputs into its instance at the call: a variable of the formal's
            // type is passed as it is.
            let direct = match value {
                Expr::Read(p) if self.constant(p).is_none() && self.ty(value) == Ok(ty) => self.operand(p).ok(),
                _ => None,
            };
            let text = match direct {
                Some(op) => op,
                None => self.argument(value, ty).0,
            };
            params.push(format!("{formal} := {text}"));
        }
        let list = match (params.is_empty(), outputs.is_empty()) {
            (true, true) => String::new(),
            (true, false) => format!(" ({})", &outputs[2..]),
            _ => format!(" ({}{outputs})", params.join(", ")),
        };
        self.emit(&format!("CALL\t{block}{list}"));
        self.temps = saved;
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

/// One POU's code and the temporaries it needs.
fn generate<'a>(unit: &'a Unit, options: &'a StlUnitOptions, blocks: &'a Blocks, pou: &'a Pou) -> Gen<'a> {
    let mut g = Gen::new(unit, options, blocks, pou);
    for v in pou.inputs.iter().chain(&pou.outputs).chain(&pou.locals) {
        if !valid_name(&v.name) {
            g.error(format!(
                "`{}` is not an STL name (letters, digits and single underscores, at most 24 characters)",
                v.name
            ));
        }
        if v.name.eq_ignore_ascii_case("RET_VAL") {
            g.error("`RET_VAL` is the result of an FC".into());
        }
    }
    if let PouKind::Function { returns } = &pou.kind {
        if !pou.outputs.is_empty() {
            g.error("a function with outputs (STL prints results through RET_VAL only)".into());
        }
        if returns.as_ref().is_some_and(|t| Ty::of(t).is_none()) {
            g.error("a function whose result is not a BOOL, INT, DINT, TIME or REAL".into());
        }
        // S7 leaves temporaries and RET_VAL undefined; IEC starts from the initial values.
        let mut first = true;
        for v in &pou.locals {
            let Some(ty) = Ty::of(&v.ty) else {
                g.error(format!("`{}` of type {} in a function (an FC has no memory)", v.name, type_name(&v.ty)));
                continue;
            };
            if first {
                g.comment("locals start from their initial values");
                first = false;
            }
            let init = v.init.clone().unwrap_or_else(|| default_value(ty));
            g.store(&init, ty, &format!("#{}", v.name));
        }
        if let Some(ty) = returns.as_ref().and_then(Ty::of) {
            g.store(&default_value(ty), ty, "#RET_VAL");
        }
    }
    if pou.kind == PouKind::FunctionBlock {
        let names: Vec<&str> =
            pou.inputs.iter().chain(&pou.outputs).chain(&pou.locals).map(|v| v.name.as_str()).collect();
        for v in &pou.locals {
            match &v.ty {
                Type::Ton => {
                    for field in ["Q", "ET"] {
                        let s = shadow(&v.name, field);
                        if !valid_name(&s) || names.iter().any(|n| n.eq_ignore_ascii_case(&s)) {
                            g.error(format!(
                                "timer `{}` keeps its {field} in `{s}`, which is not a free STL name in this block",
                                v.name
                            ));
                        }
                    }
                }
                Type::Instance(name) => g.error(format!(
                    "`{}` of type {name} in a function block: awlsim cannot address members of a \
                     multi-instance; declare it as a global or a local of the program",
                    v.name
                )),
                _ => {}
            }
        }
    }
    for v in pou.inputs.iter().chain(&pou.outputs) {
        if Ty::of(&v.ty).is_none() {
            g.error(format!("parameter `{}` of type {}", v.name, type_name(&v.ty)));
        }
    }
    g.statements(&pou.body);
    g
}

/// Problems that keep `unit` from printing as STL with `options`; empty when it prints.
pub fn check(unit: &Unit, options: &StlUnitOptions) -> Vec<String> {
    let blocks = blocks(unit, options);
    let mut errors = Vec::new();
    for v in unit.constants.iter().chain(&unit.globals) {
        if !valid_name(&v.name) {
            errors.push(format!(
                "global `{}` is not an STL name (letters, digits and single underscores, at most 24 characters)",
                v.name
            ));
        }
    }
    let vars =
        unit.globals.iter().chain(unit.pous.iter().flat_map(|p| p.inputs.iter().chain(&p.outputs).chain(&p.locals)));
    for v in vars {
        if v.init.is_some() && Ty::of(&v.ty).is_some() {
            let fits = match (init_literal(v, unit), v.init.as_ref()) {
                (None, _) => false,
                (Some(_), Some(Expr::Int(n))) if v.ty == Type::Int => fits_int(*n),
                (Some(_), Some(Expr::Int(n))) => i32::try_from(*n).is_ok(),
                _ => true,
            };
            if !fits {
                errors.push(format!("the initial value of `{}` is not a literal of type {}", v.name, type_name(&v.ty)));
            }
        }
    }
    for c in &unit.constants {
        if !matches!(c.init, Some(Expr::Bool(_) | Expr::Int(_) | Expr::Real(_) | Expr::Time(_))) {
            errors.push(format!("constant `{}` needs a literal value", c.name));
        }
    }
    for v in &unit.globals {
        if let Type::Instance(name) = &v.ty {
            if unit.pou(name).is_some_and(|p| p.kind != PouKind::FunctionBlock) {
                errors.push(format!("global `{}` is an instance of `{name}`, which is not a function block", v.name));
            }
        }
    }
    match unit.pous.last() {
        Some(p) if p.kind == PouKind::Program => {}
        _ => errors.push("the unit's last POU is not a program".into()),
    }
    if unit.pous.iter().filter(|p| p.kind == PouKind::Program).count() > 1 {
        errors.push("the unit has more than one program".into());
    }
    let externals: std::collections::BTreeSet<&str> = unit
        .globals
        .iter()
        .chain(unit.pous.iter().flat_map(|p| &p.locals))
        .filter_map(|v| match &v.ty {
            Type::Instance(name) if unit.pou(name).is_none() => Some(name.as_str()),
            _ => None,
        })
        .collect();
    if externals.len() > 1 {
        errors.push(format!("instances of several external block types {externals:?}: STL knows one controller FB"));
    }
    if blocks.fb.values().any(|&n| n == options.controller_fb) && !externals.is_empty() {
        errors.push(format!("the controller's FB {} is also a block of the unit", options.controller_fb));
    }
    let dbs: Vec<u16> = std::iter::once(options.first_db)
        .chain(blocks.instances.iter().map(|i| i.3))
        .chain(std::iter::once(blocks.program_db))
        .collect();
    if !externals.is_empty() && dbs.contains(&options.controller_db) {
        errors.push(format!("the controller's DB {} is also a data block of the unit", options.controller_db));
    }
    for pou in &unit.pous {
        errors.extend(generate(unit, options, &blocks, pou).errors);
    }
    errors
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
    fn signal_addresses() {
        assert_eq!(signal_operand("IX0.1", Ty::Bool), Ok("I 0.1".into()));
        assert_eq!(signal_operand("QX0.0", Ty::Bool), Ok("Q 0.0".into()));
        assert_eq!(signal_operand("MX20.3", Ty::Bool), Ok("M 20.3".into()));
        assert_eq!(signal_operand("IW4", Ty::Int), Ok("IW 4".into()));
        assert_eq!(signal_operand("MD8", Ty::Dint), Ok("MD 8".into()));
        assert!(signal_operand("IW4", Ty::Bool).is_err());
        assert!(signal_operand("IX0.8", Ty::Bool).is_err());
        assert!(signal_operand("GVL.lamp", Ty::Bool).is_err());
        assert!(signal_operand("", Ty::Bool).is_err());
    }

    #[test]
    fn layout_packs_bools_and_aligns_words_and_sections() {
        let v = |ty: Type| Var::new("x", ty, "");
        let (places, size) = layout(&[&[v(Type::Bool), v(Type::Bool), v(Type::Int), v(Type::Dint), v(Type::Bool)]]);
        assert_eq!(places, vec![(0, 0), (0, 1), (2, 0), (4, 0), (8, 0)]);
        assert_eq!(size, 10);
        // As awlsim lays out an FB: every declaration section starts on an even byte.
        let (places, size) = layout(&[&[v(Type::Bool)], &[v(Type::Bool), v(Type::Int)], &[v(Type::Bool)]]);
        assert_eq!(places, vec![(0, 0), (2, 0), (4, 0), (6, 0)]);
        assert_eq!(size, 8);
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
