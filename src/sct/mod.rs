//! The supervisory-control engine (Göbe 2019, SynTACS) and classic Ramadge–Wonham synthesis.
//!
//! Layers, from the bottom:
//! - [`classic`]: automata with marked states in compact sorted tables, synchronous product,
//!   trim, SupCon/SupConClosed and minimisation — the textbook theory, used for teaching and
//!   for cross-checking against libFAUDES; [`gen`] reads and writes libFAUDES `.gen` files;
//!   [`textbook`] rebuilds the small factory, the transfer line and the five AGVs.
//! - [`model`]: the SynTACS formal model of chapter 5.8 — specifications with prohibitions,
//!   plant models with alphabets, conditions, synthesis automata; the specification product,
//!   plant composition, application product, synthesis steps (`sys`, `sysp`), monolithic and
//!   incremental synthesis with preemption, and supervisor minimisation.
//! - [`syntax`] and [`project`]: the `.sct` text format (see `docs/sct-language.md`): lexer,
//!   recovering parser, name resolution over modules, templates, timers, and every check that
//!   yields a located diagnostic.
//! - [`report`]: synthesis of all specifications of a project with per-supervisor reports and
//!   their JSON form; [`transfer`] generates the transfer-line benchmark family of 7.5.
//!
//! The engine does no I/O: callers pass text in and get automata, reports and diagnostics out.
//!
//! ```
//! use plcsynth::sct::{model::Config, project::load, report::synthesize_all};
//! let src = "event open : controllable;\nevent alarm : uncontrollable;\nevent spill : uncontrollable;\n\
//!            plant Tank { alphabet open, alarm, spill;\n\
//!              state A { open -> B; } state B { alarm -> C; } state C { spill -> C; } }\n\
//!            spec NoSpill { state S { forbid spill; } }";
//! let (loaded, diagnostics) = load(src);
//! assert!(diagnostics.is_empty());
//! let (reports, _) = synthesize_all(src, &loaded.unwrap(), &Config::default(), None);
//! assert_eq!(reports[0].prohibited_events, vec!["open".to_string()]);
//! ```

pub mod classic;
pub mod gen;
pub mod model;
pub mod partition;
pub mod project;
pub mod report;
pub mod syntax;
pub mod textbook;
pub mod transfer;
