//! Invariants of the module structure that a test can check (ARCHITECTURE.md, "Invariants").

use std::path::{Path, PathBuf};

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).expect("a source folder") {
        let path = entry.expect("a directory entry").path();
        if path.is_dir() {
            rust_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

/// The code model, the printers and the file writers name no engine, so that every engine's
/// controllers print through them; only the lowerings (`src/plc/lower/`) know one.
#[test]
fn nothing_in_plc_but_the_lowerings_names_an_engine() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("src/plc");
    let lowerings = root.join("lower");
    let mut files = Vec::new();
    rust_files(&root, &mut files);
    let mut checked = 0;
    for file in files.iter().filter(|f| !f.starts_with(&lowerings)) {
        let text = std::fs::read_to_string(file).expect("a readable source");
        for engine in ["crate::timed", "crate::program", "crate::sct", "crate::ltl"] {
            assert!(!text.contains(engine), "{} mentions {engine}", file.display());
        }
        // A comment may name the lowering that builds a model; code may not use one (but the
        // front door, which declares them).
        if file.ends_with("src/plc/mod.rs") {
            continue;
        }
        let code = text.lines().filter(|l| !l.trim_start().starts_with("//"));
        for line in code {
            assert!(
                !line.contains("plc::lower") && !line.contains("lower::"),
                "{} uses a lowering: {line}",
                file.display()
            );
        }
        checked += 1;
    }
    assert!(checked >= 12, "only {checked} files checked under src/plc");
}
