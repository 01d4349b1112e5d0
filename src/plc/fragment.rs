//! Structured Text fragments that users write into specifications: the trigger conditions and
//! the action code of `.sct` events (Göbe 2019, 6.3.1). They are parsed, not pasted, so that a
//! mistake is a located error when the specification is read, and each back end can print them
//! in its own dialect (or refuse, located, what it cannot express).
//!
//! The language is a subset of IEC 61131-3 ST: Boolean, comparison and arithmetic expressions
//! over variables (dotted names), direct addresses (`%IX0.1`, `%Q4.0`, `%MW10`) and literals
//! (`TRUE`, integers in any base, reals, `T#…` durations) — no `**`, which not every dialect
//! has — with the SynTACS macros
//! `\var{name}` (a global variable of the controller) and `\last{name}` (a signal's value in the
//! previous cycle); statements are assignments and `IF … THEN … ELSIF … ELSE … END_IF`.
//! Keywords are case-insensitive; `(* … *)` and `//` comments are skipped.

use crate::diag::Span;
use logos::Logos;
use std::fmt;

#[derive(Logos, Clone, Copy, Debug, PartialEq, Eq)]
#[logos(skip r"[ \t\r\n\f]+")]
#[logos(skip(r"//[^\n]*", allow_greedy = true))]
#[logos(skip r"\(\*([^*]|\*+[^*)])*\*+\)")]
enum Tok {
    #[token("AND", ignore(case))]
    #[token("&")]
    And,
    #[token("OR", ignore(case))]
    Or,
    #[token("XOR", ignore(case))]
    Xor,
    #[token("NOT", ignore(case))]
    Not,
    #[token("MOD", ignore(case))]
    Mod,
    #[token("TRUE", ignore(case))]
    True,
    #[token("FALSE", ignore(case))]
    False,
    #[token("IF", ignore(case))]
    If,
    #[token("THEN", ignore(case))]
    Then,
    #[token("ELSIF", ignore(case))]
    Elsif,
    #[token("ELSE", ignore(case))]
    Else,
    #[token("END_IF", ignore(case))]
    EndIf,
    #[regex(r"[A-Za-z_][A-Za-z0-9_]*")]
    Ident,
    #[regex(r"%[IQMiqm][XBWDLxbwdl]?[0-9]+(\.[0-9]+)?")]
    Address,
    #[regex(r"[0-9][0-9_]*")]
    #[regex(r"(2|8|16)#[0-9A-Fa-f_]+")]
    Int,
    #[regex(r"[0-9][0-9_]*\.[0-9][0-9_]*([eE][+-]?[0-9]+)?")]
    Real,
    #[regex(r"(?i)(t|time)#[-+]?[0-9a-z_.]+")]
    Time,
    #[regex(r"\\var\{[A-Za-z_][A-Za-z0-9_.]*\}")]
    VarMacro,
    #[regex(r"\\last\{[%A-Za-z_][A-Za-z0-9_.]*\}")]
    LastMacro,
    #[token(":=")]
    Assign,
    #[token("(")]
    LParen,
    #[token(")")]
    RParen,
    #[token(";")]
    Semi,
    #[token(".")]
    Dot,
    #[token("=")]
    Eq,
    #[token("<>")]
    Ne,
    #[token("<")]
    Lt,
    #[token("<=")]
    Le,
    #[token(">")]
    Gt,
    #[token(">=")]
    Ge,
    #[token("+")]
    Plus,
    #[token("-")]
    Minus,
    #[token("*")]
    Star,
    #[token("/")]
    Slash,
    #[token("**")]
    Pow,
    Eof,
}

/// A located mistake in a fragment; the span is relative to the fragment's text.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct FragmentError {
    pub span: Span,
    pub message: String,
}

/// Binary operators, loosest first within [`BinOp::precedence`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BinOp {
    Or,
    Xor,
    And,
    Eq,
    Ne,
    Lt,
    Le,
    Gt,
    Ge,
    Add,
    Sub,
    Mul,
    Div,
    Mod,
}

impl BinOp {
    /// IEC 61131-3 precedence (table 71), higher binds tighter.
    pub fn precedence(self) -> u8 {
        match self {
            BinOp::Or => 1,
            BinOp::Xor => 2,
            BinOp::And => 3,
            BinOp::Eq | BinOp::Ne => 4,
            BinOp::Lt | BinOp::Le | BinOp::Gt | BinOp::Ge => 5,
            BinOp::Add | BinOp::Sub => 6,
            BinOp::Mul | BinOp::Div | BinOp::Mod => 7,
        }
    }

    pub fn text(self) -> &'static str {
        match self {
            BinOp::Or => "OR",
            BinOp::Xor => "XOR",
            BinOp::And => "AND",
            BinOp::Eq => "=",
            BinOp::Ne => "<>",
            BinOp::Lt => "<",
            BinOp::Le => "<=",
            BinOp::Gt => ">",
            BinOp::Ge => ">=",
            BinOp::Add => "+",
            BinOp::Sub => "-",
            BinOp::Mul => "*",
            BinOp::Div => "/",
            BinOp::Mod => "MOD",
        }
    }
}

/// Unary operators (precedence 8, above every binary operator).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum UnOp {
    Not,
    Neg,
}

const UNARY_PRECEDENCE: u8 = 8;

#[derive(Clone, Debug, PartialEq, Eq)]
pub enum ExprKind {
    Bool(bool),
    /// An integer literal as written (`42`, `16#FF`).
    Int(String),
    /// A real literal as written.
    Real(String),
    /// A duration literal as written (`T#1s500ms`).
    Time(String),
    /// A variable: a name, or a dotted path into a structure or instance.
    Var(Vec<String>),
    /// A direct address as written (`%IX0.1`).
    Address(String),
    /// `\var{name}`: a global variable of the controller.
    ControllerVar(String),
    /// `\last{name}`: the value of a signal in the previous cycle.
    Last(String),
    Unary(UnOp, Box<Expr>),
    Binary(BinOp, Box<Expr>, Box<Expr>),
}

/// An expression with the span of its text in the fragment.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Expr {
    pub kind: ExprKind,
    pub span: Span,
}

#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Stmt {
    /// `target := value;` — the target is a variable, an address or `\var{…}`.
    Assign { target: Expr, value: Expr },
    /// `IF c1 THEN … ELSIF c2 THEN … ELSE … END_IF;`
    If { arms: Vec<(Expr, Vec<Stmt>)>, otherwise: Vec<Stmt> },
}

struct Parser<'s> {
    src: &'s str,
    toks: Vec<(Tok, Span)>,
    pos: usize,
    depth: usize,
}

/// How deeply parentheses, `NOT`s and `IF`s may nest (a fragment is a line or two; the bound
/// keeps the recursive parser far from the stack limit of a wasm worker).
const MAX_NESTING: usize = 64;

type PResult<T> = Result<T, FragmentError>;

impl<'s> Parser<'s> {
    fn new(src: &'s str) -> PResult<Parser<'s>> {
        let mut toks = Vec::new();
        let mut lex = Tok::lexer(src);
        while let Some(t) = lex.next() {
            let r = lex.span();
            let span = Span::new(r.start, r.end);
            match t {
                Ok(t) => toks.push((t, span)),
                Err(()) => {
                    let c = src[r.start..].chars().next().unwrap_or('?');
                    return Err(FragmentError { span, message: format!("unexpected character `{c}`") });
                }
            }
        }
        toks.push((Tok::Eof, Span::new(src.len(), src.len())));
        Ok(Parser { src, toks, pos: 0, depth: 0 })
    }

    fn peek(&self) -> Tok {
        self.toks[self.pos].0
    }

    fn span(&self) -> Span {
        self.toks[self.pos].1
    }

    fn bump(&mut self) -> (Tok, Span) {
        let t = self.toks[self.pos];
        if t.0 != Tok::Eof {
            self.pos += 1;
        }
        t
    }

    fn text(&self, span: Span) -> &'s str {
        &self.src[span.range()]
    }

    fn error<T>(&self, message: impl Into<String>) -> PResult<T> {
        let span = self.span();
        let found = if self.peek() == Tok::Eof { "the end".to_string() } else { format!("`{}`", self.text(span)) };
        Err(FragmentError { span, message: format!("{}, found {found}", message.into()) })
    }

    fn expect(&mut self, t: Tok, what: &str) -> PResult<Span> {
        if self.peek() == t {
            Ok(self.bump().1)
        } else {
            self.error(format!("expected {what}"))
        }
    }

    fn nest(&mut self) -> PResult<()> {
        self.depth += 1;
        if self.depth > MAX_NESTING {
            return Err(FragmentError {
                span: self.span(),
                message: format!("nested more than {MAX_NESTING} levels deep"),
            });
        }
        Ok(())
    }

    fn binop(t: Tok) -> Option<BinOp> {
        Some(match t {
            Tok::Or => BinOp::Or,
            Tok::Xor => BinOp::Xor,
            Tok::And => BinOp::And,
            Tok::Eq => BinOp::Eq,
            Tok::Ne => BinOp::Ne,
            Tok::Lt => BinOp::Lt,
            Tok::Le => BinOp::Le,
            Tok::Gt => BinOp::Gt,
            Tok::Ge => BinOp::Ge,
            Tok::Plus => BinOp::Add,
            Tok::Minus => BinOp::Sub,
            Tok::Star => BinOp::Mul,
            Tok::Slash => BinOp::Div,
            Tok::Mod => BinOp::Mod,
            _ => return None,
        })
    }

    /// Precedence climbing over the binary operators; all are left-associative.
    fn expr(&mut self, min: u8) -> PResult<Expr> {
        let mut lhs = self.unary()?;
        if self.peek() == Tok::Pow {
            // Not every dialect has it (TwinCAT and blark write `EXPT`), and triggers do not need it.
            return self.error("`**` (power) is not part of the fragment language; expected an operator");
        }
        while let Some(op) = Self::binop(self.peek()) {
            if op.precedence() < min {
                break;
            }
            self.bump();
            let rhs = self.expr(op.precedence() + 1)?;
            let span = Span::new(lhs.span.start as usize, rhs.span.end as usize);
            lhs = Expr { kind: ExprKind::Binary(op, Box::new(lhs), Box::new(rhs)), span };
        }
        Ok(lhs)
    }

    fn unary(&mut self) -> PResult<Expr> {
        let op = match self.peek() {
            Tok::Not => UnOp::Not,
            Tok::Minus => UnOp::Neg,
            _ => return self.primary(),
        };
        let start = self.bump().1.start as usize;
        self.nest()?;
        // `NOT a AND b` is `(NOT a) AND b`: the operand binds tighter than every binary
        // operator.
        let operand = self.expr(UNARY_PRECEDENCE + 1)?;
        self.depth -= 1;
        let span = Span::new(start, operand.span.end as usize);
        Ok(Expr { kind: ExprKind::Unary(op, Box::new(operand)), span })
    }

    fn primary(&mut self) -> PResult<Expr> {
        let (t, span) = (self.peek(), self.span());
        let text = self.text(span);
        let kind = match t {
            Tok::True => ExprKind::Bool(true),
            Tok::False => ExprKind::Bool(false),
            Tok::Int => ExprKind::Int(text.to_string()),
            Tok::Real => ExprKind::Real(text.to_string()),
            Tok::Time => ExprKind::Time(text.to_string()),
            Tok::Address => ExprKind::Address(text.to_ascii_uppercase()),
            Tok::VarMacro => ExprKind::ControllerVar(text["\\var{".len()..text.len() - 1].to_string()),
            Tok::LastMacro => ExprKind::Last(text["\\last{".len()..text.len() - 1].to_string()),
            Tok::LParen => {
                self.bump();
                self.nest()?;
                let inner = self.expr(0)?;
                self.depth -= 1;
                let end = self.expect(Tok::RParen, "`)`")?;
                // Parentheses leave no node: printing puts back those the precedences need.
                return Ok(Expr { kind: inner.kind, span: Span::new(span.start as usize, end.end as usize) });
            }
            Tok::Ident => {
                self.bump();
                let mut parts = vec![text.to_string()];
                let mut end = span.end as usize;
                while self.peek() == Tok::Dot {
                    self.bump();
                    let s = self.expect(Tok::Ident, "a name after `.`")?;
                    parts.push(self.text(s).to_string());
                    end = s.end as usize;
                }
                return Ok(Expr { kind: ExprKind::Var(parts), span: Span::new(span.start as usize, end) });
            }
            _ => return self.error("expected an operand (a name, an address, a literal or `(`)"),
        };
        self.bump();
        Ok(Expr { kind, span })
    }

    fn statements(&mut self, until: &[Tok]) -> PResult<Vec<Stmt>> {
        let mut out = Vec::new();
        while !until.contains(&self.peek()) {
            if self.peek() == Tok::Semi {
                self.bump(); // an empty statement
                continue;
            }
            out.push(self.statement()?);
        }
        Ok(out)
    }

    fn statement(&mut self) -> PResult<Stmt> {
        if self.peek() == Tok::If {
            self.bump();
            self.nest()?;
            let mut arms = Vec::new();
            let cond = self.expr(0)?;
            self.expect(Tok::Then, "`THEN`")?;
            let body = self.statements(&[Tok::Elsif, Tok::Else, Tok::EndIf, Tok::Eof])?;
            arms.push((cond, body));
            let mut otherwise = Vec::new();
            loop {
                match self.peek() {
                    Tok::Elsif => {
                        self.bump();
                        let cond = self.expr(0)?;
                        self.expect(Tok::Then, "`THEN`")?;
                        let body = self.statements(&[Tok::Elsif, Tok::Else, Tok::EndIf, Tok::Eof])?;
                        arms.push((cond, body));
                    }
                    Tok::Else => {
                        self.bump();
                        otherwise = self.statements(&[Tok::EndIf, Tok::Eof])?;
                    }
                    _ => break,
                }
            }
            self.expect(Tok::EndIf, "`END_IF`")?;
            self.expect(Tok::Semi, "`;` after `END_IF`")?;
            self.depth -= 1;
            return Ok(Stmt::If { arms, otherwise });
        }
        let target = self.primary()?;
        if !matches!(target.kind, ExprKind::Var(_) | ExprKind::Address(_) | ExprKind::ControllerVar(_)) {
            return Err(FragmentError {
                span: target.span,
                message: "only a variable, an address or `\\var{…}` can be assigned".into(),
            });
        }
        self.expect(Tok::Assign, "`:=`")?;
        let value = self.expr(0)?;
        self.expect(Tok::Semi, "`;`")?;
        Ok(Stmt::Assign { target, value })
    }
}

/// Parses a trigger condition: one expression.
pub fn parse_expr(src: &str) -> Result<Expr, FragmentError> {
    let mut p = Parser::new(src)?;
    if p.peek() == Tok::Eof {
        return p.error("expected a condition");
    }
    let e = p.expr(0)?;
    if p.peek() != Tok::Eof {
        return p.error("expected an operator or the end of the condition");
    }
    Ok(e)
}

/// Parses action code: a sequence of statements.
pub fn parse_statements(src: &str) -> Result<Vec<Stmt>, FragmentError> {
    let mut p = Parser::new(src)?;
    let out = p.statements(&[Tok::Eof])?;
    if out.is_empty() {
        return p.error("expected a statement");
    }
    Ok(out)
}

impl Expr {
    /// Writes the expression with the parentheses its precedences need (none for `min == 0`
    /// at the top).
    fn write(&self, f: &mut fmt::Formatter<'_>, min: u8) -> fmt::Result {
        match &self.kind {
            ExprKind::Bool(b) => f.write_str(if *b { "TRUE" } else { "FALSE" }),
            ExprKind::Int(t) | ExprKind::Real(t) | ExprKind::Time(t) | ExprKind::Address(t) => f.write_str(t),
            ExprKind::Var(parts) => f.write_str(&parts.join(".")),
            ExprKind::ControllerVar(name) => write!(f, "\\var{{{name}}}"),
            ExprKind::Last(name) => write!(f, "\\last{{{name}}}"),
            ExprKind::Unary(op, e) => {
                let paren = min > UNARY_PRECEDENCE;
                if paren {
                    f.write_str("(")?;
                }
                f.write_str(match op {
                    UnOp::Not => "NOT ",
                    UnOp::Neg => "-",
                })?;
                // IEC 61131-3 allows one unary operator before a primary expression: a nested
                // one is parenthesised (`NOT (NOT a)`, `-(-x)`).
                e.write(f, UNARY_PRECEDENCE + 1)?;
                if paren {
                    f.write_str(")")?;
                }
                Ok(())
            }
            ExprKind::Binary(op, a, b) => {
                let p = op.precedence();
                let paren = p < min;
                if paren {
                    f.write_str("(")?;
                }
                a.write(f, p)?;
                write!(f, " {} ", op.text())?;
                b.write(f, p + 1)?;
                if paren {
                    f.write_str(")")?;
                }
                Ok(())
            }
        }
    }
}

impl fmt::Display for Expr {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        self.write(f, 0)
    }
}

impl Stmt {
    fn write(&self, f: &mut fmt::Formatter<'_>, indent: usize) -> fmt::Result {
        let pad = "    ".repeat(indent);
        match self {
            Stmt::Assign { target, value } => writeln!(f, "{pad}{target} := {value};"),
            Stmt::If { arms, otherwise } => {
                for (k, (cond, body)) in arms.iter().enumerate() {
                    writeln!(f, "{pad}{} {cond} THEN", if k == 0 { "IF" } else { "ELSIF" })?;
                    for s in body {
                        s.write(f, indent + 1)?;
                    }
                }
                if !otherwise.is_empty() {
                    writeln!(f, "{pad}ELSE")?;
                    for s in otherwise {
                        s.write(f, indent + 1)?;
                    }
                }
                writeln!(f, "{pad}END_IF;")
            }
        }
    }
}

impl fmt::Display for Stmt {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        self.write(f, 0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn shape(src: &str) -> String {
        parse_expr(src).unwrap_or_else(|e| panic!("{src}: {e:?}")).to_string()
    }

    #[test]
    fn precedence_follows_iec_61131_3() {
        assert_eq!(shape("a OR b AND c"), "a OR b AND c");
        assert_eq!(shape("(a OR b) AND c"), "(a OR b) AND c");
        assert_eq!(shape("NOT a AND b"), "NOT a AND b");
        assert_eq!(shape("NOT (a AND b)"), "NOT (a AND b)");
        assert_eq!(shape("x + 1 > 2 * y = TRUE"), "x + 1 > 2 * y = TRUE");
        assert_eq!(shape("a - (b - c)"), "a - (b - c)");
        assert_eq!(shape("(a - b) - c"), "a - b - c");
        assert_eq!(shape("- -x"), "-(-x)");
        assert_eq!(shape("NOT NOT a"), "NOT (NOT a)");
        assert_eq!(shape("%ix0.1 & \\last{%IX0.1}"), "%IX0.1 AND \\last{%IX0.1}");
        assert_eq!(shape("t.ET >= T#1s500ms"), "t.ET >= T#1s500ms");
        assert_eq!(shape("level > 16#FF xor \\var{Ctrl.busy}"), "level > 16#FF XOR \\var{Ctrl.busy}");
    }

    #[test]
    fn statements_print_as_they_parse() {
        let src = "Q_Inlet := FALSE; if a then x := 1; elsif b then x := 2; else x := -x; end_if; ;";
        let stmts = parse_statements(src).unwrap();
        let text: String = stmts.iter().map(|s| s.to_string()).collect();
        assert_eq!(
            text,
            "Q_Inlet := FALSE;\nIF a THEN\n    x := 1;\nELSIF b THEN\n    x := 2;\nELSE\n    x := -x;\nEND_IF;\n"
        );
        let again: String = parse_statements(&text).unwrap().iter().map(|s| s.to_string()).collect();
        assert_eq!(again, text);
    }

    #[test]
    fn mistakes_are_located() {
        let cases: &[(&str, (usize, usize), &str)] = &[
            ("a AND", (5, 5), "expected an operand (a name, an address, a literal or `(`), found the end"),
            ("a b", (2, 3), "expected an operator or the end of the condition, found `b`"),
            ("(a OR b", (7, 7), "expected `)`, found the end"),
            ("a ? b", (2, 3), "unexpected character `?`"),
            ("", (0, 0), "expected a condition, found the end"),
        ];
        for (src, (start, end), message) in cases {
            let e = parse_expr(src).unwrap_err();
            assert_eq!(
                (e.span.start as usize, e.span.end as usize, e.message.as_str()),
                (*start, *end, *message),
                "{src}"
            );
        }
        let e = parse_statements("x = 1;").unwrap_err();
        assert_eq!((e.span.start, e.message.as_str()), (2, "expected `:=`, found `=`"));
        let e = parse_statements("TRUE := x;").unwrap_err();
        assert_eq!(e.message, "only a variable, an address or `\\var{…}` can be assigned");
        let e = parse_statements("IF a THEN x := 1;").unwrap_err();
        assert_eq!(e.message, "expected `END_IF`, found the end");
        let deep = format!("{}a{}", "(".repeat(10_000), ")".repeat(10_000));
        assert!(parse_expr(&deep).unwrap_err().message.contains("nested more than 64"));
        let nots = format!("{}a", "NOT ".repeat(10_000));
        assert!(parse_expr(&nots).unwrap_err().message.contains("nested more than 64"));
    }
}
