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
//!
//! A location with `k` clocks in use splits into the product of their pieces, exponential in
//! `k`; the split is therefore charged to the memory and work budgets of the run and refused,
//! naming the location, when it would exceed them.

use super::model::*;
use super::solve::{Config, Halt, Stats, PROGRESS_WORK, STEP_COST};
use crate::diag::Span;
use crate::id::id_type;
use crate::search::OnProgress;
use crate::search::{Charge, Meter, Resource};
use serde::Serialize;
use std::mem::size_of;
use std::ops::Range;

id_type! {
    /// A sub-location of one split unit: an index into its `SplitUnit::sublocs`.
    #[derive(Serialize)]
    #[serde(transparent)]
    pub struct SubLocId;
}

impl SubLocId {
    /// No target in [`SplitGame::plan_next`]: the plan stays where it is.
    pub const STAY: SubLocId = SubLocId::from_raw(u32::MAX);
}

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
    /// Plan transitions: `plan_next[plan][subloc * messages + msg]` is the target or [`SubLocId::STAY`].
    pub plan_next: Vec<Vec<SubLocId>>,
    /// Clocks reset by the same plan transitions, as bit sets over clock ids.
    pub plan_resets: Vec<Vec<u64>>,
    pub message_count: usize,
    /// Approximate heap bytes of the sub-locations and plan tables (part of the memory budget).
    pub bytes: usize,
    /// Work spent splitting, in the units of [`Config::max_work`].
    pub work: u64,
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
    crate::sort::sort(&mut cuts);
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
            preds[to.index()].push(from);
        }
    }
    let mut stack: Vec<LocId> = (0..location_count).map(LocId::new).filter(|&l| used[l.index()]).collect();
    while let Some(l) = stack.pop() {
        for &p in &preds[l.index()] {
            if !used[p.index()] {
                used[p.index()] = true;
                stack.push(p);
            }
        }
    }
    used
}

/// Why the split was refused: building the sub-locations needed more memory or work than the
/// budget of the run allows. Names the location with the most sub-locations of the unit being
/// split, the usual culprit (every clock in use there multiplies them).
#[derive(Clone, Debug)]
pub struct SplitTooLarge {
    pub budget: Resource,
    /// The location in words, e.g. "node `q` of `A`".
    pub place: String,
    /// Where the location is declared.
    pub span: Span,
    /// Clocks in use at the location, and how many sub-locations they make of it.
    pub clocks: usize,
    pub sublocations: u64,
    /// Memory and work of the split when it was refused.
    pub bytes: usize,
    pub work: u64,
}

/// Why [`split`] gave up.
#[derive(Clone, Debug)]
pub enum SplitError {
    TooLarge(SplitTooLarge),
    /// The progress callback cancelled the run.
    Cancelled,
}

/// Accounts the memory and work of the split against the budgets of the run, and keeps the
/// caller's progress callback informed during a long split.
struct SplitMeter<'p> {
    bytes: usize,
    max_bytes: usize,
    work: Meter,
    progress: &'p mut OnProgress<'p, Stats>,
}

impl SplitMeter<'_> {
    /// Adds `bytes` and `work`; stops when a budget is exceeded or the caller cancels.
    fn charge(&mut self, bytes: usize, work: u64) -> Result<(), Halt> {
        self.bytes += bytes;
        let charge = self.work.charge(work);
        if self.bytes > self.max_bytes {
            return Err(Halt::Budget(Resource::Memory));
        }
        match charge {
            Charge::Within => Ok(()),
            Charge::Exceeded => Err(Halt::Budget(Resource::Work)),
            Charge::ReportDue => {
                let stats = Stats { bytes: self.bytes, work: self.work.used(), ..Stats::default() };
                if (self.progress)(&stats) {
                    Ok(())
                } else {
                    Err(Halt::Cancelled)
                }
            }
        }
    }
}

/// Builds the split game within the memory and work budgets of `options` (the search gets
/// what is left of them). `progress` is called during a long split, as during the search.
pub fn split(game: &Game, options: &Config, progress: &mut OnProgress<'_, Stats>) -> Result<SplitGame, SplitError> {
    let dim = game.dim();
    let mut constraints: Vec<Vec<Interval>> = vec![Vec::new(); dim];
    for a in &game.components {
        for l in &a.locations {
            for ci in &l.invariant {
                constraints[ci.clock.index()].push(ci.interval);
            }
        }
        for e in &a.edges {
            for ci in &e.guard {
                constraints[ci.clock.index()].push(ci.interval);
            }
        }
    }
    for p in &game.plans {
        for &(clock, bound) in &p.clocks {
            constraints[clock.index()].push(Interval::closed(0, bound));
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

    let mut meter = SplitMeter {
        bytes: 0,
        max_bytes: options.max_bytes,
        work: Meter::new(0, options.max_work, PROGRESS_WORK),
        progress,
    };
    let mut units = Vec::new();
    for a in &game.components {
        let unit = split_plant_unit(a, &pieces, &mut meter).map_err(|(halt, idx)| {
            let Halt::Budget(budget) = halt else { return SplitError::Cancelled };
            let (l, count) = idx.largest();
            SplitError::TooLarge(SplitTooLarge {
                budget,
                place: format!("node `{}` of `{}`", a.locations[l].name, a.name),
                span: a.locations[l].span,
                clocks: idx.boxes[l].clocks.len(),
                sublocations: count,
                bytes: meter.bytes,
                work: meter.work.used(),
            })
        })?;
        units.push(unit);
    }
    let message_count = game.messages.len();
    let mut plan_next = Vec::new();
    let mut plan_resets = Vec::new();
    for (k, p) in game.plans.iter().enumerate() {
        let (unit, next, resets) = split_plan(p, &pieces, message_count, &mut meter).map_err(|(halt, idx)| {
            let Halt::Budget(budget) = halt else { return SplitError::Cancelled };
            let (l, count) = idx.largest();
            SplitError::TooLarge(SplitTooLarge {
                budget,
                place: format!("step `{}` of plan {}", p.locations[l].name, k + 1),
                span: p.locations[l].span,
                clocks: idx.boxes[l].clocks.len(),
                sublocations: count,
                bytes: meter.bytes,
                work: meter.work.used(),
            })
        })?;
        units.push(unit);
        plan_next.push(next);
        plan_resets.push(resets);
    }
    let sync_units = game.messages.iter().map(|m| m.synchronised.clone()).collect();
    Ok(SplitGame {
        units,
        plant_count: game.components.len(),
        pieces,
        max_constant,
        sync_units,
        plan_next,
        plan_resets,
        message_count,
        bytes: meter.bytes,
        work: meter.work.used(),
    })
}

/// The units of `game` without sub-locations: what a refused split leaves for display.
pub fn unsplit(game: &Game) -> SplitGame {
    let unit = |name: &str, clocks: Vec<ClockId>| SplitUnit {
        name: name.to_string(),
        sublocs: Vec::new(),
        initial: SubLocId::new(0),
        clocks,
    };
    let mut units: Vec<SplitUnit> = game.components.iter().map(|a| unit(&a.name, a.clocks.clone())).collect();
    units.extend(game.plans.iter().map(|p| unit(&p.name, p.clocks.iter().map(|&(c, _)| c).collect())));
    SplitGame {
        units,
        plant_count: game.components.len(),
        pieces: vec![Vec::new(); game.dim()],
        max_constant: vec![-1; game.dim()],
        sync_units: game.messages.iter().map(|m| m.synchronised.clone()).collect(),
        plan_next: vec![Vec::new(); game.plans.len()],
        plan_resets: vec![Vec::new(); game.plans.len()],
        message_count: game.messages.len(),
        bytes: 0,
        work: 0,
    }
}

/// Which pieces of `clock` the conjunction `invariant` allows, as a range of piece indices.
fn allowed_pieces(pieces: &[Interval], clock: ClockId, invariant: &[ClockInterval]) -> Range<u16> {
    let ok = |p: &Interval| invariant.iter().filter(|ci| ci.clock == clock).all(|ci| within(p, &ci.interval));
    let first = pieces.iter().position(ok).unwrap_or(pieces.len());
    let last = pieces.iter().rposition(ok).map_or(first, |l| l + 1);
    first as u16..last as u16
}

/// The sub-locations of one location: every combination of the allowed pieces of the clocks in
/// use, numbered like an odometer (the first clock turns fastest), so that the id of a
/// combination is computed rather than looked up.
struct LocationBox {
    base: u64,
    clocks: Vec<ClockId>,
    ranges: Vec<Range<u16>>,
    /// Id distance between neighbouring pieces of each clock.
    strides: Vec<u64>,
    /// Number of sub-locations (saturating); 0 where the invariant can never hold.
    count: u64,
}

impl LocationBox {
    /// The id of the combination `piece(c)` for the clocks in use, if every piece is allowed.
    fn id(&self, piece: impl Fn(ClockId) -> Option<u16>) -> Option<SubLocId> {
        if self.count == 0 {
            return None;
        }
        let mut id = self.base;
        for ((&c, r), &stride) in self.clocks.iter().zip(&self.ranges).zip(&self.strides) {
            let p = piece(c)?;
            if !r.contains(&p) {
                return None;
            }
            id += u64::from(p - r.start) * stride;
        }
        Some(SubLocId::new(id as usize))
    }
}

/// Indexes the sub-locations of one unit; `sublocs` is filled by [`SubLocIndex::build`].
struct SubLocIndex {
    boxes: Vec<LocationBox>,
    sublocs: Vec<SubLoc>,
}

impl SubLocIndex {
    /// Sizes every location's box from the clocks in use there and their allowed pieces.
    fn new(active: Vec<Vec<ClockId>>, ranges: impl Fn(LocId, ClockId) -> Range<u16>) -> SubLocIndex {
        let mut base = 0u64;
        let mut boxes = Vec::with_capacity(active.len());
        for (l, clocks) in active.into_iter().enumerate() {
            let ranges: Vec<Range<u16>> = clocks.iter().map(|&c| ranges(LocId::new(l), c)).collect();
            let mut strides = Vec::with_capacity(ranges.len());
            let mut count = 1u64;
            for r in &ranges {
                strides.push(count);
                count = count.saturating_mul(r.len() as u64);
            }
            boxes.push(LocationBox { base, clocks, ranges, strides, count });
            base = base.saturating_add(count);
        }
        SubLocIndex { boxes, sublocs: Vec::new() }
    }

    /// The location with the most sub-locations, and their number.
    fn largest(&self) -> (usize, u64) {
        self.boxes.iter().enumerate().map(|(l, b)| (l, b.count)).max_by_key(|&(_, c)| c).unwrap_or((0, 0))
    }

    /// Creates the sub-locations in id order, charging each to `meter` (a refused split stops
    /// before the first sub-location when even their fixed part exceeds the memory budget).
    fn build(&mut self, meter: &mut SplitMeter) -> Result<(), Halt> {
        let fixed: u64 = self
            .boxes
            .iter()
            .map(|b| {
                b.count.saturating_mul((size_of::<SubLoc>() + b.clocks.len() * size_of::<(ClockId, u16)>()) as u64)
            })
            .fold(0, u64::saturating_add);
        if fixed > meter.max_bytes.saturating_sub(meter.bytes) as u64 {
            return Err(Halt::Budget(Resource::Memory));
        }
        let total = self.boxes.iter().map(|b| b.count).fold(0, u64::saturating_add);
        self.sublocs.reserve_exact(total as usize);
        meter.charge(self.sublocs.capacity() * size_of::<SubLoc>(), 0)?;
        for (l, b) in self.boxes.iter().enumerate() {
            if b.count == 0 {
                continue;
            }
            let mut combo: Vec<u16> = b.ranges.iter().map(|r| r.start).collect();
            loop {
                let pieces: Vec<(ClockId, u16)> = b.clocks.iter().copied().zip(combo.iter().copied()).collect();
                meter.charge(heap_bytes(&pieces), STEP_COST + combo.len() as u64)?;
                self.sublocs.push(SubLoc {
                    location: LocId::new(l),
                    pieces,
                    delays: Vec::new(),
                    timeout: None,
                    failed: false,
                    edges: Vec::new(),
                });
                // Odometer increment over the per-clock ranges.
                let mut k = 0;
                while k < combo.len() {
                    combo[k] += 1;
                    if combo[k] < b.ranges[k].end {
                        break;
                    }
                    combo[k] = b.ranges[k].start;
                    k += 1;
                }
                if k == combo.len() {
                    break;
                }
            }
        }
        Ok(())
    }

    /// The sub-location of `l` with every clock in its first piece (0 if there is none).
    fn initial(&self, l: LocId) -> SubLocId {
        self.boxes[l.index()].id(|_| Some(0)).unwrap_or(SubLocId::new(0))
    }
}

/// Heap bytes of a vector, with the allocator's overhead of about 16 bytes per allocation.
fn heap_bytes<T>(v: &Vec<T>) -> usize {
    if v.capacity() == 0 {
        0
    } else {
        v.capacity() * size_of::<T>() + 16
    }
}

/// The piece of `clock` in a sub-location's sorted piece list.
fn piece_in(pieces: &[(ClockId, u16)], clock: ClockId) -> Option<u16> {
    pieces.iter().find(|(c, _)| *c == clock).map(|&(_, p)| p)
}

/// Indices of every edge, grouped by their source location.
fn edges_by_source(location_count: usize, from: impl Iterator<Item = LocId>) -> Vec<Vec<u32>> {
    let mut out = vec![Vec::new(); location_count];
    for (e, l) in from.enumerate() {
        out[l.index()].push(e as u32);
    }
    out
}

type SplitResult<T> = Result<T, (Halt, SubLocIndex)>;

fn split_plant_unit(a: &Automaton, pieces: &[Vec<Interval>], meter: &mut SplitMeter) -> SplitResult<SplitUnit> {
    let n = a.locations.len();
    let mut active: Vec<Vec<ClockId>> = vec![Vec::new(); n];
    for &c in &a.clocks {
        let mut local = vec![false; n];
        for (l, loc) in a.locations.iter().enumerate() {
            local[l] = loc.invariant.iter().any(|ci| ci.clock == c && !is_trivial(&ci.interval));
        }
        for e in &a.edges {
            if e.guard.iter().any(|ci| ci.clock == c && !is_trivial(&ci.interval)) {
                local[e.from.index()] = true;
            }
        }
        let edges: Vec<(LocId, LocId, bool)> = a.edges.iter().map(|e| (e.from, e.to, e.resets.contains(&c))).collect();
        for (l, used) in clock_usage(n, &local, &edges).into_iter().enumerate() {
            if used {
                active[l].push(c);
            }
        }
    }
    let mut idx =
        SubLocIndex::new(active, |l, c| allowed_pieces(&pieces[c.index()], c, &a.locations[l.index()].invariant));
    if let Err(budget) = idx.build(meter) {
        return Err((budget, idx));
    }
    let outgoing = edges_by_source(n, a.edges.iter().map(|e| e.from));
    let mut sublocs = std::mem::take(&mut idx.sublocs);
    let mut result = Ok(());
    for sub in sublocs.iter_mut() {
        let piece_here = |c: ClockId| piece_in(&sub.pieces, c);
        let mut delays = Vec::new();
        let mut timeout = None;
        for &(clock, piece) in &sub.pieces {
            let next = piece + 1;
            if (next as usize) < pieces[clock.index()].len() {
                let target =
                    idx.boxes[sub.location.index()].id(|c| if c == clock { Some(next) } else { piece_here(c) });
                match target {
                    Some(target) => delays.push(Delay { clock, target }),
                    None => timeout = Some(clock),
                }
            }
        }
        let mut edges = Vec::new();
        for &ei in &outgoing[sub.location.index()] {
            let e = &a.edges[ei as usize];
            let enabled = e.guard.iter().all(|ci| match piece_here(ci.clock) {
                Some(p) => within(&pieces[ci.clock.index()][p as usize], &ci.interval),
                None => is_trivial(&ci.interval),
            });
            if !enabled {
                continue;
            }
            let target = idx.boxes[e.to.index()].id(|c| if e.resets.contains(&c) { Some(0) } else { piece_here(c) });
            if let Some(target) = target {
                edges.push(SplitEdge {
                    edge: ei,
                    target,
                    kind: e.kind,
                    message: e.message,
                    resets: e.resets.clone(),
                    instant: e.instant,
                });
            }
        }
        let bytes =
            heap_bytes(&delays) + heap_bytes(&edges) + edges.iter().map(|e| heap_bytes(&e.resets)).sum::<usize>();
        let work = (outgoing[sub.location.index()].len() + sub.pieces.len()) as u64;
        sub.delays = delays;
        sub.timeout = timeout;
        sub.edges = edges;
        if let Err(budget) = meter.charge(bytes, work) {
            result = Err(budget);
            break;
        }
    }
    if let Err(budget) = result {
        return Err((budget, idx));
    }
    let initial = idx.initial(a.initial);
    Ok(SplitUnit { name: a.name.clone(), sublocs, initial, clocks: a.clocks.clone() })
}

fn split_plan(
    p: &PlanAutomaton,
    pieces: &[Vec<Interval>],
    message_count: usize,
    meter: &mut SplitMeter,
) -> SplitResult<(SplitUnit, Vec<SubLocId>, Vec<u64>)> {
    let n = p.locations.len();
    let clocks: Vec<ClockId> = p.clocks.iter().map(|&(c, _)| c).collect();
    // A timeout clock is compared in every waiting location, so it is used everywhere but in `failed`.
    let active: Vec<Vec<ClockId>> =
        (0..n).map(|l| if LocId::new(l) == p.failed { Vec::new() } else { clocks.clone() }).collect();
    let mut idx = SubLocIndex::new(active, |_, c| 0..pieces[c.index()].len() as u16);
    let table = idx.boxes.iter().map(|b| b.count).fold(0u64, u64::saturating_add).saturating_mul(message_count as u64);
    let table_bytes = table.saturating_mul((size_of::<SubLocId>() + size_of::<u64>()) as u64);
    if let Err(budget) = meter.charge(usize::try_from(table_bytes).unwrap_or(usize::MAX), 0) {
        return Err((budget, idx));
    }
    if let Err(budget) = idx.build(meter) {
        return Err((budget, idx));
    }
    let outgoing = edges_by_source(n, p.edges.iter().map(|e| e.from));
    let mut sublocs = std::mem::take(&mut idx.sublocs);
    let mut next = vec![SubLocId::STAY; sublocs.len() * message_count];
    let mut resets = vec![0u64; sublocs.len() * message_count];
    let mut result = Ok(());
    for (s, sub) in sublocs.iter_mut().enumerate() {
        sub.failed = sub.location == p.failed
            || sub.pieces.iter().any(|&(c, piece)| {
                let bound = p.clocks.iter().find(|(pc, _)| *pc == c).map(|&(_, b)| b).unwrap_or(u32::MAX);
                !within(&pieces[c.index()][piece as usize], &Interval::closed(0, bound))
            });
        if sub.failed {
            continue;
        }
        let piece_here = |c: ClockId| piece_in(&sub.pieces, c);
        let mut delays = Vec::new();
        for &(clock, piece) in &sub.pieces {
            if ((piece + 1) as usize) < pieces[clock.index()].len() {
                let target =
                    idx.boxes[sub.location.index()].id(|c| if c == clock { Some(piece + 1) } else { piece_here(c) });
                if let Some(target) = target {
                    delays.push(Delay { clock, target });
                }
            }
        }
        for &ei in &outgoing[sub.location.index()] {
            let e = &p.edges[ei as usize];
            let target = idx.boxes[e.to.index()].id(|c| if e.resets.contains(&c) { Some(0) } else { piece_here(c) });
            if let Some(target) = target {
                next[s * message_count + e.message.index()] = target;
                resets[s * message_count + e.message.index()] =
                    e.resets.iter().fold(0, |bits, &c| bits | 1 << c.index());
            }
        }
        let work = (outgoing[sub.location.index()].len() + sub.pieces.len()) as u64;
        let bytes = heap_bytes(&delays);
        sub.delays = delays;
        if let Err(budget) = meter.charge(bytes, work) {
            result = Err(budget);
            break;
        }
    }
    if let Err(budget) = result {
        return Err((budget, idx));
    }
    let initial = idx.initial(p.initial);
    Ok((SplitUnit { name: p.name.clone(), sublocs, initial, clocks }, next, resets))
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
        let used = clock_usage(
            4,
            &[false, false, true, false],
            &[
                (LocId::new(0), LocId::new(1), false),
                (LocId::new(1), LocId::new(2), false),
                (LocId::new(3), LocId::new(1), true),
            ],
        );
        assert_eq!(used, [true, true, true, false]);
    }
}
