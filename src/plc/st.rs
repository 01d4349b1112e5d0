//! Structured Text: plain IEC 61131-3, CODESYS/TwinCAT and Siemens SCL (TIA Portal source).
//!
//! A `FUNCTION_BLOCK` with a BOOL input per input signal and a BOOL output per output signal;
//! a step variable and a `CASE` inside a `WHILE` loop that runs one scan per call (see the
//! module doc of `plc`). When variables are bound to signals, a `PROGRAM` instantiates the block
//! and wires it to the addresses or symbols.

use super::model::{Binding, Code, Effect, Statement, Test};
use super::{iec_address, preset_literal, siemens_address, time_literal};
use std::fmt::{self, Write};

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Dialect {
    Iec,
    Codesys,
    Scl,
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

fn bound_text(binding: &Binding, dialect: Dialect) -> String {
    match binding {
        Binding::Address(text) if dialect == Dialect::Scl => format!("%{}", siemens_address(text)),
        Binding::Address(text) => format!("%{}", iec_address(text)),
        Binding::Symbol(text) => text.clone(),
    }
}

/// Prints the function block (and, with bindings, a program that wires it).
pub fn print(code: &Code, dialect: Dialect, o: &mut impl Write) -> fmt::Result {
    let ton = if dialect == Dialect::Scl { "TON_TIME" } else { "TON" };
    for line in &code.header {
        writeln!(o, "(* {line} *)")?;
    }
    match dialect {
        Dialect::Scl => {
            write!(o, "FUNCTION_BLOCK {}\n{{ S7_Optimized_Access := 'TRUE' }}\nVERSION : 0.1\n", code.name)?
        }
        _ => writeln!(o, "FUNCTION_BLOCK {}", code.name)?,
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
    for t in &code.timers {
        writeln!(o, "    {} : {ton}; (* {} *)", t.symbol, t.comment)?;
    }
    o.write_str("END_VAR\n")?;
    if dialect == Dialect::Scl {
        o.write_str("BEGIN\n")?;
    }
    body(code, o)?;
    o.write_str("END_FUNCTION_BLOCK\n")?;
    if code.has_bindings() {
        wiring(code, dialect, o)?;
    }
    Ok(())
}

/// The statements of the function block (between its declarations and `END_FUNCTION_BLOCK`).
pub fn body(code: &Code, o: &mut impl Write) -> fmt::Result {
    o.write_str("(* Pulsed outputs are TRUE for one scan. *)\n")?;
    for out in code.outputs.iter().filter(|out| out.pulsed) {
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
            if target <= i {
                format!("step := {target}; scan_done := TRUE;")
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
            Statement::Act { output, effect } => {
                let value = if effect == Effect::Reset { "FALSE" } else { "TRUE" };
                write!(
                    o,
                    "        {} := {value};\n        {restarts}step := {};\n        scan_done := TRUE;\n",
                    code.outputs[output].variable.symbol,
                    i + 1
                )?
            }
            Statement::Jump { target } => writeln!(o, "        {restarts}{}", go(target))?,
        }
    }
    o.write_str("    ELSE\n        step := 0;\n        scan_done := TRUE;\n    END_CASE;\nEND_WHILE;\n")
}

/// A program that instantiates the block and wires it to addresses and symbols.
fn wiring(code: &Code, dialect: Dialect, o: &mut impl Write) -> fmt::Result {
    let scl = dialect == Dialect::Scl;
    let name = format!("{}_main", code.name);
    if scl {
        // TIA Portal: a cyclic organisation block would call the block; the wiring is given as
        // a function block of its own so it imports without a configuration.
        write!(o, "\nFUNCTION_BLOCK {name}\n{{ S7_Optimized_Access := 'TRUE' }}\nVERSION : 0.1\n")?;
    } else {
        write!(o, "\nPROGRAM {name}\n")?;
    }
    o.write_str("VAR\n")?;
    writeln!(o, "    ctrl : {};", code.name)?;
    if !scl {
        // IEC and CODESYS declare located variables; SCL reads addresses directly.
        for v in code.inputs.iter().chain(code.outputs.iter().map(|x| &x.variable)) {
            if let Some(b @ Binding::Address(_)) = &v.binding {
                writeln!(o, "    {}_io AT {} : BOOL;", v.symbol, bound_text(b, dialect))?;
            }
        }
    }
    o.write_str("END_VAR\n")?;
    if scl {
        o.write_str("BEGIN\n")?;
    }
    let signal = |symbol: &str, binding: &Option<Binding>| -> String {
        match binding {
            Some(b @ Binding::Address(_)) if scl => bound_text(b, dialect),
            Some(Binding::Address(_)) => format!("{symbol}_io"),
            Some(Binding::Symbol(text)) => text.clone(),
            None => "FALSE".to_string(),
        }
    };
    let args: Vec<String> =
        code.inputs.iter().map(|i| format!("{} := {}", i.symbol, signal(&i.symbol, &i.binding))).collect();
    writeln!(o, "ctrl({});", args.join(", "))?;
    for out in &code.outputs {
        let v = &out.variable;
        if v.binding.is_some() {
            writeln!(o, "{} := ctrl.{};", signal(&v.symbol, &v.binding), v.symbol)?;
        }
    }
    o.write_str(if scl { "END_FUNCTION_BLOCK\n" } else { "END_PROGRAM\n" })
}
