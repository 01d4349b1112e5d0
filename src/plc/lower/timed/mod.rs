//! Lowering of the timed engine's controller program (Peter 2005, chapter 6) to the code model:
//! the one module of `plc` that knows timed games. Messages become BOOL inputs and outputs (or
//! the signals of the `io` section), clocks read by delay conditions become timers, and each
//! command becomes one step.

pub mod machine;
pub mod realtime;
mod structured;

pub use machine::Code;
pub use structured::{structured, Structured};

use crate::diag::{Diagnostic, Diagnostics, Span};
use crate::plc::lower::timed::machine::{
    chain_requests, Binding, Effect, Output, RequestFacts, Statement, Step, Test, Timer, Variable,
};
use crate::plc::{
    iec_address, is_identifier_path, print::stl, render, source_hash, Namespace, Options, Target, TimeType,
};
use crate::timed::model::{
    ClockId, ClockOwner, CompId, Game, IoBinding, IoMode, IoTarget, MessageKind, MessageRole, MsgId, Pred,
};
use crate::timed::program::{Condition, Instruction, Program};

/// The signal an io binding names, as a key: the address (`%I0.0` and `%IX0.0` alike) or the
/// symbol text, and the direction.
fn signal_key(b: &IoBinding) -> (String, bool) {
    let text = match &b.target {
        IoTarget::Address { text, .. } => format!("%{}", iec_address(text)),
        IoTarget::Symbol { text, .. } => text.clone(),
    };
    (text, matches!(b.mode, IoMode::Pulse | IoMode::Set | IoMode::Reset))
}

/// The name of the variable of the signal that `binding` names: the first message bound to the
/// same signal in the same direction that reads it as it is (an input read with `not` only gives
/// `not_…`).
fn signal_name(game: &Game, binding: &IoBinding) -> String {
    let key = signal_key(binding);
    let same: Vec<&IoBinding> = game.io.iter().filter(|b| signal_key(b) == key).collect();
    let name = |b: &IoBinding| game.messages[b.message.index()].name.clone();
    match same.iter().find(|b| b.mode != IoMode::Negated) {
        Some(b) => name(b),
        None => format!("not_{}", name(same.first().copied().unwrap_or(binding))),
    }
}

/// The binding of an io target for `target`. A quoted name is a Siemens tag: targets that do not
/// quote tags take it only when it is an identifier path as written.
fn binding(io: &IoTarget, target: Target, diags: &mut Diagnostics) -> (Binding, Span) {
    match io {
        IoTarget::Address { text, span } => (Binding::Address(text.clone()), *span),
        IoTarget::Symbol { text, span, quoted: true } if target.quotes_tags() => (Binding::Quoted(text.clone()), *span),
        IoTarget::Symbol { text, span, quoted } => {
            if *quoted && !is_identifier_path(text) {
                diags
                    .error(
                        *span,
                        format!("`\"{text}\"` is not an IEC identifier, which target {} needs", target.name()),
                    )
                    .with_note(
                        "a quoted name is a Siemens tag: targets scl, scl-1500 and stl print it with its quotes; \
                         for the other targets bind a variable of the project such as `GVL.lamp_on`",
                    );
            }
            (Binding::Symbol(text.clone()), *span)
        }
    }
}

/// What a request bound with `mode` does to its output.
fn effect_of(mode: IoMode) -> Effect {
    match mode {
        IoMode::Set => Effect::Set,
        IoMode::Reset => Effect::Reset,
        _ => Effect::Pulse,
    }
}

/// A variable being built and the messages it stands for, which become its comment.
struct Signal {
    variable: Variable,
    /// The signal it stands for (bound) or the message (unbound).
    key: (String, bool),
    /// The message that made it.
    message: MsgId,
    notes: Vec<String>,
}

impl Signal {
    fn note(&mut self, note: String) {
        if !self.notes.contains(&note) {
            self.notes.push(note);
        }
    }

    fn finish(mut self) -> Variable {
        self.variable.comment = self.notes.join(", ");
        self.variable
    }
}

/// Builds the code model of `program` for `target`. `name` names the function block; `source`
/// is the specification text of `game` (hashed into the header). Variables are named after the
/// messages (a signal bound to several messages after the first that reads it as it is), unique
/// case-insensitively among themselves, the keywords and types, the block, its program, instance
/// and global variable list; every pulsed output gets a memory of its last write, `last_NAME`
/// (see [`Output::last`]), named after all other variables. A delay constant that the target's time type cannot hold exactly
/// (see [`Target::time_type`]) is an error located at the constant in `source`; nothing is
/// rounded or wrapped. For STL, `options` choose the marker byte and the CPU's timer count,
/// and clashes with them are errors located in `source` too.
pub fn build(
    game: &Game,
    program: &Program,
    target: Target,
    name: &str,
    source: &str,
    options: &Options,
) -> Result<Code, Vec<Diagnostic>> {
    build_wired(game, program, target, name, source, options).map(|(code, _)| code)
}

/// Which messages of the game each variable of a [`Code`] stands for: what a closed-loop
/// checker needs to drive the code from the plant ([`crate::plc::lower::timed::realtime`]).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Wiring {
    /// Per input: every message bound to its signal, with whether it reads the signal negated
    /// (all of the `io` section's bindings to that signal, read by the program or not), or the
    /// one message of an unbound input.
    pub inputs: Vec<Vec<(MsgId, bool)>>,
    /// Per output: every request bound to its signal with its effect, or the one request of an
    /// unbound output (pulsed).
    pub outputs: Vec<Vec<(MsgId, Effect)>>,
}

/// How the code spreads a program's requests over scans.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Pacing {
    /// A program of the zero-time strategy: a request, or a backward jump, goes on within its
    /// scan where nothing later in the scan depends on it ([`chain_requests`]).
    #[default]
    Chained,
    /// A program of the scan strategy ([`crate::timed::program::scan`]): every request and every
    /// backward jump ends its scan, so each scan reads, decides once and writes.
    ScanByScan,
}

impl Pacing {
    /// Why code paced so, for `game`, can fail a real-time run at a scan time where the scan
    /// game is won: the words of the CLI's note and the playground's.
    pub fn failure_reason(self, game: &Game) -> &'static str {
        match self {
            Pacing::Chained => {
                "the code follows the zero-time strategy with the latency of its scans; a shorter scan time may hold"
            }
            // The scan game assumes, as the thesis's game does, that a state guard holds when the
            // code checks it; the checker lets a free guard come up to a scan late.
            Pacing::ScanByScan if !game.guards.is_empty() => {
                "the code follows the scan strategy, whose game assumes that a state guard holds whenever \
                 the code checks it; a guard FALSE when checked holds the request back, which the game does \
                 not cover; a shorter scan time may hold"
            }
            // Without guards the scan strategy's code is right by construction: a failure is a bug.
            Pacing::ScanByScan => {
                "the code follows the scan strategy, which the game says wins: please report this as a bug"
            }
        }
    }
}

/// The inputs a PLC reads, as [`Wiring::inputs`] lists them: every signal of the `io` section
/// that a reaction is bound to, with all its bindings, or, without an `io` section, one input
/// per reaction. What the scan program may test.
pub fn observed_signals(game: &Game) -> Vec<Vec<(MsgId, bool)>> {
    let reaction = |m: MsgId| {
        let info = &game.messages[m.index()];
        info.role == MessageRole::Reaction && info.sender.is_some()
    };
    if game.io.is_empty() {
        return (0..game.messages.len()).map(MsgId::new).filter(|&m| reaction(m)).map(|m| vec![(m, false)]).collect();
    }
    let mut keys: Vec<(String, bool)> = Vec::new();
    for b in game.io.iter().filter(|b| reaction(b.message)) {
        let key = signal_key(b);
        if !keys.contains(&key) {
            keys.push(key);
        }
    }
    keys.iter()
        .map(|key| {
            game.io.iter().filter(|b| signal_key(b) == *key).map(|b| (b.message, b.mode == IoMode::Negated)).collect()
        })
        .collect()
}

/// Game states the scan program's extraction may follow, summed over its beliefs (two
/// machines, the largest example, follows about 500 000).
pub const SCAN_PROGRAM_BUDGET: usize = 2_000_000;

/// The program of the scan strategy of `scan` (a won scan game of `game`) over the inputs the
/// PLC reads ([`observed_signals`]), to be built with [`Pacing::ScanByScan`]; or why there is
/// none, in words (the code then follows the zero-time strategy, checked in real time).
/// `keep_going` is called with the states followed so far every few thousand; `false` cancels.
pub fn scan_program(
    game: &Game,
    scan: &crate::timed::ScanSynthesis,
    keep_going: &mut dyn FnMut(usize) -> bool,
) -> Result<crate::timed::program::scan::ScanProgram, String> {
    let signals = observed_signals(game);
    crate::timed::program::scan::extract(game, scan, &signals, SCAN_PROGRAM_BUDGET, keep_going)
        .map_err(|e| e.text(game, &signals))
}

/// [`build`], with the [`Wiring`] of the code's variables.
pub fn build_wired(
    game: &Game,
    program: &Program,
    target: Target,
    name: &str,
    source: &str,
    options: &Options,
) -> Result<(Code, Wiring), Vec<Diagnostic>> {
    build_paced(game, program, Pacing::Chained, target, name, source, options)
}

/// [`build_wired`] with the given pacing.
pub fn build_paced(
    game: &Game,
    program: &Program,
    pacing: Pacing,
    target: Target,
    name: &str,
    source: &str,
    options: &Options,
) -> Result<(Code, Wiring), Vec<Diagnostic>> {
    let mut diags = Diagnostics::new(source);
    let time = target.time_type();
    let io_of = |m: MsgId| game.io.iter().find(|b| b.message == m);
    let message_name = |m: MsgId| game.messages[m.index()].name.as_str();
    let mut names = Namespace::new();
    let fb_name = names.unique(name);
    let program_name = names.unique(&format!("{fb_name}_main"));
    let instance = names.unique("ctrl");
    let gvl = names.unique("GVL_IO");
    names.reserve("step");
    names.reserve("scan_done");
    let mut inputs: Vec<Signal> = Vec::new();
    let mut outputs: Vec<(Signal, bool)> = Vec::new();
    // The block's variable for message `m`: named after its binding's signal, or the message.
    let variable_of = |m: MsgId, names: &mut Namespace, diags: &mut Diagnostics| -> Variable {
        let (symbol, bound) = match io_of(m) {
            Some(b) => (names.unique(&signal_name(game, b)), Some(binding(&b.target, target, diags))),
            None => (names.unique(message_name(m)), None),
        };
        Variable {
            symbol,
            binding: bound.as_ref().map(|b| b.0.clone()),
            comment: String::new(),
            span: bound.map(|b| b.1),
        }
    };
    let mut input_of = |m: MsgId, names: &mut Namespace, diags: &mut Diagnostics| -> (usize, bool) {
        let (key, negated) = match io_of(m) {
            Some(b) => (signal_key(b), b.mode == IoMode::Negated),
            None => ((message_name(m).to_string(), false), false),
        };
        let index = inputs.iter().position(|i| i.key == key).unwrap_or_else(|| {
            let variable = variable_of(m, names, diags);
            inputs.push(Signal { variable, key, message: m, notes: Vec::new() });
            inputs.len() - 1
        });
        inputs[index].note(format!("{}{}", if negated { "NOT " } else { "" }, message_name(m)));
        (index, negated)
    };
    let mut output_of = |m: MsgId, names: &mut Namespace, diags: &mut Diagnostics| -> (usize, Effect) {
        let (key, effect) = match io_of(m) {
            Some(b) => (signal_key(b), effect_of(b.mode)),
            None => ((message_name(m).to_string(), true), Effect::Pulse),
        };
        let index = outputs.iter().position(|(o, _)| o.key == key).unwrap_or_else(|| {
            let variable = variable_of(m, names, diags);
            outputs.push((Signal { variable, key, message: m, notes: Vec::new() }, effect == Effect::Pulse));
            outputs.len() - 1
        });
        let verb = match effect {
            Effect::Pulse => "pulses",
            Effect::Set => "sets",
            Effect::Reset => "resets",
        };
        outputs[index].0.note(format!("{} {verb}", message_name(m)));
        (index, effect)
    };
    // Constants are at most 2^24 and a time unit at most 2^24 h (about 6·10^13 ms): their
    // product is far within u128, so the check below sees the exact value.
    let unit = u128::from(game.timeunit_ms);
    // The clock of each timer and its largest threshold, in time units.
    let mut timers: Vec<(ClockId, u32)> = Vec::new();
    let mut timer_of = |c: ClockId, units: u32| -> usize {
        match timers.iter().position(|&(clock, _)| clock == c) {
            Some(i) => {
                timers[i].1 = timers[i].1.max(units);
                i
            }
            None => {
                timers.push((c, units));
                timers.len() - 1
            }
        }
    };
    let mut refused: Vec<(ClockId, u32)> = Vec::new();
    // Every threshold compared: (timer, S5TIME preset, clock, constant), for the STL timer check.
    let mut thresholds: Vec<(usize, u64, ClockId, u32)> = Vec::new();
    let pos = program.positions();
    let mut test = |cond: &Condition, names: &mut Namespace, diags: &mut Diagnostics| -> Test {
        match *cond {
            Condition::Message { message } => {
                let (input, negated) = input_of(message, names, diags);
                Test::Input { input, negated }
            }
            Condition::Delay { clock, interval } => {
                let ms = u128::from(interval.lower) * unit;
                let strict = !interval.lower_closed;
                // A strict bound on S5TIME becomes the next value above it, which must fit too.
                if let Some((why, notes)) = time.refusal(ms).or_else(|| time.refusal(time.preset_for(ms, strict))) {
                    if !refused.contains(&(clock, interval.lower)) {
                        refused.push((clock, interval.lower));
                        let message =
                            format!("time constant {} ({ms} ms) {why} for target {}", interval.lower, target.name());
                        report(diags, game, clock, interval.lower, message, notes);
                    }
                }
                // Every accepted threshold fits in 32 bits; a refused one is never printed.
                let preset = u64::try_from(TimeType::S5Time.preset_for(ms, strict)).unwrap_or(u64::MAX);
                let ms = u64::try_from(ms).unwrap_or(u64::MAX);
                let timer = timer_of(clock, interval.lower);
                if !thresholds.iter().any(|&(t, p, _, _)| (t, p) == (timer, preset)) {
                    thresholds.push((timer, preset, clock, interval.lower));
                }
                if time == TimeType::S5Time {
                    // An S7 timer is elapsed at its S5TIME preset: the step tests that value, so
                    // that the code means what the STL does.
                    Test::Elapsed { timer, ms: preset, strict: false }
                } else {
                    Test::Elapsed { timer, ms, strict }
                }
            }
        }
    };
    let texts = program.command_texts(game);
    let mut steps = Vec::new();
    // The request of each step that sends one.
    let mut requests: Vec<Option<MsgId>> = Vec::new();
    for (c, comment) in program.commands.iter().zip(texts) {
        requests.push(match c.instruction {
            Instruction::Do { request } => Some(request),
            _ => None,
        });
        let statement = match c.instruction {
            Instruction::Do { request } => {
                let (output, effect) = output_of(request, &mut names, &mut diags);
                // Decided by `chain_requests` once the inputs are known.
                Statement::Act { output, effect, ends_scan: true }
            }
            Instruction::WaitUntil { condition } => Statement::Wait { test: test(&condition, &mut names, &mut diags) },
            Instruction::If { condition, target } => {
                let test = test(&condition, &mut names, &mut diags);
                Statement::Branch { test, target: pos[target.index()] as usize }
            }
            Instruction::Goto { target } => Statement::Jump { target: pos[target.index()] as usize },
        };
        // Timers are known only at the end; `restarts` holds the reset clocks until then.
        steps.push((Step { statement, restarts: Vec::new(), comment, back_in_scan: false }, c.resets));
    }
    let mut code_timers = Vec::new();
    for &(clock, units) in &timers {
        let threshold = u128::from(units) * unit;
        let preset = time.preset_ms(threshold, unit);
        if time.refusal(threshold).is_none() {
            if let Some((why, notes)) = time.refusal(preset) {
                let message = format!(
                    "time constant {units} ({threshold} ms) needs a timer preset one time unit above it, \
                     {preset} ms, which {why} for target {}",
                    target.name()
                );
                report(&mut diags, game, clock, units, message, notes);
            }
        }
        let clock_name = &game.clocks[clock.index()].name;
        // On S5TIME a strict threshold is tested at the next S5TIME value, above the largest
        // constant: the preset reaches every threshold tested.
        let k = code_timers.len();
        let tested = thresholds.iter().filter(|&&(t, ..)| t == k).map(|&(_, p, ..)| p);
        let preset = u64::try_from(preset).unwrap_or(u64::MAX);
        let preset = if time == TimeType::S5Time { tested.fold(preset, u64::max) } else { preset };
        code_timers.push(Timer {
            symbol: names.unique(&format!("t_{clock_name}")),
            comment: format!("clock {clock_name}"),
            preset_ms: preset,
        });
    }
    if diags.has_errors() {
        return Err(diags.items);
    }
    let steps: Vec<Step> = steps
        .into_iter()
        .map(|(mut step, resets)| {
            step.restarts = timers
                .iter()
                .enumerate()
                .filter(|(_, &(clock, _))| resets >> clock.index() & 1 == 1)
                .map(|(i, _)| i)
                .collect();
            step
        })
        .collect();
    let bound_to = |signal: &Signal| -> Vec<&IoBinding> {
        match io_of(signal.message) {
            Some(_) => game.io.iter().filter(|b| signal_key(b) == signal.key).collect(),
            None => Vec::new(),
        }
    };
    let wiring = Wiring {
        inputs: inputs
            .iter()
            .map(|i| match bound_to(i)[..] {
                [] => vec![(i.message, false)],
                ref all => all.iter().map(|b| (b.message, b.mode == IoMode::Negated)).collect(),
            })
            .collect(),
        outputs: outputs
            .iter()
            .map(|(o, _)| match bound_to(o)[..] {
                [] => vec![(o.message, Effect::Pulse)],
                ref all => all.iter().map(|b| (b.message, effect_of(b.mode))).collect(),
            })
            .collect(),
    };
    let header = vec![
        format!("Generated by plcsynth {} from a timed-game specification.", env!("CARGO_PKG_VERSION")),
        format!("Specification hash (FNV-1a 64): {}", source_hash(source)),
        "Do not edit: change the specification and generate again.".to_string(),
    ];
    let mut code = Code {
        name: fb_name,
        program: program_name,
        instance,
        gvl,
        header,
        inputs: inputs.into_iter().map(Signal::finish).collect(),
        outputs: outputs
            .into_iter()
            .map(|(o, pulsed)| {
                let variable = o.finish();
                // Named after every other variable, so that no message's name depends on it.
                let last = pulsed.then(|| names.unique(&format!("last_{}", variable.symbol)));
                Output { variable, pulsed, last }
            })
            .collect(),
        timers: code_timers,
        steps,
    };
    if pacing == Pacing::Chained {
        let facts: Vec<Option<RequestFacts>> =
            requests.iter().map(|r| r.map(|m| request_facts(game, m, &wiring.inputs))).collect();
        chain_requests(&mut code, &facts);
    }
    if target == Target::Stl {
        let unit = structured(&code).unit;
        let block =
            crate::plc::print::steps::StepBlock::of(&unit).expect("a step machine's unit has the jump-list shape");
        for clash in stl::clashes(&block, options) {
            let d = match clash.variable {
                Some(v) => {
                    let span = code.variables().nth(v).and_then(|(v, _)| v.span).unwrap_or_default();
                    diags.error(span, clash.message)
                }
                None => {
                    // A timer beyond the CPU's count: at the constant it is preset to.
                    let (timer, preset) = clash.timer.unwrap_or_default();
                    let (clock, units) = thresholds
                        .iter()
                        .find(|&&(t, p, _, _)| (t, p) == (timer, preset))
                        .map(|&(_, _, c, u)| (c, u))
                        .unwrap_or_default();
                    diags.error(crate::timed::constant_span(game, source, clock, units), clash.message)
                }
            };
            for note in clash.notes {
                d.with_note(note);
            }
        }
        if diags.has_errors() {
            return Err(diags.items);
        }
    }
    Ok((code, wiring))
}

/// What request `m` changes at once when the machine takes it, for [`chain_requests`]: the
/// components it moves (its receiver, those synchronised on it, those owning a clock it resets)
/// and, closed under them, the `instant` reactions those components may send with the
/// components those move. Its feedback is every input with a reaction such a component sends
/// (a sensor of the state reached changes when its sender moves; a latch when the reaction
/// occurs) and every state-guard input (the environment may change a guard at any move). Its
/// footprint holds those components, every assertion and state guard over one of them, and
/// every plan that observes the request or one of those reactions; requests with disjoint
/// footprints commute: neither enables, disables or reorders what the other does, and no rule
/// sees a state between them that the other order would not show.
fn request_facts(game: &Game, m: MsgId, inputs: &[Vec<(MsgId, bool)>]) -> RequestFacts {
    let n = game.components.len();
    let mut moved = vec![false; n];
    let mut sent = vec![m];
    let mut k = 0;
    while k < sent.len() {
        let msg = sent[k];
        k += 1;
        let info = &game.messages[msg.index()];
        let mut movers: Vec<CompId> = info.synchronised.clone();
        movers.extend(info.sender);
        // Clocks reset by the message's transitions belong to components that move with it.
        for a in &game.components {
            for e in a.edges.iter().filter(|e| e.message == msg) {
                for &c in &e.resets {
                    if let ClockOwner::Component(owner) = game.clocks[c.index()].owner {
                        movers.push(owner);
                    }
                }
            }
        }
        for u in movers {
            if std::mem::replace(&mut moved[u.index()], true) {
                continue;
            }
            for e in &game.components[u.index()].edges {
                if e.instant && e.kind == MessageKind::Uncontrollable && !sent.contains(&e.message) {
                    sent.push(e.message);
                }
            }
        }
    }
    let feedback = inputs
        .iter()
        .enumerate()
        .filter(|(_, ms)| {
            ms.iter().any(|&(x, _)| {
                let info = &game.messages[x.index()];
                info.role == MessageRole::Guard
                    || (info.role == MessageRole::Reaction && info.sender.is_some_and(|s| moved[s.index()]))
            })
        })
        .map(|(i, _)| i)
        .collect();
    let touches = |p: &Pred| pred_components(p).iter().any(|&c| moved[c.index()]);
    let mut footprint: Vec<u32> = (0..n as u32).filter(|&c| moved[c as usize]).collect();
    let mut token = n as u32;
    for rule in &game.assertions {
        if touches(&rule.holds) {
            footprint.push(token);
        }
        token += 1;
    }
    for rule in &game.guards {
        if touches(&rule.cond) {
            footprint.push(token);
        }
        token += 1;
    }
    for plan in &game.plans {
        if plan.edges.iter().any(|e| sent.contains(&e.message)) {
            footprint.push(token);
        }
        token += 1;
    }
    RequestFacts { feedback, footprint }
}

/// The components a predicate reads.
fn pred_components(p: &Pred) -> Vec<CompId> {
    match p {
        Pred::Const { .. } => Vec::new(),
        Pred::At { comp, .. } => vec![*comp],
        Pred::Not { operand } => pred_components(operand),
        Pred::And { operands } | Pred::Or { operands } => operands.iter().flat_map(pred_components).collect(),
    }
}

/// Generates the code of `program` for `target`. `name` names the function block, `source` is
/// the specification text (hashed into the header, and the place diagnostics point into).
pub fn generate(
    game: &Game,
    program: &Program,
    target: Target,
    name: &str,
    source: &str,
) -> Result<String, Vec<Diagnostic>> {
    let options = Options::default();
    let code = build(game, program, target, name, source, &options)?;
    Ok(render(&code, target, &options))
}

/// Reports a delay constant the target cannot hold: at the constant, with the time unit that
/// scaled it.
fn report(diags: &mut Diagnostics, game: &Game, clock: ClockId, units: u32, message: String, notes: Vec<String>) {
    let unit_note = match game.timeunit_span {
        Some(span) => {
            let (line, column) = diags.line_col(span.start as usize);
            format!("one time unit is {} ms (`timeunit` at {line}:{column})", game.timeunit_ms)
        }
        None => format!("one time unit is {} ms (the default, `timeunit 1s;`)", game.timeunit_ms),
    };
    let span = crate::timed::constant_span(game, diags.source(), clock, units);
    let d = diags.error(span, message);
    for note in notes {
        d.with_note(note);
    }
    d.with_note(format!("clock `{}` is compared with it", game.clocks[clock.index()].name)).with_note(unit_note);
}
