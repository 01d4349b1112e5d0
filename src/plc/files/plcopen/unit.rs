//! A [`Unit`] as PLCopen TC6 XML v2.01: every POU with its interface declared in XML and its
//! body as IEC Structured Text; a configuration whose resource runs the program in a cyclic
//! task and holds the unit's globals and constants (`globalVars`, `constant="true"`).
//!
//! [`Flavour::Abb`] writes the same project in the conventions Eclipse ESCET's PLC generator
//! follows for ABB's AC500 tools (Automation Builder): no named constants (their values are
//! written where they are read, [`Unit::inline_constants`]), the globals, I/O among them, as
//! the configuration's own global variables (located by `address`) while the resource holds
//! only the task, and the task interval as an ISO 8601 duration (`PT0.01S`), as CODESYS-based
//! tools write it.

use crate::plc::files::plcopen::{escape, located, project_head, st_body, variable};
use crate::plc::model::unit::{Pou, PouKind, Type, Unit, Var};
use crate::plc::print::st::unit::{pou_body, Writer};
use crate::plc::print::st::Dialect;
use crate::plc::Options;
use std::fmt::{self, Write};

/// The type as a TC6 `<type>` content.
fn xml_type(ty: &Type) -> String {
    match ty {
        Type::Bool => "<BOOL/>".into(),
        Type::Int => "<INT/>".into(),
        Type::Dint => "<DINT/>".into(),
        Type::Real => "<REAL/>".into(),
        Type::Time => "<TIME/>".into(),
        Type::Ton => "<derived name=\"TON\"/>".into(),
        Type::Instance(name) => format!("<derived name=\"{}\"/>", escape(name)),
    }
}

fn vars(o: &mut impl Write, unit: &Unit, element: &str, list: &[Var]) -> fmt::Result {
    if list.is_empty() {
        return Ok(());
    }
    writeln!(o, "          <{element}>")?;
    let w = Writer::new(unit, Dialect::Iec);
    for v in list {
        let init = v.init.as_ref().map(|e| w.init(e));
        variable(o, &v.name, &xml_type(&v.ty), init.as_deref(), &v.comment)?;
    }
    writeln!(o, "          </{element}>")
}

fn pou(o: &mut impl Write, unit: &Unit, pou: &Pou) -> fmt::Result {
    let kind = match pou.kind {
        PouKind::Function { .. } => "function",
        PouKind::FunctionBlock => "functionBlock",
        PouKind::Program => "program",
    };
    write!(o, "      <pou name=\"{}\" pouType=\"{kind}\">\n        <interface>\n", escape(&pou.name))?;
    if let PouKind::Function { returns } = &pou.kind {
        // A function without a result is not in TC6 v2.01; the lowering gives each one.
        let ty = returns.as_ref().map_or_else(|| "<BOOL/>".to_string(), xml_type);
        writeln!(o, "          <returnType>{ty}</returnType>")?;
    }
    vars(o, unit, "inputVars", &pou.inputs)?;
    vars(o, unit, "outputVars", &pou.outputs)?;
    vars(o, unit, if matches!(pou.kind, PouKind::Function { .. }) { "tempVars" } else { "localVars" }, &pou.locals)?;
    o.write_str("        </interface>\n")?;
    let mut body = String::new();
    pou_body(unit, pou, Dialect::Iec, &mut body);
    st_body(o, &body)?;
    if !pou.comment.is_empty() {
        writeln!(o, "        <documentation><xhtml:p>{}</xhtml:p></documentation>", escape(&pou.comment))?;
    }
    o.write_str("      </pou>\n")
}

/// Which tool's conventions the project follows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Flavour {
    /// Plain TC6: constants and globals in the resource, `interval="T#10ms"`.
    Tc6,
    /// ABB Automation Builder (see the module's documentation).
    Abb,
}

/// The cycle of the generated task, in milliseconds.
const TASK_MS: u64 = 10;

/// Prints the project, created at `options.created_unix`, in plain TC6.
pub fn print(unit: &Unit, options: &Options, o: &mut impl Write) -> fmt::Result {
    print_flavour(unit, Flavour::Tc6, options, o)
}

/// Prints the project, created at `options.created_unix`, in the conventions of `flavour`.
pub fn print_flavour(unit: &Unit, flavour: Flavour, options: &Options, o: &mut impl Write) -> fmt::Result {
    if flavour == Flavour::Abb && !unit.constants.is_empty() {
        return print_flavour(&unit.inline_constants(), flavour, options, o);
    }
    project_head(&unit.name, &unit.header, options, o)?;
    o.write_str("  <types>\n    <dataTypes/>\n    <pous>\n")?;
    for p in &unit.pous {
        pou(o, unit, p)?;
    }
    o.write_str("    </pous>\n  </types>\n")?;
    o.write_str("  <instances>\n    <configurations>\n      <configuration name=\"config\">\n")?;
    o.write_str("        <resource name=\"resource1\">\n")?;
    if let Some(program) = unit.pous.iter().find(|p| p.kind == PouKind::Program) {
        let interval = match flavour {
            Flavour::Tc6 => format!("T#{TASK_MS}ms"),
            Flavour::Abb => format!("PT{}.{:03}S", TASK_MS / 1000, TASK_MS % 1000),
        };
        writeln!(o, "          <task name=\"task_main\" interval=\"{interval}\" priority=\"1\">")?;
        writeln!(
            o,
            "            <pouInstance name=\"{}_instance\" typeName=\"{}\"/>",
            escape(&program.name),
            escape(&program.name)
        )?;
        o.write_str("          </task>\n")?;
    }
    if flavour == Flavour::Tc6 {
        global_vars(o, unit, "          ")?;
    }
    o.write_str("        </resource>\n")?;
    if flavour == Flavour::Abb {
        global_vars(o, unit, "        ")?;
    }
    o.write_str("      </configuration>\n    </configurations>\n  </instances>\n")?;
    o.write_str("</project>\n")
}

/// The constants and globals as `globalVars` lists, each line after `indent`.
fn global_vars(o: &mut impl Write, unit: &Unit, indent: &str) -> fmt::Result {
    let w = Writer::new(unit, Dialect::Iec);
    for (constant, list) in [(true, &unit.constants), (false, &unit.globals)] {
        if list.is_empty() {
            continue;
        }
        let attribute = if constant { " constant=\"true\"" } else { "" };
        writeln!(o, "{indent}<globalVars name=\"{}\"{attribute}>", escape(&unit.gvl))?;
        for v in list.iter() {
            let init = v.init.as_ref().map(|e| w.init(e));
            let address = v.address().map(|a| format!("%{}", crate::plc::iec_address(a)));
            located(o, &v.name, address.as_deref(), &xml_type(&v.ty), init.as_deref(), &v.comment)?;
        }
        writeln!(o, "{indent}</globalVars>")?;
    }
    Ok(())
}
