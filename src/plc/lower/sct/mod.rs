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

mod fragments;
pub mod framework_sim;
mod functions;
mod program;

use crate::diag::{Diagnostic, Diagnostics};
use crate::plc::model::unit::{Expr, Type, Unit, Var};
use crate::plc::{identifier, source_hash, Namespace};
use crate::sct::model::{EventId, EventKind, Supervisor};
use crate::sct::{Loaded, Trigger};
use fragments::{signal_table, Fragments, Lowering};
use functions::{
    enforce_pou, enforced_pou, execute_pou, occur_pou, prohibited_pou, uncontrollable_pou, Framework, Functions,
    Locals, TimerNames,
};
use program::main_pou;
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
                let meta = &loaded.events[e.index()];
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
        let e = EventId::new(id);
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
        let e = EventId::new(id);
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
