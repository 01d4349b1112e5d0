//! The located error of the model-file readers (`.gen`, `.wmod`).

use crate::diag::{Diagnostic, Diagnostics, Span};

/// A located error in a model file.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct FileError {
    /// The offending token, element, attribute or name.
    pub span: Span,
    pub message: String,
    pub notes: Vec<String>,
    /// The file declares more states than the caller's budget allows: not a malformed file,
    /// but one too large for this run (the CLI's exit status 3, as for every budget stop).
    pub over_budget: bool,
}

impl FileError {
    pub(super) fn at(span: Span, message: impl Into<String>) -> FileError {
        FileError { span, message: message.into(), notes: Vec::new(), over_budget: false }
    }

    /// More than `max_states` states declared, at `span` (what: "the generator", "the module").
    pub(super) fn budget(span: Span, what: &str, max_states: usize) -> FileError {
        FileError {
            over_budget: true,
            ..FileError::at(span, format!("{what} declares more than {max_states} states, the state budget"))
        }
    }

    pub(super) fn note(mut self, note: impl Into<String>) -> FileError {
        self.notes.push(note.into());
        self
    }

    /// The error as a diagnostic of `source`, with line and column.
    pub fn diagnostic(&self, source: &str) -> Diagnostic {
        let mut d = Diagnostics::new(source);
        let item = d.error(self.span, self.message.clone());
        item.notes = self.notes.clone();
        item.clone()
    }
}
