//! Where the printed unit keeps its data: the global data block's layout (S7 packing of BOOLs,
//! words on even bytes), the block numbers of FCs, FBs and instance DBs, and the locations of
//! globals, the program's statics and instances' variables that an HMI or a test reads.

use super::{StlUnitOptions, Ty};
use crate::plc::model::unit::{PouKind, Type, Unit, Var};
use std::collections::HashMap;

/// Where a global variable lives in the global data block.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Location {
    pub name: String,
    pub ty: Type,
    pub db: u16,
    pub byte: u32,
    /// The bit of a BOOL (0 for other types).
    pub bit: u8,
}

impl Location {
    /// The absolute STL operand: `DB1.DBX 0.3`, `DB1.DBW 2`, `DB1.DBD 4`.
    pub fn operand(&self) -> String {
        match self.ty {
            Type::Bool => format!("DB{}.DBX {}.{}", self.db, self.byte, self.bit),
            Type::Int => format!("DB{}.DBW {}", self.db, self.byte),
            _ => format!("DB{}.DBD {}", self.db, self.byte),
        }
    }
}

/// Byte and bit of each variable of `sections`, laid out as S7 does (BOOLs packed into bytes,
/// other types on even bytes, every section on an even byte), and the total size in bytes.
pub(super) fn layout(sections: &[&[Var]]) -> (Vec<(u32, u8)>, u32) {
    let mut bits: u32 = 0;
    let mut out = Vec::new();
    let align = |bits: u32| bits.div_ceil(16) * 16;
    for section in sections {
        bits = align(bits);
        for v in section.iter() {
            match v.ty {
                Type::Bool => {
                    out.push((bits / 8, (bits % 8) as u8));
                    bits += 1;
                }
                Type::Int => {
                    bits = align(bits);
                    out.push((bits / 8, 0));
                    bits += 16;
                }
                _ => {
                    bits = align(bits);
                    out.push((bits / 8, 0));
                    bits += 32;
                }
            }
        }
    }
    (out, align(bits) / 8)
}

/// The globals of `unit` in the global data block, in declaration order. Timers and block
/// instances are not in it (each has its own instance DB, listed in the header).
pub fn global_locations(unit: &Unit, options: &StlUnitOptions) -> Vec<Location> {
    let scalars: Vec<Var> = unit.globals.iter().filter(|v| Ty::of(&v.ty).is_some()).cloned().collect();
    let (places, _) = layout(&[&scalars]);
    scalars
        .iter()
        .zip(places)
        .map(|(v, (byte, bit))| Location { name: v.name.clone(), ty: v.ty.clone(), db: options.first_db, byte, bit })
        .collect()
}

/// The program's inputs, outputs and statics (BOOL, INT, DINT, TIME, REAL) in its instance DB: a
/// supervisor's state kept by the program is found there. Empty when the unit has no program.
pub fn program_locations(unit: &Unit, options: &StlUnitOptions) -> Vec<Location> {
    let Some(program) = unit.pous.last().filter(|p| p.kind == PouKind::Program) else { return Vec::new() };
    let db = blocks(unit, options).program_db;
    let scalars = |vars: &[Var]| -> Vec<Var> { vars.iter().filter(|v| Ty::of(&v.ty).is_some()).cloned().collect() };
    let sections = [scalars(&program.inputs), scalars(&program.outputs), scalars(&program.locals)];
    let (places, _) = layout(&[&sections[0], &sections[1], &sections[2]]);
    sections
        .iter()
        .flatten()
        .zip(places)
        .map(|(v, (byte, bit))| Location { name: v.name.clone(), ty: v.ty.clone(), db, byte, bit })
        .collect()
}

/// The inputs, outputs and statics (BOOL, INT, DINT, TIME, REAL) of `instance` — a global or a local
/// of the program that is an instance of one of the unit's function blocks — in its instance
/// DB: what a watch table or a test reads. Statics declared after a timer are not listed (a
/// multi-instance of SFB 4 has a layout of its own). Empty when there is no such instance.
pub fn instance_locations(unit: &Unit, options: &StlUnitOptions, instance: &str) -> Vec<Location> {
    let blocks = blocks(unit, options);
    let Some((_, _, Type::Instance(name), db)) = blocks.instances.iter().find(|(_, n, _, _)| n == instance) else {
        return Vec::new();
    };
    let Some(fb) = unit.pou(name) else { return Vec::new() };
    // Statics after a timer's multi-instance (SFB 4 has a layout of its own) are left out.
    let scalars = |vars: &[Var]| -> Vec<Var> { vars.iter().filter(|v| Ty::of(&v.ty).is_some()).cloned().collect() };
    let statics: Vec<Var> = fb.locals.iter().take_while(|v| Ty::of(&v.ty).is_some()).cloned().collect();
    let sections = [scalars(&fb.inputs), scalars(&fb.outputs), statics];
    let (places, _) = layout(&[&sections[0], &sections[1], &sections[2]]);
    sections
        .iter()
        .flatten()
        .zip(places)
        .map(|(v, (byte, bit))| Location { name: v.name.clone(), ty: v.ty.clone(), db: *db, byte, bit })
        .collect()
}

/// Where an instance lives: a global or a local of the program.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub(super) enum Owner {
    Global,
    Program,
}

/// The blocks of the printed unit.
pub(super) struct Blocks {
    pub(super) fc: HashMap<String, u16>,
    pub(super) fb: HashMap<String, u16>,
    /// Instance DBs of timers and of the unit's function blocks: (owner, name) → (DB, type).
    pub(super) instances: Vec<(Owner, String, Type, u16)>,
    pub(super) program_db: u16,
    pub(super) globals: Vec<Location>,
}

pub(super) fn blocks(unit: &Unit, options: &StlUnitOptions) -> Blocks {
    let mut fc = HashMap::new();
    let mut fb = HashMap::new();
    let (mut next_fc, mut next_fb) = (options.first_fc, options.first_fb);
    for pou in &unit.pous {
        match pou.kind {
            PouKind::Function { .. } => {
                fc.insert(pou.name.clone(), next_fc);
                next_fc = next_fc.saturating_add(1);
            }
            _ => {
                fb.insert(pou.name.clone(), next_fb);
                next_fb = next_fb.saturating_add(1);
            }
        }
    }
    let mut next_db = options.first_db.saturating_add(1);
    let mut instances = Vec::new();
    let own_db = |ty: &Type| match ty {
        Type::Ton => true,
        Type::Instance(name) => unit.pou(name).is_some_and(|p| matches!(p.kind, PouKind::FunctionBlock)),
        _ => false,
    };
    for v in &unit.globals {
        if own_db(&v.ty) {
            instances.push((Owner::Global, v.name.clone(), v.ty.clone(), next_db));
            next_db = next_db.saturating_add(1);
        }
    }
    if let Some(program) = unit.pous.last().filter(|p| p.kind == PouKind::Program) {
        for v in &program.locals {
            if own_db(&v.ty) {
                instances.push((Owner::Program, v.name.clone(), v.ty.clone(), next_db));
                next_db = next_db.saturating_add(1);
            }
        }
    }
    Blocks { fc, fb, instances, program_db: next_db, globals: global_locations(unit, options) }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn layout_packs_bools_and_aligns_words_and_sections() {
        let v = |ty: Type| Var::new("x", ty, "");
        let (places, size) = layout(&[&[v(Type::Bool), v(Type::Bool), v(Type::Int), v(Type::Dint), v(Type::Bool)]]);
        assert_eq!(places, vec![(0, 0), (0, 1), (2, 0), (4, 0), (8, 0)]);
        assert_eq!(size, 10);
        // As awlsim lays out an FB: every declaration section starts on an even byte.
        let (places, size) = layout(&[&[v(Type::Bool)], &[v(Type::Bool), v(Type::Int)], &[v(Type::Bool)]]);
        assert_eq!(places, vec![(0, 0), (2, 0), (4, 0), (6, 0)]);
        assert_eq!(size, 8);
    }
}
