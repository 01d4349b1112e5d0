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
pub fn blark_all(python: &Path, root: &Path, files: &[PathBuf]) {
    // Targets often print the same text (IEC ST and SCL after `scl_for_blark`, say): blark
    // parses each text once, which checks exactly as much in about a third less time.
    let mut seen = std::collections::HashSet::new();
    let files: Vec<&PathBuf> =
        files.iter().filter(|f| seen.insert(std::fs::read(f).expect("a file written for blark"))).collect();
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
