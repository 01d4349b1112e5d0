//! Structured Text: plain IEC 61131-3, CODESYS/TwinCAT and Siemens SCL (TIA Portal source).
//!
//! A `FUNCTION_BLOCK` with a BOOL input per input signal and a BOOL output per output signal;
//! a step variable and a `CASE` inside a `WHILE` loop that runs one scan per call (see the
//! module doc of `plc`). When the `io` section binds signals, a `PROGRAM` instantiates the block
//! and wires it to the addresses or symbols.

use super::{iec_address, siemens_address, time_literal, Code, Effect, Step, Test};
use crate::timed::model::IoTarget;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Dialect {
    Iec,
    Codesys,
    Scl,
}

fn test_text(code: &Code, test: &Test) -> String {
    match *test {
        Test::Input { input, negated } => {
            let name = &code.inputs[input].ident;
            if negated {
                format!("NOT {name}")
            } else {
                name.clone()
            }
        }
        Test::Elapsed { timer, ms, strict } => {
            format!("{}.ET {} {}", code.timers[timer].ident, if strict { ">" } else { ">=" }, time_literal(ms))
        }
    }
}

fn bound_text(target: &IoTarget, dialect: Dialect) -> String {
    match target {
        IoTarget::Address { text, .. } if dialect == Dialect::Scl => format!("%{}", siemens_address(text)),
        IoTarget::Address { text, .. } => format!("%{}", iec_address(text)),
        IoTarget::Symbol { text, .. } => text.clone(),
    }
}

/// Prints the function block (and, with bindings, a program that wires it).
pub fn print(code: &Code, dialect: Dialect) -> String {
    let mut o = String::new();
    let ton = if dialect == Dialect::Scl { "TON_TIME" } else { "TON" };
    let (bool_t, int_t) = ("BOOL", "INT");
    for line in &code.header {
        o.push_str(&format!("(* {line} *)\n"));
    }
    match dialect {
        Dialect::Scl => {
            o.push_str(&format!("FUNCTION_BLOCK {}\n{{ S7_Optimized_Access := 'TRUE' }}\nVERSION : 0.1\n", code.name));
        }
        _ => o.push_str(&format!("FUNCTION_BLOCK {}\n", code.name)),
    }
    o.push_str("VAR_INPUT\n");
    for i in &code.inputs {
        o.push_str(&format!("    {} : {bool_t}; (* {} *)\n", i.ident, i.notes.join(", ")));
    }
    o.push_str("END_VAR\nVAR_OUTPUT\n");
    for out in &code.outputs {
        o.push_str(&format!("    {} : {bool_t}; (* {} *)\n", out.ident, out.notes.join(", ")));
    }
    o.push_str("END_VAR\nVAR\n");
    o.push_str(&format!("    step : {int_t} := 0; (* program position *)\n"));
    o.push_str(&format!("    scan_done : {bool_t};\n"));
    for t in &code.timers {
        o.push_str(&format!("    {} : {ton}; (* clock {} *)\n", t.ident, t.ident.trim_start_matches("t_")));
    }
    o.push_str("END_VAR\n");
    if dialect == Dialect::Scl {
        o.push_str("BEGIN\n");
    }
    body(code, &mut o);
    o.push_str("END_FUNCTION_BLOCK\n");
    if code.inputs.iter().any(|i| i.binding.is_some()) || code.outputs.iter().any(|out| out.binding.is_some()) {
        wiring(code, dialect, &mut o);
    }
    o
}

fn body(code: &Code, o: &mut String) {
    o.push_str("(* Pulsed outputs are TRUE for one scan. *)\n");
    for out in code.outputs.iter().filter(|out| out.pulsed) {
        o.push_str(&format!("{} := FALSE;\n", out.ident));
    }
    if !code.timers.is_empty() {
        o.push_str("(* Clocks run as timers; a restart calls the timer with IN := FALSE. *)\n");
    }
    for (k, t) in code.timers.iter().enumerate() {
        o.push_str(&format!("{}(IN := TRUE, PT := {});\n", t.ident, super::preset_literal(code, k)));
    }
    o.push_str("(* One scan: run from the stored position until the program waits. *)\n");
    o.push_str("scan_done := FALSE;\nWHILE NOT scan_done DO\n    CASE step OF\n");
    for (i, step) in code.steps.iter().enumerate() {
        o.push_str(&format!("    {i}: (* {} *)\n", code.comments[i]));
        let restarts: String = code.restarts[i]
            .iter()
            .map(|&t| format!("{}(IN := FALSE, PT := {}); ", code.timers[t].ident, super::preset_literal(code, t)))
            .collect();
        let go = |target: usize| -> String {
            if target <= i {
                format!("step := {target}; scan_done := TRUE;")
            } else {
                format!("step := {target};")
            }
        };
        match step {
            Step::Wait { test } => {
                o.push_str(&format!(
                    "        IF {} THEN\n            {restarts}step := {};\n        ELSE\n            scan_done := TRUE;\n        END_IF;\n",
                    test_text(code, test),
                    i + 1
                ));
            }
            Step::Branch { test, target } => {
                o.push_str(&format!(
                    "        IF {} THEN\n            {restarts}{}\n        ELSE\n            step := {};\n        END_IF;\n",
                    test_text(code, test),
                    go(*target),
                    i + 1
                ));
            }
            Step::Act { output, effect } => {
                let value = if *effect == Effect::Reset { "FALSE" } else { "TRUE" };
                o.push_str(&format!(
                    "        {} := {value};\n        {restarts}step := {};\n        scan_done := TRUE;\n",
                    code.outputs[*output].ident,
                    i + 1
                ));
            }
            Step::Jump { target } => {
                o.push_str(&format!("        {restarts}{}\n", go(*target)));
            }
        }
    }
    o.push_str("    ELSE\n        step := 0;\n        scan_done := TRUE;\n    END_CASE;\nEND_WHILE;\n");
}

/// A program that instantiates the block and wires it to addresses and symbols.
fn wiring(code: &Code, dialect: Dialect, o: &mut String) {
    let scl = dialect == Dialect::Scl;
    let name = format!("{}_main", code.name);
    if scl {
        // TIA Portal: a cyclic organisation block would call the block; the wiring is given as
        // a function block of its own so it imports without a configuration.
        o.push_str(&format!("\nFUNCTION_BLOCK {name}\n{{ S7_Optimized_Access := 'TRUE' }}\nVERSION : 0.1\n"));
    } else {
        o.push_str(&format!("\nPROGRAM {name}\n"));
    }
    o.push_str("VAR\n");
    o.push_str(&format!("    ctrl : {};\n", code.name));
    if !scl {
        // IEC and CODESYS declare located variables; SCL reads addresses directly.
        for (ident, binding) in code
            .inputs
            .iter()
            .map(|i| (&i.ident, &i.binding))
            .chain(code.outputs.iter().map(|x| (&x.ident, &x.binding)))
        {
            if let Some(b @ IoTarget::Address { .. }) = binding {
                o.push_str(&format!("    {ident}_io AT {} : BOOL;\n", bound_text(b, dialect)));
            }
        }
    }
    o.push_str("END_VAR\n");
    if scl {
        o.push_str("BEGIN\n");
    }
    let signal = |ident: &str, binding: &Option<IoTarget>| -> String {
        match binding {
            Some(b @ IoTarget::Address { .. }) if scl => bound_text(b, dialect),
            Some(IoTarget::Address { .. }) => format!("{ident}_io"),
            Some(IoTarget::Symbol { text, .. }) => text.clone(),
            None => "FALSE".to_string(),
        }
    };
    let args: Vec<String> =
        code.inputs.iter().map(|i| format!("{} := {}", i.ident, signal(&i.ident, &i.binding))).collect();
    o.push_str(&format!("ctrl({});\n", args.join(", ")));
    for out in &code.outputs {
        if out.binding.is_some() {
            o.push_str(&format!("{} := ctrl.{};\n", signal(&out.ident, &out.binding), out.ident));
        }
    }
    o.push_str(if scl { "END_FUNCTION_BLOCK\n" } else { "END_PROGRAM\n" });
}
