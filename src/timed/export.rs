//! JSON views of a game and of a solved state space, for the playground and `--json` output.
//! Shapes are documented in `docs/timed-language.md` (section "JSON output").

use super::explain::{describe_edge, describe_state, removal_text};
use super::model::{ClockInterval, Game, LocId};
use super::solve::{Removal, StateId, StateKind};
use super::{Outcome, Synthesis};
use serde::Serialize;
use std::collections::VecDeque;

#[derive(Serialize)]
pub struct AutomatonView {
    pub name: String,
    /// `automaton`, `hardware`, `operator` or `plan`.
    pub kind: &'static str,
    pub initial: u32,
    pub locations: Vec<LocationView>,
    pub edges: Vec<EdgeView>,
}

impl AutomatonView {
    /// The automaton as a drawing (DOT, [`crate::dot`]): locations with their invariants, the
    /// initial one marked, a plan's fail location classed `failed`; edges labelled with message,
    /// guard and resets, classed by sigil (`edge-request` solid, `edge-reaction` dashed,
    /// `edge-plan` bold).
    pub fn dot(&self) -> String {
        use crate::dot::{document, Drawing, Edge, Node};
        let mut g = Drawing::new();
        let nodes: Vec<_> = self
            .locations
            .iter()
            .map(|l| {
                g.add_node(Node {
                    label: if l.invariant.is_empty() { l.name.clone() } else { format!("{}\n{}", l.name, l.invariant) },
                    class: if l.failed { "location failed".into() } else { "location".into() },
                    tooltip: if l.failed { "the plan has failed".into() } else { l.name.clone() },
                    ..Node::default()
                })
            })
            .collect();
        if let Some(&first) = nodes.get(self.initial as usize) {
            let point = g.add_node(Node { class: "initial-point".into(), shape: Some("point"), ..Node::default() });
            g.add_edge(point, first, Edge { class: "initial".into(), ..Edge::default() });
        }
        for e in &self.edges {
            let mut parts = vec![format!("{}{}{}", e.sigil, e.message, if e.instant { " (instant)" } else { "" })];
            if !e.guard.is_empty() {
                parts.push(e.guard.clone());
            }
            if !e.resets.is_empty() {
                parts.push(format!("reset{{{}}}", e.resets.join(", ")));
            }
            let (class, style) = match e.sigil {
                '?' => ("edge-request", ""),
                '!' => ("edge-reaction", "dashed"),
                _ => ("edge-plan", "bold"),
            };
            g.add_edge(
                nodes[e.from as usize],
                nodes[e.to as usize],
                Edge { label: parts.join("\n"), class: class.into(), style, ..Edge::default() },
            );
        }
        document(&g)
    }
}

#[derive(Serialize)]
pub struct LocationView {
    pub name: String,
    /// Invariant as text, empty when `true`.
    pub invariant: String,
    /// Plans only: the fail location.
    pub failed: bool,
}

#[derive(Serialize)]
pub struct EdgeView {
    pub from: u32,
    pub to: u32,
    /// `?`, `!` or `$`; plan transitions use `$`.
    pub sigil: char,
    pub message: String,
    pub guard: String,
    pub resets: Vec<String>,
    pub instant: bool,
}

fn constraints_text(game: &Game, list: &[ClockInterval]) -> String {
    let parts: Vec<String> = list
        .iter()
        .map(|ci| {
            let name = &game.clocks[ci.clock.index()].name;
            let short = name.rsplit('.').next().unwrap_or(name);
            format!("{short} in {}", ci.interval)
        })
        .collect();
    parts.join(" and ")
}

/// The plant units and plans as automata, for drawing.
pub fn automata(game: &Game) -> Vec<AutomatonView> {
    let clock_name = |c: u32| {
        let name = &game.clocks[c as usize].name;
        name.rsplit('.').next().unwrap_or(name).to_string()
    };
    let mut out: Vec<AutomatonView> = game
        .components
        .iter()
        .map(|a| AutomatonView {
            name: a.name.clone(),
            kind: match a.origin {
                super::model::ComponentOrigin::Automaton => "automaton",
                super::model::ComponentOrigin::Hardware => "hardware",
                super::model::ComponentOrigin::Operator => "operator",
            },
            initial: a.initial.raw(),
            locations: a
                .locations
                .iter()
                .map(|l| LocationView {
                    name: l.name.clone(),
                    invariant: constraints_text(game, &l.invariant),
                    failed: false,
                })
                .collect(),
            edges: a
                .edges
                .iter()
                .map(|e| EdgeView {
                    from: e.from.raw(),
                    to: e.to.raw(),
                    sigil: e.kind.sigil(),
                    message: game.messages[e.message.index()].name.clone(),
                    guard: constraints_text(game, &e.guard),
                    resets: e.resets.iter().map(|&c| clock_name(c.raw())).collect(),
                    instant: e.instant,
                })
                .collect(),
        })
        .collect();
    for p in &game.plans {
        let deadline: Vec<String> =
            p.clocks.iter().map(|&(c, b)| format!("{} in [0,{b}]", clock_name(c.raw()))).collect();
        out.push(AutomatonView {
            name: p.name.clone(),
            kind: "plan",
            initial: p.initial.raw(),
            locations: p
                .locations
                .iter()
                .enumerate()
                .map(|(i, l)| LocationView {
                    name: l.name.clone(),
                    invariant: if LocId::new(i) == p.failed { String::new() } else { deadline.join(" and ") },
                    failed: LocId::new(i) == p.failed,
                })
                .collect(),
            edges: p
                .edges
                .iter()
                .map(|e| EdgeView {
                    from: e.from.raw(),
                    to: e.to.raw(),
                    sigil: '$',
                    message: game.messages[e.message.index()].name.clone(),
                    guard: String::new(),
                    resets: e.resets.iter().map(|&c| clock_name(c.raw())).collect(),
                    instant: false,
                })
                .collect(),
        });
    }
    out
}

#[derive(Serialize)]
pub struct SpaceView {
    /// `realizable`, `unrealizable`, `budget_exceeded` or `cancelled` (`search::Outcome::outcome_name`).
    pub verdict: &'static str,
    pub initial: StateId,
    /// Clock names, index 0 being the reference clock.
    pub clocks: Vec<String>,
    /// Unit names in the order of `StateView::locations` (plant units, then plans).
    pub units: Vec<String>,
    pub states: Vec<StateView>,
    pub edges: Vec<TransitionView>,
    /// True if the space had more states than were exported.
    pub truncated: bool,
    pub total_states: usize,
}

#[derive(Serialize)]
pub struct StateView {
    pub id: StateId,
    /// Location name per unit.
    pub locations: Vec<String>,
    /// The zone as text (`true` when unconstrained).
    pub zone: String,
    /// The zone as constraints `x_i - x_j ≺ c`.
    pub constraints: Vec<crate::zone::Constraint>,
    pub kind: StateKind,
    pub winning: bool,
    /// Why the state was removed, in words.
    pub reason: Option<String>,
    pub removal: Option<Removal>,
}

#[derive(Serialize)]
pub struct TransitionView {
    pub from: StateId,
    /// Absent for timeouts and zeno repetitions.
    pub to: Option<StateId>,
    pub kind: super::solve::EdgeKind,
    pub label: String,
    pub zeno: bool,
    /// An option or delay the strategy-directed search never needed to try (`to` is absent).
    pub unexplored: bool,
    pub progress: bool,
}

/// One state: its location names, zone, kind and, if removed, why.
pub fn state_view(game: &Game, synthesis: &Synthesis, s: StateId) -> StateView {
    let (split, space) = (&synthesis.split, &synthesis.solution.space);
    let mut locations = Vec::new();
    for (u, &sub) in space.env(s).iter().enumerate() {
        let loc = split.units[u].sublocs[sub.index()].location;
        locations.push(game.components[u].locations[loc.index()].name.clone());
    }
    for (p, &sub) in space.plan(s).iter().enumerate() {
        let loc = split.units[split.plant_count + p].sublocs[sub.index()].location;
        locations.push(game.plans[p].locations[loc.index()].name.clone());
    }
    let names: Vec<&str> = game.clocks.iter().map(|c| c.name.as_str()).collect();
    let zone = space.zone(s);
    let st = &space.states[s.index()];
    StateView {
        id: s,
        locations,
        zone: zone.display_with(&names).to_string(),
        constraints: zone.constraints(),
        kind: st.kind,
        winning: st.removal.is_none(),
        reason: st.removal.map(|r| removal_text(game, split, space, s, r)),
        removal: st.removal,
    }
}

/// The explored state space, at most `limit` states in breadth-first order from the initial
/// state (winning and removed alike), with the edges among them.
pub fn space(game: &Game, synthesis: &Synthesis, limit: usize) -> SpaceView {
    let space = &synthesis.solution.space;
    let n = space.states.len();
    let mut queued = vec![false; n];
    let mut order = Vec::new();
    if n > 0 {
        let mut queue = VecDeque::from([space.initial]);
        queued[space.initial.index()] = true;
        while let Some(s) = queue.pop_front() {
            order.push(s);
            if order.len() >= limit {
                break;
            }
            for (_, e) in space.out_edges(s) {
                if e.to != StateId::NONE && !queued[e.to.index()] {
                    queued[e.to.index()] = true;
                    queue.push_back(e.to);
                }
            }
        }
    }
    let truncated = order.len() < n;
    view_of(game, synthesis, &order, truncated)
}

/// The view of the states `order` (in that order) and of the edges among them; timeouts and
/// zeno repetitions, which lead nowhere, are kept.
fn view_of(game: &Game, synthesis: &Synthesis, order: &[StateId], truncated: bool) -> SpaceView {
    let space = &synthesis.solution.space;
    let exported: std::collections::HashSet<StateId> = order.iter().copied().collect();
    let states = order.iter().map(|&s| state_view(game, synthesis, s)).collect();
    let mut edges = Vec::new();
    for &s in order {
        for (_, e) in space.out_edges(s) {
            if e.to != StateId::NONE && !exported.contains(&e.to) {
                continue;
            }
            edges.push(TransitionView {
                from: s,
                to: e.target(),
                kind: e.kind,
                label: describe_edge(game, &synthesis.split, e),
                zeno: e.zeno,
                progress: e.progress,
                unexplored: e.is_unexplored(),
            });
        }
    }
    SpaceView {
        verdict: synthesis.outcome_name(),
        initial: space.initial,
        clocks: game.clocks.iter().map(|c| c.name.clone()).collect(),
        units: synthesis.split.units.iter().map(|u| u.name.clone()).collect(),
        states,
        edges,
        truncated,
        total_states: space.states.len(),
    }
}

/// The predecessors of every explored state, for [`neighbourhood`].
pub fn incoming(synthesis: &Synthesis) -> Vec<Vec<StateId>> {
    let space = &synthesis.solution.space;
    let mut incoming = vec![Vec::new(); space.states.len()];
    for e in &space.edges {
        if let Some(to) = e.target() {
            incoming[to.index()].push(e.from);
        }
    }
    incoming
}

/// The states within `k` steps of `state` (following edges both ways, breadth-first), at most
/// `limit` of them, with the edges among them; `truncated` tells if `limit` cut it. `None` for a
/// state that does not exist. `incoming` is [`incoming`] of the same synthesis.
pub fn neighbourhood(
    game: &Game,
    synthesis: &Synthesis,
    incoming: &[Vec<StateId>],
    state: StateId,
    k: u32,
    limit: usize,
) -> Option<SpaceView> {
    let space = &synthesis.solution.space;
    if state.index() >= space.states.len() {
        return None;
    }
    let mut dist: std::collections::HashMap<StateId, u32> = std::collections::HashMap::from([(state, 0)]);
    let mut order = vec![state];
    let mut queue = VecDeque::from([state]);
    let mut cut = false;
    'bfs: while let Some(x) = queue.pop_front() {
        let d = dist[&x];
        if d >= k {
            continue;
        }
        let succ = space.out_edges(x).filter_map(|(_, e)| e.target());
        let pred = incoming[x.index()].iter().copied();
        for y in succ.chain(pred).collect::<Vec<_>>() {
            if dist.contains_key(&y) {
                continue;
            }
            if order.len() >= limit.max(1) {
                cut = true;
                break 'bfs;
            }
            dist.insert(y, d + 1);
            order.push(y);
            queue.push_back(y);
        }
    }
    Some(view_of(game, synthesis, &order, cut))
}

/// One row of the state explorer.
#[derive(Serialize)]
pub struct StateRow {
    pub id: StateId,
    pub text: String,
    pub winning: bool,
    pub initial: bool,
}

/// The states that match a search, the first `limit` of them as rows.
#[derive(Serialize)]
pub struct StateSearch {
    pub total: usize,
    pub rows: Vec<StateRow>,
}

/// The states whose description (`s12 lamp.on x<3 …`) contains every word of `query`
/// (case-insensitive); `filter` is `all`, `winning` or `removed`. Rows in state order.
pub fn search_states(game: &Game, synthesis: &Synthesis, query: &str, filter: &str, limit: usize) -> StateSearch {
    let space = &synthesis.solution.space;
    let split = &synthesis.split;
    let words: Vec<String> = query.split_whitespace().map(str::to_lowercase).collect();
    let mut total = 0;
    let mut rows = Vec::new();
    for id in space.state_ids() {
        let winning = space.is_winning(id);
        if (filter == "winning" && !winning) || (filter == "removed" && winning) {
            continue;
        }
        // Describing a state costs; without a query only the listed rows need it.
        let text = if words.is_empty() {
            None
        } else {
            let text = describe_state(game, split, space, id);
            let lower = format!("s{id} {}", text.to_lowercase());
            if !words.iter().all(|w| lower.contains(w.as_str())) {
                continue;
            }
            Some(text)
        };
        total += 1;
        if rows.len() < limit {
            let text = text.unwrap_or_else(|| describe_state(game, split, space, id));
            rows.push(StateRow { id, text, winning, initial: id == space.initial });
        }
    }
    StateSearch { total, rows }
}

/// What the winning strategy does in one of its states.
#[derive(Clone, Serialize)]
pub struct StrategyChoice {
    pub state: StateId,
    /// `request` or `wait`.
    pub choice: &'static str,
    /// For a request: its target state and its label (as in [`TransitionView::label`]).
    pub to: Option<StateId>,
    pub label: Option<String>,
}

/// The strategy the controller program follows (request selection, Peter 2005, 6.3): for each
/// state it reaches, the request it makes or `wait`, initial state first; `None` when the game
/// is not realizable.
pub fn strategy(game: &Game, synthesis: &Synthesis) -> Option<Vec<StrategyChoice>> {
    if !synthesis.solution.is_realizable() {
        return None;
    }
    let space = &synthesis.solution.space;
    let strategy = crate::timed::program::select::select(game, space);
    Some(
        strategy
            .states
            .iter()
            .map(|&st| match strategy.choice[st.index()] {
                crate::timed::program::select::Choice::Request(e) => {
                    let edge = &space.edges[e.index()];
                    StrategyChoice {
                        state: st,
                        choice: "request",
                        to: Some(edge.to),
                        label: Some(describe_edge(game, &synthesis.split, edge)),
                    }
                }
                crate::timed::program::select::Choice::Wait => {
                    StrategyChoice { state: st, choice: "wait", to: None, label: None }
                }
            })
            .collect(),
    )
}

/// The state space's drawing: top to bottom in a monospace font.
const SPACE_LAYOUT: crate::dot::Layout = crate::dot::Layout {
    graph: "rankdir = TB, bgcolor = \"transparent\", nodesep = 0.25, ranksep = 0.35, fontname = \"sans-serif\"",
    node: "shape = box, style = \"rounded,filled\", fontname = \"Courier\", fontsize = 10, margin = \"0.08,0.03\"",
    edge: "fontname = \"Courier\", fontsize = 8, arrowsize = 0.6",
};

/// Location names joined in lines of about `width` characters, at most three lines.
fn wrap(names: &[String], width: usize) -> String {
    let mut lines: Vec<String> = vec![String::new()];
    for n in names {
        let last = lines.last_mut().expect("one line at least");
        if !last.is_empty() && last.chars().count() + n.chars().count() + 2 > width {
            lines.push(n.clone());
        } else if last.is_empty() {
            last.push_str(n);
        } else {
            last.push_str(", ");
            last.push_str(n);
        }
    }
    if lines.len() > 3 {
        return format!("{}…", lines[..3].join("\n"));
    }
    lines.join("\n")
}

/// A view of the state space as a drawing (DOT): winning and removed states classed for their
/// colours (`state winning|removed`, `initial`, `selected`; the SVG group of state `n` has the id
/// `st-n`), edges classed by kind (`edge-request`, `edge-reaction`, `edge-guard`, `edge-delay`,
/// `edge-timeout`), the requests the strategy chooses classed `chosen`, zeno repetitions `zeno`,
/// options and delays the search never tried `unexplored` (their states, if created, are
/// `state unexplored`), and edges to no state (timeouts, cut repetitions, untried moves) ending
/// in a point.
pub fn space_dot(view: &SpaceView, selected: Option<StateId>, strategy: Option<&[StrategyChoice]>) -> String {
    use super::solve::EdgeKind;
    use crate::dot::{document_with, Drawing, Edge, Node};
    let plan: std::collections::HashMap<StateId, &StrategyChoice> =
        strategy.unwrap_or_default().iter().map(|c| (c.state, c)).collect();
    let mut g = Drawing::new();
    let mut nodes = std::collections::HashMap::new();
    for s in &view.states {
        let status = match s.removal {
            None => "winning",
            Some(Removal::Unexplored) => "unexplored",
            Some(_) => "removed",
        };
        let mut class = vec!["state", status];
        if s.id == view.initial {
            class.push("initial");
        }
        if Some(s.id) == selected {
            class.push("selected");
        }
        let kind = s.kind.name();
        let tooltip = if s.winning {
            let doing = match plan.get(&s.id) {
                Some(c) if c.choice == "wait" => "; strategy: wait".to_string(),
                Some(c) => format!("; strategy: {}", c.label.as_deref().unwrap_or("")),
                None => String::new(),
            };
            format!("s{}: winning{doing}", s.id)
        } else {
            format!("s{}: removed: {}", s.id, s.reason.as_deref().unwrap_or(""))
        };
        let node = g.add_node(Node {
            label: format!("s{} {kind}\n{}", s.id, wrap(&s.locations, 30)),
            class: class.join(" "),
            tooltip,
            id: Some(format!("st-{}", s.id)),
            ..Node::default()
        });
        nodes.insert(s.id, node);
    }
    for e in &view.edges {
        let Some(&from) = nodes.get(&e.from) else { continue };
        let to = match e.to.and_then(|t| nodes.get(&t).copied()) {
            Some(to) => to,
            None => g.add_node(Node {
                class: "dangling".into(),
                shape: Some("point"),
                tooltip: " ".into(),
                ..Node::default()
            }),
        };
        let chosen = plan
            .get(&e.from)
            .is_some_and(|c| c.choice == "request" && c.to == e.to && c.label.as_deref() == Some(e.label.as_str()));
        let (kind_class, sigil, style) = match e.kind {
            EdgeKind::Request => ("edge-request", '?', ""),
            EdgeKind::Reaction => ("edge-reaction", '!', "dashed"),
            EdgeKind::Guard => ("edge-guard", '%', ""),
            EdgeKind::Delay => ("edge-delay", 'D', "dotted"),
            EdgeKind::Timeout => ("edge-timeout", 'T', "dotted"),
        };
        let mut class = kind_class.to_string();
        if chosen {
            class.push_str(" chosen");
        }
        if e.zeno {
            class.push_str(" zeno");
        }
        if e.unexplored {
            class.push_str(" unexplored");
        }
        let label = if e.kind == EdgeKind::Delay {
            "D".to_string()
        } else if e.label.chars().count() > 28 {
            format!("{}…", e.label.chars().take(27).collect::<String>())
        } else {
            e.label.clone()
        };
        g.add_edge(from, to, Edge { label, class, style, tooltip: format!("{sigil} {}", e.label) });
    }
    document_with(&g, &SPACE_LAYOUT)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::timed::{compile, solve::Config, synthesize};

    fn lamp() -> (Game, Synthesis) {
        let (game, _) = compile(include_str!("../../examples/timed/lamp.tga")).unwrap();
        let synthesis = synthesize(&game, &Config::default(), &mut |_| true);
        (game, synthesis)
    }

    #[test]
    fn searches_neighbourhoods_and_drawings_of_the_lamp_space() {
        let (game, s) = lamp();
        let all = search_states(&game, &s, "", "all", 3);
        assert_eq!(all.total, s.solution.space.states.len());
        assert_eq!(all.rows.len(), 3);
        assert!(all.rows[0].initial);
        let on = search_states(&game, &s, "LAMP.ON pressing", "all", 100);
        assert!(on.total > 0 && on.rows.iter().all(|r| r.text.contains("lamp.on") && r.text.contains("pressing")));
        let removed = search_states(&game, &s, "", "removed", 100);
        assert!(removed.rows.iter().all(|r| !r.winning));

        let incoming = incoming(&s);
        let hood = neighbourhood(&game, &s, &incoming, StateId::new(0), 1, 100).unwrap();
        let succ: Vec<StateId> = s.solution.space.out_edges(StateId::new(0)).filter_map(|(_, e)| e.target()).collect();
        assert!(succ.iter().all(|t| hood.states.iter().any(|v| v.id == *t)), "one step reaches every successor");
        assert!(!neighbourhood(&game, &s, &incoming, StateId::new(0), 3, 2).unwrap().states.is_empty());
        assert!(neighbourhood(&game, &s, &incoming, StateId::new(0), 3, 2).unwrap().truncated);
        assert!(neighbourhood(&game, &s, &incoming, StateId::new(10_000), 1, 10).is_none());

        let choices = strategy(&game, &s).unwrap();
        let view = space(&game, &s, 1000);
        let dot = space_dot(&view, Some(StateId::new(0)), Some(&choices));
        assert!(dot.contains(r#"id = "st-0""#), "{dot}");
        assert!(
            dot.contains("state winning initial selected") || dot.contains("state removed initial selected"),
            "{dot}"
        );
        let chosen = choices.iter().filter(|c| c.choice == "request").count();
        assert_eq!(dot.matches(" chosen\"").count(), chosen, "every chosen request is marked once: {dot}");
        assert!(dot.contains("edge-delay"), "{dot}");
    }
}
