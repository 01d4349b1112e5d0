//! Command implementations behind `src/main.rs`; each engine has its own module.

pub mod sct;
