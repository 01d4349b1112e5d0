//! Every native integration test in one binary, a module per file of `tests/`: one link of
//! the library and its dependencies instead of one per file (`make test` builds on two cores).
//! Run one file's tests with a filter on its module: `cargo nextest run --test native plc_realtime::`.
//! The helpers the files share are declared here once (`use crate::common;` in a file).

mod common;
#[path = "../fuzz/src/lib.rs"]
mod harness;
#[path = "common/random_spec.rs"]
mod random_spec;
#[path = "common/reference.rs"]
mod reference;

#[path = "architecture.rs"]
mod architecture;
#[path = "cli.rs"]
mod cli;
#[path = "engine_contract.rs"]
mod engine_contract;
#[path = "fragment.rs"]
mod fragment;
#[path = "fuzz_regressions.rs"]
mod fuzz_regressions;
#[path = "ltl_checkers.rs"]
mod ltl_checkers;
#[path = "ltl_circuit.rs"]
mod ltl_circuit;
#[path = "ltl_cli.rs"]
mod ltl_cli;
#[path = "ltl_compare_g4ltl.rs"]
mod ltl_compare_g4ltl;
#[path = "ltl_examples.rs"]
mod ltl_examples;
#[path = "ltl_g4ltl.rs"]
mod ltl_g4ltl;
#[path = "ltl_plc.rs"]
mod ltl_plc;
#[path = "ltl_random.rs"]
mod ltl_random;
#[path = "ltl_refine.rs"]
mod ltl_refine;
#[path = "ltl_suggest.rs"]
mod ltl_suggest;
#[path = "ltl_symbolic.rs"]
mod ltl_symbolic;
#[path = "ltl_theory.rs"]
mod ltl_theory;
#[path = "ltl_timed_loop.rs"]
mod ltl_timed_loop;
#[path = "ltl_tlsf.rs"]
mod ltl_tlsf;
#[path = "plc.rs"]
mod plc;
#[path = "plc_expressions.rs"]
mod plc_expressions;
#[path = "plc_real.rs"]
mod plc_real;
#[path = "plc_realtime.rs"]
mod plc_realtime;
#[path = "plc_unit_stl.rs"]
mod plc_unit_stl;
#[path = "program.rs"]
mod program;
#[path = "random_specs.rs"]
mod random_specs;
#[path = "readme.rs"]
mod readme;
#[path = "sct_cli.rs"]
mod sct_cli;
#[path = "sct_definition5.rs"]
mod sct_definition5;
#[path = "sct_diagnostics.rs"]
mod sct_diagnostics;
#[path = "sct_examples.rs"]
mod sct_examples;
#[path = "sct_faudes.rs"]
mod sct_faudes;
#[path = "sct_framework.rs"]
mod sct_framework;
#[path = "sct_preemption.rs"]
mod sct_preemption;
#[path = "sct_runtime.rs"]
mod sct_runtime;
#[path = "sct_scale.rs"]
mod sct_scale;
#[path = "sct_textbook.rs"]
mod sct_textbook;
#[path = "sct_transfer.rs"]
mod sct_transfer;
#[path = "sct_wmod.rs"]
mod sct_wmod;
#[path = "time_constants.rs"]
mod time_constants;
#[path = "timed_budget.rs"]
mod timed_budget;
#[path = "timed_examples.rs"]
mod timed_examples;
#[path = "timed_language.rs"]
mod timed_language;
#[path = "timed_scan.rs"]
mod timed_scan;
