//! A [`Unit`] as PLCopen TC6 XML v2.01: every POU with its interface declared in XML and its
//! body as IEC Structured Text; a configuration whose resource runs the program in a cyclic
//! task and holds the unit's globals and constants (`globalVars`, `constant="true"`).

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

/// Prints the project, created at `options.created_unix`.
pub fn print(unit: &Unit, options: &Options, o: &mut impl Write) -> fmt::Result {
    project_head(&unit.name, &unit.header, options, o)?;
    o.write_str("  <types>\n    <dataTypes/>\n    <pous>\n")?;
    for p in &unit.pous {
        pou(o, unit, p)?;
    }
    o.write_str("    </pous>\n  </types>\n")?;
    o.write_str("  <instances>\n    <configurations>\n      <configuration name=\"config\">\n")?;
    o.write_str("        <resource name=\"resource1\">\n")?;
    if let Some(program) = unit.pous.iter().find(|p| p.kind == PouKind::Program) {
        writeln!(o, "          <task name=\"task_main\" interval=\"T#10ms\" priority=\"1\">")?;
        writeln!(
            o,
            "            <pouInstance name=\"{}_instance\" typeName=\"{}\"/>",
            escape(&program.name),
            escape(&program.name)
        )?;
        o.write_str("          </task>\n")?;
    }
    let w = Writer::new(unit, Dialect::Iec);
    for (constant, list) in [(true, &unit.constants), (false, &unit.globals)] {
        if list.is_empty() {
            continue;
        }
        let attribute = if constant { " constant=\"true\"" } else { "" };
        writeln!(o, "          <globalVars name=\"{}\"{attribute}>", escape(&unit.gvl))?;
        for v in list.iter() {
            let init = v.init.as_ref().map(|e| w.init(e));
            let address = v.address().map(|a| format!("%{}", crate::plc::iec_address(a)));
            located(o, &v.name, address.as_deref(), &xml_type(&v.ty), init.as_deref(), &v.comment)?;
        }
        o.write_str("          </globalVars>\n")?;
    }
    o.write_str("        </resource>\n      </configuration>\n    </configurations>\n  </instances>\n")?;
    o.write_str("</project>\n")
}
