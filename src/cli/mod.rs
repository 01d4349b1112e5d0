//! Command implementations of the CLI; `main.rs` only parses arguments and dispatches here.

pub mod bench;
pub mod timed;
