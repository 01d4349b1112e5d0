//! The plcsynth command-line interface: a thin layer over the library.

mod cli;

use clap::{Parser, Subcommand};
use plcsynth::plc::Target;
use std::process::ExitCode;

#[derive(Parser)]
#[command(name = "plcsynth", version, about = "Synthesise PLC programs from specifications")]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Solve a timed-game specification (.tga). Exit status: 0 realizable, 1 unrealizable,
    /// 2 input error, 3 budget exceeded.
    Solve {
        file: String,
        /// Print one JSON object instead of text.
        #[arg(long)]
        json: bool,
        #[command(flatten)]
        budget: cli::timed::BudgetArgs,
        #[command(flatten)]
        scan: cli::timed::ScanArgs,
        /// Also print every explored state with its status and edges.
        #[arg(long)]
        states: bool,
    },
    /// Synthesise the controller program of a timed-game specification. Exit status: 0 written,
    /// 1 unrealizable (or, at a scan time, not implementable, or its code failed a real-time
    /// run), 2 input error, 3 budget exceeded.
    Compile {
        file: String,
        #[command(flatten)]
        budget: cli::timed::BudgetArgs,
        #[command(flatten)]
        scan: cli::timed::ScanArgs,
        /// What to produce.
        #[arg(long, value_parser = output_parser(), default_value = "program")]
        target: Output,
        /// Write to this file instead of standard output; for a target of several files
        /// (twincat) a directory, created if missing.
        #[arg(short, long)]
        output: Option<String>,
        #[command(flatten)]
        plc: cli::timed::PlcArgs,
        /// At a scan time (declared or --scan): run the generated code this many times, 2000
        /// scans each, against the specification's plant timed adversarially, before writing
        /// it; a failure writes nothing and exits 1. 0 skips the check.
        #[arg(long, value_name = "N", default_value_t = 20)]
        check_runs: u64,
    },
    /// Synthesise one supervisor per specification of a `.sct` project (Göbe 2019). Exit status:
    /// 0 done, 2 input error, 3 state budget spent.
    Supervise(cli::sct::SuperviseArgs),
    /// Synthesise a controller from an LTL specification (G4LTL `.ltl` or TLSF `.tlsf`;
    /// Cheng et al. 2014). Exit status: 0 realizable, 1 unrealizable, 2 input error, 3 unknown
    /// (bound or budget reached).
    Ltl(cli::ltl::LtlArgs),
    /// Classic Ramadge–Wonham SupCon of a plant and a specification, libFAUDES `.gen` files or
    /// Supremica `.wmod` modules.
    Supcon(cli::sct::SupconArgs),
    /// Write a Supremica module (`.wmod`) or libFAUDES generators (`.gen`) as a `.sct` project.
    /// Exit status: 0 written, 2 input error or a part that does not map, 3 state budget spent.
    Import(cli::interchange::ImportArgs),
    /// Write a `.sct` project's plants and specifications (and its supervisors) as a Supremica
    /// module (`.wmod`). Exit status: 0 written, 2 input error or a part that does not map,
    /// 3 state budget spent.
    Export(cli::interchange::ExportArgs),
    /// Print benchmark tables beside the published figures.
    Bench {
        #[command(subcommand)]
        engine: BenchEngine,
    },
}

/// What `compile` produces: the intermediate program or code for one of [`Target::ALL`].
#[derive(Clone, Copy, PartialEq, Eq)]
enum Output {
    Program,
    Plc(Target),
}

/// The `--target` values: `program`, then every PLC target with its label as help.
fn output_parser() -> impl clap::builder::TypedValueParser<Value = Output> {
    use clap::builder::{PossibleValue, PossibleValuesParser, TypedValueParser};
    let program = PossibleValue::new("program").help("The intermediate controller program (Peter 2005, chapter 6)");
    let targets = Target::ALL.into_iter().map(|t| PossibleValue::new(t.name()).help(t.label()));
    PossibleValuesParser::new(std::iter::once(program).chain(targets))
        // Every value but `program` is a target name.
        .map(|name| name.parse().map_or(Output::Program, Output::Plc))
}

#[derive(Subcommand)]
enum BenchEngine {
    /// The timed-game examples beside Peter 2005, table 7.3.
    Timed {
        /// Runs per example; the median is printed.
        #[arg(long, default_value_t = 5)]
        runs: usize,
        /// Folder holding the examples.
        #[arg(long, default_value = "examples/timed")]
        examples: std::path::PathBuf,
        #[command(flatten)]
        format: cli::bench::Format,
    },
    /// Supervisory control: transfer lines (Göbe 2019, tables 7.1/7.2) and SupCon vs libFAUDES.
    Sct(cli::sct::BenchArgs),
    /// LTL synthesis: the public G4LTL and SYNTCOMP specifications beside the published verdicts.
    Ltl(cli::ltl::BenchArgs),
}

fn main() -> ExitCode {
    match Cli::parse().command {
        Command::Solve { file, json, budget, scan, states } => cli::timed::solve(&file, json, &budget, &scan, states),
        Command::Compile { file, budget, scan, target, output, plc, check_runs } => {
            let target = match target {
                Output::Program => None,
                Output::Plc(t) => Some(t),
            };
            cli::timed::compile(&file, &budget, &scan, target, output.as_deref(), &plc, check_runs)
        }
        Command::Supervise(a) => cli::sct::supervise(&a),
        Command::Supcon(a) => cli::sct::supcon(&a),
        Command::Import(a) => cli::interchange::import(&a),
        Command::Export(a) => cli::interchange::export(&a),
        Command::Ltl(a) => cli::ltl::ltl(&a),
        Command::Bench { engine: BenchEngine::Timed { runs, examples, format } } => {
            cli::bench::timed(&examples, runs, format)
        }
        Command::Bench { engine: BenchEngine::Sct(a) } => cli::sct::bench(&a),
        Command::Bench { engine: BenchEngine::Ltl(a) } => cli::ltl::bench(&a),
    }
}
