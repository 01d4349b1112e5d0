//! The I/O table of a controller: one row per interface variable with its address (or project
//! symbol), type, symbol, direction and meaning; as CSV for any tool, as a Siemens symbol
//! table (SDF, the "System Data Format" of STEP 7 that TIA Portal's PLC tag tables import too),
//! and as a CODESYS I/O mapping list ([`codesys_mapping_csv`]).

use crate::plc::model::unit::{Location, SignalKind, Type, Unit};
use crate::plc::print::steps::{StepBlock, Wire};
use crate::plc::{iec_address, siemens_address};

/// One row of the I/O table.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct IoRow {
    /// `%IX124.0`, a project symbol (`GVL.arm_up`, `"Lamp On"`), or empty when unbound.
    pub address: String,
    /// The IEC type (always `BOOL`: every signal is one bit).
    pub data_type: &'static str,
    /// The variable's name in the generated code.
    pub symbol: String,
    pub direction: SignalKind,
    /// The messages of the specification it stands for.
    pub meaning: String,
}

/// The rows of a step-list unit (a lowered timed controller, `StepBlock`): one per variable
/// of its block, inputs first, then outputs, in the order of the block's interface; none for a
/// unit of another shape (whose signals [`signal_rows`] lists).
pub fn io_table(unit: &Unit) -> Vec<IoRow> {
    let Ok(block) = StepBlock::of(unit) else { return Vec::new() };
    let n_in = block.block.inputs.len();
    block
        .variables()
        .zip(&block.wires)
        .enumerate()
        .map(|(k, (v, wire))| IoRow {
            address: match *wire {
                Wire::Address { address, .. } => format!("%{}", iec_address(address)),
                Wire::Symbol(symbol) => symbol.to_string(),
                Wire::Unbound => String::new(),
            },
            data_type: "BOOL",
            symbol: v.name.clone(),
            direction: if k < n_in { SignalKind::Input } else { SignalKind::Output },
            meaning: v.comment.clone(),
        })
        .collect()
}

/// A CSV field (RFC 4180): quoted when it holds a comma, a quote or a line break.
fn csv_field(text: &str) -> String {
    if text.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", text.replace('"', "\"\""))
    } else {
        text.to_string()
    }
}

/// The I/O table as CSV (RFC 4180, comma-separated, a header row, CRLF line ends).
pub fn io_table_csv(unit: &Unit) -> String {
    let mut out = String::from("address,type,symbol,direction,meaning\r\n");
    for row in io_table(unit) {
        let fields = [row.address.as_str(), row.data_type, &row.symbol, row.direction.name(), &row.meaning];
        let line: Vec<String> = fields.iter().map(|f| csv_field(f)).collect();
        out.push_str(&line.join(","));
        out.push_str("\r\n");
    }
    out
}

/// The globals at direct addresses as a Siemens symbol table in SDF (the PLC tags the SCL code
/// names, see [`crate::plc::model::unit::Location::Address`]): one line per tag,
/// `"symbol","address","type","comment"` (STEP 7 "Programming with STEP 7", 8.6: strings in
/// quotation marks separated by commas; the address in Siemens notation `I 124.0`). STEP 7
/// limits symbols to 24 and comments to 80 characters; comments are cut to 80. Signals bound to
/// project symbols or unbound are not tags of this table.
pub fn tag_table_sdf(unit: &Unit) -> String {
    let mut out = String::new();
    for v in &unit.globals {
        if let Some(text) = v.address() {
            let address = siemens_address(text);
            let split = address.find(|c: char| c.is_ascii_digit()).unwrap_or(address.len());
            let comment: String = v.comment.replace('"', "'").chars().take(80).collect();
            out.push_str(&format!(
                "\"{}\",\"{} {}\",\"BOOL\",\"{}\"\r\n",
                v.name,
                &address[..split],
                &address[split..],
                comment
            ));
        }
    }
    out
}

/// One row of a structured unit's signal table.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SignalRow {
    /// The address in the STL form, IEC notation (`%IX0.1`); for a constant, its value.
    pub address: String,
    pub data_type: &'static str,
    pub symbol: String,
    /// `input`, `output`, `memory` or `constant`.
    pub direction: &'static str,
    /// The events whose triggers or actions use it.
    pub events: String,
}

/// The signal table of a structured unit: the address each signal of the user's project has in
/// the STL form, its type, its symbol, its direction and the events whose triggers or actions
/// use it; then the event constants (`EV_…`, with their values), which a controller passes to
/// the framework and an HMI reads back.
pub fn signal_rows(unit: &Unit) -> Vec<SignalRow> {
    let mut rows = Vec::new();
    for s in &unit.signals {
        let data_type = type_name(&s.ty);
        let direction = match s.kind {
            SignalKind::Input => "input",
            SignalKind::Output => "output",
            SignalKind::Memory => "memory",
        };
        rows.push(SignalRow {
            address: format!("%{}", crate::plc::iec_address(&s.address)),
            data_type,
            symbol: s.symbol.clone(),
            direction,
            events: s.comment.clone(),
        });
    }
    for c in &unit.constants {
        let value = match c.init {
            Some(crate::plc::model::unit::Expr::Int(v)) => v.to_string(),
            _ => String::new(),
        };
        rows.push(SignalRow {
            address: value,
            data_type: "INT",
            symbol: c.name.clone(),
            direction: "constant",
            events: c.comment.clone(),
        });
    }
    rows
}

/// [`signal_rows`] as CSV (RFC 4180, CRLF).
pub fn signal_table_csv(unit: &Unit) -> String {
    let mut out = String::from("address,type,symbol,direction,events\r\n");
    for r in signal_rows(unit) {
        let fields = [&r.address, r.data_type, &r.symbol, r.direction, &r.events];
        let line: Vec<String> = fields.iter().map(|f| csv_field(f)).collect();
        out.push_str(&line.join(","));
        out.push_str("\r\n");
    }
    out
}

/// The IEC name of a signal's type.
fn type_name(ty: &Type) -> &'static str {
    match ty {
        Type::Int => "INT",
        Type::Dint => "DINT",
        Type::Real => "REAL",
        Type::Time => "TIME",
        _ => "BOOL",
    }
}

/// A field of a semicolon-separated file: quoted when it holds a semicolon, a quote or a line
/// break.
fn semicolon_field(text: &str) -> String {
    if text.contains([';', '"', '\n', '\r']) {
        format!("\"{}\"", text.replace('"', "\"\""))
    } else {
        text.to_string()
    }
}

/// The I/O of a unit as the CODESYS device editor's I/O mapping lists it: one row per variable
/// wired to the process, semicolon-separated (the separator CODESYS's "Export mappings to CSV"
/// writes under a semicolon list separator, and the one ABB's copy of that help names), with a
/// header row `Variable;Address;Type;Direction;Description`:
///
/// - `Variable`: what the mapping links to the channel, as CODESYS names it in the project: a
///   global of the unit's list qualified by the list's name (`GVL_IO.press`: the CODESYS target
///   declares the list `qualified_only`), or a signal's symbol in the user's project; empty for
///   a signal the code reads at its direct address (nothing to map);
/// - `Address`: the channel's IEC address (`%IX124.0`), empty for a global the tool maps
///   (`Location::Mapped`): the row then names the variable that the channel of the user's
///   choice is to be mapped to;
/// - `Type`, `Direction` (`input`, `output`, `variable`), `Description` (the messages or events
///   behind it).
///
/// CODESYS's "Import mappings from CSV" matches rows by device and channel name, which only the
/// user's device tree knows; docs/plc-code.md says how this list fills an exported mapping.
pub fn codesys_mapping_csv(unit: &Unit) -> String {
    let mut rows: Vec<[String; 5]> = Vec::new();
    for v in &unit.globals {
        let (address, kind) = match &v.at {
            Some(Location::Address(a)) => {
                let kind = match a.chars().next() {
                    Some('I') => SignalKind::Input,
                    Some('Q') => SignalKind::Output,
                    _ => SignalKind::Memory,
                };
                (format!("%{}", iec_address(a)), kind)
            }
            Some(Location::Mapped(kind)) => (String::new(), *kind),
            None => continue,
        };
        rows.push([
            format!("{}.{}", unit.gvl, v.name),
            address,
            type_name(&v.ty).to_string(),
            kind.name().to_string(),
            v.comment.clone(),
        ]);
    }
    for sig in &unit.signals {
        let variable = if sig.is_address() { String::new() } else { sig.symbol.clone() };
        rows.push([
            variable,
            format!("%{}", iec_address(&sig.address)),
            type_name(&sig.ty).to_string(),
            sig.kind.name().to_string(),
            sig.comment.clone(),
        ]);
    }
    let mut out = String::from("Variable;Address;Type;Direction;Description\r\n");
    for row in rows {
        let line: Vec<String> = row.iter().map(|f| semicolon_field(f)).collect();
        out.push_str(&line.join(";"));
        out.push_str("\r\n");
    }
    out
}
