//! The supervisory-control engine (Göbe 2019, SynTACS) and classic Ramadge–Wonham synthesis.
//!
//! The front door is three calls: [`compile`] a `.sct` text into a checked project (with every
//! diagnostic located), [`synthesize`] its specifications into supervisors with a [`Config`],
//! and read the [`Synthesis`]: its verdict (or why the run stopped) and the
//! [`SupervisorReport`]s (or their JSON form). Inside, from the bottom:
//! - [`classic`]: automata with marked states in compact sorted tables, synchronous product,
//!   trim, SupCon/SupConClosed and minimisation — the textbook theory, used for teaching and
//!   for cross-checking against libFAUDES (and for `plcsynth supcon` and the benchmarks);
//!   [`classic::gen`] reads and writes libFAUDES `.gen` files, [`classic::wmod`] Supremica's
//!   `.wmod` modules.
//! - [`model`]: the SynTACS formal model of chapter 5.8 — specifications with prohibitions,
//!   plant models with alphabets, conditions, synthesis automata; the specification product,
//!   plant composition, application product, synthesis steps (`sys`, `sysp`), monolithic and
//!   incremental synthesis with preemption, and supervisor minimisation. Public, because the
//!   model is what the thesis defines, what `plc::lower::sct` reads and what the tests check
//!   against its definitions.
//! - `lexer`, `ast`, `parser` and `check` (private): the `.sct` text format (see
//!   `docs/sct-language.md`): logos lexer, recovering parser, name resolution over modules,
//!   templates, timers, and every check that yields a located diagnostic.
//! - `report` (private, re-exported here): synthesis of all specifications of a project with
//!   per-supervisor reports.
//! - [`interchange`]: `.sct` projects to and from classic components (`.gen`, `.wmod`), for
//!   `plcsynth import`/`export` and the page's import.
//! - [`stepper`]: the closed loop of plants and supervisors stepped event by event (which
//!   events are enabled, disabled by whom, enforced), for the playground.
//! - [`export`]: drawings of plant models, specifications and supervisors (DOT), for the
//!   playground.
//! - `runtime` (private, re-exported here): the reference executor of the runtime framework —
//!   supervisors stepped cycle by cycle ([`Runtime`]): accepted, denied, unexpected and
//!   enforced events, timers.
//!
//! The benchmark and teaching models built from published definitions (the textbook problems,
//! the transfer-line family of 7.5) are not part of the engine: see [`crate::benchmarks`].
//! The engine does no I/O: callers pass text in and get automata, reports and diagnostics out.
//!
//! ```
//! use plcsynth::sct::{compile, synthesize, Config, Outcome, Verdict};
//! let src = "event open : controllable;\nevent alarm : uncontrollable;\nevent spill : uncontrollable;\n\
//!            plant Tank { alphabet open, alarm, spill;\n\
//!              state A { open -> B; } state B { alarm -> C; } state C { spill -> C; } }\n\
//!            spec NoSpill { state S { forbid spill; } }";
//! let (loaded, warnings) = compile(src).expect("a valid project");
//! assert!(warnings.is_empty());
//! let synthesis = synthesize(src, &loaded, &Config::default(), None, &mut |_| true);
//! assert_eq!(synthesis.verdict(), Some(Verdict::Realizable));
//! assert_eq!(synthesis.reports[0].prohibited_events, vec!["open".to_string()]);
//! ```

mod ast;
mod check;
pub mod classic;
pub mod export;
pub mod interchange;
mod lexer;
pub mod model;
mod parser;
mod partition;
mod report;
mod runtime;
pub mod stepper;

// The checked project: `compile` and what the lowering reads of it.
pub use ast::EdgeKind;
pub use check::{compile, compile_within, EventFragments, EventMeta, EventSpans, Loaded, TimerInfo, Trigger};
// Synthesis of every specification, and the reports.
pub use report::{synthesize, synthesize_within, JsonState, JsonTransition, SupervisorReport, Synthesis, Verdict};
// The engine contract (see `crate::search`): `compile` → `synthesize` with a `Config` → a
// `Synthesis`, whose `Outcome` is a `Verdict` or a `Stop`; progress reports a `Progress`.
pub use crate::search::{Outcome, Stop};
pub use model::{Config, Progress};
// The reference executor of the runtime framework.
pub use runtime::{CycleInput, CycleReport, EventOutcome, Runtime, RuntimeError, Step};
