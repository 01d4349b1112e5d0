//! The `.sct` lexer (logos). Keywords are contextual: every word is lexed as an identifier and
//! the parser compares its text where a keyword may stand, so that users may name states `on`,
//! `start` or `state`.

use crate::diag::{Diagnostics, Span};
use logos::Logos;

#[derive(Logos, Clone, Copy, Debug, PartialEq, Eq)]
#[logos(skip r"[ \t\r\n\f]+")]
#[logos(skip(r"//[^\n]*", allow_greedy = true))]
#[logos(skip r"/\*([^*]|\*+[^*/])*\*+/")]
pub enum Tok {
    #[regex(r"[A-Za-z_][A-Za-z0-9_]*")]
    Ident,
    #[regex(r"[0-9]+")]
    Number,
    #[regex(r"[0-9]+(ms|s|m|h)")]
    Duration,
    #[regex(r#""([^"\\\n]|\\.)*""#)]
    Str,
    #[token("{")]
    LBrace,
    #[token("}")]
    RBrace,
    #[token("[")]
    LBracket,
    #[token("]")]
    RBracket,
    #[token("(")]
    LParen,
    #[token(")")]
    RParen,
    #[token(";")]
    Semi,
    #[token(":")]
    Colon,
    #[token(",")]
    Comma,
    #[token(".")]
    Dot,
    #[token("->")]
    Arrow,
    #[token("=")]
    Eq,
    #[token("|")]
    Bar,
    Eof,
}

/// The tokens of `src`, ending with [`Tok::Eof`]; a character no token accepts is reported to
/// `diags` and skipped.
pub fn lex<'s>(src: &'s str, diags: &mut Diagnostics<'s>) -> Vec<(Tok, Span)> {
    let mut toks = Vec::new();
    let mut lex = Tok::lexer(src);
    while let Some(t) = lex.next() {
        let r = lex.span();
        let span = Span::new(r.start, r.end);
        match t {
            Ok(t) => toks.push((t, span)),
            Err(()) => {
                diags.error(span, format!("unexpected character `{}`", &src[r.clone()].chars().next().unwrap_or('?')));
            }
        }
    }
    toks.push((Tok::Eof, Span::new(src.len(), src.len())));
    toks
}
