//! The `tecon` binary on input a new user gets wrong: options that would be
//! ignored, case-file values out of order or of the wrong type, and the
//! explanation of a failure the user can act on. Every refusal exits 2 with
//! one line on stderr naming the flags, file and key at fault.

use std::path::{Path, PathBuf};
use std::process::Output;

fn cases_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/cases")
}

/// The example case `name` with its first `from` replaced by `to`.
fn edited(name: &str, from: &str, to: &str) -> String {
    let text = std::fs::read_to_string(cases_dir().join(name)).unwrap();
    assert!(text.contains(from), "{from}");
    text.replacen(from, to, 1)
}

/// Runs `tecon` with `args` and `--out` a fresh folder in `dir`.
fn tecon(dir: &Path, args: &[&str]) -> Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_tecon"))
        .args(args)
        .arg("--out")
        .arg(dir.join("results"))
        .output()
        .unwrap()
}

/// Asserts a refusal: exit 2, one line on stderr containing every `says`,
/// nothing written.
fn refused(dir: &Path, o: &Output, says: &[&str]) {
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{stderr}");
    assert_eq!(stderr.trim_end().lines().count(), 1, "{stderr}");
    for s in says {
        assert!(stderr.contains(s), "'{s}' not in: {stderr}");
    }
    assert!(!dir.join("results").exists(), "nothing written");
}

/// Runs the case `text` (written as `name` in `dir`).
fn run_case(dir: &Path, name: &str, text: &str, extra: &[&str]) -> Output {
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    let mut args = vec!["run", path.to_str().unwrap()];
    args.extend_from_slice(extra);
    tecon(dir, &args)
}

#[test]
fn case_file_type_errors_name_the_key_path() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // (shipped case, its line, the edited line, file name, what the error says)
    let cases: [(&str, &str, &str, &str, &[&str]); 4] = [
        // a string where a number belongs: the key, its table's index, the line
        (
            "shrink_fit.toml",
            "youngs_modulus = 207e9",
            "youngs_modulus = \"207e9\"",
            "wrong_type.toml",
            &[
                "wrong_type.toml:33:",
                "material[0].youngs_modulus: invalid type: string \"207e9\", expected f64",
            ],
        ),
        // a misspelt list-of-tables header: its [interface.joint] makes a
        // table of `interface`, and the error names it and how to write it
        (
            "shrink_fit.toml",
            "[[interface]]",
            "[[interfacee]]",
            "bad_table.toml",
            &[
                "bad_table.toml:50:",
                "interface: invalid type: map, expected a sequence",
                "[[interface]]",
            ],
        ),
        // a misspelt table on its own is an unknown key, named
        (
            "shrink_fit.toml",
            "[output]",
            "[outputt]",
            "unknown.toml",
            &["unknown.toml:", "outputt: unknown field `outputt`"],
        ),
        // the staged (multilayer) case files go through the same loader
        (
            "multilayer.toml",
            "seam = 120.0",
            "seam = \"120\"",
            "staged.toml",
            &[
                "staged.toml:",
                "multilayer.layer[1].seam: invalid type: string",
            ],
        ),
    ];
    for (shipped, from, to, name, says) in cases {
        let o = run_case(d, name, &edited(shipped, from, to), &[]);
        refused(d, &o, says);
    }
}

#[test]
fn case_file_times_out_of_order_or_repeated_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let shipped = "times = [1.0, 10.0, 60.0, 600.0, 3600.0, 72000.0]";
    for (times, says) in [
        (
            "times = [10.0, 1.0]",
            "output.times: 1 s (value 2) does not come after 10 s; give the output times in increasing order",
        ),
        (
            "times = [1.0, 1.0]",
            "output.times: 1 s (value 2) does not come after 1 s",
        ),
    ] {
        let text = edited("vessel.toml", shipped, times);
        let o = run_case(d, "times.toml", &text, &["--quiet"]);
        refused(d, &o, &["times.toml: ", says]);
    }
    // a staged case's [[stage]] times too
    let text = edited(
        "multilayer.toml",
        "times = [60.0, 72000.0]",
        "times = [72000.0, 60.0]",
    );
    let o = run_case(d, "staged_times.toml", &text, &["--quiet"]);
    refused(
        d,
        &o,
        &[
            "staged_times.toml: [[stage]] 1",
            "times: 60 s (value 2) does not come after 72000 s",
        ],
    );
    // the shipped cases give their times in order (they run end to end in
    // the workspace's tests/case_files.rs)
    for entry in std::fs::read_dir(cases_dir()).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "toml") {
            let text = std::fs::read_to_string(&path).unwrap();
            for line in text.lines().filter(|l| l.starts_with("times = [")) {
                let inner = line["times = [".len()..].split(']').next().unwrap();
                let v: Vec<f64> = inner
                    .split(',')
                    .map(|x| x.trim().parse().unwrap())
                    .collect();
                assert!(
                    v.windows(2).all(|w| w[0] < w[1]),
                    "{}: {line}",
                    path.display()
                );
            }
        }
    }
}

#[test]
fn run_quiet_prints_the_warnings() {
    // `tecon run --quiet`, as `tecon vessel --quiet`: nothing but warnings
    // and errors (a yield stress exceeded is a warning)
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let text = edited(
        "vessel.toml",
        "region = \"weld\"\n",
        "region = \"weld\"\nyield = 1e6\n",
    )
    .replacen(
        "times = [1.0, 10.0, 60.0, 600.0, 3600.0, 72000.0]",
        "times = [60.0, 72000.0]",
        1,
    );
    let o = run_case(d, "yielding.toml", &text, &["--quiet"]);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(0), "{stderr}");
    assert!(
        o.stdout.is_empty(),
        "{}",
        String::from_utf8_lossy(&o.stdout)
    );
    let warnings: Vec<&str> = stderr
        .lines()
        .filter(|l| l.starts_with("warning: ") && l.contains("above the yield stress"))
        .collect();
    assert_eq!(warnings.len(), 2, "one per output time: {stderr}");
    assert!(
        warnings[1].contains("t = 72000 s") && warnings[1].contains("region weld"),
        "{stderr}"
    );
    // the same warnings as in the summary
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(d.join("results/summary.json")).unwrap())
            .unwrap();
    assert_eq!(summary["warnings"].as_array().map(Vec::len), Some(2));
}

#[test]
fn vessel_options_that_would_be_ignored_are_refused_by_name() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    for (args, says) in [
        (
            &["--seams", "0,120"][..],
            &["--seams 0,120 needs --layers", "--layers 2"][..],
        ),
        (
            &["--layer-thickness", "0.01"],
            &["--layer-thickness 0.01 needs --layers"],
        ),
        // the default value is refused too when typed
        (
            &["--layer-thickness", "6.4e-3"],
            &["--layer-thickness 0.0064 needs --layers"],
        ),
        (
            &["--sync-interval", "5"],
            &[
                "--sync-interval 5 needs --coupling two-way",
                "this run is --coupling one-way",
            ],
        ),
        (
            &["--sync-tolerance", "0.5"],
            &["--sync-tolerance 0.5 needs --coupling two-way"],
        ),
        (
            &["--coupling", "one-way", "--sync-tolerance", "0.5"],
            &["--sync-tolerance 0.5 needs --coupling two-way"],
        ),
        (
            &["--layers", "2", "--sync-interval", "5"],
            &["--sync-interval 5 needs --coupling two-way"],
        ),
    ] {
        let mut all = vec!["vessel", "--mesh", "paper", "--times", "60,72000"];
        all.extend_from_slice(args);
        let o = tecon(d, &all);
        refused(d, &o, says);
    }
}

#[test]
fn vessel_layers_take_their_options_and_the_default_thickness() {
    // --layers N without --layer-thickness keeps the default thickness; with
    // --layer-thickness, --seams and --no-condensation (honoured: see
    // no_condensation_reaches_the_multilayer_solver) the run goes through
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    for (k, args) in [
        &["--layers", "1"][..],
        &[
            "--layers",
            "1",
            "--layer-thickness",
            "6.4e-3",
            "--seams",
            "0",
            "--no-condensation",
        ],
    ]
    .iter()
    .enumerate()
    {
        let out = d.join(format!("layers{k}"));
        let o = std::process::Command::new(env!("CARGO_BIN_EXE_tecon"))
            .args(["vessel", "--times", "60,72000", "--quiet"])
            .args(*args)
            .arg("--out")
            .arg(&out)
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(0), "{args:?}: {stderr}");
        let summary: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap())
                .unwrap();
        assert_eq!(
            summary["geometry"]["layers"][0]["thickness"].as_f64(),
            Some(6.4e-3),
            "{args:?}"
        );
    }
}

#[test]
fn no_condensation_reaches_the_multilayer_solver() {
    // `--no-condensation` with `--layers` sets MultilayerOptions::condensation
    // (multilayer_out::run); the stages then make full Newton passes
    use tecon_cli::multilayer::{MultilayerOptions, analyse};
    let mut o = MultilayerOptions::new(1, 6.4e-3, None).unwrap();
    o.quiet = true;
    o.times = vec![60.0, 72000.0];
    // rows enough that condensing onto the interface dofs is the cheaper
    // pass (m² ≤ nnz of the factor): the solver then condenses unless told not to
    o.spec.core_rows = 40;
    o.spec.layer_rows = 40;
    o.condensation = false;
    let full = analyse(&o).unwrap();
    assert!(full.stages.iter().all(|s| s.condensed_dofs.is_none()));
    o.condensation = true;
    let condensed = analyse(&o).unwrap();
    assert!(
        condensed.stages.iter().all(|s| s.condensed_dofs.is_some()),
        "{:?}",
        condensed
            .stages
            .iter()
            .map(|s| s.condensed_dofs)
            .collect::<Vec<_>>()
    );
    // the same answer either way
    for (a, b) in full.stages.iter().zip(&condensed.stages) {
        for (x, y) in a.ring_means.iter().zip(&b.ring_means) {
            assert!((x - y).abs() <= 1e-6 * x.abs().max(1.0), "{x} {y}");
        }
    }
}

fn msh_file() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../mesh/tests/data/two_blocks.msh")
}

#[test]
fn mesh_refuses_generator_options_with_a_file() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let msh = msh_file();
    let msh = msh.to_str().unwrap();
    let o = tecon(d, &["mesh", "--msh", msh, "--preset", "2"]);
    refused(
        d,
        &o,
        &[
            "--preset 2 cannot be used with --msh",
            "two_blocks.msh",
            "read from the file",
        ],
    );
    let o = tecon(d, &["mesh", "--msh", msh, "--fused-weld"]);
    refused(
        d,
        &o,
        &["--fused-weld cannot be used with --msh", "two_blocks.msh"],
    );
    // the file alone, and the generator's options alone, are fine
    for args in [
        &["mesh", "--msh", msh][..],
        &["mesh", "--preset", "2", "--fused-weld"],
    ] {
        mesh_ran(d, args);
    }
}

/// Runs `tecon mesh` with `args` in `d`, asserts it succeeded, and removes
/// the folder it wrote.
fn mesh_ran(d: &Path, args: &[&str]) {
    let o = tecon(d, args);
    assert_eq!(
        o.status.code(),
        Some(0),
        "{args:?}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    std::fs::remove_dir_all(d.join("results")).unwrap();
}

#[test]
fn mesh_help_lists_every_preset_form() {
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_tecon"))
        .args(["mesh", "--help"])
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(0));
    let help = String::from_utf8_lossy(&o.stdout);
    let preset = help
        .split("--preset")
        .nth(1)
        .and_then(|s| s.split("--fused-weld").next())
        .unwrap_or_default();
    for form in ["`paper`", "0–9", "`gL`", "`xF`", "`tN`", "default `paper`"] {
        assert!(preset.contains(form), "{form} not in: {preset}");
    }
    // and every form the help lists is accepted
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    for p in ["paper", "1", "g0", "x2", "t500"] {
        mesh_ran(d, &["mesh", "--preset", p]);
    }
}

#[test]
fn a_vacuum_inside_explains_the_free_layer() {
    // a negative --pressure pulls the core away from the layer: the layer,
    // held only by the interface, is free; the error says so and what to do
    // (the solver's own advice, a support, cannot be followed here)
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let vessel_on = |mesh: &str, p: &str, extra: &[&str]| {
        let mut args = vec![
            "vessel",
            "--mesh",
            mesh,
            "--times",
            "60,72000",
            "--quiet",
            "--pressure",
            p,
        ];
        args.extend_from_slice(extra);
        tecon(d, &args)
    };
    let vessel = |p: &str, extra: &[&str]| vessel_on("paper", p, extra);
    // (at -1e6 Pa the contact converges with every point open: the layer
    // is held by nothing; at -1e9 Pa its tangent is singular on the way,
    // and since session 39 that says the same instead of only that the
    // system is singular). Level 3 runs its Newton passes condensed onto
    // the interface, where the drifting layer used to end in a
    // contact-status ping-pong.
    for (mesh, p, free) in [
        ("paper", "-1e6", "held by nothing"),
        ("paper", "-1e9", "held by nothing"),
        ("3", "-1e6", "held by nothing"),
    ] {
        let o = vessel_on(mesh, p, &[]);
        refused(
            d,
            &o,
            &[
                "t = 72000 s",
                "body 'layer+weld'",
                free,
                &format!("the negative --pressure {p} Pa"),
                "pulls the core away from the layer",
                "loses all contact and is free",
                "positive (internal) --pressure",
                "--interface bonded",
            ],
        );
    }
    // the advice holds: bonded, the same vacuum runs
    let o = vessel("-1e6", &["--interface", "bonded"]);
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
}
