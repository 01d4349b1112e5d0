//! One printer per dialect family; printers read the code model only and know no engine.
//!
//! - [`st`]: Structured Text (IEC, CODESYS, TwinCAT, SCL for S7-300/400 and S7-1200/1500);
//! - [`stl`]: Siemens S7 STL (AWL);
//! - [`il`]: Instruction List (step machines only; deprecated in IEC 61131-3 ed. 3).
//!
//! Each family prints both forms of the model: `print::st` and `print::stl` the step machine
//! ([`super::model::code`]), their `unit` submodules the structured [`super::model::unit`].

pub mod il;
pub mod st;
pub(in crate::plc) mod steps;
pub mod stl;
