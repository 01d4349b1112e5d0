//! Helpers shared by the test binaries that run the independent checkers.
// Each test binary compiles this module and uses a part of it.
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

pub fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// A tool of the checkers' virtualenv, installing the checkers first if it is missing.
pub fn venv_tool(name: &str) -> PathBuf {
    let path = root().join(".venv/bin").join(name);
    if !path.exists() {
        let status = Command::new("bash").arg(root().join("scripts/python-checkers.sh")).status().unwrap();
        assert!(status.success(), "installing the Python checkers failed");
    }
    path
}

/// Runs the checker script `tests/checkers/<script>` with the virtualenv's Python, `args` after
/// it and `stdin` fed to it; its standard output. Fails with its output unless it succeeds.
pub fn run_checker<S: AsRef<std::ffi::OsStr>>(script: &str, args: &[S], stdin: &str) -> String {
    use std::io::Write as _;
    let mut child = Command::new(venv_tool("python"))
        .arg(root().join("tests/checkers").join(script))
        .args(args)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("python runs");
    child.stdin.take().unwrap().write_all(stdin.as_bytes()).unwrap();
    let out = child.wait_with_output().unwrap();
    let args: Vec<_> = args.iter().map(|a| a.as_ref().to_string_lossy().into_owned()).collect();
    assert!(
        out.status.success(),
        "{script} fails on {}:\n{}\n{}",
        args.join(" "),
        String::from_utf8_lossy(&out.stderr),
        String::from_utf8_lossy(&out.stdout)
    );
    String::from_utf8(out.stdout).unwrap()
}

/// The bytes of a hex string as the checkers print them (`0a1f…`).
pub fn hex_bytes(h: &str) -> Vec<u8> {
    (0..h.len()).step_by(2).map(|i| u8::from_str_radix(&h[i..i + 2], 16).unwrap()).collect()
}

/// Writes `text` to `name` in a directory of this process named after `prefix`.
pub fn scratch(prefix: &str, name: &str, text: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("{prefix}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

/// Runs a checker on the file `what` and fails with its output and the file unless it accepts.
pub fn check(cmd: &mut Command, what: &Path) {
    let out = cmd.output().unwrap();
    assert!(
        out.status.success(),
        "{} rejected:\n{}{}\n{}",
        what.display(),
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr),
        std::fs::read_to_string(what).unwrap_or_default()
    );
}

/// Parses `files` with blark in two processes, one per core (`tests/checkers/blark_many.py`:
/// blark's start-up costs about a second, more than most files), and fails naming every file
/// it rejects.
///
/// blark is a pure-Python Earley parser (a few kB a second) and the generated files repeat
/// themselves, so by default it parses a subset that covers every line shape (see
/// [`line_shape`]) of every file, about half the text; `PLCSYNTH_ALL_DIALECTS=1`
/// (`make test-long`) parses every file.
pub fn blark_all(python: &Path, root: &Path, files: &[PathBuf]) {
    // Targets often print the same text (IEC ST and SCL after `scl_for_blark`, say): blark
    // parses each text once, which checks exactly as much in about a third less time.
    let mut seen = std::collections::HashSet::new();
    let texts: Vec<(&PathBuf, String)> = files
        .iter()
        .map(|f| (f, std::fs::read_to_string(f).expect("a file written for blark")))
        .filter(|(_, text)| seen.insert(text.clone()))
        .collect();
    let all = std::env::var("PLCSYNTH_ALL_DIALECTS").is_ok_and(|v| v == "1");
    let files: Vec<&PathBuf> = if all {
        texts.iter().map(|(f, _)| *f).collect()
    } else {
        let chosen = covering_subset(&texts.iter().map(|(_, t)| t.as_str()).collect::<Vec<_>>());
        chosen.into_iter().map(|i| texts[i].0).collect()
    };
    let script = root.join("tests/checkers/blark_many.py");
    let children: Vec<_> = [0, 1]
        .iter()
        .map(|&half| {
            Command::new(python)
                .arg(&script)
                .args(files.iter().skip(half).step_by(2))
                .stdout(Stdio::piped())
                .stderr(Stdio::piped())
                .spawn()
                .unwrap()
        })
        .collect();
    for child in children {
        let out = child.wait_with_output().unwrap();
        assert!(
            out.status.success(),
            "blark rejects generated code:\n{}{}",
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr)
        );
    }
}

/// A line of generated ST with its names, numbers and literals abstracted: identifiers become
/// `x` (keywords stay), digit runs `0`, a run of names separated by blanks one `x`; the
/// indentation stays, so that the nesting a printer wrote is part of the shape. A comment keeps
/// only which of the characters that could end or nest it (`( ) * ' " $`) it holds, and a GUID
/// (`{x-0x-...}` in TwinCAT's XML) becomes `{}`: blark removes comments before it parses, so a
/// state listed in a comment adds nothing to check, while counted as a shape it made the
/// covering subset take the largest files (three times the text for blark, same grammar).
pub fn line_shape(line: &str) -> String {
    let shape = raw_line_shape(line);
    let mut out = String::with_capacity(shape.len());
    let mut rest = shape.as_str();
    loop {
        let comment = rest.find("(*").map(|start| (start, rest[start + 2..].find("*)").map(|len| start + 2 + len)));
        let guid = rest.find('{').and_then(|start| {
            let len = rest[start + 1..].find('}')?;
            let inner = &rest[start + 1..start + 1 + len];
            (!inner.is_empty() && inner.chars().all(|c| matches!(c, 'x' | '0' | '-')))
                .then_some((start, start + 1 + len))
        });
        match (comment, guid) {
            (Some((start, Some(end))), g) if g.is_none_or(|(gs, _)| start < gs) => {
                out.push_str(&rest[..start + 2]);
                out.extend("()*'\"$".chars().filter(|c| rest[start + 2..end].contains(*c)));
                out.push_str("*)");
                rest = &rest[end + 2..];
            }
            (_, Some((start, end))) => {
                out.push_str(&rest[..start]);
                out.push_str("{}");
                rest = &rest[end + 1..];
            }
            _ => break,
        }
    }
    out.push_str(rest);
    out
}

fn raw_line_shape(line: &str) -> String {
    const KEYWORDS: &str = "IF THEN ELSIF ELSE END_IF CASE OF END_CASE FOR TO BY DO END_FOR WHILE END_WHILE REPEAT UNTIL END_REPEAT RETURN EXIT AND OR XOR NOT \
        MOD TRUE FALSE VAR VAR_INPUT VAR_OUTPUT VAR_IN_OUT VAR_GLOBAL VAR_TEMP VAR_EXTERNAL VAR_STAT CONSTANT RETAIN END_VAR FUNCTION_BLOCK END_FUNCTION_BLOCK FUNCTION END_FUNCTION PROGRAM END_PROGRAM TYPE END_TYPE STRUCT END_STRUCT \
        ARRAY BOOL INT DINT UINT UDINT SINT USINT LINT WORD DWORD BYTE REAL LREAL TIME STRING TON TOF TP R_TRIG F_TRIG AT";
    let indent = line.len() - line.trim_start().len();
    let mut shape = line[..indent].to_string();
    let mut chars = line[indent..].trim_end().chars().peekable();
    while let Some(c) = chars.next() {
        if c.is_ascii_alphabetic() || c == '_' {
            let mut word = c.to_string();
            while let Some(&d) = chars.peek().filter(|d| d.is_ascii_alphanumeric() || **d == '_') {
                word.push(d);
                chars.next();
            }
            let kept = shape.trim_end().len();
            if KEYWORDS.split_whitespace().any(|k| k == word) {
                shape.push_str(&word);
            } else if kept > indent && kept < shape.len() && shape[..kept].ends_with('x') {
                // A name after a name and blanks (`x x`): one `x` (only names become `x`).
                shape.truncate(kept);
            } else {
                shape.push('x');
            }
        } else if c.is_ascii_digit() {
            while chars.peek().is_some_and(char::is_ascii_digit) {
                chars.next();
            }
            shape.push('0');
        } else {
            shape.push(c);
        }
    }
    shape
}

/// Indices of a subset of `texts` whose lines have every line shape of `texts`, chosen greedily
/// by new shapes per byte, in the order of `texts`.
fn covering_subset(texts: &[&str]) -> Vec<usize> {
    use std::collections::HashSet;
    let shapes: Vec<HashSet<String>> =
        texts.iter().map(|t| t.lines().filter(|l| !l.trim().is_empty()).map(line_shape).collect()).collect();
    let mut covered: HashSet<&String> = HashSet::new();
    let mut chosen = Vec::new();
    loop {
        let best = (0..texts.len())
            .map(|i| (i, shapes[i].iter().filter(|s| !covered.contains(s)).count()))
            .filter(|&(_, new)| new > 0)
            .max_by(|&(i, a), &(j, b)| (a * texts[j].len().max(1)).cmp(&(b * texts[i].len().max(1))).then(j.cmp(&i)));
        let Some((i, _)) = best else { break };
        covered.extend(shapes[i].iter());
        chosen.push(i);
    }
    chosen.sort_unstable();
    chosen
}

/// SCL as blark reads it: TIA's source lines go, the global data block becomes a global
/// variable list, `CONST` sections become `VAR CONSTANT` ones, `VAR_TEMP` becomes `VAR`, tags
/// `"x"` become `x` (`"Lamp On"` becomes `Lamp_On`), since IEC reads a double-quoted text as a
/// string literal.
// Not every test binary that includes this module prints SCL.
#[allow(dead_code)]
pub fn scl_for_blark(text: &str) -> String {
    let mut out = String::new();
    let mut in_const = false;
    for line in text.lines() {
        let t = line.trim();
        if t.starts_with("{ S7_Optimized_Access") || t.starts_with("VERSION :") || t == "BEGIN" || t == "END_DATA_BLOCK"
        {
            continue;
        }
        if t.starts_with("DATA_BLOCK ") {
            out.push_str("VAR_GLOBAL\n");
            continue;
        }
        if t == "STRUCT" {
            continue;
        }
        // blark's grammar has no VAR_TEMP in functions (IEC and SCL do).
        if t == "VAR_TEMP" {
            out.push_str("VAR\n");
            continue;
        }
        if t == "END_STRUCT;" {
            out.push_str("END_VAR\n");
            continue;
        }
        if t == "CONST" {
            in_const = true;
            out.push_str("VAR CONSTANT\n");
            continue;
        }
        if t == "END_CONST" {
            in_const = false;
            out.push_str("END_VAR\n");
            continue;
        }
        let line = if in_const { line.replacen(" := ", " : INT := ", 1) } else { line.to_string() };
        let (code, comment) = line.split_once("(*").map_or((line.as_str(), None), |(c, r)| (c, Some(r)));
        // Tags: `"Lamp On"` → `Lamp_On`.
        let mut in_tag = false;
        for ch in code.chars() {
            match ch {
                '"' => in_tag = !in_tag,
                ' ' if in_tag => out.push('_'),
                _ => out.push(ch),
            }
        }
        if let Some(rest) = comment {
            out.push_str("(*");
            out.push_str(rest);
        }
        out.push('\n');
    }
    // The data block's VAR (S7-1200/1500) inside VAR_GLOBAL: keep one section.
    out.replace("VAR_GLOBAL\nVAR\n", "VAR_GLOBAL\n")
}

#[test]
fn line_shapes_keep_keywords_nesting_and_punctuation_and_covers_keep_every_shape() {
    assert_eq!(line_shape("    IF start AND NOT t1.Q THEN"), "    IF x AND NOT x.x THEN");
    assert_eq!(line_shape("  lamp := T#1500ms; (* lamp on *)"), "  x := x#0x; (**)");
    assert_eq!(line_shape("END_IF;"), "END_IF;");
    // Comments keep the characters that could end or nest them; GUIDs are one shape.
    assert_eq!(line_shape("  (* state (n1, TL1.M1.P.I) *)"), line_shape("  (* state (n0, TL1.M1.P.W, TL1.TU.P.W) *)"));
    assert_eq!(line_shape("  x := 1; (* 'a' (b) *)"), "  x := 0; (*()'*)");
    assert_ne!(line_shape("(* a *)"), line_shape("(* a (b) *)"));
    assert_eq!(line_shape("(* a *) b (* c *)"), "(**) x (**)");
    assert_eq!(line_shape(r#"  <POU Name="A" Id="{8d2f-11aa-4c}">"#), r#"  <x="x" x="{}">"#);
    assert_eq!(line_shape("{attribute 'hide'}"), "{x 'x'}");
    assert_eq!(line_shape("(* open"), "(* x");
    assert_ne!(line_shape("  END_IF;"), line_shape("    END_IF;"));
    let a = "IF a THEN\n  b := 1;\nEND_IF;\n";
    let b = "IF c THEN\n  d := 22;\nEND_IF;\n";
    let c = "WHILE a DO\n  b := 1;\nEND_WHILE;\n";
    // `b` adds no shape to `a`; `c` adds two.
    assert_eq!(covering_subset(&[a, b, c]), vec![0, 2]);
    assert_eq!(covering_subset(&[a, a]).len(), 1);
}

/// The configuration of every proptest block: `base` cases, times `PLCSYNTH_PROPTEST_SCALE`
/// (`make test-long` sets 10). Blocks name their own base because their cases differ in cost
/// by orders of magnitude; the scale is the one knob that makes all of them bigger.
pub fn proptest_config(base: u32) -> proptest::prelude::ProptestConfig {
    let scale = std::env::var("PLCSYNTH_PROPTEST_SCALE").ok().and_then(|v| v.parse::<u32>().ok()).unwrap_or(1).max(1);
    proptest::prelude::ProptestConfig::with_cases(base.saturating_mul(scale))
}

/// The STL form of `unit` written to a scratch file for awlsim (`prefix`, `name`), checked
/// first, with where its program's block instance lives: its variables, its data block and
/// the bytes to read of it.
pub fn awl_instance(
    prefix: &str,
    name: &str,
    unit: &plcsynth::plc::model::unit::Unit,
) -> (PathBuf, Vec<plcsynth::plc::print::stl::unit::Location>, u16, u32) {
    use plcsynth::plc::{self, model::unit::PouKind, print::stl::unit as unit_stl};
    let options = plc::unit_stl_options(&plc::Options::default());
    assert_eq!(unit_stl::check(unit, &options), Vec::<String>::new(), "{name}");
    let text = &plc::render_unit_files(unit, plc::Target::Stl, &plc::Options::default()).unwrap()[0].text;
    let path = scratch(prefix, &format!("{name}.awl"), text);
    let program = unit.pous.iter().find(|p| p.kind == PouKind::Program).unwrap();
    let locations = unit_stl::instance_locations(unit, &options, &program.locals[0].name);
    let db = locations[0].db;
    let size = locations.iter().map(|l| l.byte + 2).max().unwrap();
    (path, locations, db, size)
}
