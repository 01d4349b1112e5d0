//! PLC back ends, in four layers that show in the folders:
//!
//! - [`model`]: the one code model — the unit of POUs ([`model::unit`]: functions, function
//!   blocks and a program over typed variables, with expressions, `IF`, `CASE` and step lists) —
//!   and its reference interpreter ([`model::exec`]);
//! - [`lower`]: one lowering per engine, the only place that knows one: [`lower::timed`] (the
//!   timed engine's intermediate program, through the step machine [`lower::timed::machine`]
//!   to a unit, with the real-time checker [`lower::timed::realtime`]), [`lower::sct`] (the
//!   supervisors' runtime framework, with the playground's cycle simulator
//!   [`lower::sct::framework_sim`]) and [`lower::ltl`] (an LTL controller's state machine);
//! - [`print`](mod@print): one printer per dialect family over the model alone: Structured Text (plain,
//!   CODESYS, TwinCAT, Siemens SCL), Siemens S7 STL (AWL) and Instruction List;
//! - [`files`]: what a PLC tool imports around the printed code: TwinCAT files, PLCopen TC6 XML,
//!   I/O tables.
//!
//! [`fragment`] reads the Structured Text fragments written into `.sct` specifications;
//! [`Target`] lists the targets, and [`render_unit_files`] picks the printer and writer of one
//! ([`render_files`] for a timed controller's step machine).
//!
//! Step lists on every target share the execution scheme of Peter 2005, 6.7.2: the program
//! position is kept in a step variable; every call (one PLC scan) enters at the stored position
//! and runs until a step ends the scan. For a timed controller a scan ends when a wait condition
//! is false, when the program jumps backwards (so no loop can run within one scan; a jump back
//! from which the scan cannot jump back again goes on, [`lower::timed::machine::Step::back_in_scan`]),
//! and after a request unless nothing later in the scan depends on it having taken effect
//! ([`lower::timed::machine::chain_requests`]: outputs are written and inputs read again before
//! a test of its feedback or a request that might not commute with it). Inputs are levels read
//! once per scan; a request either pulses its output for one scan or sets/resets a latched
//! output (the `io` section). Clocks read by delay conditions are IEC `TON` timers (S7 timers
//! in STL), restarted where the program resets the clock.

pub mod files;
pub mod fragment;
pub mod lower;
pub mod model;
pub mod print;
mod target;

pub use files::iotable::{
    codesys_mapping_csv, io_table, io_table_csv, signal_rows, signal_table_csv, tag_table_sdf, IoRow, SignalRow,
};
pub use lower::timed::Code;
pub use lower::timed::{build, generate};

use files::plcopen::unit as unit_plcopen;
use model::unit;
use print::st::unit as unit_st;
use print::stl::unit as unit_stl;
use print::{il, st, stl};

pub use target::{Target, TimeType, UnknownTarget, S5TIME_MAX_MS};

use std::fmt;

/// Choices of the printers beyond the code itself. The library reads no clock and no
/// environment: the caller passes the creation time (the CLI from `SOURCE_DATE_EPOCH` or the
/// system clock, the page from `Date.now()`).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Options {
    /// STL: the organisation block that runs the controller (`OB 1`).
    pub ob: u16,
    /// STL: when set, the controller is `FB n` with instance `DB n`, called from the OB;
    /// otherwise the OB holds the controller itself, as in the thesis.
    pub fb: Option<u16>,
    /// STL: the marker byte holding the program position (`MB 0`; a word `MW n` when the
    /// program has more than 255 resumption points). Unbound signals get memory bits from byte
    /// `marker_byte + 10` on.
    pub marker_byte: u16,
    /// STL: the number of S7 timers of the CPU (`T 1` … `T n`); more thresholds are refused.
    pub cpu_timers: u16,
    /// PLCopen: the creation time, seconds since 1970-01-01 UTC.
    pub created_unix: u64,
}

impl Default for Options {
    fn default() -> Options {
        Options { ob: 1, fb: None, marker_byte: 0, cpu_timers: 256, created_unix: 0 }
    }
}

/// One generated file: its name (with extension) and its text.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct OutputFile {
    pub name: String,
    pub text: String,
}

/// The files of `code` for `target`: one for most targets; TwinCAT writes a `.TcPOU` per block
/// and program and a `.TcGVL` for the I/O. The first file holds the function block. Every
/// target prints the code's unit ([`lower::timed::structured`]).
pub fn render_files(code: &Code, target: Target, options: &Options) -> Vec<OutputFile> {
    render_unit_files(&lower::timed::structured(code).unit, target, options)
        .expect("every target prints a step machine's unit")
}

/// The files of a `unit` for `target`: one for most targets; TwinCAT writes a `.TcPOU` per POU
/// and a `.TcGVL` for the globals. A unit of the jump-list shape (one block running a step list,
/// wired by its program, `print::steps`) prints in IL and STL in the layout of Peter 2005,
/// 6.7.2; other units print in STL as [`print::stl::unit`] lays them out (what STL cannot hold is
/// refused with its `check`'s reasons) and are refused in Instruction List: it is deprecated in
/// IEC 61131-3 (3rd edition) and no SCL or ST tool needs it for structured code (the SyRF
/// framework of `lower::sct`, the LTL controllers of `lower::ltl`).
pub fn render_unit_files(unit: &unit::Unit, target: Target, options: &Options) -> Result<Vec<OutputFile>, String> {
    let single = |text: String| Ok(vec![OutputFile { name: format!("{}.{}", unit.name, target.extension()), text }]);
    let mut text = String::new();
    let dialect = match target {
        Target::St => st::Dialect::Iec,
        Target::Codesys => st::Dialect::Codesys,
        Target::Scl => st::Dialect::Scl,
        Target::Scl1500 => st::Dialect::Scl1500,
        Target::Twincat => return Ok(unit_st::files(unit)),
        Target::Plcopen | Target::Abb => {
            let flavour = if target == Target::Abb { unit_plcopen::Flavour::Abb } else { unit_plcopen::Flavour::Tc6 };
            unit_plcopen::print_flavour(unit, flavour, options, &mut text).expect("writing to a String cannot fail");
            return single(text);
        }
        Target::Stl => {
            if let Ok(block) = print::steps::StepBlock::of(unit) {
                stl::print(&block, options, &mut text).expect("writing to a String cannot fail");
                return single(text);
            }
            let stl_options = unit_stl_options(options);
            let problems = unit_stl::check(unit, &stl_options);
            if !problems.is_empty() {
                return Err(format!("the STL form cannot hold this code: {}", problems.join("; ")));
            }
            return single(unit_stl::render(unit, &stl_options));
        }
        Target::Il => {
            return match print::steps::StepBlock::of(unit) {
                Ok(block) => {
                    il::print(&block, &mut text).expect("writing to a String cannot fail");
                    single(text)
                }
                Err(_) => Err("structured code (function blocks and functions) is not generated as Instruction List (deprecated in IEC 61131-3 ed. 3); use st, codesys, scl or stl".into()),
            }
        }
    };
    unit_st::print(unit, dialect, &mut text).expect("writing to a String cannot fail");
    single(text)
}

/// The STL block numbers of a unit: the program is called from `options.ob`; the existing
/// controller is `FB n` with instance `DB n` for `options.fb` (100 when not given).
pub fn unit_stl_options(options: &Options) -> unit_stl::StlUnitOptions {
    let controller = options.fb.unwrap_or(100);
    unit_stl::StlUnitOptions {
        ob: options.ob,
        controller_fb: controller,
        controller_db: controller,
        ..Default::default()
    }
}

/// Names in one scope, compared case-insensitively as IEC 61131-3 does, where no name may be a
/// keyword or type of IEC 61131-3 or of the dialects printed. [`Namespace::unique`] derives a
/// fresh identifier, adding `_2`, `_3`, … on a clash.
#[derive(Clone, Debug, Default)]
pub struct Namespace {
    taken: std::collections::HashSet<String>,
}

impl Namespace {
    pub fn new() -> Namespace {
        Namespace::default()
    }

    /// Marks `name` as used.
    pub fn reserve(&mut self, name: &str) {
        self.taken.insert(name.to_ascii_uppercase());
    }

    /// Whether `name` is used or reserved (case-insensitively).
    pub fn contains(&self, name: &str) -> bool {
        let upper = name.to_ascii_uppercase();
        self.taken.contains(&upper) || is_keyword(&upper)
    }

    /// A valid identifier derived from `base` (see [`identifier`]) that is not yet used, now
    /// reserved.
    pub fn unique(&mut self, base: &str) -> String {
        let base = identifier(base);
        let mut name = base.clone();
        let mut n = 2;
        while self.contains(&name) {
            name = format!("{base}_{n}");
            n += 1;
        }
        self.reserve(&name);
        name
    }
}

/// A stable 64-bit FNV-1a hash, printed in headers to tie generated code to its source.
pub fn source_hash(source: &str) -> String {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for b in source.bytes() {
        h ^= b as u64;
        h = h.wrapping_mul(0x0100_0000_01b3);
    }
    format!("{h:016x}")
}

/// Reserved words and standard types of IEC 61131-3, IL operators, and the words of the dialects
/// printed (CODESYS, TwinCAT, SCL) that may not name a variable.
const KEYWORDS: &[&str] = &[
    "ADD",
    "ANY",
    "BOOL",
    "CAL",
    "CALC",
    "CALCN",
    "CHAR",
    "CONTINUE",
    "CTD",
    "CTU",
    "CTUD",
    "DATA_BLOCK",
    "DATE_AND_TIME",
    "DIV",
    "END_CASE",
    "END_FOR",
    "END_FUNCTION",
    "END_FUNCTION_BLOCK",
    "END_IF",
    "END_PROGRAM",
    "END_REPEAT",
    "END_STRUCT",
    "END_TYPE",
    "END_VAR",
    "END_WHILE",
    "EQ",
    "EXTENDS",
    "F_TRIG",
    "FUNCTION_BLOCK",
    "GE",
    "GOTO",
    "GT",
    "IMPLEMENTS",
    "JMP",
    "JMPC",
    "JMPCN",
    "LD",
    "LDN",
    "LE",
    "LINT",
    "LREAL",
    "LT",
    "LTIME",
    "LWORD",
    "MUL",
    "NE",
    "NULL",
    "ORGANIZATION_BLOCK",
    "POINTER",
    "PROPERTY",
    "R_TRIG",
    "REFERENCE",
    "RET",
    "RETAIN",
    "RS",
    "SINT",
    "SR",
    "ST",
    "STN",
    "SUB",
    "SUPER",
    "THIS",
    "TOD",
    "TOF",
    "TON_TIME",
    "TP",
    "UDINT",
    "UINT",
    "ULINT",
    "USINT",
    "VAR_EXTERNAL",
    "VAR_GLOBAL",
    "VAR_IN_OUT",
    "VAR_INPUT",
    "VAR_OUTPUT",
    "VAR_TEMP",
    "VERSION",
    "WCHAR",
    "WSTRING",
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
    if is_keyword(&out) {
        out.push_str("_sig");
    }
    out
}

fn is_keyword(name: &str) -> bool {
    KEYWORDS.iter().any(|k| k.eq_ignore_ascii_case(name))
}

/// Whether `text` is an identifier or a dotted path of identifiers (`GVL.lamp`) as written.
pub fn is_identifier_path(text: &str) -> bool {
    text.split('.').all(|part| identifier(part) == part)
}

/// Prints `code` as `target` writes it. A multi-file target prints each file after a line
/// `==> NAME <==` (as `head` does); [`render_files`] gives them apart.
pub fn print(code: &Code, target: Target, options: &Options, out: &mut impl fmt::Write) -> fmt::Result {
    out.write_str(&render(code, target, options))
}

/// [`print()`] into a string.
pub fn render(code: &Code, target: Target, options: &Options) -> String {
    let files = render_files(code, target, options);
    if target == Target::Twincat {
        files.iter().map(|f| format!("==> {} <==\n{}", f.name, f.text)).collect()
    } else {
        files.into_iter().map(|f| f.text).collect()
    }
}

/// A stable name-based GUID (`{8-4-4-4-12}` hex digits, version 4 and variant bits set) for an
/// object `name` of code whose header is `header`: the same input gives the same files.
pub fn stable_guid(header: &[String], name: &str) -> String {
    let a = source_hash(&format!("{}\u{1}{name}", header.join("\n")));
    let b = source_hash(&format!("{name}\u{1}{}", header.join("\n")));
    format!("{{{}-{}-4{}-8{}-{}}}", &a[0..8], &a[8..12], &a[13..16], &b[1..4], &b[4..16])
}

/// `YYYY-MM-DDTHH:MM:SS` (UTC) of a time in seconds since 1970-01-01.
pub fn iso_datetime(unix: u64) -> String {
    let days = (unix / 86_400) as i64;
    let secs = unix % 86_400;
    // Civil date from days since the epoch (H. Hinnant's algorithm).
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let day = doy - (153 * mp + 2) / 5 + 1;
    let month = if mp < 10 { mp + 3 } else { mp - 9 };
    let year = yoe + era * 400 + i64::from(month <= 2);
    format!("{year:04}-{month:02}-{day:02}T{:02}:{:02}:{:02}", secs / 3600, secs / 60 % 60, secs % 60)
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_never_clash_case_insensitively_with_keywords_or_each_other() {
        let mut names = Namespace::new();
        names.reserve("lamp");
        assert_eq!(names.unique("LAMP"), "LAMP_2");
        assert_eq!(names.unique("lamp"), "lamp_3");
        assert_eq!(names.unique("ton"), "ton_sig");
        assert_eq!(names.unique("Ton"), "Ton_sig_2");
        assert_eq!(names.unique("end_if"), "end_if_sig");
        assert_eq!(names.unique("Lamp On"), "Lamp_On");
        assert_eq!(names.unique("7up"), "x_7up");
        assert!(is_identifier_path("GVL.lamp") && !is_identifier_path("Lamp On") && !is_identifier_path("GVL..x"));
    }

    #[test]
    fn dates_and_guids() {
        assert_eq!(iso_datetime(0), "1970-01-01T00:00:00");
        assert_eq!(iso_datetime(951_782_400), "2000-02-29T00:00:00");
        assert_eq!(iso_datetime(1_700_000_000), "2023-11-14T22:13:20");
        let header = vec!["x".to_string()];
        let guid = stable_guid(&header, "lamp");
        assert_eq!(guid.len(), 38);
        assert_eq!(guid, stable_guid(&header, "lamp"));
        assert_ne!(guid, stable_guid(&header, "lamp_main"));
        assert_eq!(&guid[15..16], "4");
    }
}
