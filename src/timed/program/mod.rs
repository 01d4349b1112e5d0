//! Intermediate controller programs (Peter 2005, chapter 6): the language, its generation from a
//! winning strategy and its optimisation.
//!
//! A program is a list of commands `DO (request)`, `IF (condition) THEN GOTO l`, `GOTO l` and
//! `WAITUNTIL (condition)`, each optionally resetting clocks (PLC timers). Conditions are input
//! messages or delay conditions on clocks. Commands are kept in execution order; jumps name the
//! target command by a stable id, so inserting and removing commands never renumbers jumps
//! (the thesis uses a dense label set for the same reason).
//!
//! - [`select`]: request selection (algorithms 8 and 9);
//! - [`generate`]: intermediate code generation (algorithm 10);
//! - [`optimize`]: the post optimisations of 6.6 to a fixpoint (algorithms 11–13).

pub mod generate;
pub mod optimize;
pub mod scan;
pub mod select;
pub mod simulate;

use crate::id::id_type;
use crate::timed::model::{ClockId, Game, Interval, MsgId};
use serde::Serialize;

id_type! {
    /// Stable identity of a command (a number in the JSON views).
    #[derive(Default, Serialize)]
    #[serde(transparent)]
    pub struct CmdId;
}

impl CmdId {
    /// No command: a jump to it leaves the program (as a jump past the last command does), and
    /// a command built with it gets its id later. [`Program::fresh_id`] never gives it out.
    pub const NONE: CmdId = CmdId::from_raw(u32::MAX);
}

/// The position [`Program::positions`] gives an id that no command of the program has.
pub const NOT_PLACED: u32 = u32::MAX;

/// A condition the controller tests.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize)]
#[serde(tag = "kind", rename_all = "lowercase")]
pub enum Condition {
    /// The input message has occurred.
    Message { message: MsgId },
    /// The timer of `clock` lies in `interval` (time since its last reset).
    Delay { clock: ClockId, interval: Interval },
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(tag = "op", rename_all = "lowercase")]
pub enum Instruction {
    Do { request: MsgId },
    If { condition: Condition, target: CmdId },
    Goto { target: CmdId },
    WaitUntil { condition: Condition },
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub struct Command {
    pub id: CmdId,
    pub instruction: Instruction,
    /// Clocks (timers) reset when the command takes effect, as a bit set over clock ids.
    pub resets: u64,
}

/// A controller program; execution starts at the first command.
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize)]
pub struct Program {
    pub commands: Vec<Command>,
    next_id: CmdId,
}

impl Program {
    pub fn new() -> Program {
        Program::default()
    }

    /// Appends a command and returns its id.
    pub fn push(&mut self, instruction: Instruction, resets: u64) -> CmdId {
        let id = self.fresh_id();
        self.commands.push(Command { id, instruction, resets });
        id
    }

    /// A new id not used by any command yet (for commands built before being placed).
    pub fn fresh_id(&mut self) -> CmdId {
        let id = self.next_id;
        self.next_id = CmdId::from_raw(id.raw() + 1);
        id
    }

    /// Appends a command with an id obtained from [`Program::fresh_id`].
    pub fn push_with_id(&mut self, id: CmdId, instruction: Instruction, resets: u64) {
        self.next_id = self.next_id.max(CmdId::from_raw(id.raw() + 1));
        self.commands.push(Command { id, instruction, resets });
    }

    pub fn len(&self) -> usize {
        self.commands.len()
    }

    pub fn is_empty(&self) -> bool {
        self.commands.is_empty()
    }

    /// Position of every command id ([`NOT_PLACED`] for ids not in the program).
    pub fn positions(&self) -> Vec<u32> {
        let mut pos = vec![NOT_PLACED; self.next_id.index()];
        for (i, c) in self.commands.iter().enumerate() {
            pos[c.id.index()] = i as u32;
        }
        pos
    }

    /// Each command in the thesis's notation without label and `;`, jump targets numbered by
    /// position: `WAITUNTIL (press)`, `IF (c0_is_blue) THEN GOTO 26`,
    /// `DO (x) AND RESET CLOCKS {c}`. Back ends print it beside the code of the command.
    pub fn command_texts(&self, game: &Game) -> Vec<String> {
        let pos = self.positions();
        self.commands
            .iter()
            .map(|c| {
                let text = match c.instruction {
                    Instruction::Do { request } => format!("DO ({})", game.messages[request.index()].name),
                    Instruction::If { condition, target } => {
                        format!("IF ({}) THEN GOTO {}", condition_text(game, &condition), pos[target.index()])
                    }
                    Instruction::Goto { target } => format!("GOTO {}", pos[target.index()]),
                    Instruction::WaitUntil { condition } => {
                        format!("WAITUNTIL ({})", condition_text(game, &condition))
                    }
                };
                if c.resets == 0 {
                    return text;
                }
                let names: Vec<&str> =
                    (1..64).filter(|b| c.resets >> b & 1 == 1).map(|b| game.clocks[b as usize].name.as_str()).collect();
                format!("{text} AND RESET CLOCKS {{{}}}", names.join(", "))
            })
            .collect()
    }

    /// The program in the thesis's notation, labels renumbered 0, 1, 2, ….
    pub fn render(&self, game: &Game) -> String {
        let width = self.commands.len().saturating_sub(1).to_string().len();
        let mut out = String::new();
        for (i, text) in self.command_texts(game).iter().enumerate() {
            out.push_str(&format!("{i:>width$} : {text};\n"));
        }
        out
    }
}

/// `reached_up`, or a delay `{vertical.moving} WAIT 2` (the timer has reached 2), `WAIT >2`
/// (passed 2).
pub fn condition_text(game: &Game, condition: &Condition) -> String {
    match condition {
        Condition::Message { message } => game.messages[(*message).index()].name.clone(),
        Condition::Delay { clock, interval } => {
            let name = &game.clocks[(*clock).index()].name;
            if interval.lower_closed {
                format!("{{{name}}} WAIT {}", interval.lower)
            } else {
                format!("{{{name}}} WAIT >{}", interval.lower)
            }
        }
    }
}

/// The optimised controller program of a solved game, or `None` if no controller exists.
pub fn controller(game: &Game, synthesis: &crate::timed::Synthesis) -> Option<Program> {
    let space = &synthesis.solution.space;
    if !synthesis.solution.is_realizable() {
        return None;
    }
    let strategy = select::select(game, space);
    let mut program = generate::generate(game, &synthesis.split, space, &strategy).program;
    optimize::optimize(&mut program, &optimize::Context::from_game(game));
    Some(program)
}

/// Reads a program in the thesis's notation (`3 : WAITUNTIL (reached_up);`,
/// `11 : IF (c0_is_blue) THEN GOTO 26;`, `DO (x) AND RESET CLOCKS {c}`), as printed by
/// [`Program::render`]. Labels may be any numbers; `THEN 10` is accepted for `THEN GOTO 10`.
/// Message and clock names are resolved by the given functions. Used to state expected programs.
pub fn parse_listing(
    text: &str,
    message: &dyn Fn(&str) -> Option<MsgId>,
    clock: &dyn Fn(&str) -> Option<ClockId>,
) -> Result<Program, String> {
    let mut lines = Vec::new();
    for raw in text.split(';') {
        let line = raw.trim();
        if line.is_empty() {
            continue;
        }
        let (label, rest) = line.split_once(':').ok_or_else(|| format!("missing label in `{line}`"))?;
        lines.push((label.trim().to_string(), rest.trim().to_string()));
    }
    let mut program = Program::new();
    let ids: std::collections::HashMap<String, CmdId> =
        lines.iter().map(|(l, _)| (l.clone(), program.fresh_id())).collect();
    let target = |l: &str| ids.get(l.trim()).copied().ok_or_else(|| format!("unknown label `{}`", l.trim()));
    let condition = |c: &str| -> Result<Condition, String> {
        let c = c.trim();
        if let Some(rest) = c.strip_prefix('{') {
            let (name, wait) = rest.split_once('}').ok_or("unclosed clock list")?;
            let wait = wait.trim().strip_prefix("WAIT").ok_or("expected WAIT")?.trim();
            let (open, value) = match wait.strip_prefix('>') {
                Some(v) => (true, v),
                None => (false, wait),
            };
            let value: u32 = value.trim().parse().map_err(|_| format!("bad delay `{wait}`"))?;
            let clock = clock(name.trim()).ok_or_else(|| format!("unknown clock `{name}`"))?;
            let interval = Interval {
                lower: value,
                lower_closed: !open,
                upper: None,
                upper_closed: false,
                span: Default::default(),
            };
            return Ok(Condition::Delay { clock, interval });
        }
        message(c).map(|m| Condition::Message { message: m }).ok_or_else(|| format!("unknown message `{c}`"))
    };
    let inner = |s: &str| -> Result<String, String> {
        let open = s.find('(').ok_or_else(|| format!("expected `(` in `{s}`"))?;
        let close = s.rfind(')').ok_or_else(|| format!("expected `)` in `{s}`"))?;
        Ok(s[open + 1..close].to_string())
    };
    for (label, rest) in &lines {
        let (body, resets) = match rest.split_once(" AND RESET CLOCKS ") {
            Some((b, r)) => {
                let names = r.trim().trim_start_matches('{').trim_end_matches('}');
                let mut bits = 0u64;
                for n in names.split(',') {
                    bits |= 1 << clock(n.trim()).ok_or_else(|| format!("unknown clock `{n}`"))?.index();
                }
                (b.trim(), bits)
            }
            None => (rest.as_str(), 0),
        };
        let instruction = if let Some(r) = body.strip_prefix("DO") {
            let name = inner(r)?;
            Instruction::Do { request: message(name.trim()).ok_or_else(|| format!("unknown message `{name}`"))? }
        } else if let Some(r) = body.strip_prefix("WAITUNTIL") {
            Instruction::WaitUntil { condition: condition(&inner(r)?)? }
        } else if let Some(r) = body.strip_prefix("GOTO") {
            Instruction::Goto { target: target(r)? }
        } else if let Some(r) = body.strip_prefix("IF") {
            let (cond, then) = r.split_once("THEN").ok_or("expected THEN")?;
            let then = then.trim();
            let l = then.strip_prefix("GOTO").unwrap_or(then);
            Instruction::If { condition: condition(&inner(cond)?)?, target: target(l)? }
        } else {
            return Err(format!("unknown instruction `{body}`"));
        };
        program.push_with_id(ids[label], instruction, resets);
    }
    Ok(program)
}
