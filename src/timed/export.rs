//! JSON views of a game and of a solved state space, for the playground and `--json` output.
//! Shapes are documented in `docs/timed-language.md` (section "JSON output").

use super::explain::{describe_edge, describe_state, removal_text};
use super::model::{ClockInterval, Game};
use super::solve::{Removal, StateId, StateKind, Verdict};
use super::Synthesis;
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
                    shape: None,
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
                Edge { label: parts.join("\n"), class: class.into(), style },
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
            let name = &game.clocks[ci.clock as usize].name;
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
            initial: a.initial,
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
                    from: e.from,
                    to: e.to,
                    sigil: e.kind.sigil(),
                    message: game.messages[e.message as usize].name.clone(),
                    guard: constraints_text(game, &e.guard),
                    resets: e.resets.iter().map(|&c| clock_name(c)).collect(),
                    instant: e.instant,
                })
                .collect(),
        })
        .collect();
    for p in &game.plans {
        let deadline: Vec<String> = p.clocks.iter().map(|&(c, b)| format!("{} in [0,{b}]", clock_name(c))).collect();
        out.push(AutomatonView {
            name: p.name.clone(),
            kind: "plan",
            initial: p.initial,
            locations: p
                .locations
                .iter()
                .enumerate()
                .map(|(i, l)| LocationView {
                    name: l.name.clone(),
                    invariant: if i as u32 == p.failed { String::new() } else { deadline.join(" and ") },
                    failed: i as u32 == p.failed,
                })
                .collect(),
            edges: p
                .edges
                .iter()
                .map(|e| EdgeView {
                    from: e.from,
                    to: e.to,
                    sigil: '$',
                    message: game.messages[e.message as usize].name.clone(),
                    guard: String::new(),
                    resets: e.resets.iter().map(|&c| clock_name(c)).collect(),
                    instant: false,
                })
                .collect(),
        });
    }
    out
}

#[derive(Serialize)]
pub struct SpaceView {
    pub verdict: Verdict,
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
    pub progress: bool,
}

/// One state: its location names, zone, kind and, if removed, why.
pub fn state_view(game: &Game, synthesis: &Synthesis, s: StateId) -> StateView {
    let (split, space) = (&synthesis.split, &synthesis.solution.space);
    let mut locations = Vec::new();
    for (u, &sub) in space.env(s).iter().enumerate() {
        let loc = split.units[u].sublocs[sub as usize].location;
        locations.push(game.components[u].locations[loc as usize].name.clone());
    }
    for (p, &sub) in space.plan(s).iter().enumerate() {
        let loc = split.units[split.plant_count + p].sublocs[sub as usize].location;
        locations.push(game.plans[p].locations[loc as usize].name.clone());
    }
    let names: Vec<&str> = game.clocks.iter().map(|c| c.name.as_str()).collect();
    let zone = space.zone(s);
    let st = &space.states[s as usize];
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
    let mut index = vec![u32::MAX; n];
    let mut order = Vec::new();
    if n > 0 {
        let mut queue = VecDeque::from([space.initial]);
        index[space.initial as usize] = 0;
        while let Some(s) = queue.pop_front() {
            order.push(s);
            if order.len() >= limit {
                break;
            }
            for (_, e) in space.out_edges(s) {
                if e.to != u32::MAX && index[e.to as usize] == u32::MAX {
                    index[e.to as usize] = 0;
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
            if e.to != u32::MAX && !exported.contains(&e.to) {
                continue;
            }
            edges.push(TransitionView {
                from: s,
                to: (e.to != u32::MAX).then_some(e.to),
                kind: e.kind,
                label: describe_edge(game, &synthesis.split, e),
                zeno: e.zeno,
                progress: e.progress,
            });
        }
    }
    SpaceView {
        verdict: synthesis.solution.verdict,
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
        if e.to != u32::MAX {
            incoming[e.to as usize].push(e.from);
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
    if state as usize >= space.states.len() {
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
        let succ = space.out_edges(x).map(|(_, e)| e.to).filter(|&t| t != u32::MAX);
        let pred = incoming[x as usize].iter().copied();
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
    for id in 0..space.states.len() as StateId {
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
