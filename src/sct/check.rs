//! Name resolution and checking: turns the syntax tree of a `.sct` file into a
//! [`model::Project`], reporting every problem found with its location.
//!
//! Modules form a namespace tree (6.1.2). A dotted name is first resolved from the root
//! (absolute); if that fails, from the module where it is written and each enclosing module
//! (relative). Absolute resolution wins a clash; two relative candidates are ambiguous.
//! Timers declare a scope holding their `timeout` event. Template instances (6.1.4) become
//! ordinary plants or specifications once their binding events are bound.

use super::ast::{self, AutDecl, AutKind, CondExpr, EdgeKind, EventItem, Item, Path, StateItem};
use super::model::{self, Budget, Cond, EventId, EventKind, Prohibition, Stop, SynthError, Transition};
use super::parser::{self, raw_offset};
use crate::diag::{Checked, Diagnostic, Diagnostics, Span};
use crate::graph::{Lists, View};
use crate::plc::fragment::{self, parse_expr, parse_statements, ExprKind, FragmentError};
use hashbrown::HashMap;
use petgraph::visit::{depth_first_search, Control, DfsEvent};
use serde::Serialize;

/// How the runtime framework detects or executes an event (5.3.2, 6.3.1).
#[derive(Clone, Debug, Serialize)]
pub struct EventMeta {
    pub trigger: Trigger,
    pub reset_on_denial: Vec<String>,
    pub code_on_accept: Option<String>,
    pub code_on_denial: Option<String>,
    /// Where the event is declared (its name), and where its fragments are written (the
    /// string literals), for diagnostics of code generation.
    #[serde(skip)]
    pub spans: EventSpans,
    /// The fragments as the checker parsed them, for code generation.
    #[serde(skip)]
    pub fragments: EventFragments,
}

/// An event's Structured Text fragments, parsed once by the checker. What does not parse is
/// left out: the checker reported it, and a file with errors does not reach code generation.
#[derive(Clone, Debug, Default)]
pub struct EventFragments {
    /// The trigger condition of a detected event.
    pub trigger: Option<fragment::Expr>,
    /// The signals reset on denial.
    pub resets: Vec<fragment::Expr>,
    /// The code on accept.
    pub accept: Vec<fragment::Stmt>,
    /// The code on denial.
    pub denial: Vec<fragment::Stmt>,
}

/// Source locations of an event's declaration and fragments.
#[derive(Clone, Debug, Default)]
pub struct EventSpans {
    pub name: Span,
    pub trigger: Option<Span>,
    pub reset_on_denial: Vec<Span>,
    pub code_on_accept: Option<Span>,
    pub code_on_denial: Option<Span>,
}

#[derive(Clone, Debug, Serialize)]
#[serde(rename_all = "lowercase", tag = "class")]
pub enum Trigger {
    /// No trigger: the event is virtual (only tracked, never detected).
    Virtual,
    Detected {
        edge: EdgeKind,
        expr: String,
    },
    Executed,
    /// Timeouts of timers.
    Timer {
        timer: String,
    },
}

/// A PLC timer (6.1.3).
#[derive(Clone, Debug, Serialize)]
pub struct TimerInfo {
    pub name: String,
    pub duration_ms: u64,
    pub start: String,
    pub stop: Vec<String>,
    pub timeout: String,
}

/// A loaded project: the synthesis model plus what the runtime framework and the reports need.
#[derive(Clone, Debug)]
pub struct Loaded {
    pub project: model::Project,
    pub events: Vec<EventMeta>,
    pub timers: Vec<TimerInfo>,
    /// Source location of every user transition and prohibition (`origin` ids of the model).
    pub origins: Vec<Span>,
    /// Location of each specification's name.
    pub spec_spans: Vec<Span>,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Entry {
    Module(usize),
    Event(u32),
    Plant(usize),
    Spec(usize),
    Template(usize),
    /// A timer: a scope (module index) holding `timeout`.
    Timer(usize),
    /// An instance whose template is not resolved yet.
    Instance(usize),
    /// A specification product.
    Product(usize),
}

impl Entry {
    fn what(&self) -> &'static str {
        match self {
            Entry::Module(_) => "a module",
            Entry::Event(_) => "an event",
            Entry::Plant(_) => "a plant",
            Entry::Spec(_) => "a specification",
            Entry::Template(_) => "a template",
            Entry::Timer(_) => "a timer",
            Entry::Instance(_) => "an instance",
            Entry::Product(_) => "a specification product",
        }
    }
}

struct Module {
    path: String,
    parent: Option<usize>,
    entries: HashMap<String, (Entry, Span)>,
}

struct AutRef<'a> {
    decl: &'a AutDecl,
    module: usize,
    /// For instances: the binding map and the instance location.
    binding: Option<(HashMap<Vec<String>, EventId>, Span)>,
    name: String,
}

struct Ctx<'s, 'a> {
    diags: Diagnostics<'s>,
    modules: Vec<Module>,
    events: Vec<model::EventInfo>,
    metas: Vec<EventMeta>,
    event_decls: Vec<Option<&'a ast::EventDecl>>,
    timers: Vec<(&'a ast::TimerDecl, usize, u32)>,
    templates: Vec<(&'a AutDecl, usize)>,
    instances: Vec<(&'a ast::InstanceDecl, usize)>,
    plants: Vec<AutRef<'a>>,
    specs: Vec<AutRef<'a>>,
    products: Vec<(String, Span, &'a [Path], usize)>,
    origins: Vec<Span>,
}

enum Lookup {
    Found(Entry),
    Missing,
    Ambiguous(Vec<String>),
}

/// Parses and resolves a `.sct` source: the project with its warnings, or (with an error)
/// every diagnostic, in source order. Specification products written in the file may build up
/// to [`model::DEFAULT_MAX_STATES`] states.
pub fn compile(src: &str) -> Checked<Loaded> {
    match compile_within(src, &mut Budget::new(model::DEFAULT_MAX_STATES, &mut |_| true)) {
        (Some(loaded), diagnostics, _) => Ok((loaded, diagnostics)),
        (None, diagnostics, _) => Err(diagnostics),
    }
}

/// [`compile`] drawing the states of the specification products written in the file from
/// `budget`, the budget of the whole run (synthesis draws on the rest). The third value is set
/// when a product stopped the load (budget spent or cancelled): its error diagnostic is not an
/// input error.
pub fn compile_within(src: &str, budget: &mut Budget) -> (Option<Loaded>, Vec<Diagnostic>, Option<Stop>) {
    let mut diags = Diagnostics::new(src);
    let items = parser::parse(src, &mut diags);
    let mut cx = Ctx {
        diags,
        modules: vec![Module { path: String::new(), parent: None, entries: HashMap::new() }],
        events: Vec::new(),
        metas: Vec::new(),
        event_decls: Vec::new(),
        timers: Vec::new(),
        templates: Vec::new(),
        instances: Vec::new(),
        plants: Vec::new(),
        specs: Vec::new(),
        products: Vec::new(),
        origins: Vec::new(),
    };
    cx.declare(&items, 0);
    cx.check_events();
    cx.resolve_instances();
    let timers = cx.build_timers();
    // State names for conditions, gathered once (per automaton they made loading quadratic).
    let declared_states = cx.plant_state_names();
    let plants: Vec<model::Plant> = (0..cx.plants.len()).map(|i| cx.build_plant(i, &declared_states)).collect();
    let plant_states: Vec<Vec<String>> = plants.iter().map(|p| p.states.clone()).collect();
    let built: Vec<model::Spec> = (0..cx.specs.len()).map(|i| cx.build_spec(i, &plant_states)).collect();
    let mut consumed = vec![false; built.len()];
    let mut specs = Vec::new();
    let mut spec_spans = Vec::new();
    let mut product_specs = Vec::new();
    let mut stop = None;
    for k in 0..cx.products.len() {
        let (name, span, operands, module) = cx.products[k].clone();
        let mut parts: Vec<usize> = Vec::new();
        for p in operands {
            if let Some(Entry::Spec(i)) = cx.resolve(module, p, "a specification", &|e| matches!(e, Entry::Spec(_))) {
                if parts.contains(&i) {
                    cx.diags.error(p.span, format!("`{}` appears twice in the product", p.text()));
                }
                consumed[i] = true;
                parts.push(i);
            }
        }
        if parts.len() == operands.len() && !cx.diags.has_errors() {
            let full = qualify(&cx.modules[module].path, &name);
            let specs: Vec<&model::Spec> = parts.iter().map(|&i| &built[i]).collect();
            match product_of(&full, &specs, budget) {
                Ok(acc) => product_specs.push((acc, span)),
                Err((_, error)) => {
                    stop = error.stop();
                    let message = match error {
                        SynthError::Cancelled => format!("cancelled while building the product `{full}`"),
                        _ => format!(
                            "building the product `{full}` spent the state budget: more than {} product states",
                            budget.max_states()
                        ),
                    };
                    cx.diags.error(span, message).with_note(
                        "synthesise the specifications separately, compose fewer of them, or raise the state budget",
                    );
                }
            }
        }
    }
    for (i, s) in built.into_iter().enumerate() {
        if !consumed[i] {
            spec_spans.push(cx.specs[i].binding.as_ref().map_or(cx.specs[i].decl.name_span, |b| b.1));
            specs.push(s);
        }
    }
    for (s, span) in product_specs {
        specs.push(s);
        spec_spans.push(span);
    }
    let mut items = std::mem::take(&mut cx.diags.items);
    crate::sort::sort_by_key(&mut items, |d| (d.span.start, d.span.end));
    if items.iter().any(Diagnostic::is_error) {
        return (None, items, stop);
    }
    let project = model::Project { events: cx.events, plants, specs };
    (Some(Loaded { project, events: cx.metas, timers, origins: cx.origins, spec_spans }), items, stop)
}

impl Loaded {
    /// The project with all its specifications composed into one (definition 6), named
    /// `name`: the single-supervisor setting that the formal model of preemption assumes
    /// (5.8.5), where no supervisor can enforce an event that another prohibits (6.4.2).
    /// Diagnostics about the composed specification point at the first one. The product's states
    /// are drawn from `budget`; when it stops, the error comes with the index of the
    /// specification whose product with the ones before it stopped.
    pub fn composed(&self, name: &str, budget: &mut Budget) -> Result<Loaded, (usize, SynthError)> {
        let mut out = self.clone();
        if !self.project.specs.is_empty() {
            let specs: Vec<&model::Spec> = self.project.specs.iter().collect();
            out.project.specs = vec![product_of(name, &specs, budget)?];
            out.spec_spans = vec![self.spec_spans[0]];
        }
        Ok(out)
    }
}

/// The specification product of `specs` (at least one), named `name`, drawing its states from
/// `budget`; when it stops, the error comes with the index of the operand being multiplied in.
fn product_of(name: &str, specs: &[&model::Spec], budget: &mut Budget) -> Result<model::Spec, (usize, SynthError)> {
    let mut acc = specs[0].clone();
    for (k, s) in specs.iter().enumerate().skip(1) {
        acc = model::spec_product(name, &acc, s, budget).map_err(|e| (k, e))?;
    }
    acc.name = name.to_string();
    Ok(acc)
}

/// Joins two or more operands into a balanced binary tree, so that a chain of `n` operands nests
/// `log2 n` deep rather than `n` (the model's conditions are evaluated recursively).
fn balanced(mut operands: Vec<Cond>, join: &impl Fn(Box<Cond>, Box<Cond>) -> Cond) -> Cond {
    if operands.len() == 1 {
        return operands.pop().expect("one operand");
    }
    let right = operands.split_off(operands.len() / 2);
    join(Box::new(balanced(operands, join)), Box::new(balanced(right, join)))
}

fn qualify(prefix: &str, name: &str) -> String {
    if prefix.is_empty() {
        name.to_string()
    } else {
        format!("{prefix}.{name}")
    }
}

impl<'s, 'a> Ctx<'s, 'a> {
    /// Reports a mistake in a Structured Text fragment at its place inside the string literal
    /// `literal` (quotes included) of the source.
    fn check_fragment<T>(&mut self, parsed: &Result<T, FragmentError>, literal: Span, what: &str) {
        let Err(e) = parsed else { return };
        let (start, end) = (literal.start as usize + 1, (literal.end as usize).saturating_sub(1));
        let raw = &self.diags.source()[start..end.max(start)];
        let span =
            Span::new(start + raw_offset(raw, e.span.start as usize), start + raw_offset(raw, e.span.end as usize));
        self.diags
            .error(span, format!("{what}: {}", e.message))
            .with_note("triggers and actions are Structured Text (docs/sct-language.md, Events)");
    }

    fn loc(&self, span: Span) -> String {
        let (l, c) = self.diags.line_col(span.start as usize);
        format!("{l}:{c}")
    }

    fn add(&mut self, module: usize, name: &str, entry: Entry, span: Span) {
        if let Some((prev, prev_span)) = self.modules[module].entries.get(name).copied() {
            let at = self.loc(prev_span);
            let scope = if self.modules[module].path.is_empty() {
                "the top level".to_string()
            } else {
                format!("module `{}`", self.modules[module].path)
            };
            self.diags
                .error(span, format!("`{name}` is declared twice in {scope}"))
                .with_note(format!("first declared at {at} as {}", prev.what()));
            return;
        }
        self.modules[module].entries.insert(name.to_string(), (entry, span));
    }

    fn new_module(&mut self, parent: usize, name: &str) -> usize {
        let path = qualify(&self.modules[parent].path, name);
        self.modules.push(Module { path, parent: Some(parent), entries: HashMap::new() });
        self.modules.len() - 1
    }

    fn new_event(
        &mut self,
        module: usize,
        name: &str,
        kind: EventKind,
        meta: EventMeta,
        decl: Option<&'a ast::EventDecl>,
        span: Span,
    ) -> u32 {
        let id = self.events.len() as u32;
        self.events.push(model::EventInfo { name: qualify(&self.modules[module].path, name), kind });
        let mut meta = meta;
        meta.spans.name = span;
        self.metas.push(meta);
        self.event_decls.push(decl);
        self.add(module, name, Entry::Event(id), span);
        id
    }

    fn declare(&mut self, items: &'a [Item], module: usize) {
        for item in items {
            match item {
                Item::Module { name, name_span, items } => {
                    let m = self.new_module(module, name);
                    self.add(module, name, Entry::Module(m), *name_span);
                    self.declare(items, m);
                }
                Item::Event(e) => {
                    let meta = EventMeta {
                        trigger: Trigger::Virtual,
                        reset_on_denial: Vec::new(),
                        code_on_accept: None,
                        code_on_denial: None,
                        spans: EventSpans::default(),
                        fragments: EventFragments::default(),
                    };
                    self.new_event(
                        module,
                        &e.name,
                        e.kind.unwrap_or(EventKind::Controllable),
                        meta,
                        Some(e),
                        e.name_span,
                    );
                }
                Item::Timer(t) => {
                    let m = self.new_module(module, &t.name);
                    self.add(module, &t.name, Entry::Timer(m), t.name_span);
                    let meta = EventMeta {
                        trigger: Trigger::Timer { timer: self.modules[m].path.clone() },
                        reset_on_denial: Vec::new(),
                        code_on_accept: None,
                        code_on_denial: None,
                        spans: EventSpans::default(),
                        fragments: EventFragments::default(),
                    };
                    let id = self.new_event(m, "timeout", EventKind::Uncontrollable, meta, None, t.name_span);
                    self.timers.push((t, module, id));
                }
                Item::Automaton(a) => {
                    let r =
                        AutRef { decl: a, module, binding: None, name: qualify(&self.modules[module].path, &a.name) };
                    match a.kind {
                        AutKind::Plant => {
                            self.plants.push(r);
                            self.add(module, &a.name, Entry::Plant(self.plants.len() - 1), a.name_span);
                        }
                        AutKind::Spec => {
                            self.specs.push(r);
                            self.add(module, &a.name, Entry::Spec(self.specs.len() - 1), a.name_span);
                        }
                    }
                }
                Item::Template(a) => {
                    self.templates.push((a, module));
                    self.add(module, &a.name, Entry::Template(self.templates.len() - 1), a.name_span);
                }
                Item::Instance(i) => {
                    self.instances.push((i, module));
                    self.add(module, &i.name, Entry::Instance(self.instances.len() - 1), i.name_span);
                }
                Item::SpecProduct { name, name_span, operands } => {
                    self.products.push((name.clone(), *name_span, operands, module));
                    self.add(module, name, Entry::Product(self.products.len() - 1), *name_span);
                }
            }
        }
    }

    fn walk(&self, from: usize, parts: &[String]) -> Option<Entry> {
        let mut m = from;
        for (i, p) in parts.iter().enumerate() {
            let (e, _) = *self.modules[m].entries.get(p)?;
            if i + 1 == parts.len() {
                return Some(e);
            }
            match e {
                Entry::Module(x) | Entry::Timer(x) => m = x,
                _ => return None,
            }
        }
        None
    }

    /// Absolute first, then relative from `module` outwards; `accept` filters entry kinds.
    fn lookup(&self, module: usize, parts: &[String], accept: &dyn Fn(Entry) -> bool) -> (Lookup, Option<Entry>) {
        let mut wrong = None;
        if let Some(e) = self.walk(0, parts) {
            if accept(e) {
                return (Lookup::Found(e), None);
            }
            wrong = Some(e);
        }
        let mut found: Vec<(usize, Entry)> = Vec::new();
        let mut m = Some(module);
        while let Some(x) = m {
            if x != 0 {
                if let Some(e) = self.walk(x, parts) {
                    if accept(e) {
                        found.push((x, e));
                    } else {
                        wrong = wrong.or(Some(e));
                    }
                }
            }
            m = self.modules[x].parent;
        }
        match found.len() {
            0 => (Lookup::Missing, wrong),
            1 => (Lookup::Found(found[0].1), None),
            _ => (
                Lookup::Ambiguous(
                    found.iter().map(|(x, _)| qualify(&self.modules[*x].path, &parts.join("."))).collect(),
                ),
                None,
            ),
        }
    }

    fn resolve(&mut self, module: usize, path: &Path, what: &str, accept: &dyn Fn(Entry) -> bool) -> Option<Entry> {
        match self.lookup(module, &path.parts, accept) {
            (Lookup::Found(e), _) => Some(e),
            (Lookup::Ambiguous(c), _) => {
                let d = self.diags.error(path.span, format!("ambiguous name `{}`", path.text()));
                for x in c {
                    d.with_note(format!("could be `{x}`"));
                }
                d.with_note("write the absolute name to choose one");
                None
            }
            (Lookup::Missing, Some(w)) => {
                self.diags.error(path.span, format!("`{}` is {}, not {what}", path.text(), w.what()));
                None
            }
            (Lookup::Missing, None) => {
                let noun = what.trim_start_matches("an ").trim_start_matches("a ");
                self.diags.error(path.span, format!("unknown {noun} `{}`", path.text()));
                None
            }
        }
    }

    fn resolve_event(&mut self, module: usize, path: &Path) -> Option<EventId> {
        match self.resolve(module, path, "an event", &|e| matches!(e, Entry::Event(_))) {
            Some(Entry::Event(id)) => Some(EventId::from_raw(id)),
            _ => None,
        }
    }

    fn check_events(&mut self) {
        for id in 0..self.event_decls.len() {
            let Some(d) = self.event_decls[id] else { continue };
            let kind = self.events[id].kind;
            let mut meta = EventMeta {
                trigger: Trigger::Virtual,
                reset_on_denial: Vec::new(),
                code_on_accept: None,
                code_on_denial: None,
                spans: EventSpans::default(),
                fragments: EventFragments::default(),
            };
            let mut trigger_span: Option<Span> = None;
            for it in &d.items {
                match it {
                    EventItem::Detect { span, .. } | EventItem::Executed { span } if trigger_span.is_some() => {
                        let at = self.loc(trigger_span.unwrap_or(*span));
                        self.diags
                            .error(*span, format!("event `{}` has a second trigger", d.name))
                            .with_note(format!("first trigger at {at}"));
                    }
                    EventItem::Detect { edge, expr, expr_span, span } => {
                        let parsed = parse_expr(expr);
                        self.check_fragment(&parsed, *expr_span, "in the trigger");
                        meta.fragments.trigger = parsed.ok();
                        trigger_span = Some(*span);
                        if kind == EventKind::Enforceable {
                            self.diags
                                .error(*span, format!("enforceable event `{}` cannot be detected", d.name))
                                .with_note(
                                    "the supervisor executes enforceable events; give it `on accept` code instead",
                                );
                        }
                        if *edge == EdgeKind::Cyclic && kind == EventKind::Uncontrollable {
                            self.diags
                                .warning(*span, format!("cyclic uncontrollable event `{}`", d.name))
                                .with_note("cyclic triggers are meant for controllable events (5.6)");
                        }
                        meta.trigger = Trigger::Detected { edge: *edge, expr: expr.clone() };
                        meta.spans.trigger = Some(*expr_span);
                    }
                    EventItem::Executed { span } => {
                        trigger_span = Some(*span);
                        if kind == EventKind::Uncontrollable {
                            self.diags
                                .error(
                                    *span,
                                    format!("uncontrollable event `{}` cannot be executed by the controller", d.name),
                                )
                                .with_note("uncontrollable events are always detected");
                        }
                        if kind == EventKind::Enforceable {
                            self.diags.error(
                                *span,
                                format!(
                                    "enforceable event `{}` is executed by the supervisor, not the controller",
                                    d.name
                                ),
                            );
                        }
                        meta.trigger = Trigger::Executed;
                    }
                    EventItem::ResetOnDenial { addrs, span } => {
                        for (addr, at) in addrs {
                            let parsed = parse_expr(addr);
                            let signal = match &parsed {
                                Ok(e) if !matches!(e.kind, ExprKind::Var(_) | ExprKind::Address(_)) => {
                                    Err(FragmentError {
                                        span: e.span,
                                        message: "expected a variable or an address to reset".into(),
                                    })
                                }
                                Ok(_) => Ok(()),
                                Err(e) => Err(e.clone()),
                            };
                            self.check_fragment(&signal, *at, "in `reset on denial`");
                            meta.fragments.resets.extend(parsed.ok());
                        }
                        if kind != EventKind::Controllable {
                            self.diags.error(
                                *span,
                                format!("only controllable events can be reset on denial (`{}` is not)", d.name),
                            );
                        }
                        meta.reset_on_denial.extend(addrs.iter().map(|(a, _)| a.clone()));
                        meta.spans.reset_on_denial.extend(addrs.iter().map(|(_, at)| *at));
                    }
                    EventItem::OnAccept { code, code_span, span } => {
                        let parsed = parse_statements(code);
                        self.check_fragment(&parsed, *code_span, "in the code");
                        if kind == EventKind::Uncontrollable {
                            self.diags.error(*span, format!("uncontrollable event `{}` cannot have actions", d.name));
                        }
                        meta.code_on_accept = Some(code.clone());
                        meta.fragments.accept = parsed.unwrap_or_default();
                        meta.spans.code_on_accept = Some(*code_span);
                    }
                    EventItem::OnDenial { code, code_span, span } => {
                        let parsed = parse_statements(code);
                        self.check_fragment(&parsed, *code_span, "in the code");
                        if kind == EventKind::Uncontrollable {
                            self.diags.error(*span, format!("uncontrollable event `{}` cannot have actions", d.name));
                        }
                        meta.code_on_denial = Some(code.clone());
                        meta.fragments.denial = parsed.unwrap_or_default();
                        meta.spans.code_on_denial = Some(*code_span);
                    }
                }
            }
            meta.spans.name = self.metas[id].spans.name;
            let executed = matches!(meta.trigger, Trigger::Executed);
            if (kind == EventKind::Enforceable || executed) && meta.code_on_accept.is_none() {
                let why = if executed { "an executed controllable event" } else { "an enforceable event" };
                self.diags.error(d.name_span, format!("`{}` is {why} and needs `on accept \"...\";` code", d.name));
            }
            self.metas[id] = meta;
        }
    }

    fn resolve_instances(&mut self) {
        for i in 0..self.instances.len() {
            let (inst, module) = self.instances[i];
            let Some(Entry::Template(t)) =
                self.resolve(module, &inst.template, "a template", &|e| matches!(e, Entry::Template(_)))
            else {
                self.modules[module].entries.remove(&inst.name);
                continue;
            };
            let (tpl, _) = self.templates[t];
            let mut map: HashMap<Vec<String>, EventId> = HashMap::new();
            let mut ok = true;
            // Check that every binding names a bind or namespace of the template.
            for b in &inst.bindings {
                let l = &b.lhs.parts;
                let known = (l.len() == 1
                    && (tpl.binds.iter().any(|x| x.0 == l[0]) || tpl.namespaces.iter().any(|n| n.0 == l[0])))
                    || (l.len() == 2 && tpl.namespaces.iter().any(|n| n.0 == l[0] && n.2.iter().any(|e| e.0 == l[1])));
                if !known {
                    self.diags.error(
                        b.lhs.span,
                        format!("template `{}` has no binding event or namespace `{}`", tpl.name, b.lhs.text()),
                    );
                    ok = false;
                }
            }
            let explicit = |key: &[String]| inst.bindings.iter().find(|b| b.lhs.parts == key);
            for (bname, bspan) in &tpl.binds {
                let key = vec![bname.clone()];
                let ev = if let Some(b) = explicit(&key) {
                    self.resolve_event(module, &b.rhs)
                } else if let Some((Entry::Event(id), _)) = self.modules[module].entries.get(bname).copied() {
                    Some(EventId::from_raw(id))
                } else {
                    let at = self.loc(*bspan);
                    let mpath = self.modules[module].path.clone();
                    self.diags
                        .error(
                            inst.name_span,
                            format!("binding event `{bname}` of template `{}` is not bound", tpl.name),
                        )
                        .with_note(format!(
                            "declared at {at}; add `{bname} = <event>;` or declare event `{bname}` in module `{mpath}`"
                        ));
                    None
                };
                match ev {
                    Some(e) => {
                        map.insert(key, e);
                    }
                    None => ok = false,
                }
            }
            for (ns, ns_span, evs) in &tpl.namespaces {
                let target_module = match explicit(std::slice::from_ref(ns)) {
                    Some(b) => match self.resolve(module, &b.rhs, "a module", &|e| matches!(e, Entry::Module(_))) {
                        Some(Entry::Module(m)) => Some(m),
                        _ => {
                            ok = false;
                            None
                        }
                    },
                    None => None,
                };
                for (ename, espan) in evs {
                    let key = vec![ns.clone(), ename.clone()];
                    let ev = if let Some(b) = explicit(&key) {
                        self.resolve_event(module, &b.rhs)
                    } else if let Some(m) = target_module {
                        match self.modules[m].entries.get(ename).copied() {
                            Some((Entry::Event(id), _)) => Some(EventId::from_raw(id)),
                            _ => {
                                let mpath = self.modules[m].path.clone();
                                self.diags
                                    .error(inst.name_span, format!("binding event `{ns}.{ename}` is not bound: module `{mpath}` has no event `{ename}`"))
                                    .with_note(format!("add `{ns}.{ename} = <event>;` to override"));
                                None
                            }
                        }
                    } else {
                        let at = self.loc(*ns_span);
                        let _ = espan;
                        self.diags
                            .error(inst.name_span, format!("binding event `{ns}.{ename}` of template `{}` is not bound", tpl.name))
                            .with_note(format!("namespace `{ns}` declared at {at}; add `{ns} = <module>;` or `{ns}.{ename} = <event>;`"));
                        None
                    };
                    match ev {
                        Some(e) => {
                            map.insert(key, e);
                        }
                        None => ok = false,
                    }
                }
            }
            let name = qualify(&self.modules[module].path, &inst.name);
            let r = AutRef { decl: tpl, module, binding: Some((map, inst.name_span)), name };
            let entry = match tpl.kind {
                AutKind::Plant => {
                    self.plants.push(r);
                    Entry::Plant(self.plants.len() - 1)
                }
                AutKind::Spec => {
                    self.specs.push(r);
                    Entry::Spec(self.specs.len() - 1)
                }
            };
            if let Some(slot) = self.modules[module].entries.get_mut(&inst.name) {
                slot.0 = entry;
            }
            let _ = ok;
        }
    }

    fn build_timers(&mut self) -> Vec<TimerInfo> {
        let mut out = Vec::new();
        for k in 0..self.timers.len() {
            let (t, module, timeout) = self.timers[k];
            if t.duration_ms.is_none() {
                self.diags.error(t.name_span, format!("timer `{}` has no `duration`", t.name));
            }
            let start = match &t.start {
                Some(p) => self.resolve_event(module, p).map(|e| self.events[e.index()].name.clone()),
                None => {
                    self.diags.error(t.name_span, format!("timer `{}` has no `start` event", t.name));
                    None
                }
            };
            let stop_ids: Vec<EventId> = t.stops.iter().filter_map(|p| self.resolve_event(module, p)).collect();
            let stop: Vec<String> = stop_ids.iter().map(|e| self.events[e.index()].name.clone()).collect();
            out.push(TimerInfo {
                name: qualify(&self.modules[module].path, &t.name),
                duration_ms: t.duration_ms.unwrap_or(0),
                start: start.unwrap_or_default(),
                stop,
                timeout: self.events[timeout as usize].name.clone(),
            });
        }
        out
    }

    /// Resolves an event written in an automaton body (binding events first for instances).
    fn body_event(&mut self, r: usize, is_plant: bool, path: &Path) -> Option<EventId> {
        let aref = if is_plant { &self.plants[r] } else { &self.specs[r] };
        let module = aref.module;
        if let Some((map, _)) = &aref.binding {
            if let Some(&e) = map.get(&path.parts) {
                return Some(e);
            }
        }
        self.resolve_event(module, path)
    }

    /// Resolves a condition; `plant_states` holds the state names of every plant.
    fn cond(&mut self, module: usize, c: &CondExpr, plant_states: &[Vec<String>]) -> Option<Cond> {
        Some(match c {
            CondExpr::True => Cond::True,
            CondExpr::False => Cond::False,
            CondExpr::Not(x) => Cond::Not(Box::new(self.cond(module, x, plant_states)?)),
            CondExpr::And(operands) | CondExpr::Or(operands) => {
                // Every operand is resolved so that all unknown names are reported at once.
                let resolved: Vec<Option<Cond>> = operands.iter().map(|x| self.cond(module, x, plant_states)).collect();
                let resolved: Vec<Cond> = resolved.into_iter().collect::<Option<_>>()?;
                let join = if matches!(c, CondExpr::And(_)) { Cond::And } else { Cond::Or };
                balanced(resolved, &join)
            }
            CondExpr::State(p) => {
                if p.parts.len() < 2 {
                    self.diags
                        .error(p.span, format!("`{}` is not a state reference", p.text()))
                        .with_note("write `Automaton.state`, e.g. `Heater.on`");
                    return None;
                }
                let aut = Path { parts: p.parts[..p.parts.len() - 1].to_vec(), span: p.span };
                let state = &p.parts[p.parts.len() - 1];
                match self.resolve(module, &aut, "a plant", &|e| matches!(e, Entry::Plant(_))) {
                    Some(Entry::Plant(i)) => {
                        let names = &plant_states[i];
                        match names.iter().position(|s| s == state) {
                            Some(k) => Cond::State { plant: i as u32, state: k as u32 },
                            None => {
                                let pname = self.plants[i].name.clone();
                                self.diags
                                    .error(p.span, format!("plant `{pname}` has no state `{state}`"))
                                    .with_note(format!("its states are: {}", names.join(", ")));
                                return None;
                            }
                        }
                    }
                    _ => return None,
                }
            }
        })
    }

    fn plant_state_names(&self) -> Vec<Vec<String>> {
        self.plants.iter().map(|p| p.decl.states.iter().map(|s| s.name.clone()).collect()).collect()
    }

    /// States, initial state and per-state items common to plants and specs.
    fn states_of(&mut self, decl: &AutDecl, name: &str, span: Span) -> (Vec<String>, u32, HashMap<String, u32>) {
        let mut names = Vec::new();
        let mut index: HashMap<String, u32> = HashMap::new();
        let mut init: Option<(u32, Span)> = None;
        for st in &decl.states {
            if let Some(&prev) = index.get(&st.name) {
                let at = self.loc(decl.states[prev as usize].span);
                self.diags
                    .error(st.span, format!("state `{}` is declared twice in `{name}`", st.name))
                    .with_note(format!("first declared at {at}"));
                continue;
            }
            index.insert(st.name.clone(), names.len() as u32);
            if st.initial {
                if let Some((_, ps)) = init {
                    let at = self.loc(ps);
                    self.diags
                        .error(st.span, format!("`{name}` has a second initial state `{}`", st.name))
                        .with_note(format!("first initial state at {at}"));
                } else {
                    init = Some((names.len() as u32, st.span));
                }
            }
            names.push(st.name.clone());
        }
        if names.is_empty() {
            self.diags.error(span, format!("`{name}` has no states"));
        }
        (names, init.map_or(0, |x| x.0), index)
    }

    fn build_plant(&mut self, i: usize, all_states: &[Vec<String>]) -> model::Plant {
        let decl = self.plants[i].decl;
        let module = self.plants[i].module;
        let name = self.plants[i].name.clone();
        let span = self.plants[i].binding.as_ref().map_or(decl.name_span, |b| b.1);
        let (states, init, index) = self.states_of(decl, &name, span);
        let mut alphabet = Vec::new();
        match &decl.alphabet {
            None => {
                self.diags
                    .error(span, format!("plant `{name}` needs an `alphabet`"))
                    .with_note("the alphabet lists every event the plant model makes statements about");
            }
            Some((list, _)) => {
                for p in list {
                    if let Some(e) = self.body_event(i, true, p) {
                        alphabet.push(e);
                    }
                }
            }
        }
        crate::sort::sort(&mut alphabet);
        alphabet.dedup();
        let mut trans: Vec<Transition> = Vec::new();
        let mut spans: Vec<Span> = Vec::new();
        let mut impossible: Vec<(u32, EventId)> = Vec::new();
        for (sidx, st) in decl.states.iter().enumerate() {
            let Some(&src) = index.get(&st.name).filter(|&&x| x as usize == sidx) else { continue };
            for item in &st.items {
                match item {
                    StateItem::Trans { event, target, target_span, cond, span } => {
                        let e = self.body_event(i, true, event);
                        let dst = index.get(target).copied();
                        if dst.is_none() {
                            self.diags.error(*target_span, format!("unknown state `{target}` in plant `{name}`"));
                        }
                        let c = match cond {
                            Some(c) => self.cond(module, c, all_states),
                            None => Some(Cond::True),
                        };
                        if let (Some(e), Some(dst), Some(c)) = (e, dst, c) {
                            if alphabet.binary_search(&e).is_err() && decl.alphabet.is_some() {
                                self.diags
                                    .error(
                                        event.span,
                                        format!("event `{}` is not in the alphabet of plant `{name}`", event.text()),
                                    )
                                    .with_note("add it to the `alphabet` line");
                            }
                            let origin = self.origins.len() as u32;
                            self.origins.push(*span);
                            trans.push(Transition { src, event: e, cond: c, dst, origin });
                            spans.push(*span);
                        }
                    }
                    StateItem::Forbid { span, .. } => {
                        self.diags
                            .error(*span, format!("plant `{name}` cannot forbid events"))
                            .with_note("prohibitions belong in a `spec`; a plant says what is possible");
                    }
                    StateItem::Impossible { events, span } => {
                        if decl.selfloops.is_none() {
                            self.diags.error(*span, "`impossible` only makes sense in a plant with `selfloops;`");
                        }
                        for p in events {
                            if let Some(e) = self.body_event(i, true, p) {
                                impossible.push((src, e));
                            }
                        }
                    }
                }
            }
        }
        self.check_duplicates(&trans, &spans, &name);
        if decl.selfloops.is_some() {
            let n = states.len() as u32;
            let mut has = std::collections::HashSet::new();
            for t in &trans {
                has.insert((t.src, t.event));
            }
            for s in 0..n {
                for &e in &alphabet {
                    if !has.contains(&(s, e)) && !impossible.contains(&(s, e)) {
                        trans.push(Transition { src: s, event: e, cond: Cond::True, dst: s, origin: model::NO_ORIGIN });
                    }
                }
            }
        }
        self.check_enforceable_cycle(&trans, &name);
        model::Plant { name, alphabet, states, init, trans }
    }

    fn check_duplicates(&mut self, trans: &[Transition], spans: &[Span], name: &str) {
        let mut seen: HashMap<(u32, EventId), usize> = HashMap::new();
        for (k, t) in trans.iter().enumerate() {
            if !t.cond.is_true() {
                continue;
            }
            if let Some(&prev) = seen.get(&(t.src, t.event)) {
                let at = self.loc(spans[prev]);
                self.diags
                    .error(
                        spans[k],
                        format!(
                            "two unconditional transitions on `{}` leave the same state of `{name}`",
                            self.events[t.event.index()].name
                        ),
                    )
                    .with_note(format!("the other transition is at {at}"))
                    .with_note(
                        "automata are deterministic: give the transitions mutually exclusive conditions `if [...]`",
                    );
            } else {
                seen.insert((t.src, t.event), k);
            }
        }
    }

    fn check_enforceable_cycle(&mut self, trans: &[Transition], name: &str) {
        // A cycle made only of enforceable transitions could be enforced forever (5.5.5).
        let enf: Vec<&Transition> = trans
            .iter()
            .filter(|t| self.events[t.event.index()].kind == EventKind::Enforceable && t.src != t.dst)
            .collect();
        if enf.is_empty() {
            return;
        }
        let n = trans.iter().map(|t| t.src.max(t.dst)).max().unwrap_or(0) as usize + 1;
        let mut adj: Vec<Vec<usize>> = vec![Vec::new(); n];
        for (k, t) in enf.iter().enumerate() {
            adj[t.src as usize].push(k);
        }
        let graph = Lists(adj.iter().map(|ks| ks.iter().map(|&k| enf[k].dst).collect()).collect());
        // The first back edge of a depth-first search closes a cycle: back from its source up
        // the search tree to its target.
        let mut parent = vec![None; n];
        let found = depth_first_search(View(&graph), 0..n as u32, |event| match event {
            DfsEvent::TreeEdge(u, v) => {
                parent[v as usize] = Some(u);
                Control::Continue
            }
            DfsEvent::BackEdge(u, v) => Control::Break((u, v)),
            _ => Control::Continue,
        });
        if let Some((last, entry)) = found.break_value() {
            let mut states = vec![last];
            while states[states.len() - 1] != entry {
                let up = parent[states[states.len() - 1] as usize];
                states.push(up.expect("the search tree leads from a back edge's source up to its target"));
            }
            states.reverse();
            states.push(entry);
            // Between two states the search took the first enforceable transition listed.
            let step = |w: &[u32]| adj[w[0] as usize].iter().copied().find(|&k| enf[k].dst == w[1]);
            let cycle: Vec<usize> = states.windows(2).filter_map(step).collect();
            let first = self.origins.get(enf[cycle[0]].origin as usize).copied().unwrap_or_default();
            let notes: Vec<String> = cycle[1..]
                .iter()
                .filter_map(|&k| self.origins.get(enf[k].origin as usize).copied())
                .map(|sp| format!("continues at {}", self.loc(sp)))
                .collect();
            let d = self.diags.warning(first, format!("plant `{name}` has a cycle of enforceable transitions"));
            for nt in notes {
                d.with_note(nt);
            }
            d.with_note("if synthesis enforces them all, the supervisor would enforce events forever (5.5.5)");
        }
    }

    fn build_spec(&mut self, i: usize, all_states: &[Vec<String>]) -> model::Spec {
        let decl = self.specs[i].decl;
        let module = self.specs[i].module;
        let name = self.specs[i].name.clone();
        let span = self.specs[i].binding.as_ref().map_or(decl.name_span, |b| b.1);
        let (states, init, index) = self.states_of(decl, &name, span);
        if let Some((_, sp)) = &decl.alphabet {
            self.diags
                .error(*sp, format!("specification `{name}` cannot have an alphabet"))
                .with_note("specifications prohibit events explicitly with `forbid`; every other event is allowed");
        }
        if let Some(sp) = decl.selfloops {
            self.diags.error(sp, "`selfloops` is a helper for plant models only");
        }
        let mut trans = Vec::new();
        let mut spans = Vec::new();
        let mut prohib: Vec<Prohibition> = Vec::new();
        let mut pspans: Vec<Span> = Vec::new();
        for (sidx, st) in decl.states.iter().enumerate() {
            let Some(&src) = index.get(&st.name).filter(|&&x| x as usize == sidx) else { continue };
            for item in &st.items {
                match item {
                    StateItem::Trans { event, target, target_span, cond, span } => {
                        let e = self.body_event(i, false, event);
                        let dst = index.get(target).copied();
                        if dst.is_none() {
                            self.diags
                                .error(*target_span, format!("unknown state `{target}` in specification `{name}`"));
                        }
                        let c = match cond {
                            Some(c) => self.cond(module, c, all_states),
                            None => Some(Cond::True),
                        };
                        if let (Some(e), Some(dst), Some(c)) = (e, dst, c) {
                            let origin = self.origins.len() as u32;
                            self.origins.push(*span);
                            trans.push(Transition { src, event: e, cond: c, dst, origin });
                            spans.push(*span);
                        }
                    }
                    StateItem::Forbid { events, cond, span } => {
                        let c = match cond {
                            Some(c) => self.cond(module, c, all_states),
                            None => Some(Cond::True),
                        };
                        for p in events {
                            if let (Some(e), Some(c)) = (self.body_event(i, false, p), c.clone()) {
                                let origin = self.origins.len() as u32;
                                self.origins.push(p.span);
                                prohib.push(Prohibition { state: src, event: e, cond: c, origin });
                                pspans.push(p.span);
                            }
                        }
                        let _ = span;
                    }
                    StateItem::Impossible { span, .. } => {
                        self.diags.error(*span, "`impossible` is a helper for plant models only");
                    }
                }
            }
        }
        self.check_duplicates(&trans, &spans, &name);
        // Consistency (definition 2): an unconditionally forbidden event has no transition.
        for (k, p) in prohib.iter().enumerate() {
            if !p.cond.is_true() {
                continue;
            }
            if let Some(j) = trans.iter().position(|t| t.src == p.state && t.event == p.event && t.cond.is_true()) {
                let at = self.loc(spans[j]);
                self.diags
                    .error(
                        pspans[k],
                        format!(
                            "`{}` is both forbidden and taken in state `{}` of `{name}`",
                            self.events[p.event.index()].name,
                            states[p.state as usize]
                        ),
                    )
                    .with_note(format!("the transition is at {at}"));
            }
        }
        model::Spec { name, states, init, trans, prohib }
    }
}
