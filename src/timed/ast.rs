//! Abstract syntax of `.tga` specifications (Peter 2005, chapter 4, plus `timeunit` and `io`).
//!
//! Every node keeps the span of its source text so that semantic errors found later can be
//! located. The parser produces this tree together with all syntax diagnostics; names are not
//! resolved here (see `check`).

use crate::diag::Span;
use serde::Serialize;

// The values a checked game keeps (bounds, message kinds, io bindings) are model types; the
// syntax tree holds them as written.
pub use super::model::{Interval, IoMode, IoTarget, MessageKind};

/// An identifier with its location.
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
pub struct Ident {
    pub name: String,
    pub span: Span,
}

/// A whole specification. Sections may appear in any order and more than once; repeated
/// sections are concatenated.
#[derive(Clone, Debug, Default, Serialize)]
pub struct Spec {
    pub timeunit: Vec<TimeUnitDecl>,
    pub scan: Vec<TimeUnitDecl>,
    pub components: Vec<Component>,
    pub assertions: Vec<Assertion>,
    pub dependencies: Vec<Dependency>,
    pub guards: Vec<StateGuard>,
    pub plans: Vec<Plan>,
    pub io: Vec<IoEntry>,
}

/// `timeunit 100ms;`: the real duration of one time unit of the clocks; also `scan 10 ms;`, the
/// PLC's cycle time.
#[derive(Clone, Debug, Serialize)]
pub struct TimeUnitDecl {
    pub millis: u64,
    pub span: Span,
}

#[derive(Clone, Debug, Serialize)]
#[serde(tag = "kind", rename_all = "lowercase")]
pub enum Component {
    Automaton(AutomatonDecl),
    Hardware(HardwareDecl),
    Operator(OperatorDecl),
}

impl Component {
    pub fn name(&self) -> &Ident {
        match self {
            Component::Automaton(a) => &a.name,
            Component::Hardware(h) => &h.name,
            Component::Operator(o) => &o.name,
        }
    }
}

/// `automaton NAME { clocks …; nodes …; transitions … }` (4.1.1).
#[derive(Clone, Debug, Serialize)]
pub struct AutomatonDecl {
    pub name: Ident,
    pub clocks: Vec<Ident>,
    pub nodes: Vec<NodeDecl>,
    pub transitions: Vec<TransitionDecl>,
    pub span: Span,
}

/// A node and its invariant (a conjunction of clock intervals; empty means `true`).
#[derive(Clone, Debug, Serialize)]
pub struct NodeDecl {
    pub name: Ident,
    pub invariant: Vec<ClockConstraint>,
}

/// `clock in interval`.
#[derive(Clone, Debug, Serialize)]
pub struct ClockConstraint {
    pub clock: Ident,
    pub interval: Interval,
    pub span: Span,
}

/// `from -> to ?msg {guard} reset{clocks} instant;`
#[derive(Clone, Debug, Serialize)]
pub struct TransitionDecl {
    pub from: Ident,
    pub to: Ident,
    pub kind: MessageKind,
    pub message: Ident,
    pub guard: Vec<ClockConstraint>,
    pub resets: Vec<Ident>,
    pub instant: bool,
    pub span: Span,
}

/// `hardware NAME { states …; moves … }` (4.1.2).
#[derive(Clone, Debug, Serialize)]
pub struct HardwareDecl {
    pub name: Ident,
    pub states: Vec<Ident>,
    pub moves: Vec<MoveDecl>,
    pub span: Span,
}

/// `operator NAME { states …; moves … }` (4.1.3).
#[derive(Clone, Debug, Serialize)]
pub struct OperatorDecl {
    pub name: Ident,
    pub states: Vec<Ident>,
    pub moves: Vec<MoveDecl>,
    pub span: Span,
}

/// How the states of a move are connected.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum MoveShape {
    /// `A -> B`: from A to B.
    Forward,
    /// `A <- B`: from B to A.
    Backward,
    /// `A <-> B`: both directions.
    Both,
    /// `A, B, C`: every ordered pair of distinct listed states.
    All,
}

/// One line of a hardware or operator body.
#[derive(Clone, Debug, Serialize)]
pub struct MoveDecl {
    pub shape: MoveShape,
    pub states: Vec<Ident>,
    pub takes: Option<Interval>,
    pub span: Span,
}

impl MoveDecl {
    /// The directed (from, to) pairs this line declares.
    pub fn pairs(&self) -> Vec<(&Ident, &Ident)> {
        let s = &self.states;
        match self.shape {
            MoveShape::Forward if s.len() == 2 => vec![(&s[0], &s[1])],
            MoveShape::Backward if s.len() == 2 => vec![(&s[1], &s[0])],
            MoveShape::Both if s.len() == 2 => vec![(&s[0], &s[1]), (&s[1], &s[0])],
            MoveShape::All => {
                let mut pairs = Vec::new();
                for a in s {
                    for b in s {
                        if a.name != b.name {
                            pairs.push((a, b));
                        }
                    }
                }
                pairs
            }
            _ => Vec::new(),
        }
    }
}

/// A condition over the current nodes of the plant units (4.1.4).
#[derive(Clone, Debug, Serialize)]
#[serde(tag = "kind", rename_all = "lowercase")]
pub enum Cond {
    Const {
        value: bool,
        span: Span,
    },
    /// `unit.node`, or `unit.prefix*` when `prefix` is set.
    State {
        unit: Ident,
        node: Ident,
        prefix: bool,
        span: Span,
    },
    Not {
        operand: Box<Cond>,
        span: Span,
    },
    /// Two or more operands joined by `and`. Chains are flat, so that a long chain is a wide
    /// node rather than a deep tree (no recursion depth grows with its length).
    And {
        operands: Vec<Cond>,
        span: Span,
    },
    /// Two or more operands joined by `or`; flat like `And`.
    Or {
        operands: Vec<Cond>,
        span: Span,
    },
}

impl Cond {
    pub fn span(&self) -> Span {
        match self {
            Cond::Const { span, .. }
            | Cond::State { span, .. }
            | Cond::Not { span, .. }
            | Cond::And { span, .. }
            | Cond::Or { span, .. } => *span,
        }
    }
}

/// One line of the `assertions` section.
#[derive(Clone, Debug, Serialize)]
#[serde(tag = "kind", rename_all = "lowercase")]
pub enum Assertion {
    Never { cond: Cond, span: Span },
    Always { cond: Cond, span: Span },
    OnlyIf { cond: Cond, requires: Cond, span: Span },
}

impl Assertion {
    pub fn span(&self) -> Span {
        match self {
            Assertion::Never { span, .. } | Assertion::Always { span, .. } | Assertion::OnlyIf { span, .. } => *span,
        }
    }
}

/// What a message depends on.
#[derive(Clone, Debug, Serialize)]
#[serde(tag = "kind", rename_all = "lowercase")]
pub enum DependencyTarget {
    Time { span: Span },
    Message { name: Ident },
}

/// `msg dependson time, other;` (4.1.5).
#[derive(Clone, Debug, Serialize)]
pub struct Dependency {
    pub message: Ident,
    pub targets: Vec<DependencyTarget>,
    pub span: Span,
}

/// `cond guardedby message;` (4.2.1).
#[derive(Clone, Debug, Serialize)]
pub struct StateGuard {
    pub cond: Cond,
    pub message: Ident,
    pub span: Span,
}

/// `plan { clocks t 15; commands }` (4.2.2).
#[derive(Clone, Debug, Serialize)]
pub struct Plan {
    pub clocks: Vec<PlanClock>,
    pub commands: Vec<PlanCommand>,
    pub span: Span,
}

/// A timeout clock of a plan and its bound.
#[derive(Clone, Debug, Serialize)]
pub struct PlanClock {
    pub name: Ident,
    pub bound: u32,
    pub span: Span,
}

/// One (optionally labelled) plan command.
#[derive(Clone, Debug, Serialize)]
pub struct PlanCommand {
    pub label: Option<Ident>,
    pub action: PlanAction,
    pub span: Span,
}

#[derive(Clone, Debug, Serialize)]
#[serde(tag = "kind", rename_all = "lowercase")]
pub enum PlanAction {
    Reset { clocks: Vec<Ident> },
    Waitfor { items: Vec<WaitItem> },
}

/// `message` or `message -> label` inside `waitfor`.
#[derive(Clone, Debug, Serialize)]
pub struct WaitItem {
    pub message: Ident,
    pub target: Option<Ident>,
}

/// `message = [mode] target;` in the `io` section.
#[derive(Clone, Debug, Serialize)]
pub struct IoEntry {
    pub message: Ident,
    pub mode: IoMode,
    pub target: IoTarget,
    pub span: Span,
}
