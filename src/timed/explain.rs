//! Why a state was lost: a shortest counter-strategy of the plant, as a tree.
//!
//! Every removed state gets a *rank*, the number of moves within which the plant can force a
//! failure against every controller choice (the attractor rank of 2.1.3): violations are rank
//! 0; a forced move adds one to the best (smallest) rank among its removed targets; a state
//! lost for want of a controller move adds one to the worst (largest) rank among the
//! controller's choices. The explanation follows, from the initial state, the plant's
//! best moves and every controller choice.

use super::model::{ClockId, Game};
use super::precompute::SplitGame;
use super::solve::{Edge, EdgeId, EdgeKind, Label, Removal, StateId, StateKind, StateSpace};
use serde::Serialize;
use std::collections::VecDeque;

/// The rank of a state the attractor has not reached.
const UNRANKED: u32 = u32::MAX;

/// One step of the explanation.
#[derive(Clone, Debug, Serialize)]
pub struct Step {
    pub state: StateId,
    /// The move that led here (absent at the root).
    pub event: Option<String>,
    /// The state, as `unit.location` names and the zone.
    pub locations: String,
    pub outcome: Outcome,
}

#[derive(Clone, Debug, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Outcome {
    /// The state itself is a failure.
    Violation { reason: String },
    /// The plant (or passing time) moves on; or, for a state lost by dominance, the lost state
    /// that dominates it (the event says so).
    Forced { next: Box<Step> },
    /// Every controller choice fails; one branch per choice.
    Choices { branches: Vec<Step> },
    /// Cut off to keep the explanation readable.
    Truncated,
}

#[derive(Clone, Debug, Serialize)]
pub struct Explanation {
    pub root: Step,
    /// Moves the plant needs at most to force a failure (in a scan game, a step from a state
    /// lost by dominance to the lost state dominating it counts as one).
    pub depth: u32,
}

/// Builds the explanation for the removed state `from` (normally the initial state).
pub fn explain(game: &Game, split: &SplitGame, space: &StateSpace, from: StateId) -> Option<Explanation> {
    space.states[from.index()].removal?;
    let ranks = ranks(space);
    let mut budget = 400usize;
    let root = step(game, split, space, &ranks, from, None, 0, &mut budget);
    Some(Explanation { root, depth: ranks.rank[from.index()] })
}

struct Ranks {
    rank: Vec<u32>,
    /// The plant's best forced edge, or its best reaction to waiting.
    witness: Vec<EdgeId>,
}

fn is_option(e: &Edge) -> bool {
    matches!(e.kind, EdgeKind::Request | EdgeKind::Guard)
}

fn is_wait(e: &Edge) -> bool {
    e.kind == EdgeKind::Delay
}

/// Retrograde analysis over the removed states.
fn ranks(space: &StateSpace) -> Ranks {
    let n = space.states.len();
    let mut rank = vec![UNRANKED; n];
    let mut witness = vec![EdgeId::NONE; n];
    let mut pending = vec![0u32; n];
    let mut wait_done = vec![false; n];
    let mut preds: Vec<Vec<EdgeId>> = vec![Vec::new(); n];
    // States lost by dominance, per the lost state dominating them: one more than its rank.
    let mut dominated: Vec<Vec<StateId>> = vec![Vec::new(); n];
    let mut queue = VecDeque::new();
    // States of rank 1 from the start go behind those of rank 0: the queue must hold ranks in
    // order, so that a state lost by its last controller choice gets one more than the largest.
    let mut ones = Vec::new();
    for (s, st) in space.states.iter().enumerate() {
        let Some(removal) = st.removal else { continue };
        let mut options = 0;
        let mut cut = 0;
        let mut waits = false;
        let mut wait_cut = false;
        let mut forced = false;
        for (id, e) in space.out_edges(StateId::new(s)) {
            let controller_cut = e.zeno && (is_option(e) || is_wait(e));
            if e.to != StateId::NONE && !controller_cut {
                preds[e.to.index()].push(id);
            }
            // A request or wait cut as a zeno move (a return without progress, or a move on a
            // cycle without progress) leads nowhere: the controller loses with it at once, so it
            // is not waited for (it would otherwise leave the state unranked).
            if is_option(e) && e.zeno {
                cut += 1;
            } else {
                options += u32::from(is_option(e));
            }
            waits |= is_wait(e);
            wait_cut |= is_wait(e) && e.zeno;
            forced |= e.kind == EdgeKind::Reaction;
        }
        cut += u32::from(wait_cut);
        // Waiting fails once a delay target is lost; without delays it stays possible while the
        // plant has a move, so only a lost forced target can then decide the state.
        pending[s] = options + u32::from((waits || forced) && !wait_cut);
        if removal == Removal::NoMove && pending[s] == 0 && cut > 0 {
            // Every move the controller has is a zeno repetition: lost in one move.
            rank[s] = 1;
            ones.push(StateId::new(s));
            continue;
        }
        match removal {
            Removal::Assertion { .. } | Removal::PlanFailed { .. } | Removal::Deadlock => {
                rank[s] = 0;
                queue.push_back(StateId::new(s));
            }
            Removal::ZenoLoop { edge } => {
                rank[s] = 1;
                witness[s] = edge;
                ones.push(StateId::new(s));
            }
            Removal::Dominated { by } => dominated[by.index()].push(StateId::new(s)),
            Removal::Forced { .. } | Removal::NoMove | Removal::Unexplored => {}
        }
    }
    queue.extend(ones);
    while let Some(y) = queue.pop_front() {
        let r = rank[y.index()];
        for &x in &dominated[y.index()] {
            if rank[x.index()] == UNRANKED {
                rank[x.index()] = r + 1;
                queue.push_back(x);
            }
        }
        for &id in &preds[y.index()] {
            let e = &space.edges[id.index()];
            let x = e.from.index();
            if space.states[x].removal.is_none() || rank[x] != UNRANKED {
                continue;
            }
            let done = match e.kind {
                EdgeKind::Reaction => {
                    witness[x] = id;
                    true
                }
                EdgeKind::Request | EdgeKind::Guard => {
                    pending[x] -= 1;
                    pending[x] == 0
                }
                EdgeKind::Delay => {
                    // Time passing is the plant's choice once the controller waits. A state with
                    // no option is forced by time (the first removed delay target suffices).
                    if !wait_done[x] {
                        wait_done[x] = true;
                        witness[x] = id;
                        pending[x] -= 1;
                    }
                    pending[x] == 0
                }
                EdgeKind::Timeout => false,
            };
            if done {
                rank[x] = r + 1;
                queue.push_back(StateId::new(x));
            }
        }
    }
    Ranks { rank, witness }
}

/// Who makes a move of a counter-play.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Mover {
    /// A reaction, or time passing where the controller has no say.
    Plant,
    /// A request or a guard check: the controller's choice.
    Controller,
    /// The controller waits and the plant lets time pass.
    Wait,
}

/// One move of a counter-play: an edge of the explored space.
#[derive(Clone, Debug, Serialize)]
pub struct PlayMove {
    pub edge: EdgeId,
    pub from: StateId,
    /// The state reached ([`StateId::NONE`] for a zeno repetition, which leads nowhere).
    pub to: StateId,
    pub mover: Mover,
    /// The move in words, as in the explanation.
    pub label: String,
    /// For the controller's moves: how many choices it had (waiting included); 1 otherwise.
    pub choices: u32,
    /// Moves within which the plant can still force the failure after this one.
    pub left: u32,
}

/// One line of play from the initial state into a failure: the plant's winning line against
/// the controller that holds out longest.
#[derive(Clone, Debug, Serialize)]
pub struct CounterPlay {
    pub moves: Vec<PlayMove>,
    /// The failure it ends in, in words.
    pub end: String,
    /// The state of the failure (for a zeno loop: the state the loop starts from).
    pub end_state: StateId,
}

/// The counter-play of a lost initial state: along the attractor ranks, the plant takes its
/// best move (the one that fails soonest) and the controller the choice that fails last (the
/// largest rank; the first such one in edge order), so the line is the longest the best
/// controller can make it, and ends in a violation after `depth` moves. `None` when the initial
/// state is not lost, or lost in a way the ranks do not decide (cut cycles).
pub fn counter_play(game: &Game, split: &SplitGame, space: &StateSpace) -> Option<CounterPlay> {
    let from = space.initial;
    space.states.get(from.index())?.removal?;
    let ranks = ranks(space);
    let rank = |s: StateId| if s == StateId::NONE { 0 } else { ranks.rank[s.index()] };
    if rank(from) == UNRANKED {
        return None;
    }
    let mut moves = Vec::new();
    let mut s = from;
    // Ranks fall by one with every move, so the line has `rank(from)` moves; the bound only
    // guards against a rank table that would not.
    for _ in 0..=ranks.rank[from.index()] {
        if let Some(end) = violation(game, split, space, s) {
            return Some(CounterPlay { moves, end, end_state: s });
        }
        let mut play = |edge: EdgeId, mover: Mover, choices: u32| {
            let e = &space.edges[edge.index()];
            moves.push(PlayMove {
                edge,
                from: e.from,
                to: e.to,
                mover,
                label: describe_edge(game, split, e),
                choices,
                left: if e.zeno { 0 } else { rank(e.to) },
            });
            e.to
        };
        if let Some(Removal::ZenoLoop { edge }) = space.states[s.index()].removal {
            play(edge, Mover::Plant, 1);
            let end = format!(
                "zeno loop: the plant can send {} and come back without plan progress, forever",
                describe_edge(game, split, &space.edges[edge.index()])
            );
            return Some(CounterPlay { moves, end, end_state: s });
        }
        let w = ranks.witness[s.index()];
        let forced = w != EdgeId::NONE && space.edges[w.index()].kind == EdgeKind::Reaction;
        // The controller's alternatives: its live options and, if the plant can make waiting
        // fail, waiting. A zeno-cut option leads nowhere and loses at once.
        let options: Vec<(EdgeId, u32)> = space
            .out_edges(s)
            .filter(|(_, e)| is_option(e) && e.to != StateId::NONE && !e.zeno)
            .map(|(id, e)| (id, rank(e.to)))
            .collect();
        let wait =
            (w != EdgeId::NONE && is_wait(&space.edges[w.index()])).then(|| (w, rank(space.edges[w.index()].to)));
        let next = if forced {
            play(w, Mover::Plant, 1)
        } else if options.is_empty() && wait.is_none() {
            // Every move of the controller is a zeno move (the ranks count it lost at once): the
            // line ends with the controller taking one.
            let cut: Vec<EdgeId> =
                space.out_edges(s).filter(|(_, e)| (is_option(e) || is_wait(e)) && e.zeno).map(|(id, _)| id).collect();
            let &edge = cut.first()?;
            let mover = if is_wait(&space.edges[edge.index()]) { Mover::Wait } else { Mover::Controller };
            play(edge, mover, cut.len() as u32);
            let end = format!(
                "zeno loop: every move of the controller ({}) returns to a plant state visited since the last plan progress or goes round without progress",
                cut.iter()
                    .map(|&e| describe_edge(game, split, &space.edges[e.index()]))
                    .collect::<Vec<_>>()
                    .join(", ")
            );
            return Some(CounterPlay { moves, end, end_state: s });
        } else if options.is_empty() {
            let (w, _) = wait?;
            play(w, Mover::Plant, 1) // only time can pass: the plant's move
        } else {
            let choices = options.len() as u32 + u32::from(wait.is_some());
            let best = options.iter().chain(wait.iter()).copied().max_by_key(|&(id, r)| (r, std::cmp::Reverse(id)))?;
            let mover = if Some(best) == wait { Mover::Wait } else { Mover::Controller };
            play(best.0, mover, choices)
        };
        if next == StateId::NONE || space.states[next.index()].removal.is_none() {
            return None; // the ranks promised a lost state
        }
        s = next;
    }
    None
}

/// `unit.location` names of a state, the plan locations and the zone.
pub fn describe_state(game: &Game, split: &SplitGame, space: &StateSpace, s: StateId) -> String {
    let mut parts: Vec<String> = Vec::new();
    for (u, &sub) in space.env(s).iter().enumerate() {
        let unit = &split.units[u];
        let loc = unit.sublocs[sub.index()].location;
        parts.push(format!("{}.{}", unit.name, game.components[u].locations[loc.index()].name));
    }
    let plant = parts.join(", ");
    let plans: Vec<String> = space
        .plan(s)
        .iter()
        .enumerate()
        .map(|(p, &sub)| {
            let unit = &split.units[split.plant_count + p];
            let loc = unit.sublocs[sub.index()].location;
            format!("{}.{}", unit.name, game.plans[p].locations[loc.index()].name)
        })
        .collect();
    let names: Vec<&str> = game.clocks.iter().map(|c| c.name.as_str()).collect();
    let zone = space.zone(s);
    let zone_text = zone.display_with(&names).to_string();
    let mut text = plant;
    if !plans.is_empty() {
        text.push_str(" | ");
        text.push_str(&plans.join(", "));
    }
    if !zone_text.is_empty() && zone_text != "true" {
        text.push_str(" | ");
        text.push_str(&zone_text);
    }
    match space.states[s.index()].kind {
        StateKind::Waiting => text.push_str(" (waiting)"),
        StateKind::Guard => text.push_str(" (checking a guard)"),
        _ => {}
    }
    text
}

/// A move in words: `!press`, `?turn_on`, `%part_present`, `time passes until c ∈ (2,4]`.
pub fn describe_edge(game: &Game, split: &SplitGame, e: &Edge) -> String {
    match e.label {
        Label::Message { message } => format!("{}{}", e.kind.sigil(), game.messages[message.index()].name),
        Label::Wait => "wait".to_string(),
        Label::Piece { clock, piece, clocks } => {
            let mut text = format!(
                "time passes until {} ∈ {}",
                game.clocks[clock.index()].name,
                split.pieces[clock.index()][piece as usize]
            );
            let others: Vec<&str> = (1..64)
                .map(ClockId::new)
                .filter(|&c| c != clock && clocks >> c.index() & 1 == 1)
                .map(|c| game.clocks[c.index()].name.as_str())
                .collect();
            if !others.is_empty() {
                text.push_str(&format!(" (and, at the same instant, {} into their next pieces)", others.join(", ")));
            }
            text
        }
        Label::Overrun { clock } => format!("timeout: {} exceeds its invariant", game.clocks[clock.index()].name),
    }
}

fn violation(game: &Game, split: &SplitGame, space: &StateSpace, s: StateId) -> Option<String> {
    Some(match space.states[s.index()].removal? {
        Removal::Assertion { rule } => format!("assertion violated: {}", game.assertions[rule as usize].text),
        Removal::PlanFailed { plan } => {
            let p = &game.plans[plan as usize];
            let sub = space.plan(s)[plan as usize];
            let unit = &split.units[split.plant_count + plan as usize];
            if unit.sublocs[sub.index()].location == p.failed {
                format!("{} fails: a message it forbids occurred", p.name)
            } else {
                format!("{} fails: a timeout clock exceeded its bound", p.name)
            }
        }
        Removal::Deadlock => "deadlock: nothing can happen any more".to_string(),
        _ => return None,
    })
}

#[allow(clippy::too_many_arguments)]
fn step(
    game: &Game,
    split: &SplitGame,
    space: &StateSpace,
    ranks: &Ranks,
    s: StateId,
    event: Option<String>,
    depth: u32,
    budget: &mut usize,
) -> Step {
    let locations = describe_state(game, split, space, s);
    if *budget == 0 || depth > 60 {
        return Step { state: s, event, locations, outcome: Outcome::Truncated };
    }
    *budget -= 1;
    if let Some(reason) = violation(game, split, space, s) {
        return Step { state: s, event, locations, outcome: Outcome::Violation { reason } };
    }
    let removal = space.states[s.index()].removal;
    let outcome = match removal {
        Some(Removal::ZenoLoop { edge }) => {
            let e = &space.edges[edge.index()];
            Outcome::Violation {
                reason: format!("the plant can send {} and return to a plant state it visited since the last plan progress, or keep the plays from progress forever (zeno loop)", describe_edge(game, split, e)),
            }
        }
        Some(Removal::Forced { .. }) | Some(Removal::NoMove) if is_forced_state(space, ranks, s) => {
            let e = &space.edges[ranks.witness[s.index()].index()];
            let next = step(game, split, space, ranks, e.to, Some(describe_edge(game, split, e)), depth + 1, budget);
            Outcome::Forced { next: Box::new(next) }
        }
        Some(Removal::Dominated { by }) => {
            let next = step(game, split, space, ranks, by, Some(dominated_text(by)), depth + 1, budget);
            Outcome::Forced { next: Box::new(next) }
        }
        Some(Removal::NoMove) => {
            let mut branches = Vec::new();
            for (_, e) in space.out_edges(s) {
                if is_option(e) && e.to != StateId::NONE {
                    let label = describe_edge(game, split, e);
                    if e.zeno {
                        branches.push(Step {
                            state: s,
                            event: Some(label),
                            locations: String::new(),
                            outcome: Outcome::Violation { reason: "zeno loop".into() },
                        });
                    } else {
                        branches.push(step(game, split, space, ranks, e.to, Some(label), depth + 1, budget));
                    }
                } else if is_option(e) && e.zeno {
                    branches.push(Step {
                        state: s,
                        event: Some(describe_edge(game, split, e)),
                        locations: String::new(),
                        outcome: Outcome::Violation {
                            reason: "returns to a plant state visited since the last plan progress, or goes round without progress (zeno loop)".into(),
                        },
                    });
                }
            }
            let w = ranks.witness[s.index()];
            if w != EdgeId::NONE {
                let e = &space.edges[w.index()];
                branches.push(step(
                    game,
                    split,
                    space,
                    ranks,
                    e.to,
                    Some(format!("wait; then {}", describe_edge(game, split, e))),
                    depth + 1,
                    budget,
                ));
            } else if !space.out_edges(s).any(|(_, e)| is_wait(e)) {
                branches.push(Step {
                    state: s,
                    event: Some("wait".into()),
                    locations: String::new(),
                    outcome: Outcome::Violation { reason: "nothing would ever happen".into() },
                });
            }
            Outcome::Choices { branches }
        }
        _ => Outcome::Truncated,
    };
    Step { state: s, event, locations, outcome }
}

/// True if the plant can force the loss without a controller choice: by a reaction, or by
/// passing time where the controller has no move.
fn is_forced_state(space: &StateSpace, ranks: &Ranks, s: StateId) -> bool {
    let w = ranks.witness[s.index()];
    if w == EdgeId::NONE {
        return false;
    }
    match space.edges[w.index()].kind {
        EdgeKind::Reaction => true,
        EdgeKind::Delay => !space.out_edges(s).any(|(_, e)| is_option(e)),
        _ => false,
    }
}

impl Explanation {
    /// Indented text, one move per line.
    pub fn render(&self) -> String {
        let mut out = String::new();
        render_step(&self.root, 0, &mut out);
        out
    }
}

fn render_step(step: &Step, indent: usize, out: &mut String) {
    let pad = "  ".repeat(indent);
    if let Some(ev) = &step.event {
        out.push_str(&format!("{pad}{ev}"));
        if !step.locations.is_empty() {
            out.push_str(&format!("  → {}", step.locations));
        }
        out.push('\n');
    } else {
        out.push_str(&format!("{pad}in {}\n", step.locations));
    }
    match &step.outcome {
        Outcome::Violation { reason } => out.push_str(&format!("{pad}  ✗ {reason}\n")),
        Outcome::Forced { next } => render_step(next, indent, out),
        Outcome::Choices { branches } => {
            out.push_str(&format!("{pad}  every controller choice fails:\n"));
            for b in branches {
                render_step(b, indent + 2, out);
            }
        }
        Outcome::Truncated => out.push_str(&format!("{pad}  …\n")),
    }
}

/// The whole explored state space as text: one line per state with its status, then its edges.
pub fn dump(game: &Game, split: &SplitGame, space: &StateSpace) -> String {
    let mut out = String::new();
    for (s, st) in space.states.iter().enumerate() {
        let s = StateId::new(s);
        let status = match st.removal {
            None => "winning".to_string(),
            Some(r) => format!("removed ({})", removal_text(game, split, space, s, r)),
        };
        let initial = if s == space.initial { " initial" } else { "" };
        out.push_str(&format!("s{s}{initial} [{status}] {}\n", describe_state(game, split, space, s)));
        for (_, e) in space.out_edges(s) {
            let target = match (e.to == StateId::NONE, e.zeno) {
                _ if e.is_unexplored() => "not explored".to_string(),
                (true, true) => "zeno".to_string(),
                (true, false) => "timeout".to_string(),
                (false, true) => format!("s{} (cut: a zero-time cycle of requests)", e.to),
                (false, false) => format!("s{}", e.to),
            };
            out.push_str(&format!("    {} -> {target}\n", describe_edge(game, split, e)));
        }
    }
    out
}

/// Why a state lost by dominance is lost, in words.
fn dominated_text(by: StateId) -> String {
    format!("lost as s{by} is: the same locations, and s{by}'s clock values lie in this state's with the plans' clocks at most as high")
}

/// A removal reason in words.
pub fn removal_text(game: &Game, split: &SplitGame, space: &StateSpace, s: StateId, r: Removal) -> String {
    match r {
        Removal::Forced { edge } => {
            format!("forced: {} leads to a removed state", describe_edge(game, split, &space.edges[edge.index()]))
        }
        Removal::ZenoLoop { edge } => format!("zeno loop: {}", describe_edge(game, split, &space.edges[edge.index()])),
        Removal::NoMove => "every controller move fails and waiting is not possible".to_string(),
        Removal::Unexplored => "not explored: the strategy found does not pass through this state".to_string(),
        Removal::Dominated { by } => dominated_text(by),
        _ => violation(game, split, space, s).unwrap_or_default(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::timed::program::simulate::{replay_line, Simulation};
    use crate::timed::{compile, synthesize, Synthesis};

    fn solved(source: &str) -> (Game, Synthesis) {
        let (game, _) = compile(source).unwrap();
        let s = synthesize(&game, &Default::default(), &mut |_| true);
        (game, s)
    }

    /// The line is a path of the explored space from the initial state, ranks falling by one per
    /// move, into a state that violates something.
    fn check_line(game: &Game, s: &Synthesis) -> CounterPlay {
        let space = &s.solution.space;
        let play = counter_play(game, &s.split, space).expect("a counter-play");
        let mut at = space.initial;
        for m in &play.moves {
            let e = &space.edges[m.edge.index()];
            assert_eq!((e.from, e.to), (m.from, m.to), "{m:?} is the edge it names");
            assert_eq!(m.from, at, "{m:?} leaves the state the line is in");
            assert!(space.out_edges(at).any(|(id, _)| id == m.edge));
            at = m.to;
        }
        assert_eq!(at, play.end_state);
        assert!(
            matches!(
                space.states[at.index()].removal,
                Some(Removal::Assertion { .. } | Removal::PlanFailed { .. } | Removal::Deadlock)
            ),
            "ends in {:?}",
            space.states[at.index()].removal
        );
        let depth = s.explanation.as_ref().unwrap().depth as usize;
        assert_eq!(play.moves.len(), depth, "the line is as long as the explanation is deep");
        let left: Vec<u32> = play.moves.iter().map(|m| m.left).collect();
        assert!(left.windows(2).all(|w| w[0] == w[1] + 1) && left.last() == Some(&0), "{left:?}");
        play
    }

    #[test]
    fn the_two_robots_in_13_seconds_lose_on_one_line_that_the_plant_replays() {
        let (game, s) = solved(include_str!("../../examples/timed/two_robots_13.tga"));
        let play = check_line(&game, &s);
        assert!(play.end.contains("fails"), "{}", play.end);
        assert!(play.moves.iter().any(|m| m.mover == Mover::Controller && m.choices > 1), "the controller chooses");
        // Far shorter than the explanation's tree, which repeats subtrees.
        assert!(play.moves.len() < 40 && s.explanation.as_ref().unwrap().render().lines().count() > 100);
        // Played on the concrete plant (both sides, no program), it ends in the plan's failure.
        let line: Vec<EdgeId> = play.moves.iter().map(|m| m.edge).collect();
        let (choices, stopped) = replay_line(&game, &s.split, &s.solution.space, &line);
        assert_eq!(stopped, None);
        let mut sim = Simulation::new(&game, None, &[], 0);
        for c in &choices {
            sim.apply(c).unwrap();
        }
        let view = sim.view();
        assert!(
            matches!(view.failure, Some(crate::timed::program::simulate::Failure::PlanFailed { .. })),
            "{:?}\n{:#?}",
            view.failure,
            view.events
        );
    }

    #[test]
    fn the_naive_lamp_loses_on_a_press() {
        let (game, s) = solved(include_str!("../../examples/timed/lamp_naive.tga"));
        let play = check_line(&game, &s);
        assert!(play.moves.iter().any(|m| m.label == "!press"), "{play:?}");
        assert!(play.end.contains("assertion"), "{}", play.end);
        let line: Vec<EdgeId> = play.moves.iter().map(|m| m.edge).collect();
        let (choices, stopped) = replay_line(&game, &s.split, &s.solution.space, &line);
        assert_eq!(stopped, None);
        let mut sim = Simulation::new(&game, None, &[], 0);
        choices.iter().for_each(|c| sim.apply(c).unwrap());
        assert!(sim.failure().is_some());
    }

    #[test]
    fn a_realizable_spec_has_no_counter_play() {
        let (game, s) = solved(include_str!("../../examples/timed/lamp.tga"));
        assert!(counter_play(&game, &s.split, &s.solution.space).is_none());
    }
}
