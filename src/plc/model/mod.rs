//! The code model the printers read, and its reference interpreter.
//!
//! - [`code`]: the step machine of the timed engine's controllers (a function block of BOOL
//!   signals, timers and program positions), printed by [`crate::plc::print`](mod@crate::plc::print);
//! - [`unit`](mod@unit): the structured model (POUs over typed variables, expressions, `IF`, `CASE`)
//!   that the supervisory-control and LTL lowerings build;
//! - [`exec`]: the reference interpreter of a [`unit::Unit`] on a virtual clock: what a
//!   lowering means and what printed code must do.

pub mod code;
pub mod exec;
pub mod unit;
