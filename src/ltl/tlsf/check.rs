//! The name check before evaluation: every name in the file (in definitions that are never
//! called, too) must be a bound variable, an argument, a parameter, a definition or a signal;
//! calls must match the definition's arity. Reports each problem, with a close name as a hint.

use super::parser::{Binder, Domain, Expr, ExprKind, Tlsf};
use crate::diag::{Diagnostics, Span};
use std::collections::HashMap;

/// What a global name is, as far as the check needs to know.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    Parameter,
    /// A definition and its number of parameters.
    Definition(usize),
    Signal,
    Bus,
}

struct Checker<'t, 'd, 's> {
    globals: &'t HashMap<&'t str, Kind>,
    /// Arguments and bound variables in scope, innermost last.
    scope: Vec<&'t str>,
    diags: &'d mut Diagnostics<'s>,
}

/// Checks every expression of `tlsf` against `globals`.
pub fn check_names<'t>(tlsf: &'t Tlsf, globals: &'t HashMap<&'t str, Kind>, diags: &mut Diagnostics<'_>) {
    let mut checker = Checker { globals, scope: Vec::new(), diags };
    for p in &tlsf.parameters {
        checker.expr(&p.value);
    }
    for d in &tlsf.definitions {
        checker.scope = d.params.iter().map(|(name, _)| name.as_str()).collect();
        for case in &d.cases {
            if let Some(guard) = &case.guard {
                checker.expr(guard);
            }
            checker.expr(&case.value);
        }
    }
    checker.scope.clear();
    for width in tlsf.inputs.iter().chain(&tlsf.outputs).filter_map(|s| s.width.as_ref()) {
        checker.expr(width);
    }
    for (_, formula) in &tlsf.formulas {
        checker.expr(formula);
    }
}

impl<'t> Checker<'t, '_, '_> {
    fn expr(&mut self, e: &'t Expr) {
        match &e.kind {
            ExprKind::Number(_) | ExprKind::True | ExprKind::False | ExprKind::Otherwise => {}
            ExprKind::Name(name) => {
                self.known(name, e.span);
            }
            ExprKind::Index { bus, bus_span, index } => {
                if let Some(kind) = self.known(bus, *bus_span) {
                    if kind != Kind::Bus {
                        self.diags.error(*bus_span, format!("`{bus}` is not a bus: only buses `{bus}[n]` are indexed"));
                    }
                }
                self.expr(index);
            }
            ExprKind::Call { name, name_span, args } => {
                match self.known(name, *name_span) {
                    Some(Kind::Definition(arity)) if arity != args.len() => {
                        self.diags.error(e.span, format!("`{name}` takes {arity} arguments, given {}", args.len()));
                    }
                    Some(Kind::Definition(_)) | None => {}
                    Some(_) => {
                        self.diags.error(*name_span, format!("`{name}` is not a function"));
                    }
                }
                args.iter().for_each(|a| self.expr(a));
            }
            ExprKind::Set(elements) => elements.iter().for_each(|x| self.expr(x)),
            ExprKind::Unary(_, x) => self.expr(x),
            ExprKind::Binary(_, a, b) => {
                self.expr(a);
                self.expr(b);
            }
            ExprKind::Chain(_, parts) => parts.iter().for_each(|x| self.expr(x)),
            ExprKind::NextN { count, body } => {
                self.expr(count);
                self.expr(body);
            }
            ExprKind::Bounded { from, to, body, .. } => {
                self.expr(from);
                self.expr(to);
                self.expr(body);
            }
            ExprKind::Big { binders, body, .. } => {
                let depth = self.scope.len();
                for Binder { var, domain, .. } in binders {
                    match domain {
                        Domain::Range { from, to, .. } => {
                            self.expr(from);
                            self.expr(to);
                        }
                        Domain::Set(set) => self.expr(set),
                    }
                    self.scope.push(var);
                }
                self.expr(body);
                self.scope.truncate(depth);
            }
        }
    }

    /// What `name` is (`None` for a local, whose kind is known only when evaluated), or an
    /// error if it is nothing.
    fn known(&mut self, name: &str, span: Span) -> Option<Kind> {
        if self.scope.contains(&name) {
            return None;
        }
        if let Some(kind) = self.globals.get(name) {
            return Some(*kind);
        }
        let candidates = self.scope.iter().copied().chain(self.globals.keys().copied());
        let hint = closest(name, candidates);
        let d = self.diags.error(span, format!("unknown name `{name}`"));
        if let Some(hint) = hint {
            d.with_note(format!("did you mean `{hint}`?"));
        }
        None
    }
}

/// The candidate nearest to `name` by edit distance, if it is close (at most a third of the
/// name's length, at least one edit); ties go to the alphabetically first.
fn closest<'a>(name: &str, candidates: impl Iterator<Item = &'a str>) -> Option<&'a str> {
    // The distance costs length × length: a long garbage word gets no hint.
    if name.len() > 64 {
        return None;
    }
    let limit = (name.chars().count() / 3).max(1);
    candidates.map(|c| (edit_distance(name, c), c)).filter(|(d, _)| *d <= limit).min().map(|(_, c)| c)
}

fn edit_distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut diagonal = row[0];
        row[0] = i + 1;
        for (j, cb) in b.iter().enumerate() {
            let substitution = diagonal + usize::from(ca != *cb);
            diagonal = row[j + 1];
            row[j + 1] = substitution.min(row[j] + 1).min(row[j + 1] + 1);
        }
    }
    row[b.len()]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn close_names_are_suggested() {
        assert_eq!(edit_distance("kitten", "sitting"), 3);
        let names = ["grant", "request", "idle"];
        assert_eq!(closest("grnt", names.iter().copied()), Some("grant"));
        assert_eq!(closest("x", names.iter().copied()), None);
    }
}
