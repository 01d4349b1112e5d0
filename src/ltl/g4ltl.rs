//! G4LTL's line format (`.ltl`): one formula per line, `ASSUME φ` an assumption and any other
//! formula a guarantee, `INPUT a, b` / `OUTPUT c` declarations and `TIMER t1(10s)` timers, `##`
//! and `!--` comments (and `//`, which G4LTL does not know, for the `// Expected:` lines of the
//! project's examples). Operators: `ALWAYS`/`[]`/`G`, `EVENTUALLY`/`<>`/`F`, `NEXT`/`X`,
//! `UNTIL`/`U`, `R`/`V` (release), `W` (weak until), `! && || -> <->`, `true`/`false`.
//!
//! Precedence, loosest first: `<->` (left), `->` (right), `||`, `&&`, the binary temporal
//! operators `U R V W` (right), then the unary operators, which bind tightest (`!a U b` is
//! `(!a) U b`, as in G4LTL and Spot).

use super::spec::{Clause, Ltl, Signal, SignalId, SignalKind, Spec, Timer, MAX_FORMULA_DEPTH};
use crate::diag::{Diagnostic, Diagnostics, Span};
use logos::Logos;
use std::collections::HashMap;

#[derive(Logos, Clone, Copy, Debug, PartialEq, Eq)]
#[logos(skip r"[ \t\r\f]+")]
#[logos(skip(r"(##|!--|//)[^\n]*", allow_greedy = true))]
enum Tok {
    #[regex(r"[A-Za-z_][A-Za-z0-9_]*(\.[A-Za-z_][A-Za-z0-9_]*)?")]
    Ident,
    #[regex(r"[0-9]+[A-Za-z]*")]
    Number,
    #[token("\n")]
    Newline,
    #[token("[]")]
    Box_,
    #[token("<>")]
    Diamond,
    #[token("!")]
    Not,
    #[token("&&")]
    #[token("&")]
    And,
    #[token("||")]
    #[token("|")]
    Or,
    #[token("->")]
    Implies,
    #[token("<->")]
    Iff,
    #[token("(")]
    LParen,
    #[token(")")]
    RParen,
    #[token(",")]
    Comma,
}

/// An operator spelled as a word, and the words that may not name a signal.
fn word_operator(word: &str) -> Option<Op> {
    Some(match word {
        "ALWAYS" | "G" => Op::Globally,
        "EVENTUALLY" | "F" => Op::Finally,
        "NEXT" | "X" => Op::Next,
        "UNTIL" | "U" => Op::Until,
        "R" | "V" => Op::Release,
        "W" => Op::WeakUntil,
        _ => return None,
    })
}

const KEYWORDS: [&str; 4] = ["INPUT", "OUTPUT", "TIMER", "ASSUME"];

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Op {
    Globally,
    Finally,
    Next,
    Until,
    Release,
    WeakUntil,
}

/// A formula as written, names unresolved (declarations may follow their use).
#[derive(Debug)]
enum Expr {
    Const(bool),
    Name(Span),
    Not(Box<Expr>),
    Unary(Op, Box<Expr>),
    Binary(Bin, Box<Expr>, Box<Expr>),
    /// A chain of `&&` or `||`, kept flat so that a long chain nests nothing.
    Many(Bin, Vec<Expr>),
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Bin {
    And,
    Or,
    Implies,
    Iff,
    Temporal(Op),
}

/// Nesting of parentheses and unary operators the parser follows before it reports an error
/// (its recursion must stay far inside a wasm worker's stack).
const MAX_NESTING: usize = 128;

struct Parser<'s, 'd> {
    src: &'s str,
    toks: &'s [(Tok, Span)],
    pos: usize,
    diags: &'d mut Diagnostics<'s>,
}

impl<'s> Parser<'s, '_> {
    fn peek(&self) -> Option<Tok> {
        self.toks.get(self.pos).map(|t| t.0)
    }
    fn span(&self) -> Span {
        self.toks.get(self.pos).map(|t| t.1).unwrap_or_else(|| {
            self.toks.last().map_or(Span::new(0, 0), |t| Span::new(t.1.end as usize, t.1.end as usize))
        })
    }
    fn text(&self, span: Span) -> &'s str {
        &self.src[span.range()]
    }
    fn bump(&mut self) -> Span {
        let span = self.span();
        self.pos += 1;
        span
    }
    fn at_word(&self) -> Option<&'s str> {
        (self.peek() == Some(Tok::Ident)).then(|| self.text(self.span()))
    }

    /// After an item of a declaration list: `Some(true)` past a `,`, `Some(false)` at the end
    /// of the line, `None` (reported) on anything else.
    fn another_item(&mut self) -> Option<bool> {
        match self.peek() {
            None => Some(false),
            Some(Tok::Comma) => {
                self.bump();
                Some(true)
            }
            Some(_) => {
                let span = self.span();
                self.diags.error(span, "expected `,` or the end of the line");
                None
            }
        }
    }

    /// `<->`, loosest and left-associative.
    fn iff(&mut self, depth: usize) -> Option<(Expr, Span)> {
        let (mut lhs, mut span) = self.implies(depth)?;
        let mut operands = 1;
        while self.peek() == Some(Tok::Iff) {
            operands += 1;
            if depth + operands > MAX_NESTING {
                self.diags.error(self.span(), format!("more than {MAX_NESTING} operands of `<->` in a row"));
                return None;
            }
            self.bump();
            let (rhs, rspan) = self.implies(depth + operands)?;
            lhs = Expr::Binary(Bin::Iff, Box::new(lhs), Box::new(rhs));
            span = span.to(rspan);
        }
        Some((lhs, span))
    }

    /// `->`, right-associative; parsed as a list and folded from the right, without recursion.
    fn implies(&mut self, depth: usize) -> Option<(Expr, Span)> {
        let mut parts = vec![self.or(depth)?];
        while self.peek() == Some(Tok::Implies) {
            if depth + parts.len() >= MAX_NESTING {
                self.diags.error(self.span(), format!("more than {MAX_NESTING} operands of `->` in a row"));
                return None;
            }
            self.bump();
            parts.push(self.or(depth + parts.len())?);
        }
        Some(fold_right(parts, |_| Bin::Implies))
    }

    fn or(&mut self, depth: usize) -> Option<(Expr, Span)> {
        self.flat_chain(depth, Tok::Or, Bin::Or, Self::and)
    }

    fn and(&mut self, depth: usize) -> Option<(Expr, Span)> {
        self.flat_chain(depth, Tok::And, Bin::And, Self::temporal)
    }

    /// Operands of `operand` joined by `tok`, kept as one flat [`Expr::Many`] of `bin`.
    fn flat_chain(
        &mut self,
        depth: usize,
        tok: Tok,
        bin: Bin,
        operand: fn(&mut Self, usize) -> Option<(Expr, Span)>,
    ) -> Option<(Expr, Span)> {
        let (first, mut span) = operand(self, depth + 1)?;
        let mut parts = vec![first];
        while self.peek() == Some(tok) {
            self.bump();
            let (rhs, rspan) = operand(self, depth + 1)?;
            parts.push(rhs);
            span = span.to(rspan);
        }
        Some((if parts.len() == 1 { parts.pop().expect("one part") } else { Expr::Many(bin, parts) }, span))
    }

    /// `U R V W`, right-associative, folded from the right.
    fn temporal(&mut self, depth: usize) -> Option<(Expr, Span)> {
        let mut parts = vec![self.unary(depth)?];
        let mut ops = Vec::new();
        while let Some(op) =
            self.at_word().and_then(word_operator).filter(|op| matches!(op, Op::Until | Op::Release | Op::WeakUntil))
        {
            if depth + parts.len() >= MAX_NESTING {
                self.diags.error(self.span(), format!("more than {MAX_NESTING} temporal operators in a row"));
                return None;
            }
            self.bump();
            ops.push(op);
            parts.push(self.unary(depth + parts.len())?);
        }
        Some(fold_right(parts, |i| Bin::Temporal(ops[i])))
    }

    fn unary(&mut self, depth: usize) -> Option<(Expr, Span)> {
        let start = self.span();
        if depth >= MAX_NESTING {
            self.diags.error(start, format!("the formula nests deeper than {MAX_NESTING} levels"));
            return None;
        }
        let op = match self.peek() {
            Some(Tok::Not) => None,
            Some(Tok::Box_) => Some(Op::Globally),
            Some(Tok::Diamond) => Some(Op::Finally),
            Some(Tok::Ident) => match self.at_word().and_then(word_operator) {
                Some(op @ (Op::Globally | Op::Finally | Op::Next)) => Some(op),
                Some(_) => {
                    let word = self.text(start);
                    self.diags.error(start, format!("`{word}` needs a formula on its left"));
                    return None;
                }
                None => return self.atom(depth),
            },
            _ => return self.atom(depth),
        };
        self.bump();
        let (inner, span) = self.unary(depth + 1)?;
        let span = start.to(span);
        Some(match op {
            None => (Expr::Not(Box::new(inner)), span),
            Some(op) => (Expr::Unary(op, Box::new(inner)), span),
        })
    }

    fn atom(&mut self, depth: usize) -> Option<(Expr, Span)> {
        let span = self.span();
        match self.peek() {
            Some(Tok::Ident) => {
                self.bump();
                let word = self.text(span);
                if KEYWORDS.contains(&word) {
                    self.diags.error(span, format!("`{word}` starts a line; it cannot stand inside a formula"));
                    return None;
                }
                Some(match word {
                    "true" | "TRUE" => (Expr::Const(true), span),
                    "false" | "FALSE" => (Expr::Const(false), span),
                    _ => (Expr::Name(span), span),
                })
            }
            Some(Tok::LParen) => {
                self.bump();
                let (inner, _) = self.iff(depth + 1)?;
                if self.peek() == Some(Tok::RParen) {
                    let close = self.bump();
                    Some((inner, span.to(close)))
                } else {
                    let (line, column) = self.diags.line_col(span.start as usize);
                    let here = self.span();
                    self.diags.error(here, "expected `)`").with_note(format!("to close the `(` at {line}:{column}"));
                    None
                }
            }
            Some(Tok::Number) => {
                self.diags.error(span, format!("unexpected number `{}` in a formula", self.text(span)));
                None
            }
            None => {
                self.diags
                    .error(span, "the formula ends here; expected a signal, `true`, `false`, `(` or a unary operator");
                None
            }
            Some(_) => {
                self.diags.error(
                    span,
                    format!(
                        "unexpected `{}`; expected a signal, `true`, `false`, `(` or a unary operator",
                        self.text(span)
                    ),
                );
                None
            }
        }
    }
}

/// Folds `parts` (each with its span) from the right with the operator `bin(i)` between
/// part `i` and `i + 1`.
fn fold_right(mut parts: Vec<(Expr, Span)>, bin: impl Fn(usize) -> Bin) -> (Expr, Span) {
    let (mut acc, mut span) = parts.pop().expect("at least one part");
    while let Some((lhs, lspan)) = parts.pop() {
        acc = Expr::Binary(bin(parts.len()), Box::new(lhs), Box::new(acc));
        span = lspan.to(span);
    }
    (acc, span)
}

/// One line of the file.
enum Line {
    Formula { assume: bool, expr: Expr, span: Span },
    Declare { kind: SignalKind, names: Vec<Span> },
    Timers(Vec<(Span, u64)>),
}

/// Checks a G4LTL text into a [`Spec`]. On success the specification and its warnings,
/// otherwise every diagnostic.
pub fn compile_g4ltl(source: &str) -> Result<(Spec, Vec<Diagnostic>), Vec<Diagnostic>> {
    let mut diags = Diagnostics::new(source);
    let toks = lex(source, &mut diags);
    let mut lines = Vec::new();
    for line in toks.split(|t| t.0 == Tok::Newline).filter(|l| !l.is_empty()) {
        if let Some(parsed) = parse_line(source, line, &mut diags) {
            lines.push(parsed);
        }
    }
    let spec = resolve(source, &lines, &mut diags);
    if diags.has_errors() {
        Err(diags.items)
    } else {
        Ok((spec, diags.items))
    }
}

fn lex<'s>(src: &'s str, diags: &mut Diagnostics<'s>) -> Vec<(Tok, Span)> {
    let mut toks = Vec::new();
    let mut lexer = Tok::lexer(src);
    while let Some(tok) = lexer.next() {
        let r = lexer.span();
        let span = Span::new(r.start, r.end);
        match tok {
            Ok(t) => toks.push((t, span)),
            Err(()) => {
                let c = src[r.start..].chars().next().unwrap_or('?');
                diags.error(span, format!("unexpected character `{}`", c.escape_default()));
            }
        }
    }
    toks
}

fn parse_line<'s>(src: &'s str, toks: &'s [(Tok, Span)], diags: &mut Diagnostics<'s>) -> Option<Line> {
    let mut p = Parser { src, toks, pos: 0, diags };
    let first = p.at_word();
    match first {
        Some(kw @ ("INPUT" | "OUTPUT")) => {
            p.bump();
            let kind = if kw == "INPUT" { SignalKind::Input } else { SignalKind::Output };
            let mut names = Vec::new();
            loop {
                let span = p.span();
                match p.peek() {
                    Some(Tok::Ident) => {
                        p.bump();
                        names.push(span);
                    }
                    _ => {
                        p.diags.error(span, format!("expected a signal name after `{kw}`"));
                        return None;
                    }
                }
                if !p.another_item()? {
                    break;
                }
            }
            Some(Line::Declare { kind, names })
        }
        Some("TIMER") => {
            p.bump();
            let mut timers = Vec::new();
            loop {
                let name = p.span();
                if p.peek() != Some(Tok::Ident) {
                    p.diags.error(name, "expected a timer name, as in `TIMER t1(10s)`");
                    return None;
                }
                p.bump();
                if p.peek() != Some(Tok::LParen) {
                    let span = p.span();
                    p.diags.error(span, "expected `(` and the timer's preset, as in `t1(10s)`");
                    return None;
                }
                p.bump();
                let preset = p.span();
                if p.peek() != Some(Tok::Number) {
                    p.diags.error(preset, "expected a duration such as `10s`, `500ms`, `2min` or `1h`");
                    return None;
                }
                p.bump();
                let ms = duration_ms(p.text(preset)).or_else(|| {
                    p.diags.error(
                        preset,
                        format!("`{}` is not a duration: write e.g. `10s`, `500ms`, `2min`, `1h`", p.text(preset)),
                    );
                    None
                })?;
                if p.peek() != Some(Tok::RParen) {
                    let span = p.span();
                    p.diags.error(span, "expected `)`");
                    return None;
                }
                p.bump();
                timers.push((name, ms));
                if !p.another_item()? {
                    break;
                }
            }
            Some(Line::Timers(timers))
        }
        _ => {
            let assume = first == Some("ASSUME");
            if assume {
                p.bump();
            }
            let (expr, span) = p.iff(0)?;
            if p.peek().is_some() {
                let extra = p.span();
                p.diags
                    .error(extra, format!("unexpected `{}` after the formula", p.text(extra)))
                    .with_note("write one formula per line; combine formulas with `&&`");
                return None;
            }
            Some(Line::Formula { assume, expr, span })
        }
    }
}

/// Milliseconds of `10s`, `500ms`, `2min`, `1h`; `None` if malformed or beyond 2^63 ms.
fn duration_ms(text: &str) -> Option<u64> {
    let digits = text.find(|c: char| !c.is_ascii_digit()).unwrap_or(text.len());
    let value: u64 = text[..digits].parse().ok()?;
    let unit: u64 = match &text[digits..] {
        "ms" => 1,
        "s" | "sec" => 1000,
        "min" | "m" => 60_000,
        "h" => 3_600_000,
        _ => return None,
    };
    value.checked_mul(unit).filter(|&ms| ms <= i64::MAX as u64)
}

fn resolve(src: &str, lines: &[Line], diags: &mut Diagnostics) -> Spec {
    let mut spec = Spec::default();
    let mut ids: HashMap<String, SignalId> = HashMap::new();
    let mut declare = |spec: &mut Spec, diags: &mut Diagnostics, name: &str, kind: SignalKind, span: Span| {
        if let Some(&prior) = ids.get(name) {
            let prior = spec.signal(prior).span;
            let (line, col) = diags.line_col(prior.start as usize);
            diags
                .error(span, format!("`{name}` is declared twice"))
                .with_note(format!("first declared at {line}:{col}"));
            return None;
        }
        let id = SignalId(spec.signals.len() as u32);
        spec.signals.push(Signal { name: name.to_string(), kind, span });
        ids.insert(name.to_string(), id);
        Some(id)
    };
    for line in lines {
        if let Line::Declare { kind, names } = line {
            for &span in names {
                let name = &src[span.range()];
                if word_operator(name).is_some()
                    || KEYWORDS.contains(&name)
                    || matches!(name, "true" | "false" | "TRUE" | "FALSE")
                {
                    diags.error(span, format!("`{name}` is an operator or keyword of the language; rename the signal"));
                } else if name.contains('.') {
                    diags
                        .error(span, format!("`{name}`: signal names have no `.`"))
                        .with_note("`t.start` and `t.expire` come from a `TIMER t(…)` declaration");
                } else {
                    declare(&mut spec, diags, name, *kind, span);
                }
            }
        }
    }
    for line in lines {
        if let Line::Timers(timers) = line {
            for &(span, preset_ms) in timers {
                let name = &src[span.range()];
                if name.contains('.') {
                    diags.error(span, format!("`{name}`: timer names have no `.`"));
                    continue;
                }
                let start = declare(&mut spec, diags, &format!("{name}.start"), SignalKind::Output, span);
                let expire = declare(&mut spec, diags, &format!("{name}.expire"), SignalKind::Input, span);
                if let (Some(start), Some(expire)) = (start, expire) {
                    spec.timers.push(Timer { name: name.to_string(), preset_ms, start, expire, span });
                }
            }
        }
    }
    let mut used = vec![false; spec.signals.len()];
    for line in lines {
        if let Line::Formula { assume, expr, span } = line {
            let Some(formula) = to_ltl(src, expr, &spec, &mut used, diags) else { continue };
            if formula.depth() > MAX_FORMULA_DEPTH {
                diags.error(*span, format!("the formula nests deeper than {MAX_FORMULA_DEPTH} levels"));
                continue;
            }
            let clause = Clause { formula, span: *span };
            if *assume {
                spec.assumptions.push(clause);
            } else {
                spec.guarantees.push(clause);
            }
        }
    }
    // The timer abstraction of section 2: the environment's timer block expires some time after
    // each start. A first, coarse model (expiry strictly later, a restart not modelled); the
    // refinement from counter-strategies comes with the timer support of the next issue.
    for timer in &spec.timers {
        let (start, expire) = (Ltl::Var(timer.start), Ltl::Var(timer.expire));
        let formula = Ltl::globally(Ltl::implies(start, Ltl::next(Ltl::finally(expire))));
        spec.assumptions.push(Clause { formula, span: timer.span });
        used[timer.start.index()] = true;
        used[timer.expire.index()] = true;
    }
    for (signal, used) in spec.signals.iter().zip(&used) {
        if !used {
            diags.warning(signal.span, format!("`{}` is declared but no formula uses it", signal.name));
        }
    }
    spec
}

fn to_ltl(src: &str, expr: &Expr, spec: &Spec, used: &mut [bool], diags: &mut Diagnostics) -> Option<Ltl> {
    Some(match expr {
        Expr::Const(true) => Ltl::True,
        Expr::Const(false) => Ltl::False,
        Expr::Name(span) => {
            let name = &src[span.range()];
            match spec.signal_id(name) {
                Some(id) => {
                    used[id.index()] = true;
                    Ltl::Var(id)
                }
                None => {
                    let d = diags.error(*span, format!("`{name}` is not declared"));
                    if let Some((timer, field)) = name.split_once('.') {
                        if spec.timers.iter().any(|t| t.name == timer) {
                            d.with_note(format!("a timer has `{timer}.start` and `{timer}.expire`, not `.{field}`"));
                        } else {
                            d.with_note(format!("declare it with `TIMER {timer}(10s)`"));
                        }
                    } else {
                        d.with_note("declare it in an `INPUT` or `OUTPUT` line");
                    }
                    return None;
                }
            }
        }
        Expr::Not(a) => Ltl::not(to_ltl(src, a, spec, used, diags)?),
        Expr::Unary(op, a) => {
            let a = to_ltl(src, a, spec, used, diags)?;
            match op {
                Op::Globally => Ltl::globally(a),
                Op::Finally => Ltl::finally(a),
                _ => Ltl::next(a),
            }
        }
        Expr::Many(bin, parts) => {
            // Every part is checked, so that every unknown name is reported.
            let parts: Vec<Option<Ltl>> = parts.iter().map(|p| to_ltl(src, p, spec, used, diags)).collect();
            let parts: Vec<Ltl> = parts.into_iter().collect::<Option<_>>()?;
            if *bin == Bin::And {
                Ltl::And(parts)
            } else {
                Ltl::Or(parts)
            }
        }
        Expr::Binary(bin, a, b) => {
            // Both sides are checked, so that every unknown name is reported.
            let a = to_ltl(src, a, spec, used, diags);
            let b = to_ltl(src, b, spec, used, diags);
            let (a, b) = (a?, b?);
            match bin {
                Bin::And => Ltl::And(vec![a, b]),
                Bin::Or => Ltl::Or(vec![a, b]),
                Bin::Implies => Ltl::implies(a, b),
                Bin::Iff => Ltl::iff(a, b),
                Bin::Temporal(Op::Until) => Ltl::until(a, b),
                Bin::Temporal(Op::Release) => Ltl::release(a, b),
                Bin::Temporal(_) => Ltl::weak_until(a, b),
            }
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn text(src: &str) -> String {
        let (spec, _) = compile_g4ltl(src).unwrap_or_else(|d| panic!("{d:?}"));
        spec.formula_text()
    }

    fn first_error(src: &str) -> (u32, u32, String) {
        let diags = compile_g4ltl(src).expect_err("an error");
        let d = diags.iter().find(|d| d.is_error()).expect("an error");
        (d.line, d.column, d.message.clone())
    }

    #[test]
    fn reads_both_spellings_and_precedence() {
        let src =
            "ALWAYS (req -> EVENTUALLY grant)\n[] (!a U b && c)\nASSUME [] <> a\nINPUT req, a\nOUTPUT grant, b, c\n";
        assert_eq!(text(src), "G F a -> (G (req -> F grant) && G ((!a U b) && c))");
        assert_eq!(text("a -> b -> c <-> d\nINPUT a, b\nOUTPUT c, d"), "(a -> (b -> c)) <-> d");
        assert_eq!(text("a U b W c R d V e\nINPUT a, b\nOUTPUT c, d, e"), "a U (b W (c R (d R e)))");
    }

    #[test]
    fn comments_and_crlf_are_skipped() {
        let src = "## a comment\r\nALWAYS a !-- another\r\n\r\nOUTPUT a\r\n";
        assert_eq!(text(src), "G a");
    }

    #[test]
    fn timers_declare_two_signals_and_an_assumption() {
        let (spec, warnings) = compile_g4ltl("ALWAYS (req -> t1.start)\nINPUT req\nTIMER t1(10s)\n").unwrap();
        assert!(warnings.is_empty(), "{warnings:?}");
        assert_eq!(spec.timers[0].preset_ms, 10_000);
        assert_eq!(spec.signal(spec.timers[0].start).kind, SignalKind::Output);
        assert_eq!(spec.signal(spec.timers[0].expire).kind, SignalKind::Input);
        assert_eq!(spec.formula_text(), "G (t1.start -> X F t1.expire) -> G (req -> t1.start)");
    }

    #[test]
    fn errors_are_located() {
        assert_eq!(first_error("ALWAYS (a -> b\nINPUT a\nOUTPUT b").0, 1);
        assert_eq!(first_error("ALWAYS (a -> b\nINPUT a\nOUTPUT b").1, 15);
        let (line, col, msg) = first_error("ALWAYS a\nG (a -> c)\nINPUT a");
        assert_eq!((line, col), (2, 9));
        assert!(msg.contains("`c` is not declared"), "{msg}");
        assert!(first_error("a\nINPUT a, a").2.contains("declared twice"));
        assert!(first_error("X\nINPUT X").2.contains("operator"));
        assert!(first_error("a b\nINPUT a, b").2.contains("after the formula"));
        assert!(first_error("U a\nINPUT a").2.contains("on its left"));
        assert!(first_error("t1.stop\nTIMER t1(1s)").2.contains("not declared"));
        assert!(first_error("a\nINPUT a\nTIMER t(10 parsecs)").2.contains("not a duration"));
        assert!(first_error("a\nINPUT a\nTIMER t(10y)").2.contains("not a duration"));
        assert!(first_error("a \u{0}\nINPUT a").2.contains("unexpected character"));
        let deep = format!("{}a{}\nINPUT a", "(".repeat(5000), ")".repeat(5000));
        assert!(first_error(&deep).2.contains("deeper"));
        let chain = format!("{}a\nINPUT a", "! ".repeat(100_000));
        assert!(first_error(&chain).2.contains("deeper"));
        let long = format!("{}a\nINPUT a", "a -> ".repeat(100_000));
        let message = first_error(&long).2;
        assert!(message.contains("in a row") || message.contains("deeper"), "{message}");
        let conjunction = format!("{}a\nINPUT a", "a && ".repeat(100_000));
        assert!(compile_g4ltl(&conjunction).is_ok(), "a long conjunction nests nothing");
    }
}
