//! DOT documents of the drawings the playground shows (supervisors, plant models, Mealy
//! machines), written by petgraph's [`Dot`] with the defaults every drawing shares.
//!
//! Engines build a petgraph [`DiGraph`] whose node and edge weights are [`Node`] and [`Edge`]:
//! a label (petgraph escapes it; a line break becomes a left-justified break) and a CSS class
//! the page styles. Graphviz then lays the document out in the browser.

use petgraph::dot::{Config, Dot};
use petgraph::graph::DiGraph;
use std::fmt;

/// A node of a drawing.
#[derive(Clone, Debug, Default)]
pub struct Node {
    pub label: String,
    /// CSS classes, space-separated (`state`, `initial-point`, `prohibits`, …).
    pub class: String,
    /// Hover text; the label when empty.
    pub tooltip: String,
    /// A Graphviz shape other than the default rounded box (`point`, `doublecircle`).
    pub shape: Option<&'static str>,
    /// The `id` of its SVG group, for the page to find it.
    pub id: Option<String>,
}

/// An edge of a drawing.
#[derive(Clone, Debug, Default)]
pub struct Edge {
    pub label: String,
    pub class: String,
    /// `dashed`, `dotted`, `bold`, or empty for a solid line.
    pub style: &'static str,
    /// Hover text; none when empty.
    pub tooltip: String,
}

impl fmt::Display for Node {
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str(&self.label)
    }
}

impl fmt::Display for Edge {
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str(&self.label)
    }
}

/// A drawing: nodes and edges with labels and classes.
pub type Drawing = DiGraph<Node, Edge>;

/// `text` as a quoted DOT string.
pub fn quote(text: &str) -> String {
    let mut out = String::with_capacity(text.len() + 2);
    out.push('"');
    for c in text.chars() {
        match c {
            '"' | '\\' => {
                out.push('\\');
                out.push(c);
            }
            '\n' => out.push_str("\\n"),
            _ => out.push(c),
        }
    }
    out.push('"');
    out
}

/// The look of a drawing: its direction and the default attributes of the graph, its nodes and
/// its edges (DOT attribute lists without brackets).
pub struct Layout {
    pub graph: &'static str,
    pub node: &'static str,
    pub edge: &'static str,
}

/// Automata, supervisors and Mealy machines: left to right, rounded boxes.
pub const AUTOMATON: Layout = Layout {
    graph: "rankdir = LR, bgcolor = \"transparent\", nodesep = 0.35, ranksep = 0.5, fontname = \"sans-serif\"",
    node: "shape = box, style = rounded, fontname = \"sans-serif\", fontsize = 11, margin = \"0.12,0.05\"",
    edge: "fontname = \"sans-serif\", fontsize = 10, arrowsize = 0.7",
};

/// The DOT document of `graph`, laid out left to right.
pub fn document(graph: &Drawing) -> String {
    document_with(graph, &AUTOMATON)
}

/// The DOT document of `graph` in `layout`.
pub fn document_with(graph: &Drawing, layout: &Layout) -> String {
    let node_attrs = |_: &Drawing, (_, node): (petgraph::graph::NodeIndex, &Node)| {
        let mut attrs = format!("class = {}", quote(&node.class));
        let tooltip = if node.tooltip.is_empty() { &node.label } else { &node.tooltip };
        attrs.push_str(&format!(", tooltip = {}", quote(tooltip)));
        if let Some(shape) = node.shape {
            attrs.push_str(&format!(", shape = {shape}"));
            if shape == "point" {
                attrs.push_str(", width = 0.08");
            }
        }
        if let Some(id) = &node.id {
            attrs.push_str(&format!(", id = {}", quote(id)));
        }
        attrs
    };
    let edge_attrs = |_: &Drawing, edge: petgraph::graph::EdgeReference<'_, Edge>| {
        let e = edge.weight();
        let mut attrs = format!("class = {}", quote(&e.class));
        if !e.style.is_empty() {
            attrs.push_str(&format!(", style = {}", e.style));
        }
        if !e.tooltip.is_empty() {
            attrs.push_str(&format!(", tooltip = {}", quote(&e.tooltip)));
        }
        attrs
    };
    let body = Dot::with_attr_getters(graph, &[Config::GraphContentOnly], &edge_attrs, &node_attrs);
    format!(
        "digraph {{\n    graph [{}];\n    node [{}];\n    edge [{}];\n{body}}}\n",
        layout.graph, layout.node, layout.edge
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn labels_and_attributes_are_escaped() {
        let mut g = Drawing::new();
        let a = g.add_node(Node { label: "say \"hi\"\nnow".into(), class: "location".into(), ..Node::default() });
        let b = g.add_node(Node {
            label: String::new(),
            class: "initial-point".into(),
            shape: Some("point"),
            ..Node::default()
        });
        g.add_edge(
            b,
            a,
            Edge { label: "a\\b".into(), class: "edge-x".into(), style: "dashed", tooltip: String::new() },
        );
        let dot = document(&g);
        assert!(dot.starts_with("digraph {"), "{dot}");
        assert!(dot.contains(r#"label = "say \"hi\"\lnow""#), "{dot}");
        assert!(dot.contains(r#"tooltip = "say \"hi\"\nnow""#), "{dot}");
        assert!(dot.contains("shape = point, width = 0.08"), "{dot}");
        assert!(dot.contains(r#"1 -> 0 [ label = "a\\b" class = "edge-x", style = dashed]"#), "{dot}");
        assert!(dot.trim_end().ends_with('}'));
    }
}
