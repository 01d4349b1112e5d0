//! IEC 61131-3 Instruction List: the same function block as the ST target, with the control
//! structure of 6.7.2 — a jump list on the step variable at the top, each wait storing its
//! position and ending the scan while its condition is false. It prints units of the jump-list
//! shape (`StepBlock`).

use crate::plc::model::unit::Next;
use crate::plc::print::steps::{Action, Bit, Cond, Drive, StepBlock, Wire};
use crate::plc::{iec_address, time_literal};
use std::fmt::{self, Write};

fn load(block: &StepBlock<'_>, cond: &Cond, o: &mut impl Write) -> fmt::Result {
    match *cond {
        Cond::Bit { bit, negated } => {
            let name = match bit {
                Bit::Input(k) => block.block.inputs[k].name.as_str(),
                Bit::Last(k) => block.last[k].expect("a tested memory of the last write exists"),
            };
            writeln!(o, "        {} {name}", if negated { "LDN" } else { "LD" })
        }
        Cond::Elapsed { timer, ms, strict } => write!(
            o,
            "        LD {}.ET\n        {} {}\n",
            block.timers[timer].var.name,
            if strict { "GT" } else { "GE" },
            time_literal(ms)
        ),
    }
}

/// Stores position `k` in the step variable.
fn store(o: &mut impl Write, position: &str, k: usize) -> fmt::Result {
    write!(o, "        LD {k}\n        ST {position}\n")
}

/// Prints the function block in Instruction List, and the program that wires it when a signal
/// is bound.
pub(in crate::plc) fn print(block: &StepBlock<'_>, o: &mut impl Write) -> fmt::Result {
    let fb = block.block;
    let position = block.list.position.as_str();
    let n = block.steps.len();
    for line in &block.unit.header {
        writeln!(o, "(* {line} *)")?;
    }
    write!(o, "FUNCTION_BLOCK {}\nVAR_INPUT\n", fb.name)?;
    for v in &fb.inputs {
        writeln!(o, "    {} : BOOL; (* {} *)", v.name, v.comment)?;
    }
    o.write_str("END_VAR\nVAR_OUTPUT\n")?;
    for v in &fb.outputs {
        writeln!(o, "    {} : BOOL; (* {} *)", v.name, v.comment)?;
    }
    writeln!(o, "END_VAR\nVAR\n    {position} : INT := 0;")?;
    for (k, v) in fb.outputs.iter().enumerate() {
        if let Some(last) = block.last[k] {
            writeln!(o, "    {last} : BOOL; (* {} at the last output write *)", v.name)?;
        }
    }
    for t in &block.timers {
        writeln!(o, "    {} : TON;", t.var.name)?;
    }
    o.write_str("END_VAR\n")?;
    for (k, v) in fb.outputs.iter().enumerate().filter(|(k, _)| block.pulsed[*k]) {
        if let Some(last) = block.last[k] {
            write!(o, "        LD {}\n        ST {last}\n", v.name)?;
        }
        write!(o, "        LD FALSE\n        ST {}\n", v.name)?;
    }
    for t in &block.timers {
        writeln!(o, "        CAL {}(IN := TRUE, PT := {})", t.var.name, time_literal(t.preset_ms))?;
    }
    // Jump list.
    for i in 0..n {
        write!(o, "        LD {position}\n        EQ {i}\n        JMPC S{i}\n")?;
    }
    o.write_str("        JMP RESTART\n")?;
    let transfer = |next: Next, o: &mut String| -> fmt::Result {
        match next {
            Next::Continue(k) => writeln!(o, "        JMP S{}", k.min(n)),
            Next::Resume(k) => {
                store(o, position, k)?;
                o.write_str("        JMP END_SCAN\n")
            }
        }
    };
    for (i, step) in block.steps.iter().enumerate() {
        writeln!(o, "S{i}: (* {} *)", step.comment)?;
        let mut actions = String::new();
        for a in &step.actions {
            match *a {
                Action::Drive { output, value } => {
                    let (load, verb) = match block.drive(output, value) {
                        Drive::Assign(level) => (if level { "TRUE" } else { "FALSE" }, "ST"),
                        Drive::Set => ("TRUE", "S"),
                        Drive::Reset => ("TRUE", "R"),
                    };
                    write!(actions, "        LD {load}\n        {verb} {}\n", fb.outputs[output].name)?;
                }
                Action::Restart { timer } => {
                    let t = &block.timers[timer];
                    writeln!(actions, "        CAL {}(IN := FALSE, PT := {})", t.var.name, time_literal(t.preset_ms))?;
                }
            }
        }
        if let Some(wait) = &step.wait {
            store(o, position, i)?;
            load(block, wait, o)?;
            o.write_str("        JMPCN END_SCAN\n")?;
        }
        match &step.when {
            Some(when) => {
                if step.wait.is_none() {
                    store(o, position, i)?;
                }
                load(block, when, o)?;
                write!(o, "        JMPC B{i}\n        JMP S{}\nB{i}:\n{actions}", i + 1)?;
                let mut jump = String::new();
                transfer(step.next, &mut jump)?;
                o.write_str(&jump)?;
            }
            None => {
                o.write_str(&actions)?;
                if step.next != Next::Continue(i + 1) {
                    let mut jump = String::new();
                    transfer(step.next, &mut jump)?;
                    o.write_str(&jump)?;
                }
            }
        }
    }
    write!(o, "S{n}:\nRESTART:\n")?;
    store(o, position, 0)?;
    o.write_str("END_SCAN:\n        RET\nEND_FUNCTION_BLOCK\n")?;
    if block.wires.iter().any(|w| *w != Wire::Unbound) {
        program(block, o)?;
    }
    Ok(())
}

/// The program that wires the block: located variables for the addresses, project symbols as
/// written.
fn program(block: &StepBlock<'_>, o: &mut impl Write) -> fmt::Result {
    let fb = block.block;
    write!(o, "\nPROGRAM {}\nVAR\n    {} : {};\n", block.program.name, block.instance, fb.name)?;
    for (v, wire) in block.variables().zip(&block.wires) {
        if let Wire::Address { name, address } = wire {
            writeln!(o, "    {name} AT %{} : BOOL; (* {} *)", iec_address(address), v.comment)?;
        }
    }
    o.write_str("END_VAR\n")?;
    let outside = |wire: &Wire<'_>| match *wire {
        Wire::Address { name, .. } => name.to_string(),
        Wire::Symbol(symbol) => symbol.to_string(),
        Wire::Unbound => "FALSE".to_string(),
    };
    let n_in = fb.inputs.len();
    let args: Vec<String> =
        fb.inputs.iter().zip(&block.wires).map(|(v, w)| format!("{} := {}", v.name, outside(w))).collect();
    writeln!(o, "        CAL {}({})", block.instance, args.join(", "))?;
    for (v, wire) in fb.outputs.iter().zip(&block.wires[n_in..]).filter(|(_, w)| **w != Wire::Unbound) {
        write!(o, "        LD {}.{}\n        ST {}\n", block.instance, v.name, outside(wire))?;
    }
    o.write_str("END_PROGRAM\n")
}
