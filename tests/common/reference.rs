//! The strategy-directed timed solver against the exhaustive reference (`--exhaustive`).

use plcsynth::timed::model::Game;
use plcsynth::timed::solve::{EdgeKind, Removal, SolveOptions, StateId, StateKind, StateSpace, Verdict};
use plcsynth::timed::synthesize;
use plcsynth::zone::Dbm;
use std::collections::HashSet;

/// A state independent of the run that stored it: sub-locations, plans, zone and kind.
type Key = (Vec<u32>, Vec<u32>, Dbm, StateKind);

fn key(space: &StateSpace, s: StateId) -> Key {
    (space.env(s).to_vec(), space.plan(s).to_vec(), space.zone(s), space.states[s as usize].kind)
}

/// Checks, for one game solved both ways within `max_states`: the same verdict; every winning
/// state of the strategy-directed search is winning in the reference; and the winning states are
/// closed: every plant reaction and timeout-free delay the strategy allows stays winning, and
/// every winning state has a winning request or can wait. Returns the visited states of the
/// search and of the reference, or `None` if either exceeded the budget.
pub fn compare_with_reference(game: &Game, max_states: usize) -> Result<Option<(usize, usize)>, Mismatch> {
    let options = SolveOptions { max_states, ..SolveOptions::default() };
    let fast = synthesize(game, &options, &mut |_| true);
    let reference = synthesize(game, &SolveOptions { exhaustive: true, ..options }, &mut |_| true);
    let (f, r) = (&fast.solution, &reference.solution);
    if f.verdict == Verdict::BudgetExceeded || r.verdict == Verdict::BudgetExceeded {
        return Ok(None);
    }
    let cut_zeno = |space: &StateSpace| {
        space.edges.iter().any(|e| e.zeno)
            || space.states.iter().any(|st| matches!(st.removal, Some(Removal::ZenoLoop { .. })))
    };
    let mismatch = |message: String| Mismatch { message, zeno_cut: cut_zeno(&r.space) || cut_zeno(&f.space) };
    closed(&f.space).map_err(|message| Mismatch { zeno_cut: false, ..mismatch(message) })?;
    if f.verdict != r.verdict {
        return Err(mismatch(format!("verdicts differ: {:?} against the reference's {:?}", f.verdict, r.verdict)));
    }
    let winning: HashSet<Key> = r.space.winning_states().into_iter().map(|s| key(&r.space, s)).collect();
    if let Some(s) = f.space.winning_states().into_iter().find(|&s| !winning.contains(&key(&f.space, s))) {
        return Err(mismatch(format!("s{s} wins in the search but not in the reference")));
    }
    Ok(Some((f.stats.visited, r.stats.visited)))
}

/// Why the two searches disagree, and whether either cut a zeno move (the one way they may, see
/// `tests/random_specs.rs`).
#[derive(Debug)]
pub struct Mismatch {
    pub message: String,
    pub zeno_cut: bool,
}

impl std::fmt::Display for Mismatch {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{} (a zeno move was cut: {})", self.message, self.zeno_cut)
    }
}

/// Every winning state's plant reactions stay winning, and it has a winning request or can wait.
fn closed(space: &StateSpace) -> Result<(), String> {
    for s in space.winning_states() {
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
