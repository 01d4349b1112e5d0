//! `plcsynth solve`: solve a timed-game specification.

use clap::Args;
use plcsynth::diag::{render_plain, Diagnostics};
use plcsynth::plc;
use plcsynth::search::{Decision as _, Outcome as _};
use plcsynth::timed::solve::{self, Config, Resource, Solution, Stop, Verdict};
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
    /// Explore the whole reachable game (the thesis's breadth-first algorithm, the reference)
    /// instead of only the strategy being built.
    #[arg(long)]
    pub exhaustive: bool,
    /// Search without the thesis's zeno memory (5.1) at once, rather than first with it: the
    /// exact search, which may store more states.
    #[arg(long)]
    pub no_zeno_memory: bool,
    /// Scan games: store every zone as its own state at once, rather than first letting a move
    /// go to a surviving state of the same locations that wins its zone (inclusion, with plan
    /// clocks lower; a quarter of every budget): the larger search, for comparison.
    #[arg(long)]
    pub no_inclusion: bool,
    /// Scan games: explore every new state, rather than counting one lost at once when a lost
    /// state of the same locations has its clock values with the plans' clocks at most as high
    /// (dominance): the larger search, for comparison.
    #[arg(long)]
    pub no_dominance: bool,
}

/// The PLC's cycle time.
#[derive(Args)]
pub struct ScanArgs {
    /// Decide implementability on a PLC with this cycle time (`10ms`, `0.5s`, or milliseconds),
    /// overriding the specification's `scan` declaration.
    #[arg(long, value_name = "DURATION", value_parser = parse_duration_ms)]
    pub scan: Option<u64>,
}

/// `10ms`, `10 ms`, `2s`, `0.5s` or `10` (milliseconds) as whole milliseconds.
fn parse_duration_ms(text: &str) -> Result<u64, String> {
    let t = text.trim();
    let (number, factor) = if let Some(n) = t.strip_suffix("ms") {
        (n, 1.0)
    } else if let Some(n) = t.strip_suffix('s') {
        (n, 1000.0)
    } else {
        (t, 1.0)
    };
    let value: f64 = number.trim().parse().map_err(|_| format!("`{text}` is not a duration such as `10ms`"))?;
    let ms = value * factor;
    if !(ms >= 1.0 && ms.fract() == 0.0 && ms <= 1e12) {
        return Err(format!("`{text}` is not a whole number of milliseconds of at least 1 ms"));
    }
    Ok(ms as u64)
}

impl ScanArgs {
    /// The scan time in force: the flag, else the specification's declaration.
    fn resolve(&self, game: &timed::model::Game) -> Option<u64> {
        self.scan.or(game.scan_ms.map(|(ms, _)| ms))
    }
}

/// The scan-time verdict of a game realizable in zero time.
struct ScanOutcome {
    scan_ms: u64,
    result: timed::ScanSynthesis,
    millis: f64,
    bound: Option<timed::ScanBound>,
}

impl ScanOutcome {
    fn implementable(&self) -> bool {
        self.result.synthesis.solution.verdict() == Some(Verdict::Realizable)
    }

    fn verdict_text(&self) -> String {
        match self.result.synthesis.solution.outcome {
            Ok(Verdict::Realizable) => format!("implementable at {} ms", self.scan_ms),
            Ok(Verdict::Unrealizable) => format!("not implementable at {} ms", self.scan_ms),
            Err(Stop::Budget { .. }) => format!(
                "budget exceeded at {} ms after {} states",
                self.scan_ms, self.result.synthesis.solution.stats.visited
            ),
            Err(Stop::Cancelled) => "cancelled".to_string(),
        }
    }

    fn bound_text(&self) -> Option<String> {
        self.bound?.text()
    }
}

/// Solves the scan game after a zero-time verdict of realizable, with the bound if asked.
/// A game the construction refuses is an input error (exit status 2), printed here.
fn solve_at_scan(
    file: &str,
    source: &str,
    game: &timed::model::Game,
    scan_ms: u64,
    options: &Config,
    with_bound: bool,
) -> Result<ScanOutcome, ExitCode> {
    let started = Instant::now();
    let result = match timed::synthesize_at_scan(game, scan_ms, options, &mut |_| true) {
        Ok(result) => result,
        Err(error) => {
            let mut d = Diagnostics::new(source);
            let span = game.scan_ms.map(|(_, span)| span).unwrap_or_default();
            d.error(span, error.to_string());
            eprint!("{}", render_plain(file, source, &d.items));
            return Err(ExitCode::from(2));
        }
    };
    let millis = started.elapsed().as_secs_f64() * 1000.0;
    let decided = result.synthesis.solution.verdict().is_some();
    let bound = (with_bound && decided).then(|| {
        let implementable = result.synthesis.solution.verdict() == Some(Verdict::Realizable);
        timed::scan_bound(game, scan_ms, implementable, options, &mut |_| true)
    });
    Ok(ScanOutcome { scan_ms, result, millis, bound })
}

/// The note every zero-time verdict carries.
const ZERO_TIME: &str = "assumes a controller that reacts in zero time (the thesis's semantics); \
                         declare `scan 10 ms;` or pass --scan to decide it for a PLC's cycle";

/// Options of the PLC targets.
#[derive(Args)]
pub struct PlcArgs {
    /// Also write the I/O table: CSV (address, type, symbol, direction, meaning) for a `.csv`
    /// file, a Siemens symbol table for STEP 7 / TIA Portal for a `.sdf` file (or as
    /// --io-format says).
    #[arg(long, value_name = "FILE")]
    pub io_table: Option<String>,
    /// The form of --io-table: csv, sdf (Siemens symbols / TIA Portal tags) or codesys (the
    /// CODESYS I/O mapping list, semicolon-separated); by default from the file's extension.
    #[arg(long, value_enum, value_name = "FORMAT", requires = "io_table")]
    pub io_format: Option<super::IoFormat>,
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
    fn options(&self) -> Config {
        Config::default()
            .max_states(self.max_states)
            .max_bytes(self.max_memory.saturating_mul(1 << 20))
            .max_work(self.max_work)
            .exhaustive(self.exhaustive)
            .zeno_memory(!self.no_zeno_memory)
            .inclusion(!self.no_inclusion)
            .dominance(!self.no_dominance)
    }
}

/// A budget stop of `solution` as a diagnostic with the flag that raises the budget, located
/// at the declaration to blame when there is one; nothing for a decision or a cancellation.
fn render_stop(file: &str, source: &str, solution: &Solution) -> String {
    let Some(Stop::Budget { resource, message }) = solution.stop() else { return String::new() };
    let flag = match resource {
        Resource::States => "--max-states N",
        Resource::Memory => "--max-memory MIB",
        Resource::Work | Resource::Size => "--max-work N",
    };
    let note = format!("this is the {} budget; raise it with {flag}", resource.name());
    match solution.blame {
        Some(span) => {
            let mut d = Diagnostics::new(source);
            d.error(span, format!("budget exceeded: {message}")).with_note(note).with_note(
                "every clock in use at a node multiplies its sub-locations by the clock's pieces (5.2.2); \
                 fewer clocks per automaton, or resets before clocks are read again, keep the split small",
            );
            render_plain(file, source, &d.items)
        }
        None => format!("{file}: budget exceeded: {message}\n  = note: {note}\n"),
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

/// Exit status: 0 realizable (implementable at the scan time, if one is given), 1 unrealizable
/// or not implementable, 2 input error, 3 budget exceeded.
pub fn solve(file: &str, json: bool, budget: &BudgetArgs, scan: &ScanArgs, dump_states: bool) -> ExitCode {
    let (source, game) = match load(file) {
        Ok(ok) => ok,
        Err(code) => return code,
    };
    let options = budget.options();
    let started = Instant::now();
    let result = timed::synthesize(&game, &options, &mut |_| true);
    let millis = started.elapsed().as_secs_f64() * 1000.0;
    let scan_ms = scan.resolve(&game);
    let at_scan = match scan_ms {
        Some(ms) if result.solution.verdict() == Some(Verdict::Realizable) => {
            match solve_at_scan(file, &source, &game, ms, &options, true) {
                Ok(outcome) => Some(outcome),
                Err(code) => return code,
            }
        }
        _ => None,
    };
    let stats = &result.solution.stats;
    let explanation = result.explanation.as_ref().map(|e| e.render());
    let scan_explanation = at_scan.as_ref().and_then(|o| o.result.synthesis.explanation.as_ref().map(|e| e.render()));
    if json {
        let scan_value = at_scan.as_ref().map(|o| {
            let st = &o.result.synthesis.solution.stats;
            serde_json::json!({
                "scan_ms": o.scan_ms,
                "verdict": o.result.synthesis.solution.outcome_name(),
                "implementable": o.implementable(),
                "visited": st.visited,
                "removed": st.removed,
                "edges": st.edges,
                "work": st.work,
                "millis": o.millis,
                "stop": o.result.synthesis.solution.stop(),
                "bound": o.bound,
                "explanation": scan_explanation,
            })
        });
        let value = serde_json::json!({
            "file": file,
            "verdict": result.solution.outcome_name(),
            "realizable": result.solution.verdict() == Some(Verdict::Realizable),
            "semantics": "zero-time controller",
            "visited": stats.visited,
            "expanded": stats.expanded,
            "winning": stats.winning,
            "removed": stats.removed,
            "edges": stats.edges,
            "zones": stats.zones,
            "bytes": stats.bytes,
            "work": stats.work,
            "stop": result.solution.stop(),
            "blame": result.solution.blame,
            "millis": millis,
            "explanation": explanation,
            "scan": scan_value,
        });
        outln!("{value}");
    } else {
        let verdict = match result.solution.outcome {
            Ok(verdict) => verdict.name().to_string(),
            Err(Stop::Budget { .. }) => format!("budget exceeded after {} states", stats.visited),
            Err(Stop::Cancelled) => "cancelled".to_string(),
        };
        match &at_scan {
            Some(o) => outln!("{file}: {} (realizable with a zero-time controller)", o.verdict_text()),
            None if scan_ms.is_some() => outln!("{file}: {verdict} (even with a zero-time controller)"),
            None => outln!("{file}: {verdict}\n  = note: this verdict {ZERO_TIME}"),
        }
        outln!(
            "visited {} · winning {} · removed {} · edges {} · {:.1} ms",
            stats.visited,
            stats.winning,
            stats.removed,
            stats.edges,
            millis
        );
        if let Some(o) = &at_scan {
            let st = &o.result.synthesis.solution.stats;
            outln!(
                "at {} ms: visited {} · removed {} · edges {} · {:.1} ms",
                o.scan_ms,
                st.visited,
                st.removed,
                st.edges,
                o.millis
            );
            if let Some(text) = o.bound_text() {
                outln!("scan time: {text}");
            }
        }
        if let Some(text) = explanation {
            outln!("\nwhy the initial state is lost:\n{text}");
        }
        if let (Some(o), Some(text)) = (&at_scan, scan_explanation) {
            outln!("\nwhy a PLC with a {} ms scan cannot do it (`plc` is the scan: it reads at `plc.read`, decides `scan:r` or `scan:idle`, and its output `r` takes effect at some moment of the scan):\n{text}", o.scan_ms);
        }
        if dump_states {
            outln!("\n{}", timed::explain::dump(&game, &result.split, &result.solution.space));
            if let Some(o) = &at_scan {
                let s = &o.result.synthesis;
                outln!("\nat {} ms:\n{}", o.scan_ms, timed::explain::dump(&o.result.game, &s.split, &s.solution.space));
            }
        }
    }
    eprint!("{}", render_stop(file, &source, &result.solution));
    if let Some(o) = &at_scan {
        eprint!("{}", render_stop(file, &source, &o.result.synthesis.solution));
    }
    let verdict = at_scan.as_ref().map_or(result.solution.verdict(), |o| o.result.synthesis.solution.verdict());
    match verdict {
        Some(Verdict::Realizable) => ExitCode::SUCCESS,
        Some(Verdict::Unrealizable) => ExitCode::from(1),
        None => ExitCode::from(3),
    }
}

/// `plcsynth compile FILE --target T`: the intermediate program (`target` = None) or PLC code.
/// Unrealizable specifications exit 1 with the explanation and write nothing; a time constant
/// the target cannot hold, or an STL option that clashes with the code, exits 2 with a located
/// diagnostic and writes nothing. At a scan time the code must also pass `check_runs` runs of
/// the real-time checker ([`plc::lower::timed::realtime::check`]; the intermediate program is checked as ST).
pub fn compile(
    file: &str,
    budget: &BudgetArgs,
    scan: &ScanArgs,
    target: Option<plc::Target>,
    out: Option<&str>,
    plc_args: &PlcArgs,
    check_runs: u64,
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
    let Some(program) = plcsynth::timed::program::controller(&game, &result) else {
        match result.solution.verdict() {
            None => {
                eprint!("{}", render_stop(file, &source, &result.solution));
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
    // At a scan time the code follows the scan game's strategy where the PLC's inputs tell it
    // enough; else the zero-time strategy's, with the real-time check as its gate.
    let mut program = program;
    let mut pacing = plc::lower::timed::Pacing::Chained;
    if let Some(ms) = scan.resolve(&game) {
        let outcome = match solve_at_scan(file, &source, &game, ms, &budget.options(), false) {
            Ok(outcome) => outcome,
            Err(code) => return code,
        };
        match outcome.result.synthesis.solution.verdict() {
            Some(Verdict::Realizable) => match plc::lower::timed::scan_program(&game, &outcome.result, &mut |_| true) {
                Ok(scan_program) => {
                    let (nodes, followed) = (scan_program.nodes.len(), scan_program.work);
                    eprintln!(
                        "{file}: code from the scan strategy at {ms} ms: {nodes} nodes, one decision per scan \
                         ({followed} states followed)"
                    );
                    program = scan_program.program();
                    pacing = plc::lower::timed::Pacing::ScanByScan;
                }
                Err(why) => eprintln!(
                    "{file}: code from the zero-time strategy, checked in real time: no program follows the \
                     scan strategy: {why}"
                ),
            },
            Some(Verdict::Unrealizable) => {
                let bound = timed::scan_bound(&game, ms, false, &budget.options(), &mut |_| true);
                let outcome = ScanOutcome { bound: Some(bound), ..outcome };
                eprintln!("{file}: {}; nothing written", outcome.verdict_text());
                if let Some(text) = outcome.bound_text() {
                    eprintln!("scan time: {text}");
                }
                if let Some(e) = &outcome.result.synthesis.explanation {
                    eprintln!("\nwhy a PLC with a {ms} ms scan cannot do it:\n{}", e.render());
                }
                return ExitCode::from(1);
            }
            None => {
                eprint!("{}", render_stop(file, &source, &outcome.result.synthesis.solution));
                eprintln!("{file}: {}; nothing written", outcome.verdict_text());
                return ExitCode::from(3);
            }
        }
    }
    let name = std::path::Path::new(file).file_stem().and_then(|s| s.to_str()).unwrap_or("controller");
    let check_at = scan.resolve(&game).filter(|_| check_runs > 0);
    if target.is_none() && check_at.is_none() {
        return write_files(out, None, &[plc::OutputFile { name: String::new(), text: program.render(&game) }]);
    }
    let built = plc::lower::timed::build_paced(
        &game,
        &program,
        pacing,
        target.unwrap_or(plc::Target::St),
        name,
        &source,
        &options,
    );
    let (code, wiring) = match built {
        Ok(built) => built,
        // A constant the target cannot hold is an input error, located in the spec.
        Err(diags) if target.is_some() => {
            eprint!("{}", render_plain(file, &source, &diags));
            eprintln!("{file}: nothing written");
            return ExitCode::from(2);
        }
        // The intermediate program has no time type; only its check needed the ST code.
        Err(_) => {
            eprintln!("{file}: not checked in real time: the program does not lower to ST");
            return write_files(out, None, &[plc::OutputFile { name: String::new(), text: program.render(&game) }]);
        }
    };
    if let Some(ms) = check_at {
        let config = plc::lower::timed::realtime::Config {
            scan_us: ms.saturating_mul(1000),
            ..plc::lower::timed::realtime::Config::default()
        };
        let report = plc::lower::timed::realtime::check(&game, &code, &wiring, &config, check_runs);
        if let Some(r) = &report.failure {
            let why = pacing.failure_reason(&game);
            eprintln!(
                "{file}: the generated code fails at {ms} ms in real-time run {} of {check_runs} (seed {}), although \
                 the scan game is implementable; nothing written\n  = note: {why}\n{r}",
                report.runs, r.seed,
            );
            return ExitCode::from(1);
        }
        eprintln!(
            "{file}: checked at {ms} ms: {} runs of {} scans against the plant timed adversarially, no failure \
             ({} requests, {} plan steps; request latency per plan round: mean {:.2}, max {} scans)",
            report.runs,
            config.scans,
            report.requests,
            report.progress,
            report.latency.round_mean(),
            report.latency.round_max
        );
    }
    let Some(t) = target else {
        return write_files(out, None, &[plc::OutputFile { name: String::new(), text: program.render(&game) }]);
    };
    if let Some(path) = &plc_args.io_table {
        let unit = plc::lower::timed::structured(&code).unit;
        let text = match super::IoFormat::of(plc_args.io_format, path) {
            super::IoFormat::Sdf => plc::tag_table_sdf(&unit),
            super::IoFormat::Csv => plc::io_table_csv(&unit),
            super::IoFormat::Codesys => plc::codesys_mapping_csv(&unit),
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
