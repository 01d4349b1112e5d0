//! Import and export of Supremica/Waters module files (`.wmod`).
//!
//! A Waters module is XML in the namespace [`NS_MODULE`] (newer files put comments in
//! [`NS_BASE`], prefixed `B:`): a `<Module Name=…>` with an `<EventDeclList>` of `<EventDecl
//! Kind="CONTROLLABLE|UNCONTROLLABLE|PROPOSITION" Name=…>`, an optional `<EventAliasList>` and a
//! `<ComponentList>` of `<SimpleComponent Kind="PLANT|SPEC|SUPERVISOR|PROPERTY" Name=…>`, each
//! holding one `<Graph>`: an optional `<LabelBlock>` of *blocked* events (in the component's
//! alphabet, on no edge; `:accepting` there when no state is marked), a `<NodeList>` of `<SimpleNode Name=… Initial="true">` whose
//! `<EventList>` names the propositions `:accepting` (marked) and `:forbidden`, and an
//! `<EdgeList>` of `<Edge Source=… Target=…>` whose `<LabelBlock>` names one or more events or
//! event aliases (an edge with several labels is several transitions).
//!
//! What is read: the above, attributes in any order, namespace prefixes, comments, processing
//! instructions and any whitespace; layout (`*Geometry` elements) and attribute maps are
//! skipped. A component that never names `:accepting` has every state marked (the Waters
//! convention: a proposition outside a component's alphabet does not constrain it). A
//! `:forbidden` state of a specification, supervisor or property is left out with its edges
//! (reaching it is what the component forbids); in a plant it is an error. What is refused,
//! each with a located error naming the element: EFA variables (`<VariableComponent>`), guards
//! and actions (`<GuardActionBlock>`), instances and parameters (`<Instance>`,
//! `<ConstantAliasList>`, …), indexed names and `foreach` blocks, group nodes, unobservable
//! events, propositions other than `:accepting` and `:forbidden` on nodes; and, because the
//! classic automata are deterministic, a second initial state or a second edge leaving a state
//! on one event towards another target. Nothing is dropped silently: an element the reader does
//! not know is an error too.
//!
//! The writer emits such a module in the layout Supremica writes (without geometry, which
//! Supremica computes when it opens a graph without it): events with their kinds and
//! `:accepting`, components with their kinds, marked states, blocked events, edges grouped by
//! target. plcsynth's enforceable events (`.sct`) have no Waters kind; they are written
//! `CONTROLLABLE` with the attribute `plcsynth:enforceable` in the event's `<AttributeMap>`
//! (where Waters tools keep their own data), which this reader reads back.

use super::{Automaton, AutomatonBuilder, ClassicEventId, Events, StateId};
use crate::diag::Span;
use hashbrown::{HashMap, HashSet};
use std::fmt::Write as _;

/// The attribute holding an event's `.sct` properties (the text between the braces of its
/// declaration: triggers and actions), so that a project exported and imported again keeps
/// them.
pub const SCT_ATTRIBUTE: &str = "plcsynth:sct";
/// The namespace of Waters modules.
pub const NS_MODULE: &str = "http://waters.sourceforge.net/xsd/module";
/// The namespace of Waters base elements (`B:Comment`).
pub const NS_BASE: &str = "http://waters.sourceforge.net/xsd/base";
/// The attribute that marks an enforceable event (a `.sct` notion Waters does not have).
pub const ENFORCEABLE_ATTRIBUTE: &str = "plcsynth:enforceable";

/// A located error in a `.wmod` text.
pub type WmodError = super::FileError;

/// The kind of a Waters component.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ComponentKind {
    Plant,
    Spec,
    Supervisor,
    Property,
}

impl ComponentKind {
    /// The `Kind` attribute as Waters writes it.
    pub fn waters_name(self) -> &'static str {
        match self {
            ComponentKind::Plant => "PLANT",
            ComponentKind::Spec => "SPEC",
            ComponentKind::Supervisor => "SUPERVISOR",
            ComponentKind::Property => "PROPERTY",
        }
    }

    fn parse(s: &str) -> Option<ComponentKind> {
        Some(match s {
            "PLANT" => ComponentKind::Plant,
            "SPEC" => ComponentKind::Spec,
            "SUPERVISOR" => ComponentKind::Supervisor,
            "PROPERTY" => ComponentKind::Property,
            _ => return None,
        })
    }
}

/// One `<SimpleComponent>` read as a classic automaton.
#[derive(Clone, Debug)]
pub struct Component {
    pub name: String,
    pub kind: ComponentKind,
    /// Its states (forbidden ones left out), transitions, alphabet (edge labels and blocked
    /// events) and marking.
    pub automaton: Automaton,
    /// Where the component's name is written.
    pub span: Span,
    /// Where each state's name is written (by state id).
    pub state_spans: Vec<Span>,
    /// How many `:forbidden` states were left out.
    pub forbidden: usize,
}

/// A module read from a `.wmod` text.
#[derive(Clone, Debug)]
pub struct Module {
    pub name: String,
    /// The events the module declares (not propositions), in the file's order.
    pub events: Vec<ClassicEventId>,
    /// The events marked [`ENFORCEABLE_ATTRIBUTE`].
    pub enforceable: Vec<ClassicEventId>,
    /// The events' attributes (`<AttributeMap>`): event, name, value.
    pub attributes: Vec<(ClassicEventId, String, String)>,
    pub components: Vec<Component>,
    /// Where each event is declared.
    event_spans: HashMap<ClassicEventId, Span>,
}

impl Module {
    /// Where the module declares `e`, if it does.
    pub fn event_span(&self, e: ClassicEventId) -> Option<Span> {
        self.event_spans.get(&e).copied()
    }

    pub fn is_enforceable(&self, e: ClassicEventId) -> bool {
        self.enforceable.contains(&e)
    }
}

/// Reads a module within the default state budget
/// ([`DEFAULT_MAX_STATES`](crate::sct::model::DEFAULT_MAX_STATES)).
pub fn read_wmod(src: &str, events: &mut Events) -> Result<Module, WmodError> {
    read_wmod_within(src, events, crate::sct::model::DEFAULT_MAX_STATES)
}

/// Reads a module, adding its events to `events` (an event already known keeps being
/// controllable if either source says so). A module with more than `max_states` states in all
/// its components is refused (a [`WmodError`] with `over_budget`) before they are built.
pub fn read_wmod_within(src: &str, events: &mut Events, max_states: usize) -> Result<Module, WmodError> {
    // The tree holds one node per element, attribute-free text and comment: bounded by the
    // input's length, which the caller chose to read.
    let options = roxmltree::ParsingOptions { allow_dtd: false, ..roxmltree::ParsingOptions::default() };
    let doc = roxmltree::Document::parse_with_options(src, options).map_err(|e| xml_error(src, &e))?;
    let mut r = Reader { events, max_states, states: 0, declared: HashMap::new(), aliases: HashMap::new() };
    r.module(doc.root_element())
}

/// The text of a module file's bytes: UTF-8 as it is; a file that is not UTF-8 but declares a
/// single-byte Western encoding (`windows-1252`, which Supremica writes, or `ISO-8859-1`) is
/// decoded from it. `None`: neither (XML without a declaration is UTF-8).
pub fn decode(bytes: &[u8]) -> Option<std::borrow::Cow<'_, str>> {
    if let Ok(s) = std::str::from_utf8(bytes) {
        return Some(std::borrow::Cow::Borrowed(s));
    }
    let head = String::from_utf8_lossy(&bytes[..bytes.len().min(200)]).to_ascii_lowercase();
    let declaration = head.strip_prefix("<?xml").and_then(|h| h.split("?>").next())?;
    let single_byte = ["windows-1252", "cp1252", "iso-8859-1", "iso8859-1", "latin1", "latin-1"]
        .iter()
        .any(|enc| declaration.contains(&format!("\"{enc}\"")) || declaration.contains(&format!("'{enc}'")));
    if !single_byte {
        return None;
    }
    // Windows-1252's 0x80–0x9F; the rest of the byte range is Latin-1. (Unassigned codes map
    // to the C1 control of the same number, as browsers do.)
    const HIGH: [u16; 32] = [
        0x20AC, 0x81, 0x201A, 0x192, 0x201E, 0x2026, 0x2020, 0x2021, 0x2C6, 0x2030, 0x160, 0x2039, 0x152, 0x8D, 0x17D,
        0x8F, 0x90, 0x2018, 0x2019, 0x201C, 0x201D, 0x2022, 0x2013, 0x2014, 0x2DC, 0x2122, 0x161, 0x203A, 0x153, 0x9D,
        0x17E, 0x178,
    ];
    let text = bytes
        .iter()
        .map(|&b| match b {
            0x80..=0x9F => char::from_u32(u32::from(HIGH[usize::from(b - 0x80)])).unwrap_or('\u{FFFD}'),
            b => char::from(b),
        })
        .collect();
    Some(std::borrow::Cow::Owned(text))
}

/// roxmltree's error, at its text position.
fn xml_error(src: &str, e: &roxmltree::Error) -> WmodError {
    let pos = e.pos();
    let index = crate::diag::LineIndex::new(src);
    let start = index.line_start(pos.row);
    let offset = src[start..]
        .char_indices()
        .nth((pos.col as usize).saturating_sub(1))
        .map_or(src.len(), |(i, _)| start + i)
        .min(src.len());
    let end = src[offset..].chars().next().map_or(offset, |c| offset + c.len_utf8());
    let message = e.to_string();
    // roxmltree appends " at ROW:COL"; the diagnostic has its own position.
    let message = match message.rfind(" at ") {
        Some(k) if message[k + 4..].chars().all(|c| c.is_ascii_digit() || c == ':') => message[..k].to_string(),
        _ => message,
    };
    WmodError::at(Span::new(offset, end), format!("malformed XML: {message}"))
}

/// What an event name declared in the module stands for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Declared {
    Event(ClassicEventId),
    Accepting,
    Forbidden,
    /// Any other proposition (multi-coloured marking), refused where it is used.
    Proposition,
}

type Node<'a, 'i> = roxmltree::Node<'a, 'i>;

/// An alias not resolved yet: its name, where it is declared, and its members with theirs.
type PendingAlias = (String, Span, Vec<(String, Span)>);

struct Reader<'e> {
    events: &'e mut Events,
    max_states: usize,
    /// States built so far, over all components.
    states: usize,
    declared: HashMap<String, Declared>,
    /// Alias name → the events it stands for.
    aliases: HashMap<String, Vec<ClassicEventId>>,
}

/// The element's start tag, for errors about the element.
fn tag_span(n: Node) -> Span {
    let r = n.range();
    let end = n.first_child().map_or(r.end, |c| c.range().start).min(r.end);
    Span::new(r.start, end)
}

/// The span of attribute `name`'s value (or of the tag without it).
fn attr_span(n: Node, name: &str) -> Span {
    n.attributes().find(|a| a.name() == name && a.namespace().is_none()).map_or(tag_span(n), |a| {
        let r = a.range_value();
        Span::new(r.start, r.end)
    })
}

fn local<'a>(n: Node<'a, '_>) -> &'a str {
    n.tag_name().name()
}

/// Elements that only carry layout or tool data: skipped wherever they appear.
fn is_presentation(n: Node) -> bool {
    let name = local(n);
    name.ends_with("Geometry")
        || name == "AttributeMap"
        || (name == "Comment" && n.tag_name().namespace() == Some(NS_BASE))
}

/// Why an element is refused, for its error's note.
fn unsupported_note(name: &str) -> &'static str {
    match name {
        "VariableComponent" => "EFA variables are not read: plcsynth synthesises over plain automata",
        "GuardActionBlock" => "guards and actions (EFA) are not read: plcsynth synthesises over plain automata",
        "Instance" | "InstanceDecl" | "ModuleInstance" | "ParameterBinding" | "ConstantAliasList" | "ConstantAlias" => {
            "module instances and parameters are not read: flatten the module in Supremica first"
        }
        "IndexedIdentifier" | "QualifiedIdentifier" | "RangeList" => {
            "indexed and qualified names are not read: plcsynth reads simple names only"
        }
        "ForeachComponent" | "ForeachEvent" | "ForeachEventAlias" => "foreach blocks are not read",
        "GroupNode" => "group nodes (hierarchical states) are not read",
        _ => "plcsynth reads plain automata: events, simple components, nodes and edges",
    }
}

fn unsupported(n: Node, parent: &str) -> WmodError {
    let name = local(n);
    WmodError::at(tag_span(n), format!("<{name}> in <{parent}> is not supported")).note(unsupported_note(name))
}

/// The element children of `n`, with anything but elements, layout and comments refused.
fn elements<'a, 'i>(n: Node<'a, 'i>) -> Result<Vec<Node<'a, 'i>>, WmodError> {
    let mut out = Vec::new();
    for c in n.children() {
        if c.is_element() {
            if !is_presentation(c) {
                out.push(c);
            }
        } else if c.is_text() && c.text().is_some_and(|t| !t.trim().is_empty()) {
            // The first character that is not a blank, in the source (the node's text may
            // differ from it by entities, so it is looked up in the source itself).
            let r = c.range();
            let raw = n.document().input_text().get(r.clone()).unwrap_or("");
            let lead = raw.len() - raw.trim_start().len();
            let width = raw[lead..].chars().next().map_or(0, char::len_utf8);
            return Err(WmodError::at(
                Span::new(r.start + lead, r.start + lead + width),
                format!("unexpected text in <{}>", local(n)),
            ));
        }
    }
    Ok(out)
}

/// Attribute `name`, which must be present and (a name, a kind) not empty.
fn required<'a>(n: Node<'a, '_>, name: &str) -> Result<&'a str, WmodError> {
    match n.attribute(name) {
        None => Err(WmodError::at(tag_span(n), format!("<{}> needs a `{name}` attribute", local(n)))),
        Some("") => Err(WmodError::at(attr_span(n, name), format!("the `{name}` of <{}> is empty", local(n)))),
        Some(v) => Ok(v),
    }
}

/// Refuses namespaces other than the module's (and no namespace, for hand-written files).
fn check_namespace(n: Node) -> Result<(), WmodError> {
    match n.tag_name().namespace() {
        None | Some(NS_MODULE) => Ok(()),
        Some(ns) => Err(WmodError::at(
            tag_span(n),
            format!("<{}> in the namespace `{ns}` is not part of a Waters module", local(n)),
        )
        .note(format!("Waters modules use `{NS_MODULE}`"))),
    }
}

impl Reader<'_> {
    fn module(&mut self, root: Node) -> Result<Module, WmodError> {
        if local(root) != "Module" {
            return Err(WmodError::at(tag_span(root), format!("the root element is <{}>, not <Module>", local(root)))
                .note("a Waters module (`.wmod`) is a <Module> element"));
        }
        check_namespace(root)?;
        let name = root.attribute("Name").unwrap_or("module").to_string();
        let mut module = Module {
            name,
            events: Vec::new(),
            enforceable: Vec::new(),
            attributes: Vec::new(),
            components: Vec::new(),
            event_spans: HashMap::new(),
        };
        let mut seen: HashSet<&str> = HashSet::new();
        let children = elements(root)?;
        // Events first, then aliases, then components, whatever the order in the file.
        for pass in ["EventDeclList", "EventAliasList", "ComponentList"] {
            for &c in &children {
                check_namespace(c)?;
                if local(c) != pass {
                    continue;
                }
                if !seen.insert(local(c)) {
                    return Err(WmodError::at(tag_span(c), format!("a second <{}>", local(c))));
                }
                match pass {
                    "EventDeclList" => self.event_decls(c, &mut module)?,
                    "EventAliasList" => self.aliases(c)?,
                    _ => self.components(c, &mut module)?,
                }
            }
        }
        if let Some(&c) =
            children.iter().find(|c| !matches!(local(**c), "EventDeclList" | "EventAliasList" | "ComponentList"))
        {
            return Err(unsupported(c, "Module"));
        }
        Ok(module)
    }

    fn event_decls(&mut self, list: Node, module: &mut Module) -> Result<(), WmodError> {
        for d in elements(list)? {
            check_namespace(d)?;
            if local(d) != "EventDecl" {
                return Err(unsupported(d, "EventDeclList"));
            }
            let name = required(d, "Name")?;
            let kind = required(d, "Kind")?;
            let span = attr_span(d, "Name");
            if self.declared.contains_key(name) {
                return Err(WmodError::at(span, format!("event `{name}` is declared twice")));
            }
            if d.attribute("Observable") == Some("false") {
                return Err(WmodError::at(attr_span(d, "Observable"), format!("event `{name}` is unobservable"))
                    .note("SupCon here assumes every event is observed; unobservable events are not read"));
            }
            let mut attributes: Vec<(String, String)> = Vec::new();
            for c in d.children().filter(|c| c.is_element()) {
                if local(c) == "AttributeMap" {
                    for a in c.children().filter(|a| a.is_element() && local(*a) == "Attribute") {
                        let key = a.attribute("Name").unwrap_or_default().to_string();
                        attributes.push((key, a.attribute("Value").unwrap_or_default().to_string()));
                    }
                } else if !is_presentation(c) {
                    return Err(unsupported(c, "EventDecl"));
                }
            }
            let enforceable = attributes.iter().any(|(k, v)| k == ENFORCEABLE_ATTRIBUTE && v != "false");
            let declared = match kind {
                "PROPOSITION" => match name {
                    ":accepting" => Declared::Accepting,
                    ":forbidden" => Declared::Forbidden,
                    _ => Declared::Proposition,
                },
                "CONTROLLABLE" | "UNCONTROLLABLE" if matches!(name, ":accepting" | ":forbidden") => {
                    return Err(WmodError::at(attr_span(d, "Kind"), format!("`{name}` is a proposition, not an event"))
                        .note("declare it with Kind=\"PROPOSITION\""))
                }
                "CONTROLLABLE" | "UNCONTROLLABLE" => {
                    let controllable = kind == "CONTROLLABLE";
                    let e = self.events.intern(name, controllable);
                    if controllable {
                        self.events.set_controllable(e, true);
                    }
                    module.events.push(e);
                    module.event_spans.insert(e, span);
                    if enforceable {
                        module.enforceable.push(e);
                    }
                    module.attributes.extend(attributes.into_iter().map(|(k, v)| (e, k, v)));
                    Declared::Event(e)
                }
                _ => {
                    return Err(WmodError::at(attr_span(d, "Kind"), format!("unknown event kind `{kind}`"))
                        .note("Waters event kinds are CONTROLLABLE, UNCONTROLLABLE and PROPOSITION"))
                }
            };
            self.declared.insert(name.to_string(), declared);
        }
        Ok(())
    }

    /// `<EventAlias Name=…><ExpressionList>` of names of events or other aliases; an alias may
    /// name an alias declared after it, but no cycle.
    fn aliases(&mut self, list: Node) -> Result<(), WmodError> {
        let mut pending: Vec<PendingAlias> = Vec::new();
        for a in elements(list)? {
            check_namespace(a)?;
            if local(a) != "EventAlias" {
                return Err(unsupported(a, "EventAliasList"));
            }
            let name = required(a, "Name")?;
            let span = attr_span(a, "Name");
            if self.declared.contains_key(name) || pending.iter().any(|(n, _, _)| n == name) {
                return Err(WmodError::at(span, format!("alias `{name}` has the name of another event or alias")));
            }
            let mut members = Vec::new();
            for c in elements(a)? {
                check_namespace(c)?;
                if local(c) != "ExpressionList" {
                    return Err(unsupported(c, "EventAlias"));
                }
                for id in elements(c)? {
                    check_namespace(id)?;
                    if local(id) != "SimpleIdentifier" {
                        return Err(unsupported(id, "ExpressionList"));
                    }
                    members.push((required(id, "Name")?.to_string(), attr_span(id, "Name")));
                }
            }
            pending.push((name.to_string(), span, members));
        }
        // Resolve in rounds: each round settles the aliases whose members are all known.
        while !pending.is_empty() {
            let before = pending.len();
            let mut i = 0;
            while i < pending.len() {
                let resolved: Option<Vec<ClassicEventId>> =
                    pending[i].2.iter().try_fold(Vec::new(), |mut acc, (m, _)| {
                        match (self.declared.get(m.as_str()), self.aliases.get(m.as_str())) {
                            (Some(Declared::Event(e)), _) => acc.push(*e),
                            (_, Some(es)) => acc.extend(es),
                            _ => return None,
                        }
                        Some(acc)
                    });
                match resolved {
                    Some(es) => {
                        let (name, _, _) = pending.swap_remove(i);
                        self.aliases.insert(name, es);
                    }
                    None => i += 1,
                }
            }
            if pending.len() == before {
                // Nothing settled: an unknown member, a proposition, or a cycle.
                let (alias, _, members) = &pending[0];
                for (m, span) in members {
                    match self.declared.get(m.as_str()) {
                        Some(Declared::Event(_)) => {}
                        Some(_) => {
                            return Err(WmodError::at(*span, format!("alias `{alias}` names the proposition `{m}`"))
                                .note("an alias of edge labels holds events only"))
                        }
                        None if self.aliases.contains_key(m.as_str()) => {}
                        None if pending.iter().any(|(n, _, _)| n == m) => {
                            return Err(WmodError::at(
                                *span,
                                format!("alias `{alias}` is part of a cycle of aliases through `{m}`"),
                            ))
                        }
                        None => {
                            return Err(WmodError::at(
                                *span,
                                format!("alias `{alias}` names `{m}`, which is not declared"),
                            ))
                        }
                    }
                }
                return Err(WmodError::at(pending[0].1, format!("alias `{alias}` cannot be resolved")));
            }
        }
        Ok(())
    }

    fn components(&mut self, list: Node, module: &mut Module) -> Result<(), WmodError> {
        for c in elements(list)? {
            check_namespace(c)?;
            if local(c) != "SimpleComponent" {
                return Err(unsupported(c, "ComponentList"));
            }
            let component = self.component(c)?;
            if module.components.iter().any(|o| o.name == component.name) {
                return Err(WmodError::at(component.span, format!("a second component `{}`", component.name)));
            }
            module.components.push(component);
        }
        Ok(())
    }

    /// The events a label names (an alias stands for its events), refusing propositions.
    fn label(&self, id: Node, parent: &str) -> Result<Vec<ClassicEventId>, WmodError> {
        check_namespace(id)?;
        if local(id) != "SimpleIdentifier" {
            return Err(unsupported(id, parent));
        }
        let name = required(id, "Name")?;
        let span = attr_span(id, "Name");
        match (self.declared.get(name), self.aliases.get(name)) {
            (Some(Declared::Event(e)), _) => Ok(vec![*e]),
            (Some(_), _) => Err(WmodError::at(span, format!("the proposition `{name}` labels an edge"))
                .note("edges carry events; propositions mark nodes")),
            (None, Some(es)) => Ok(es.clone()),
            (None, None) => Err(WmodError::at(span, format!("`{name}` is not a declared event or alias"))
                .note("declare it in the module's <EventDeclList>")),
        }
    }

    fn component(&mut self, c: Node) -> Result<Component, WmodError> {
        let name = required(c, "Name")?.to_string();
        let span = attr_span(c, "Name");
        let kind_text = required(c, "Kind")?;
        let kind = ComponentKind::parse(kind_text).ok_or_else(|| {
            WmodError::at(attr_span(c, "Kind"), format!("unknown component kind `{kind_text}`"))
                .note("Waters component kinds are PLANT, SPEC, SUPERVISOR and PROPERTY")
        })?;
        let mut graph = None;
        for g in elements(c)? {
            check_namespace(g)?;
            if local(g) != "Graph" {
                return Err(unsupported(g, "SimpleComponent"));
            }
            if graph.replace(g).is_some() {
                return Err(WmodError::at(tag_span(g), format!("a second <Graph> in component `{name}`")));
            }
        }
        let g = graph.ok_or_else(|| WmodError::at(tag_span(c), format!("component `{name}` has no <Graph>")))?;
        let (mut blocked, mut nodes, mut edges) = (None, None, None);
        for part in elements(g)? {
            check_namespace(part)?;
            let slot = match local(part) {
                "LabelBlock" => &mut blocked,
                "NodeList" => &mut nodes,
                "EdgeList" => &mut edges,
                _ => return Err(unsupported(part, "Graph")),
            };
            if slot.replace(part).is_some() {
                return Err(WmodError::at(tag_span(part), format!("a second <{}> in component `{name}`", local(part))));
            }
        }
        let mut b = AutomatonBuilder::new();
        let mut uses_marking = false;
        if let Some(block) = blocked {
            for id in elements(block)? {
                check_namespace(id)?;
                if local(id) == "SimpleIdentifier" {
                    match self.declared.get(required(id, "Name")?) {
                        Some(Declared::Accepting) => {
                            uses_marking = true;
                            continue;
                        }
                        Some(Declared::Forbidden) => continue,
                        _ => {}
                    }
                }
                for e in self.label(id, "LabelBlock")? {
                    b.add_event(e);
                }
            }
        }
        // Nodes: name → state id, or None for a forbidden state left out.
        let mut by_name: HashMap<&str, (Option<StateId>, Span)> = HashMap::new();
        let mut state_spans = Vec::new();
        let mut unmarked: Vec<StateId> = Vec::new();
        let mut initial: Option<(StateId, Span)> = None;
        let mut forbidden = 0;
        for n in nodes.map(elements).transpose()?.unwrap_or_default() {
            check_namespace(n)?;
            if local(n) != "SimpleNode" {
                return Err(unsupported(n, "NodeList"));
            }
            let node_name = required(n, "Name")?;
            let nspan = attr_span(n, "Name");
            if by_name.contains_key(node_name) {
                return Err(WmodError::at(nspan, format!("component `{name}` has two nodes named `{node_name}`")));
            }
            let is_initial = match n.attribute("Initial") {
                None | Some("false") => false,
                Some("true") => true,
                Some(v) => {
                    return Err(WmodError::at(
                        attr_span(n, "Initial"),
                        format!("`Initial` is `{v}`, not `true` or `false`"),
                    ))
                }
            };
            let (mut marked, mut is_forbidden) = (false, false);
            for list in elements(n)? {
                check_namespace(list)?;
                if local(list) != "EventList" {
                    return Err(unsupported(list, "SimpleNode"));
                }
                for id in elements(list)? {
                    check_namespace(id)?;
                    if local(id) != "SimpleIdentifier" {
                        return Err(unsupported(id, "EventList"));
                    }
                    let p = required(id, "Name")?;
                    match self.declared.get(p) {
                        Some(Declared::Accepting) => marked = true,
                        Some(Declared::Forbidden) => is_forbidden = true,
                        Some(Declared::Proposition) => {
                            return Err(WmodError::at(
                                attr_span(id, "Name"),
                                format!("the proposition `{p}` is not read"),
                            )
                            .note("plcsynth reads the propositions `:accepting` and `:forbidden` only"))
                        }
                        Some(Declared::Event(_)) => {
                            return Err(WmodError::at(
                                attr_span(id, "Name"),
                                format!("the event `{p}` is listed on a node"),
                            )
                            .note("a node's <EventList> holds propositions (`:accepting`, `:forbidden`)"))
                        }
                        None => {
                            return Err(WmodError::at(
                                attr_span(id, "Name"),
                                format!("`{p}` is not a declared proposition"),
                            )
                            .note("declare `:accepting` with Kind=\"PROPOSITION\""))
                        }
                    }
                }
            }
            uses_marking |= marked;
            if is_forbidden {
                if kind == ComponentKind::Plant {
                    return Err(WmodError::at(nspan, format!("plant `{name}` has the forbidden state `{node_name}`"))
                        .note("forbidden states are read in specifications, supervisors and properties only"));
                }
                // A forbidden initial state is no initial state: the component's language
                // starts nowhere there.
                forbidden += 1;
                by_name.insert(node_name, (None, nspan));
                continue;
            }
            if self.states >= self.max_states {
                return Err(WmodError::budget(nspan, "the module", self.max_states)
                    .note("raise the budget (`--max-states N`) if the module is meant to be this large"));
            }
            self.states += 1;
            let s = b.add_state(node_name, true);
            if !marked {
                unmarked.push(s);
            }
            state_spans.push(nspan);
            by_name.insert(node_name, (Some(s), nspan));
            if is_initial {
                if let Some((first, _)) = initial {
                    return Err(WmodError::at(
                        attr_span(n, "Initial"),
                        format!("a second initial state `{node_name}` in component `{name}` (the first is `{}`)", {
                            let k = first.index();
                            by_name.iter().find(|(_, v)| v.0 == Some(StateId::new(k))).map_or("?", |(n, _)| n)
                        }),
                    )
                    .note("SupCon needs deterministic automata: one initial state"));
                }
                initial = Some((s, nspan));
            }
        }
        if uses_marking {
            for s in unmarked {
                b.set_marked(s, false);
            }
        }
        if let Some((s, _)) = initial {
            b.set_init(s);
        }
        let mut seen: HashMap<(StateId, ClassicEventId), StateId> = HashMap::new();
        for edge in edges.map(elements).transpose()?.unwrap_or_default() {
            check_namespace(edge)?;
            if local(edge) != "Edge" {
                return Err(unsupported(edge, "EdgeList"));
            }
            let mut ends = [None, None];
            for (k, attr) in ["Source", "Target"].into_iter().enumerate() {
                let v = required(edge, attr)?;
                match by_name.get(v) {
                    Some(&(s, _)) => ends[k] = s,
                    None => {
                        return Err(WmodError::at(
                            attr_span(edge, attr),
                            format!("`{v}` is not a node of component `{name}`"),
                        ))
                    }
                }
            }
            let mut labels: Vec<(ClassicEventId, Span)> = Vec::new();
            for part in elements(edge)? {
                check_namespace(part)?;
                if local(part) != "LabelBlock" {
                    return Err(unsupported(part, "Edge"));
                }
                for id in elements(part)? {
                    let span = attr_span(id, "Name");
                    labels.extend(self.label(id, "LabelBlock")?.into_iter().map(|e| (e, span)));
                }
            }
            if labels.is_empty() {
                return Err(WmodError::at(tag_span(edge), format!("an edge of component `{name}` has no event"))
                    .note("label it with one or more events in a <LabelBlock>"));
            }
            for &(e, _) in &labels {
                b.add_event(e);
            }
            // An edge into or out of a forbidden state is left out with the state.
            let (Some(x1), Some(x2)) = (ends[0], ends[1]) else { continue };
            for (e, span) in labels {
                match seen.get(&(x1, e)) {
                    Some(&t) if t != x2 => {
                        return Err(WmodError::at(
                            span,
                            format!(
                                "state `{}` of component `{name}` has two edges on event `{}` (to `{}` and `{}`)",
                                edge.attribute("Source").unwrap_or("?"),
                                self.events.name(e),
                                state_name(&by_name, t),
                                state_name(&by_name, x2),
                            ),
                        )
                        .note("SupCon needs deterministic automata"));
                    }
                    Some(_) => {}
                    None => {
                        seen.insert((x1, e), x2);
                        b.add_transition(x1, e, x2);
                    }
                }
            }
        }
        let automaton =
            b.build().map_err(|_| WmodError::at(span, format!("component `{name}` is not a valid automaton")))?;
        Ok(Component { name, kind, automaton, span, state_spans, forbidden })
    }
}

fn state_name<'a>(by_name: &HashMap<&'a str, (Option<StateId>, Span)>, s: StateId) -> &'a str {
    by_name.iter().find(|(_, v)| v.0 == Some(s)).map_or("?", |(n, _)| n)
}

/// XML's five entities, for attribute values and text.
fn escape(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '&' => out.push_str("&amp;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            // Line breaks and tabs in attribute values would be normalised to blanks on reading.
            '\n' => out.push_str("&#10;"),
            '\r' => out.push_str("&#13;"),
            '\t' => out.push_str("&#9;"),
            c => out.push(c),
        }
    }
    out
}

/// A component to write.
pub struct ComponentOut<'a> {
    pub name: &'a str,
    pub kind: ComponentKind,
    pub automaton: &'a Automaton,
}

/// Writes a module of `components`, declaring the events of their alphabets (controllability
/// from `events`) with their `attributes` (event, name, value: an `<AttributeMap>`, such as
/// [`ENFORCEABLE_ATTRIBUTE`]) and `:accepting`; `comment`, if not empty, becomes the module's
/// `<B:Comment>`. State names are the automata's, made unique within a component (`name`,
/// `name_2`, …; `s<id>` for empty names), so that edges can refer to them.
pub fn write_wmod(
    module_name: &str,
    comment: &str,
    components: &[ComponentOut],
    events: &Events,
    attributes: &[(ClassicEventId, &str, String)],
) -> String {
    let mut used: Vec<ClassicEventId> =
        components.iter().flat_map(|c| c.automaton.alphabet().iter().copied()).collect();
    crate::sort::sort(&mut used);
    used.dedup();
    let mut o = String::from("<?xml version=\"1.0\" encoding=\"UTF-8\" standalone=\"yes\"?>\n");
    let _ = writeln!(o, "<Module Name=\"{}\" xmlns=\"{NS_MODULE}\" xmlns:B=\"{NS_BASE}\">", escape(module_name));
    if !comment.is_empty() {
        let _ = writeln!(o, "<B:Comment>{}</B:Comment>", escape(comment));
    }
    o.push_str("<EventDeclList>\n<EventDecl Kind=\"PROPOSITION\" Name=\":accepting\"/>\n");
    for &e in &used {
        let kind = if events.is_controllable(e) { "CONTROLLABLE" } else { "UNCONTROLLABLE" };
        let name = escape(events.name(e));
        let attrs: Vec<&(ClassicEventId, &str, String)> = attributes.iter().filter(|a| a.0 == e).collect();
        if attrs.is_empty() {
            let _ = writeln!(o, "<EventDecl Kind=\"{kind}\" Name=\"{name}\"/>");
            continue;
        }
        let _ = writeln!(o, "<EventDecl Kind=\"{kind}\" Name=\"{name}\">\n<AttributeMap>");
        for (_, key, value) in attrs {
            let _ = writeln!(o, "<Attribute Name=\"{}\" Value=\"{}\"/>", escape(key), escape(value));
        }
        o.push_str("</AttributeMap>\n</EventDecl>\n");
    }
    o.push_str("</EventDeclList>\n<ComponentList>\n");
    for c in components {
        let a = c.automaton;
        let _ = writeln!(o, "<SimpleComponent Kind=\"{}\" Name=\"{}\">\n<Graph>", c.kind.waters_name(), escape(c.name));
        let names = unique_state_names(a);
        let mut on_edge = vec![false; events.len()];
        for s in a.states() {
            for e in a.edges(s) {
                on_edge[e.event.index()] = true;
            }
        }
        let blocked: Vec<ClassicEventId> = a.alphabet().iter().copied().filter(|e| !on_edge[e.index()]).collect();
        // No state marked: `:accepting` in the alphabet all the same, or every state would
        // read as marked.
        let unmarked = a.num_states() > 0 && a.states().all(|s| !a.is_marked(s));
        if !blocked.is_empty() || unmarked {
            o.push_str("<LabelBlock>\n");
            if unmarked {
                o.push_str("<SimpleIdentifier Name=\":accepting\"/>\n");
            }
            for e in blocked {
                let _ = writeln!(o, "<SimpleIdentifier Name=\"{}\"/>", escape(events.name(e)));
            }
            o.push_str("</LabelBlock>\n");
        }
        if a.num_states() > 0 {
            o.push_str("<NodeList>\n");
            for s in a.states() {
                let initial = if a.init() == Some(s) { " Initial=\"true\"" } else { "" };
                let name = escape(&names[s.index()]);
                if a.is_marked(s) {
                    let _ = writeln!(
                        o,
                        "<SimpleNode{initial} Name=\"{name}\">\n<EventList>\n<SimpleIdentifier Name=\":accepting\"/>\n</EventList>\n</SimpleNode>"
                    );
                } else {
                    let _ = writeln!(o, "<SimpleNode{initial} Name=\"{name}\"/>");
                }
            }
            o.push_str("</NodeList>\n");
        }
        if a.num_transitions() > 0 {
            o.push_str("<EdgeList>\n");
            for s in a.states() {
                // One edge per target, labelled with all its events, as Supremica draws them.
                let mut by_target: Vec<(StateId, Vec<ClassicEventId>)> = Vec::new();
                for e in a.edges(s) {
                    match by_target.iter_mut().find(|(t, _)| *t == e.target) {
                        Some((_, es)) => es.push(e.event),
                        None => by_target.push((e.target, vec![e.event])),
                    }
                }
                for (t, es) in by_target {
                    let _ = writeln!(
                        o,
                        "<Edge Source=\"{}\" Target=\"{}\">\n<LabelBlock>",
                        escape(&names[s.index()]),
                        escape(&names[t.index()])
                    );
                    for e in es {
                        let _ = writeln!(o, "<SimpleIdentifier Name=\"{}\"/>", escape(events.name(e)));
                    }
                    o.push_str("</LabelBlock>\n</Edge>\n");
                }
            }
            o.push_str("</EdgeList>\n");
        }
        o.push_str("</Graph>\n</SimpleComponent>\n");
    }
    o.push_str("</ComponentList>\n</Module>\n");
    o
}

/// The automaton's state names, unique: a repeated or empty name gets a suffix or `s<id>`.
fn unique_state_names(a: &Automaton) -> Vec<String> {
    let mut taken: HashSet<String> = HashSet::new();
    let mut out = Vec::with_capacity(a.num_states());
    for s in a.states() {
        let base = a.state_name(s);
        let base = if base.is_empty() { format!("s{s}") } else { base.to_string() };
        let mut name = base.clone();
        let mut k = 2;
        while !taken.insert(name.clone()) {
            name = format!("{base}_{k}");
            k += 1;
        }
        out.push(name);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Written as Supremica writes modules: namespace prefixes, a `B:Comment`, layout elements,
    /// `Initial` before `Name`, an edge with two labels, an alias, blocked events.
    const SUPREMICA_STYLE: &str = r#"<?xml version="1.0" encoding="UTF-8" standalone="yes"?>
<!-- a comment before the root -->
<Module Name="cell" xmlns="http://waters.sourceforge.net/xsd/module" xmlns:B="http://waters.sourceforge.net/xsd/base">
<B:Comment>Two machines &amp; a buffer.</B:Comment>
<EventDeclList>
<EventDecl Kind="PROPOSITION" Name=":accepting"/>
<EventDecl Kind="PROPOSITION" Name=":forbidden"/>
<EventDecl Kind="CONTROLLABLE" Name="start"><ColorGeometry><Color Red="0" Green="0" Blue="255"/></ColorGeometry></EventDecl>
<EventDecl Name="finish" Kind="UNCONTROLLABLE"/>
<EventDecl Kind="UNCONTROLLABLE" Name="break"/>
</EventDeclList>
<EventAliasList>
<EventAlias Name="done"><ExpressionList><SimpleIdentifier Name="finish"/><SimpleIdentifier Name="break"/></ExpressionList></EventAlias>
</EventAliasList>
<ComponentList>
<SimpleComponent Kind="PLANT" Name="M">
<Graph>
<NodeList>
<SimpleNode Initial="true" Name="idle">
<EventList>
<SimpleIdentifier Name=":accepting"/>
</EventList>
<PointGeometry>
<Point X="48" Y="-176"/>
</PointGeometry>
</SimpleNode>
<SimpleNode Name="busy"/>
</NodeList>
<EdgeList>
<Edge Source="idle" Target="busy">
<LabelBlock><SimpleIdentifier Name="start"/><LabelGeometry Anchor="NW"><Point X="4" Y="6"/></LabelGeometry></LabelBlock>
<SplineGeometry><Point X="78" Y="-109"/></SplineGeometry>
</Edge>
<Edge   Target = "idle"
        Source='busy' >
<LabelBlock>
  <SimpleIdentifier Name="done"/>
</LabelBlock>
</Edge>
</EdgeList>
</Graph>
</SimpleComponent>
<SimpleComponent Kind="SPEC" Name="NoBreak">
<Graph Deterministic="true">
<LabelBlock><SimpleIdentifier Name="start"/></LabelBlock>
<NodeList>
<SimpleNode Initial="true" Name="ok"/>
<SimpleNode Name="bad"><EventList><SimpleIdentifier Name=":forbidden"/></EventList></SimpleNode>
</NodeList>
<EdgeList>
<Edge Source="ok" Target="bad"><LabelBlock><SimpleIdentifier Name="break"/></LabelBlock></Edge>
</EdgeList>
</Graph>
</SimpleComponent>
</ComponentList>
</Module>
"#;

    #[test]
    fn reads_supremica_style_modules() {
        let mut ev = Events::new();
        let m = read_wmod(SUPREMICA_STYLE, &mut ev).unwrap();
        assert_eq!(m.name, "cell");
        assert_eq!(m.events.len(), 3);
        let [plant, spec] = &m.components[..] else { panic!("two components") };
        assert_eq!((plant.kind, spec.kind), (ComponentKind::Plant, ComponentKind::Spec));
        let (start, finish, brk) = (ev.get("start").unwrap(), ev.get("finish").unwrap(), ev.get("break").unwrap());
        assert!(ev.is_controllable(start) && !ev.is_controllable(finish));
        let a = &plant.automaton;
        assert_eq!((a.num_states(), a.num_transitions()), (2, 3));
        assert!(a.is_marked(StateId::new(0)) && !a.is_marked(StateId::new(1)));
        assert_eq!(a.run(&[start, brk, start, finish]), Some(StateId::new(0)));
        // The forbidden state is left out with its edge; `break` stays in the alphabet, so the
        // specification disables it; `start` is blocked (in the alphabet, on no edge).
        let s = &spec.automaton;
        assert_eq!((s.num_states(), s.num_transitions(), spec.forbidden), (1, 0, 1));
        assert_eq!(
            s.alphabet(),
            &{
                let mut v = vec![start, brk];
                crate::sort::sort(&mut v);
                v
            }[..]
        );
        // No `:accepting` in the specification: every state marked.
        assert!(s.is_marked(StateId::new(0)));
        assert_eq!(&SUPREMICA_STYLE[plant.span.range()], "M");
    }

    #[test]
    fn round_trips_through_the_writer() {
        let mut ev = Events::new();
        let m = read_wmod(SUPREMICA_STYLE, &mut ev).unwrap();
        let attributes = vec![
            (ev.get("start").unwrap(), ENFORCEABLE_ATTRIBUTE, "true".to_string()),
            (ev.get("break").unwrap(), "note", "a\n\"b\" <c>".to_string()),
        ];
        let out: Vec<ComponentOut> = m
            .components
            .iter()
            .map(|c| ComponentOut { name: &c.name, kind: c.kind, automaton: &c.automaton })
            .collect();
        let text = write_wmod("cell <2>", "a \"comment\"", &out, &ev, &attributes);
        let mut ev2 = Events::new();
        let back = read_wmod(&text, &mut ev2).unwrap_or_else(|e| panic!("{e:?}\n{text}"));
        assert_eq!(back.name, "cell <2>");
        assert_eq!(back.enforceable, vec![ev2.get("start").unwrap()]);
        assert!(back.attributes.contains(&(ev2.get("break").unwrap(), "note".to_string(), "a\n\"b\" <c>".to_string())));
        for (a, b) in m.components.iter().zip(&back.components) {
            assert_eq!((a.name.as_str(), a.kind), (b.name.as_str(), b.kind));
            let (x, y) = (&a.automaton, &b.automaton);
            assert_eq!(
                (x.num_states(), x.num_transitions(), x.init()),
                (y.num_states(), y.num_transitions(), y.init())
            );
            for s in x.states() {
                assert_eq!(x.is_marked(s), y.is_marked(s));
                assert_eq!(x.state_name(s), y.state_name(s));
                let names = |a: &Automaton, ev: &Events| {
                    a.edges(s).iter().map(|e| (ev.name(e.event).to_string(), e.target)).collect::<Vec<_>>()
                };
                let mut l = names(x, &ev);
                let mut r = names(y, &ev2);
                crate::sort::sort(&mut l);
                crate::sort::sort(&mut r);
                assert_eq!(l, r);
            }
            let alpha = |a: &Automaton, ev: &Events| {
                let mut v: Vec<String> = a.alphabet().iter().map(|&e| ev.name(e).to_string()).collect();
                crate::sort::sort(&mut v);
                v
            };
            assert_eq!(alpha(x, &ev), alpha(y, &ev2));
        }
    }

    /// The error of `src` as (line, column, message).
    fn error(src: &str) -> (u32, u32, String) {
        let e = read_wmod(src, &mut Events::new()).unwrap_err();
        let d = e.diagnostic(src);
        (d.line, d.column, d.message)
    }

    fn module(components: &str) -> String {
        format!(
            "<Module Name=\"m\" xmlns=\"{NS_MODULE}\">\n<EventDeclList><EventDecl Kind=\"CONTROLLABLE\" Name=\"a\"/>\
             <EventDecl Kind=\"PROPOSITION\" Name=\":accepting\"/></EventDeclList>\n<ComponentList>\n{components}\n</ComponentList></Module>"
        )
    }

    #[test]
    fn every_unsupported_element_is_a_located_error_naming_it() {
        let comp = |graph: &str| {
            module(&format!("<SimpleComponent Kind=\"PLANT\" Name=\"P\"><Graph>{graph}</Graph></SimpleComponent>"))
        };
        let cases: Vec<(String, &str)> = vec![
            (module("<VariableComponent Name=\"x\"/>"), "<VariableComponent> in <ComponentList> is not supported"),
            (module("<Instance Name=\"i\" ModuleName=\"other\"/>"), "<Instance> in <ComponentList> is not supported"),
            (module("<InstanceDecl Name=\"i\"/>"), "<InstanceDecl> in <ComponentList> is not supported"),
            (module("<ModuleInstance Name=\"i\"/>"), "<ModuleInstance> in <ComponentList> is not supported"),
            (module("<ForeachComponent Name=\"i\"/>"), "<ForeachComponent> in <ComponentList> is not supported"),
            (
                comp("<NodeList><SimpleNode Name=\"q\"/></NodeList><EdgeList><Edge Source=\"q\" Target=\"q\"><LabelBlock><SimpleIdentifier Name=\"a\"/></LabelBlock><GuardActionBlock/></Edge></EdgeList>"),
                "<GuardActionBlock> in <Edge> is not supported",
            ),
            (
                comp("<NodeList><SimpleNode Name=\"q\"/></NodeList><EdgeList><Edge Source=\"q\" Target=\"q\"><LabelBlock><IndexedIdentifier Name=\"a\"/></LabelBlock></Edge></EdgeList>"),
                "<IndexedIdentifier> in <LabelBlock> is not supported",
            ),
            (comp("<NodeList><GroupNode Name=\"g\"/></NodeList>"), "<GroupNode> in <NodeList> is not supported"),
        ];
        for (src, message) in cases {
            let (line, column, got) = error(&src);
            assert_eq!(got, message, "{src}");
            let element = &message[1..message.find('>').unwrap()];
            let offset = src.find(&format!("<{element}")).unwrap();
            let (l, c) = crate::diag::LineIndex::new(&src).line_col(offset);
            assert_eq!((line, column), (l, c), "{message}");
        }
    }

    #[test]
    fn every_error_is_located() {
        let nodes = "<NodeList><SimpleNode Initial=\"true\" Name=\"p\"/><SimpleNode Name=\"q\"/></NodeList>";
        let cases: Vec<(String, (u32, u32), &str)> = vec![
            ("<Module><EventDeclList>".into(), (1, 1), "malformed XML: the root node was opened but never closed"),
            ("<Graph/>".into(), (1, 1), "the root element is <Graph>, not <Module>"),
            (
                module(&format!("<SimpleComponent Kind=\"PLANT\" Name=\"P\"><Graph>{nodes}<EdgeList>\n<Edge Source=\"p\" Target=\"q\"><LabelBlock><SimpleIdentifier Name=\"a\"/></LabelBlock></Edge>\n<Edge Source=\"p\" Target=\"p\"><LabelBlock><SimpleIdentifier Name=\"a\"/></LabelBlock></Edge></EdgeList></Graph></SimpleComponent>")),
                (6, 65),
                "state `p` of component `P` has two edges on event `a` (to `q` and `p`)",
            ),
            (
                module("<SimpleComponent Kind=\"PLANT\" Name=\"P\"><Graph><NodeList><SimpleNode Initial=\"true\" Name=\"p\"/><SimpleNode Initial=\"true\" Name=\"q\"/></NodeList></Graph></SimpleComponent>"),
                (4, 115),
                "a second initial state `q` in component `P` (the first is `p`)",
            ),
            (
                module(&format!("<SimpleComponent Kind=\"PLANT\" Name=\"P\"><Graph>{nodes}<EdgeList><Edge Source=\"p\" Target=\"r\"><LabelBlock><SimpleIdentifier Name=\"a\"/></LabelBlock></Edge></EdgeList></Graph></SimpleComponent>")),
                (4, 162),
                "`r` is not a node of component `P`",
            ),
            (
                module(&format!("<SimpleComponent Kind=\"PLANT\" Name=\"P\"><Graph>{nodes}<EdgeList><Edge Source=\"p\" Target=\"q\"><LabelBlock><SimpleIdentifier Name=\"zz\"/></LabelBlock></Edge></EdgeList></Graph></SimpleComponent>")),
                (4, 201),
                "`zz` is not a declared event or alias",
            ),
            (module("<SimpleComponent Kind=\"HOLE\" Name=\"P\"><Graph/></SimpleComponent>"), (4, 24), "unknown component kind `HOLE`"),
            (
                module("<SimpleComponent Kind=\"PLANT\" Name=\"P\"><Graph><NodeList><SimpleNode Name=\"p\"><EventList><SimpleIdentifier Name=\":forbidden\"/></EventList></SimpleNode></NodeList></Graph></SimpleComponent>"),
                (4, 113),
                "`:forbidden` is not a declared proposition",
            ),
            ("<Module xmlns=\"urn:other\"/>".into(), (1, 1), "<Module> in the namespace `urn:other` is not part of a Waters module"),
            (
                "<Module><EventDeclList><EventDecl Kind=\"CONTROLLABLE\" Name=\"a\" Observable=\"false\"/></EventDeclList></Module>".into(),
                (1, 76),
                "event `a` is unobservable",
            ),
            (
                "<Module><EventAliasList><EventAlias Name=\"x\"><ExpressionList><SimpleIdentifier Name=\"y\"/></ExpressionList></EventAlias><EventAlias Name=\"y\"><ExpressionList><SimpleIdentifier Name=\"x\"/></ExpressionList></EventAlias></EventAliasList></Module>".into(),
                (1, 86),
                "alias `x` is part of a cycle of aliases through `y`",
            ),
            ("<Module>text</Module>".into(), (1, 9), "unexpected text in <Module>"),
        ];
        let mut wrong = Vec::new();
        for (src, at, message) in cases {
            let (line, column, got) = error(&src);
            if (line, column, got.as_str()) != (at.0, at.1, message) {
                wrong.push(format!("{src}\n  got {line}:{column} {got}\n  expected {}:{} {message}", at.0, at.1));
            }
        }
        assert!(wrong.is_empty(), "{}", wrong.join("\n"));
    }

    #[test]
    fn a_plant_may_not_forbid_and_the_budget_holds() {
        let src = module("<SimpleComponent Kind=\"PLANT\" Name=\"P\"><Graph><NodeList><SimpleNode Name=\"p\"><EventList><SimpleIdentifier Name=\":forbidden\"/></EventList></SimpleNode></NodeList></Graph></SimpleComponent>")
            .replace("<EventDeclList>", "<EventDeclList><EventDecl Kind=\"PROPOSITION\" Name=\":forbidden\"/>");
        assert_eq!(error(&src).2, "plant `P` has the forbidden state `p`");
        let nodes: String = (0..10).map(|i| format!("<SimpleNode Name=\"s{i}\"/>")).collect();
        let src = module(&format!(
            "<SimpleComponent Kind=\"SPEC\" Name=\"S\"><Graph><NodeList>{nodes}</NodeList></Graph></SimpleComponent>"
        ));
        let e = read_wmod_within(&src, &mut Events::new(), 5).unwrap_err();
        assert!(e.over_budget && e.message.contains("more than 5 states"), "{e:?}");
        assert!(read_wmod_within(&src, &mut Events::new(), 10).is_ok());
    }
}
