//! Between `.sct` projects and the classic automata of other tools' files (`.wmod`, `.gen`).
//!
//! [`classic_to_sct`] writes classic components (read from a Supremica module or libFAUDES
//! generators) as a `.sct` project, and [`project_to_classic`] turns a checked project (and
//! synthesised supervisors) into classic components for [`write_wmod`](super::classic::wmod::write_wmod).
//! Both map only what means the same on both sides; everything else is a located error, never a
//! silent drop:
//!
//! - a plant is a plant: its alphabet, states and transitions (the plant contract of `.sct` is
//!   the classic reading of a plant: an alphabet event without a transition cannot occur);
//! - a classic specification (or a Waters supervisor) is a `.sct` specification: in each state
//!   an alphabet event with a transition moves, one without is `forbid`den; a self-loop is
//!   written as nothing, because in `.sct` an allowed event without a transition stays;
//!   backwards, every allowed alphabet event without a transition gets its self-loop;
//! - marking has no `.sct` meaning (SynTACS synthesis keeps specifications safe, it does not
//!   make them nonblocking): a component with an unmarked state does not map, unless the caller
//!   says to ignore marking; every exported state is marked;
//! - conditional transitions and prohibitions (`if [...]`), properties and components without
//!   an initial state do not map; names that are not `.sct` (or Waters) identifiers are renamed,
//!   and each renaming is listed in the output.
//!
//! The `.sct` parts that are not automata — event triggers and actions, timers' durations and
//! start and stop events — are PLC runtime data, not synthesis: [`project_to_classic`] lists
//! them in [`Classic::left_out`] for the caller to report, and the timeout events stay
//! uncontrollable events.

use super::check::Loaded;
use super::classic::wmod::{ComponentKind, ENFORCEABLE_ATTRIBUTE, SCT_ATTRIBUTE};
use super::classic::{Automaton, AutomatonBuilder, ClassicEventId, Events, StateId};
use super::model::{self, Cond, EventKind, Supervisor};
use crate::diag::{Diagnostic, Diagnostics, Span};
use hashbrown::{HashMap, HashSet};
use std::fmt::Write as _;

/// One classic component to write as `.sct`.
pub struct Part<'a> {
    pub name: &'a str,
    pub kind: ComponentKind,
    pub automaton: &'a Automaton,
    /// Where the component is named in its file, for errors.
    pub span: Span,
    /// Where each state is named, if known (for errors about one state).
    pub state_spans: &'a [Span],
}

/// An error of [`classic_to_sct`]: in part `part`'s file at `span`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PartError {
    pub part: usize,
    pub span: Span,
    pub message: String,
    pub notes: Vec<String>,
    /// The error is an unmarked state: the part maps with [`ToSct::ignore_marking`].
    pub unmarked: bool,
}

impl PartError {
    /// The error as a diagnostic of its part's `source`.
    pub fn diagnostic(&self, source: &str) -> Diagnostic {
        let mut d = Diagnostics::new(source);
        let item = d.error(self.span, self.message.clone());
        item.notes = self.notes.clone();
        item.clone()
    }
}

/// Names of the `.sct` grammar that a generated name avoids (they are contextual keywords, but
/// `forbid x;` or `state initial initial` would read ambiguously to a person).
const RESERVED: &[&str] = &[
    "module",
    "event",
    "timer",
    "plant",
    "spec",
    "template",
    "instance",
    "state",
    "initial",
    "forbid",
    "alphabet",
    "selfloops",
    "impossible",
    "if",
    "and",
    "or",
    "not",
    "true",
    "false",
    "controllable",
    "uncontrollable",
    "enforceable",
    "bind",
    "namespace",
    "detect",
    "executed",
    "reset",
    "on",
    "duration",
    "start",
    "stop",
];

/// Makes names identifiers (`[A-Za-z_][A-Za-z0-9_]*`, not reserved) and unique within one
/// scope, remembering what it renamed.
#[derive(Default)]
struct Namer {
    taken: HashSet<String>,
    renamed: Vec<(String, String)>,
}

impl Namer {
    fn name(&mut self, original: &str) -> String {
        let mut base: String =
            original.chars().map(|c| if c.is_ascii_alphanumeric() || c == '_' { c } else { '_' }).collect();
        if base.is_empty() || base.starts_with(|c: char| c.is_ascii_digit()) {
            base.insert(0, '_');
        }
        if RESERVED.contains(&base.as_str()) {
            base.push('_');
        }
        let mut name = base.clone();
        let mut k = 2;
        while !self.taken.insert(name.clone()) {
            name = format!("{base}_{k}");
            k += 1;
        }
        if name != original {
            self.renamed.push((original.to_string(), name.clone()));
        }
        name
    }
}

/// Whether `text` between `{` and a closing brace on its own line is the whole body of a
/// declaration: no brace closes it early, no string or comment swallows the closing one.
fn is_one_body(text: &str) -> bool {
    let declaration = format!(" : k {{{text}\n}}");
    event_body(&declaration, 0) == Some(&declaration[6..declaration.len() - 1])
}

/// A foreign name as it may stand in a `//` comment: control characters (a line break would end
/// the comment and leave the rest of the name as `.sct` text) escaped as Rust writes them.
fn in_comment(name: &str) -> String {
    name.chars().flat_map(|c| if c.is_control() { c.escape_debug().collect::<Vec<_>>() } else { vec![c] }).collect()
}

/// Options of [`classic_to_sct`].
#[derive(Clone, Copy, Debug)]
pub struct ToSct {
    /// Read every component as if all its states were marked, instead of refusing a component
    /// with an unmarked state.
    pub ignore_marking: bool,
    /// How the caller's user asks for `ignore_marking` (the CLI's `--ignore-marking`, the
    /// playground's `Ignore marking`), named in the error on an unmarked state and in the header.
    pub switch: &'static str,
}

impl Default for ToSct {
    fn default() -> ToSct {
        ToSct { ignore_marking: false, switch: "--ignore-marking" }
    }
}

/// Writes classic components as a `.sct` project: `header` (one comment line per line), the
/// events (enforceable where `enforceable` says so), plants and specifications (supervisors as
/// specifications), each with its `.sct` properties from `bodies` (what [`SCT_ATTRIBUTE`]
/// holds). Every part that does not map is an error; all are reported.
pub fn classic_to_sct(
    parts: &[Part],
    events: &Events,
    enforceable: &[ClassicEventId],
    bodies: &[(ClassicEventId, String)],
    header: &str,
    options: ToSct,
) -> Result<String, Vec<PartError>> {
    let mut errors = Vec::new();
    for (k, p) in parts.iter().enumerate() {
        let err = |span: Span, message: String, note: &str| PartError {
            part: k,
            span,
            message,
            notes: vec![note.to_string()],
            unmarked: false,
        };
        let a = p.automaton;
        match p.kind {
            ComponentKind::Property => errors.push(err(
                p.span,
                format!("the property `{}` does not map to a .sct project", p.name),
                ".sct projects have plants and specifications; properties are for verification",
            )),
            _ if a.init().is_none() => errors.push(err(
                p.span,
                format!("component `{}` has no initial state", p.name),
                "a .sct plant or specification starts in a state (a component whose initial state is forbidden, or that has none, is the empty language)",
            )),
            ComponentKind::Plant if a.alphabet().is_empty() => errors.push(err(
                p.span,
                format!("plant `{}` has no events", p.name),
                "a .sct plant needs an alphabet",
            )),
            _ => {}
        }
        if !options.ignore_marking {
            if let Some(s) = a.states().find(|&s| !a.is_marked(s)) {
                errors.push(PartError {
                    unmarked: true,
                    ..err(
                        p.state_spans.get(s.index()).copied().unwrap_or(p.span),
                        format!("state `{}` of `{}` is not marked", a.state_name(s), p.name),
                        &format!("the .sct language has no marking: its synthesis keeps specifications safe, it does not make them nonblocking; `{}` reads every state as marked", options.switch),
                    )
                });
            }
        }
    }
    if !errors.is_empty() {
        return Err(errors);
    }
    let mut o = String::new();
    for line in header.lines() {
        let _ = writeln!(o, "// {line}");
    }
    if options.ignore_marking {
        let _ = writeln!(o, "// Marking ignored ({}): every state is read as marked.", options.switch);
    }
    // One scope for events and components (the .sct top level), one per component for states.
    let mut top = Namer::default();
    let mut used: Vec<ClassicEventId> = parts.iter().flat_map(|p| p.automaton.alphabet().iter().copied()).collect();
    crate::sort::sort(&mut used);
    used.dedup();
    let event_names: HashMap<ClassicEventId, String> = used.iter().map(|&e| (e, top.name(events.name(e)))).collect();
    let part_names: Vec<String> = parts.iter().map(|p| top.name(p.name)).collect();
    let mut body = String::new();
    if !used.is_empty() {
        body.push('\n');
    }
    for &e in &used {
        let kind = if enforceable.contains(&e) {
            "enforceable"
        } else if events.is_controllable(e) {
            "controllable"
        } else {
            "uncontrollable"
        };
        match bodies.iter().find(|(x, _)| *x == e) {
            Some((_, text)) if is_one_body(text.trim()) => {
                let text = text.trim();
                if text.contains('\n') || text.contains("//") {
                    let _ = writeln!(body, "event {} : {kind} {{\n  {text}\n}}", event_names[&e]);
                } else {
                    let _ = writeln!(body, "event {} : {kind} {{ {text} }}", event_names[&e]);
                }
            }
            Some((_, text)) => {
                // Text that would close the declaration early (or never): not pasted, but said.
                let _ = writeln!(
                    body,
                    "// The `plcsynth:sct` properties of `{}` are not one declaration body, left out: {}",
                    event_names[&e],
                    in_comment(text)
                );
                let _ = writeln!(body, "event {} : {kind};", event_names[&e]);
            }
            None => {
                if kind == "enforceable" {
                    let _ = writeln!(
                        body,
                        "// `{}` is enforceable: give it its `on accept \"...\";` code.",
                        event_names[&e]
                    );
                }
                let _ = writeln!(body, "event {} : {kind};", event_names[&e]);
            }
        }
    }
    let mut state_renamed = Vec::new();
    for (p, name) in parts.iter().zip(&part_names) {
        let a = p.automaton;
        let mut states = Namer::default();
        let names: Vec<String> = a.states().map(|s| states.name(a.state_name(s))).collect();
        state_renamed.extend(states.renamed.into_iter().map(|(from, to)| (p.name, from, to)));
        let plant = p.kind == ComponentKind::Plant;
        body.push('\n');
        if p.kind == ComponentKind::Supervisor {
            let _ = writeln!(body, "// `{}` is a Waters SUPERVISOR: read as a specification.", in_comment(p.name));
        }
        let _ = writeln!(body, "{} {name} {{", if plant { "plant" } else { "spec" });
        if plant {
            let alphabet: Vec<&str> = a.alphabet().iter().map(|e| event_names[e].as_str()).collect();
            let _ = writeln!(body, "  alphabet {};", alphabet.join(", "));
        }
        // The initial state first, so that it also reads as initial without the keyword.
        let init = a.init().unwrap_or(StateId::new(0));
        let order = std::iter::once(init).chain(a.states().filter(|&s| s != init));
        for s in order {
            let mut items: Vec<String> = Vec::new();
            for edge in a.edges(s) {
                if !plant && edge.target == s {
                    continue; // an allowed event stays: no .sct transition needed
                }
                items.push(format!("{} -> {};", event_names[&edge.event], names[edge.target.index()]));
            }
            if !plant {
                let forbidden: Vec<&str> =
                    a.alphabet().iter().filter(|&&e| a.step(s, e).is_none()).map(|e| event_names[e].as_str()).collect();
                if !forbidden.is_empty() {
                    items.push(format!("forbid {};", forbidden.join(", ")));
                }
            }
            let initial = if s == init { " initial" } else { "" };
            if items.is_empty() {
                let _ = writeln!(body, "  state {}{initial};", names[s.index()]);
            } else {
                let _ = writeln!(body, "  state {}{initial} {{ {} }}", names[s.index()], items.join(" "));
            }
        }
        body.push_str("}\n");
    }
    if !top.renamed.is_empty() || !state_renamed.is_empty() {
        o.push_str("// Renamed to .sct names:\n");
        for (from, to) in &top.renamed {
            let _ = writeln!(o, "//   `{}` is `{to}`", in_comment(from));
        }
        for (component, from, to) in &state_renamed {
            let _ = writeln!(o, "//   state `{}` of `{}` is `{to}`", in_comment(from), in_comment(component));
        }
    }
    o.push_str(&body);
    Ok(o)
}

/// One file for [`import`]: its name (`….wmod` is a Supremica module, any other a libFAUDES
/// generator), its text (see [`decode`](super::classic::wmod::decode) for a module's bytes),
/// and for a generator what it is ([`ComponentKind::Plant`] or [`ComponentKind::Spec`]; a
/// module says that of each of its components).
pub struct ImportFile<'a> {
    pub name: &'a str,
    pub text: &'a str,
    pub kind: ComponentKind,
}

/// Options of [`import`].
#[derive(Clone, Copy, Debug)]
pub struct Import<'a> {
    /// Who imports, for the header: "Imported by {by} from `a.gen`, `b.gen`."
    pub by: &'a str,
    pub to_sct: ToSct,
    /// The states the files may declare in all.
    pub max_states: usize,
}

/// An error of [`import`]: a diagnostic of file `file`'s text.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ImportError {
    pub file: usize,
    pub diagnostic: Diagnostic,
    /// The files declare more states than [`Import::max_states`].
    pub over_budget: bool,
    /// An unmarked state ([`PartError::unmarked`]).
    pub unmarked: bool,
}

/// Whether a file name says Supremica module (`.wmod`, in any case).
pub fn is_wmod(name: &str) -> bool {
    name.to_ascii_lowercase().ends_with(".wmod")
}

/// Reads other tools' files as one `.sct` project: `plcsynth import` and the playground's
/// *Open* both call it. Either one `.wmod` module, or any number of `.gen` generators (each a
/// component named after its file). The first file that does not read stops the import; when
/// all read, every component that does not map is reported ([`classic_to_sct`]).
///
/// ```
/// use plcsynth::sct::classic::wmod::ComponentKind;
/// use plcsynth::sct::interchange::{import, Import, ImportFile, ToSct};
/// let gen = "<Generator> \"M\" <Alphabet> go +C+ done </Alphabet> <States> idle busy </States>\n\
///            <TransRel> idle go busy busy done idle </TransRel> <InitStates> idle </InitStates>\n\
///            <MarkedStates> idle busy </MarkedStates> </Generator>";
/// let files = [ImportFile { name: "machine.gen", text: gen, kind: ComponentKind::Plant }];
/// let options = Import { by: "a doc test", to_sct: ToSct::default(), max_states: 1000 };
/// let project = import(&files, &options).unwrap();
/// assert!(project.starts_with("// Imported by a doc test from `machine.gen`."));
/// assert!(project.contains("plant machine {"));
/// ```
pub fn import(files: &[ImportFile], options: &Import) -> Result<String, Vec<ImportError>> {
    use super::classic::gen::read_gen_file_within;
    use super::classic::wmod::read_wmod_within;
    let fail = |file: usize, diagnostic: Diagnostic, over_budget: bool| {
        Err(vec![ImportError { file, diagnostic, over_budget, unmarked: false }])
    };
    if files.len() > 1 {
        if let Some(k) = files.iter().position(|f| is_wmod(f.name)) {
            let mut d = Diagnostics::new(files[k].text);
            let item = d.error(Span::new(0, 0), "import one `.wmod` module at a time, without other files");
            return fail(k, item.clone(), false);
        }
    }
    let mut events = Events::new();
    let mut enforceable: Vec<ClassicEventId> = Vec::new();
    let mut bodies: Vec<(ClassicEventId, String)> = Vec::new();
    // Per component: name, kind, automaton, span, state spans; `owner[k]` is its file.
    let mut components = Vec::new();
    let mut owner = Vec::new();
    let mut budget = options.max_states;
    for (i, f) in files.iter().enumerate() {
        if is_wmod(f.name) {
            let m = match read_wmod_within(f.text, &mut events, budget) {
                Ok(m) => m,
                Err(e) => return fail(i, e.diagnostic(f.text), e.over_budget),
            };
            enforceable.extend(&m.enforceable);
            bodies.extend(m.attributes.iter().filter(|a| a.1 == SCT_ATTRIBUTE).map(|a| (a.0, a.2.clone())));
            for c in m.components {
                components.push((c.name, c.kind, c.automaton, c.span, c.state_spans));
                owner.push(i);
            }
            continue;
        }
        let g = match read_gen_file_within(f.text, &mut events, budget) {
            Ok(g) => g,
            Err(e) => return fail(i, e.diagnostic(f.text), e.over_budget),
        };
        budget = budget.saturating_sub(g.automaton.num_states());
        let stem = std::path::Path::new(f.name).file_stem().and_then(|s| s.to_str()).unwrap_or("generator").to_string();
        components.push((stem, f.kind, g.automaton, Span::default(), Vec::new()));
        owner.push(i);
    }
    let parts: Vec<Part> = components
        .iter()
        .map(|(name, kind, automaton, span, state_spans)| Part {
            name,
            kind: *kind,
            automaton,
            span: *span,
            state_spans,
        })
        .collect();
    let header = format!(
        "Imported by {} from {}.",
        options.by,
        files.iter().map(|f| format!("`{}`", in_comment(f.name))).collect::<Vec<_>>().join(", ")
    );
    classic_to_sct(&parts, &events, &enforceable, &bodies, &header, options.to_sct).map_err(|errors| {
        errors
            .into_iter()
            .map(|e| {
                let file = owner[e.part];
                ImportError {
                    file,
                    diagnostic: e.diagnostic(files[file].text),
                    over_budget: false,
                    unmarked: e.unmarked,
                }
            })
            .collect()
    })
}

/// A project as classic components: what [`write_wmod`](super::classic::wmod::write_wmod) writes.
pub struct Classic {
    pub events: Events,
    pub enforceable: Vec<ClassicEventId>,
    /// Each event's `.sct` properties (triggers, actions), for [`SCT_ATTRIBUTE`].
    pub bodies: Vec<(ClassicEventId, String)>,
    /// (name, kind, automaton), plants first, then specifications, then supervisors.
    pub components: Vec<(String, ComponentKind, Automaton)>,
    /// The `.sct` parts that are not written (timers), one line each.
    pub left_out: Vec<String>,
    /// The supervisors' enforced events, which Waters cannot say, one line each.
    pub enforcement: Vec<String>,
}

/// A checked project's plants and specifications, and the given supervisors, as classic
/// components over Waters-safe names (`Tank.levelAlarm` becomes `Tank_levelAlarm`). Errors
/// (conditional transitions and prohibitions, names that clash once made safe) are located in
/// `src`, the project's text.
pub fn project_to_classic(src: &str, loaded: &Loaded, supervisors: &[&Supervisor]) -> Result<Classic, Vec<Diagnostic>> {
    let p = &loaded.project;
    let mut d = Diagnostics::new(src);
    let mut events = Events::new();
    let mut enforceable = Vec::new();
    let mut safe: HashMap<String, usize> = HashMap::new();
    // The project's events in its order, so that the classic ids follow the model's.
    for (i, info) in p.events.iter().enumerate() {
        let name = waters_name(&info.name);
        if let Some(&j) = safe.get(&name) {
            let span = loaded.events.get(i).map_or(Span::default(), |m| m.spans.name);
            d.error(
                span,
                format!("events `{}` and `{}` both become `{name}` in a Waters module", p.events[j].name, info.name),
            )
            .with_note("Waters names are identifiers: the dots of qualified names become `_`; rename one of them");
        }
        safe.insert(name.clone(), i);
        let e = events.intern(&name, info.kind != EventKind::Uncontrollable);
        if info.kind == EventKind::Enforceable {
            enforceable.push(e);
        }
    }
    let ev = |e: model::EventId| ClassicEventId::from_raw(e.raw());
    let origin_span = |o: u32| loaded.origins.get(o as usize).copied().unwrap_or_default();
    let mut components = Vec::new();
    let mut component_names: HashMap<String, String> = HashMap::new();
    let mut name_component = |d: &mut Diagnostics, name: &str, span: Span| {
        let safe = waters_name(name);
        if let Some(other) = component_names.insert(safe.clone(), name.to_string()) {
            d.error(span, format!("`{other}` and `{name}` both become the component `{safe}` in a Waters module"))
                .with_note("rename one of them");
        }
        safe
    };
    for plant in &p.plants {
        let mut b = AutomatonBuilder::new();
        for &e in &plant.alphabet {
            b.add_event(ev(e));
        }
        for s in &plant.states {
            b.add_state(s.clone(), true);
        }
        b.set_init(StateId::from_raw(plant.init));
        for t in &plant.trans {
            if t.cond != Cond::True {
                d.error(origin_span(t.origin), format!("plant `{}` has a conditional transition", plant.name))
                    .with_note("a Waters module has no conditions over other plants' states");
                continue;
            }
            b.add_transition(StateId::from_raw(t.src), ev(t.event), StateId::from_raw(t.dst));
        }
        let name = name_component(&mut d, &plant.name, Span::default());
        if let Ok(a) = b.build() {
            components.push((name, ComponentKind::Plant, a));
        }
    }
    for (k, spec) in p.specs.iter().enumerate() {
        let mut alphabet: Vec<model::EventId> =
            spec.trans.iter().map(|t| t.event).chain(spec.prohib.iter().map(|x| x.event)).collect();
        crate::sort::sort(&mut alphabet);
        alphabet.dedup();
        let mut moves: HashMap<(u32, model::EventId), u32> = HashMap::new();
        let mut prohibited: HashSet<(u32, model::EventId)> = HashSet::new();
        for t in &spec.trans {
            if t.cond != Cond::True {
                d.error(origin_span(t.origin), format!("specification `{}` has a conditional transition", spec.name))
                    .with_note("a Waters module has no conditions over plant states");
                continue;
            }
            moves.insert((t.src, t.event), t.dst);
        }
        for x in &spec.prohib {
            if x.cond != Cond::True {
                d.error(origin_span(x.origin), format!("specification `{}` has a conditional prohibition", spec.name))
                    .with_note("a Waters module has no conditions over plant states");
                continue;
            }
            prohibited.insert((x.state, x.event));
        }
        let mut b = AutomatonBuilder::new();
        for &e in &alphabet {
            b.add_event(ev(e));
        }
        for s in &spec.states {
            b.add_state(s.clone(), true);
        }
        b.set_init(StateId::from_raw(spec.init));
        for s in 0..spec.states.len() as u32 {
            for &e in &alphabet {
                match moves.get(&(s, e)) {
                    Some(&t) => b.add_transition(StateId::from_raw(s), ev(e), StateId::from_raw(t)),
                    None if !prohibited.contains(&(s, e)) => {
                        b.add_transition(StateId::from_raw(s), ev(e), StateId::from_raw(s))
                    }
                    None => {}
                }
            }
        }
        let span = loaded.spec_spans.get(k).copied().unwrap_or_default();
        let name = name_component(&mut d, &spec.name, span);
        if let Ok(a) = b.build() {
            components.push((name, ComponentKind::Spec, a));
        }
    }
    for sup in supervisors {
        let name = name_component(&mut d, &format!("sup_{}", sup.name), Span::default());
        components.push((name, ComponentKind::Supervisor, supervisor_automaton(sup)));
    }
    if d.has_errors() {
        return Err(d.items);
    }
    let mut left_out = Vec::new();
    let bodies: Vec<(ClassicEventId, String)> = loaded
        .events
        .iter()
        .enumerate()
        .filter_map(|(i, m)| {
            event_body(src, m.spans.name.end as usize)
                .map(|b| (ClassicEventId::from_raw(i as u32), b.trim().to_string()))
        })
        .collect();
    for t in &loaded.timers {
        left_out.push(format!(
            "timer `{}` ({} ms from `{}`): `{}` is an uncontrollable event",
            t.name, t.duration_ms, t.start, t.timeout
        ));
    }
    let mut enforcement = Vec::new();
    for sup in supervisors {
        for s in &sup.states {
            if let Some(e) = s.enforced {
                enforcement.push(format!(
                    "supervisor `{}` enforces `{}` in state `{}` (Waters has no enforcement)",
                    sup.name,
                    p.event_name(e),
                    s.label
                ));
            }
        }
    }
    Ok(Classic { events, enforceable, bodies, components, left_out, enforcement })
}

/// A supervisor as a classic automaton over the events it names: explicit transitions, a
/// self-loop for every such event neither prohibited nor moving in a state, nothing for a
/// prohibited one. Every state is marked; a void supervisor has no states.
pub fn supervisor_automaton(sup: &Supervisor) -> Automaton {
    let mut alphabet: Vec<model::EventId> = sup
        .states
        .iter()
        .flat_map(|s| s.transitions.iter().map(|t| t.0).chain(s.prohibited.iter().copied()).chain(s.enforced))
        .collect();
    crate::sort::sort(&mut alphabet);
    alphabet.dedup();
    let ev = |e: model::EventId| ClassicEventId::from_raw(e.raw());
    let mut b = AutomatonBuilder::new();
    for &e in &alphabet {
        b.add_event(ev(e));
    }
    if sup.init.is_none() {
        return Automaton::empty(alphabet.into_iter().map(ev).collect());
    }
    for s in &sup.states {
        b.add_state(label_name(&s.label), true);
    }
    if let Some(i) = sup.init {
        b.set_init(StateId::from_raw(i));
    }
    for (k, s) in sup.states.iter().enumerate() {
        for &e in &alphabet {
            match s.next(e) {
                Some(t) => b.add_transition(StateId::new(k), ev(e), StateId::from_raw(t)),
                None if !s.prohibits(e) => b.add_transition(StateId::new(k), ev(e), StateId::new(k)),
                None => {}
            }
        }
    }
    b.build().unwrap_or_else(|_| Automaton::empty(Vec::new()))
}

impl Classic {
    /// The events' attributes for [`write_wmod`](super::classic::wmod::write_wmod):
    /// enforceability and `.sct` properties.
    pub fn attributes(&self) -> Vec<(ClassicEventId, &'static str, String)> {
        let enforceable = self.enforceable.iter().map(|&e| (e, ENFORCEABLE_ATTRIBUTE, "true".to_string()));
        enforceable.chain(self.bodies.iter().map(|(e, b)| (*e, SCT_ATTRIBUTE, b.clone()))).collect()
    }
}

/// The text between the braces of an event declaration whose name ends at `name_end`
/// (`event NAME : KIND { … }`), or `None` for a declaration without braces (or a timer's
/// timeout event). Strings and
/// comments are passed over whole, so a brace inside them does not count.
fn event_body(src: &str, name_end: usize) -> Option<&str> {
    let b = src.as_bytes();
    let mut i = name_end;
    // `event NAME :` — a timer's timeout event is named at its timer (`timer NAME {`).
    while i < b.len() && b[i].is_ascii_whitespace() {
        i += 1;
    }
    if b.get(i) != Some(&b':') {
        return None;
    }
    let mut open = None;
    let mut depth = 0usize;
    while i < b.len() {
        match b[i] {
            b'"' => {
                i += 1;
                while i < b.len() && b[i] != b'"' {
                    i += if b[i] == b'\\' { 2 } else { 1 };
                }
            }
            b'/' if b.get(i + 1) == Some(&b'/') => {
                while i < b.len() && b[i] != b'\n' {
                    i += 1;
                }
            }
            b'/' if b.get(i + 1) == Some(&b'*') => {
                i += 2;
                while i + 1 < b.len() && !(b[i] == b'*' && b[i + 1] == b'/') {
                    i += 1;
                }
                i += 1;
            }
            b';' if open.is_none() => return None,
            b'{' => {
                open.get_or_insert(i + 1);
                depth += 1;
            }
            b'}' => {
                depth = depth.checked_sub(1)?;
                if depth == 0 {
                    return src.get(open?..i);
                }
            }
            _ => {}
        }
        i += 1;
    }
    None
}

/// A supervisor state's label (`(S, Tank.Inlet.C)`) as a readable identifier (`S_Tank_Inlet_C`):
/// runs of other characters become one `_`, none at the ends.
fn label_name(label: &str) -> String {
    let mut out = String::new();
    for c in label.chars() {
        if c.is_ascii_alphanumeric() || c == '_' {
            out.push(c);
        } else if !out.is_empty() && !out.ends_with('_') {
            out.push('_');
        }
    }
    while out.ends_with('_') {
        out.pop();
    }
    if out.is_empty() {
        out.push('s');
    }
    out
}

/// A name as a Waters identifier: `[A-Za-z0-9_]`, other characters (the dots of qualified
/// `.sct` names) as `_`.
pub fn waters_name(name: &str) -> String {
    name.chars().map(|c| if c.is_ascii_alphanumeric() || c == '_' { c } else { '_' }).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_a_whole_declaration_body_is_pasted() {
        assert!(is_one_body(r#"detect rising "Q_Inlet"; reset on denial "Q_Inlet";"#));
        assert!(is_one_body(r#"on accept "IF a THEN b := TRUE; END_IF;"; // a comment"#));
        assert!(is_one_body(r#"on accept "x := \"}\";";"#));
        assert!(!is_one_body("detect rising \"a\"; } plant X { alphabet e; state s; "));
        assert!(!is_one_body("on accept \"unterminated;"));
        assert!(!is_one_body("/* open comment"));
        assert_eq!(in_comment("a\nb\tc"), "a\\nb\\tc");
    }
}
