//! plcsynth: correct-by-construction PLC programs synthesised from specifications.
//!
//! The engines do no I/O and know nothing of the browser:
//! - [`zone`]: difference bound matrices (clock zones);
//! - [`timed`]: the timed-game engine of Peter (2005): specification language, timed game
//!   automata, precomputation and the on-the-fly safety-game solver;
//! - [`sct`]: the supervisory-control engine of Göbe (2019) and classic Ramadge–Wonham
//!   synthesis.
//!
//! [`benchmarks`] rebuilds published models for benchmarks and tests.
//!
//! [`diag`] holds the located diagnostics every front end reports; [`dot`] the DOT documents
//! of the drawings the engines export; `graph` lends the engines' tables to petgraph's searches;
//! `syntax` holds the token cursor of the recursive-descent parsers; `id` the typed table ids.

pub mod benchmarks;
pub mod diag;
pub mod dot;
pub(crate) mod graph;
pub(crate) mod id;
pub mod ltl;
pub mod plc;
pub mod rng;
pub mod sct;
pub mod search;
pub(crate) mod sort;
pub(crate) mod syntax;
pub mod timed;
// On the host only to be linted (feature `wasm-lint`, Cargo.toml).
#[cfg(any(target_arch = "wasm32", feature = "wasm-lint"))]
pub mod wasm;
pub mod zone;
