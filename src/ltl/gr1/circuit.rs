//! The controller of a won GR(1) game as a circuit ([`Circuit`]): the monitors' bits are its
//! latches, the pursued justice its goal, and per goal each output is a Boolean function of
//! the bits and the inputs, read off the rings over all positions at once with the priorities
//! of the explicit strategy (`Game::moves`): reach the justice inside the winning region, else
//! descend a ring, else stay in the ring's `X` while the environment misses its justice.
//!
//! The functions are printed as irredundant sums of products (Minato and Morreale's ISOP),
//! with every position outside the winning region (never reached) as a don't-care, so that
//! the function block stays readable. Latches no output, no goal condition and no other such
//! latch reads are dropped.

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
        let z_next = self.next(self.z, work)?;
        let mut goals = Vec::with_capacity(self.js.len());
        let mut isop = Isop { memo: HashMap::new(), products: 0, max_products };
        for l in 0..self.js.len() {
            let (writes, reached) = self.goal(l, z_next, work)?;
            let mut logic = Vec::with_capacity(writes.len());
            for f in writes.into_iter().chain([reached]) {
                let (lower, upper) = self.within(f, self.z, work)?;
                let products = isop.cover(&mut self.d, lower, upper, work)?;
                logic.push(self.logic(&products));
            }
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
    memo: HashMap<(Bdd, Bdd), (Bdd, Vec<Product>)>,
    products: usize,
    max_products: usize,
}

impl Isop {
    /// An irredundant cover of some function `f` with `lower ≤ f ≤ upper`.
    fn cover(&mut self, d: &mut Diagram, lower: Bdd, upper: Bdd, work: &mut Work) -> Result<Vec<Product>, Stop> {
        let (_, products) = self.go(d, lower, upper, work)?;
        self.products += products.len();
        if self.products > self.max_products {
            return Err(Stop::budget(
                Resource::Size,
                format!("the circuit's functions would pass {} products", self.max_products),
            ));
        }
        Ok(products)
    }

    fn go(&mut self, d: &mut Diagram, lower: Bdd, upper: Bdd, work: &mut Work) -> Result<(Bdd, Vec<Product>), Stop> {
        if lower == Bdd::FALSE {
            return Ok((Bdd::FALSE, Vec::new()));
        }
        if upper == Bdd::TRUE {
            return Ok((Bdd::TRUE, vec![Vec::new()]));
        }
        if let Some(done) = self.memo.get(&(lower, upper)) {
            return Ok(done.clone());
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
        self.memo.insert((lower, upper), (f, products.clone()));
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
