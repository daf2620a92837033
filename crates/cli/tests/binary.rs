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

#[test]
fn negative_numbers_reach_the_checks_that_name_them() {
    // a value written with a leading minus is the option's value, not an
    // unknown flag: the option's own check names it (or it is used)
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("results");
    let tecon = |args: &[&str]| {
        std::process::Command::new(env!("CARGO_BIN_EXE_tecon"))
            .args(args)
            .arg("--out")
            .arg(&out)
            .output()
            .unwrap()
    };
    for (args, says) in [
        (
            &["vessel", "--mesh", "paper", "--friction", "-1"][..],
            "--friction -1: must be a non-negative coefficient",
        ),
        (
            &["vessel", "--mesh", "paper", "--times", "-1,2"][..],
            "--times: value 1 is -1",
        ),
        (
            &["vessel", "--mesh", "paper", "--yield", "-1"][..],
            "--yield -1",
        ),
        (
            &["vessel", "--layers", "2", "--seams", "-10,0"][..],
            "--seams: -10°",
        ),
        (
            &["torsion", "--section", "circle:r=1", "--tol", "-1"][..],
            "--tol: need 0 < TOL < 1, got -1",
        ),
    ] {
        let o = tecon(args);
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {stderr}");
        assert!(stderr.contains(says), "{args:?}: {stderr}");
    }
    // interior points with negative coordinates
    let o = tecon(&[
        "torsion",
        "--section",
        "circle:r=1",
        "--points",
        "-0.5,0.1",
        "--format",
        "json",
    ]);
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let v: serde_json::Value = serde_json::from_str(&stdout).unwrap();
    let p = &v["interior"][0];
    // the unit disc: u = (1 − x² − y²)/2, τ_xz = −y, τ_yz = x
    assert_eq!(p["x"][0].as_f64(), Some(-0.5), "{p}");
    let close = |key: &str, want: f64| (p[key].as_f64().unwrap() - want).abs() < 1e-9;
    assert!(
        close("u", 0.37) && close("tau_xz", -0.1) && close("tau_yz", -0.5),
        "{p}"
    );
}

#[test]
fn an_overflowing_load_fails_at_once_and_says_why() {
    // 1e300 Pa overflows the products of the residual: Newton stops at its
    // first iterate instead of iterating on NaN to its limit in every
    // cut-back (150 iterations × 11 attempts before)
    let dir = tempfile::tempdir().unwrap();
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_tecon"))
        .args([
            "vessel",
            "--mesh",
            "paper",
            "--pressure",
            "1e300",
            "--quiet",
        ])
        .arg("--out")
        .arg(dir.path().join("results"))
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(
        stderr.contains("the residual is not finite")
            && stderr.contains("overflows double precision")
            && stderr.contains("the halved increment overflowed too"),
        "{stderr}"
    );
    assert!(
        stderr.matches("it  0:").count() >= 1 && !stderr.contains("it  1:"),
        "{stderr}"
    );
}
