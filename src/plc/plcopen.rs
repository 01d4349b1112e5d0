//! PLCopen TC6 XML v2.01: a project holding the IEC Structured Text function block, for import
//! into CODESYS, TwinCAT, Beremiz and other tools. The body is the ST target's body; variables are
//! declared in the XML interface.

use super::model::Code;
use super::st;
use std::fmt::{self, Write};

fn escape(text: &str) -> String {
    text.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;").replace('"', "&quot;")
}

fn variable(o: &mut impl Write, name: &str, ty: &str, init: Option<&str>, doc: &str) -> fmt::Result {
    write!(o, "            <variable name=\"{}\">\n              <type>{ty}</type>\n", escape(name))?;
    if let Some(v) = init {
        writeln!(o, "              <initialValue><simpleValue value=\"{}\"/></initialValue>", escape(v))?;
    }
    if !doc.is_empty() {
        writeln!(o, "              <documentation><xhtml:p>{}</xhtml:p></documentation>", escape(doc))?;
    }
    o.write_str("            </variable>\n")
}

/// Prints the project. Timestamps are fixed so that the output depends on the input only.
pub fn print(code: &Code, o: &mut impl Write) -> fmt::Result {
    o.write_str("<?xml version=\"1.0\" encoding=\"utf-8\"?>\n")?;
    for line in &code.header {
        writeln!(o, "<!-- {} -->", escape(line))?;
    }
    o.write_str(
        "<project xmlns=\"http://www.plcopen.org/xml/tc6_0201\" xmlns:xhtml=\"http://www.w3.org/1999/xhtml\">\n",
    )?;
    writeln!(
        o,
        "  <fileHeader companyName=\"plcsynth\" productName=\"plcsynth\" productVersion=\"{}\" creationDateTime=\"1970-01-01T00:00:00\"/>",
        env!("CARGO_PKG_VERSION")
    )?;
    writeln!(o, "  <contentHeader name=\"{}\" modificationDateTime=\"1970-01-01T00:00:00\">", escape(&code.name))?;
    o.write_str("    <coordinateInfo>\n      <fbd><scaling x=\"1\" y=\"1\"/></fbd>\n      <ld><scaling x=\"1\" y=\"1\"/></ld>\n      <sfc><scaling x=\"1\" y=\"1\"/></sfc>\n    </coordinateInfo>\n  </contentHeader>\n")?;
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
    for t in &code.timers {
        variable(o, &t.symbol, "<derived name=\"TON\"/>", None, "timer of a clock")?;
    }
    o.write_str("          </localVars>\n        </interface>\n")?;
    let mut body = String::new();
    st::body(code, &mut body)?;
    o.write_str("        <body>\n          <ST>\n            <xhtml:p><![CDATA[")?;
    o.write_str(&body.replace("]]>", "]]]]><![CDATA[>"))?;
    o.write_str("]]></xhtml:p>\n          </ST>\n        </body>\n")?;
    o.write_str("        <documentation><xhtml:p>")?;
    o.write_str(&escape(&code.header.join(" ")))?;
    o.write_str("</xhtml:p></documentation>\n      </pou>\n    </pous>\n  </types>\n")?;
    o.write_str("  <instances>\n    <configurations/>\n  </instances>\n</project>\n")
}
