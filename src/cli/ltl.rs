//! `plcsynth ltl`: LTL synthesis of G4LTL or TLSF specifications.

use clap::Args;
use plcsynth::diag::render_plain;
use plcsynth::ltl::{self, Config, Format, Verdict};
use plcsynth::plc;
use std::process::ExitCode;

#[derive(Args)]
pub struct LtlArgs {
    /// The specification: `.ltl`/`.g4ltl` (G4LTL's lines) or `.tlsf` (SYNTCOMP's TLSF).
    pub file: String,
    /// Print one JSON object instead of text.
    #[arg(long)]
    pub json: bool,
    /// The largest co-Büchi bound k tried (k grows from 0 until a player wins).
    #[arg(long, value_name = "N", default_value_t = ltl::DEFAULT_MAX_K, value_parser = clap::value_parser!(u32).range(0..=100))]
    pub max_k: u32,
    /// Game positions all games of the run may build together; past it the verdict is unknown
    /// (exit status 3).
    #[arg(long, value_name = "N", default_value_t = ltl::DEFAULT_MAX_STATES)]
    pub max_states: usize,
    /// Units of work the run may spend (translation and games; about proportional to time).
    #[arg(long, value_name = "N", default_value_t = ltl::DEFAULT_MAX_WORK)]
    pub max_work: u64,
    /// Override a TLSF parameter, e.g. `--param n=3` (repeatable).
    #[arg(long = "param", value_name = "NAME=VALUE", value_parser = parse_param)]
    pub params: Vec<(String, i64)>,
    /// Generate the controller as a PLC function block for this target instead of printing it
    /// (docs/ltl-plc.md); an unrealizable or unknown verdict writes nothing.
    #[arg(long, value_parser = super::sct::target_parser(), conflicts_with = "json")]
    pub target: Option<plc::Target>,
    /// Write the code to this file instead of standard output; for a target of several files
    /// (twincat) a directory, created if missing.
    #[arg(short, long, requires = "target")]
    pub output: Option<String>,
    /// Also write the signal table (CSV: address, type, symbol, direction).
    #[arg(long, value_name = "FILE", requires = "target")]
    pub io_table: Option<String>,
    /// The function block's name (default `FB_` and the TLSF title, or `FB_Controller`).
    #[arg(long, value_name = "NAME", requires = "target")]
    pub name: Option<String>,
}

fn parse_param(text: &str) -> Result<(String, i64), String> {
    let (name, value) = text.split_once('=').ok_or("expected NAME=VALUE, e.g. n=3")?;
    let value = value.trim().parse().map_err(|_| format!("`{value}` is not an integer"))?;
    Ok((name.trim().to_string(), value))
}

/// Exit status: 0 realizable, 1 unrealizable, 2 input error, 3 unknown (bound or budget).
pub fn ltl(a: &LtlArgs) -> ExitCode {
    let source = match std::fs::read_to_string(&a.file) {
        Ok(s) => s,
        Err(e) => {
            eprintln!("error: cannot read `{}`: {e}", a.file);
            return ExitCode::from(2);
        }
    };
    let format = Format::of_path(&a.file);
    if format == Format::G4ltl && !a.params.is_empty() {
        eprintln!("error: --param sets TLSF parameters; `{}` is not a .tlsf file", a.file);
        return ExitCode::from(2);
    }
    let spec = match ltl::compile(&source, format, &a.params) {
        Ok((spec, warnings)) => {
            if !warnings.is_empty() {
                eprint!("{}", render_plain(&a.file, &source, &warnings));
            }
            spec
        }
        Err(diagnostics) => {
            eprint!("{}", render_plain(&a.file, &source, &diagnostics));
            return ExitCode::from(2);
        }
    };
    let cfg = Config { max_k: a.max_k, max_states: a.max_states, max_work: a.max_work, ..Config::default() };
    let outcome = match ltl::synthesize(&spec, &cfg, &mut |_| true) {
        Ok(outcome) => outcome,
        Err(stop) => {
            eprintln!("{}: stopped: {stop}", a.file);
            return ExitCode::from(3);
        }
    };
    if let Some(target) = a.target {
        let Some(controller) = &outcome.controller else {
            eprintln!("{}: {}; no code written", a.file, ltl::summary(&outcome));
            return exit_code(outcome.verdict);
        };
        return write_code(a, target, &source, &spec, controller);
    }
    if a.json {
        outln!("{}", ltl::report_json(&spec, &outcome));
    } else {
        outln!("{}", ltl::summary(&outcome));
        outln!("specification: {}", spec.formula_text());
        if let Some(m) = &outcome.controller {
            outln!("controller (state: inputs / outputs -> next):");
            outln!("{}", ltl::render_machine(&spec, m).trim_end());
        }
        if let Some(m) = &outcome.counter_strategy {
            outln!("environment's counter-strategy (state: inputs it sets / outputs it sees -> next):");
            outln!("{}", ltl::render_machine(&spec, m).trim_end());
        }
    }
    exit_code(outcome.verdict)
}

fn exit_code(verdict: Verdict) -> ExitCode {
    ExitCode::from(match verdict {
        Verdict::Realizable => 0,
        Verdict::Unrealizable => 1,
        Verdict::Unknown => 3,
    })
}

/// Lowers the controller into a function block (`plc::lower_ltl`) and writes it for `target`.
fn write_code(a: &LtlArgs, target: plc::Target, source: &str, spec: &ltl::Spec, controller: &ltl::Machine) -> ExitCode {
    let options = plc::lower_ltl::LowerOptions { name: a.name.clone() };
    let unit = match plc::lower_ltl::lower(source, spec, controller, &options) {
        Ok(unit) => unit,
        Err(diags) => {
            eprint!("{}", render_plain(&a.file, source, &diags));
            eprintln!("{}: nothing written", a.file);
            return ExitCode::from(2);
        }
    };
    let created_unix = match super::timed::creation_time() {
        Ok(t) => t,
        Err(message) => {
            eprintln!("error: {message}");
            return ExitCode::from(2);
        }
    };
    let files = match plc::render_unit_files(&unit, target, &plc::Options { created_unix, ..plc::Options::default() }) {
        Ok(files) => files,
        Err(message) => {
            eprintln!("error: {message}");
            return ExitCode::from(2);
        }
    };
    if let Some(path) = &a.io_table {
        if let Err(e) = std::fs::write(path, plc::signal_table_csv(&unit)) {
            eprintln!("error: cannot write {path}: {e}");
            return ExitCode::from(2);
        }
    }
    super::timed::write_files(a.output.as_deref(), Some(target), &files)
}
