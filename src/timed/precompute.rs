//! Precomputation (Peter 2005, 5.2): clock usage analysis and the unique-choice-interval split.
//!
//! For every component (plant units and plans) and each of its clocks, the constants of all
//! invariants and guards cut `[0, ∞)` into *pieces* (the unique choice intervals of 5.2.2). A
//! location is split into *sub-locations*, one per combination of pieces of the clocks that
//! are used there (5.2.1); inside a sub-location no guard or invariant changes its truth value,
//! so every decision is explicit:
//! - a delay edge (D) leads to the sub-location of the next piece of one clock;
//! - beyond the last piece an invariant allows, a timeout edge (T) marks the exceptional
//!   overrun of 5.2.2 (plant units only);
//! - for plans, the pieces beyond a timeout bound are *failed* sub-locations.
//!
//! The pieces of a clock are the same in all locations of its component, so a transition that
//! does not reset a clock keeps the clock's piece.

use super::model::*;
use serde::Serialize;
use std::collections::HashMap;

pub type SubLocId = u32;

/// No target: the observer stays where it is.
pub const STAY: SubLocId = u32::MAX;

/// The split form of the whole game.
#[derive(Clone, Debug, Serialize)]
pub struct SplitGame {
    /// Plant units first (same order as `Game::components`), then plans.
    pub units: Vec<SplitUnit>,
    pub plant_count: usize,
    /// Pieces of every clock (index 0, the reference clock, has none).
    pub pieces: Vec<Vec<Interval>>,
    /// Largest constant compared with each clock (for extrapolation); -1 if never compared.
    pub max_constant: Vec<i32>,
    /// For each message, the plant units that must take a `$` transition along with it.
    pub sync_units: Vec<Vec<CompId>>,
    /// Plan transitions: `plan_next[plan][subloc * messages + msg]` is the target or `STAY`.
    pub plan_next: Vec<Vec<SubLocId>>,
    /// Clocks reset by the same plan transitions, as bit sets over clock ids.
    pub plan_resets: Vec<Vec<u64>>,
    pub message_count: usize,
}

#[derive(Clone, Debug, Serialize)]
pub struct SplitUnit {
    pub name: String,
    pub sublocs: Vec<SubLoc>,
    pub initial: SubLocId,
    pub clocks: Vec<ClockId>,
}

#[derive(Clone, Debug, Serialize)]
pub struct SubLoc {
    pub location: LocId,
    /// The piece of every clock used here, sorted by clock.
    pub pieces: Vec<(ClockId, u16)>,
    /// Time passes into the next piece of `clock`.
    pub delays: Vec<Delay>,
    /// The invariant ends here: time passing beyond it is the exceptional timeout of 5.2.2.
    pub timeout: Option<ClockId>,
    /// A plan that has failed (its `failed` location, or a timeout clock beyond its bound).
    pub failed: bool,
    /// Sending and synchronising transitions enabled in this sub-location.
    pub edges: Vec<SplitEdge>,
}

#[derive(Clone, Copy, Debug, Serialize)]
pub struct Delay {
    pub clock: ClockId,
    pub target: SubLocId,
}

#[derive(Clone, Debug, Serialize)]
pub struct SplitEdge {
    /// Index into the component's `edges`.
    pub edge: u32,
    pub target: SubLocId,
    pub kind: MessageKind,
    pub message: MsgId,
    pub resets: Vec<ClockId>,
    pub instant: bool,
}

/// Positions on the time line: point `k` is tick `2k`, the open interval `(k, k+1)` is tick
/// `2k+1`. Intervals with integer bounds are exactly the tick ranges.
fn ticks(i: &Interval) -> (u64, u64) {
    let lo = 2 * i.lower as u64 + u64::from(!i.lower_closed);
    let hi = match i.upper {
        None => u64::MAX,
        Some(u) => (2 * u as u64).saturating_sub(u64::from(!i.upper_closed)),
    };
    (lo, hi)
}

fn from_ticks(lo: u64, hi: u64) -> Interval {
    let lower = (lo / 2) as u32;
    let lower_closed = lo % 2 == 0;
    let (upper, upper_closed) = if hi == u64::MAX { (None, false) } else { (Some(hi.div_ceil(2) as u32), hi % 2 == 0) };
    Interval { lower, lower_closed, upper, upper_closed, span: Default::default() }
}

/// True if `inner` lies within `outer`.
fn within(inner: &Interval, outer: &Interval) -> bool {
    let (a, b) = ticks(inner);
    let (c, d) = ticks(outer);
    c <= a && b <= d
}

/// Cuts `[0, ∞)` at every bound of `constraints` (5.2.2).
pub fn unique_choice_pieces(constraints: &[Interval]) -> Vec<Interval> {
    let mut cuts = vec![0u64];
    for c in constraints {
        let (lo, hi) = ticks(c);
        cuts.push(lo);
        if hi != u64::MAX {
            cuts.push(hi + 1);
        }
    }
    cuts.sort_unstable();
    cuts.dedup();
    let mut pieces = Vec::with_capacity(cuts.len());
    for (k, &lo) in cuts.iter().enumerate() {
        let hi = cuts.get(k + 1).map_or(u64::MAX, |next| next - 1);
        pieces.push(from_ticks(lo, hi));
    }
    pieces
}

fn is_trivial(i: &Interval) -> bool {
    i.lower == 0 && i.lower_closed && i.upper.is_none()
}

/// Clock usage (5.2.1): the locations where `clock` is used, locally or before it is read
/// again without a reset. `local[l]` marks local use; `edges` are (from, to, resets clock).
pub fn clock_usage(location_count: usize, local: &[bool], edges: &[(LocId, LocId, bool)]) -> Vec<bool> {
    let mut used = local.to_vec();
    debug_assert_eq!(used.len(), location_count);
    // Reverse adjacency restricted to edges that keep the clock.
    let mut preds: Vec<Vec<LocId>> = vec![Vec::new(); location_count];
    for &(from, to, resets) in edges {
        if !resets {
            preds[to as usize].push(from);
        }
    }
    let mut stack: Vec<LocId> = (0..location_count as LocId).filter(|&l| used[l as usize]).collect();
    while let Some(l) = stack.pop() {
        for &p in &preds[l as usize] {
            if !used[p as usize] {
                used[p as usize] = true;
                stack.push(p);
            }
        }
    }
    used
}

/// Builds the split game. Infallible for a checked game.
pub fn split(game: &Game) -> SplitGame {
    let dim = game.dim();
    let mut constraints: Vec<Vec<Interval>> = vec![Vec::new(); dim];
    for a in &game.components {
        for l in &a.locations {
            for ci in &l.invariant {
                constraints[ci.clock as usize].push(ci.interval);
            }
        }
        for e in &a.edges {
            for ci in &e.guard {
                constraints[ci.clock as usize].push(ci.interval);
            }
        }
    }
    for p in &game.plans {
        for &(clock, bound) in &p.clocks {
            constraints[clock as usize].push(Interval::closed(0, bound));
        }
    }
    let pieces: Vec<Vec<Interval>> = constraints
        .iter()
        .enumerate()
        .map(|(c, cs)| if c == 0 { Vec::new() } else { unique_choice_pieces(cs) })
        .collect();
    let max_constant: Vec<i32> = constraints
        .iter()
        .map(|cs| cs.iter().flat_map(|i| [Some(i.lower), i.upper]).flatten().map(|v| v as i32).max().unwrap_or(-1))
        .collect();

    let mut units = Vec::new();
    for a in &game.components {
        units.push(split_plant_unit(a, &pieces));
    }
    let message_count = game.messages.len();
    let mut plan_next = Vec::new();
    let mut plan_resets = Vec::new();
    for p in &game.plans {
        let (unit, next, resets) = split_plan(p, &pieces, message_count);
        units.push(unit);
        plan_next.push(next);
        plan_resets.push(resets);
    }
    let sync_units = game.messages.iter().map(|m| m.synchronised.clone()).collect();
    SplitGame {
        units,
        plant_count: game.components.len(),
        pieces,
        max_constant,
        sync_units,
        plan_next,
        plan_resets,
        message_count,
    }
}

/// Which pieces of `clock` the conjunction `invariant` allows, as a range of piece indices.
fn allowed_pieces(pieces: &[Interval], clock: ClockId, invariant: &[ClockInterval]) -> std::ops::Range<u16> {
    let ok = |p: &Interval| invariant.iter().filter(|ci| ci.clock == clock).all(|ci| within(p, &ci.interval));
    let first = pieces.iter().position(ok).unwrap_or(pieces.len());
    let last = pieces.iter().rposition(ok).map_or(first, |l| l + 1);
    first as u16..last as u16
}

/// Enumerates the sub-locations of every location and indexes them.
struct SubLocIndex {
    index: HashMap<(LocId, Vec<u16>), SubLocId>,
    sublocs: Vec<SubLoc>,
    /// Clocks used at each location.
    active: Vec<Vec<ClockId>>,
}

impl SubLocIndex {
    fn build(active: Vec<Vec<ClockId>>, ranges: impl Fn(LocId, ClockId) -> std::ops::Range<u16>) -> SubLocIndex {
        let mut index = HashMap::new();
        let mut sublocs = Vec::new();
        for (l, clocks) in active.iter().enumerate() {
            let per_clock: Vec<std::ops::Range<u16>> = clocks.iter().map(|&c| ranges(l as LocId, c)).collect();
            if per_clock.iter().any(|r| r.is_empty()) {
                continue; // the invariant can never hold
            }
            let mut combo: Vec<u16> = per_clock.iter().map(|r| r.start).collect();
            loop {
                index.insert((l as LocId, combo.clone()), sublocs.len() as SubLocId);
                sublocs.push(SubLoc {
                    location: l as LocId,
                    pieces: clocks.iter().copied().zip(combo.iter().copied()).collect(),
                    delays: Vec::new(),
                    timeout: None,
                    failed: false,
                    edges: Vec::new(),
                });
                // Odometer increment over the per-clock ranges.
                let mut k = 0;
                loop {
                    if k == combo.len() {
                        break;
                    }
                    combo[k] += 1;
                    if combo[k] < per_clock[k].end {
                        break;
                    }
                    combo[k] = per_clock[k].start;
                    k += 1;
                }
                if k == combo.len() {
                    break;
                }
            }
        }
        SubLocIndex { index, sublocs, active }
    }

    fn piece_of(&self, s: SubLocId, clock: ClockId) -> Option<u16> {
        self.sublocs[s as usize].pieces.iter().find(|(c, _)| *c == clock).map(|&(_, p)| p)
    }

    /// The sub-location of `to` reached from `from` when `resets` are reset, if it exists.
    fn target(&self, from: SubLocId, to: LocId, resets: &[ClockId]) -> Option<SubLocId> {
        let combo: Option<Vec<u16>> = self.active[to as usize]
            .iter()
            .map(|&c| if resets.contains(&c) { Some(0) } else { self.piece_of(from, c) })
            .collect();
        self.index.get(&(to, combo?)).copied()
    }

    fn with_piece(&self, s: SubLocId, clock: ClockId, piece: u16) -> Option<SubLocId> {
        let sub = &self.sublocs[s as usize];
        let combo: Vec<u16> = sub.pieces.iter().map(|&(c, p)| if c == clock { piece } else { p }).collect();
        self.index.get(&(sub.location, combo)).copied()
    }
}

fn split_plant_unit(a: &Automaton, pieces: &[Vec<Interval>]) -> SplitUnit {
    let n = a.locations.len();
    let mut active: Vec<Vec<ClockId>> = vec![Vec::new(); n];
    for &c in &a.clocks {
        let mut local = vec![false; n];
        for (l, loc) in a.locations.iter().enumerate() {
            local[l] = loc.invariant.iter().any(|ci| ci.clock == c && !is_trivial(&ci.interval));
        }
        for e in &a.edges {
            if e.guard.iter().any(|ci| ci.clock == c && !is_trivial(&ci.interval)) {
                local[e.from as usize] = true;
            }
        }
        let edges: Vec<(LocId, LocId, bool)> = a.edges.iter().map(|e| (e.from, e.to, e.resets.contains(&c))).collect();
        for (l, used) in clock_usage(n, &local, &edges).into_iter().enumerate() {
            if used {
                active[l].push(c);
            }
        }
    }
    let idx =
        SubLocIndex::build(active, |l, c| allowed_pieces(&pieces[c as usize], c, &a.locations[l as usize].invariant));
    let mut sublocs = idx.sublocs.clone();
    for (s, sub) in sublocs.iter_mut().enumerate() {
        let s = s as SubLocId;
        for &(clock, piece) in &sub.pieces {
            let next = piece + 1;
            if (next as usize) < pieces[clock as usize].len() {
                match idx.with_piece(s, clock, next) {
                    Some(target) => sub.delays.push(Delay { clock, target }),
                    None => sub.timeout = Some(clock),
                }
            }
        }
        for (ei, e) in a.edges.iter().enumerate() {
            if e.from != sub.location {
                continue;
            }
            let enabled = e.guard.iter().all(|ci| match idx.piece_of(s, ci.clock) {
                Some(p) => within(&pieces[ci.clock as usize][p as usize], &ci.interval),
                None => is_trivial(&ci.interval),
            });
            if !enabled {
                continue;
            }
            if let Some(target) = idx.target(s, e.to, &e.resets) {
                sub.edges.push(SplitEdge {
                    edge: ei as u32,
                    target,
                    kind: e.kind,
                    message: e.message,
                    resets: e.resets.clone(),
                    instant: e.instant,
                });
            }
        }
    }
    let initial = idx.index.get(&(a.initial, vec![0; idx.active[a.initial as usize].len()])).copied().unwrap_or(0);
    SplitUnit { name: a.name.clone(), sublocs, initial, clocks: a.clocks.clone() }
}

fn split_plan(
    p: &PlanAutomaton,
    pieces: &[Vec<Interval>],
    message_count: usize,
) -> (SplitUnit, Vec<SubLocId>, Vec<u64>) {
    let n = p.locations.len();
    let clocks: Vec<ClockId> = p.clocks.iter().map(|&(c, _)| c).collect();
    // A timeout clock is compared in every waiting location, so it is used everywhere but in `failed`.
    let active: Vec<Vec<ClockId>> =
        (0..n).map(|l| if l as LocId == p.failed { Vec::new() } else { clocks.clone() }).collect();
    let idx = SubLocIndex::build(active, |_, c| 0..pieces[c as usize].len() as u16);
    let mut sublocs = idx.sublocs.clone();
    let mut next = vec![STAY; sublocs.len() * message_count];
    let mut resets = vec![0u64; sublocs.len() * message_count];
    for (s, sub) in sublocs.iter_mut().enumerate() {
        let s = s as SubLocId;
        sub.failed = sub.location == p.failed
            || sub.pieces.iter().any(|&(c, piece)| {
                let bound = p.clocks.iter().find(|(pc, _)| *pc == c).map(|&(_, b)| b).unwrap_or(u32::MAX);
                !within(&pieces[c as usize][piece as usize], &Interval::closed(0, bound))
            });
        if sub.failed {
            continue;
        }
        for &(clock, piece) in &sub.pieces {
            if ((piece + 1) as usize) < pieces[clock as usize].len() {
                if let Some(target) = idx.with_piece(s, clock, piece + 1) {
                    sub.delays.push(Delay { clock, target });
                }
            }
        }
        for e in p.edges.iter().filter(|e| e.from == sub.location) {
            if let Some(target) = idx.target(s, e.to, &e.resets) {
                next[s as usize * message_count + e.message as usize] = target;
                resets[s as usize * message_count + e.message as usize] =
                    e.resets.iter().fold(0, |bits, &c| bits | 1 << c);
            }
        }
    }
    let initial = idx.index.get(&(p.initial, vec![0; idx.active[p.initial as usize].len()])).copied().unwrap_or(0);
    (SplitUnit { name: p.name.clone(), sublocs, initial, clocks }, next, resets)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn iv(lower: u32, lc: bool, upper: Option<u32>, uc: bool) -> Interval {
        Interval { lower, lower_closed: lc, upper, upper_closed: uc, span: Default::default() }
    }

    #[test]
    fn pieces_of_the_thesis_example() {
        // 5.2.2: invariant 0 ≤ c ≤ 4 and a guard c > 2 give [0,2], (2,4], (4,∞).
        let p = unique_choice_pieces(&[iv(0, true, Some(4), true), iv(2, false, None, false)]);
        let shown: Vec<String> = p.iter().map(|i| i.to_string()).collect();
        assert_eq!(shown, ["[0,2]", "(2,4]", "(4,inf)"]);
    }

    #[test]
    fn pieces_partition_the_time_line() {
        let p =
            unique_choice_pieces(&[iv(1, false, Some(3), false), iv(3, true, Some(3), true), iv(5, true, None, false)]);
        let shown: Vec<String> = p.iter().map(|i| i.to_string()).collect();
        assert_eq!(shown, ["[0,1]", "(1,3)", "[3,3]", "(3,5)", "[5,inf)"]);
        for w in p.windows(2) {
            assert_eq!(ticks(&w[0]).1 + 1, ticks(&w[1]).0, "pieces are adjacent");
        }
    }

    #[test]
    fn clock_usage_follows_edges_backwards_until_a_reset() {
        // 0 -> 1 -> 2 (uses c); 3 -> 1 resets c.
        let used = clock_usage(4, &[false, false, true, false], &[(0, 1, false), (1, 2, false), (3, 1, true)]);
        assert_eq!(used, [true, true, true, false]);
    }
}
