//! SYNTCOMP's Temporal Logic Synthesis Format (placeholder: being written).

use super::spec::Spec;
use crate::diag::{Diagnostic, Diagnostics, Span};

/// Checks a TLSF text into a [`Spec`], `overrides` replacing `PARAMETERS` by name.
pub fn compile_tlsf(source: &str, _overrides: &[(String, i64)]) -> Result<(Spec, Vec<Diagnostic>), Vec<Diagnostic>> {
    let mut diags = Diagnostics::new(source);
    diags.error(Span::new(0, 0), "TLSF is not read yet");
    Err(diags.items)
}
