//! Synthesis (5.8): applying a plant to a synthesis automaton, the synthesis step (with
//! preemption by enforceable events, 5.8.5), monolithic and incremental synthesis, the plants a
//! specification depends on, and the supervisor read off the result.

use super::minimize::minimize_supervisor;
use super::{
    Budget, Cond, Config, Conflict, EventId, EventKind, Method, Project, SProhib, STrans, Spec, SupState, Supervisor,
    SynthAut, SynthError, Transition, NO_ORIGIN,
};

fn state_label(project: &Project, spec: &Spec, a: &SynthAut, s: u32) -> String {
    let t = a.tuple(s);
    let mut parts = vec![spec.states[t[0] as usize].clone()];
    for (i, &p) in a.plants.iter().enumerate() {
        let plant = &project.plants[p as usize];
        parts.push(format!("{}.{}", plant.name, plant.states[t[i + 1] as usize]));
    }
    format!("({})", parts.join(", "))
}

/// A transition under construction: event, condition, target pair, origins.
type NewTrans = (EventId, Cond, (u32, u32), [u32; 2]);

/// Application product `C @ G` (definitions 20, 27 and 32): applies the knowledge of plant
/// `g` to the synthesis automaton `c`. Conflicting transitions that both become unconditional
/// are reported.
fn apply(project: &Project, spec: &Spec, c: &SynthAut, g_id: u32, budget: &mut Budget) -> Result<SynthAut, SynthError> {
    let g = &project.plants[g_id as usize];
    let mut g_alphabet = g.alphabet.clone();
    crate::sort::sort(&mut g_alphabet);
    g_alphabet.dedup();
    let in_g = |e: EventId| g_alphabet.binary_search(&e).is_ok();
    let in_c = |e: EventId| c.plant_alphabet.binary_search(&e).is_ok();
    let mut plant_alphabet: Vec<EventId> = c.plant_alphabet.iter().chain(&g_alphabet).copied().collect();
    crate::sort::sort(&mut plant_alphabet);
    plant_alphabet.dedup();
    // Plant transitions per state, sorted by event.
    let mut g_out: Vec<Vec<&Transition>> = vec![Vec::new(); g.states.len()];
    for t in &g.trans {
        g_out[t.src as usize].push(t);
    }
    for v in &mut g_out {
        crate::sort::sort_by_key(v, |t| t.event);
    }
    let mut plants = c.plants.clone();
    plants.push(g_id);
    let w_old = c.width();
    let mut out = SynthAut {
        plants,
        tuples: Vec::new(),
        plant_alphabet,
        init: None,
        trans: Vec::new(),
        prohib: Vec::new(),
        enforced: Vec::new(),
    };
    let Some(ci) = c.init else { return Ok(out) };
    budget.take_one()?;
    let mut index: hashbrown::HashMap<(u32, u32), u32> = hashbrown::HashMap::new();
    let mut pairs: Vec<(u32, u32)> = vec![(ci, g.init)];
    index.insert((ci, g.init), 0);
    let mut k = 0;
    let mut new_trans: Vec<NewTrans> = Vec::new();
    while k < pairs.len() {
        let (qc, qg) = pairs[k];
        let ctuple = &c.tuples[qc as usize * w_old..(qc as usize + 1) * w_old];
        let lookup = |p: u32| -> Option<u32> {
            if p == g_id {
                return Some(qg);
            }
            c.plants.iter().position(|&x| x == p).map(|i| ctuple[i + 1])
        };
        new_trans.clear();
        let mut new_prohib: Vec<SProhib> = Vec::new();
        let gts = &g_out[qg as usize];
        let g_for = |e: EventId| {
            let lo = gts.partition_point(|t| t.event < e);
            let hi = gts.partition_point(|t| t.event <= e);
            &gts[lo..hi]
        };
        let gamma = c.enforced[qc as usize];
        for tc in &c.trans[qc as usize] {
            let e = tc.event;
            if !in_g(e) {
                let cond = tc.cond.refine(&lookup);
                if cond != Cond::False {
                    new_trans.push((e, cond, (tc.dst, qg), tc.origin));
                }
            } else {
                for tg in g_for(e) {
                    let cond = tc.cond.refine(&lookup).and(tg.cond.refine(&lookup));
                    if cond != Cond::False {
                        let o0 = if tc.origin[0] != NO_ORIGIN { tc.origin[0] } else { tc.origin[1] };
                        new_trans.push((e, cond, (tc.dst, tg.dst), [o0, tg.origin]));
                    }
                }
            }
        }
        for p in &c.prohib[qc as usize] {
            let e = p.event;
            if !in_g(e) {
                let cond = p.cond.refine(&lookup);
                if cond != Cond::False {
                    new_prohib.push(SProhib { event: e, cond, origin: p.origin });
                }
            } else {
                // Kept only where the plant considers the event possible.
                let mut any = Cond::False;
                for tg in g_for(e) {
                    let cond = p.cond.refine(&lookup).and(tg.cond.refine(&lookup));
                    any = any.or(cond);
                }
                if any != Cond::False {
                    new_prohib.push(SProhib { event: e, cond: any, origin: p.origin });
                }
            }
        }
        // Plant moves while the synthesis automaton stays (it has no knowledge of the event).
        for tg in gts.iter() {
            let e = tg.event;
            if in_c(e) {
                continue;
            }
            if let Some(f) = gamma {
                // Preempted events (definition 30) cannot occur here.
                if f != e && project.kind(e) != EventKind::Controllable {
                    continue;
                }
            }
            let mut cond = tg.cond.refine(&lookup);
            for tc in c.trans[qc as usize].iter().filter(|t| t.event == e) {
                cond = cond.and(tc.cond.refine(&lookup).negate());
            }
            for p in c.prohib[qc as usize].iter().filter(|p| p.event == e) {
                cond = cond.and(p.cond.refine(&lookup).negate());
            }
            if cond != Cond::False {
                new_trans.push((e, cond, (qc, tg.dst), [NO_ORIGIN, tg.origin]));
            }
        }
        // Prohibitions dominate: a transition on an unconditionally prohibited event is dropped.
        new_trans.retain(|(e, _, _, _)| !new_prohib.iter().any(|p| p.event == *e && p.cond.is_true()));
        crate::sort::sort_by_key(&mut new_trans, |t| (t.0, t.2));
        new_trans.dedup_by(|b, a| a.0 == b.0 && a.2 == b.2 && a.1.is_true() && b.1.is_true());
        // Determinism: two unconditional transitions on one event.
        for w in new_trans.windows(2) {
            if w[0].0 == w[1].0 && w[0].1.is_true() && w[1].1.is_true() && w[0].2 != w[1].2 {
                let mut origins: Vec<u32> =
                    w[0].3.iter().chain(w[1].3.iter()).copied().filter(|&o| o != NO_ORIGIN).collect();
                crate::sort::sort(&mut origins);
                origins.dedup();
                let mut tup: Vec<u32> = ctuple.to_vec();
                tup.push(qg);
                let tmp = SynthAut {
                    plants: out.plants.clone(),
                    tuples: tup,
                    plant_alphabet: Vec::new(),
                    init: None,
                    trans: vec![Vec::new()],
                    prohib: vec![Vec::new()],
                    enforced: vec![None],
                };
                return Err(SynthError::Conflict(Conflict {
                    event: w[0].0,
                    origins,
                    state: state_label(project, spec, &tmp, 0),
                }));
            }
        }
        crate::sort::sort_by_key(&mut new_prohib, |p| p.event);
        let mut row = Vec::with_capacity(new_trans.len());
        for (e, cond, pair, origin) in new_trans.drain(..) {
            let id = match index.entry(pair) {
                hashbrown::hash_map::Entry::Occupied(o) => *o.get(),
                hashbrown::hash_map::Entry::Vacant(v) => {
                    budget.take_one()?;
                    pairs.push(pair);
                    *v.insert(pairs.len() as u32 - 1)
                }
            };
            row.push(STrans { event: e, cond, dst: id, origin });
        }
        out.tuples.extend_from_slice(ctuple);
        out.tuples.push(qg);
        out.trans.push(row);
        out.prohib.push(new_prohib);
        // γ survives if the plant can do the enforced event here (definition 32).
        let keep_gamma = gamma.filter(|f| !in_g(*f) || !g_for(*f).is_empty());
        out.enforced.push(keep_gamma);
        k += 1;
    }
    out.init = Some(0);
    Ok(out)
}

/// Is a prohibition "uncontrollable" for synthesis? Unresolved conditions count as true
/// (conservative, 5.7.3).
fn has_uncontrollable_prohibition(project: &Project, a: &SynthAut, s: usize) -> bool {
    a.prohib[s].iter().any(|p| project.kind(p.event) == EventKind::Uncontrollable && p.cond != Cond::False)
}

/// One synthesis step: `sys` (definition 21) or, with `preempt`, `sysp` (definition 36).
/// Returns the new automaton and whether anything changed.
pub fn step(project: &Project, a: &SynthAut, preempt: bool) -> (SynthAut, bool) {
    let n = a.num_states();
    let critical: Vec<bool> = (0..n).map(|s| has_uncontrollable_prohibition(project, a, s)).collect();
    let is_enf = |e: EventId| project.kind(e) == EventKind::Enforceable;
    // Q': the largest set where every critical state has an enforceable way into Q'.
    let mut alive = vec![true; n];
    if preempt {
        // Greatest fixpoint: repeatedly drop critical states without a live enforceable exit.
        let mut preds: Vec<Vec<u32>> = vec![Vec::new(); n];
        for s in 0..n {
            for t in &a.trans[s] {
                if is_enf(t.event) && t.cond.is_true() {
                    preds[t.dst as usize].push(s as u32);
                }
            }
        }
        let exits = |s: usize, alive: &[bool]| {
            a.trans[s].iter().any(|t| is_enf(t.event) && t.cond.is_true() && alive[t.dst as usize])
        };
        let mut work: Vec<u32> =
            (0..n as u32).filter(|&s| critical[s as usize] && !exits(s as usize, &alive)).collect();
        for &s in &work {
            alive[s as usize] = false;
        }
        while let Some(s) = work.pop() {
            for &p in &preds[s as usize] {
                if alive[p as usize] && critical[p as usize] && !exits(p as usize, &alive) {
                    alive[p as usize] = false;
                    work.push(p);
                }
            }
        }
    } else {
        for s in 0..n {
            if critical[s] {
                alive[s] = false;
            }
        }
    }
    let mut changed = alive.iter().any(|x| !x);
    let mut b = a.clone();
    for s in 0..n {
        if !alive[s] {
            continue;
        }
        // γ' (definition 36): keep a still valid choice, else choose the smallest event.
        if preempt && critical[s] {
            let valid = a.enforced[s]
                .filter(|f| a.trans[s].iter().any(|t| t.event == *f && t.cond.is_true() && alive[t.dst as usize]));
            let g = valid.or_else(|| {
                a.trans[s]
                    .iter()
                    .find(|t| is_enf(t.event) && t.cond.is_true() && alive[t.dst as usize])
                    .map(|t| t.event)
            });
            if g != a.enforced[s] {
                changed = true;
            }
            b.enforced[s] = g;
        } else if let Some(f) = a.enforced[s] {
            if !a.trans[s].iter().any(|t| t.event == f && alive[t.dst as usize]) {
                b.enforced[s] = None;
                changed = true;
            }
        }
        // Transitions into removed states become prohibitions of their event.
        let mut newp: Vec<SProhib> = Vec::new();
        b.trans[s].retain(|t| {
            if alive[t.dst as usize] {
                true
            } else {
                newp.push(SProhib { event: t.event, cond: Cond::True, origin: t.origin[0] });
                false
            }
        });
        if !newp.is_empty() {
            for p in newp {
                if let Some(q) = b.prohib[s].iter_mut().find(|q| q.event == p.event) {
                    q.cond = Cond::True;
                } else {
                    b.prohib[s].push(p);
                }
            }
            crate::sort::sort_by_key(&mut b.prohib[s], |p| p.event);
        }
    }
    if !changed {
        return (b, false);
    }
    let out = b.restrict(&alive);
    (out, true)
}

/// Synthesises the supervisor for specification `spec_id` within `cfg.max_states`.
pub fn synthesize(project: &Project, spec_id: usize, cfg: &Config) -> Result<Supervisor, SynthError> {
    synthesize_within(project, spec_id, cfg, &mut Budget::new(cfg.max_states, &mut |_| true))
}

/// [`synthesize`] drawing on a caller's budget (which may be shared by several
/// specifications and carries the progress callback); `cfg.max_states` is not consulted.
pub fn synthesize_within(
    project: &Project,
    spec_id: usize,
    cfg: &Config,
    budget: &mut Budget,
) -> Result<Supervisor, SynthError> {
    synthesize_known(project, &Knowledge::new(project), spec_id, cfg, budget)
}

/// Which plants know each event (have it in their alphabet): what incremental synthesis looks
/// up. Built once per run, as it is as large as the project.
pub struct Knowledge {
    knows: Vec<Vec<u32>>,
}

impl Knowledge {
    pub fn new(project: &Project) -> Knowledge {
        let mut knows: Vec<Vec<u32>> = vec![Vec::new(); project.events.len()];
        for (i, p) in project.plants.iter().enumerate() {
            for e in &p.alphabet {
                knows[e.index()].push(i as u32);
            }
        }
        Knowledge { knows }
    }
}

/// [`synthesize_within`] with the project's [`Knowledge`] built by the caller: the work for one
/// specification then depends on its own size and the plants it needs, not on the project's.
pub fn synthesize_known(
    project: &Project,
    knowledge: &Knowledge,
    spec_id: usize,
    cfg: &Config,
    budget: &mut Budget,
) -> Result<Supervisor, SynthError> {
    let spec = &project.specs[spec_id];
    let mut c = SynthAut::from_spec(spec);
    let mut applied: hashbrown::HashSet<u32> = hashbrown::HashSet::new();
    let remaining = |applied: &hashbrown::HashSet<u32>, g: u32| !applied.contains(&g);
    let knows = &knowledge.knows;
    match cfg.method {
        Method::Monolithic => {
            for g in 0..project.plants.len() as u32 {
                c = apply(project, spec, &c, g, budget)?;
            }
            loop {
                let (next, changed) = step(project, &c, cfg.preempt);
                c = next;
                if !changed || c.init.is_none() {
                    break;
                }
            }
        }
        Method::Incremental => loop {
            // Gather plants until none is relevant: those knowing an uncontrollable prohibited
            // event (lemma 18), those knowing an enforceable event offered where preemption may
            // be needed (so that preemption rests on full knowledge, 5.8.5), and those that
            // conditions still refer to (5.7.3).
            loop {
                let mut gather: Vec<u32> =
                    c.unresolved_plants().into_iter().filter(|&p| remaining(&applied, p)).collect();
                for s in 0..c.num_states() {
                    if !has_uncontrollable_prohibition(project, &c, s) {
                        continue;
                    }
                    for p in &c.prohib[s] {
                        if project.kind(p.event) == EventKind::Uncontrollable {
                            gather.extend(knows[p.event.index()].iter().filter(|&&g| remaining(&applied, g)));
                        }
                    }
                    if cfg.preempt {
                        for t in &c.trans[s] {
                            if project.kind(t.event) == EventKind::Enforceable {
                                gather.extend(knows[t.event.index()].iter().filter(|&&g| remaining(&applied, g)));
                            }
                        }
                    }
                }
                crate::sort::sort(&mut gather);
                gather.dedup();
                if gather.is_empty() {
                    break;
                }
                for g in gather {
                    applied.insert(g);
                    c = apply(project, spec, &c, g, budget)?;
                }
            }
            let (next, changed) = step(project, &c, cfg.preempt);
            c = next;
            if !changed || c.init.is_none() {
                break;
            }
        },
    }
    Ok(to_supervisor(project, spec, &c, cfg))
}

/// The plants Åkesson et al.'s modular criterion would compose with a specification (the
/// `Dep` closure of 5.8.3): start from the uncontrollable events the specification mentions,
/// add every plant sharing one of them, then those plants' uncontrollable events, until
/// nothing changes. Incremental synthesis usually needs far fewer; used for comparison.
pub fn dep_closure(project: &Project, spec_id: usize) -> Vec<u32> {
    let spec = &project.specs[spec_id];
    let n = project.events.len();
    let mut events = vec![false; n];
    for e in spec.trans.iter().map(|t| t.event).chain(spec.prohib.iter().map(|p| p.event)) {
        if project.kind(e) == EventKind::Uncontrollable {
            events[e.index()] = true;
        }
    }
    let mut taken = vec![false; project.plants.len()];
    loop {
        let mut changed = false;
        for (i, g) in project.plants.iter().enumerate() {
            if !taken[i] && g.alphabet.iter().any(|e| events[e.index()]) {
                taken[i] = true;
                changed = true;
                for e in &g.alphabet {
                    if project.kind(*e) == EventKind::Uncontrollable {
                        events[e.index()] = true;
                    }
                }
            }
        }
        if !changed {
            break;
        }
    }
    (0..project.plants.len() as u32).filter(|&i| taken[i as usize]).collect()
}

/// Converts a synthesis fixpoint into a supervisor: drops the plant alphabet, explicit
/// self-loops (they mean the same as no transition), preempted prohibitions in enforcing
/// states and enforceable transitions that are not enforced (6.4.2); then minimises.
fn to_supervisor(project: &Project, spec: &Spec, c: &SynthAut, cfg: &Config) -> Supervisor {
    let mut sup = Supervisor {
        name: spec.name.clone(),
        init: c.init,
        states: Vec::new(),
        plants_used: c.plants.iter().map(|&p| project.plants[p as usize].name.clone()).collect(),
    };
    if c.init.is_none() {
        return sup;
    }
    for s in 0..c.num_states() {
        let gamma = c.enforced[s];
        let transitions: Vec<(EventId, u32)> = c.trans[s]
            .iter()
            .filter(|t| t.dst as usize != s)
            .filter(|t| project.kind(t.event) != EventKind::Enforceable || Some(t.event) == gamma)
            .map(|t| (t.event, t.dst))
            .collect();
        let prohibited: Vec<EventId> = c.prohib[s]
            .iter()
            .filter(|p| gamma.is_none() || project.kind(p.event) != EventKind::Uncontrollable)
            .map(|p| p.event)
            .collect();
        let enforced_origin = gamma
            .and_then(|f| c.trans[s].iter().find(|t| t.event == f))
            .map(|t| t.origin.iter().copied().filter(|&o| o != NO_ORIGIN).collect())
            .unwrap_or_default();
        sup.states.push(SupState {
            label: state_label(project, spec, c, s as u32),
            transitions,
            prohibited,
            enforced: gamma,
            enforced_origin,
        });
    }
    if cfg.minimize {
        sup = minimize_supervisor(&sup);
    }
    sup
}
