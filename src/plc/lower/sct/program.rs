//! The framework's program `N_Main`, which the PLC task calls instead of the controller: the
//! cycle of Göbe 2019, 6.3.4 (inputs latched, uncontrollable events detected, the controller run
//! with its executed events checked, preemption, the timers).

use super::fragments::{fragment_span, FragmentAt, Lowering};
use super::functions::{enforcement_chain, Framework};
use crate::plc::fragment::BinOp;
use crate::plc::model::unit::{Expr, Place, Pou, PouKind, Stmt, Type, Var};
use crate::sct::model::{EventId, EventKind};
use crate::sct::{EdgeKind, Trigger};
use std::collections::BTreeMap;

pub(super) fn main_pou(fw: &Framework, l: &mut Lowering<'_>) -> Pou {
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
                let e = EventId::new(id);
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
        let e = EventId::new(id);
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
        let e = EventId::new(id);
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
        let e = EventId::new(id);
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
