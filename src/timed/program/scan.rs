//! The controller program of a scan game's winning strategy: code whose every scan reads its
//! inputs, takes one decision and writes, as the scan game's PLC does (`crate::timed::scan`),
//! so that a PLC running it stays inside the game's semantics by construction.
//!
//! The scan game's controller sees the plant's whole state at each read; a PLC sees its input
//! levels (the I/O contract, `Sensors`). The extraction follows the strategy from read to
//! read: between two reads the plant may move in every way the game allows (its reactions, the
//! delivery of the request, time passing), and at the next read the PLC learns only the levels.
//! So the program tracks a *belief*: the read states of the strategy, each with the sensors'
//! memory, that agree with every image read so far. Each belief is one node of the program.
//! Its decision is the strategy's, which must be the same in every state of the belief; where
//! it is not, the belief takes a decision that every state in it may take (one into the winning
//! region, a live one if there is), if the program still keeps the plans progressing
//! (`stalls`); where there is none, the strategy needs to know more than the PLC reads
//! (usually how long it has waited: timers are not part of the observation yet) and no program
//! is built. The successors of a node are the beliefs of
//! the next read, one per image it can read.
//!
//! A read that changed nothing leaves the scan game's PLC quiet until the plant changes; a
//! real PLC reads again every scan, sees the same image and must take the same decision: a
//! state whose idle decision quiets the PLC is its own successor under its image.
//!
//! The program, in the intermediate language: a first `GOTO` to the initial node's decision (or,
//! when the plant moves at once from its initial state, to a dispatch on the first read's image),
//! then per node its *dispatch*, a decision tree of input tests over the levels that tell its
//! successors apart, each leaf a `GOTO` to a successor's decision; then per node its decision,
//! `DO (r)` or nothing, and a `GOTO` back to its dispatch. Every dispatch comes before every
//! decision, so a dispatch reaches a decision within its scan (forward jumps), and a decision
//! returns to a dispatch only with the next scan (a backward jump ends the scan; the lowering's
//! [`Pacing::ScanByScan`](crate::plc::lower::timed::Pacing) makes every request end it too):
//! one read, one decision, one write per scan.
//!
//! State guards (4.2.1) are left out of the scan game: like the zero-time game, it assumes a
//! guard holds whenever the controller checks it, so a check never changes who wins. The
//! program checks them all the same: a decision whose request may enter a guarded condition
//! (at any moment of its scan the strategy lets the plant deliver it) first waits for every such
//! guard, read at the start of the scan (`WAITUNTIL`, or a chain of `IF`s that re-reads all of
//! them the next scan). Under the game's assumption the wait passes in the scan of the read; a
//! guard that does not hold holds the request back, as the zero-time program's wait does.

use super::{CmdId, Condition, Instruction, Program};
use crate::timed::model::{CompId, Game, GuardRule, LocId, MsgId};
use crate::timed::plant::Sensors;
use crate::timed::precompute::SplitGame;
use crate::timed::solve::{EdgeId, EdgeKind, Label, StateId, StateSpace};
use crate::timed::ScanSynthesis;
use std::collections::HashMap;

/// Why no program follows the scan strategy.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum ScanProgramError {
    /// The scan game is not won (or not decided).
    NotImplementable,
    /// Two read states the PLC cannot tell apart by its inputs need different decisions.
    Ambiguous {
        /// The input levels both read (per observed signal).
        image: Vec<bool>,
        /// The two decisions (`None`: no request).
        decisions: [Option<MsgId>; 2],
        /// Decisions that every state of each belief may take were found, but they could keep
        /// the plans from progressing for ever (see [`ScanProgramError::Stalls`]).
        stalls: bool,
    },
    /// The belief construction passed its budget of tracked states.
    Budget { limit: usize },
    /// The scan game without inclusion, which the extraction follows, passed a solver budget.
    ExactBudget,
    /// The caller's progress callback asked to stop.
    Cancelled,
    /// Decisions shared by the states the PLC cannot tell apart could keep the plans from
    /// progressing for ever (within the extraction; [`extract`] reports it as the ambiguity
    /// that made it share decisions, with `stalls` set).
    Stalls,
}

impl ScanProgramError {
    /// The reason in words, naming messages and signals of `game`.
    pub fn text(&self, game: &Game, signals: &[Vec<(MsgId, bool)>]) -> String {
        let decision = |d: &Option<MsgId>| match d {
            Some(r) => format!("send `{}`", game.messages[(*r).index()].name),
            None => "send nothing".to_string(),
        };
        match self {
            ScanProgramError::NotImplementable => "the scan game is not won".into(),
            ScanProgramError::Ambiguous { image, decisions, stalls } => {
                let levels: Vec<String> = signals
                    .iter()
                    .zip(image)
                    .map(|(ms, &level)| {
                        let names: Vec<&str> =
                            ms.iter().map(|&(m, _)| game.messages[m.index()].name.as_str()).collect();
                        format!("{}={}", names.join("/"), u8::from(level))
                    })
                    .collect();
                format!(
                    "the PLC reads the same inputs ({}) in two states where the scan strategy must {} and {}: \
                     the game's controller tells them apart by the plant's clocks, which the PLC does not read{}",
                    if levels.is_empty() { "none".to_string() } else { levels.join(", ") },
                    decision(&decisions[0]),
                    decision(&decisions[1]),
                    if *stalls {
                        "; deciding alike in such states, as every state may, could keep the plans from progressing"
                    } else {
                        ""
                    },
                )
            }
            ScanProgramError::Budget { limit } => {
                format!("following the scan strategy from read to read passed {limit} tracked states")
            }
            ScanProgramError::ExactBudget => {
                "the scan game with a state per zone, whose strategy the code follows, passes the solver's budget"
                    .into()
            }
            ScanProgramError::Cancelled => "cancelled".into(),
            ScanProgramError::Stalls => {
                "the decisions shared by the states the PLC cannot tell apart could keep the plans from progressing"
                    .into()
            }
        }
    }
}

/// One node of a scan program: what the PLC may be in after a read, and what it does there.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Node {
    /// The request sent in the scan of the read, if any.
    pub decision: Option<MsgId>,
    /// The state guards the request may enter the condition of: all must read TRUE first.
    pub guards: Vec<MsgId>,
    /// The nodes of the next read, each with the levels (per observed signal) that lead there.
    pub next: Vec<(Vec<bool>, usize)>,
    /// The read states of the scan game in the belief.
    pub states: usize,
}

/// The program of a scan strategy, node by node; node 0 is the first read, or the PLC before
/// it (see [`ScanProgram::before_first_read`]).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ScanProgram {
    pub nodes: Vec<Node>,
    /// Node 0 is the PLC before its first read (it decides nothing), not the first read.
    pub before_first_read: bool,
    /// The observed signals: per input, its messages and whether each reads it negated.
    pub signals: Vec<Vec<(MsgId, bool)>>,
    /// States visited while following the strategy from read to read.
    pub work: usize,
    /// Whether the decisions come from the whole winning region (each belief taking a
    /// decision all its states share) because the strategy's own split two states the PLC
    /// cannot tell apart.
    pub shared_decisions: bool,
}

/// A read state of the scan game with the sensors' memory on arrival.
type Element = (StateId, Sensors);

/// What follows an element's decision: the read states of the next read, and the state guards
/// whose conditions the decision's request may enter.
#[derive(Clone, Default)]
struct Followed {
    next: Vec<Element>,
    /// Where the extraction checks progress: those of `next` that the plant can reach without a
    /// plan progressing on the way (a quiet PLC's repeated read of the same state is not one).
    calm: Vec<Element>,
    guards: Vec<MsgId>,
}

/// The extraction's view of a solved scan game.
struct Extraction<'a> {
    game: &'a Game,
    space: &'a StateSpace,
    /// Per state: the strategy's decision at a read (`Some(edge)`), `None` elsewhere.
    decision_edge: Vec<Option<EdgeId>>,
    /// `Some`: the space is the whole winning region (the exhaustive search), and a belief's
    /// decision is chosen among the decisions of least goal distance (request selection's rule,
    /// [`super::select`]) that all its states share, these distances per state; `None`: each
    /// state decides as the strategy does.
    distances: Option<Vec<u32>>,
    split: &'a SplitGame,
    /// The scan automaton and its location after an idle read.
    plc: CompId,
    quiet: LocId,
    budget: usize,
    work: usize,
    /// Whether to tell the next reads reached without progress apart (`Followed::calm`).
    track_progress: bool,
    /// What follows every element and decision followed so far (an element recurs in many
    /// beliefs).
    memo: HashMap<(Element, EdgeId), Followed>,
    /// The specification's state guards (the scan game has none).
    guard_rules: &'a [GuardRule],
    /// Called with the states followed so far every [`PROGRESS_EVERY`]; `false` stops.
    keep_going: &'a mut dyn FnMut(usize) -> bool,
}

/// How many followed states between two calls of the progress callback.
const PROGRESS_EVERY: usize = 4096;

impl Extraction<'_> {
    /// The scan automaton's location in state `s`.
    fn plc_location(&self, s: StateId) -> LocId {
        let plc = self.plc.index();
        self.split.units[plc].sublocs[self.space.env(s)[plc].index()].location
    }

    /// The request a decision edge sends (`None`: idle).
    fn request_of(&self, edge: EdgeId) -> Option<MsgId> {
        let roles = self.game.scan.as_ref()?;
        match self.space.edges[edge.index()].label {
            Label::Message { message } => roles.commits[message.index()],
            _ => None,
        }
    }

    /// Whether the PLC decides in state `s`: a read of the strategy (or, in the whole winning
    /// region, any winning read).
    fn is_read(&self, s: StateId) -> bool {
        match &self.distances {
            None => self.decision_edge[s.index()].is_some(),
            Some(_) => self.space.is_winning(s) && self.space.out_edges(s).any(|(_, e)| e.kind == EdgeKind::Request),
        }
    }

    /// The decisions the PLC may take in read state `s`, each with its goal distance: the
    /// strategy's, or every decision into the winning region: the live ones first (least goal
    /// distance first, ties in request selection's order), then those the solver's final cut
    /// left out (`Edge::zeno`). A cut decision stays winning; it was cut because it may close
    /// a cycle without progress in the game, and the program's own cycles are checked for
    /// progress (`stalls`) whatever its decisions are.
    fn options(&self, s: StateId) -> Vec<(u32, EdgeId)> {
        let Some(dist) = &self.distances else {
            return self.decision_edge[s.index()].into_iter().map(|e| (0, e)).collect();
        };
        let mut winning: Vec<(bool, u32, Option<&str>, EdgeId)> = self
            .space
            .out_edges(s)
            .filter(|(_, e)| e.kind == EdgeKind::Request && e.to != StateId::NONE && self.space.is_winning(e.to))
            .map(|(id, e)| {
                let name = self.request_of(id).map(|r| self.game.messages[r.index()].name.as_str());
                (e.zeno, super::select::edge_distance(self.space, dist, id), name, id)
            })
            .collect();
        crate::sort::sort(&mut winning);
        winning.into_iter().map(|o| (o.1, o.3)).collect()
    }

    /// The plant components' locations in state `s` (the scan automaton's among them).
    fn locations(&self, s: StateId) -> Vec<LocId> {
        let env = self.space.env(s);
        (0..self.split.plant_count).map(|u| self.split.units[u].sublocs[env[u].index()].location).collect()
    }

    /// The read states (with the sensors' memory) the plant can bring the PLC to at its next
    /// read after `element`'s decision, and the guards its request may enter.
    fn successors(&mut self, element: &Element, decision: EdgeId) -> Result<Followed, ScanProgramError> {
        let key = (element.clone(), decision);
        if let Some(known) = self.memo.get(&key) {
            return Ok(known.clone());
        }
        let out = self.follow(element, decision)?;
        self.memo.insert(key, out.clone());
        Ok(out)
    }

    /// [`Extraction::successors`], computed.
    fn follow(&mut self, element: &Element, decision: EdgeId) -> Result<Followed, ScanProgramError> {
        let (_, sensors) = element;
        let request = self.request_of(decision);
        let edge = &self.space.edges[decision.index()];
        let (start, progressed) = (edge.to, edge.progress);
        let mut out = Followed::default();
        if self.plc_location(start) == self.quiet {
            out.next.push(element.clone());
        }
        self.reach(start, sensors.clone(), progressed, request, &mut out)?;
        Ok(out)
    }

    /// Adds to `out` the read states the plant can bring the PLC to from `start` (with the
    /// sensors' memory `sensors`; `progressed`: a plan has progressed since the read), and the
    /// guards the delivery of `request` on the way enters.
    fn reach(
        &mut self,
        start: StateId,
        sensors: Sensors,
        progressed: bool,
        request: Option<MsgId>,
        out: &mut Followed,
    ) -> Result<(), ScanProgramError> {
        // Without progress tracking every path counts as progressed: one search per state.
        let progressed = progressed || !self.track_progress;
        // Per `progressed`, the states (with the sensors' memory) seen so far.
        let mut seen: [std::collections::HashSet<Element>; 2] = Default::default();
        let mut stack = vec![(start, sensors, progressed)];
        while let Some((s, sensors, progressed)) = stack.pop() {
            if !seen[usize::from(progressed)].insert((s, sensors.clone())) {
                continue;
            }
            self.work += 1;
            if self.work > self.budget {
                return Err(ScanProgramError::Budget { limit: self.budget });
            }
            if self.work % PROGRESS_EVERY == 0 && !(self.keep_going)(self.work) {
                return Err(ScanProgramError::Cancelled);
            }
            if self.is_read(s) {
                if !progressed {
                    out.calm.push((s, sensors.clone()));
                }
                out.next.push((s, sensors));
                continue;
            }
            for (_, e) in self.space.out_edges(s) {
                if !self.space.is_winning(e.to) {
                    continue;
                }
                match (e.kind, e.label) {
                    (EdgeKind::Reaction, Label::Message { message }) => {
                        if Some(message) == request && !self.guard_rules.is_empty() {
                            // The delivery: the guards of the conditions it enters (4.2.1).
                            let (before, after) = (self.locations(s), self.locations(e.to));
                            for rule in self.guard_rules {
                                if !rule.cond.eval(&before)
                                    && rule.cond.eval(&after)
                                    && !out.guards.contains(&rule.message)
                                {
                                    out.guards.push(rule.message);
                                }
                            }
                        }
                        let info = &self.game.messages[message.index()];
                        let mut next = sensors.clone();
                        let parts = info.sender.into_iter().chain(info.synchronised.iter().copied());
                        next.moved(self.game, message, e.instant, parts);
                        next.forget_unread();
                        stack.push((e.to, next, progressed || e.progress));
                    }
                    (EdgeKind::Delay, _) => stack.push((e.to, sensors.clone(), progressed || e.progress)),
                    _ => {}
                }
            }
        }
        crate::sort::sort(&mut out.guards);
        Ok(())
    }
}

/// The canonical order of a belief's elements.
fn element_order(a: &Element, b: &Element) -> std::cmp::Ordering {
    a.0.cmp(&b.0).then_with(|| a.1.memory().cmp(&b.1.memory()))
}

/// A belief's elements in canonical order, each once.
fn canonical(mut belief: Vec<Element>) -> Vec<Element> {
    crate::sort::sort_by(&mut belief, element_order);
    belief.dedup();
    belief
}

/// Runs one more solve of the scan game for [`extract`], reporting its progress to
/// `keep_going` and stopping it (as cancelled) when that answers `false`.
fn solve_again<T>(
    keep_going: &mut dyn FnMut(usize) -> bool,
    solve: impl FnOnce(&mut crate::search::OnProgress<'_, crate::timed::solve::Stats>) -> T,
) -> Result<T, ScanProgramError> {
    let mut stopped = false;
    let solved = solve(&mut |stats| {
        stopped = stopped || !keep_going(stats.visited);
        !stopped
    });
    if stopped {
        Err(ScanProgramError::Cancelled)
    } else {
        Ok(solved)
    }
}

/// Builds the scan program of a won scan game. `game` is the specification's own game (its
/// message ids are the scan game's first ones); `signals` are the inputs the PLC reads (per
/// input, its messages and whether each reads it negated); `budget` bounds the read states
/// tracked, summed over all beliefs; `keep_going` is called with the states followed so far
/// every few thousand and stops the extraction when it answers `false`.
pub fn extract(
    game: &Game,
    scan: &ScanSynthesis,
    signals: &[Vec<(MsgId, bool)>],
    budget: usize,
    keep_going: &mut dyn FnMut(usize) -> bool,
) -> Result<ScanProgram, ScanProgramError> {
    // A solution with covers (inclusion) is followed as it is first: a cover decides for its
    // larger zone, which wins all of it, and the plant moves it allows there only add states
    // to the beliefs, so a program found this way keeps the plant safe and the plans
    // progressing. The added states can make two states of a belief disagree where their own
    // zones would not: then the game is solved again with a state per zone (two machines at
    // 10 ms follows 11 000 states with its covers, 500 000 without; gear checking needs the
    // game without covers).
    if scan.has_covers() {
        match follow_beliefs(game, scan, signals, budget, false, keep_going) {
            Err(ScanProgramError::Ambiguous { .. } | ScanProgramError::Budget { .. }) => {}
            other => return other,
        }
    }
    let exact = solve_again(keep_going, |progress| scan.exact(game, progress))?;
    let scan = match &exact {
        Some(exact) if matches!(exact.synthesis.solution.outcome, Err(crate::search::Stop::Budget { .. })) => {
            return Err(ScanProgramError::ExactBudget)
        }
        Some(exact) => exact,
        None => scan,
    };
    let ambiguous = match follow_beliefs(game, scan, signals, budget, false, keep_going) {
        Err(ambiguous @ ScanProgramError::Ambiguous { .. }) => ambiguous,
        other => return other,
    };
    // The strategy took different decisions in two states the PLC cannot tell apart. Each
    // belief may instead take a decision that all its states may take (it stays winning), as
    // long as the program still makes the plans progress: first among the decisions the search
    // tried, then in the whole winning region (the exhaustive search, every decision's
    // consequences known).
    let mut stalled = false;
    let mut shared = |scan: &ScanSynthesis, keep_going: &mut dyn FnMut(usize) -> bool| match follow_beliefs(
        game, scan, signals, budget, true, keep_going,
    ) {
        Err(ScanProgramError::Stalls) => {
            stalled = true;
            None
        }
        Err(ScanProgramError::Budget { .. } | ScanProgramError::Ambiguous { .. }) => None,
        other => Some(other),
    };
    if let Some(found) = shared(scan, keep_going) {
        return found;
    }
    let whole = solve_again(keep_going, |progress| scan.exhaustive(game, progress))?;
    if let Some(whole) = whole.filter(|w| w.synthesis.solution.is_realizable()) {
        if let Some(found) = shared(&whole, keep_going) {
            return found;
        }
    }
    match ambiguous {
        ScanProgramError::Ambiguous { image, decisions, .. } => {
            Err(ScanProgramError::Ambiguous { image, decisions, stalls: stalled })
        }
        other => Err(other),
    }
}

/// The belief construction of [`extract`] on the solved scan game `scan`: each state decides as
/// its strategy does, or, with `shared`, each belief takes a winning decision that all its
/// states share (live ones first, then least worst goal distance), and the program is refused
/// ([`ScanProgramError::Stalls`]) if its plays could then go round without a plan progressing.
fn follow_beliefs(
    game: &Game,
    scan: &ScanSynthesis,
    signals: &[Vec<(MsgId, bool)>],
    budget: usize,
    shared: bool,
    keep_going: &mut dyn FnMut(usize) -> bool,
) -> Result<ScanProgram, ScanProgramError> {
    let space = &scan.synthesis.solution.space;
    if !scan.synthesis.solution.is_realizable() || !space.is_winning(space.initial) {
        return Err(ScanProgramError::NotImplementable);
    }
    let roles = scan.game.scan.as_ref().ok_or(ScanProgramError::NotImplementable)?;
    let mut decision_edge = vec![None; space.states.len()];
    let distances = if shared {
        Some(super::select::goal_distances(space))
    } else {
        let strategy = super::select::select(&scan.game, space);
        for &s in &strategy.states {
            if let super::select::Choice::Request(e) = strategy.choice[s.index()] {
                decision_edge[s.index()] = Some(e);
            }
        }
        None
    };
    let mut x = Extraction {
        game: &scan.game,
        space,
        decision_edge,
        distances,
        split: &scan.synthesis.split,
        plc: roles.plc,
        quiet: roles.quiet,
        budget,
        work: 0,
        track_progress: shared,
        memo: HashMap::new(),
        guard_rules: &game.guards,
        keep_going,
    };
    let mut sensors = Sensors::new(game, signals);
    sensors.forget_unread();
    // Node 0 is the first read, or, where the plant moves at once from its initial state (the
    // round table's instant restart and load), the PLC before its first read, whose image
    // picks the node the first scan decides in.
    let before_first_read = !x.is_read(space.initial);
    let mut first = Followed::default();
    let mut beliefs: Vec<Vec<Element>> = vec![Vec::new()];
    let mut index: HashMap<Vec<Element>, usize> = HashMap::new();
    if before_first_read {
        x.reach(space.initial, sensors, true, None, &mut first)?;
    } else {
        beliefs[0].push((space.initial, sensors));
        index.insert(beliefs[0].clone(), 0);
    }
    let mut nodes: Vec<Node> = Vec::new();
    // With `shared`: per belief, the moves of its states to the next read that no plan's
    // progress interrupts (element, next element, the next element's belief).
    let mut calm: Vec<Vec<(usize, usize, usize)>> = Vec::new();
    let mut k = 0;
    while k < beliefs.len() {
        let belief = beliefs[k].clone();
        k += 1;
        let (decision, edges) =
            if k == 1 && before_first_read { (None, Vec::new()) } else { x.shared_decision(&belief)? };
        let mut by_image: Vec<(Vec<bool>, Vec<Element>)> = Vec::new();
        let mut guards: Vec<MsgId> = Vec::new();
        let followed: Vec<Followed> = if k == 1 && before_first_read {
            vec![std::mem::take(&mut first)]
        } else {
            belief.iter().zip(edges).map(|(element, edge)| x.successors(element, edge)).collect::<Result<_, _>>()?
        };
        let mut calm_here: Vec<(usize, Element)> = Vec::new();
        for (i, followed) in followed.into_iter().enumerate() {
            guards.extend(followed.guards);
            calm_here.extend(followed.calm.into_iter().map(|e| (i, e)));
            for next in followed.next {
                let image = next.1.image();
                match by_image.iter_mut().find(|(i, _)| *i == image) {
                    Some((_, group)) => group.push(next),
                    None => by_image.push((image, vec![next])),
                }
            }
        }
        crate::sort::sort_by(&mut by_image, |a, b| a.0.cmp(&b.0));
        let mut next = Vec::new();
        for (image, group) in by_image {
            let group = canonical(group);
            let id = *index.entry(group.clone()).or_insert_with(|| {
                beliefs.push(group);
                beliefs.len() - 1
            });
            next.push((image, id));
        }
        let belief_of = |e: &Element| next.iter().find(|(i, _)| *i == e.1.image()).map(|n| n.1);
        let position = |b: usize, e: &Element| beliefs[b].binary_search_by(|x| element_order(x, e)).ok();
        let moves =
            calm_here.into_iter().filter_map(|(i, e)| belief_of(&e).and_then(|b| Some((i, b, position(b, &e)?))));
        calm.push(moves.collect());
        crate::sort::sort(&mut guards);
        guards.dedup();
        nodes.push(Node { decision, guards, next, states: belief.len() });
    }
    let sizes: Vec<usize> = beliefs.iter().map(Vec::len).collect();
    if shared && stalls(&sizes, &calm, before_first_read) {
        return Err(ScanProgramError::Stalls);
    }
    let nodes = minimise(nodes);
    Ok(ScanProgram { nodes, before_first_read, signals: signals.to_vec(), work: x.work, shared_decisions: shared })
}

/// Whether some play of the program can go round for ever without a plan progressing: a cycle
/// of (belief, state) pairs linked by the moves of `calm` (per belief, whose `sizes` states are
/// numbered in canonical order: the state's number, the next belief and the next state's number
/// there; the first belief's moves are skipped with `before_first_read`, it has no states). The
/// solver makes every live decision that could close a cycle without progress bring the state
/// closer to progress (its final cut, `keep_rank_decreasing`; the zeno memory does the rest), so
/// live decisions a belief shares in place of the strategy's should not stall either; the check
/// costs one walk of the program and does not take that on trust, and it is what rules out a
/// stall for a decision the cut left out. A quiet PLC that reads the same state again is not a
/// move: time passes and the plant changes.
fn stalls(sizes: &[usize], calm: &[Vec<(usize, usize, usize)>], before_first_read: bool) -> bool {
    let mut offsets = Vec::with_capacity(sizes.len());
    let mut total = 0;
    for &size in sizes {
        offsets.push(total);
        total += size;
    }
    let mut graph = petgraph::Graph::<(), ()>::with_capacity(total, 0);
    for _ in 0..total {
        graph.add_node(());
    }
    let mut self_loop = false;
    for (b, moves) in calm.iter().enumerate().skip(usize::from(before_first_read)) {
        for &(i, to, j) in moves {
            let (from, into) = (offsets[b] + i, offsets[to] + j);
            self_loop |= from == into;
            graph.add_edge(petgraph::graph::NodeIndex::new(from), petgraph::graph::NodeIndex::new(into), ());
        }
    }
    self_loop || petgraph::algo::kosaraju_scc(&graph).iter().any(|component| component.len() > 1)
}

/// How a decision shared by a belief ranks, least first: whether some state takes it by a move
/// the solver's final cut left out, and its worst goal distance over the states.
type DecisionCost = (bool, u32);

impl Extraction<'_> {
    /// The decision of a belief (the request, `None` for idle) and, per element, the edge that
    /// takes it. Following the strategy, every element must have the same one. In the whole
    /// winning region, it is the decision every element may take (live in all if there is one)
    /// whose worst goal distance over the elements is least (ties: the first element's order).
    fn shared_decision(&self, belief: &[Element]) -> Result<(Option<MsgId>, Vec<EdgeId>), ScanProgramError> {
        let options: Vec<Vec<(u32, EdgeId)>> = belief.iter().map(|e| self.options(e.0)).collect();
        // Per element, its best edge taking `request`, with that edge's distance.
        let pick = |request: Option<MsgId>| -> Option<Vec<(u32, EdgeId)>> {
            options.iter().map(|o| o.iter().copied().find(|&(_, edge)| self.request_of(edge) == request)).collect()
        };
        let first = options.first().map(Vec::as_slice).unwrap_or_default();
        // A decision live in every state (the solver's final cut kept it) comes before one that
        // some state may take only by a move that cut left out; then the least worst distance.
        let mut best: Option<(DecisionCost, Option<MsgId>, Vec<EdgeId>)> = None;
        for &(_, edge) in first {
            let request = self.request_of(edge);
            if best.as_ref().is_some_and(|b| b.1 == request) {
                continue;
            }
            if let Some(edges) = pick(request) {
                let cut = edges.iter().any(|&(_, e)| self.space.edges[e.index()].zeno);
                let worst = (cut, edges.iter().map(|e| e.0).max().unwrap_or(0));
                if best.as_ref().is_none_or(|b| worst < b.0) {
                    best = Some((worst, request, edges.into_iter().map(|e| e.1).collect()));
                }
            }
        }
        if let Some((_, request, edges)) = best {
            return Ok((request, edges));
        }
        // No decision is shared: name the first element's preferred one and one it lacks.
        let decision = first.first().and_then(|&(_, e)| self.request_of(e));
        let (element, other) = belief
            .iter()
            .zip(&options)
            .find(|(_, o)| !o.iter().any(|&(_, edge)| self.request_of(edge) == decision))
            .map(|(element, o)| (element, o.first().and_then(|&(_, e)| self.request_of(e))))
            .unwrap_or((&belief[0], decision));
        Err(ScanProgramError::Ambiguous { image: element.1.image(), decisions: [decision, other], stalls: false })
    }
}

/// What a node does, up to the current partition: its class and, per image read next, the
/// class it leads to.
type Signature<'n> = (usize, Vec<(&'n [bool], usize)>);

/// Merges the nodes no run can tell apart (the coarsest partition stable under decision and
/// successors by image, refined from the decisions), node 0's class first. Beliefs are sets of
/// game states, and many sets behave alike: the lamp's 10 beliefs are 4 nodes.
fn minimise(nodes: Vec<Node>) -> Vec<Node> {
    let mut class: Vec<usize> = Vec::new();
    let mut decisions: Vec<(Option<MsgId>, &[MsgId])> = Vec::new();
    for node in &nodes {
        let decision = (node.decision, node.guards.as_slice());
        let c = decisions.iter().position(|d| *d == decision).unwrap_or_else(|| {
            decisions.push(decision);
            decisions.len() - 1
        });
        class.push(c);
    }
    loop {
        let mut signatures: HashMap<Signature, usize> = HashMap::new();
        let mut refined = Vec::with_capacity(nodes.len());
        for (k, node) in nodes.iter().enumerate() {
            let next: Vec<(&[bool], usize)> = node.next.iter().map(|(i, c)| (i.as_slice(), class[*c])).collect();
            let fresh = signatures.len();
            refined.push(*signatures.entry((class[k], next)).or_insert(fresh));
        }
        let stable = signatures.len() == class.iter().collect::<std::collections::HashSet<_>>().len();
        class = refined;
        if stable {
            break;
        }
    }
    // Renumber by first occurrence, so that node 0 stays first.
    let mut number: HashMap<usize, usize> = HashMap::new();
    for &c in &class {
        let fresh = number.len();
        number.entry(c).or_insert(fresh);
    }
    let mut merged: Vec<Option<Node>> = vec![None; number.len()];
    for (k, node) in nodes.iter().enumerate() {
        let id = number[&class[k]];
        let next = node.next.iter().map(|(i, c)| (i.clone(), number[&class[*c]])).collect();
        match &mut merged[id] {
            Some(m) => m.states += node.states,
            slot @ None => *slot = Some(Node { next, ..node.clone() }),
        }
    }
    merged.into_iter().flatten().collect()
}

impl ScanProgram {
    /// The program in the intermediate language (see the module's documentation for its shape).
    pub fn program(&self) -> Program {
        let mut program = Program::new();
        let start = program.fresh_id();
        let dispatch: Vec<CmdId> = self.nodes.iter().map(|_| program.fresh_id()).collect();
        let decide: Vec<CmdId> = self.nodes.iter().map(|_| program.fresh_id()).collect();
        let first = if self.before_first_read { dispatch[0] } else { decide[0] };
        program.push_with_id(start, Instruction::Goto { target: first }, 0);
        for (k, node) in self.nodes.iter().enumerate() {
            let entries: Vec<&(Vec<bool>, usize)> = node.next.iter().collect();
            self.tree(&mut program, dispatch[k], &entries, &decide, k);
        }
        for (k, node) in self.nodes.iter().enumerate() {
            match node.decision {
                Some(request) => {
                    let mut label = decide[k];
                    match node.guards.as_slice() {
                        [] => {}
                        &[message] => {
                            let condition = Condition::Message { message };
                            program.push_with_id(label, Instruction::WaitUntil { condition }, 0);
                            label = program.fresh_id();
                        }
                        several => {
                            // Each test passed goes on; one that fails waits for the next scan,
                            // which tests them all again on its image.
                            for &message in several {
                                let next = program.fresh_id();
                                let condition = Condition::Message { message };
                                program.push_with_id(label, Instruction::If { condition, target: next }, 0);
                                program.push(Instruction::Goto { target: decide[k] }, 0);
                                label = next;
                            }
                        }
                    }
                    program.push_with_id(label, Instruction::Do { request }, 0);
                    program.push(Instruction::Goto { target: dispatch[k] }, 0);
                }
                None => program.push_with_id(decide[k], Instruction::Goto { target: dispatch[k] }, 0),
            }
        }
        program
    }

    /// The decision tree that sends each image of `entries` to its node's decision, its first
    /// command taking id `label`; an input is tested only where the entries left lead to
    /// different nodes. A node without successors (the plant cannot move any more) stays.
    fn tree(
        &self,
        program: &mut Program,
        label: CmdId,
        entries: &[&(Vec<bool>, usize)],
        decide: &[CmdId],
        node: usize,
    ) {
        let Some(&&(ref first, child)) = entries.first() else {
            program.push_with_id(label, Instruction::Goto { target: decide[node] }, 0);
            return;
        };
        if entries.iter().all(|e| e.1 == child) {
            program.push_with_id(label, Instruction::Goto { target: decide[child] }, 0);
            return;
        }
        // Entries have distinct images: some input splits them.
        let input = (0..first.len())
            .find(|&i| entries.iter().any(|e| e.0[i] != first[i]))
            .expect("entries with different nodes have different images");
        // `IF (m)` holds when input `input` reads as `m` says: TRUE, or FALSE for `not`.
        let (message, negated) = self.signals[input][0];
        let (yes, no): (Vec<_>, Vec<_>) = entries.iter().partition(|e| e.0[input] != negated);
        let yes_label = program.fresh_id();
        program.push_with_id(
            label,
            Instruction::If { condition: Condition::Message { message }, target: yes_label },
            0,
        );
        let no_label = program.fresh_id();
        self.tree(program, no_label, &no, decide, node);
        self.tree(program, yes_label, &yes, decide, node);
    }
}

#[cfg(test)]
mod tests {
    use super::stalls;

    #[test]
    fn a_cycle_of_moves_without_progress_stalls_and_a_chain_does_not() {
        // Two beliefs, of one state and of two: state 0 of belief 0 moves to state 0 of belief
        // 1 without progress, state 1 of belief 1 to state 0 of belief 1.
        let sizes = [1, 2];
        let chain = vec![vec![(0, 1, 0)], vec![(1, 1, 0)]];
        assert!(!stalls(&sizes, &chain, false), "the chain ends at state 0 of belief 1");
        // State 0 of belief 1 goes back to belief 0: round and round.
        let cycle = vec![vec![(0, 1, 0)], vec![(0, 0, 0)]];
        assert!(stalls(&sizes, &cycle, false));
        // A state that moves to itself.
        assert!(stalls(&sizes, &[vec![], vec![(0, 1, 0)]], false));
        // Before the first read, belief 0 has no states and its moves are skipped.
        assert!(!stalls(&[0, 1], &[vec![(0, 1, 0)], vec![]], true));
    }
}
