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
pub mod sct;
pub mod timed;

/// Prints `unit` for `target` with `options` (the creation time taken from
/// `SOURCE_DATE_EPOCH` or the clock) and writes it to `output` or standard output, and the
/// signal table to `io_table`: the last step of `supervise --target` and `ltl --target`.
pub fn write_unit(
    unit: &plcsynth::plc::model::unit::Unit,
    target: plcsynth::plc::Target,
    options: plcsynth::plc::Options,
    io_table: Option<&str>,
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
        if let Err(e) = std::fs::write(path, plc::signal_table_csv(unit)) {
            eprintln!("error: cannot write {path}: {e}");
            return ExitCode::from(2);
        }
    }
    timed::write_files(output, Some(target), &files)
}
