//! G4LTL's line format (placeholder: being written).

use super::spec::Spec;
use crate::diag::{Diagnostic, Diagnostics, Span};

pub fn compile_g4ltl(source: &str) -> Result<(Spec, Vec<Diagnostic>), Vec<Diagnostic>> {
    let mut diags = Diagnostics::new(source);
    diags.error(Span::new(0, 0), "not read yet");
    Err(diags.items)
}
