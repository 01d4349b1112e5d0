//! The supervisors' step functions of the framework: `N_Prohibited`, `N_Occur`, `N_Execute`,
//! `N_Uncontrollable`, `N_Enforced` and `N_Enforce`, over the names every POU refers to.

use super::fragments::{fragment_span, FragmentAt, Fragments, Lowering};
use crate::plc::fragment::BinOp;
use crate::plc::model::unit::{Expr, Place, Pou, PouKind, Stmt, Type, Var};
use crate::sct::model::{EventId, EventKind, Supervisor};
use crate::sct::Loaded;
use std::collections::BTreeMap;

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
pub(super) fn enforcement_chain(s: &Supervisor) -> usize {
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
pub(super) struct Locals {
    pub(super) ev: String,
    pub(super) only: String,
    pub(super) skip: String,
    pub(super) timers: String,
    pub(super) by: String,
    pub(super) sup: String,
    pub(super) f: String,
    pub(super) p: String,
    pub(super) k: String,
    pub(super) moved: String,
    pub(super) ok: String,
    pub(super) go: String,
    pub(super) controller: String,
}

/// Names of a timer's variables.
pub(super) struct TimerNames {
    pub(super) run: String,
    pub(super) restart: String,
    pub(super) expired: String,
    pub(super) ton: String,
    pub(super) due: String,
}

/// Names of the generated functions and the program.
pub(super) struct Functions {
    pub(super) prohibited: String,
    pub(super) occur: String,
    pub(super) execute: String,
    pub(super) uncontrollable: String,
    pub(super) enforced: String,
    pub(super) enforce: String,
    pub(super) program: String,
}

/// Everything the POUs of the framework refer to by name.
pub(super) struct Framework<'a> {
    pub(super) loaded: &'a Loaded,
    pub(super) supervisors: &'a [&'a Supervisor],
    pub(super) fragments: Vec<&'a Fragments>,
    pub(super) lv: Locals,
    pub(super) fun: Functions,
    pub(super) controller: String,
    /// The constant of every event (by id) and every supervisor (by position).
    pub(super) event_const: Vec<String>,
    pub(super) sup_const: Vec<String>,
    /// The global holding every supervisor's state.
    pub(super) sup_state: Vec<String>,
    /// The diagnostic globals, by their base name.
    pub(super) diag: BTreeMap<&'static str, String>,
    pub(super) flag_acc: BTreeMap<EventId, String>,
    pub(super) flag_den: BTreeMap<EventId, String>,
    pub(super) flag_occ: BTreeMap<EventId, String>,
    pub(super) latch: BTreeMap<EventId, String>,
    pub(super) saved: BTreeMap<usize, String>,
    pub(super) timers: Vec<TimerNames>,
}

impl Framework<'_> {
    pub(super) fn ev(&self, e: EventId) -> String {
        self.event_const[e.index()].clone()
    }

    pub(super) fn d(&self, name: &str) -> String {
        self.diag[name].clone()
    }

    /// The occurrence flags of the events of `kind`. (Filled by insertion: a `collect` into a
    /// B-tree instantiates its sort and bulk build for the page's wasm once more.)
    fn occurrence_flags(&self, kind: EventKind) -> BTreeMap<EventId, String> {
        let mut flags = BTreeMap::new();
        for (&e, g) in &self.flag_occ {
            if self.loaded.project.kind(e) == kind {
                flags.insert(e, g.clone());
            }
        }
        flags
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

pub(super) fn prohibited_pou(fw: &Framework) -> Pou {
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

pub(super) fn occur_pou(fw: &Framework) -> Pou {
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

pub(super) fn execute_pou(fw: &Framework) -> Pou {
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

pub(super) fn uncontrollable_pou(fw: &Framework) -> Pou {
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
    body.extend(fw.flag_chain(&fw.occurrence_flags(EventKind::Uncontrollable), &fw.lv.ev));
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

pub(super) fn enforced_pou(fw: &Framework) -> Pou {
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

pub(super) fn enforce_pou(fw: &Framework, l: &mut Lowering<'_>) -> Pou {
    // N_Enforce(by): supervisor `by` executes the event its state enforces, if any.
    let mut action_arms = Vec::new();
    for (id, f) in fw.fragments.iter().enumerate() {
        let e = EventId::new(id);
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
    enforce.extend(fw.flag_chain(&fw.occurrence_flags(EventKind::Enforceable), &fw.lv.f));
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
