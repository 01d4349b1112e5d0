//! The reference executor of the runtime framework (`sct::Runtime`), run as the PLC runs it:
//! the tank stories of Göbe 2019 (figures 5.7, 5.8 and the timer of 6.1.3), and every example
//! driven by a plant that follows its models and a random controller, checked against what
//! supervision promises.

use plcsynth::rng::Rng;
use plcsynth::sct::model::{Config, EventId, EventKind, Project, Transition, Truth};
use plcsynth::sct::{compile, synthesize, CycleInput, EventOutcome, Loaded, Runtime, SupervisorReport, Synthesis};

fn example(name: &str) -> (Loaded, Vec<SupervisorReport>) {
    let path = format!("{}/examples/sct/{name}", env!("CARGO_MANIFEST_DIR"));
    let src = std::fs::read_to_string(&path).unwrap();
    let (loaded, _) = compile(&src).unwrap_or_else(|d| panic!("{d:?}"));
    let Synthesis { reports, .. } = synthesize(&src, &loaded, &Config::default(), None, &mut |_| true);
    (loaded, reports)
}

fn ev(p: &Project, name: &str) -> EventId {
    p.event(name).unwrap_or_else(|| panic!("no event {name}"))
}

fn detected(p: &Project, names: &[&str]) -> Vec<EventId> {
    names.iter().map(|n| ev(p, n)).collect()
}

/// Figure 5.7: without preemption the supervisor interlocks; a controller that opens the inlet
/// is denied, and nothing changes.
#[test]
fn the_interlocked_tank_denies_opening_the_inlet() {
    let (l, reports) = example("tank_interlock.sct");
    let p = &l.project;
    let sups: Vec<_> = reports.iter().map(|r| &r.supervisor).collect();
    let mut rt = Runtime::new(p, &sups, &l.timers).unwrap();
    let before = rt.states().to_vec();
    let report = rt.cycle(&CycleInput { detected: detected(p, &["Tank.openInlet"]), ..Default::default() });
    assert_eq!(report.denied().collect::<Vec<_>>(), vec![(ev(p, "Tank.openInlet"), 0)]);
    assert_eq!(report.occurred().count(), 0);
    assert_eq!(rt.states(), before.as_slice(), "a denied event changes no supervisor");
}

/// Figure 5.8: with preemption the inlet may be opened; after `levelAlarm` the supervisor closes
/// it by force in the same cycle, unless the controller closed it itself in that cycle.
#[test]
fn the_preemptive_tank_enforces_closing_only_when_the_controller_does_not() {
    let (l, reports) = example("tank_preemption.sct");
    let p = &l.project;
    let sups: Vec<_> = reports.iter().map(|r| &r.supervisor).collect();
    let (open, close, alarm, now) =
        (ev(p, "Tank.openInlet"), ev(p, "Tank.closeInlet"), ev(p, "Tank.levelAlarm"), ev(p, "Tank.closeInlNow"));

    let mut rt = Runtime::new(p, &sups, &l.timers).unwrap();
    let r = rt.cycle(&CycleInput { detected: vec![open], ..Default::default() });
    assert_eq!(r.occurred().collect::<Vec<_>>(), vec![open]);
    // The controller does not react to the alarm: the supervisor does.
    let r = rt.cycle(&CycleInput { uncontrollable: vec![alarm], ..Default::default() });
    assert_eq!(r.occurred().collect::<Vec<_>>(), vec![alarm, now]);
    assert_eq!(r.steps[1].outcome, EventOutcome::Enforced { by: 0 });
    let r = rt.cycle(&CycleInput::default());
    assert!(r.steps.is_empty(), "{r:?}");

    // The controller closes the inlet in the cycle of the alarm: no enforcement.
    let mut rt = Runtime::new(p, &sups, &l.timers).unwrap();
    rt.cycle(&CycleInput { detected: vec![open], ..Default::default() });
    let r = rt.cycle(&CycleInput { uncontrollable: vec![alarm], detected: vec![close], ..Default::default() });
    assert_eq!(r.occurred().collect::<Vec<_>>(), vec![alarm, close]);
    assert_eq!(r.enforced().count(), 0);
}

/// 6.1.3: the timer starts with the alarm; 15 s later its timeout makes the supervisor close the
/// inlet by force, which also stops the timer. Closing in time stops it without a timeout.
#[test]
fn the_timer_gives_the_controller_its_grace_period() {
    let (l, reports) = example("tank_timer.sct");
    let p = &l.project;
    let sups: Vec<_> = reports.iter().map(|r| &r.supervisor).collect();
    let (open, close, alarm, timeout, force) =
        (ev(p, "openInlet"), ev(p, "closeInlet"), ev(p, "levelAlarm"), ev(p, "T.timeout"), ev(p, "forceCloseInlet"));
    let cycle_ms = 10;
    let tick = |rt: &mut Runtime, uncontrollable: Vec<EventId>, detected: Vec<EventId>| {
        rt.cycle(&CycleInput { elapsed_ms: cycle_ms, uncontrollable, executed: Vec::new(), detected })
    };

    let mut rt = Runtime::new(p, &sups, &l.timers).unwrap();
    tick(&mut rt, vec![], vec![open]);
    let r = tick(&mut rt, vec![alarm], vec![]);
    assert_eq!(r.enforced().count(), 0, "no enforcement before the timeout");
    // The alarm's cycle started the timer; 1499 more cycles of 10 ms stay below 15 s.
    for k in 0..1499 {
        let r = tick(&mut rt, vec![], vec![]);
        assert!(r.steps.is_empty(), "cycle {k}: {r:?}");
    }
    let r = tick(&mut rt, vec![], vec![]);
    assert_eq!(r.occurred().collect::<Vec<_>>(), vec![timeout, force]);
    // The forced closing stopped the timer: no second timeout.
    for _ in 0..2000 {
        assert!(tick(&mut rt, vec![], vec![]).steps.is_empty());
    }

    // The controller closes the inlet in time: the timer stops, nothing is enforced.
    let mut rt = Runtime::new(p, &sups, &l.timers).unwrap();
    tick(&mut rt, vec![], vec![open]);
    tick(&mut rt, vec![alarm], vec![]);
    for _ in 0..100 {
        tick(&mut rt, vec![], vec![]);
    }
    tick(&mut rt, vec![], vec![close]);
    for _ in 0..2000 {
        assert!(tick(&mut rt, vec![], vec![]).steps.is_empty());
    }
}

/// Where the transition of `trans` that leaves `from` on `e`, with its condition true in the
/// plant states `plant`, leads.
fn taken(trans: &[Transition], from: u32, e: EventId, plant: &[u32]) -> Option<u32> {
    let lookup = |g: u32| plant.get(g as usize).copied();
    trans.iter().find(|t| t.src == from && t.event == e && t.cond.eval(&lookup) == Truth::True).map(|t| t.dst)
}

/// The plant models as a running plant: current states, and which events they allow now.
struct Plant<'p> {
    project: &'p Project,
    states: Vec<u32>,
}

impl<'p> Plant<'p> {
    fn new(project: &'p Project) -> Plant<'p> {
        Plant { project, states: project.plants.iter().map(|g| g.init).collect() }
    }

    /// The successor states if every plant with `e` in its alphabet can take it now.
    fn after(&self, e: EventId) -> Option<Vec<u32>> {
        let mut next = self.states.clone();
        for (g, plant) in self.project.plants.iter().enumerate() {
            if plant.alphabet.contains(&e) {
                next[g] = taken(&plant.trans, self.states[g], e, &self.states)?;
            }
        }
        Some(next)
    }

    fn enabled(&self, kind: EventKind) -> Vec<EventId> {
        (0..self.project.events.len())
            .map(EventId::new)
            .filter(|&e| self.project.kind(e) == kind && self.after(e).is_some())
            .collect()
    }
}

/// The specifications as monitors: their current states; an event they prohibit (under the
/// plant states of the moment) is a violation.
struct Monitors<'p> {
    project: &'p Project,
    states: Vec<u32>,
}

impl<'p> Monitors<'p> {
    fn new(project: &'p Project) -> Monitors<'p> {
        Monitors { project, states: project.specs.iter().map(|h| h.init).collect() }
    }

    /// The specification violated by `e` in the plant states `plant`, or steps every
    /// specification on it (an event without a transition loops).
    fn step(&mut self, e: EventId, plant: &[u32]) -> Result<(), String> {
        let lookup = |g: u32| plant.get(g as usize).copied();
        for (h, spec) in self.project.specs.iter().enumerate() {
            let q = self.states[h];
            if spec.prohib.iter().any(|f| f.state == q && f.event == e && f.cond.eval(&lookup) == Truth::True) {
                return Err(format!(
                    "`{}` violates `{}` in state {}",
                    self.project.event_name(e),
                    spec.name,
                    spec.states[q as usize]
                ));
            }
            if let Some(next) = taken(&spec.trans, q, e, plant) {
                self.states[h] = next;
            }
        }
        Ok(())
    }
}

/// Every example, driven for 2000 cycles by a plant that follows its models (at most one
/// uncontrollable event per cycle: the plant is slower than the PLC, as the preemption contract
/// assumes) and a controller that does whatever the plant allows: no event that occurs violates
/// a specification (what supervision promises, checked against the specifications themselves);
/// no supervisor meets an uncontrollable event it prohibits; every denial is by a supervisor
/// that prohibits the event; no cascade is left unfinished at the end of a cycle.
#[test]
fn supervision_keeps_every_example_safe_against_a_random_controller() {
    let dir = format!("{}/examples/sct", env!("CARGO_MANIFEST_DIR"));
    let mut names: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".sct"))
        .collect();
    names.sort();
    let (mut checked, mut total_denied) = (0, 0);
    for name in &names {
        let (l, reports) = example(name);
        let p = &l.project;
        if reports.iter().any(|r| !r.realizable) || reports.is_empty() {
            continue;
        }
        let sups: Vec<_> = reports.iter().map(|r| &r.supervisor).collect();
        for seed in 0..5 {
            let mut rng = Rng::new(seed);
            let mut rt = Runtime::new(p, &sups, &l.timers).unwrap();
            let mut plant = Plant::new(p);
            let mut monitors = Monitors::new(p);
            let (mut accepted, mut denied) = (0, 0);
            for cycle in 0..2000 {
                let uncontrollable: Vec<EventId> = {
                    let now = plant.enabled(EventKind::Uncontrollable);
                    if !now.is_empty() && rng.below(3) == 0 {
                        vec![now[rng.below(now.len() as u64) as usize]]
                    } else {
                        Vec::new()
                    }
                };
                rt.begin_cycle(10, &uncontrollable);
                // The controller acts on the plant as it is after the uncontrollable events.
                let mut shadow = Plant { project: p, states: plant.states.clone() };
                for &e in &uncontrollable {
                    if let Some(s) = shadow.after(e) {
                        shadow.states = s;
                    }
                }
                let mut detected = Vec::new();
                for _ in 0..rng.below(3) {
                    let now = shadow.enabled(EventKind::Controllable);
                    if now.is_empty() {
                        break;
                    }
                    let e = now[rng.below(now.len() as u64) as usize];
                    if !detected.contains(&e) {
                        detected.push(e);
                    }
                }
                for &e in &detected {
                    let prohibiting = rt.prohibited_by(e);
                    let ok = rt.execute(e);
                    assert_eq!(ok, prohibiting.is_none(), "{name}: denial disagrees with the prohibitions");
                    if ok {
                        accepted += 1;
                    } else {
                        denied += 1;
                    }
                }
                let report = rt.end_cycle();
                for step in &report.steps {
                    assert!(
                        !matches!(step.outcome, EventOutcome::Unexpected { .. }),
                        "{name} seed {seed} cycle {cycle}: `{}` met a supervisor that prohibits it ({:?})",
                        p.event_name(step.event),
                        rt.states()
                    );
                }
                // The specifications watch, and the plant takes, what occurred, in the
                // framework's order.
                for e in report.occurred() {
                    if let Err(violation) = monitors.step(e, &plant.states) {
                        panic!("{name} seed {seed} cycle {cycle}: {violation}\n{report:?}");
                    }
                    if let Some(s) = plant.after(e) {
                        plant.states = s;
                    }
                }
                for (k, sup) in sups.iter().enumerate() {
                    let state = &sup.states[rt.states()[k] as usize];
                    if let Some(f) = state.enforced {
                        let leaves = state.transitions.iter().any(|&(e, t)| e == f && t != rt.states()[k]);
                        assert!(!leaves, "{name}: supervisor {k} ends a cycle in a state that enforces a way out");
                    }
                }
            }
            assert!(accepted > 0, "{name} seed {seed}: the controller never acted");
            total_denied += denied;
        }
        checked += 1;
    }
    assert!(checked >= 6, "only {checked} examples checked");
    assert!(total_denied > 0, "no controller action was ever denied: the check is too weak");
}
