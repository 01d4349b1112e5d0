//! The TLSF parser: recursive descent over the three top-level blocks, a precedence climber for
//! expressions. It recovers at `;` and `}`, so every syntax error of a file is reported at once.
//!
//! Expressions follow SyfCo's operator table (tightest first): `SIZEOF SIZE MIN MAX SUM[..]
//! PROD[..]`; `*`; `/ %` (right); `+ -`; `SETMINUS` (right); `CAP`; `CUP`; comparisons; `IN`;
//! the prefix operators `! X G F X[n] F[a:b] G[a:b] &&[..] ||[..]`; `&&`; `||`; `-> <->`
//! (right); `W` (right); `U` (right); `R`. So `G a && b` is `(G a) && b`, and `a -> b U c` is
//! `(a -> b) U c`, as SyfCo reads it.

use super::lexer::{lex, Tok};
use crate::diag::{Diagnostics, Span};
use crate::syntax::Cursor;

/// Nesting of parentheses, prefix operators and right operands an expression may have. Deeper
/// input is reported instead of recursing further: the parser, the name check and the
/// evaluation all recurse on the tree, and the page runs them on a 1 MiB stack.
pub const MAX_NESTING: usize = 64;

#[derive(Clone, Debug)]
pub struct Expr {
    pub kind: ExprKind,
    pub span: Span,
}

#[derive(Clone, Debug)]
pub enum ExprKind {
    Number(i64),
    True,
    False,
    /// A guard that always holds (only meaningful before `:` in a definition).
    Otherwise,
    Name(String),
    /// `bus[index]`.
    Index {
        bus: String,
        bus_span: Span,
        index: Box<Expr>,
    },
    Call {
        name: String,
        name_span: Span,
        args: Vec<Expr>,
    },
    /// `{a, b, c}`.
    Set(Vec<Expr>),
    Unary(Unary, Box<Expr>),
    Binary(Binary, Box<Expr>, Box<Expr>),
    /// `a && b && c` (or `||`) written as one chain: one n-ary node, as the formula reads.
    Chain(Junction, Vec<Expr>),
    /// `X[count] body`.
    NextN {
        count: Box<Expr>,
        body: Box<Expr>,
    },
    /// `F[from:to] body`, `G[from:to] body`.
    Bounded {
        op: BoundedOp,
        from: Box<Expr>,
        to: Box<Expr>,
        body: Box<Expr>,
    },
    /// `&&[binders] body` and the other big operators.
    Big {
        op: BigOp,
        binders: Vec<Binder>,
        body: Box<Expr>,
    },
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Unary {
    Not,
    Next,
    Globally,
    Finally,
    SizeOf,
    Size,
    Min,
    Max,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Binary {
    Mul,
    Div,
    Mod,
    Add,
    Sub,
    SetMinus,
    Cap,
    Cup,
    Eq,
    Ne,
    Lt,
    Le,
    Gt,
    Ge,
    In,
    Implies,
    Iff,
    WeakUntil,
    Until,
    Release,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Junction {
    And,
    Or,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BoundedOp {
    Finally,
    Globally,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BigOp {
    And,
    Or,
    Sum,
    Prod,
}

/// One variable of a big operator: `from <= var < to` or `var IN set`.
#[derive(Clone, Debug)]
pub struct Binder {
    pub var: String,
    pub span: Span,
    pub domain: Domain,
}

#[derive(Clone, Debug)]
pub enum Domain {
    /// `from (<|<=) var (<|<=) to`; a strict bound excludes its end.
    Range {
        from: Expr,
        from_strict: bool,
        to: Expr,
        to_strict: bool,
    },
    Set(Expr),
}

/// `name(params) = cases;` in `DEFINITIONS` (a constant has no parameters).
#[derive(Clone, Debug)]
pub struct Definition {
    pub name: String,
    pub span: Span,
    pub params: Vec<(String, Span)>,
    pub cases: Vec<Case>,
}

/// One alternative of a definition: `guard : value`, or just `value` (always taken).
#[derive(Clone, Debug)]
pub struct Case {
    pub guard: Option<Expr>,
    pub value: Expr,
}

#[derive(Clone, Debug)]
pub struct Parameter {
    pub name: String,
    pub span: Span,
    pub value: Expr,
}

/// A declared signal: `r;` or the bus `r[width];`.
#[derive(Clone, Debug)]
pub struct SignalDecl {
    pub name: String,
    pub span: Span,
    pub width: Option<Expr>,
}

/// The formula sections of `MAIN`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Section {
    Initially,
    Preset,
    Require,
    Assume,
    Assert,
    Guarantee,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Turn {
    Mealy,
    Moore,
}

/// `SEMANTICS: Mealy`, `Moore,Strict`, …
#[derive(Clone, Copy, Debug)]
pub struct SemanticsDecl {
    pub turn: Turn,
    pub strict: bool,
}

/// A parsed TLSF file; parts that failed to parse are left out (and were reported).
#[derive(Clone, Debug, Default)]
pub struct Tlsf {
    pub title: Option<String>,
    pub semantics: Option<SemanticsDecl>,
    pub parameters: Vec<Parameter>,
    /// The `PARAMETERS` keyword, where an unknown override is reported.
    pub parameters_span: Option<Span>,
    pub definitions: Vec<Definition>,
    pub inputs: Vec<SignalDecl>,
    pub outputs: Vec<SignalDecl>,
    pub formulas: Vec<(Section, Expr)>,
    /// The `MAIN` keyword, where a combined formula is located.
    pub main_span: Option<Span>,
}

struct Parser<'s, 'd> {
    src: &'s str,
    cur: Cursor<Tok>,
    diags: &'d mut Diagnostics<'s>,
    /// Expression nesting at the parse position; see [`MAX_NESTING`].
    nesting: usize,
}

type PResult<T> = Result<T, ()>;

/// Parses a TLSF file; errors go to `diags`.
pub fn parse<'s>(src: &'s str, diags: &mut Diagnostics<'s>) -> Tlsf {
    let toks = lex(src, diags);
    let mut p = Parser { src, cur: Cursor::new(toks), diags, nesting: 0 };
    let mut tlsf = Tlsf::default();
    let mut seen: Vec<&str> = Vec::new();
    // One error per stretch of junk between blocks, not one per token.
    let mut in_junk = false;
    while !p.cur.at(Tok::Eof) {
        let word = if p.cur.at(Tok::Ident) { p.text() } else { "" };
        if matches!(word, "INFO" | "GLOBAL" | "MAIN") {
            in_junk = false;
            let span = p.cur.bump().1;
            if seen.contains(&word) {
                p.diags.error(span, format!("a second `{word}` block"));
            }
            seen.push(word);
            let _ = match word {
                "INFO" => p.info(&mut tlsf),
                "GLOBAL" => p.global(&mut tlsf),
                _ => {
                    tlsf.main_span.get_or_insert(span);
                    p.main(&mut tlsf)
                }
            };
            continue;
        }
        if !in_junk {
            let found = p.describe();
            let span = p.cur.span();
            p.diags.error(span, format!("expected `INFO`, `GLOBAL` or `MAIN`, found {found}"));
            in_junk = true;
        }
        if p.cur.at(Tok::LBrace) {
            p.skip_block();
        } else {
            p.cur.bump();
        }
    }
    if !seen.contains(&"MAIN") && !p.diags.has_errors() {
        let end = Span::new(src.len(), src.len());
        p.diags.error(end, "no `MAIN` block: a TLSF specification needs `MAIN { INPUTS { … } OUTPUTS { … } … }`");
    }
    tlsf
}

impl<'s> Parser<'s, '_> {
    fn text(&self) -> &'s str {
        &self.src[self.cur.span().range()]
    }

    fn is_word(&self, word: &str) -> bool {
        self.cur.at(Tok::Ident) && self.text() == word
    }

    fn describe(&self) -> String {
        match self.cur.peek() {
            Tok::Eof => "end of file".into(),
            _ => format!("`{}`", self.text()),
        }
    }

    fn err<T>(&mut self, expected: &str) -> PResult<T> {
        let span = self.cur.span();
        let found = self.describe();
        self.diags.error(span, format!("expected {expected}, found {found}"));
        Err(())
    }

    fn expect(&mut self, tok: Tok, what: &str) -> PResult<Span> {
        if self.cur.at(tok) {
            Ok(self.cur.bump().1)
        } else {
            self.err(what)
        }
    }

    fn ident(&mut self, what: &str) -> PResult<(String, Span)> {
        if self.cur.at(Tok::Ident) {
            let name = self.text().to_string();
            Ok((name, self.cur.bump().1))
        } else {
            self.err(what)
        }
    }

    /// Skips a balanced `{ … }` starting at the current `{`.
    fn skip_block(&mut self) {
        let mut depth = 0usize;
        loop {
            match self.cur.bump().0 {
                Tok::Eof => return,
                Tok::LBrace => depth += 1,
                Tok::RBrace => {
                    depth = depth.saturating_sub(1);
                    if depth == 0 {
                        return;
                    }
                }
                _ => {}
            }
        }
    }

    /// Skips the rest of a block entry: past the next `;` outside brackets, or up to the `}`
    /// that closes the block.
    fn skip_entry(&mut self) {
        let mut depth = 0usize;
        loop {
            match self.cur.peek() {
                Tok::Eof => return,
                Tok::Semi if depth == 0 => {
                    self.cur.bump();
                    return;
                }
                Tok::RBrace if depth == 0 => return,
                Tok::LBrace | Tok::LParen | Tok::LBracket => depth += 1,
                Tok::RBrace | Tok::RParen | Tok::RBracket => depth = depth.saturating_sub(1),
                _ => {}
            }
            self.cur.bump();
        }
    }

    /// `{ entry* }`: calls `entry` in front of each entry until the closing brace; an entry
    /// that fails is skipped up to its `;`.
    fn block(&mut self, mut entry: impl FnMut(&mut Self) -> PResult<()>) -> PResult<()> {
        let open = self.expect(Tok::LBrace, "`{`")?;
        loop {
            match self.cur.peek() {
                Tok::RBrace => {
                    self.cur.bump();
                    return Ok(());
                }
                Tok::Eof => {
                    self.diags.error(open, "unclosed `{`: the file ends before its `}`");
                    return Err(());
                }
                _ => {}
            }
            let before = self.cur.pos();
            if entry(self).is_err() {
                if self.cur.pos() == before && !self.cur.at(Tok::RBrace) {
                    self.cur.bump();
                }
                self.skip_entry();
            }
        }
    }

    /// `;`-separated entries (the last `;` may be left out), as SyfCo reads sections.
    fn entries(&mut self, mut entry: impl FnMut(&mut Self) -> PResult<()>) -> PResult<()> {
        self.block(|p| {
            if p.cur.at(Tok::Semi) {
                p.cur.bump();
                return Ok(());
            }
            entry(p)?;
            match p.cur.peek() {
                Tok::Semi => {
                    p.cur.bump();
                    Ok(())
                }
                Tok::RBrace => Ok(()),
                _ => {
                    let found = p.describe();
                    let end = p.cur.prev_end();
                    let at = Span::new(end, end);
                    p.diags.error(at, format!("expected `;` after this entry, found {found}"));
                    Err(())
                }
            }
        })
    }

    fn info(&mut self, tlsf: &mut Tlsf) -> PResult<()> {
        self.block(|p| {
            let (field, span) = p.ident("an INFO field (`TITLE:`, `SEMANTICS:`, …)")?;
            p.expect(Tok::Colon, "`:`")?;
            match field.as_str() {
                "TITLE" => tlsf.title = Some(p.string("the title in quotes")?),
                "DESCRIPTION" => {
                    p.string("the description in quotes")?;
                }
                "SEMANTICS" => tlsf.semantics = Some(p.semantics()?),
                "TARGET" => {
                    let (target, span) = p.ident("`Mealy` or `Moore`")?;
                    if target != "Mealy" && target != "Moore" {
                        p.diags.error(span, format!("unknown target `{target}`: expected `Mealy` or `Moore`"));
                    }
                }
                "TAGS" => {
                    p.string("a tag in quotes")?;
                    while p.cur.at(Tok::Comma) {
                        p.cur.bump();
                        p.string("a tag in quotes")?;
                    }
                }
                _ => {
                    p.diags.warning(span, format!("unknown INFO field `{field}` is ignored"));
                    // Its value runs up to the next `FIELD:` or the end of the block.
                    while !(matches!(p.cur.peek(), Tok::RBrace | Tok::Eof)
                        || p.cur.at(Tok::Ident) && p.cur.peek_at(1) == Tok::Colon)
                    {
                        p.cur.bump();
                    }
                }
            }
            Ok(())
        })
    }

    fn string(&mut self, what: &str) -> PResult<String> {
        if !self.cur.at(Tok::Str) {
            return self.err(what);
        }
        let text = self.text();
        self.cur.bump();
        Ok(text[1..text.len() - 1].replace("\\\"", "\"").replace("\\\\", "\\"))
    }

    /// `Mealy`, `Moore`, optionally with `Strict` before or after, separated by a comma.
    fn semantics(&mut self) -> PResult<SemanticsDecl> {
        let mut words = vec![self.ident("`Mealy` or `Moore`")?];
        if self.cur.at(Tok::Comma) {
            self.cur.bump();
            words.push(self.ident("`Strict`")?);
        }
        let turns: Vec<&(String, Span)> = words.iter().filter(|(w, _)| w == "Mealy" || w == "Moore").collect();
        let stricts = words.iter().filter(|(w, _)| w == "Strict").count();
        if let Some((word, span)) = words.iter().find(|(w, _)| !matches!(w.as_str(), "Mealy" | "Moore" | "Strict")) {
            let note = if word == "Finite" { "finite-trace (LTLf) semantics is not supported" } else { "" };
            let d = self.diags.error(
                *span,
                format!("unknown semantics `{word}`: expected `Mealy` or `Moore`, optionally with `Strict`"),
            );
            if !note.is_empty() {
                d.with_note(note);
            }
            return Err(());
        }
        if turns.len() != 1 || stricts > 1 {
            let span = words[0].1.to(words[words.len() - 1].1);
            self.diags.error(span, "expected one of `Mealy` and `Moore`, optionally with `Strict`");
            return Err(());
        }
        let turn = if turns[0].0 == "Mealy" { Turn::Mealy } else { Turn::Moore };
        Ok(SemanticsDecl { turn, strict: stricts == 1 })
    }

    fn global(&mut self, tlsf: &mut Tlsf) -> PResult<()> {
        self.block(|p| {
            let (word, span) = p.ident("`PARAMETERS` or `DEFINITIONS`")?;
            match word.as_str() {
                "PARAMETERS" => {
                    tlsf.parameters_span.get_or_insert(span);
                    p.entries(|p| {
                        let (name, span) = p.ident("a parameter name")?;
                        p.expect(Tok::Assign, "`=`")?;
                        let value = p.expr()?;
                        tlsf.parameters.push(Parameter { name, span, value });
                        Ok(())
                    })
                }
                "DEFINITIONS" => p.entries(|p| {
                    let definition = p.definition()?;
                    tlsf.definitions.push(definition);
                    Ok(())
                }),
                _ => {
                    p.diags.error(span, format!("expected `PARAMETERS` or `DEFINITIONS`, found `{word}`"));
                    if p.cur.at(Tok::LBrace) {
                        p.skip_block();
                    }
                    Ok(())
                }
            }
        })
    }

    fn definition(&mut self) -> PResult<Definition> {
        if self.is_word("enum") {
            let span = self.cur.span();
            self.diags.error(span, "`enum` definitions are not supported");
            return Err(());
        }
        let (name, span) = self.ident("a definition name")?;
        let mut params = Vec::new();
        if self.cur.at(Tok::LParen) {
            self.cur.bump();
            if !self.cur.at(Tok::RParen) {
                params.push(self.ident("a parameter name")?);
                while self.cur.at(Tok::Comma) {
                    self.cur.bump();
                    params.push(self.ident("a parameter name")?);
                }
            }
            self.expect(Tok::RParen, "`,` or `)`")?;
        }
        self.expect(Tok::Assign, "`=`")?;
        let mut cases = vec![self.case()?];
        // Guarded alternatives follow each other without separator, up to the `;`.
        while !matches!(self.cur.peek(), Tok::Semi | Tok::RBrace | Tok::Eof) {
            if cases[0].guard.is_none() {
                return self.err("`;`");
            }
            let case = self.case()?;
            if case.guard.is_none() {
                self.diags.error(case.value.span, "expected `guard : value` like the alternatives before");
                return Err(());
            }
            cases.push(case);
        }
        Ok(Definition { name, span, params, cases })
    }

    /// `guard : value` or a plain value.
    fn case(&mut self) -> PResult<Case> {
        let first = self.expr()?;
        if !self.cur.at(Tok::Colon) {
            return Ok(Case { guard: None, value: first });
        }
        self.cur.bump();
        let value = self.expr()?;
        Ok(Case { guard: Some(first), value })
    }

    fn main(&mut self, tlsf: &mut Tlsf) -> PResult<()> {
        self.block(|p| {
            let (word, span) = p.ident("a section (`INPUTS`, `OUTPUTS`, `GUARANTEES`, …)")?;
            let section = match word.as_str() {
                "INPUTS" | "OUTPUTS" => {
                    let input = word == "INPUTS";
                    return p.entries(|p| {
                        let decl = p.signal()?;
                        (if input { &mut tlsf.inputs } else { &mut tlsf.outputs }).push(decl);
                        Ok(())
                    });
                }
                "INITIALLY" => Section::Initially,
                "PRESET" => Section::Preset,
                "REQUIRE" | "REQUIREMENTS" => Section::Require,
                "ASSUME" | "ASSUMPTIONS" => Section::Assume,
                "ASSERT" | "INVARIANTS" => Section::Assert,
                "GUARANTEE" | "GUARANTEES" => Section::Guarantee,
                _ => {
                    p.diags.error(span, format!("unknown section `{word}`")).with_note(
                        "MAIN holds INPUTS, OUTPUTS, INITIALLY, PRESET, REQUIRE, ASSUME (ASSUMPTIONS), \
                         ASSERT (INVARIANTS) and GUARANTEE (GUARANTEES)",
                    );
                    if p.cur.at(Tok::LBrace) {
                        p.skip_block();
                    }
                    return Ok(());
                }
            };
            p.entries(|p| {
                let formula = p.expr()?;
                tlsf.formulas.push((section, formula));
                Ok(())
            })
        })
    }

    fn signal(&mut self) -> PResult<SignalDecl> {
        let (name, span) = self.ident("a signal name")?;
        let mut width = None;
        if self.cur.at(Tok::LBracket) {
            self.cur.bump();
            width = Some(self.expr()?);
            self.expect(Tok::RBracket, "`]`")?;
        }
        Ok(SignalDecl { name, span, width })
    }

    /// A whole expression (guards' `:` excluded).
    pub fn expr(&mut self) -> PResult<Expr> {
        self.climb(0)
    }

    /// Enters one level of expression nesting, or reports that the limit is reached.
    fn nest(&mut self) -> PResult<()> {
        if self.nesting >= MAX_NESTING {
            let span = self.cur.span();
            self.diags.error(span, format!("expression nested more than {MAX_NESTING} levels deep"));
            // Skip the rest, so that each enclosing level does not report it again.
            self.skip_entry_inside();
            return Err(());
        }
        self.nesting += 1;
        Ok(())
    }

    /// Skips to the end of the current entry without consuming its `;` (the entry loop does).
    fn skip_entry_inside(&mut self) {
        let mut depth = 0usize;
        while !matches!(self.cur.peek(), Tok::Eof) {
            match self.cur.peek() {
                Tok::Semi | Tok::RBrace if depth == 0 => return,
                Tok::LBrace | Tok::LParen | Tok::LBracket => depth += 1,
                Tok::RBrace | Tok::RParen | Tok::RBracket => depth = depth.saturating_sub(1),
                _ => {}
            }
            self.cur.bump();
        }
    }

    /// Precedence climbing: operators binding at least as tightly as `min` join `lhs`.
    fn climb(&mut self, min: u8) -> PResult<Expr> {
        self.nest()?;
        let result = self.climb_nested(min);
        self.nesting -= 1;
        result
    }

    fn climb_nested(&mut self, min: u8) -> PResult<Expr> {
        let mut lhs = self.prefix()?;
        // Whether `lhs` is a chain built by this loop (and not a parenthesised one).
        let mut open_chain = false;
        while let Some((op, power, right_assoc)) = self.infix() {
            if power < min {
                break;
            }
            self.cur.bump();
            let rhs = self.climb(if right_assoc { power } else { power + 1 })?;
            let span = lhs.span.to(rhs.span);
            lhs = match op {
                Infix::Chain(junction) => {
                    let extends = open_chain && matches!(&lhs.kind, ExprKind::Chain(j, _) if *j == junction);
                    open_chain = true;
                    match lhs.kind {
                        ExprKind::Chain(j, mut parts) if extends => {
                            parts.push(rhs);
                            Expr { kind: ExprKind::Chain(j, parts), span }
                        }
                        kind => {
                            let lhs = Expr { kind, span: lhs.span };
                            Expr { kind: ExprKind::Chain(junction, vec![lhs, rhs]), span }
                        }
                    }
                }
                Infix::Binary(op) => {
                    open_chain = false;
                    Expr { kind: ExprKind::Binary(op, Box::new(lhs), Box::new(rhs)), span }
                }
            };
        }
        Ok(lhs)
    }

    /// The infix operator at the parse position, its binding power and associativity.
    fn infix(&self) -> Option<(Infix, u8, bool)> {
        use Binary::*;
        let bin = |op, power, right| Some((Infix::Binary(op), power, right));
        match self.cur.peek() {
            Tok::Star => bin(Mul, 20, false),
            Tok::Slash => bin(Div, 19, true),
            Tok::Percent => bin(Mod, 19, true),
            Tok::Plus => bin(Add, 18, false),
            Tok::Minus => bin(Sub, 18, false),
            Tok::EqEq => bin(Eq, 14, false),
            Tok::NotEq => bin(Ne, 14, false),
            Tok::Lt => bin(Lt, 14, false),
            Tok::Le => bin(Le, 14, false),
            Tok::Gt => bin(Gt, 14, false),
            Tok::Ge => bin(Ge, 14, false),
            Tok::ElemArrow => bin(In, 13, false),
            Tok::AndAnd => Some((Infix::Chain(Junction::And), 11, false)),
            Tok::OrOr => Some((Infix::Chain(Junction::Or), 10, false)),
            Tok::Arrow => bin(Implies, 9, true),
            Tok::Iff => bin(Iff, 9, true),
            Tok::Ident => match self.text() {
                "MUL" => bin(Mul, 20, false),
                "DIV" => bin(Div, 19, true),
                "MOD" => bin(Mod, 19, true),
                "PLUS" => bin(Add, 18, false),
                "MINUS" => bin(Sub, 18, false),
                "SETMINUS" => bin(SetMinus, 17, true),
                "CAP" => bin(Cap, 16, false),
                "CUP" => bin(Cup, 15, false),
                "EQ" => bin(Eq, 14, false),
                "NEQ" => bin(Ne, 14, false),
                "LE" => bin(Lt, 14, false),
                "LEQ" => bin(Le, 14, false),
                "GE" => bin(Gt, 14, false),
                "GEQ" => bin(Ge, 14, false),
                "IN" | "ELEM" => bin(In, 13, false),
                "AND" => Some((Infix::Chain(Junction::And), 11, false)),
                "OR" => Some((Infix::Chain(Junction::Or), 10, false)),
                "IMPLIES" => bin(Implies, 9, true),
                "EQUIV" => bin(Iff, 9, true),
                "W" => bin(WeakUntil, 8, true),
                "U" => bin(Until, 7, true),
                "R" => bin(Release, 6, false),
                _ => None,
            },
            _ => None,
        }
    }

    /// A prefix operator applied to its operand, or a primary expression.
    fn prefix(&mut self) -> PResult<Expr> {
        // Numeric prefixes take a primary; temporal ones everything above `&&` (SyfCo's levels).
        const NUMERIC_OPERAND: u8 = 21;
        const TEMPORAL_OPERAND: u8 = 13;
        let start = self.cur.span();
        let bracket_follows = self.cur.peek_at(1) == Tok::LBracket;
        let unary = match self.cur.peek() {
            Tok::Bang => Some((Unary::Not, TEMPORAL_OPERAND)),
            Tok::Ident if !bracket_follows => match self.text() {
                "NOT" => Some((Unary::Not, TEMPORAL_OPERAND)),
                "X" => Some((Unary::Next, TEMPORAL_OPERAND)),
                "G" => Some((Unary::Globally, TEMPORAL_OPERAND)),
                "F" => Some((Unary::Finally, TEMPORAL_OPERAND)),
                "SIZEOF" => Some((Unary::SizeOf, NUMERIC_OPERAND)),
                "SIZE" => Some((Unary::Size, NUMERIC_OPERAND)),
                "MIN" => Some((Unary::Min, NUMERIC_OPERAND)),
                "MAX" => Some((Unary::Max, NUMERIC_OPERAND)),
                _ => None,
            },
            _ => None,
        };
        if let Some((op, operand_power)) = unary {
            self.cur.bump();
            let operand = self.climb(operand_power)?;
            let span = start.to(operand.span);
            return Ok(Expr { kind: ExprKind::Unary(op, Box::new(operand)), span });
        }
        if bracket_follows {
            let big = match (self.cur.peek(), self.text()) {
                (Tok::AndAnd, _) | (Tok::Ident, "AND" | "FORALL") => Some((BigOp::And, TEMPORAL_OPERAND)),
                (Tok::OrOr, _) | (Tok::Ident, "OR" | "EXISTS") => Some((BigOp::Or, TEMPORAL_OPERAND)),
                (Tok::Plus, _) | (Tok::Ident, "SUM") => Some((BigOp::Sum, NUMERIC_OPERAND)),
                (Tok::Star, _) | (Tok::Ident, "PROD") => Some((BigOp::Prod, NUMERIC_OPERAND)),
                _ => None,
            };
            if let Some((op, operand_power)) = big {
                self.cur.bump();
                self.cur.bump();
                let binders = self.binders()?;
                self.expect(Tok::RBracket, "`,` or `]`")?;
                let body = self.climb(operand_power)?;
                let span = start.to(body.span);
                return Ok(Expr { kind: ExprKind::Big { op, binders, body: Box::new(body) }, span });
            }
            if self.cur.at(Tok::Ident) && matches!(self.text(), "X" | "F" | "G") {
                return self.bounded_temporal(start);
            }
        }
        self.primary()
    }

    /// `X[n] φ`, `F[a:b] φ`, `G[a:b] φ`; the parse position is at the operator.
    fn bounded_temporal(&mut self, start: Span) -> PResult<Expr> {
        let op = self.text();
        self.cur.bump();
        self.cur.bump();
        if self.cur.at(Tok::Bang) {
            let span = self.cur.span();
            self.diags
                .error(span, "strong operators (`X[!]`, …) belong to finite-trace semantics, which is not supported");
            return Err(());
        }
        let first = self.expr()?;
        let kind = if op == "X" {
            self.expect(Tok::RBracket, "`]`")?;
            let body = self.climb(13)?;
            ExprKind::NextN { count: Box::new(first), body: Box::new(body) }
        } else {
            self.expect(Tok::Colon, "`:` between the bounds")?;
            let second = self.expr()?;
            self.expect(Tok::RBracket, "`]`")?;
            let body = self.climb(13)?;
            let op = if op == "F" { BoundedOp::Finally } else { BoundedOp::Globally };
            ExprKind::Bounded { op, from: Box::new(first), to: Box::new(second), body: Box::new(body) }
        };
        let span = match &kind {
            ExprKind::NextN { body, .. } | ExprKind::Bounded { body, .. } => start.to(body.span),
            _ => start,
        };
        Ok(Expr { kind, span })
    }

    /// `0 <= i < n, j IN s, …`: each binder is an expression of one of the two shapes.
    fn binders(&mut self) -> PResult<Vec<Binder>> {
        let mut binders = vec![self.binder()?];
        while self.cur.at(Tok::Comma) {
            self.cur.bump();
            binders.push(self.binder()?);
        }
        Ok(binders)
    }

    fn binder(&mut self) -> PResult<Binder> {
        let expr = self.expr()?;
        let span = expr.span;
        let name_of = |e: &Expr| match &e.kind {
            ExprKind::Name(n) => Some((n.clone(), e.span)),
            _ => None,
        };
        let strictness = |op: Binary| match op {
            Binary::Lt => Some(true),
            Binary::Le => Some(false),
            _ => None,
        };
        if let ExprKind::Binary(outer, lhs, to) = expr.kind {
            if outer == Binary::In {
                if let Some((var, span)) = name_of(&lhs) {
                    return Ok(Binder { var, span, domain: Domain::Set(*to) });
                }
            }
            if let (Some(to_strict), ExprKind::Binary(inner, from, var)) = (strictness(outer), lhs.kind) {
                if let (Some(from_strict), Some((var, span))) = (strictness(inner), name_of(&var)) {
                    return Ok(Binder {
                        var,
                        span,
                        domain: Domain::Range { from: *from, from_strict, to: *to, to_strict },
                    });
                }
            }
        }
        self.diags.error(span, "expected a binder such as `0 <= i < n` or `i IN set`");
        Err(())
    }

    fn primary(&mut self) -> PResult<Expr> {
        let start = self.cur.span();
        match self.cur.peek() {
            Tok::Number => {
                let text = self.text();
                self.cur.bump();
                match text.parse::<i64>() {
                    Ok(n) => Ok(Expr { kind: ExprKind::Number(n), span: start }),
                    Err(_) => {
                        self.diags.error(start, format!("number `{text}` is too large"));
                        Err(())
                    }
                }
            }
            Tok::LParen => {
                self.cur.bump();
                let inner = self.expr()?;
                let end = self.expect(Tok::RParen, "`)`")?;
                Ok(Expr { span: start.to(end), ..inner })
            }
            Tok::LBrace => {
                self.cur.bump();
                let mut elements = Vec::new();
                if !self.cur.at(Tok::RBrace) {
                    elements.push(self.expr()?);
                    while self.cur.at(Tok::Comma) {
                        self.cur.bump();
                        elements.push(self.expr()?);
                    }
                }
                let end = self.expect(Tok::RBrace, "`,` or `}`")?;
                Ok(Expr { kind: ExprKind::Set(elements), span: start.to(end) })
            }
            Tok::Ident => self.name_expr(),
            _ => self.err("an expression"),
        }
    }

    /// A name, `bus[index]` or `f(args)`.
    fn name_expr(&mut self) -> PResult<Expr> {
        let (name, span) = self.ident("a name")?;
        match name.as_str() {
            "true" => return Ok(Expr { kind: ExprKind::True, span }),
            "false" => return Ok(Expr { kind: ExprKind::False, span }),
            "otherwise" => return Ok(Expr { kind: ExprKind::Otherwise, span }),
            "Y" | "H" | "O" | "S" | "T" => {
                self.diags.error(span, format!("past-time operator `{name}` is not supported"));
                return Err(());
            }
            _ => {}
        }
        if RESERVED.contains(&name.as_str()) {
            self.diags.error(span, format!("expected an expression, found the operator `{name}`"));
            return Err(());
        }
        match self.cur.peek() {
            Tok::LBracket => {
                self.cur.bump();
                let index = self.expr()?;
                let end = self.expect(Tok::RBracket, "`]`")?;
                let kind = ExprKind::Index { bus: name, bus_span: span, index: Box::new(index) };
                Ok(Expr { kind, span: span.to(end) })
            }
            Tok::LParen => {
                self.cur.bump();
                let mut args = Vec::new();
                if !self.cur.at(Tok::RParen) {
                    args.push(self.expr()?);
                    while self.cur.at(Tok::Comma) {
                        self.cur.bump();
                        args.push(self.expr()?);
                    }
                }
                let end = self.expect(Tok::RParen, "`,` or `)`")?;
                Ok(Expr { kind: ExprKind::Call { name, name_span: span, args }, span: span.to(end) })
            }
            _ => Ok(Expr { kind: ExprKind::Name(name), span }),
        }
    }
}

/// Operator words that cannot be names (SyfCo reserves them too).
const RESERVED: &[&str] = &[
    "X", "G", "F", "U", "R", "W", "NOT", "AND", "OR", "IMPLIES", "EQUIV", "MUL", "DIV", "MOD", "PLUS", "MINUS",
    "SETMINUS", "CAP", "CUP", "EQ", "NEQ", "LE", "LEQ", "GE", "GEQ", "IN", "ELEM", "SIZEOF", "SIZE", "MIN", "MAX",
    "SUM", "PROD", "FORALL", "EXISTS",
];

enum Infix {
    Binary(Binary),
    Chain(Junction),
}
