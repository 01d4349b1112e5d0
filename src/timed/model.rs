//! The timed game built from a checked specification (Peter 2005, chapter 3 and 4.3).
//!
//! Hardware and operator units are already expanded into automata (4.3.2, 4.3.3); plans are
//! plan automata (algorithm 4) whose `reset` commands are folded into the transitions that
//! reach them; conditions are resolved to sets of locations. Names are kept for display only:
//! everything else refers to dense indices.

use crate::diag::Span;
use crate::id::id_type;
use serde::Serialize;

id_type! {
    /// A clock: an index into [`Game::clocks`] (0 is the zones' reference clock), and a bit of
    /// the `resets` sets.
    #[derive(Default, Serialize)]
    #[serde(transparent)]
    pub struct ClockId;
}

id_type! {
    /// A message: an index into [`Game::messages`].
    #[derive(Serialize)]
    #[serde(transparent)]
    pub struct MsgId;
}

id_type! {
    /// A plant component: an index into [`Game::components`].
    #[derive(Serialize)]
    #[serde(transparent)]
    pub struct CompId;
}

id_type! {
    /// A location of one automaton (a component's or a plan's): an index into its locations.
    #[derive(Serialize)]
    #[serde(transparent)]
    pub struct LocId;
}

/// The complete game: plant components, plans, safety predicate, guards and side information.
#[derive(Clone, Debug, Serialize)]
pub struct Game {
    /// Milliseconds per clock time unit (`timeunit`, default 1 s).
    pub timeunit_ms: u64,
    /// Where `timeunit` is declared (`None`: the default), for diagnostics of the code generator.
    pub timeunit_span: Option<Span>,
    /// The PLC's scan time in milliseconds (`scan 10 ms;`), and where it is declared. `None`:
    /// the zero-time controller of the thesis.
    pub scan_ms: Option<(u64, Span)>,
    /// Set in a scan game (built by [`super::scan::scan_game`]): the messages of its scan
    /// automaton, which the solver treats specially.
    pub scan: Option<super::scan::ScanRoles>,
    /// Index 0 is the reference clock of the zones; real clocks start at 1.
    pub clocks: Vec<Clock>,
    pub messages: Vec<Message>,
    pub components: Vec<Automaton>,
    pub plans: Vec<PlanAutomaton>,
    /// Every rule must hold in every reachable state (4.3.4).
    pub assertions: Vec<AssertionRule>,
    pub guards: Vec<GuardRule>,
    pub dependencies: Vec<DependencyRule>,
    pub io: Vec<IoBinding>,
}

#[derive(Clone, Debug, Serialize)]
pub struct Clock {
    /// Qualified name: `unit.clock` or `plan1.timeout`.
    pub name: String,
    pub owner: ClockOwner,
    /// Its declaration: the clock name, the unit of a hardware or operator clock, or a plan's
    /// `name bound` (diagnostics of the code generator find the bound there).
    pub span: Span,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(tag = "kind", content = "index", rename_all = "lowercase")]
pub enum ClockOwner {
    Reference,
    Component(CompId),
    Plan(u32),
}

/// What a message is to the controller.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum MessageRole {
    /// Sent by the controller (`?`): an output of the PLC.
    Request,
    /// Sent by the plant (`!`): an input of the PLC.
    Reaction,
    /// A state-guard condition (4.2.1): an input of the PLC.
    Guard,
}

#[derive(Clone, Debug, Serialize)]
pub struct Message {
    pub name: String,
    pub role: MessageRole,
    /// The one component that sends it with `?` or `!` (none for guard messages).
    pub sender: Option<CompId>,
    /// Components that take a `$` transition on it.
    pub synchronised: Vec<CompId>,
}

/// Where a plant component came from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum ComponentOrigin {
    Automaton,
    Hardware,
    Operator,
}

/// A timed game automaton of the plant.
#[derive(Clone, Debug, Serialize)]
pub struct Automaton {
    pub name: String,
    pub origin: ComponentOrigin,
    pub locations: Vec<Location>,
    pub initial: LocId,
    pub clocks: Vec<ClockId>,
    pub edges: Vec<Edge>,
    pub span: Span,
}

#[derive(Clone, Debug, Serialize)]
pub struct Location {
    pub name: String,
    pub invariant: Vec<ClockInterval>,
    /// Where the node (or the hardware state or move it was expanded from) is declared.
    pub span: Span,
}

/// `clock ∈ interval`; guards and invariants are conjunctions of these.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub struct ClockInterval {
    pub clock: ClockId,
    pub interval: Interval,
}

#[derive(Clone, Debug, Serialize)]
pub struct Edge {
    pub from: LocId,
    pub to: LocId,
    pub kind: MessageKind,
    pub message: MsgId,
    pub guard: Vec<ClockInterval>,
    pub resets: Vec<ClockId>,
    pub instant: bool,
    pub span: Span,
}

/// A plan automaton (3.2, algorithm 4). Location `failed` is a sink; every other location waits
/// for messages, and fails when a timeout clock exceeds its bound.
#[derive(Clone, Debug, Serialize)]
pub struct PlanAutomaton {
    pub name: String,
    pub locations: Vec<PlanLocation>,
    pub initial: LocId,
    pub failed: LocId,
    /// Timeout clocks and their bounds: the plan fails as soon as a clock exceeds its bound.
    pub clocks: Vec<(ClockId, u32)>,
    pub edges: Vec<PlanEdge>,
    pub span: Span,
}

#[derive(Clone, Debug, Serialize)]
pub struct PlanLocation {
    pub name: String,
    pub span: Span,
}

/// Observing `message` in `from` moves the plan to `to`, resetting the clocks of the `reset`
/// commands passed on the way.
#[derive(Clone, Debug, Serialize)]
pub struct PlanEdge {
    pub from: LocId,
    pub message: MsgId,
    pub to: LocId,
    pub resets: Vec<ClockId>,
}

/// A predicate over the current locations of the plant components.
#[derive(Clone, Debug, Serialize)]
#[serde(tag = "kind", rename_all = "lowercase")]
pub enum Pred {
    Const {
        value: bool,
    },
    /// Component `comp` is in one of `locations`.
    At {
        comp: CompId,
        locations: Vec<LocId>,
    },
    Not {
        operand: Box<Pred>,
    },
    And {
        operands: Vec<Pred>,
    },
    Or {
        operands: Vec<Pred>,
    },
}

impl Pred {
    /// Evaluates on a vector holding one location per plant component.
    pub fn eval(&self, locations: &[LocId]) -> bool {
        match self {
            Pred::Const { value } => *value,
            Pred::At { comp, locations: set } => set.contains(&locations[(*comp).index()]),
            Pred::Not { operand } => !operand.eval(locations),
            Pred::And { operands } => operands.iter().all(|p| p.eval(locations)),
            Pred::Or { operands } => operands.iter().any(|p| p.eval(locations)),
        }
    }

    /// Marks in `read` (one flag per plant component) the components whose location it reads.
    pub fn mark_components(&self, read: &mut [bool]) {
        match self {
            Pred::Const { .. } => {}
            Pred::At { comp, .. } => read[comp.index()] = true,
            Pred::Not { operand } => operand.mark_components(read),
            Pred::And { operands } | Pred::Or { operands } => operands.iter().for_each(|p| p.mark_components(read)),
        }
    }
}

/// An assertion: `holds` must be true in every state of a winning strategy.
#[derive(Clone, Debug, Serialize)]
pub struct AssertionRule {
    pub holds: Pred,
    /// The assertion as written, for explanations.
    pub text: String,
    pub span: Span,
}

/// Entering a state satisfying `cond` by a controller request requires `message` (4.2.1).
#[derive(Clone, Debug, Serialize)]
pub struct GuardRule {
    pub cond: Pred,
    pub message: MsgId,
    pub text: String,
    pub span: Span,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(tag = "kind", content = "message", rename_all = "lowercase")]
pub enum DependsOn {
    Time,
    Message(MsgId),
}

/// `message dependson …` (4.1.5): used by the optimiser of the code generator.
#[derive(Clone, Debug, Serialize)]
pub struct DependencyRule {
    pub message: MsgId,
    pub on: Vec<DependsOn>,
}

/// A message's PLC signal. `mode` is never `Default` here: inputs get `Level`, requests `Pulse`.
#[derive(Clone, Debug, Serialize)]
pub struct IoBinding {
    pub message: MsgId,
    pub mode: IoMode,
    pub target: IoTarget,
}

impl Game {
    pub fn message_id(&self, name: &str) -> Option<MsgId> {
        self.messages.iter().position(|m| m.name == name).map(MsgId::new)
    }

    pub fn component_id(&self, name: &str) -> Option<CompId> {
        self.components.iter().position(|c| c.name == name).map(CompId::new)
    }

    /// Number of zone indices: the reference clock plus every real clock.
    pub fn dim(&self) -> usize {
        self.clocks.len()
    }
}

/// An interval with integer bounds; `upper: None` is `inf`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize)]
pub struct Interval {
    pub lower: u32,
    pub lower_closed: bool,
    pub upper: Option<u32>,
    pub upper_closed: bool,
    pub span: Span,
}

impl Interval {
    /// `[l, u]`.
    pub fn closed(lower: u32, upper: u32) -> Interval {
        Interval { lower, lower_closed: true, upper: Some(upper), upper_closed: true, span: Span::default() }
    }

    /// True if no real number lies in the interval.
    pub fn is_empty(&self) -> bool {
        match self.upper {
            None => false,
            Some(u) => u < self.lower || (u == self.lower && !(self.lower_closed && self.upper_closed)),
        }
    }
}

impl std::fmt::Display for Interval {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let open = if self.lower_closed { '[' } else { '(' };
        match self.upper {
            Some(u) => {
                let close = if self.upper_closed { ']' } else { ')' };
                write!(f, "{open}{},{u}{close}", self.lower)
            }
            None => write!(f, "{open}{},inf)", self.lower),
        }
    }
}

/// Message type of a transition.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum MessageKind {
    /// `?m`: a request the controller may send.
    Controllable,
    /// `!m`: a spontaneous reaction of the plant.
    Uncontrollable,
    /// `$m`: taken together with another component's `?m`/`!m`.
    Synchronised,
}

impl MessageKind {
    pub fn sigil(self) -> char {
        match self {
            MessageKind::Controllable => '?',
            MessageKind::Uncontrollable => '!',
            MessageKind::Synchronised => '$',
        }
    }
}

/// How a message maps to its signal.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum IoMode {
    /// Input: the message holds while the signal is TRUE (the default for inputs).
    Level,
    /// Input: the message holds while the signal is FALSE (`not %I0.0`).
    Negated,
    /// Output: the signal is TRUE for one scan (the default for requests).
    Pulse,
    /// Output: the request sets the signal (`set %Q0.0`).
    Set,
    /// Output: the request resets the signal (`reset %Q0.0`).
    Reset,
    /// Not written: chosen by the message's role.
    Default,
}

#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
#[serde(tag = "kind", rename_all = "lowercase")]
pub enum IoTarget {
    /// A direct IEC address such as `%I0.0`, `%QX1.3`, `%MW10` (stored without the `%`).
    Address { text: String, span: Span },
    /// A symbolic name, possibly dotted (`GVL.lamp`) or quoted (`"Lamp On"`, stored without the
    /// quotes and `quoted` set).
    Symbol { text: String, span: Span, quoted: bool },
}
