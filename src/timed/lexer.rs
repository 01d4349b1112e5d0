//! Tokens of the `.tga` language, produced by a `logos` lexer.
//!
//! Words are not reserved: `plan`, `reset` or `time` may name nodes or messages. The parser
//! recognises keywords by context, which keeps every thesis listing valid.

use crate::diag::Span;
use logos::Logos;

#[derive(Logos, Clone, Copy, Debug, PartialEq, Eq)]
#[logos(skip r"[ \t\r\n\f]+")]
#[logos(skip(r"//[^\n]*", allow_greedy = true))]
pub enum Tok {
    #[regex(r"[A-Za-z_][A-Za-z0-9_]*")]
    Ident,
    #[regex(r"[0-9]+")]
    Int,
    /// An IEC direct address: `%I0.0`, `%QX1.3`, `%MW10`, `%IB3`.
    #[regex(r"%[IQM][XBWDL]?[0-9]+(\.[0-9]+)?")]
    Address,
    #[regex(r#""[^"\n]*""#, allow_greedy = true)]
    Str,
    #[token("/*", block_comment)]
    BlockComment,
    #[token("{")]
    LBrace,
    #[token("}")]
    RBrace,
    #[token("(")]
    LParen,
    #[token(")")]
    RParen,
    #[token("[")]
    LBracket,
    #[token("]")]
    RBracket,
    #[token(",")]
    Comma,
    #[token(";")]
    Semi,
    #[token(":")]
    Colon,
    #[token(".")]
    Dot,
    #[token("*")]
    Star,
    #[token("?")]
    Question,
    #[token("!")]
    Bang,
    #[token("$")]
    Dollar,
    #[token("=")]
    Eq,
    #[token("->")]
    Arrow,
    #[token("→")]
    UnicodeArrow,
    #[token("<-")]
    BackArrow,
    #[token("<->")]
    BothArrow,
    /// Produced by the wrapper for a `/*` without `*/`.
    UnterminatedComment,
    /// Any character the language does not use.
    Error,
    Eof,
}

/// Skips a block comment; returns false (an error) if it is not closed.
fn block_comment(lex: &mut logos::Lexer<Tok>) -> bool {
    match lex.remainder().find("*/") {
        Some(end) => {
            lex.bump(end + 2);
            true
        }
        None => {
            lex.bump(lex.remainder().len());
            false
        }
    }
}

/// One token with its span.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Token {
    pub tok: Tok,
    pub span: Span,
}

/// Lexes the whole source. Comments are dropped; lexical errors become `Error` or
/// `UnterminatedComment` tokens for the parser to report. Always ends with `Eof`.
pub fn tokenize(source: &str) -> Vec<Token> {
    let mut out = Vec::new();
    let mut lex = Tok::lexer(source);
    while let Some(result) = lex.next() {
        let span = Span::new(lex.span().start, lex.span().end);
        match result {
            Ok(Tok::BlockComment) => {}
            Ok(tok) => out.push(Token { tok, span }),
            Err(()) if source[lex.span()].starts_with("/*") => out.push(Token {
                tok: Tok::UnterminatedComment,
                span: Span::new(span.start as usize, span.start as usize + 2),
            }),
            Err(()) => out.push(Token { tok: Tok::Error, span }),
        }
    }
    out.push(Token { tok: Tok::Eof, span: Span::new(source.len(), source.len()) });
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn kinds(src: &str) -> Vec<Tok> {
        tokenize(src).into_iter().map(|t| t.tok).collect()
    }

    #[test]
    fn arrows_and_sigils() {
        assert_eq!(
            kinds("a -> b <- c <-> d ?x !y $z"),
            vec![
                Tok::Ident,
                Tok::Arrow,
                Tok::Ident,
                Tok::BackArrow,
                Tok::Ident,
                Tok::BothArrow,
                Tok::Ident,
                Tok::Question,
                Tok::Ident,
                Tok::Bang,
                Tok::Ident,
                Tok::Dollar,
                Tok::Ident,
                Tok::Eof
            ]
        );
    }

    #[test]
    fn comments_are_skipped_and_unterminated_ones_reported() {
        assert_eq!(kinds("a // x\n /* y \n z */ b"), vec![Tok::Ident, Tok::Ident, Tok::Eof]);
        assert_eq!(kinds("a /* never closed"), vec![Tok::Ident, Tok::UnterminatedComment, Tok::Eof]);
    }

    #[test]
    fn numbers_units_and_addresses() {
        assert_eq!(kinds("100ms"), vec![Tok::Int, Tok::Ident, Tok::Eof]);
        assert_eq!(kinds("%I0.0 %QX12.7 %MW10"), vec![Tok::Address, Tok::Address, Tok::Address, Tok::Eof]);
        assert_eq!(kinds("#"), vec![Tok::Error, Tok::Eof]);
    }
}
