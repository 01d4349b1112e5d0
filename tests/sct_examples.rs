//! The examples of `examples/sct/`: each is loaded, synthesised and checked against the
//! expected result stated in its header comment.

use plcsynth::diag::render_plain;
use plcsynth::sct::model::{Config, EventKind, Method, Supervisor};
use plcsynth::sct::{compile, Loaded};
use plcsynth::sct::{synthesize, synthesize_within, Outcome, Stop, SupervisorReport, Synthesis, Verdict};
use plcsynth::search::{Decision as _, Resource};

fn example(name: &str) -> (String, Loaded) {
    let path = format!("{}/examples/sct/{name}", env!("CARGO_MANIFEST_DIR"));
    let src = std::fs::read_to_string(&path).unwrap();
    let (loaded, diags) = compile(&src).unwrap_or_else(|d| panic!("{d:?}"));
    let errors: Vec<_> = diags.iter().filter(|d| d.is_error()).cloned().collect();
    assert!(errors.is_empty(), "{}", render_plain(name, &src, &errors));
    (src.clone(), loaded)
}

fn synth(name: &str, method: Method) -> (Loaded, Vec<SupervisorReport>) {
    let (src, l) = example(name);
    let Synthesis { reports: reps, diagnostics: diags, .. } =
        synthesize(&src, &l, &Config { method, ..Config::default() }, None, &mut |_| true);
    assert!(!diags.iter().any(|d| d.is_error()), "{}", render_plain(name, &src, &diags));
    (l, reps)
}

fn word(l: &Loaded, names: &[&str]) -> Vec<plcsynth::sct::model::EventId> {
    names.iter().map(|n| l.project.event(n).unwrap_or_else(|| panic!("no event {n}"))).collect()
}

fn allowed(l: &Loaded, s: &Supervisor, names: &[&str]) -> bool {
    s.run(&word(l, names)).is_some()
}

fn sup<'a>(reps: &'a [SupervisorReport], name: &str) -> &'a Supervisor {
    &reps.iter().find(|r| r.name == name).unwrap_or_else(|| panic!("no supervisor {name}")).supervisor
}

fn no_uncontrollable_prohibitions(l: &Loaded, reps: &[SupervisorReport]) {
    for r in reps {
        for e in r.supervisor.prohibited_events() {
            assert_ne!(
                l.project.kind(e),
                EventKind::Uncontrollable,
                "{} prohibits uncontrollable {}",
                r.name,
                l.project.event_name(e)
            );
        }
    }
}

#[test]
fn tank_interlock_disables_open_inlet() {
    for m in [Method::Incremental, Method::Monolithic] {
        let (l, reps) = synth("tank_interlock.sct", m);
        let s = sup(&reps, "Safety.NoOverflow");
        assert_eq!(s.states.len(), 1);
        assert!(!allowed(&l, s, &["Tank.openInlet"]));
        assert!(allowed(&l, s, &["Tank.closeInlet"]));
        assert!(s.enforced_events().is_empty());
        no_uncontrollable_prohibitions(&l, &reps);
    }
}

#[test]
fn tank_preemption_allows_open_inlet_and_enforces_closing() {
    for m in [Method::Incremental, Method::Monolithic] {
        let (l, reps) = synth("tank_preemption.sct", m);
        let s = sup(&reps, "Safety.NoOverflow");
        let c = s.run(&word(&l, &["Tank.openInlet", "Tank.levelAlarm"])).expect("allowed");
        assert_eq!(s.states[c as usize].enforced, l.project.event("Tank.closeInlNow"));
        assert!(allowed(&l, s, &["Tank.openInlet", "Tank.levelAlarm", "Tank.closeInlet", "Tank.openInlet"]));
        assert_eq!(s.enforced_events(), word(&l, &["Tank.closeInlNow"]));
        no_uncontrollable_prohibitions(&l, &reps);
    }
}

#[test]
fn tank_cyclic_denies_inlet_after_alarm_only() {
    let (l, reps) = synth("tank_cyclic.sct", Method::Incremental);
    let s = sup(&reps, "NoOverflow");
    assert!(allowed(&l, s, &["Tank.inletOpen1Cyc", "Tank.inletOpen1Cyc"]));
    assert!(!allowed(&l, s, &["Tank.inletOpen1Cyc", "Tank.levelAlarm", "Tank.inletOpen1Cyc"]));
    assert!(allowed(&l, s, &["Tank.inletOpen1Cyc", "Tank.levelAlarm", "Tank.levelLow", "Tank.inletOpen1Cyc"]));
    no_uncontrollable_prohibitions(&l, &reps);
}

#[test]
fn heating_tank_heats_only_while_stirring() {
    for m in [Method::Incremental, Method::Monolithic] {
        let (l, reps) = synth("heating_tank.sct", m);
        let s = sup(&reps, "NoJelly");
        assert!(s.realizable());
        assert!(!allowed(&l, s, &["heatOn"]), "heating without stirring must be prohibited");
        assert!(allowed(&l, s, &["stirOn", "heatOn", "up1", "up2"]));
        assert!(!allowed(&l, s, &["stirOn", "heatOn", "up1", "stirOff"]));
        assert!(allowed(&l, s, &["stirOn", "heatOn", "up1", "heatOff", "stirOff"]));
        no_uncontrollable_prohibitions(&l, &reps);
    }
}

#[test]
fn three_tanks_templates_bind_and_synthesise() {
    for m in [Method::Incremental, Method::Monolithic] {
        let (l, reps) = synth("three_tanks.sct", m);
        assert_eq!(reps.len(), 10);
        assert!(reps.iter().all(|r| r.realizable));
        let s = sup(&reps, "NoReflux");
        assert!(!allowed(&l, s, &["Y2.op", "Y3.op"]));
        assert!(allowed(&l, s, &["Y2.op", "Y2.cl", "Y3.op"]));
        let r = sup(&reps, "NoReaction");
        assert!(!allowed(&l, r, &["Y2.op", "Y3.op"]));
        assert!(allowed(&l, r, &["Y2.op", "T3.empty", "Y3.op"]));
        let x = sup(&reps, "Mtx.Y0Y2");
        assert!(!allowed(&l, x, &["Y0.op", "Y2.op"]));
        assert!(allowed(&l, x, &["Y0.op", "Y0.cl", "Y2.op"]));
        no_uncontrollable_prohibitions(&l, &reps);
    }
}

#[test]
fn crane_prohibits_stepping_beyond_the_sensor() {
    let (l, reps) = synth("crane.sct", Method::Incremental);
    let r = sup(&reps, "Right.NoCrash");
    assert_eq!(r.states.len(), 2);
    assert!(allowed(&l, r, &["stepRight", "stepRight", "stepLeft"]));
    assert!(!allowed(&l, r, &["sensorRight", "stepRight"]));
    assert!(allowed(&l, r, &["sensorRight", "stepLeft", "stepRight"]));
    let lft = sup(&reps, "Left.NoCrash");
    assert!(!allowed(&l, lft, &["sensorLeft", "stepLeft"]));
    no_uncontrollable_prohibitions(&l, &reps);
}

#[test]
fn singularizer_prevents_stacking() {
    let (l, reps) = synth("singularizer.sct", Method::Incremental);
    let s = sup(&reps, "NoStacking");
    assert!(!allowed(&l, s, &["Clasp.open"]));
    assert!(allowed(&l, s, &["Belt.start", "Clasp.open", "Clasp.closed", "Belt.stop"]));
    assert!(!allowed(&l, s, &["Belt.start", "Clasp.open", "Belt.stop"]));
    no_uncontrollable_prohibitions(&l, &reps);
}

#[test]
fn timer_delays_enforcement_until_timeout() {
    let (l, reps) = synth("tank_timer.sct", Method::Incremental);
    assert_eq!(l.timers.len(), 1);
    assert_eq!(l.timers[0].duration_ms, 15_000);
    assert_eq!(l.timers[0].timeout, "T.timeout");
    let s = sup(&reps, "NoOverflow");
    let c1 = s.run(&word(&l, &["openInlet", "levelAlarm"])).unwrap();
    assert_eq!(s.states[c1 as usize].enforced, None);
    let c2 = s.run(&word(&l, &["openInlet", "levelAlarm", "T.timeout"])).unwrap();
    assert_eq!(s.states[c2 as usize].enforced, l.project.event("forceCloseInlet"));
    no_uncontrollable_prohibitions(&l, &reps);
}

#[test]
fn enforcement_conflict_is_resolved_by_the_specification_product() {
    let (l, reps) = synth("enforcement_conflict.sct", Method::Incremental);
    assert_eq!(reps.len(), 1, "operands of the product are not synthesised alone");
    let s = sup(&reps, "Safety");
    let c = s.run(&word(&l, &["openInlet", "levelAlarm"])).unwrap();
    assert_eq!(s.states[c as usize].enforced, l.project.event("closeInlNow"));
    assert!(!allowed(&l, s, &["pumpOn", "openInlet"]));
    assert!(!allowed(&l, s, &["openInlet", "pumpOn"]));
    assert!(allowed(&l, s, &["openInlet", "closeInlet", "pumpOn", "pumpOff", "openInlet"]));
    no_uncontrollable_prohibitions(&l, &reps);

    // Without the product: two supervisors and the 6.4.2 warning.
    let (src, _) = example("enforcement_conflict.sct");
    let src = src.replace("spec Safety = NoOverflow | PumpProtection;", "");
    let (loaded, _) = compile(&src).unwrap_or_else(|d| panic!("{d:?}"));
    let Synthesis { reports: reps, diagnostics: diags, .. } =
        synthesize(&src, &loaded, &Config::default(), None, &mut |_| true);
    assert_eq!(reps.len(), 2);
    let w = diags.iter().find(|d| {
        !d.is_error() && d.message.contains("prohibits `closeInlNow`, which supervisor `NoOverflow` enforces")
    });
    assert!(w.is_some(), "{diags:?}");
}

#[test]
fn unrealizable_specifications_are_reported() {
    let src = "event u : uncontrollable;\nspec H { state s { forbid u; } }\n";
    let (loaded, _) = compile(src).unwrap_or_else(|d| panic!("{d:?}"));
    let synthesis = synthesize(src, &loaded, &Config::default(), None, &mut |_| true);
    assert_eq!(synthesis.verdict(), Some(Verdict::Unrealizable));
    let Synthesis { reports: reps, diagnostics: diags, .. } = synthesis;
    assert!(!reps[0].realizable);
    assert!(diags.iter().any(|d| d.line == 2 && d.message.contains("`H` is unrealizable")), "{diags:?}");
}

/// The verdict the CLI and the page show is decided in Rust (`sct::Verdict`): every example is
/// realizable; a budget too small and a cancellation stop the run without a verdict, and the
/// outcome names them as the other engines do.
#[test]
fn the_engine_decides_the_verdict() {
    use plcsynth::sct::model::Budget;
    let dir = format!("{}/examples/sct", env!("CARGO_MANIFEST_DIR"));
    let mut names: Vec<String> =
        std::fs::read_dir(&dir).unwrap().map(|e| e.unwrap().file_name().into_string().unwrap()).collect();
    names.retain(|n| n.ends_with(".sct"));
    assert!(names.len() >= 8, "{names:?}");
    for name in &names {
        let (src, loaded) = example(name);
        let cfg = Config::default();
        let run = |max_states: usize| {
            let mut go_on = |_: &_| true;
            let mut budget = Budget::new(max_states, &mut go_on);
            synthesize_within(&src, &loaded, &cfg, None, &mut budget).outcome
        };
        assert_eq!(run(cfg.max_states), Ok(Verdict::Realizable), "{name}");
        assert!(matches!(run(1), Err(Stop::Budget { resource: Resource::States, .. })), "{name}");
    }
    // A cancellation: the callback runs every few thousand states, so a bigger line.
    let src = plcsynth::benchmarks::transfer::transfer_lines(4, 3, 2);
    let (loaded, _) = compile(&src).unwrap_or_else(|d| panic!("{d:?}"));
    let cfg = Config { method: Method::Monolithic, ..Config::default() };
    let cancelled = synthesize(&src, &loaded, &cfg, None, &mut |p| p.states < 10_000);
    assert_eq!(cancelled.outcome, Err(Stop::Cancelled));
    assert_eq!(cancelled.outcome_name(), "cancelled");
    assert_eq!(serde_json::to_string(&Verdict::Unrealizable).unwrap(), "\"unrealizable\"");
    assert_eq!(Verdict::Error.name(), "error");
}

#[test]
fn selfloops_helper_adds_missing_loops_except_impossible_ones() {
    let src = "event a : controllable;\nevent b : uncontrollable;\nplant P {\n  alphabet a, b;\n  selfloops;\n  state s { a -> t; impossible b; }\n  state t;\n}\n";
    let (loaded, d) = compile(src).unwrap_or_else(|e| panic!("{e:?}"));
    assert!(d.is_empty(), "{d:?}");
    let p = &loaded.project.plants[0];
    let mut t: Vec<(u32, u32, u32)> = p.trans.iter().map(|t| (t.src, t.event.raw(), t.dst)).collect();
    t.sort_unstable();
    assert_eq!(t, vec![(0, 0, 1), (1, 0, 1), (1, 1, 1)]);
}
