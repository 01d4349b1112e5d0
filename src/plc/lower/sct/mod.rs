//! The SynTACS runtime framework (Göbe 2019, 6.3; "SyRF") lowered into a [`Unit`]: synthesised
//! supervisors as PLC code around an existing controller. `docs/syrf.md` describes the
//! generated code; [`crate::sct::Runtime`] is the reference it is checked against, cycle by
//! cycle, so the two must keep one semantics.
//!
//! What is generated (the unit's name `N`, `SyRF` by default):
//! - constants `EV_…` (one per event, the controller passes them to `N_Execute`) and `SUP_…`;
//! - globals `N_Data`: every supervisor's state, the diagnostics an HMI shows (denials, the
//!   last denied event and its supervisor, unexpected uncontrollable events, enforcements,
//!   conflicts), per-cycle flags per event, edge latches, saved outputs, timer flags;
//! - functions: `N_Prohibited` (the first supervisor that prohibits an event, or 0), `N_Occur`
//!   (supervisors take an event; timers react), `N_Execute` (a controllable event: checked by
//!   all, committed only if all accept — 5.2.3), `N_Uncontrollable`, `N_Enforced` and
//!   `N_Enforce` (preemption, 5.5);
//! - the program `N_Main`, which the PLC task calls instead of the controller: the cycle of 6.3.4.

pub mod framework_sim;

use crate::diag::{Diagnostic, Diagnostics, Span};
use crate::plc::fragment::{self, BinOp, ExprKind, UnOp};
use crate::plc::model::unit::{Expr, Place, Pou, PouKind, Signal, SignalKind, Stmt, Type, Unit, Var};
use crate::plc::{identifier, source_hash, Namespace};
use crate::sct::model::{EventId, EventKind, Supervisor};
use crate::sct::{EdgeKind, EventMeta, Loaded, Trigger};
use std::collections::BTreeMap;

/// Choices of the framework beyond the specification.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct FrameworkOptions {
    /// Prefix of every generated name (`SyRF`).
    pub name: String,
    /// The function block type of the existing controller, which the framework calls.
    pub controller: String,
}

impl Default for FrameworkOptions {
    fn default() -> FrameworkOptions {
        FrameworkOptions { name: "SyRF".into(), controller: "Controller".into() }
    }
}

/// Where a fragment of an event is written, to locate what cannot be lowered.
#[derive(Clone, Copy)]
enum FragmentAt {
    Trigger,
    Accept,
    Denial,
}

fn fragment_span(meta: &EventMeta, at: FragmentAt) -> Span {
    let s = &meta.spans;
    match at {
        FragmentAt::Trigger => s.trigger,
        FragmentAt::Accept => s.code_on_accept,
        FragmentAt::Denial => s.code_on_denial,
    }
    .unwrap_or(s.name)
}

/// Signals found in the fragments, with what is known of their use.
#[derive(Default)]
struct SignalUse {
    written: bool,
    read_by_uncontrollable: bool,
    read_by_controllable: bool,
    int: bool,
    memory: bool,
    /// Events whose fragments mention it.
    events: Vec<String>,
}

struct Lowering<'a> {
    names: Namespace,
    /// Signal key (symbol, or address without `%`) → index in `signals`.
    signal_index: BTreeMap<String, usize>,
    signals: Vec<(String, SignalUse)>,
    /// Signals read through `\last{}`: signal index → global holding last cycle's value.
    last: BTreeMap<usize, String>,
    diags: Diagnostics<'a>,
    /// The type of every signal, once known (see [`signal_table`]).
    types: Vec<Type>,
}

fn address_kind(address: &str) -> SignalKind {
    match address.as_bytes().first() {
        Some(b'I') => SignalKind::Input,
        Some(b'Q') => SignalKind::Output,
        _ => SignalKind::Memory,
    }
}

/// The size of a direct address's value: a bit, or an integer (`B`, `W` as INT, `D` as DINT).
fn address_type(address: &str) -> Type {
    match address.as_bytes().get(1) {
        Some(b'W') | Some(b'B') => Type::Int,
        Some(b'D') | Some(b'L') => Type::Dint,
        _ => Type::Bool,
    }
}

/// Milliseconds of an IEC duration literal (`T#1s500ms`, `TIME#2m`, `t#1h_30m`).
fn duration_ms(text: &str) -> Option<u64> {
    let body = text.split_once('#')?.1.to_ascii_lowercase().replace('_', "");
    let mut total: u64 = 0;
    let mut rest = body.as_str();
    if rest.is_empty() {
        return None;
    }
    while !rest.is_empty() {
        let digits = rest.find(|c: char| !c.is_ascii_digit()).unwrap_or(rest.len());
        if digits == 0 {
            return None;
        }
        let value: u64 = rest[..digits].parse().ok()?;
        rest = &rest[digits..];
        let (unit, len) = if rest.starts_with("ms") {
            (1, 2)
        } else if rest.starts_with('d') {
            (86_400_000, 1)
        } else if rest.starts_with('h') {
            (3_600_000, 1)
        } else if rest.starts_with('m') {
            (60_000, 1)
        } else if rest.starts_with('s') {
            (1000, 1)
        } else {
            return None;
        };
        rest = &rest[len..];
        total = total.checked_add(value.checked_mul(unit)?)?;
    }
    Some(total)
}

fn int_literal(text: &str) -> Option<i64> {
    let clean = text.replace('_', "");
    match clean.split_once('#') {
        Some((base, digits)) => i64::from_str_radix(digits, base.parse().ok()?).ok(),
        None => clean.parse().ok(),
    }
}

/// The longest generated name: STEP 7 Classic (STL, SCL for S7-300/400) limits symbols to 24
/// characters, so every target gets names that fit.
const MAX_NAME: usize = 24;

impl<'a> Lowering<'a> {
    /// A fresh name `prefix + qualified + suffix` made an identifier; when it is longer than
    /// [`MAX_NAME`], the qualified name's last part stands for it (`accepted_Tank.fill` becomes
    /// `accepted_fill`), and past that it is cut. Unique case-insensitively, and reserved.
    fn name(&mut self, prefix: &str, qualified: &str, suffix: &str) -> String {
        let full = identifier(&format!("{prefix}{qualified}{suffix}"));
        let base = if full.len() <= MAX_NAME {
            full
        } else {
            let last = qualified.rsplit('.').next().unwrap_or(qualified);
            identifier(&format!("{prefix}{last}{suffix}"))
        };
        let cut = |text: &str, room: usize| text[..text.len().min(room)].trim_end_matches('_').to_string();
        let mut name = cut(&base, MAX_NAME);
        let mut n = 2;
        while self.names.contains(&name) {
            let tail = format!("_{n}");
            name = format!("{}{tail}", cut(&base, MAX_NAME - tail.len()));
            n += 1;
        }
        self.names.reserve(&name);
        name
    }

    /// The signal for a fragment name or address, registered on first sight.
    fn signal(&mut self, key: &str) -> usize {
        if let Some(&k) = self.signal_index.get(key) {
            return k;
        }
        let k = self.signals.len();
        self.signal_index.insert(key.to_string(), k);
        self.signals.push((key.to_string(), SignalUse::default()));
        k
    }

    fn signal_key(kind: &ExprKind) -> Option<String> {
        match kind {
            ExprKind::Var(path) => Some(path.join(".")),
            ExprKind::Address(text) => Some(text.trim_start_matches('%').to_ascii_uppercase()),
            ExprKind::ControllerVar(name) => Some(name.clone()),
            _ => None,
        }
    }

    /// First pass over a fragment expression: which signals, and how they are used. `kind` is
    /// the kind of the event whose trigger reads it (`None` for action code, whose reads say
    /// nothing of a signal's direction).
    fn scan_expr(&mut self, e: &fragment::Expr, event: &str, kind: Option<EventKind>, int_context: bool) {
        match &e.kind {
            ExprKind::Var(_) | ExprKind::Address(_) | ExprKind::ControllerVar(_) => {
                let key = Self::signal_key(&e.kind).unwrap_or_default();
                let k = self.signal(&key);
                let u = &mut self.signals[k].1;
                u.int |= int_context;
                u.memory |= matches!(e.kind, ExprKind::ControllerVar(_));
                match kind {
                    Some(EventKind::Uncontrollable) => u.read_by_uncontrollable = true,
                    Some(_) => u.read_by_controllable = true,
                    None => {}
                }
                if !u.events.iter().any(|x| x == event) {
                    u.events.push(event.to_string());
                }
            }
            ExprKind::Last(name) => {
                let key = name.trim_start_matches('%').to_string();
                let k = self.signal(&key);
                self.signals[k].1.int |= int_context;
                if !self.signals[k].1.events.iter().any(|x| x == event) {
                    self.signals[k].1.events.push(event.to_string());
                }
                self.last.entry(k).or_default();
            }
            ExprKind::Unary(UnOp::Neg, a) => self.scan_expr(a, event, kind, true),
            ExprKind::Unary(UnOp::Not, a) => self.scan_expr(a, event, kind, int_context),
            ExprKind::Binary(op, a, b) => {
                let numeric = !matches!(op, BinOp::Or | BinOp::Xor | BinOp::And | BinOp::Eq | BinOp::Ne);
                // `x = 5`: an integer comparison.
                let literal_int =
                    |e: &fragment::Expr| matches!(e.kind, ExprKind::Int(_) | ExprKind::Unary(UnOp::Neg, _));
                let eq_int = matches!(op, BinOp::Eq | BinOp::Ne) && (literal_int(a) || literal_int(b));
                self.scan_expr(a, event, kind, numeric || eq_int || (int_context && !is_logic(*op)));
                self.scan_expr(b, event, kind, numeric || eq_int || (int_context && !is_logic(*op)));
            }
            ExprKind::Bool(_) | ExprKind::Int(_) | ExprKind::Real(_) | ExprKind::Time(_) => {}
        }
    }

    fn scan_stmts(&mut self, stmts: &[fragment::Stmt], event: &str) {
        for s in stmts {
            match s {
                fragment::Stmt::Assign { target, value } => {
                    let int = matches!(value.kind, ExprKind::Int(_) | ExprKind::Unary(UnOp::Neg, _))
                        || matches!(value.kind, ExprKind::Binary(op, ..) if !is_logic(op) && !is_comparison(op));
                    self.scan_expr(target, event, None, int);
                    if let Some(key) = Self::signal_key(&target.kind) {
                        let k = self.signal(&key);
                        self.signals[k].1.written = true;
                    }
                    self.scan_expr(value, event, None, false);
                }
                fragment::Stmt::If { arms, otherwise } => {
                    for (c, body) in arms {
                        self.scan_expr(c, event, None, false);
                        self.scan_stmts(body, event);
                    }
                    self.scan_stmts(otherwise, event);
                }
            }
        }
    }

    /// A fragment expression as a unit expression; what the framework cannot hold is an error
    /// at `at`.
    fn expr(&mut self, e: &fragment::Expr, at: Span) -> Option<Expr> {
        Some(match &e.kind {
            ExprKind::Bool(b) => Expr::Bool(*b),
            ExprKind::Int(text) => match int_literal(text) {
                Some(v) => Expr::Int(v),
                None => {
                    self.diags.error(at, format!("the integer `{text}` is out of range for the PLC code"));
                    return None;
                }
            },
            ExprKind::Real(text) => {
                self.diags
                    .error(at, format!("real numbers such as `{text}` are not supported in the generated framework"))
                    .with_note("triggers and actions may use BOOL, INT, DINT and TIME values");
                return None;
            }
            ExprKind::Time(text) => match duration_ms(text) {
                Some(ms) => Expr::Time(ms),
                None => {
                    self.diags.error(
                        at,
                        format!("`{text}` is not a duration the framework can use (days to ms, whole numbers)"),
                    );
                    return None;
                }
            },
            ExprKind::Var(_) | ExprKind::Address(_) | ExprKind::ControllerVar(_) => {
                let key = Self::signal_key(&e.kind).unwrap_or_default();
                Expr::Read(Place::Signal(self.signal(&key)))
            }
            ExprKind::Last(name) => {
                let k = self.signal(name.trim_start_matches('%'));
                Expr::global(self.last[&k].clone())
            }
            ExprKind::Unary(UnOp::Not, a) => {
                let a = self.expr(a, at)?;
                self.logic_on_bool(&[&a], "NOT", at)?;
                Expr::Not(Box::new(a))
            }
            ExprKind::Unary(UnOp::Neg, a) => match &a.kind {
                ExprKind::Int(text) => Expr::Int(-int_literal(text).unwrap_or(0)),
                _ => Expr::Neg(Box::new(self.expr(a, at)?)),
            },
            ExprKind::Binary(op, a, b) => {
                let (a, b) = (self.expr(a, at)?, self.expr(b, at)?);
                if is_logic(*op) {
                    self.logic_on_bool(&[&a, &b], op.text(), at)?;
                }
                Expr::binary(*op, a, b)
            }
        })
    }

    /// Whether `e` is an integer (a signal typed INT, a number, arithmetic).
    fn is_int(&self, e: &Expr) -> bool {
        match e {
            Expr::Int(_) | Expr::Neg(_) => true,
            Expr::Read(Place::Signal(k)) => matches!(self.types.get(*k), Some(Type::Int | Type::Dint)),
            Expr::Binary(op, a, _) if is_logic(*op) => self.is_int(a),
            Expr::Binary(op, ..) => !is_comparison(*op),
            Expr::Not(a) => self.is_int(a),
            _ => false,
        }
    }

    /// `AND`, `OR`, `XOR` and `NOT` take BOOL operands: bit logic on integers means something
    /// else in every dialect (and STL has none), so it is refused where it is written.
    fn logic_on_bool(&mut self, operands: &[&Expr], op: &str, at: Span) -> Option<()> {
        if operands.iter().any(|e| self.is_int(e)) {
            self.diags
                .error(at, format!("`{op}` on an integer: triggers and actions use logic on BOOL values only"))
                .with_note("compare the integer instead, e.g. `Level > 0`");
            return None;
        }
        Some(())
    }

    fn stmts(&mut self, stmts: &[fragment::Stmt], at: Span) -> Option<Vec<Stmt>> {
        let mut out = Vec::new();
        for s in stmts {
            out.push(match s {
                fragment::Stmt::Assign { target, value } => {
                    let Some(key) = Self::signal_key(&target.kind) else {
                        self.diags.error(at, "only a variable or an address can be assigned");
                        return None;
                    };
                    Stmt::assign(Place::Signal(self.signal(&key)), self.expr(value, at)?)
                }
                fragment::Stmt::If { arms, otherwise } => {
                    let mut lowered = Vec::new();
                    for (c, body) in arms {
                        lowered.push((self.expr(c, at)?, self.stmts(body, at)?));
                    }
                    Stmt::If { arms: lowered, otherwise: self.stmts(otherwise, at)? }
                }
            });
        }
        Some(out)
    }
}

fn is_logic(op: BinOp) -> bool {
    matches!(op, BinOp::Or | BinOp::Xor | BinOp::And)
}

fn is_comparison(op: BinOp) -> bool {
    matches!(op, BinOp::Eq | BinOp::Ne | BinOp::Lt | BinOp::Le | BinOp::Gt | BinOp::Ge)
}

/// The parsed fragments of one event: parsed once, by the checker (`sct::check`).
type Fragments = crate::sct::EventFragments;

/// `a = x OR a = y …` for the events `list` (by their constants).
fn any_of(selector: &str, list: &[&str]) -> Expr {
    let mut it = list.iter().map(|c| Expr::local(selector).eq(Expr::global(*c)));
    let first = it.next().unwrap_or(Expr::Bool(false));
    it.fold(first, Expr::or)
}

fn counter_up(name: &str) -> Stmt {
    Stmt::assign(Place::global(name), Expr::binary(BinOp::Add, Expr::global(name), Expr::Int(1)))
}

/// How many enforcements supervisor `s` may make in one cycle: the longest chain of enforced
/// transitions, at most its number of states (the bound of [`crate::sct::Runtime`]).
fn enforcement_chain(s: &Supervisor) -> usize {
    let n = s.states.len();
    let mut longest = 0;
    for start in 0..n {
        let mut state = start as u32;
        let mut len = 0;
        while len < n {
            let Some(f) = s.states[state as usize].enforced else { break };
            len += 1;
            let next = s.successor(state, f);
            if next == state {
                break;
            }
            state = next;
        }
        longest = longest.max(len);
    }
    longest
}

/// Names of parameters and locals of the generated POUs.
struct Locals {
    ev: String,
    only: String,
    skip: String,
    timers: String,
    by: String,
    sup: String,
    f: String,
    p: String,
    k: String,
    moved: String,
    ok: String,
    go: String,
    controller: String,
}

/// Lowers the framework for `supervisors` of `loaded` (whose text is `source`).
pub fn lower(
    source: &str,
    loaded: &Loaded,
    supervisors: &[&Supervisor],
    options: &FrameworkOptions,
) -> Result<Unit, Vec<Diagnostic>> {
    lower_mapped(source, loaded, supervisors, options).map(|(unit, _)| unit)
}

/// Where the generated framework keeps what a simulator shows: the globals of the supervisors'
/// states, of the per-cycle event flags and of the timers (names of `Unit::globals`).
#[derive(Clone, Debug, Default)]
pub struct FrameworkMap {
    /// Per supervisor (in the order given to [`lower`]), the global holding its state index.
    pub supervisor_states: Vec<String>,
    /// Per event, its flags of the current cycle: `(event, what, global)` with `what` one of
    /// `accepted`, `denied` (controllable), `occurred` (uncontrollable), `enforced`.
    pub event_flags: Vec<(EventId, &'static str, String)>,
    /// Per timer of the project: `(name, running global, expired global)`.
    pub timers: Vec<(String, String, String)>,
    /// The globals of the last denied event (an `EV_` value: event id + 1) and of the
    /// supervisor that denied it (a `SUP_` value: its position + 1).
    pub last_denied: (String, String),
}

/// [`lower`], with the map of the framework's globals.
pub fn lower_mapped(
    source: &str,
    loaded: &Loaded,
    supervisors: &[&Supervisor],
    options: &FrameworkOptions,
) -> Result<(Unit, FrameworkMap), Vec<Diagnostic>> {
    let project = &loaded.project;
    let mut l = Lowering {
        names: Namespace::new(),
        signal_index: BTreeMap::new(),
        signals: Vec::new(),
        last: BTreeMap::new(),
        diags: Diagnostics::new(source),
        types: Vec::new(),
    };
    let fragments: Vec<&Fragments> = loaded.events.iter().map(|m| &m.fragments).collect();

    // Supervisors that cannot run.
    for s in supervisors {
        if !s.realizable() {
            let spec = project.specs.iter().position(|p| p.name == s.name);
            let at = spec.and_then(|k| loaded.spec_spans.get(k).copied()).unwrap_or_default();
            l.diags.error(
                at,
                format!("supervisor `{}` is void (its specification is unrealizable) and cannot run", s.name),
            );
        }
        let mut reported = Vec::new();
        for (q, state) in s.states.iter().enumerate() {
            for &(e, t) in &state.transitions {
                let meta = &loaded.events[e.0 as usize];
                let virtual_event =
                    matches!(meta.trigger, Trigger::Virtual) && project.kind(e) != EventKind::Enforceable;
                if virtual_event && t as usize != q && !reported.contains(&e) {
                    reported.push(e);
                    l.diags
                        .error(
                            meta.spans.name,
                            format!(
                                "supervisor `{}` changes state on the virtual event `{}`, which the PLC cannot detect",
                                s.name,
                                project.event_name(e)
                            ),
                        )
                        .with_note(format!(
                            "in state `{}`; give the event a trigger (`detect …` or `executed`)",
                            state.label
                        ))
                        .with_note("a virtual event may only be prohibited or loop (Göbe 2019, 6.3.1)");
                }
            }
        }
    }

    // Signals, first pass: the user's names are taken before any generated one.
    for (id, f) in fragments.iter().enumerate() {
        let e = EventId(id as u32);
        let (name, kind) = (project.event_name(e).to_string(), project.kind(e));
        if let Some(t) = &f.trigger {
            l.scan_expr(t, &name, Some(kind), false);
        }
        for r in &f.resets {
            l.scan_expr(r, &name, None, false);
            if let Some(key) = Lowering::signal_key(&r.kind) {
                let k = l.signal(&key);
                l.signals[k].1.written = true;
            }
        }
        l.scan_stmts(&f.accept, &name);
        l.scan_stmts(&f.denial, &name);
    }
    for (key, _) in &l.signals {
        l.names.reserve(key.split('.').next().unwrap_or(key));
    }
    l.names.reserve(&options.controller);
    let n = identifier(&options.name);
    let prefixed = |l: &mut Lowering<'_>, what: &str| l.name(&format!("{n}_"), what, "");
    let gvl = prefixed(&mut l, "Data");
    let f_prohibited = prefixed(&mut l, "Prohibited");
    let f_occur = prefixed(&mut l, "Occur");
    let f_execute = prefixed(&mut l, "Execute");
    let f_uncontrollable = prefixed(&mut l, "Uncontrollable");
    let f_enforced = prefixed(&mut l, "Enforced");
    let f_enforce = prefixed(&mut l, "Enforce");
    let program = prefixed(&mut l, "Main");
    // Parameters and locals: unique too, so that none hides a signal of the user's project.
    let lv = Locals {
        ev: l.name("", "ev", ""),
        only: l.name("", "only", ""),
        skip: l.name("", "skip", ""),
        timers: l.name("", "with_timers", ""),
        by: l.name("", "enforcer", ""),
        sup: l.name("", "sup", ""),
        f: l.name("", "f", ""),
        p: l.name("", "p", ""),
        k: l.name("", "k", ""),
        moved: l.name("", "moved", ""),
        ok: l.name("", "ok", ""),
        go: l.name("", "go", ""),
        controller: l.name("", "supervised", ""),
    };

    let signals = signal_table(&l);
    l.types = signals.iter().map(|s| s.ty.clone()).collect();
    let signal_names: Vec<String> = signals.iter().map(|s| s.symbol.clone()).collect();
    for k in l.last.keys().copied().collect::<Vec<_>>() {
        let global = l.name("last_", &signal_names[k], "");
        l.last.insert(k, global);
    }

    // Constants.
    let mut constants = Vec::new();
    let mut event_const = Vec::new();
    for (id, info) in project.events.iter().enumerate() {
        let c = l.name("EV_", &info.name, "");
        constants.push(
            Var::new(&c, Type::Int, format!("{} ({})", info.name, format!("{:?}", info.kind).to_lowercase()))
                .with_init(Expr::Int(id as i64 + 1)),
        );
        event_const.push(c);
    }
    let mut sup_state = Vec::new();
    let mut sup_const = Vec::new();
    for (k, s) in supervisors.iter().enumerate() {
        let c = l.name("SUP_", &s.name, "");
        sup_const.push(c.clone());
        constants.push(Var::new(&c, Type::Int, format!("supervisor {}", s.name)).with_init(Expr::Int(k as i64 + 1)));
        sup_state.push(l.name("state_", &s.name, ""));
    }

    // Globals.
    let mut globals = Vec::new();
    for (k, s) in supervisors.iter().enumerate() {
        let init = s.init.unwrap_or(0);
        let label = s.states.get(init as usize).map_or("", |st| st.label.as_str());
        globals.push(
            Var::new(&sup_state[k], Type::Int, format!("state of supervisor {} (initial: {label})", s.name))
                .with_init(Expr::Int(i64::from(init))),
        );
    }
    let diag_names = [
        ("denials", Type::Dint, "controllable events denied since start"),
        ("last_denied_event", Type::Int, "the last denied event (an EV_ constant)"),
        ("last_denied_supervisor", Type::Int, "the supervisor that denied it (a SUP_ constant)"),
        ("unexpected", Type::Dint, "uncontrollable events that a supervisor prohibits (plant model violated)"),
        ("last_unexpected_event", Type::Int, "the last unexpected event"),
        ("last_unexpected_sup", Type::Int, "the supervisor that prohibits it (a SUP_ constant)"),
        ("enforcements", Type::Dint, "events enforced since start"),
        ("last_enforced_event", Type::Int, "the last enforced event"),
        ("conflicts", Type::Dint, "enforced events that another supervisor prohibits (6.4.2)"),
    ];
    let mut diag = BTreeMap::new();
    for (name, ty, comment) in diag_names {
        let g = l.name("", name, "");
        globals.push(Var::new(&g, ty, comment));
        diag.insert(name, g);
    }
    // Per-event flags of the current cycle, edge latches, saved outputs.
    let mut flag_acc = BTreeMap::new();
    let mut flag_den = BTreeMap::new();
    let mut flag_occ = BTreeMap::new();
    let mut latch = BTreeMap::new();
    for (id, info) in project.events.iter().enumerate() {
        let e = EventId(id as u32);
        match info.kind {
            EventKind::Controllable => {
                let a = l.name("accepted_", &info.name, "");
                let b = l.name("denied_", &info.name, "");
                globals.push(Var::new(&a, Type::Bool, format!("{} accepted this cycle", info.name)));
                globals.push(Var::new(&b, Type::Bool, format!("{} denied this cycle", info.name)));
                flag_acc.insert(e, a);
                flag_den.insert(e, b);
            }
            EventKind::Uncontrollable | EventKind::Enforceable => {
                let what = if info.kind == EventKind::Enforceable { "enforced" } else { "occurred" };
                let a = l.name(&format!("{what}_"), &info.name, "");
                globals.push(Var::new(&a, Type::Bool, format!("{} {what} this cycle", info.name)));
                flag_occ.insert(e, a);
            }
        }
        if fragments[id].trigger.is_some() {
            let g = l.name("latch_", &info.name, "");
            globals.push(Var::new(&g, Type::Bool, format!("trigger of {} in the previous cycle", info.name)));
            latch.insert(e, g);
        }
    }
    for (&k, g) in &l.last {
        globals.push(Var::new(g, signals[k].ty.clone(), format!("{} in the previous cycle (\\last)", signal_names[k])));
    }
    let mut saved: BTreeMap<usize, String> = BTreeMap::new();
    for f in &fragments {
        for r in &f.resets {
            if let Some(key) = Lowering::signal_key(&r.kind) {
                let k = l.signal(&key);
                if let std::collections::btree_map::Entry::Vacant(slot) = saved.entry(k) {
                    let g = l.name("saved_", &signal_names[k], "");
                    globals.push(Var::new(
                        &g,
                        signals[k].ty.clone(),
                        format!("{} before the controller ran", signal_names[k]),
                    ));
                    slot.insert(g);
                }
            }
        }
    }
    let mut timer_names = Vec::new();
    for t in &loaded.timers {
        let names = TimerNames {
            run: l.name("", &t.name, "_running"),
            restart: l.name("", &t.name, "_restart"),
            expired: l.name("", &t.name, "_expired"),
            ton: l.name("", &t.name, "_ton"),
            due: l.name("", &t.name, "_due"),
        };
        globals.push(Var::new(&names.run, Type::Bool, format!("timer {} runs", t.name)));
        globals.push(Var::new(&names.restart, Type::Bool, format!("timer {} starts at the end of this cycle", t.name)));
        globals.push(Var::new(&names.expired, Type::Bool, format!("timer {} reached {} ms", t.name, t.duration_ms)));
        timer_names.push(names);
    }

    let fw = Framework {
        loaded,
        supervisors,
        fragments,
        lv,
        fun: Functions {
            prohibited: f_prohibited,
            occur: f_occur,
            execute: f_execute,
            uncontrollable: f_uncontrollable,
            enforced: f_enforced,
            enforce: f_enforce,
            program,
        },
        controller: options.controller.clone(),
        event_const,
        sup_const,
        sup_state,
        diag,
        flag_acc,
        flag_den,
        flag_occ,
        latch,
        saved,
        timers: timer_names,
    };
    let pous = vec![
        prohibited_pou(&fw),
        occur_pou(&fw),
        execute_pou(&fw),
        uncontrollable_pou(&fw),
        enforced_pou(&fw),
        enforce_pou(&fw, &mut l),
        main_pou(&fw, &mut l),
    ];
    if l.diags.items.iter().any(Diagnostic::is_error) {
        return Err(l.diags.items);
    }
    let mut event_flags = Vec::new();
    for (what, flags) in [("accepted", &fw.flag_acc), ("denied", &fw.flag_den)] {
        event_flags.extend(flags.iter().map(|(&e, g)| (e, what, g.clone())));
    }
    for (&e, g) in &fw.flag_occ {
        let what = if project.kind(e) == EventKind::Enforceable { "enforced" } else { "occurred" };
        event_flags.push((e, what, g.clone()));
    }
    let map = FrameworkMap {
        supervisor_states: fw.sup_state.clone(),
        event_flags,
        timers: loaded
            .timers
            .iter()
            .zip(&fw.timers)
            .map(|(t, names)| (t.name.clone(), names.run.clone(), names.expired.clone()))
            .collect(),
        last_denied: (fw.d("last_denied_event"), fw.d("last_denied_supervisor")),
    };
    let header = vec![
        format!("Generated by plcsynth {} from a supervisory-control specification.", env!("CARGO_PKG_VERSION")),
        format!("Specification hash (FNV-1a 64): {}", source_hash(source)),
        format!(
            "Supervisors: {}.",
            supervisors
                .iter()
                .map(|s| format!("{} ({} states)", s.name, s.states.len()))
                .collect::<Vec<_>>()
                .join(", ")
        ),
        "Do not edit: change the specification and generate again.".to_string(),
    ];
    Ok((Unit { name: n, header, gvl, constants, globals, signals, pous }, map))
}

/// The signals found in the fragments, with their kind, type and the address the STL form
/// gives them: direct addresses as written; symbols after the highest byte written directly,
/// bits first, words on even bytes (memory from byte 100).
fn signal_table(l: &Lowering<'_>) -> Vec<Signal> {
    // Signals, second pass: kinds, types, addresses for dialects that need one.
    let mut used_bytes: BTreeMap<char, u32> = BTreeMap::new();
    for (key, _) in &l.signals {
        if key.starts_with(['I', 'Q', 'M'])
            && key[1..].trim_start_matches(['X', 'B', 'W', 'D']).starts_with(|c: char| c.is_ascii_digit())
        {
            let digits = key[1..].trim_start_matches(['X', 'B', 'W', 'D']);
            let byte: u32 = digits.split('.').next().and_then(|b| b.parse().ok()).unwrap_or(0);
            let area = key.chars().next().unwrap_or('M');
            let e = used_bytes.entry(area).or_insert(0);
            *e = (*e).max(byte + 4);
        }
    }
    let mut next_bit: BTreeMap<char, u32> = BTreeMap::new();
    let mut signals = Vec::new();
    for (key, u) in &l.signals {
        let is_address = key.starts_with(['I', 'Q', 'M'])
            && key[1..].trim_start_matches(['X', 'B', 'W', 'D']).starts_with(|c: char| c.is_ascii_digit());
        let (kind, ty, address) = if is_address {
            (address_kind(key), address_type(key), key.clone())
        } else {
            let kind = if u.memory {
                SignalKind::Memory
            } else if u.written || u.read_by_controllable {
                SignalKind::Output
            } else {
                SignalKind::Input
            };
            let ty = if u.int { Type::Int } else { Type::Bool };
            let area = match kind {
                SignalKind::Input => 'I',
                SignalKind::Output => 'Q',
                SignalKind::Memory => 'M',
            };
            let base = used_bytes.get(&area).copied().unwrap_or(0) + if area == 'M' { 100 } else { 0 };
            let next = next_bit.entry(area).or_insert(base * 8);
            let address = if ty == Type::Bool {
                let a = format!("{area}X{}.{}", *next / 8, *next % 8);
                *next += 1;
                a
            } else {
                // Words start on an even byte after the bits taken so far.
                let byte = (next.div_ceil(8) + 1) & !1;
                *next = (byte + 2) * 8;
                format!("{area}W{byte}")
            };
            (kind, ty, address)
        };
        signals.push(Signal { symbol: key.clone(), kind, ty, address, comment: u.events.join(", ") });
    }
    signals
}

/// Names of a timer's variables.
struct TimerNames {
    run: String,
    restart: String,
    expired: String,
    ton: String,
    due: String,
}

/// Names of the generated functions and the program.
struct Functions {
    prohibited: String,
    occur: String,
    execute: String,
    uncontrollable: String,
    enforced: String,
    enforce: String,
    program: String,
}

/// Everything the POUs of the framework refer to by name.
struct Framework<'a> {
    loaded: &'a Loaded,
    supervisors: &'a [&'a Supervisor],
    fragments: Vec<&'a Fragments>,
    lv: Locals,
    fun: Functions,
    controller: String,
    /// The constant of every event (by id) and every supervisor (by position).
    event_const: Vec<String>,
    sup_const: Vec<String>,
    /// The global holding every supervisor's state.
    sup_state: Vec<String>,
    /// The diagnostic globals, by their base name.
    diag: BTreeMap<&'static str, String>,
    flag_acc: BTreeMap<EventId, String>,
    flag_den: BTreeMap<EventId, String>,
    flag_occ: BTreeMap<EventId, String>,
    latch: BTreeMap<EventId, String>,
    saved: BTreeMap<usize, String>,
    timers: Vec<TimerNames>,
}

impl Framework<'_> {
    fn ev(&self, e: EventId) -> String {
        self.event_const[e.0 as usize].clone()
    }

    fn d(&self, name: &str) -> String {
        self.diag[name].clone()
    }

    /// Sets the flag of the event `selector` holds: an IF chain over the events in `flags`.
    fn flag_chain(&self, flags: &BTreeMap<EventId, String>, selector: &str) -> Vec<Stmt> {
        let arms: Vec<(Expr, Vec<Stmt>)> = flags
            .iter()
            .map(|(&e, g)| {
                (
                    Expr::local(selector).eq(Expr::global(self.ev(e))),
                    vec![Stmt::assign(Place::global(g), Expr::Bool(true))],
                )
            })
            .collect();
        if arms.is_empty() {
            Vec::new()
        } else {
            vec![Stmt::If { arms, otherwise: Vec::new() }]
        }
    }
}

fn prohibited_pou(fw: &Framework) -> Pou {
    // N_Prohibited(ev): the first supervisor whose state prohibits ev, else 0.
    let mut body = vec![Stmt::assign(Place::local(&fw.fun.prohibited), Expr::Int(0))];
    for (k, s) in fw.supervisors.iter().enumerate() {
        let mut arms = Vec::new();
        for (q, state) in s.states.iter().enumerate() {
            if state.prohibited.is_empty() {
                continue;
            }
            let list: Vec<String> = state.prohibited.iter().map(|&e| fw.ev(e)).collect();
            let refs: Vec<&str> = list.iter().map(String::as_str).collect();
            arms.push((
                vec![q as i64],
                vec![
                    Stmt::Comment(format!("state {}", state.label)),
                    Stmt::when(
                        any_of(&fw.lv.ev, &refs),
                        vec![Stmt::assign(Place::local(&fw.fun.prohibited), Expr::global(&fw.sup_const[k]))],
                    ),
                ],
            ));
        }
        if arms.is_empty() {
            continue;
        }
        body.push(Stmt::Comment(format!("supervisor {}", s.name)));
        body.push(Stmt::when(
            Expr::local(&fw.fun.prohibited).eq(Expr::Int(0)),
            vec![Stmt::Case { selector: Expr::global(&fw.sup_state[k]), arms, otherwise: Vec::new() }],
        ));
    }
    Pou {
        kind: PouKind::Function { returns: Some(Type::Int) },
        name: fw.fun.prohibited.clone(),
        comment: "The first supervisor (SUP_ constant) whose current state prohibits event ev, or 0 if all allow it."
            .into(),
        inputs: vec![Var::new(&fw.lv.ev, Type::Int, "an EV_ constant")],
        outputs: Vec::new(),
        locals: Vec::new(),
        body,
    }
}

fn occur_pou(fw: &Framework) -> Pou {
    // N_Occur(ev, only, skip, timers): fw.supervisors take ev; timers react.
    let mut body = vec![Stmt::assign(Place::local(&fw.fun.occur), Expr::Bool(false))];
    for (k, s) in fw.supervisors.iter().enumerate() {
        let mut arms = Vec::new();
        for (q, state) in s.states.iter().enumerate() {
            // Transitions grouped by target; loops change nothing and are left out.
            let mut by_target: BTreeMap<u32, Vec<String>> = BTreeMap::new();
            for &(e, t) in &state.transitions {
                if t as usize != q {
                    by_target.entry(t).or_default().push(fw.ev(e));
                }
            }
            if by_target.is_empty() {
                continue;
            }
            let branches = by_target
                .iter()
                .map(|(&t, list)| {
                    let refs: Vec<&str> = list.iter().map(String::as_str).collect();
                    (
                        any_of(&fw.lv.ev, &refs),
                        vec![
                            Stmt::assign(Place::global(&fw.sup_state[k]), Expr::Int(i64::from(t))),
                            Stmt::assign(Place::local(&fw.fun.occur), Expr::Bool(true)),
                        ],
                    )
                })
                .collect();
            arms.push((
                vec![q as i64],
                vec![
                    Stmt::Comment(format!("state {}", state.label)),
                    Stmt::If { arms: branches, otherwise: Vec::new() },
                ],
            ));
        }
        if arms.is_empty() {
            continue;
        }
        let k1 = Expr::Int(k as i64 + 1);
        let selected = Expr::local(&fw.lv.only)
            .eq(Expr::Int(0))
            .or(Expr::local(&fw.lv.only).eq(k1.clone()))
            .and(Expr::local(&fw.lv.skip).ne(k1));
        body.push(Stmt::Comment(format!("supervisor {}", s.name)));
        body.push(Stmt::when(
            selected,
            vec![Stmt::Case { selector: Expr::global(&fw.sup_state[k]), arms, otherwise: Vec::new() }],
        ));
    }
    let mut timer_stmts = Vec::new();
    for (t, names) in fw.loaded.timers.iter().zip(&fw.timers) {
        let stops: Vec<String> = t.stop.iter().filter_map(|s| fw.loaded.project.event(s)).map(|e| fw.ev(e)).collect();
        if !stops.is_empty() {
            let refs: Vec<&str> = stops.iter().map(String::as_str).collect();
            timer_stmts.push(Stmt::when(
                any_of(&fw.lv.ev, &refs),
                vec![
                    Stmt::assign(Place::global(&names.run), Expr::Bool(false)),
                    Stmt::assign(Place::global(&names.expired), Expr::Bool(false)),
                    Stmt::assign(Place::global(&names.restart), Expr::Bool(false)),
                ],
            ));
        }
        if let Some(start) = fw.loaded.project.event(&t.start) {
            let idle_or_expired = Expr::global(&names.run).not().or(Expr::global(&names.expired));
            timer_stmts.push(Stmt::when(
                Expr::local(&fw.lv.ev).eq(Expr::global(fw.ev(start))).and(idle_or_expired),
                vec![
                    Stmt::assign(Place::global(&names.run), Expr::Bool(true)),
                    Stmt::assign(Place::global(&names.expired), Expr::Bool(false)),
                    Stmt::assign(Place::global(&names.restart), Expr::Bool(true)),
                ],
            ));
        }
    }
    if !timer_stmts.is_empty() {
        body.push(Stmt::Comment("timers: a stop event resets, a start event starts unless running".into()));
        body.push(Stmt::when(Expr::local(&fw.lv.timers), timer_stmts));
    }
    Pou {
        kind: PouKind::Function { returns: Some(Type::Bool) },
        name: fw.fun.occur.clone(),
        comment: "Event ev occurs: every supervisor (or only supervisor `only`; none is 0) except `skip` takes it, \
                  and with `timers` the timers react. TRUE if a supervisor changed state."
            .into(),
        inputs: vec![
            Var::new(&fw.lv.ev, Type::Int, "an EV_ constant"),
            Var::new(&fw.lv.only, Type::Int, "0: all supervisors"),
            Var::new(&fw.lv.skip, Type::Int, "0: none"),
            Var::new(&fw.lv.timers, Type::Bool, "the timers react"),
        ],
        outputs: Vec::new(),
        locals: Vec::new(),
        body,
    }
}

fn execute_pou(fw: &Framework) -> Pou {
    // N_Execute(ev): a controllable event, committed only if every supervisor accepts it.
    let mut denied = vec![
        Stmt::assign(
            Place::global(fw.d("denials")),
            Expr::binary(BinOp::Add, Expr::global(fw.d("denials")), Expr::Int(1)),
        ),
        Stmt::assign(Place::global(fw.d("last_denied_event")), Expr::local(&fw.lv.ev)),
        Stmt::assign(Place::global(fw.d("last_denied_supervisor")), Expr::local(&fw.lv.k)),
        Stmt::assign(Place::local(&fw.fun.execute), Expr::Bool(false)),
    ];
    denied.extend(fw.flag_chain(&fw.flag_den, &fw.lv.ev));
    let mut accepted = vec![
        Stmt::CallFunction {
            function: fw.fun.occur.clone(),
            args: vec![
                (fw.lv.ev.clone(), Expr::local(&fw.lv.ev)),
                (fw.lv.only.clone(), Expr::Int(0)),
                (fw.lv.skip.clone(), Expr::Int(0)),
                (fw.lv.timers.clone(), Expr::Bool(true)),
            ],
            result: Some(Place::local(&fw.lv.moved)),
        },
        Stmt::assign(Place::local(&fw.fun.execute), Expr::Bool(true)),
    ];
    accepted.extend(fw.flag_chain(&fw.flag_acc, &fw.lv.ev));
    Pou {
        kind: PouKind::Function { returns: Some(Type::Bool) },
        name: fw.fun.execute.clone(),
        comment: format!(
            "A controllable event: TRUE and taken by every supervisor if all accept it, else FALSE and nothing changes. \
             The controller calls it for its executed events, e.g. {}(ev := EV_…).",
            fw.fun.execute
        ),
        inputs: vec![Var::new(&fw.lv.ev, Type::Int, "an EV_ constant of a controllable event")],
        outputs: Vec::new(),
        locals: vec![Var::new(&fw.lv.k, Type::Int, ""), Var::new(&fw.lv.moved, Type::Bool, "")],
        body: vec![
            Stmt::CallFunction {
                function: fw.fun.prohibited.clone(),
                args: vec![(fw.lv.ev.clone(), Expr::local(&fw.lv.ev))],
                result: Some(Place::local(&fw.lv.k)),
            },
            Stmt::If { arms: vec![(Expr::local(&fw.lv.k).ne(Expr::Int(0)), denied)], otherwise: accepted },
        ],
    }
}

fn uncontrollable_pou(fw: &Framework) -> Pou {
    // N_Uncontrollable(ev): it happened; a supervisor that prohibits it keeps its state.
    let mut body = vec![
        Stmt::CallFunction {
            function: fw.fun.prohibited.clone(),
            args: vec![(fw.lv.ev.clone(), Expr::local(&fw.lv.ev))],
            result: Some(Place::local(&fw.lv.k)),
        },
        Stmt::CallFunction {
            function: fw.fun.occur.clone(),
            args: vec![
                (fw.lv.ev.clone(), Expr::local(&fw.lv.ev)),
                (fw.lv.only.clone(), Expr::Int(0)),
                (fw.lv.skip.clone(), Expr::local(&fw.lv.k)),
                (fw.lv.timers.clone(), Expr::Bool(true)),
            ],
            result: Some(Place::local(&fw.lv.moved)),
        },
        Stmt::assign(Place::local(&fw.fun.uncontrollable), Expr::local(&fw.lv.k).eq(Expr::Int(0))),
        Stmt::when(
            Expr::local(&fw.lv.k).ne(Expr::Int(0)),
            vec![
                counter_up(&fw.d("unexpected")),
                Stmt::assign(Place::global(fw.d("last_unexpected_event")), Expr::local(&fw.lv.ev)),
                Stmt::assign(Place::global(fw.d("last_unexpected_sup")), Expr::local(&fw.lv.k)),
            ],
        ),
    ];
    let uncontrollable_flags: BTreeMap<EventId, String> = fw
        .flag_occ
        .iter()
        .filter(|(&e, _)| fw.loaded.project.kind(e) == EventKind::Uncontrollable)
        .map(|(&e, g)| (e, g.clone()))
        .collect();
    body.extend(fw.flag_chain(&uncontrollable_flags, &fw.lv.ev));
    Pou {
        kind: PouKind::Function { returns: Some(Type::Bool) },
        name: fw.fun.uncontrollable.clone(),
        comment: "An uncontrollable event happened: every supervisor takes it, except one that prohibits it \
                  (reported as unexpected). FALSE if one did."
            .into(),
        inputs: vec![Var::new(&fw.lv.ev, Type::Int, "an EV_ constant of an uncontrollable event")],
        outputs: Vec::new(),
        locals: vec![Var::new(&fw.lv.k, Type::Int, ""), Var::new(&fw.lv.moved, Type::Bool, "")],
        body,
    }
}

fn enforced_pou(fw: &Framework) -> Pou {
    // N_Enforced(sup): the event supervisor sup enforces in its current state, or 0.
    let mut body = vec![Stmt::assign(Place::local(&fw.fun.enforced), Expr::Int(0))];
    let mut sup_arms = Vec::new();
    for (k, s) in fw.supervisors.iter().enumerate() {
        let arms: Vec<(Vec<i64>, Vec<Stmt>)> = s
            .states
            .iter()
            .enumerate()
            .filter_map(|(q, st)| {
                st.enforced.map(|f| {
                    (
                        vec![q as i64],
                        vec![
                            Stmt::Comment(format!("state {}", st.label)),
                            Stmt::assign(Place::local(&fw.fun.enforced), Expr::global(fw.ev(f))),
                        ],
                    )
                })
            })
            .collect();
        if !arms.is_empty() {
            sup_arms.push((
                vec![k as i64 + 1],
                vec![Stmt::Case { selector: Expr::global(&fw.sup_state[k]), arms, otherwise: Vec::new() }],
            ));
        }
    }
    if !sup_arms.is_empty() {
        body.push(Stmt::Case { selector: Expr::local(&fw.lv.sup), arms: sup_arms, otherwise: Vec::new() });
    }
    Pou {
        kind: PouKind::Function { returns: Some(Type::Int) },
        name: fw.fun.enforced.clone(),
        comment: "The event (EV_ constant) that supervisor sup enforces in its current state, or 0.".into(),
        inputs: vec![Var::new(&fw.lv.sup, Type::Int, "a SUP_ constant")],
        outputs: Vec::new(),
        locals: Vec::new(),
        body,
    }
}

fn enforce_pou(fw: &Framework, l: &mut Lowering<'_>) -> Pou {
    // N_Enforce(by): supervisor `by` executes the event its state enforces, if any.
    let mut action_arms = Vec::new();
    for (id, f) in fw.fragments.iter().enumerate() {
        let e = EventId(id as u32);
        if fw.loaded.project.kind(e) != EventKind::Enforceable || f.accept.is_empty() {
            continue;
        }
        let at = fragment_span(&fw.loaded.events[id], FragmentAt::Accept);
        if let Some(code) = l.stmts(&f.accept, at) {
            action_arms.push((Expr::local(&fw.lv.f).eq(Expr::global(fw.ev(e))), code));
        }
    }
    let mut also = Vec::new();
    let mut locals = vec![
        Var::new(&fw.lv.f, Type::Int, "the enforced event"),
        Var::new(&fw.lv.p, Type::Int, ""),
        Var::new(&fw.lv.moved, Type::Bool, ""),
    ];
    for (j, s) in fw.supervisors.iter().enumerate() {
        let name = l.name("also_", &(j + 1).to_string(), "");
        locals.push(Var::new(&name, Type::Bool, format!("supervisor {} enforces the same event", s.name)));
        also.push(name);
    }
    let mut enforce = vec![
        Stmt::CallFunction {
            function: fw.fun.prohibited.clone(),
            args: vec![(fw.lv.ev.clone(), Expr::local(&fw.lv.f))],
            result: Some(Place::local(&fw.lv.p)),
        },
        Stmt::when(Expr::local(&fw.lv.p).ne(Expr::Int(0)), vec![counter_up(&fw.d("conflicts"))]),
        Stmt::Comment("the others take it only where they enforce it themselves (6.4.2)".into()),
    ];
    for (j, name) in also.iter().enumerate() {
        enforce.push(Stmt::assign(Place::local(name), Expr::Bool(false)));
        enforce.push(Stmt::when(
            Expr::local(&fw.lv.by).ne(Expr::Int(j as i64 + 1)),
            vec![
                Stmt::CallFunction {
                    function: fw.fun.enforced.clone(),
                    args: vec![(fw.lv.sup.clone(), Expr::Int(j as i64 + 1))],
                    result: Some(Place::local(&fw.lv.p)),
                },
                Stmt::assign(Place::local(name), Expr::local(&fw.lv.p).eq(Expr::local(&fw.lv.f))),
            ],
        ));
    }
    enforce.push(Stmt::CallFunction {
        function: fw.fun.occur.clone(),
        args: vec![
            (fw.lv.ev.clone(), Expr::local(&fw.lv.f)),
            (fw.lv.only.clone(), Expr::local(&fw.lv.by)),
            (fw.lv.skip.clone(), Expr::Int(0)),
            (fw.lv.timers.clone(), Expr::Bool(true)),
        ],
        result: Some(Place::local(&fw.fun.enforce)),
    });
    for (j, name) in also.iter().enumerate() {
        enforce.push(Stmt::when(
            Expr::local(name),
            vec![Stmt::CallFunction {
                function: fw.fun.occur.clone(),
                args: vec![
                    (fw.lv.ev.clone(), Expr::local(&fw.lv.f)),
                    (fw.lv.only.clone(), Expr::Int(j as i64 + 1)),
                    (fw.lv.skip.clone(), Expr::Int(0)),
                    (fw.lv.timers.clone(), Expr::Bool(false)),
                ],
                result: Some(Place::local(&fw.lv.moved)),
            }],
        ));
    }
    enforce.push(counter_up(&fw.d("enforcements")));
    enforce.push(Stmt::assign(Place::global(fw.d("last_enforced_event")), Expr::local(&fw.lv.f)));
    let enforced_flags: BTreeMap<EventId, String> = fw
        .flag_occ
        .iter()
        .filter(|(&e, _)| fw.loaded.project.kind(e) == EventKind::Enforceable)
        .map(|(&e, g)| (e, g.clone()))
        .collect();
    enforce.extend(fw.flag_chain(&enforced_flags, &fw.lv.f));
    if !action_arms.is_empty() {
        enforce.push(Stmt::Comment("the enforced event's code".into()));
        enforce.push(Stmt::If { arms: action_arms, otherwise: Vec::new() });
    }
    Pou {
        kind: PouKind::Function { returns: Some(Type::Bool) },
        name: fw.fun.enforce.clone(),
        comment: "Supervisor `by` executes the event its current state enforces (preemption, 5.5). \
                  TRUE if its state changed, so that a cascade goes on."
            .into(),
        inputs: vec![Var::new(&fw.lv.by, Type::Int, "a SUP_ constant")],
        outputs: Vec::new(),
        locals,
        body: vec![
            Stmt::assign(Place::local(&fw.fun.enforce), Expr::Bool(false)),
            Stmt::CallFunction {
                function: fw.fun.enforced.clone(),
                args: vec![(fw.lv.sup.clone(), Expr::local(&fw.lv.by))],
                result: Some(Place::local(&fw.lv.f)),
            },
            Stmt::when(Expr::local(&fw.lv.f).ne(Expr::Int(0)), enforce),
        ],
    }
}

fn main_pou(fw: &Framework, l: &mut Lowering<'_>) -> Pou {
    // The program: the cycle of 6.3.4.
    let mut main = Vec::new();
    let mut locals = vec![
        Var::new(&fw.lv.controller, Type::Instance(fw.controller.clone()), "the supervised controller"),
        Var::new(&fw.lv.ok, Type::Bool, "an event's answer"),
        Var::new(&fw.lv.go, Type::Bool, "an enforcement cascade goes on"),
    ];
    main.push(Stmt::Comment("1. a new cycle: this cycle's event flags are cleared".into()));
    for g in fw.flag_acc.values().chain(fw.flag_den.values()).chain(fw.flag_occ.values()) {
        main.push(Stmt::assign(Place::global(g), Expr::Bool(false)));
    }
    if !fw.loaded.timers.is_empty() {
        main.push(Stmt::Comment("timers are refreshed; a timer that reaches its time is due".into()));
    }
    for (t, names) in fw.loaded.timers.iter().zip(&fw.timers) {
        locals.push(Var::new(&names.ton, Type::Ton, format!("timer {} ({} ms)", t.name, t.duration_ms)));
        locals.push(Var::new(&names.due, Type::Bool, format!("{} is due this cycle", t.timeout)));
        main.push(Stmt::CallInstance {
            instance: Place::local(&names.ton),
            args: vec![("IN".into(), Expr::global(&names.run)), ("PT".into(), Expr::Time(t.duration_ms))],
        });
        main.push(Stmt::assign(
            Place::local(&names.due),
            Expr::global(&names.run)
                .and(Expr::global(&names.expired).not())
                .and(Expr::read(Place::local(&names.ton).member("Q"))),
        ));
        main.push(Stmt::when(
            Expr::local(&names.due),
            vec![Stmt::assign(Place::global(&names.expired), Expr::Bool(true))],
        ));
    }
    main.push(Stmt::Comment("2. uncontrollable events: due timeouts first, then the detected ones".into()));
    let call_uncontrollable = |e: EventId| Stmt::CallFunction {
        function: fw.fun.uncontrollable.clone(),
        args: vec![(fw.lv.ev.clone(), Expr::global(fw.ev(e)))],
        result: Some(Place::local(&fw.lv.ok)),
    };
    for (t, names) in fw.loaded.timers.iter().zip(&fw.timers) {
        if let Some(e) = fw.loaded.project.event(&t.timeout) {
            main.push(Stmt::when(Expr::local(&names.due), vec![call_uncontrollable(e)]));
        }
    }
    let mut triggers = BTreeMap::new();
    for (id, f) in fw.fragments.iter().enumerate() {
        if let (Some(t), Trigger::Detected { edge, .. }) = (&f.trigger, &fw.loaded.events[id].trigger) {
            let at = fragment_span(&fw.loaded.events[id], FragmentAt::Trigger);
            if let Some(now) = l.expr(t, at) {
                let e = EventId(id as u32);
                let before = Expr::global(&fw.latch[&e]);
                let fires = match edge {
                    EdgeKind::Rising => now.clone().and(before.not()),
                    EdgeKind::Falling => now.clone().not().and(before),
                    EdgeKind::Either => Expr::binary(BinOp::Xor, now.clone(), before),
                    EdgeKind::Cyclic => now.clone(),
                };
                triggers.insert(e, (now, fires));
            }
        }
    }
    for (&e, (_, fires)) in &triggers {
        if fw.loaded.project.kind(e) == EventKind::Uncontrollable {
            main.push(Stmt::when(fires.clone(), vec![call_uncontrollable(e)]));
        }
    }
    main.push(Stmt::Comment("3. outputs that a denial resets are saved".into()));
    for (&k, g) in &fw.saved {
        main.push(Stmt::assign(Place::global(g), Expr::read(Place::Signal(k))));
    }
    main.push(Stmt::Comment(format!(
        "4. the controller runs; its executed events are answered by {} at once",
        fw.fun.execute
    )));
    main.push(Stmt::CallInstance { instance: Place::local(&fw.lv.controller), args: Vec::new() });
    main.push(Stmt::Comment("5. detected controllable events".into()));
    for (&e, (_, fires)) in &triggers {
        if fw.loaded.project.kind(e) == EventKind::Controllable {
            main.push(Stmt::when(
                fires.clone(),
                vec![Stmt::CallFunction {
                    function: fw.fun.execute.clone(),
                    args: vec![(fw.lv.ev.clone(), Expr::global(fw.ev(e)))],
                    result: Some(Place::local(&fw.lv.ok)),
                }],
            ));
        }
    }
    main.push(Stmt::Comment("6. denied detected events without code on denial: their outputs are restored".into()));
    for (id, f) in fw.fragments.iter().enumerate() {
        let e = EventId(id as u32);
        let meta = &fw.loaded.events[id];
        if f.resets.is_empty() || meta.code_on_denial.is_some() || !matches!(meta.trigger, Trigger::Detected { .. }) {
            continue;
        }
        let Some(flag) = fw.flag_den.get(&e) else { continue };
        let mut restore = Vec::new();
        for r in &f.resets {
            if let Some(key) = Lowering::signal_key(&r.kind) {
                let k = l.signal(&key);
                restore.push(Stmt::assign(Place::Signal(k), Expr::global(&fw.saved[&k])));
            }
        }
        main.push(Stmt::when(Expr::global(flag), restore));
    }
    main.push(Stmt::Comment("7. code on acceptance of controllable events".into()));
    for (id, f) in fw.fragments.iter().enumerate() {
        let e = EventId(id as u32);
        let Some(flag) = fw.flag_acc.get(&e) else { continue };
        if f.accept.is_empty() {
            continue;
        }
        if let Some(code) = l.stmts(&f.accept, fragment_span(&fw.loaded.events[id], FragmentAt::Accept)) {
            main.push(Stmt::when(Expr::global(flag), code));
        }
    }
    main.push(Stmt::Comment("8. enforcement: each supervisor executes what its state enforces, in cascades".into()));
    for (k, s) in fw.supervisors.iter().enumerate() {
        let chain = enforcement_chain(s);
        if chain == 0 {
            continue;
        }
        let call = Stmt::CallFunction {
            function: fw.fun.enforce.clone(),
            args: vec![(fw.lv.by.clone(), Expr::Int(k as i64 + 1))],
            result: Some(Place::local(&fw.lv.go)),
        };
        main.push(Stmt::Comment(format!("supervisor {}: enforcements in a row, at most {chain}", s.name)));
        main.push(call.clone());
        for _ in 1..chain {
            main.push(Stmt::when(Expr::local(&fw.lv.go), vec![call.clone()]));
        }
    }
    main.push(Stmt::Comment("9. code on denial".into()));
    for (id, f) in fw.fragments.iter().enumerate() {
        let e = EventId(id as u32);
        let Some(flag) = fw.flag_den.get(&e) else { continue };
        if f.denial.is_empty() {
            continue;
        }
        if let Some(code) = l.stmts(&f.denial, fragment_span(&fw.loaded.events[id], FragmentAt::Denial)) {
            main.push(Stmt::when(Expr::global(flag), code));
        }
    }
    main.push(Stmt::Comment("10. triggers and \\last{} signals are latched for the next cycle".into()));
    for (&e, (now, _)) in &triggers {
        main.push(Stmt::assign(Place::global(&fw.latch[&e]), now.clone()));
    }
    for (&k, g) in &l.last {
        main.push(Stmt::assign(Place::global(g), Expr::read(Place::Signal(k))));
    }
    if !fw.loaded.timers.is_empty() {
        main.push(Stmt::Comment("11. timers started this cycle start now; stopped ones are reset".into()));
    }
    for (t, names) in fw.loaded.timers.iter().zip(&fw.timers) {
        let ton = Place::local(&names.ton);
        let call = |on: bool| Stmt::CallInstance {
            instance: ton.clone(),
            args: vec![("IN".into(), Expr::Bool(on)), ("PT".into(), Expr::Time(t.duration_ms))],
        };
        main.push(Stmt::If {
            arms: vec![
                (
                    Expr::global(&names.restart),
                    vec![call(false), call(true), Stmt::assign(Place::global(&names.restart), Expr::Bool(false))],
                ),
                (Expr::global(&names.run).not(), vec![call(false)]),
            ],
            otherwise: Vec::new(),
        });
    }
    Pou {
        kind: PouKind::Program,
        name: fw.fun.program.clone(),
        comment: format!(
            "The runtime framework (Göbe 2019, 6.3.4): call it from the cyclic task in place of the controller {}.",
            fw.controller
        ),
        inputs: Vec::new(),
        outputs: Vec::new(),
        locals,
        body: main,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn durations() {
        assert_eq!(duration_ms("T#1s500ms"), Some(1500));
        assert_eq!(duration_ms("TIME#2m"), Some(120_000));
        assert_eq!(duration_ms("t#1h_30m"), Some(5_400_000));
        assert_eq!(duration_ms("T#1.5s"), None);
        assert_eq!(duration_ms("T#"), None);
    }

    #[test]
    fn integers() {
        assert_eq!(int_literal("16#FF"), Some(255));
        assert_eq!(int_literal("1_000"), Some(1000));
        assert_eq!(int_literal("2#101"), Some(5));
    }
}
