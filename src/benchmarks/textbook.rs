//! Classic textbook problems rebuilt from their published definitions (Wonham's course notes,
//! "Supervisory Control of Discrete-Event Systems"): the small factory, the transfer line and the
//! five automated guided vehicles.
//! Each function returns the plant, the specification and the shared event table.

use crate::sct::classic::{product, Automaton, AutomatonBuilder, ClassicEventId, Events, StateId};

/// Builds an automaton from `(from, event, to)` triples over named states; the first state
/// listed in `states` is initial, `marked` lists the marked ones.
pub fn build(
    events: &Events,
    alphabet: &[&str],
    states: &[&str],
    marked: &[&str],
    trans: &[(&str, &str, &str)],
) -> Automaton {
    let mut b = AutomatonBuilder::new();
    for a in alphabet {
        b.add_event(events.get(a).expect("event declared"));
    }
    for s in states {
        b.add_state(*s, marked.contains(s));
    }
    let id = |n: &str| states.iter().position(|s| *s == n).expect("state declared");
    for (f, e, t) in trans {
        b.add_transition(StateId::new(id(f)), events.get(e).expect("event declared"), StateId::new(id(t)));
    }
    b.set_init(StateId::new(0));
    b.build().expect("textbook automaton is deterministic")
}

fn declare(events: &mut Events, controllable: &[&str], uncontrollable: &[&str]) {
    for c in controllable {
        events.intern(c, true);
    }
    for u in uncontrollable {
        events.intern(u, false);
    }
}

/// A machine `I -start-> W -finish-> I`, with optional breakdown `W -brk-> D -rep-> I`.
fn machine(events: &Events, start: &str, finish: &str, brk: Option<(&str, &str)>) -> Automaton {
    match brk {
        None => build(events, &[start, finish], &["I", "W"], &["I"], &[("I", start, "W"), ("W", finish, "I")]),
        Some((b, r)) => build(
            events,
            &[start, finish, b, r],
            &["I", "W", "D"],
            &["I"],
            &[("I", start, "W"), ("W", finish, "I"), ("W", b, "D"), ("D", r, "I")],
        ),
    }
}

/// Wonham's small factory: two machines with breakdown and repair, a buffer of capacity one
/// between them (BUFSPEC) and priority of repair for the second machine (BRSPEC).
/// Events: `a_i` start (c), `b_i` finish (u), `l_i` breakdown (u), `m_i` repair (c).
/// The published supervisor has 12 states and 24 transitions.
pub fn small_factory() -> (Automaton, Automaton, Events) {
    let mut ev = Events::new();
    declare(&mut ev, &["a1", "m1", "a2", "m2"], &["b1", "l1", "b2", "l2"]);
    let m1 = machine(&ev, "a1", "b1", Some(("l1", "m1")));
    let m2 = machine(&ev, "a2", "b2", Some(("l2", "m2")));
    let plant = product(&m1, &m2, ev.len()).automaton;
    let buf = build(&ev, &["b1", "a2"], &["0", "1"], &["0"], &[("0", "b1", "1"), ("1", "a2", "0")]);
    let br =
        build(&ev, &["l2", "m2", "m1"], &["0", "1"], &["0"], &[("0", "l2", "1"), ("1", "m2", "0"), ("0", "m1", "0")]);
    let spec = product(&buf, &br, ev.len()).automaton;
    (plant, spec, ev)
}

/// A buffer counting `up` events in and `down` events out, holding at most `cap` pieces;
/// every count is marked only at zero.
pub fn buffer(events: &Events, up: &[&str], down: &[&str], cap: usize) -> Automaton {
    let mut b = AutomatonBuilder::new();
    let ups: Vec<ClassicEventId> = up.iter().map(|e| events.get(e).expect("declared")).collect();
    let downs: Vec<ClassicEventId> = down.iter().map(|e| events.get(e).expect("declared")).collect();
    for &e in ups.iter().chain(&downs) {
        b.add_event(e);
    }
    for k in 0..=cap {
        b.add_state(k.to_string(), k == 0);
    }
    for k in 0..=cap {
        if k < cap {
            for &u in &ups {
                b.add_transition(StateId::new(k), u, StateId::new(k + 1));
            }
        }
        if k > 0 {
            for &d in &downs {
                b.add_transition(StateId::new(k), d, StateId::new(k - 1));
            }
        }
    }
    b.set_init(StateId::new(0));
    b.build().expect("buffer is deterministic")
}

/// Wonham's transfer line: machines M1, M2 and test unit TU; buffer B1 (capacity `c1`) fed by
/// M1's output (2) and TU's rejects (60), emptied by M2 (3); buffer B2 (capacity `c2`) fed by
/// M2 (4), emptied by TU (5). Controllable: 1, 3, 5; uncontrollable: 2, 4, 60, 80.
/// With capacities 3 and 1 the published supervisor has 28 states and 65 transitions.
pub fn transfer_line(c1: usize, c2: usize) -> (Automaton, Automaton, Events) {
    let mut ev = Events::new();
    declare(&mut ev, &["1", "3", "5"], &["2", "4", "60", "80"]);
    let m1 = machine(&ev, "1", "2", None);
    let m2 = machine(&ev, "3", "4", None);
    let tu =
        build(&ev, &["5", "60", "80"], &["I", "W"], &["I"], &[("I", "5", "W"), ("W", "60", "I"), ("W", "80", "I")]);
    let plant = product(&product(&m1, &m2, ev.len()).automaton, &tu, ev.len()).automaton;
    let b1 = buffer(&ev, &["2", "60"], &["3"], c1);
    let b2 = buffer(&ev, &["4"], &["5"], c2);
    let spec = product(&b1, &b2, ev.len()).automaton;
    (plant, spec, ev)
}

/// The transfer-line family of [`super::transfer`] as a classic problem: the plant is the
/// product of all machines and test units, the specification the product of all buffers
/// (marked when empty). Used to compare SupCon times with libFAUDES on identical inputs.
pub fn transfer_lines_classic(k: usize, m: usize, cap: usize) -> (Automaton, Automaton, Events) {
    let mut ev = Events::new();
    let dev = |i: usize, j: usize| if j == m + 1 { format!("TL{i}.TU") } else { format!("TL{i}.M{j}") };
    for i in 1..=k {
        for j in 1..=m + 1 {
            ev.intern(&format!("{}.start", dev(i, j)), true);
            if j == m + 1 {
                ev.intern(&format!("{}.reject", dev(i, j)), false);
                ev.intern(&format!("{}.accept", dev(i, j)), false);
            } else {
                ev.intern(&format!("{}.finish", dev(i, j)), false);
            }
        }
    }
    let mut plant: Option<Automaton> = None;
    for i in 1..=k {
        for j in 1..=m + 1 {
            let d = dev(i, j);
            let (s, names) =
                (format!("{d}.start"), [format!("{d}.finish"), format!("{d}.reject"), format!("{d}.accept")]);
            let a = if j == m + 1 {
                build(
                    &ev,
                    &[&s, &names[1], &names[2]],
                    &["I", "W"],
                    &["I"],
                    &[("I", &s, "W"), ("W", &names[1], "I"), ("W", &names[2], "I")],
                )
            } else {
                build(&ev, &[&s, &names[0]], &["I", "W"], &["I"], &[("I", &s, "W"), ("W", &names[0], "I")])
            };
            plant = Some(match plant {
                None => a,
                Some(p) => product(&p, &a, ev.len()).automaton,
            });
        }
    }
    let mut spec: Option<Automaton> = None;
    for i in 1..=k {
        for j in 1..=m {
            let mut ins = vec![format!("{}.finish", dev(i, j))];
            if j == 1 {
                ins.push(format!("TL{i}.TU.reject"));
            }
            let outs = [format!("{}.start", dev(i, j + 1))];
            let ins: Vec<&str> = ins.iter().map(String::as_str).collect();
            let outs: Vec<&str> = outs.iter().map(String::as_str).collect();
            let b = buffer(&ev, &ins, &outs, cap);
            spec = Some(match spec {
                None => b,
                Some(s) => product(&s, &b, ev.len()).automaton,
            });
        }
        if i < k {
            let (a, s) = (format!("TL{i}.TU.accept"), format!("TL{}.M1.start", i + 1));
            let b = buffer(&ev, &[&a], &[&s], cap);
            spec = Some(product(spec.as_ref().expect("k >= 1"), &b, ev.len()).automaton);
        }
    }
    (plant.expect("k >= 1"), spec.expect("k >= 1"), ev)
}

/// A cyclic vehicle route: states `0..n`, the i-th event leads from state i to i+1 (mod n);
/// only the parked state 0 is marked.
fn route(events: &Events, cycle: &[&str]) -> Automaton {
    let names: Vec<String> = (0..cycle.len()).map(|i| i.to_string()).collect();
    let states: Vec<&str> = names.iter().map(String::as_str).collect();
    let trans: Vec<(&str, &str, &str)> =
        cycle.iter().enumerate().map(|(i, e)| (states[i], *e, states[(i + 1) % cycle.len()])).collect();
    build(events, cycle, &states, &["0"], &trans)
}

/// Mutual exclusion of two vehicles in one zone: `enter_a` events take the zone for the first
/// vehicle until one of its `leave_a` events, likewise for the second; all states are marked.
fn zone(events: &Events, enter_a: [&str; 2], leave_a: [&str; 2], enter_b: [&str; 2], leave_b: [&str; 2]) -> Automaton {
    let alphabet: Vec<&str> = enter_a.iter().chain(&leave_a).chain(&enter_b).chain(&leave_b).copied().collect();
    let mut trans = Vec::new();
    for e in enter_a {
        trans.push(("free", e, "a"));
    }
    for e in leave_a {
        trans.push(("a", e, "free"));
    }
    for e in enter_b {
        trans.push(("free", e, "b"));
    }
    for e in leave_b {
        trans.push(("b", e, "free"));
    }
    build(events, &alphabet, &["free", "a", "b"], &["free", "a", "b"], &trans)
}

/// Wonham's five automated guided vehicles serving a work cell (course notes, "AGVs"; the same
/// model is the AGV benchmark of Eclipse ESCET). Event `ij`: vehicle i, odd j controllable
/// (unpark / re-enter a zone), even j uncontrollable. Specifications: four shared zones
/// (Z1–Z4), the cyclic use of workstation 1 (two deliveries, then one pick-up), alternation at
/// workstations 2 and 3, and exclusion at the input parts stations (IPS).
/// The published supervisor has 4406 states and 11338 transitions.
pub fn agv() -> (Automaton, Automaton, Events) {
    let mut ev = Events::new();
    declare(
        &mut ev,
        &["11", "13", "21", "23", "31", "33", "41", "43", "51", "53"],
        &["10", "12", "18", "20", "22", "24", "26", "28", "32", "34", "40", "42", "44", "46", "50", "52"],
    );
    let n = ev.len();
    let vehicles = [
        route(&ev, &["11", "10", "13", "12"]),
        route(&ev, &["21", "18", "20", "22", "23", "24", "26", "28"]),
        route(&ev, &["33", "34", "31", "32"]),
        route(&ev, &["41", "40", "42", "43", "44", "46"]),
        route(&ev, &["51", "50", "53", "52"]),
    ];
    let plant = vehicles[1..].iter().fold(vehicles[0].clone(), |p, v| product(&p, v, n).automaton);
    let all = ["0", "1", "2", "3"];
    let specs = [
        zone(&ev, ["11", "13"], ["10", "12"], ["20", "23"], ["22", "24"]),
        zone(&ev, ["18", "24"], ["20", "26"], ["31", "33"], ["32", "34"]),
        zone(&ev, ["21", "26"], ["18", "28"], ["41", "44"], ["40", "46"]),
        zone(&ev, ["40", "43"], ["42", "44"], ["51", "53"], ["50", "52"]),
        // Workstation 1 assembles a part from AGV3 (32) and AGV4 (46), in either order, before
        // AGV5 takes it away (50).
        build(
            &ev,
            &["32", "46", "50"],
            &all,
            &all,
            &[("0", "32", "1"), ("0", "46", "2"), ("1", "46", "3"), ("2", "32", "3"), ("3", "50", "0")],
        ),
        build(&ev, &["12", "34"], &all[..2], &all[..2], &[("0", "12", "1"), ("1", "34", "0")]),
        build(&ev, &["28", "42"], &all[..2], &all[..2], &[("0", "28", "1"), ("1", "42", "0")]),
        build(
            &ev,
            &["10", "13", "22", "23"],
            &all[..3],
            &all[..3],
            &[("0", "10", "1"), ("1", "13", "0"), ("0", "22", "2"), ("2", "23", "0")],
        ),
    ];
    let spec = specs[1..].iter().fold(specs[0].clone(), |s, z| product(&s, z, n).automaton);
    (plant, spec, ev)
}
