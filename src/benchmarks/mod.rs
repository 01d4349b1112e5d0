//! Benchmark and teaching models rebuilt from their published definitions. Not part of any
//! engine: they feed the benchmarks (`plcsynth bench`, `benches/`), the tests and the examples.
//!
//! - [`textbook`]: the small factory, the transfer line and the five AGVs as classic automata
//!   (Wonham's course notes), for SupCon against libFAUDES;
//! - [`transfer`]: the transfer-line family of Göbe 2019, 7.5, as `.sct` text.

pub mod textbook;
pub mod transfer;
