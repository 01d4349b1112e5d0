//! An LTL controller (a finite-state [`Machine`] of `crate::ltl`) lowered into a [`Unit`]: one
//! function block that is the machine, and a program that wires it to the PLC's I/O.
//! `docs/ltl-plc.md` shows the generated code; `plc::model::exec` runs it against
//! [`Machine::row`] in `tests/ltl_plc.rs`, so the two must keep one semantics.
//!
//! What is generated (the block `FB_<title>`, `FB_Controller` without a title):
//! - constants `S_<k>`, one per state reachable from the initial one (`k` is the machine's state
//!   number, as `plcsynth ltl --json` prints it);
//! - the block: the read signals as `VAR_INPUT`, the written ones as `VAR_OUTPUT`, the state
//!   (`INT`), a `TON` per timer; its body is a `CASE` over the state with one branch per state.
//!   A branch first assigns the outputs that every row of the state writes alike (all of them
//!   for a Moore machine), then decides the rest with `IF`/`ELSIF`/`ELSE` over the state's rows
//!   grouped by what they do (next state and outputs), each group's condition a small cover of
//!   its valuations (see `cover`);
//! - the program `<block>_main`: calls an instance `ctrl` with the inputs `%IX0.0`, `%IX0.1`, …
//!   and copies its outputs to `%QX0.0`, `%QX0.1`, … (in the order of the machine's signals).
//!
//! Timers (G4LTL's `TIMER t1(10s)`, the signals `t1.start` and `t1.expire`): the block owns a
//! `TON` per timer and calls it at the start of every scan, so that `Q` and `ET` are current.
//! `t1.expire` is not an input of the block but `t1.Q`: TRUE once the preset has passed since
//! the last start (FALSE before the first). `t1.start` is an output of the block like any
//! other; in a scan that sets it the timer restarts after the `CASE` with a real rising edge
//! on `IN` (`t1(IN := FALSE)` then `t1(IN := TRUE, PT := …)`), so the next scans count from
//! this one. (G4LTL-ST's `t1(IN := 0, PT := …)` resets the timer without starting it.) A start
//! takes effect from the next scan on: within the scan that starts it, `t1.Q` is still the value
//! read at the scan's start.

use crate::diag::{Diagnostic, Diagnostics, Span};
use crate::ltl::{
    Circuit, Cube, Logic, Machine, NumExpr, NumberKind, NumericId, Relation, Row, SignalId, SignalKind as Direction,
    Spec, StateId, Synthesis,
};
use crate::plc::model::unit::{BinOp, Expr, Place, Pou, PouKind, Signal, SignalKind, Stmt, Type, Unit, Var};
use crate::plc::{identifier, source_hash, Namespace};
use std::collections::BTreeSet;

/// Choices of the lowering beyond the machine.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct LowerOptions {
    /// The function block's name; by default `FB_` and the specification's title, or
    /// `FB_Controller` without one.
    pub name: Option<String>,
}

/// The longest generated name: STEP 7 Classic (STL, SCL for S7-300/400) limits symbols to 24
/// characters, so every target gets names that fit.
const MAX_NAME: usize = 24;

/// Room for a timer's name: STL keeps its `Q` and `ET` in statics `<timer>_Q`, `<timer>_ET`.
const MAX_TIMER_NAME: usize = MAX_NAME - 3;

/// The names of one unit: one scope for the block, the program and the constants, so that no
/// generated name hides another wherever it is read.
struct Names(Namespace);

impl Names {
    /// A fresh identifier from `base`, at most `room` characters (cut, then `_2`, `_3`, … on a
    /// clash), now reserved.
    fn fresh(&mut self, base: &str, room: usize) -> String {
        let base = identifier(base);
        let cut = |text: &str, room: usize| text[..text.len().min(room)].trim_end_matches('_').to_string();
        let mut name = cut(&base, room);
        let mut n = 2;
        while self.0.contains(&name) {
            let tail = format!("_{n}");
            name = format!("{}{tail}", cut(&base, room - tail.len()));
            n += 1;
        }
        self.0.reserve(&name);
        name
    }
}

/// Where the block finds a read signal.
enum Source {
    /// Its input of that name.
    Input(String),
    /// The `Q` of its timer of that name (the signal is the timer's `expire`).
    Expired(String),
}

/// A timer of the specification that the machine uses.
struct TimerUse {
    instance: String,
    preset_ms: u64,
    /// The block's output that starts it (when the machine writes `start`).
    start: Option<String>,
    name: String,
}

/// Lowers `machine`, a controller of `spec` (whose text is `source`, hashed into the header).
/// Errors are located in `source`: a machine that does not validate, one that reads an output
/// or writes an input of the specification (a counter-strategy is not a controller), a timer
/// longer than a PLC's `TIME` holds.
pub fn lower(source: &str, spec: &Spec, machine: &Machine, options: &LowerOptions) -> Result<Unit, Vec<Diagnostic>> {
    lower_machines(source, spec, std::slice::from_ref(machine), options)
}

/// Lowers a run's controller: one state machine per group of a compositional run (the
/// paper's appendix A), else the one controller. `None` for a run without a controller.
pub fn lower_outcome(
    source: &str,
    spec: &Spec,
    outcome: &Synthesis,
    options: &LowerOptions,
) -> Option<Result<Unit, Vec<Diagnostic>>> {
    if let Some(circuit) = &outcome.circuit {
        return Some(lower_circuit(source, spec, circuit, options));
    }
    let machines: Vec<Machine> = outcome.groups.iter().filter_map(|g| g.controller.clone()).collect();
    if machines.len() > 1 {
        return Some(lower_machines(source, spec, &machines, options));
    }
    outcome.controller.as_ref().map(|m| lower(source, spec, m, options))
}

/// Lowers machines that run side by side in one block (disjoint writes), each with its own
/// state variable and `CASE`.
pub fn lower_machines(
    source: &str,
    spec: &Spec,
    machines: &[Machine],
    options: &LowerOptions,
) -> Result<Unit, Vec<Diagnostic>> {
    lower_controller(source, spec, Controller::Machines(machines), options)
}

/// Lowers a controller circuit (a GR(1) run's, see [`crate::ltl::Circuit`]): its latches are
/// BOOL variables of the block, its goal an INT; per scan the outputs of the current goal, the
/// goal's advance, then every latch's next value at once.
pub fn lower_circuit(
    source: &str,
    spec: &Spec,
    circuit: &Circuit,
    options: &LowerOptions,
) -> Result<Unit, Vec<Diagnostic>> {
    lower_controller(source, spec, Controller::Circuit(circuit), options)
}

/// What becomes the block's body: state machines side by side, or one circuit.
#[derive(Clone, Copy)]
enum Controller<'a> {
    Machines(&'a [Machine]),
    Circuit(&'a Circuit),
}

fn lower_controller(
    source: &str,
    spec: &Spec,
    controller: Controller<'_>,
    options: &LowerOptions,
) -> Result<Unit, Vec<Diagnostic>> {
    let mut diags = Diagnostics::new(source);
    let (machines, all_reads, written): (&[Machine], Vec<SignalId>, Vec<SignalId>) = match controller {
        Controller::Machines(machines) => {
            for machine in machines {
                if let Err(problem) = machine.validate() {
                    diags.error(
                        Span::default(),
                        format!("the controller is not a complete deterministic machine: {problem}"),
                    );
                }
                check(spec, &machine.reads, &machine.writes, &mut diags);
            }
            (
                machines,
                machines.iter().flat_map(|m| m.reads.iter().copied()).collect(),
                machines.iter().flat_map(|m| m.writes.iter().copied()).collect(),
            )
        }
        Controller::Circuit(circuit) => {
            check(spec, &circuit.reads, &circuit.writes, &mut diags);
            (&[], circuit.reads.clone(), circuit.writes.clone())
        }
    };
    let mut distinct = written.clone();
    crate::sort::sort(&mut distinct);
    distinct.dedup();
    if distinct.len() != written.len() {
        diags.error(Span::default(), "two state machines write one output");
    }
    if machines.is_empty() && matches!(controller, Controller::Machines(_)) {
        diags.error(Span::default(), "no state machine to lower");
    }
    if diags.has_errors() {
        return Err(diags.items);
    }
    let many = machines.len() > 1;
    let mut names = Names(Namespace::new());
    let block_base = match (&options.name, &spec.title) {
        (Some(name), _) => name.clone(),
        (None, Some(title)) => format!("FB_{title}"),
        (None, None) => "FB_Controller".into(),
    };
    let block = names.fresh(&block_base, MAX_NAME);
    let program = names.fresh(&format!("{block}_main"), MAX_NAME);
    let gvl = names.fresh(&format!("{block}_States"), MAX_NAME);
    let instance = names.fresh("ctrl", MAX_NAME);
    let state_vars: Vec<String> = (1..=machines.len())
        .map(|k| names.fresh(&if many { format!("state{k}") } else { "state".to_string() }, MAX_NAME))
        .collect();

    // Every signal some machine reads or writes, in the specification's order: the signals'
    // own names first, timers after them.
    let timer_of_expire = |s: SignalId| spec.timers.iter().position(|t| t.expire == s);
    let timer_of_start = |s: SignalId| spec.timers.iter().position(|t| t.start == s);
    let mut inputs = Vec::new();
    let mut input_name: std::collections::HashMap<SignalId, String> = Default::default();
    // In the machines' own order (a single machine's reads stay as they are), each once.
    let mut reads_in_order: Vec<SignalId> = Vec::new();
    for &s in &all_reads {
        if !reads_in_order.contains(&s) {
            reads_in_order.push(s);
        }
    }
    // Numeric inputs first (those the predicates read), then the Boolean ones; a predicate is
    // a local BOOL computed at the start of the scan (the paper's appendix A).
    let mut numeric_name: Vec<Option<String>> = vec![None; spec.numeric.len()];
    let predicates: Vec<&crate::ltl::Predicate> = reads_in_order.iter().filter_map(|&s| spec.predicate_of(s)).collect();
    for p in &predicates {
        for v in numeric_vars(&p.lhs).into_iter().chain(numeric_vars(&p.rhs)) {
            let n = &spec.numeric[v.0 as usize];
            if numeric_name[v.0 as usize].is_none() {
                let name = names.fresh(&n.name, MAX_NAME);
                let ty = match n.kind {
                    NumberKind::Real => Type::Real,
                    NumberKind::Int => Type::Int,
                };
                inputs.push(Var::new(&name, ty, format!("input {} in [{}, {}]", n.name, n.lo, n.hi)));
                numeric_name[v.0 as usize] = Some(name);
            }
        }
    }
    let mut predicate_locals = Vec::new();
    let mut predicate_updates = Vec::new();
    for &s in &reads_in_order {
        if let Some(p) = spec.predicate_of(s) {
            let name = names.fresh(spec.name(s), MAX_NAME);
            let text = spec.predicate_text(p);
            match predicate_expr(spec, p, &numeric_name) {
                Ok(e) => predicate_updates.push(Stmt::assign(Place::local(&name), e)),
                Err(message) => {
                    diags.error(p.span, format!("predicate `{text}`: {message}"));
                }
            }
            predicate_locals.push(Var::new(&name, Type::Bool, format!("{text}, this scan")));
            input_name.insert(s, name);
        } else if timer_of_expire(s).is_none() {
            let name = names.fresh(spec.name(s), MAX_NAME);
            inputs.push(Var::new(&name, Type::Bool, format!("input {}", spec.name(s))));
            input_name.insert(s, name);
        }
    }
    if diags.has_errors() {
        return Err(diags.items);
    }
    let mut outputs = Vec::new();
    let mut output_name: std::collections::HashMap<SignalId, String> = Default::default();
    for &s in &written {
        let name = names.fresh(spec.name(s), MAX_NAME);
        let comment = match timer_of_start(s) {
            Some(t) => format!("{}: TRUE in a scan that starts timer {}", spec.name(s), spec.timers[t].name),
            None => format!("output {}", spec.name(s)),
        };
        outputs.push(Var::new(&name, Type::Bool, comment));
        output_name.insert(s, name);
    }
    let mut timers: Vec<TimerUse> = Vec::new();
    let mut timer_instance = vec![None; spec.timers.len()];
    for (k, t) in spec.timers.iter().enumerate() {
        if !output_name.contains_key(&t.start) && !reads_in_order.contains(&t.expire) {
            continue;
        }
        let instance = loop {
            let candidate = names.fresh(&t.name, MAX_TIMER_NAME);
            let shadows = [format!("{candidate}_Q"), format!("{candidate}_ET")];
            if shadows.iter().all(|s| !names.0.contains(s)) {
                shadows.iter().for_each(|s| names.0.reserve(s));
                break candidate;
            }
        };
        timer_instance[k] = Some(instance.clone());
        timers.push(TimerUse {
            instance,
            preset_ms: t.preset_ms,
            start: output_name.get(&t.start).cloned(),
            name: t.name.clone(),
        });
    }
    let source_of = |s: SignalId| match input_name.get(&s) {
        Some(name) => Source::Input(name.clone()),
        None => Source::Expired(
            timer_instance[timer_of_expire(s).expect("an expire signal")]
                .clone()
                .expect("a timer whose expiry is read is used"),
        ),
    };

    // States: those reachable from the initial one, named after the machine's numbers
    // (`S_3`; `S1_3`, `S2_0`, … for the machines of a compositional run).
    let mut constants = Vec::new();
    let mut body = Vec::new();
    if !predicate_updates.is_empty() {
        body.push(Stmt::Comment("the predicates on the numeric inputs, once per scan".into()));
        body.extend(predicate_updates);
    }
    if !timers.is_empty() {
        body.push(Stmt::Comment("timers run every scan, so that Q and ET are current (IN keeps its value)".into()));
        for t in &timers {
            body.push(Stmt::CallInstance {
                instance: Place::local(&t.instance),
                args: vec![("PT".into(), Expr::Time(t.preset_ms))],
            });
        }
    }
    let mut locals = predicate_locals;
    let mut reachable_counts = Vec::new();
    for (k, machine) in machines.iter().enumerate() {
        let reachable = reachable(machine);
        reachable_counts.push(reachable.len());
        let mut state_name = vec![String::new(); machine.states.len()];
        for &s in &reachable {
            let base = if many { format!("S{}_{}", k + 1, s.0) } else { format!("S_{}", s.0) };
            let name = names.fresh(&base, MAX_NAME);
            let what = if s == machine.init { "state (initial)" } else { "state" };
            constants.push(Var::new(&name, Type::Int, what).with_init(Expr::Int(i64::from(s.0))));
            state_name[s.index()] = name;
        }
        let sources: Vec<Source> = machine.reads.iter().map(|&s| source_of(s)).collect();
        let output_names: Vec<String> = machine.writes.iter().map(|s| output_name[s].clone()).collect();
        let state = &state_vars[k];
        let lowering = Lowering { machine, sources: &sources, outputs: &output_names, state, state_name: &state_name };
        if many {
            let outs: Vec<&str> = machine.writes.iter().map(|&s| spec.name(s)).collect();
            body.push(Stmt::Comment(format!(
                "state machine {} of {}: writes {}",
                k + 1,
                machines.len(),
                outs.join(", ")
            )));
        }
        let arms = reachable.iter().map(|&s| (vec![i64::from(s.0)], lowering.state_branch(s))).collect();
        body.push(Stmt::Case { selector: Expr::local(state), arms, otherwise: Vec::new() });
        locals.push(
            Var::new(
                state,
                Type::Int,
                format!("the current state, an S_ constant (initially {})", state_name[machine.init.index()]),
            )
            .with_init(Expr::Int(i64::from(machine.init.0))),
        );
    }
    if let Controller::Circuit(circuit) = controller {
        let sources: Vec<Source> = circuit.reads.iter().map(|&s| source_of(s)).collect();
        let output_names: Vec<String> = circuit.writes.iter().map(|s| output_name[s].clone()).collect();
        let (circuit_locals, circuit_body) = circuit_code(circuit, &sources, &output_names, &mut names);
        locals.extend(circuit_locals);
        body.extend(circuit_body);
    }
    let started: Vec<&TimerUse> = timers.iter().filter(|t| t.start.is_some()).collect();
    if !started.is_empty() {
        body.push(Stmt::Comment("a timer started in this scan restarts: a rising edge on IN".into()));
    }
    for t in started {
        let call = |on: bool, preset: bool| Stmt::CallInstance {
            instance: Place::local(&t.instance),
            args: std::iter::once(("IN".to_string(), Expr::Bool(on)))
                .chain(preset.then(|| ("PT".to_string(), Expr::Time(t.preset_ms))))
                .collect(),
        };
        let start = t.start.as_deref().expect("filtered");
        body.push(Stmt::when(Expr::local(start), vec![call(false, false), call(true, true)]));
    }
    for t in &timers {
        locals.push(Var::new(&t.instance, Type::Ton, format!("timer {} ({} ms)", t.name, t.preset_ms)));
    }
    let moore = match controller {
        Controller::Machines(machines) => machines.iter().all(|m| m.moves_first),
        Controller::Circuit(circuit) => circuit.moves_first,
    };
    let turn = if matches!(controller, Controller::Circuit(_)) {
        if moore {
            "a circuit of latches, Moore: the outputs do not depend on the inputs of the same scan"
        } else {
            "a circuit of latches, Mealy: reads the inputs and answers in the same scan"
        }
    } else if moore {
        "Moore machine: a state's outputs do not depend on the inputs of the same scan"
    } else {
        "Mealy machine: reads the inputs and answers in the same scan"
    };
    let mut comment = if many {
        format!(
            "The synthesised controller: {} state machines side by side, one per group of guarantees with \
             their own outputs ({turn}). Call it once per scan.",
            machines.len()
        )
    } else {
        format!("The synthesised controller ({turn}). Call it once per scan.")
    };
    if !timers.is_empty() {
        comment.push_str(
            " A timer's expire input is its TON's Q (TRUE once the preset has passed since the last start); \
             a start output restarts the timer with a rising edge on IN after the state machine, \
             effective from the next scan.",
        );
    }
    let fb = Pou { kind: PouKind::FunctionBlock, name: block.clone(), comment, inputs, outputs, locals, body };

    // The program: the block wired to direct addresses, in the block's input order (numeric
    // inputs as words or double words after the bits).
    let mut signals = Vec::new();
    let mut args = Vec::new();
    let input_types: Vec<Type> = fb.inputs.iter().map(|v| v.ty.clone()).collect();
    let addresses = crate::plc::model::unit::direct_addresses('I', &input_types);
    for (var, address) in fb.inputs.iter().zip(addresses) {
        let address = address.expect("inputs are BOOL, INT or REAL");
        let k = signals.len();
        signals.push(Signal {
            symbol: address.clone(),
            kind: SignalKind::Input,
            ty: var.ty.clone(),
            address,
            comment: var.comment.trim_start_matches("input ").to_string(),
        });
        args.push((var.name.clone(), Expr::read(Place::Signal(k))));
    }
    let mut main = vec![Stmt::CallInstance { instance: Place::local(&instance), args }];
    let mut q = 0;
    for &s in &written {
        if timer_of_start(s).is_some() {
            continue;
        }
        let address = format!("QX{}.{}", q / 8, q % 8);
        q += 1;
        let name = &output_name[&s];
        main.push(Stmt::assign(Place::Signal(signals.len()), Expr::read(Place::local(&instance).member(name))));
        signals.push(Signal {
            symbol: address.clone(),
            kind: SignalKind::Output,
            ty: Type::Bool,
            address,
            comment: spec.name(s).to_string(),
        });
    }
    let main = Pou {
        kind: PouKind::Program,
        name: program,
        comment: format!(
            "Runs {block} once per scan on the PLC's inputs and outputs: change the addresses to the project's, \
             or call {block} from a program of your own."
        ),
        inputs: Vec::new(),
        outputs: Vec::new(),
        locals: vec![Var::new(&instance, Type::Instance(block.clone()), "the controller")],
        body: main,
    };

    let signal_list = |list: &[SignalId]| list.iter().map(|&s| spec.name(s)).collect::<Vec<_>>().join(", ");
    let mut header = vec![
        format!("Generated by plcsynth {} from an LTL specification.", env!("CARGO_PKG_VERSION")),
        format!("Specification hash (FNV-1a 64): {}", source_hash(source)),
    ];
    if let Controller::Circuit(circuit) = controller {
        header.push(format!(
            "Controller: a circuit of {} latches and {} goals (GR(1) strategy), {}; reads {}; writes {}.",
            circuit.latches.len(),
            circuit.goals.len(),
            if circuit.moves_first { "Moore" } else { "Mealy" },
            if circuit.reads.is_empty() { "nothing".into() } else { signal_list(&circuit.reads) },
            if circuit.writes.is_empty() { "nothing".into() } else { signal_list(&circuit.writes) },
        ));
    }
    for (k, machine) in machines.iter().enumerate() {
        header.push(format!(
            "{}: {} states ({} reachable), {}; reads {}; writes {}.",
            if many { format!("State machine {}", k + 1) } else { "Controller".to_string() },
            machine.states.len(),
            reachable_counts[k],
            if machine.moves_first { "Moore" } else { "Mealy" },
            if machine.reads.is_empty() { "nothing".into() } else { signal_list(&machine.reads) },
            if machine.writes.is_empty() { "nothing".into() } else { signal_list(&machine.writes) },
        ));
    }
    header.push("Do not edit: change the specification and generate again.".to_string());
    Ok(Unit { name: block, header, gvl, constants, globals: Vec::new(), signals, pous: vec![fb, main] })
}

/// The circuit's variables and statements: per goal its outputs and its advance (a `CASE` over
/// the goal when there are several), then every latch's next value, computed from this scan's
/// latches, inputs and outputs.
fn circuit_code(circuit: &Circuit, sources: &[Source], outputs: &[String], names: &mut Names) -> (Vec<Var>, Vec<Stmt>) {
    let latch_names: Vec<String> = circuit.latches.iter().map(|l| names.fresh(&l.name, MAX_NAME)).collect();
    let many = circuit.goals.len() > 1;
    let goal_name = if many { names.fresh("goal", MAX_NAME) } else { String::new() };
    let lowering = CircuitLowering { circuit, sources, outputs, latches: &latch_names };
    let mut locals: Vec<Var> = circuit
        .latches
        .iter()
        .zip(&latch_names)
        .map(|(l, name)| Var::new(name, Type::Bool, &l.comment).with_init(Expr::Bool(l.init)))
        .collect();
    let mut body = Vec::new();
    // An output every goal computes alike is assigned once, before the goals; one that some
    // goal holds FALSE is FALSE unless the goal pursued sets it.
    let alike: Vec<bool> =
        (0..outputs.len()).map(|j| circuit.goals.iter().all(|g| g.writes[j] == circuit.goals[0].writes[j])).collect();
    let by_default: Vec<bool> = (0..outputs.len())
        .map(|j| !alike[j] && circuit.goals.iter().any(|g| g.writes[j] == Logic::Const(false)))
        .collect();
    let mut before = Vec::new();
    for (j, name) in outputs.iter().enumerate() {
        if alike[j] {
            before.push(Stmt::assign(Place::local(name), lowering.expr(&circuit.goals[0].writes[j])));
        } else if by_default[j] {
            before.push(Stmt::assign(Place::local(name), Expr::Bool(false)));
        }
    }
    if many && !before.is_empty() {
        body.push(Stmt::Comment("outputs alike in every goal, and FALSE unless the goal pursued sets them".into()));
        body.extend(before);
    }
    let goal_code = |g: usize| {
        let goal = &circuit.goals[g];
        let mut stmts: Vec<Stmt> = outputs
            .iter()
            .zip(&goal.writes)
            .enumerate()
            .filter(|&(j, (_, f))| !many || !(alike[j] || by_default[j] && *f == Logic::Const(false)))
            .map(|(_, (name, f))| Stmt::assign(Place::local(name), lowering.expr(f)))
            .collect();
        if many {
            let advance = Stmt::assign(Place::local(&goal_name), Expr::Int(((g + 1) % circuit.goals.len()) as i64));
            match &goal.reached {
                Logic::Const(false) => {}
                Logic::Const(true) => stmts.push(advance),
                reached => stmts.push(Stmt::when(lowering.expr(reached), vec![advance])),
            }
        }
        stmts
    };
    if many {
        body.push(Stmt::Comment("the outputs of the goal pursued; the next goal once it is reached".into()));
        let arms = (0..circuit.goals.len())
            .map(|g| {
                let mut arm = vec![Stmt::Comment(format!("goal {g}: {}", circuit.goals[g].comment))];
                arm.extend(goal_code(g));
                (vec![g as i64], arm)
            })
            .collect();
        body.push(Stmt::Case { selector: Expr::local(&goal_name), arms, otherwise: Vec::new() });
        locals.push(
            Var::new(
                &goal_name,
                Type::Int,
                format!("the goal pursued, 0 to {} (each in turn, once reached)", circuit.goals.len() - 1),
            )
            .with_init(Expr::Int(0)),
        );
    } else {
        body.push(Stmt::Comment("the outputs".into()));
        body.extend(goal_code(0));
    }
    if circuit.latches.is_empty() {
        return (locals, body);
    }
    // Every latch takes its next value at once: a latch is assigned after the latches that
    // read it, and through a temporary where they read each other in a cycle.
    let order = update_order(circuit);
    body.push(Stmt::Comment("the latches' next values, from this scan's inputs and outputs".into()));
    match order {
        Some(order) => {
            for b in order {
                body.push(Stmt::assign(Place::local(&latch_names[b]), lowering.expr(&circuit.latches[b].next)));
            }
        }
        None => {
            let temps: Vec<String> = latch_names.iter().map(|n| names.fresh(&format!("next_{n}"), MAX_NAME)).collect();
            for (b, temp) in temps.iter().enumerate() {
                body.push(Stmt::assign(Place::local(temp), lowering.expr(&circuit.latches[b].next)));
                locals.push(Var::new(temp, Type::Bool, format!("the next value of {}", latch_names[b])));
            }
            for (name, temp) in latch_names.iter().zip(&temps) {
                body.push(Stmt::assign(Place::local(name), Expr::local(temp)));
            }
        }
    }
    (locals, body)
}

/// An order of the latches in which each is assigned before every other latch its next value
/// reads (so that it reads the old value); `None` when they read each other in a cycle.
fn update_order(circuit: &Circuit) -> Option<Vec<usize>> {
    let n = circuit.latches.len();
    // `readers[b]`: the latches whose next value reads `b`; each must come before `b`.
    let mut waiting_for = vec![0usize; n];
    let mut readers: Vec<Vec<usize>> = vec![Vec::new(); n];
    for (a, latch) in circuit.latches.iter().enumerate() {
        let mut read = Vec::new();
        latch.next.latches(&mut read);
        read.sort_unstable();
        read.dedup();
        for b in read.into_iter().filter(|&b| b != a) {
            readers[b].push(a);
            waiting_for[b] += 1;
        }
    }
    let mut ready: Vec<usize> = (0..n).rev().filter(|&b| waiting_for[b] == 0).collect();
    let mut order = Vec::with_capacity(n);
    while let Some(a) = ready.pop() {
        order.push(a);
        let mut read = Vec::new();
        circuit.latches[a].next.latches(&mut read);
        read.sort_unstable();
        read.dedup();
        for b in read.into_iter().filter(|&b| b != a) {
            waiting_for[b] -= 1;
            if waiting_for[b] == 0 {
                ready.push(b);
            }
        }
    }
    (order.len() == n).then_some(order)
}

/// What the circuit's expressions need to know.
struct CircuitLowering<'a> {
    circuit: &'a Circuit,
    sources: &'a [Source],
    outputs: &'a [String],
    latches: &'a [String],
}

impl CircuitLowering<'_> {
    fn expr(&self, f: &Logic) -> Expr {
        match f {
            Logic::Const(b) => Expr::Bool(*b),
            Logic::Latch(b) => Expr::local(&self.latches[*b]),
            Logic::Signal(s) => match self.circuit.reads.iter().position(|r| r == s) {
                Some(i) => match &self.sources[i] {
                    Source::Input(name) => Expr::local(name),
                    Source::Expired(timer) => Expr::read(Place::local(timer).member("Q")),
                },
                None => {
                    let j =
                        self.circuit.writes.iter().position(|w| w == s).expect("a signal the circuit reads or writes");
                    Expr::local(&self.outputs[j])
                }
            },
            Logic::Not(p) => self.expr(p).not(),
            Logic::And(ps) => ps.iter().map(|p| self.expr(p)).reduce(Expr::and).unwrap_or(Expr::Bool(true)),
            Logic::Or(ps) => ps.iter().map(|p| self.expr(p)).reduce(Expr::or).unwrap_or(Expr::Bool(false)),
        }
    }
}

/// The numeric inputs an expression reads.
fn numeric_vars(e: &NumExpr) -> Vec<NumericId> {
    match e {
        NumExpr::Const(_) => Vec::new(),
        NumExpr::Var(v) => vec![*v],
        NumExpr::Neg(a) | NumExpr::Pow(a, _) => numeric_vars(a),
        NumExpr::Add(a, b) | NumExpr::Sub(a, b) | NumExpr::Mul(a, b) | NumExpr::Div(a, b) => {
            let mut v = numeric_vars(a);
            v.extend(numeric_vars(b));
            v
        }
    }
}

/// A predicate as a BOOL expression of the block: in REAL when it reads a REAL input, in INT
/// when it reads only INT inputs and integers (and no value can leave INT's range, which the
/// inputs' bounds decide). IEC has no implicit conversion, so a predicate mixing the two is
/// refused, as is one whose INT arithmetic could overflow or divide.
fn predicate_expr(spec: &Spec, p: &crate::ltl::Predicate, names: &[Option<String>]) -> Result<Expr, String> {
    let mut kinds: BTreeSet<NumberKind> = BTreeSet::new();
    kinds.extend(numeric_vars(&p.lhs).into_iter().chain(numeric_vars(&p.rhs)).map(|v| spec.numeric[v.0 as usize].kind));
    let has_decimal = |e: &NumExpr| num_any(e, &|x| matches!(x, NumExpr::Const(t) if t.parse::<i64>().is_err()));
    let real = kinds.contains(&NumberKind::Real) || has_decimal(&p.lhs) || has_decimal(&p.rhs);
    if real && kinds.contains(&NumberKind::Int) {
        return Err("it mixes INT and REAL (IEC 61131-3 needs an explicit conversion): declare its inputs alike".into());
    }
    if !real {
        let bounds = |v: NumericId| {
            let n = &spec.numeric[v.0 as usize];
            (n.lo.parse::<f64>().unwrap_or(0.0), n.hi.parse::<f64>().unwrap_or(0.0))
        };
        for side in [&p.lhs, &p.rhs] {
            if num_any(side, &|x| matches!(x, NumExpr::Div(..))) {
                return Err("division of INT values truncates: write it without `/` or declare the inputs REAL".into());
            }
            let (lo, hi) = int_range(side, &bounds);
            if lo < -32768.0 || hi > 32767.0 {
                return Err(format!("a value can reach [{lo}, {hi}], beyond INT; declare the inputs REAL"));
            }
        }
    }
    let lhs = num_expr(&p.lhs, names, real)?;
    let rhs = num_expr(&p.rhs, names, real)?;
    let op = match p.relation {
        Relation::Lt => BinOp::Lt,
        Relation::Le => BinOp::Le,
        Relation::Gt => BinOp::Gt,
        Relation::Ge => BinOp::Ge,
        Relation::Eq => BinOp::Eq,
        Relation::Ne => BinOp::Ne,
    };
    Ok(Expr::binary(op, lhs, rhs))
}

fn num_any(e: &NumExpr, f: &dyn Fn(&NumExpr) -> bool) -> bool {
    f(e) || match e {
        NumExpr::Const(_) | NumExpr::Var(_) => false,
        NumExpr::Neg(a) | NumExpr::Pow(a, _) => num_any(a, f),
        NumExpr::Add(a, b) | NumExpr::Sub(a, b) | NumExpr::Mul(a, b) | NumExpr::Div(a, b) => {
            num_any(a, f) || num_any(b, f)
        }
    }
}

/// The range of every intermediate value of an integer expression bounds the whole (interval
/// arithmetic); the widest range met is returned.
fn int_range(e: &NumExpr, bounds: &dyn Fn(NumericId) -> (f64, f64)) -> (f64, f64) {
    fn go(e: &NumExpr, bounds: &dyn Fn(NumericId) -> (f64, f64), widest: &mut (f64, f64)) -> (f64, f64) {
        let r = match e {
            NumExpr::Const(t) => {
                let v = t.parse::<f64>().unwrap_or(0.0);
                (v, v)
            }
            NumExpr::Var(v) => bounds(*v),
            NumExpr::Neg(a) => {
                let (lo, hi) = go(a, bounds, widest);
                (-hi, -lo)
            }
            NumExpr::Add(a, b) | NumExpr::Sub(a, b) | NumExpr::Mul(a, b) | NumExpr::Div(a, b) => {
                let (x, y) = (go(a, bounds, widest), go(b, bounds, widest));
                match e {
                    NumExpr::Add(..) => (x.0 + y.0, x.1 + y.1),
                    NumExpr::Sub(..) => (x.0 - y.1, x.1 - y.0),
                    _ => {
                        let p = [x.0 * y.0, x.0 * y.1, x.1 * y.0, x.1 * y.1];
                        (
                            p.iter().copied().fold(f64::INFINITY, f64::min),
                            p.iter().copied().fold(f64::NEG_INFINITY, f64::max),
                        )
                    }
                }
            }
            NumExpr::Pow(a, n) => {
                let mut r = (1.0, 1.0);
                let x = go(a, bounds, widest);
                for _ in 0..*n {
                    let p = [r.0 * x.0, r.0 * x.1, r.1 * x.0, r.1 * x.1];
                    r = (
                        p.iter().copied().fold(f64::INFINITY, f64::min),
                        p.iter().copied().fold(f64::NEG_INFINITY, f64::max),
                    );
                    *widest = (widest.0.min(r.0), widest.1.max(r.1));
                }
                r
            }
        };
        *widest = (widest.0.min(r.0), widest.1.max(r.1));
        r
    }
    let mut widest = (0.0, 0.0);
    go(e, bounds, &mut widest);
    widest
}

/// An arithmetic expression of the block: literals as REAL or INT, `x^n` as a product.
fn num_expr(e: &NumExpr, names: &[Option<String>], real: bool) -> Result<Expr, String> {
    let go = |x: &NumExpr| num_expr(x, names, real);
    Ok(match e {
        NumExpr::Const(text) => {
            let v: f64 = text.parse().map_err(|_| format!("`{text}` is not a number"))?;
            if real {
                Expr::real(v).ok_or_else(|| format!("`{text}` is beyond REAL"))?
            } else {
                Expr::Int(v as i64)
            }
        }
        NumExpr::Var(v) => Expr::local(names[v.0 as usize].as_deref().expect("a named numeric input")),
        NumExpr::Neg(a) => go(a)?.neg(),
        NumExpr::Add(a, b) => Expr::binary(BinOp::Add, go(a)?, go(b)?),
        NumExpr::Sub(a, b) => Expr::binary(BinOp::Sub, go(a)?, go(b)?),
        NumExpr::Mul(a, b) => Expr::binary(BinOp::Mul, go(a)?, go(b)?),
        NumExpr::Div(a, b) => Expr::binary(BinOp::Div, go(a)?, go(b)?),
        NumExpr::Pow(a, n) => {
            let base = go(a)?;
            match n {
                0 => {
                    if real {
                        Expr::real(1.0).expect("finite")
                    } else {
                        Expr::Int(1)
                    }
                }
                _ => (1..*n).fold(base.clone(), |acc, _| Expr::binary(BinOp::Mul, acc, base.clone())),
            }
        }
    })
}

/// What keeps a controller reading `reads` and writing `writes` from being lowered as a
/// controller of `spec`.
fn check(spec: &Spec, reads: &[SignalId], writes: &[SignalId], diags: &mut Diagnostics<'_>) {
    for (list, want, verb) in [(reads, Direction::Input, "reads"), (writes, Direction::Output, "writes")] {
        for &s in list {
            match spec.signals.get(s.index()) {
                None => {
                    diags.error(
                        Span::default(),
                        format!("the controller {verb} signal {}, which the specification does not declare", s.0),
                    );
                }
                Some(signal) if signal.kind != want => {
                    diags
                        .error(signal.span, format!("the machine {verb} `{}`, which is not its {}", signal.name, if want == Direction::Input { "input" } else { "output" }))
                        .with_note("only a controller (reading the inputs, writing the outputs) becomes PLC code, not the environment's counter-strategy");
                }
                Some(_) => {}
            }
        }
    }
    for t in &spec.timers {
        if t.preset_ms > i32::MAX as u64 {
            diags.error(
                t.span,
                format!(
                    "timer `{}` runs {} ms, longer than a PLC's TIME holds (T#24D20H31M23S647MS)",
                    t.name, t.preset_ms
                ),
            );
        }
    }
}

/// The states reachable from the initial one, in the machine's order.
fn reachable(machine: &Machine) -> Vec<StateId> {
    let mut seen = BTreeSet::new();
    seen.insert(machine.init);
    let mut todo = vec![machine.init];
    while let Some(s) = todo.pop() {
        for row in &machine.states[s.index()] {
            if seen.insert(row.next) {
                todo.push(row.next);
            }
        }
    }
    seen.into_iter().collect()
}

/// What one CASE branch needs to know.
struct Lowering<'a> {
    machine: &'a Machine,
    sources: &'a [Source],
    outputs: &'a [String],
    state: &'a str,
    state_name: &'a [String],
}

/// Rows of a state that do the same: go to `next` writing `write`, on any valuation in `cubes`.
struct Group {
    next: StateId,
    write: u64,
    cubes: Vec<Cube>,
}

impl Lowering<'_> {
    fn read(&self, i: usize) -> Expr {
        match &self.sources[i] {
            Source::Input(name) => Expr::local(name),
            Source::Expired(timer) => Expr::read(Place::local(timer).member("Q")),
        }
    }

    /// `a AND NOT b OR c` for a cover; TRUE for the cover of everything.
    fn condition(&self, cubes: &[Cube]) -> Expr {
        let term = |c: &Cube| {
            let literals = (0..self.sources.len()).filter(|i| c.care >> i & 1 == 1).map(|i| {
                let e = self.read(i);
                if c.value >> i & 1 == 1 {
                    e
                } else {
                    e.not()
                }
            });
            literals.reduce(Expr::and).unwrap_or(Expr::Bool(true))
        };
        cubes.iter().map(term).reduce(Expr::or).unwrap_or(Expr::Bool(false))
    }

    /// The assignments of a group: the outputs in `outputs` (a mask) and the state when it
    /// changes.
    fn actions(&self, from: StateId, next: StateId, write: u64, outputs: u64) -> Vec<Stmt> {
        let mut stmts: Vec<Stmt> = (0..self.outputs.len())
            .filter(|i| outputs >> i & 1 == 1)
            .map(|i| Stmt::assign(Place::local(&self.outputs[i]), Expr::Bool(write >> i & 1 == 1)))
            .collect();
        if next != from {
            stmts.push(Stmt::assign(Place::local(self.state), Expr::global(&self.state_name[next.index()])));
        }
        stmts
    }

    /// The CASE branch of state `s`.
    fn state_branch(&self, s: StateId) -> Vec<Stmt> {
        let mut groups: Vec<Group> = Vec::new();
        for &Row { read, write, next } in &self.machine.states[s.index()] {
            let cube = Cube { care: read.care, value: read.value & read.care };
            match groups.iter_mut().find(|g| g.next == next && g.write == write) {
                Some(g) => g.cubes.push(cube),
                None => groups.push(Group { next, write, cubes: vec![cube] }),
            }
        }
        let all = mask(self.outputs.len());
        // Outputs every group writes alike are assigned once, before the decision.
        let same = groups.iter().fold(all, |m, g| m & !(g.write ^ groups[0].write));
        let differ = all & !same;
        let mut branch = vec![Stmt::Comment(format!("state {}", self.state_name[s.index()]))];
        branch.extend(self.actions(s, s, groups[0].write, same));
        // The ELSE: the group with nothing left to do (it stays), else the one with the most
        // valuations (the last of equals), so that the conditions printed are the small ones.
        let size = |g: &Group| {
            g.cubes.iter().map(|c| 1u128 << (self.sources.len() - c.care.count_ones() as usize)).sum::<u128>()
        };
        let last = groups
            .iter()
            .position(|g| self.actions(s, g.next, g.write, differ).is_empty())
            .or_else(|| (0..groups.len()).max_by_key(|&k| size(&groups[k])))
            .expect("a state has rows");
        let otherwise_group = groups.remove(last);
        let mut decided: Vec<Cube> = Vec::new();
        let mut arms = Vec::new();
        for g in &groups {
            let condition = self.condition(&cover(&g.cubes, &decided));
            decided.extend(&g.cubes);
            arms.push((condition, self.actions(s, g.next, g.write, differ)));
        }
        let otherwise = self.actions(s, otherwise_group.next, otherwise_group.write, differ);
        if arms.is_empty() {
            branch.extend(otherwise);
        } else {
            branch.push(Stmt::If { arms, otherwise });
        }
        if branch.len() == 1 {
            branch.clear(); // nothing happens: an empty branch
        }
        branch
    }
}

/// The mask of the first `n` bits.
fn mask(n: usize) -> u64 {
    if n >= 64 {
        u64::MAX
    } else {
        (1 << n) - 1
    }
}

/// Whether `outer` contains every valuation of `inner`.
fn contains(outer: Cube, inner: Cube) -> bool {
    outer.care & !inner.care == 0 && inner.value & outer.care == outer.value
}

fn intersects(a: Cube, b: Cube) -> bool {
    (a.value ^ b.value) & a.care & b.care == 0
}

/// Whether every valuation of `c` is in one of `cubes` (cubes normalised: `value ⊆ care`).
/// Splits `c` on a variable that some overlapping cube cares for until one cube contains it.
fn covered(c: Cube, cubes: &[Cube]) -> bool {
    let overlapping: Vec<Cube> = cubes.iter().copied().filter(|&d| intersects(c, d)).collect();
    if overlapping.iter().any(|&d| contains(d, c)) {
        return true;
    }
    // An overlapping cube that cares only for variables `c` fixes contains `c`: so one cares
    // for a variable `c` leaves free, unless there are none.
    let Some(free) = overlapping.iter().map(|d| d.care & !c.care).find(|&m| m != 0) else { return false };
    let bit = free & free.wrapping_neg();
    let half = |v: u64| Cube { care: c.care | bit, value: c.value | v };
    covered(half(0), &overlapping) && covered(half(bit), &overlapping)
}

/// A small set of cubes whose union contains every valuation of `on` and lies within `on` and
/// `decided` (valuations an earlier `IF` arm takes, which a later condition may match or not):
/// each cube is widened by dropping every variable it can (which also merges cubes that differ
/// in one variable), then cubes the others already cover are dropped, the smallest first.
pub(crate) fn cover(on: &[Cube], decided: &[Cube]) -> Vec<Cube> {
    let allowed: Vec<Cube> = on.iter().chain(decided).copied().collect();
    let mut cubes: Vec<Cube> = Vec::new();
    for &c in on {
        if cubes.iter().any(|&d| contains(d, c)) {
            continue;
        }
        let mut wide = c;
        let mut care = c.care;
        while care != 0 {
            let bit = care & care.wrapping_neg();
            care &= !bit;
            let candidate = Cube { care: wide.care & !bit, value: wide.value & !bit };
            if covered(candidate, &allowed) {
                wide = candidate;
            }
        }
        cubes.retain(|&d| !contains(wide, d));
        cubes.push(wide);
    }
    // Irredundant: the most specific cubes go first when the others cover them.
    let mut order: Vec<usize> = (0..cubes.len()).collect();
    crate::sort::sort_by_key(&mut order, |&k| std::cmp::Reverse(cubes[k].care.count_ones()));
    let mut keep = vec![true; cubes.len()];
    for k in order {
        keep[k] = false;
        let others: Vec<Cube> =
            (0..cubes.len()).filter(|&j| keep[j]).map(|j| cubes[j]).chain(decided.iter().copied()).collect();
        if !covered(cubes[k], &others) {
            keep[k] = true;
        }
    }
    cubes.into_iter().zip(keep).filter(|(_, k)| *k).map(|(c, _)| c).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cube(care: u64, value: u64) -> Cube {
        Cube { care, value }
    }

    /// Every valuation of `n` variables in `on` is in the cover, and every one in the cover is
    /// in `on` or `decided`.
    fn exact(n: u32, on: &[Cube], decided: &[Cube], got: &[Cube]) {
        for v in 0..1u64 << n {
            let want = on.iter().any(|c| c.contains(v));
            let free = decided.iter().any(|c| c.contains(v));
            let have = got.iter().any(|c| c.contains(v));
            assert!(have == want || free, "valuation {v:#b}: cover {got:?} of {on:?} (decided {decided:?})");
        }
    }

    #[test]
    fn neighbours_merge_and_a_full_cover_is_true() {
        // a ∧ b ∨ a ∧ ¬b = a
        assert_eq!(cover(&[cube(0b11, 0b11), cube(0b11, 0b01)], &[]), vec![cube(0b01, 0b01)]);
        // all four valuations of two variables: the cube of everything (TRUE)
        let all = [cube(3, 0), cube(3, 1), cube(3, 2), cube(3, 3)];
        assert_eq!(cover(&all, &[]), vec![Cube::ANY]);
        // with ¬a decided earlier, a ∧ b needs only b
        assert_eq!(cover(&[cube(3, 3)], &[cube(1, 0)]), vec![cube(2, 2)]);
    }

    #[test]
    fn covers_are_exact_on_random_groups() {
        let mut rng = crate::rng::Rng::new(7);
        for _ in 0..2000 {
            let n = 1 + rng.below(5) as u32;
            let mask = (1u64 << n) - 1;
            let mut on = Vec::new();
            let mut decided = Vec::new();
            for v in 0..1u64 << n {
                match rng.below(3) {
                    0 => on.push(cube(mask, v)),
                    1 => decided.push(cube(mask, v)),
                    _ => {}
                }
            }
            let got = cover(&on, &decided);
            exact(n, &on, &decided, &got);
            assert!(got.len() <= on.len());
        }
    }
}
