//! Siemens S7 Statement List (AWL), as in Peter 2005, 6.7.2, for a unit of the jump-list shape
//! (`crate::plc::print::steps`): an organisation block (`OB 1`, or with [`Options::fb`] a
//! function block with its instance data block called from the OB) whose position is kept in a
//! marker byte (`MB 0` by default, [`Options::marker_byte`]) and entered through a `JL` jump
//! list over the resumption points; a wait stores its position and ends the cycle (`JCN end`)
//! while its condition is false; requests `SET` / `S` / `R` outputs. Labels are four letters
//! numbered by step (`aaaa` is step 0, `aaac` step 2), as in the thesis's listing. Other units
//! print as [`mod@unit`] lays them out.
//!
//! Beyond the thesis: the cycle ends where the step list says (after a request that a later test
//! or request of the cycle depends on, say, so that the next test reads inputs taken after the
//! request was written out); and clocks are S7 on-delay timers, one per compared threshold,
//! restarted by calling `SD` with RLO 0 (resolution 10 ms). Inputs and outputs without a binding
//! get memory bits from byte `marker_byte + 10` on (M 10.0), then each pulsed output a bit for
//! its value at the last output write: a pulse while that bit is set stores its own position and
//! ends the cycle (`AN M …`, `JCN end`), to pulse in the next. `clashes` finds user `%M`
//! bindings on those bytes and thresholds beyond the CPU's timers.

pub mod unit;

use crate::plc::model::unit::{Next, Unit};
use crate::plc::print::steps::{Action, Bit, Cond, Drive, StepBlock, Wire};
use crate::plc::target::TimeType;
use crate::plc::{siemens_address, Options};
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

fn operand(wire: &Wire<'_>, fallback: &str) -> String {
    match wire {
        Wire::Address { address, .. } => {
            let a = siemens_address(address);
            let split = a.find(|c: char| c.is_ascii_digit()).unwrap_or(a.len());
            format!("{} {}", &a[..split], &a[split..])
        }
        Wire::Symbol(text) => format!("\"{}\"", text.trim_matches('"')),
        Wire::Unbound => fallback.to_string(),
    }
}

/// A problem of the chosen [`Options`] with a block, for the lowering to locate.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Clash {
    /// The variable of the block (inputs, then outputs) whose binding clashes, if that is the
    /// cause.
    pub variable: Option<usize>,
    /// The S7 timer (timer of the block, preset in ms) beyond the CPU's timers, if that is the
    /// cause.
    pub timer: Option<(usize, u64)>,
    pub message: String,
    pub notes: Vec<String>,
}

/// The S7 timers that `unit` (of the jump-list shape) needs in the layout of 6.7.2: one per
/// (timer of its block, S5TIME preset), numbered `T 1` on in this order.
pub fn s7_timers(unit: &Unit) -> Result<Vec<(usize, u64)>, String> {
    StepBlock::of(unit).map(|block| block_timers(&block))
}

/// The STL operands of the inputs and of the outputs of `unit`'s block (`I 124.0`, `Q 125.6`,
/// `"Lamp On"`, `M 10.0` for an unbound signal).
pub fn operands(unit: &Unit, options: &Options) -> Result<(Vec<String>, Vec<String>), String> {
    let block = StepBlock::of(unit)?;
    let (inputs, outputs, _) = all_operands(&block, options);
    Ok((inputs, outputs))
}

/// [`s7_timers`] of a block.
fn block_timers(block: &StepBlock<'_>) -> Vec<(usize, u64)> {
    let mut s7_timers: Vec<(usize, u64)> = Vec::new();
    for s in &block.steps {
        for c in s.wait.iter().chain(&s.when) {
            if let Cond::Elapsed { timer, ms, strict } = *c {
                let key = (timer, preset(ms, strict));
                if !s7_timers.contains(&key) {
                    s7_timers.push(key);
                }
            }
        }
    }
    s7_timers
}

/// The S5TIME preset of a threshold: a strict one waits for the next S5TIME value.
pub fn preset(ms: u64, strict: bool) -> u64 {
    u64::try_from(TimeType::S5Time.preset_for(u128::from(ms), strict)).unwrap_or(u64::MAX)
}

/// The marker bytes a block uses with `options`: the position (one byte, or a word when there
/// are more than 255 resumption points) and the bytes of the memory bits of unbound signals.
fn marker_bytes(block: &StepBlock<'_>, options: &Options) -> (std::ops::Range<u32>, std::ops::Range<u32>) {
    let first = u32::from(options.marker_byte);
    let width = if block.resume_points().iter().filter(|&&r| r).count() > 255 { 2 } else { 1 };
    let unbound = block.wires.iter().filter(|w| **w == Wire::Unbound).count() as u32 + gaps(block).count() as u32;
    let bits = first + 10;
    (first..first + width, bits..bits + unbound.div_ceil(8))
}

/// The pulsed outputs with a memory of their last write.
fn gaps<'b>(block: &'b StepBlock<'_>) -> impl Iterator<Item = usize> + 'b {
    (0..block.last.len()).filter(|&k| block.pulsed[k] && block.last[k].is_some())
}

/// Memory bits of user bindings on the position or the unbound signals' bytes, and thresholds
/// beyond the CPU's timers.
pub(in crate::plc) fn clashes(block: &StepBlock<'_>, options: &Options) -> Vec<Clash> {
    let (position, bits) = marker_bytes(block, options);
    let mut out = Vec::new();
    for (k, (v, wire)) in block.variables().zip(&block.wires).enumerate() {
        let Wire::Address { address, .. } = wire else { continue };
        let address = siemens_address(address);
        let Some(rest) = address.strip_prefix('M') else { continue };
        let Some(byte) = rest.split('.').next().and_then(|b| b.parse::<u32>().ok()) else { continue };
        let what = if position.contains(&byte) {
            let word =
                if position.len() > 1 { format!("MW {}", position.start) } else { format!("MB {}", position.start) };
            format!("{word}, which holds the program position")
        } else if bits.contains(&byte) {
            format!(
                "MB {byte}, which holds the signals without an io binding and the pulsed outputs' last writes \
                 (from M {}.0 on)",
                bits.start
            )
        } else {
            continue;
        };
        out.push(Clash {
            variable: Some(k),
            timer: None,
            message: format!("`{}` is bound to %{address}, in {what}", v.name),
            notes: vec!["choose another marker byte with `--marker-byte N` (the default is 0)".to_string()],
        });
    }
    let timers = block_timers(block);
    if timers.len() > usize::from(options.cpu_timers) {
        let key = timers[usize::from(options.cpu_timers)];
        out.push(Clash {
            variable: None,
            timer: Some(key),
            message: format!(
                "this threshold needs S7 timer T {}, but the CPU has {} timers",
                usize::from(options.cpu_timers) + 1,
                options.cpu_timers
            ),
            notes: vec![
                format!("the program compares {} thresholds, each an S7 timer", timers.len()),
                "raise the count with `--cpu-timers N` (S7-300 CPUs have 128 to 2048, S7-400 2048)".to_string(),
            ],
        });
    }
    out
}

/// The STL operands of the inputs, of the outputs (`I 124.0`, `Q 125.6`, `"Lamp On"`), and per
/// output the memory bit of its value at the last output write: unbound signals take memory
/// bits from byte `marker_byte + 10` on, inputs first, then outputs, then the last writes.
fn all_operands(block: &StepBlock<'_>, options: &Options) -> (Vec<String>, Vec<String>, Vec<Option<String>>) {
    let (_, bit_bytes) = marker_bytes(block, options);
    let mut next_bit = bit_bytes.start as usize * 8;
    let mut bit = || {
        let b = next_bit;
        next_bit += 1;
        format!("M {}.{}", b / 8, b % 8)
    };
    let n_in = block.block.inputs.len();
    let inputs = block.wires[..n_in].iter().map(|w| operand(w, &bit())).collect();
    let outputs = block.wires[n_in..].iter().map(|w| operand(w, &bit())).collect();
    let gaps: Vec<usize> = gaps(block).collect();
    let last = (0..block.last.len()).map(|k| gaps.contains(&k).then(&mut bit)).collect();
    (inputs, outputs, last)
}

/// Prints the organisation block (or the function block, its data block and the calling OB).
pub(in crate::plc) fn print(block: &StepBlock<'_>, options: &Options, o: &mut impl Write) -> fmt::Result {
    let n = block.steps.len();
    let resume = block.resume_points();
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
    let (position_bytes, _) = marker_bytes(block, options);
    let (inputs, outputs, last) = all_operands(block, options);
    // One S7 timer per (timer, preset); a strict threshold waits for the next S5TIME value.
    let s7_timers = block_timers(block);
    let t_number = |timer: usize, ms: u64| s7_timers.iter().position(|&x| x == (timer, ms)).map_or(0, |k| k + 1);
    let position = if wide { format!("MW {}", position_bytes.start) } else { format!("MB {}", position_bytes.start) };

    for line in &block.unit.header {
        writeln!(o, "// {line}")?;
    }
    o.write_str("// Signals:\n")?;
    for (k, v) in block.block.inputs.iter().enumerate() {
        writeln!(o, "//   {:<10} {}", inputs[k], v.comment)?;
    }
    for (k, v) in block.block.outputs.iter().enumerate() {
        writeln!(o, "//   {:<10} {}", outputs[k], v.comment)?;
    }
    for (k, v) in block.block.outputs.iter().enumerate() {
        if let Some(bit) = &last[k] {
            writeln!(o, "//   {bit:<10} {} at the last output write", v.name)?;
        }
    }
    writeln!(o, "//   {position:<10} program position")?;
    for (k, &(timer, ms)) in s7_timers.iter().enumerate() {
        writeln!(o, "//   T {:<8} {} reached {} ms", k + 1, block.timers[timer].var.comment, ms)?;
    }
    match options.fb {
        Some(fb) => write!(o, "FUNCTION_BLOCK FB {fb}\nBEGIN\n")?,
        None => write!(o, "ORGANIZATION_BLOCK OB {}\nBEGIN\n", options.ob)?,
    }
    for k in 0..block.block.outputs.len() {
        if block.pulsed[k] {
            if let Some(bit) = &last[k] {
                write!(o, "\tA\t{}\n\t=\t{bit}\n", outputs[k])?;
            }
            write!(o, "\tCLR\n\t=\t{}\n", outputs[k])?;
        }
    }
    for &(timer, ms) in &s7_timers {
        write!(o, "\tSET\n\tL\t{}\n\tSD\tT {}\n", s5time(ms), t_number(timer, ms))?;
    }
    let store = |k: usize| format!("\tL\t{k}\n\tT\t{position}\n");
    if wide {
        for &p in &points {
            write!(o, "\tL\t{position}\n\tL\t{}\n\t==I\n\tJC\t{}\n", index[p], label(p))?;
        }
        o.write_str("\tJU\tud\n")?;
    } else {
        write!(o, "\tL\t{position}\n\tJL\tud\n")?;
        for &p in &points {
            writeln!(o, "\tJU\t{}", label(p))?;
        }
    }
    o.write_str("ud:\tL\t0\n")?;
    write!(o, "\tT\t{position}\n\tJU\t{}\n", label(0))?;
    let test = |c: &Cond| match *c {
        Cond::Bit { bit, negated } => {
            let operand = match bit {
                Bit::Input(k) => &inputs[k],
                Bit::Last(k) => last[k].as_ref().expect("a tested memory of the last write has a bit"),
            };
            format!("\t{}\t{operand}\n", if negated { "AN" } else { "A" })
        }
        Cond::Elapsed { timer, ms, strict } => format!("\tA\tT {}\n", t_number(timer, preset(ms, strict))),
    };
    let act = |a: &Action| -> String {
        match *a {
            Action::Drive { output, value } => {
                let (rlo, verb) = match block.drive(output, value) {
                    Drive::Assign(level) => (if level { "SET" } else { "CLR" }, "="),
                    Drive::Set => ("SET", "S"),
                    Drive::Reset => ("SET", "R"),
                };
                format!("\t{rlo}\n\t{verb}\t{}\n", outputs[output])
            }
            Action::Restart { timer } => s7_timers
                .iter()
                .filter(|(t, _)| *t == timer)
                .map(|&(t, ms)| format!("\tCLR\n\tL\t{}\n\tSD\tT {}\n", s5time(ms), t_number(t, ms)))
                .collect(),
        }
    };
    // A transfer as a jump: within the scan to a step's label, else store where the next scan
    // resumes and end this one.
    let transfer = |next: Next| match next {
        Next::Continue(k) if k < n => format!("\tJU\t{}\n", label(k)),
        Next::Continue(_) => format!("{}\tJU\tend\n", store(index[0])),
        Next::Resume(k) => format!("{}\tJU\tend\n", store(index[k.min(resume.len() - 1)])),
    };
    let jumped = block.jumped_to();
    // Text, not output: the taken branches are collected apart and printed last.
    let mut trampolines = String::new();
    // After an unconditional transfer, only labelled code can be reached.
    let mut falls_in = true;
    for (i, step) in block.steps.iter().enumerate() {
        let needs_label = resume[i] || jumped[i];
        if !falls_in && !needs_label {
            continue;
        }
        let lbl = if needs_label { format!("{}:", label(i)) } else { String::new() };
        writeln!(o, "{lbl}\tNOP\t0\t// {}", step.comment)?;
        if let Some(wait) = &step.wait {
            writeln!(o, "{}{}\tJCN\tend", store(index[i]), test(wait))?;
        }
        let actions: String = step.actions.iter().map(act).collect();
        match &step.when {
            Some(when) => {
                let taken = format!("b{}", &label(i)[1..]);
                writeln!(o, "{}\tJC\t{taken}", test(when))?;
                trampolines.push_str(&format!("{taken}:\tNOP\t0\n{actions}{}", transfer(step.next)));
                falls_in = true;
            }
            None => {
                o.write_str(&actions)?;
                // Going on at the next step falls through into it.
                falls_in = step.next == Next::Continue(i + 1);
                if !falls_in {
                    o.write_str(&transfer(step.next))?;
                }
            }
        }
    }
    // Falling off the last command restarts the program.
    if falls_in {
        writeln!(o, "{}\tJU\tend", store(0))?;
    }
    o.write_str(&trampolines)?;
    match options.fb {
        Some(fb) => write!(
            o,
            "end:\tNOP\t0\nEND_FUNCTION_BLOCK\n\nDATA_BLOCK DB {fb}\n\tFB {fb}\nBEGIN\nEND_DATA_BLOCK\n\n\
             ORGANIZATION_BLOCK OB {}\nBEGIN\n\tCALL\tFB {fb}, DB {fb}\nEND_ORGANIZATION_BLOCK\n",
            options.ob
        ),
        None => o.write_str("end:\tNOP\t0\nEND_ORGANIZATION_BLOCK\n"),
    }
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
