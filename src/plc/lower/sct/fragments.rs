//! The events' code: the fragments of the specification (triggers, resets, code on accept and
//! on denial) scanned for the signals they use and translated into the unit's expressions and
//! statements, the generated names (unique, at most 24 characters), and the signal table.

use crate::diag::{Diagnostics, Span};
use crate::plc::fragment::{self, BinOp, ExprKind, UnOp};
use crate::plc::model::unit::{Expr, Place, Signal, SignalKind, Stmt, Type};
use crate::plc::{identifier, Namespace};
use crate::sct::model::EventKind;
use crate::sct::EventMeta;
use std::collections::BTreeMap;

/// Where a fragment of an event is written, to locate what cannot be lowered.
#[derive(Clone, Copy)]
pub(super) enum FragmentAt {
    Trigger,
    Accept,
    Denial,
}

pub(super) fn fragment_span(meta: &EventMeta, at: FragmentAt) -> Span {
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
pub(super) struct SignalUse {
    pub(super) written: bool,
    pub(super) read_by_uncontrollable: bool,
    pub(super) read_by_controllable: bool,
    pub(super) int: bool,
    pub(super) memory: bool,
    /// Events whose fragments mention it.
    pub(super) events: Vec<String>,
}

pub(super) struct Lowering<'a> {
    pub(super) names: Namespace,
    /// Signal key (symbol, or address without `%`) → index in `signals`.
    pub(super) signal_index: BTreeMap<String, usize>,
    pub(super) signals: Vec<(String, SignalUse)>,
    /// Signals read through `\last{}`: signal index → global holding last cycle's value.
    pub(super) last: BTreeMap<usize, String>,
    pub(super) diags: Diagnostics<'a>,
    /// The type of every signal, once known (see [`signal_table`]).
    pub(super) types: Vec<Type>,
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
pub(super) fn duration_ms(text: &str) -> Option<u64> {
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
    pub(super) fn name(&mut self, prefix: &str, qualified: &str, suffix: &str) -> String {
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
    pub(super) fn signal(&mut self, key: &str) -> usize {
        if let Some(&k) = self.signal_index.get(key) {
            return k;
        }
        let k = self.signals.len();
        self.signal_index.insert(key.to_string(), k);
        self.signals.push((key.to_string(), SignalUse::default()));
        k
    }

    pub(super) fn signal_key(kind: &ExprKind) -> Option<String> {
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
    pub(super) fn scan_expr(&mut self, e: &fragment::Expr, event: &str, kind: Option<EventKind>, int_context: bool) {
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

    pub(super) fn scan_stmts(&mut self, stmts: &[fragment::Stmt], event: &str) {
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
    pub(super) fn expr(&mut self, e: &fragment::Expr, at: Span) -> Option<Expr> {
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

    pub(super) fn stmts(&mut self, stmts: &[fragment::Stmt], at: Span) -> Option<Vec<Stmt>> {
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
pub(super) type Fragments = crate::sct::EventFragments;

/// The signals found in the fragments, with their kind, type and the address the STL form
/// gives them: direct addresses as written; symbols after the highest byte written directly,
/// bits first, words on even bytes (memory from byte 100).
pub(super) fn signal_table(l: &Lowering<'_>) -> Vec<Signal> {
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
