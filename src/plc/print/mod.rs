//! One printer per dialect family; printers read the code model only and know no engine.
//!
//! - [`st`]: Structured Text (IEC, CODESYS, TwinCAT, SCL for S7-300/400 and S7-1200/1500);
//! - [`stl`]: Siemens S7 STL (AWL);
//! - [`il`]: Instruction List (units of the jump-list shape only; deprecated in IEC 61131-3
//!   ed. 3).
//!
//! All print the one model, [`super::model::unit`]. `steps` reads the jump-list shape (one block
//! running a step list, wired by its program), which IL and the STL layout of Peter 2005, 6.7.2
//! (`print::stl`) print; `print::stl::unit` lays out any other unit; `print::st::unit` prints
//! every unit in the Structured Text dialects.

pub mod il;
pub mod st;
pub(in crate::plc) mod steps;
pub mod stl;
