//! The supervisory-control engine (Göbe 2019, SynTACS) and classic Ramadge–Wonham synthesis.
//!
//! - [`classic`]: automata with marked states, synchronous product, trim, SupCon/SupConClosed,
//!   minimisation — the textbook theory, used for teaching and for cross-checking.
//! - [`gen`]: libFAUDES `.gen` import and export.
//! - [`textbook`]: the classic examples (small factory, transfer line) rebuilt from their
//!   published definitions.
//!
//! The engine does no I/O: callers pass text in and get automata, reports and diagnostics out.

pub mod classic;
pub mod gen;
pub mod model;
pub mod project;
pub mod report;
pub mod syntax;
pub mod textbook;
pub mod transfer;
