//! G4LTL's line format (`.ltl`): one formula per line, `ASSUME φ` an assumption and any other
//! formula a guarantee, `INPUT a, b` / `OUTPUT c` declarations and `TIMER t1(10s)` timers, `##`
//! and `!--` comments (and `//`, which G4LTL does not know, for the `// Expected:` lines of the
//! project's examples). Operators: `ALWAYS`/`[]`/`G`, `EVENTUALLY`/`<>`/`F`, `NEXT`/`X`,
//! `UNTIL`/`U`, `R`/`V` (release), `W` (weak until), `! && || -> <->`, `true`/`false`.
//!
//! Precedence, loosest first: `<->` (left), `->` (right), `||`, `&&`, the binary temporal
//! operators `U R V W` (right), then the unary operators, which bind tightest (`!a U b` is
//! `(!a) U b`, as in G4LTL and Spot).

use super::spec::{
    Clause, Ltl, NumExpr, NumberKind, NumericId, NumericInput, Predicate, Relation, Signal, SignalId, SignalKind, Spec,
    Timer, MAX_FORMULA_DEPTH,
};
use crate::diag::{Diagnostic, Diagnostics, Span};
use crate::syntax::Cursor;
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
    #[regex(r"[0-9]+\.[0-9]+([eE][+-]?[0-9]+)?")]
    Decimal,
    #[token("+")]
    Plus,
    #[token("-")]
    Minus,
    #[token("*")]
    Star,
    #[token("/")]
    Slash,
    #[token("^")]
    Caret,
    #[token("<")]
    Lt,
    #[token("<=")]
    Le,
    #[token(">")]
    Gt,
    #[token(">=")]
    Ge,
    #[token("=")]
    #[token("==")]
    Eq,
    #[token("!=")]
    Ne,
    #[token(":")]
    Colon,
    #[token("[")]
    LBracket,
    #[token("]")]
    RBracket,
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
    /// The end of a line (or of a part of one), after its last token; never lexed.
    Eof,
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

const KEYWORDS: [&str; 7] = ["INPUT", "OUTPUT", "TIMER", "ASSUME", "WHENEVER", "THEN", "FOR"];

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Op {
    Globally,
    Finally,
    Next,
    Until,
    Release,
    WeakUntil,
}

/// A formula as written, names unresolved (declarations may follow their use). Arithmetic
/// and comparisons are parsed with it; the resolver checks which is which.
#[derive(Debug)]
enum Expr {
    Const(bool),
    Name(Span),
    /// A numeric literal.
    Number(Span),
    Neg(Box<Expr>),
    Arith(ArithOp, Box<Expr>, Box<Expr>),
    /// `x ^ n` with the exponent's span.
    Pow(Box<Expr>, Span),
    Compare(Relation, Box<Expr>, Box<Expr>, Span),
    Not(Box<Expr>),
    Unary(Op, Box<Expr>),
    Binary(Bin, Box<Expr>, Box<Expr>),
    /// A chain of `&&` or `||`, kept flat so that a long chain nests nothing.
    Many(Bin, Vec<Expr>),
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum ArithOp {
    Add,
    Sub,
    Mul,
    Div,
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
    /// The tokens of a line or of a part of one, then [`Tok::Eof`] where the last one ends.
    cur: Cursor<Tok>,
    diags: &'d mut Diagnostics<'s>,
}

impl<'s, 'd> Parser<'s, 'd> {
    fn new(src: &'s str, toks: &[(Tok, Span)], diags: &'d mut Diagnostics<'s>) -> Self {
        Parser { src, cur: Cursor::with_end(toks, Tok::Eof), diags }
    }
}

impl<'s> Parser<'s, '_> {
    fn text(&self, span: Span) -> &'s str {
        &self.src[span.range()]
    }
    fn at_word(&self) -> Option<&'s str> {
        self.cur.at(Tok::Ident).then(|| self.text(self.cur.span()))
    }

    /// After an item of a declaration list: `Some(true)` past a `,`, `Some(false)` at the end
    /// of the line, `None` (reported) on anything else.
    fn another_item(&mut self) -> Option<bool> {
        match self.cur.peek() {
            Tok::Eof => Some(false),
            Tok::Comma => {
                self.cur.bump();
                Some(true)
            }
            _ => {
                let span = self.cur.span();
                self.diags.error(span, "expected `,` or the end of the line");
                None
            }
        }
    }

    /// `<->`, loosest and left-associative.
    fn iff(&mut self, depth: usize) -> Option<(Expr, Span)> {
        let (mut lhs, mut span) = self.implies(depth)?;
        let mut operands = 1;
        while self.cur.at(Tok::Iff) {
            operands += 1;
            if depth + operands > MAX_NESTING {
                self.diags.error(self.cur.span(), format!("more than {MAX_NESTING} operands of `<->` in a row"));
                return None;
            }
            self.cur.bump();
            let (rhs, rspan) = self.implies(depth + operands)?;
            lhs = Expr::Binary(Bin::Iff, Box::new(lhs), Box::new(rhs));
            span = span.to(rspan);
        }
        Some((lhs, span))
    }

    /// `->`, right-associative; parsed as a list and folded from the right, without recursion.
    fn implies(&mut self, depth: usize) -> Option<(Expr, Span)> {
        let mut parts = vec![self.or(depth)?];
        while self.cur.at(Tok::Implies) {
            if depth + parts.len() >= MAX_NESTING {
                self.diags.error(self.cur.span(), format!("more than {MAX_NESTING} operands of `->` in a row"));
                return None;
            }
            self.cur.bump();
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
        while self.cur.at(tok) {
            self.cur.bump();
            let (rhs, rspan) = operand(self, depth + 1)?;
            parts.push(rhs);
            span = span.to(rspan);
        }
        Some((if parts.len() == 1 { parts.pop().expect("one part") } else { Expr::Many(bin, parts) }, span))
    }

    /// `U R V W`, right-associative, folded from the right.
    fn temporal(&mut self, depth: usize) -> Option<(Expr, Span)> {
        let mut parts = vec![self.compare(depth)?];
        let mut ops = Vec::new();
        while let Some(op) =
            self.at_word().and_then(word_operator).filter(|op| matches!(op, Op::Until | Op::Release | Op::WeakUntil))
        {
            if depth + parts.len() >= MAX_NESTING {
                self.diags.error(self.cur.span(), format!("more than {MAX_NESTING} temporal operators in a row"));
                return None;
            }
            self.cur.bump();
            ops.push(op);
            parts.push(self.compare(depth + parts.len())?);
        }
        Some(fold_right(parts, |i| Bin::Temporal(ops[i])))
    }

    /// `sum REL sum` or just a sum: a comparison binds tighter than every logical operator.
    fn compare(&mut self, depth: usize) -> Option<(Expr, Span)> {
        let (lhs, span) = self.sum(depth)?;
        let relation = match self.cur.peek() {
            Tok::Lt => Relation::Lt,
            Tok::Le => Relation::Le,
            Tok::Gt => Relation::Gt,
            Tok::Ge => Relation::Ge,
            Tok::Eq => Relation::Eq,
            Tok::Ne => Relation::Ne,
            _ => return Some((lhs, span)),
        };
        self.cur.bump();
        let (rhs, rspan) = self.sum(depth + 1)?;
        let span = span.to(rspan);
        Some((Expr::Compare(relation, Box::new(lhs), Box::new(rhs), span), span))
    }

    /// `+` and `-` (left-associative), then `*` and `/`, then `^`, then a sign.
    fn sum(&mut self, depth: usize) -> Option<(Expr, Span)> {
        self.arith_chain(depth, &[(Tok::Plus, ArithOp::Add), (Tok::Minus, ArithOp::Sub)], Self::product)
    }

    fn product(&mut self, depth: usize) -> Option<(Expr, Span)> {
        self.arith_chain(depth, &[(Tok::Star, ArithOp::Mul), (Tok::Slash, ArithOp::Div)], Self::power)
    }

    fn arith_chain(
        &mut self,
        depth: usize,
        ops: &[(Tok, ArithOp)],
        operand: fn(&mut Self, usize) -> Option<(Expr, Span)>,
    ) -> Option<(Expr, Span)> {
        let (mut lhs, mut span) = operand(self, depth + 1)?;
        let mut count = 1;
        while let Some(&(_, op)) = ops.iter().find(|(t, _)| *t == self.cur.peek()) {
            count += 1;
            if depth + count >= MAX_NESTING {
                self.diags.error(self.cur.span(), format!("more than {MAX_NESTING} arithmetic operands in a row"));
                return None;
            }
            self.cur.bump();
            let (rhs, rspan) = operand(self, depth + count)?;
            lhs = Expr::Arith(op, Box::new(lhs), Box::new(rhs));
            span = span.to(rspan);
        }
        Some((lhs, span))
    }

    fn power(&mut self, depth: usize) -> Option<(Expr, Span)> {
        let (base, span) = self.signed(depth)?;
        if !self.cur.at(Tok::Caret) {
            return Some((base, span));
        }
        self.cur.bump();
        let exponent = self.cur.span();
        if !self.cur.at(Tok::Number) || !self.text(exponent).bytes().all(|b| b.is_ascii_digit()) {
            self.diags.error(exponent, "expected a whole number as the exponent, as in `x^2`");
            return None;
        }
        self.cur.bump();
        Some((Expr::Pow(Box::new(base), exponent), span.to(exponent)))
    }

    fn signed(&mut self, depth: usize) -> Option<(Expr, Span)> {
        if !self.cur.at(Tok::Minus) {
            return self.unary(depth);
        }
        let start = self.cur.bump().1;
        if depth >= MAX_NESTING {
            self.diags.error(start, format!("the formula nests deeper than {MAX_NESTING} levels"));
            return None;
        }
        let (inner, span) = self.signed(depth + 1)?;
        Some((Expr::Neg(Box::new(inner)), start.to(span)))
    }

    fn unary(&mut self, depth: usize) -> Option<(Expr, Span)> {
        let start = self.cur.span();
        if depth >= MAX_NESTING {
            self.diags.error(start, format!("the formula nests deeper than {MAX_NESTING} levels"));
            return None;
        }
        let op = match self.cur.peek() {
            Tok::Not => None,
            Tok::Box_ => Some(Op::Globally),
            Tok::Diamond => Some(Op::Finally),
            Tok::Ident => match self.at_word().and_then(word_operator) {
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
        self.cur.bump();
        let (inner, span) = self.compare(depth + 1)?;
        let span = start.to(span);
        Some(match op {
            None => (Expr::Not(Box::new(inner)), span),
            Some(op) => (Expr::Unary(op, Box::new(inner)), span),
        })
    }

    fn atom(&mut self, depth: usize) -> Option<(Expr, Span)> {
        let span = self.cur.span();
        match self.cur.peek() {
            Tok::Ident => {
                self.cur.bump();
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
            Tok::LParen => {
                self.cur.bump();
                let (inner, _) = self.iff(depth + 1)?;
                if self.cur.at(Tok::RParen) {
                    let close = self.cur.bump().1;
                    Some((inner, span.to(close)))
                } else {
                    let (line, column) = self.diags.line_col(span.start as usize);
                    let here = self.cur.span();
                    self.diags.error(here, "expected `)`").with_note(format!("to close the `(` at {line}:{column}"));
                    None
                }
            }
            Tok::Number | Tok::Decimal => {
                self.cur.bump();
                Some((Expr::Number(span), span))
            }
            Tok::Eof => {
                self.diags
                    .error(span, "the formula ends here; expected a signal, `true`, `false`, `(` or a unary operator");
                None
            }
            _ => {
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

/// The real-time patterns of the paper's table 1 (`docs/ltl-language.md` gives their
/// encodings).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Pattern {
    /// `WHENEVER a THEN b FOR d`: b from each `a` on, until d has passed since the last `a`.
    HoldFor,
    /// `WHENEVER a FOR d THEN b`: b whenever a has held for d without a break.
    After,
    /// `WHENEVER a THEN b UNTIL c FOR d`: b from each `a` on, until c has held for d.
    UntilHeld,
}

/// The type of a numeric input as declared: `REAL[0, 4]`.
struct NumberType {
    kind: NumberKind,
    lo: String,
    hi: String,
    span: Span,
}

/// One line of the file.
enum Line {
    Formula { assume: bool, expr: Expr, span: Span },
    Pattern { pattern: Pattern, a: Expr, b: Expr, c: Option<Expr>, ms: u64, span: Span },
    Declare { kind: SignalKind, names: Vec<(Span, Option<NumberType>)> },
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
    let mut p = Parser::new(src, toks, diags);
    let first = p.at_word();
    match first {
        Some(kw @ ("INPUT" | "OUTPUT")) => {
            p.cur.bump();
            let kind = if kw == "INPUT" { SignalKind::Input } else { SignalKind::Output };
            let mut names = Vec::new();
            loop {
                let span = p.cur.span();
                match p.cur.peek() {
                    Tok::Ident => {
                        p.cur.bump();
                        let ty = if p.cur.at(Tok::Colon) {
                            p.cur.bump();
                            Some(number_type(&mut p, kind)?)
                        } else {
                            None
                        };
                        names.push((span, ty));
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
            p.cur.bump();
            let mut timers = Vec::new();
            loop {
                let name = p.cur.span();
                if !p.cur.at(Tok::Ident) {
                    p.diags.error(name, "expected a timer name, as in `TIMER t1(10s)`");
                    return None;
                }
                p.cur.bump();
                if !p.cur.at(Tok::LParen) {
                    let span = p.cur.span();
                    p.diags.error(span, "expected `(` and the timer's preset, as in `t1(10s)`");
                    return None;
                }
                p.cur.bump();
                let preset = p.cur.span();
                if !p.cur.at(Tok::Number) {
                    p.diags.error(preset, "expected a duration such as `10s`, `500ms`, `2min` or `1h`");
                    return None;
                }
                p.cur.bump();
                let ms = duration_ms(p.text(preset)).or_else(|| {
                    p.diags.error(
                        preset,
                        format!("`{}` is not a duration: write e.g. `10s`, `500ms`, `2min`, `1h`", p.text(preset)),
                    );
                    None
                })?;
                if !p.cur.at(Tok::RParen) {
                    let span = p.cur.span();
                    p.diags.error(span, "expected `)`");
                    return None;
                }
                p.cur.bump();
                timers.push((name, ms));
                if !p.another_item()? {
                    break;
                }
            }
            Some(Line::Timers(timers))
        }
        Some("WHENEVER") => parse_pattern(src, toks, p.diags),
        _ => {
            let assume = first == Some("ASSUME");
            if assume {
                p.cur.bump();
            }
            let (expr, span) = p.iff(0)?;
            if !p.cur.at_end() {
                let extra = p.cur.span();
                p.diags
                    .error(extra, format!("unexpected `{}` after the formula", p.text(extra)))
                    .with_note("write one formula per line; combine formulas with `&&`");
                return None;
            }
            Some(Line::Formula { assume, expr, span })
        }
    }
}

/// `REAL[lo, hi]` or `INT[lo, hi]` after `name:` in an `INPUT` line.
fn number_type(p: &mut Parser, kind: SignalKind) -> Option<NumberType> {
    let start = p.cur.span();
    let word = p.at_word();
    let number = match word {
        Some("REAL") => NumberKind::Real,
        Some("INT") => NumberKind::Int,
        _ => {
            p.diags.error(start, "expected `REAL[lo, hi]` or `INT[lo, hi]` after `:`");
            return None;
        }
    };
    if kind == SignalKind::Output {
        p.diags
            .error(start, "outputs are Boolean: only inputs can be numbers")
            .with_note("the paper's engine, like this one, abstracts predicates on inputs only");
        return None;
    }
    p.cur.bump();
    let expect = |p: &mut Parser, tok: Tok, what: &str| {
        if p.cur.at(tok) {
            p.cur.bump();
            Some(())
        } else {
            let span = p.cur.span();
            p.diags.error(span, format!("expected {what}, as in `x: REAL[0, 4]`"));
            None
        }
    };
    expect(p, Tok::LBracket, "`[` and the bounds")?;
    let lo = bound(p)?;
    expect(p, Tok::Comma, "`,` between the bounds")?;
    let hi = bound(p)?;
    let end = p.cur.span();
    expect(p, Tok::RBracket, "`]` after the bounds")?;
    Some(NumberType { kind: number, lo, hi, span: start.to(end) })
}

/// A bound: an optionally negative decimal literal, checked later.
fn bound(p: &mut Parser) -> Option<String> {
    let negative = p.cur.at(Tok::Minus);
    if negative {
        p.cur.bump();
    }
    let span = p.cur.span();
    if !matches!(p.cur.peek(), Tok::Number | Tok::Decimal) {
        p.diags.error(span, "expected a number as a bound");
        return None;
    }
    p.cur.bump();
    Some(format!("{}{}", if negative { "-" } else { "" }, p.text(span)))
}

/// Whether a numeric type's bounds are numbers, integers for `INT`, and ordered (reported).
fn check_bounds(ty: &NumberType, diags: &mut Diagnostics) -> bool {
    let value = |text: &str| text.parse::<f64>().ok().filter(|v| v.is_finite());
    let (Some(lo), Some(hi)) = (value(&ty.lo), value(&ty.hi)) else {
        diags.error(ty.span, "the bounds must be decimal numbers, as in `REAL[-1.5, 4]`");
        return false;
    };
    // The theory checker computes with exact rationals of 128 bits.
    let exact = |t: &str| super::theory::Rational::parse_decimal(t).is_some();
    if !exact(&ty.lo) || !exact(&ty.hi) {
        diags.error(ty.span, "a bound is too large or has too many digits to compute with exactly");
        return false;
    }
    if ty.kind == NumberKind::Int
        && !(ty.lo.bytes().all(|b| b.is_ascii_digit() || b == b'-')
            && ty.hi.bytes().all(|b| b.is_ascii_digit() || b == b'-'))
    {
        diags.error(ty.span, "the bounds of an `INT` input must be whole numbers");
        return false;
    }
    if ty.kind == NumberKind::Int && (lo < -32768.0 || hi > 32767.0) {
        diags.error(ty.span, "an `INT` holds -32768 to 32767");
        return false;
    }
    if lo > hi {
        diags.error(ty.span, format!("the lower bound {} is above the upper bound {}", ty.lo, ty.hi));
        return false;
    }
    true
}

/// A `WHENEVER` line: its parts are cut at the keywords `THEN` and `FOR` (and, in the
/// `THEN` part before a `FOR`, at `UNTIL`/`U`) outside parentheses, then parsed as formulas.
fn parse_pattern<'s>(src: &'s str, toks: &'s [(Tok, Span)], diags: &mut Diagnostics<'s>) -> Option<Line> {
    let span = toks.first()?.1.to(toks.last()?.1);
    let word = |i: usize| (toks[i].0 == Tok::Ident).then(|| &src[toks[i].1.range()]);
    let mut depth = 0i32;
    let (mut then, mut for_, mut until) = (None, None, None);
    for (i, &(tok, _)) in toks.iter().enumerate().skip(1) {
        match tok {
            Tok::LParen => depth += 1,
            Tok::RParen => depth -= 1,
            _ if depth == 0 => match word(i) {
                Some("THEN") if then.is_none() => then = Some(i),
                Some("FOR") if for_.is_none() => for_ = Some(i),
                Some("UNTIL" | "U") if then.is_some() && for_.is_none() && until.is_none() => until = Some(i),
                _ => {}
            },
            _ => {}
        }
    }
    let usage = "write `WHENEVER a THEN b FOR 10s`, `WHENEVER a FOR 10s THEN b` or `WHENEVER a THEN b UNTIL c FOR 10s`";
    let Some(then) = then else {
        diags.error(span, "a `WHENEVER` line needs `THEN`").with_note(usage);
        return None;
    };
    let Some(for_) = for_ else {
        diags.error(span, "a `WHENEVER` line needs `FOR` and a duration").with_note(usage);
        return None;
    };
    let formula = |from: usize, to: usize, what: &str, diags: &mut Diagnostics<'s>| -> Option<Expr> {
        if from >= to {
            let at = toks.get(from).or(toks.last()).map_or(span, |t| t.1);
            diags.error(at, format!("expected {what} here")).with_note(usage);
            return None;
        }
        let mut p = Parser::new(src, &toks[from..to], diags);
        let (expr, _) = p.iff(0)?;
        if !p.cur.at_end() {
            let extra = p.cur.span();
            p.diags.error(extra, format!("unexpected `{}` in {what}", p.text(extra))).with_note(usage);
            return None;
        }
        Some(expr)
    };
    // The duration is one number token, right after `FOR`.
    let duration = |at: usize, diags: &mut Diagnostics<'s>| -> Option<u64> {
        let Some(&(tok, dspan)) = toks.get(at) else {
            diags.error(toks[at - 1].1, "expected a duration such as `10s` after `FOR`");
            return None;
        };
        let text = &src[dspan.range()];
        match (tok, duration_ms(text)) {
            (Tok::Number, Some(0)) => {
                diags.error(dspan, "a pattern's duration must be longer than 0");
                None
            }
            (Tok::Number, Some(ms)) => Some(ms),
            _ => {
                diags.error(dspan, format!("`{text}` is not a duration: write e.g. `10s`, `500ms`, `2min`, `1h`"));
                None
            }
        }
    };
    if for_ < then {
        // WHENEVER a FOR d THEN b
        let a = formula(1, for_, "the condition after `WHENEVER`", diags);
        let ms = duration(for_ + 1, diags);
        if for_ + 2 != then {
            let at = toks.get(for_ + 2).map_or(span, |t| t.1);
            diags.error(at, "expected `THEN` after the duration").with_note(usage);
            return None;
        }
        let b = formula(then + 1, toks.len(), "the reaction after `THEN`", diags);
        return Some(Line::Pattern { pattern: Pattern::After, a: a?, b: b?, c: None, ms: ms?, span });
    }
    let a = formula(1, then, "the condition after `WHENEVER`", diags);
    let (b, c, pattern) = match until {
        Some(u) => (
            formula(then + 1, u, "the reaction after `THEN`", diags),
            formula(u + 1, for_, "the condition after `UNTIL`", diags).map(Some),
            Pattern::UntilHeld,
        ),
        None => (formula(then + 1, for_, "the reaction after `THEN`", diags), Some(None), Pattern::HoldFor),
    };
    let ms = duration(for_ + 1, diags);
    if let Some(&(_, extra)) = toks.get(for_ + 2) {
        diags.error(extra, format!("unexpected `{}` after the duration", &src[extra.range()])).with_note(usage);
        return None;
    }
    Some(Line::Pattern { pattern, a: a?, b: b?, c: c?, ms: ms?, span })
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
    let mut numeric_ids: HashMap<String, NumericId> = HashMap::new();
    let mut declare =
        |spec: &mut Spec, diags: &mut Diagnostics, name: &str, kind, span: Span, ty: Option<&NumberType>| {
            let prior = match (ids.get(name), numeric_ids.get(name)) {
                (Some(&s), _) => Some(spec.signal(s).span),
                (None, Some(&n)) => Some(spec.numeric[n.0 as usize].span),
                (None, None) => None,
            };
            if let Some(prior) = prior {
                let (line, col) = diags.line_col(prior.start as usize);
                diags
                    .error(span, format!("`{name}` is declared twice"))
                    .with_note(format!("first declared at {line}:{col}"));
                return None;
            }
            if let Some(ty) = ty {
                numeric_ids.insert(name.to_string(), NumericId(spec.numeric.len() as u32));
                spec.numeric.push(NumericInput {
                    name: name.to_string(),
                    kind: ty.kind,
                    lo: ty.lo.clone(),
                    hi: ty.hi.clone(),
                    span,
                });
                return None;
            }
            let id = SignalId(spec.signals.len() as u32);
            spec.signals.push(Signal { name: name.to_string(), kind, span });
            ids.insert(name.to_string(), id);
            Some(id)
        };
    for line in lines {
        if let Line::Declare { kind, names } = line {
            for (span, ty) in names {
                let span = *span;
                let name = &src[span.range()];
                if word_operator(name).is_some()
                    || KEYWORDS.contains(&name)
                    || matches!(name, "true" | "false" | "TRUE" | "FALSE" | "REAL" | "INT")
                {
                    diags.error(span, format!("`{name}` is an operator or keyword of the language; rename the signal"));
                } else if name.contains('.') {
                    diags
                        .error(span, format!("`{name}`: signal names have no `.`"))
                        .with_note("`t.start` and `t.expire` come from a `TIMER t(…)` declaration");
                } else if let Some(ty) = ty {
                    if check_bounds(ty, diags) {
                        declare(&mut spec, diags, name, *kind, span, Some(ty));
                    }
                } else {
                    declare(&mut spec, diags, name, *kind, span, None);
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
                let start = declare(&mut spec, diags, &format!("{name}.start"), SignalKind::Output, span, None);
                let expire = declare(&mut spec, diags, &format!("{name}.expire"), SignalKind::Input, span, None);
                if let (Some(start), Some(expire)) = (start, expire) {
                    spec.timers.push(Timer { name: name.to_string(), preset_ms, start, expire, span });
                }
            }
        }
    }
    // Each pattern gets a timer of its own: `w1`, `w2`, … (a name no declared timer has).
    let mut pattern_timers = Vec::new();
    for line in lines {
        if let Line::Pattern { ms, span, .. } = line {
            let taken = |name: &str| spec.timers.iter().any(|t| t.name == name) || spec.signal_id(name).is_some();
            let name = (1..).map(|n| format!("w{n}")).find(|n| !taken(n)).expect("a free name");
            let start = declare(&mut spec, diags, &format!("{name}.start"), SignalKind::Output, *span, None);
            let expire = declare(&mut spec, diags, &format!("{name}.expire"), SignalKind::Input, *span, None);
            let (Some(start), Some(expire)) = (start, expire) else { continue };
            pattern_timers.push(spec.timers.len());
            spec.timers.push(Timer { name, preset_ms: *ms, start, expire, span: *span });
        }
    }
    let mut uses = Uses {
        signals: vec![false; spec.signals.len()],
        numeric: vec![false; spec.numeric.len()],
        predicates: Vec::new(),
        base: spec.signals.len() as u32,
    };
    let mut next_pattern_timer = pattern_timers.into_iter();
    for line in lines {
        if let Line::Pattern { pattern, a, b, c, span, .. } = line {
            let Some(timer) = next_pattern_timer.next() else { continue };
            let (a, b) = (to_ltl(src, a, &spec, &mut uses, diags), to_ltl(src, b, &spec, &mut uses, diags));
            let c = c.as_ref().map(|c| to_ltl(src, c, &spec, &mut uses, diags));
            let (Some(a), Some(b)) = (a, b) else { continue };
            let c = match c {
                Some(None) => continue,
                Some(Some(c)) => Some(c),
                None => None,
            };
            let formula = expand_pattern(*pattern, a, b, c, &spec.timers[timer]);
            if formula.depth() > MAX_FORMULA_DEPTH {
                diags.error(*span, format!("the formula nests deeper than {MAX_FORMULA_DEPTH} levels"));
                continue;
            }
            spec.guarantees.push(Clause { formula, span: *span });
        }
        if let Line::Formula { assume, expr, span } = line {
            let Some(formula) = to_ltl(src, expr, &spec, &mut uses, diags) else { continue };
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
    // The timer abstraction of section 2, corrected for restarts (`refine`): a timer expires
    // some scans after a start unless it is started again first. What else a real timer does is
    // learned from counter-strategies.
    for timer in &spec.timers {
        let formula = super::refine::timer_liveness(timer);
        spec.assumptions.push(Clause { formula, span: timer.span });
        uses.signals[timer.start.index()] = true;
        uses.signals[timer.expire.index()] = true;
    }
    for (signal, used) in spec.signals.iter().zip(&uses.signals) {
        if !used {
            diags.warning(signal.span, format!("`{}` is declared but no formula uses it", signal.name));
        }
    }
    for (input, used) in spec.numeric.iter().zip(&uses.numeric) {
        if !used {
            diags.warning(input.span, format!("`{}` is declared but no formula uses it", input.name));
        }
    }
    // Each predicate becomes a Boolean input `p0`, `p1`, … (a name nothing else has).
    let mut next = 0;
    for (lhs, relation, rhs, span) in uses.predicates {
        let taken = |n: &str| spec.signal_id(n).is_some() || spec.numeric.iter().any(|x| x.name == n);
        let name = loop {
            let name = format!("p{next}");
            next += 1;
            if !taken(&name) {
                break name;
            }
        };
        let signal = SignalId(spec.signals.len() as u32);
        spec.signals.push(Signal { name, kind: SignalKind::Input, span });
        spec.predicates.push(Predicate { signal, lhs, relation, rhs, span });
    }
    spec
}

/// The encoding of a table-1 pattern with its timer (start `s`, expiry `e`); the timer model
/// is that of `refine` (a start restarts it).
fn expand_pattern(pattern: Pattern, a: Ltl, b: Ltl, c: Option<Ltl>, timer: &Timer) -> Ltl {
    let (s, e) = (Ltl::Var(timer.start), Ltl::Var(timer.expire));
    // The timer starts exactly when `x` rises (in the first step if `x` holds there).
    let started_on_rise = |x: Ltl| {
        Ltl::And(vec![
            Ltl::iff(s.clone(), x.clone()),
            Ltl::globally(Ltl::iff(Ltl::next(s.clone()), Ltl::And(vec![Ltl::not(x.clone()), Ltl::next(x)]))),
        ])
    };
    // Has `x` held since its last rise for the timer's preset? (In the scan of the rise the timer
    // still shows the previous run, hence `!s`.)
    let held = |x: Ltl| Ltl::And(vec![x, e.clone(), Ltl::not(s.clone())]);
    match pattern {
        Pattern::HoldFor => Ltl::globally(Ltl::implies(
            a,
            Ltl::And(vec![b.clone(), s.clone(), Ltl::next(Ltl::weak_until(b, e.clone()))]),
        )),
        Pattern::After => Ltl::And(vec![started_on_rise(a.clone()), Ltl::globally(Ltl::implies(held(a), b))]),
        Pattern::UntilHeld => {
            let c = c.expect("an UNTIL pattern has its condition");
            Ltl::And(vec![started_on_rise(c.clone()), Ltl::globally(Ltl::implies(a, Ltl::weak_until(b, held(c))))])
        }
    }
}

/// What the formulas use: signals and numeric inputs (for the warnings), and the predicates
/// met so far, each to become the Boolean input `base + its index`.
struct Uses {
    signals: Vec<bool>,
    numeric: Vec<bool>,
    predicates: Vec<(NumExpr, Relation, NumExpr, Span)>,
    base: u32,
}

/// An arithmetic expression over numeric inputs (`None`: reported).
fn to_num(src: &str, expr: &Expr, spec: &Spec, uses: &mut Uses, diags: &mut Diagnostics) -> Option<NumExpr> {
    let numeric = |e: &Expr| matches!(e, Expr::Number(_));
    Some(match expr {
        Expr::Number(span) => {
            let text = &src[span.range()];
            if text.parse::<f64>().map_or(true, |v| !v.is_finite()) || text.ends_with(|c: char| c.is_ascii_alphabetic())
            {
                diags.error(*span, format!("`{text}` is not a number"));
                return None;
            }
            NumExpr::Const(text.to_string())
        }
        Expr::Name(span) => {
            let name = &src[span.range()];
            match spec.numeric.iter().position(|n| n.name == name) {
                Some(i) => {
                    uses.numeric[i] = true;
                    NumExpr::Var(NumericId(i as u32))
                }
                None if spec.signal_id(name).is_some() => {
                    diags.error(*span, format!("`{name}` is a Boolean signal, not a number"));
                    return None;
                }
                None => {
                    diags
                        .error(*span, format!("`{name}` is not declared"))
                        .with_note(format!("declare a numeric input with `INPUT {name}: REAL[0, 10]`"));
                    return None;
                }
            }
        }
        Expr::Neg(a) => NumExpr::Neg(Box::new(to_num(src, a, spec, uses, diags)?)),
        Expr::Arith(op, a, b) => {
            let (x, y) = (to_num(src, a, spec, uses, diags), to_num(src, b, spec, uses, diags));
            let (x, y) = (Box::new(x?), Box::new(y?));
            match op {
                ArithOp::Add => NumExpr::Add(x, y),
                ArithOp::Sub => NumExpr::Sub(x, y),
                ArithOp::Mul => NumExpr::Mul(x, y),
                ArithOp::Div if numeric(b) || matches!(**b, Expr::Neg(ref n) if numeric(n)) => {
                    if y.as_ref() == &NumExpr::Const("0".into())
                        || matches!(&*y, NumExpr::Const(t) if t.parse::<f64>() == Ok(0.0))
                    {
                        diags.error(span_of(b), "division by zero");
                        return None;
                    }
                    NumExpr::Div(x, y)
                }
                ArithOp::Div => {
                    diags.error(span_of(b), "only division by a number is supported").with_note(
                        "predicates are polynomials: multiply out, e.g. `x > 2 * y` for `x / y > 2` with y > 0",
                    );
                    return None;
                }
            }
        }
        Expr::Pow(a, exponent) => {
            let n: u32 = match src[exponent.range()].parse() {
                Ok(n) if n <= 16 => n,
                _ => {
                    diags.error(*exponent, "exponents go up to 16");
                    return None;
                }
            };
            NumExpr::Pow(Box::new(to_num(src, a, spec, uses, diags)?), n)
        }
        _ => {
            diags.error(span_of(expr), "expected an arithmetic expression over numeric inputs here");
            return None;
        }
    })
}

/// Where a parsed expression starts (for diagnostics on arithmetic operands).
fn span_of(expr: &Expr) -> Span {
    match expr {
        Expr::Name(s) | Expr::Number(s) | Expr::Compare(.., s) => *s,
        Expr::Neg(a) | Expr::Arith(_, a, _) | Expr::Pow(a, _) | Expr::Not(a) | Expr::Unary(_, a) => span_of(a),
        Expr::Binary(_, a, _) => span_of(a),
        Expr::Many(_, parts) => parts.first().map_or_else(Span::default, span_of),
        Expr::Const(_) => Span::default(),
    }
}

fn to_ltl(src: &str, expr: &Expr, spec: &Spec, uses: &mut Uses, diags: &mut Diagnostics) -> Option<Ltl> {
    let used = &mut uses.signals;
    Some(match expr {
        Expr::Compare(relation, a, b, span) => {
            let (x, y) = (to_num(src, a, spec, uses, diags), to_num(src, b, spec, uses, diags));
            let (x, y) = (x?, y?);
            let key = (x, *relation, y);
            let index = match uses.predicates.iter().position(|(l, r, h, _)| (l, r, h) == (&key.0, &key.1, &key.2)) {
                Some(i) => i,
                None => {
                    uses.predicates.push((key.0, key.1, key.2, *span));
                    uses.predicates.len() - 1
                }
            };
            Ltl::Var(SignalId(uses.base + index as u32))
        }
        Expr::Number(span) | Expr::Pow(_, span) => {
            diags.error(*span, "a number is not a formula: compare it, as in `x > 3`");
            return None;
        }
        Expr::Neg(_) | Expr::Arith(..) => {
            diags.error(span_of(expr), "an arithmetic expression is not a formula: compare it, as in `x + y > 3`");
            return None;
        }
        Expr::Const(true) => Ltl::True,
        Expr::Const(false) => Ltl::False,
        Expr::Name(span) => {
            let name = &src[span.range()];
            match spec.signal_id(name) {
                Some(id) => {
                    used[id.index()] = true;
                    Ltl::Var(id)
                }
                None if spec.numeric.iter().any(|n| n.name == name) => {
                    diags
                        .error(*span, format!("`{name}` is a number, not a formula"))
                        .with_note(format!("compare it, as in `{name} > 3`"));
                    return None;
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
        Expr::Not(a) => Ltl::not(to_ltl(src, a, spec, uses, diags)?),
        Expr::Unary(op, a) => {
            let a = to_ltl(src, a, spec, uses, diags)?;
            match op {
                Op::Globally => Ltl::globally(a),
                Op::Finally => Ltl::finally(a),
                _ => Ltl::next(a),
            }
        }
        Expr::Many(bin, parts) => {
            // Every part is checked, so that every unknown name is reported.
            let parts: Vec<Option<Ltl>> = parts.iter().map(|p| to_ltl(src, p, spec, uses, diags)).collect();
            let parts: Vec<Ltl> = parts.into_iter().collect::<Option<_>>()?;
            if *bin == Bin::And {
                Ltl::And(parts)
            } else {
                Ltl::Or(parts)
            }
        }
        Expr::Binary(bin, a, b) => {
            // Both sides are checked, so that every unknown name is reported.
            let a = to_ltl(src, a, spec, uses, diags);
            let b = to_ltl(src, b, spec, uses, diags);
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
        assert_eq!(spec.formula_text(), "G (t1.start -> X F (t1.expire || t1.start)) -> G (req -> t1.start)");
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
