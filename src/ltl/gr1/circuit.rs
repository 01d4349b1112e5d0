//! The controller of a won GR(1) game as a circuit ([`Circuit`]): the monitors' bits are its
//! latches, the pursued justice its goal, and per goal each output is a Boolean function of
//! the bits and the inputs, read off the rings over all positions at once with the priorities
//! of the explicit strategy (`Game::moves`): reach the justice inside the winning region, else
//! descend a ring, else stay in the ring's `X` while the environment misses its justice.
//!
//! The functions are printed as irredundant sums of products (Minato and Morreale's ISOP),
//! with every position outside the winning region as a don't-care, then again with every
//! position the circuit does not reach (or reaches only after the environment broke an
//! assumption), so that the function block stays readable. Latches no output, no goal
//! condition and no other such latch reads are dropped.

use super::{Game, Prop};
use crate::ltl::bdd::diagram::{Bdd, Diagram};
use crate::ltl::circuit::{Circuit, Goal, Latch, Logic};
use crate::ltl::{Resource, Stop, Work};
use hashbrown::HashMap;

/// A product of literals: (level, value).
type Product = Vec<(u32, bool)>;

impl Game<'_> {
    /// The controller as a circuit, from the winning region and the rings of the last round.
    /// Stops when its functions would pass `max_products` products in all.
    pub(super) fn circuit(&mut self, max_products: usize, work: &mut Work) -> Result<Circuit, Stop> {
        // What the fixpoint and the table left behind goes first: only the game and its rings stay.
        let mut rings = std::mem::take(&mut self.rings);
        self.compacted = 0;
        self.maybe_compact(&mut [], &mut rings, &mut []);
        self.rings = rings;
        let z_next = self.next(self.z, work)?;
        let mut exact = Vec::with_capacity(self.js.len());
        for l in 0..self.js.len() {
            let (writes, reached) = self.goal(l, z_next, work)?;
            exact.push(writes.into_iter().chain([reached]).collect::<Vec<_>>());
        }
        // First simplified within the winning region, which every play keeps until the
        // environment breaks an assumption; then, where the positions that circuit reaches can
        // be computed within a share of the work left, within those (on the arbiters far
        // fewer: most combinations of open requests never occur under the circuit's grants).
        let mut isop = Isop::new(max_products);
        let winning = vec![self.z; exact.len()];
        let (simple, mut products) = match self.simplified(&exact, &winning, &mut isop, work) {
            Ok((simple, products)) => (simple, Ok(products)),
            Err(Stop::Cancelled) => return Err(Stop::Cancelled),
            // Too large within the winning region: within the reachable positions it may not be.
            Err(stop) => (exact, Err(stop)),
        };
        let share = work.remaining() / 4;
        let reached = work.capped(share, |work| {
            let functions: Vec<(Vec<Bdd>, Bdd)> =
                simple.iter().map(|fs| (fs[..fs.len() - 1].to_vec(), fs[fs.len() - 1])).collect();
            let reached = self.reachable(&functions, work)?;
            let mut isop = Isop::new(max_products);
            self.simplified(&simple, &reached, &mut isop, work)
        });
        match reached {
            Ok((_, tighter)) => products = Ok(tighter),
            Err(Stop::Cancelled) => return Err(Stop::Cancelled),
            Err(Stop::Budget { .. }) => {}
        }
        let products = products?;
        let mut goals = Vec::with_capacity(self.js.len());
        for (l, mut logic) in products.into_iter().enumerate() {
            let reached = logic.pop().expect("the goal's condition");
            let comment = match self.monitors.sys.labels.get(l) {
                Some(label) => format!("pursue {label}"),
                None => "keep the guarantees' invariants".to_string(),
            };
            goals.push(Goal { comment, writes: logic, reached });
        }
        let mut latches: Vec<Latch> = self
            .monitors
            .bits
            .iter()
            .map(|b| Latch { name: b.name.clone(), comment: b.comment.clone(), init: b.init, next: b.next.clone() })
            .collect();
        let v = latches.len();
        latches.push(Latch {
            name: "broken".into(),
            comment: "a guarantee's invariant was broken once".into(),
            init: false,
            next: Prop::or(vec![Prop::Latch(v), Prop::negated(Prop::and(self.monitors.sys.safety.clone()))]),
        });
        let (inputs, outputs) = (self.spec.inputs(), self.spec.outputs());
        Ok(cone(Circuit { reads: inputs, writes: outputs, moves_first: self.moore, latches, goals }))
    }

    /// The outputs while justice `l` is pursued, as functions of the bits and the inputs
    /// (of the bits alone under Moore semantics), and when `l` is reached.
    fn goal(&mut self, l: usize, z_next: Bdd, work: &mut Work) -> Result<(Vec<Bdd>, Bdd), Stop> {
        let d = &mut self.d;
        let reach = d.and(self.js[l], z_next, work)?;
        let progress = d.or(self.broken, reach, work)?;
        // Per ring, the positions it adds, and their moves: down a ring, or stay in the first
        // X that holds the position while the environment misses that X's justice.
        let mut fallback = Bdd::FALSE;
        let mut below = Bdd::FALSE;
        let ladder: Vec<(Bdd, Vec<Bdd>)> = self.rings[l].iter().map(|r| (r.y, r.x.clone())).collect();
        for (y, xs) in ladder {
            let below_next = self.next(below, work)?;
            let mut moves = below_next;
            let mut earlier = Bdd::FALSE;
            for (k, &x) in xs.iter().enumerate() {
                let x_next = self.next(x, work)?;
                let d = &mut self.d;
                let first = d.not(earlier, work)?;
                let first = d.and(x, first, work)?;
                let missed = d.not(self.je[k], work)?;
                let stay = d.and(missed, x_next, work)?;
                let stay = d.and(first, stay, work)?;
                moves = d.or(moves, stay, work)?;
                earlier = d.or(earlier, x, work)?;
            }
            let d = &mut self.d;
            let new = d.not(below, work)?;
            let new = d.and(y, new, work)?;
            let moves = d.and(new, moves, work)?;
            fallback = d.or(fallback, moves, work)?;
            below = y;
        }
        let d = &mut self.d;
        let options = if self.moore {
            let always = d.quantify(progress, &self.inputs, false, work)?;
            let can = d.quantify(always, &self.outputs, true, work)?;
            let either = d.or(progress, fallback, work)?;
            d.ite(can, progress, either, work)?
        } else {
            let possible = d.quantify(progress, &self.outputs, true, work)?;
            d.ite(possible, progress, fallback, work)?
        };
        // The outputs fixed one at a time in level order, each true only where false cannot be
        // completed to an option (moving first: against every input).
        let outputs = self.spec.outputs();
        let mut own: Vec<(u32, usize)> = Vec::with_capacity(outputs.len());
        for level in 0..self.by.len() as u32 {
            if let Some(i) = outputs.iter().position(|s| self.signal_level[s.index()] == level) {
                own.push((level, i));
            }
        }
        let mut options = options;
        let mut writes = vec![Bdd::FALSE; outputs.len()];
        let mut by_own: Vec<Option<Bdd>> = vec![None; self.by.len()];
        for (n, &(level, index)) in own.iter().enumerate() {
            let d = &mut self.d;
            let rest = d.level_set(own[n + 1..].iter().map(|&(l, _)| l));
            let off = d.restrict_one(options, level, false, work)?;
            let on = d.restrict_one(options, level, true, work)?;
            let against_all = if self.moore { d.quantify(off, &self.inputs, false, work)? } else { off };
            let possible = d.quantify(against_all, &rest, true, work)?;
            let value = d.not(possible, work)?;
            options = d.ite(value, on, off, work)?;
            writes[index] = value;
            by_own[level as usize] = Some(value);
        }
        let reached = self.d.compose(progress, &by_own, work)?;
        Ok((writes, reached))
    }

    /// Per goal, each function simplified to an irredundant sum of products that agrees with it
    /// on the goal's `care` positions: the sums' functions and the sums as `Logic`.
    #[allow(clippy::type_complexity)]
    fn simplified(
        &mut self,
        functions: &[Vec<Bdd>],
        care: &[Bdd],
        isop: &mut Isop,
        work: &mut Work,
    ) -> Result<(Vec<Vec<Bdd>>, Vec<Vec<Logic>>), Stop> {
        let mut simple = Vec::with_capacity(functions.len());
        let mut logic = Vec::with_capacity(functions.len());
        for (fs, &care) in functions.iter().zip(care) {
            let mut bdds = Vec::with_capacity(fs.len());
            let mut sums = Vec::with_capacity(fs.len());
            for &f in fs {
                let (lower, upper) = self.within(f, care, work)?;
                let (g, products) = isop.cover(&mut self.d, lower, upper, work)?;
                bdds.push(g);
                sums.push(self.logic(&products));
            }
            simple.push(bdds);
            logic.push(sums);
        }
        Ok((simple, logic))
    }

    /// The winning positions the controller reaches from the initial one, per goal pursued,
    /// when each goal's outputs and advance are `goals` (functions of the bits and inputs): a
    /// forward fixpoint of images through a relation to the bits' next values (each the level
    /// after its bit). A move leaves the winning region only by breaking an assumption, so
    /// the circuit may do anything on the positions left out.
    fn reachable(&mut self, goals: &[(Vec<Bdd>, Bdd)], work: &mut Work) -> Result<Vec<Bdd>, Stop> {
        let bits = self.monitors.bits.len() + 1;
        let primed = |game: &Self, b: usize| game.bit_level[b] + 1;
        let outputs = self.spec.outputs();
        let mut quantified: Vec<u32> = self.bit_level.clone();
        quantified.extend(self.signal_level.iter().copied());
        let unprimed = self.d.level_set(quantified);
        let mut rename: Vec<Option<Bdd>> = vec![None; self.by.len()];
        for b in 0..bits {
            rename[primed(self, b) as usize] = Some(self.d.literal(self.bit_level[b], true)?);
        }
        // Per goal, the step as a relation of the bits, inputs and outputs to the next bits:
        // each output equal to its function, each next bit to its next-state function.
        let mut next_bits = Bdd::TRUE;
        for b in (0..bits).rev() {
            let next = self.by[self.bit_level[b] as usize].expect("a bit's successor");
            let primed = self.d.literal(primed(self, b), true)?;
            let same = self.equal(primed, next, work)?;
            next_bits = self.d.and(next_bits, same, work)?;
        }
        let mut relations = Vec::with_capacity(goals.len());
        for (writes, _) in goals {
            let mut relation = next_bits;
            for (s, &w) in outputs.iter().zip(writes) {
                let output = self.d.literal(self.signal_level[s.index()], true)?;
                let same = self.equal(output, w, work)?;
                relation = self.d.and(relation, same, work)?;
            }
            relations.push(relation);
        }
        let initial = self.initial();
        let mut reached = vec![Bdd::FALSE; goals.len()];
        reached[0] = self.cube(&initial)?;
        let mut frontier = reached.clone();
        while frontier.iter().any(|&f| f != Bdd::FALSE) {
            let mut found = vec![Bdd::FALSE; goals.len()];
            for l in 0..goals.len() {
                if frontier[l] == Bdd::FALSE {
                    continue;
                }
                let advance = goals[l].1;
                let stay = self.d.not(advance, work)?;
                for (condition, to) in [(stay, l), (advance, (l + 1) % goals.len())] {
                    let from = self.d.and(frontier[l], condition, work)?;
                    let step = self.d.and(from, relations[l], work)?;
                    let image = self.d.quantify(step, &unprimed, true, work)?;
                    let image = self.d.compose(image, &rename, work)?;
                    found[to] = self.d.or(found[to], image, work)?;
                }
            }
            for l in 0..goals.len() {
                // Outside the winning region only after the environment broke an assumption:
                // from there on nothing the circuit does matters.
                let kept = self.d.and(found[l], self.z, work)?;
                let old = self.d.not(reached[l], work)?;
                frontier[l] = self.d.and(kept, old, work)?;
                reached[l] = self.d.or(reached[l], kept, work)?;
            }
        }
        Ok(reached)
    }

    /// `f ↔ g`.
    fn equal(&mut self, f: Bdd, g: Bdd, work: &mut Work) -> Result<Bdd, Stop> {
        let not_g = self.d.not(g, work)?;
        self.d.ite(f, g, not_g, work)
    }

    /// The interval of functions that agree with `f` on `care`: `[f ∧ care, f ∨ ¬care]`.
    fn within(&mut self, f: Bdd, care: Bdd, work: &mut Work) -> Result<(Bdd, Bdd), Stop> {
        let lower = self.d.and(f, care, work)?;
        let outside = self.d.not(care, work)?;
        let upper = self.d.or(f, outside, work)?;
        Ok((lower, upper))
    }

    /// A sum of products over the game's levels as a function of latches (the monitors' bits,
    /// then `v`) and signals.
    fn logic(&self, products: &[Product]) -> Logic {
        let term = |level: u32| match self.signal_level.iter().position(|&l| l == level) {
            Some(s) => Prop::Signal(crate::ltl::SignalId(s as u32)),
            None => Prop::Latch(self.bit_level.iter().position(|&l| l == level).expect("a bit's level")),
        };
        Logic::or(
            products
                .iter()
                .map(|p| {
                    Logic::and(
                        p.iter()
                            .map(|&(level, value)| if value { term(level) } else { Logic::negated(term(level)) })
                            .collect(),
                    )
                })
                .collect(),
        )
    }
}

/// Minato–Morreale's irredundant sum of products of a function between two bounds, memoised
/// per pair of bounds.
struct Isop {
    /// The pair of bounds (as `key_of` bytes: the page's bundle then carries no hash table
    /// instance for it) to its result in `done`.
    memo: HashMap<Vec<i8>, u32>,
    done: Vec<(Bdd, Vec<Product>)>,
    products: usize,
    max_products: usize,
}

impl Isop {
    fn new(max_products: usize) -> Isop {
        Isop { memo: HashMap::new(), done: Vec::new(), products: 0, max_products }
    }

    fn key(lower: Bdd, upper: Bdd) -> Vec<i8> {
        [lower.index(), upper.index()].into_iter().flat_map(u32::to_le_bytes).map(|b| b as i8).collect()
    }

    /// An irredundant cover of some function `f` with `lower ≤ f ≤ upper`.
    fn cover(&mut self, d: &mut Diagram, lower: Bdd, upper: Bdd, work: &mut Work) -> Result<(Bdd, Vec<Product>), Stop> {
        let (f, products) = self.go(d, lower, upper, work)?;
        self.products += products.len();
        if self.products > self.max_products {
            return Err(Stop::budget(
                Resource::Size,
                format!("the circuit's functions would pass {} products", self.max_products),
            ));
        }
        Ok((f, products))
    }

    fn go(&mut self, d: &mut Diagram, lower: Bdd, upper: Bdd, work: &mut Work) -> Result<(Bdd, Vec<Product>), Stop> {
        if lower == Bdd::FALSE {
            return Ok((Bdd::FALSE, Vec::new()));
        }
        if upper == Bdd::TRUE {
            return Ok((Bdd::TRUE, vec![Vec::new()]));
        }
        if let Some(&i) = self.memo.get(&Isop::key(lower, upper)) {
            return Ok(self.done[i as usize].clone());
        }
        work.spend(1)?;
        let level = d.level(lower).min(d.level(upper));
        let (l0, l1) = (d.cofactor_at(lower, level, false), d.cofactor_at(lower, level, true));
        let (u0, u1) = (d.cofactor_at(upper, level, false), d.cofactor_at(upper, level, true));
        // Products that need the literal: the lower bound's part the other side cannot take.
        let not_u1 = d.not(u1, work)?;
        let only0 = d.and(l0, not_u1, work)?;
        let (f0, c0) = self.go(d, only0, u0, work)?;
        let not_u0 = d.not(u0, work)?;
        let only1 = d.and(l1, not_u0, work)?;
        let (f1, c1) = self.go(d, only1, u1, work)?;
        // The rest, without the literal.
        let not_f0 = d.not(f0, work)?;
        let rest0 = d.and(l0, not_f0, work)?;
        let not_f1 = d.not(f1, work)?;
        let rest1 = d.and(l1, not_f1, work)?;
        let rest = d.or(rest0, rest1, work)?;
        let both = d.and(u0, u1, work)?;
        let (fr, cr) = self.go(d, rest, both, work)?;
        let x = d.literal(level, true)?;
        let with0 = d.ite(x, Bdd::FALSE, f0, work)?;
        let with1 = d.ite(x, f1, Bdd::FALSE, work)?;
        let f = d.or(with0, with1, work)?;
        let f = d.or(f, fr, work)?;
        let mut products = Vec::with_capacity(c0.len() + c1.len() + cr.len());
        for (cubes, literal) in [(c0, Some(false)), (c1, Some(true)), (cr, None)] {
            for mut p in cubes {
                if let Some(value) = literal {
                    p.insert(0, (level, value));
                }
                products.push(p);
            }
        }
        if products.len() > self.max_products {
            return Err(Stop::budget(
                Resource::Size,
                format!("the circuit's functions would pass {} products", self.max_products),
            ));
        }
        self.memo.insert(Isop::key(lower, upper), self.done.len() as u32);
        self.done.push((f, products.clone()));
        Ok((f, products))
    }
}

/// `circuit` without the latches that nothing it writes or decides depends on, renumbered in
/// their order.
fn cone(circuit: Circuit) -> Circuit {
    let mut needed = vec![false; circuit.latches.len()];
    let mut todo = Vec::new();
    for g in &circuit.goals {
        for f in g.writes.iter().chain([&g.reached]) {
            f.latches(&mut todo);
        }
    }
    while let Some(b) = todo.pop() {
        if !needed[b] {
            needed[b] = true;
            circuit.latches[b].next.latches(&mut todo);
        }
    }
    let mut rename = vec![usize::MAX; needed.len()];
    let mut kept = 0;
    for (b, &n) in needed.iter().enumerate() {
        if n {
            rename[b] = kept;
            kept += 1;
        }
    }
    let latches = circuit
        .latches
        .iter()
        .zip(&needed)
        .filter(|(_, &n)| n)
        .map(|(l, _)| Latch { next: l.next.renamed(&rename), ..l.clone() })
        .collect();
    let goals = circuit
        .goals
        .iter()
        .map(|g| Goal {
            comment: g.comment.clone(),
            writes: g.writes.iter().map(|f| f.renamed(&rename)).collect(),
            reached: g.reached.renamed(&rename),
        })
        .collect();
    Circuit { latches, goals, ..circuit }
}
