//! GR(1) games over deterministic monitors (`--solver gr1`): the symbolic route for
//! specifications whose conjuncts are invariants, responses, `U`/`W`/`R` obligations and
//! `G F` conditions, as SYNTCOMP's arbiter families are (Piterman, Pnueli and Sa'ar 2006;
//! Bloem et al. 2012).
//!
//! Each conjunct becomes an exact deterministic monitor (`monitor`): state bits, safety
//! conditions on a step and justice conditions. The game's positions are valuations of the
//! bits, held as binary decision diagrams (`bdd::diagram`), so neither positions nor letters
//! are enumerated, and no counter bound k is needed: the game is decided outright.
//!
//! **Winning condition.** With `ρe`, `ρs` the safety conditions of assumptions and
//! guarantees and `Je`, `Js` their justices, the controller wins a play exactly when
//! `(G ρe ∧ ∧ GF Je) → (G ρs ∧ ∧ GF Js)`: the implication of the specification itself, not
//! the "strict" reading in which the controller must keep its invariants even after the
//! environment broke its own. So a move that breaks `ρe` wins outright, and a move that
//! breaks `ρs` sets a sticky bit `v` that no controller justice survives: `G ρs` is
//! `G F ¬v`, and after breaking it the controller wins only by keeping the environment from
//! its justices (which a specification such as `G F (i ∧ X ¬o) → G ¬i` allows). With that, the
//! verdict in both directions is exact, and one strategy extraction serves every case.
//!
//! **Fixpoint.** `W = νZ. ∧_l μY. ∨_k νX. CPre((Js_l ∧ ¬v ∧ Z') ∨ Y' ∨ (¬Je_k ∧ X'))`, where
//! `'` is the successor (each bit replaced by its next-state function, `v' = v ∨ ¬ρs`) and
//! `CPre(T) = ∀ inputs ∃ outputs. ¬ρe ∨ T` (under Moore semantics `∃ outputs ∀ inputs`).
//! Justices are conditions on a step (the letter included), which the successor substitution
//! allows directly.
//!
//! **Strategies** are read off the last round's rings per explicit position reached, with
//! a memory of the justice `l` being pursued: reach `Js_l` inside `Z` (then pursue `l + 1`),
//! else descend a ring of `Y_l`, else stay in the ring's `X` while the environment misses
//! its justice `k`.

mod circuit;
mod monitor;

use super::bdd::diagram::{Bdd, Diagram, LevelSet};
use super::bdd::NODES_PER_POSITION;
use super::machine::{Cube, Machine};
use super::spec::{Semantics, SignalId, Spec};
use super::symbolic::machine_from_rows;
use super::{Config, Resource, Stats, Stop, Synthesis, Verdict, Work};
use hashbrown::HashMap;
use monitor::{Justice, Monitors, Prop};

/// Whether `spec` is in the fragment this game decides.
pub(super) fn in_fragment(spec: &Spec) -> bool {
    monitor::monitors(spec, Justice::Before).is_ok()
}

/// Decides `spec` as a GR(1) game, or stops: a specification outside the fragment stops with
/// the clause and the reason.
pub(super) fn synthesize(spec: &Spec, cfg: &Config, work: &mut Work) -> Result<Synthesis, Stop> {
    let monitors = monitor::monitors(spec, Justice::Before).map_err(|outside| {
        let text = outside.clause.formula.to_infix(&|s| spec.name(s).to_string());
        Stop::budget(
            Resource::Size,
            format!(
                "`{text}` is outside the GR(1) fragment ({}); `--solver bdd` plays the bounded games on any specification",
                outside.reason
            ),
        )
    })?;
    let max_nodes = cfg.max_states.saturating_mul(NODES_PER_POSITION);
    let mut game = Game::new(spec, &monitors, max_nodes, work)?;
    let won = game.winning(work)?;
    let mut outcome = Synthesis {
        verdict: if won { Verdict::Realizable } else { Verdict::Unrealizable },
        k: 0,
        controller: None,
        counter_strategy: None,
        circuit: None,
        stats: Stats { gr1: true, monitor_bits: monitors.bits.len(), ..Stats::default() },
        limit: None,
        refinement: Default::default(),
        groups: Vec::new(),
        split: 1,
    };
    // The strategy as a table may be far larger than the game (one state per monitor
    // valuation reached): past its budget the verdict stands without it.
    let share = work.remaining() / 2;
    let built = work.capped(share, |work| {
        let side = if won { Side::Controller } else { Side::Environment(game.losing(work)?) };
        game.strategy(&side, cfg.max_states, work)
    });
    outcome.stats.bdd_nodes = game.d.peak();
    let mut built = match built {
        Ok(built) => Some(built),
        Err(Stop::Cancelled) => return Err(Stop::Cancelled),
        Err(Stop::Budget { message, .. }) => {
            outcome.limit = Some(message);
            None
        }
    };
    if won && (cfg.circuit || built.is_none()) {
        // The controller as a circuit: its size follows the specification's, not the number of
        // monitor valuations reached.
        let share = work.remaining() / 2;
        match work.capped(share, |work| game.circuit(cfg.max_states, work)) {
            Ok(circuit) => outcome.circuit = Some(circuit),
            Err(Stop::Cancelled) => return Err(Stop::Cancelled),
            Err(Stop::Budget { message, .. }) => {
                let table = outcome.limit.take().map(|t| format!("; its table: {t}")).unwrap_or_default();
                outcome.limit = Some(format!("the circuit: {message}{table}"));
            }
        }
        outcome.stats.bdd_nodes = game.d.peak();
    }
    if won && outcome.limit.is_none() && built.is_some() {
        // The same game with each obligation's justice met after the step: its controller is
        // often smaller (the arbiters'), sometimes larger (full_arbiter's); the smaller is kept.
        drop(game);
        let eager = monitor::monitors(spec, Justice::After).expect("the same fragment");
        let share = work.remaining() / 3;
        let other = work.capped(share, |work| {
            let mut game = Game::new(spec, &eager, max_nodes, work)?;
            let won = game.winning(work)?;
            debug_assert!(won, "the justices' two forms decide the same game");
            if !won {
                return Err(Stop::budget(Resource::Size, "the second reading lost (a bug: the first one's is kept)"));
            }
            game.strategy(&Side::Controller, cfg.max_states, work)
        });
        match other {
            Ok(other) if built.as_ref().is_some_and(|b| other.2.states.len() < b.2.states.len()) => built = Some(other),
            Err(Stop::Cancelled) => return Err(Stop::Cancelled),
            _ => {}
        }
    }
    if let Some((visited, raw, machine)) = built {
        outcome.stats.positions = visited;
        outcome.stats.strategy_states_raw = raw;
        if won {
            outcome.controller = Some(machine);
        } else {
            outcome.counter_strategy = Some(machine);
        }
    }
    outcome.stats.work = work.used();
    Ok(outcome)
}

/// One ring of `Y_l`: the positions won by then, and per environment justice `k` the `X`
/// that won them.
struct Ring {
    y: Bdd,
    x: Vec<Bdd>,
}

/// The environment's winning region, ranked for its strategy: per rank `a` (positions it wins
/// with at most `a` changes of the controller justice it starves), the region below and, per
/// controller justice `l`, the positions where it keeps `Js_l` away (`Ȳ`) with, per
/// assumption justice `k`, the rings of its way to `Je_k` inside them.
struct Rank {
    below: Bdd,
    starved: Vec<(Bdd, Vec<Vec<Bdd>>)>,
}

/// Whose strategy is read off: the controller's from the winning region's rings, or the
/// environment's from the ranks of its own region.
enum Side {
    Controller,
    Environment(Vec<Rank>),
}

/// The game in the diagram: its conditions as functions, and the fixpoint's results.
struct Game<'a> {
    spec: &'a Spec,
    monitors: &'a Monitors,
    d: Diagram,
    /// Per signal id, its level; per bit, its level (the next level is the bit's next value).
    signal_level: Vec<u32>,
    bit_level: Vec<u32>,
    inputs: LevelSet,
    outputs: LevelSet,
    moore: bool,
    /// The next-state function of each bit, indexed by the bit's level (`None`: a signal).
    by: Vec<Option<Bdd>>,
    /// `¬ρe`: the steps that win whatever follows.
    broken: Bdd,
    je: Vec<Bdd>,
    /// The controller's justices, each with `¬v`.
    js: Vec<Bdd>,
    /// The winning region and, per controller justice, the rings of the last round.
    z: Bdd,
    rings: Vec<Vec<Ring>>,
    /// Nodes after the last compaction: the next is due at twice as many.
    compacted: usize,
}

impl<'a> Game<'a> {
    fn new(spec: &'a Spec, monitors: &'a Monitors, max_nodes: usize, work: &mut Work) -> Result<Game<'a>, Stop> {
        // The variable order: clause by clause (fewest signals first), its signals then its
        // bits, so that a response's request, grant and open bit sit together.
        // (A counting order rather than a sort: the page's bundle carries no sort instance for it.)
        let widest = monitors.groups.iter().map(|(signals, _)| signals.len()).max().unwrap_or(0);
        let order = (0..=widest).flat_map(|w| monitors.groups.iter().filter(move |(signals, _)| signals.len() == w));
        let mut signal_level = vec![u32::MAX; spec.signals.len()];
        // The monitors' bits, then `v` (the guarantees' invariants broken once).
        let mut bit_level = vec![u32::MAX; monitors.bits.len() + 1];
        let mut level = 0;
        for (signals, bits) in order {
            for s in signals {
                if signal_level[s.index()] == u32::MAX {
                    signal_level[s.index()] = level;
                    level += 1;
                }
            }
            // Each bit is followed by a level for its next value, which only the circuit's
            // reachable positions use (`circuit::reachable`): beside it, the step's relation
            // stays small.
            for &b in bits {
                bit_level[b] = level;
                level += 2;
            }
        }
        for l in signal_level.iter_mut().filter(|l| **l == u32::MAX) {
            *l = level;
            level += 1;
        }
        for l in bit_level.iter_mut().filter(|l| **l == u32::MAX) {
            *l = level;
            level += 2;
        }
        let mut d = Diagram::new(max_nodes);
        let levels = |ids: Vec<SignalId>| ids.into_iter().map(|s| signal_level[s.index()]).collect::<Vec<_>>();
        let inputs = d.level_set(levels(spec.inputs()));
        let outputs = d.level_set(levels(spec.outputs()));
        let mut game = Game {
            spec,
            monitors,
            d,
            signal_level,
            bit_level,
            inputs,
            outputs,
            moore: spec.semantics == Semantics::Moore,
            by: vec![None; level as usize],
            broken: Bdd::FALSE,
            je: Vec::new(),
            js: Vec::new(),
            z: Bdd::TRUE,
            rings: Vec::new(),
            compacted: 0,
        };
        for (b, bit) in monitors.bits.iter().enumerate() {
            let f = game.prop(&bit.next, work)?;
            game.by[game.bit_level[b] as usize] = Some(f);
        }
        let rho_e = game.all(&monitors.env.safety, work)?;
        game.broken = game.d.not(rho_e, work)?;
        let rho_s = game.all(&monitors.sys.safety, work)?;
        let v_level = game.bit_level[monitors.bits.len()];
        let v = game.d.literal(v_level, true)?;
        let kept = game.d.not(v, work)?;
        let broken_s = game.d.not(rho_s, work)?;
        game.by[v_level as usize] = Some(game.d.or(v, broken_s, work)?);
        for (side, out) in [(&monitors.env.justice, &mut game.je), (&monitors.sys.justice, &mut game.js)] {
            let mut made = Vec::new();
            for p in side {
                made.push(game_prop(&mut game.d, &game.signal_level, &game.bit_level, p, work)?);
            }
            if made.is_empty() {
                made.push(Bdd::TRUE);
            }
            *out = made;
        }
        for f in game.js.iter_mut() {
            *f = game.d.and(*f, kept, work)?;
        }
        game.compacted = game.d.len();
        Ok(game)
    }

    fn prop(&mut self, p: &Prop, work: &mut Work) -> Result<Bdd, Stop> {
        game_prop(&mut self.d, &self.signal_level, &self.bit_level, p, work)
    }

    fn all(&mut self, ps: &[Prop], work: &mut Work) -> Result<Bdd, Stop> {
        let mut f = Bdd::TRUE;
        for p in ps {
            let g = self.prop(p, work)?;
            f = self.d.and(f, g, work)?;
        }
        Ok(f)
    }

    /// `f` of the successor position.
    fn next(&mut self, f: Bdd, work: &mut Work) -> Result<Bdd, Stop> {
        self.d.compose(f, &self.by, work)
    }

    /// Quantifies the letter in turn order, the second mover's signals innermost: the
    /// controller's outputs `∃` and the environment's inputs `∀` when `controller_chooses`,
    /// the reverse otherwise.
    fn turn(&mut self, f: Bdd, controller_chooses: bool, work: &mut Work) -> Result<Bdd, Stop> {
        // The second mover's signals are quantified first (innermost).
        let (inner, outer) = if self.moore { (&self.inputs, &self.outputs) } else { (&self.outputs, &self.inputs) };
        // The controller chooses the outputs; the environment the inputs.
        let inner_is_output = !self.moore;
        let inner_exists = inner_is_output == controller_chooses;
        let g = self.d.quantify(f, inner, inner_exists, work)?;
        self.d.quantify(g, outer, !inner_exists, work)
    }

    /// `CPre(T)`: the positions from which the controller makes the step winning or lands in
    /// `T` (a function of the step and the successor).
    fn cpre(&mut self, target: Bdd, work: &mut Work) -> Result<Bdd, Stop> {
        let good = self.d.or(self.broken, target, work)?;
        self.turn(good, true, work)
    }

    /// The initial position: the monitors' initial bits, and `v` clear.
    fn initial(&self) -> Vec<bool> {
        self.monitors.bits.iter().map(|b| b.init).chain([false]).collect()
    }

    /// Solves the game; `true` when the controller wins from the initial position. The rings
    /// of the last round are kept for the strategy.
    fn winning(&mut self, work: &mut Work) -> Result<bool, Stop> {
        let init = self.initial();
        let mut z = Bdd::TRUE;
        loop {
            let mut z_next = self.next(z, work)?;
            let mut new_z = Bdd::TRUE;
            let mut rings = Vec::with_capacity(self.js.len());
            for l in 0..self.js.len() {
                let mut progress = self.d.and(self.js[l], z_next, work)?;
                let mut y = Bdd::FALSE;
                let mut ladder = Vec::new();
                loop {
                    let y_next = self.next(y, work)?;
                    let start = self.d.or(progress, y_next, work)?;
                    let mut ring = Ring { y, x: Vec::with_capacity(self.je.len()) };
                    for k in 0..self.je.len() {
                        let missed = self.d.not(self.je[k], work)?;
                        let mut x = z;
                        loop {
                            let x_next = self.next(x, work)?;
                            let stay = self.d.and(missed, x_next, work)?;
                            let target = self.d.or(start, stay, work)?;
                            let new_x = self.cpre(target, work)?;
                            let new_x = self.d.and(new_x, x, work)?;
                            if new_x == x {
                                break;
                            }
                            x = new_x;
                        }
                        ring.y = self.d.or(ring.y, x, work)?;
                        ring.x.push(x);
                    }
                    if ring.y == y {
                        break;
                    }
                    y = ring.y;
                    ladder.push(ring);
                    work.at.nodes = self.d.len();
                    let live = &mut [&mut z, &mut z_next, &mut y, &mut new_z, &mut progress];
                    self.maybe_compact(live, &mut rings, &mut ladder);
                }
                new_z = self.d.and(new_z, y, work)?;
                rings.push(ladder);
            }
            let done = new_z == z;
            z = new_z;
            self.rings = rings;
            if !self.holds_at(z, &init) {
                return Ok(false);
            }
            if done {
                break;
            }
        }
        self.z = z;
        Ok(true)
    }

    /// Drops the garbage of finished iterations once the table has doubled.
    fn maybe_compact(&mut self, live: &mut [&mut Bdd], rings: &mut [Vec<Ring>], ladder: &mut [Ring]) {
        if self.d.len() < 2 * self.compacted {
            return;
        }
        let mut roots: Vec<Bdd> = Vec::new();
        roots.extend(self.by.iter().flatten());
        roots.extend([self.broken, self.z]);
        roots.extend(self.je.iter().chain(&self.js));
        roots.extend(live.iter().map(|f| **f));
        for ring in rings.iter().flatten().chain(ladder.iter()) {
            roots.push(ring.y);
            roots.extend(&ring.x);
        }
        self.d.compact(&mut roots);
        let mut it = roots.into_iter();
        for f in self.by.iter_mut().flatten() {
            *f = it.next().expect("a root");
        }
        for f in [&mut self.broken, &mut self.z] {
            *f = it.next().expect("a root");
        }
        for f in self.je.iter_mut().chain(self.js.iter_mut()) {
            *f = it.next().expect("a root");
        }
        for f in live.iter_mut() {
            **f = it.next().expect("a root");
        }
        for ring in rings.iter_mut().flatten().chain(ladder.iter_mut()) {
            ring.y = it.next().expect("a root");
            for x in &mut ring.x {
                *x = it.next().expect("a root");
            }
        }
        self.compacted = self.d.len().max(1 << 16);
    }

    /// The winner's strategy from the initial position, as a machine: one state per explicit
    /// position and memory reached (the pursued justice `l`; for the environment also its
    /// own `k`), at most `max_positions` states and rows together. Returns the positions
    /// visited, the states before minimisation and the machine.
    fn strategy(
        &mut self,
        side: &Side,
        max_positions: usize,
        work: &mut Work,
    ) -> Result<(usize, usize, Machine), Stop> {
        let init = self.initial();
        let start = self.memory_at(side, &init, (0, 0));
        let mut members: Vec<(Vec<bool>, Memory)> = vec![(init.clone(), start)];
        let mut member_of: HashMap<Vec<i8>, u32> = HashMap::new();
        member_of.insert(key_of(&init, start), 0);
        let controller = matches!(side, Side::Controller);
        // Per pursued justice, the positions the controller's machine has a state for: a move
        // into one adds no state.
        let mut known = vec![Bdd::FALSE; self.js.len()];
        if controller {
            let cube = self.cube(&init)?;
            known[0] = cube;
        }
        // A position outside the winner's region is reached only after the loser broke its
        // invariants (the environment its assumptions): from there anything goes, and one
        // state writes false for ever.
        let mut sink = None;
        let mut table: Vec<Vec<(Cube, u64, u32)>> = Vec::new();
        let mut rows_made = 0usize;
        let (inputs, outputs) = (self.spec.inputs(), self.spec.outputs());
        let (reads, writes) = if controller { (inputs, outputs) } else { (outputs, inputs) };
        let region = match side {
            Side::Controller => self.z,
            Side::Environment(ranks) => {
                let mut won = Bdd::FALSE;
                for (y, _) in ranks.iter().flat_map(|rank| &rank.starved) {
                    won = self.d.or(won, *y, work)?;
                }
                won
            }
        };
        let mut i = 0;
        while i < members.len() {
            if Some(i as u32) == sink {
                table.push(vec![(Cube::ANY, 0, i as u32)]);
                i += 1;
                continue;
            }
            let (position, memory) = members[i].clone();
            let leaves = match side {
                Side::Controller => self.moves(&position, memory.0, &known, work)?,
                Side::Environment(ranks) => self.counter_moves(ranks, &position, memory, work)?,
            };
            let mut rows = Vec::with_capacity(leaves.len());
            for (read, write, next, progressed) in leaves {
                let memory = match side {
                    Side::Controller if progressed => ((memory.0 + 1) % self.js.len(), 0),
                    Side::Environment(_) if progressed => (memory.0, (memory.1 + 1) % self.je.len()),
                    _ => memory,
                };
                if !self.holds_at(region, &next) {
                    rows.push((
                        read,
                        write,
                        *sink.get_or_insert_with(|| {
                            members.push((Vec::new(), (0, 0)));
                            members.len() as u32 - 1
                        }),
                    ));
                    continue;
                }
                let memory = self.memory_at(side, &next, memory);
                let key = key_of(&next, memory);
                let state = match member_of.get(&key) {
                    Some(&s) => s,
                    None => {
                        if controller {
                            let cube = self.cube(&next)?;
                            known[memory.0] = self.d.or(known[memory.0], cube, work)?;
                        }
                        members.push((next, memory));
                        member_of.insert(key, members.len() as u32 - 1);
                        members.len() as u32 - 1
                    }
                };
                rows.push((read, write, state));
            }
            rows_made += rows.len();
            if members.len() + rows_made > max_positions {
                return Err(Stop::budget(
                    Resource::States,
                    format!(
                        "its table would pass {max_positions} states and rows together (--max-states; a state per \
                         monitor valuation and memory reached, a row per cube of the opponent's signals)"
                    ),
                ));
            }
            table.push(rows);
            i += 1;
        }
        let raw = table.len();
        Ok((members.len(), raw, machine_from_rows(&table, &reads, &writes, controller == self.moore)))
    }

    /// The memory the winner keeps at `position`: the controller's as it is; the
    /// environment's `l` kept while the position is in its rank's `Ȳ_l`, else the first `l`
    /// whose `Ȳ_l` holds it (and `k` from 0).
    fn memory_at(&self, side: &Side, position: &[bool], memory: Memory) -> Memory {
        let Side::Environment(ranks) = side else { return memory };
        let rank = self.rank_of(ranks, position);
        let starved = &ranks[rank].starved;
        if self.holds_at(starved[memory.0].0, position) {
            return memory;
        }
        let l =
            starved.iter().position(|(y, _)| self.holds_at(*y, position)).expect("a ranked position starves some Js");
        (l, 0)
    }

    /// The lowest rank whose `Ȳ`s hold `position`.
    fn rank_of(&self, ranks: &[Rank], position: &[bool]) -> usize {
        ranks
            .iter()
            .position(|rank| rank.starved.iter().any(|(y, _)| self.holds_at(*y, position)))
            .expect("a position the environment wins has a rank")
    }

    fn values(&self, position: &[bool]) -> Vec<Option<bool>> {
        let mut values = vec![None; self.by.len()];
        for (b, &v) in position.iter().enumerate() {
            values[self.bit_level[b] as usize] = Some(v);
        }
        values
    }

    fn holds_at(&self, f: Bdd, position: &[bool]) -> bool {
        let values = self.values(position);
        self.d.eval(f, |level| values[level as usize] == Some(true))
    }

    /// The controller's moves at `(position, l)`: rows of (read cube, written value,
    /// successor position, whether justice `l` was reached on the step).
    /// The position as a cube over the bits.
    fn cube(&mut self, position: &[bool]) -> Result<Bdd, Stop> {
        let literals: Vec<(u32, bool)> = position.iter().enumerate().map(|(b, &v)| (self.bit_level[b], v)).collect();
        self.d.cube(&literals)
    }

    /// The successor functions at a position (`values` fixing its bits): functions of the
    /// letter alone, indexed by level as `by`.
    fn successors_at(&mut self, values: &[Option<bool>], work: &mut Work) -> Result<Vec<Option<Bdd>>, Stop> {
        let mut here = vec![None; self.by.len()];
        for (level, f) in self.by.iter().enumerate() {
            if let Some(f) = f {
                here[level] = Some(self.d.restrict(*f, values, work)?);
            }
        }
        Ok(here)
    }

    fn moves(&mut self, position: &[bool], l: usize, known: &[Bdd], work: &mut Work) -> Result<Vec<Leaf>, Stop> {
        let values = self.values(position);
        let at = |d: &Diagram, f: Bdd| d.eval(f, |level| values[level as usize] == Some(true));
        // The ring of Y_l that won the position, and the X in it.
        let ladder = &self.rings[l];
        let r = ladder.iter().position(|ring| at(&self.d, ring.y)).expect("a winning position is in every Y_l");
        let k = ladder[r].x.iter().position(|&x| at(&self.d, x)).expect("a ring is the union of its X");
        let below = if r == 0 { Bdd::FALSE } else { ladder[r - 1].y };
        let x = ladder[r].x[k];
        let here = self.successors_at(&values, work)?;
        let d = &mut self.d;
        let broken = d.restrict(self.broken, &values, work)?;
        // Reach the pursued justice inside the winning region.
        let js = d.restrict(self.js[l], &values, work)?;
        let z_next = d.compose(self.z, &here, work)?;
        let reach = d.and(js, z_next, work)?;
        let progress = d.or(broken, reach, work)?;
        // Else descend to the ring below, else stay in this ring's X while the environment
        // misses its justice k.
        let below_next = d.compose(below, &here, work)?;
        let x_next = d.compose(x, &here, work)?;
        let missed = d.not(self.je[k], work)?;
        let missed = d.restrict(missed, &values, work)?;
        let stay = d.and(missed, x_next, work)?;
        let fallback = d.or(below_next, stay, work)?;
        let either = d.or(progress, fallback, work)?;
        let options = if self.moore {
            // One output for every input: one that progresses against all, if there is one.
            let always = d.quantify(progress, &self.inputs, false, work)?;
            let some = d.quantify(always, &self.outputs, true, work)?;
            if some == Bdd::FALSE {
                either
            } else {
                progress
            }
        } else {
            // Per input, progress where the input allows it.
            let possible = d.quantify(progress, &self.outputs, true, work)?;
            d.ite(possible, progress, fallback, work)?
        };
        debug_assert_eq!(self.turn(options, true, work)?, Bdd::TRUE, "a ring's position has a move for every input");
        let options = if self.moore {
            options
        } else {
            // Among the good moves for an input, prefer one into a position the machine has
            // (with the memory it would have there): it adds no state, and the machine stays
            // small. Only an order among good moves, so the strategy still wins.
            let d = &mut self.d;
            let next_l = (l + 1) % self.js.len();
            let stays = d.compose(known[l], &here, work)?;
            let advances = d.compose(known[next_l], &here, work)?;
            let into_known = d.ite(progress, advances, stays, work)?;
            let preferred = d.and(options, into_known, work)?;
            let somewhere = d.quantify(preferred, &self.outputs, true, work)?;
            d.ite(somewhere, preferred, options, work)?
        };
        self.resolve(options, progress, &here, position.len(), true, work)
    }

    /// The environment's moves at `(position, (l, k))`: keep the controller from `Js_l`
    /// (except into a lower rank) inside `Ȳ_l`, and go down the rings towards `Je_k`; the
    /// flag says `Je_k` was met on the step.
    fn counter_moves(
        &mut self,
        ranks: &[Rank],
        position: &[bool],
        memory: Memory,
        work: &mut Work,
    ) -> Result<Vec<Leaf>, Stop> {
        let (l, k) = memory;
        let values = self.values(position);
        let rank = &ranks[self.rank_of(ranks, position)];
        let (starved, ladders) = &rank.starved[l];
        let ladder = &ladders[k];
        let at = |d: &Diagram, f: Bdd| d.eval(f, |level| values[level as usize] == Some(true));
        let j = ladder.iter().position(|&x| at(&self.d, x)).expect("a position of Ȳ is in each of its X̄");
        let lower = if j == 0 { Bdd::FALSE } else { ladder[j - 1] };
        let (below, starved) = (rank.below, *starved);
        let here = self.successors_at(&values, work)?;
        let d = &mut self.d;
        let kept = d.not(self.broken, work)?;
        let kept = d.restrict(kept, &values, work)?;
        let met = d.restrict(self.je[k], &values, work)?;
        let reached = d.restrict(self.js[l], &values, work)?;
        let below_next = d.compose(below, &here, work)?;
        let starved_next = d.compose(starved, &here, work)?;
        let lower_next = d.compose(lower, &here, work)?;
        // ¬Js_l ∨ Z̄', inside Ȳ', towards Je_k or a lower ring, keeping ρe.
        let avoided = d.not(reached, work)?;
        let avoided = d.or(avoided, below_next, work)?;
        let onward = d.or(met, lower_next, work)?;
        let good = d.and(avoided, starved_next, work)?;
        let good = d.and(good, onward, work)?;
        let good = d.and(kept, good, work)?;
        debug_assert_eq!(self.turn(good, false, work)?, Bdd::TRUE, "a ranked position has a move against every reply");

        self.resolve(good, met, &here, position.len(), false, work)
    }

    /// The protagonist's signals fixed one at a time in the diagram's order, each as a
    /// function of what it reads: true only where false cannot be completed to an option
    /// (moving first, a constant good against every reply), then the rows from a decision
    /// on the read signals: (read cube, written value, successor position, `flag` on the
    /// step).
    fn resolve(
        &mut self,
        options: Bdd,
        flag: Bdd,
        here: &[Option<Bdd>],
        bits: usize,
        controller: bool,
        work: &mut Work,
    ) -> Result<Vec<Leaf>, Stop> {
        let Game { d, inputs, outputs, spec, signal_level, bit_level, by, moore, .. } = self;
        let (own, opponent) =
            if controller { (spec.outputs(), spec.inputs()) } else { (spec.inputs(), spec.outputs()) };
        let replies = if controller { &*inputs } else { &*outputs };
        let own_first = controller == *moore;
        // The own signals by level, ascending.
        let mut own_levels: Vec<(u32, usize)> = Vec::with_capacity(own.len());
        for level in 0..by.len() as u32 {
            if let Some(i) = own.iter().position(|s| signal_level[s.index()] == level) {
                own_levels.push((level, i));
            }
        }
        let mut options = options;
        let mut writes = vec![Bdd::FALSE; own.len()];
        let mut by_own: Vec<Option<Bdd>> = vec![None; by.len()];
        for (n, &(level, index)) in own_levels.iter().enumerate() {
            let rest = d.level_set(own_levels[n + 1..].iter().map(|&(l, _)| l));
            let off = d.restrict_one(options, level, false, work)?;
            let on = d.restrict_one(options, level, true, work)?;
            let value = if own_first {
                let against_all = d.quantify(off, replies, false, work)?;
                if d.quantify(against_all, &rest, true, work)? == Bdd::FALSE {
                    Bdd::TRUE
                } else {
                    Bdd::FALSE
                }
            } else {
                let possible = d.quantify(off, &rest, true, work)?;
                d.not(possible, work)?
            };
            options = d.ite(value, on, off, work)?;
            writes[index] = value;
            by_own[level as usize] = Some(value);
        }
        let mut functions = writes;
        for &level in bit_level.iter().take(bits) {
            let f = here[level as usize].expect("a bit's successor");
            functions.push(d.compose(f, &by_own, work)?);
        }
        functions.push(d.compose(flag, &by_own, work)?);
        let mut read_index: Vec<Option<usize>> = vec![None; by.len()];
        for (i, s) in opponent.iter().enumerate() {
            read_index[signal_level[s.index()] as usize] = Some(i);
        }
        let mut leaves = Vec::new();
        split(d, &read_index, own.len(), &functions, &mut Vec::new(), &mut leaves, work)?;
        Ok(leaves)
    }

    /// The environment's winning region, the complement of the controller's, ranked:
    /// `μZ̄. ∨_l νȲ. ∧_k μX̄. EPre((¬Js_l ∨ Z̄') ∧ Ȳ' ∧ (Je_k ∨ X̄'))`, with
    /// `EPre(T) = ∃ inputs ∀ outputs. ρe ∧ T` (Moore: `∀ outputs ∃ inputs`).
    fn losing(&mut self, work: &mut Work) -> Result<Vec<Rank>, Stop> {
        let kept = self.d.not(self.broken, work)?;
        let mut z = Bdd::FALSE;
        let mut ranks: Vec<Rank> = Vec::new();
        loop {
            let z_next = self.next(z, work)?;
            let mut grown = z;
            let mut starved = Vec::with_capacity(self.js.len());
            for l in 0..self.js.len() {
                let reached = self.d.not(self.js[l], work)?;
                let avoided = self.d.or(reached, z_next, work)?;
                let mut y = Bdd::TRUE;
                let ladders = loop {
                    let y_next = self.next(y, work)?;
                    let base = self.d.and(avoided, y_next, work)?;
                    let base = self.d.and(kept, base, work)?;
                    let mut all = Bdd::TRUE;
                    let mut ladders = Vec::with_capacity(self.je.len());
                    for k in 0..self.je.len() {
                        let mut x = Bdd::FALSE;
                        let mut ladder = Vec::new();
                        loop {
                            let x_next = self.next(x, work)?;
                            let onward = self.d.or(self.je[k], x_next, work)?;
                            let target = self.d.and(base, onward, work)?;
                            let new_x = self.turn(target, false, work)?;
                            let new_x = self.d.or(new_x, x, work)?;
                            if new_x == x {
                                break;
                            }
                            x = new_x;
                            ladder.push(x);
                        }
                        all = self.d.and(all, x, work)?;
                        ladders.push(ladder);
                    }
                    let new_y = self.d.and(all, y, work)?;
                    if new_y == y {
                        break ladders;
                    }
                    y = new_y;
                };
                grown = self.d.or(grown, y, work)?;
                starved.push((y, ladders));
            }
            work.at.nodes = self.d.len();
            if grown == z {
                return Ok(ranks);
            }
            ranks.push(Rank { below: z, starved });
            z = grown;
        }
    }
}

/// What a strategy state remembers besides its position: the controller justice pursued (or
/// starved, for the environment) and the environment's justice pursued.
type Memory = (usize, usize);

/// The key of a strategy state: the position's bits, then the memory's bytes (the
/// bdd extraction's key type, so that the page's bundle carries one hash table instance).
fn key_of(position: &[bool], memory: Memory) -> Vec<i8> {
    let bits = position.iter().map(|&b| i8::from(b));
    let memory = [memory.0 as u32, memory.1 as u32].into_iter().flat_map(u32::to_le_bytes);
    bits.chain(memory.map(|b| b as i8)).collect()
}

/// A row of a strategy state before the machine: read cube, written value, successor
/// position, whether the pursued justice was met on the step.
type Leaf = (Cube, u64, Vec<bool>, bool);

/// The leaves of the decision on the read signals below `fixed`: where every function (the writes,
/// then the successor bits, then the progress flag) is constant, one row.
fn split(
    d: &mut Diagram,
    read_index: &[Option<usize>],
    writes: usize,
    functions: &[Bdd],
    fixed: &mut Vec<(u32, bool)>,
    leaves: &mut Vec<Leaf>,
    work: &mut Work,
) -> Result<(), Stop> {
    work.spend(1 + functions.len() as u64)?;
    if functions.iter().all(|f| f.is_constant()) {
        let write = (0..writes).filter(|&i| functions[i] == Bdd::TRUE).fold(0u64, |m, i| m | 1 << i);
        let bits = functions.len() - writes - 1;
        let next = (0..bits).map(|b| functions[writes + b] == Bdd::TRUE).collect();
        let mut read = Cube::ANY;
        for &(level, value) in fixed.iter() {
            let index = read_index[level as usize].expect("a read signal");
            read.care |= 1 << index;
            read.value |= u64::from(value) << index;
        }
        leaves.push((read, write, next, functions[functions.len() - 1] == Bdd::TRUE));
        return Ok(());
    }
    let top = functions.iter().map(|&f| d.level(f)).min().expect("a function");
    debug_assert!(read_index[top as usize].is_some(), "only read signals are left");
    for value in [false, true] {
        let cofactors: Vec<Bdd> = functions.iter().map(|&f| d.cofactor_at(f, top, value)).collect();
        fixed.push((top, value));
        split(d, read_index, writes, &cofactors, fixed, leaves, work)?;
        fixed.pop();
    }
    Ok(())
}

/// The function of `p` in the diagram.
fn game_prop(d: &mut Diagram, signal_level: &[u32], bit_level: &[u32], p: &Prop, work: &mut Work) -> Result<Bdd, Stop> {
    Ok(match p {
        Prop::Const(b) => {
            if *b {
                Bdd::TRUE
            } else {
                Bdd::FALSE
            }
        }
        Prop::Signal(s) => d.literal(signal_level[s.index()], true)?,
        Prop::Latch(b) => d.literal(bit_level[*b], true)?,
        Prop::Not(q) => {
            let f = game_prop(d, signal_level, bit_level, q, work)?;
            d.not(f, work)?
        }
        Prop::And(ps) | Prop::Or(ps) => {
            let conjunction = matches!(p, Prop::And(_));
            let mut f = if conjunction { Bdd::TRUE } else { Bdd::FALSE };
            for q in ps {
                let g = game_prop(d, signal_level, bit_level, q, work)?;
                f = if conjunction { d.and(f, g, work)? } else { d.or(f, g, work)? };
            }
            f
        }
    })
}
