//! `plcsynth solve`: solve a timed-game specification.

use clap::Args;
use plcsynth::diag::{render_plain, Diagnostics};
use plcsynth::timed::solve::{self, Budget, BudgetStop, SolveOptions, Verdict};
use plcsynth::timed::{self};
use std::process::ExitCode;
use std::time::Instant;

/// The budgets of a search; a search that exceeds one stops with exit status 3.
#[derive(Args)]
pub struct BudgetArgs {
    /// Give up after storing this many states.
    #[arg(long, value_name = "N", default_value_t = solve::DEFAULT_MAX_STATES)]
    pub max_states: usize,
    /// Give up once the split automata and the state space take about this much memory.
    #[arg(long, value_name = "MIB", default_value_t = solve::DEFAULT_MAX_BYTES >> 20)]
    pub max_memory: usize,
    /// Give up after this much work (zone bounds and state entries computed, about 10-20 ns
    /// each): bounds the time of games whose states are few but expensive.
    #[arg(long, value_name = "N", default_value_t = solve::DEFAULT_MAX_WORK)]
    pub max_work: u64,
}

impl BudgetArgs {
    fn options(&self) -> SolveOptions {
        SolveOptions {
            max_states: self.max_states,
            max_bytes: self.max_memory.saturating_mul(1 << 20),
            max_work: self.max_work,
            ..SolveOptions::default()
        }
    }
}

/// The budget stop as a diagnostic with the flag that raises the budget, located at the
/// declaration to blame when there is one.
fn render_stop(file: &str, source: &str, stop: &BudgetStop) -> String {
    let flag = match stop.budget {
        Budget::States => "--max-states N",
        Budget::Memory => "--max-memory MIB",
        Budget::Work => "--max-work N",
    };
    let note = format!("this is the {} budget; raise it with {flag}", stop.budget.name());
    match stop.span {
        Some(span) => {
            let mut d = Diagnostics::new(source);
            d.error(span, format!("budget exceeded: {}", stop.message)).with_note(note).with_note(
                "every clock in use at a node multiplies its sub-locations by the clock's pieces (5.2.2); \
                 fewer clocks per automaton, or resets before clocks are read again, keep the split small",
            );
            render_plain(file, source, &d.items)
        }
        None => format!("{file}: budget exceeded: {}\n  = note: {note}\n", stop.message),
    }
}

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
pub fn solve(file: &str, json: bool, budget: &BudgetArgs, dump_states: bool) -> ExitCode {
    let (source, game) = match load(file) {
        Ok(ok) => ok,
        Err(code) => return code,
    };
    let options = budget.options();
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
            "work": stats.work,
            "budget": result.solution.stop,
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
    if let Some(stop) = &result.solution.stop {
        eprint!("{}", render_stop(file, &source, stop));
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
pub fn compile(file: &str, budget: &BudgetArgs, target: Option<plcsynth::plc::Target>, out: Option<&str>) -> ExitCode {
    let (source, game) = match load(file) {
        Ok(ok) => ok,
        Err(code) => return code,
    };
    let result = timed::synthesize(&game, &budget.options(), &mut |_| true);
    let Some(program) = plcsynth::program::controller(&game, &result) else {
        match result.solution.verdict {
            Verdict::BudgetExceeded | Verdict::Cancelled => {
                if let Some(stop) = &result.solution.stop {
                    eprint!("{}", render_stop(file, &source, stop));
                }
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
