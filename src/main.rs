//! The plcsynth command-line interface: a thin layer over the library.

use clap::Parser;

#[derive(Parser)]
#[command(name = "plcsynth", version, about = "Synthesise PLC programs from specifications")]
struct Cli {}

fn main() {
    let _ = Cli::parse();
}
