//! README.md's measured tables are generated (`make readme-bench`): each sits between its
//! marker comments, under the caption of the command that made it, with the header lines that
//! command prints now. The figures are not compared (they vary from run to run).

use std::process::Command;

const ENGINES: [&str; 3] = ["timed", "sct", "ltl"];

fn readme() -> String {
    std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/README.md")).expect("README.md")
}

/// The standard output of `plcsynth bench ARGS...`, which must succeed.
fn bench(args: &[&str]) -> String {
    let out = Command::new(env!("CARGO_BIN_EXE_plcsynth"))
        .arg("bench")
        .args(args)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .unwrap();
    assert!(out.status.success(), "bench {args:?}: {}", String::from_utf8_lossy(&out.stderr));
    String::from_utf8(out.stdout).unwrap()
}

/// The text between `<!-- bench ENGINE: begin -->` and `<!-- bench ENGINE: end -->`, each
/// present once and in this order.
fn generated<'a>(readme: &'a str, engine: &str) -> &'a str {
    let begin = format!("<!-- bench {engine}: begin -->");
    let end = format!("<!-- bench {engine}: end -->");
    assert_eq!(readme.matches(&begin).count(), 1, "README.md needs exactly one `{begin}`");
    assert_eq!(readme.matches(&end).count(), 1, "README.md needs exactly one `{end}`");
    let (b, e) = (readme.find(&begin).unwrap() + begin.len(), readme.find(&end).unwrap());
    assert!(b <= e, "`{begin}` must come before `{end}`");
    &readme[b..e]
}

/// Every markdown table's header line: a `|` line followed by an alignment rule.
fn header_lines(markdown: &str) -> Vec<&str> {
    let lines: Vec<&str> = markdown.lines().map(str::trim_end).collect();
    lines.windows(2).filter(|w| w[0].starts_with('|') && w[1].starts_with("|---")).map(|w| w[0]).collect()
}

#[test]
fn readme_tables_have_the_headers_the_benches_print() {
    let readme = readme();
    for engine in ENGINES {
        let section = generated(&readme, engine);
        assert!(
            section.contains(&format!("`plcsynth bench {engine} --markdown --runs ")),
            "README's `bench {engine}` tables lack their caption: regenerate them with `make readme-bench`"
        );
        let expected = bench(&[engine, "--headers"]);
        let expected: Vec<&str> = expected.lines().collect();
        assert!(!expected.is_empty());
        assert_eq!(
            header_lines(section),
            expected,
            "README's `bench {engine}` tables differ from what the bench prints: run `make readme-bench`"
        );
    }
}

/// `--headers` (cheap) gives the header lines `--markdown` prints; checked on `bench sct`,
/// the one quick enough to run here (timed and ltl share the same column constants).
#[test]
fn headers_flag_matches_the_markdown_output() {
    let markdown = bench(&["sct", "--markdown", "--runs", "1"]);
    let headers = bench(&["sct", "--headers"]);
    assert_eq!(header_lines(&markdown), headers.lines().collect::<Vec<_>>(), "{markdown}");
    let caption = markdown.lines().next().unwrap();
    assert!(caption.contains("plcsynth bench sct --markdown --runs 1") && caption.contains("median"), "{caption}");
    // Only tables under the caption: no chatter.
    assert!(markdown.lines().skip(1).all(|l| l.is_empty() || l.starts_with('|')), "{markdown}");
}
