//! The abstract syntax tree of a `.sct` file, as the parser builds it (names unresolved).

use crate::diag::Span;

/// A dotted name such as `Machine1.React.S2`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Path {
    pub parts: Vec<String>,
    pub span: Span,
}

impl Path {
    pub fn text(&self) -> String {
        self.parts.join(".")
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum EdgeKind {
    Rising,
    Falling,
    Either,
    Cyclic,
}

#[derive(Clone, Debug, PartialEq, Eq)]
pub enum EventItem {
    /// `expr_span`, like the other `*_span`s and the addresses' spans, is the string literal's.
    Detect {
        edge: EdgeKind,
        expr: String,
        expr_span: Span,
        span: Span,
    },
    Executed {
        span: Span,
    },
    ResetOnDenial {
        addrs: Vec<(String, Span)>,
        span: Span,
    },
    OnAccept {
        code: String,
        code_span: Span,
        span: Span,
    },
    OnDenial {
        code: String,
        code_span: Span,
        span: Span,
    },
}

#[derive(Clone, Debug)]
pub struct EventDecl {
    pub name: String,
    pub name_span: Span,
    pub kind: Option<crate::sct::model::EventKind>,
    pub items: Vec<EventItem>,
}

#[derive(Clone, Debug)]
pub struct TimerDecl {
    pub name: String,
    pub name_span: Span,
    pub duration_ms: Option<u64>,
    pub start: Option<Path>,
    pub stops: Vec<Path>,
}

#[derive(Clone, Debug, PartialEq, Eq)]
pub enum CondExpr {
    True,
    False,
    State(Path),
    Not(Box<CondExpr>),
    /// Two or more operands; chains are flat so that their length adds no nesting.
    And(Vec<CondExpr>),
    /// Two or more operands, flat like `And`.
    Or(Vec<CondExpr>),
}

#[derive(Clone, Debug)]
pub enum StateItem {
    Trans { event: Path, target: String, target_span: Span, cond: Option<CondExpr>, span: Span },
    Forbid { events: Vec<Path>, cond: Option<CondExpr>, span: Span },
    Impossible { events: Vec<Path>, span: Span },
}

#[derive(Clone, Debug)]
pub struct StateDecl {
    pub name: String,
    pub span: Span,
    pub initial: bool,
    pub items: Vec<StateItem>,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AutKind {
    Plant,
    Spec,
}

/// A template namespace (role): its name, location and binding events.
pub type Namespace = (String, Span, Vec<(String, Span)>);

#[derive(Clone, Debug)]
pub struct AutDecl {
    pub kind: AutKind,
    pub name: String,
    pub name_span: Span,
    pub alphabet: Option<(Vec<Path>, Span)>,
    pub selfloops: Option<Span>,
    pub states: Vec<StateDecl>,
    /// Template only: binding events without a namespace.
    pub binds: Vec<(String, Span)>,
    /// Template only: namespaces (roles) and their binding events.
    pub namespaces: Vec<Namespace>,
}

#[derive(Clone, Debug)]
pub struct Binding {
    /// `ns`, `ns.event` or `event`.
    pub lhs: Path,
    pub rhs: Path,
}

#[derive(Clone, Debug)]
pub struct InstanceDecl {
    pub name: String,
    pub name_span: Span,
    pub template: Path,
    pub bindings: Vec<Binding>,
}

#[derive(Clone, Debug)]
pub enum Item {
    Module {
        name: String,
        name_span: Span,
        items: Vec<Item>,
    },
    Event(EventDecl),
    Timer(TimerDecl),
    Automaton(AutDecl),
    Template(AutDecl),
    Instance(InstanceDecl),
    /// `spec NAME = A | B | ...;` — the specification product (definition 6).
    SpecProduct {
        name: String,
        name_span: Span,
        operands: Vec<Path>,
    },
}
