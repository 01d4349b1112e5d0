//! Bounded synthesis (Schewe–Finkbeiner 2007, appendix C of the paper): the universal
//! co-Büchi reading of a Büchi automaton, unrolled into a safety game with counters.
//!
//! A position maps every automaton state to the largest number of accepting transitions of any
//! run prefix that ends there (`-1`: no run is there). One round: the player who moves first
//! sets its signals, then the other; all runs advance on the letter. The protagonist — who
//! wants the word rejected by the automaton — loses a round when some counter passes `k` or a
//! run reaches a state that accepts every word. Bounded counters along a play mean no run
//! accepts, so a strategy that wins the safety game for some `k` wins the LTL game. The
//! converse holds for k large enough; the run tries k = 0, 1, … up to a bound.
//!
//! The controller plays this game on the automaton of `¬φ`; the environment plays it on the
//! automaton of `φ`, so that an unrealizable specification is shown by a counter-strategy
//! rather than by a timeout. Both games keep the turn order of the specification's semantics.
//!
//! Positions are compared pointwise: a smaller position is at least as good for the
//! protagonist (its runs are a subset with smaller counters), which lets the strategy
//! extraction (`strategy`) reuse a winning position for every position below it.

use super::antichain::{self, Antichain};
use super::bdd::{self, Played};
use super::strategy::extract_from_antichain;
use super::symbolic::{Halt, SymbolicGame};
use super::translate::Automaton;
use super::{
    translate, Config, Ltl, Progress, Resource, Semantics, SignalId, Solver, Spec, Stats, Stop, Synthesis, Verdict,
    Work,
};
use crate::search::OnProgress;
use hashbrown::HashMap;

/// The successor of a lost round.
const LOST: u32 = u32::MAX;

/// Work the explicit solver may spend on the antichain fixpoint of a won game, for a smaller
/// strategy; past it the explored positions serve.
const EXTRACTION_WORK: u64 = 10_000_000;

/// Up to this many signals the symbolic solver's strategy is extracted as the explicit
/// solver's is (4 096 letters per position at most).
const EXPLICIT_EXTRACTION_SIGNALS: usize = 12;

/// Successor entries (positions × letters) a game may hold: 4 bytes each, so 200 MB.
const MAX_ENTRIES: usize = 50_000_000;

/// An explored bounded game.
struct Game {
    /// Signal masks of the first mover's valuations (index = valuation of `first_signals`).
    first: Vec<u64>,
    /// Signal masks of the second mover's valuations.
    second: Vec<u64>,
    /// Whether the protagonist moves first.
    protagonist_first: bool,
    /// Counter vectors, position 0 initial.
    positions: Vec<Box<[i8]>>,
    /// `succ[(p * first.len() + a) * second.len() + b]`: the next position or [`LOST`].
    succ: Vec<u32>,
    /// Whether the protagonist loses from each position (after [`Game::solve`]).
    lost: Vec<bool>,
}

impl Game {
    /// The maximal winning positions: the winning region is closed downwards within the
    /// explored positions (a position below a winning one wins with the same moves), so these
    /// describe it, as the antichain solver's result does.
    fn maximal_winning(&self) -> Antichain {
        let mut set = Antichain::default();
        for (p, position) in self.positions.iter().enumerate() {
            if !self.lost[p] {
                set.insert(position.clone());
            }
        }
        set
    }

    /// Explores every position reachable from the initial one. `budget` is the number of
    /// positions still allowed in this run; `progress` is told about every 1024 positions.
    fn explore(
        automaton: &Automaton,
        k: u32,
        first: Vec<u64>,
        second: Vec<u64>,
        protagonist_first: bool,
        budget: usize,
        work: &mut Work,
    ) -> Result<Game, Explored> {
        let n = automaton.states.len();
        let k = k as i8;
        let letters = first.len() * second.len();
        let mut init = vec![-1i8; n].into_boxed_slice();
        if !automaton.is_empty() {
            init[automaton.init as usize] = 0;
        }
        let mut positions = vec![init.clone()];
        let mut index: HashMap<Box<[i8]>, u32> = HashMap::new();
        index.insert(init, 0);
        let mut succ = Vec::new();
        let mut next = vec![-1i8; n];
        let mut p = 0;
        while p < positions.len() {
            work.at.positions = positions.len();
            let alive: u64 = positions[p]
                .iter()
                .enumerate()
                .filter(|(_, &c)| c >= 0)
                .map(|(q, _)| automaton.states[q].edges.len() as u64)
                .sum();
            work.spend(letters as u64 * (1 + alive)).map_err(Explored::Stopped)?;
            if positions.len() > budget {
                return Err(Explored::OverBudget);
            }
            if succ.len() + letters > MAX_ENTRIES {
                return Err(Explored::OverBudget);
            }
            for &fa in &first {
                for &fb in &second {
                    if !advance(automaton, k, &positions[p], fa | fb, &mut next) {
                        succ.push(LOST);
                        continue;
                    }
                    let id = match index.get(next.as_slice()) {
                        Some(&id) => id,
                        None => {
                            let key: Box<[i8]> = next.clone().into_boxed_slice();
                            let id = positions.len() as u32;
                            positions.push(key.clone());
                            index.insert(key, id);
                            id
                        }
                    };
                    succ.push(id);
                }
            }
            p += 1;
        }
        let lost = vec![false; positions.len()];
        Ok(Game { first, second, protagonist_first, positions, succ, lost })
    }

    /// Marks the positions the protagonist loses: the least fixpoint of "the opponent can force
    /// a lost round or a lost position", by counting per position the options left.
    fn solve(&mut self) {
        let (l1, l2) = (self.first.len(), self.second.len());
        let n = self.positions.len();
        // Per (position, first-mover valuation): the second mover's choices that do not lose
        // for the protagonist (protagonist second), or whether the valuation is still safe
        // (protagonist first: a flag, 1 or 0).
        let mut alive = vec![0u32; n * l1];
        let mut options = vec![0u32; n];
        let mut preds: Vec<Vec<u32>> = vec![Vec::new(); n];
        for p in 0..n {
            for a in 0..l1 {
                let row = &self.succ[(p * l1 + a) * l2..(p * l1 + a + 1) * l2];
                let good = row.iter().filter(|&&q| q != LOST).count() as u32;
                alive[p * l1 + a] = if self.protagonist_first { u32::from(good == l2 as u32) } else { good };
                options[p] += u32::from(alive[p * l1 + a] > 0);
                for &q in row.iter().filter(|&&q| q != LOST) {
                    preds[q as usize].push((p * l1 + a) as u32);
                }
            }
        }
        let mut stack = Vec::new();
        for (p, &left) in options.iter().enumerate() {
            let loses = if self.protagonist_first { left == 0 } else { left < l1 as u32 };
            if loses {
                self.lost[p] = true;
                stack.push(p as u32);
            }
        }
        while let Some(q) = stack.pop() {
            for &pa in &preds[q as usize] {
                let p = pa as usize / l1;
                if self.lost[p] || alive[pa as usize] == 0 {
                    continue;
                }
                alive[pa as usize] = if self.protagonist_first { 0 } else { alive[pa as usize] - 1 };
                if alive[pa as usize] == 0 {
                    options[p] -= 1;
                    let loses = !self.protagonist_first || options[p] == 0;
                    if loses {
                        self.lost[p] = true;
                        stack.push(p as u32);
                    }
                }
            }
        }
    }
}

/// One round from `position` on `letter`: the counters of every run after it in `next`, or
/// `false` when the protagonist loses the round (a counter past `k`, or a run reaching a state
/// that accepts every word).
pub(super) fn advance(automaton: &Automaton, k: i8, position: &[i8], letter: u64, next: &mut [i8]) -> bool {
    next.fill(-1);
    for (q, &c) in position.iter().enumerate() {
        if c < 0 {
            continue;
        }
        for e in automaton.states[q].edges.iter().filter(|e| e.enabled(letter)) {
            let count = c + i8::from(e.accepting);
            if count > k || automaton.states[e.to as usize].universal {
                return false;
            }
            let slot = &mut next[e.to as usize];
            *slot = (*slot).max(count);
        }
    }
    true
}

enum Explored {
    OverBudget,
    Stopped(Stop),
}

/// The valuations of `signals` as signal masks: entry `v` sets signal `signals[i]` when bit
/// `i` of `v` is set.
fn valuations(signals: &[SignalId]) -> Vec<u64> {
    (0..1u64 << signals.len())
        .map(|v| signals.iter().enumerate().filter(|(i, _)| v >> i & 1 == 1).fold(0, |m, (_, s)| m | 1 << s.0))
        .collect()
}

pub fn synthesize(spec: &Spec, cfg: &Config, progress: &mut OnProgress<'_, Progress>) -> Result<Synthesis, Stop> {
    let signals = spec.signals.len();
    let letters_symbolic = matches!(cfg.solver, Solver::Symbolic | Solver::Bdd | Solver::Gr1);
    if letters_symbolic && signals > 63 {
        return Err(Stop::budget(
            Resource::Size,
            format!("{signals} signals: the symbolic games hold a letter in 64 bits"),
        ));
    }
    if !letters_symbolic && signals > cfg.max_signals.min(63) {
        // A specification in the GR(1) fragment is best served by that game.
        let gr1 = if super::gr1::in_fragment(spec) {
            "it is in the GR(1) fragment, which `--solver gr1` decides without a bound; "
        } else {
            ""
        };
        return Err(Stop::budget(
            Resource::Size,
            format!(
                "{signals} signals: the explicit games enumerate 2^{signals} letters per position, and the limit is {} \
                 ({gr1}the symbolic and bdd solvers do not enumerate letters: `--solver symbolic` or `bdd`; or split \
                 the specification into parts with fewer signals)",
                cfg.max_signals.min(63)
            ),
        ));
    }
    if cfg.solver == Solver::Gr1 {
        return decide_gr1(spec, cfg, progress);
    }
    let name = |s: SignalId| spec.name(s).to_string();
    let formula = spec.formula();
    let mut work = Work::new(cfg.max_work, progress);
    // Each player's automaton within half of what is left: the dual of a large conjunction
    // (the environment's, a disjunction of eventualities) can grow exponentially where the
    // controller's stays small, and losing it should cost only the environment's game.
    let translate_for = |formula: &Ltl, work: &mut Work| {
        let share = work.remaining() / 2;
        work.capped(share, |work| translate::translate_within(formula, &name, cfg.max_automaton_states, work))
    };
    let against = translate_for(&Ltl::not(formula.clone()), &mut work);
    let towards = translate_for(&formula, &mut work);
    let (against, towards) = match (against, towards) {
        (Err(stop), Err(_)) => return Err(stop),
        (Err(Stop::Cancelled), _) | (_, Err(Stop::Cancelled)) => return Err(Stop::Cancelled),
        pair => pair,
    };
    // A player whose game outgrew its share of the budgets plays no more; the other goes on, so
    // that an exploding game of the environment does not hide a controller, nor the reverse.
    let mut given_up: [Option<String>; 2] = [None, None];
    for (side, automaton) in [&against, &towards].into_iter().enumerate() {
        if let Err(Stop::Budget { message, .. }) = automaton {
            let player = if side == 0 { "the controller's" } else { "the environment's" };
            given_up[side] = Some(format!("{player} automaton: {message}"));
        }
    }
    let (against, towards) = (against.ok(), towards.ok());
    let (inputs, outputs) = (spec.inputs(), spec.outputs());
    let controller_first = spec.semantics == Semantics::Moore;
    let (first_signals, second_signals) = if controller_first { (&outputs, &inputs) } else { (&inputs, &outputs) };
    // The symbolic solvers never enumerate the valuations.
    let (first, second) = match letters_symbolic {
        true => (Vec::new(), Vec::new()),
        false => (valuations(first_signals), valuations(second_signals)),
    };
    let mut stats = Stats {
        automaton_states: against.as_ref().map_or(0, |a| a.states.len()),
        dual_automaton_states: towards.as_ref().map_or(0, |a| a.states.len()),
        ..Stats::default()
    };
    let max_k = cfg.max_k.min(100);
    let mut positions = 0usize;
    let mut decided_up_to = None;
    for k in 0..=max_k {
        // The controller's game, then the environment's, each on the automaton its opponent
        // wants accepted.
        for (side, controller) in [(0, true), (1, false)] {
            let automaton = if controller { &against } else { &towards };
            let Some(automaton) = automaton.as_ref().filter(|_| given_up[side].is_none()) else {
                continue;
            };
            work.at.k = k;
            let game = Play {
                automaton,
                k,
                first: &first,
                second: &second,
                first_signals,
                second_signals,
                protagonist_first: controller == controller_first,
                reads: if controller { &inputs } else { &outputs },
                writes: if controller { &outputs } else { &inputs },
                max_positions: cfg.max_states.saturating_sub(positions),
                max_states: cfg.max_states,
            };
            let share = work.remaining() / 3 * 2;
            match work.capped(share, |work| game.play(cfg.solver, work)) {
                Ok(Played { positions: built, nodes, strategy: won }) => {
                    positions += built;
                    stats.bdd_nodes = stats.bdd_nodes.max(nodes);
                    if let Some((raw, machine)) = won {
                        stats.positions = positions;
                        stats.work = work.used();
                        stats.strategy_states_raw = raw;
                        let verdict = if controller { Verdict::Realizable } else { Verdict::Unrealizable };
                        return Ok(Synthesis {
                            verdict,
                            k,
                            controller: controller.then(|| machine.clone()),
                            counter_strategy: (!controller).then_some(machine),
                            circuit: None,
                            stats,
                            limit: None,
                            refinement: Default::default(),
                            groups: Vec::new(),
                            split: 1,
                        });
                    }
                }
                Err(Stop::Cancelled) => return Err(Stop::Cancelled),
                Err(Stop::Budget { message: limit, .. }) => {
                    let player = if controller { "the controller's" } else { "the environment's" };
                    given_up[side] = Some(format!("{player} game at k = {k}: {limit}"));
                }
            }
        }
        if let [Some(a), Some(b)] = &given_up {
            stats.positions = positions;
            stats.work = work.used();
            return Ok(unknown(decided_up_to.unwrap_or(0), stats, format!("{a}; {b}")));
        }
        if given_up.iter().all(Option::is_none) {
            decided_up_to = Some(k);
        }
    }
    stats.positions = positions;
    stats.work = work.used();
    let limit = match given_up.iter().flatten().next() {
        Some(gave_up) => format!("{gave_up}; and the other player wins no game up to k = {max_k} (--max-k)"),
        None => format!("neither player wins with counters bounded by k = {max_k} (--max-k)"),
    };
    Ok(unknown(max_k, stats, limit))
}

/// `spec` as a GR(1) game (`gr1`), with its own budget meter.
fn decide_gr1(spec: &Spec, cfg: &Config, progress: &mut OnProgress<'_, Progress>) -> Result<Synthesis, Stop> {
    let mut work = Work::new(cfg.max_work, progress);
    super::gr1::synthesize(spec, cfg, &mut work)
}

/// One bounded game of one player.
struct Play<'a> {
    automaton: &'a Automaton,
    k: u32,
    first: &'a [u64],
    second: &'a [u64],
    /// The first mover's signals and the second's (the symbolic solver's diagram order).
    first_signals: &'a [SignalId],
    second_signals: &'a [SignalId],
    protagonist_first: bool,
    /// The protagonist's signals and the opponent's, for its strategy.
    reads: &'a [SignalId],
    writes: &'a [SignalId],
    /// Positions (or antichain elements) this game may build, and the run's whole budget.
    max_positions: usize,
    max_states: usize,
}

impl Play<'_> {
    /// Solves the game: the positions built, and the protagonist's strategy if it wins (with
    /// its size before minimisation). A budget stop ends only this game.
    fn play(&self, solver: Solver, work: &mut Work) -> Result<Played, Stop> {
        let (k, automaton) = (self.k, self.automaton);
        let played = |positions, strategy| Played { positions, nodes: 0, strategy };
        let winning = match solver {
            Solver::Gr1 => unreachable!("`synthesize` hands a gr1 run over before any bounded game"),
            Solver::Bdd => {
                let game = bdd::Game {
                    automaton,
                    k,
                    first: self.first_signals,
                    second: self.second_signals,
                    protagonist_first: self.protagonist_first,
                    reads: self.reads,
                    writes: self.writes,
                    max_nodes: self.max_states.saturating_mul(bdd::NODES_PER_POSITION),
                    max_positions: self.max_positions,
                };
                return bdd::play(&game, work);
            }
            Solver::Symbolic => {
                let explored = SymbolicGame::explore(
                    automaton,
                    k,
                    self.first_signals,
                    self.second_signals,
                    self.protagonist_first,
                    self.max_positions,
                    work,
                );
                let mut game = match explored {
                    Ok(game) => game,
                    Err(Halt::Stopped(stop)) => return Err(stop),
                    Err(Halt::OverBudget) => {
                        return Err(Stop::budget(
                            Resource::States,
                            position_budget(k, self.max_positions, self.max_states),
                        ))
                    }
                };
                game.solve();
                let built = game.positions();
                if !game.won() {
                    return Ok(played(built, None));
                }
                let signals = self.first_signals.len() + self.second_signals.len();
                if signals > EXPLICIT_EXTRACTION_SIGNALS {
                    return Ok(played(built, Some(game.strategy(self.reads, self.writes, self.protagonist_first))));
                }
                // Few signals: the letters are cheap to enumerate, and the strategy is extracted
                // as the explicit solver's is, over the maximal winning positions (those of the
                // whole game when affordable, else the explored ones): smaller machines than
                // the diagram's rows give.
                let (first, second) = (valuations(self.first_signals), valuations(self.second_signals));
                let explicit = Play { first: &first, second: &second, ..*self };
                let winning = match work.capped(EXTRACTION_WORK, |work| explicit.fixpoint(work)) {
                    Ok(winning) => winning,
                    Err(Stop::Cancelled) => return Err(Stop::Cancelled),
                    Err(Stop::Budget { .. }) => game.maximal_winning(),
                };
                let strategy = extract_from_antichain(
                    automaton,
                    k,
                    &winning,
                    &first,
                    &second,
                    self.protagonist_first,
                    self.reads,
                    self.writes,
                );
                return Ok(played(built, Some(strategy)));
            }
            Solver::Antichain => {
                let winning = self.fixpoint(work)?;
                let built = winning.elements.len();
                if !winning.contains(&self.initial()) {
                    return Ok(played(built, None));
                }
                (built, winning)
            }
            Solver::Explicit => {
                let explored = Game::explore(
                    automaton,
                    k,
                    self.first.to_vec(),
                    self.second.to_vec(),
                    self.protagonist_first,
                    self.max_positions,
                    work,
                );
                let mut game = match explored {
                    Ok(game) => game,
                    Err(Explored::Stopped(stop)) => return Err(stop),
                    Err(Explored::OverBudget) => {
                        return Err(Stop::budget(
                            Resource::States,
                            position_budget(k, self.max_positions, self.max_states),
                        ))
                    }
                };
                game.solve();
                let built = game.positions.len();
                if game.lost[0] {
                    return Ok(played(built, None));
                }
                // The strategy is read off the maximal winning positions. Those of the whole
                // game (the antichain fixpoint) lie higher than the explored ones and give
                // smaller machines, so they are computed when affordable.
                match work.capped(EXTRACTION_WORK, |work| self.fixpoint(work)) {
                    Ok(winning) => (built, winning),
                    Err(Stop::Cancelled) => return Err(Stop::Cancelled),
                    Err(Stop::Budget { .. }) => (built, game.maximal_winning()),
                }
            }
        };
        let (built, winning) = winning;
        let strategy = extract_from_antichain(
            automaton,
            k,
            &winning,
            self.first,
            self.second,
            self.protagonist_first,
            self.reads,
            self.writes,
        );
        Ok(played(built, Some(strategy)))
    }

    fn fixpoint(&self, work: &mut Work) -> Result<Antichain, Stop> {
        antichain::solve(
            self.automaton,
            self.k,
            self.first,
            self.second,
            self.protagonist_first,
            self.max_positions,
            work,
        )
    }

    fn initial(&self) -> Vec<i8> {
        let mut init = vec![-1i8; self.automaton.states.len()];
        if !self.automaton.is_empty() {
            init[self.automaton.init as usize] = 0;
        }
        init
    }
}

/// The message of a run that needed more positions than `budget` (of `max_states`) at `k`.
pub(super) fn position_budget(k: u32, budget: usize, max_states: usize) -> String {
    format!("the game at k = {k} needs more than the {budget} positions left of the budget ({max_states} in all, --max-states)")
}

fn unknown(k: u32, stats: Stats, limit: String) -> Synthesis {
    Synthesis {
        verdict: Verdict::Unknown,
        k,
        controller: None,
        counter_strategy: None,
        circuit: None,
        stats,
        limit: Some(limit),
        refinement: Default::default(),
        groups: Vec::new(),
        split: 1,
    }
}
