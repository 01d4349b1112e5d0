//! Structured Text: plain IEC 61131-3, CODESYS V3 / TwinCAT 3, and Siemens SCL for S7-300/400
//! and for S7-1200/1500 (TIA Portal external sources).
//!
//! A `FUNCTION_BLOCK` with a BOOL input per input signal and a BOOL output per output signal;
//! a step variable and a `CASE` inside a `WHILE` loop that runs one scan per call (see the
//! module doc of `plc`). When variables are bound to signals, a program instantiates the block
//! and wires it; addresses appear only there: IEC declares located variables (`AT %IX0.0`) in
//! the program, CODESYS and TwinCAT in a global variable list, SCL reads PLC tags (`"press"`)
//! that the tag table ([`crate::plc::tag_table_sdf`]) defines.

pub mod unit;

use crate::plc::model::code::{Binding, Code, Direction, Effect, Statement, Test};
use crate::plc::{preset_literal, time_literal};
use std::fmt::{self, Write};

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Dialect {
    Iec,
    /// CODESYS V3: the I/O in a global variable list, unbound signals unlocated (for the
    /// device's I/O mapping).
    Codesys,
    /// TwinCAT 3: as CODESYS, unbound signals `AT %I*` / `AT %Q*` (linked in the System Manager).
    Twincat,
    /// SCL for S7-300/400: standard access, IEC timer `TON`.
    Scl,
    /// SCL for S7-1200/1500: optimised access, `TON_TIME`.
    Scl1500,
}

impl Dialect {
    fn siemens(self) -> bool {
        matches!(self, Dialect::Scl | Dialect::Scl1500)
    }

    /// Whether the I/O lives in a global variable list.
    fn gvl(self) -> bool {
        matches!(self, Dialect::Codesys | Dialect::Twincat)
    }
}

/// Whether the code of `dialect` has a program that wires the block: with bindings, and always
/// for the dialects with a global variable list (whose unbound signals are mapped in the tool).
pub fn wired(code: &Code, dialect: Dialect) -> bool {
    code.has_bindings() || (dialect.gvl() && code.variables().next().is_some())
}

/// Whether a variable is declared in the global variable list: bound to an address, or unbound.
fn in_gvl(binding: &Option<Binding>) -> bool {
    matches!(binding, None | Some(Binding::Address(_)))
}

/// Whether `dialect` has a global variable list for `code`.
pub fn has_gvl(code: &Code, dialect: Dialect) -> bool {
    dialect.gvl() && code.variables().any(|(v, _)| in_gvl(&v.binding))
}

fn test_text(code: &Code, test: &Test) -> String {
    match *test {
        Test::Input { input, negated } => {
            let name = &code.inputs[input].symbol;
            if negated {
                format!("NOT {name}")
            } else {
                name.clone()
            }
        }
        Test::Elapsed { timer, ms, strict } => {
            format!("{}.ET {} {}", code.timers[timer].symbol, if strict { ">" } else { ">=" }, time_literal(ms))
        }
    }
}

/// The head of a Siemens block: attribute (S7-1200/1500) and version.
fn siemens_head(dialect: Dialect) -> &'static str {
    if dialect == Dialect::Scl1500 {
        "{ S7_Optimized_Access := 'TRUE' }\nVERSION : 0.1\n"
    } else {
        "VERSION : 0.1\n"
    }
}

/// Prints the header comment, the function block and, with bindings, what wires it: for
/// CODESYS the global variable list first, then the block and the program.
pub fn print(code: &Code, dialect: Dialect, o: &mut impl Write) -> fmt::Result {
    for line in &code.header {
        writeln!(o, "(* {line} *)")?;
    }
    let wired = wired(code, dialect);
    if has_gvl(code, dialect) {
        writeln!(
            o,
            "\n(* Global variable list {}: in CODESYS add a Global Variable List named {} and paste this. *)",
            code.gvl, code.gvl
        )?;
        gvl(code, dialect, o)?;
        o.write_str("\n")?;
    }
    declaration(code, dialect, o)?;
    if dialect.siemens() {
        o.write_str("BEGIN\n")?;
    }
    body(code, o)?;
    o.write_str("END_FUNCTION_BLOCK\n")?;
    if wired {
        o.write_str("\n")?;
        program_declaration(code, dialect, o)?;
        if dialect.siemens() {
            o.write_str("BEGIN\n")?;
        }
        program_body(code, dialect, o)?;
        o.write_str(if dialect.siemens() { "END_FUNCTION_BLOCK\n" } else { "END_PROGRAM\n" })?;
    }
    Ok(())
}

/// The global variable list of the I/O (CODESYS, TwinCAT) under `{attribute 'qualified_only'}`,
/// so that the code names its variables `GVL_IO.press`: every variable bound to an address,
/// located, and every unbound one, for the tool's I/O mapping (TwinCAT: `AT %I*`, `AT %Q*`).
pub fn gvl(code: &Code, dialect: Dialect, o: &mut impl Write) -> fmt::Result {
    o.write_str("{attribute 'qualified_only'}\nVAR_GLOBAL\n")?;
    for (v, direction) in code.variables() {
        let at = match &v.binding {
            Some(b @ Binding::Address(_)) => format!(" AT {}", b.iec_text()),
            None if dialect == Dialect::Twincat => {
                if direction == Direction::Input {
                    " AT %I*".to_string()
                } else {
                    " AT %Q*".to_string()
                }
            }
            None => String::new(),
            Some(_) => continue,
        };
        writeln!(o, "    {}{at} : BOOL; (* {} *)", v.symbol, v.comment)?;
    }
    o.write_str("END_VAR\n")
}

/// The declaration part of the function block, from `FUNCTION_BLOCK` to the last `END_VAR`.
pub fn declaration(code: &Code, dialect: Dialect, o: &mut impl Write) -> fmt::Result {
    let ton = if dialect == Dialect::Scl1500 { "TON_TIME" } else { "TON" };
    writeln!(o, "FUNCTION_BLOCK {}", code.name)?;
    if dialect.siemens() {
        o.write_str(siemens_head(dialect))?;
    }
    o.write_str("VAR_INPUT\n")?;
    for i in &code.inputs {
        writeln!(o, "    {} : BOOL; (* {} *)", i.symbol, i.comment)?;
    }
    o.write_str("END_VAR\nVAR_OUTPUT\n")?;
    for out in &code.outputs {
        writeln!(o, "    {} : BOOL; (* {} *)", out.variable.symbol, out.variable.comment)?;
    }
    o.write_str("END_VAR\nVAR\n")?;
    o.write_str("    step : INT := 0; (* program position *)\n")?;
    o.write_str("    scan_done : BOOL;\n")?;
    for out in &code.outputs {
        if let Some(last) = out.gap() {
            writeln!(o, "    {last} : BOOL; (* {} at the last output write *)", out.variable.symbol)?;
        }
    }
    for t in &code.timers {
        writeln!(o, "    {} : {ton}; (* {} *)", t.symbol, t.comment)?;
    }
    o.write_str("END_VAR\n")
}

/// The declaration part of the program that wires the block (an FB in SCL: TIA calls it from
/// an organisation block).
pub fn program_declaration(code: &Code, dialect: Dialect, o: &mut impl Write) -> fmt::Result {
    if dialect.siemens() {
        write!(o, "FUNCTION_BLOCK {}\n{}", code.program, siemens_head(dialect))?;
    } else {
        writeln!(o, "PROGRAM {}", code.program)?;
    }
    o.write_str("VAR\n")?;
    writeln!(o, "    {} : {};", code.instance, code.name)?;
    if dialect == Dialect::Iec {
        for (v, _) in code.variables() {
            if let Some(b @ Binding::Address(_)) = &v.binding {
                writeln!(o, "    {} AT {} : BOOL; (* {} *)", v.symbol, b.iec_text(), v.comment)?;
            }
        }
    }
    o.write_str("END_VAR\n")
}

/// The statements of the program: call the block with the inputs, copy its outputs out.
pub fn program_body(code: &Code, dialect: Dialect, o: &mut impl Write) -> fmt::Result {
    let signal = |symbol: &str, binding: &Option<Binding>| -> String {
        match binding {
            _ if dialect.gvl() && in_gvl(binding) => format!("{}.{symbol}", code.gvl),
            Some(Binding::Address(_)) if dialect.siemens() => format!("\"{symbol}\""),
            Some(Binding::Address(_)) => symbol.to_string(),
            Some(b) => b.iec_text(),
            None => "FALSE".to_string(),
        }
    };
    let args: Vec<String> =
        code.inputs.iter().map(|i| format!("{} := {}", i.symbol, signal(&i.symbol, &i.binding))).collect();
    writeln!(o, "{}({});", code.instance, args.join(", "))?;
    for out in &code.outputs {
        let v = &out.variable;
        if v.binding.is_some() || dialect.gvl() {
            writeln!(o, "{} := {}.{};", signal(&v.symbol, &v.binding), code.instance, v.symbol)?;
        }
    }
    Ok(())
}

/// The statements of the function block (between its declarations and `END_FUNCTION_BLOCK`).
pub fn body(code: &Code, o: &mut impl Write) -> fmt::Result {
    o.write_str("(* Pulsed outputs are TRUE for one scan, with a FALSE scan between two pulses. *)\n")?;
    for out in code.outputs.iter().filter(|out| out.pulsed) {
        if let Some(last) = out.gap() {
            writeln!(o, "{last} := {};", out.variable.symbol)?;
        }
        writeln!(o, "{} := FALSE;", out.variable.symbol)?;
    }
    if !code.timers.is_empty() {
        o.write_str("(* Clocks run as timers; a restart calls the timer with IN := FALSE. *)\n")?;
    }
    for (k, t) in code.timers.iter().enumerate() {
        writeln!(o, "{}(IN := TRUE, PT := {});", t.symbol, preset_literal(code, k))?;
    }
    o.write_str("(* One scan: run from the stored position until the program waits. *)\n")?;
    o.write_str("scan_done := FALSE;\nWHILE NOT scan_done DO\n    CASE step OF\n")?;
    for (i, step) in code.steps.iter().enumerate() {
        writeln!(o, "    {i}: (* {} *)", step.comment)?;
        let restarts: String = step
            .restarts
            .iter()
            .map(|&t| format!("{}(IN := FALSE, PT := {}); ", code.timers[t].symbol, preset_literal(code, t)))
            .collect();
        let go = |target: usize| -> String {
            if target <= i && !step.back_in_scan {
                format!("step := {}; scan_done := TRUE;", code.resume_at(target))
            } else {
                format!("step := {target};")
            }
        };
        match step.statement {
            Statement::Wait { test } => write!(
                o,
                "        IF {} THEN\n            {restarts}step := {};\n        ELSE\n            scan_done := TRUE;\n        END_IF;\n",
                test_text(code, &test),
                i + 1
            )?,
            Statement::Branch { test, target } => write!(
                o,
                "        IF {} THEN\n            {restarts}{}\n        ELSE\n            step := {};\n        END_IF;\n",
                test_text(code, &test),
                go(target),
                i + 1
            )?,
            Statement::Act { output, effect, ends_scan } => {
                let value = if effect == Effect::Reset { "FALSE" } else { "TRUE" };
                let symbol = &code.outputs[output].variable.symbol;
                // Going on within the scan, or from where the next scan resumes.
                let next = if ends_scan {
                    format!("step := {}; scan_done := TRUE;", code.resume_at(i + 1))
                } else {
                    format!("step := {};", i + 1)
                };
                match code.outputs[output].gap().filter(|_| effect == Effect::Pulse) {
                    // Pulsed in the previous scan: wait here for one scan with the output FALSE.
                    Some(last) => write!(
                        o,
                        "        IF {last} THEN\n            scan_done := TRUE;\n        ELSE\n            {symbol} := {value};\n            {restarts}{next}\n        END_IF;\n"
                    )?,
                    None => write!(o, "        {symbol} := {value};\n        {restarts}{next}\n")?,
                }
            }
            Statement::Jump { target } => writeln!(o, "        {restarts}{}", go(target))?,
        }
    }
    o.write_str("    ELSE\n        step := 0;\n        scan_done := TRUE;\n    END_CASE;\nEND_WHILE;\n")
}
