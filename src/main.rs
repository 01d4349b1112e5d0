//! The plcsynth command-line interface: a thin layer over the library.

mod cli;

use clap::{Parser, Subcommand};
use std::process::ExitCode;

#[derive(Parser)]
#[command(name = "plcsynth", version, about = "Synthesise PLC programs from specifications")]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
}

#[derive(Subcommand)]
enum Command {
    /// Synthesise one supervisor per specification of a `.sct` project (Göbe 2019).
    Supervise(cli::sct::SuperviseArgs),
    /// Classic Ramadge–Wonham SupCon of a plant and a specification in libFAUDES `.gen` format.
    Supcon(cli::sct::SupconArgs),
    /// Print benchmark tables beside the published figures.
    Bench {
        #[command(subcommand)]
        engine: BenchEngine,
    },
}

#[derive(Subcommand)]
enum BenchEngine {
    /// Supervisory control: transfer lines (Göbe 2019, tables 7.1/7.2) and SupCon vs libFAUDES.
    Sct(cli::sct::BenchArgs),
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    match cli.command {
        Some(Command::Supervise(a)) => cli::sct::supervise(&a),
        Some(Command::Supcon(a)) => cli::sct::supcon(&a),
        Some(Command::Bench { engine: BenchEngine::Sct(a) }) => cli::sct::bench(&a),
        None => {
            use clap::CommandFactory;
            let _ = Cli::command().print_help();
            ExitCode::SUCCESS
        }
    }
}
