//! PLCopen TC6 XML v2.01: a project holding the IEC Structured Text function block, for import
//! into CODESYS, TwinCAT, Beremiz and other tools. The body is the ST target's body; variables are
//! declared in the XML interface.

use super::{st, Code};

fn escape(text: &str) -> String {
    text.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;").replace('"', "&quot;")
}

fn variable(o: &mut String, name: &str, ty: &str, init: Option<&str>, doc: &str) {
    o.push_str(&format!("            <variable name=\"{}\">\n              <type>{ty}</type>\n", escape(name)));
    if let Some(v) = init {
        o.push_str(&format!("              <initialValue><simpleValue value=\"{}\"/></initialValue>\n", escape(v)));
    }
    if !doc.is_empty() {
        o.push_str(&format!("              <documentation><xhtml:p>{}</xhtml:p></documentation>\n", escape(doc)));
    }
    o.push_str("            </variable>\n");
}

/// Prints the project. Timestamps are fixed so that the output depends on the input only.
pub fn print(code: &Code) -> String {
    let full = st::print(code, st::Dialect::Iec);
    // The body: between the last END_VAR of the function block and END_FUNCTION_BLOCK.
    let fb = full.split("END_FUNCTION_BLOCK").next().unwrap_or("");
    let body = fb.rsplit_once("END_VAR\n").map_or("", |(_, b)| b);
    let mut o = String::new();
    o.push_str("<?xml version=\"1.0\" encoding=\"utf-8\"?>\n");
    for line in &code.header {
        o.push_str(&format!("<!-- {} -->\n", escape(line)));
    }
    o.push_str(
        "<project xmlns=\"http://www.plcopen.org/xml/tc6_0201\" xmlns:xhtml=\"http://www.w3.org/1999/xhtml\">\n",
    );
    o.push_str(&format!(
        "  <fileHeader companyName=\"plcsynth\" productName=\"plcsynth\" productVersion=\"{}\" creationDateTime=\"1970-01-01T00:00:00\"/>\n",
        env!("CARGO_PKG_VERSION")
    ));
    o.push_str(&format!(
        "  <contentHeader name=\"{}\" modificationDateTime=\"1970-01-01T00:00:00\">\n",
        escape(&code.name)
    ));
    o.push_str("    <coordinateInfo>\n      <fbd><scaling x=\"1\" y=\"1\"/></fbd>\n      <ld><scaling x=\"1\" y=\"1\"/></ld>\n      <sfc><scaling x=\"1\" y=\"1\"/></sfc>\n    </coordinateInfo>\n  </contentHeader>\n");
    o.push_str("  <types>\n    <dataTypes/>\n    <pous>\n");
    o.push_str(&format!(
        "      <pou name=\"{}\" pouType=\"functionBlock\">\n        <interface>\n",
        escape(&code.name)
    ));
    o.push_str("          <inputVars>\n");
    for i in &code.inputs {
        variable(&mut o, &i.ident, "<BOOL/>", None, &i.notes.join(", "));
    }
    o.push_str("          </inputVars>\n          <outputVars>\n");
    for out in &code.outputs {
        variable(&mut o, &out.ident, "<BOOL/>", None, &out.notes.join(", "));
    }
    o.push_str("          </outputVars>\n          <localVars>\n");
    variable(&mut o, "step", "<INT/>", Some("0"), "program position");
    variable(&mut o, "scan_done", "<BOOL/>", None, "");
    for t in &code.timers {
        variable(&mut o, &t.ident, "<derived name=\"TON\"/>", None, "timer of a clock");
    }
    o.push_str("          </localVars>\n        </interface>\n");
    o.push_str("        <body>\n          <ST>\n            <xhtml:p><![CDATA[");
    o.push_str(&body.replace("]]>", "]]]]><![CDATA[>"));
    o.push_str("]]></xhtml:p>\n          </ST>\n        </body>\n");
    o.push_str("        <documentation><xhtml:p>");
    o.push_str(&escape(&code.header.join(" ")));
    o.push_str("</xhtml:p></documentation>\n      </pou>\n    </pous>\n  </types>\n");
    o.push_str("  <instances>\n    <configurations/>\n  </instances>\n</project>\n");
    o
}
