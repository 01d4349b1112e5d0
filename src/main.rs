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
}

fn main() -> ExitCode {
    match Cli::parse().command {
        Command::Solve { file, json, max_states, states } => cli::timed::solve(&file, json, max_states, states),
    }
}
