//! `plcsynth solve`: solve a timed-game specification.

use plcsynth::diag::render_plain;
use plcsynth::timed::{self, solve::Verdict};
use std::process::ExitCode;
use std::time::Instant;

/// Reads and checks a specification, printing diagnostics (and warnings) to stderr; an input
/// error is exit status 2.
fn load(file: &str) -> Result<(String, timed::model::Game), ExitCode> {
    let source = std::fs::read_to_string(file).map_err(|e| {
        eprintln!("error: cannot read {file}: {e}");
        ExitCode::from(2)
    })?;
    match timed::compile(&source) {
        Ok((game, warnings)) => {
            if !warnings.is_empty() {
                eprint!("{}", render_plain(file, &source, &warnings));
            }
            Ok((source, game))
        }
        Err(diags) => {
            eprint!("{}", render_plain(file, &source, &diags));
            Err(ExitCode::from(2))
        }
    }
}

/// Exit status: 0 realizable, 1 unrealizable, 2 input error, 3 budget exceeded.
pub fn solve(file: &str, json: bool, max_states: Option<usize>, dump_states: bool) -> ExitCode {
    let (_, game) = match load(file) {
        Ok(ok) => ok,
        Err(code) => return code,
    };
    let mut options = timed::solve::SolveOptions::default();
    if let Some(n) = max_states {
        options.max_states = n;
    }
    let started = Instant::now();
    let result = timed::synthesize(&game, &options, &mut |_| true);
    let millis = started.elapsed().as_secs_f64() * 1000.0;
    let stats = &result.solution.stats;
    let explanation = result.explanation.as_ref().map(|e| e.render());
    if json {
        let value = serde_json::json!({
            "file": file,
            "verdict": result.solution.verdict,
            "realizable": result.solution.verdict == Verdict::Realizable,
            "visited": stats.visited,
            "expanded": stats.expanded,
            "winning": stats.winning,
            "removed": stats.removed,
            "edges": stats.edges,
            "zones": stats.zones,
            "bytes": stats.bytes,
            "millis": millis,
            "explanation": explanation,
        });
        outln!("{value}");
    } else {
        let verdict = match result.solution.verdict {
            Verdict::Realizable => "realizable".to_string(),
            Verdict::Unrealizable => "unrealizable".to_string(),
            Verdict::BudgetExceeded => format!("budget exceeded after {} states", stats.visited),
            Verdict::Cancelled => "cancelled".to_string(),
        };
        outln!("{file}: {verdict}");
        outln!(
            "visited {} · winning {} · removed {} · edges {} · {:.1} ms",
            stats.visited,
            stats.winning,
            stats.removed,
            stats.edges,
            millis
        );
        if let Some(text) = explanation {
            outln!("\nwhy the initial state is lost:\n{text}");
        }
        if dump_states {
            outln!("\n{}", timed::explain::dump(&game, &result.split, &result.solution.space));
        }
    }
    match result.solution.verdict {
        Verdict::Realizable => ExitCode::SUCCESS,
        Verdict::Unrealizable => ExitCode::from(1),
        Verdict::BudgetExceeded | Verdict::Cancelled => ExitCode::from(3),
    }
}

/// `plcsynth compile FILE --target T`: the intermediate program (`target` = None) or PLC code.
/// Unrealizable specifications exit 1 with the explanation and write nothing; a time constant
/// the target cannot hold exits 2 with a located diagnostic and writes nothing.
pub fn compile(file: &str, target: Option<plcsynth::plc::Target>, out: Option<&str>) -> ExitCode {
    let (source, game) = match load(file) {
        Ok(ok) => ok,
        Err(code) => return code,
    };
    let result = timed::synthesize(&game, &timed::solve::SolveOptions::default(), &mut |_| true);
    let Some(program) = plcsynth::program::controller(&game, &result) else {
        match result.solution.verdict {
            Verdict::BudgetExceeded => {
                eprintln!("{file}: budget exceeded after {} states; nothing written", result.solution.stats.visited);
                return ExitCode::from(3);
            }
            _ => {
                eprintln!("{file}: unrealizable; nothing written");
                if let Some(e) = &result.explanation {
                    eprintln!("\nwhy the initial state is lost:\n{}", e.render());
                }
                return ExitCode::from(1);
            }
        }
    };
    let name = std::path::Path::new(file).file_stem().and_then(|s| s.to_str()).unwrap_or("controller");
    let text = match target {
        None => program.render(&game),
        Some(t) => match plcsynth::plc::generate(&game, &program, t, name, &source) {
            Ok(text) => text,
            // A constant the target cannot hold is an input error, located in the spec.
            Err(diags) => {
                eprint!("{}", render_plain(file, &source, &diags));
                eprintln!("{file}: nothing written");
                return ExitCode::from(2);
            }
        },
    };
    match out {
        Some(path) => {
            if let Err(e) = std::fs::write(path, text) {
                eprintln!("error: cannot write {path}: {e}");
                return ExitCode::from(2);
            }
        }
        None => {
            use std::io::Write as _;
            let _ = write!(std::io::stdout(), "{text}");
        }
    }
    ExitCode::SUCCESS
}
