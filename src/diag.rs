//! Located diagnostics shared by every front end (timed-game specs, SCT projects, …).
//!
//! A diagnostic carries a byte span into the source, the 1-based line and column of its start,
//! a one-line message and optional notes. Front ends collect all diagnostics of a file instead of
//! stopping at the first; the CLI renders them with the offending source line and a caret, the
//! playground turns them into editor squiggles.

use serde::Serialize;

/// A half-open byte range `start..end` into the source text.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize)]
pub struct Span {
    pub start: u32,
    pub end: u32,
}

impl Span {
    pub fn new(start: usize, end: usize) -> Span {
        Span { start: start as u32, end: end.max(start) as u32 }
    }

    /// The smallest span covering both.
    pub fn to(self, other: Span) -> Span {
        Span { start: self.start.min(other.start), end: self.end.max(other.end) }
    }

    pub fn range(self) -> std::ops::Range<usize> {
        self.start as usize..self.end as usize
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Severity {
    Error,
    Warning,
}

/// What every engine's `compile` returns: the checked model with the warnings, or every
/// diagnostic (errors and warnings) when the text has an error.
pub type Checked<T> = Result<(T, Vec<Diagnostic>), Vec<Diagnostic>>;

/// One located message about the input.
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
pub struct Diagnostic {
    pub severity: Severity,
    pub span: Span,
    /// 1-based line of `span.start`.
    pub line: u32,
    /// 1-based column of `span.start`, counted in characters.
    pub column: u32,
    pub message: String,
    pub notes: Vec<String>,
}

impl Diagnostic {
    pub fn is_error(&self) -> bool {
        self.severity == Severity::Error
    }
}

/// Maps byte offsets to line/column; built once per source.
pub struct LineIndex<'a> {
    source: &'a str,
    line_starts: Vec<usize>,
}

impl<'a> LineIndex<'a> {
    pub fn new(source: &'a str) -> LineIndex<'a> {
        let mut line_starts = vec![0];
        line_starts.extend(source.match_indices('\n').map(|(i, _)| i + 1));
        LineIndex { source, line_starts }
    }

    /// 1-based (line, column) of a byte offset; offsets inside a UTF-8 sequence are rounded down.
    pub fn line_col(&self, offset: usize) -> (u32, u32) {
        let offset = offset.min(self.source.len());
        let line = self.line_starts.partition_point(|&s| s <= offset) - 1;
        let start = self.line_starts[line];
        let mut end = offset;
        while !self.source.is_char_boundary(end) {
            end -= 1;
        }
        let column = self.source[start..end].chars().count() + 1;
        (line as u32 + 1, column as u32)
    }

    /// The byte offset where a 1-based line starts.
    pub fn line_start(&self, line: u32) -> usize {
        self.line_starts[(line as usize).saturating_sub(1).min(self.line_starts.len() - 1)]
    }

    /// The text of a 1-based line without its line break.
    pub fn line_text(&self, line: u32) -> &'a str {
        let i = (line as usize).saturating_sub(1).min(self.line_starts.len() - 1);
        let start = self.line_starts[i];
        let end = self.line_starts.get(i + 1).copied().unwrap_or(self.source.len());
        self.source[start..end].trim_end_matches(['\n', '\r'])
    }
}

/// At most this many diagnostics are kept per source. A long line of garbage yields one per
/// token, and each costs a scan of its line (the column) and a copy of it when rendered: without
/// a bound, 200 KB on one line took minutes and printed gigabytes.
pub const MAX_DIAGNOSTICS: usize = 100;

/// Collects diagnostics for one source, computing line and column as they are added.
pub struct Diagnostics<'a> {
    index: LineIndex<'a>,
    pub items: Vec<Diagnostic>,
    /// Errors reported, kept or not.
    errors: usize,
    /// Whether an error past the bound was reported (and the bound said so).
    truncated: bool,
    /// Where a diagnostic past [`MAX_DIAGNOSTICS`] goes, so that callers may still add notes.
    discarded: Diagnostic,
}

impl<'a> Diagnostics<'a> {
    pub fn new(source: &'a str) -> Diagnostics<'a> {
        let discarded = Diagnostic {
            severity: Severity::Error,
            span: Span::default(),
            line: 1,
            column: 1,
            message: String::new(),
            notes: Vec::new(),
        };
        Diagnostics { index: LineIndex::new(source), items: Vec::new(), errors: 0, truncated: false, discarded }
    }

    pub fn error(&mut self, span: Span, message: impl Into<String>) -> &mut Diagnostic {
        self.push(Severity::Error, span, message.into())
    }

    pub fn warning(&mut self, span: Span, message: impl Into<String>) -> &mut Diagnostic {
        self.push(Severity::Warning, span, message.into())
    }

    fn push(&mut self, severity: Severity, span: Span, message: String) -> &mut Diagnostic {
        let error = severity == Severity::Error;
        self.errors += usize::from(error);
        if self.items.len() < MAX_DIAGNOSTICS {
            let (line, column) = self.index.line_col(span.start as usize);
            self.items.push(Diagnostic { severity, span, line, column, message, notes: Vec::new() });
            return self.items.last_mut().expect("just pushed");
        }
        if error && !self.truncated {
            // Said once, as an error, so that the kept diagnostics always contain one.
            self.truncated = true;
            let (line, column) = self.index.line_col(span.start as usize);
            let message = format!("too many diagnostics: only the first {MAX_DIAGNOSTICS} are shown");
            self.items.push(Diagnostic { severity, span, line, column, message, notes: Vec::new() });
        }
        self.discarded.notes.clear();
        &mut self.discarded
    }

    pub fn has_errors(&self) -> bool {
        self.errors > 0
    }

    /// Errors reported so far, including those past [`MAX_DIAGNOSTICS`] that were not kept.
    pub fn error_count(&self) -> usize {
        self.errors
    }

    pub fn line_col(&self, offset: usize) -> (u32, u32) {
        self.index.line_col(offset)
    }

    /// The source text the spans refer to.
    pub fn source(&self) -> &'a str {
        self.index.source
    }
}

impl Diagnostic {
    pub fn with_note(&mut self, note: impl Into<String>) -> &mut Diagnostic {
        self.notes.push(note.into());
        self
    }
}

/// A source line as a terminal can show it: control characters (a lone `\r`, which would return
/// the cursor, a tab, whose width varies) become one visible character each, so that the caret
/// line, which counts characters, stays under the right column.
fn visible(text: &str) -> String {
    text.chars()
        .map(|c| match c {
            '\t' => ' ',
            // The Unicode "control pictures" block: U+2400 + code for C0 controls, U+2421 for DEL.
            c if (c as u32) < 0x20 => char::from_u32(0x2400 + c as u32).unwrap_or('?'),
            '\u{7f}' => '\u{2421}',
            c => c,
        })
        .collect()
}

/// Longest source line shown whole; a longer one is cut to this many characters around the
/// caret, so that the rendering of a long line stays short.
const SHOWN_CHARACTERS: usize = 120;

/// The visible part of a source line for a caret at character `column` (0-based): the text,
/// the caret's position in it, and how many caret characters fit from there.
fn window(text: &str, column: usize) -> (String, usize, usize) {
    let count = text.chars().count();
    if count <= SHOWN_CHARACTERS {
        return (visible(text), column, usize::MAX);
    }
    let from = column.saturating_sub(SHOWN_CHARACTERS / 3).min(count - SHOWN_CHARACTERS);
    let part: String = text.chars().skip(from).take(SHOWN_CHARACTERS).collect();
    let before = if from > 0 { "…" } else { "" };
    let after = if from + SHOWN_CHARACTERS < count { "…" } else { "" };
    let caret_at = column - from + before.chars().count();
    (format!("{before}{}{after}", visible(&part)), caret_at, (from + SHOWN_CHARACTERS).saturating_sub(column).max(1))
}

/// Renders diagnostics as plain text: `file:line:col: error: message`, the source line and a
/// caret under the span. Used by the CLI and by tests; the page renders its own squiggles.
pub fn render_plain(file: &str, source: &str, diagnostics: &[Diagnostic]) -> String {
    let index = LineIndex::new(source);
    let mut out = String::new();
    for d in diagnostics {
        let kind = match d.severity {
            Severity::Error => "error",
            Severity::Warning => "warning",
        };
        out.push_str(&format!("{file}:{}:{}: {kind}: {}\n", d.line, d.column, d.message));
        let text = index.line_text(d.line);
        let gutter = d.line.to_string();
        let column = (d.column as usize).saturating_sub(1);
        let (shown, caret_at, room) = window(text, column);
        out.push_str(&format!("{gutter} | {shown}\n"));
        // The caret covers the span's part on its first line, at least one column; a span past
        // the end of the displayed text (after a trailing `\r`, say) gets one caret after it.
        let start = (d.span.start as usize).min(source.len());
        let line_start = index.line_start(d.line);
        let line_end = (line_start + text.len()).max(start);
        let end = (d.span.end as usize).clamp(start, line_end);
        let width = source.get(start..end).map_or(1, |s| s.chars().count()).clamp(1, room);
        out.push_str(&format!("{} | {}{}\n", " ".repeat(gutter.len()), " ".repeat(caret_at), "^".repeat(width)));
        for note in &d.notes {
            out.push_str(&format!("{} = note: {note}\n", " ".repeat(gutter.len())));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn line_col_counts_characters_from_one() {
        let src = "ab\ncdé\nf";
        let idx = LineIndex::new(src);
        assert_eq!(idx.line_col(0), (1, 1));
        assert_eq!(idx.line_col(3), (2, 1));
        assert_eq!(idx.line_col(7), (2, 4)); // after the two-byte é
        assert_eq!(idx.line_text(2), "cdé");
        assert_eq!(idx.line_col(src.len()), (3, 2));
    }

    #[test]
    fn render_shows_source_line_and_caret() {
        let src = "plant {\n  automaton A { nodes q0; q0 -> q9 ?a; }\n}\n";
        let start = src.find("q9").unwrap();
        let mut diags = Diagnostics::new(src);
        diags.error(Span::new(start, start + 2), "unknown node `q9`");
        let text = render_plain("x.tga", src, &diags.items);
        assert!(text.starts_with("x.tga:2:33: error: unknown node `q9`\n"), "{text}");
        assert!(text.contains("2 |   automaton A { nodes q0; q0 -> q9 ?a; }\n"));
        assert!(text.contains("  |                                 ^^\n"), "{text}");
    }

    #[test]
    fn diagnostics_are_bounded_and_keep_an_error() {
        let src = "x".repeat(1000);
        let mut diags = Diagnostics::new(&src);
        for i in 0..MAX_DIAGNOSTICS + 50 {
            diags.warning(Span::new(i, i + 1), "w").with_note("kept or not");
        }
        assert!(!diags.has_errors());
        diags.error(Span::new(900, 901), "e").with_note("dropped");
        diags.error(Span::new(901, 902), "e");
        assert_eq!(diags.items.len(), MAX_DIAGNOSTICS + 1);
        assert_eq!(diags.error_count(), 2);
        let last = diags.items.last().unwrap();
        assert!(last.is_error() && last.message.starts_with("too many diagnostics"), "{last:?}");
        assert!(last.notes.is_empty());
    }

    #[test]
    fn a_long_line_is_cut_around_the_caret() {
        let src = format!("{}@{}", "a".repeat(5000), "b".repeat(5000));
        let mut diags = Diagnostics::new(&src);
        diags.error(Span::new(5000, 5001), "here");
        diags.error(Span::new(0, 10_001), "all of it");
        let text = render_plain("a", &src, &diags.items);
        let lines: Vec<&str> = text.lines().collect();
        assert!(lines[1].starts_with("1 | …a") && lines[1].ends_with("b…"), "{text}");
        assert_eq!(lines[1].chars().count(), "1 | ".len() + SHOWN_CHARACTERS + 2);
        let caret = lines[2].find('^').unwrap();
        assert_eq!(lines[1].chars().nth(caret), Some('@'), "{text}");
        assert!(lines[5].starts_with("  | ^") && lines[5].chars().count() == "  | ".len() + SHOWN_CHARACTERS, "{text}");
    }

    #[test]
    fn render_survives_a_trailing_carriage_return() {
        let src = "dependencies\r";
        let mut diags = Diagnostics::new(src);
        diags.error(Span::new(src.len(), src.len()), "expected `{`, found end of file");
        let text = render_plain("a.tga", src, &diags.items);
        assert_eq!(text, "a.tga:1:14: error: expected `{`, found end of file\n1 | dependencies\n  |              ^\n");
    }

    #[test]
    fn caret_stays_under_its_column_after_a_lone_carriage_return() {
        let src = "ab\rcd x\n";
        let start = src.find('x').unwrap();
        let mut diags = Diagnostics::new(src);
        diags.error(Span::new(start, start + 1), "here");
        let text = render_plain("a", src, &diags.items);
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines[1], "1 | ab\u{240d}cd x");
        let caret = lines[2].find('^').unwrap();
        assert_eq!(lines[1].chars().count() - 1, lines[2][..caret].chars().count(), "{text}");
    }
}
