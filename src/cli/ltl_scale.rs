//! `plcsynth bench ltl --scale`: SYNTCOMP's parametric families at growing n, each instance
//! decided once by the explicit solver (the reference), the bdd solver and the GR(1) game,
//! every run cut off after a wall-clock limit (cancelled through the progress callback, as
//! the page's cancel button does).

use super::bench::print_header;
use super::bench::Column;
use super::ltl::BenchArgs;
use plcsynth::ltl::{self, Config, Format, Solver, Stop, Verdict};
use std::process::ExitCode;
use std::time::{Duration, Instant};

/// A TLSF file's parameters and their values.
type Params = &'static [(&'static str, i64)];

/// The instances: the family's file, its parameters, and SYNTCOMP's status (the families'
/// `.csv` files; an `_unreal` family is unrealizable for every parameter).
const INSTANCES: &[(&str, Params, &str)] = &[
    ("simple_arbiter/simple_arbiter.tlsf", &[("n", 4)], "realizable"),
    ("simple_arbiter/simple_arbiter.tlsf", &[("n", 6)], "realizable"),
    ("simple_arbiter/simple_arbiter.tlsf", &[("n", 8)], "realizable"),
    ("simple_arbiter/simple_arbiter.tlsf", &[("n", 10)], "realizable"),
    ("simple_arbiter/simple_arbiter.tlsf", &[("n", 12)], "realizable"),
    ("simple_arbiter/simple_arbiter.tlsf", &[("n", 20)], "realizable"),
    ("simple_arbiter_unreal/simple_arbiter_unreal1.tlsf", &[("n", 4), ("u", 2)], "unrealizable"),
    ("simple_arbiter_unreal/simple_arbiter_unreal2.tlsf", &[("n", 4)], "unrealizable"),
    ("simple_arbiter_unreal/simple_arbiter_unreal2.tlsf", &[("n", 8)], "unrealizable"),
    ("full_arbiter/full_arbiter.tlsf", &[("n", 3)], "realizable"),
    ("full_arbiter/full_arbiter.tlsf", &[("n", 4)], "realizable"),
    ("full_arbiter/full_arbiter.tlsf", &[("n", 5)], "realizable"),
    ("full_arbiter/full_arbiter.tlsf", &[("n", 8)], "realizable"),
    ("load_balancer/load_balancer.tlsf", &[("n", 3)], "realizable"),
    ("load_balancer/load_balancer.tlsf", &[("n", 4)], "realizable"),
    ("load_balancer/load_balancer.tlsf", &[("n", 5)], "realizable"),
    ("load_balancer/load_balancer.tlsf", &[("n", 10)], "realizable"),
    ("prioritized_arbiter/prioritized_arbiter.tlsf", &[("n", 3)], "realizable"),
    ("prioritized_arbiter/prioritized_arbiter.tlsf", &[("n", 4)], "realizable"),
    ("prioritized_arbiter_unreal/prioritized_arbiter_unreal1.tlsf", &[("n", 3), ("u", 4)], "unrealizable"),
    ("prioritized_arbiter_unreal/prioritized_arbiter_unreal2.tlsf", &[("n", 4)], "unrealizable"),
    ("round_robin_arbiter/round_robin_arbiter.tlsf", &[("n", 3)], "realizable"),
    ("round_robin_arbiter/round_robin_arbiter.tlsf", &[("n", 4)], "realizable"),
    ("round_robin_arbiter/round_robin_arbiter.tlsf", &[("n", 8)], "realizable"),
];

const SOLVERS: [Solver; 3] = [Solver::Explicit, Solver::Bdd, Solver::Gr1];

const COLUMNS: &[Column] = &[
    ("SYNTCOMP instance", false),
    ("signals", true),
    ("status", false),
    ("explicit", false),
    ("explicit [s]", true),
    ("bdd", false),
    ("bdd [s]", true),
    ("gr1", false),
    ("gr1 [s]", true),
];

/// One run's cell: the verdict with its bound and strategy size, or why it ended.
fn cell(result: &Result<ltl::Synthesis, Stop>, limit: Duration, elapsed: Duration) -> String {
    match result {
        Ok(outcome) if outcome.verdict == Verdict::Unknown => {
            format!("unknown ({})", short_reason(outcome.limit.as_deref().unwrap_or("no verdict")))
        }
        Ok(outcome) => {
            let verdict = format!("{:?}", outcome.verdict).to_lowercase();
            let bound = if outcome.stats.gr1 { String::new() } else { format!("k = {}, ", outcome.k) };
            match (outcome.controller.as_ref().or(outcome.counter_strategy.as_ref()), &outcome.circuit) {
                (Some(m), _) => format!("{verdict} ({bound}{} states)", m.states.len()),
                (None, Some(c)) => format!("{verdict} (circuit: {} latches, {} goals)", c.latches.len(), c.goals.len()),
                (None, None) => {
                    format!("{verdict} ({bound}no machine: {})", short_reason(outcome.limit.as_deref().unwrap_or("")))
                }
            }
        }
        Err(Stop::Cancelled) if elapsed >= limit => format!("stopped after {} s", limit.as_secs()),
        Err(Stop::Budget { message, .. }) => format!("refused ({})", short_reason(message)),
        Err(stop) => stop.to_string(),
    }
}

/// The controller's reason for giving up, in a few words: where (its game at which bound, or its
/// automaton) and which budget (`ltl::summary` has the whole text).
fn short_reason(limit: &str) -> String {
    let first = limit.split("; ").next().unwrap_or(limit);
    let (place, why) = first.split_once(": ").unwrap_or(("", first));
    let budget = if why.contains("units of work") {
        "work"
    } else if why.contains("BDD nodes") {
        "BDD nodes"
    } else if why.contains("letters per position") {
        "2^n letters"
    } else if why.contains("positions") || why.contains("states") {
        "positions"
    } else {
        why
    };
    let place = place.trim_start_matches("the ").replace("controller's ", "");
    if place.is_empty() {
        budget.to_string()
    } else {
        format!("{place}: {budget}")
    }
}

/// `plcsynth bench ltl --scale`.
pub fn scale(a: &BenchArgs) -> ExitCode {
    let limit = Duration::from_secs(a.scale_timeout);
    outln!(
        "SYNTCOMP's families at growing n: one run per solver at the default budgets, each cut off after {} s",
        a.scale_timeout
    );
    outln!();
    print_header(COLUMNS);
    for (file, params, status) in INSTANCES {
        let path = a.data.join(format!("tlsf/{file}"));
        let Ok(source) = std::fs::read_to_string(&path) else {
            eprintln!("missing {}", path.display());
            return ExitCode::from(2);
        };
        let params: Vec<(String, i64)> = params.iter().map(|&(name, value)| (name.to_string(), value)).collect();
        let shown: Vec<String> = params.iter().map(|(name, value)| format!("{name} = {value}")).collect();
        let label =
            format!("{} {}", file.rsplit('/').next().unwrap_or(file).trim_end_matches(".tlsf"), shown.join(", "));
        let spec = match ltl::compile(&source, Format::Tlsf, &params) {
            Ok((spec, _)) => spec,
            Err(diagnostics) => {
                outln!("| {label} | | {status} | {} errors | | | | | |", diagnostics.len());
                continue;
            }
        };
        let mut cells = Vec::new();
        for solver in SOLVERS {
            let cfg = Config { solver, ..Config::default() };
            let started = Instant::now();
            let result = ltl::synthesize(&spec, &cfg, &mut |_| started.elapsed() < limit);
            let elapsed = started.elapsed();
            cells.push(format!("{} | {:.2}", cell(&result, limit, elapsed), elapsed.as_secs_f64()));
        }
        outln!("| {label} | {} | {status} | {} |", spec.signals.len(), cells.join(" | "));
    }
    ExitCode::SUCCESS
}
