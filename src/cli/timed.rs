//! `plcsynth solve`: solve a timed-game specification.

use clap::Args;
use plcsynth::diag::{render_plain, Diagnostics};
use plcsynth::plc;
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

/// Options of the PLC targets.
#[derive(Args)]
pub struct PlcArgs {
    /// Also write the I/O table: CSV (address, type, symbol, direction, meaning) for a `.csv`
    /// file, a Siemens symbol table for STEP 7 / TIA Portal for a `.sdf` file.
    #[arg(long, value_name = "FILE")]
    pub io_table: Option<String>,
    /// STL: the organisation block that runs the controller.
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u16).range(1..))]
    pub ob: Option<u16>,
    /// STL: put the controller in FB N with instance DB N, called from the OB.
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u16).range(1..))]
    pub fb: Option<u16>,
    /// STL: the marker byte holding the program position (signals without io use bits from
    /// byte N+10 on).
    #[arg(long, value_name = "N")]
    pub marker_byte: Option<u16>,
    /// STL: the number of S7 timers of the CPU.
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u16).range(1..))]
    pub cpu_timers: Option<u16>,
}

impl PlcArgs {
    /// The printers' options; the creation time is `SOURCE_DATE_EPOCH` if set, else now. The
    /// STL options are refused for other targets.
    fn options(&self, target: Option<plc::Target>) -> Result<plc::Options, String> {
        let stl_flags = [
            ("--ob", self.ob.is_some()),
            ("--fb", self.fb.is_some()),
            ("--marker-byte", self.marker_byte.is_some()),
            ("--cpu-timers", self.cpu_timers.is_some()),
        ];
        if target != Some(plc::Target::Stl) {
            if let Some((flag, _)) = stl_flags.iter().find(|(_, given)| *given) {
                return Err(format!("{flag} applies to --target stl only"));
            }
        }
        let created_unix = creation_time()?;
        let defaults = plc::Options::default();
        Ok(plc::Options {
            ob: self.ob.unwrap_or(defaults.ob),
            fb: self.fb,
            marker_byte: self.marker_byte.unwrap_or(defaults.marker_byte),
            cpu_timers: self.cpu_timers.unwrap_or(defaults.cpu_timers),
            created_unix,
        })
    }
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
/// the target cannot hold, or an STL option that clashes with the code, exits 2 with a located
/// diagnostic and writes nothing.
pub fn compile(
    file: &str,
    budget: &BudgetArgs,
    target: Option<plc::Target>,
    out: Option<&str>,
    plc_args: &PlcArgs,
) -> ExitCode {
    let options = match plc_args.options(target) {
        Ok(options) => options,
        Err(message) => {
            eprintln!("error: {message}");
            return ExitCode::from(2);
        }
    };
    if plc_args.io_table.is_some() && target.is_none() {
        eprintln!("error: --io-table needs a PLC --target");
        return ExitCode::from(2);
    }
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
    let Some(t) = target else {
        return write_files(out, None, &[plc::OutputFile { name: String::new(), text: program.render(&game) }]);
    };
    let code = match plc::build(&game, &program, t, name, &source, &options) {
        Ok(code) => code,
        // A constant the target cannot hold is an input error, located in the spec.
        Err(diags) => {
            eprint!("{}", render_plain(file, &source, &diags));
            eprintln!("{file}: nothing written");
            return ExitCode::from(2);
        }
    };
    if let Some(path) = &plc_args.io_table {
        let text = if path.to_ascii_lowercase().ends_with(".sdf") {
            plc::tag_table_sdf(&code)
        } else {
            plc::io_table_csv(&code)
        };
        if let Err(e) = std::fs::write(path, text) {
            eprintln!("error: cannot write {path}: {e}");
            return ExitCode::from(2);
        }
    }
    write_files(out, Some(t), &plc::render_files(&code, t, &options))
}

/// The creation time printed into PLCopen files: `SOURCE_DATE_EPOCH` if set (reproducible
/// builds), else now.
pub(crate) fn creation_time() -> Result<u64, String> {
    match std::env::var("SOURCE_DATE_EPOCH") {
        Ok(text) => {
            text.trim().parse::<u64>().map_err(|_| format!("SOURCE_DATE_EPOCH is not a number of seconds: `{text}`"))
        }
        Err(_) => Ok(std::time::SystemTime::now().duration_since(std::time::UNIX_EPOCH).map_or(0, |d| d.as_secs())),
    }
}

/// Writes `files` to `out` (a file, or a directory for a multi-file target) or to standard
/// output (several files each after a line `==> NAME <==`).
pub(crate) fn write_files(out: Option<&str>, target: Option<plc::Target>, files: &[plc::OutputFile]) -> ExitCode {
    let multi = target.is_some_and(plc::Target::multi_file);
    let result = match out {
        Some(dir) if multi => std::fs::create_dir_all(dir).and_then(|()| {
            files.iter().try_for_each(|f| std::fs::write(std::path::Path::new(dir).join(&f.name), &f.text))
        }),
        Some(path) => std::fs::write(path, &files[0].text),
        None => {
            use std::io::Write as _;
            let mut stdout = std::io::stdout();
            let _ = files.iter().try_for_each(|f| {
                if multi {
                    write!(stdout, "==> {} <==\n{}", f.name, f.text)
                } else {
                    write!(stdout, "{}", f.text)
                }
            });
            Ok(())
        }
    };
    if let Err(e) = result {
        eprintln!("error: cannot write {}: {e}", out.unwrap_or("-"));
        return ExitCode::from(2);
    }
    ExitCode::SUCCESS
}
