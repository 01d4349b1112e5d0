//! Helpers shared by the test binaries that run the independent checkers.

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

/// Parses `files` with blark in two processes, one per core (`tests/checkers/blark_many.py`:
/// blark's start-up costs about a second, more than most files), and fails naming every file
/// it rejects.
pub fn blark_all(python: &Path, root: &Path, files: &[PathBuf]) {
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
