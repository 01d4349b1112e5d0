//! TwinCAT 3 source files, as TwinCAT's "Add → Existing Item" reads them: a `.TcPOU` per
//! program organisation unit (the function block and the program that wires it) and a `.TcGVL`
//! with the I/O's variables, located at their addresses or, when unbound, `AT %I*`/`AT %Q*` for
//! linking in the System Manager. Each is a `TcPlcObject` (format version 1.1.0.1)
//! whose declaration and implementation are the CODESYS dialect's Structured Text in CDATA.
//! Object ids are name-based GUIDs ([`crate::plc::stable_guid`]), so the files depend on the input
//! only.

use crate::plc::{stable_guid, OutputFile};
use std::fmt::Write;

fn escape(text: &str) -> String {
    text.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;").replace('"', "&quot;")
}

/// Text inside `<![CDATA[…]]>`: a `]]>` in it is split over two sections.
fn cdata(text: &str) -> String {
    format!("<![CDATA[{}]]>", text.replace("]]>", "]]]]><![CDATA[>"))
}

/// The start of every file: the XML declaration, the provenance as an XML comment, the root.
fn head(header: &[String]) -> String {
    let mut out = String::from("<?xml version=\"1.0\" encoding=\"utf-8\"?>\n");
    for line in header {
        out.push_str(&format!("<!-- {} -->\n", escape(line).replace("--", "- -")));
    }
    out.push_str("<TcPlcObject Version=\"1.1.0.1\">\n");
    out
}

/// A `.TcPOU` file of one POU whose declaration and implementation are given as ST text.
pub fn pou_file(header: &[String], name: &str, declaration: &str, implementation: &str) -> OutputFile {
    let mut text = head(header);
    let _ = write!(
        text,
        "  <POU Name=\"{}\" Id=\"{}\" SpecialFunc=\"None\">\n    <Declaration>{}</Declaration>\n    \
         <Implementation>\n      <ST>{}</ST>\n    </Implementation>\n  </POU>\n</TcPlcObject>\n",
        escape(name),
        stable_guid(header, name),
        cdata(declaration),
        cdata(implementation)
    );
    OutputFile { name: format!("{name}.TcPOU"), text }
}

/// A `.TcGVL` file of a global variable list given as ST text.
pub fn gvl_file(header: &[String], name: &str, declaration: &str) -> OutputFile {
    let mut text = head(header);
    let _ = write!(
        text,
        "  <GVL Name=\"{}\" Id=\"{}\">\n    <Declaration>{}</Declaration>\n  </GVL>\n</TcPlcObject>\n",
        escape(name),
        stable_guid(header, name),
        cdata(declaration)
    );
    OutputFile { name: format!("{name}.TcGVL"), text }
}
