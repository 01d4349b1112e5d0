//! A [`Unit`] as Structured Text: plain IEC 61131-3, CODESYS V3, TwinCAT 3 (the same text in
//! `.TcPOU`/`.TcGVL` files, see [`files`]) and Siemens SCL for S7-300/400 and S7-1200/1500.
//!
//! Where the dialects differ:
//! - **Globals.** IEC, CODESYS and TwinCAT keep them in a global variable list; CODESYS and
//!   TwinCAT mark it `qualified_only`, so the code writes `SyRF_Data.denials`. Plain IEC 61131-3
//!   has no standard place for variables that functions share (functions may not use
//!   `VAR_EXTERNAL`); the text uses the global-variable-list form that CODESYS, TwinCAT and most
//!   IEC tools read. SCL keeps them in a global data block, `"SyRF_Data".denials`.
//! - **Constants.** A `VAR_GLOBAL CONSTANT` list beside the globals, except in SCL, where a
//!   global data block holds no constants: every block declares the constants it uses (`CONST`
//!   on S7-300/400, `VAR CONSTANT` on S7-1200/1500).
//! - **Signals** of the user's project are written as the project writes them: a symbol
//!   (`Q_Inlet`) or a direct address (`%QX0.0`); in SCL a PLC tag in quotes (`"Q_Inlet"`) or a
//!   Siemens address (`%Q0.0`).
//! - **Timers** are `TON`, on S7-1200/1500 `TON_TIME`; the program is an FB on Siemens targets,
//!   called from an organisation block the user adds.

use crate::plc::model::unit::{Expr, Location, Next, Place, Pou, PouKind, SignalKind, StepList, Stmt, Type, Unit, Var};
use crate::plc::print::st::Dialect;
use crate::plc::{iec_address, siemens_address, time_literal, OutputFile};
use std::collections::BTreeSet;
use std::fmt::{self, Write};

fn siemens(dialect: Dialect) -> bool {
    matches!(dialect, Dialect::Scl | Dialect::Scl1500)
}

fn qualified(dialect: Dialect) -> bool {
    matches!(dialect, Dialect::Codesys | Dialect::Twincat)
}

/// The type as the dialect declares it.
pub fn type_name(ty: &Type, dialect: Dialect) -> String {
    match ty {
        Type::Bool => "BOOL".into(),
        Type::Int => "INT".into(),
        Type::Dint => "DINT".into(),
        Type::Real => "REAL".into(),
        Type::Time => "TIME".into(),
        Type::Ton if dialect == Dialect::Scl1500 => "TON_TIME".into(),
        Type::Ton => "TON".into(),
        Type::Instance(name) if siemens(dialect) => format!("\"{name}\""),
        Type::Instance(name) => name.clone(),
    }
}

/// How one POU's code names things in `dialect`.
pub(in crate::plc) struct Writer<'u> {
    unit: &'u Unit,
    dialect: Dialect,
}

impl<'u> Writer<'u> {
    pub(in crate::plc) fn new(unit: &'u Unit, dialect: Dialect) -> Writer<'u> {
        Writer { unit, dialect }
    }

    fn place(&self, place: &Place) -> String {
        match place {
            Place::Global(name) => {
                let constant = self.unit.constants.iter().any(|c| &c.name == name);
                let located = self.unit.globals.iter().any(|g| &g.name == name && g.address().is_some());
                if siemens(self.dialect) {
                    if located {
                        // A PLC tag, which the tag table defines at the address.
                        format!("\"{name}\"")
                    } else if constant {
                        name.clone()
                    } else {
                        format!("\"{}\".{name}", self.unit.gvl)
                    }
                } else if qualified(self.dialect) {
                    format!("{}.{name}", self.unit.gvl)
                } else {
                    name.clone()
                }
            }
            Place::Local(name) => name.clone(),
            Place::Signal(n) => {
                let s = &self.unit.signals[*n];
                match (siemens(self.dialect), s.is_address()) {
                    (true, true) => format!("%{}", siemens_address(&s.address)),
                    // A tag in quotes; a member of a data block (`GVL.lamp`) as `"GVL".lamp`;
                    // a symbol written with its quotes as it is.
                    (true, false) if s.symbol.starts_with('"') => s.symbol.clone(),
                    (true, false) => match s.symbol.split_once('.') {
                        Some((block, member)) => format!("\"{block}\".{member}"),
                        None => format!("\"{}\"", s.symbol),
                    },
                    (false, true) => format!("%{}", iec_address(&s.address)),
                    (false, false) => s.symbol.clone(),
                }
            }
            Place::Member(base, field) => format!("{}.{field}", self.place(base)),
        }
    }

    pub(in crate::plc) fn expr(&self, e: &Expr) -> String {
        let mut out = String::new();
        self.write_expr(e, 0, &mut out);
        out
    }

    fn write_expr(&self, e: &Expr, min: u8, out: &mut String) {
        match e {
            Expr::Bool(b) => out.push_str(if *b { "TRUE" } else { "FALSE" }),
            Expr::Int(v) if *v < 0 => {
                let _ = write!(out, "({v})");
            }
            Expr::Int(v) => {
                let _ = write!(out, "{v}");
            }
            Expr::Real(r) if r.value() < 0.0 => {
                let _ = write!(out, "({})", r.iec_text());
            }
            Expr::Real(r) => out.push_str(&r.iec_text()),
            Expr::Time(ms) => out.push_str(&time_literal(*ms)),
            Expr::Read(p) => out.push_str(&self.place(p)),
            Expr::Not(inner) | Expr::Neg(inner) => {
                let paren = min > UNARY;
                if paren {
                    out.push('(');
                }
                out.push_str(if matches!(e, Expr::Not(_)) { "NOT " } else { "-" });
                // A unary operand that is itself unary is parenthesised: IEC 61131-3 has no
                // `NOT NOT a` (blark rejects it) and `--x` is no negation.
                self.write_expr(inner, UNARY + 1, out);
                if paren {
                    out.push(')');
                }
            }
            Expr::Binary(op, a, b) => {
                let p = op.precedence();
                let paren = p < min;
                if paren {
                    out.push('(');
                }
                self.write_expr(a, p, out);
                let _ = write!(out, " {} ", op.text());
                // Left-associative: a right operand of the same precedence needs parentheses.
                self.write_expr(b, p + 1, out);
                if paren {
                    out.push(')');
                }
            }
        }
    }

    /// An initial value: a negative literal without the parentheses an operand needs.
    pub(in crate::plc) fn init(&self, e: &Expr) -> String {
        match e {
            Expr::Int(v) => v.to_string(),
            Expr::Real(r) => r.iec_text(),
            e => self.expr(e),
        }
    }

    fn args(&self, args: &[(String, Expr)]) -> String {
        args.iter().map(|(name, value)| format!("{name} := {}", self.expr(value))).collect::<Vec<_>>().join(", ")
    }

    fn function_name(&self, name: &str) -> String {
        if siemens(self.dialect) {
            format!("\"{name}\"")
        } else {
            name.to_string()
        }
    }

    fn stmts(&self, stmts: &[Stmt], indent: usize, o: &mut String) {
        for s in stmts {
            self.stmt(s, indent, o);
        }
    }

    fn stmt(&self, s: &Stmt, indent: usize, o: &mut String) {
        let pad = "    ".repeat(indent);
        match s {
            Stmt::Comment(text) => {
                let _ = writeln!(o, "{pad}(* {} *)", comment_text(text));
            }
            Stmt::Assign { target, value } => {
                let _ = writeln!(o, "{pad}{} := {};", self.place(target), self.expr(value));
            }
            Stmt::If { arms, otherwise } => {
                for (k, (cond, body)) in arms.iter().enumerate() {
                    let _ = writeln!(o, "{pad}{} {} THEN", if k == 0 { "IF" } else { "ELSIF" }, self.expr(cond));
                    self.stmts(body, indent + 1, o);
                }
                if !otherwise.is_empty() {
                    let _ = writeln!(o, "{pad}ELSE");
                    self.stmts(otherwise, indent + 1, o);
                }
                let _ = writeln!(o, "{pad}END_IF;");
            }
            Stmt::Case { selector, arms, otherwise } => {
                let _ = writeln!(o, "{pad}CASE {} OF", self.expr(selector));
                for (labels, body) in arms {
                    let labels: Vec<String> = labels.iter().map(i64::to_string).collect();
                    let _ = writeln!(o, "{pad}    {}:", labels.join(", "));
                    if body.is_empty() {
                        // An empty arm is not allowed everywhere: say nothing happens.
                        let _ = writeln!(o, "{pad}        ;");
                    }
                    self.stmts(body, indent + 2, o);
                }
                if !otherwise.is_empty() {
                    let _ = writeln!(o, "{pad}ELSE");
                    self.stmts(otherwise, indent + 1, o);
                }
                let _ = writeln!(o, "{pad}END_CASE;");
            }
            Stmt::CallFunction { function, args, result } => {
                let call = format!("{}({})", self.function_name(function), self.args(args));
                match result {
                    Some(target) => {
                        let _ = writeln!(o, "{pad}{} := {call};", self.place(target));
                    }
                    None => {
                        let _ = writeln!(o, "{pad}{call};");
                    }
                }
            }
            Stmt::CallInstance { instance, args } => {
                let _ = writeln!(o, "{pad}{}({});", self.place(instance), self.args(args));
            }
            Stmt::Steps(list) => self.step_list(list, indent, o),
        }
    }

    /// A step list as a `CASE` over its position inside a `WHILE` loop that runs until a step
    /// ends the scan; each step's body is the `IF` its wait and branch make of it.
    fn step_list(&self, list: &StepList, indent: usize, o: &mut String) {
        let pad = "    ".repeat(indent);
        let (position, done) = (&list.position, &list.done);
        let _ = write!(o, "{pad}{done} := FALSE;\n{pad}WHILE NOT {done} DO\n{pad}    CASE {position} OF\n");
        let go_to = |k: usize| Stmt::assign(Place::local(position.clone()), Expr::Int(k as i64));
        let end_scan = || Stmt::assign(Place::local(done.clone()), Expr::Bool(true));
        for (i, step) in list.steps.iter().enumerate() {
            let _ = writeln!(o, "{pad}    {i}: (* {} *)", comment_text(&step.comment));
            let mut effect = step.actions.clone();
            match step.next {
                Next::Continue(k) => effect.push(go_to(k)),
                Next::Resume(k) => effect.extend([go_to(k), end_scan()]),
            }
            let body = match (&step.wait, &step.when) {
                (None, None) => effect,
                (Some(wait), None) => {
                    vec![Stmt::If { arms: vec![(wait.clone(), effect)], otherwise: vec![end_scan()] }]
                }
                (wait, Some(when)) => {
                    let mut arms: Vec<(Expr, Vec<Stmt>)> =
                        wait.iter().map(|w| (w.clone().not(), vec![end_scan()])).collect();
                    arms.push((when.clone(), effect));
                    vec![Stmt::If { arms, otherwise: vec![go_to(i + 1)] }]
                }
            };
            self.stmts(&body, indent + 2, o);
        }
        let _ = write!(
            o,
            "{pad}    ELSE\n{pad}        {position} := 0;\n{pad}        {done} := TRUE;\n{pad}    END_CASE;\n{pad}END_WHILE;\n"
        );
    }
}

const UNARY: u8 = 8;

/// Comment text that cannot end the comment early.
fn comment_text(text: &str) -> String {
    text.replace("*)", "* )").replace("(*", "( *")
}

fn declare(o: &mut String, w: &Writer<'_>, v: &Var) {
    let init = v.init.as_ref().map(|e| format!(" := {}", w.init(e))).unwrap_or_default();
    let comment = if v.comment.is_empty() { String::new() } else { format!(" (* {} *)", comment_text(&v.comment)) };
    // TwinCAT links a variable to the I/O in its System Manager when it is declared `AT %I*`.
    let at = match &v.at {
        Some(Location::Address(a)) => format!(" AT %{}", iec_address(a)),
        Some(Location::Mapped(SignalKind::Input)) if w.dialect == Dialect::Twincat => " AT %I*".into(),
        Some(Location::Mapped(SignalKind::Output)) if w.dialect == Dialect::Twincat => " AT %Q*".into(),
        _ => String::new(),
    };
    let _ = writeln!(o, "    {}{at} : {}{init};{comment}", v.name, type_name(&v.ty, w.dialect));
}

/// The constants a POU reads (SCL declares them per block).
fn constants_used<'u>(unit: &'u Unit, pou: &Pou) -> Vec<&'u Var> {
    let mut names = BTreeSet::new();
    fn expr(e: &Expr, names: &mut BTreeSet<String>) {
        match e {
            Expr::Read(p) => place(p, names),
            Expr::Not(a) | Expr::Neg(a) => expr(a, names),
            Expr::Binary(_, a, b) => {
                expr(a, names);
                expr(b, names);
            }
            Expr::Bool(_) | Expr::Int(_) | Expr::Real(_) | Expr::Time(_) => {}
        }
    }
    fn place(p: &Place, names: &mut BTreeSet<String>) {
        match p {
            Place::Global(n) => {
                names.insert(n.clone());
            }
            Place::Member(b, _) => place(b, names),
            Place::Local(_) | Place::Signal(_) => {}
        }
    }
    fn stmts(list: &[Stmt], names: &mut BTreeSet<String>) {
        for s in list {
            match s {
                Stmt::Comment(_) => {}
                Stmt::Assign { target, value } => {
                    place(target, names);
                    expr(value, names);
                }
                Stmt::If { arms, otherwise } => {
                    for (c, b) in arms {
                        expr(c, names);
                        stmts(b, names);
                    }
                    stmts(otherwise, names);
                }
                Stmt::Case { selector, arms, otherwise } => {
                    expr(selector, names);
                    for (_, b) in arms {
                        stmts(b, names);
                    }
                    stmts(otherwise, names);
                }
                Stmt::CallFunction { args, result, .. } => {
                    args.iter().for_each(|(_, e)| expr(e, names));
                    if let Some(r) = result {
                        place(r, names);
                    }
                }
                Stmt::CallInstance { instance, args } => {
                    place(instance, names);
                    args.iter().for_each(|(_, e)| expr(e, names));
                }
                Stmt::Steps(list) => {
                    for step in &list.steps {
                        step.wait.iter().chain(&step.when).for_each(|e| expr(e, names));
                        stmts(&step.actions, names);
                    }
                }
            }
        }
    }
    stmts(&pou.body, &mut names);
    unit.constants.iter().filter(|c| names.contains(&c.name)).collect()
}

/// The global variable list (IEC, CODESYS, TwinCAT): constants, then variables.
pub fn gvl(unit: &Unit, dialect: Dialect, o: &mut String) {
    let w = Writer { unit, dialect };
    let attribute = if qualified(dialect) { "{attribute 'qualified_only'}\n" } else { "" };
    if !unit.constants.is_empty() {
        let _ = writeln!(o, "{attribute}VAR_GLOBAL CONSTANT");
        for c in &unit.constants {
            declare(o, &w, c);
        }
        o.push_str("END_VAR\n");
    }
    if !unit.globals.is_empty() {
        let attribute = if unit.constants.is_empty() { attribute } else { "" };
        let _ = writeln!(o, "{attribute}VAR_GLOBAL");
        for v in &unit.globals {
            declare(o, &w, v);
        }
        o.push_str("END_VAR\n");
    }
}

/// The globals a Siemens data block holds: all but those at a direct address, which are PLC tags.
fn data_block_globals(unit: &Unit) -> impl Iterator<Item = &Var> {
    unit.globals.iter().filter(|v| v.address().is_none())
}

/// The global data block (SCL).
fn data_block(unit: &Unit, dialect: Dialect, o: &mut String) {
    let w = Writer { unit, dialect };
    let _ = write!(o, "DATA_BLOCK \"{}\"\n{}", unit.gvl, siemens_head(dialect));
    if dialect == Dialect::Scl1500 {
        o.push_str("VAR\n");
        for v in data_block_globals(unit) {
            declare(o, &w, v);
        }
        o.push_str("END_VAR\n");
    } else {
        o.push_str("STRUCT\n");
        for v in data_block_globals(unit) {
            declare(o, &w, v);
        }
        o.push_str("END_STRUCT;\n");
    }
    o.push_str("BEGIN\nEND_DATA_BLOCK\n");
}

fn siemens_head(dialect: Dialect) -> &'static str {
    if dialect == Dialect::Scl1500 {
        "{ S7_Optimized_Access := 'TRUE' }\nVERSION : 0.1\n"
    } else {
        "VERSION : 0.1\n"
    }
}

fn section(o: &mut String, w: &Writer<'_>, keyword: &str, vars: &[Var]) {
    if vars.is_empty() {
        return;
    }
    let _ = writeln!(o, "{keyword}");
    for v in vars {
        declare(o, w, v);
    }
    o.push_str("END_VAR\n");
}

/// A POU's declaration part: from `FUNCTION`/`FUNCTION_BLOCK`/`PROGRAM` to the last `END_VAR`.
pub fn pou_declaration(unit: &Unit, pou: &Pou, dialect: Dialect, o: &mut String) {
    let w = Writer { unit, dialect };
    if !pou.comment.is_empty() {
        for line in pou.comment.lines() {
            let _ = writeln!(o, "(* {} *)", comment_text(line));
        }
    }
    let name = if siemens(dialect) { format!("\"{}\"", pou.name) } else { pou.name.clone() };
    match &pou.kind {
        PouKind::Function { returns } => {
            let ty = returns.as_ref().map_or_else(|| "VOID".to_string(), |t| type_name(t, dialect));
            let _ = writeln!(o, "FUNCTION {name} : {ty}");
        }
        PouKind::FunctionBlock => {
            let _ = writeln!(o, "FUNCTION_BLOCK {name}");
        }
        PouKind::Program if siemens(dialect) => {
            let _ = writeln!(o, "FUNCTION_BLOCK {name}");
        }
        PouKind::Program => {
            let _ = writeln!(o, "PROGRAM {name}");
        }
    }
    if siemens(dialect) {
        o.push_str(siemens_head(dialect));
    }
    section(o, &w, "VAR_INPUT", &pou.inputs);
    section(o, &w, "VAR_OUTPUT", &pou.outputs);
    let temp = matches!(pou.kind, PouKind::Function { .. });
    section(o, &w, if temp && siemens(dialect) { "VAR_TEMP" } else { "VAR" }, &pou.locals);
    if siemens(dialect) {
        let used = constants_used(unit, pou);
        if !used.is_empty() {
            if dialect == Dialect::Scl1500 {
                o.push_str("VAR CONSTANT\n");
                for c in used {
                    declare(o, &w, c);
                }
                o.push_str("END_VAR\n");
            } else {
                o.push_str("CONST\n");
                for c in used {
                    let value = c.init.as_ref().map(|e| w.init(e)).unwrap_or_else(|| "0".into());
                    let _ = writeln!(o, "    {} := {value};", c.name);
                }
                o.push_str("END_CONST\n");
            }
        }
    }
}

/// A POU's statements.
pub fn pou_body(unit: &Unit, pou: &Pou, dialect: Dialect, o: &mut String) {
    Writer { unit, dialect }.stmts(&pou.body, 0, o);
}

fn end_keyword(pou: &Pou, dialect: Dialect) -> &'static str {
    match pou.kind {
        PouKind::Function { .. } => "END_FUNCTION",
        PouKind::FunctionBlock => "END_FUNCTION_BLOCK",
        PouKind::Program if siemens(dialect) => "END_FUNCTION_BLOCK",
        PouKind::Program => "END_PROGRAM",
    }
}

/// The whole unit as one text: header, globals, then every POU in call order.
pub fn print(unit: &Unit, dialect: Dialect, o: &mut impl Write) -> fmt::Result {
    let mut text = String::new();
    for line in &unit.header {
        let _ = writeln!(text, "(* {} *)", comment_text(line));
    }
    signal_list(unit, &mut text);
    text.push('\n');
    if siemens(dialect) {
        if data_block_globals(unit).next().is_some() {
            data_block(unit, dialect, &mut text);
            text.push('\n');
        }
    } else if !unit.constants.is_empty() || !unit.globals.is_empty() {
        let _ = writeln!(
            text,
            "(* Global variable list {0}: in CODESYS or TwinCAT add a Global Variable List named {0} and paste this. *)",
            unit.gvl
        );
        gvl(unit, dialect, &mut text);
        text.push('\n');
    }
    for (k, pou) in unit.pous.iter().enumerate() {
        if k > 0 {
            text.push('\n');
        }
        pou_declaration(unit, pou, dialect, &mut text);
        if siemens(dialect) {
            text.push_str("BEGIN\n");
        }
        pou_body(unit, pou, dialect, &mut text);
        text.push_str(end_keyword(pou, dialect));
        text.push('\n');
    }
    o.write_str(&text)
}

/// The signals of the user's project the unit reads and writes, as comment lines.
fn signal_list(unit: &Unit, o: &mut String) {
    if unit.signals.is_empty() {
        return;
    }
    o.push_str("(* Signals of the project (declared there): *)\n");
    for s in &unit.signals {
        let kind = match s.kind {
            SignalKind::Input => "input",
            SignalKind::Output => "output",
            SignalKind::Memory => "variable",
        };
        let _ = writeln!(o, "(*   {:<24} {kind:<8} {} *)", s.symbol, comment_text(&s.comment));
    }
}

/// TwinCAT 3 files: a `.TcPOU` per POU and a `.TcGVL` for the globals.
pub fn files(unit: &Unit) -> Vec<OutputFile> {
    let header: String = unit.header.iter().map(|l| format!("(* {} *)\n", comment_text(l))).collect();
    let mut out = Vec::new();
    for pou in &unit.pous {
        let mut declaration = header.clone();
        pou_declaration(unit, pou, Dialect::Twincat, &mut declaration);
        let mut body = String::new();
        pou_body(unit, pou, Dialect::Twincat, &mut body);
        out.push(crate::plc::files::twincat::pou_file(&unit.header, &pou.name, &declaration, &body));
    }
    if !unit.constants.is_empty() || !unit.globals.is_empty() {
        let mut declaration = header;
        gvl(unit, Dialect::Twincat, &mut declaration);
        out.push(crate::plc::files::twincat::gvl_file(&unit.header, &unit.gvl, &declaration));
    }
    out
}
