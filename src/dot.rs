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
}

/// An edge of a drawing.
#[derive(Clone, Debug, Default)]
pub struct Edge {
    pub label: String,
    pub class: String,
    /// `dashed`, `bold`, or empty for a solid line.
    pub style: &'static str,
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

/// The DOT document of `graph`, laid out left to right.
pub fn document(graph: &Drawing) -> String {
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
        attrs
    };
    let edge_attrs = |_: &Drawing, edge: petgraph::graph::EdgeReference<'_, Edge>| {
        let e = edge.weight();
        let mut attrs = format!("class = {}", quote(&e.class));
        if !e.style.is_empty() {
            attrs.push_str(&format!(", style = {}", e.style));
        }
        attrs
    };
    let body = Dot::with_attr_getters(graph, &[Config::GraphContentOnly], &edge_attrs, &node_attrs);
    format!(
        "digraph {{\n    graph [rankdir = LR, bgcolor = \"transparent\", nodesep = 0.35, ranksep = 0.5, fontname = \"sans-serif\"];\n    \
         node [shape = box, style = rounded, fontname = \"sans-serif\", fontsize = 11, margin = \"0.12,0.05\"];\n    \
         edge [fontname = \"sans-serif\", fontsize = 10, arrowsize = 0.7];\n{body}}}\n"
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
        g.add_edge(b, a, Edge { label: "a\\b".into(), class: "edge-x".into(), style: "dashed" });
        let dot = document(&g);
        assert!(dot.starts_with("digraph {"), "{dot}");
        assert!(dot.contains(r#"label = "say \"hi\"\lnow""#), "{dot}");
        assert!(dot.contains(r#"tooltip = "say \"hi\"\nnow""#), "{dot}");
        assert!(dot.contains("shape = point, width = 0.08"), "{dot}");
        assert!(dot.contains(r#"1 -> 0 [ label = "a\\b" class = "edge-x", style = dashed]"#), "{dot}");
        assert!(dot.trim_end().ends_with('}'));
    }
}
