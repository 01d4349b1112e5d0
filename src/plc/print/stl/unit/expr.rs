//! Expressions: places to operands, the types of expressions, BOOL logic through the RLO
//! (brackets, hoisting what nests too deep), loads, comparisons and arithmetic in the
//! accumulators, stores, and the Structured Text of places and expressions for comments.

use super::layout::layout;
use super::{fits_int, real_literal, shadow, time_literal, type_name, Gen, TempKind, Ty, MAX_DEPTH};
use crate::plc::model::unit::{BinOp, Expr, Place, Type, Unit};
use crate::plc::siemens_address;

impl<'a> Gen<'a> {
    /// The STL operand of a scalar place.
    pub(super) fn operand(&mut self, place: &Place) -> Result<String, String> {
        let ty = self.place_type(place)?;
        let scalar = Ty::of(&ty)
            .ok_or_else(|| format!("`{}` is not a BOOL, INT, DINT, TIME or REAL", place_text(self.unit, place)))?;
        match place {
            Place::Global(name) => {
                if self.unit.constants.iter().any(|c| c.name == *name) {
                    return Err(format!("constant `{name}` cannot be written"));
                }
                let loc = self.blocks.globals.iter().find(|l| l.name == *name).expect("a scalar global has a place");
                Ok(loc.operand())
            }
            Place::Local(name) => {
                if self.is_function() && *name == self.pou.name {
                    Ok("#RET_VAL".into())
                } else {
                    Ok(format!("#{name}"))
                }
            }
            Place::Signal(i) => signal_operand(&self.unit.signals[*i].address, scalar),
            Place::Member(inner, field) => {
                if let Some(timer) = self.block_timer(inner) {
                    // awlsim cannot read `#t.Q`: the call copies Q and ET into statics.
                    let field = field.to_ascii_uppercase();
                    return match field.as_str() {
                        "Q" | "ET" => Ok(format!("#{}", shadow(timer, &field))),
                        _ => Err(format!(
                            "`{timer}.{field}` of a timer in a function block (STL keeps only its Q and ET)"
                        )),
                    };
                }
                let db = self.instance_db(inner).ok_or_else(|| {
                    format!(
                        "`{}` is an instance inside a function or function block; STL reads members only of \
                         instances with their own DB (globals or locals of the program)",
                        place_text(self.unit, inner)
                    )
                })?;
                let field = field.to_ascii_uppercase();
                match self.place_type(inner)? {
                    Type::Ton => Ok(match field.as_str() {
                        "IN" => format!("DB{db}.DBX 0.0"),
                        "PT" => format!("DB{db}.DBD 2"),
                        "Q" => format!("DB{db}.DBX 6.0"),
                        _ => format!("DB{db}.DBD 8"),
                    }),
                    Type::Instance(fb_name) => {
                        let fb = self.unit.pou(&fb_name).expect("checked by place_type");
                        let (places, _) = layout(&[&fb.inputs, &fb.outputs, &fb.locals]);
                        let k = fb
                            .inputs
                            .iter()
                            .chain(&fb.outputs)
                            .chain(&fb.locals)
                            .position(|v| v.name.eq_ignore_ascii_case(&field))
                            .expect("checked by place_type");
                        let (byte, bit) = places[k];
                        Ok(match scalar {
                            Ty::Bool => format!("DB{db}.DBX {byte}.{bit}"),
                            Ty::Int => format!("DB{db}.DBW {byte}"),
                            _ => format!("DB{db}.DBD {byte}"),
                        })
                    }
                    _ => unreachable!("place_type accepts members of instances only"),
                }
            }
        }
    }

    /// The type of an expression; an integer literal is INT when it fits.
    pub(super) fn ty(&self, e: &Expr) -> Result<Ty, String> {
        match e {
            Expr::Bool(_) => Ok(Ty::Bool),
            Expr::Int(n) => Ok(if fits_int(*n) { Ty::Int } else { Ty::Dint }),
            Expr::Real(_) => Ok(Ty::Real),
            Expr::Time(_) => Ok(Ty::Time),
            Expr::Read(p) => {
                let ty = self.place_type(p)?;
                Ty::of(&ty)
                    .ok_or_else(|| format!("`{}` of type {} is not a value", place_text(self.unit, p), type_name(&ty)))
            }
            Expr::Not(x) => match self.ty(x)? {
                Ty::Bool => Ok(Ty::Bool),
                t => Err(format!("NOT of {} (bitwise NOT is not printed in STL)", t.name())),
            },
            Expr::Neg(x) => match self.ty(x)? {
                Ty::Bool => Err("negation of a BOOL".into()),
                t => Ok(t),
            },
            Expr::Binary(op, a, b) => {
                let (ta, tb) = (self.ty(a)?, self.ty(b)?);
                if (ta == Ty::Real) != (tb == Ty::Real) && ta != Ty::Bool && tb != Ty::Bool {
                    return Err(format!(
                        "`{}` of {} and {}: IEC needs an explicit conversion between REAL and integers",
                        op.text(),
                        ta.name(),
                        tb.name()
                    ));
                }
                if ta == Ty::Real && matches!(op, BinOp::Mod) {
                    return Err("MOD of REAL values".into());
                }
                match op {
                    BinOp::And | BinOp::Or | BinOp::Xor => {
                        if ta == Ty::Bool && tb == Ty::Bool {
                            Ok(Ty::Bool)
                        } else {
                            Err(format!(
                                "{} of {} and {} (bitwise logic is not printed in STL)",
                                op.text(),
                                ta.name(),
                                tb.name()
                            ))
                        }
                    }
                    BinOp::Eq | BinOp::Ne => {
                        if (ta == Ty::Bool) != (tb == Ty::Bool) {
                            Err(format!("comparison of {} and {}", ta.name(), tb.name()))
                        } else {
                            Ok(Ty::Bool)
                        }
                    }
                    BinOp::Lt | BinOp::Le | BinOp::Gt | BinOp::Ge => {
                        if ta == Ty::Bool || tb == Ty::Bool {
                            Err(format!("ordering comparison of {} and {}", ta.name(), tb.name()))
                        } else {
                            Ok(Ty::Bool)
                        }
                    }
                    _ => {
                        if ta == Ty::Bool || tb == Ty::Bool {
                            Err(format!("arithmetic on {} and {}", ta.name(), tb.name()))
                        } else {
                            Ok(numeric(ta, tb))
                        }
                    }
                }
            }
        }
    }

    /// A BOOL operand read directly (`A op`), or `None` when the expression needs code.
    fn bit_operand(&mut self, e: &Expr) -> Option<String> {
        let Expr::Read(p) = e else { return None };
        if self.constant(p).is_some() {
            return None;
        }
        self.operand(p).ok()
    }

    /// Code that leaves BOOL `e` in the RLO, starting a new logic string (first check).
    fn bool_fresh(&mut self, e: &Expr, depth: usize) {
        match e {
            Expr::Bool(b) => self.emit(if *b { "SET" } else { "CLR" }),
            Expr::Read(p) => {
                if let Some(c) = self.constant(p) {
                    return self.bool_fresh(&c, depth);
                }
                match self.operand(p) {
                    Ok(op) => self.emit(&format!("A\t{op}")),
                    Err(m) => self.error(m),
                }
            }
            Expr::Not(x) => match self.bit_operand(x) {
                Some(op) => self.emit(&format!("AN\t{op}")),
                None => {
                    self.bool_fresh(x, depth);
                    self.emit("NOT");
                }
            },
            Expr::Binary(op @ (BinOp::And | BinOp::Or | BinOp::Xor), _, _) => {
                let letter = match op {
                    BinOp::And => "A",
                    BinOp::Or => "O",
                    _ => "X",
                };
                let mut terms = Vec::new();
                flatten(*op, e, &mut terms);
                for t in terms {
                    self.bool_term(letter, t, false, depth);
                }
            }
            Expr::Binary(op @ (BinOp::Eq | BinOp::Ne), a, b) if self.ty(a) == Ok(Ty::Bool) => {
                self.bool_term("A", a, false, depth);
                self.bool_term(if *op == BinOp::Eq { "XN" } else { "X" }, b, false, depth);
            }
            Expr::Binary(op, a, b) if is_comparison(*op) => self.compare(*op, a, b),
            other => match self.ty(other) {
                Err(m) => self.error(m),
                Ok(t) => self.error(format!("a {} expression where a BOOL is needed", t.name())),
            },
        }
    }

    /// Combines `e` with the RLO by `letter` (`A`, `O`, `X`; negated with `N`).
    fn bool_term(&mut self, letter: &str, e: &Expr, negate: bool, depth: usize) {
        if let Expr::Not(x) = e {
            return self.bool_term(letter, x, !negate, depth);
        }
        let letter = match (letter, negate) {
            ("XN", true) => "X".to_string(),
            (l, true) => format!("{l}N"),
            (l, false) => l.to_string(),
        };
        if let Some(op) = self.bit_operand(e) {
            return self.emit(&format!("{letter}\t{op}"));
        }
        if depth + 1 >= MAX_DEPTH {
            // Too deep for the nesting stack: compute it first into a temporary bit.
            let saved = std::mem::take(&mut self.code);
            let tmp = self.push_temp(TempKind::X);
            self.bool_fresh(e, 0);
            self.emit(&format!("=\t{tmp}"));
            let hoisted = std::mem::replace(&mut self.code, saved);
            self.hoisted.push(hoisted);
            self.emit(&format!("{letter}\t{tmp}"));
            return;
        }
        self.emit(&format!("{letter}("));
        self.bool_fresh(e, depth + 1);
        self.emit(")");
    }
}

pub(super) fn flatten<'e>(op: BinOp, e: &'e Expr, out: &mut Vec<&'e Expr>) {
    match e {
        Expr::Binary(o, a, b) if *o == op => {
            flatten(op, a, out);
            flatten(op, b, out);
        }
        _ => out.push(e),
    }
}

/// Whether a value of type `value` cannot be stored into a `target` (BOOL only into BOOL, REAL
/// only into REAL; integers of any width into each other).
pub(super) fn incompatible(value: Ty, target: Ty) -> bool {
    (value == Ty::Bool) != (target == Ty::Bool) || (value == Ty::Real) != (target == Ty::Real)
}

fn is_comparison(op: BinOp) -> bool {
    matches!(op, BinOp::Eq | BinOp::Ne | BinOp::Lt | BinOp::Le | BinOp::Gt | BinOp::Ge)
}

/// The type arithmetic on `a` and `b` has.
fn numeric(a: Ty, b: Ty) -> Ty {
    if a == Ty::Real || b == Ty::Real {
        Ty::Real
    } else if a == Ty::Time || b == Ty::Time {
        Ty::Time
    } else if a == Ty::Dint || b == Ty::Dint {
        Ty::Dint
    } else {
        Ty::Int
    }
}

/// The STL operand of a signal address (IEC form without `%`) read as `ty`.
pub(super) fn signal_operand(address: &str, ty: Ty) -> Result<String, String> {
    let a = siemens_address(address);
    let bad = || format!("`{address}` is not an I, Q or M address of a {}", ty.name());
    let split = a.find(|c: char| c.is_ascii_digit()).ok_or_else(bad)?;
    let (area, number) = a.split_at(split);
    let (mem, size) = match area {
        "I" | "Q" | "M" => (area, ""),
        "IB" | "QB" | "MB" | "IW" | "QW" | "MW" | "ID" | "QD" | "MD" => area.split_at(1),
        _ => return Err(bad()),
    };
    let _ = mem;
    let ok = match ty {
        Ty::Bool => {
            size.is_empty()
                && number
                    .split_once('.')
                    .is_some_and(|(b, x)| b.parse::<u32>().is_ok() && x.parse::<u8>().is_ok_and(|x| x < 8))
        }
        Ty::Int => size == "W" && number.parse::<u32>().is_ok(),
        Ty::Dint | Ty::Time | Ty::Real => size == "D" && number.parse::<u32>().is_ok(),
    };
    if ok {
        Ok(format!("{area} {number}"))
    } else {
        Err(bad())
    }
}

/// Structured Text of a place, for comments.
pub(super) fn place_text(unit: &Unit, place: &Place) -> String {
    match place {
        Place::Global(n) | Place::Local(n) => n.clone(),
        Place::Signal(i) => unit.signals.get(*i).map_or_else(|| format!("signal{i}"), |s| s.symbol.clone()),
        Place::Member(inner, f) => format!("{}.{f}", place_text(unit, inner)),
    }
}

/// Structured Text of an expression, for comments.
pub(super) fn expr_text(unit: &Unit, e: &Expr) -> String {
    fn go(unit: &Unit, e: &Expr, out: &mut String) -> u8 {
        match e {
            Expr::Bool(b) => out.push_str(if *b { "TRUE" } else { "FALSE" }),
            Expr::Int(n) => out.push_str(&n.to_string()),
            Expr::Real(r) => out.push_str(&r.iec_text()),
            Expr::Time(ms) => out.push_str(&time_literal(i64::try_from(*ms).unwrap_or(i64::MAX))),
            Expr::Read(p) => out.push_str(&place_text(unit, p)),
            Expr::Not(x) | Expr::Neg(x) => {
                out.push_str(if matches!(e, Expr::Not(_)) { "NOT " } else { "-" });
                let mut inner = String::new();
                // Binary operands, nested unary ones and negative literals in parentheses
                // (`NOT (NOT a)`, `-(-x)`, `-(-5)`).
                let negative = matches!(x.as_ref(), Expr::Int(n) if *n < 0)
                    || matches!(x.as_ref(), Expr::Real(r) if r.value() < 0.0);
                if go(unit, x, &mut inner) <= 8 || negative {
                    out.push_str(&format!("({inner})"));
                } else {
                    out.push_str(&inner);
                }
                return 8;
            }
            Expr::Binary(op, a, b) => {
                let p = op.precedence();
                for (k, x) in [a, b].into_iter().enumerate() {
                    let mut inner = String::new();
                    let q = go(unit, x, &mut inner);
                    let negative = match x.as_ref() {
                        Expr::Int(n) => *n < 0,
                        Expr::Real(r) => r.value() < 0.0,
                        _ => false,
                    };
                    if q < p || (k == 1 && q == p) || negative {
                        out.push_str(&format!("({inner})"));
                    } else {
                        out.push_str(&inner);
                    }
                    if k == 0 {
                        out.push_str(&format!(" {} ", op.text()));
                    }
                }
                return p;
            }
        }
        9
    }
    let mut out = String::new();
    go(unit, e, &mut out);
    out
}

impl Gen<'_> {
    /// Code that leaves BOOL `e` in the RLO, with the subexpressions too deep to nest computed
    /// first into temporary bits.
    pub(super) fn bool_value(&mut self, e: &Expr) {
        let bits = self.temps[TempKind::X.index()];
        let saved_hoisted = std::mem::take(&mut self.hoisted);
        let saved = std::mem::take(&mut self.code);
        self.bool_fresh(e, 0);
        let main = std::mem::replace(&mut self.code, saved);
        for h in std::mem::replace(&mut self.hoisted, saved_hoisted) {
            self.code.push_str(&h);
        }
        self.code.push_str(&main);
        self.temps[TempKind::X.index()] = bits;
    }

    /// An integer or time literal as loaded into a 16-bit (`wide == false`) or 32-bit accumulator.
    fn number_literal(&mut self, e: &Expr, ty: Ty) -> Option<String> {
        match (e, ty) {
            (Expr::Real(r), Ty::Real) => Some(real_literal(*r)),
            (Expr::Real(_), _) | (_, Ty::Real) => {
                self.error(format!("{} where a {} is needed", expr_text(self.unit, e), ty.name()));
                Some("0".into())
            }
            (Expr::Int(n), Ty::Int) => {
                if fits_int(*n) {
                    Some(n.to_string())
                } else {
                    self.error(format!("{n} does not fit in an INT"));
                    Some("0".into())
                }
            }
            (Expr::Int(n), Ty::Dint) => {
                if i32::try_from(*n).is_err() {
                    self.error(format!("{n} does not fit in a DINT"));
                }
                Some(format!("L#{}", *n as i32))
            }
            (Expr::Int(n), _) => Some(self.time(*n)),
            (Expr::Time(ms), _) => Some(self.time(i64::try_from(*ms).unwrap_or(i64::MAX))),
            _ => None,
        }
    }

    /// A TIME literal, or an error beyond the range of TIME (±24 days).
    fn time(&mut self, ms: i64) -> String {
        if i32::try_from(ms).is_err() {
            self.error(format!("{ms} ms is beyond the range of TIME (T#24D20H31M23S647MS)"));
        }
        time_literal(ms)
    }

    /// Whether `e` loads with one `L` (and perhaps `ITD`).
    fn simple_load(&self, e: &Expr) -> bool {
        match e {
            Expr::Int(_) | Expr::Real(_) | Expr::Time(_) => true,
            Expr::Read(p) => self.constant(p).is_some() || Ty::of(&self.place_type(p).unwrap_or(Type::Ton)).is_some(),
            _ => false,
        }
    }

    /// Code that leaves numeric `e` in ACCU1, as 16 bits for `ty` INT and 32 bits otherwise.
    pub(super) fn load(&mut self, e: &Expr, ty: Ty) {
        let own = match self.ty(e) {
            Ok(Ty::Bool) => return self.error("a BOOL expression where a number is needed".into()),
            Ok(t) => t,
            Err(m) => return self.error(m),
        };
        let widen = !own.wide() && ty.wide();
        match e {
            Expr::Int(_) | Expr::Real(_) | Expr::Time(_) => {
                let lit = self.number_literal(e, if widen { ty } else { own }).unwrap_or_default();
                return self.emit(&format!("L\t{lit}"));
            }
            Expr::Read(p) => {
                if let Some(c) = self.constant(p) {
                    let lit = self.number_literal(&c, ty).unwrap_or_default();
                    return self.emit(&format!("L\t{lit}"));
                }
                match self.operand(p) {
                    Ok(op) => self.emit(&format!("L\t{op}")),
                    Err(m) => return self.error(m),
                }
            }
            Expr::Neg(x) => {
                self.load(x, own);
                self.emit(match own {
                    Ty::Real => "NEGR",
                    t if t.wide() => "NEGD",
                    _ => "NEGI",
                });
            }
            Expr::Binary(op, a, b) => {
                self.load_pair(a, b, own);
                let s = match own {
                    Ty::Real => "R",
                    t if t.wide() => "D",
                    _ => "I",
                };
                match op {
                    BinOp::Add => self.emit(&format!("+{s}")),
                    BinOp::Sub => self.emit(&format!("-{s}")),
                    BinOp::Mul => self.emit(&format!("*{s}")),
                    BinOp::Div => self.emit(&format!("/{s}")),
                    BinOp::Mod if own.wide() => self.emit("MOD"),
                    BinOp::Mod => {
                        // The remainder of /I is in the high word.
                        self.emit("/I");
                        self.emit("SRD\t16");
                    }
                    _ => return self.error(format!("{} where a number is needed", op.text())),
                }
            }
            Expr::Bool(_) | Expr::Not(_) => unreachable!("typed BOOL above"),
        }
        if widen {
            self.emit("ITD");
        }
    }

    /// `a` into ACCU2 and `b` into ACCU1, both as `ty`.
    fn load_pair(&mut self, a: &Expr, b: &Expr, ty: Ty) {
        if self.simple_load(b) {
            self.load(a, ty);
            self.load(b, ty);
        } else {
            let kind = TempKind::of(ty);
            let tmp = self.push_temp(kind);
            self.load(b, ty);
            self.emit(&format!("T\t{tmp}"));
            self.load(a, ty);
            self.emit(&format!("L\t{tmp}"));
            self.pop_temp(kind);
        }
    }

    /// A comparison of numbers, its result in the RLO.
    fn compare(&mut self, op: BinOp, a: &Expr, b: &Expr) {
        let ty = match (self.ty(a), self.ty(b)) {
            (Ok(x), Ok(y)) if (x == Ty::Real) != (y == Ty::Real) && x != Ty::Bool && y != Ty::Bool => {
                return self.error(format!(
                    "`{}` of {} and {}: IEC needs an explicit conversion between REAL and integers",
                    op.text(),
                    x.name(),
                    y.name()
                ))
            }
            (Ok(x), Ok(y)) => numeric(x, y),
            (Err(m), _) | (_, Err(m)) => return self.error(m),
        };
        self.load_pair(a, b, ty);
        let cmp = match op {
            BinOp::Eq => "==",
            BinOp::Ne => "<>",
            BinOp::Lt => "<",
            BinOp::Le => "<=",
            BinOp::Gt => ">",
            _ => ">=",
        };
        self.emit(&format!(
            "{cmp}{}",
            match ty {
                Ty::Real => "R",
                t if t.wide() => "D",
                _ => "I",
            }
        ));
    }

    /// Stores `value` into the operand `op` of type `ty`.
    pub(super) fn store(&mut self, value: &Expr, ty: Ty, op: &str) {
        if ty == Ty::Bool {
            self.bool_value(value);
            self.emit(&format!("=\t{op}"));
        } else {
            // A DINT value stored into an INT keeps its low word, as the CPU does.
            let vty = self.ty(value).unwrap_or(ty);
            self.load(value, if vty.wide() && !ty.wide() { vty } else { ty });
            self.emit(&format!("T\t{op}"));
        }
    }

    /// An actual parameter of type `ty`: a literal, or a temporary holding the value (the
    /// temporary stays allocated until the caller pops it). Returns the text and the temporary's
    /// kind.
    pub(super) fn argument(&mut self, value: &Expr, ty: Ty) -> (String, Option<TempKind>) {
        let value = match value {
            Expr::Read(p) => self.constant(p).unwrap_or_else(|| value.clone()),
            _ => value.clone(),
        };
        if let Ok(vt) = self.ty(&value) {
            if (vt == Ty::Real) != (ty == Ty::Real) {
                self.error(format!(
                    "{} of type {} passed as a {}: IEC needs an explicit conversion between REAL and integers",
                    expr_text(self.unit, &value),
                    vt.name(),
                    ty.name()
                ));
            }
        }
        match (&value, ty) {
            (Expr::Bool(b), Ty::Bool) => return ((if *b { "TRUE" } else { "FALSE" }).into(), None),
            (Expr::Int(_) | Expr::Time(_), Ty::Int | Ty::Dint | Ty::Time) => {
                if let Some(lit) = self.number_literal(&value, ty) {
                    return (lit, None);
                }
            }
            _ => {}
        }
        let kind = TempKind::of(ty);
        let tmp = self.push_temp(kind);
        self.store(&value, ty, &tmp);
        (tmp, Some(kind))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn signal_addresses() {
        assert_eq!(signal_operand("IX0.1", Ty::Bool), Ok("I 0.1".into()));
        assert_eq!(signal_operand("QX0.0", Ty::Bool), Ok("Q 0.0".into()));
        assert_eq!(signal_operand("MX20.3", Ty::Bool), Ok("M 20.3".into()));
        assert_eq!(signal_operand("IW4", Ty::Int), Ok("IW 4".into()));
        assert_eq!(signal_operand("MD8", Ty::Dint), Ok("MD 8".into()));
        assert!(signal_operand("IW4", Ty::Bool).is_err());
        assert!(signal_operand("IX0.8", Ty::Bool).is_err());
        assert!(signal_operand("GVL.lamp", Ty::Bool).is_err());
        assert!(signal_operand("", Ty::Bool).is_err());
    }
}
