//! Post optimisation (Peter 2005, 6.6, algorithm 11): simplification rules applied until none
//! applies any more.
//!
//! The six rules of the thesis — WAITUNTIL replacement, inlining, reference inlining,
//! unreachable block removal, redundant GOTO removal and redundant IF removal (algorithms 12
//! and 13) — plus one of plcsynth's own, *silent wait removal*: a `WAITUNTIL` on something the
//! PLC cannot observe or need not time (a reaction without an io binding, or a delay) is dropped
//! when what follows only waits for observable plant messages. Such a wait is the state's only exit,
//! so nothing the next block tests can happen before it; the thesis's lamp and gear-checking
//! programs discard these waits the same way ("all clock, delay, and intermediate events are
//! discarded"). Finally, resets of clocks no condition reads are dropped.

use super::{CmdId, Command, Condition, Instruction, Program, NOT_PLACED};
use crate::timed::model::{DependsOn, Game, MessageRole, MsgId};
use std::collections::HashSet;

/// What the optimiser needs to know about the messages.
#[derive(Clone, Debug, Default)]
pub struct Context {
    /// Messages the PLC can read (indexed by message id).
    pub observable: Vec<bool>,
    /// `dependson` declarations: (message, what it depends on).
    pub dependencies: Vec<(MsgId, DependsOn)>,
    /// Messages with at least one declaration; the others may change at any time.
    pub declared: Vec<bool>,
    /// Reactions sent only by unguarded `instant` transitions: the plant takes them before the
    /// controller can act.
    pub urgent: Vec<bool>,
    /// Whether waits on delays may be dropped (before observable waits).
    pub silent_delays: bool,
    /// State-guard messages (4.2.1): sensor levels that may hold at any time, unlike plant
    /// messages, which only the plant's current state can send.
    pub guards: Vec<bool>,
}

impl Context {
    /// Observable messages: those bound in the `io` section, or all when there is none.
    pub fn from_game(game: &Game) -> Context {
        let n = game.messages.len();
        let observable = if game.io.is_empty() {
            vec![true; n]
        } else {
            let mut v = vec![false; n];
            for b in &game.io {
                v[b.message.index()] = true;
            }
            v
        };
        let mut dependencies = Vec::new();
        let mut declared = vec![false; n];
        for d in &game.dependencies {
            declared[d.message.index()] = true;
            for &on in &d.on {
                dependencies.push((d.message, on));
            }
        }
        let mut urgent = vec![true; n];
        let mut sent = vec![false; n];
        for a in &game.components {
            for e in &a.edges {
                if e.kind != crate::timed::model::MessageKind::Synchronised {
                    sent[e.message.index()] = true;
                    // Urgent from the moment its location is entered: instant and unguarded (a
                    // guarded one may be enabled only later, and the controller acts before).
                    urgent[e.message.index()] &=
                        e.instant && e.guard.is_empty() && e.kind == crate::timed::model::MessageKind::Uncontrollable;
                }
            }
        }
        for (u, s) in urgent.iter_mut().zip(&sent) {
            *u &= *s;
        }
        let guards = game.messages.iter().map(|m| m.role == MessageRole::Guard).collect();
        Context { observable, dependencies, declared, urgent, silent_delays: true, guards }
    }

    fn urgent(&self, c: &Condition) -> bool {
        matches!(c, Condition::Message { message } if self.urgent.get((*message).index()).copied().unwrap_or(false))
    }

    fn silent(&self, c: &Condition) -> bool {
        match c {
            Condition::Delay { .. } => self.silent_delays,
            Condition::Message { message } => !self.observable.get((*message).index()).copied().unwrap_or(true),
        }
    }

    /// True if `cond` may change when `event` happens (a request sent, or time passing).
    fn dependent(&self, cond: &Condition, event: DependsOn) -> bool {
        match cond {
            Condition::Delay { .. } => event == DependsOn::Time,
            Condition::Message { message } => {
                if !self.declared.get((*message).index()).copied().unwrap_or(false) {
                    return true; // undeclared: assume it may change at any time
                }
                self.dependencies.iter().any(|&(m, on)| {
                    (m == *message && on == event)
                        || matches!(event, DependsOn::Message(e) if on == DependsOn::Message(*message) && m == e)
                })
            }
        }
    }
}

/// Algorithm 11: applies all rules to a fixpoint.
pub fn optimize(program: &mut Program, cx: &Context) {
    let mut rounds = 0;
    loop {
        rounds += 1;
        drop_unread_resets(program);
        let mut changed = false;
        changed |= waituntil_replacement(program);
        changed |= silent_wait_removal(program, cx);
        changed |= reference_inlining(program);
        changed |= inlining(program);
        changed |= unreachable_removal(program);
        changed |= redundant_goto_removal(program);
        if !changed {
            changed = merge_equivalent(program);
        }
        if !changed {
            changed = redundant_if_removal(program, cx);
        }
        if !changed || rounds > 10_000 {
            break;
        }
    }
    if layout(program) {
        while redundant_goto_removal(program) || reference_inlining(program) || unreachable_removal(program) {}
    }
    drop_unread_resets(program);
}

fn jump_target(c: &Command) -> Option<CmdId> {
    match c.instruction {
        Instruction::If { target, .. } | Instruction::Goto { target } => Some(target),
        _ => None,
    }
}

/// R(P, l) of 6.2 for every position: 1 for the first command or after a non-GOTO command, plus
/// the number of jumps to it.
pub fn reference_counts(program: &Program) -> Vec<u32> {
    let pos = program.positions();
    let cmds = &program.commands;
    let mut r: Vec<u32> = (0..cmds.len())
        .map(|i| u32::from(i == 0 || !matches!(cmds[i - 1].instruction, Instruction::Goto { .. })))
        .collect();
    for c in cmds {
        if let Some(t) = jump_target(c) {
            let p = pos[t.index()];
            if p != NOT_PLACED {
                r[p as usize] += 1;
            }
        }
    }
    r
}

/// 6.6.1: `l0: IF (c) THEN GOTO d; GOTO l0` becomes `l0: WAITUNTIL (c); GOTO d`.
pub fn waituntil_replacement(program: &mut Program) -> bool {
    let mut changed = false;
    let cmds = &mut program.commands;
    for i in 0..cmds.len().saturating_sub(1) {
        if let (Instruction::If { condition, target }, Instruction::Goto { target: back }) =
            (cmds[i].instruction, cmds[i + 1].instruction)
        {
            if back == cmds[i].id && cmds[i + 1].resets == 0 && target != cmds[i].id {
                cmds[i].instruction = Instruction::WaitUntil { condition };
                cmds[i + 1].instruction = Instruction::Goto { target };
                changed = true;
            }
        }
    }
    changed
}

/// 6.6.3: a jump to `GOTO dest` (without resets) jumps to `dest` directly.
pub fn reference_inlining(program: &mut Program) -> bool {
    let pos = program.positions();
    let snapshot = program.commands.clone();
    let mut changed = false;
    for c in &mut program.commands {
        let Some(t) = jump_target(c) else { continue };
        let p = pos[t.index()];
        if p == NOT_PLACED {
            continue;
        }
        let referenced = &snapshot[p as usize];
        if let Instruction::Goto { target: dest } = referenced.instruction {
            if referenced.resets == 0 && dest != t && dest != c.id {
                match &mut c.instruction {
                    Instruction::If { target, .. } | Instruction::Goto { target } => *target = dest,
                    _ => {}
                }
                changed = true;
            }
        }
    }
    changed
}

/// 6.6.2: `GOTO l2`, where the block at `l2` is one non-IF command and a `GOTO dest` and nothing
/// else refers to `l2`, becomes a copy of that block. Every such GOTO is rewritten in one pass,
/// except where two rewrites touch the same commands (the fixpoint loop comes back for those):
/// one site per round made the optimiser quadratic on large programs.
pub fn inlining(program: &mut Program) -> bool {
    let pos = program.positions();
    let r = reference_counts(program);
    let n = program.commands.len();
    // Commands read or written by a rewrite of this pass.
    let mut touched = vec![false; n];
    let mut sites: Vec<(usize, Command, CmdId)> = Vec::new();
    for i in 0..n {
        let Instruction::Goto { target: l2 } = program.commands[i].instruction else { continue };
        if program.commands[i].resets != 0 {
            continue;
        }
        let j = pos[l2.index()];
        if j == NOT_PLACED || j as usize + 1 >= n || r[j as usize] != 1 || j as usize == i {
            continue;
        }
        let j = j as usize;
        let (s, next) = (program.commands[j], program.commands[j + 1]);
        let Instruction::Goto { target: dest } = next.instruction else { continue };
        if next.resets != 0 || dest == l2 || matches!(s.instruction, Instruction::If { .. } | Instruction::Goto { .. })
        {
            continue;
        }
        if touched[i] || touched[j] || touched[j + 1] {
            continue;
        }
        touched[i] = true;
        touched[j] = true;
        touched[j + 1] = true;
        sites.push((i, s, dest));
    }
    if sites.is_empty() {
        return false;
    }
    let mut out = Vec::with_capacity(n + sites.len());
    let mut next_site = sites.iter().peekable();
    for (i, c) in program.commands.iter().enumerate() {
        match next_site.peek() {
            Some(&&(at, s, dest)) if at == i => {
                next_site.next();
                out.push(Command { id: c.id, instruction: s.instruction, resets: s.resets });
                out.push(Command { id: CmdId::NONE, instruction: Instruction::Goto { target: dest }, resets: 0 });
            }
            _ => out.push(*c),
        }
    }
    for c in out.iter_mut().filter(|c| c.id == CmdId::NONE) {
        c.id = program.fresh_id();
    }
    program.commands = out;
    true
}

/// 6.6.4: commands with reference count zero can never run.
pub fn unreachable_removal(program: &mut Program) -> bool {
    let r = reference_counts(program);
    let before = program.commands.len();
    let mut k = 0;
    program.commands.retain(|_| {
        let keep = r[k] > 0;
        k += 1;
        keep
    });
    program.commands.len() != before
}

/// 6.6.5: `GOTO l` right before `l` is removed; jumps to it go to `l`. All such GOTOs go in one
/// pass (a run of them collapses onto the command after the run).
pub fn redundant_goto_removal(program: &mut Program) -> bool {
    let cmds = &program.commands;
    let n = cmds.len();
    let mut removed = vec![false; n];
    for i in 0..n.saturating_sub(1) {
        if let Instruction::Goto { target } = cmds[i].instruction {
            removed[i] = target == cmds[i + 1].id && cmds[i].resets == 0;
        }
    }
    if !removed.contains(&true) {
        return false;
    }
    remove_falling_through(program, &removed);
    true
}

fn retarget(program: &mut Program, from: CmdId, to: CmdId) {
    for c in &mut program.commands {
        match &mut c.instruction {
            Instruction::If { target, .. } | Instruction::Goto { target } if *target == from => *target = to,
            _ => {}
        }
    }
}

/// Removes the marked commands, none of them the last: control that reached one falls through
/// to the first kept command after it, so jumps to it go there.
fn remove_falling_through(program: &mut Program, removed: &[bool]) {
    let cmds = &program.commands;
    let mut redirect: hashbrown::HashMap<CmdId, CmdId> = hashbrown::HashMap::new();
    let mut landing = None;
    for i in (0..cmds.len()).rev() {
        if removed[i] {
            if let Some(to) = landing {
                redirect.insert(cmds[i].id, to);
            }
        } else {
            landing = Some(cmds[i].id);
        }
    }
    let mut k = 0;
    program.commands.retain(|_| {
        let keep = !removed[k];
        k += 1;
        keep
    });
    for c in &mut program.commands {
        if let Instruction::If { target, .. } | Instruction::Goto { target } = &mut c.instruction {
            if let Some(&to) = redirect.get(target) {
                *target = to;
            }
        }
    }
}

/// plcsynth: `WAITUNTIL (silent)` is dropped when the commands it falls through to (following
/// GOTOs) start with a wait on observable plant messages only: a `WAITUNTIL (m)` or a wait
/// block of `IF (m)` commands that loops back. Not before a state-guard message: a sensor may
/// report at any time, so the wait before it is needed.
pub fn silent_wait_removal(program: &mut Program, cx: &Context) -> bool {
    // The plant takes an urgent reaction before the controller can do anything else: such a
    // wait goes wherever it stands, so all of them go in one pass (one per round made the
    // optimiser quadratic on programs with many instant reactions).
    let cmds = &program.commands;
    let urgent: Vec<bool> = (0..cmds.len())
        .map(|i| {
            matches!(cmds[i].instruction, Instruction::WaitUntil { condition } if cx.urgent(&condition))
                && cmds[i].resets == 0
                && i + 1 < cmds.len()
        })
        .collect();
    if urgent.contains(&true) {
        remove_falling_through(program, &urgent);
        return true;
    }
    let pos = program.positions();
    let cmds = &program.commands;
    for i in 0..cmds.len() {
        let Instruction::WaitUntil { condition } = cmds[i].instruction else { continue };
        if cmds[i].resets != 0 || i + 1 >= cmds.len() {
            continue;
        }
        if !cx.silent(&condition) {
            continue;
        }
        // Follow GOTOs from the next command.
        let mut j = i + 1;
        let mut hops = 0;
        while let Instruction::Goto { target } = cmds[j].instruction {
            let p = pos[target.index()];
            hops += 1;
            if p == NOT_PLACED || hops > cmds.len() {
                break;
            }
            j = p as usize;
        }
        if j == i || !waits_for_observable(program, j, cx) {
            continue;
        }
        let id = cmds[i].id;
        program.commands.remove(i);
        let next = program.commands[i].id;
        retarget(program, id, next);
        return true;
    }
    false
}

fn waits_for_observable(program: &Program, j: usize, cx: &Context) -> bool {
    let cmds = &program.commands;
    // A guard may already hold before the silent wait ends: waiting for it proves nothing.
    let observable = |c: &Condition| {
        matches!(c, Condition::Message { message } if !cx.guards.get((*message).index()).copied().unwrap_or(false))
            && !cx.silent(c)
    };
    match cmds[j].instruction {
        Instruction::WaitUntil { condition } => observable(&condition),
        Instruction::If { .. } => {
            let head = cmds[j].id;
            let mut k = j;
            while let Some(c) = cmds.get(k) {
                match c.instruction {
                    Instruction::If { condition, .. } if observable(&condition) => k += 1,
                    Instruction::Goto { target } => return target == head,
                    _ => return false,
                }
            }
            false
        }
        _ => false,
    }
}

/// 6.6.6, algorithms 12 and 13: IF commands whose outcome is known from earlier tests (and the
/// declared dependencies) are removed or become GOTOs.
pub fn redundant_if_removal(program: &mut Program, cx: &Context) -> bool {
    if program.is_empty() {
        return false;
    }
    let pos = program.positions();
    let r = reference_counts(program);
    let mut edits = Edits::default();
    let mut vis = HashSet::new();
    remove_if(program, &pos, &r, cx, 0, &mut vis, Vec::new(), Vec::new(), &mut edits, 0);
    if edits.removed.is_empty() && edits.to_goto.is_empty() {
        return false;
    }
    for c in &mut program.commands {
        if edits.to_goto.contains(&c.id) {
            if let Instruction::If { target, .. } = c.instruction {
                c.instruction = Instruction::Goto { target };
            }
        }
    }
    let removed = edits.removed;
    // Jumps to a removed command go to the command after it.
    let after: Vec<(CmdId, CmdId)> = program
        .commands
        .iter()
        .enumerate()
        .filter(|(_, c)| removed.contains(&c.id))
        .filter_map(|(i, c)| program.commands[i + 1..].iter().find(|n| !removed.contains(&n.id)).map(|n| (c.id, n.id)))
        .collect();
    program.commands.retain(|c| !removed.contains(&c.id));
    for (from, to) in after {
        retarget(program, from, to);
    }
    true
}

#[derive(Default)]
struct Edits {
    removed: HashSet<CmdId>,
    to_goto: HashSet<CmdId>,
}

/// The commands of the block entered at position `p`: up to and including the first GOTO.
fn block(program: &Program, p: usize) -> std::ops::Range<usize> {
    let end = program.commands[p..]
        .iter()
        .position(|c| matches!(c.instruction, Instruction::Goto { .. }))
        .map_or(program.len(), |k| p + k + 1);
    p..end
}

/// W of 6.6.6: only IF commands and a final GOTO back to the block's first command.
fn is_wait_block(program: &Program, range: &std::ops::Range<usize>) -> bool {
    let cmds = &program.commands[range.clone()];
    match cmds.last().map(|c| c.instruction) {
        Some(Instruction::Goto { target }) => {
            target == cmds[0].id
                && cmds[..cmds.len() - 1].iter().all(|c| matches!(c.instruction, Instruction::If { .. }))
        }
        _ => false,
    }
}

#[allow(clippy::too_many_arguments)]
fn remove_if(
    program: &Program,
    pos: &[u32],
    r: &[u32],
    cx: &Context,
    start: usize,
    vis: &mut HashSet<CmdId>,
    mut t: Vec<Condition>,
    mut f: Vec<Condition>,
    edits: &mut Edits,
    depth: usize,
) {
    if start >= program.len() || vis.contains(&program.commands[start].id) || depth > 4096 {
        return;
    }
    let range = block(program, start);
    let forget = |set: &mut Vec<Condition>, event: DependsOn| set.retain(|c| !cx.dependent(c, event));
    if is_wait_block(program, &range) {
        if r[start] > 2 {
            t.clear();
            f.clear();
        } else {
            forget(&mut t, DependsOn::Time);
            forget(&mut f, DependsOn::Time);
        }
    } else if r[start] > 1 {
        t.clear();
        f.clear();
    }
    for k in range {
        let c = program.commands[k];
        // A command that jumps also reach starts a block of its own: what is known on the way
        // in through this block need not hold on the other ways in (algorithm 13 assumes one
        // entry per block, which the other rules do not keep).
        if k != start && r[k] > 1 {
            remove_if(program, pos, r, cx, k, vis, t, f, edits, depth + 1);
            return;
        }
        vis.insert(c.id);
        match c.instruction {
            Instruction::Goto { target } => {
                let p = pos[target.index()];
                if p != NOT_PLACED {
                    remove_if(program, pos, r, cx, p as usize, vis, t, f, edits, depth + 1);
                }
                return;
            }
            Instruction::Do { request } => {
                forget(&mut t, DependsOn::Message(request));
                forget(&mut f, DependsOn::Message(request));
            }
            Instruction::WaitUntil { condition } => {
                forget(&mut t, DependsOn::Time);
                forget(&mut f, DependsOn::Time);
                if t.contains(&condition) {
                    edits.removed.insert(c.id);
                }
            }
            Instruction::If { condition, target } => {
                if f.contains(&condition) {
                    edits.removed.insert(c.id);
                } else if t.contains(&condition) {
                    edits.to_goto.insert(c.id);
                } else {
                    let p = pos[target.index()];
                    if p != NOT_PLACED {
                        let mut t2 = t.clone();
                        t2.push(condition);
                        remove_if(program, pos, r, cx, p as usize, vis, t2, f.clone(), edits, depth + 1);
                    }
                    f.push(condition);
                }
            }
        }
    }
}

/// Bisimulation classes of a program's control flow, with GOTOs (without resets) transparent.
/// `class[i]` for positions `0..n`, plus two virtual positions: `n` (past the end) and `n + 1`
/// (a cycle of GOTOs). `resolve(i)` is where execution really continues from position `i`.
pub struct Classes {
    pub class: Vec<usize>,
    resolved: Vec<usize>,
}

impl Classes {
    pub fn resolve(&self, i: usize) -> usize {
        self.resolved[i]
    }
}

pub fn bisimulation(program: &Program) -> Classes {
    let n = program.len();
    let pos = program.positions();
    let cmds = &program.commands;
    let (end, looping) = (n, n + 1);
    let at = |t: CmdId| pos.get(t.index()).map_or(end, |&p| if p == NOT_PLACED { end } else { p as usize });
    // The target of a GOTO without resets: such a GOTO is not a step of its own.
    let goto_target = |i: usize| match cmds.get(i) {
        Some(Command { instruction: Instruction::Goto { target }, resets: 0, .. }) if i < n => Some(*target),
        _ => None,
    };
    let transparent = |i: usize| goto_target(i).is_some();
    let mut resolved: Vec<usize> = (0..n + 2).collect();
    for (i, r) in resolved.iter_mut().enumerate().take(n) {
        let mut j = i;
        let mut hops = 0;
        while let Some(target) = goto_target(j) {
            j = at(target);
            hops += 1;
            if hops > n {
                j = looping;
                break;
            }
        }
        *r = j;
    }
    // Successors as (when false, when true). `WAITUNTIL (c)` is the IF that loops on itself
    // while `c` is false (6.1), so both compare alike.
    let succ = |i: usize| -> (usize, usize) {
        match cmds[i].instruction {
            Instruction::Do { .. } => (resolved[i + 1], end),
            Instruction::WaitUntil { .. } => (i, resolved[i + 1]),
            Instruction::If { target, .. } => (resolved[i + 1], resolved[at(target)]),
            Instruction::Goto { target } => (resolved[at(target)], looping),
        }
    };
    let label = |i: usize| -> (u8, Option<Condition>, Option<u32>, u64) {
        let c = &cmds[i];
        match c.instruction {
            Instruction::Do { request } => (0, None, Some(request.raw()), c.resets),
            Instruction::If { condition, .. } | Instruction::WaitUntil { condition } => {
                (1, Some(condition), None, c.resets)
            }
            Instruction::Goto { .. } => (2, None, None, c.resets),
        }
    };
    let members: Vec<usize> = (0..n).filter(|&i| !transparent(i)).collect();
    let mut class: Vec<usize> = vec![usize::MAX; n + 2];
    class[end] = 0;
    class[looping] = 1;
    let mut ids = std::collections::HashMap::new();
    for &i in &members {
        let len = ids.len() + 2;
        class[i] = *ids.entry(label(i)).or_insert(len);
    }
    let mut count = ids.len() + 2;
    loop {
        let mut ids = std::collections::HashMap::new();
        let mut next = class.clone();
        for &i in &members {
            let (a, b) = succ(i);
            let len = ids.len() + 2;
            next[i] = *ids.entry((class[i], class[a], class[b])).or_insert(len);
        }
        class = next;
        if ids.len() + 2 == count {
            break;
        }
        count = ids.len() + 2;
    }
    for i in 0..n {
        if transparent(i) {
            class[i] = class[resolved[i]];
        }
    }
    Classes { class, resolved }
}

/// True if the two programs behave alike from their first commands: the same tests, actions and
/// timer resets in the same control flow, whatever the inputs.
pub fn equivalent(a: &Program, b: &Program) -> bool {
    let mut both = a.clone();
    let offset = a.next_id;
    for c in &b.commands {
        let mut c = *c;
        let shift = |id: CmdId| CmdId::from_raw(id.raw() + offset.raw());
        c.id = shift(c.id);
        match &mut c.instruction {
            Instruction::If { target, .. } | Instruction::Goto { target } => *target = shift(*target),
            _ => {}
        }
        both.push_with_id(c.id, c.instruction, c.resets);
    }
    // Execution of `a` must not run into `b`: end `a` explicitly with a jump nowhere.
    let stop = both.fresh_id();
    both.commands
        .insert(a.len(), Command { id: stop, instruction: Instruction::Goto { target: CmdId::NONE }, resets: 0 });
    let classes = bisimulation(&both);
    let (sa, sb) = (classes.resolve(0), classes.resolve(a.len() + 1));
    let virtual_end = |i: usize| i >= both.len();
    if virtual_end(sa) || virtual_end(sb) {
        return sa == sb || (virtual_end(sa) && virtual_end(sb));
    }
    classes.class[sa] == classes.class[sb]
}

/// plcsynth: folds program points that behave alike (the coarsest bisimulation of the control
/// flow, see [`bisimulation`]). Jumps go to the first command of their target's class, and a
/// fall-through into a folded copy becomes a `GOTO`; the copies become unreachable and the
/// other rules remove them.
pub fn merge_equivalent(program: &mut Program) -> bool {
    let n = program.len();
    if n == 0 {
        return false;
    }
    let classes = bisimulation(program);
    let pos = program.positions();
    let cmds = &program.commands;
    let transparent = |i: usize| matches!(cmds[i].instruction, Instruction::Goto { .. }) && cmds[i].resets == 0;
    let mut first = std::collections::HashMap::new();
    for i in (0..n).filter(|&i| !transparent(i)) {
        first.entry(classes.class[i]).or_insert(i);
    }
    let rep = |i: usize| if !transparent(i) { first[&classes.class[i]] } else { i };
    if (0..n).all(|i| rep(i) == i) {
        return false;
    }
    let redirect = |t: CmdId| -> CmdId {
        let p = pos.get(t.index()).copied().unwrap_or(NOT_PLACED);
        if p == NOT_PLACED {
            return t;
        }
        let r = classes.resolve(p as usize);
        if r < n {
            cmds[rep(r)].id
        } else {
            t
        }
    };
    let mut out = Vec::with_capacity(n);
    let mut extra = Vec::new();
    for i in 0..n {
        if !transparent(i) && rep(i) != i {
            continue;
        }
        let mut c = cmds[i];
        match &mut c.instruction {
            Instruction::If { target, .. } | Instruction::Goto { target } => *target = redirect(*target),
            _ => {}
        }
        out.push(c);
        let falls = !matches!(c.instruction, Instruction::Goto { .. });
        if falls && i + 1 < n && !transparent(i + 1) && rep(i + 1) != i + 1 {
            extra.push((out.len(), cmds[rep(i + 1)].id));
        }
    }
    for (k, (at_index, target)) in extra.into_iter().enumerate() {
        let id = program.fresh_id();
        out.insert(at_index + k, Command { id, instruction: Instruction::Goto { target }, resets: 0 });
    }
    program.commands = out;
    true
}

/// Places blocks so that a block ending in `GOTO l` is followed by the block at `l` where that
/// block is only entered by jumps (trace layout); the redundant GOTOs then disappear.
pub fn layout(program: &mut Program) -> bool {
    let n = program.len();
    if n == 0 || !matches!(program.commands[n - 1].instruction, Instruction::Goto { .. }) {
        return false; // a final segment that falls off the end must stay last
    }
    let pos = program.positions();
    let cmds = &program.commands;
    // Segments: maximal runs that end with a GOTO (or at the end of the program).
    let mut starts = vec![0usize];
    starts.extend(
        cmds[..n - 1]
            .iter()
            .enumerate()
            .filter(|(_, c)| matches!(c.instruction, Instruction::Goto { .. }))
            .map(|(i, _)| i + 1),
    );
    let segment_of_start: std::collections::HashMap<usize, usize> =
        starts.iter().enumerate().map(|(k, &s)| (s, k)).collect();
    let seg_end = |k: usize| starts.get(k + 1).copied().unwrap_or(n);
    let mut placed = vec![false; starts.len()];
    let mut order = Vec::with_capacity(starts.len());
    let mut current = 0usize;
    loop {
        placed[current] = true;
        order.push(current);
        let last = &cmds[seg_end(current) - 1];
        let chained = match last.instruction {
            Instruction::Goto { target } => {
                let p = pos.get(target.index()).copied().unwrap_or(NOT_PLACED);
                (p != NOT_PLACED)
                    .then(|| segment_of_start.get(&(p as usize)).copied())
                    .flatten()
                    .filter(|&k| !placed[k])
            }
            _ => None,
        };
        match chained.or_else(|| placed.iter().position(|p| !p)) {
            Some(k) => current = k,
            None => break,
        }
    }
    if order.iter().enumerate().all(|(i, &k)| i == k) {
        return false;
    }
    let mut out = Vec::with_capacity(n);
    for k in order {
        out.extend_from_slice(&cmds[starts[k]..seg_end(k)]);
    }
    program.commands = out;
    true
}

/// Resets of clocks that no delay condition reads are dropped.
pub fn drop_unread_resets(program: &mut Program) {
    let mut read = 0u64;
    for c in &program.commands {
        if let Instruction::If { condition: Condition::Delay { clock, .. }, .. }
        | Instruction::WaitUntil { condition: Condition::Delay { clock, .. } } = c.instruction
        {
            read |= 1 << clock.index();
        }
    }
    for c in &mut program.commands {
        c.resets &= read;
    }
}
