//! Cross-check against libFAUDES: random plant/specification pairs are solved by plcsynth and
//! by libFAUDES (`SupCon`, `SupConClosed`, `StateMin`, `LanguageEquality`), side by side.
//! Two families alternate: independent random specifications, and specifications that cut one
//! uncontrollable transition out of the plant (so that synthesis has to restrict). The
//! textbook problems with published sizes are checked the same way.
//!
//! Needs the virtualenv created by `scripts/python-checkers.sh` (run by `make test`). Without
//! it the test fails and says so: a silently skipped comparison proves nothing.

use plcsynth::rng::Rng;
use plcsynth::sct::classic::gen::{read_gen, write_gen};
use plcsynth::sct::classic::{
    is_controllable, language_equal, minimize, product, supcon, Automaton, AutomatonBuilder, ClassicEventId, Events,
    StateId,
};
use std::path::{Path, PathBuf};
use std::process::Command;

fn random_automaton(
    rng: &mut Rng,
    ev: &Events,
    alphabet: &[ClassicEventId],
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
                b.add_transition(StateId::from_raw(from), e, StateId::from_raw(s));
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
                b.add_transition(StateId::from_raw(s), e, StateId::from_raw(t));
            }
        }
    }
    b.set_init(StateId::new(0));
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
    let edges: Vec<(StateId, ClassicEventId, StateId)> =
        plant.states().flat_map(|s| plant.edges(s).iter().map(move |e| (s, e.event, e.target))).collect();
    // States the plant reaches from its initial state by uncontrollable events alone: a cut
    // there would leave nothing to synthesise, so the cut is chosen elsewhere if possible.
    let mut forced = vec![false; plant.num_states()];
    let mut stack: Vec<StateId> = plant.init().into_iter().collect();
    while let Some(s) = stack.pop() {
        if !std::mem::replace(&mut forced[s.index()], true) {
            stack.extend(plant.edges(s).iter().filter(|e| !ev.is_controllable(e.event)).map(|e| e.target));
        }
    }
    let mut uncontrollable: Vec<usize> =
        (0..edges.len()).filter(|&i| !ev.is_controllable(edges[i].1) && !forced[edges[i].0.index()]).collect();
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
    b.set_init(plant.init().unwrap_or(StateId::new(0)));
    b.build().unwrap()
}

/// The ways a generator of the random comparison is emptied, so that its files have empty
/// sections (`<MarkedStates/>`, `<TransRel/>`, `<States/>`, `<InitStates/>`, `<Alphabet/>`).
#[derive(Clone, Copy, Debug)]
enum Emptied {
    SpecUnmarked,
    PlantUnmarked,
    SpecWithoutTransitions,
    PlantWithoutTransitions,
    SpecWithoutStates,
    PlantWithoutInitialState,
    NoEvents,
}

/// A copy of `a` without its marking, transitions or initial state.
fn stripped(a: &Automaton, marking: bool, transitions: bool, init: bool) -> Automaton {
    let mut b = AutomatonBuilder::new();
    for &e in a.alphabet() {
        b.add_event(e);
    }
    for s in a.states() {
        b.add_state(a.state_name(s), marking && a.is_marked(s));
        if transitions {
            for e in a.edges(s) {
                b.add_transition(s, e.event, e.target);
            }
        }
    }
    if let Some(i) = a.init().filter(|_| init) {
        b.set_init(i);
    }
    b.build().unwrap()
}

/// Applies `how` to a case's plant and specification.
fn emptied(how: Emptied, plant: Automaton, spec: Automaton, rng: &mut Rng) -> (Automaton, Automaton) {
    match how {
        Emptied::SpecUnmarked => (plant, stripped(&spec, false, true, true)),
        Emptied::PlantUnmarked => (stripped(&plant, false, true, true), spec),
        Emptied::SpecWithoutTransitions => (plant, stripped(&spec, true, false, true)),
        Emptied::PlantWithoutTransitions => (stripped(&plant, true, false, true), spec),
        Emptied::SpecWithoutStates => (plant, Automaton::empty(spec.alphabet().to_vec())),
        Emptied::PlantWithoutInitialState => (stripped(&plant, true, true, false), spec),
        Emptied::NoEvents => {
            let lone = |rng: &mut Rng| {
                let mut b = AutomatonBuilder::new();
                for s in 0..1 + rng.below(3) {
                    b.add_state(format!("q{s}"), rng.chance(50));
                }
                b.set_init(StateId::new(0));
                b.build().unwrap()
            };
            (lone(rng), lone(rng))
        }
    }
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

const EMPTIED: [Emptied; 7] = [
    Emptied::SpecUnmarked,
    Emptied::PlantUnmarked,
    Emptied::SpecWithoutTransitions,
    Emptied::PlantWithoutTransitions,
    Emptied::SpecWithoutStates,
    Emptied::PlantWithoutInitialState,
    Emptied::NoEvents,
];

/// Random problems solved by plcsynth and by libFAUDES, compared by language and minimal size.
/// libFAUDES then writes every generator back (`Write` and `XWrite` alternately), and plcsynth
/// reads those files: the plant and specification as written, SupCon on them, and libFAUDES's
/// supervisors must all agree with ours.
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
    let mut problems = Vec::new();
    for case in 0..cases {
        let mut ev = Events::new();
        let n_events = 2 + rng.below(6) as usize;
        // Percentage of controllable events; the pruned family (odd cases) needs controllable
        // events upstream of its cut to be informative.
        let ratio = if case % 2 == 0 { [0, 25, 50, 75, 100][(case / 2) % 5] } else { [50, 70, 85][(case / 2) % 3] };
        let alphabet: Vec<ClassicEventId> =
            (0..n_events).map(|i| ev.intern(&format!("e{i}"), rng.chance(ratio))).collect();
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
        // Every eighth case empties a section of one generator, so that both libFAUDES and our
        // reader meet `<TransRel/>`, `<MarkedStates/>` and the other self-closing forms.
        let (plant, spec) = if case % 8 == 7 {
            let how = EMPTIED[(case / 8) % EMPTIED.len()];
            emptied(how, plant, spec, &mut rng)
        } else {
            (plant, spec)
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
        problems.push((plant, spec, sup, supc, ev));
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
    let mut self_closing = std::collections::BTreeSet::new();
    for (case, (plant, spec, sup, supc, ev)) in problems.iter_mut().enumerate() {
        let d = dir.join(format!("case{case:03}"));
        let mut read = |file: &str| {
            let text = std::fs::read_to_string(d.join(file)).unwrap();
            for tag in
                ["Alphabet", "States", "StateSet", "TransRel", "TransitionRelation", "InitStates", "MarkedStates"]
            {
                if text.contains(&format!("<{tag}/>")) {
                    self_closing.insert(tag);
                }
            }
            read_gen(&text, ev).unwrap_or_else(|e| panic!("case {case}: {file}: {}", e.diagnostic(&text).message))
        };
        let (lf_plant, lf_spec, lf_sup, lf_supc) =
            (read("lf_plant.gen"), read("lf_spec.gen"), read("lf_sup.gen"), read("lf_supc.gen"));
        let same = |a: &Automaton, b: &Automaton| {
            a.num_states() == b.num_states()
                && a.num_transitions() == b.num_transitions()
                && a.alphabet() == b.alphabet()
                && same_language(a, b)
        };
        assert!(same(&lf_plant, plant), "case {case}: the plant libFAUDES wrote reads differently");
        assert!(same(&lf_spec, spec), "case {case}: the specification libFAUDES wrote reads differently");
        assert_eq!(lf_sup.num_states() as u64, lines[case]["faudes_states"].as_u64().unwrap(), "case {case}");
        assert!(same_language(&lf_sup, sup), "case {case}: libFAUDES's supervisor, read back, differs from ours");
        assert!(same_language(&lf_supc, supc), "case {case}: libFAUDES's closed supervisor, read back, differs");
        let again = supcon(&lf_plant, &lf_spec, ev, true).unwrap();
        assert!(same_language(&again, &lf_sup), "case {case}: SupCon on libFAUDES's files differs from libFAUDES's");
    }
    // libFAUDES writes an empty set as a self-closing section; every kind must have come up.
    assert_eq!(
        self_closing.into_iter().collect::<Vec<_>>(),
        ["Alphabet", "InitStates", "MarkedStates", "StateSet", "States", "TransRel", "TransitionRelation"]
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// Equal marked languages and equal prefix-closures.
fn same_language(a: &Automaton, b: &Automaton) -> bool {
    let min = |x: &Automaton| minimize(x);
    language_equal(&min(a), &min(b)) && language_equal(&min(&a.with_all_marked()), &min(&b.with_all_marked()))
}

/// The textbook problems with published supervisor sizes (small factory, transfer line, the
/// five AGVs): libFAUDES computes the same languages and the same (unminimised) state counts.
#[test]
fn textbook_supervisors_agree_with_libfaudes() {
    use plcsynth::benchmarks::textbook::{agv, small_factory, transfer_line};
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

/// Token-level forms libFAUDES reads, written by hand: (file stem, text). libFAUDES's reading of
/// each is the expectation (`faudes_forms.py read`).
const HAND_WRITTEN: &[(&str, &str)] = &[
    // Unnamed states count from 1 over every state read before them: `x` is state 2.
    ("unnamed_count", "<Generator> <Alphabet> a </Alphabet> <States> 5 x </States> <TransRel> 2 a 5 </TransRel> <InitStates> x </InitStates> </Generator>"),
    ("relaxed_indices", "<Generator> <Alphabet/> <States/> <TransRel> 1 a 2 2 b 7 </TransRel> <InitStates> 1 </InitStates> <MarkedStates> 7 </MarkedStates> </Generator>"),
    ("relaxed_names", "<Generator> <TransRel> p a q q b p </TransRel> <InitStates> p </InitStates> </Generator>"),
    ("relaxed_mixed", "<Generator> <TransRel> p a q 3 b p </TransRel> </Generator>"),
    ("index_suffix", "<Generator> <Alphabet> a </Alphabet> <States> x#4 y#2 </States> <TransRel> 4 a y y a x </TransRel> <InitStates> 4 </InitStates> </Generator>"),
    ("index_suffix_mixed", "<Generator> <Alphabet> a </Alphabet> <States> x#4 y </States> <TransRel/> </Generator>"),
    ("short_tags", "<Generator> \"nm\" <A> a +C+ b </A> <S> 1 2 </S> <T> 1 a 2 2 b 1 </T> <I> 1 </I> <M> 2 </M> </Generator>"),
    ("consecutive_init", "<Generator> <Alphabet> a </Alphabet> <States> <Consecutive> 1 3 </Consecutive> </States> <TransRel/> <InitStates> <Consecutive> 2 2 </Consecutive> </InitStates> <MarkedStates> <Consecutive> 1 3 </Consecutive> </MarkedStates> </Generator>"),
    ("hex_index_and_flags", "<Generator> <Alphabet> a 0x01 b 0x10 c +c+ </Alphabet> <States> 0x1 2 </States> <TransRel> 1 a 2 2 b 1 2 c 2 </TransRel> </Generator>"),
    ("quoted_numbers", "<Generator> <Alphabet> \"1\" </Alphabet> <States> \"7\" 2 </States> <TransRel> 1 \"1\" 2 2 1 \"7\" </TransRel> </Generator>"),
    ("entities", "<Generator> <Alphabet> a&lt;b \"c&amp;d\" </Alphabet> <States> s&amp;t </States> <TransRel> s&amp;t a&lt;b \"s&amp;t\" </TransRel> </Generator>"),
    ("single_quotes_cdata", "<Generator> 'my gen' <Alphabet> 'a' <![CDATA[b]]> </Alphabet> <States> 1 </States> <TransRel> 1 'a' 1 1 b 1 </TransRel> </Generator>"),
    ("xml_comments_declarations", "<?xml version=\"1.0\"?>\n<!DOCTYPE Generator SYSTEM \"generator.dtd\">\n<!-- a comment -->\n<Generator> <!-- x --> <Alphabet> a </Alphabet>\n% a faudes comment <not markup>\n<States> 1 % trailing\n</States> <TransRel> 1 a 1 </TransRel> </Generator>"),
    ("crlf_tabs", "<Generator>\r\n<Alphabet>\ta\t+C+\r\n</Alphabet>\r\n<States>\r\n1\t2\r\n</States>\r\n<TransRel>\r\n1\ta\t2\r\n</TransRel>\r\n<InitStates> 1 </InitStates>\r\n</Generator>\r\n"),
    ("attributes_skipped", "<Generator name=\"with space\" ftype=System> <Alphabet> a +C+ <Extra> 1 x </Extra> b </Alphabet> <States> 1 +X+ 2 <Attr> 9 </Attr> 3 </States> <TransRel> 1 a 2 +Y+ 2 b 3 0x10 <T> 5 </T> </TransRel> </Generator>"),
    ("numbers_as_attributes", "<Generator> <Alphabet> a </Alphabet> <States> x true 2 -1 </States> <TransRel> x a 2 </TransRel> </Generator>"),
    ("decimal_is_index", "<Generator> <Alphabet> a </Alphabet> <States> 1.5 2 </States> <TransRel> 1 a 2 </TransRel> </Generator>"),
    ("negative_first", "<Generator> <Alphabet> a </Alphabet> <States> -1 2 </States> <TransRel> -1 a 2 </TransRel> </Generator>"),
    ("xml_by_name", "<Generator> <Alphabet> <Event name=\"a\"/> <Event name='u'><Controllable value=\"false\"/></Event> </Alphabet> <StateSet> <State id=\"3\" name=\"p\"> <Initial/> </State> <State name=\"q\" id=\"5\"><Marked value=\"true\"/><Initial value=\"false\"/></State> <Consecutive from=\"7\" to=\"9\"/> </StateSet> <TransitionRelation> <Transition x1=\"3\" event=\"a\" x2=\"q\"/> <Transition x1=\"q\" event=\"u\" x2=\"8\"/> </TransitionRelation> </Generator>"),
    ("trailing_sections", "<Generator> <Alphabet> a </Alphabet> <States> 1 </States> <TransRel/> <InitStates> 1 </InitStates> <MarkedStates/> <Foo> x y </Foo> </Generator> trailing text"),
    ("state_index_zero", "<Generator> <Alphabet> a </Alphabet> <States> 0 1 </States> <TransRel/> </Generator>"),
    ("duplicate_state", "<Generator> <Alphabet> a </Alphabet> <States> 1 1.5 </States> <TransRel/> </Generator>"),
    ("unknown_event", "<Generator> <Alphabet> a </Alphabet> <States> 1 </States> <TransRel> 1 b 1 </TransRel> </Generator>"),
    ("unknown_state", "<Generator> <Alphabet> a </Alphabet> <States> 1 </States> <TransRel> 1 a 2 </TransRel> </Generator>"),
    ("suffix_outside_states", "<Generator> <Alphabet> a </Alphabet> <States> x#1 </States> <TransRel/> <InitStates> x#1 </InitStates> </Generator>"),
    ("nondeterministic_by_hand", "<Generator> <Alphabet> a </Alphabet> <States> 1 2 </States> <TransRel> 1 a 1\n1 a 2 </TransRel> </Generator>"),
    // Without a <TransRel>, libFAUDES tries the XML format and fails; plcsynth reads no transitions.
    ("no_trans_rel", "<Generator> <Alphabet> a </Alphabet> <States> 1 </States> <InitStates> 1 </InitStates> </Generator>"),
];

/// Files libFAUDES refuses that plcsynth reads, on purpose: a generator written under another
/// label (libFAUDES needs the label to read it back) and one without `<TransRel>`.
const LENIENT: &[&str] = &["native_labelled", "hand_no_trans_rel"];

/// Files libFAUDES's `System` reads that plcsynth refuses, on purpose: state index 0, which
/// libFAUDES reserves for "no state" (its `Generator` refuses it too), and a `<TransRel>` naming
/// a state that `<States>` does not declare. libFAUDES means to add such states only when no
/// states are declared (2.24e), but its test for that looks at a fresh empty set, so it adds
/// them always; plcsynth reports the unknown state, which is most likely a typo.
const STRICT: &[&str] = &["hand_state_index_zero", "hand_unknown_state"];

/// Our reading of a generator in the shape `faudes_forms.py read` prints.
fn describe(a: &Automaton, ev: &Events) -> serde_json::Value {
    let label = |s: StateId| a.state_name(s).to_string();
    let sorted = |mut v: Vec<String>| {
        v.sort();
        v
    };
    let states = a.states();
    let mut trans: Vec<[String; 3]> = states
        .clone()
        .flat_map(|s| a.edges(s).iter().map(move |e| [label(s), ev.name(e.event).to_string(), label(e.target)]))
        .collect();
    trans.sort();
    serde_json::json!({
        "states": sorted(states.clone().map(label).collect()),
        "init": sorted(a.init().into_iter().map(label).collect()),
        "marked": sorted(states.filter(|&s| a.is_marked(s)).map(label).collect()),
        "alphabet": sorted(a.alphabet().iter().map(|&e| ev.name(e).to_string()).collect()),
        "controllable": sorted(a.alphabet().iter().filter(|&&e| ev.is_controllable(e)).map(|&e| ev.name(e).to_string()).collect()),
        "transitions": trans,
    })
}

/// Every form libFAUDES writes (`Write` and `XWrite`: empty sections as `<TransRel/>`,
/// `<MarkedStates/>`, `<InitStates/>`, `<States/>`, `<Alphabet/>`; `+C+` and other attributes;
/// names, `name#index`, `<Consecutive>`; large generators whose `<TransRel>` uses indices) and
/// the token-level forms above are read as libFAUDES reads them; libFAUDES's errors are ours,
/// and nondeterministic generators are refused with a located message.
#[test]
fn reader_reads_every_form_libfaudes_writes() {
    use plcsynth::sct::classic::gen::read_gen_file;
    let py = venv_python();
    let dir = std::env::temp_dir().join(format!("plcsynth-gen-forms-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/faudes_forms.py");
    let out = Command::new(&py).arg(&script).arg("write").arg(&dir).output().unwrap();
    assert!(out.status.success(), "libFAUDES failed to write: {}", String::from_utf8_lossy(&out.stderr));
    for (stem, text) in HAND_WRITTEN {
        std::fs::write(dir.join(format!("hand_{stem}.gen")), text).unwrap();
    }
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir).unwrap().map(|e| e.unwrap().path()).collect();
    files.sort();
    let texts: Vec<String> = files.iter().map(|f| std::fs::read_to_string(f).unwrap()).collect();
    // The forms this test is about must be among the files.
    let all = texts.concat();
    for form in [
        "<TransRel/>",
        "<MarkedStates/>",
        "<InitStates/>",
        "<States/>",
        "<Alphabet/>",
        "<StateSet/>",
        "<TransitionRelation/>",
        "<Consecutive>",
        "<Consecutive from=",
        "+C+",
        "+CF+",
        "<Controllable/>",
        "#2",
        "<Generator name=",
        "ftype=\"System\"",
    ] {
        assert!(all.contains(form), "no file has {form}");
    }
    let out = Command::new(&py).arg(&script).arg("read").args(&files).output().unwrap();
    assert!(out.status.success(), "libFAUDES failed to read: {}", String::from_utf8_lossy(&out.stderr));
    let theirs: Vec<serde_json::Value> = String::from_utf8(out.stdout)
        .unwrap()
        .lines()
        .filter(|l| l.starts_with('{'))
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    assert_eq!(theirs.len(), files.len());
    let mut agreed = 0;
    for ((file, text), v) in files.iter().zip(&texts).zip(&theirs) {
        let stem = file.file_stem().unwrap().to_str().unwrap();
        let mut ev = Events::new();
        let ours = read_gen_file(text, &mut ev);
        if LENIENT.contains(&stem) {
            assert_eq!(v["ok"], false, "{stem}: libFAUDES now reads it: {v}");
            assert!(ours.is_ok(), "{stem}: {:?}", ours.err());
            continue;
        }
        if STRICT.contains(&stem) {
            assert_eq!(v["ok"], true, "{stem}: libFAUDES now refuses it: {v}");
            assert!(ours.is_err(), "{stem}: read");
            continue;
        }
        if v["ok"] == false {
            assert!(ours.is_err(), "{stem}: libFAUDES refuses it ({}), we read it", v["error"]);
            continue;
        }
        let deterministic = v["deterministic"] == true && v["init"].as_array().unwrap().len() <= 1;
        match ours {
            Ok(g) => {
                assert!(deterministic, "{stem}: nondeterministic, yet read: {v}");
                let mut mine = describe(&g.automaton, &ev);
                mine["ok"] = true.into();
                mine["deterministic"] = true.into();
                mine["file"] = v["file"].clone();
                assert_eq!(&mine, v, "{stem}: read differently");
                agreed += 1;
            }
            Err(e) => {
                assert!(!deterministic, "{stem}: libFAUDES reads it, we refuse: {e:?}");
                let d = e.diagnostic(text);
                assert!(
                    d.message.contains("two transitions on event") || d.message.contains("a second initial state"),
                    "{stem}: {}",
                    d.message
                );
                assert!(d.notes.iter().any(|n| n.contains("SupCon needs deterministic generators")), "{stem}: {d:?}");
            }
        }
    }
    eprintln!("{agreed} of {} files read alike", files.len());
    assert!(agreed >= 40, "only {agreed} files read alike");
    let _ = std::fs::remove_dir_all(&dir);
}
