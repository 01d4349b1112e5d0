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
        for engine in ["crate::timed", "crate::sct", "crate::ltl"] {
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

/// The code of `file` without its comment lines (a comment may name what code may not use).
fn code_lines(file: &Path) -> Vec<String> {
    let text = std::fs::read_to_string(file).expect("a readable source");
    text.lines().filter(|l| !l.trim_start().starts_with("//")).map(str::to_string).collect()
}

fn files_under(dir: &str) -> Vec<PathBuf> {
    let mut files = Vec::new();
    rust_files(&Path::new(env!("CARGO_MANIFEST_DIR")).join(dir), &mut files);
    assert!(!files.is_empty(), "no Rust files under {dir}");
    files
}

/// Fails naming the first line of a file under `dir` (but those under `except`) holding one of
/// `words`.
fn assert_no_mention(dir: &str, except: &[&str], words: &[&str], rule: &str) {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    for file in files_under(dir) {
        if except.iter().any(|e| file.starts_with(root.join(e))) {
            continue;
        }
        for line in code_lines(&file) {
            if let Some(word) = words.iter().find(|w| line.contains(*w)) {
                panic!("{}: {rule}, but it uses `{word}`: {}", file.display(), line.trim());
            }
        }
    }
}

/// The engines and the shared modules do no I/O and read no clock (`Instant` panics on wasm32):
/// the CLI and the page measure and print.
#[test]
fn nothing_but_the_adapters_does_io_or_reads_the_clock() {
    assert_no_mention(
        "src",
        // Unit tests read the test tiers' scale from the environment.
        &["src/cli", "src/main.rs", "src/wasm", "src/zone/tests.rs"],
        &[
            "std::fs",
            "std::io::std",
            "std::net",
            "std::process",
            "std::env",
            "Instant",
            "SystemTime",
            "println!",
            "eprintln!",
            "print!(",
        ],
        "only the CLI and the wasm adapter do I/O",
    );
}

/// wasm-bindgen and its crates are known to the page's adapter only, clap to the CLI only.
#[test]
fn the_adapters_own_their_frameworks() {
    assert_no_mention(
        "src",
        &["src/wasm"],
        &["wasm_bindgen", "js_sys", "web_sys", "serde_wasm_bindgen", "console_error_panic_hook"],
        "only src/wasm knows the browser",
    );
    assert_no_mention("src", &["src/cli", "src/main.rs"], &["clap::", "use clap"], "only the CLI parses arguments");
}

/// The three engines do not know each other (the timed engine's controller language,
/// `timed::program`, is inside it); `zone` knows no automata; `plc::fragment`, `diag`, `dot`,
/// `graph`, `syntax` and `rng` are shared.
#[test]
fn the_engines_are_independent() {
    assert_no_mention("src/sct", &[], &["crate::ltl", "crate::timed", "crate::zone"], "the SCT engine is on its own");
    assert_no_mention(
        "src/ltl",
        &[],
        &["crate::sct", "crate::timed", "crate::zone", "crate::plc"],
        "the LTL engine is on its own",
    );
    assert_no_mention("src/timed", &[], &["crate::sct", "crate::ltl"], "the timed engine is on its own");
    // What the engines share knows none of them.
    let search = Path::new(env!("CARGO_MANIFEST_DIR")).join("src/search.rs");
    for line in code_lines(&search) {
        // (`$crate::search` is its own macros naming it from where they are used.)
        let others = line.replace("crate::search::", "");
        assert!(!others.contains("crate::"), "src/search.rs uses another module: {}", line.trim());
    }
    assert_no_mention(
        "src/zone",
        &[],
        &["crate::timed", "crate::sct", "crate::ltl", "crate::plc"],
        "zones know no automata",
    );
}

/// An engine's `testing` module holds internals for the integration tests and the fuzz harness,
/// not API: nothing in `src/` outside the engine, and no benchmark, uses it.
#[test]
fn only_the_tests_use_the_engines_testing_modules() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    for engine in ["ltl", "sct", "timed"] {
        let own = root.join("src").join(engine);
        let path = format!("{engine}::");
        for file in files_under("src").into_iter().chain(files_under("benches")) {
            if file.starts_with(&own) {
                continue;
            }
            for line in code_lines(&file) {
                assert!(
                    !(line.contains(&path) && line.contains("testing")),
                    "{}: `{engine}::testing` is for the tests, but it uses it: {}",
                    file.display(),
                    line.trim()
                );
            }
        }
    }
    // The check looks for what the tests write.
    let tests: Vec<String> = files_under("tests").iter().flat_map(|f| code_lines(f)).collect();
    for engine in ["ltl", "timed"] {
        let name = format!("{engine}::testing");
        assert!(tests.iter().any(|l| l.contains(&name)), "no test uses `{name}`");
    }
}
