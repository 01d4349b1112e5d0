//! The one code model the printers read, and its reference interpreter.
//!
//! - [`unit`](mod@unit): POUs over typed variables, expressions, `IF`, `CASE` and step lists
//!   (sequential code that keeps its position between scans), which every lowering builds;
//! - [`exec`]: the reference interpreter of a [`unit::Unit`] on a virtual clock: what a
//!   lowering means and what printed code must do.

pub mod exec;
pub mod unit;
