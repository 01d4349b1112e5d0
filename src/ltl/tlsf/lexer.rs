//! The TLSF lexer (logos). Keywords and the temporal operators `X G F U R W` are lexed as
//! identifiers and recognised by the parser where they may stand, as SyfCo reserves them.

use crate::diag::{Diagnostics, Span};
use logos::Logos;

#[derive(Logos, Clone, Copy, Debug, PartialEq, Eq)]
#[logos(skip r"[ \t\r\n\f]+")]
#[logos(skip(r"//[^\n]*", allow_greedy = true))]
#[logos(skip r"/\*([^*]|\*+[^*/])*\*+/")]
pub enum Tok {
    #[regex(r"[A-Za-z_][A-Za-z0-9_@']*")]
    Ident,
    #[regex(r"[0-9]+")]
    Number,
    #[regex(r#""([^"\\\n]|\\.)*""#)]
    Str,
    /// A string that the line ends before it closes; reported by [`lex`] and dropped.
    #[regex(r#""([^"\\\n]|\\.)*"#)]
    UnclosedStr,
    /// A block comment that the file ends inside; reported by [`lex`] and dropped.
    #[regex(r"/\*([^*]|\*+[^*/])*\**", allow_greedy = true)]
    UnclosedComment,
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
    #[token("=")]
    Assign,
    #[token("==")]
    EqEq,
    #[token("!=")]
    #[token("/=")]
    NotEq,
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
    #[token("%")]
    Percent,
    #[token("!")]
    Bang,
    #[token("&&")]
    AndAnd,
    #[token("||")]
    OrOr,
    #[token("->")]
    Arrow,
    #[token("<->")]
    Iff,
    #[token("<-")]
    ElemArrow,
    Eof,
}

/// The tokens of `src`, ending with [`Tok::Eof`]. A character no token accepts, an unclosed
/// string or comment is reported to `diags` and skipped.
pub fn lex<'s>(src: &'s str, diags: &mut Diagnostics<'s>) -> Vec<(Tok, Span)> {
    let mut toks = Vec::new();
    let mut lexer = Tok::lexer(src);
    while let Some(tok) = lexer.next() {
        let range = lexer.span();
        let span = Span::new(range.start, range.end);
        match tok {
            Ok(Tok::UnclosedStr) => {
                diags.error(
                    Span::new(range.start, range.start + 1),
                    "unclosed string: it needs a `\"` on the same line",
                );
            }
            Ok(Tok::UnclosedComment) => {
                diags.error(Span::new(range.start, range.start + 2), "unclosed comment: `/*` without `*/`");
            }
            Ok(tok) => toks.push((tok, span)),
            Err(()) => {
                let c = src[range].chars().next().unwrap_or('?');
                let shown = if c.is_control() { format!("U+{:04X}", c as u32) } else { format!("`{c}`") };
                diags.error(span, format!("unexpected character {shown}"));
            }
        }
    }
    toks.push((Tok::Eof, Span::new(src.len(), src.len())));
    toks
}
