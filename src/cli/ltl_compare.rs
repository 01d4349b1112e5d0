//! `plcsynth bench ltl --compare-g4ltl PATH`: our engine and G4LTL itself on the same
//! specifications in one run, with time and verdict for both.
//!
//! G4LTL (github.com/yyergg/g4ltl, Java) is not part of plcsynth: PATH holds its compiled
//! classes (or a jar) and the jars beside them. Our small driver `scripts/g4ltl/PlcsynthBatch.java`,
//! built into this binary, is compiled against PATH at bench time and decides every file with
//! G4LTL's co-Büchi engine, one JVM per file under a timeout, printing one line per file. G4LTL's
//! own demos go to it as written; TLSF instances and our examples go as `plcsynth ltl
//! --to-g4ltl` writes them; what G4LTL cannot express (numeric inputs) is not given to it.

use super::ltl::{BenchArgs, G4LTL, SYNTCOMP};
use plcsynth::ltl::{self, Config, Format, Verdict};
use std::collections::HashMap;
use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Command, ExitCode, Stdio};

/// The driver's source, compiled at bench time against the user's G4LTL.
const DRIVER: &str = include_str!("../../scripts/g4ltl/PlcsynthBatch.java");

/// The verdicts the data's README gives for G4LTL's demos: G4LTL's own at unroll depth 3
/// (depth 1 for `paper_fig1_abstract`), and for `ptii_AutomaticDoor`, which G4LTL cannot
/// parse, its header's claim.
const G4LTL_KNOWN: &[(&str, &str)] = &[
    ("ptii_Arbitor", "realizable"),
    ("ptii_PriorityArbitor", "realizable"),
    ("ptii_ErrorHandling", "realizable"),
    ("ptii_HydraulicRamp", "realizable"),
    ("ptii_NumericalOriginal", "unrealizable"),
    ("ptii_NumericalRefined", "realizable"),
    ("ptii_AutomaticDoor", "realizable"),
    ("sample", "realizable"),
    ("example1", "unrealizable"),
    ("example1_ass", "realizable"),
    ("example2", "unrealizable"),
    ("example3", "unrealizable"),
    ("example4", "realizable"),
    ("paper_appC_grant", "realizable"),
    ("paper_fig1_abstract", "unrealizable"),
    ("paper_fig1_refined", "realizable"),
];

/// One specification of the comparison.
struct Case {
    /// As shown in the table.
    label: String,
    /// The file name the driver reports it under (without extension): unique in the run.
    key: String,
    path: PathBuf,
    format: Format,
    params: Vec<(String, i64)>,
    /// Known verdict, from the data's README, SYNTCOMP or the example's `// Expected:` line.
    known: String,
    /// Whether G4LTL reads the file as written (its own demos) rather than our translation.
    native: bool,
}

/// G4LTL's answer for one file: one line of the driver.
#[derive(Debug, Clone, PartialEq)]
pub struct G4ltlResult {
    /// realizable, unrealizable, unknown, timeout or error.
    pub verdict: String,
    /// The unroll depth that decided (0 if none).
    pub unroll: u32,
    pub ms: u64,
    pub note: String,
}

/// The driver's output by file stem. Lines not starting with `g4ltl<TAB>` are not the
/// driver's and are skipped; a malformed driver line is an error naming its line.
pub fn parse_driver_output(text: &str) -> Result<HashMap<String, G4ltlResult>, String> {
    let mut out = HashMap::new();
    for (i, line) in text.lines().enumerate() {
        let Some(rest) = line.strip_prefix("g4ltl\t") else { continue };
        let fields: Vec<&str> = rest.split('\t').collect();
        let bad = |why: &str| format!("driver output line {}: {why}: `{line}`", i + 1);
        let [file, verdict, unroll, ms, note] = fields[..] else {
            return Err(bad("expected 6 tab-separated fields"));
        };
        if !["realizable", "unrealizable", "unknown", "timeout", "error"].contains(&verdict) {
            return Err(bad("unknown verdict"));
        }
        let unroll = unroll.parse().map_err(|_| bad("the unroll depth is not a number"))?;
        let ms = ms.parse().map_err(|_| bad("the time is not a number of milliseconds"))?;
        let stem = Path::new(file).file_stem().and_then(|s| s.to_str()).unwrap_or(file).to_string();
        let result = G4ltlResult { verdict: verdict.to_string(), unroll, ms, note: note.to_string() };
        out.insert(stem, result);
    }
    Ok(out)
}

/// The specifications compared: G4LTL's demos, the SYNTCOMP instances of `bench ltl` with n
/// at most 2 (G4LTL runs out of time on the larger ones), and our examples.
fn cases(data: &Path, examples: &Path) -> Result<Vec<Case>, String> {
    let mut cases = Vec::new();
    for (name, _, _) in G4LTL {
        let known = G4LTL_KNOWN.iter().find(|k| k.0 == *name).map_or("–", |k| k.1);
        cases.push(Case {
            label: name.to_string(),
            key: name.to_string(),
            path: data.join(format!("g4ltl/{name}.g4ltl")),
            format: Format::G4ltl,
            params: Vec::new(),
            known: known.to_string(),
            native: true,
        });
    }
    for (file, n, status) in SYNTCOMP.iter().filter(|s| s.1.is_none_or(|n| n <= 2)) {
        let stem = Path::new(file).file_stem().and_then(|s| s.to_str()).unwrap_or(file);
        let (label, key) = match n {
            Some(n) => (format!("{stem} n = {n}"), format!("{stem}_n{n}")),
            None => (stem.to_string(), stem.to_string()),
        };
        cases.push(Case {
            label,
            key,
            path: data.join(format!("tlsf/{file}")),
            format: Format::Tlsf,
            params: n.iter().map(|&n| ("n".to_string(), n)).collect(),
            known: status.to_string(),
            native: false,
        });
    }
    let mut files: Vec<PathBuf> = std::fs::read_dir(examples)
        .map_err(|e| format!("cannot read {}: {e} (run from the repository's root)", examples.display()))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "ltl" || x == "tlsf"))
        .collect();
    files.sort();
    for path in files {
        let name = path.file_name().and_then(|s| s.to_str()).unwrap_or("?").to_string();
        let text = std::fs::read_to_string(&path).map_err(|e| format!("{}: {e}", path.display()))?;
        let known = text.lines().find_map(|l| l.strip_prefix("// Expected: ")).unwrap_or("–").trim().to_string();
        cases.push(Case {
            key: name.replace('.', "_"),
            label: name,
            format: Format::of_path(&path.to_string_lossy()),
            path,
            params: Vec::new(),
            known,
            native: false,
        });
    }
    Ok(cases)
}

/// Our side of one row.
struct Ours {
    signals: String,
    /// `realizable`, `unrealizable`, `unknown`, or why it was not decided.
    verdict: String,
    k: u32,
    ms: f64,
    /// The file handed to G4LTL, or why none was.
    g4ltl_input: Result<PathBuf, String>,
}

/// Decides `case` `runs` times (median time) and writes the file G4LTL gets into `dir`.
fn ours(case: &Case, runs: usize, dir: &Path) -> Result<Ours, String> {
    let source =
        std::fs::read_to_string(&case.path).map_err(|e| format!("cannot read {}: {e}", case.path.display()))?;
    let (spec, _) = ltl::compile(&source, case.format, &case.params)
        .map_err(|d| format!("{}: {} errors", case.path.display(), d.len()))?;
    let mut times = Vec::new();
    let mut last = None;
    for _ in 0..runs.max(1) {
        let started = std::time::Instant::now();
        let outcome = ltl::synthesize(&spec, &Config::default(), &mut |_| true);
        times.push(started.elapsed().as_secs_f64() * 1000.0);
        last = Some(outcome);
    }
    times.sort_by(f64::total_cmp);
    let (verdict, k) = match last.expect("at least one run") {
        Ok(o) => (word(o.verdict).to_string(), o.k),
        Err(stop) => (format!("stopped: {stop}"), 0),
    };
    let g4ltl_input = if case.native {
        Ok(case.path.clone())
    } else {
        match ltl::to_g4ltl(&source, &spec) {
            Ok(text) => {
                let path = dir.join(format!("{}.ltl", case.key));
                let header = format!("## {} written for G4LTL by plcsynth ltl --to-g4ltl\n", case.label);
                std::fs::write(&path, header + &text).map_err(|e| format!("cannot write {}: {e}", path.display()))?;
                Ok(path)
            }
            Err(d) => Err(d.first().map_or("refused".to_string(), |d| d.message.clone())),
        }
    };
    // Predicates are inputs of the abstraction; the user wrote numeric inputs.
    let boolean = spec.inputs().into_iter().filter(|&s| spec.predicate_of(s).is_none()).count();
    let numeric = if spec.numeric.is_empty() { String::new() } else { format!(" + {} numeric", spec.numeric.len()) };
    let signals = format!("{boolean}{numeric} / {}", spec.outputs().len());
    Ok(Ours { signals, verdict, k, ms: times[times.len() / 2], g4ltl_input })
}

fn word(v: Verdict) -> &'static str {
    match v {
        Verdict::Realizable => "realizable",
        Verdict::Unrealizable => "unrealizable",
        Verdict::Unknown => "unknown",
    }
}

/// `PATH` and the jars in its folder, as a Java class path: a folder of classes (with
/// `jdd_104.jar` and `ltl2buchi.jar` in it) or a jar (with them beside it).
fn classpath(g4ltl: &Path, extra: &Path) -> Result<std::ffi::OsString, String> {
    let folder = if g4ltl.is_dir() {
        g4ltl.to_path_buf()
    } else if g4ltl.is_file() {
        g4ltl.parent().unwrap_or(Path::new(".")).to_path_buf()
    } else {
        return Err(format!("{}: no such folder or jar (G4LTL's compiled classes)", g4ltl.display()));
    };
    std::env::join_paths([g4ltl.to_path_buf(), folder.join("*"), extra.to_path_buf()]).map_err(|e| e.to_string())
}

/// Compiles the driver in `dir` against G4LTL and runs it on `files`; the driver's lines are
/// echoed to standard error as they come (a long run shows its progress, and `2>` records it).
fn run_driver(a: &BenchArgs, g4ltl: &Path, dir: &Path, files: &[PathBuf]) -> Result<String, String> {
    let source = dir.join("PlcsynthBatch.java");
    std::fs::write(&source, DRIVER).map_err(|e| format!("cannot write {}: {e}", source.display()))?;
    let classes = dir.join("classes");
    let cp = classpath(g4ltl, &classes)?;
    let javac = Command::new("javac")
        .args(["-nowarn", "-encoding", "UTF-8", "-cp"])
        .arg(&cp)
        .arg("-d")
        .arg(&classes)
        .arg(&source)
        .output()
        .map_err(|e| format!("cannot run javac (a JDK is needed): {e}"))?;
    if !javac.status.success() {
        return Err(format!(
            "javac could not compile the driver against {} (G4LTL's classes?):\n{}",
            g4ltl.display(),
            String::from_utf8_lossy(&javac.stderr)
        ));
    }
    let mut child = Command::new("java")
        .arg("-cp")
        .arg(&cp)
        .arg("g4ltl.PlcsynthBatch")
        .args(["--timeout", &a.g4ltl_timeout.to_string(), "--max-unroll", &a.g4ltl_max_unroll.to_string()])
        .args(files)
        .stdout(Stdio::piped())
        .spawn()
        .map_err(|e| format!("cannot run java: {e}"))?;
    let mut out = String::new();
    for line in BufReader::new(child.stdout.take().expect("piped")).lines() {
        let line = line.map_err(|e| e.to_string())?;
        eprintln!("{line}");
        out.push_str(&line);
        out.push('\n');
    }
    let status = child.wait().map_err(|e| e.to_string())?;
    if !status.success() {
        return Err(format!("the G4LTL driver ended with {status}"));
    }
    Ok(out)
}

/// The columns of the comparison.
const COLUMNS: &[super::bench::Column] = &[
    ("specification", false),
    ("inputs / outputs", false),
    ("plcsynth", false),
    ("time [ms]", true),
    ("G4LTL", false),
    ("time [ms]", true),
    ("G4LTL / plcsynth time", true),
    ("known", false),
    ("agree", false),
];

/// `bench ltl --compare-g4ltl PATH` (or `--g4ltl-replay FILE`, recorded driver output).
pub fn compare(a: &BenchArgs) -> ExitCode {
    match run(a) {
        Ok(code) => code,
        Err(message) => {
            eprintln!("error: {message}");
            ExitCode::from(2)
        }
    }
}

fn run(a: &BenchArgs) -> Result<ExitCode, String> {
    // Recorded output is checked before anything is decided, so a malformed file fails at once.
    let recorded = match &a.g4ltl_replay {
        Some(path) => {
            let text = std::fs::read_to_string(path).map_err(|e| format!("cannot read {}: {e}", path.display()))?;
            Some(parse_driver_output(&text)?)
        }
        None => None,
    };
    let cases = cases(&a.data, &a.examples)?;
    let dir = std::env::temp_dir().join(format!("plcsynth-g4ltl-{}", std::process::id()));
    std::fs::create_dir_all(&dir).map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
    let mut rows = Vec::new();
    for case in &cases {
        eprintln!("plcsynth: {}", case.label);
        rows.push(ours(case, a.runs, &dir)?);
    }
    let theirs = match (recorded, &a.compare_g4ltl) {
        (Some(recorded), _) => Ok(recorded),
        (None, Some(g4ltl)) => {
            let files: Vec<PathBuf> = rows.iter().filter_map(|r| r.g4ltl_input.clone().ok()).collect();
            run_driver(a, g4ltl, &dir, &files).and_then(|output| parse_driver_output(&output))
        }
        (None, None) => unreachable!("called only with --compare-g4ltl or --g4ltl-replay"),
    };
    let _ = std::fs::remove_dir_all(&dir);
    let theirs = theirs?;
    print_table(a, &cases, &rows, &theirs);
    Ok(ExitCode::SUCCESS)
}

fn print_table(a: &BenchArgs, cases: &[Case], rows: &[Ours], theirs: &HashMap<String, G4ltlResult>) {
    let t = super::bench::ms;
    outln!(
        "LTL synthesis: plcsynth (median of {} runs) and G4LTL (co-Büchi engine, monolithic, unroll depth 1 to {}, \
         {} s per file, one JVM per file) on the same specifications",
        a.runs.max(1),
        a.g4ltl_max_unroll,
        a.g4ltl_timeout
    );
    outln!();
    super::bench::print_header(COLUMNS);
    let (mut agree, mut disagree, mut undecided, mut not_given) = (0, 0, 0, 0);
    let mut ratios: Vec<f64> = Vec::new();
    for (case, ours) in cases.iter().zip(rows) {
        let ours_cell = format!("{} (k = {})", ours.verdict, ours.k);
        let translated = if case.native { "" } else { ", translated" };
        let (theirs_cell, theirs_ms, ratio, agrees) = match (&ours.g4ltl_input, theirs.get(&case.key)) {
            (Err(why), _) => {
                not_given += 1;
                (format!("not given: {why}"), "–".to_string(), "–".to_string(), "–")
            }
            (Ok(_), None) => {
                undecided += 1;
                ("no answer from the driver".to_string(), "–".to_string(), "–".to_string(), "–")
            }
            (Ok(_), Some(r)) => {
                let decided = r.verdict == "realizable" || r.verdict == "unrealizable";
                let cell = match r.verdict.as_str() {
                    "realizable" | "unrealizable" => format!("{} (depth {}{translated})", r.verdict, r.unroll),
                    "unknown" => format!("unknown up to depth {}{translated}", a.g4ltl_max_unroll),
                    "timeout" => format!("timeout{translated}"),
                    _ => format!("error: {}", r.note),
                };
                let ratio = r.ms as f64 / ours.ms.max(1e-3);
                let agrees = if !decided {
                    undecided += 1;
                    "–"
                } else if r.verdict == ours.verdict {
                    agree += 1;
                    ratios.push(ratio);
                    "yes"
                } else {
                    disagree += 1;
                    "no"
                };
                let ratio = if decided { format!("{ratio:.0}×") } else { "–".to_string() };
                (cell, r.ms.to_string(), ratio, agrees)
            }
        };
        outln!(
            "| {} | {} | {ours_cell} | {} | {theirs_cell} | {theirs_ms} | {ratio} | {} | {agrees} |",
            case.label,
            ours.signals,
            t(ours.ms),
            case.known
        );
    }
    outln!();
    ratios.sort_by(f64::total_cmp);
    let range = match (ratios.first(), ratios.last()) {
        (Some(lo), Some(hi)) => format!("; where both agree, G4LTL took {lo:.0}× to {hi:.0}× our time"),
        _ => String::new(),
    };
    outln!(
        "{agree} agree, {disagree} disagree, {undecided} undecided by G4LTL (unknown, timeout, error), \
         {not_given} not given to G4LTL{range}."
    );
}
