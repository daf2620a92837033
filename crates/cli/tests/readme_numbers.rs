//! The numbers the README quotes are true: each is read from README.md, the
//! command that makes it is run, and the result must round to the printed
//! digits (half a unit of the last printed digit; counts exactly).
//!
//! Covered: the `tecon vessel` table rows `paper`, `1`, `2` (triangles, the
//! four mean hoop prestresses, the mean contact pressure, Newton
//! iterations), the rows `paper` and `2` of the Newton counts in "Known
//! limits", the shrink-fit example's FE contact pressure, and the
//! torsion examples (J and τ_max of the unit square, J of the box). The
//! finer meshes of the table (levels 3 to 5, minutes) and the wall times
//! are not run here.

use std::path::{Path, PathBuf};
use std::process::Command;

use serde_json::Value;

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn readme() -> String {
    std::fs::read_to_string(root().join("README.md")).unwrap()
}

/// A number as the README prints it: Unicode minus, thin grouping spaces.
fn parse(s: &str) -> f64 {
    let t: String = s
        .trim()
        .replace('−', "-")
        .chars()
        .filter(|c| !c.is_whitespace())
        .collect();
    t.parse()
        .unwrap_or_else(|_| panic!("README number `{s}` does not parse"))
}

/// Half a unit of the last printed digit of `s`.
fn half_ulp(s: &str) -> f64 {
    let t = s.trim();
    let decimals = t.split_once('.').map_or(0, |(_, d)| {
        d.chars().take_while(char::is_ascii_digit).count()
    });
    0.5 * 10f64.powi(-(decimals as i32))
}

fn assert_printed(what: &str, printed: &str, actual: f64) {
    let (p, tol) = (parse(printed), half_ulp(printed));
    // 1e-9 relative slack for the decimal representation itself
    assert!(
        (actual - p).abs() <= tol * (1.0 + 1e-9),
        "README says {what} = {printed}, the run gives {actual}"
    );
}

fn tecon(args: &[&str], cwd: &Path) -> String {
    let o = Command::new(env!("CARGO_BIN_EXE_tecon"))
        .args(args)
        .current_dir(cwd)
        .output()
        .unwrap();
    assert!(
        o.status.success(),
        "tecon {args:?}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    String::from_utf8_lossy(&o.stdout).into_owned()
}

fn summary(dir: &Path) -> Value {
    serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap()
}

fn num(v: &Value, key: &str) -> f64 {
    v.pointer(key)
        .and_then(Value::as_f64)
        .unwrap_or_else(|| panic!("{key} missing"))
}

#[test]
fn the_vessel_table_rows_paper_1_2_and_g0_are_what_tecon_vessel_gives() {
    let text = readme();
    let d = tempfile::tempdir().unwrap();
    for mesh in ["paper", "1", "2", "g0"] {
        let row: Vec<&str> = text
            .lines()
            .find(|l| {
                l.starts_with(&format!("| {mesh} |")) || l.starts_with(&format!("| {mesh} ("))
            })
            .unwrap_or_else(|| panic!("README has no table row for mesh {mesh}"))
            .split('|')
            .map(str::trim)
            .collect();
        // | mesh | triangles | core inner | core outer | layer inner | layer outer | p | Newton | time |
        let out = d.path().join(format!("v{mesh}"));
        tecon(
            &[
                "vessel",
                "--mesh",
                mesh,
                "--quiet",
                "--out",
                out.to_str().unwrap(),
            ],
            d.path(),
        );
        let v = summary(&out);
        assert_eq!(
            parse(row[2]),
            num(&v, "/mesh/triangles"),
            "mesh {mesh}: triangles"
        );
        for (k, key) in ["core_inner", "core_outer", "layer_inner", "layer_outer"]
            .iter()
            .enumerate()
        {
            assert_printed(
                &format!("mesh {mesh}: hoop {key} [MPa]"),
                row[3 + k],
                num(&v, &format!("/final/hoop_mean/{key}")) / 1e6,
            );
        }
        assert_printed(
            &format!("mesh {mesh}: contact pressure [MPa]"),
            row[7],
            num(&v, "/final/contact_pressure_mean") / 1e6,
        );
        assert_eq!(
            parse(row[8]),
            num(&v, "/newton/iterations"),
            "mesh {mesh}: Newton iterations in the README"
        );
    }
}

/// The "Known limits" table of Newton counts: the rows `paper` and `2`
/// (most iterations in one increment / in one pass, per joint).
#[test]
fn the_newton_count_rows_paper_and_2_are_what_tecon_vessel_gives() {
    let text = readme();
    let header = "| mesh | frictionless | μ = 0.3 | μ = 1 | μ = 2 | bonded |";
    let table: Vec<&str> = text
        .lines()
        .map(str::trim)
        .skip_while(|l| *l != header)
        .take_while(|l| l.starts_with('|'))
        .collect();
    assert!(!table.is_empty(), "README has no Newton count table");
    let d = tempfile::tempdir().unwrap();
    let joints: [&[&str]; 5] = [
        &["--interface", "frictionless"],
        &["--friction", "0.3"],
        &["--friction", "1"],
        &["--friction", "2"],
        &["--interface", "bonded"],
    ];
    for mesh in ["paper", "2"] {
        let row: Vec<&str> = table
            .iter()
            .find(|l| l.starts_with(&format!("| {mesh} |")))
            .unwrap_or_else(|| panic!("the Newton count table has no row {mesh}"))
            .split('|')
            .map(str::trim)
            .collect();
        for (k, joint) in joints.iter().enumerate() {
            let (inc, pass) = row[2 + k]
                .split_once('/')
                .unwrap_or_else(|| panic!("cell `{}` is not `N / M`", row[2 + k]));
            let out = d.path().join(format!("n{mesh}_{k}"));
            let mut args = vec!["vessel", "--mesh", mesh, "--quiet", "--out"];
            args.push(out.to_str().unwrap());
            args.extend_from_slice(joint);
            tecon(&args, d.path());
            let v = summary(&out);
            assert_eq!(
                (parse(inc), parse(pass)),
                (
                    num(&v, "/newton/max_iterations_per_increment"),
                    num(&v, "/newton/max_iterations_per_pass")
                ),
                "mesh {mesh} {joint:?}: most Newton iterations per increment / pass"
            );
        }
    }
}

#[test]
fn the_shrink_fit_example_gives_the_quoted_fe_pressure() {
    let text = readme();
    let line = text
        .lines()
        .find(|l| l.starts_with("tecon run examples/cases/shrink_fit.toml"))
        .expect("README: the shrink-fit command");
    let fe = line
        .split("FE ")
        .nth(1)
        .and_then(|s| s.split_whitespace().next())
        .expect("README: `FE <value> MPa`");
    let d = tempfile::tempdir().unwrap();
    let case = root().join("examples/cases/shrink_fit.toml");
    let out = d.path().join("out");
    tecon(
        &[
            "run",
            case.to_str().unwrap(),
            "--quiet",
            "--out",
            out.to_str().unwrap(),
        ],
        d.path(),
    );
    let p = num(
        &summary(&out),
        "/times/0/interfaces/inner_outer/contact_pressure_mean",
    );
    assert_printed("the shrink fit's FE contact pressure [MPa]", fe, p / 1e6);
}

#[test]
fn the_torsion_examples_give_the_quoted_values() {
    let text = readme();
    let d = tempfile::tempdir().unwrap();
    for (section, extra) in [
        ("rectangle:w=1,h=1", vec![]),
        ("box:w=2,h=1,tf=0.1,tw=0.05", vec!["--tol", "1e-6"]),
    ] {
        let line = text
            .lines()
            .find(|l| l.starts_with(&format!("tecon torsion --section {section} ")))
            .unwrap_or_else(|| panic!("README: the {section} example"));
        let comment = line.split_once('#').expect("a comment with the values").1;
        let mut args = vec!["torsion", "--section", section, "--format", "json"];
        args.extend(extra);
        let v: Value = serde_json::from_str(&tecon(&args, d.path())).unwrap();
        for (name, key) in [
            ("J = ", "torsional_rigidity"),
            ("τ_max = ", "max_shear_stress"),
        ] {
            if let Some(s) = comment.split(name).nth(1) {
                let printed = s.split([',', ' ']).next().unwrap();
                assert_printed(
                    &format!("{section}: {name}"),
                    printed,
                    v[key].as_f64().unwrap(),
                );
            }
        }
    }
}
