//! Structured Text: plain IEC 61131-3, CODESYS V3 / TwinCAT 3, and Siemens SCL for S7-300/400
//! and for S7-1200/1500 (TIA Portal external sources).
//!
//! The printer is [`mod@unit`]: it writes any [`crate::plc::model::unit::Unit`] — a step list as a
//! `CASE` over its position inside a `WHILE` loop that runs one scan per call — in each of the
//! [`Dialect`]s.

pub mod unit;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Dialect {
    Iec,
    /// CODESYS V3: globals in a `qualified_only` global variable list; variables the tool maps
    /// to I/O are left unlocated (for the device's I/O mapping).
    Codesys,
    /// TwinCAT 3: as CODESYS, variables mapped to I/O declared `AT %I*` / `AT %Q*` (linked in
    /// the System Manager).
    Twincat,
    /// SCL for S7-300/400: standard access, IEC timer `TON`.
    Scl,
    /// SCL for S7-1200/1500: optimised access, `TON_TIME`.
    Scl1500,
}
