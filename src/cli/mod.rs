//! Command implementations of the CLI; `main.rs` only parses arguments and dispatches here.
//! Each engine has its own module.

/// `println!` that ignores write errors, so that `plcsynth ... | head` ends quietly instead of
/// panicking on a closed pipe.
macro_rules! outln {
    ($($t:tt)*) => {{
        use std::io::Write as _;
        let _ = writeln!(std::io::stdout(), $($t)*);
    }};
}

pub mod bench;
pub mod interchange;
pub mod ltl;
pub mod ltl_compare;
pub mod ltl_scale;
pub mod sct;
pub mod timed;

/// The form of the I/O table written by `--io-table`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum IoFormat {
    /// plcsynth's own CSV (comma-separated, one row per signal).
    Csv,
    /// A Siemens symbol table (STEP 7 symbols, TIA Portal PLC tags; timed games only).
    Sdf,
    /// The CODESYS I/O mapping list (semicolon-separated: Variable;Address;Type;Direction;Description).
    Codesys,
}

impl IoFormat {
    /// The format given, or the one the file name implies: `.sdf` a symbol table, else CSV.
    pub fn of(given: Option<IoFormat>, path: &str) -> IoFormat {
        given.unwrap_or(if path.to_ascii_lowercase().ends_with(".sdf") { IoFormat::Sdf } else { IoFormat::Csv })
    }
}

/// Prints `unit` for `target` with `options` (the creation time taken from
/// `SOURCE_DATE_EPOCH` or the clock) and writes it to `output` or standard output, and the
/// signal table to `io_table` in `io_format` (CSV, or the CODESYS mapping list): the last step of
/// `supervise --target` and `ltl --target`.
pub fn write_unit(
    unit: &plcsynth::plc::model::unit::Unit,
    target: plcsynth::plc::Target,
    options: plcsynth::plc::Options,
    io_table: Option<&str>,
    io_format: Option<IoFormat>,
    output: Option<&str>,
) -> std::process::ExitCode {
    use plcsynth::plc;
    use std::process::ExitCode;
    let created_unix = match timed::creation_time() {
        Ok(t) => t,
        Err(message) => {
            eprintln!("error: {message}");
            return ExitCode::from(2);
        }
    };
    let files = match plc::render_unit_files(unit, target, &plc::Options { created_unix, ..options }) {
        Ok(files) => files,
        Err(message) => {
            eprintln!("error: {message}");
            return ExitCode::from(2);
        }
    };
    if let Some(path) = io_table {
        let text = match IoFormat::of(io_format, path) {
            IoFormat::Csv => plc::signal_table_csv(unit),
            IoFormat::Codesys => plc::codesys_mapping_csv(unit),
            IoFormat::Sdf => {
                eprintln!("error: --io-format sdf is for timed controllers; this code reads the user's own symbols");
                return ExitCode::from(2);
            }
        };
        if let Err(e) = std::fs::write(path, text) {
            eprintln!("error: cannot write {path}: {e}");
            return ExitCode::from(2);
        }
    }
    timed::write_files(output, Some(target), &files)
}
