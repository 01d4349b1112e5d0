//! SYNTCOMP's Temporal Logic Synthesis Format (TLSF, Jacobs, Klein and Schirmer), read the way
//! SyfCo reads it: the basic format and the full one with parameters, definitions, buses and
//! big operators. The user's view is `docs/ltl-tlsf.md`.
//!
//! Pipeline: [`parser`] (every syntax error located) → [`check`] (every name resolved) →
//! [`eval`] (parameters, overrides, signals, formulas) → the sections combined into a
//! [`Spec`] here.

mod check;
mod eval;
mod lexer;
mod parser;

use super::spec::{Clause, Ltl, Semantics, Signal, SignalId, SignalKind, Spec, MAX_FORMULA_DEPTH};
use crate::diag::{Diagnostic, Diagnostics, Span};
use check::Kind;
use eval::{Bus, Evaluator, Global};
use parser::{Section, SignalDecl, Tlsf, Turn};
use std::collections::{HashMap, HashSet};

/// Signals one bus may have; the synthesis handles a few dozen signals at most anyway.
const MAX_BUS_WIDTH: i64 = 10_000;

/// SyfCo's default separator between a bus name and the index: `r[2]` declares `r_0, r_1`.
const BUS_DELIMITER: &str = "_";

/// Checks a TLSF text into a [`Spec`], `overrides` replacing `PARAMETERS` by name.
pub fn compile_tlsf(source: &str, overrides: &[(String, i64)]) -> Result<(Spec, Vec<Diagnostic>), Vec<Diagnostic>> {
    let mut diags = Diagnostics::new(source);
    let tlsf = parser::parse(source, &mut diags);
    let kinds = declare(&tlsf, &mut diags);
    check::check_names(&tlsf, &kinds, &mut diags);
    check_overrides(&tlsf, overrides, &mut diags);
    if diags.has_errors() {
        return Err(diags.items);
    }
    let spec = evaluate(&tlsf, overrides, &mut diags);
    match spec {
        Some(spec) if !diags.has_errors() => Ok((spec, diags.items)),
        _ => Err(diags.items),
    }
}

/// The kinds of all global names; a name declared twice is reported at its second place.
fn declare<'t>(tlsf: &'t Tlsf, diags: &mut Diagnostics<'_>) -> HashMap<&'t str, Kind> {
    let mut kinds = HashMap::new();
    let mut places: HashMap<&str, (Span, Kind)> = HashMap::new();
    let parameters = tlsf.parameters.iter().map(|p| (p.name.as_str(), p.span, Kind::Parameter));
    let definitions = tlsf.definitions.iter().map(|d| (d.name.as_str(), d.span, Kind::Definition(d.params.len())));
    let signal =
        |s: &'t SignalDecl| (s.name.as_str(), s.span, if s.width.is_some() { Kind::Bus } else { Kind::Signal });
    let signals = tlsf.inputs.iter().chain(&tlsf.outputs).map(signal);
    let is_input = |span: Span| tlsf.inputs.iter().any(|s| s.span == span);
    let is_signal = |kind: Kind| matches!(kind, Kind::Signal | Kind::Bus);
    for (name, span, kind) in parameters.chain(definitions).chain(signals) {
        if let Some(&(first, first_kind)) = places.get(name) {
            let (line, column) = diags.line_col(first.start as usize);
            let message = if is_signal(kind) && is_signal(first_kind) && is_input(first) != is_input(span) {
                format!("`{name}` is declared both as an input and as an output (also at {line}:{column})")
            } else {
                format!("`{name}` is declared twice (first at {line}:{column})")
            };
            diags.error(span, message);
            continue;
        }
        places.insert(name, (span, kind));
        kinds.insert(name, kind);
    }
    kinds
}

/// An override must name a parameter; it is reported where the parameters are (or at 1:1).
fn check_overrides(tlsf: &Tlsf, overrides: &[(String, i64)], diags: &mut Diagnostics<'_>) {
    for (name, value) in overrides {
        if tlsf.parameters.iter().any(|p| &p.name == name) {
            continue;
        }
        let span = tlsf.parameters_span.unwrap_or_default();
        let d = diags.error(span, format!("unknown parameter `{name}` in the override `{name}={value}`"));
        if tlsf.parameters.is_empty() {
            d.with_note("the specification has no PARAMETERS");
        } else {
            let names: Vec<&str> = tlsf.parameters.iter().map(|p| p.name.as_str()).collect();
            d.with_note(format!("its parameters are {}", names.join(", ")));
        }
    }
}

/// Evaluates the parameters, signals and formulas of a file that parsed and checked cleanly.
fn evaluate(tlsf: &Tlsf, overrides: &[(String, i64)], diags: &mut Diagnostics<'_>) -> Option<Spec> {
    let mut globals = HashMap::new();
    for p in &tlsf.parameters {
        globals.insert(p.name.as_str(), Global::Parameter(None));
    }
    for d in &tlsf.definitions {
        globals.insert(d.name.as_str(), Global::Definition(d));
    }
    let declared: HashSet<&str> = tlsf.inputs.iter().chain(&tlsf.outputs).map(|s| s.name.as_str()).collect();
    let mut ev = Evaluator::new(globals, declared, diags);
    for p in &tlsf.parameters {
        // The last override of a name wins, as on a command line.
        let value = match overrides.iter().rev().find(|(name, _)| *name == p.name) {
            Some((_, value)) => *value,
            None => ev.int(&p.value).ok()?,
        };
        ev.globals.insert(&p.name, Global::Parameter(Some(value)));
    }
    let signals = declare_signals(tlsf, &mut ev)?;

    let mut sections: HashMap<Section, Vec<Clause>> = HashMap::new();
    let mut failed = false;
    for (section, expr) in &tlsf.formulas {
        match ev.formula(expr) {
            Ok(f) => {
                let clauses = sections.entry(*section).or_default();
                split_conjunction(f.ltl, expr.span, clauses);
            }
            Err(_) => failed = true,
        }
    }
    if failed {
        return None;
    }
    let semantics = tlsf.semantics.unwrap_or_else(|| {
        ev.diags().warning(Span::default(), "no `SEMANTICS` in `INFO`: Mealy semantics assumed");
        parser::SemanticsDecl { turn: Turn::Mealy, strict: false }
    });
    let main = tlsf.main_span.unwrap_or_default();
    let mut take = |s: Section| sections.remove(&s).unwrap_or_default();
    let parts = Parts {
        initially: take(Section::Initially),
        preset: take(Section::Preset),
        require: take(Section::Require),
        assume: take(Section::Assume),
        assert: take(Section::Assert),
        guarantee: take(Section::Guarantee),
    };
    let (assumptions, guarantees) = if semantics.strict { parts.strict(main) } else { parts.standard(main) };
    let spec = Spec {
        signals,
        assumptions,
        guarantees,
        semantics: match semantics.turn {
            Turn::Mealy => Semantics::Mealy,
            Turn::Moore => Semantics::Moore,
        },
        title: tlsf.title.clone(),
        ..Spec::default()
    };
    let depth = spec.formula().depth();
    if depth > MAX_FORMULA_DEPTH {
        let deepest = spec.assumptions.iter().chain(&spec.guarantees).max_by_key(|c| c.formula.depth());
        let span = deepest.map_or(main, |c| c.span);
        ev.diags().error(span, format!("the specification nests {depth} levels deep, more than {MAX_FORMULA_DEPTH}"));
        return None;
    }
    Some(spec)
}

/// The inputs, then the outputs, buses expanded to `r_0 … r_{n-1}`; registers them with the
/// evaluator. `None` if a width failed or two signals share a name (reported).
fn declare_signals<'t>(tlsf: &'t Tlsf, ev: &mut Evaluator<'t, '_, '_>) -> Option<Vec<Signal>> {
    let mut signals: Vec<Signal> = Vec::new();
    let mut names: HashMap<String, usize> = HashMap::new();
    let mut ok = true;
    let decls =
        tlsf.inputs.iter().map(|s| (s, SignalKind::Input)).chain(tlsf.outputs.iter().map(|s| (s, SignalKind::Output)));
    for (decl, kind) in decls {
        let expanded = match &decl.width {
            None => vec![decl.name.clone()],
            Some(width) => {
                let Ok(n) = ev.int(width) else {
                    ok = false;
                    continue;
                };
                if !(1..=MAX_BUS_WIDTH).contains(&n) {
                    let message =
                        format!("bus `{}` has width {n}: it must be between 1 and {MAX_BUS_WIDTH}", decl.name);
                    ev.diags().error(width.span, message);
                    ok = false;
                    continue;
                }
                (0..n).map(|i| format!("{}{BUS_DELIMITER}{i}", decl.name)).collect()
            }
        };
        let first = signals.len() as u32;
        for name in expanded {
            if let Some(&other) = names.get(&name) {
                let earlier = &signals[other];
                let (line, column) = ev.diags().line_col(earlier.span.start as usize);
                let message = if earlier.kind != kind {
                    format!("`{name}` is declared both as an input and as an output (also at {line}:{column})")
                } else {
                    format!("signal `{name}` clashes with the signal of that name declared at {line}:{column}")
                };
                ev.diags().error(decl.span, message);
                ok = false;
                continue;
            }
            names.insert(name.clone(), signals.len());
            signals.push(Signal { name, kind, span: decl.span });
        }
        let width = signals.len() as u32 - first;
        let global =
            if decl.width.is_some() { Global::Bus(Bus { first, width }) } else { Global::Signal(SignalId(first)) };
        ev.globals.insert(&decl.name, global);
    }
    ok.then_some(signals)
}

/// A top-level conjunction becomes one clause per conjunct, all located at the entry (as
/// SyfCo splits them), so that the engine sees the parts.
fn split_conjunction(f: Ltl, span: Span, out: &mut Vec<Clause>) {
    match f {
        Ltl::And(parts) => parts.into_iter().for_each(|p| split_conjunction(p, span, out)),
        formula => out.push(Clause { formula, span }),
    }
}

/// The evaluated sections of `MAIN`, each entry split into its conjuncts.
struct Parts {
    initially: Vec<Clause>,
    preset: Vec<Clause>,
    require: Vec<Clause>,
    assume: Vec<Clause>,
    assert: Vec<Clause>,
    guarantee: Vec<Clause>,
}

fn globally(clauses: Vec<Clause>) -> impl Iterator<Item = Clause> {
    clauses.into_iter().map(|c| Clause { formula: Ltl::globally(c.formula), span: c.span })
}

fn conjunction(clauses: &[Clause]) -> Ltl {
    Ltl::all(clauses.iter().map(|c| c.formula.clone()).collect())
}

impl Parts {
    /// Standard (Mealy, Moore) semantics. SyfCo's formula is
    /// `INITIALLY → (PRESET ∧ ((G REQUIRE ∧ ASSUME) → (G ASSERT ∧ GUARANTEE)))`. With no
    /// PRESET, or nothing assumed but INITIALLY, it equals
    /// `(INITIALLY ∧ G REQUIRE ∧ ASSUME) → (PRESET ∧ G ASSERT ∧ GUARANTEE)`: assumptions and
    /// guarantees clause by clause. Otherwise the PRESET holds even when the environment
    /// breaks its assumptions, which `A → G` cannot say: then the whole formula is one guarantee.
    fn standard(self, main: Span) -> (Vec<Clause>, Vec<Clause>) {
        let assumed: Vec<Clause> = globally(self.require).chain(self.assume).collect();
        let promised: Vec<Clause> = globally(self.assert).chain(self.guarantee).collect();
        if self.preset.is_empty() || assumed.is_empty() {
            let assumptions = self.initially.into_iter().chain(assumed).collect();
            return (assumptions, self.preset.into_iter().chain(promised).collect());
        }
        let inner = Ltl::implies(conjunction(&assumed), conjunction(&promised));
        let body = Ltl::all(self.preset.into_iter().map(|c| c.formula).chain([inner]).collect());
        (Vec::new(), vec![Clause { formula: implied_by(&self.initially, body), span: main }])
    }

    /// Strict semantics, as SyfCo turns it into a standard formula:
    /// `INITIALLY → (PRESET ∧ (ASSERT W ¬REQUIRE) ∧ ((G REQUIRE ∧ ASSUME) → GUARANTEE))`:
    /// the system keeps its invariants at least as long as the environment keeps its own
    /// (`G ASSERT` without requirements, nothing without invariants), and its guarantees are
    /// due only if the environment keeps all of its. One guarantee clause, located at `MAIN`.
    fn strict(self, main: Span) -> (Vec<Clause>, Vec<Clause>) {
        let mut body: Vec<Ltl> = self.preset.iter().map(|c| c.formula.clone()).collect();
        if !self.assert.is_empty() {
            let invariants = conjunction(&self.assert);
            body.push(if self.require.is_empty() {
                Ltl::globally(invariants)
            } else {
                Ltl::weak_until(invariants, Ltl::not(conjunction(&self.require)))
            });
        }
        if !self.guarantee.is_empty() {
            let assumed: Vec<Clause> = globally(self.require).chain(self.assume).collect();
            let promised = conjunction(&self.guarantee);
            body.push(if assumed.is_empty() { promised } else { Ltl::implies(conjunction(&assumed), promised) });
        }
        if body.is_empty() {
            return (Vec::new(), Vec::new());
        }
        (Vec::new(), vec![Clause { formula: implied_by(&self.initially, Ltl::all(body)), span: main }])
    }
}

/// `INITIALLY → body`, or `body` when nothing is initially assumed.
fn implied_by(initially: &[Clause], body: Ltl) -> Ltl {
    if initially.is_empty() {
        body
    } else {
        Ltl::implies(conjunction(initially), body)
    }
}
