//! Semantic analysis: resolves names, expands hardware and operator units (4.3.2, 4.3.3),
//! compiles plans (algorithm 4) and conditions, and reports every semantic error with its
//! location. Produces a [`Game`] only when there is no error.

use super::ast::{self, Component, Cond, Interval, MessageKind, MoveShape, PlanAction};
use super::model::*;
use crate::diag::{Diagnostics, Span};
use std::collections::HashMap;

/// Checks `spec` and lowers it to a game. All problems are appended to `diags`; the game is
/// returned only if none of them is an error.
pub fn check(spec: &ast::Spec, diags: &mut Diagnostics) -> Option<Game> {
    let mut cx = Checker { diags, game: empty_game(), message_index: HashMap::new(), comp_index: HashMap::new() };
    cx.timeunit(spec);
    cx.components(spec);
    cx.sort_synchronised();
    cx.guards(spec);
    cx.assertions(spec);
    cx.plans(spec);
    cx.dependencies(spec);
    cx.io(spec);
    if cx.game.clocks.len() > MAX_CLOCKS + 1 {
        let n = cx.game.clocks.len() - 1;
        cx.diags
            .error(Span::default(), format!("the specification uses {n} clocks; at most {MAX_CLOCKS} are supported"))
            .with_note("every hardware and operator unit has one clock, plans have their timeout clocks");
    }
    if spec.components.is_empty() {
        cx.diags
            .error(Span::default(), "the specification has no plant components")
            .with_note("add a `plant { … }` section");
    }
    if spec.plans.is_empty() && !spec.components.is_empty() {
        cx.diags
            .warning(Span::default(), "the specification has no plans")
            .with_note("without production goals every repeated plant state counts as a zeno loop");
    }
    if cx.diags.has_errors() {
        None
    } else {
        super::timelock::warn(&cx.game, cx.diags);
        Some(cx.game)
    }
}

/// Clocks are kept in 64-bit sets (bit 0 is the reference clock).
pub const MAX_CLOCKS: usize = 63;

fn empty_game() -> Game {
    Game {
        timeunit_ms: 1000,
        timeunit_span: None,
        scan_ms: None,
        scan: None,
        clocks: vec![Clock { name: "0".into(), owner: ClockOwner::Reference, span: Span::default() }],
        messages: Vec::new(),
        components: Vec::new(),
        plans: Vec::new(),
        assertions: Vec::new(),
        guards: Vec::new(),
        dependencies: Vec::new(),
        io: Vec::new(),
    }
}

struct Checker<'d, 'a> {
    diags: &'d mut Diagnostics<'a>,
    game: Game,
    message_index: HashMap<String, MsgId>,
    comp_index: HashMap<String, CompId>,
}

/// One use of a message by a plant transition, remembered for the consistency checks.
struct MessageUse {
    comp: CompId,
    kind: MessageKind,
    span: Span,
}

impl Checker<'_, '_> {
    fn where_(&self, span: Span) -> String {
        let (line, col) = self.diags.line_col(span.start as usize);
        format!("{line}:{col}")
    }

    fn timeunit(&mut self, spec: &ast::Spec) {
        if let Some(first) = spec.timeunit.first() {
            self.game.timeunit_ms = first.millis.max(1);
            self.game.timeunit_span = Some(first.span);
        }
        if let Some(first) = spec.scan.first() {
            self.game.scan_ms = Some((first.millis, first.span));
        }
        for extra in spec.scan.iter().skip(1) {
            let first = self.where_(spec.scan[0].span);
            self.diags
                .error(extra.span, "the scan time is declared twice")
                .with_note(format!("first declared at {first}"));
        }
        for extra in spec.timeunit.iter().skip(1) {
            let first = self.where_(spec.timeunit[0].span);
            self.diags
                .error(extra.span, "the time unit is declared twice")
                .with_note(format!("first declared at {first}"));
        }
    }

    fn intern_message(&mut self, name: &str, role: MessageRole) -> MsgId {
        if let Some(&id) = self.message_index.get(name) {
            return id;
        }
        let id = MsgId::new(self.game.messages.len());
        self.game.messages.push(Message { name: name.to_string(), role, sender: None, synchronised: Vec::new() });
        self.message_index.insert(name.to_string(), id);
        id
    }

    // ----- components -----------------------------------------------------------------------

    fn components(&mut self, spec: &ast::Spec) {
        let mut first_decl: HashMap<&str, Span> = HashMap::new();
        let mut uses: Vec<(MsgId, MessageUse)> = Vec::new();
        for component in &spec.components {
            let name = component.name();
            if let Some(prev) = first_decl.get(name.name.as_str()) {
                let at = self.where_(*prev);
                self.diags
                    .error(name.span, format!("a unit named `{}` is already declared", name.name))
                    .with_note(format!("first declared at {at}"));
                continue;
            }
            first_decl.insert(&name.name, name.span);
            let comp = CompId::new(self.game.components.len());
            let automaton = match component {
                Component::Automaton(a) => self.automaton(comp, a, &mut uses),
                Component::Hardware(h) => self.moves_unit(comp, &h.name, &h.states, &h.moves, h.span, true, &mut uses),
                Component::Operator(o) => self.moves_unit(comp, &o.name, &o.states, &o.moves, o.span, false, &mut uses),
            };
            self.comp_index.insert(name.name.clone(), comp);
            self.game.components.push(automaton);
        }
        self.record_message_uses(uses);
    }

    fn new_clock(&mut self, name: String, owner: ClockOwner, span: Span) -> ClockId {
        self.game.clocks.push(Clock { name, owner, span });
        ClockId::new(self.game.clocks.len() - 1)
    }

    fn automaton(&mut self, comp: CompId, decl: &ast::AutomatonDecl, uses: &mut Vec<(MsgId, MessageUse)>) -> Automaton {
        let unit = &decl.name.name;
        let mut clock_ids: HashMap<&str, ClockId> = HashMap::new();
        let mut clocks = Vec::new();
        for c in &decl.clocks {
            if clock_ids.contains_key(c.name.as_str()) {
                self.diags.error(c.span, format!("clock `{}` is declared twice in `{unit}`", c.name));
                continue;
            }
            let id = self.new_clock(format!("{unit}.{}", c.name), ClockOwner::Component(comp), c.span);
            clock_ids.insert(&c.name, id);
            clocks.push(id);
        }
        let mut loc_ids: HashMap<&str, LocId> = HashMap::new();
        let mut locations = Vec::new();
        for n in &decl.nodes {
            if loc_ids.contains_key(n.name.name.as_str()) {
                self.diags.error(n.name.span, format!("node `{}` is declared twice in `{unit}`", n.name.name));
                continue;
            }
            let invariant = self.constraints(unit, &n.invariant, &clock_ids);
            loc_ids.insert(&n.name.name, LocId::new(locations.len()));
            locations.push(Location { name: n.name.name.clone(), invariant, span: n.name.span });
        }
        if decl.nodes.is_empty() {
            self.diags
                .error(decl.name.span, format!("automaton `{unit}` declares no nodes"))
                .with_note("add `nodes a, b;`");
        }
        let mut edges = Vec::new();
        for t in &decl.transitions {
            let from = self.node_ref(unit, &t.from, &loc_ids);
            let to = self.node_ref(unit, &t.to, &loc_ids);
            let guard = self.constraints(unit, &t.guard, &clock_ids);
            let mut resets = Vec::new();
            for r in &t.resets {
                match clock_ids.get(r.name.as_str()) {
                    Some(&id) => resets.push(id),
                    None => self.unknown_clock(unit, r),
                }
            }
            let message = self.intern_message(&t.message.name, MessageRole::Reaction);
            uses.push((message, MessageUse { comp, kind: t.kind, span: t.message.span }));
            if let (Some(from), Some(to)) = (from, to) {
                edges.push(Edge { from, to, kind: t.kind, message, guard, resets, instant: t.instant, span: t.span });
            }
        }
        Automaton {
            name: unit.clone(),
            origin: ComponentOrigin::Automaton,
            locations,
            initial: LocId::new(0),
            clocks,
            edges,
            span: decl.span,
        }
    }

    fn node_ref(&mut self, unit: &str, node: &ast::Ident, loc_ids: &HashMap<&str, LocId>) -> Option<LocId> {
        let found = loc_ids.get(node.name.as_str()).copied();
        if found.is_none() {
            self.diags.error(node.span, format!("unknown node `{}` in `{unit}`", node.name));
        }
        found
    }

    fn unknown_clock(&mut self, unit: &str, clock: &ast::Ident) {
        let suffix = format!(".{}", clock.name);
        let owner = self.game.clocks.iter().find(|c| c.name.ends_with(&suffix)).map(|c| c.name.clone());
        let d = self.diags.error(clock.span, format!("unknown clock `{}` in `{unit}`", clock.name));
        match owner {
            Some(q) => d.with_note(format!("`{q}` belongs to another unit; a unit may only use its own clocks")),
            None => d.with_note(format!("declare it with `clocks {};`", clock.name)),
        };
    }

    fn constraints(
        &mut self,
        unit: &str,
        list: &[ast::ClockConstraint],
        clocks: &HashMap<&str, ClockId>,
    ) -> Vec<ClockInterval> {
        let mut out = Vec::new();
        for c in list {
            self.check_interval(&c.interval);
            match clocks.get(c.clock.name.as_str()) {
                Some(&clock) => out.push(ClockInterval { clock, interval: c.interval }),
                None => self.unknown_clock(unit, &c.clock),
            }
        }
        out
    }

    fn check_interval(&mut self, i: &Interval) {
        if i.is_empty() {
            let msg = match i.upper {
                Some(u) if u < i.lower => {
                    format!("the interval {i} is empty: its lower bound {} exceeds its upper bound {u}", i.lower)
                }
                _ => format!("the interval {i} is empty"),
            };
            self.diags.error(i.span, msg);
        }
    }

    /// Expands a hardware unit (4.3.2) or an operator unit (4.3.3) into an automaton.
    #[allow(clippy::too_many_arguments)]
    fn moves_unit(
        &mut self,
        comp: CompId,
        name: &ast::Ident,
        states: &[ast::Ident],
        moves: &[ast::MoveDecl],
        span: Span,
        hardware: bool,
        uses: &mut Vec<(MsgId, MessageUse)>,
    ) -> Automaton {
        let unit = &name.name;
        let kind_word = if hardware { "hardware" } else { "operator" };
        let mut loc_ids: HashMap<String, LocId> = HashMap::new();
        let mut locations = Vec::new();
        for s in states {
            if loc_ids.contains_key(&s.name) {
                self.diags.error(s.span, format!("state `{}` is declared twice in `{unit}`", s.name));
                continue;
            }
            loc_ids.insert(s.name.clone(), LocId::new(locations.len()));
            locations.push(Location { name: s.name.clone(), invariant: Vec::new(), span: s.span });
        }
        if states.is_empty() {
            self.diags
                .error(name.span, format!("{kind_word} `{unit}` declares no states"))
                .with_note("add `states a, b;`");
        }
        let clock = self.new_clock(format!("{unit}.moving"), ClockOwner::Component(comp), name.span);
        let mut edges = Vec::new();
        let mut seen: HashMap<(LocId, LocId), Span> = HashMap::new();
        for m in moves {
            if matches!(m.shape, MoveShape::All) && m.states.len() < 2 {
                self.diags.error(m.span, "a move list needs at least two states");
                continue;
            }
            let timing = match (hardware, m.takes) {
                (true, Some(t)) => {
                    self.check_interval(&t);
                    t
                }
                (true, None) => {
                    self.diags
                        .error(m.span, "a hardware move needs its duration")
                        .with_note("write for example `A -> B takes [2,4];`");
                    continue;
                }
                (false, Some(t)) => {
                    self.diags
                        .error(t.span, "operator moves take no duration")
                        .with_note("an operator reacts within one time unit (4.3.3); use `hardware` for timed moves");
                    continue;
                }
                // 4.3.3: the reaction follows within (0, 1).
                (false, None) => {
                    Interval { lower: 0, lower_closed: false, upper: Some(1), upper_closed: false, span: m.span }
                }
            };
            for (a, b) in m.pairs() {
                let (Some(&from), Some(&to)) = (loc_ids.get(&a.name), loc_ids.get(&b.name)) else {
                    for s in [a, b] {
                        if !loc_ids.contains_key(&s.name) {
                            self.diags.error(s.span, format!("unknown state `{}` in `{unit}`", s.name));
                        }
                    }
                    continue;
                };
                if from == to {
                    self.diags.error(m.span, format!("a move from `{}` to itself", a.name));
                    continue;
                }
                if let Some(prev) = seen.get(&(from, to)) {
                    let at = self.where_(*prev);
                    self.diags
                        .error(m.span, format!("the move from `{}` to `{}` is declared twice", a.name, b.name))
                        .with_note(format!("first declared at {at}"));
                    continue;
                }
                seen.insert((from, to), m.span);
                let moving = LocId::new(locations.len());
                let upper = Interval {
                    lower: 0,
                    lower_closed: true,
                    upper: timing.upper,
                    upper_closed: timing.upper_closed,
                    span: timing.span,
                };
                let lower = Interval {
                    lower: timing.lower,
                    lower_closed: timing.lower_closed,
                    upper: None,
                    upper_closed: false,
                    span: timing.span,
                };
                let invariant =
                    if timing.upper.is_some() { vec![ClockInterval { clock, interval: upper }] } else { Vec::new() };
                locations.push(Location { name: format!("moving_{}_{}", a.name, b.name), invariant, span: m.span });
                let (start_name, start_kind) = if hardware {
                    (format!("moveto_{}", b.name), MessageKind::Controllable)
                } else {
                    (format!("occurred_{}", b.name), MessageKind::Uncontrollable)
                };
                let start = self.intern_message(&start_name, MessageRole::Reaction);
                uses.push((start, MessageUse { comp, kind: start_kind, span: m.span }));
                let reached = self.intern_message(&format!("reached_{}", b.name), MessageRole::Reaction);
                uses.push((reached, MessageUse { comp, kind: MessageKind::Uncontrollable, span: m.span }));
                edges.push(Edge {
                    from,
                    to: moving,
                    kind: start_kind,
                    message: start,
                    guard: Vec::new(),
                    resets: vec![clock],
                    instant: false,
                    span: m.span,
                });
                let guard = if timing.lower > 0 || !timing.lower_closed {
                    vec![ClockInterval { clock, interval: lower }]
                } else {
                    Vec::new()
                };
                edges.push(Edge {
                    from: moving,
                    to,
                    kind: MessageKind::Uncontrollable,
                    message: reached,
                    guard,
                    resets: Vec::new(),
                    instant: false,
                    span: m.span,
                });
            }
        }
        let origin = if hardware { ComponentOrigin::Hardware } else { ComponentOrigin::Operator };
        Automaton { name: unit.clone(), origin, locations, initial: LocId::new(0), clocks: vec![clock], edges, span }
    }

    /// Precondition of 3.3: each `?`/`!` message has one sender; `$` needs a sender elsewhere.
    fn record_message_uses(&mut self, uses: Vec<(MsgId, MessageUse)>) {
        let mut sender: HashMap<MsgId, (CompId, MessageKind, Span)> = HashMap::new();
        for (msg, u) in &uses {
            if u.kind == MessageKind::Synchronised {
                continue;
            }
            match sender.get(msg) {
                None => {
                    sender.insert(*msg, (u.comp, u.kind, u.span));
                }
                Some(&(comp, kind, span)) if comp != u.comp => {
                    let name = self.game.messages[(*msg).index()].name.clone();
                    let other = self.game.components.get(comp.index()).map(|c| c.name.clone()).unwrap_or_default();
                    let at = self.where_(span);
                    self.diags.error(u.span, format!("message `{name}` is already sent by unit `{other}`")).with_note(
                        format!(
                        "{}{name} at {at}; a `?`/`!` message may belong to one unit only (3.3); use `$` to synchronise",
                        kind.sigil()
                    ),
                    );
                }
                Some(&(_, kind, span)) if kind != u.kind => {
                    let name = self.game.messages[(*msg).index()].name.clone();
                    let at = self.where_(span);
                    self.diags
                        .error(
                            u.span,
                            format!("message `{name}` is used both as `{}` and `{}`", kind.sigil(), u.kind.sigil()),
                        )
                        .with_note(format!("first use at {at}"));
                }
                Some(_) => {}
            }
        }
        for (msg, (comp, kind, _)) in &sender {
            let m = &mut self.game.messages[(*msg).index()];
            m.sender = Some(*comp);
            m.role = if *kind == MessageKind::Controllable { MessageRole::Request } else { MessageRole::Reaction };
        }
        for (msg, u) in &uses {
            if u.kind != MessageKind::Synchronised {
                continue;
            }
            let name = self.game.messages[(*msg).index()].name.clone();
            match sender.get(msg) {
                None => {
                    self.diags
                        .error(u.span, format!("synchronised message `{name}` is never sent"))
                        .with_note(format!("no unit has a transition with `?{name}` or `!{name}`"));
                }
                Some(&(comp, _, _)) if comp == u.comp => {
                    self.diags.error(u.span, format!("unit sends `{name}` and also synchronises on it"));
                }
                Some(_) => {
                    let m = &mut self.game.messages[(*msg).index()];
                    if !m.synchronised.contains(&u.comp) {
                        m.synchronised.push(u.comp);
                    }
                }
            }
        }
    }

    /// Sorts the synchronising units of every message, so that moves are generated in a
    /// deterministic order whatever the declaration order.
    fn sort_synchronised(&mut self) {
        for m in &mut self.game.messages {
            crate::sort::sort(&mut m.synchronised);
        }
    }

    // ----- conditions, assertions, guards -----------------------------------------------------

    fn cond(&mut self, c: &Cond) -> Option<Pred> {
        Some(match c {
            Cond::Const { value, .. } => Pred::Const { value: *value },
            Cond::Not { operand, .. } => Pred::Not { operand: Box::new(self.cond(operand)?) },
            // Every operand is checked, so that all unknown names are reported at once.
            Cond::And { operands, .. } => {
                let checked: Vec<Option<Pred>> = operands.iter().map(|c| self.cond(c)).collect();
                Pred::And { operands: checked.into_iter().collect::<Option<_>>()? }
            }
            Cond::Or { operands, .. } => {
                let checked: Vec<Option<Pred>> = operands.iter().map(|c| self.cond(c)).collect();
                Pred::Or { operands: checked.into_iter().collect::<Option<_>>()? }
            }
            Cond::State { unit, node, prefix, .. } => {
                let Some(&comp) = self.comp_index.get(&unit.name) else {
                    let d = self.diags.error(unit.span, format!("unknown unit `{}`", unit.name));
                    if let Some(best) = closest(&unit.name, self.game.components.iter().map(|c| c.name.as_str())) {
                        d.with_note(format!("did you mean `{best}`?"));
                    }
                    return None;
                };
                let automaton = &self.game.components[comp.index()];
                let locations: Vec<LocId> = automaton
                    .locations
                    .iter()
                    .enumerate()
                    .filter(|(_, l)| if *prefix { l.name.starts_with(&node.name) } else { l.name == node.name })
                    .map(|(i, _)| LocId::new(i))
                    .collect();
                if locations.is_empty() {
                    let names: Vec<&str> = automaton.locations.iter().map(|l| l.name.as_str()).collect();
                    let msg = if *prefix {
                        format!("no node of `{}` starts with `{}`", unit.name, node.name)
                    } else {
                        format!("unknown node `{}` in unit `{}`", node.name, unit.name)
                    };
                    self.diags.error(node.span, msg).with_note(format!("its nodes are: {}", names.join(", ")));
                    return None;
                }
                Pred::At { comp, locations }
            }
        })
    }

    fn source_text(&self, span: Span) -> String {
        let src = self.diags_source();
        src.get(span.range()).map(|s| s.split_whitespace().collect::<Vec<_>>().join(" ")).unwrap_or_default()
    }

    fn diags_source(&self) -> &str {
        self.diags.source()
    }

    fn assertions(&mut self, spec: &ast::Spec) {
        for a in &spec.assertions {
            let holds = match a {
                ast::Assertion::Never { cond, .. } => self.cond(cond).map(|p| Pred::Not { operand: Box::new(p) }),
                ast::Assertion::Always { cond, .. } => self.cond(cond),
                ast::Assertion::OnlyIf { cond, requires, .. } => {
                    let (c, r) = (self.cond(cond), self.cond(requires));
                    match (c, r) {
                        (Some(c), Some(r)) => Some(Pred::Or { operands: vec![Pred::Not { operand: Box::new(c) }, r] }),
                        _ => None,
                    }
                }
            };
            if let Some(holds) = holds {
                let text = self.source_text(a.span());
                self.game.assertions.push(AssertionRule { holds, text, span: a.span() });
            }
        }
    }

    fn guards(&mut self, spec: &ast::Spec) {
        for g in &spec.guards {
            let pred = self.cond(&g.cond);
            if let Some(&id) = self.message_index.get(&g.message.name) {
                let m = &self.game.messages[id.index()];
                if m.role != MessageRole::Guard {
                    self.diags
                        .error(g.message.span, format!("`{}` is a plant message and cannot be a guard", g.message.name))
                        .with_note("a guard names a sensor condition of its own, such as `part_present`");
                    continue;
                }
            }
            let message = self.intern_message(&g.message.name, MessageRole::Guard);
            if let Some(cond) = pred {
                let text = self.source_text(g.cond.span());
                self.game.guards.push(GuardRule { cond, message, text, span: g.span });
            }
        }
    }

    // ----- plans ------------------------------------------------------------------------------

    fn plans(&mut self, spec: &ast::Spec) {
        for (index, plan) in spec.plans.iter().enumerate() {
            if let Some(p) = self.plan(index, plan) {
                self.game.plans.push(p);
            }
        }
    }

    /// Algorithm 4, with `reset` commands folded into the transitions that reach them: a plan
    /// location is a `waitfor` command; reaching a run of `reset` commands resets their clocks
    /// and continues at the next `waitfor`.
    fn plan(&mut self, index: usize, plan: &ast::Plan) -> Option<PlanAutomaton> {
        let name = format!("plan{}", index + 1);
        let errors_before = self.diags.error_count();
        let mut clock_ids: HashMap<&str, ClockId> = HashMap::new();
        let mut clocks = Vec::new();
        for c in &plan.clocks {
            if clock_ids.contains_key(c.name.name.as_str()) {
                self.diags.error(c.name.span, format!("timeout clock `{}` is declared twice", c.name.name));
                continue;
            }
            let id = self.new_clock(format!("{name}.{}", c.name.name), ClockOwner::Plan(index as u32), c.span);
            clock_ids.insert(&c.name.name, id);
            clocks.push((id, c.bound));
        }
        let commands = &plan.commands;
        let mut labels: HashMap<&str, usize> = HashMap::new();
        for (i, cmd) in commands.iter().enumerate() {
            if let Some(l) = &cmd.label {
                if l.name == "failed" {
                    self.diags.error(l.span, "`failed` is the plan's fail location and cannot be a label");
                } else if labels.insert(&l.name, i).is_some() {
                    self.diags.error(l.span, format!("label `{}` is defined twice in this plan", l.name));
                }
            }
        }
        // Location of each waitfor command.
        let mut loc_of_cmd = vec![None; commands.len()];
        let mut locations = Vec::new();
        for (i, cmd) in commands.iter().enumerate() {
            if let PlanAction::Waitfor { .. } = cmd.action {
                loc_of_cmd[i] = Some(LocId::new(locations.len()));
                let lname =
                    cmd.label.as_ref().map_or_else(|| format!("waitfor{}", locations.len() + 1), |l| l.name.clone());
                locations.push(PlanLocation { name: lname, span: cmd.span });
            }
        }
        if locations.is_empty() {
            self.diags
                .error(plan.span, "this plan has no `waitfor` command")
                .with_note("a plan needs at least one goal to wait for");
            return None;
        }
        for cmd in commands {
            if let PlanAction::Reset { clocks } = &cmd.action {
                for c in clocks {
                    if !clock_ids.contains_key(c.name.as_str()) {
                        self.diags
                            .error(c.span, format!("unknown timeout clock `{}`", c.name))
                            .with_note(format!("declare it with `clocks {} 10;` at the start of the plan", c.name));
                    }
                }
            }
        }
        let failed = LocId::new(locations.len());
        locations.push(PlanLocation { name: "failed".into(), span: plan.span });
        // From command i, follow resets (wrapping at the end) to the next waitfor.
        let resolve = |start: usize| -> (LocId, Vec<ClockId>) {
            let mut resets = Vec::new();
            let mut i = start % commands.len();
            loop {
                match &commands[i].action {
                    PlanAction::Waitfor { .. } => return (loc_of_cmd[i].expect("waitfor has a location"), resets),
                    PlanAction::Reset { clocks } => {
                        for c in clocks {
                            if let Some(&id) = clock_ids.get(c.name.as_str()) {
                                if !resets.contains(&id) {
                                    resets.push(id);
                                }
                            }
                        }
                    }
                }
                i = (i + 1) % commands.len();
            }
        };
        // Clocks start at 0, so the resets before the first waitfor change nothing.
        let (initial, _) = resolve(0);
        let mut edges = Vec::new();
        for (i, cmd) in commands.iter().enumerate() {
            let PlanAction::Waitfor { items } = &cmd.action else { continue };
            let from = loc_of_cmd[i].expect("waitfor has a location");
            let mut seen: HashMap<&str, Span> = HashMap::new();
            for item in items {
                if seen.insert(&item.message.name, item.message.span).is_some() {
                    self.diags
                        .error(item.message.span, format!("`{}` is listed twice in this waitfor", item.message.name));
                    continue;
                }
                let message = match self.message_index.get(&item.message.name) {
                    Some(&id) if self.game.messages[id.index()].role == MessageRole::Guard => {
                        self.diags.error(
                            item.message.span,
                            format!("`{}` is a guard condition, not a message a plan can wait for", item.message.name),
                        );
                        continue;
                    }
                    Some(&id) => id,
                    None => {
                        let d = self
                            .diags
                            .error(item.message.span, format!("no unit sends the message `{}`", item.message.name));
                        if let Some(best) =
                            closest(&item.message.name, self.game.messages.iter().map(|m| m.name.as_str()))
                        {
                            d.with_note(format!("did you mean `{best}`?"));
                        }
                        continue;
                    }
                };
                let (to, resets) = match &item.target {
                    None => resolve(i + 1),
                    Some(l) if l.name == "failed" => (failed, Vec::new()),
                    Some(l) => match labels.get(l.name.as_str()) {
                        Some(&target) => resolve(target),
                        None => {
                            self.diags
                                .error(l.span, format!("undefined label `{}`", l.name))
                                .with_note("labels are written `name:` before a plan command");
                            continue;
                        }
                    },
                };
                edges.push(PlanEdge { from, message, to, resets });
            }
        }
        let errors_after = self.diags.error_count();
        (errors_after == errors_before).then_some(PlanAutomaton {
            name,
            locations,
            initial,
            failed,
            clocks,
            edges,
            span: plan.span,
        })
    }

    // ----- dependencies and io ----------------------------------------------------------------

    fn dependencies(&mut self, spec: &ast::Spec) {
        for d in &spec.dependencies {
            let Some(&message) = self.message_index.get(&d.message.name) else {
                self.diags.warning(
                    d.message.span,
                    format!("dependency on unknown message `{}` has no effect", d.message.name),
                );
                continue;
            };
            let mut on = Vec::new();
            for t in &d.targets {
                match t {
                    ast::DependencyTarget::Time { .. } => on.push(DependsOn::Time),
                    ast::DependencyTarget::Message { name } => match self.message_index.get(&name.name) {
                        Some(&id) => on.push(DependsOn::Message(id)),
                        None => {
                            self.diags.warning(
                                name.span,
                                format!("unknown message `{}` in a dependency is ignored", name.name),
                            );
                        }
                    },
                }
            }
            self.game.dependencies.push(DependencyRule { message, on });
        }
    }

    fn io(&mut self, spec: &ast::Spec) {
        let mut seen: HashMap<&str, Span> = HashMap::new();
        for e in &spec.io {
            let Some(&message) = self.message_index.get(&e.message.name) else {
                let d = self.diags.error(e.message.span, format!("io entry for unknown message `{}`", e.message.name));
                if let Some(best) = closest(&e.message.name, self.game.messages.iter().map(|m| m.name.as_str())) {
                    d.with_note(format!("did you mean `{best}`?"));
                }
                continue;
            };
            if let Some(prev) = seen.insert(&e.message.name, e.span) {
                let at = self.where_(prev);
                self.diags
                    .error(e.span, format!("`{}` is mapped twice", e.message.name))
                    .with_note(format!("first mapped at {at}"));
                continue;
            }
            let request = self.game.messages[message.index()].role == MessageRole::Request;
            let mode = match (e.mode, request) {
                (ast::IoMode::Default, true) => ast::IoMode::Pulse,
                (ast::IoMode::Default, false) => ast::IoMode::Level,
                (m @ (ast::IoMode::Pulse | ast::IoMode::Set | ast::IoMode::Reset), true)
                | (m @ (ast::IoMode::Level | ast::IoMode::Negated), false) => m,
                (m, _) => {
                    let (word, what) = match m {
                        ast::IoMode::Negated => ("not", "inputs (reactions and guards)"),
                        ast::IoMode::Set => ("set", "requests"),
                        ast::IoMode::Reset => ("reset", "requests"),
                        _ => ("pulse", "requests"),
                    };
                    self.diags
                        .error(e.span, format!("`{word}` applies to {what}, but `{}` is {}", e.message.name, if request { "a request" } else { "an input" }))
                        .with_note("requests (`?`) may be `pulse`, `set` or `reset`; inputs (`!`, guards) may be negated with `not`");
                    continue;
                }
            };
            let target = match &e.target {
                ast::IoTarget::Address { text, span } => match self.bit_address(text, *span) {
                    Some(text) => ast::IoTarget::Address { text, span: *span },
                    None => continue,
                },
                symbol => symbol.clone(),
            };
            self.game.io.push(IoBinding { message, mode, target });
        }
    }

    /// Validates a direct address (the lexer guarantees `[IQM][XBWDL]?digits[.digits]`, without
    /// the `%`) and returns it without leading zeros. Every io signal is one BOOL, so it must be
    /// a bit address: byte 0 to [`MAX_ADDRESS_BYTE`], bit 0 to 7. Errors point at the offending part.
    fn bit_address(&mut self, text: &str, span: Span) -> Option<String> {
        let (area, rest) = text.split_at(1);
        let size = rest.chars().next().filter(|c| c.is_ascii_alphabetic());
        let numbers = &rest[size.map_or(0, |c| c.len_utf8())..];
        let (byte, bit) = match numbers.split_once('.') {
            Some((byte, bit)) => (byte, Some(bit)),
            None => (numbers, None),
        };
        // Offsets of the parts in the source: `%`, area, optional size letter, then the numbers.
        let byte_start = span.start as usize + 2 + size.map_or(0, |_| 1);
        let byte_span = Span::new(byte_start, byte_start + byte.len());
        if let Some(size @ ('B' | 'W' | 'D' | 'L')) = size {
            let width = match size {
                'B' => "a byte",
                'W' => "a word",
                'D' => "a double word",
                _ => "a long word",
            };
            self.diags
                .error(span, format!("`%{text}` is {width} address, but an io signal is one bit (BOOL)"))
                .with_note(format!("use a bit address such as `%{area}X{byte}.0`"));
            return None;
        }
        let Some(bit) = bit else {
            self.diags
                .error(span, format!("`%{text}` has no bit number"))
                .with_note(format!("an io signal is one bit: write `%{text}.0` … `%{text}.7`"));
            return None;
        };
        let byte_value = byte.parse::<u32>().ok().filter(|&b| b <= MAX_ADDRESS_BYTE);
        if byte_value.is_none() {
            self.diags
                .error(byte_span, format!("byte number {byte} is out of range in `%{text}`"))
                .with_note(format!("byte numbers of io addresses go from 0 to {MAX_ADDRESS_BYTE}"));
        }
        let bit_value = bit.parse::<u32>().ok().filter(|&b| b <= 7);
        if bit_value.is_none() {
            let bit_start = byte_span.end as usize + 1;
            self.diags
                .error(
                    Span::new(bit_start, bit_start + bit.len()),
                    format!("bit number {bit} is out of range in `%{text}`"),
                )
                .with_note("a byte has bits 0 to 7");
        }
        let (Some(byte), Some(bit)) = (byte_value, bit_value) else { return None };
        Some(format!("{area}{}{byte}.{bit}", size.map_or(String::new(), String::from)))
    }
}

/// Largest byte number of an io address: a 16-bit byte offset. IEC 61131-3 leaves the range to
/// the PLC; a given PLC's configuration may allow fewer (an S7-1500 has 32 KB of inputs).
pub const MAX_ADDRESS_BYTE: u32 = 65_535;

/// The candidate closest to `name` by edit distance, if it is close enough to be a typo.
fn closest<'a>(name: &str, candidates: impl Iterator<Item = &'a str>) -> Option<&'a str> {
    candidates
        .map(|c| (edit_distance(name, c), c))
        .filter(|(d, c)| *d <= 2.max(c.len() / 4) && *d > 0)
        .min_by_key(|(d, _)| *d)
        .map(|(_, c)| c)
}

fn edit_distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut prev = row[0];
        row[0] = i + 1;
        for (j, cb) in b.iter().enumerate() {
            let cur = row[j + 1];
            row[j + 1] = (prev + usize::from(ca != *cb)).min(row[j] + 1).min(cur + 1);
            prev = cur;
        }
    }
    row[b.len()]
}
