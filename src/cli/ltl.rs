//! `plcsynth ltl`: LTL synthesis of G4LTL or TLSF specifications.

use super::bench::{print_caption, print_header, print_headers, Column};
use clap::Args;
use plcsynth::diag::render_plain;
use plcsynth::ltl::{self, Config, Format, Verdict};
use plcsynth::plc;
use std::process::ExitCode;

#[derive(Clone, Copy, Debug, clap::ValueEnum)]
pub enum SolverArg {
    Explicit,
    Antichain,
    Symbolic,
    Bdd,
    Gr1,
}

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
    /// How the bounded games are solved: `explicit` (every reachable position; the default),
    /// `antichain` (the fixpoint on maximal winning positions), `symbolic` (the explicit
    /// solver's positions, letters as decision diagrams: no 2^n enumeration, up to 63 signals)
    /// `bdd` (positions and letters as BDDs: no position enumerated; `--max-states N` caps
    /// each game's diagram at 16·N nodes), or `gr1` (no bounded games: a GR(1) game over
    /// monitors of the conjuncts, for invariants, responses and until/release obligations;
    /// other specifications are refused with the conjunct named).
    #[arg(long, value_enum, default_value = "explicit")]
    pub solver: SolverArg,
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
    /// The form of --io-table: csv (the signal table) or codesys (the CODESYS I/O mapping
    /// list, semicolon-separated).
    #[arg(long, value_enum, value_name = "FORMAT", requires = "io_table")]
    pub io_format: Option<super::IoFormat>,
    /// The function block's name (default `FB_` and the TLSF title, or `FB_Controller`).
    #[arg(long, value_name = "NAME", requires = "target")]
    pub name: Option<String>,
    /// After an unrealizable verdict, search environment assumptions that make the
    /// specification realizable, and print each with the controller it allows
    /// (docs/ltl-language.md, "Assumption suggestions"). Nothing extra for other verdicts.
    #[arg(long, conflicts_with = "target")]
    pub suggest: bool,
    /// Solve the whole specification at once, not its groups of guarantees with their own
    /// outputs first (the verdict is the same).
    #[arg(long)]
    pub monolithic: bool,
    /// Decide the Boolean abstraction only: learn no timer facts and no exclusions of
    /// predicate combinations from counter-strategies.
    #[arg(long)]
    pub no_refine: bool,
    /// Write the specification in the input syntax G4LTL reads instead of deciding it (a TLSF
    /// file, or ours with `<->`, `//` comments or patterns, becomes a file G4LTL can decide);
    /// what G4LTL cannot express is refused with a located error (exit status 2).
    #[arg(long, conflicts_with_all = ["json", "target", "suggest"])]
    pub to_g4ltl: bool,
    /// With --solver gr1: build the controller as a circuit (latches, and per goal the
    /// outputs as Boolean functions) and generate code from it, even when its table fits.
    /// Without the flag gr1 builds the circuit only when the table would pass --max-states.
    #[arg(long)]
    pub circuit: bool,
    /// With --suggest: add at most N assumptions (one set).
    #[arg(long, value_name = "N", default_value_t = 3, requires = "suggest", value_parser = clap::value_parser!(u64).range(1..=10))]
    pub suggest_max: u64,
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
    if a.to_g4ltl {
        return match ltl::to_g4ltl(&source, &spec) {
            Ok(text) => {
                outln!("## {} written for G4LTL by plcsynth ltl --to-g4ltl", a.file);
                outln!("{}", text.trim_end());
                ExitCode::SUCCESS
            }
            Err(diagnostics) => {
                eprint!("{}", render_plain(&a.file, &source, &diagnostics));
                ExitCode::from(2)
            }
        };
    }
    let solver = match a.solver {
        SolverArg::Explicit => ltl::Solver::Explicit,
        SolverArg::Antichain => ltl::Solver::Antichain,
        SolverArg::Symbolic => ltl::Solver::Symbolic,
        SolverArg::Bdd => ltl::Solver::Bdd,
        SolverArg::Gr1 => ltl::Solver::Gr1,
    };
    let cfg = Config::default()
        .max_k(a.max_k)
        .max_states(a.max_states)
        .max_work(a.max_work)
        .solver(solver)
        .compositional(!a.monolithic)
        .refine(!a.no_refine)
        .circuit(a.circuit);
    let outcome = match ltl::synthesize(&spec, &cfg, &mut |_| true) {
        Ok(outcome) => outcome,
        Err(stop) => {
            eprintln!("{}: stopped: {stop}", a.file);
            return ExitCode::from(3);
        }
    };
    if let Some(target) = a.target {
        if outcome.controller.is_none() && outcome.circuit.is_none() {
            eprintln!("{}: {}; no code written", a.file, ltl::summary(&outcome));
            return exit_code(outcome.verdict);
        }
        return write_code(a, target, &source, &spec, &outcome);
    }
    let suggestions = if a.suggest && outcome.verdict == Verdict::Unrealizable {
        let scfg = ltl::SuggestConfig { max_assumptions: a.suggest_max as usize, ..ltl::SuggestConfig::default() };
        match ltl::suggest(&spec, &outcome, &cfg, &scfg, &mut |_| true) {
            Ok(s) => Some(s),
            Err(stop) => {
                eprintln!("{}: suggestions stopped: {stop}", a.file);
                None
            }
        }
    } else {
        None
    };
    if a.json {
        let mut doc = ltl::report_json(&spec, &outcome);
        if let Some(s) = &suggestions {
            add_suggestions_json(&mut doc, &spec, s);
        }
        outln!("{doc}");
    } else {
        outln!("{}", ltl::summary(&outcome));
        outln!("specification: {}", spec.formula_text());
        for p in &spec.predicates {
            outln!("predicate: {} := {}", spec.name(p.signal), spec.predicate_text(p));
        }
        for learned in &outcome.refinement.learned {
            outln!("learned: ASSUME {}  ({})", learned.formula, learned.reason);
        }
        for w in &outcome.refinement.witnesses {
            let values: Vec<String> = w.values.iter().map(|(n, v)| format!("{n} = {v}")).collect();
            outln!("possible: {} with {}", w.combination, values.join(", "));
        }
        if outcome.groups.len() > 1 {
            outln!(
                "compositional: {} groups of guarantees with their own outputs, each solved alone:",
                outcome.groups.len()
            );
            for (i, g) in outcome.groups.iter().enumerate() {
                let outs: Vec<&str> = g.outputs.iter().map(|&s| spec.name(s)).collect();
                let states = g.controller.as_ref().map_or(0, |m| m.states.len());
                outln!(
                    "  group {}: guarantees {:?}, writes {}; {} states at k = {}",
                    i + 1,
                    g.guarantees.iter().map(|i| i + 1).collect::<Vec<_>>(),
                    outs.join(", "),
                    states,
                    g.k
                );
            }
            outln!("(the controller below is the groups' machines run side by side)");
        } else if outcome.split > 1 {
            outln!("compositional: {} groups, not all realizable alone; decided as a whole", outcome.split);
        }
        if let Some(m) = &outcome.controller {
            outln!("controller (state: inputs / outputs -> next):");
            outln!("{}", ltl::render_machine(&spec, m).trim_end());
        }
        if let Some(c) = &outcome.circuit {
            outln!("controller circuit (latches, then per goal the outputs):");
            outln!("{}", c.render(&spec).trim_end());
        }
        if let Some(m) = &outcome.counter_strategy {
            outln!("the environment's counter-strategy, unfolded from its initial state:");
            outln!("{}", ltl::render_tree(&spec, m).trim_end());
        }
        if let Some(s) = &suggestions {
            print_suggestions(&spec, s);
        }
    }
    exit_code(outcome.verdict)
}

/// The `--suggest` keys of `--json`: `suggestions`, `suggest_play`, and `suggest_limit` when
/// nothing was found.
fn add_suggestions_json(doc: &mut serde_json::Value, spec: &ltl::Spec, s: &ltl::Suggestions) {
    doc["suggestions"] = s.to_json();
    if let Some(play) = &s.play {
        doc["suggest_play"] = serde_json::json!(play.describe(spec));
    }
    doc["suggest_tried"] = serde_json::json!(s.tried);
    if let Some(limit) = &s.limit {
        doc["suggest_limit"] = serde_json::json!(limit);
    }
}

/// The `--suggest` section of the text report.
fn print_suggestions(spec: &ltl::Spec, s: &ltl::Suggestions) {
    if let Some(play) = &s.play {
        outln!("longest play the counter-strategy forces: {}", play.describe(spec));
    }
    outln!("assumption suggestions ({} candidates from the templates, {} re-syntheses):", s.candidates, s.tried);
    if s.found.is_empty() {
        outln!("none: {}", s.limit.as_deref().unwrap_or("no candidate made the specification realizable"));
    }
    // The best few; `--json` lists them all.
    const SHOWN: usize = 5;
    for (i, found) in s.found.iter().take(SHOWN).enumerate() {
        let patterns: Vec<&str> = found.templates.iter().map(|t| t.pattern()).collect();
        outln!("{}. ASSUME {}   (template {})", i + 1, found.texts().join(" ; ASSUME "), patterns.join(" + "));
        let m = found.controller();
        outln!(
            "   realizable at k = {}: a controller of {} states, {} rows",
            found.outcome.k,
            m.states.len(),
            m.rows()
        );
        for line in ltl::render_machine(&found.spec, m).lines() {
            outln!("   {line}");
        }
    }
    if s.found.len() > SHOWN {
        outln!("... and {} more (--json lists every suggestion)", s.found.len() - SHOWN);
    }
}

fn exit_code(verdict: Verdict) -> ExitCode {
    ExitCode::from(match verdict {
        Verdict::Realizable => 0,
        Verdict::Unrealizable => 1,
        Verdict::Unknown => 3,
    })
}

/// Lowers the controller into a function block (`plc::lower::ltl`) and writes it for `target`.
fn write_code(a: &LtlArgs, target: plc::Target, source: &str, spec: &ltl::Spec, outcome: &ltl::Synthesis) -> ExitCode {
    let options = plc::lower::ltl::LowerOptions { name: a.name.clone() };
    let unit = match plc::lower::ltl::lower_outcome(source, spec, outcome, &options).expect("a controller") {
        Ok(unit) => unit,
        Err(diags) => {
            eprint!("{}", render_plain(&a.file, source, &diags));
            eprintln!("{}: nothing written", a.file);
            return ExitCode::from(2);
        }
    };
    super::write_unit(&unit, target, plc::Options::default(), a.io_table.as_deref(), a.io_format, a.output.as_deref())
}

#[derive(Args)]
pub struct BenchArgs {
    /// Runs per specification; the median time is printed.
    #[arg(long, default_value_t = 5)]
    pub runs: usize,
    /// The folder of the public test data (G4LTL files in `g4ltl/`, TLSF in `tlsf/`).
    #[arg(long, default_value = "../shared/ltl")]
    pub data: std::path::PathBuf,
    /// The folder of our examples (the table beside the paper's table 2, and --compare-g4ltl).
    #[arg(long, default_value = "examples/ltl")]
    pub examples: std::path::PathBuf,
    /// Instead of the tables: decide every G4LTL demo, the SYNTCOMP instances up to n = 2 and
    /// our examples with plcsynth and with G4LTL itself, and print both verdicts and times.
    /// PATH: G4LTL's compiled classes (a folder, or a jar) with the jars it needs beside them
    /// (docs/ltl-language.md, "Beside G4LTL"); needs `javac` and `java`.
    #[arg(long, value_name = "PATH")]
    pub compare_g4ltl: Option<std::path::PathBuf>,
    /// With --compare-g4ltl: seconds G4LTL may spend on one file.
    #[arg(long, value_name = "SECONDS", default_value_t = 60)]
    pub g4ltl_timeout: u64,
    /// With --compare-g4ltl: the largest unroll depth G4LTL tries (it starts at 1).
    #[arg(long, value_name = "K", default_value_t = 3)]
    pub g4ltl_max_unroll: u32,
    /// Instead of the tables: SYNTCOMP's parametric families at growing n (simple_arbiter up
    /// to n = 12, full_arbiter and load_balancer up to 5, the prioritized and round-robin
    /// arbiters at 4, the `_unreal` variants), each decided once by the explicit and the bdd
    /// solver at the default budgets.
    #[arg(long, conflicts_with = "compare_g4ltl")]
    pub scale: bool,
    /// With --scale: seconds one solver may spend on one instance before it is cancelled.
    #[arg(long, value_name = "SECONDS", default_value_t = 60)]
    pub scale_timeout: u64,
    /// Build the comparison from recorded driver output instead of running G4LTL (tests).
    #[arg(long, value_name = "FILE", hide = true, conflicts_with = "compare_g4ltl")]
    pub g4ltl_replay: Option<std::path::PathBuf>,
    #[command(flatten)]
    pub format: super::bench::Format,
}

/// G4LTL's own verdicts at unroll depths 1 and 3 (`../shared/ltl/README.md`).
pub(super) const G4LTL: &[(&str, &str, &str)] = &[
    ("ptii_Arbitor", "realizable", "realizable"),
    ("ptii_PriorityArbitor", "unknown", "realizable"),
    ("ptii_ErrorHandling", "unknown", "realizable"),
    ("ptii_HydraulicRamp", "realizable", "realizable"),
    ("ptii_NumericalOriginal", "unrealizable", "unrealizable"),
    ("ptii_NumericalRefined", "realizable", "realizable"),
    ("ptii_AutomaticDoor", "unknown", "unknown (cannot parse `<->`)"),
    ("sample", "unknown", "realizable"),
    ("example1", "unrealizable", "unrealizable"),
    ("example1_ass", "realizable", "realizable"),
    ("example2", "unrealizable", "unrealizable"),
    ("example3", "unrealizable", "unrealizable"),
    ("example4", "unknown", "realizable"),
    ("paper_appC_grant", "realizable", "realizable"),
    ("paper_fig1_abstract", "unrealizable", "–"),
    ("paper_fig1_refined", "unknown", "realizable"),
];

/// SYNTCOMP instances: file under `tlsf/`, parameter n (if any), the known status and the
/// reference controller size of the family's table (states of the reference solution's
/// circuit, where listed).
pub(super) const SYNTCOMP: &[(&str, Option<i64>, &str)] = &[
    ("simple_arbiter/simple_arbiter.tlsf", Some(2), "realizable"),
    ("simple_arbiter/simple_arbiter.tlsf", Some(3), "realizable"),
    ("simple_arbiter_unreal/simple_arbiter_unreal2.tlsf", Some(2), "unrealizable"),
    ("full_arbiter/full_arbiter.tlsf", Some(2), "realizable"),
    ("full_arbiter/full_arbiter.tlsf", Some(3), "realizable"),
    ("prioritized_arbiter/prioritized_arbiter.tlsf", Some(2), "realizable"),
    ("prioritized_arbiter_unreal/prioritized_arbiter_unreal2.tlsf", Some(2), "unrealizable"),
    ("round_robin_arbiter/round_robin_arbiter.tlsf", Some(2), "realizable"),
    ("load_balancer/load_balancer.tlsf", Some(2), "realizable"),
    ("load_balancer/load_balancer.tlsf", Some(3), "realizable"),
    ("ltl2dba/ltl2dba_R.tlsf", Some(2), "unrealizable"),
    ("ltl2dba/ltl2dba_C2_unreal.tlsf", Some(2), "unrealizable"),
    ("ltl2dba/ltl2dba08.tlsf", None, "realizable"),
    ("ltl2dba/ltl2dba27.tlsf", None, "unrealizable"),
];

/// The paper's table 2 beside our specifications after appendix B: example, our file, timer
/// (T) / data (D), lines of specification, synthesis time, lines of ST, learned assumptions and
/// the time of learning (the paper's assumption-generation half; `–` where not listed).
/// One row of table 2, and our file for it.
struct Published {
    example: &'static str,
    file: &'static str,
    /// Timer (T), data (D).
    kind: &'static str,
    spec_lines: &'static str,
    time: &'static str,
    st_lines: &'static str,
    learned: &'static str,
    learning: &'static str,
}

const TABLE2: &[Published] = &[
    Published {
        example: "Ex1",
        file: "fig1.ltl",
        kind: "T, D",
        spec_lines: "9",
        time: "1.598 s (comp)",
        st_lines: "110",
        learned: "1",
        learning: "0.127 s",
    },
    Published {
        example: "Ex2",
        file: "ex2_discrepancy.ltl",
        kind: "T",
        spec_lines: "13",
        time: "0.691 s",
        st_lines: "148",
        learned: "1",
        learning: "0.452 s",
    },
    Published {
        example: "Ex3",
        file: "ex3_safety_request.ltl",
        kind: "T",
        spec_lines: "9",
        time: "0.303 s",
        st_lines: "80",
        learned: "1",
        learning: "3.486 s",
    },
    Published {
        example: "Ex4",
        file: "ex4_muting.ltl",
        kind: "T",
        spec_lines: "13",
        time: "21 s",
        st_lines: "1374",
        learned: "4",
        learning: "22 s (DFS)",
    },
    Published {
        example: "Ex5",
        file: "ex5_conveyor_alarm.ltl",
        kind: "T",
        spec_lines: "11",
        time: "0.678 s (comp)",
        st_lines: "210",
        learned: "1",
        learning: "2.107 s",
    },
    Published {
        example: "Ex7 (ours: a numeric arbiter)",
        file: "heating.ltl",
        kind: "D",
        spec_lines: "8",
        time: "17 s",
        st_lines: "43",
        learned: "1",
        learning: "0.154 s",
    },
    Published {
        example: "Ex8",
        file: "ex8_pick_place.ltl",
        kind: "T",
        spec_lines: "8",
        time: "0.397 s (comp)",
        st_lines: "653",
        learned: "1",
        learning: "2.877 s",
    },
];

/// Decides a specification `runs` times: the median milliseconds, the outcome, and the lines
/// of the controller's IEC Structured Text.
fn measure(
    source: &str,
    format: Format,
    params: &[(String, i64)],
    runs: usize,
) -> Result<(f64, ltl::Synthesis, Option<usize>), String> {
    let (spec, _) = ltl::compile(source, format, params).map_err(|d| format!("{} errors", d.len()))?;
    let mut times = Vec::new();
    let mut last = None;
    for _ in 0..runs.max(1) {
        let started = std::time::Instant::now();
        let outcome = ltl::synthesize(&spec, &Config::default(), &mut |_| true).map_err(|s| s.to_string())?;
        times.push(started.elapsed().as_secs_f64() * 1000.0);
        last = Some(outcome);
    }
    times.sort_by(f64::total_cmp);
    let outcome = last.expect("at least one run");
    let lines = outcome.controller.as_ref().and_then(|_| {
        let unit =
            plc::lower::ltl::lower_outcome(source, &spec, &outcome, &plc::lower::ltl::LowerOptions::default())?.ok()?;
        let files = plc::render_unit_files(&unit, plc::Target::St, &plc::Options::default()).ok()?;
        Some(files.iter().map(|f| f.text.lines().count()).sum())
    });
    Ok((times[times.len() / 2], outcome, lines))
}

fn cells(outcome: &ltl::Synthesis) -> (String, String) {
    let verdict = format!("{:?} (k = {})", outcome.verdict, outcome.k).to_lowercase();
    let size = outcome
        .controller
        .as_ref()
        .or(outcome.counter_strategy.as_ref())
        .map_or("–".to_string(), |m| format!("{} / {}", m.states.len(), m.rows()));
    (verdict, size)
}

/// The columns of the G4LTL table.
const G4LTL_COLUMNS: &[Column] = &[
    ("specification", false),
    ("verdict", false),
    ("time [ms]", true),
    ("strategy states / rows", true),
    ("ST lines", true),
    ("G4LTL k = 1", false),
    ("G4LTL k = 3", false),
];

/// The columns of the SYNTCOMP table.
const SYNTCOMP_COLUMNS: &[Column] = &[
    ("SYNTCOMP instance", false),
    ("verdict", false),
    ("time [ms]", true),
    ("strategy states / rows", true),
    ("ST lines", true),
    ("status", false),
];

/// The columns of the table beside the paper's table 2.
const TABLE2_COLUMNS: &[Column] = &[
    ("example", false),
    ("ours", false),
    ("verdict", false),
    ("time [ms]", true),
    ("groups", true),
    ("learned (refinement)", true),
    ("ST lines", true),
    ("spec lines (ours / paper)", false),
    ("paper: T/D, time, ST lines", false),
    ("paper: assumptions generated, time (section 4)", false),
];

/// `plcsynth bench ltl`: every listed specification, our time and sizes beside the
/// published verdicts.
pub fn bench(a: &BenchArgs) -> ExitCode {
    if a.compare_g4ltl.is_some() || a.g4ltl_replay.is_some() {
        return super::ltl_compare::compare(a);
    }
    if a.scale {
        return super::ltl_scale::scale(a);
    }
    if a.format.headers {
        return print_headers(&[G4LTL_COLUMNS, SYNTCOMP_COLUMNS, TABLE2_COLUMNS]);
    }
    let md = a.format.markdown;
    // Times: two decimals as always, or rounded for reading in markdown.
    let t = |x: f64| if md { super::bench::ms(x) } else { format!("{x:.2}") };
    if md {
        print_caption("ltl", a.runs);
    } else {
        outln!(
            "LTL synthesis: plcsynth (median of {} runs) beside G4LTL (../shared/ltl/README.md) and SYNTCOMP",
            a.runs
        );
    }
    outln!();
    print_header(G4LTL_COLUMNS);
    let mut slowest: f64 = 0.0;
    for (file, k1, k3) in G4LTL {
        let path = a.data.join(format!("g4ltl/{file}.g4ltl"));
        let Ok(source) = std::fs::read_to_string(&path) else {
            eprintln!("missing {}", path.display());
            return ExitCode::from(2);
        };
        match measure(&source, Format::G4ltl, &[], a.runs) {
            Ok((ms, outcome, lines)) => {
                slowest = slowest.max(ms);
                let (verdict, size) = cells(&outcome);
                let lines = lines.map_or("–".into(), |l| l.to_string());
                outln!("| {file} | {verdict} | {} | {size} | {lines} | {k1} | {k3} |", t(ms));
            }
            Err(e) => outln!("| {file} | {e} | | | | {k1} | {k3} |"),
        }
    }
    outln!();
    print_header(SYNTCOMP_COLUMNS);
    for (file, n, status) in SYNTCOMP {
        let path = a.data.join(format!("tlsf/{file}"));
        let Ok(source) = std::fs::read_to_string(&path) else {
            eprintln!("missing {}", path.display());
            return ExitCode::from(2);
        };
        let params: Vec<(String, i64)> = n.iter().map(|&n| ("n".to_string(), n)).collect();
        let label = match n {
            Some(n) => format!("{} n = {n}", file.rsplit('/').next().unwrap_or(file)),
            None => file.rsplit('/').next().unwrap_or(file).to_string(),
        };
        match measure(&source, Format::Tlsf, &params, a.runs) {
            Ok((ms, outcome, lines)) => {
                slowest = slowest.max(ms);
                let (verdict, size) = cells(&outcome);
                let lines = lines.map_or("–".into(), |l| l.to_string());
                outln!("| {label} | {verdict} | {} | {size} | {lines} | {status} |", t(ms));
            }
            Err(e) => outln!("| {label} | {e} | | | | {status} |"),
        }
    }
    outln!();
    if !md {
        outln!(
            "The paper's table 2 (G4LTL-ST, unroll depth 3, 2014 hardware) beside our specifications after its appendix B"
        );
        outln!("(its specifications are not public: ours are written from the descriptions, so sizes differ):");
        outln!();
    }
    print_header(TABLE2_COLUMNS);
    for Published { example, file, kind: td, spec_lines, time, st_lines: st, learned, learning } in TABLE2 {
        let path = a.examples.join(file);
        let Ok(source) = std::fs::read_to_string(&path) else {
            eprintln!("missing {} (run from the repository's root)", path.display());
            return ExitCode::from(2);
        };
        let ours = source.lines().filter(|l| !l.trim().is_empty() && !l.trim_start().starts_with("//")).count();
        match measure(&source, Format::G4ltl, &[], a.runs) {
            Ok((ms, outcome, lines)) => {
                let verdict = format!("{:?} (k = {})", outcome.verdict, outcome.k).to_lowercase();
                let groups = outcome.groups.len().max(1);
                let lines = lines.map_or("–".into(), |l| l.to_string());
                let n = outcome.refinement.learned.len();
                outln!(
                    "| {example} | {file} | {verdict} | {} | {groups} | {n} | {lines} | {ours} / {spec_lines} | {td}, {time}, {st} | {learned}, {learning} |",
                    t(ms)
                );
            }
            Err(e) => outln!("| {example} | {file} | {e} | | | | | {ours} / {spec_lines} | {td}, {time}, {st} | {learned}, {learning} |"),
        }
    }
    if md {
        return ExitCode::SUCCESS;
    }
    outln!();
    outln!("slowest: {slowest:.1} ms (goal: every listed specification under 1 s).");
    outln!(
        "Learned (refinement): assumptions our loop added (timer facts, exclusions of predicate combinations). The \
         paper's last column is its assumption generation (section 4, `plcsynth ltl --suggest` here), for reference."
    );
    ExitCode::SUCCESS
}
