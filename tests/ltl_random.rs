//! Random LTL formulas and specifications checked against definitions written here, apart
//! from the engine:
//! - the translation: on random lasso words `u v^ω`, the Büchi automaton accepts exactly when
//!   the formula holds, where "holds" is computed by fixpoints straight from the semantics of
//!   appendix C (X, U, R, G, F, W over the lasso's positions);
//! - the games: a realizable verdict comes with a controller under which no play is accepted
//!   by the automaton of the negation (checked by a product emptiness search written here), an
//!   unrealizable one with a counter-strategy under which every play is accepted by the
//!   automaton of the specification's negation's complement — i.e. no play satisfies the
//!   specification's automaton's rejection — checked the same way on the automaton of the
//!   specification; and never both.
//!
//! `PLCSYNTH_RANDOM_SPECS` scales the number of cases: five times it (400 by default, as the
//! timed tests), because an LTL case costs microseconds.

use plcsynth::ltl::testing::{translate, Automaton};
use plcsynth::ltl::{
    self, Config, Format, Ltl, Machine, Semantics, Signal, SignalId, SignalKind, Solver, Spec, Stop, Verdict,
};
use plcsynth::rng::Rng;

fn cases() -> usize {
    5 * std::env::var("PLCSYNTH_RANDOM_SPECS").ok().and_then(|v| v.parse().ok()).unwrap_or(400)
}

fn random_formula(rng: &mut Rng, signals: u32, depth: u32) -> Ltl {
    let leaf = depth == 0 || rng.chance(25);
    if leaf {
        return match rng.below(10) {
            0 => Ltl::True,
            1 => Ltl::False,
            _ => Ltl::Var(SignalId(rng.below(signals as u64) as u32)),
        };
    }
    let sub = |rng: &mut Rng| random_formula(rng, signals, depth - 1);
    match rng.below(13) {
        0 => Ltl::not(sub(rng)),
        1 => Ltl::And(vec![sub(rng), sub(rng)]),
        2 => Ltl::Or(vec![sub(rng), sub(rng)]),
        3 => Ltl::implies(sub(rng), sub(rng)),
        4 => Ltl::iff(sub(rng), sub(rng)),
        5 => Ltl::next(sub(rng)),
        6 => Ltl::globally(sub(rng)),
        7 => Ltl::finally(sub(rng)),
        8 => Ltl::until(sub(rng), sub(rng)),
        9 => Ltl::release(sub(rng), sub(rng)),
        10 => Ltl::weak_until(sub(rng), sub(rng)),
        11 => Ltl::globally(Ltl::finally(sub(rng))),
        _ => Ltl::finally(Ltl::globally(sub(rng))),
    }
}

/// The truth of `f` at every position of the lasso `letters` whose loop starts at `loop_start`.
fn holds(f: &Ltl, letters: &[u64], loop_start: usize) -> Vec<bool> {
    let n = letters.len();
    let succ = |i: usize| if i + 1 == n { loop_start } else { i + 1 };
    // Least (`least`) or greatest fixpoint of v(i) = now(i) || (keep(i) && v(succ(i))).
    let fix = |now: &[bool], keep: &[bool], least: bool| {
        let mut v = vec![!least; n];
        loop {
            let next: Vec<bool> = (0..n).map(|i| now[i] || (keep[i] && v[succ(i)])).collect();
            if next == v {
                return v;
            }
            v = next;
        }
    };
    match f {
        Ltl::True => vec![true; n],
        Ltl::False => vec![false; n],
        Ltl::Var(s) => letters.iter().map(|l| l >> s.0 & 1 == 1).collect(),
        Ltl::Not(a) => holds(a, letters, loop_start).iter().map(|x| !x).collect(),
        Ltl::And(xs) => xs.iter().fold(vec![true; n], |acc, x| {
            acc.iter().zip(holds(x, letters, loop_start)).map(|(a, b)| *a && b).collect()
        }),
        Ltl::Or(xs) => xs.iter().fold(vec![false; n], |acc, x| {
            acc.iter().zip(holds(x, letters, loop_start)).map(|(a, b)| *a || b).collect()
        }),
        Ltl::Implies(a, b) => holds(&Ltl::Or(vec![Ltl::not((**a).clone()), (**b).clone()]), letters, loop_start),
        Ltl::Iff(a, b) => {
            let (a, b) = (holds(a, letters, loop_start), holds(b, letters, loop_start));
            a.iter().zip(b).map(|(x, y)| *x == y).collect()
        }
        Ltl::Next(a) => {
            let a = holds(a, letters, loop_start);
            (0..n).map(|i| a[succ(i)]).collect()
        }
        // a U b: b now, or a now and a U b next (least fixpoint).
        Ltl::Until(a, b) => fix(&holds(b, letters, loop_start), &holds(a, letters, loop_start), true),
        Ltl::Finally(a) => fix(&holds(a, letters, loop_start), &vec![true; n], true),
        // a R b: b now, and a now or a R b next (greatest fixpoint) — as !( !a U !b ).
        Ltl::Release(a, b) => {
            let (na, nb): (Vec<bool>, Vec<bool>) = (
                holds(a, letters, loop_start).iter().map(|x| !x).collect(),
                holds(b, letters, loop_start).iter().map(|x| !x).collect(),
            );
            fix(&nb, &na, true).iter().map(|x| !x).collect()
        }
        Ltl::Globally(a) => {
            let na: Vec<bool> = holds(a, letters, loop_start).iter().map(|x| !x).collect();
            fix(&na, &vec![true; n], true).iter().map(|x| !x).collect()
        }
        // a W b = (a U b) || G a.
        Ltl::WeakUntil(a, b) => {
            let until = holds(&Ltl::until((**a).clone(), (**b).clone()), letters, loop_start);
            let always = holds(&Ltl::globally((**a).clone()), letters, loop_start);
            until.iter().zip(always).map(|(x, y)| *x || y).collect()
        }
    }
}

/// Whether the automaton has an accepting run on the lasso: an accepting edge of the product
/// of automaton and lasso positions that lies on a reachable cycle.
fn accepts(a: &Automaton, letters: &[u64], loop_start: usize) -> bool {
    if a.is_empty() {
        return false;
    }
    let n = letters.len();
    let id = |q: u32, i: usize| q as usize * n + i;
    let succ = |i: usize| if i + 1 == n { loop_start } else { i + 1 };
    let edges = |node: usize| {
        let (q, i) = (node / n, node % n);
        a.states[q].edges.iter().filter(move |e| e.enabled(letters[i])).map(move |e| (id(e.to, succ(i)), e.accepting))
    };
    let reach = |from: usize| {
        let mut seen = vec![false; a.states.len() * n];
        let mut stack = vec![from];
        seen[from] = true;
        while let Some(x) = stack.pop() {
            for (y, _) in edges(x) {
                if !seen[y] {
                    seen[y] = true;
                    stack.push(y);
                }
            }
        }
        seen
    };
    let reachable = reach(id(a.init, 0));
    (0..reachable.len()).filter(|&x| reachable[x]).any(|x| edges(x).any(|(y, accepting)| accepting && reach(y)[x]))
}

#[test]
fn the_automaton_accepts_exactly_the_lassos_the_formula_holds_on() {
    let mut rng = Rng::new(7);
    let names = |s: SignalId| format!("p{}", s.0);
    for case in 0..cases() {
        let formula = random_formula(&mut rng, 3, 4);
        let automaton = translate(&formula, &names, 100_000, u64::MAX).expect("small formulas translate");
        for _ in 0..20 {
            let len = 1 + rng.below(5) as usize;
            let letters: Vec<u64> = (0..len).map(|_| rng.below(8)).collect();
            let loop_start = rng.below(len as u64) as usize;
            let expected = holds(&formula, &letters, loop_start)[0];
            assert_eq!(
                accepts(&automaton, &letters, loop_start),
                expected,
                "case {case}: {} on {letters:?} looping at {loop_start}",
                formula.to_infix(&names)
            );
        }
    }
}

/// Whether some play of `machine` (against every behaviour of its opponent) has a run of
/// `automaton` with infinitely many accepting edges: a search of the product graph.
/// `machine` is a complete deterministic strategy, moves first exactly when `moves_first`,
/// and no play against it is accepted by `automaton` (that of what its player must avoid).
fn assert_wins(machine: &Machine, moves_first: bool, automaton: &Automaton, what: &str) {
    machine.validate().unwrap_or_else(|e| panic!("{what}: {e}"));
    assert_eq!(machine.moves_first, moves_first, "{what}");
    assert!(!some_play_accepted(machine, automaton), "{what}: a play against it is accepted");
}

pub(crate) fn some_play_accepted(machine: &Machine, automaton: &Automaton) -> bool {
    if automaton.is_empty() {
        return false;
    }
    let opponents = 1u64 << machine.reads.len();
    let mask = |signals: &[SignalId], v: u64| {
        signals.iter().enumerate().filter(|(i, _)| v >> i & 1 == 1).fold(0u64, |m, (_, s)| m | 1 << s.0)
    };
    let q_count = automaton.states.len();
    let node = |m: usize, q: usize| m * q_count + q;
    let successors = |x: usize| {
        let (m, q) = (x / q_count, x % q_count);
        let mut out = Vec::new();
        for v in 0..opponents {
            let row = machine.row(plcsynth::ltl::StateId(m as u32), v);
            let letter = mask(&machine.reads, v) | mask(&machine.writes, row.write);
            for e in automaton.states[q].edges.iter().filter(|e| e.enabled(letter)) {
                out.push((node(row.next.index(), e.to as usize), e.accepting));
            }
        }
        out
    };
    let reach = |from: usize| {
        let mut seen = vec![false; machine.states.len() * q_count];
        let mut stack = vec![from];
        seen[from] = true;
        while let Some(x) = stack.pop() {
            for (y, _) in successors(x) {
                if !seen[y] {
                    seen[y] = true;
                    stack.push(y);
                }
            }
        }
        seen
    };
    let reachable = reach(node(machine.init.index(), automaton.init as usize));
    (0..reachable.len()).filter(|&x| reachable[x]).any(|x| successors(x).iter().any(|&(y, acc)| acc && reach(y)[x]))
}

fn random_spec(rng: &mut Rng, semantics: Semantics) -> Spec {
    let signal = |name: &str, kind| Signal { name: name.into(), kind, span: Default::default() };
    let mut spec = Spec {
        signals: vec![
            signal("i0", SignalKind::Input),
            signal("i1", SignalKind::Input),
            signal("o0", SignalKind::Output),
            signal("o1", SignalKind::Output),
        ],
        semantics,
        ..Spec::default()
    };
    let clause = |formula| ltl::Clause { formula, span: Default::default() };
    for _ in 0..rng.below(2) {
        spec.assumptions.push(clause(random_formula(rng, 4, 3)));
    }
    for _ in 0..1 + rng.below(3) {
        spec.guarantees.push(clause(random_formula(rng, 4, 3)));
    }
    spec
}

#[test]
fn verdicts_come_with_strategies_that_win() {
    strategies_win(Solver::Explicit, 11);
}

#[test]
fn the_antichain_solver_wins_with_its_strategies_too() {
    strategies_win(Solver::Antichain, 13);
}

#[test]
fn the_symbolic_solver_wins_with_its_strategies_too() {
    strategies_win(Solver::Symbolic, 19);
}

#[test]
fn the_bdd_solver_wins_with_its_strategies_too() {
    strategies_win(Solver::Bdd, 23);
}

/// The solvers decide the same games: the same verdict at the same bound on every
/// specification all finish (the symbolic solver also builds the explicit one's positions).
#[test]
fn the_solvers_agree() {
    let mut rng = Rng::new(17);
    let mut compared = 0;
    for case in 0..cases() / 2 {
        let semantics = if case % 3 == 0 { Semantics::Moore } else { Semantics::Mealy };
        let spec = random_spec(&mut rng, semantics);
        let run = |solver| {
            let cfg = Config { max_k: 3, max_states: 20_000, solver, ..Config::default() };
            ltl::synthesize(&spec, &cfg, &mut |_| true)
                .ok()
                .filter(|o| o.limit.as_deref().is_none_or(|l| l.contains("--max-k")))
        };
        let solved = (run(Solver::Explicit), run(Solver::Antichain), run(Solver::Symbolic), run(Solver::Bdd));
        if let (Some(a), Some(b), Some(c), Some(d)) = solved {
            assert_eq!((a.verdict, a.k), (b.verdict, b.k), "case {case}: {}", spec.formula_text());
            assert_eq!((a.verdict, a.k), (c.verdict, c.k), "case {case}: {}", spec.formula_text());
            assert_eq!((a.verdict, a.k), (d.verdict, d.k), "case {case}: bdd: {}", spec.formula_text());
            assert_eq!(a.stats.positions, c.stats.positions, "case {case}: {}", spec.formula_text());
            compared += 1;
        }
    }
    assert!(compared > cases() / 4, "{compared} compared");
}

#[test]
fn a_run_is_cancelled_when_the_callback_says_so() {
    let source = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/examples/ltl/mutex.tlsf")).unwrap();
    let (spec, _) = ltl::compile(&source, Format::Tlsf, &[]).unwrap();
    let mut calls = 0;
    let result = ltl::synthesize(&spec, &Config::default(), &mut |_| {
        calls += 1;
        false
    });
    assert_eq!(result.err(), Some(Stop::Cancelled));
    assert_eq!(calls, 1);
}

fn strategies_win(solver: Solver, seed: u64) {
    let mut rng = Rng::new(seed);
    let names = |s: SignalId| ["i0", "i1", "o0", "o1"][s.index()].to_string();
    let (mut realizable, mut unrealizable) = (0, 0);
    let cfg = Config { max_k: 3, max_states: 20_000, solver, ..Config::default() };
    for case in 0..cases() / 2 {
        let semantics = if case % 3 == 0 { Semantics::Moore } else { Semantics::Mealy };
        let spec = random_spec(&mut rng, semantics);
        let Ok(outcome) = ltl::synthesize(&spec, &cfg, &mut |_| true) else { continue };
        let formula = spec.formula();
        let text = formula.to_infix(&names);
        match outcome.verdict {
            Verdict::Realizable => {
                realizable += 1;
                let controller = outcome.controller.as_ref().expect("a controller");
                controller.validate().unwrap();
                assert_eq!(controller.moves_first, semantics == Semantics::Moore);
                let negation = translate(&Ltl::not(formula.clone()), &names, 100_000, u64::MAX).unwrap();
                assert!(!some_play_accepted(controller, &negation), "case {case}: the controller violates {text}");
            }
            Verdict::Unrealizable => {
                unrealizable += 1;
                let counter = outcome.counter_strategy.as_ref().expect("a counter-strategy");
                counter.validate().unwrap();
                let automaton = translate(&formula, &names, 100_000, u64::MAX).unwrap();
                assert!(!some_play_accepted(counter, &automaton), "case {case}: the counter-strategy lets {text} hold");
            }
            Verdict::Unknown => {}
        }
    }
    assert!(realizable > cases() / 20 && unrealizable > cases() / 20, "{realizable} / {unrealizable}");
}

/// A random proposition over `signals`, at most one `X` deep.
fn random_prop(rng: &mut Rng, signals: u32, depth: u32) -> Ltl {
    if depth == 0 || rng.chance(30) {
        let v = Ltl::Var(SignalId(rng.below(signals as u64) as u32));
        return if rng.chance(50) { Ltl::not(v) } else { v };
    }
    let sub = |rng: &mut Rng| random_prop(rng, signals, depth - 1);
    match rng.below(5) {
        0 | 1 => Ltl::And(vec![sub(rng), sub(rng)]),
        2 | 3 => Ltl::Or(vec![sub(rng), sub(rng)]),
        _ => Ltl::next(random_prop(rng, signals, 0)),
    }
}

/// A random conjunct of the GR(1) fragment (`--solver gr1`).
fn random_gr1_conjunct(rng: &mut Rng, signals: u32) -> Ltl {
    let p = |rng: &mut Rng| random_prop(rng, signals, 2);
    match rng.below(9) {
        0 => p(rng),
        1 | 2 => Ltl::globally(p(rng)),
        3 => Ltl::globally(Ltl::finally(p(rng))),
        4 => Ltl::globally(Ltl::implies(p(rng), Ltl::finally(p(rng)))),
        5 => Ltl::globally(Ltl::implies(p(rng), Ltl::next(Ltl::until(p(rng), p(rng))))),
        6 => Ltl::release(p(rng), p(rng)),
        7 => Ltl::globally(Ltl::implies(p(rng), Ltl::weak_until(p(rng), p(rng)))),
        _ => Ltl::not(Ltl::finally(Ltl::globally(p(rng)))),
    }
}

/// The GR(1) game (`--solver gr1`) on random specifications of its fragment: it always
/// decides, where the explicit bounded games decide it agrees with them, and its strategies
/// win: no play of a controller is accepted by the automaton of the negation, none of a
/// counter-strategy by the automaton of the specification.
#[test]
fn the_gr1_game_decides_its_fragment_as_the_bounded_games_do() {
    let mut rng = Rng::new(29);
    let names = |s: SignalId| ["i0", "i1", "o0", "o1"][s.index()].to_string();
    let (mut agreed, mut beyond_bound, mut realizable, mut unrealizable, mut circuits) = (0, 0, 0, 0, 0);
    for case in 0..cases() / 4 {
        let semantics = if case % 3 == 0 { Semantics::Moore } else { Semantics::Mealy };
        let mut spec = random_spec(&mut rng, semantics);
        let clause = |formula| ltl::Clause { formula, span: Default::default() };
        spec.assumptions = (0..rng.below(3)).map(|_| clause(random_gr1_conjunct(&mut rng, 4))).collect();
        spec.guarantees = (0..1 + rng.below(3)).map(|_| clause(random_gr1_conjunct(&mut rng, 4))).collect();
        let text = spec.formula_text();
        let gr1 = Config { solver: Solver::Gr1, circuit: true, ..Config::default() };
        let outcome =
            ltl::synthesize(&spec, &gr1, &mut |_| true).unwrap_or_else(|stop| panic!("case {case}: {stop}: {text}"));
        assert_ne!(outcome.verdict, Verdict::Unknown, "case {case}: {text}");
        let bounded = Config { max_k: 4, max_states: 20_000, compositional: false, ..Config::default() };
        match ltl::synthesize(&spec, &bounded, &mut |_| true) {
            Ok(explicit) if explicit.verdict != Verdict::Unknown => {
                assert_eq!(outcome.verdict, explicit.verdict, "case {case}: gr1 against explicit: {text}");
                agreed += 1;
            }
            _ => beyond_bound += 1,
        }
        if outcome.verdict == Verdict::Realizable {
            realizable += 1;
            let controller = outcome
                .controller
                .as_ref()
                .unwrap_or_else(|| panic!("case {case}: no controller: {:?}: {text}", outcome.limit));
            let negation = translate(&Ltl::not(spec.formula()), &names, 100_000, u64::MAX).unwrap();
            let moore = semantics == Semantics::Moore;
            assert_wins(controller, moore, &negation, &format!("case {case}: the gr1 controller of {text}"));
            // The same strategy as a circuit, unfolded into its table.
            let circuit = outcome.circuit.as_ref().unwrap_or_else(|| panic!("case {case}: no circuit: {text}"));
            let table = circuit.to_machine(100_000).expect("a small table");
            assert_wins(&table, moore, &negation, &format!("case {case}: the gr1 circuit of {text}"));
            circuits += 1;
        } else {
            unrealizable += 1;
            let counter = outcome
                .counter_strategy
                .as_ref()
                .unwrap_or_else(|| panic!("case {case}: no counter-strategy: {:?}: {text}", outcome.limit));
            let automaton = translate(&spec.formula(), &names, 100_000, u64::MAX).unwrap();
            let mealy = semantics == Semantics::Mealy;
            assert_wins(counter, mealy, &automaton, &format!("case {case}: the gr1 counter-strategy of {text}"));
        }
    }
    eprintln!(
        "gr1: {agreed} agreed with the explicit games, {beyond_bound} beyond their bound, {realizable} realizable \
         ({circuits} circuits checked), {unrealizable} unrealizable"
    );
    assert!(
        agreed > cases() / 8 && realizable > cases() / 40 && unrealizable > cases() / 40,
        "{agreed} agreed, {realizable} realizable, {unrealizable} unrealizable"
    );
}
