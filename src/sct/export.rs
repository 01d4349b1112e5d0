//! Drawings of a project's automata for the playground: plant models, specifications and
//! synthesised supervisors as DOT documents ([`crate::dot`]), grouped by module.
//!
//! What a drawing shows, after the thesis's figures: a specification's prohibitions are listed
//! in their state (`✕ event [condition]`), conditions stand on their edges in brackets, an
//! enforced event is marked in its supervisor state (`⇒ event`) and its edge is bold, and every
//! edge is classed by its event's kind (controllable, uncontrollable, enforceable).

use super::model::{Cond, EventId, EventKind, Project, Supervisor, Transition};
use crate::dot::{self, Drawing, Edge, Node};
use petgraph::graph::NodeIndex;
use serde::Serialize;
use std::collections::BTreeMap;

/// One drawn automaton.
#[derive(Clone, Debug, Serialize)]
pub struct AutomatonDrawing {
    /// The fully qualified name (`Line1.Machine`).
    pub name: String,
    /// The module it is declared in (`Line1`), empty at the top level.
    pub module: String,
    /// `plant`, `spec` or `supervisor`.
    pub kind: &'static str,
    pub states: usize,
    pub transitions: usize,
    pub dot: String,
}

/// The module of a qualified name: everything before its last dot.
pub fn module_of(name: &str) -> &str {
    name.rsplit_once('.').map_or("", |(module, _)| module)
}

/// A condition in the language's notation: `Valve.open and not Tank.full`.
pub fn cond_text(project: &Project, cond: &Cond) -> String {
    fn go(p: &Project, c: &Cond, out: &mut String, parent_and: bool) {
        match c {
            Cond::True => out.push_str("true"),
            Cond::False => out.push_str("false"),
            Cond::State { plant, state } => {
                let plant = &p.plants[*plant as usize];
                out.push_str(&plant.name);
                out.push('.');
                out.push_str(&plant.states[*state as usize]);
            }
            Cond::Not(inner) => {
                out.push_str("not ");
                let atomic = matches!(**inner, Cond::State { .. } | Cond::True | Cond::False);
                if !atomic {
                    out.push('(');
                }
                go(p, inner, out, false);
                if !atomic {
                    out.push(')');
                }
            }
            Cond::And(a, b) => {
                go(p, a, out, true);
                out.push_str(" and ");
                go(p, b, out, true);
            }
            Cond::Or(a, b) => {
                if parent_and {
                    out.push('(');
                }
                go(p, a, out, false);
                out.push_str(" or ");
                go(p, b, out, false);
                if parent_and {
                    out.push(')');
                }
            }
        }
    }
    let mut out = String::new();
    go(project, cond, &mut out, false);
    out
}

fn kind_class(project: &Project, event: EventId) -> &'static str {
    match project.kind(event) {
        EventKind::Controllable => "ev-controllable",
        EventKind::Uncontrollable => "ev-uncontrollable",
        EventKind::Enforceable => "ev-enforceable",
    }
}

/// An event with its condition, if any: `open [Tank.low]` (the condition in brackets, as written).
fn guarded(project: &Project, event: EventId, cond: &Cond) -> String {
    let name = project.event_name(event);
    if cond.is_true() {
        name.to_string()
    } else {
        format!("{name} [{}]", cond_text(project, cond))
    }
}

/// Adds the states and an arrow from a point into the initial one.
fn add_states(g: &mut Drawing, labels: impl Iterator<Item = Node>, init: Option<u32>) -> Vec<NodeIndex> {
    let nodes: Vec<NodeIndex> = labels.map(|n| g.add_node(n)).collect();
    if let Some(init) = init {
        let point = g.add_node(Node { class: "initial-point".into(), shape: Some("point"), ..Node::default() });
        g.add_edge(point, nodes[init as usize], Edge { class: "initial".into(), ..Edge::default() });
    }
    nodes
}

/// Edges between the same two states with events of one kind share one drawn edge, one label
/// line per event: large plants stay readable.
fn add_edges(
    g: &mut Drawing,
    nodes: &[NodeIndex],
    edges: impl Iterator<Item = (u32, u32, &'static str, String, bool)>,
) {
    let mut merged: BTreeMap<(u32, u32, &'static str, bool), Vec<String>> = BTreeMap::new();
    for (from, to, class, label, bold) in edges {
        merged.entry((from, to, class, bold)).or_default().push(label);
    }
    for ((from, to, class, bold), labels) in merged {
        let style = if bold {
            "bold"
        } else if class == "ev-uncontrollable" {
            "dashed"
        } else {
            ""
        };
        let class = if bold { format!("{class} enforced") } else { class.to_string() };
        g.add_edge(
            nodes[from as usize],
            nodes[to as usize],
            Edge { label: labels.join("\n"), class, style, ..Edge::default() },
        );
    }
}

fn transitions<'a>(
    project: &'a Project,
    trans: &'a [Transition],
) -> impl Iterator<Item = (u32, u32, &'static str, String, bool)> + 'a {
    trans.iter().map(move |t| (t.src, t.dst, kind_class(project, t.event), guarded(project, t.event, &t.cond), false))
}

/// Plant `index` of `project`.
pub fn plant(project: &Project, index: usize) -> AutomatonDrawing {
    let plant = &project.plants[index];
    let mut g = Drawing::new();
    let states = plant.states.iter().map(|s| Node { label: s.clone(), class: "location".into(), ..Node::default() });
    let nodes = add_states(&mut g, states, Some(plant.init));
    add_edges(&mut g, &nodes, transitions(project, &plant.trans));
    AutomatonDrawing {
        name: plant.name.clone(),
        module: module_of(&plant.name).to_string(),
        kind: "plant",
        states: plant.states.len(),
        transitions: plant.trans.len(),
        dot: dot::document(&g),
    }
}

/// Specification `index` of `project`, its prohibitions listed in their states.
pub fn spec(project: &Project, index: usize) -> AutomatonDrawing {
    let spec = &project.specs[index];
    let mut g = Drawing::new();
    let states = spec.states.iter().enumerate().map(|(s, name)| {
        let forbidden: Vec<String> = spec
            .prohib
            .iter()
            .filter(|p| p.state as usize == s)
            .map(|p| format!("✕ {}", guarded(project, p.event, &p.cond)))
            .collect();
        if forbidden.is_empty() {
            Node { label: name.clone(), class: "location".into(), ..Node::default() }
        } else {
            Node {
                label: format!("{name}\n{}", forbidden.join("\n")),
                class: "location prohibits".into(),
                tooltip: format!("{name}: prohibits {}", forbidden.join(", ").replace("✕ ", "")),
                ..Node::default()
            }
        }
    });
    let nodes = add_states(&mut g, states, Some(spec.init));
    add_edges(&mut g, &nodes, transitions(project, &spec.trans));
    AutomatonDrawing {
        name: spec.name.clone(),
        module: module_of(&spec.name).to_string(),
        kind: "spec",
        states: spec.states.len(),
        transitions: spec.trans.len(),
        dot: dot::document(&g),
    }
}

/// A synthesised supervisor: prohibited events in their states, the enforced event marked
/// (`⇒`) and its edge bold; events without an edge leave the state unchanged.
pub fn supervisor(project: &Project, sup: &Supervisor) -> AutomatonDrawing {
    let mut g = Drawing::new();
    let states = sup.states.iter().map(|st| {
        let mut lines = vec![st.label.clone()];
        let mut class = String::from("location");
        if !st.prohibited.is_empty() {
            let names: Vec<&str> = st.prohibited.iter().map(|&e| project.event_name(e)).collect();
            lines.push(format!("✕ {}", names.join(", ")));
            class.push_str(" prohibits");
        }
        if let Some(e) = st.enforced {
            lines.push(format!("⇒ {}", project.event_name(e)));
            class.push_str(" enforces");
        }
        Node { label: lines.join("\n"), class, ..Node::default() }
    });
    let nodes = add_states(&mut g, states, sup.init);
    let edges = sup.states.iter().enumerate().flat_map(|(s, st)| {
        st.transitions.iter().map(move |&(e, t)| {
            (s as u32, t, kind_class(project, e), project.event_name(e).to_string(), st.enforced == Some(e))
        })
    });
    add_edges(&mut g, &nodes, edges);
    AutomatonDrawing {
        name: sup.name.clone(),
        module: module_of(&sup.name).to_string(),
        kind: "supervisor",
        states: sup.states.len(),
        transitions: sup.num_transitions(),
        dot: dot::document(&g),
    }
}

/// Every plant model and specification of `project`, plants first, in declaration order.
pub fn models(project: &Project) -> Vec<AutomatonDrawing> {
    (0..project.plants.len())
        .map(|i| plant(project, i))
        .chain((0..project.specs.len()).map(|i| spec(project, i)))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sct::{compile, model::Config, synthesize, Synthesis};

    const TANK: &str = "event open : controllable;\nevent alarm : uncontrollable;\nevent spill : uncontrollable;\n\
        module Site { plant Tank { alphabet open, alarm, spill;\n\
          state A { open -> B; } state B { alarm -> C; } state C { spill -> C; } } }\n\
        spec NoSpill { state S { forbid spill; } }";

    #[test]
    fn plants_specs_and_supervisors_are_drawn_with_their_marks() {
        let (loaded, diagnostics) = compile(TANK).unwrap_or_else(|d| panic!("{d:?}"));
        assert!(diagnostics.is_empty(), "{diagnostics:?}");
        let drawn = models(&loaded.project);
        assert_eq!(
            drawn.iter().map(|d| (d.name.as_str(), d.kind)).collect::<Vec<_>>(),
            [("Site.Tank", "plant"), ("NoSpill", "spec")]
        );
        assert_eq!(drawn[0].module, "Site");
        assert_eq!((drawn[0].states, drawn[0].transitions), (3, 3));
        assert!(drawn[0].dot.contains("label = \"open\" class = \"ev-controllable\""), "{}", drawn[0].dot);
        assert!(drawn[0].dot.contains("class = \"ev-uncontrollable\", style = dashed"), "{}", drawn[0].dot);
        assert!(drawn[1].dot.contains("✕ spill"), "{}", drawn[1].dot);
        assert!(drawn[1].dot.contains("class = \"location prohibits\""), "{}", drawn[1].dot);

        let Synthesis { reports, .. } = synthesize(TANK, &loaded, &Config::default(), None, &mut |_| true);
        let sup = supervisor(&loaded.project, &reports[0].supervisor);
        assert_eq!(sup.kind, "supervisor");
        assert_eq!(sup.states, reports[0].states);
        assert!(sup.dot.contains("✕ open"), "the supervisor prohibits open before the alarm: {}", sup.dot);
        assert!(sup.dot.contains("initial-point"), "{}", sup.dot);
    }

    #[test]
    fn conditions_print_in_the_language_notation() {
        let src = "event go : controllable;\nplant V { alphabet go; state Closed { go -> Open; } state Open { } }\n\
                   plant W { alphabet go; state Low { } state High { } }\n\
                   spec S { state A { forbid go if [V.Open and not (W.Low or W.High)]; } }";
        let (loaded, _) = compile(src).unwrap_or_else(|d| panic!("{d:?}"));
        let p = &loaded.project;
        let cond = &p.specs[0].prohib[0].cond;
        assert_eq!(cond_text(p, cond), "V.Open and not (W.Low or W.High)");
    }
}
