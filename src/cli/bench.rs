//! `plcsynth bench timed`: our figures beside the published ones (Peter 2005, table of 7.3);
//! and what every bench shares: `--markdown` (only the tables, with a caption, for the
//! README; `scripts/readme-bench.sh`) and the tables' columns.

use plcsynth::timed::solve::{Config, Solution, Stop, Verdict};
use plcsynth::timed::{compile, synthesize};
use std::path::Path;
use std::time::Instant;

/// How a bench prints: flattened into `bench timed|sct|ltl`.
#[derive(clap::Args, Clone, Copy, Default)]
pub struct Format {
    /// Print only the tables as GitHub markdown, under a one-line caption (`make readme-bench`
    /// puts them into README.md).
    #[arg(long)]
    pub markdown: bool,
    /// Print only the header line of every table `--markdown` prints, without running
    /// anything (the README test compares them with the README's).
    #[arg(long, hide = true)]
    pub headers: bool,
}

/// A table column: its heading and whether it is right-aligned (numbers).
pub type Column = (&'static str, bool);

/// `| a | b |`: a markdown table's header line.
pub fn header(columns: &[Column]) -> String {
    let names: Vec<&str> = columns.iter().map(|c| c.0).collect();
    format!("| {} |", names.join(" | "))
}

/// The header line and the alignment rule of a markdown table.
pub fn print_header(columns: &[Column]) {
    let rule: String = columns.iter().map(|c| if c.1 { "---:|" } else { "---|" }).collect();
    outln!("{}", header(columns));
    outln!("|{rule}");
}

/// Prints the header lines of `tables` (`--headers`).
pub fn print_headers(tables: &[&[Column]]) -> std::process::ExitCode {
    for columns in tables {
        outln!("{}", header(columns));
    }
    std::process::ExitCode::SUCCESS
}

/// The one-line caption of `--markdown` output: the command, the machine, the runs.
pub fn print_caption(engine: &str, runs: usize) {
    let cores = std::thread::available_parallelism().map_or(String::new(), |n| format!(" on a {n}-core machine"));
    let runs = runs.max(1);
    outln!(
        "_`plcsynth bench {engine} --markdown --runs {runs}`{cores}; our times are medians of {runs} run{}._",
        if runs == 1 { "" } else { "s" }
    );
}

/// Milliseconds rounded for reading: whole above 100, one decimal above 1, else two.
pub fn ms(x: f64) -> String {
    if x >= 100.0 {
        format!("{x:.0}")
    } else if x >= 1.0 {
        format!("{x:.1}")
    } else if x >= 0.01 {
        format!("{x:.2}")
    } else {
        "< 0.01".to_string()
    }
}

/// The thesis's figures: visited, winning, code size (lines), seconds.
type Published = Option<(u32, u32, u32, f64)>;

/// (example file, label, the thesis's figures).
const THESIS: &[(&str, &str, Published)] = &[
    ("lamp", "Lamp", Some((11, 10, 5, 0.0))),
    ("gear_checking", "GCM", Some((1660, 483, 30, 6.0))),
    ("round_table_1", "RT 1/8", Some((60, 51, 53, 0.0))),
    ("round_table_2", "RT 2/8", Some((206, 138, 141, 0.4))),
    ("round_table_3", "RT 3/8", Some((656, 330, 312, 1.1))),
    ("round_table_4", "RT 4/8", Some((2118, 841, 773, 5.5))),
    ("round_table_5", "RT 5/8", None),
    ("round_table_6", "RT 6/8", None),
    ("round_table_7", "RT 7/8", None),
    ("round_table_8", "RT 8/8", None),
    ("round_table_10_of_10", "RT 10/10", None),
    ("round_table_12_of_12", "RT 12/12", None),
    ("two_robots_14", "Robots 14 s", None),
];

/// The columns of the table beside the thesis's.
const TIMED_COLUMNS: &[Column] = &[
    ("example", false),
    ("verdict", false),
    ("visited", true),
    ("winning", true),
    ("visited/winning", true),
    ("code lines", true),
    ("time [ms]", true),
    ("state space [MiB]", true),
    ("reference visited", true),
    ("reference time [ms]", true),
    ("speed-up", true),
    ("thesis visited", true),
    ("thesis winning", true),
    ("thesis code", true),
    ("thesis time [s]", true),
];

/// The columns of the scan-game table.
const SCAN_COLUMNS: &[Column] = &[
    ("example", false),
    ("zero-time verdict", false),
    ("visited", true),
    ("winning", true),
    ("time [ms]", true),
    ("scan [ms]", true),
    ("scan verdict", false),
    ("visited", true),
    ("winning", true),
    ("time [ms]", true),
    ("visited ratio", true),
    ("time ratio", true),
];

/// Runs every example `runs` times and prints medians beside the thesis figures.
pub fn timed(examples_dir: &Path, runs: usize, format: Format) -> std::process::ExitCode {
    if format.headers {
        return print_headers(&[TIMED_COLUMNS, SCAN_COLUMNS]);
    }
    let md = format.markdown;
    // Times: one decimal as always, or rounded for reading in markdown.
    let t = |x: f64| if md { ms(x) } else { format!("{x:.1}") };
    if md {
        print_caption("timed", runs);
    } else {
        outln!(
            "Timed-game synthesis: plcsynth (median of {runs} runs) beside Peter 2005, table 7.3 (Pentium III 1.2 GHz)"
        );
        outln!();
        outln!("The search expands only the strategy it builds; the reference (`--exhaustive`, the thesis's");
        outln!("breadth-first algorithm) explores the whole reachable game, run once, in the same process.");
    }
    outln!();
    print_header(TIMED_COLUMNS);
    for (file, label, thesis) in THESIS {
        let path = examples_dir.join(format!("{file}.tga"));
        let Ok(source) = std::fs::read_to_string(&path) else {
            eprintln!("missing {}", path.display());
            return std::process::ExitCode::from(2);
        };
        let (game, _) = match compile(&source) {
            Ok(ok) => ok,
            Err(_) => {
                eprintln!("{} does not compile", path.display());
                return std::process::ExitCode::from(2);
            }
        };
        let mut times = Vec::new();
        let mut last = None;
        for _ in 0..runs.max(1) {
            let started = Instant::now();
            // The default budgets solve every example, round table 8/8 included.
            let s = synthesize(&game, &Config::default(), &mut |_| true);
            times.push(started.elapsed().as_secs_f64() * 1000.0);
            last = Some(s);
        }
        times.sort_by(f64::total_cmp);
        let median = times[times.len() / 2];
        let s = last.expect("at least one run");
        let st = &s.solution.stats;
        let verdict = word(&s.solution, "realizable", "unrealizable");
        let (tv, tw, tc, tt) = match thesis {
            Some((v, w, c, t)) => (v.to_string(), w.to_string(), c.to_string(), format!("{t:.1}")),
            None if file.starts_with("round_table_5") => ("out of memory".into(), "–".into(), "–".into(), "–".into()),
            None => ("–".into(), "–".into(), "–".into(), "–".into()),
        };
        let lines = plcsynth::timed::program::controller(&game, &s).map_or("–".to_string(), |p| p.len().to_string());
        let started = Instant::now();
        let reference = synthesize(&game, &Config { exhaustive: true, ..Config::default() }, &mut |_| true);
        let reference_ms = started.elapsed().as_secs_f64() * 1000.0;
        let (rv, rt, speedup) = match reference.solution.outcome {
            Err(_) => ("budget exceeded".to_string(), t(reference_ms), "–".to_string()),
            _ => (
                reference.solution.stats.visited.to_string(),
                t(reference_ms),
                format!("{:.0}×", reference_ms / median.max(0.001)),
            ),
        };
        let ratio = st.visited as f64 / st.winning.max(1) as f64;
        outln!(
            "| {label} | {verdict} | {} | {} | {ratio:.1} | {lines} | {} | {:.1} | {rv} | {rt} | {speedup} | {tv} | {tw} | {tc} | {tt} |",
            st.visited,
            st.winning,
            t(median),
            st.bytes as f64 / (1024.0 * 1024.0)
        );
    }
    scan_table(examples_dir, runs, md);
    if let Some(peak) = peak_rss_kib().filter(|_| !md) {
        outln!();
        outln!("peak resident memory of this process: {:.1} MiB", peak as f64 / 1024.0);
    }
    std::process::ExitCode::SUCCESS
}

/// The scan time of the scan-game table: the example's own `scan`, else this.
const BENCH_SCAN_MS: u64 = 10;

/// Every example at a PLC's scan time beside its zero-time verdict: what the scan semantics
/// costs (states and time, as a ratio measured in the same run). The scan time includes the
/// zero-time solves that build its guide (`timed::scan_guide`). The thesis has no such figures.
fn scan_table(examples_dir: &Path, runs: usize, md: bool) {
    let t = |x: f64| if md { ms(x) } else { format!("{x:.1}") };
    outln!();
    if !md {
        outln!(
            "At a PLC scan time (the example's `scan`, else {BENCH_SCAN_MS} ms; default budgets; median of {runs} runs): the zero-time game beside the scan game (its search guided by zero-time strategies, whose solves its time includes)"
        );
        outln!();
    }
    print_header(SCAN_COLUMNS);
    let mut files: Vec<_> = std::fs::read_dir(examples_dir)
        .map(|d| {
            d.filter_map(|e| e.ok()).map(|e| e.path()).filter(|p| p.extension().is_some_and(|x| x == "tga")).collect()
        })
        .unwrap_or_default();
    files.sort();
    let median = |mut times: Vec<f64>| {
        times.sort_by(f64::total_cmp);
        times[times.len() / 2]
    };
    for path in files {
        let Ok(source) = std::fs::read_to_string(&path) else { continue };
        let Ok((game, _)) = compile(&source) else { continue };
        let name = path.file_stem().and_then(|s| s.to_str()).unwrap_or("?");
        let scan_ms = game.scan_ms.map_or(BENCH_SCAN_MS, |(ms, _)| ms);
        let (mut zero_times, mut scan_times) = (Vec::new(), Vec::new());
        let mut last = None;
        for _ in 0..runs.max(1) {
            let started = Instant::now();
            let zero = synthesize(&game, &Config::default(), &mut |_| true);
            zero_times.push(started.elapsed().as_secs_f64() * 1000.0);
            let started = Instant::now();
            let scan = plcsynth::timed::synthesize_at_scan(&game, scan_ms, &Config::default(), &mut |_| true);
            scan_times.push(started.elapsed().as_secs_f64() * 1000.0);
            last = Some((zero, scan));
        }
        let Some((zero, Ok(scan))) = last else { continue };
        let (zt, st) = (median(zero_times), median(scan_times));
        let (z, sc) = (&zero.solution.stats, &scan.synthesis.solution.stats);
        outln!(
            "| {name} | {} | {} | {} | {} | {scan_ms} | {} | {} | {} | {} | {:.0}× | {:.0}× |",
            word(&zero.solution, "realizable", "unrealizable"),
            z.visited,
            z.winning,
            t(zt),
            word(&scan.synthesis.solution, "implementable", "not implementable"),
            sc.visited,
            sc.winning,
            t(st),
            sc.visited as f64 / z.visited.max(1) as f64,
            st / zt.max(1e-3)
        );
    }
}

/// Peak resident set size from /proc (Linux), in KiB.
fn peak_rss_kib() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    line.split_whitespace().nth(1)?.parse().ok()
}

/// A solution's outcome in a table: the given words for the two verdicts, else the stop.
fn word(solution: &Solution, realizable: &'static str, not: &'static str) -> &'static str {
    match solution.outcome {
        Ok(Verdict::Realizable) => realizable,
        Ok(Verdict::Unrealizable) => not,
        Err(Stop::Budget { .. }) => "budget exceeded",
        Err(Stop::Cancelled) => "cancelled",
    }
}
