//! What STL cannot say: the problems that keep a unit from printing, found by generating every
//! block and checking block numbers, names and the controller's place.

use super::layout::blocks;
use super::stmt::generate;
use super::{fits_int, init_literal, type_name, valid_name, StlUnitOptions, Ty};
use crate::plc::model::unit::{Expr, PouKind, Type, Unit};

/// Problems that keep `unit` from printing as STL with `options`; empty when it prints.
pub fn check(unit: &Unit, options: &StlUnitOptions) -> Vec<String> {
    let blocks = blocks(unit, options);
    let mut errors = Vec::new();
    for v in unit.constants.iter().chain(&unit.globals) {
        if !valid_name(&v.name) {
            errors.push(format!(
                "global `{}` is not an STL name (letters, digits and single underscores, at most 24 characters)",
                v.name
            ));
        }
    }
    let vars =
        unit.globals.iter().chain(unit.pous.iter().flat_map(|p| p.inputs.iter().chain(&p.outputs).chain(&p.locals)));
    for v in vars {
        if v.init.is_some() && Ty::of(&v.ty).is_some() {
            let fits = match (init_literal(v, unit), v.init.as_ref()) {
                (None, _) => false,
                (Some(_), Some(Expr::Int(n))) if v.ty == Type::Int => fits_int(*n),
                (Some(_), Some(Expr::Int(n))) => i32::try_from(*n).is_ok(),
                _ => true,
            };
            if !fits {
                errors.push(format!("the initial value of `{}` is not a literal of type {}", v.name, type_name(&v.ty)));
            }
        }
    }
    for c in &unit.constants {
        if !matches!(c.init, Some(Expr::Bool(_) | Expr::Int(_) | Expr::Real(_) | Expr::Time(_))) {
            errors.push(format!("constant `{}` needs a literal value", c.name));
        }
    }
    for v in &unit.globals {
        if v.at.is_some() {
            errors.push(format!(
                "global `{}` is wired to the process: the STL form keeps every global in its data block",
                v.name
            ));
        }
        if let Type::Instance(name) = &v.ty {
            if unit.pou(name).is_some_and(|p| p.kind != PouKind::FunctionBlock) {
                errors.push(format!("global `{}` is an instance of `{name}`, which is not a function block", v.name));
            }
        }
    }
    match unit.pous.last() {
        Some(p) if p.kind == PouKind::Program => {}
        _ => errors.push("the unit's last POU is not a program".into()),
    }
    if unit.pous.iter().filter(|p| p.kind == PouKind::Program).count() > 1 {
        errors.push("the unit has more than one program".into());
    }
    let mut externals: std::collections::BTreeSet<&str> = std::collections::BTreeSet::new();
    externals.extend(unit.globals.iter().chain(unit.pous.iter().flat_map(|p| &p.locals)).filter_map(|v| match &v.ty {
        Type::Instance(name) if unit.pou(name).is_none() => Some(name.as_str()),
        _ => None,
    }));
    if externals.len() > 1 {
        errors.push(format!("instances of several external block types {externals:?}: STL knows one controller FB"));
    }
    if blocks.fb.values().any(|&n| n == options.controller_fb) && !externals.is_empty() {
        errors.push(format!("the controller's FB {} is also a block of the unit", options.controller_fb));
    }
    let dbs: Vec<u16> = std::iter::once(options.first_db)
        .chain(blocks.instances.iter().map(|i| i.3))
        .chain(std::iter::once(blocks.program_db))
        .collect();
    if !externals.is_empty() && dbs.contains(&options.controller_db) {
        errors.push(format!("the controller's DB {} is also a data block of the unit", options.controller_db));
    }
    for pou in &unit.pous {
        errors.extend(generate(unit, options, &blocks, pou).errors);
    }
    errors
}
