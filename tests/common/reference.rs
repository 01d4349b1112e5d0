//! The strategy-directed timed solver against the exact exhaustive reference (`--exhaustive
//! --no-zeno-memory`), and the properties both must have.

use plcsynth::search::Outcome as _;
use plcsynth::timed::model::Game;
use plcsynth::timed::solve::{Config, EdgeKind, Removal, StateId, StateKind, StateSpace, Stop, Verdict};
use plcsynth::timed::testing::SubLocId;
use plcsynth::timed::{synthesize, synthesize_at_scan, Synthesis};
use plcsynth::zone::{includes_only_lowered, Dbm};
use std::collections::HashSet;

/// A state independent of the run that stored it: sub-locations, plans, zone and kind.
type Key = (Vec<SubLocId>, Vec<SubLocId>, Dbm, StateKind);

fn key(space: &StateSpace, s: StateId) -> Key {
    (space.env(s).to_vec(), space.plan(s).to_vec(), space.zone(s), space.states[s.index()].kind)
}

/// The comparisons' budget: `max_states` and a work budget of 250 million, half the default, so
/// that a game beyond the budget costs a comparison what it did before the default grew.
pub fn options(max_states: usize) -> Config {
    Config { max_states, max_work: 250_000_000, ..Config::default() }
}

/// Checks, for one game solved both ways within `max_states` (the default search, and the exact
/// reference: exhaustive, without the thesis's zeno memory): the same verdict; every winning
/// state of the search is winning in the reference; and in both, the winning states are closed
/// (every plant reaction and timeout-free delay the strategy allows stays winning, and every
/// winning state has a winning request or can wait) and every cycle through them makes plan
/// progress. Returns the visited states of the search and of the reference, or `None` if either
/// exceeded the budget.
pub fn compare_with_reference(game: &Game, max_states: usize) -> Result<Visited, String> {
    let options = options(max_states);
    let fast = synthesize(game, &options, &mut |_| true);
    let exact = Config { exhaustive: true, zeno_memory: false, ..options };
    let reference = synthesize(game, &exact, &mut |_| true);
    agree(game, &fast, &reference)
}

/// The states visited by the search and by the reference, `None` if either exceeded the budget.
pub type Visited = Option<(usize, usize)>;

/// [`compare_with_reference`] for the scan game of `game` at `scan_ms`, the search guided by the
/// zero-time strategy as `synthesize_at_scan` runs it; also returns the search's verdict, if it
/// reached one.
pub fn compare_scan_with_reference(
    game: &Game,
    scan_ms: u64,
    max_states: usize,
) -> Result<(Option<Verdict>, Visited), String> {
    let options = options(max_states);
    let fast = synthesize_at_scan(game, scan_ms, &options, &mut |_| true).map_err(|e| e.to_string())?;
    let exact = Config { exhaustive: true, zeno_memory: false, ..options };
    let reference = synthesize(&fast.game, &exact, &mut |_| true);
    Ok((fast.synthesis.solution.verdict(), agree(&fast.game, &fast.synthesis, &reference)?))
}

fn agree(game: &Game, fast: &Synthesis, reference: &Synthesis) -> Result<Visited, String> {
    let (f, r) = (&fast.solution, &reference.solution);
    if matches!(f.outcome, Err(Stop::Budget { .. })) || matches!(r.outcome, Err(Stop::Budget { .. })) {
        return Ok(None);
    }
    let lowered = deadline_clocks(game);
    closed(&f.space, lowered).map_err(|m| format!("search: {m}"))?;
    closed(&r.space, lowered).map_err(|m| format!("reference: {m}"))?;
    progressing(&f.space).map_err(|m| format!("search: {m}"))?;
    progressing(&r.space).map_err(|m| format!("reference: {m}"))?;
    if f.outcome != r.outcome {
        return Err(format!("verdicts differ: {:?} against the reference's {:?}", f.outcome, r.outcome));
    }
    // Winning in the reference: surviving its exact removal. (Not only the survivors reachable
    // through survivors: the search's inclusion may reach a surviving state from one whose
    // zone it includes, where the reference's own moves do not go.)
    let all: HashSet<Key> = r.space.state_ids().map(|s| key(&r.space, s)).collect();
    let survivors: HashSet<Key> =
        r.space.state_ids().filter(|&s| r.space.is_winning(s)).map(|s| key(&r.space, s)).collect();
    if let Some(s) = f.space.winning_states().into_iter().find(|&s| !survivors.contains(&key(&f.space, s))) {
        return Err(format!("s{s} wins in the search but not in the reference"));
    }
    // A move into a zone that a winning state includes: the zone, where the reference has it,
    // survives there too.
    for s in f.space.winning_states() {
        for (_, e) in f.space.out_edges(s).filter(|(_, e)| f.space.is_live(e)) {
            let Some(own) = f.space.own_zone(e) else { continue };
            let t = e.to;
            let own_key = (f.space.env(t).to_vec(), f.space.plan(t).to_vec(), own, f.space.states[t.index()].kind);
            if all.contains(&own_key) && !survivors.contains(&own_key) {
                return Err(format!("s{s}: the move to s{t} (including its zone) enters a zone the reference loses"));
            }
        }
    }
    // A state lost by dominance: the state dominating it has the same locations and kind, is
    // lost (not merely unexplored), and its zone lies in this one's, plan clocks lowered. Both,
    // where the reference has them, are lost there too (only where the reference wins: a lost
    // initial state ends its search before every removal is made, so its survivors need not win).
    let reference_complete = r.is_realizable();
    for s in f.space.state_ids() {
        let Some(Removal::Dominated { by }) = f.space.states[s.index()].removal else { continue };
        let (a, b) = (key(&f.space, s), key(&f.space, by));
        if (&a.0, &a.1, a.3) != (&b.0, &b.1, b.3) {
            return Err(format!("s{s} is lost by dominance of s{by}, of other locations or kind"));
        }
        if matches!(f.space.states[by.index()].removal, None | Some(Removal::Unexplored)) {
            return Err(format!("s{s} is lost by dominance of s{by}, which is not lost"));
        }
        if !a.2.includes_lowered(&b.2, lowered) {
            return Err(format!("s{s} is lost by dominance of s{by}, whose zone does not lie in its own"));
        }
        for (what, t, k) in [("dominated", s, &a), ("dominating", by, &b)] {
            if reference_complete && survivors.contains(k) {
                let why = f.space.states[by.index()].removal;
                return Err(format!(
                    "{what} s{t} (s{s} lost by dominance of s{by}, lost as {why:?}) wins in the reference"
                ));
            }
        }
    }
    Ok(Some((f.stats.visited, r.stats.visited)))
}

/// The clocks of the plans (a bit per zone index): only ever checked against a deadline.
fn deadline_clocks(game: &Game) -> u64 {
    game.plans.iter().flat_map(|p| &p.clocks).fold(0, |bits, &(c, _)| bits | 1 << c.index())
}

/// Every winning state's plant reactions stay winning, and it has a winning request or can wait;
/// a move to a state whose zone includes the move's own lies in that zone, once the clocks
/// `lowered` (the plans' deadline clocks) may be lower there, and agrees with it on the others.
pub fn closed(space: &StateSpace, lowered: u64) -> Result<(), String> {
    for s in space.winning_states() {
        for (_, e) in space.out_edges(s) {
            if let Some(own) = space.own_zone(e) {
                let cover = space.zone(e.to);
                if !includes_only_lowered(cover.as_slice(), own.as_slice(), cover.dim(), lowered) {
                    return Err(format!(
                        "s{s}: the move to s{} does not lie in its zone, or differs in other clocks",
                        e.to
                    ));
                }
            }
        }
        let edges: Vec<_> = space.out_edges(s).map(|(_, e)| e).collect();
        if let Some(e) = edges.iter().find(|e| e.kind == EdgeKind::Reaction && !space.is_live(e)) {
            return Err(format!("s{s}: the reaction to s{} leaves the winning states", e.to));
        }
        let option = edges.iter().any(|e| matches!(e.kind, EdgeKind::Request | EdgeKind::Guard) && space.is_live(e));
        let delays: Vec<_> = edges.iter().filter(|e| e.kind == EdgeKind::Delay).collect();
        let wait = if delays.is_empty() {
            edges.iter().any(|e| e.kind == EdgeKind::Reaction)
        } else {
            delays.iter().all(|e| space.is_live(e))
        };
        if !option && !wait {
            return Err(format!("s{s} is winning without a winning request and without waiting"));
        }
    }
    Ok(())
}

/// The progress condition from its definition: among the winning states, the live moves that
/// make no plan progress form no cycle, so whatever live move a program takes, every cycle of
/// its plays reaches a plan goal.
pub fn progressing(space: &StateSpace) -> Result<(), String> {
    let winning = space.winning_states();
    let mut graph = petgraph::Graph::<StateId, ()>::new();
    let nodes: std::collections::HashMap<StateId, _> = winning.iter().map(|&s| (s, graph.add_node(s))).collect();
    for &s in &winning {
        for (_, e) in space.out_edges(s) {
            if space.is_live(e) && !e.progress {
                graph.add_edge(nodes[&s], nodes[&e.to], ());
            }
        }
    }
    match petgraph::algo::toposort(&graph, None) {
        Ok(_) => Ok(()),
        Err(cycle) => {
            Err(format!("s{} lies on a cycle of winning states without plan progress", graph[cycle.node_id()]))
        }
    }
}
