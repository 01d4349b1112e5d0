//! Preemptive synthesis (Göbe 2019, 5.8.5) checked against its definitions on random problems:
//! the supervisor prohibits no uncontrollable event, enforces only events the plant can execute
//! there, and the closed loop never performs an event the specification forbids, where in an
//! enforcing state only controllable events and the enforced one can still happen (definitions
//! 30 and 33; controllable events are never preempted).

use plcsynth::sct::model::{
    self, Cond, Config, EventId, EventInfo, EventKind, Method, Plant, Prohibition, Project, Spec, Transition, NO_ORIGIN,
};
use std::collections::{HashSet, VecDeque};

use plcsynth::rng::Rng;

fn random_project(rng: &mut Rng) -> Project {
    let kinds = [EventKind::Controllable, EventKind::Uncontrollable, EventKind::Enforceable];
    let n_events = 3 + rng.below(4) as usize;
    let events: Vec<EventInfo> = (0..n_events)
        .map(|i| EventInfo { name: format!("e{i}"), kind: kinds[(i + rng.below(3) as usize) % 3] })
        .collect();
    let mut plants = Vec::new();
    for g in 0..1 + rng.below(2) {
        let n = 1 + rng.below(6) as u32;
        let alphabet: Vec<EventId> = (0..n_events).filter(|_| g == 0 || rng.below(2) == 0).map(EventId::new).collect();
        let mut trans = Vec::new();
        for s in 0..n {
            for &e in &alphabet {
                if rng.below(100) < 50 {
                    trans.push(Transition {
                        src: s,
                        event: e,
                        cond: Cond::True,
                        dst: rng.below(n as u64) as u32,
                        origin: NO_ORIGIN,
                    });
                }
            }
        }
        plants.push(Plant {
            name: format!("G{g}"),
            alphabet,
            states: (0..n).map(|i| format!("q{i}")).collect(),
            init: 0,
            trans,
        });
    }
    let hn = 1 + rng.below(4) as u32;
    let (mut ht, mut hp) = (Vec::new(), Vec::new());
    for s in 0..hn {
        for e in 0..n_events as u32 {
            match rng.below(10) {
                0..=2 => ht.push(Transition {
                    src: s,
                    event: EventId::from_raw(e),
                    cond: Cond::True,
                    dst: rng.below(hn as u64) as u32,
                    origin: NO_ORIGIN,
                }),
                3 if events[e as usize].kind == EventKind::Uncontrollable => {
                    hp.push(Prohibition { state: s, event: EventId::from_raw(e), cond: Cond::True, origin: NO_ORIGIN })
                }
                _ => {}
            }
        }
    }
    Project {
        events,
        plants,
        specs: vec![Spec {
            name: "H".into(),
            states: (0..hn).map(|i| format!("h{i}")).collect(),
            init: 0,
            trans: ht,
            prohib: hp,
        }],
    }
}

/// Can every plant do `e` from its state (plants not knowing `e` do not care)? Returns the
/// successor states.
fn plant_step(p: &Project, qs: &[u32], e: EventId) -> Option<Vec<u32>> {
    let mut out = qs.to_vec();
    for (i, g) in p.plants.iter().enumerate() {
        if g.alphabet.contains(&e) {
            out[i] = g.trans.iter().find(|t| t.src == qs[i] && t.event == e)?.dst;
        }
    }
    Some(out)
}

fn check(p: &Project, sup: &model::Supervisor, case: usize) {
    for st in &sup.states {
        assert!(
            st.prohibited.iter().all(|e| p.kind(*e) != EventKind::Uncontrollable),
            "case {case}: uncontrollable prohibition"
        );
    }
    let Some(s0) = sup.init else { return };
    let h = &p.specs[0];
    let start = (s0, p.plants.iter().map(|g| g.init).collect::<Vec<_>>(), h.init);
    let mut seen = HashSet::new();
    let mut queue = VecDeque::from([start.clone()]);
    seen.insert(start);
    while let Some((s, qs, hs)) = queue.pop_front() {
        let st = &sup.states[s as usize];
        if let Some(f) = st.enforced {
            assert!(plant_step(p, &qs, f).is_some(), "case {case}: enforces {f:?} where the plant cannot execute it");
        }
        for e in (0..p.events.len()).map(EventId::new) {
            let kind = p.kind(e);
            let can_happen = match st.enforced {
                Some(f) => kind == EventKind::Controllable || e == f,
                None => kind != EventKind::Enforceable,
            };
            if !can_happen || st.prohibited.contains(&e) {
                continue;
            }
            let Some(qs2) = plant_step(p, &qs, e) else { continue };
            assert!(
                !h.prohib.iter().any(|x| x.state == hs && x.event == e),
                "case {case}: closed loop performs forbidden {} in spec state {hs}",
                p.event_name(e)
            );
            let hs2 = h.trans.iter().find(|t| t.src == hs && t.event == e).map_or(hs, |t| t.dst);
            let s2 = st.transitions.iter().find(|(x, _)| *x == e).map_or(s, |&(_, d)| d);
            let next = (s2, qs2, hs2);
            if seen.insert(next.clone()) {
                queue.push_back(next);
            }
        }
    }
}

#[test]
fn preemptive_supervisors_are_safe_modulo_preemption() {
    let mut rng = Rng::new(0x5EED_0505);
    let mut enforcing = 0;
    let mut realizable = 0;
    for case in 0..400 {
        let p = random_project(&mut rng);
        for method in [Method::Monolithic, Method::Incremental] {
            let sup = model::synthesize(
                &p,
                0,
                &Config { method, preempt: true, minimize: case % 2 == 0, ..Config::default() },
            )
            .unwrap();
            check(&p, &sup, case);
            let plain =
                model::synthesize(&p, 0, &Config { method, preempt: false, minimize: true, ..Config::default() })
                    .unwrap();
            check(&p, &plain, case);
            assert!(plain.enforced_events().is_empty());
            // Preemption never makes a realizable problem unrealizable.
            assert!(!plain.realizable() || sup.realizable(), "case {case}");
            if method == Method::Monolithic {
                enforcing += usize::from(!sup.enforced_events().is_empty());
                realizable += usize::from(sup.realizable());
            }
        }
    }
    assert!(enforcing >= 20 && realizable >= 100, "uninformative: {enforcing} enforcing, {realizable} realizable");
}
