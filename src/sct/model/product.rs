//! Products: plant composition `G1 || G2` (definitions 17 and 26) and the product of two
//! specifications, each building only its accessible part within the run's budget.

use super::{Budget, Cond, EventId, Plant, Prohibition, Project, Spec, SynthError, Transition};

/// Plant composition `G1 || G2` (definitions 17 and 26): synchronous on shared events, the
/// conditions of each operand refined on the other's state (conditions naming `g1` or `g2`
/// are decided, those naming other plants remain). Only the accessible part is built.
pub fn plant_compose(project: &Project, g1: u32, g2: u32) -> Plant {
    let (a, b) = (&project.plants[g1 as usize], &project.plants[g2 as usize]);
    let n = project.events.len();
    let mut in_a = vec![false; n];
    let mut in_b = vec![false; n];
    a.alphabet.iter().for_each(|e| in_a[e.index()] = true);
    b.alphabet.iter().for_each(|e| in_b[e.index()] = true);
    fn out_of(p: &Plant) -> Vec<Vec<&Transition>> {
        let mut v: Vec<Vec<&Transition>> = vec![Vec::new(); p.states.len()];
        p.trans.iter().for_each(|t| v[t.src as usize].push(t));
        v
    }
    let (ta, tb) = (out_of(a), out_of(b));
    let mut alphabet: Vec<EventId> = a.alphabet.iter().chain(&b.alphabet).copied().collect();
    crate::sort::sort(&mut alphabet);
    alphabet.dedup();
    let mut out =
        Plant { name: format!("{}||{}", a.name, b.name), alphabet, states: Vec::new(), init: 0, trans: Vec::new() };
    let mut index: hashbrown::HashMap<(u32, u32), u32> = hashbrown::HashMap::new();
    let mut pairs = vec![(a.init, b.init)];
    index.insert((a.init, b.init), 0);
    let mut k = 0;
    while k < pairs.len() {
        let (q1, q2) = pairs[k];
        out.states.push(format!("{}|{}", a.states[q1 as usize], b.states[q2 as usize]));
        let lookup = |p: u32| {
            if p == g1 {
                Some(q1)
            } else if p == g2 {
                Some(q2)
            } else {
                None
            }
        };
        let mut moves: Vec<(EventId, Cond, (u32, u32), u32)> = Vec::new();
        for x in &ta[q1 as usize] {
            if !in_b[x.event.index()] {
                moves.push((x.event, x.cond.refine(&lookup), (x.dst, q2), x.origin));
            } else {
                for y in tb[q2 as usize].iter().filter(|y| y.event == x.event) {
                    moves.push((x.event, x.cond.refine(&lookup).and(y.cond.refine(&lookup)), (x.dst, y.dst), x.origin));
                }
            }
        }
        for y in &tb[q2 as usize] {
            if !in_a[y.event.index()] {
                moves.push((y.event, y.cond.refine(&lookup), (q1, y.dst), y.origin));
            }
        }
        push_moves(&mut out.trans, &mut index, &mut pairs, k as u32, moves);
        k += 1;
    }
    out
}

/// Adds the transitions of a product state: each move whose condition can hold goes to the
/// pair it names, numbered on first sight (shared by the plant and specification products).
fn push_moves(
    trans: &mut Vec<Transition>,
    index: &mut hashbrown::HashMap<(u32, u32), u32>,
    pairs: &mut Vec<(u32, u32)>,
    src: u32,
    moves: Vec<(EventId, Cond, (u32, u32), u32)>,
) {
    for (event, cond, pair, origin) in moves {
        if cond == Cond::False {
            continue;
        }
        let next = pairs.len() as u32;
        let dst = *index.entry(pair).or_insert_with(|| {
            pairs.push(pair);
            next
        });
        trans.push(Transition { src, event, cond, dst, origin });
    }
}

/// Specification product `H1 | H2` (definition 6, with conditions): prohibits everything
/// either operand prohibits; an event moves the operands that have a transition for it, and
/// an operand without one stays unless it prohibits the event. Only the accessible part is
/// built. Conditions of competing transitions are combined as in the application product.
/// Every product state is drawn from `budget`.
pub fn spec_product(name: &str, a: &Spec, b: &Spec, budget: &mut Budget) -> Result<Spec, SynthError> {
    fn by_state(h: &Spec) -> (Vec<Vec<&Transition>>, Vec<Vec<&Prohibition>>) {
        let mut t: Vec<Vec<&Transition>> = vec![Vec::new(); h.states.len()];
        let mut p: Vec<Vec<&Prohibition>> = vec![Vec::new(); h.states.len()];
        for x in &h.trans {
            t[x.src as usize].push(x);
        }
        for x in &h.prohib {
            p[x.state as usize].push(x);
        }
        (t, p)
    }
    if a.states.is_empty() || b.states.is_empty() {
        return Ok(Spec { name: name.to_string(), states: Vec::new(), init: 0, trans: Vec::new(), prohib: Vec::new() });
    }
    let (ta, pa) = by_state(a);
    let (tb, pb) = by_state(b);
    let mut index: hashbrown::HashMap<(u32, u32), u32> = hashbrown::HashMap::new();
    let mut pairs = vec![(a.init, b.init)];
    index.insert((a.init, b.init), 0);
    budget.take_one()?;
    let mut out = Spec { name: name.to_string(), states: Vec::new(), init: 0, trans: Vec::new(), prohib: Vec::new() };
    let any = |cs: &mut dyn Iterator<Item = &Cond>| cs.fold(Cond::False, |acc, c| acc.or(c.clone()));
    let mut k = 0;
    while k < pairs.len() {
        let (q1, q2) = pairs[k];
        out.states.push(format!("{}|{}", a.states[q1 as usize], b.states[q2 as usize]));
        let mut evs: Vec<EventId> = ta[q1 as usize]
            .iter()
            .map(|t| t.event)
            .chain(tb[q2 as usize].iter().map(|t| t.event))
            .chain(pa[q1 as usize].iter().map(|p| p.event))
            .chain(pb[q2 as usize].iter().map(|p| p.event))
            .collect();
        crate::sort::sort(&mut evs);
        evs.dedup();
        let mut moves: Vec<(EventId, Cond, (u32, u32), u32)> = Vec::new();
        for e in evs {
            let t1: Vec<&&Transition> = ta[q1 as usize].iter().filter(|t| t.event == e).collect();
            let t2: Vec<&&Transition> = tb[q2 as usize].iter().filter(|t| t.event == e).collect();
            let p1 = any(&mut pa[q1 as usize].iter().filter(|p| p.event == e).map(|p| &p.cond));
            let p2 = any(&mut pb[q2 as usize].iter().filter(|p| p.event == e).map(|p| &p.cond));
            let c1 = any(&mut t1.iter().map(|t| &t.cond));
            let c2 = any(&mut t2.iter().map(|t| &t.cond));
            for x in &t1 {
                for y in &t2 {
                    moves.push((e, x.cond.clone().and(y.cond.clone()), (x.dst, y.dst), x.origin));
                }
                moves.push((
                    e,
                    x.cond.clone().and(c2.clone().negate()).and(p2.clone().negate()),
                    (x.dst, q2),
                    x.origin,
                ));
            }
            for y in &t2 {
                moves.push((
                    e,
                    y.cond.clone().and(c1.clone().negate()).and(p1.clone().negate()),
                    (q1, y.dst),
                    y.origin,
                ));
            }
            for p in pa[q1 as usize].iter().chain(pb[q2 as usize].iter()).filter(|p| p.event == e) {
                out.prohib.push(Prohibition { state: k as u32, ..(*p).clone() });
            }
        }
        let known = pairs.len();
        push_moves(&mut out.trans, &mut index, &mut pairs, k as u32, moves);
        for _ in known..pairs.len() {
            budget.take_one()?;
        }
        k += 1;
    }
    Ok(out)
}
