//! The `tecon` binary's output folders and pipes, as a user meets them:
//! a closed pipe ends the program quietly, bad `--times` and unusable output
//! folders are refused before any computation, a rerun owns its folder (no
//! stale files, a manifest), and every run writes a self-contained
//! `report.html` with its figures inline.
//!
//! All runs use the published vessel on the paper mesh (136 triangles,
//! about 0.1 s).

use std::io::{BufRead, BufReader};
use std::path::Path;
use std::process::{Command, Stdio};

fn tecon() -> Command {
    Command::new(env!("CARGO_BIN_EXE_tecon"))
}

fn vessel(out: &Path, extra: &[&str]) -> std::process::Output {
    tecon()
        .args(["vessel", "--mesh", "paper", "--quiet", "--out"])
        .arg(out)
        .args(extra)
        .output()
        .unwrap()
}

#[test]
fn a_closed_pipe_ends_tecon_mesh_quietly() {
    let d = tempfile::tempdir().unwrap();
    let mut child = tecon()
        .args(["mesh", "--preset", "3", "--out"])
        .arg(d.path().join("m"))
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // read one line, then close the pipe as `head -1` does
    let mut first = String::new();
    BufReader::new(child.stdout.take().unwrap())
        .read_line(&mut first)
        .unwrap();
    let out = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(first.starts_with("mesh: "), "{first}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert!(
        matches!(out.status.code(), Some(0) | Some(141)),
        "{:?} {stderr}",
        out.status
    );
}

#[test]
fn times_out_of_order_are_refused_before_computing() {
    let d = tempfile::tempdir().unwrap();
    let out = d.path().join("v");
    let o = vessel(&out, &["--times", "600,10,60"]);
    assert_eq!(o.status.code(), Some(2));
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(e.contains("--times") && e.contains("increasing"), "{e}");
    assert!(!out.exists(), "nothing written");
}

#[test]
fn unusable_output_folders_are_refused_before_computing() {
    let d = tempfile::tempdir().unwrap();
    // a file where the folder should be
    let file = d.path().join("plain");
    std::fs::write(&file, "x").unwrap();
    let o = vessel(&file, &[]);
    assert_eq!(o.status.code(), Some(2));
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(e.contains("plain") && e.contains("not a folder"), "{e}");
    // a folder of someone else's files
    let mine = d.path().join("thesis");
    std::fs::create_dir(&mine).unwrap();
    std::fs::write(mine.join("chapter1.tex"), "text").unwrap();
    let o = vessel(&mine, &[]);
    assert_eq!(o.status.code(), Some(2));
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(e.contains("chapter1.tex") && e.contains("--force"), "{e}");
    let o = vessel(&mine, &["--force", "--times", "1"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(mine.join("chapter1.tex").exists() && mine.join("summary.json").exists());
}

#[test]
fn a_rerun_owns_its_folder_and_leaves_no_stale_files() {
    let d = tempfile::tempdir().unwrap();
    let out = d.path().join("v");
    let o = vessel(&out, &["--times", "1,60,600"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(out.join("vessel_002.vtu").exists());
    let o = vessel(&out, &["--times", "1"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(out.join("vessel_000.vtu").exists());
    assert!(
        !out.join("vessel_001.vtu").exists() && !out.join("vessel_002.vtu").exists(),
        "stale VTU files of the longer run removed"
    );
    let manifest = std::fs::read_to_string(out.join("tecon-manifest.json")).unwrap();
    let m: serde_json::Value = serde_json::from_str(&manifest).unwrap();
    let files: Vec<&str> = m["files"]
        .as_array()
        .unwrap()
        .iter()
        .filter_map(|f| f.as_str())
        .collect();
    assert!(files.contains(&"summary.json") && files.contains(&"report.html"));
    assert!(!files.contains(&"vessel_001.vtu"));
    // every file in the folder is in the manifest
    for e in std::fs::read_dir(&out).unwrap() {
        let name = e.unwrap().file_name().to_string_lossy().into_owned();
        assert!(
            name == "tecon-manifest.json" || files.contains(&name.as_str()),
            "{name} not in the manifest"
        );
    }
}

/// A Chromium binary, if one is installed.
fn chromium() -> Option<String> {
    [
        "chromium",
        "chromium-browser",
        "google-chrome",
        "google-chrome-stable",
    ]
    .into_iter()
    .find(|b| {
        Command::new(b)
            .arg("--version")
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .status()
            .is_ok_and(|s| s.success())
    })
    .map(String::from)
}

#[test]
fn report_html_is_self_contained_and_renders_its_figures_in_chromium() {
    let d = tempfile::tempdir().unwrap();
    let out = d.path().join("v");
    let o = vessel(&out, &["--times", "1,60,72000"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let page = out.join("report.html");
    let html = std::fs::read_to_string(&page).unwrap();
    let svgs = std::fs::read_dir(&out)
        .unwrap()
        .filter(|e| {
            e.as_ref()
                .unwrap()
                .file_name()
                .to_string_lossy()
                .ends_with(".svg")
        })
        .count();
    assert!(svgs >= 6, "{svgs} figures");
    assert_eq!(html.matches("<figure").count(), svgs, "every figure inline");
    // nothing fetched: no scripts, style sheets, images or fonts by address
    for bad in ["<script", "<link", "src=\"http", "url(", "@import", "<img"] {
        assert!(!html.contains(bad), "report.html holds {bad}");
    }
    let Some(browser) = chromium() else {
        eprintln!(
            "SKIPPED: report_html renders in Chromium — no chromium binary on this machine \
             (.ci/run installs the Debian package `chromium`)"
        );
        return;
    };
    // Render it headless with the network off; dump the DOM after layout.
    let profile = d.path().join("profile");
    let o = Command::new(&browser)
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--no-first-run",
            "--proxy-server=127.0.0.1:9",
            "--proxy-bypass-list=<-loopback>",
            "--virtual-time-budget=5000",
            "--dump-dom",
        ])
        .arg(format!("--user-data-dir={}", profile.display()))
        .arg(format!("file://{}", page.display()))
        .output()
        .unwrap();
    let dom = String::from_utf8_lossy(&o.stdout);
    assert!(
        o.status.success(),
        "chromium failed: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    assert!(dom.contains("tecon vessel"), "page title shown");
    assert_eq!(
        dom.matches("<svg").count(),
        svgs,
        "every figure in the rendered page"
    );
    assert!(dom.contains("Warnings and notes") && dom.contains("Key numbers"));
    // and a screenshot with the figures drawn: not a blank page
    let shot = d.path().join("shot.png");
    let o = Command::new(&browser)
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--no-first-run",
            "--proxy-server=127.0.0.1:9",
            "--window-size=1400,2400",
        ])
        .arg(format!("--user-data-dir={}", profile.display()))
        .arg(format!("--screenshot={}", shot.display()))
        .arg(format!("file://{}", page.display()))
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let png = std::fs::read(&shot).unwrap();
    assert!(png.starts_with(b"\x89PNG"), "a PNG screenshot");
    assert!(
        png.len() > 50_000,
        "a page with figures, not a blank one ({} bytes)",
        png.len()
    );
}

/// `tecon vessel --mesh paper --quiet` with `extra` on `threads` threads
/// into `out`: summary.json as bytes. The child is killed, and the test
/// fails, after five minutes (a thread pool waiting on itself).
fn paper_summary_on(threads: &str, out: &Path, extra: &[&str]) -> Vec<u8> {
    let err = out.with_extension("stderr");
    let mut child = tecon()
        .env("RAYON_NUM_THREADS", threads)
        .args(["vessel", "--mesh", "paper", "--quiet", "--out"])
        .arg(out)
        .args(extra)
        .stdout(std::process::Stdio::null())
        // to a file, not a pipe: an unread pipe that fills would stop the
        // child and look like the hang the deadline is there to catch
        .stderr(std::fs::File::create(&err).unwrap())
        .spawn()
        .unwrap();
    let deadline = std::time::Instant::now() + std::time::Duration::from_secs(300);
    let status = loop {
        if let Some(status) = child.try_wait().unwrap() {
            break status;
        }
        if std::time::Instant::now() > deadline {
            child.kill().unwrap();
            panic!("tecon vessel {extra:?} on {threads} thread(s) did not finish in 300 s");
        }
        std::thread::sleep(std::time::Duration::from_millis(50));
    };
    assert!(
        status.success(),
        "{extra:?} on {threads} thread(s): {}",
        std::fs::read_to_string(&err).unwrap_or_default()
    );
    std::fs::read(out.join("summary.json")).unwrap()
}

#[test]
fn summary_json_is_bitwise_the_same_on_one_and_two_threads_and_timings_go_apart() {
    let d = tempfile::tempdir().unwrap();
    let mut texts = Vec::new();
    for threads in ["1", "2"] {
        let out = d.path().join(format!("t{threads}"));
        texts.push(paper_summary_on(threads, &out, &["--times", "1,600,72000"]));
        let timing: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(out.join("timing.json")).unwrap())
                .unwrap();
        assert!(timing["seconds"].as_f64().unwrap() > 0.0);
    }
    assert!(!String::from_utf8_lossy(&texts[0]).contains("\"seconds"));
    assert!(
        texts[0] == texts[1],
        "summary.json differs between 1 and 2 threads"
    );
}

/// The two-way loop runs on a worker of the thread pool: with a pool of
/// one worker it must neither wait on itself nor change a bit of the
/// results.
#[test]
fn two_way_summary_is_bitwise_the_same_on_one_and_two_threads() {
    let d = tempfile::tempdir().unwrap();
    let extra = [
        "--coupling",
        "two-way",
        "--conductance",
        "contact",
        "--times",
        "1,60",
    ];
    let texts: Vec<Vec<u8>> = ["1", "2"]
        .iter()
        .map(|t| paper_summary_on(t, &d.path().join(format!("t{t}")), &extra))
        .collect();
    assert!(String::from_utf8_lossy(&texts[0]).contains("\"two-way\""));
    assert!(
        texts[0] == texts[1],
        "summary.json differs between 1 and 2 threads"
    );
}

#[test]
fn the_yield_check_names_the_regions_above_yield_and_the_peak() {
    let d = tempfile::tempdir().unwrap();
    let out = d.path().join("y");
    let o = vessel(&out, &["--times", "1,72000", "--yield", "250e6"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    // --quiet: nothing on stdout, the warnings on stderr, the report in report.txt
    assert!(
        o.stdout.is_empty(),
        "{}",
        String::from_utf8_lossy(&o.stdout)
    );
    assert!(String::from_utf8_lossy(&o.stderr).contains("warning: after cooling"));
    let text = std::fs::read_to_string(out.join("report.txt")).unwrap();
    assert!(
        text.contains("region weld: peak von Mises") && text.contains("EXCEEDED"),
        "{text}"
    );
    assert!(text.contains("warning: after cooling"), "{text}");
    // the weld's peak sits at a weld corner, a stress singularity: said so,
    // with the angle of each peak beside the corner's
    assert!(
        text.contains("within one element of a weld corner") && text.contains("weld (θ = "),
        "{text}"
    );
    let html = std::fs::read_to_string(out.join("report.html")).unwrap();
    assert!(html.contains("class=\"warn\"") && html.contains("above the yield stress"));
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    let weld = s["yield_check"]["after cooling (t = 72000 s)"]
        .as_array()
        .unwrap()
        .iter()
        .find(|r| r["region"] == "weld")
        .unwrap();
    assert!(weld["von_mises_max"].as_f64().unwrap() > 250e6);
    // without --yield: the peak and where, no warning
    let o = vessel(&d.path().join("n"), &["--times", "1,72000"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = std::fs::read_to_string(d.path().join("n/report.txt")).unwrap();
    assert!(
        text.contains("no yield stress given") && !text.contains("warning:"),
        "{text}"
    );
    // --pressure results in the printed report
    let o = vessel(
        &d.path().join("p"),
        &["--times", "1,72000", "--pressure", "5e6"],
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = std::fs::read_to_string(d.path().join("p/report.txt")).unwrap();
    assert!(
        text.contains("operating pressure 5 MPa") && text.contains("pressure alone"),
        "{text}"
    );
}

/// The report's input table shows the model as run: defaults by value (mesh
/// size and order, the joint law with μ and cohesion, materials, output
/// times), never an option left unset ("None").
#[test]
fn report_html_lists_the_resolved_inputs() {
    let d = tempfile::tempdir().unwrap();
    let out = d.path().join("v");
    let o = vessel(&out, &["--times", "1,72000"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let html = std::fs::read_to_string(out.join("report.html")).unwrap();
    let start = html
        .find("<table class=\"inputs\">")
        .expect("an input table");
    let table = &html[start..start + html[start..].find("</table>").unwrap()];
    for want in [
        "paper (136 triangles, order 1)",
        "frictional: μ = 0.3, cohesion 0 Pa",
        "E = 207 GPa",
        "constant 850 W/(m² K)",
        "one-way",
        "1 s, 72000 s",
    ] {
        assert!(table.contains(want), "input table lacks {want:?}: {table}");
    }
    assert!(!table.contains("None"), "an unset option shown: {table}");
    // a bonded run names its joint, and rejects nothing it should show
    let out = d.path().join("b");
    let o = vessel(&out, &["--times", "1,72000", "--interface", "bonded"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let html = std::fs::read_to_string(out.join("report.html")).unwrap();
    assert!(html.contains("bonded (tied nodes)"));
}

/// Other commands' input tables list the options given a value, shown as a
/// user writes them: no unset options ("None"), no Rust syntax ("Some(",
/// quotes); the torsion report's numbers are on the page (report.txt).
#[test]
fn torsion_report_lists_its_options_as_written() {
    let d = tempfile::tempdir().unwrap();
    let out = d.path().join("t");
    let o = tecon()
        .args(["torsion", "--section", "ellipse:a=1,b=0.5", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let html = std::fs::read_to_string(out.join("report.html")).unwrap();
    let start = html
        .find("<table class=\"inputs\">")
        .expect("an input table");
    let table = &html[start..start + html[start..].find("</table>").unwrap()];
    assert!(
        table.contains("<td>section</td><td>ellipse:a=1,b=0.5</td>"),
        "{table}"
    );
    assert!(table.contains(&format!("<td>out</td><td>{}</td>", out.display())));
    for bad in ["None", "Some(", "&quot;"] {
        assert!(!table.contains(bad), "{bad} in {table}");
    }
    // the printed report is the page's report and report.txt
    let printed = String::from_utf8_lossy(&o.stdout);
    let txt = std::fs::read_to_string(out.join("report.txt")).unwrap();
    assert!(txt.contains("torsional rigidity J = "), "{txt}");
    assert!(printed.starts_with(&txt[..txt.find("wrote").unwrap()]));
    let report = &html[html.find("id=\"report\"").expect("a report section")..];
    assert!(report.contains("torsional rigidity J = "));
}
