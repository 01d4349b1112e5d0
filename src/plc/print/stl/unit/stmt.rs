//! Statements and blocks: assignments, `IF` and `CASE` (jump lists and comparison chains),
//! calls of functions (arguments through temporaries) and instances (timers, the unit's blocks,
//! the user's controller), and the code of one POU with its prologue.

use super::expr::incompatible;
use super::expr::{expr_text, place_text};
use super::layout::Blocks;
use super::{default_value, fits_int, shadow, type_name, valid_name, Gen, StlUnitOptions, TempKind, Ty};
use crate::plc::model::unit::{Expr, Next, Place, Pou, PouKind, StepList, Stmt, Type, Unit};
use std::fmt::Write;

impl Gen<'_> {
    pub(super) fn statements(&mut self, body: &[Stmt]) {
        for s in body {
            self.statement(s);
        }
    }

    pub(super) fn statement(&mut self, s: &Stmt) {
        let unit = self.unit;
        match s {
            Stmt::Comment(text) => self.comment(text),
            Stmt::Assign { target, value } => {
                self.comment(&format!("{} := {};", place_text(unit, target), expr_text(unit, value)));
                let ty = match self.place_type(target) {
                    Ok(t) => t,
                    Err(m) => return self.error(m),
                };
                let Some(ty) = Ty::of(&ty) else {
                    return self.error(format!("cannot assign to `{}`", place_text(unit, target)));
                };
                match self.ty(value) {
                    Ok(vt) if incompatible(vt, ty) => {
                        return self.error(format!(
                            "`{}` of type {} gets a value of type {}",
                            place_text(unit, target),
                            ty.name(),
                            vt.name()
                        ))
                    }
                    Err(m) => return self.error(m),
                    _ => {}
                }
                match self.operand(target) {
                    Ok(op) => self.store(value, ty, &op),
                    Err(m) => self.error(m),
                }
            }
            Stmt::If { arms, otherwise } => {
                let end = self.new_label();
                for (k, (cond, body)) in arms.iter().enumerate() {
                    let word = if k == 0 { "IF" } else { "ELSIF" };
                    self.comment(&format!("{word} {} THEN", expr_text(unit, cond)));
                    let next = self.new_label();
                    self.bool_value(cond);
                    self.emit(&format!("JCN\t{next}"));
                    self.statements(body);
                    self.emit(&format!("JU\t{end}"));
                    self.place_label(&next);
                }
                if !otherwise.is_empty() {
                    self.comment("ELSE");
                    self.statements(otherwise);
                }
                self.comment("END_IF");
                self.place_label(&end);
            }
            Stmt::Case { selector, arms, otherwise } => self.case(selector, arms, otherwise),
            Stmt::CallFunction { function, args, result } => self.call_function(function, args, result.as_ref()),
            Stmt::CallInstance { instance, args } => self.call_instance(instance, args),
            Stmt::Steps(list) => self.step_list(list),
        }
    }

    /// A step list in the layout of Peter 2005, 6.7.2: a jump list on the position (a chain of
    /// comparisons beyond 255 steps), a label per step; a wait stores its own position and ends
    /// the scan (`JCN` to the list's end) while its condition is false; a position outside the
    /// list restarts it at step 0 in the next scan.
    fn step_list(&mut self, list: &StepList) {
        let position = Place::local(&list.position);
        let op = match self.operand(&position) {
            Ok(op) => op,
            Err(m) => return self.error(m),
        };
        if self.ty(&Expr::Read(position)) != Ok(Ty::Int) {
            return self.error(format!("the position `{}` of a step list is not an INT", list.position));
        }
        let n = list.steps.len();
        if n > 32_767 {
            return self.error(format!("{n} steps do not fit an INT position"));
        }
        let end = self.new_label();
        let restart = self.new_label();
        let labels: Vec<String> = (0..n).map(|_| self.new_label()).collect();
        let at = |k: usize| if k < n { labels[k].clone() } else { restart.clone() };
        self.comment(&format!(
            "Step list on {}: one scan runs from the stored step until a step ends it.",
            list.position
        ));
        if n <= 255 {
            self.emit(&format!("L\t{op}"));
            let list_end = self.new_label();
            self.emit(&format!("JL\t{list_end}"));
            for l in &labels {
                self.emit(&format!("JU\t{l}"));
            }
            let _ = writeln!(self.code, "{list_end}:\tJU\t{restart}");
        } else {
            for (k, l) in labels.iter().enumerate() {
                self.emit(&format!("L\t{op}"));
                self.emit(&format!("L\t{k}"));
                self.emit("==I");
                self.emit(&format!("JC\t{l}"));
            }
            self.emit(&format!("JU\t{restart}"));
        }
        let store = |g: &mut Self, k: usize| {
            g.emit(&format!("L\t{k}"));
            g.emit(&format!("T\t{op}"));
        };
        let _ = writeln!(self.code, "{restart}:\tNOP\t0");
        store(self, 0);
        self.emit(&format!("JU\t{end}"));
        for (i, step) in list.steps.iter().enumerate() {
            self.place_label(&labels[i]);
            self.comment(&step.comment);
            if let Some(wait) = &step.wait {
                store(self, i);
                self.bool_value(wait);
                self.emit(&format!("JCN\t{end}"));
            }
            if let Some(when) = &step.when {
                self.bool_value(when);
                self.emit(&format!("JCN\t{}", at(i + 1)));
            }
            self.statements(&step.actions);
            match step.next {
                // The next step's label follows: fall into it.
                Next::Continue(k) if k == i + 1 && k < n => {}
                Next::Continue(k) => self.emit(&format!("JU\t{}", at(k))),
                Next::Resume(k) => {
                    store(self, k);
                    self.emit(&format!("JU\t{end}"));
                }
            }
        }
        self.place_label(&end);
    }

    fn case(&mut self, selector: &Expr, arms: &[(Vec<i64>, Vec<Stmt>)], otherwise: &[Stmt]) {
        let unit = self.unit;
        self.comment(&format!("CASE {} OF", expr_text(unit, selector)));
        let ty = match self.ty(selector) {
            Ok(Ty::Bool) => return self.error("CASE over a BOOL".into()),
            Ok(Ty::Real) => return self.error("CASE over a REAL".into()),
            Ok(t) => t,
            Err(m) => return self.error(m),
        };
        let end = self.new_label();
        let other = self.new_label();
        let arm_labels: Vec<String> = arms.iter().map(|_| self.new_label()).collect();
        let all: Vec<i64> = arms.iter().flat_map(|(ls, _)| ls.iter().copied()).collect();
        let max = all.iter().copied().max().unwrap_or(0);
        let dense =
            !all.is_empty() && all.iter().all(|&l| (0..=254).contains(&l)) && (max as usize) < 2 * all.len() + 8;
        // The selector: a place loaded directly, or a temporary.
        let kind = TempKind::of(ty);
        let (sel, temp) = match selector {
            Expr::Read(p) if self.constant(p).is_none() && self.ty(selector) == Ok(ty) => match self.operand(p) {
                Ok(op) => (op, false),
                Err(m) => return self.error(m),
            },
            _ => {
                let tmp = self.push_temp(kind);
                self.load(selector, ty);
                self.emit(&format!("T\t{tmp}"));
                (tmp, true)
            }
        };
        let (s, lit): (&str, fn(i64) -> String) = if ty.wide() {
            ("D", |n| if n as i32 as i64 == n { format!("L#{n}") } else { "L#0".into() })
        } else {
            ("I", |n| n.to_string())
        };
        let out_of_range: Vec<i64> =
            all.iter().copied().filter(|&n| if ty.wide() { n as i32 as i64 != n } else { !fits_int(n) }).collect();
        if !out_of_range.is_empty() {
            self.error(format!("CASE labels {out_of_range:?} do not fit the selector's type {}", ty.name()));
        }
        if dense {
            self.emit(&format!("L\t{sel}"));
            self.emit(&format!("L\t{}", lit(0)));
            self.emit(&format!("<{s}"));
            self.emit(&format!("JC\t{other}"));
            self.emit(&format!("L\t{sel}"));
            self.emit(&format!("L\t{}", lit(max)));
            self.emit(&format!(">{s}"));
            self.emit(&format!("JC\t{other}"));
            self.emit(&format!("L\t{sel}"));
            let list_end = self.new_label();
            self.emit(&format!("JL\t{list_end}"));
            for value in 0..=max {
                let target = arms.iter().position(|(ls, _)| ls.contains(&value)).map_or(&other, |k| &arm_labels[k]);
                let line = format!("JU\t{target}");
                self.emit(&line);
            }
            let _ = writeln!(self.code, "{list_end}:\tJU\t{other}");
        } else {
            for (k, (labels, _)) in arms.iter().enumerate() {
                for &l in labels {
                    self.emit(&format!("L\t{sel}"));
                    self.emit(&format!("L\t{}", lit(l)));
                    self.emit(&format!("=={s}"));
                    let line = format!("JC\t{}", arm_labels[k]);
                    self.emit(&line);
                }
            }
            self.emit(&format!("JU\t{other}"));
        }
        if temp {
            self.pop_temp(kind);
        }
        for (k, (labels, body)) in arms.iter().enumerate() {
            let text: Vec<String> = labels.iter().map(|l| l.to_string()).collect();
            let _ = writeln!(self.code, "{}:\tNOP\t0\t// {}:", arm_labels[k], text.join(", "));
            self.statements(body);
            self.emit(&format!("JU\t{end}"));
        }
        let _ = writeln!(self.code, "{other}:\tNOP\t0\t// ELSE");
        self.statements(otherwise);
        self.comment("END_CASE");
        self.place_label(&end);
    }

    fn args_text(&self, args: &[(String, Expr)]) -> String {
        args.iter().map(|(n, e)| format!("{n} := {}", expr_text(self.unit, e))).collect::<Vec<_>>().join(", ")
    }

    fn call_function(&mut self, function: &str, args: &[(String, Expr)], result: Option<&Place>) {
        let unit = self.unit;
        let target = result.map(|p| format!("{} := ", place_text(unit, p))).unwrap_or_default();
        self.comment(&format!("{target}{function}({});", self.args_text(args)));
        let Some(f) = unit.pou(function).filter(|p| matches!(p.kind, PouKind::Function { .. })) else {
            return self.error(format!("`{function}` is not a function of the unit"));
        };
        let fc = self.blocks.fc[function];
        for (name, _) in args {
            if !f.inputs.iter().any(|v| v.name == *name) {
                self.error(format!("function `{function}` has no input `{name}`"));
            }
        }
        let saved = self.temps;
        let mut params = Vec::new();
        for p in &f.inputs {
            let Some(ty) = Ty::of(&p.ty) else {
                self.error(format!("input `{}` of `{function}` is not a BOOL, INT, DINT, TIME or REAL", p.name));
                continue;
            };
            let value = args
                .iter()
                .find(|(n, _)| *n == p.name)
                .map(|(_, e)| e.clone())
                .or_else(|| p.init.clone())
                .unwrap_or_else(|| default_value(ty));
            let (text, _) = self.argument(&value, ty);
            params.push(format!("{} := {text}", p.name));
        }
        let returns = match &f.kind {
            PouKind::Function { returns } => returns.as_ref().and_then(Ty::of),
            _ => None,
        };
        let mut copy_back = None;
        if let Some(rt) = returns {
            let kind = TempKind::of(rt);
            let tmp = self.push_temp(kind);
            params.push(format!("RET_VAL := {tmp}"));
            copy_back = Some((tmp, rt));
        } else if result.is_some() {
            self.error(format!("function `{function}` has no result to store"));
        }
        let list = if params.is_empty() { String::new() } else { format!(" ({})", params.join(", ")) };
        self.emit(&format!("CALL\tFC {fc}{list}"));
        if let (Some((tmp, rt)), Some(place)) = (copy_back, result) {
            let ty = self.place_type(place).ok().as_ref().and_then(Ty::of);
            match (ty, self.operand(place)) {
                (Some(ty), Ok(op)) if !incompatible(rt, ty) => {
                    if ty == Ty::Bool {
                        self.emit(&format!("A\t{tmp}"));
                        self.emit(&format!("=\t{op}"));
                    } else {
                        self.emit(&format!("L\t{tmp}"));
                        if ty.wide() && !rt.wide() {
                            self.emit("ITD");
                        }
                        self.emit(&format!("T\t{op}"));
                    }
                }
                (_, Err(m)) => self.error(m),
                _ => self.error(format!("the result of `{function}` does not fit `{}`", place_text(unit, place))),
            }
        }
        self.temps = saved;
    }

    fn call_instance(&mut self, instance: &Place, args: &[(String, Expr)]) {
        let unit = self.unit;
        self.comment(&format!("{}({});", place_text(unit, instance), self.args_text(args)));
        let ty = match self.place_type(instance) {
            Ok(t) => t,
            Err(m) => return self.error(m),
        };
        let saved = self.temps;
        let mut outputs = String::new();
        // The formal parameters and their types, and the block called.
        let (block, formals): (String, Vec<(String, Option<Ty>)>) = match &ty {
            Type::Ton if self.block_timer(instance).is_some() => {
                let timer = self.block_timer(instance).unwrap_or_default();
                outputs = format!(", Q := #{}, ET := #{}", shadow(timer, "Q"), shadow(timer, "ET"));
                (format!("#{timer}"), vec![("IN".into(), Some(Ty::Bool)), ("PT".into(), Some(Ty::Time))])
            }
            Type::Ton => {
                let Some(db) = self.instance_db(instance) else {
                    return self.error(format!(
                        "timer `{}` is local to a function or function block: STL needs a DB of its own for it \
                         (make it a global or a local of the program)",
                        place_text(unit, instance)
                    ));
                };
                (format!("SFB 4, DB {db}"), vec![("IN".into(), Some(Ty::Bool)), ("PT".into(), Some(Ty::Time))])
            }
            Type::Instance(name) => match unit.pou(name) {
                Some(fb) if fb.kind == PouKind::FunctionBlock => {
                    let Some(db) = self.instance_db(instance) else {
                        return self.error(format!(
                            "instance `{}` is local to a function or function block: STL needs a DB of its own \
                             for it (make it a global or a local of the program)",
                            place_text(unit, instance)
                        ));
                    };
                    (
                        format!("FB {}, DB {db}", self.blocks.fb[name]),
                        fb.inputs.iter().map(|v| (v.name.clone(), Ty::of(&v.ty))).collect(),
                    )
                }
                Some(_) => return self.error(format!("`{name}` is not a function block")),
                None => {
                    let formals = args.iter().map(|(n, e)| (n.clone(), self.ty(e).ok())).collect();
                    (format!("FB {}, DB {}", self.options.controller_fb, self.options.controller_db), formals)
                }
            },
            other => {
                return self.error(format!(
                    "`{}` of type {} cannot be called",
                    place_text(unit, instance),
                    type_name(other)
                ))
            }
        };
        let mut params = Vec::new();
        for (name, value) in args {
            let Some((formal, ty)) = formals.iter().find(|(f, _)| f.eq_ignore_ascii_case(name)) else {
                self.error(format!("`{}` has no input `{name}`", place_text(unit, instance)));
                continue;
            };
            let Some(ty) = *ty else {
                self.error(format!("input `{name}` of `{}` has no STL value type", place_text(unit, instance)));
                continue;
            };
            // An FB copies its inputs into its instance at the call: a variable of the formal's
            // type is passed as it is.
            let direct = match value {
                Expr::Read(p) if self.constant(p).is_none() && self.ty(value) == Ok(ty) => self.operand(p).ok(),
                _ => None,
            };
            let text = match direct {
                Some(op) => op,
                None => self.argument(value, ty).0,
            };
            params.push(format!("{formal} := {text}"));
        }
        let list = match (params.is_empty(), outputs.is_empty()) {
            (true, true) => String::new(),
            (true, false) => format!(" ({})", &outputs[2..]),
            _ => format!(" ({}{outputs})", params.join(", ")),
        };
        self.emit(&format!("CALL\t{block}{list}"));
        self.temps = saved;
    }
}

/// One POU's code and the temporaries it needs.
pub(super) fn generate<'a>(unit: &'a Unit, options: &'a StlUnitOptions, blocks: &'a Blocks, pou: &'a Pou) -> Gen<'a> {
    let mut g = Gen::new(unit, options, blocks, pou);
    for v in pou.inputs.iter().chain(&pou.outputs).chain(&pou.locals) {
        if !valid_name(&v.name) {
            g.error(format!(
                "`{}` is not an STL name (letters, digits and single underscores, at most 24 characters)",
                v.name
            ));
        }
        if v.name.eq_ignore_ascii_case("RET_VAL") {
            g.error("`RET_VAL` is the result of an FC".into());
        }
    }
    if let PouKind::Function { returns } = &pou.kind {
        if !pou.outputs.is_empty() {
            g.error("a function with outputs (STL prints results through RET_VAL only)".into());
        }
        if returns.as_ref().is_some_and(|t| Ty::of(t).is_none()) {
            g.error("a function whose result is not a BOOL, INT, DINT, TIME or REAL".into());
        }
        // S7 leaves temporaries and RET_VAL undefined; IEC starts from the initial values.
        let mut first = true;
        for v in &pou.locals {
            let Some(ty) = Ty::of(&v.ty) else {
                g.error(format!("`{}` of type {} in a function (an FC has no memory)", v.name, type_name(&v.ty)));
                continue;
            };
            if first {
                g.comment("locals start from their initial values");
                first = false;
            }
            let init = v.init.clone().unwrap_or_else(|| default_value(ty));
            g.store(&init, ty, &format!("#{}", v.name));
        }
        if let Some(ty) = returns.as_ref().and_then(Ty::of) {
            g.store(&default_value(ty), ty, "#RET_VAL");
        }
    }
    if pou.kind == PouKind::FunctionBlock {
        let names: Vec<&str> =
            pou.inputs.iter().chain(&pou.outputs).chain(&pou.locals).map(|v| v.name.as_str()).collect();
        for v in &pou.locals {
            match &v.ty {
                Type::Ton => {
                    for field in ["Q", "ET"] {
                        let s = shadow(&v.name, field);
                        if !valid_name(&s) || names.iter().any(|n| n.eq_ignore_ascii_case(&s)) {
                            g.error(format!(
                                "timer `{}` keeps its {field} in `{s}`, which is not a free STL name in this block",
                                v.name
                            ));
                        }
                    }
                }
                Type::Instance(name) => g.error(format!(
                    "`{}` of type {name} in a function block: awlsim cannot address members of a \
                     multi-instance; declare it as a global or a local of the program",
                    v.name
                )),
                _ => {}
            }
        }
    }
    for v in pou.inputs.iter().chain(&pou.outputs) {
        if Ty::of(&v.ty).is_none() {
            g.error(format!("parameter `{}` of type {}", v.name, type_name(&v.ty)));
        }
    }
    g.statements(&pou.body);
    g
}
