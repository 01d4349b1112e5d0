//! IEC 61131-3 Instruction List: the same function block as the ST target, with the control
//! structure of 6.7.2 — a jump list on the step variable at the top, each wait storing its
//! position and ending the scan while its condition is false.

use crate::plc::model::code::{Binding, Code, Effect, Statement, Test};
use crate::plc::{preset_literal, print::st, time_literal};
use std::fmt::{self, Write};

fn load(code: &Code, test: &Test, o: &mut impl Write) -> fmt::Result {
    match *test {
        Test::Input { input, negated } => {
            writeln!(o, "        {} {}", if negated { "LDN" } else { "LD" }, code.inputs[input].symbol)
        }
        Test::Elapsed { timer, ms, strict } => write!(
            o,
            "        LD {}.ET\n        {} {}\n",
            code.timers[timer].symbol,
            if strict { "GT" } else { "GE" },
            time_literal(ms)
        ),
    }
}

/// Stores position `k` in the step variable.
fn store(o: &mut impl Write, k: usize) -> fmt::Result {
    write!(o, "        LD {k}\n        ST step\n")
}

/// Prints the function block in Instruction List.
pub fn print(code: &Code, o: &mut impl Write) -> fmt::Result {
    for line in &code.header {
        writeln!(o, "(* {line} *)")?;
    }
    write!(o, "FUNCTION_BLOCK {}\nVAR_INPUT\n", code.name)?;
    for i in &code.inputs {
        writeln!(o, "    {} : BOOL; (* {} *)", i.symbol, i.comment)?;
    }
    o.write_str("END_VAR\nVAR_OUTPUT\n")?;
    for out in &code.outputs {
        writeln!(o, "    {} : BOOL; (* {} *)", out.variable.symbol, out.variable.comment)?;
    }
    o.write_str("END_VAR\nVAR\n    step : INT := 0;\n")?;
    for out in &code.outputs {
        if let Some(last) = out.gap() {
            writeln!(o, "    {last} : BOOL; (* {} at the last output write *)", out.variable.symbol)?;
        }
    }
    for t in &code.timers {
        writeln!(o, "    {} : TON;", t.symbol)?;
    }
    o.write_str("END_VAR\n")?;
    for out in code.outputs.iter().filter(|out| out.pulsed) {
        if let Some(last) = out.gap() {
            write!(o, "        LD {}\n        ST {last}\n", out.variable.symbol)?;
        }
        write!(o, "        LD FALSE\n        ST {}\n", out.variable.symbol)?;
    }
    for (k, t) in code.timers.iter().enumerate() {
        writeln!(o, "        CAL {}(IN := TRUE, PT := {})", t.symbol, preset_literal(code, k))?;
    }
    // Jump list.
    for i in 0..code.steps.len() {
        write!(o, "        LD step\n        EQ {i}\n        JMPC S{i}\n")?;
    }
    o.write_str("        JMP RESTART\n")?;
    for (i, step) in code.steps.iter().enumerate() {
        writeln!(o, "S{i}: (* {} *)", step.comment)?;
        let restarts: String = step
            .restarts
            .iter()
            .map(|&t| {
                format!("        CAL {}(IN := FALSE, PT := {})\n", code.timers[t].symbol, preset_literal(code, t))
            })
            .collect();
        match step.statement {
            Statement::Wait { test } => {
                store(o, i)?;
                load(code, &test, o)?;
                o.write_str("        JMPCN END_SCAN\n")?;
                o.write_str(&restarts)?;
            }
            Statement::Branch { test, target } => {
                store(o, i)?;
                load(code, &test, o)?;
                write!(o, "        JMPC B{i}\n        JMP S{}\n", i + 1)?;
                write!(o, "B{i}:\n{restarts}")?;
                if target > i || step.back_in_scan {
                    writeln!(o, "        JMP S{target}")?;
                } else {
                    store(o, code.resume_at(target))?;
                    o.write_str("        JMP END_SCAN\n")?;
                }
            }
            Statement::Act { output, effect, ends_scan } => {
                let out = &code.outputs[output].variable.symbol;
                let verb = match effect {
                    Effect::Pulse => "ST",
                    Effect::Set => "S",
                    Effect::Reset => "R",
                };
                if let Some(last) = code.outputs[output].gap().filter(|_| effect == Effect::Pulse) {
                    // Pulsed in the previous scan: wait here for one scan with the output FALSE.
                    store(o, i)?;
                    write!(o, "        LD {last}\n        JMPC END_SCAN\n")?;
                }
                write!(o, "        LD TRUE\n        {verb} {out}\n")?;
                o.write_str(&restarts)?;
                if ends_scan {
                    store(o, code.resume_at(i + 1))?;
                    o.write_str("        JMP END_SCAN\n")?;
                }
            }
            Statement::Jump { target } => {
                o.write_str(&restarts)?;
                if target > i || step.back_in_scan {
                    writeln!(o, "        JMP S{target}")?;
                } else {
                    store(o, code.resume_at(target))?;
                    o.write_str("        JMP END_SCAN\n")?;
                }
            }
        }
    }
    write!(o, "S{}:\nRESTART:\n", code.steps.len())?;
    store(o, 0)?;
    o.write_str("END_SCAN:\n        RET\nEND_FUNCTION_BLOCK\n")?;
    if code.has_bindings() {
        program(code, o)?;
    }
    Ok(())
}

/// The program that wires the block, with the ST target's located declarations.
fn program(code: &Code, o: &mut impl Write) -> fmt::Result {
    o.write_str("\n")?;
    st::program_declaration(code, st::Dialect::Iec, o)?;
    let signal = |symbol: &str, binding: &Option<Binding>| match binding {
        Some(Binding::Address(_)) => symbol.to_string(),
        Some(b) => b.iec_text(),
        None => "FALSE".to_string(),
    };
    let args: Vec<String> =
        code.inputs.iter().map(|i| format!("{} := {}", i.symbol, signal(&i.symbol, &i.binding))).collect();
    writeln!(o, "        CAL {}({})", code.instance, args.join(", "))?;
    for out in code.outputs.iter().filter(|out| out.variable.binding.is_some()) {
        let v = &out.variable;
        write!(o, "        LD {}.{}\n        ST {}\n", code.instance, v.symbol, signal(&v.symbol, &v.binding))?;
    }
    o.write_str("END_PROGRAM\n")
}
