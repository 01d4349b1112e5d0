//! PLCopen TC6 XML v2.01: a project for import into CODESYS, TwinCAT, Beremiz and other tools,
//! holding the IEC Structured Text function block, a program that instantiates and wires it,
//! and a configuration with a resource, a cyclic task running the program, and the I/O as the
//! resource's global variables (located with `address` where the specification binds one). The
//! bodies are the ST target's; variables are declared in the XML interfaces.

pub mod unit;

use crate::plc::model::code::{Binding, Code};
use crate::plc::{iso_datetime, print::st, Options};
use std::fmt::{self, Write};

pub(in crate::plc) fn escape(text: &str) -> String {
    text.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;").replace('"', "&quot;")
}

pub(in crate::plc) fn variable(o: &mut impl Write, name: &str, ty: &str, init: Option<&str>, doc: &str) -> fmt::Result {
    located(o, name, None, ty, init, doc)
}

pub(in crate::plc) fn located(
    o: &mut impl Write,
    name: &str,
    address: Option<&str>,
    ty: &str,
    init: Option<&str>,
    doc: &str,
) -> fmt::Result {
    let at = address.map(|a| format!(" address=\"{}\"", escape(a))).unwrap_or_default();
    write!(o, "            <variable name=\"{}\"{at}>\n              <type>{ty}</type>\n", escape(name))?;
    if let Some(v) = init {
        writeln!(o, "              <initialValue><simpleValue value=\"{}\"/></initialValue>", escape(v))?;
    }
    if !doc.is_empty() {
        writeln!(o, "              <documentation><xhtml:p>{}</xhtml:p></documentation>", escape(doc))?;
    }
    o.write_str("            </variable>\n")
}

/// The ST text inside `<xhtml:p>`.
pub(in crate::plc) fn st_body(o: &mut impl Write, text: &str) -> fmt::Result {
    o.write_str("        <body>\n          <ST>\n            <xhtml:p><![CDATA[")?;
    o.write_str(&text.replace("]]>", "]]]]><![CDATA[>"))?;
    o.write_str("]]></xhtml:p>\n          </ST>\n        </body>\n")
}

/// The XML declaration, the provenance, `<project>`, `<fileHeader>` and `<contentHeader>`.
pub(in crate::plc) fn project_head(
    name: &str,
    header: &[String],
    options: &Options,
    o: &mut impl Write,
) -> fmt::Result {
    let created = iso_datetime(options.created_unix);
    o.write_str("<?xml version=\"1.0\" encoding=\"utf-8\"?>\n")?;
    for line in header {
        writeln!(o, "<!-- {} -->", escape(line))?;
    }
    o.write_str(
        "<project xmlns=\"http://www.plcopen.org/xml/tc6_0201\" xmlns:xhtml=\"http://www.w3.org/1999/xhtml\">\n",
    )?;
    writeln!(
        o,
        "  <fileHeader companyName=\"plcsynth\" productName=\"plcsynth\" productVersion=\"{}\" creationDateTime=\"{created}\"/>",
        env!("CARGO_PKG_VERSION")
    )?;
    writeln!(o, "  <contentHeader name=\"{}\" modificationDateTime=\"{created}\">", escape(name))?;
    o.write_str("    <coordinateInfo>\n      <fbd><scaling x=\"1\" y=\"1\"/></fbd>\n      <ld><scaling x=\"1\" y=\"1\"/></ld>\n      <sfc><scaling x=\"1\" y=\"1\"/></sfc>\n    </coordinateInfo>\n  </contentHeader>\n")?;
    Ok(())
}

/// Prints the project, created at `options.created_unix`.
pub fn print(code: &Code, options: &Options, o: &mut impl Write) -> fmt::Result {
    project_head(&code.name, &code.header, options, o)?;
    o.write_str("  <types>\n    <dataTypes/>\n    <pous>\n")?;
    write!(o, "      <pou name=\"{}\" pouType=\"functionBlock\">\n        <interface>\n", escape(&code.name))?;
    o.write_str("          <inputVars>\n")?;
    for i in &code.inputs {
        variable(o, &i.symbol, "<BOOL/>", None, &i.comment)?;
    }
    o.write_str("          </inputVars>\n          <outputVars>\n")?;
    for out in &code.outputs {
        variable(o, &out.variable.symbol, "<BOOL/>", None, &out.variable.comment)?;
    }
    o.write_str("          </outputVars>\n          <localVars>\n")?;
    variable(o, "step", "<INT/>", Some("0"), "program position")?;
    variable(o, "scan_done", "<BOOL/>", None, "")?;
    for out in &code.outputs {
        if let Some(last) = out.gap() {
            variable(o, last, "<BOOL/>", None, &format!("{} at the last output write", out.variable.symbol))?;
        }
    }
    for t in &code.timers {
        variable(o, &t.symbol, "<derived name=\"TON\"/>", None, "timer of a clock")?;
    }
    o.write_str("          </localVars>\n        </interface>\n")?;
    let mut body = String::new();
    st::body(code, &mut body)?;
    st_body(o, &body)?;
    o.write_str("        <documentation><xhtml:p>")?;
    o.write_str(&escape(&code.header.join(" ")))?;
    o.write_str("</xhtml:p></documentation>\n      </pou>\n")?;
    program(code, o)?;
    o.write_str("    </pous>\n  </types>\n")?;
    configuration(code, o)?;
    o.write_str("</project>\n")
}

/// The name a variable of the block has outside it: its symbol as a global variable of the
/// resource (bound to an address or unbound), or the project symbol it is bound to.
fn outside(symbol: &str, binding: &Option<Binding>) -> String {
    match binding {
        Some(Binding::Symbol(text) | Binding::Quoted(text)) => text.clone(),
        _ => symbol.to_string(),
    }
}

/// Whether a variable is one of the resource's global variables.
fn is_global(binding: &Option<Binding>) -> bool {
    matches!(binding, None | Some(Binding::Address(_)))
}

/// The program: the block's instance, the I/O as external variables, the call and the copies.
fn program(code: &Code, o: &mut impl Write) -> fmt::Result {
    write!(o, "      <pou name=\"{}\" pouType=\"program\">\n        <interface>\n", escape(&code.program))?;
    o.write_str("          <localVars>\n")?;
    variable(o, &code.instance, &format!("<derived name=\"{}\"/>", escape(&code.name)), None, "the controller")?;
    o.write_str("          </localVars>\n")?;
    if code.variables().any(|(v, _)| is_global(&v.binding)) {
        o.write_str("          <externalVars>\n")?;
        for (v, _) in code.variables().filter(|(v, _)| is_global(&v.binding)) {
            variable(o, &v.symbol, "<BOOL/>", None, &v.comment)?;
        }
        o.write_str("          </externalVars>\n")?;
    }
    o.write_str("        </interface>\n")?;
    let args: Vec<String> =
        code.inputs.iter().map(|i| format!("{} := {}", i.symbol, outside(&i.symbol, &i.binding))).collect();
    let mut body = format!("{}({});\n", code.instance, args.join(", "));
    for out in &code.outputs {
        let v = &out.variable;
        body.push_str(&format!("{} := {}.{};\n", outside(&v.symbol, &v.binding), code.instance, v.symbol));
    }
    st_body(o, &body)?;
    o.write_str("      </pou>\n")
}

/// A configuration with one resource: a cyclic task (10 ms) running the program, and the I/O as
/// global variables, located where bound to an address.
fn configuration(code: &Code, o: &mut impl Write) -> fmt::Result {
    o.write_str("  <instances>\n    <configurations>\n      <configuration name=\"config\">\n")?;
    o.write_str("        <resource name=\"resource1\">\n")?;
    writeln!(o, "          <task name=\"task_main\" interval=\"T#10ms\" priority=\"1\">")?;
    writeln!(
        o,
        "            <pouInstance name=\"{}_instance\" typeName=\"{}\"/>",
        escape(&code.program),
        escape(&code.program)
    )?;
    o.write_str("          </task>\n")?;
    if code.variables().any(|(v, _)| is_global(&v.binding)) {
        o.write_str("          <globalVars>\n")?;
        for (v, _) in code.variables().filter(|(v, _)| is_global(&v.binding)) {
            let address = v.binding.as_ref().map(Binding::iec_text);
            located(o, &v.symbol, address.as_deref(), "<BOOL/>", None, &v.comment)?;
        }
        o.write_str("          </globalVars>\n")?;
    }
    o.write_str("        </resource>\n      </configuration>\n    </configurations>\n  </instances>\n")
}
