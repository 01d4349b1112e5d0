//! Warnings where time cannot pass. A verdict assumes that time goes on; where a plant unit
//! stops it, the verdict rests on zero-time behaviour and may be realizable without any real
//! run behind it (docs/timed-language.md, "Where time cannot pass"). Found statically, per
//! unit, without false alarms: every warning names a place where time stops once it is
//! reached (whether it is reached is the solver's business).
//! - an initial node whose invariant excludes 0: the initial state violates its invariant;
//! - a node whose invariant lets no time pass (`c in [3,3]`) and that no transition can leave
//!   at that value: entering it is a timelock;
//! - a cycle of transitions that are `instant` (urgent) or leave such nodes, whose guards and
//!   invariants can all hold at once: it can repeat forever at one instant.

use super::model::{Automaton, ClockId, ClockInterval, Edge, Game, Interval, MessageKind};
use crate::diag::Diagnostics;

const DOCS: &str = "see \"Where time cannot pass\" in docs/timed-language.md";

/// How many search steps the cycle enumeration may take per unit; beyond it, cycles go
/// unreported rather than slow the check down.
const CYCLE_SEARCH_STEPS: usize = 100_000;

/// Appends a warning for every place where time cannot pass.
pub fn warn(game: &Game, diags: &mut Diagnostics) {
    for unit in &game.components {
        let mut leaving: Vec<Vec<usize>> = vec![Vec::new(); unit.locations.len()];
        for (i, e) in unit.edges.iter().enumerate() {
            leaving[e.from.index()].push(i);
        }
        initial_invariant(game, unit, diags);
        frozen_nodes(game, unit, &leaving, diags);
        zero_time_cycles(game, unit, &leaving, diags);
    }
}

/// The clock's name without its unit's prefix, as the user wrote it.
fn clock_name<'g>(game: &'g Game, unit: &Automaton, c: ClockId) -> &'g str {
    let name = &game.clocks[c.index()].name;
    name.strip_prefix(&format!("{}.", unit.name)).unwrap_or(name)
}

fn contains_zero(i: &Interval) -> bool {
    i.lower == 0 && i.lower_closed
}

/// The intersection of two intervals (bounds and closedness); may be empty.
fn intersect(a: &Interval, b: &Interval) -> Interval {
    let (lower, lower_closed) = match a.lower.cmp(&b.lower) {
        std::cmp::Ordering::Less => (b.lower, b.lower_closed),
        std::cmp::Ordering::Greater => (a.lower, a.lower_closed),
        std::cmp::Ordering::Equal => (a.lower, a.lower_closed && b.lower_closed),
    };
    let (upper, upper_closed) = match (a.upper, b.upper) {
        (None, _) => (b.upper, b.upper_closed),
        (_, None) => (a.upper, a.upper_closed),
        (Some(x), Some(y)) if x < y => (a.upper, a.upper_closed),
        (Some(x), Some(y)) if x > y => (b.upper, b.upper_closed),
        (Some(_), Some(_)) => (a.upper, a.upper_closed && b.upper_closed),
    };
    Interval { lower, lower_closed, upper, upper_closed, span: a.span }
}

/// True if some valuation satisfies all `constraints`, where the clocks in `zero` are 0.
fn satisfiable<'a>(constraints: impl IntoIterator<Item = &'a ClockInterval>, zero: u64) -> bool {
    let mut by_clock: Vec<(ClockId, Interval)> = Vec::new();
    for ci in constraints {
        if zero >> ci.clock.index() & 1 == 1 {
            if !contains_zero(&ci.interval) {
                return false;
            }
            continue;
        }
        match by_clock.iter_mut().find(|(c, _)| *c == ci.clock) {
            Some((_, i)) => *i = intersect(i, &ci.interval),
            None => by_clock.push((ci.clock, ci.interval)),
        }
    }
    by_clock.iter().all(|(_, i)| !i.is_empty())
}

/// A transition as written: `a -> b ?x`.
fn transition(game: &Game, unit: &Automaton, e: &Edge) -> String {
    let from = &unit.locations[e.from.index()].name;
    let to = &unit.locations[e.to.index()].name;
    format!("`{from} -> {to} {}{}`", e.kind.sigil(), game.messages[e.message.index()].name)
}

/// The initial state has every clock at 0; an initial invariant that excludes 0 is violated
/// from the start, and the solver judges the state as if the invariant held.
fn initial_invariant(game: &Game, unit: &Automaton, diags: &mut Diagnostics) {
    let node = &unit.locations[unit.initial.index()];
    for ci in node.invariant.iter().filter(|ci| !contains_zero(&ci.interval)) {
        let clock = clock_name(game, unit, ci.clock);
        diags
            .warning(
                ci.interval.span,
                format!(
                    "time cannot pass in the initial state: node `{}` of `{}` requires `{clock} in {}`, but clocks start at 0",
                    node.name, unit.name, ci.interval
                ),
            )
            .with_note(
                "the initial state violates this invariant; the solver judges it as if the invariant held, and a controller \
                 may win by acting forever at time 0",
            )
            .with_note(DOCS);
    }
}

/// A node whose invariant allows a single value of a clock lets no time pass; if no
/// transition can leave it at that value, a state there can do nothing but run past its
/// invariant.
fn frozen_nodes(game: &Game, unit: &Automaton, leaving: &[Vec<usize>], diags: &mut Diagnostics) {
    for (l, node) in unit.locations.iter().enumerate() {
        let Some(point) = point_invariant(node) else {
            continue;
        };
        let can_leave = leaving[l].iter().any(|&i| satisfiable(node.invariant.iter().chain(&unit.edges[i].guard), 0));
        if !can_leave {
            let clock = clock_name(game, unit, point.clock);
            diags
                .warning(
                    point.interval.span,
                    format!(
                        "time cannot pass in node `{}` of `{}` (`{clock} in {}`), and no transition can leave it there",
                        node.name, unit.name, point.interval
                    ),
                )
                .with_note("a state in this node can only run past its invariant, a deadlock")
                .with_note(DOCS);
        }
    }
}

/// The first invariant of `node` that allows a single clock value: no time passes there.
fn point_invariant(node: &super::model::Location) -> Option<&ClockInterval> {
    node.invariant.iter().find(|ci| ci.interval.upper == Some(ci.interval.lower))
}

/// Cycles of requests and reactions (`$` transitions need a partner and are left out) in which
/// time cannot pass, because each transition is `instant` or leaves a node whose invariant
/// lets no time pass, and that can repeat: in the repetition every clock reset on the cycle is
/// 0, and the others keep one value that all guards and invariants on the cycle allow.
fn zero_time_cycles(game: &Game, unit: &Automaton, leaving: &[Vec<usize>], diags: &mut Diagnostics) {
    let n = unit.locations.len();
    let frozen: Vec<Option<&ClockInterval>> = unit.locations.iter().map(point_invariant).collect();
    let out: Vec<Vec<usize>> = (0..n)
        .map(|l| {
            let zero_time = |&&i: &&usize| {
                let e = &unit.edges[i];
                e.kind != MessageKind::Synchronised && (e.instant || frozen[l].is_some())
            };
            leaving[l].iter().filter(zero_time).copied().collect()
        })
        .collect();
    let feasible = |cycle: &[usize]| {
        let zero = cycle.iter().flat_map(|&i| &unit.edges[i].resets).fold(0u64, |z, &c| z | 1 << c.index());
        let guards = cycle.iter().flat_map(|&i| &unit.edges[i].guard);
        let invariants = cycle.iter().flat_map(|&i| &unit.locations[(unit.edges[i].from).index()].invariant);
        satisfiable(guards.chain(invariants), zero)
    };
    let mut reported = vec![false; n];
    let mut on_path = vec![false; n];
    let mut steps = 0usize;
    // Elementary cycles, each found once from its smallest node (Tiernan's enumeration).
    for start in (0..n).filter(|&l| !out[l].is_empty()) {
        let mut path: Vec<usize> = Vec::new(); // edge indices
        let mut stack: Vec<(usize, usize)> = vec![(start, 0)]; // (node, next out-edge to try)
        on_path[start] = true;
        while let Some((node, next)) = stack.last_mut().map(|(node, next)| (*node, next)) {
            steps += 1;
            if steps > CYCLE_SEARCH_STEPS {
                return;
            }
            let Some(&e) = out[node].get(*next) else {
                on_path[node] = false;
                stack.pop();
                path.pop();
                continue;
            };
            *next += 1;
            let to = (unit.edges[e].to).index();
            if to == start {
                path.push(e);
                let on_cycle = || path.iter().map(|&i| (unit.edges[i].from).index());
                if feasible(&path) && !on_cycle().any(|l| reported[l]) {
                    let cycle: Vec<usize> = on_cycle().collect();
                    cycle.iter().for_each(|&l| reported[l] = true);
                    report_cycle(game, unit, &path, &frozen, diags);
                }
                path.pop();
            } else if to > start && !on_path[to] {
                path.push(e);
                on_path[to] = true;
                stack.push((to, 0));
            }
        }
    }
}

fn report_cycle(
    game: &Game,
    unit: &Automaton,
    path: &[usize],
    frozen: &[Option<&ClockInterval>],
    diags: &mut Diagnostics,
) {
    let steps: Vec<String> = path.iter().map(|&i| transition(game, unit, &unit.edges[i])).collect();
    let mut why = Vec::new();
    if path.iter().any(|&i| unit.edges[i].instant) {
        why.push(
            "instant transitions are urgent: while one is enabled nothing else happens and no time passes".to_string(),
        );
    }
    for &i in path {
        let from = (unit.edges[i].from).index();
        if let (false, Some(ci)) = (unit.edges[i].instant, frozen[from]) {
            why.push(format!(
                "node `{}` lets no time pass (`{} in {}`)",
                unit.locations[from].name,
                clock_name(game, unit, ci.clock),
                ci.interval
            ));
        }
    }
    diags
        .warning(
            unit.edges[path[0]].span,
            format!("time cannot pass in the cycle {} of `{}`", steps.join(", "), unit.name),
        )
        .with_note(format!(
            "{}; so the cycle can repeat forever at one instant, and a verdict may rest on that when each round \
             reaches a plan goal",
            why.join("; ")
        ))
        .with_note(DOCS);
}
