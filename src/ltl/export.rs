//! The serialisable views of a run: the JSON document of `plcsynth ltl --json` (and of the
//! playground), and a plain-text rendering of a strategy.

use super::machine::Machine;
use super::{Spec, Synthesis, Verdict};
use serde_json::{json, Value};

/// `{"verdict", "k", "semantics", "inputs", "outputs", "ltl", "assumptions", "guarantees",
/// "stats", then "mealy" (realizable) or "counterstrategy" (unrealizable) or "limit"
/// (unknown)}`; `docs/ltl-language.md` describes every field.
pub fn report_json(spec: &Spec, outcome: &Synthesis) -> Value {
    // The result is about the specification with what the refinement loop learned.
    let spec = &super::refined(spec, &outcome.refinement);
    let name = |s| spec.name(s).to_string();
    let names = |ids: Vec<super::SignalId>| ids.into_iter().map(name).collect::<Vec<_>>();
    let clauses = |cs: &[super::Clause]| cs.iter().map(|c| c.formula.to_infix(&name)).collect::<Vec<_>>();
    let mut doc = json!({
        "verdict": outcome.verdict,
        "k": outcome.k,
        "semantics": spec.semantics,
        "inputs": names(spec.inputs()),
        "outputs": names(spec.outputs()),
        "ltl": spec.formula_text(),
        "assumptions": clauses(&spec.assumptions),
        "guarantees": clauses(&spec.guarantees),
        "stats": outcome.stats,
    });
    if let Some(machine) = &outcome.controller {
        doc["mealy"] = machine.to_json(spec);
    }
    if let Some(circuit) = &outcome.circuit {
        doc["circuit"] = circuit.to_json(spec);
    }
    if let Some(machine) = &outcome.counter_strategy {
        let mut counter = machine.to_json(spec);
        counter["moves_first"] = json!(machine.moves_first);
        doc["counterstrategy"] = counter;
    }
    if let Some(limit) = &outcome.limit {
        doc["limit"] = json!(limit);
    }
    if !outcome.refinement.learned.is_empty() {
        doc["learned"] = json!(outcome.refinement.learned);
    }
    doc["rounds"] = json!(outcome.refinement.rounds);
    if !spec.numeric.is_empty() {
        doc["numeric_inputs"] = json!(spec.numeric);
        doc["predicates"] = spec
            .predicates
            .iter()
            .map(|p| json!({"signal": spec.name(p.signal), "predicate": spec.predicate_text(p)}))
            .collect();
    }
    if !outcome.refinement.witnesses.is_empty() {
        doc["witnesses"] = json!(outcome.refinement.witnesses);
    }
    if let Some(theory) = &outcome.refinement.theory {
        doc["theory"] = json!(theory);
    }
    doc["split"] = json!(outcome.split);
    if outcome.groups.len() > 1 {
        doc["groups"] = outcome
            .groups
            .iter()
            .map(|g| {
                json!({
                    "guarantees": g.guarantees,
                    "outputs": g.outputs.iter().map(|&s| spec.name(s)).collect::<Vec<_>>(),
                    "k": g.k,
                    "mealy": g.controller.as_ref().map(|m| m.to_json(spec)),
                })
            })
            .collect();
    }
    doc
}

/// The signals of `ids` whose bit is set in `care`, each with its value in `value`
/// (`req & !ack`); every one of them when `all`; `true` for none.
fn literals(spec: &Spec, ids: &[super::SignalId], care: u64, value: u64, all: bool) -> String {
    let parts: Vec<String> = ids
        .iter()
        .enumerate()
        .filter(|(i, _)| all || care >> i & 1 == 1)
        .map(|(i, &s)| format!("{}{}", if value >> i & 1 == 1 { "" } else { "!" }, spec.name(s)))
        .collect();
    if parts.is_empty() {
        "true".to_string()
    } else {
        parts.join(" & ")
    }
}

/// Every row of `machine` as (state, label, next): `req & !ack / grant` (reads, then the
/// signals written, each with its value), written first for a machine that moves first.
fn row_labels<'a>(spec: &'a Spec, machine: &'a Machine) -> impl Iterator<Item = (usize, String, usize)> + 'a {
    machine.states.iter().enumerate().flat_map(move |(s, rows)| {
        rows.iter().map(move |row| {
            let read = literals(spec, &machine.reads, row.read.care, row.read.value, false);
            let write = if machine.writes.is_empty() {
                "-".to_string()
            } else {
                literals(spec, &machine.writes, u64::MAX, row.write, true)
            };
            let label = if machine.moves_first { format!("{write} / {read}") } else { format!("{read} / {write}") };
            (s, label, row.next.index())
        })
    })
}

/// A strategy as text, one line per row:
/// `s0: req & !ack / grant -> s1` (reads, then the signals written true, then the next state).
pub fn render_machine(spec: &Spec, machine: &Machine) -> String {
    row_labels(spec, machine).map(|(s, label, next)| format!("s{s}: {label} -> s{next}\n")).collect()
}

/// A strategy as a Mealy-machine drawing (DOT): one node per state, the initial one marked,
/// one edge per pair of states with a line `inputs / outputs` per row between them.
pub fn machine_dot(spec: &Spec, machine: &Machine) -> String {
    use crate::dot::{document, Drawing, Edge, Node};
    let mut g = Drawing::new();
    let nodes: Vec<_> = (0..machine.states.len())
        .map(|s| g.add_node(Node { label: format!("s{s}"), class: "location".into(), ..Node::default() }))
        .collect();
    let point = g.add_node(Node { class: "initial-point".into(), shape: Some("point"), ..Node::default() });
    g.add_edge(point, nodes[machine.init.index()], Edge { class: "initial".into(), ..Edge::default() });
    let mut merged: std::collections::BTreeMap<(usize, usize), Vec<String>> = Default::default();
    for (s, label, next) in row_labels(spec, machine) {
        merged.entry((s, next)).or_default().push(label);
    }
    for ((s, next), labels) in merged {
        g.add_edge(nodes[s], nodes[next], Edge { label: labels.join("\n"), class: "row".into(), ..Edge::default() });
    }
    document(&g)
}

/// The counter-strategy unfolded as a tree from its initial state: each state's inputs, then
/// one branch per answer of the controller, each state unfolded once (later visits refer back
/// to it), so that a plain sequence of inputs reads as a lasso.
///
/// For `examples/ltl/arbiter_same_scan.ltl`:
///
/// ```text
/// s0: the environment sets req1 & req2
/// └─ whatever the controller answers → s0 again
/// ```
pub fn render_tree(spec: &Spec, machine: &Machine) -> String {
    let literals = |ids: &[super::SignalId], care: u64, value: u64| -> String {
        let text = literals(spec, ids, care, value, false);
        if text == "true" {
            "nothing".to_string()
        } else {
            text
        }
    };
    let all = u64::MAX >> (64 - machine.writes.len().max(1));
    enum Item {
        Text(String),
        State(super::StateId, String),
    }
    let mut out = String::new();
    let mut shown = vec![false; machine.states.len()];
    // Depth-first with an explicit stack (a machine may be long): text to print, or a state to
    // unfold with the indentation of its branches.
    let mut stack = vec![Item::State(machine.init, String::new())];
    while let Some(item) = stack.pop() {
        let (state, indent) = match item {
            Item::Text(text) => {
                out.push_str(&text);
                continue;
            }
            Item::State(state, indent) => (state, indent),
        };
        let s = state.index();
        if shown[s] {
            // Planned as a branch of an earlier state, unfolded meanwhile by another branch.
            out.push_str(&format!("s{s} again\n"));
            continue;
        }
        shown[s] = true;
        if machine.moves_first {
            out.push_str(&format!(
                "s{s}: the environment sets {}\n",
                literals(&machine.writes, all, machine.first_write(state))
            ));
        } else {
            out.push_str(&format!("s{s}\n"));
        }
        let rows = &machine.states[s];
        let mut items = Vec::new();
        for (i, row) in rows.iter().enumerate() {
            let (fork, deeper) = if i + 1 == rows.len() { ("└─ ", "   ") } else { ("├─ ", "│  ") };
            let answer = if row.read.care == 0 {
                "whatever the controller answers".to_string()
            } else {
                format!("if the controller answers {}", literals(&machine.reads, row.read.care, row.read.value))
            };
            let sets = if machine.moves_first {
                String::new()
            } else {
                format!(", it sets {}", literals(&machine.writes, all, row.write))
            };
            let next = row.next;
            let head = format!("{indent}{fork}{answer}{sets} → ");
            // A state is unfolded once, where it is first reached; elsewhere it is referred to.
            let planned = items.iter().any(|item| matches!(item, Item::State(n, _) if *n == next));
            if shown[next.index()] || planned {
                items.push(Item::Text(format!("{head}s{} again\n", next.0)));
            } else {
                items.push(Item::Text(head));
                items.push(Item::State(next, format!("{indent}{deeper}")));
            }
        }
        stack.extend(items.into_iter().rev());
    }
    out
}

/// A one-line summary: `realizable at k = 1: controller of 2 states, 3 rows`.
pub fn summary(outcome: &Synthesis) -> String {
    let count = |n: usize, what: &str| format!("{n} {what}{}", if n == 1 { "" } else { "s" });
    let size = |m: &Machine| format!("{}, {}", count(m.states.len(), "state"), count(m.rows(), "row"));
    // A gr1 run decides without a bound and may decide without building the machine.
    let at = if outcome.stats.gr1 { " (GR(1) game)".to_string() } else { format!(" at k = {}", outcome.k) };
    let missing = || format!("not built: {}", outcome.limit.as_deref().unwrap_or("no machine"));
    match outcome.verdict {
        Verdict::Realizable => {
            let circuit = |c: &super::Circuit| {
                let latches = c.latches.len();
                format!("{latches} latch{} and {}", if latches == 1 { "" } else { "es" }, count(c.goals.len(), "goal"))
            };
            match (&outcome.controller, &outcome.circuit) {
                (Some(m), None) => format!("realizable{at}: a controller of {}", size(m)),
                (Some(m), Some(c)) => {
                    format!("realizable{at}: a controller of {}; as a circuit, {}", size(m), circuit(c))
                }
                (None, Some(c)) => format!(
                    "realizable{at}: a controller circuit of {} (no table: {})",
                    circuit(c),
                    outcome.limit.as_deref().unwrap_or("not built")
                ),
                (None, None) => format!("realizable{at}: the controller was {}", missing()),
            }
        }
        Verdict::Unrealizable => match &outcome.counter_strategy {
            Some(m) => format!("unrealizable{at}: the environment wins with a counter-strategy of {}", size(m)),
            None => format!("unrealizable{at}: the environment's counter-strategy was {}", missing()),
        },
        Verdict::Unknown => {
            format!("unknown at k = {}: {}", outcome.k, outcome.limit.as_deref().unwrap_or("no player won"))
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::ltl::{compile_g4ltl, machine_dot, render_machine, synthesize, Config};

    #[test]
    fn the_mealy_drawing_has_every_row_of_the_text() {
        let source = "ALWAYS (req -> (grant || NEXT grant))\nALWAYS (grant -> NEXT !grant)\nINPUT req\nOUTPUT grant\n";
        let (spec, _) = compile_g4ltl(source).unwrap();
        let outcome = synthesize(&spec, &Config::default(), &mut |_| true).unwrap();
        let machine = outcome.controller.as_ref().unwrap();
        let dot = machine_dot(&spec, machine);
        let text = render_machine(&spec, machine);
        assert!(dot.contains("initial-point"), "{dot}");
        for line in text.lines() {
            let (_, row) = line.split_once(": ").unwrap();
            let (label, _) = row.rsplit_once(" -> ").unwrap();
            assert!(dot.contains(label), "{label} is missing from {dot}");
        }
        // One drawn edge per pair of states with rows between them, and the initial arrow.
        let pairs: std::collections::BTreeSet<(&str, &str)> =
            text.lines().map(|line| (line.split_once(':').unwrap().0, line.rsplit_once(" -> ").unwrap().1)).collect();
        assert_eq!(dot.matches(" -> ").count(), pairs.len() + 1, "{dot}");
    }
}
