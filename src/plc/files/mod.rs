//! File writers around the printers: what a PLC tool imports.
//!
//! - [`twincat`]: TwinCAT 3 `.TcPOU` / `.TcGVL` files;
//! - [`plcopen`]: PLCopen TC6 XML projects (program, configuration, resource);
//! - [`iotable`]: the I/O tables (CSV, Siemens SDF tag tables, signal lists).

pub mod iotable;
pub mod plcopen;
pub mod twincat;
