//! PLCopen TC6 XML v2.01: a project for import into CODESYS, TwinCAT, Beremiz and other tools,
//! holding the IEC Structured Text function block, a program that instantiates and wires it,
//! and a configuration with a resource, a cyclic task running the program, and the I/O as the
//! resource's global variables (located with `address` where the specification binds one). The
//! bodies are the ST target's; variables are declared in the XML interfaces.

pub mod unit;

use crate::plc::{iso_datetime, Options};
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
