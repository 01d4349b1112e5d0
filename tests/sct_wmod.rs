//! Supremica/Waters `.wmod` modules: reading hand-written modules in Supremica's layout, SupCon
//! on a module against the same problem as `.gen` files and against libFAUDES, round trips
//! `.sct` → `.wmod` → `.sct` (same supervisors) and `.gen` → `.wmod` → `.gen` (same automaton),
//! random automata written and read back, and the `import`/`export` commands.

use plcsynth::sct::classic::gen::{read_gen, write_gen};
use plcsynth::sct::classic::wmod::{read_wmod, write_wmod, ComponentKind, ComponentOut, Module};
use plcsynth::sct::classic::{
    language_equal, product, supcon, Automaton, AutomatonBuilder, ClassicEventId, Events, StateId,
};
use plcsynth::sct::interchange::{classic_to_sct, project_to_classic, Part, ToSct};
use plcsynth::sct::model::{Config, Supervisor};
use plcsynth::sct::{compile, synthesize, Synthesis};
use proptest::prelude::*;
use std::path::PathBuf;
use std::process::Command;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn fixture(name: &str) -> String {
    std::fs::read_to_string(root().join("tests/fixtures/wmod").join(name)).unwrap()
}

fn plcsynth(args: &[&str]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_plcsynth")).args(args).current_dir(root()).output().unwrap();
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into(),
        String::from_utf8_lossy(&out.stderr).into(),
    )
}

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("plcsynth-wmod-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

/// The module's components of `kinds`, composed.
fn composed(m: &Module, ev: &Events, kinds: &[ComponentKind]) -> Automaton {
    let parts: Vec<&Automaton> =
        m.components.iter().filter(|c| kinds.contains(&c.kind)).map(|c| &c.automaton).collect();
    let mut acc = parts[0].clone();
    for p in &parts[1..] {
        acc = product(&acc, p, ev.len()).automaton;
    }
    acc
}

/// `src` with every element of the module namespace written with the prefix `w:`, the
/// namespace declared for that prefix instead of as the default: the same module to a
/// namespace-aware reader.
fn prefixed(src: &str) -> String {
    let mut out = String::with_capacity(src.len() * 2);
    let mut rest = src;
    while let Some(k) = rest.find('<') {
        out.push_str(&rest[..k]);
        rest = &rest[k..];
        let after = &rest[1..];
        let (close, name_start) = if let Some(a) = after.strip_prefix('/') { ("/", a) } else { ("", after) };
        let is_element = name_start.starts_with(|c: char| c.is_ascii_alphabetic()) && !name_start.starts_with("B:");
        out.push('<');
        out.push_str(close);
        if is_element {
            out.push_str("w:");
        }
        rest = &rest[1 + close.len()..];
    }
    out.push_str(rest);
    out.replace("xmlns=\"http://waters", "xmlns:w=\"http://waters")
}

#[test]
fn a_supremica_style_module_reads_with_prefixes_comments_and_odd_whitespace() {
    let src = fixture("small_factory.wmod");
    let mut ev = Events::new();
    let m = read_wmod(&src, &mut ev).unwrap();
    let kinds: Vec<(&str, ComponentKind)> = m.components.iter().map(|c| (c.name.as_str(), c.kind)).collect();
    use ComponentKind::*;
    assert_eq!(kinds, [("M1", Plant), ("M2", Plant), ("Buffer", Spec), ("Repair", Spec)]);
    assert_eq!(m.events.len(), 8);
    for (name, controllable) in [("s1", true), ("f1", false), ("b1", false), ("r1", true), ("f2", false)] {
        assert_eq!(ev.is_controllable(ev.get(name).unwrap()), controllable, "{name}");
    }
    // The same module with every element prefixed reads the same.
    let other = prefixed(&src);
    assert!(other.contains("<w:SimpleComponent") && other.contains("<B:Comment>"), "{other}");
    let mut ev2 = Events::new();
    let m2 = read_wmod(&other, &mut ev2).unwrap_or_else(|e| panic!("{:?}\n{other}", e.diagnostic(&other)));
    for (a, b) in m.components.iter().zip(&m2.components) {
        assert_eq!(
            (&a.name, a.kind, a.automaton.num_states(), a.automaton.num_transitions()),
            (&b.name, b.kind, b.automaton.num_states(), b.automaton.num_transitions())
        );
        assert!(language_equal(&a.automaton, &b.automaton), "{}", a.name);
    }
    // Written by Supremica in windows-1252: a byte that is not UTF-8 in a comment.
    let mut bytes = src.clone().into_bytes();
    let k = src.find("Small factory").unwrap();
    bytes[k] = 0xE9; // 'é' in windows-1252
    let path = scratch("cp1252.wmod");
    std::fs::write(&path, &bytes).unwrap();
    let (code, out, err) = plcsynth(&["supcon", path.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    assert!(out.starts_with("SupCon: 12 states, 24 transitions"), "{out}");
}

#[test]
fn supcon_on_a_module_agrees_with_gen_files_the_textbook_and_libfaudes() {
    let src = fixture("small_factory.wmod");
    let mut ev = Events::new();
    let m = read_wmod(&src, &mut ev).unwrap();
    let plant = composed(&m, &ev, &[ComponentKind::Plant]);
    // Over the plant's alphabet, as libFAUDES needs it (the same specification for SupCon).
    let spec = composed(&m, &ev, &[ComponentKind::Spec]).with_selfloops(plant.alphabet());
    let sup = supcon(&plant, &spec, &ev, true).unwrap();
    // The published size of the small factory's supervisor, and our textbook model's.
    assert_eq!((sup.num_states(), sup.num_transitions()), (12, 24));
    let (tp, ts, tev) = plcsynth::benchmarks::textbook::small_factory();
    let textbook = supcon(&tp, &ts.with_selfloops(tp.alphabet()), &tev, true).unwrap();
    assert_eq!((textbook.num_states(), textbook.num_transitions()), (12, 24));

    // The CLI on the module, and on the same problem as `.gen` files, write the same language.
    let (pg, sg) = (scratch("sf_plant.gen"), scratch("sf_spec.gen"));
    std::fs::write(&pg, write_gen(&plant, &ev, "plant")).unwrap();
    std::fs::write(&sg, write_gen(&spec, &ev, "spec")).unwrap();
    let (sup_wmod, sup_gen) = (scratch("sf_sup.wmod"), scratch("sf_sup.gen"));
    let module = root().join("tests/fixtures/wmod/small_factory.wmod");
    let (code, out_w, err) = plcsynth(&["supcon", module.to_str().unwrap(), "-o", sup_wmod.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    let (code, out_g, err) =
        plcsynth(&["supcon", pg.to_str().unwrap(), sg.to_str().unwrap(), "-o", sup_gen.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    let counts = |s: &str| s.split(" (").next().unwrap().to_string();
    assert_eq!(counts(&out_w), counts(&out_g));
    let mut ev2 = ev.clone();
    let written = read_wmod(&std::fs::read_to_string(&sup_wmod).unwrap(), &mut ev2).unwrap();
    assert_eq!(written.components.len(), 1);
    assert_eq!(written.components[0].kind, ComponentKind::Supervisor);
    let from_gen = read_gen(&std::fs::read_to_string(&sup_gen).unwrap(), &mut ev2).unwrap();
    assert!(language_equal(&written.components[0].automaton, &from_gen));
    assert!(language_equal(&written.components[0].automaton, &sup));

    // libFAUDES on the module's plant and specification: the same supervisor language.
    let py = root().join(".venv/bin/python");
    let has_faudes = py.exists()
        && Command::new(&py).args(["-c", "import faudes"]).output().map(|o| o.status.success()).unwrap_or(false);
    assert!(has_faudes, "libFAUDES is needed: run `scripts/python-checkers.sh` (creates {})", py.display());
    let dir = scratch("faudes_case");
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("plant.gen"), write_gen(&plant, &ev, "plant")).unwrap();
    std::fs::write(dir.join("spec.gen"), write_gen(&spec, &ev, "spec")).unwrap();
    std::fs::write(dir.join("sup.gen"), write_gen(&sup, &ev, "sup")).unwrap();
    let closed = supcon(&plant, &spec, &ev, false).unwrap();
    std::fs::write(dir.join("supc.gen"), write_gen(&closed, &ev, "supc")).unwrap();
    let manifest = scratch("faudes_manifest.txt");
    std::fs::write(&manifest, format!("{}\n", dir.display())).unwrap();
    let out = Command::new(&py).arg(root().join("tests/faudes_check.py")).arg(&manifest).output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let v: serde_json::Value =
        serde_json::from_str(String::from_utf8_lossy(&out.stdout).lines().last().unwrap()).unwrap();
    for key in ["marked_eq", "closure_eq", "closed_gen_eq", "closed_marked_eq"] {
        assert_eq!(v[key], true, "libFAUDES disagrees on {key}: {v}");
    }
    assert_eq!(v["faudes_states"], 12, "{v}");
}

/// Two supervisors are the same up to the names of states and of events (`rename` maps the
/// first one's event names to the second's): a bijection of states from the initial ones that
/// keeps explicit transitions, prohibitions and enforced events.
fn same_supervisor(
    a: &Supervisor,
    ea: &dyn Fn(u32) -> String,
    b: &Supervisor,
    eb: &dyn Fn(u32) -> String,
) -> Result<(), String> {
    if a.states.len() != b.states.len() {
        return Err(format!("{} states against {}", a.states.len(), b.states.len()));
    }
    let (Some(ia), Some(ib)) = (a.init, b.init) else {
        return if a.init.is_none() && b.init.is_none() { Ok(()) } else { Err("one is void".into()) };
    };
    let mut map = vec![None; a.states.len()];
    map[ia as usize] = Some(ib);
    let mut work = vec![ia];
    let names = |es: &[plcsynth::sct::model::EventId], f: &dyn Fn(u32) -> String| {
        let mut v: Vec<String> = es.iter().map(|e| f(e.raw())).collect();
        v.sort();
        v
    };
    while let Some(s) = work.pop() {
        let t = map[s as usize].unwrap();
        let (x, y) = (&a.states[s as usize], &b.states[t as usize]);
        if names(&x.prohibited, ea) != names(&y.prohibited, eb) {
            return Err(format!(
                "state {} prohibits {:?}, state {} {:?}",
                x.label,
                names(&x.prohibited, ea),
                y.label,
                names(&y.prohibited, eb)
            ));
        }
        if x.enforced.map(|e| ea(e.raw())) != y.enforced.map(|e| eb(e.raw())) {
            return Err(format!("state {} enforces differently", x.label));
        }
        let moves = |st: &plcsynth::sct::model::SupState, f: &dyn Fn(u32) -> String| {
            let mut v: Vec<(String, u32)> = st.transitions.iter().map(|(e, t)| (f(e.raw()), *t)).collect();
            v.sort();
            v
        };
        let (mx, my) = (moves(x, ea), moves(y, eb));
        if mx.iter().map(|m| &m.0).ne(my.iter().map(|m| &m.0)) {
            return Err(format!("state {} moves on {:?}, state {} on {:?}", x.label, mx, y.label, my));
        }
        for ((_, sx), (_, sy)) in mx.iter().zip(&my) {
            match map[*sx as usize] {
                Some(m) if m != *sy => return Err(format!("state {} is matched twice", a.states[*sx as usize].label)),
                Some(_) => {}
                None => {
                    map[*sx as usize] = Some(*sy);
                    work.push(*sx);
                }
            }
        }
    }
    Ok(())
}

/// `.sct` → `.wmod` → `.sct` through the library: the project written as a module, read back,
/// written as a project again.
fn through_wmod(src: &str) -> String {
    let (loaded, _) = compile(src).unwrap_or_else(|d| panic!("{d:?}"));
    let classic = project_to_classic(src, &loaded, &[]).unwrap_or_else(|d| panic!("{d:?}"));
    let out: Vec<ComponentOut> = classic
        .components
        .iter()
        .map(|(name, kind, automaton)| ComponentOut { name, kind: *kind, automaton })
        .collect();
    let text = write_wmod("m", "", &out, &classic.events, &classic.attributes());
    let mut ev = Events::new();
    let m = read_wmod(&text, &mut ev).unwrap_or_else(|e| panic!("{:?}\n{text}", e.diagnostic(&text)));
    let parts: Vec<Part> = m
        .components
        .iter()
        .map(|c| Part {
            name: &c.name,
            kind: c.kind,
            automaton: &c.automaton,
            span: c.span,
            state_spans: &c.state_spans,
        })
        .collect();
    let bodies: Vec<(ClassicEventId, String)> = m
        .attributes
        .iter()
        .filter(|a| a.1 == plcsynth::sct::classic::wmod::SCT_ATTRIBUTE)
        .map(|a| (a.0, a.2.clone()))
        .collect();
    classic_to_sct(&parts, &ev, &m.enforceable, &bodies, "round trip", ToSct::default())
        .unwrap_or_else(|e| panic!("{e:?}"))
}

#[test]
fn sct_to_wmod_to_sct_keeps_every_supervisor() {
    // The examples without conditions (conditions have no Waters form; see below).
    let mut checked = 0;
    for entry in std::fs::read_dir(root().join("examples/sct")).unwrap() {
        let path = entry.unwrap().path();
        let src = std::fs::read_to_string(&path).unwrap();
        let (loaded, _) = compile(&src).unwrap_or_else(|d| panic!("{d:?}"));
        if project_to_classic(&src, &loaded, &[]).is_err() {
            continue;
        }
        let again = through_wmod(&src);
        let (loaded2, _) = compile(&again).unwrap_or_else(|d| panic!("{d:?}"));
        let Synthesis { reports: r1, .. } = synthesize(&src, &loaded, &Config::default(), None, &mut |_| true);
        let Synthesis { reports: r2, .. } = synthesize(&again, &loaded2, &Config::default(), None, &mut |_| true);
        assert_eq!(r1.len(), r2.len(), "{}", path.display());
        let p1 = &loaded.project;
        let p2 = &loaded2.project;
        let ea = |e: u32| plcsynth::sct::interchange::waters_name(&p1.events[e as usize].name);
        let eb = |e: u32| p2.events[e as usize].name.clone();
        for (a, b) in r1.iter().zip(&r2) {
            assert_eq!(plcsynth::sct::interchange::waters_name(&a.name), b.name);
            assert_eq!(
                (a.states, a.transitions, a.prohibitions),
                (b.states, b.transitions, b.prohibitions),
                "{}",
                a.name
            );
            same_supervisor(&a.supervisor, &ea, &b.supervisor, &eb)
                .unwrap_or_else(|e| panic!("{} {}: {e}\n{again}", path.display(), a.name));
        }
        checked += 1;
    }
    assert!(checked >= 6, "only {checked} examples map");
}

#[test]
fn export_and_import_round_trip_on_the_command_line() {
    let wmod = scratch("tank_timer.wmod");
    let sct = scratch("tank_timer.sct");
    let (code, _, err) = plcsynth(&["export", "examples/sct/tank_timer.sct", "-o", wmod.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    // The timer is not in the module, and the user is told so.
    assert!(err.contains("timer `T` (15000 ms from `levelAlarm`)"), "{err}");
    let module = std::fs::read_to_string(&wmod).unwrap();
    assert!(module.contains("Name=\"plcsynth:sct\" Value=\"detect rising &quot;Q_Inlet&quot;;\""), "{module}");
    let (code, _, err) = plcsynth(&["import", wmod.to_str().unwrap(), "-o", sct.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    let (code, out1, _) = plcsynth(&["supervise", "examples/sct/tank_timer.sct"]);
    assert_eq!(code, 0);
    let (code, out2, err) = plcsynth(&["supervise", sct.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    let table = |s: &str| {
        s.lines()
            .map(|l| l.split_whitespace().filter(|w| !w.contains('.')).collect::<Vec<_>>().join(" "))
            .collect::<Vec<_>>()
    };
    assert_eq!(table(&out1), table(&out2));
    // `supervise -o F.wmod` writes the supervisors, `--with-supervisors` adds them to the model.
    let sups = scratch("sups.wmod");
    let (code, _, err) = plcsynth(&["supervise", "examples/sct/transfer_line_2x2.sct", "-o", sups.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    let m = read_wmod(&std::fs::read_to_string(&sups).unwrap(), &mut Events::new()).unwrap();
    assert_eq!(m.components.len(), 5);
    assert!(m.components.iter().all(|c| c.kind == ComponentKind::Supervisor));
    let all = scratch("all.wmod");
    let (code, _, err) =
        plcsynth(&["export", "examples/sct/transfer_line_2x2.sct", "--with-supervisors", "-o", all.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    let m = read_wmod(&std::fs::read_to_string(&all).unwrap(), &mut Events::new()).unwrap();
    let count = |k| m.components.iter().filter(|c| c.kind == k).count();
    assert_eq!((count(ComponentKind::Supervisor), count(ComponentKind::Spec)), (5, 5));
    // `supervise -o` without a target needs a `.wmod` name.
    let (code, _, err) = plcsynth(&["supervise", "examples/sct/crane.sct", "-o", "x.st"]);
    assert_eq!(code, 2);
    assert!(err.contains("`--output` needs `--target`"), "{err}");
}

#[test]
fn what_does_not_map_is_a_located_error() {
    // A conditional transition has no Waters form.
    let (code, _, err) =
        plcsynth(&["export", "examples/sct/heating_tank.sct", "-o", scratch("h.wmod").to_str().unwrap()]);
    assert_eq!(code, 2);
    assert!(
        err.contains("examples/sct/heating_tank.sct:48:13: error: plant `Jelly` has a conditional transition"),
        "{err}"
    );
    assert!(!scratch("h.wmod").exists());
    // Marking: refused with the state located, unless asked to ignore it.
    let module = "tests/fixtures/wmod/small_factory.wmod";
    let (code, out, err) = plcsynth(&["import", module]);
    assert_eq!((code, out.as_str()), (2, ""));
    assert!(err.contains("small_factory.wmod:43:19: error: state `W` of `M1` is not marked"), "{err}");
    assert!(err.contains("43 | <SimpleNode Name=\"W\">"), "{err}");
    let (code, out, err) = plcsynth(&["import", module, "--ignore-marking"]);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("spec Buffer {\n  state empty initial { f1 -> full; forbid s2; }"), "{out}");
    // EFA: a variable component, as Supremica writes one, named and located.
    let efa = fixture("small_factory.wmod").replace(
        "<ComponentList>",
        "<ComponentList>\n<VariableComponent Name=\"count\">\n<VariableRange><BinaryExpression Operator=\"..\"><IntConstant Value=\"0\"/><IntConstant Value=\"3\"/></BinaryExpression></VariableRange>\n</VariableComponent>",
    );
    let path = scratch("efa.wmod");
    std::fs::write(&path, &efa).unwrap();
    let line = efa[..efa.find("<VariableComponent").unwrap()].lines().count() + 1;
    for cmd in [vec!["import", path.to_str().unwrap()], vec!["supcon", path.to_str().unwrap()]] {
        let (code, _, err) = plcsynth(&cmd);
        assert_eq!(code, 2);
        assert!(
            err.contains(&format!("efa.wmod:{line}:1: error: <VariableComponent> in <ComponentList> is not supported")),
            "{err}"
        );
        assert!(err.contains("EFA variables are not read"), "{err}");
    }
}

#[test]
fn gen_files_import_as_a_project_and_round_trip_through_wmod() {
    // `.gen` → `.wmod` → `.gen` keeps the automaton.
    for seed in ["faudes_style.gen", "machine_and_buffer.gen"] {
        let text = std::fs::read_to_string(root().join("fuzz/seeds/gen").join(seed)).unwrap();
        let mut ev = Events::new();
        let a = read_gen(&text, &mut ev).unwrap();
        let module =
            write_wmod("g", "", &[ComponentOut { name: "G", kind: ComponentKind::Plant, automaton: &a }], &ev, &[]);
        let mut ev2 = ev.clone();
        let m = read_wmod(&module, &mut ev2).unwrap();
        let back_text = write_gen(&m.components[0].automaton, &ev2, "g");
        let b = read_gen(&back_text, &mut ev2).unwrap();
        assert_eq!(
            (a.num_states(), a.num_transitions(), a.init(), a.alphabet()),
            (b.num_states(), b.num_transitions(), b.init(), b.alphabet()),
            "{seed}"
        );
        for s in a.states() {
            assert_eq!((a.is_marked(s), a.edges(s)), (b.is_marked(s), b.edges(s)), "{seed}");
        }
    }
    // `plcsynth import PLANT.gen --spec SPEC.gen`: a project whose supervisor prohibits what
    // SupConClosed disables.
    let (plant, spec, ev) = plcsynth::benchmarks::textbook::transfer_line(3, 1);
    let all_marked = |a: &Automaton| a.with_all_marked();
    let (pg, sg, out) = (scratch("line.gen"), scratch("line_spec.gen"), scratch("line.sct"));
    std::fs::write(&pg, write_gen(&all_marked(&plant), &ev, "plant")).unwrap();
    std::fs::write(&sg, write_gen(&all_marked(&spec), &ev, "spec")).unwrap();
    let (code, _, err) =
        plcsynth(&["import", pg.to_str().unwrap(), "--spec", sg.to_str().unwrap(), "-o", out.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    let project = std::fs::read_to_string(&out).unwrap();
    assert!(project.contains("plant line {") && project.contains("spec line_spec {"), "{project}");
    let (code, table, err) = plcsynth(&["supervise", out.to_str().unwrap(), "--no-preemption"]);
    assert_eq!(code, 0, "{err}");
    assert!(table.contains("line_spec") && table.contains(" yes "), "{table}");
    // A marked .gen is refused without --ignore-marking (it has no state spans: the file).
    std::fs::write(&pg, write_gen(&plant, &ev, "plant")).unwrap();
    let (code, _, err) = plcsynth(&["import", pg.to_str().unwrap()]);
    assert_eq!(code, 2);
    assert!(err.contains("line.gen:1:1: error: state") && err.contains("is not marked"), "{err}");
}

/// A random deterministic automaton over events `0..n_events` of `ev`.
fn random_automaton(
    ev: &Events,
    n_events: usize,
    states: usize,
    marked: &[bool],
    trans: &[(usize, usize, usize)],
    blocked: &[bool],
) -> Automaton {
    let mut b = AutomatonBuilder::new();
    for s in 0..states {
        b.add_state(format!("q{s}"), marked[s % marked.len()]);
    }
    let mut used = vec![false; n_events];
    let mut seen = std::collections::HashSet::new();
    for &(s, e, t) in trans {
        let (s, e, t) = (s % states, e % n_events, t % states);
        if seen.insert((s, e)) {
            b.add_transition(StateId::new(s), ClassicEventId::from_raw(e as u32), StateId::new(t));
            used[e] = true;
        }
    }
    for e in 0..n_events {
        if used[e] || blocked[e % blocked.len()] {
            b.add_event(ClassicEventId::from_raw(e as u32));
        }
    }
    let _ = ev;
    b.set_init(StateId::new(0));
    b.build().unwrap()
}

proptest! {
    #![proptest_config(crate::common::proptest_config(200))]

    /// Random automata written as a module and read back are identical: states, names,
    /// marking, initial state, alphabet (blocked events included), transitions, kinds and
    /// controllability.
    #[test]
    fn random_automata_survive_a_wmod_round_trip(
        n_events in 1usize..6,
        controllable in proptest::collection::vec(any::<bool>(), 6),
        automata in proptest::collection::vec(
            (1usize..8, proptest::collection::vec(any::<bool>(), 1..8),
             proptest::collection::vec((0usize..8, 0usize..6, 0usize..8), 0..30),
             proptest::collection::vec(any::<bool>(), 1..6), 0usize..4),
            1..4),
    ) {
        let mut ev = Events::new();
        for (e, &c) in controllable.iter().enumerate().take(n_events) {
            ev.intern(&format!("e{e}<&\"{e}\">"), c);
        }
        let kinds = [ComponentKind::Plant, ComponentKind::Spec, ComponentKind::Supervisor, ComponentKind::Property];
        let built: Vec<(String, ComponentKind, Automaton)> = automata
            .iter()
            .enumerate()
            .map(|(i, (states, marked, trans, blocked, kind))| {
                (format!("C{i}"), kinds[*kind], random_automaton(&ev, n_events, *states, marked, trans, blocked))
            })
            .collect();
        let out: Vec<ComponentOut> = built.iter().map(|(n, k, a)| ComponentOut { name: n, kind: *k, automaton: a }).collect();
        let text = write_wmod("random", "", &out, &ev, &[]);
        let mut ev2 = Events::new();
        let m = read_wmod(&text, &mut ev2).map_err(|e| TestCaseError::fail(format!("{:?}\n{text}", e.diagnostic(&text))))?;
        prop_assert_eq!(m.components.len(), built.len());
        for ((name, kind, a), c) in built.iter().zip(&m.components) {
            let b = &c.automaton;
            prop_assert_eq!((name, *kind), (&c.name, c.kind));
            prop_assert_eq!((a.num_states(), a.num_transitions(), a.init()), (b.num_states(), b.num_transitions(), b.init()));
            let names = |x: &Automaton, ev: &Events| x.alphabet().iter().map(|&e| (ev.name(e).to_string(), ev.is_controllable(e))).collect::<std::collections::BTreeSet<_>>();
            prop_assert_eq!(names(a, &ev), names(b, &ev2));
            for s in a.states() {
                prop_assert_eq!(a.state_name(s), b.state_name(s));
                prop_assert_eq!(a.is_marked(s), b.is_marked(s));
                let edges = |x: &Automaton, ev: &Events| x.edges(s).iter().map(|e| (ev.name(e.event).to_string(), e.target)).collect::<std::collections::BTreeSet<_>>();
                prop_assert_eq!(edges(a, &ev), edges(b, &ev2));
            }
        }
    }
}

/// The fuzz target's check (`fuzz/src/lib.rs`) on the fixture, its prefixed form and every
/// example that maps, as exported: the seeds of the `wmod` target pass it.
#[test]
fn wmod_fixtures_pass_the_fuzz_check() {
    let src = fixture("small_factory.wmod");
    crate::harness::check_wmod(&src);
    crate::harness::check_wmod(&prefixed(&src));
    for entry in std::fs::read_dir(root().join("examples/sct")).unwrap() {
        let src = std::fs::read_to_string(entry.unwrap().path()).unwrap();
        let (loaded, _) = compile(&src).unwrap_or_else(|d| panic!("{d:?}"));
        let Ok(classic) = project_to_classic(&src, &loaded, &[]) else { continue };
        let out: Vec<ComponentOut> = classic
            .components
            .iter()
            .map(|(name, kind, automaton)| ComponentOut { name, kind: *kind, automaton })
            .collect();
        crate::harness::check_wmod(&write_wmod("m", "", &out, &classic.events, &classic.attributes()));
    }
}
