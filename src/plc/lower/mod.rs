//! One lowering per engine: the only part of `plc` that knows an engine. Each turns an engine's
//! controller into the code model ([`super::model`]); nothing else in `plc` names an engine.
//!
//! - [`timed`]: the timed engine's controller program to a step machine, and
//!   [`timed::realtime`], the checker that scans it against the game's automata in real time;
//! - [`sct`]: the supervisors' runtime framework (Göbe 2019, 6.3) to a unit, and
//!   [`sct::framework_sim`], the playground's cycle simulator over it;
//! - [`ltl`]: an LTL controller (Mealy machine) to a function block.

pub mod ltl;
pub mod sct;
pub mod timed;
