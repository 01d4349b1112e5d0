//! Cross-check against libFAUDES: random plant/specification pairs are solved by plcsynth and
//! by libFAUDES (`SupCon`, `SupConClosed`, `StateMin`, `LanguageEquality`), side by side.
//! Two families alternate: independent random specifications, and specifications that cut one
//! uncontrollable transition out of the plant (so that synthesis has to restrict). The
//! textbook problems with published sizes are checked the same way.
//!
//! Needs the virtualenv created by `scripts/python-checkers.sh` (run by `make test`). Without
//! it the test fails and says so: a silently skipped comparison proves nothing.

use plcsynth::rng::Rng;
use plcsynth::sct::classic::{
    is_controllable, language_equal, minimize, product, supcon, Automaton, AutomatonBuilder, EventId, Events,
};
use plcsynth::sct::gen::write_gen;
use std::path::{Path, PathBuf};
use std::process::Command;

fn random_automaton(
    rng: &mut Rng,
    ev: &Events,
    alphabet: &[EventId],
    states: usize,
    density: (u64, u64),
    marked: u64,
) -> Automaton {
    let mut b = AutomatonBuilder::new();
    for &e in alphabet {
        b.add_event(e);
    }
    for s in 0..states {
        b.add_state(format!("q{s}"), rng.chance(marked));
    }
    // A spanning tree first, so that every state is reachable, then random extra transitions.
    let mut taken = std::collections::HashSet::new();
    for s in 1..states as u32 {
        for _ in 0..8 {
            let from = rng.below(s as u64) as u32;
            let e = alphabet[rng.below(alphabet.len() as u64) as usize];
            if taken.insert((from, e)) {
                b.add_transition(from, e, s);
                break;
            }
        }
    }
    for s in 0..states as u32 {
        for &e in alphabet {
            if taken.contains(&(s, e)) {
                continue;
            }
            let d = if ev.is_controllable(e) { density.0 } else { density.1 };
            if rng.chance(d) {
                let t = rng.below(states as u64) as u32;
                taken.insert((s, e));
                b.add_transition(s, e, t);
            }
        }
    }
    b.set_init(0);
    b.build().unwrap()
}

/// The plant with one uncontrollable transition cut out (chosen at random, away from the
/// initial state's uncontrollable reach where possible), each controllable
/// transition kept with probability `keep` percent, and each state marked with probability
/// `marked` percent: a specification that synthesis must enforce by cutting controllable
/// events upstream of the missing uncontrollable one.
fn pruned_copy(rng: &mut Rng, plant: &Automaton, ev: &Events, keep: u64, marked: u64) -> Automaton {
    let mut b = AutomatonBuilder::new();
    for &e in plant.alphabet() {
        b.add_event(e);
    }
    for s in 0..plant.num_states() {
        b.add_state(format!("h{s}"), rng.chance(marked));
    }
    let edges: Vec<(u32, EventId, u32)> = (0..plant.num_states() as u32)
        .flat_map(|s| plant.edges(s).iter().map(move |e| (s, e.event, e.target)))
        .collect();
    // States the plant reaches from its initial state by uncontrollable events alone: a cut
    // there would leave nothing to synthesise, so the cut is chosen elsewhere if possible.
    let mut forced = vec![false; plant.num_states()];
    let mut stack: Vec<u32> = plant.init().into_iter().collect();
    while let Some(s) = stack.pop() {
        if !std::mem::replace(&mut forced[s as usize], true) {
            stack.extend(plant.edges(s).iter().filter(|e| !ev.is_controllable(e.event)).map(|e| e.target));
        }
    }
    let mut uncontrollable: Vec<usize> =
        (0..edges.len()).filter(|&i| !ev.is_controllable(edges[i].1) && !forced[edges[i].0 as usize]).collect();
    if uncontrollable.is_empty() {
        uncontrollable = (0..edges.len()).filter(|&i| !ev.is_controllable(edges[i].1)).collect();
    }
    let cut = if uncontrollable.is_empty() {
        None
    } else {
        Some(uncontrollable[rng.below(uncontrollable.len() as u64) as usize])
    };
    for (i, &(s, e, t)) in edges.iter().enumerate() {
        let kept = if ev.is_controllable(e) { rng.chance(keep) } else { Some(i) != cut };
        if kept {
            b.add_transition(s, e, t);
        }
    }
    b.set_init(plant.init().unwrap_or(0));
    b.build().unwrap()
}

fn venv_python() -> PathBuf {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let py = root.join(".venv/bin/python");
    let ok = py.exists()
        && Command::new(&py).args(["-c", "import faudes"]).output().map(|o| o.status.success()).unwrap_or(false);
    assert!(
        ok,
        "libFAUDES is not installed in {}: run `scripts/python-checkers.sh` (or `make test`) first",
        root.join(".venv").display()
    );
    py
}

#[test]
fn supcon_agrees_with_libfaudes_on_random_problems() {
    let py = venv_python();
    let dir = std::env::temp_dir().join(format!("plcsynth-sct-faudes-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let mut rng = Rng::new(0x5EED_0005);
    let mut manifest = String::new();
    let mut ours_min = Vec::new();
    let cases = 240;
    let mut nontrivial = 0;
    let mut empty = 0;
    for case in 0..cases {
        let mut ev = Events::new();
        let n_events = 2 + rng.below(6) as usize;
        // Percentage of controllable events; the pruned family (odd cases) needs controllable
        // events upstream of its cut to be informative.
        let ratio = if case % 2 == 0 { [0, 25, 50, 75, 100][(case / 2) % 5] } else { [50, 70, 85][(case / 2) % 3] };
        let alphabet: Vec<EventId> = (0..n_events).map(|i| ev.intern(&format!("e{i}"), rng.chance(ratio))).collect();
        let plant_states = 2 + rng.below([4, 12, 40][case % 3]) as usize;
        let spec_states = 1 + rng.below(6) as usize;
        let density = [30, 50, 80][(case / 3) % 3];
        let plant = random_automaton(
            &mut rng,
            &ev,
            &alphabet,
            plant_states,
            (density, density * if case % 2 == 0 { 6 } else { 3 } / 10),
            75,
        );
        // Specifications are more permissive on uncontrollable events, so that synthesis has
        // something to keep in most cases. Every other case cuts a few transitions out of the
        // plant itself instead, which makes synthesis restrict without emptying.
        let spec = if case % 2 == 0 {
            random_automaton(&mut rng, &ev, &alphabet, spec_states, (70, [90, 97, 100][(case / 5) % 3]), 80)
        } else {
            pruned_copy(&mut rng, &plant, &ev, 85, 85)
        };
        let sup = supcon(&plant, &spec, &ev, true).unwrap();
        let supc = supcon(&plant, &spec, &ev, false).unwrap();
        // Our own checks against the definitions.
        assert!(is_controllable(&plant, &sup, &ev), "case {case}: SupCon result not controllable");
        assert!(is_controllable(&plant, &supc, &ev), "case {case}: SupConClosed result not controllable");
        assert!(sup.is_nonblocking(), "case {case}: SupCon result blocks");
        let both = product(&plant, &spec, ev.len()).automaton;
        let inside = product(&both, &sup, ev.len()).automaton;
        assert!(language_equal(&minimize(&inside), &minimize(&sup)), "case {case}: result not inside plant||spec");
        let min = minimize(&sup);
        let restricted_nb = sup.num_states() > 0 && !language_equal(&minimize(&sup), &minimize(&both.trim()));
        let restricted_closed = supc.num_states() > 0 && !language_equal(&minimize(&supc), &minimize(&both));
        if restricted_nb || restricted_closed {
            nontrivial += 1;
        }
        if sup.num_states() == 0 {
            empty += 1;
        }
        ours_min.push(if sup.init().is_some() { min.num_states() } else { 0 });
        manifest.push_str(&format!(
            "{}\n",
            write_case(&dir.join(format!("case{case:03}")), &plant, &spec, &sup, &supc, &ev).display()
        ));
    }
    eprintln!("{cases} cases: {nontrivial} restricted by synthesis, {empty} empty supervisors");
    assert!(
        nontrivial >= cases / 6 && empty <= cases / 2,
        "too few informative cases: {nontrivial} restricted, {empty} empty"
    );
    let lines = run_checker(&py, &dir, &manifest);
    assert_eq!(lines.len(), cases, "checker answered {} of {cases} cases", lines.len());
    for (case, v) in lines.iter().enumerate() {
        assert_languages_agree(v, &format!("case {case}"));
        let faudes_min = v["faudes_min_states"].as_u64().unwrap() as usize;
        assert_eq!(faudes_min, ours_min[case], "case {case}: minimal state counts differ: {v}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// The textbook problems with published supervisor sizes (small factory, transfer line, the
/// five AGVs): libFAUDES computes the same languages and the same (unminimised) state counts.
#[test]
fn textbook_supervisors_agree_with_libfaudes() {
    use plcsynth::sct::textbook::{agv, small_factory, transfer_line};
    let py = venv_python();
    let dir = std::env::temp_dir().join(format!("plcsynth-sct-textbook-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let problems = [("small factory", small_factory()), ("transfer line 3/1", transfer_line(3, 1)), ("AGV", agv())];
    let mut manifest = String::new();
    let mut sizes = Vec::new();
    for (name, (plant, spec, ev)) in &problems {
        // libFAUDES asks for the specification over the plant's alphabet.
        let spec = spec.with_selfloops(plant.alphabet());
        let sup = supcon(plant, &spec, ev, true).unwrap();
        let supc = supcon(plant, &spec, ev, false).unwrap();
        sizes.push(sup.num_states());
        manifest.push_str(&format!(
            "{}\n",
            write_case(&dir.join(name.replace([' ', '/'], "_")), plant, &spec, &sup, &supc, ev).display()
        ));
    }
    let lines = run_checker(&py, &dir, &manifest);
    assert_eq!(lines.len(), problems.len());
    for ((name, _), (v, ours)) in problems.iter().zip(lines.iter().zip(sizes)) {
        assert_languages_agree(v, name);
        assert_eq!(v["faudes_states"].as_u64().unwrap() as usize, ours, "{name}: SupCon state counts differ: {v}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// Writes one case directory in the layout `faudes_check.py` reads.
fn write_case(
    d: &Path,
    plant: &Automaton,
    spec: &Automaton,
    sup: &Automaton,
    supc: &Automaton,
    ev: &Events,
) -> PathBuf {
    std::fs::create_dir_all(d).unwrap();
    std::fs::write(d.join("plant.gen"), write_gen(plant, ev, "plant")).unwrap();
    std::fs::write(d.join("spec.gen"), write_gen(spec, ev, "spec")).unwrap();
    std::fs::write(d.join("sup.gen"), write_gen(sup, ev, "sup")).unwrap();
    std::fs::write(d.join("supc.gen"), write_gen(supc, ev, "supc")).unwrap();
    d.to_path_buf()
}

/// Runs `faudes_check.py` over the listed case directories; one JSON object per case.
fn run_checker(py: &Path, dir: &Path, manifest: &str) -> Vec<serde_json::Value> {
    let mpath = dir.join("manifest.txt");
    std::fs::write(&mpath, manifest).unwrap();
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/faudes_check.py");
    let out = Command::new(py).arg(&script).arg(&mpath).output().unwrap();
    assert!(out.status.success(), "libFAUDES checker failed: {}", String::from_utf8_lossy(&out.stderr));
    let text = String::from_utf8(out.stdout).unwrap();
    text.lines().filter(|l| l.starts_with('{')).map(|l| serde_json::from_str(l).unwrap()).collect()
}

fn assert_languages_agree(v: &serde_json::Value, what: &str) {
    for key in ["marked_eq", "closure_eq", "closed_gen_eq", "closed_marked_eq"] {
        assert_eq!(v[key], serde_json::Value::Bool(true), "{what}: libFAUDES disagrees on {key}: {v}");
    }
}
