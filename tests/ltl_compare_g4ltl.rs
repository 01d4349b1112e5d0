//! `plcsynth ltl --to-g4ltl` and `bench ltl --compare-g4ltl` without G4LTL: the table is built
//! from recorded driver output (`tests/fixtures/ltl/g4ltl-driver-output.txt`, a real run's
//! lines), every translation reads back with the verdict of its original, and what G4LTL cannot
//! express is refused where it is written.

use plcsynth::ltl::{self, Config, Format, Verdict};
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn plcsynth(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_plcsynth")).current_dir(root()).args(args).output().unwrap()
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

fn scratch(name: &str, contents: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("ltl-compare-g4ltl-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(name);
    std::fs::write(&path, contents).unwrap();
    path
}

const FIXTURE: &str = "tests/fixtures/ltl/g4ltl-driver-output.txt";

/// The comparison table built from `driver_output` (a file), with one run of ours.
fn replay(driver_output: &str) -> Output {
    plcsynth(&["bench", "ltl", "--runs", "1", "--g4ltl-replay", driver_output])
}

/// The table row of `spec` (its first cell), split into cells.
fn row(table: &str, spec: &str) -> Vec<String> {
    let line = table
        .lines()
        .find(|l| l.starts_with(&format!("| {spec} |")))
        .unwrap_or_else(|| panic!("no row for {spec} in\n{table}"));
    line.trim_matches('|').split(" | ").map(|c| c.trim().to_string()).collect()
}

#[test]
fn recorded_driver_output_becomes_the_table() {
    let out = replay(FIXTURE);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    let table = text(&out.stdout);
    // specification, inputs / outputs, plcsynth, time, G4LTL, time, ratio, known, agree
    let example1 = row(&table, "example1");
    assert_eq!(example1[2], "unrealizable (k = 0)");
    assert_eq!(example1[4], "unrealizable (depth 1)");
    assert_eq!(example1[7], "unrealizable");
    assert_eq!(example1[8], "yes");
    // The time is the fixture's, to the millisecond.
    let recorded = std::fs::read_to_string(root().join(FIXTURE)).unwrap();
    let ms = recorded.lines().find(|l| l.contains("/example1.g4ltl\t")).unwrap().split('\t').nth(4).unwrap();
    assert_eq!(example1[5], ms);
    // TLSF goes to G4LTL translated.
    assert!(row(&table, "simple_arbiter n = 2")[4].starts_with("realizable (depth 1, translated"), "{table}");
    // The timer restarted forever: G4LTL promises the expiry anyway.
    let restart = row(&table, "restart_forever.ltl");
    assert_eq!((restart[2].as_str(), restart[8].as_str()), ("unrealizable (k = 1)", "no"));
    assert!(restart[4].starts_with("realizable"), "{restart:?}");
    // Numeric inputs are not given to G4LTL, and say why.
    let heating = row(&table, "heating.ltl");
    assert!(heating[4].starts_with("not given: G4LTL reads Boolean signals only"), "{heating:?}");
    assert_eq!(heating[8], "–");
    // `<->` is G4LTL's parse error, reported as such.
    assert!(row(&table, "ptii_AutomaticDoor")[4].starts_with("error: "), "{table}");
    assert!(table.contains(" agree, 2 disagree, "), "{table}");
    assert!(table.contains(", 3 not given to G4LTL"), "{table}");
}

#[test]
fn the_table_follows_the_driver_output() {
    // The same run with G4LTL's answer on example1 flipped: the row disagrees, the count moves.
    let recorded = std::fs::read_to_string(root().join(FIXTURE)).unwrap();
    let flipped: String =
        recorded
            .lines()
            .map(|l| {
                if l.contains("/example1.g4ltl\t") {
                    l.replace("\tunrealizable\t", "\trealizable\t")
                } else {
                    l.into()
                }
            })
            .map(|l| l + "\n")
            .collect();
    let out = replay(scratch("flipped.txt", &flipped).to_str().unwrap());
    let table = text(&out.stdout);
    assert_eq!(row(&table, "example1")[8], "no");
    assert!(table.contains(" agree, 3 disagree, "), "{table}");
    // A file the driver did not answer for is undecided, not an agreement.
    let without: String =
        recorded.lines().filter(|l| !l.contains("/example1.g4ltl\t")).map(|l| format!("{l}\n")).collect();
    let out = replay(scratch("without.txt", &without).to_str().unwrap());
    assert_eq!(row(&text(&out.stdout), "example1")[4], "no answer from the driver");
}

#[test]
fn malformed_driver_output_is_an_error_naming_the_line() {
    let path = scratch("bad.txt", "G4LTL prints this\ng4ltl\tx.ltl\trealizable\tone\t12\t\n");
    let out = replay(path.to_str().unwrap());
    assert_eq!(out.status.code(), Some(2));
    let err = text(&out.stderr);
    assert!(err.contains("driver output line 2: the unroll depth is not a number"), "{err}");
    let path = scratch("verdict.txt", "g4ltl\tx.ltl\tmaybe\t1\t12\t\n");
    assert!(text(&replay(path.to_str().unwrap()).stderr).contains("line 1: unknown verdict"));
}

/// Every specification file of `dir` and below.
fn files(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            out.extend(files(&path));
        } else if path.extension().is_some_and(|e| e == "ltl" || e == "g4ltl" || e == "tlsf") {
            out.push(path);
        }
    }
    out.sort();
    out
}

/// Whether `text` stays inside what G4LTL reads: `##` comments, declarations, and formulas of
/// JPF's operators over names without an upper-case U, V, W or X (its parser splits them).
/// Independent of the writer: a token scan of its output.
fn g4ltl_readable(text: &str) -> Result<(), String> {
    for line in text.lines().filter(|l| !l.is_empty() && !l.starts_with("##")) {
        if line.starts_with("INPUT ") || line.starts_with("OUTPUT ") || line.starts_with("TIMER ") {
            continue;
        }
        let formula = line.strip_prefix("ASSUME ").unwrap_or(line);
        let mut rest = formula;
        while let Some(c) = rest.chars().next() {
            if c == ' ' || c == '(' || c == ')' || c == '!' {
                rest = &rest[1..];
            } else if let Some(r) = ["[]", "<>", "&&", "||", "->"].iter().find_map(|op| rest.strip_prefix(op)) {
                rest = r;
            } else if c.is_ascii_alphanumeric() || c == '_' {
                let end =
                    rest.find(|c: char| !(c.is_ascii_alphanumeric() || c == '_' || c == '.')).unwrap_or(rest.len());
                let word = &rest[..end];
                let operator = ["X", "U", "V", "W"].contains(&word);
                // JPF has no G, F or R; it splits a name at an upper-case U, V, W or X.
                let foreign = ["G", "F", "R"].contains(&word) || word.starts_with(|c: char| c.is_ascii_digit());
                if foreign || (!operator && word.contains(['U', 'V', 'W', 'X'])) {
                    return Err(format!("`{word}` in `{line}`"));
                }
                if word.contains('.') && !(word.ends_with(".start") || word.ends_with(".expire")) {
                    return Err(format!("`{word}` in `{line}`"));
                }
                rest = &rest[end..];
            } else {
                return Err(format!("`{c}` in `{line}`"));
            }
        }
    }
    Ok(())
}

/// The verdict within an eighth of the default work budget: the check is that a translation
/// never flips a decided verdict, and most files decide in far less (the few that need more
/// would double this test's time, twice over).
fn decide(spec: &ltl::Spec) -> Verdict {
    let cfg = Config { max_work: ltl::DEFAULT_MAX_WORK / 8, ..Config::default() };
    ltl::synthesize(spec, &cfg, &mut |_| true).map_or(Verdict::Unknown, |o| o.verdict)
}

#[test]
fn every_translation_reads_back_with_the_same_verdict() {
    let mut all = files(&root().join("examples/ltl"));
    all.extend(files(&root().join("../shared/ltl")));
    let (mut translated, mut refused, mut decided) = (0, Vec::new(), 0);
    for path in &all {
        let source = std::fs::read_to_string(path).unwrap();
        let (spec, _) = ltl::compile(&source, Format::of_path(path.to_str().unwrap()), &[]).unwrap();
        let written = match ltl::to_g4ltl(&source, &spec) {
            Ok(written) => written,
            Err(errors) => {
                assert!(errors[0].message.contains("numeric input"), "{}: {}", path.display(), errors[0].message);
                refused.push(path.file_name().unwrap().to_string_lossy().into_owned());
                continue;
            }
        };
        translated += 1;
        g4ltl_readable(&written).unwrap_or_else(|e| panic!("{}: G4LTL cannot read {e}", path.display()));
        let (again, _) = ltl::compile(&written, Format::G4ltl, &[])
            .unwrap_or_else(|d| panic!("{}: {d:?}\n{written}", path.display()));
        assert_eq!(again.inputs().len(), spec.inputs().len(), "{}", path.display());
        assert_eq!(again.outputs().len(), spec.outputs().len(), "{}", path.display());
        let (before, after) = (decide(&spec), decide(&again));
        // The translation may cost more work (`<->` written as two implications): a verdict one
        // side reaches within the budget and the other not is no disagreement.
        if before != Verdict::Unknown && after != Verdict::Unknown {
            assert_eq!(before, after, "{}: the translation changes the verdict\n{written}", path.display());
            decided += 1;
        }
    }
    refused.sort();
    assert_eq!(refused, ["fig1.ltl", "heating.ltl", "heating_overlap.ltl"]);
    assert!(translated >= 70 && decided >= 60, "{translated} translated, {decided} decided");
}

#[test]
fn the_readability_check_catches_what_g4ltl_cannot_read() {
    assert!(g4ltl_readable("[] (a -> X <> b)\nASSUME [] <> !a\nINPUT a\nOUTPUT b\n").is_ok());
    assert!(g4ltl_readable("G (a -> b)\n").is_err());
    assert!(g4ltl_readable("[] (a <-> b)\n").is_err());
    assert!(g4ltl_readable("[] (aXb -> b)\n").is_err());
    assert!(g4ltl_readable("// a comment\n").is_err());
}

#[test]
fn the_cli_writes_a_file_g4ltl_reads_and_we_read_back() {
    let out = plcsynth(&["ltl", "examples/ltl/copy_moore.tlsf", "--to-g4ltl"]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    let written = text(&out.stdout);
    assert!(written.starts_with("## examples/ltl/copy_moore.tlsf written for G4LTL"), "{written}");
    assert!(written.contains("[] ((X r -> g) && (g -> X r))"), "{written}");
    let path = scratch("copy_moore.ltl", &written);
    // Moore's copy stays unrealizable once its inputs are read a step later.
    assert_eq!(plcsynth(&["ltl", path.to_str().unwrap()]).status.code(), Some(1));
}

#[test]
fn numeric_inputs_and_unreadable_names_are_refused_where_declared() {
    let out = plcsynth(&["ltl", "examples/ltl/heating.ltl", "--to-g4ltl"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(out.stdout.is_empty());
    let err = text(&out.stderr);
    assert!(
        err.contains(
            "heating.ltl:10:7: error: G4LTL reads Boolean signals only: the numeric input `temp` has no G4LTL form"
        ),
        "{err}"
    );
    let names = scratch(
        "names.ltl",
        "ALWAYS (reqX -> grant)\nALWAYS (t1.start -> t1_start)\nINPUT reqX\nOUTPUT grant, t1_start\nTIMER t1(1s)\n",
    );
    let out = plcsynth(&["ltl", names.to_str().unwrap(), "--to-g4ltl"]);
    assert_eq!(out.status.code(), Some(2));
    let err = text(&out.stderr);
    assert!(err.contains("names.ltl:3:7: error: G4LTL cannot read the signal name `reqX`"), "{err}");
    assert!(err.contains("names.ltl:4:15: error: `t1_start` clashes with G4LTL's name for `t1.start`"), "{err}");
}
