//! The plcsynth command-line interface: a thin layer over the library.

mod cli;

use clap::{Parser, Subcommand};
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
        /// Also print every explored state with its status and edges.
        #[arg(long)]
        states: bool,
    },
    /// Synthesise the controller program of a timed-game specification. Exit status: 0 written,
    /// 1 unrealizable, 2 input error, 3 budget exceeded.
    Compile {
        file: String,
        #[command(flatten)]
        budget: cli::timed::BudgetArgs,
        /// What to produce.
        #[arg(long, value_enum, default_value_t = Target::Program)]
        target: Target,
        /// Write to this file instead of standard output.
        #[arg(short, long)]
        output: Option<String>,
    },
    /// Synthesise one supervisor per specification of a `.sct` project (Göbe 2019). Exit status:
    /// 0 done, 2 input error, 3 state budget spent.
    Supervise(cli::sct::SuperviseArgs),
    /// Classic Ramadge–Wonham SupCon of a plant and a specification in libFAUDES `.gen` format.
    Supcon(cli::sct::SupconArgs),
    /// Print benchmark tables beside the published figures.
    Bench {
        #[command(subcommand)]
        engine: BenchEngine,
    },
}

#[derive(Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
enum Target {
    /// The intermediate controller program (Peter 2005, chapter 6).
    Program,
    /// IEC 61131-3 Structured Text function block.
    St,
    /// Siemens SCL source for TIA Portal (S7-1200/1500).
    Scl,
    /// CODESYS / TwinCAT Structured Text.
    Codesys,
    /// IEC 61131-3 Instruction List.
    Il,
    /// Siemens S7 Statement List (AWL) with marker byte and jump list.
    Stl,
    /// PLCopen TC6 XML v2.01 project.
    Plcopen,
}

impl Target {
    fn plc(self) -> Option<plcsynth::plc::Target> {
        use plcsynth::plc::Target as T;
        Some(match self {
            Target::Program => return None,
            Target::St => T::St,
            Target::Scl => T::Scl,
            Target::Codesys => T::Codesys,
            Target::Il => T::Il,
            Target::Stl => T::Stl,
            Target::Plcopen => T::Plcopen,
        })
    }
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
    },
    /// Supervisory control: transfer lines (Göbe 2019, tables 7.1/7.2) and SupCon vs libFAUDES.
    Sct(cli::sct::BenchArgs),
}

fn main() -> ExitCode {
    match Cli::parse().command {
        Command::Solve { file, json, budget, states } => cli::timed::solve(&file, json, &budget, states),
        Command::Compile { file, budget, target, output } => {
            cli::timed::compile(&file, &budget, target.plc(), output.as_deref())
        }
        Command::Supervise(a) => cli::sct::supervise(&a),
        Command::Supcon(a) => cli::sct::supcon(&a),
        Command::Bench { engine: BenchEngine::Timed { runs, examples } } => cli::bench::timed(&examples, runs),
        Command::Bench { engine: BenchEngine::Sct(a) } => cli::sct::bench(&a),
    }
}
