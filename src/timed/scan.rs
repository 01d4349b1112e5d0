//! The scan game: the timed game of a controller that runs on a PLC with a fixed cycle time.
//!
//! The game of chapter 5 lets the controller react in zero time: it sees a plant reaction the
//! instant it happens and its request takes effect at that instant. A PLC reads its inputs at
//! the start of a scan, runs, and writes its outputs before the next scan starts. This module
//! builds, from a checked game and a scan time `T`, a game of the same kind whose controller can
//! only do that; the unchanged solver then decides whether the specification is implementable
//! at `T`. The construction (an explicit scan automaton with its own clock, one of the two ways
//! De Wulf, Doyen and Raskin (2005) relate ideal and implementable controllers):
//!
//! - a component `plc` with clock `plc.scan` and locations `read`, `quiet`, `armed`,
//!   `scheduled` and one `out_r` per request `r`; time 0 is the PLC's first read;
//! - at `read` (urgent: `scan ∈ [0,0]`) the controller decides at once, on what it has just
//!   read: `?scan:r` commits request `r` (to `out_r`), `?scan:idle` commits nothing (to
//!   `quiet`). The decisions are instant requests, so no plant reaction slips between the read
//!   and the decision. One request per scan, as the generated code issues them;
//! - `out_r -!r-> scheduled` at any `scan ∈ [0,T]`, chosen by the plant: the output takes effect
//!   at some moment of the scan. The plant's own `?r` transitions become `$r`, taken with it;
//! - `scheduled -!scan-> read` at `scan = T`, resetting `scan`: the next scan reads. After a
//!   pulsed request `r` (an output TRUE for one scan, the default) the next read is
//!   `read_after_r`, which may not commit `r` again: pulsed in two scans in a row, the output
//!   would stay TRUE and the plant see one request. Idle there, it reads again a scan later;
//! - a scan that changed nothing leaves the PLC `quiet` (its clock unused): until something
//!   changes, every further scan reads the same inputs and timers and decides the same. A
//!   change is a plant reaction (the automaton takes `$m` with every reaction `m`) or time
//!   moving a plant or plan clock into its next piece, a timer reaching a threshold (the solver
//!   does that move, see [`ScanRoles::quiet`]). It arms the PLC: `armed -!scan-> read` at any
//!   `scan ∈ [0,T]` after the change, because the scan's phase is not known. This forgets the
//!   phase while nothing happens, which keeps the zone graph free of one state per scan over
//!   long waits; the plant gains behaviours by it (two changes far apart need not be a whole
//!   number of scans apart), so *implementable* stays sound;
//! - a request the plant cannot take when it arrives is refused: every component with a
//!   transition on `r` gets, from each location, `$r` transitions into a location `refused`
//!   covering the clock valuations where no transition on `r` is enabled, and an assertion
//!   forbids that location. (In the zero-time game the controller simply never sends it.)
//!
//! The controller of this game sees the whole plant state at a read, as the controller of the
//! zero-time game sees it at every instant. State guards are dropped: a guard check is an
//! option that leads only to its request, so it never changes who wins, and the scan game is
//! solved for its verdict only (the program still comes from the zero-time strategy).
//!
//! Constants are rescaled so that `T` is a whole number of time units: the new unit is the
//! greatest common divisor of the old unit and `T` in milliseconds.

use super::model::*;
use crate::diag::Span;

/// Largest constant of a scan game: the parser's own limit on numbers.
pub const MAX_CONSTANT: u64 = 1 << 24;

/// The messages the construction adds, for the solver and for explanations.
#[derive(Clone, Debug, serde::Serialize)]
pub struct ScanRoles {
    /// `plc.scan = T`: a scan instant.
    pub tick: MsgId,
    /// The controller commits no request in this scan.
    pub idle: MsgId,
    /// Per message id: `Some(r)` if the message commits request `r` in this scan.
    pub commits: Vec<Option<MsgId>>,
    /// The scan time in time units of the scan game.
    pub period: u32,
    /// The scan time in milliseconds.
    pub scan_ms: u64,
    /// Time units of the scan game per time unit of the specification.
    pub scale: u32,
    /// The component `plc` and its clock.
    pub plc: CompId,
    pub clock: ClockId,
    /// Its location after a scan that changed nothing, where the clock is not in use, and the
    /// one after a change, where the next read is due within a scan. The solver moves the
    /// automaton from `quiet` to `armed` when time moves a plant or plan clock into its next
    /// piece (a change no message announces).
    pub quiet: LocId,
    pub armed: LocId,
}

/// Why no scan game is built.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum ScanError {
    /// A rescaled constant exceeds `MAX_CONSTANT`.
    TooFine { constant: u64, scaled: u64, scale: u64 },
    /// The scan time is zero.
    Zero,
}

impl std::fmt::Display for ScanError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ScanError::TooFine { constant, scaled, scale } => write!(
                f,
                "at this scan time the constant {constant} becomes {scaled} ({scale} steps per time unit), \
                 beyond the limit of {MAX_CONSTANT}"
            ),
            ScanError::Zero => f.write_str("the scan time must be longer than zero"),
        }
    }
}

fn gcd(a: u64, b: u64) -> u64 {
    if b == 0 {
        a
    } else {
        gcd(b, a % b)
    }
}

/// `game` itself (zero-time semantics) in the time units of its scan game at `scan_ms`.
pub fn rescaled(game: &Game, scan_ms: u64) -> Result<Game, ScanError> {
    if scan_ms == 0 {
        return Err(ScanError::Zero);
    }
    let unit = gcd(game.timeunit_ms, scan_ms);
    let mut out = game.clone();
    out.timeunit_ms = unit;
    rescale(&mut out, game.timeunit_ms / unit)?;
    Ok(out)
}

/// The scan game of `game` at a scan time of `scan_ms` milliseconds.
pub fn scan_game(game: &Game, scan_ms: u64) -> Result<Game, ScanError> {
    if scan_ms == 0 {
        return Err(ScanError::Zero);
    }
    let unit = gcd(game.timeunit_ms, scan_ms);
    let scale = game.timeunit_ms / unit;
    let period = scan_ms / unit;
    let mut out = game.clone();
    // A state guard (4.2.1) adds a check, an option of the controller leading only to the
    // request, in front of the request: it never changes who wins, and the scan game is solved
    // for its verdict only.
    out.guards.clear();
    out.timeunit_ms = unit;
    rescale(&mut out, scale)?;
    if period > MAX_CONSTANT {
        return Err(ScanError::TooFine { constant: scan_ms, scaled: period, scale });
    }
    let period = period as u32;

    let plc = CompId::new(out.components.len());
    let clock = ClockId::new(out.clocks.len());
    out.clocks.push(Clock { name: "plc.scan".into(), owner: ClockOwner::Component(plc), span: Span::default() });
    let requests: Vec<MsgId> = (0..game.messages.len())
        .map(MsgId::new)
        .filter(|&m| game.messages[m.index()].role == MessageRole::Request && game.messages[m.index()].sender.is_some())
        .collect();

    // The plant takes each request with the delivery; where it cannot, it refuses.
    let mut refused_assertions = Vec::new();
    for (c, comp) in out.components.iter_mut().enumerate() {
        let mut refused: Option<LocId> = None;
        let locations = comp.locations.len();
        for &r in &requests {
            let on_r: Vec<usize> = (0..comp.edges.len()).filter(|&i| comp.edges[i].message == r).collect();
            if on_r.is_empty() {
                continue;
            }
            for &i in &on_r {
                comp.edges[i].kind = MessageKind::Synchronised;
            }
            for l in (0..locations).map(LocId::new) {
                let guards: Vec<&[ClockInterval]> =
                    on_r.iter().map(|&i| &comp.edges[i]).filter(|e| e.from == l).map(|e| e.guard.as_slice()).collect();
                let uncovered = complement(&guards);
                if uncovered.is_empty() {
                    continue;
                }
                let to = *refused.get_or_insert_with(|| {
                    comp.locations.push(Location { name: "refused".into(), invariant: Vec::new(), span: comp.span });
                    LocId::new(comp.locations.len() - 1)
                });
                for guard in uncovered {
                    comp.edges.push(Edge {
                        from: l,
                        to,
                        kind: MessageKind::Synchronised,
                        message: r,
                        guard,
                        resets: Vec::new(),
                        instant: false,
                        span: comp.span,
                    });
                }
            }
        }
        if let Some(loc) = refused {
            refused_assertions.push(AssertionRule {
                holds: Pred::Not { operand: Box::new(Pred::At { comp: CompId::new(c), locations: vec![loc] }) },
                text: format!("never {}.refused (a request arrives where {} cannot take it)", comp.name, comp.name),
                span: comp.span,
            });
        }
    }
    out.assertions.extend(refused_assertions);
    for &r in &requests {
        let m = &mut out.messages[r.index()];
        if let Some(sender) = m.sender.replace(plc) {
            if !m.synchronised.contains(&sender) {
                m.synchronised.push(sender);
            }
        }
    }

    // The scan automaton. Every plant reaction is a change the PLC sees at its next read: the
    // automaton takes `$m` with it in each location.
    let reactions: Vec<MsgId> = (0..game.messages.len())
        .map(MsgId::new)
        .filter(|&m| {
            game.messages[m.index()].role == MessageRole::Reaction && game.messages[m.index()].sender.is_some()
        })
        .collect();
    let mut message = |name: String, role: MessageRole| {
        out.messages.push(Message { name, role, sender: Some(plc), synchronised: Vec::new() });
        MsgId::new(out.messages.len() - 1)
    };
    let tick = message("scan".into(), MessageRole::Reaction);
    let idle_msg = message("scan:idle".into(), MessageRole::Request);
    let commit_msgs: Vec<MsgId> = requests
        .iter()
        .map(|&r| message(format!("scan:{}", game.messages[r.index()].name), MessageRole::Request))
        .collect();
    for &m in &reactions {
        out.messages[m.index()].synchronised.push(plc);
    }
    let within = |lower: u32, upper: u32| vec![ClockInterval { clock, interval: Interval::closed(lower, upper) }];
    let (read, quiet, armed, scheduled) = (LocId::new(0), LocId::new(1), LocId::new(2), LocId::new(3));
    let location = |name: &str, invariant| Location { name: name.into(), invariant, span: Span::default() };
    let mut locations = vec![
        location("read", within(0, 0)),
        location("quiet", Vec::new()),
        location("armed", within(0, period)),
        location("scheduled", within(0, period)),
    ];
    let edge = |from, to, kind, message, guard, resets: Vec<ClockId>, instant| Edge {
        from,
        to,
        kind,
        message,
        guard,
        resets,
        instant,
        span: Span::default(),
    };
    let mut edges = vec![
        edge(read, quiet, MessageKind::Controllable, idle_msg, Vec::new(), Vec::new(), true),
        edge(armed, read, MessageKind::Uncontrollable, tick, within(0, period), vec![clock], false),
        edge(scheduled, read, MessageKind::Uncontrollable, tick, within(period, period), vec![clock], false),
    ];
    // A pulsed output is TRUE for the scan of its request; pulsed again in the next scan it
    // stays TRUE, and the plant sees one rising edge for two requests. So after a scan that
    // pulsed `r`, the next read (`read_after_r`) may not commit `r`: one scan must leave it FALSE.
    let pulsed = |r: MsgId| !game.io.iter().any(|b| b.message == r && matches!(b.mode, IoMode::Set | IoMode::Reset));
    let mut reads = vec![(read, None)];
    let mut after: Vec<Option<(LocId, LocId)>> = vec![None; requests.len()];
    for (k, &r) in requests.iter().enumerate() {
        if pulsed(r) {
            let name = &game.messages[r.index()].name;
            let read_after = LocId::new(locations.len());
            locations.push(location(&format!("read_after_{name}"), within(0, 0)));
            let scheduled_after = LocId::new(locations.len());
            locations.push(location(&format!("scheduled_after_{name}"), within(0, period)));
            // Idle there, the PLC reads again a scan later, where `r` is allowed again.
            edges.push(edge(read_after, scheduled, MessageKind::Controllable, idle_msg, Vec::new(), Vec::new(), true));
            edges.push(edge(
                scheduled_after,
                read_after,
                MessageKind::Uncontrollable,
                tick,
                within(period, period),
                vec![clock],
                false,
            ));
            reads.push((read_after, Some(r)));
            after[k] = Some((read_after, scheduled_after));
        }
    }
    for (k, (&r, &commit)) in requests.iter().zip(&commit_msgs).enumerate() {
        let out_r = LocId::new(locations.len());
        locations.push(location(&format!("out_{}", game.messages[r.index()].name), within(0, period)));
        for &(from, barred) in &reads {
            if barred != Some(r) {
                edges.push(edge(from, out_r, MessageKind::Controllable, commit, Vec::new(), Vec::new(), true));
            }
        }
        let next = after[k].map_or(scheduled, |(_, scheduled_after)| scheduled_after);
        edges.push(edge(out_r, next, MessageKind::Uncontrollable, r, within(0, period), Vec::new(), false));
    }
    for &m in &reactions {
        for l in (0..locations.len()).map(LocId::new) {
            let (to, resets) = if l == quiet { (armed, vec![clock]) } else { (l, Vec::new()) };
            edges.push(edge(l, to, MessageKind::Synchronised, m, Vec::new(), resets, false));
        }
    }
    out.components.push(Automaton {
        name: "plc".into(),
        origin: ComponentOrigin::Automaton,
        locations,
        initial: read,
        clocks: vec![clock],
        edges,
        span: Span::default(),
    });
    let mut commits = vec![None; out.messages.len()];
    for (&r, &c) in requests.iter().zip(&commit_msgs) {
        commits[c.index()] = Some(r);
    }
    out.scan = Some(ScanRoles {
        tick,
        idle: idle_msg,
        commits,
        period,
        scan_ms,
        scale: scale as u32,
        plc,
        clock,
        quiet,
        armed,
    });
    Ok(out)
}

/// Multiplies every constant of `game` by `scale`.
fn rescale(game: &mut Game, scale: u64) -> Result<(), ScanError> {
    let scaled = |v: u32| -> Result<u32, ScanError> {
        let s = u64::from(v) * scale;
        if s > MAX_CONSTANT {
            Err(ScanError::TooFine { constant: u64::from(v), scaled: s, scale })
        } else {
            Ok(s as u32)
        }
    };
    let interval = |i: &mut Interval| -> Result<(), ScanError> {
        i.lower = scaled(i.lower)?;
        if let Some(u) = i.upper.as_mut() {
            *u = scaled(*u)?;
        }
        Ok(())
    };
    for comp in &mut game.components {
        for loc in &mut comp.locations {
            for ci in &mut loc.invariant {
                interval(&mut ci.interval)?;
            }
        }
        for e in &mut comp.edges {
            for ci in &mut e.guard {
                interval(&mut ci.interval)?;
            }
        }
    }
    for plan in &mut game.plans {
        for (_, bound) in &mut plan.clocks {
            *bound = scaled(*bound)?;
        }
    }
    Ok(())
}

/// The clock valuations (each clock ≥ 0) in none of the `guards` (conjunctions of intervals),
/// as disjoint conjunctions.
pub fn complement(guards: &[&[ClockInterval]]) -> Vec<Vec<ClockInterval>> {
    let mut boxes: Vec<Vec<ClockInterval>> = vec![Vec::new()];
    for guard in guards {
        boxes = boxes.iter().flat_map(|b| subtract(b, guard)).collect();
    }
    boxes
}

/// `b` minus the conjunction `g`, as disjoint boxes: the first clock of `g` outside its
/// interval, or inside and the second outside, and so on.
fn subtract(b: &[ClockInterval], g: &[ClockInterval]) -> Vec<Vec<ClockInterval>> {
    let mut out = Vec::new();
    let mut inside = b.to_vec();
    for ci in g {
        for outside in interval_complement(&ci.interval) {
            if let Some(piece) = restrict(&inside, ci.clock, &outside) {
                out.push(piece);
            }
        }
        match restrict(&inside, ci.clock, &ci.interval) {
            Some(next) => inside = next,
            None => return out,
        }
    }
    out
}

/// `b` with clock `clock` also in `i`, or `None` if that is empty.
fn restrict(b: &[ClockInterval], clock: ClockId, i: &Interval) -> Option<Vec<ClockInterval>> {
    let mut out = b.to_vec();
    match out.iter_mut().find(|ci| ci.clock == clock) {
        Some(ci) => ci.interval = intersect(&ci.interval, i)?,
        None => out.push(ClockInterval { clock, interval: *i }),
    }
    Some(out)
}

fn intersect(a: &Interval, b: &Interval) -> Option<Interval> {
    let (lower, lower_closed) = match a.lower.cmp(&b.lower) {
        std::cmp::Ordering::Greater => (a.lower, a.lower_closed),
        std::cmp::Ordering::Less => (b.lower, b.lower_closed),
        std::cmp::Ordering::Equal => (a.lower, a.lower_closed && b.lower_closed),
    };
    let (upper, upper_closed) = match (a.upper, b.upper) {
        (None, None) => (None, false),
        (Some(u), None) => (Some(u), a.upper_closed),
        (None, Some(u)) => (Some(u), b.upper_closed),
        (Some(x), Some(y)) if x < y => (Some(x), a.upper_closed),
        (Some(x), Some(y)) if y < x => (Some(y), b.upper_closed),
        (Some(x), Some(_)) => (Some(x), a.upper_closed && b.upper_closed),
    };
    let i = Interval { lower, lower_closed, upper, upper_closed, span: a.span };
    (!i.is_empty()).then_some(i)
}

/// The non-negative reals outside `i`: at most two intervals.
fn interval_complement(i: &Interval) -> Vec<Interval> {
    let mut out = Vec::new();
    let below =
        Interval { lower: 0, lower_closed: true, upper: Some(i.lower), upper_closed: !i.lower_closed, span: i.span };
    if !below.is_empty() {
        out.push(below);
    }
    if let Some(u) = i.upper {
        out.push(Interval { lower: u, lower_closed: !i.upper_closed, upper: None, upper_closed: false, span: i.span });
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn iv(lower: u32, lc: bool, upper: Option<u32>, uc: bool) -> Interval {
        Interval { lower, lower_closed: lc, upper, upper_closed: uc, span: Span::default() }
    }

    /// A point on a grid of half units, inside `b`?
    fn inside(b: &[ClockInterval], point: &[u32]) -> bool {
        b.iter().all(|ci| {
            let v = point[ci.clock.index()];
            let i = ci.interval;
            let lo = 2 * i.lower;
            let above = if i.lower_closed { v >= lo } else { v > lo };
            let below = match i.upper {
                None => true,
                Some(u) if i.upper_closed => v <= 2 * u,
                Some(u) => v < 2 * u,
            };
            above && below
        })
    }

    #[test]
    fn the_complement_covers_exactly_the_points_no_guard_covers() {
        let g1 = vec![
            ClockInterval { clock: ClockId::new(0), interval: iv(1, true, Some(3), false) },
            ClockInterval { clock: ClockId::new(1), interval: iv(2, false, None, false) },
        ];
        let g2 = vec![ClockInterval { clock: ClockId::new(1), interval: iv(0, true, Some(1), true) }];
        let g3 = vec![ClockInterval { clock: ClockId::new(0), interval: iv(4, true, Some(4), true) }];
        let guards: Vec<&[ClockInterval]> = vec![&g1, &g2, &g3];
        let boxes = complement(&guards);
        for x in 0..14 {
            for y in 0..14 {
                let p = [x, y];
                let covered = guards.iter().any(|g| inside(g, &p));
                let hits = boxes.iter().filter(|b| inside(b, &p)).count();
                assert_eq!(hits, usize::from(!covered), "point ({x}/2, {y}/2): {boxes:?}");
            }
        }
    }

    #[test]
    fn no_guard_leaves_everything_and_a_true_guard_nothing() {
        assert_eq!(complement(&[]), vec![Vec::<ClockInterval>::new()]);
        assert!(complement(&[&[]]).is_empty());
    }
}
