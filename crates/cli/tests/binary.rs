//! The `tecon` binary on bad input: exit code 2, one line on stderr naming
//! the case file and the key, and no output folder left behind. (The case
//! files themselves are tested end to end in the workspace's top-level
//! `tests/case_files.rs`.)

use std::path::Path;

fn cases_dir() -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/cases")
}

fn edited(from: &str, to: &str) -> String {
    let text = std::fs::read_to_string(cases_dir().join("shrink_fit.toml")).unwrap();
    assert!(text.contains(from), "{from}");
    text.replacen(from, to, 1)
}

#[test]
fn binary_exits_2_with_one_line_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("bad.toml");
    std::fs::write(&path, edited("poisson_ratio = 0.3", "poisson_ration = 0.3")).unwrap();
    let out = dir.path().join("results");
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_tecon"))
        .arg("run")
        .arg(&path)
        .arg("--out")
        .arg(&out)
        .arg("--quiet")
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert_eq!(stderr.trim_end().lines().count(), 1, "{stderr}");
    assert!(
        stderr.starts_with("error: ")
            && stderr.contains("bad.toml")
            && stderr.contains("poisson_ration"),
        "{stderr}"
    );
    assert!(!out.exists(), "nothing written");
}
