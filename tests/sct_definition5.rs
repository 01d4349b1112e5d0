//! Prohibition-style monolithic synthesis (Göbe 2019, 5.8.2) agrees with the classic supremal
//! controllable closed sublanguage (Ramadge–Wonham) on translated inputs.
//!
//! A random prohibition-style specification H is translated into a classic specification H'
//! by definition 5 (self-loops for legal events without a transition, prohibited events left
//! undefined). The plant G is a generator over all events, so it is both a SynTACS plant model
//! and a classic plant. Then the closed loop `G` under the SynTACS supervisor `sys^fix(H@G)`
//! must generate exactly `SupConClosed(G, H')`.

use plcsynth::sct::classic::{self, language_equal, minimize, AutomatonBuilder, ClassicEventId, Events, StateId};
use plcsynth::sct::model::{
    self, Cond, Config, EventId, EventInfo, EventKind, Method, Plant, Prohibition, Project, Spec, Transition, NO_ORIGIN,
};

use plcsynth::rng::Rng;

fn random_project(rng: &mut Rng) -> Project {
    let n_events = 2 + rng.below(5) as usize;
    let ratio = rng.below(101);
    let events: Vec<EventInfo> = (0..n_events)
        .map(|i| EventInfo {
            name: format!("e{i}"),
            kind: if rng.chance(ratio) { EventKind::Controllable } else { EventKind::Uncontrollable },
        })
        .collect();
    let gn = 1 + rng.below(12) as u32;
    let mut gt = Vec::new();
    for s in 0..gn {
        for e in 0..n_events as u32 {
            if rng.chance(55) {
                gt.push(Transition {
                    src: s,
                    event: EventId::from_raw(e),
                    cond: Cond::True,
                    dst: rng.below(gn as u64) as u32,
                    origin: NO_ORIGIN,
                });
            }
        }
    }
    let plant = Plant {
        name: "G".into(),
        alphabet: (0..n_events).map(EventId::new).collect(),
        states: (0..gn).map(|i| format!("g{i}")).collect(),
        init: 0,
        trans: gt,
    };
    let hn = 1 + rng.below(5) as u32;
    let (mut ht, mut hp) = (Vec::new(), Vec::new());
    for s in 0..hn {
        for e in 0..n_events as u32 {
            match rng.below(10) {
                0..=3 => ht.push(Transition {
                    src: s,
                    event: EventId::from_raw(e),
                    cond: Cond::True,
                    dst: rng.below(hn as u64) as u32,
                    origin: NO_ORIGIN,
                }),
                4 => {
                    hp.push(Prohibition { state: s, event: EventId::from_raw(e), cond: Cond::True, origin: NO_ORIGIN })
                }
                _ => {}
            }
        }
    }
    let spec =
        Spec { name: "H".into(), states: (0..hn).map(|i| format!("h{i}")).collect(), init: 0, trans: ht, prohib: hp };
    Project { events, plants: vec![plant], specs: vec![spec] }
}

/// Classic event table mirroring the project's events (enforceable events are not generated).
fn classic_events(p: &Project) -> Events {
    let mut ev = Events::new();
    for e in &p.events {
        ev.intern(&e.name, e.kind == EventKind::Controllable);
    }
    ev
}

fn classic_plant(p: &Project) -> classic::Automaton {
    let g = &p.plants[0];
    let mut b = AutomatonBuilder::new();
    for e in &g.alphabet {
        b.add_event(ClassicEventId::from_raw(e.raw()));
    }
    for s in &g.states {
        b.add_state(s.clone(), true);
    }
    for t in &g.trans {
        b.add_transition(StateId::from_raw(t.src), ClassicEventId::from_raw(t.event.raw()), StateId::from_raw(t.dst));
    }
    b.set_init(StateId::from_raw(g.init));
    b.build().unwrap()
}

/// Definition 5: the dual classic specification of a prohibition-style one.
fn dual(p: &Project) -> classic::Automaton {
    let h = &p.specs[0];
    let mut sigma: Vec<u32> =
        h.trans.iter().map(|t| t.event.raw()).chain(h.prohib.iter().map(|q| q.event.raw())).collect();
    sigma.sort_unstable();
    sigma.dedup();
    let mut b = AutomatonBuilder::new();
    for &e in &sigma {
        b.add_event(ClassicEventId::from_raw(e));
    }
    for s in &h.states {
        b.add_state(s.clone(), true);
    }
    for s in 0..h.states.len() as u32 {
        for &e in &sigma {
            if h.prohib.iter().any(|q| q.state == s && q.event.raw() == e) {
                continue;
            }
            let dst = h.trans.iter().find(|t| t.src == s && t.event.raw() == e).map_or(s, |t| t.dst);
            b.add_transition(StateId::from_raw(s), ClassicEventId::from_raw(e), StateId::from_raw(dst));
        }
    }
    b.set_init(StateId::from_raw(h.init));
    b.build().unwrap()
}

/// The plant under a SynTACS supervisor, as a classic automaton (all states marked).
fn closed_loop(p: &Project, sup: &model::Supervisor) -> classic::Automaton {
    let g = &p.plants[0];
    let mut b = AutomatonBuilder::new();
    for e in &g.alphabet {
        b.add_event(ClassicEventId::from_raw(e.raw()));
    }
    let Some(si) = sup.init else {
        return classic::Automaton::empty(g.alphabet.iter().map(|e| ClassicEventId::from_raw(e.raw())).collect());
    };
    let mut index = std::collections::HashMap::new();
    let mut queue = vec![(si, g.init)];
    index.insert((si, g.init), 0u32);
    b.add_state("0", true);
    let mut k = 0;
    while k < queue.len() {
        let (s, q) = queue[k];
        for t in g.trans.iter().filter(|t| t.src == q) {
            let st = &sup.states[s as usize];
            if st.prohibited.contains(&t.event) {
                continue;
            }
            let s2 = st.transitions.iter().find(|(e, _)| *e == t.event).map_or(s, |&(_, d)| d);
            let next = index.len() as u32;
            let id = *index.entry((s2, t.dst)).or_insert_with(|| {
                queue.push((s2, t.dst));
                next
            });
            if id == next {
                b.add_state(id.to_string(), true);
            }
            b.add_transition(
                StateId::from_raw(k as u32),
                ClassicEventId::from_raw(t.event.raw()),
                StateId::from_raw(id),
            );
        }
        k += 1;
    }
    b.set_init(StateId::new(0));
    b.build().unwrap()
}

#[test]
fn monolithic_prohibition_synthesis_equals_classic_supconclosed() {
    let mut rng = Rng::new(0xD5F1_2019);
    let (mut restricted, mut empty) = (0, 0);
    for case in 0..300 {
        let p = random_project(&mut rng);
        let ev = classic_events(&p);
        let g = classic_plant(&p);
        let h = dual(&p);
        let k = classic::supcon(&g, &h, &ev, false).unwrap();
        for method in [Method::Monolithic, Method::Incremental] {
            let sup = model::synthesize(
                &p,
                0,
                &Config { method, preempt: false, minimize: case % 2 == 0, ..Config::default() },
            )
            .unwrap();
            // Admissibility: the supervisor never disables an uncontrollable event.
            for st in &sup.states {
                assert!(st.prohibited.iter().all(|e| p.kind(*e) == EventKind::Controllable), "case {case}");
            }
            let cl = closed_loop(&p, &sup);
            assert_eq!(sup.realizable(), k.init().is_some(), "case {case} {method:?}: realizability differs");
            assert!(
                language_equal(&minimize(&cl), &minimize(&k)),
                "case {case} {method:?}: closed loop differs from SupConClosed ({} vs {} states)",
                cl.num_states(),
                k.num_states()
            );
            // Controllability of the closed loop with respect to the plant (lemma 4).
            assert!(classic::is_controllable(&g, &cl, &ev), "case {case}");
        }
        if k.init().is_none() {
            empty += 1;
        } else if !language_equal(&minimize(&k), &minimize(&g.with_all_marked())) {
            restricted += 1;
        }
    }
    assert!(
        restricted >= 30 && (10..=200).contains(&empty),
        "uninformative cases: {restricted} restricted, {empty} empty"
    );
}

/// Lemma 9: applying the composition of two plants equals applying them one after the other.
#[test]
fn applying_composed_plants_equals_applying_them_in_turn() {
    let mut rng = Rng::new(0x1E44A9);
    for case in 0..200 {
        let mut p = random_project(&mut rng);
        // A second plant over a random sub-alphabet.
        let mut extra = random_project(&mut rng).plants.remove(0);
        extra.alphabet.retain(|e| e.index() < p.events.len() && rng.chance(60));
        extra.trans.retain(|t| extra.alphabet.contains(&t.event));
        p.plants.push(extra);
        let composed = model::plant_compose(&p, 0, 1);
        let q = Project { events: p.events.clone(), plants: vec![composed], specs: p.specs.clone() };
        let cfg = Config { method: Method::Monolithic, preempt: false, minimize: true, ..Config::default() };
        let s1 = model::synthesize(&p, 0, &cfg).unwrap();
        let s2 = model::synthesize(&q, 0, &cfg).unwrap();
        assert_eq!(s1.realizable(), s2.realizable(), "case {case}");
        // Same behaviour on the physically possible words: compare closed loops with the
        // composed plant as classic automata.
        let g = {
            let c = &q.plants[0];
            let mut b = AutomatonBuilder::new();
            for e in 0..q.events.len() as u32 {
                b.add_event(ClassicEventId::from_raw(e));
            }
            for s in &c.states {
                b.add_state(s.clone(), true);
            }
            for t in &c.trans {
                b.add_transition(
                    StateId::from_raw(t.src),
                    ClassicEventId::from_raw(t.event.raw()),
                    StateId::from_raw(t.dst),
                );
            }
            b.set_init(StateId::new(0));
            b.build().unwrap()
        };
        let pq = Project { plants: vec![q.plants[0].clone()], ..q.clone() };
        let (l1, l2) = (closed_loop(&pq, &s1), closed_loop(&pq, &s2));
        assert!(language_equal(&minimize(&l1), &minimize(&l2)), "case {case}");
        assert!(classic::is_controllable(&g, &l1, &classic_events(&q)), "case {case}");
    }
}
