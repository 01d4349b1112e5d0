//! `plcsynth supervise`, `plcsynth supcon` and `plcsynth bench sct`.

use super::bench::{print_caption, print_header, print_headers, Column};
use clap::{Args, ValueEnum};
use plcsynth::benchmarks::textbook::{agv, small_factory, transfer_line, transfer_lines_classic};
use plcsynth::benchmarks::transfer::{extended_line, transfer_lines};
use plcsynth::diag::{render_plain, Diagnostics};
use plcsynth::plc;
use plcsynth::sct::classic::gen::{read_gen_file_within, write_gen, GenFile};
use plcsynth::sct::classic::wmod::{write_wmod, ComponentKind, ComponentOut};
use plcsynth::sct::classic::{minimize, supcon as classic_supcon, supcon_within, ClassicEventId, Events, SupConError};
use plcsynth::sct::model::dep_closure;
use plcsynth::sct::model::{Budget, Config, Method, DEFAULT_MAX_STATES};
use plcsynth::sct::{compile, compile_within, Outcome};
use plcsynth::sct::{synthesize, synthesize_within, Synthesis};
use std::process::{Command, ExitCode};
use std::time::Instant;

#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum MethodArg {
    Incremental,
    Monolithic,
}

#[derive(Args)]
pub struct SuperviseArgs {
    /// The `.sct` project file.
    pub file: String,
    /// Synthesis method.
    #[arg(long, value_enum, default_value = "incremental")]
    pub method: MethodArg,
    /// Print the supervisors as JSON (for the playground).
    #[arg(long)]
    pub json: bool,
    /// Do not use enforceable events to preempt uncontrollable ones.
    #[arg(long)]
    pub no_preemption: bool,
    /// Keep the supervisors unminimised.
    #[arg(long)]
    pub no_minimize: bool,
    /// Compose all specifications into one and synthesise a single supervisor `Composed`
    /// (the setting of 5.8.5; avoids enforcing an event another requirement prohibits, 6.4.2).
    #[arg(long)]
    pub compose: bool,
    /// State budget: the product states one run may build, shared by the specification products
    /// (written in the file or by `--compose`) and the synthesis of every specification; when it
    /// is spent, the run stops with exit status 3.
    #[arg(long, value_name = "N", default_value_t = DEFAULT_MAX_STATES)]
    pub max_states: usize,
    /// Generate the runtime framework (Göbe 2019, 6.3) for this PLC target instead of printing
    /// the report (docs/syrf.md).
    #[arg(long, value_parser = target_parser(), conflicts_with = "json")]
    pub target: Option<plc::Target>,
    /// With `--target`: write the framework to this file instead of standard output; for a
    /// target of several files (twincat) a directory, created if missing. Without: a file named
    /// `….wmod`, to which the supervisors are written as a Supremica module.
    #[arg(short, long)]
    pub output: Option<String>,
    /// Also write the signal table (CSV: address, type, symbol, direction, events).
    #[arg(long, value_name = "FILE", requires = "target")]
    pub io_table: Option<String>,
    /// The form of --io-table: csv (the signal table) or codesys (the CODESYS I/O mapping
    /// list, semicolon-separated).
    #[arg(long, value_enum, value_name = "FORMAT", requires = "io_table")]
    pub io_format: Option<super::IoFormat>,
    /// The function block type of the existing controller that the framework calls.
    #[arg(long, value_name = "TYPE", default_value = "Controller", requires = "target")]
    pub controller: String,
    /// Prefix of the framework's names (`SyRF_Main`, `SyRF_Execute`, ...).
    #[arg(long, value_name = "NAME", default_value = "SyRF", requires = "target")]
    pub name: String,
    /// STL: the organisation block that calls the framework's program.
    #[arg(long, value_name = "N", default_value_t = 1, value_parser = clap::value_parser!(u16).range(1..), requires = "target")]
    pub ob: u16,
    /// STL: the existing controller is FB N with instance DB N.
    #[arg(long, value_name = "N", default_value_t = 100, value_parser = clap::value_parser!(u16).range(1..), requires = "target")]
    pub controller_fb: u16,
}

/// The `--target` values of `supervise`: every PLC target, with its label as help.
pub(crate) fn target_parser() -> impl clap::builder::TypedValueParser<Value = plc::Target> {
    use clap::builder::{PossibleValue, PossibleValuesParser, TypedValueParser};
    let targets = plc::Target::ALL.into_iter().map(|t| PossibleValue::new(t.name()).help(t.label()));
    PossibleValuesParser::new(targets).map(|name| name.parse().unwrap_or(plc::Target::St))
}

#[derive(Args)]
pub struct SupconArgs {
    /// Plant: a libFAUDES generator (`.gen`), or a Supremica module (`.wmod`) whose PLANT
    /// components are composed.
    pub plant: String,
    /// Specification over a subset of the plant's events: a generator (`.gen`), or a module
    /// (`.wmod`) whose SPEC and SUPERVISOR components are composed. Without it, the
    /// specification is that of the plant's module.
    pub spec: Option<String>,
    /// Write the supervisor here: a Supremica module if the name ends in `.wmod`, a libFAUDES
    /// generator otherwise.
    #[arg(short = 'o', long)]
    pub output: Option<String>,
    /// Supremal controllable closed sublanguage (no nonblocking requirement).
    #[arg(long)]
    pub closed: bool,
    /// Minimise the supervisor before writing it.
    #[arg(long)]
    pub minimize: bool,
    /// State budget: the states each generator file may declare and the states of
    /// `plant || spec`; past it, the run stops with exit status 3.
    #[arg(long, value_name = "N", default_value_t = DEFAULT_MAX_STATES)]
    pub max_states: usize,
}

#[derive(Args)]
pub struct BenchArgs {
    /// Repetitions per measurement (the median is printed).
    #[arg(long, default_value_t = 5)]
    pub runs: usize,
    /// Skip the libFAUDES comparison.
    #[arg(long)]
    pub no_faudes: bool,
    #[command(flatten)]
    pub format: super::bench::Format,
}

fn read(path: &str) -> Result<String, ExitCode> {
    std::fs::read_to_string(path).map_err(|e| {
        eprintln!("error: cannot read `{path}`: {e}");
        ExitCode::from(2)
    })
}

/// Exit status: 0 supervisors synthesised, 2 input error (located diagnostics), 3 the state
/// budget is spent (specification products and synthesis draw on one budget per run).
pub fn supervise(a: &SuperviseArgs) -> ExitCode {
    let wmod_output = a.target.is_none().then_some(a.output.as_deref()).flatten();
    if wmod_output.is_some_and(|o| !o.to_ascii_lowercase().ends_with(".wmod")) {
        eprintln!("error: `--output` needs `--target`, or a file name ending in `.wmod` for the supervisors");
        return ExitCode::from(2);
    }
    let src = match read(&a.file) {
        Ok(s) => s,
        Err(c) => return c,
    };
    let mut go_on = |_: &_| true;
    let mut budget = Budget::new(a.max_states, &mut go_on);
    let (loaded, diags, stop) = compile_within(&src, &mut budget);
    if !diags.is_empty() {
        eprint!("{}", render_plain(&a.file, &src, &diags));
    }
    if stop.is_some() {
        budget_note(a.max_states);
        return ExitCode::from(3);
    }
    let Some(mut loaded) = loaded else { return ExitCode::from(2) };
    let mut composed_from = 0;
    if a.compose {
        match loaded.composed("Composed", &mut budget) {
            Ok(l) => {
                composed_from = loaded.project.specs.len();
                loaded = l
            }
            Err((k, _)) => {
                let specs = &loaded.project.specs;
                let mut d = Diagnostics::new(&src);
                d.error(
                    loaded.spec_spans[k],
                    format!(
                        "composing the {} specifications spent the state budget at `{}`: more than {} product states",
                        specs.len(),
                        specs[k].name,
                        a.max_states
                    ),
                )
                .with_note(format!("this is the product of the first {} specifications", k + 1))
                .with_note("compose fewer of them with a product `spec X = A | B;` in the file");
                eprint!("{}", render_plain(&a.file, &src, &d.items));
                budget_note(a.max_states);
                return ExitCode::from(3);
            }
        }
    }
    let method = match a.method {
        MethodArg::Incremental => Method::Incremental,
        MethodArg::Monolithic => Method::Monolithic,
    };
    let cfg =
        Config::default().method(method).preempt(!a.no_preemption).minimize(!a.no_minimize).max_states(a.max_states);
    let start = Instant::now();
    let clock = move || start.elapsed().as_secs_f64() * 1000.0;
    let synthesis = synthesize_within(&src, &loaded, &cfg, Some(&clock), &mut budget);
    let (reports, sdiags, stop) = (&synthesis.reports, &synthesis.diagnostics, synthesis.stop());
    if !sdiags.is_empty() {
        eprint!("{}", render_plain(&a.file, &src, sdiags));
        if composed_from > 1 {
            eprintln!("note: `Composed` is the product of all {composed_from} specifications; its diagnostics point at the first");
        }
    }
    if stop.is_some() {
        budget_note(a.max_states);
    }
    // The budget stop is one error diagnostic; any other error is an input error.
    let input_errors = sdiags.iter().filter(|d| d.is_error()).count() > usize::from(stop.is_some());
    if let Some(target) = a.target {
        if input_errors {
            return ExitCode::from(2);
        }
        if stop.is_some() {
            return ExitCode::from(3);
        }
        return write_framework(a, target, &src, &loaded, reports);
    }
    if a.json {
        let out = serde_json::json!({
            "file": a.file,
            "verdict": synthesis.outcome_name(),
            "stop": stop,
            "method": method,
            "supervisors": reports,
            "events": loaded.project.events,
            "event_actions": loaded.events,
            "timers": loaded.timers,
            "diagnostics": diags.iter().chain(sdiags).collect::<Vec<_>>(),
        });
        outln!("{}", serde_json::to_string_pretty(&out).unwrap_or_default());
    } else {
        outln!(
            "{:<28} {:>10} {:>7} {:>6} {:>7}  {:>9}  enforced",
            "supervisor",
            "realizable",
            "states",
            "trans",
            "prohib",
            "millis"
        );
        let mut total = 0;
        for r in reports {
            total += r.states;
            outln!(
                "{:<28} {:>10} {:>7} {:>6} {:>7}  {:>9.3}  {}",
                r.name,
                if r.realizable { "yes" } else { "NO" },
                r.states,
                r.transitions,
                r.prohibitions,
                r.millis,
                r.enforced_events.join(", ")
            );
        }
        outln!("{} supervisors, {} states in total", reports.len(), total);
    }
    if input_errors {
        ExitCode::from(2)
    } else if stop.is_some() {
        ExitCode::from(3)
    } else if let Some(o) = wmod_output {
        let sups: Vec<_> = reports.iter().map(|r| &r.supervisor).collect();
        super::interchange::write_project(&a.file, &src, &loaded, &sups, true, Some(o))
    } else {
        ExitCode::SUCCESS
    }
}

/// Lowers the supervisors of `reports` into the runtime framework and writes it for `target`.
fn write_framework(
    a: &SuperviseArgs,
    target: plc::Target,
    src: &str,
    loaded: &plcsynth::sct::Loaded,
    reports: &[plcsynth::sct::SupervisorReport],
) -> ExitCode {
    let supervisors: Vec<&plcsynth::sct::model::Supervisor> = reports.iter().map(|r| &r.supervisor).collect();
    let options = plc::lower::sct::FrameworkOptions { name: a.name.clone(), controller: a.controller.clone() };
    let unit = match plc::lower::sct::lower(src, loaded, &supervisors, &options) {
        Ok(unit) => unit,
        Err(diags) => {
            eprint!("{}", render_plain(&a.file, src, &diags));
            eprintln!("{}: nothing written", a.file);
            return ExitCode::from(2);
        }
    };
    let options = plc::Options { ob: a.ob, fb: Some(a.controller_fb), ..plc::Options::default() };
    super::write_unit(&unit, target, options, a.io_table.as_deref(), a.io_format, a.output.as_deref())
}

/// How to go on after the state budget stopped a run.
fn budget_note(max_states: usize) {
    eprintln!(
        "note: the state budget of {max_states} product states is spent (specification products and synthesis share it); raise it with --max-states N"
    );
}

/// Reads a `.gen` file; returns its text too, for diagnostics that point into it later.
fn read_gen_located(path: &str, events: &mut Events, max_states: usize) -> Result<(String, GenFile), ExitCode> {
    let src = read(path)?;
    match read_gen_file_within(&src, events, max_states) {
        Ok(g) => Ok((src, g)),
        Err(e) => {
            eprint!("{}", render_plain(path, &src, &[e.diagnostic(&src)]));
            Err(ExitCode::from(if e.over_budget { 3 } else { 2 }))
        }
    }
}

/// One side of `supcon` (plant or specification) and where its events are declared.
struct Side {
    path: String,
    src: String,
    automaton: plcsynth::sct::classic::Automaton,
    event_spans: Box<dyn Fn(ClassicEventId) -> Option<plcsynth::diag::Span>>,
}

/// Reads the plant or the specification of `supcon` from a `.gen` or `.wmod` file.
fn read_side(path: &str, plant: bool, events: &mut Events, max_states: usize) -> Result<Side, ExitCode> {
    if path.to_ascii_lowercase().ends_with(".wmod") {
        let (src, m) = super::interchange::read_module(path, events, max_states)?;
        let automaton = super::interchange::module_side(path, &src, &m, plant, events, max_states)?;
        return Ok(Side { path: path.to_string(), src, automaton, event_spans: Box::new(move |e| m.event_span(e)) });
    }
    let (src, g) = read_gen_located(path, events, max_states)?;
    let spans: Vec<(ClassicEventId, plcsynth::diag::Span)> =
        g.automaton.alphabet().iter().filter_map(|&e| g.event_span(e).map(|s| (e, s))).collect();
    let event_spans = Box::new(move |e| spans.iter().find(|(x, _)| *x == e).map(|(_, s)| *s));
    Ok(Side { path: path.to_string(), src, automaton: g.automaton, event_spans })
}

pub fn supcon(a: &SupconArgs) -> ExitCode {
    let mut events = Events::new();
    let plant = match read_side(&a.plant, true, &mut events, a.max_states) {
        Ok(p) => p,
        Err(c) => return c,
    };
    let spec = match &a.spec {
        Some(path) => read_side(path, false, &mut events, a.max_states),
        None if a.plant.to_ascii_lowercase().ends_with(".wmod") => {
            read_side(&a.plant, false, &mut events, a.max_states)
        }
        None => {
            eprintln!("error: a specification file is needed with a `.gen` plant");
            return ExitCode::from(2);
        }
    };
    let spec = match spec {
        Ok(p) => p,
        Err(c) => return c,
    };
    let start = Instant::now();
    let sup = match supcon_within(&plant.automaton, &spec.automaton, &events, !a.closed, a.max_states) {
        Ok(s) => s,
        Err(SupConError::BudgetExceeded { max_states }) => {
            eprintln!("error: `{}` || `{}` has more than {max_states} states", plant.path, spec.path);
            eprintln!("note: the state budget is {max_states} states; raise it with --max-states N");
            return ExitCode::from(3);
        }
        Err(SupConError::SpecEventsOutsidePlant(outside)) => {
            let names = |es: &[ClassicEventId]| {
                es.iter().map(|e| format!("`{}`", events.name(*e))).collect::<Vec<_>>().join(", ")
            };
            let mut d = Diagnostics::new(&spec.src);
            let span = (spec.event_spans)(outside[0]).unwrap_or_default();
            d.error(span, format!("the specification uses events the plant does not know: {}", names(&outside)))
                .with_note(format!("the plant `{}` has the events {}", a.plant, names(plant.automaton.alphabet())))
                .with_note("SupCon needs the specification's events among the plant's");
            eprint!("{}", render_plain(&spec.path, &spec.src, &d.items));
            return ExitCode::from(2);
        }
    };
    let sup = if a.minimize { minimize(&sup) } else { sup };
    let ms = start.elapsed().as_secs_f64() * 1000.0;
    outln!(
        "{}: {} states, {} transitions ({:.3} ms){}",
        if a.closed { "SupConClosed" } else { "SupCon" },
        sup.num_states(),
        sup.num_transitions(),
        ms,
        if sup.init().is_none() { " -- empty: no supervisor exists" } else { "" }
    );
    if let Some(o) = &a.output {
        let text = if o.to_ascii_lowercase().ends_with(".wmod") {
            let component = ComponentOut { name: "supervisor", kind: ComponentKind::Supervisor, automaton: &sup };
            let kind = if a.closed { "SupConClosed" } else { "SupCon" };
            let comment = format!("{kind} of {} and {} by plcsynth.", plant.path, spec.path);
            write_wmod("supervisor", &comment, &[component], &events, &[])
        } else {
            write_gen(&sup, &events, "supervisor")
        };
        if let Err(e) = std::fs::write(o, text) {
            eprintln!("error: cannot write `{o}`: {e}");
            return ExitCode::from(1);
        }
    }
    ExitCode::SUCCESS
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(|a, b| a.total_cmp(b));
    v[v.len() / 2]
}

/// Median milliseconds and Σ supervisor states for all specifications of a generated line.
fn run_lines(k: usize, m: usize, method: Method, runs: usize) -> (f64, usize, usize, usize) {
    let src = transfer_lines(k, m, 2);
    let (l, _) = compile(&src).expect("generated transfer lines are valid");
    let cfg = Config { method, ..Config::default() };
    let mut times = Vec::new();
    let mut states = 0;
    for _ in 0..runs.max(1) {
        let t = Instant::now();
        let Synthesis { reports: reps, .. } = synthesize(&src, &l, &cfg, None, &mut |_| true);
        times.push(t.elapsed().as_secs_f64() * 1000.0);
        states = reps.iter().map(|r| r.states).sum();
    }
    (median(times), states, l.project.plants.len(), l.project.specs.len())
}

/// The columns of table 7.1 (`--markdown`).
const LINES_COLUMNS: &[Column] = &[
    ("lines × machines", false),
    ("plants", true),
    ("specs", true),
    ("IncSyn [ms]", true),
    ("states", true),
    ("thesis IncSyn [ms]", true),
    ("thesis states", true),
    ("ModSyn [ms]", true),
    ("ModSyn states", true),
    ("thesis ModSyn", false),
];

/// The columns of table 7.2 (`--markdown`).
const EXTENDED_COLUMNS: &[Column] = &[
    ("extended line", false),
    ("plants", true),
    ("specs", true),
    ("IncSyn [ms]", true),
    ("states", true),
    ("plants applied", true),
    ("Dep criterion would compose", true),
    ("thesis", false),
];

/// The columns of the libFAUDES comparison (`--markdown`).
const FAUDES_COLUMNS: &[Column] = &[
    ("problem", false),
    ("states", true),
    ("transitions", true),
    ("ours [ms]", true),
    ("libFAUDES [ms]", true),
    ("ours / libFAUDES", true),
];

pub fn bench(a: &BenchArgs) -> ExitCode {
    if a.format.headers {
        return print_headers(&[LINES_COLUMNS, EXTENDED_COLUMNS, FAUDES_COLUMNS]);
    }
    let md = a.format.markdown;
    if md {
        print_caption("sct", a.runs);
        outln!();
        print_header(LINES_COLUMNS);
    } else {
        outln!("Incremental synthesis on transfer lines (Göbe 2019, table 7.1; buffers of capacity 2)");
        outln!("ours: median of {} runs on this machine; thesis: Intel Core i5 750, 2.67 GHz", a.runs);
        outln!();
        outln!(
            "{:<22} {:>7} {:>6} | {:>12} {:>8} | {:>12} {:>8} | {:>12} {:>8}",
            "TLs x machines",
            "plants",
            "specs",
            "IncSyn ms",
            "states",
            "thesis ms",
            "states",
            "ModSyn ms",
            "states"
        );
    }
    // (k, m, thesis label, thesis IncSyn ms, thesis states, thesis ModSyn)
    let rows: &[(usize, usize, &str, &str, &str, &str)] = &[
        (2, 2, "2 x 2", "164", "38", "985 ms / 5994"),
        (2, 6, "2 x 4 (14 plants)", "242", "112", "TO/MO"),
        (3, 2, "3 x 2", "186", "60", "60 s / 262440"),
        (4, 2, "4 x 2", "194", "82", "TO/MO"),
        (5, 2, "5 x 2", "238", "104", "TO/MO"),
        (50, 4, "50 x 4 (goal < 1 s)", "-", "-", "-"),
    ];
    for &(k, m, label, t_ms, t_states, t_mod) in rows {
        let (ms, states, np, ns) = run_lines(k, m, Method::Incremental, a.runs);
        let modsyn = (np <= 9).then(|| run_lines(k, m, Method::Monolithic, a.runs.min(3)));
        if md {
            let label = label.replace(" x ", " × ");
            let (mms, mst) = modsyn.map_or(("skipped".to_string(), "–".to_string()), |(mms, mst, _, _)| {
                (super::bench::ms(mms), mst.to_string())
            });
            let dash = |s: &str| if s == "-" { "–".to_string() } else { s.to_string() };
            outln!(
                "| {label} | {np} | {ns} | {} | {states} | {} | {} | {mms} | {mst} | {} |",
                super::bench::ms(ms),
                dash(t_ms),
                dash(t_states),
                dash(t_mod)
            );
            continue;
        }
        let modsyn = match modsyn {
            Some((mms, mst, _, _)) => format!("{mms:>12.3} {mst:>8}"),
            None => format!("{:>12} {:>8}", "skipped", ""),
        };
        outln!("{label:<22} {np:>7} {ns:>6} | {ms:>12.3} {states:>8} | {t_ms:>12} {t_states:>8} | {modsyn}   (thesis ModSyn {t_mod})");
    }
    outln!();
    if !md {
        outln!("Table 7.2: one line, 3 extended machines, a globally shared sensor (thesis: 15 plants, 4 specs,");
        outln!("IncSyn 156 ms / 48 states; iModSyn out of memory). Reconstructed: the thesis publishes only sizes.");
    }
    {
        let src = extended_line(3);
        let (l, _) = compile(&src).expect("generated line is valid");
        let p = &l.project;
        let cfg = Config::default();
        let mut times = Vec::new();
        let mut states = 0;
        let mut used = 0;
        for _ in 0..a.runs.max(1) {
            let t = Instant::now();
            let Synthesis { reports: reps, .. } = synthesize(&src, &l, &cfg, None, &mut |_| true);
            times.push(t.elapsed().as_secs_f64() * 1000.0);
            states = reps.iter().map(|r| r.states).sum();
            used = reps.iter().map(|r| r.plants_used.len()).sum();
        }
        let dep: usize = (0..p.specs.len()).map(|i| dep_closure(p, i).len()).sum();
        if md {
            print_header(EXTENDED_COLUMNS);
            outln!(
                "| 1 line, 3 extended machines, a shared sensor | {} | {} | {} | {states} | {used} | {dep} | 15 plants, 4 specs, IncSyn 156 ms / 48 states; iModSyn out of memory |",
                p.plants.len(),
                p.specs.len(),
                super::bench::ms(median(times)),
            );
        } else {
            outln!(
                "  ours: {} plants, {} specs, IncSyn {:.3} ms, {} states; plants applied {} (Dep criterion would compose {})",
                p.plants.len(),
                p.specs.len(),
                median(times),
                states,
                used,
                dep
            );
        }
    }
    if a.no_faudes {
        if !md {
            outln!();
        }
        return ExitCode::SUCCESS;
    }
    outln!();
    bench_faudes(a.runs, md)
}

fn bench_faudes(runs: usize, md: bool) -> ExitCode {
    if !md {
        outln!("Classic SupCon, plcsynth vs libFAUDES on identical .gen inputs (median ms)");
    }
    let py = std::path::Path::new(".venv/bin/python");
    let script = std::path::Path::new("tests/faudes_bench.py");
    let available = py.exists() && script.exists();
    if !available && !md {
        outln!("  libFAUDES not available: run `scripts/python-checkers.sh` from the repository root");
        return ExitCode::SUCCESS;
    }
    let dir = std::env::temp_dir().join(format!("plcsynth-bench-{}", std::process::id()));
    let _ = std::fs::create_dir_all(&dir);
    let cases: Vec<(&str, (plcsynth::sct::classic::Automaton, plcsynth::sct::classic::Automaton, Events))> = vec![
        ("small factory", small_factory()),
        ("transfer line 3/1", transfer_line(3, 1)),
        ("transfer lines 1x2", transfer_lines_classic(1, 2, 2)),
        ("transfer lines 2x2", transfer_lines_classic(2, 2, 2)),
        ("transfer lines 1x4", transfer_lines_classic(1, 4, 2)),
        ("AGV (published 4406/11338)", agv()),
    ];
    if md {
        print_header(FAUDES_COLUMNS);
    } else {
        outln!(
            "{:<24} {:>8} {:>8} | {:>10} {:>10} {:>7}",
            "problem",
            "states",
            "trans",
            "ours ms",
            "faudes ms",
            "ratio"
        );
    }
    for (name, (plant, spec, ev)) in &cases {
        let spec = &spec.with_selfloops(plant.alphabet());
        let mut times = Vec::new();
        let mut sup = None;
        for _ in 0..runs.max(1) {
            let t = Instant::now();
            let s = classic_supcon(plant, spec, ev, true).expect("textbook specs use plant events");
            times.push(t.elapsed().as_secs_f64() * 1000.0);
            sup = Some(s);
        }
        let sup = sup.expect("ran at least once");
        let ours = median(times);
        let faudes = if available { faudes_supcon(py, script, &dir, name, plant, spec, ev, runs) } else { None };
        let sizes_agree =
            |(_, fst, ftr): (f64, u64, u64)| fst as usize == sup.num_states() && ftr as usize == sup.num_transitions();
        if md {
            let (fms, ratio) = match faudes {
                Some(f @ (fms, _, _)) => {
                    let agree = if sizes_agree(f) { "" } else { " (sizes differ!)" };
                    (super::bench::ms(fms), format!("{:.2}{agree}", ours / fms.max(1e-6)))
                }
                None if available => ("error".to_string(), "–".to_string()),
                None => ("not available".to_string(), "–".to_string()),
            };
            outln!(
                "| {name} | {} | {} | {} | {fms} | {ratio} |",
                sup.num_states(),
                sup.num_transitions(),
                super::bench::ms(ours)
            );
            continue;
        }
        match faudes {
            Some(f @ (fms, _, _)) => {
                let agree = if sizes_agree(f) { "" } else { "  (sizes differ!)" };
                outln!(
                    "{name:<24} {:>8} {:>8} | {ours:>10.3} {fms:>10.3} {:>7.2}{agree}",
                    sup.num_states(),
                    sup.num_transitions(),
                    ours / fms.max(1e-6)
                );
            }
            None => outln!(
                "{name:<24} {:>8} {:>8} | {ours:>10.3} {:>10} {:>7}",
                sup.num_states(),
                sup.num_transitions(),
                "error",
                "-"
            ),
        }
    }
    if !md {
        outln!("ratio = ours / libFAUDES (below 1 means plcsynth is faster); libFAUDES time excludes file reading.");
    }
    let _ = std::fs::remove_dir_all(&dir);
    ExitCode::SUCCESS
}

/// libFAUDES's SupCon of `plant` and `spec`, written as `.gen` files into `dir`: its median
/// milliseconds over `runs` (file reading excluded), states and transitions.
#[allow(clippy::too_many_arguments)]
fn faudes_supcon(
    py: &std::path::Path,
    script: &std::path::Path,
    dir: &std::path::Path,
    name: &str,
    plant: &plcsynth::sct::classic::Automaton,
    spec: &plcsynth::sct::classic::Automaton,
    ev: &Events,
    runs: usize,
) -> Option<(f64, u64, u64)> {
    let pf = dir.join("plant.gen");
    let sf = dir.join("spec.gen");
    let _ = std::fs::write(&pf, write_gen(plant, ev, "plant"));
    let _ = std::fs::write(&sf, write_gen(spec, ev, "spec"));
    let out = Command::new(py).arg(script).arg(&pf).arg(&sf).arg(runs.max(1).to_string()).output();
    if let Ok(o) = &out {
        if !o.status.success() {
            eprintln!(
                "libFAUDES failed on {name}: {}",
                String::from_utf8_lossy(&o.stderr).lines().last().unwrap_or("")
            );
        }
    }
    out.ok().and_then(|o| String::from_utf8(o.stdout).ok()).and_then(|s| {
        let v: serde_json::Value = serde_json::from_str(s.lines().last()?).ok()?;
        Some((v["ms"].as_f64()?, v["states"].as_u64()?, v["transitions"].as_u64()?))
    })
}
