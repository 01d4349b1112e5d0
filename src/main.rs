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
        /// Give up after storing this many states.
        #[arg(long, value_name = "N")]
        max_states: Option<usize>,
        /// Also print every explored state with its status and edges.
        #[arg(long)]
        states: bool,
    },
    /// Print benchmark tables beside the published figures.
    Bench {
        #[command(subcommand)]
        engine: BenchEngine,
    },
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
}

fn main() -> ExitCode {
    match Cli::parse().command {
        Command::Solve { file, json, max_states, states } => cli::timed::solve(&file, json, max_states, states),
        Command::Bench { engine: BenchEngine::Timed { runs, examples } } => cli::bench::timed(&examples, runs),
    }
}
