//! PLC back ends: one neutral code model ([`model`]), lowerings that build it from an engine's
//! controller ([`lower_timed`]: the timed engine's intermediate program), and printers over the
//! model alone for IEC 61131-3 Structured Text (plain, CODESYS, Siemens SCL), Instruction List,
//! Siemens S7 STL (AWL, Peter 2005, 6.7.2) and PLCopen TC6 XML. Printers know no engine, so every
//! engine's controllers print through the same back ends.
//!
//! All targets share the execution scheme of 6.7.2: the program position is kept in a step
//! variable; every call (one PLC scan) jumps to the stored position and runs until the program
//! waits. A scan ends when a wait condition is false, when the program jumps backwards (so no
//! loop can run within one scan), and after every request (so that outputs are written and
//! inputs are read again before the next test). Inputs are levels read once per scan; a request
//! either pulses its output for one scan or sets/resets a latched output (the `io` section).
//! Clocks read by delay conditions are IEC `TON` timers (S7 timers in STL), restarted where the
//! program resets the clock.

pub mod fragment;
pub mod il;
pub mod lower_timed;
pub mod model;
pub mod plcopen;
pub mod st;
pub mod stl;
mod target;

pub use lower_timed::{build, generate};
pub use model::Code;

pub use target::{Target, TimeType, UnknownTarget, S5TIME_MAX_MS};

use std::fmt;

/// A stable 64-bit FNV-1a hash, printed in headers to tie generated code to its source.
pub fn source_hash(source: &str) -> String {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for b in source.bytes() {
        h ^= b as u64;
        h = h.wrapping_mul(0x0100_0000_01b3);
    }
    format!("{h:016x}")
}

/// Reserved words of IEC 61131-3 and common dialects that may not name a variable.
const KEYWORDS: &[&str] = &[
    "ABS",
    "ACTION",
    "AND",
    "ARRAY",
    "AT",
    "BOOL",
    "BY",
    "BYTE",
    "CASE",
    "CONFIGURATION",
    "CONSTANT",
    "DATE",
    "DINT",
    "DO",
    "DT",
    "DWORD",
    "ELSE",
    "ELSIF",
    "END",
    "EN",
    "ENO",
    "EXIT",
    "FALSE",
    "FOR",
    "FUNCTION",
    "IF",
    "IN",
    "INT",
    "MOD",
    "NOT",
    "OF",
    "ON",
    "OR",
    "PROGRAM",
    "PT",
    "Q",
    "ET",
    "R",
    "S",
    "REAL",
    "REPEAT",
    "RETURN",
    "STEP",
    "STRING",
    "STRUCT",
    "THEN",
    "TIME",
    "TO",
    "TON",
    "TRUE",
    "TYPE",
    "UNTIL",
    "VAR",
    "WHILE",
    "WORD",
    "XOR",
    "BEGIN",
    "REGION",
    "METHOD",
    "INTERFACE",
    "CLASS",
    "TASK",
    "RESOURCE",
];

/// A valid, non-reserved IEC identifier derived from `name` (no double or trailing underscores).
pub fn identifier(name: &str) -> String {
    let mut out = String::new();
    for ch in name.chars() {
        let ch = if ch.is_ascii_alphanumeric() { ch } else { '_' };
        if ch == '_' && (out.is_empty() || out.ends_with('_')) {
            continue;
        }
        out.push(ch);
    }
    while out.ends_with('_') {
        out.pop();
    }
    if out.is_empty() || out.starts_with(|c: char| c.is_ascii_digit()) {
        out.insert_str(0, "x_");
    }
    if KEYWORDS.iter().any(|k| k.eq_ignore_ascii_case(&out)) {
        out.push_str("_sig");
    }
    out
}

/// Prints `code` as `target` writes it.
pub fn print(code: &Code, target: Target, out: &mut impl fmt::Write) -> fmt::Result {
    match target {
        Target::St => st::print(code, st::Dialect::Iec, out),
        Target::Codesys => st::print(code, st::Dialect::Codesys, out),
        Target::Scl => st::print(code, st::Dialect::Scl, out),
        Target::Il => il::print(code, out),
        Target::Stl => stl::print(code, out),
        Target::Plcopen => plcopen::print(code, out),
    }
}

/// [`print`] into a string.
pub fn render(code: &Code, target: Target) -> String {
    let mut text = String::new();
    print(code, target, &mut text).expect("writing to a String cannot fail");
    text
}

/// `T#…` literal for a duration.
pub fn time_literal(ms: u64) -> String {
    format!("T#{ms}MS")
}

/// An address in IEC notation (`IX0.0`, `QX1.3`, `MW10`; without `%`): a bit address gets the
/// `X` size prefix that IEC and CODESYS require.
pub fn iec_address(text: &str) -> String {
    let mut chars = text.chars();
    let area = chars.next().unwrap_or('I');
    let rest: String = chars.collect();
    let has_size = rest.starts_with(['X', 'B', 'W', 'D', 'L']);
    if !has_size && rest.contains('.') {
        format!("{area}X{rest}")
    } else {
        format!("{area}{rest}")
    }
}

/// An address in Siemens notation (`I0.0`, `Q1.3`, `MW10`): the bit size prefix `X` is dropped.
pub fn siemens_address(text: &str) -> String {
    let mut chars = text.chars();
    let area = chars.next().unwrap_or('I');
    let rest: String = chars.collect();
    match rest.strip_prefix('X') {
        Some(bit) => format!("{area}{bit}"),
        None => format!("{area}{rest}"),
    }
}

/// The preset of a timer: above its largest threshold, so every comparison can still become true.
pub fn preset_literal(code: &Code, timer: usize) -> String {
    time_literal(code.timers[timer].preset_ms)
}

#[cfg(test)]
mod tests {
    /// The model and the printers name no engine, so that every engine's controllers can print
    /// through them; only lowerings (`lower_*`) know one.
    #[test]
    fn printers_and_model_know_no_engine() {
        let sources = [
            ("model.rs", include_str!("model.rs")),
            ("target.rs", include_str!("target.rs")),
            ("st.rs", include_str!("st.rs")),
            ("il.rs", include_str!("il.rs")),
            ("stl.rs", include_str!("stl.rs")),
            ("plcopen.rs", include_str!("plcopen.rs")),
        ];
        for (file, text) in sources {
            for engine in ["crate::timed", "crate::program", "crate::sct", "lower_timed::"] {
                assert!(!text.contains(engine), "src/plc/{file} mentions {engine}");
            }
        }
    }
}
