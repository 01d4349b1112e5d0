//! IEC 61131-3 Instruction List: the same function block as the ST target, with the control
//! structure of 6.7.2 — a jump list on the step variable at the top, each wait storing its
//! position and ending the scan while its condition is false.

use super::{preset_literal, Code, Effect, Step, Test};

fn load(code: &Code, test: &Test) -> String {
    match *test {
        Test::Input { input, negated } => {
            format!("        {} {}\n", if negated { "LDN" } else { "LD" }, code.inputs[input].ident)
        }
        Test::Elapsed { timer, ms, strict } => {
            format!(
                "        LD {}.ET\n        {} {}\n",
                code.timers[timer].ident,
                if strict { "GT" } else { "GE" },
                super::time_literal(ms)
            )
        }
    }
}

/// Prints the function block in Instruction List.
pub fn print(code: &Code) -> String {
    let mut o = String::new();
    for line in &code.header {
        o.push_str(&format!("(* {line} *)\n"));
    }
    o.push_str(&format!("FUNCTION_BLOCK {}\nVAR_INPUT\n", code.name));
    for i in &code.inputs {
        o.push_str(&format!("    {} : BOOL; (* {} *)\n", i.ident, i.notes.join(", ")));
    }
    o.push_str("END_VAR\nVAR_OUTPUT\n");
    for out in &code.outputs {
        o.push_str(&format!("    {} : BOOL; (* {} *)\n", out.ident, out.notes.join(", ")));
    }
    o.push_str("END_VAR\nVAR\n    step : INT := 0;\n");
    for t in &code.timers {
        o.push_str(&format!("    {} : TON;\n", t.ident));
    }
    o.push_str("END_VAR\n");
    for out in code.outputs.iter().filter(|out| out.pulsed) {
        o.push_str(&format!("        LD FALSE\n        ST {}\n", out.ident));
    }
    for (k, t) in code.timers.iter().enumerate() {
        o.push_str(&format!("        CAL {}(IN := TRUE, PT := {})\n", t.ident, preset_literal(code, k)));
    }
    // Jump list.
    for i in 0..code.steps.len() {
        o.push_str(&format!("        LD step\n        EQ {i}\n        JMPC S{i}\n"));
    }
    o.push_str("        JMP RESTART\n");
    let store = |o: &mut String, k: usize| o.push_str(&format!("        LD {k}\n        ST step\n"));
    for (i, step) in code.steps.iter().enumerate() {
        o.push_str(&format!("S{i}: (* {} *)\n", code.comments[i]));
        let restarts: String = code.restarts[i]
            .iter()
            .map(|&t| format!("        CAL {}(IN := FALSE, PT := {})\n", code.timers[t].ident, preset_literal(code, t)))
            .collect();
        match step {
            Step::Wait { test } => {
                store(&mut o, i);
                o.push_str(&load(code, test));
                o.push_str("        JMPCN END_SCAN\n");
                o.push_str(&restarts);
            }
            Step::Branch { test, target } => {
                store(&mut o, i);
                o.push_str(&load(code, test));
                o.push_str(&format!("        JMPC B{i}\n        JMP S{}\n", i + 1));
                o.push_str(&format!("B{i}:\n{restarts}"));
                if *target > i {
                    o.push_str(&format!("        JMP S{target}\n"));
                } else {
                    store(&mut o, *target);
                    o.push_str("        JMP END_SCAN\n");
                }
            }
            Step::Act { output, effect } => {
                let out = &code.outputs[*output].ident;
                match effect {
                    Effect::Pulse => o.push_str(&format!("        LD TRUE\n        ST {out}\n")),
                    Effect::Set => o.push_str(&format!("        LD TRUE\n        S {out}\n")),
                    Effect::Reset => o.push_str(&format!("        LD TRUE\n        R {out}\n")),
                }
                o.push_str(&restarts);
                store(&mut o, i + 1);
                o.push_str("        JMP END_SCAN\n");
            }
            Step::Jump { target } => {
                o.push_str(&restarts);
                if *target > i {
                    o.push_str(&format!("        JMP S{target}\n"));
                } else {
                    store(&mut o, *target);
                    o.push_str("        JMP END_SCAN\n");
                }
            }
        }
    }
    o.push_str(&format!("S{}:\nRESTART:\n", code.steps.len()));
    store(&mut o, 0);
    o.push_str("END_SCAN:\n        RET\nEND_FUNCTION_BLOCK\n");
    o
}
