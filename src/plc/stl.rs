//! Siemens S7 Statement List (AWL), as in Peter 2005, 6.7.2: an organisation block whose
//! position is kept in the marker byte MB 0 and entered through a `JL` jump list; a wait stores
//! its position and ends the cycle (`JCN end`) while its condition is false, so the program has
//! no backward jumps; requests `SET` / `S` / `R` outputs. Labels are four letters numbered by
//! command position (`aaaa` is command 0, `aaac` command 2), as in the thesis's listing.
//!
//! Two choices beyond the thesis: the cycle also ends after every request, so that the next test
//! reads inputs taken after the request was written out (the thesis continues into the next test,
//! which then sees the input image from before the request); and clocks are S7 on-delay timers,
//! one per compared threshold, restarted by calling `SD` with RLO 0 (resolution 10 ms). Inputs
//! and outputs without an io binding get memory bits from M 10.0 on.

use super::model::{Binding, Code, Effect, Statement, Test};
use super::siemens_address;
use super::target::TimeType;
use std::fmt::{self, Write};

/// Four-letter label of command `i`: aaaa, aaab, …
fn label(i: usize) -> String {
    let mut n = i;
    let mut chars = ['a'; 4];
    for c in chars.iter_mut().rev() {
        *c = (b'a' + (n % 26) as u8) as char;
        n /= 26;
    }
    chars.iter().collect()
}

/// `S5T#…` literal.
fn s5time(ms: u64) -> String {
    let (h, m, s, r) = (ms / 3_600_000, ms / 60_000 % 60, ms / 1000 % 60, ms % 1000);
    let mut out = String::from("S5T#");
    for (v, u) in [(h, "H"), (m, "M"), (s, "S"), (r, "MS")] {
        if v > 0 {
            out.push_str(&format!("{v}{u}"));
        }
    }
    if ms == 0 {
        out.push_str("0MS");
    }
    out
}

fn operand(binding: &Option<Binding>, fallback: &str) -> String {
    match binding {
        Some(Binding::Address(text)) => {
            let a = siemens_address(text);
            let split = a.find(|c: char| c.is_ascii_digit()).unwrap_or(a.len());
            format!("{} {}", &a[..split], &a[split..])
        }
        Some(Binding::Symbol(text)) => format!("\"{text}\""),
        None => fallback.to_string(),
    }
}

/// Prints the organisation block.
pub fn print(code: &Code, o: &mut impl Write) -> fmt::Result {
    let n = code.steps.len();
    // Where execution continues after step i when it falls through (through jumps).
    let resolve = |mut i: usize| -> usize {
        let mut hops = 0;
        while i < n && hops <= n {
            match code.steps[i].statement {
                Statement::Jump { target } if code.steps[i].restarts.is_empty() => {
                    i = target;
                    hops += 1;
                }
                _ => break,
            }
        }
        if i >= n {
            0
        } else {
            i
        }
    };
    // Resumption points: the start, every wait, the continuation of every request, and the
    // targets of backward jumps.
    let mut resume = vec![false; n.max(1)];
    resume[0] = true;
    for (i, s) in code.steps.iter().enumerate() {
        match s.statement {
            Statement::Wait { .. } => resume[i] = true,
            Statement::Act { .. } => resume[resolve(i + 1)] = true,
            Statement::Branch { target, .. } | Statement::Jump { target } if target <= i => {
                resume[resolve(target)] = true
            }
            _ => {}
        }
    }
    let index: Vec<usize> = resume
        .iter()
        .scan(0, |k, &r| {
            let v = *k;
            if r {
                *k += 1;
            }
            Some(v)
        })
        .collect();
    let points: Vec<usize> = (0..resume.len()).filter(|&i| resume[i]).collect();
    let wide = points.len() > 255;
    // Memory bits for unbound signals.
    let mut next_bit = 80usize; // M 10.0
    let mut bit = || {
        let b = next_bit;
        next_bit += 1;
        format!("M {}.{}", b / 8, b % 8)
    };
    let inputs: Vec<String> = code.inputs.iter().map(|i| operand(&i.binding, &bit())).collect();
    let outputs: Vec<String> = code.outputs.iter().map(|o| operand(&o.variable.binding, &bit())).collect();
    // One S7 timer per (timer, preset); a strict threshold waits for the next S5TIME value.
    let preset =
        |ms: u64, strict: bool| u64::try_from(TimeType::S5Time.preset_for(u128::from(ms), strict)).unwrap_or(u64::MAX);
    let mut s7_timers: Vec<(usize, u64)> = Vec::new();
    for s in &code.steps {
        if let Statement::Wait { test: Test::Elapsed { timer, ms, strict } }
        | Statement::Branch { test: Test::Elapsed { timer, ms, strict }, .. } = s.statement
        {
            let key = (timer, preset(ms, strict));
            if !s7_timers.contains(&key) {
                s7_timers.push(key);
            }
        }
    }
    let t_number = |timer: usize, ms: u64| s7_timers.iter().position(|&x| x == (timer, ms)).map_or(0, |k| k + 1);
    let position = if wide { "MW 0" } else { "MB 0" };

    for line in &code.header {
        writeln!(o, "// {line}")?;
    }
    o.write_str("// Signals:\n")?;
    for (i, input) in code.inputs.iter().enumerate() {
        writeln!(o, "//   {:<10} {}", inputs[i], input.comment)?;
    }
    for (k, out) in code.outputs.iter().enumerate() {
        writeln!(o, "//   {:<10} {}", outputs[k], out.variable.comment)?;
    }
    writeln!(o, "//   {position:<10} program position")?;
    for (k, &(timer, ms)) in s7_timers.iter().enumerate() {
        writeln!(o, "//   T {:<8} {} reached {} ms", k + 1, code.timers[timer].comment, ms)?;
    }
    o.write_str("ORGANIZATION_BLOCK OB 1\nBEGIN\n")?;
    for (k, out) in code.outputs.iter().enumerate() {
        if out.pulsed {
            write!(o, "\tCLR\n\t=\t{}\n", outputs[k])?;
        }
    }
    for &(timer, ms) in &s7_timers {
        write!(o, "\tSET\n\tL\t{}\n\tSD\tT {}\n", s5time(ms), t_number(timer, ms))?;
    }
    // Text, not output: the trampolines of branches are collected apart and printed last.
    let store = |k: usize| format!("\tL\t{k}\n\tT\t{position}\n");
    if wide {
        for &p in &points {
            write!(o, "\tL\tMW 0\n\tL\t{}\n\t==I\n\tJC\t{}\n", index[p], label(p))?;
        }
        o.write_str("\tJU\tud\n")?;
    } else {
        o.write_str("\tL\tMB 0\n\tJL\tud\n")?;
        for &p in &points {
            writeln!(o, "\tJU\t{}", label(p))?;
        }
    }
    o.write_str("ud:\tL\t0\n")?;
    write!(o, "\tT\t{position}\n\tJU\t{}\n", label(0))?;
    let test = |t: &Test| match *t {
        Test::Input { input, negated } => format!("\t{}\t{}\n", if negated { "AN" } else { "A" }, inputs[input]),
        Test::Elapsed { timer, ms, strict } => format!("\tA\tT {}\n", t_number(timer, preset(ms, strict))),
    };
    let restart = |i: usize| -> String {
        let mut text = String::new();
        for &timer in &code.steps[i].restarts {
            for &(t, ms) in s7_timers.iter().filter(|(t, _)| *t == timer) {
                text.push_str(&format!("\tCLR\n\tL\t{}\n\tSD\tT {}\n", s5time(ms), t_number(t, ms)));
            }
        }
        text
    };
    let jumped = code.jumped_to();
    let mut trampolines = String::new();
    // After an unconditional jump, only labelled code can be reached.
    let mut falls_in = true;
    for (i, step) in code.steps.iter().enumerate() {
        let needs_label = resume[i] || jumped[i];
        if !falls_in && !needs_label {
            continue;
        }
        falls_in = !matches!(step.statement, Statement::Act { .. } | Statement::Jump { .. });
        let lbl = if needs_label { format!("{}:", label(i)) } else { String::new() };
        writeln!(o, "{lbl}\tNOP\t0\t// {}", step.comment)?;
        match step.statement {
            Statement::Wait { test: t } => {
                write!(o, "{}{}\tJCN\tend\n{}", store(index[i]), test(&t), restart(i))?;
            }
            Statement::Branch { test: t, target } => {
                let taken = format!("b{}", &label(i)[1..]);
                writeln!(o, "{}\tJC\t{taken}", test(&t))?;
                trampolines.push_str(&format!("{taken}:\tNOP\t0\n{}", restart(i)));
                if target > i {
                    trampolines.push_str(&format!("\tJU\t{}\n", label(target)));
                } else {
                    trampolines.push_str(&format!("{}\tJU\tend\n", store(index[resolve(target)])));
                }
            }
            Statement::Act { output, effect } => {
                let verb = match effect {
                    Effect::Pulse => "=",
                    Effect::Set => "S",
                    Effect::Reset => "R",
                };
                write!(o, "\tSET\n\t{verb}\t{}\n", outputs[output])?;
                writeln!(o, "{}{}\tJU\tend", restart(i), store(index[resolve(i + 1)]))?;
            }
            Statement::Jump { target } => {
                o.write_str(&restart(i))?;
                if target > i {
                    writeln!(o, "\tJU\t{}", label(target))?;
                } else {
                    writeln!(o, "{}\tJU\tend", store(index[resolve(target)]))?;
                }
            }
        }
    }
    // Falling off the last command restarts the program.
    if falls_in {
        writeln!(o, "{}\tJU\tend", store(0))?;
    }
    o.write_str(&trampolines)?;
    o.write_str("end:\tNOP\t0\nEND_ORGANIZATION_BLOCK\n")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn labels_are_four_letters_as_in_the_thesis() {
        assert_eq!(label(0), "aaaa");
        assert_eq!(label(2), "aaac");
        assert_eq!(label(26), "aaba");
    }

    #[test]
    fn s5time_literals() {
        assert_eq!(s5time(1500), "S5T#1S500MS");
        assert_eq!(s5time(3_723_000), "S5T#1H2M3S");
        assert_eq!(s5time(0), "S5T#0MS");
    }
}
