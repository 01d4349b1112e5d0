//! The token cursor the recursive-descent front ends share (`.tga`, `.sct`, TLSF, G4LTL): a
//! position in a lexed token list, with look-ahead, consumption and span bookkeeping. Each
//! parser keeps its own error wording (`expect`, `describe`) on top of it.
//!
//! The last token of the list is its end marker (the lexers' `Eof`): the cursor never moves
//! past it, and looking beyond it sees it again, so a parser at the end keeps seeing the end.

use crate::diag::Span;

/// A position in a token list that ends with an end marker.
#[derive(Clone, Debug)]
pub(crate) struct Cursor<T> {
    toks: Vec<(T, Span)>,
    pos: usize,
}

impl<T: Copy + PartialEq> Cursor<T> {
    /// A cursor on the first of `toks`; the last of `toks` is the end marker.
    ///
    /// # Panics
    /// If `toks` is empty (it must hold at least the end marker).
    pub fn new(toks: Vec<(T, Span)>) -> Self {
        assert!(!toks.is_empty(), "a token list ends with an end marker");
        Cursor { toks, pos: 0 }
    }

    /// A cursor on `toks` followed by the end marker `end`, placed where the last token ends
    /// (at 0 if there is none).
    pub fn with_end(toks: &[(T, Span)], end: T) -> Self {
        let at = toks.last().map_or(0, |t| t.1.end as usize);
        let mut all = Vec::with_capacity(toks.len() + 1);
        all.extend_from_slice(toks);
        all.push((end, Span::new(at, at)));
        Cursor { toks: all, pos: 0 }
    }

    /// How many tokens have been consumed: parsers compare it to see whether a step made
    /// progress.
    pub fn pos(&self) -> usize {
        self.pos
    }

    /// The token `ahead` places after the next one (the next one at 0); the end marker beyond
    /// the end.
    pub fn token_at(&self, ahead: usize) -> (T, Span) {
        self.toks[(self.pos.saturating_add(ahead)).min(self.toks.len() - 1)]
    }

    /// The next token.
    pub fn token(&self) -> (T, Span) {
        self.token_at(0)
    }

    /// The kind of the next token.
    pub fn peek(&self) -> T {
        self.token().0
    }

    /// The kind of the token `ahead` places after the next one.
    pub fn peek_at(&self, ahead: usize) -> T {
        self.token_at(ahead).0
    }

    /// The span of the next token.
    pub fn span(&self) -> Span {
        self.token().1
    }

    /// The span of the last consumed token, if any.
    pub fn prev_span(&self) -> Option<Span> {
        self.pos.checked_sub(1).map(|i| self.toks[i].1)
    }

    /// Where the last consumed token ends (0 before the first).
    pub fn prev_end(&self) -> usize {
        self.prev_span().map_or(0, |s| s.end as usize)
    }

    /// Whether the next token is the end marker.
    pub fn at_end(&self) -> bool {
        self.pos >= self.toks.len() - 1
    }

    /// Whether the next token is of kind `kind`.
    pub fn at(&self, kind: T) -> bool {
        self.peek() == kind
    }

    /// Consumes the next token and returns it; at the end marker, returns it and stays.
    pub fn bump(&mut self) -> (T, Span) {
        let t = self.token();
        if !self.at_end() {
            self.pos += 1;
        }
        t
    }

    /// Consumes the next token if it is of kind `kind`.
    pub fn eat(&mut self, kind: T) -> bool {
        let yes = self.at(kind);
        if yes {
            self.bump();
        }
        yes
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Clone, Copy, Debug, PartialEq)]
    enum K {
        A,
        B,
        End,
    }

    #[test]
    fn the_cursor_stops_at_the_end_marker() {
        let mut c = Cursor::new(vec![(K::A, Span::new(0, 1)), (K::B, Span::new(2, 3)), (K::End, Span::new(5, 5))]);
        assert_eq!((c.peek(), c.peek_at(1), c.peek_at(7), c.prev_end(), c.prev_span()), (K::A, K::B, K::End, 0, None));
        assert!(!c.eat(K::B) && c.eat(K::A) && c.at(K::B));
        assert_eq!((c.pos(), c.prev_end(), c.span()), (1, 1, Span::new(2, 3)));
        assert_eq!(c.bump(), (K::B, Span::new(2, 3)));
        assert!(c.at_end());
        assert_eq!(c.bump(), (K::End, Span::new(5, 5)));
        assert_eq!((c.pos(), c.prev_span()), (2, Some(Span::new(2, 3))));
    }

    #[test]
    fn an_end_marker_is_placed_after_the_last_token() {
        let c = Cursor::with_end(&[(K::A, Span::new(3, 7))], K::End);
        assert_eq!(c.token_at(1), (K::End, Span::new(7, 7)));
        let c = Cursor::with_end(&[], K::End);
        assert!(c.at_end());
        assert_eq!(c.token(), (K::End, Span::new(0, 0)));
    }
}
