//! `plcsynth bench timed`: our figures beside the published ones (Peter 2005, table of 7.3).

use plcsynth::timed::{compile, solve::SolveOptions, solve::Verdict, synthesize};
use std::path::Path;
use std::time::Instant;

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

/// Runs every example `runs` times and prints medians beside the thesis figures.
pub fn timed(examples_dir: &Path, runs: usize) -> std::process::ExitCode {
    outln!("Timed-game synthesis: plcsynth (median of {runs} runs) beside Peter 2005, table 7.3 (Pentium III 1.2 GHz)");
    outln!();
    outln!("The search expands only the strategy it builds; the reference (`--exhaustive`, the thesis's");
    outln!("breadth-first algorithm) explores the whole reachable game, run once, in the same process.");
    outln!();
    outln!("| example | verdict | visited | winning | visited/winning | code lines | time [ms] | state space [MiB] | reference visited | reference time [ms] | speed-up | thesis visited | thesis winning | thesis code | thesis time [s] |");
    outln!("|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|");
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
            let s = synthesize(&game, &SolveOptions::default(), &mut |_| true);
            times.push(started.elapsed().as_secs_f64() * 1000.0);
            last = Some(s);
        }
        times.sort_by(f64::total_cmp);
        let median = times[times.len() / 2];
        let s = last.expect("at least one run");
        let st = &s.solution.stats;
        let verdict = match s.solution.verdict {
            Verdict::Realizable => "realizable",
            Verdict::Unrealizable => "unrealizable",
            Verdict::BudgetExceeded => "budget exceeded",
            Verdict::Cancelled => "cancelled",
        };
        let (tv, tw, tc, tt) = match thesis {
            Some((v, w, c, t)) => (v.to_string(), w.to_string(), c.to_string(), format!("{t:.1}")),
            None if file.starts_with("round_table_5") => ("out of memory".into(), "–".into(), "–".into(), "–".into()),
            None => ("–".into(), "–".into(), "–".into(), "–".into()),
        };
        let lines = plcsynth::program::controller(&game, &s).map_or("–".to_string(), |p| p.len().to_string());
        let started = Instant::now();
        let reference = synthesize(&game, &SolveOptions { exhaustive: true, ..SolveOptions::default() }, &mut |_| true);
        let reference_ms = started.elapsed().as_secs_f64() * 1000.0;
        let (rv, rt, speedup) = match reference.solution.verdict {
            Verdict::BudgetExceeded => ("budget exceeded".to_string(), format!("{reference_ms:.1}"), "–".to_string()),
            _ => (
                reference.solution.stats.visited.to_string(),
                format!("{reference_ms:.1}"),
                format!("{:.0}×", reference_ms / median.max(0.001)),
            ),
        };
        let ratio = st.visited as f64 / st.winning.max(1) as f64;
        outln!(
            "| {label} | {verdict} | {} | {} | {ratio:.1} | {lines} | {median:.1} | {:.1} | {rv} | {rt} | {speedup} | {tv} | {tw} | {tc} | {tt} |",
            st.visited,
            st.winning,
            st.bytes as f64 / (1024.0 * 1024.0)
        );
    }
    scan_table(examples_dir, runs);
    if let Some(peak) = peak_rss_kib() {
        outln!();
        outln!("peak resident memory of this process: {:.1} MiB", peak as f64 / 1024.0);
    }
    std::process::ExitCode::SUCCESS
}

/// The scan time of the scan-game table: the example's own `scan`, else this.
const BENCH_SCAN_MS: u64 = 10;

/// Every example at a PLC's scan time beside its zero-time verdict: what the scan semantics
/// costs (states and time, as a ratio measured in the same run). The thesis has no such figures.
fn scan_table(examples_dir: &Path, runs: usize) {
    outln!();
    outln!(
        "At a PLC scan time (the example's `scan`, else {BENCH_SCAN_MS} ms; default budgets; median of {runs} runs): the zero-time game beside the scan game"
    );
    outln!();
    outln!("| example | zero-time verdict | visited | time [ms] | scan [ms] | scan verdict | visited | time [ms] | time ratio |");
    outln!("|---|---|---:|---:|---:|---|---:|---:|---:|");
    let mut files: Vec<_> = std::fs::read_dir(examples_dir)
        .map(|d| {
            d.filter_map(|e| e.ok()).map(|e| e.path()).filter(|p| p.extension().is_some_and(|x| x == "tga")).collect()
        })
        .unwrap_or_default();
    // The larger round tables (`round_table_P_of_P`) exceed the default budget at a scan time
    // after seconds each: left out of this table.
    files.retain(|p: &std::path::PathBuf| !p.to_string_lossy().contains("_of_"));
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
            let zero = synthesize(&game, &SolveOptions::default(), &mut |_| true);
            zero_times.push(started.elapsed().as_secs_f64() * 1000.0);
            let started = Instant::now();
            let scan = plcsynth::timed::synthesize_at_scan(&game, scan_ms, &SolveOptions::default(), &mut |_| true);
            scan_times.push(started.elapsed().as_secs_f64() * 1000.0);
            last = Some((zero, scan));
        }
        let Some((zero, Ok(scan))) = last else { continue };
        let word = |v: Verdict, realizable: &'static str, not: &'static str| match v {
            Verdict::Realizable => realizable,
            Verdict::Unrealizable => not,
            Verdict::BudgetExceeded => "budget exceeded",
            Verdict::Cancelled => "cancelled",
        };
        let (zt, st) = (median(zero_times), median(scan_times));
        outln!(
            "| {name} | {} | {} | {zt:.1} | {scan_ms} | {} | {} | {st:.1} | {:.0}× |",
            word(zero.solution.verdict, "realizable", "unrealizable"),
            zero.solution.stats.visited,
            word(scan.synthesis.solution.verdict, "implementable", "not implementable"),
            scan.synthesis.solution.stats.visited,
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
