//! `report.html`: one self-contained page per run — the command and inputs,
//! the notes and warnings, the printed report, the key numbers of
//! `summary.json`, the small tables, and every figure of the folder inline
//! as SVG. No scripts, styles or fonts are loaded from anywhere: the page
//! opens offline and can be mailed as one file.
//!
//! The page is built from the output folder after a run, so every command
//! (`tecon vessel`, `tecon run`, `tecon torsion`) gets the same report.

use std::fmt::Write as _;
use std::path::Path;

use serde_json::Value;

/// Name of the page in the output folder.
pub const REPORT: &str = "report.html";

/// Name of the printed report saved beside it (shown in the page when present).
pub const REPORT_TEXT: &str = "report.txt";

/// CSV files with at most this many rows are shown as tables.
pub const TABLE_ROWS: usize = 40;

/// What the page says about the run besides the folder's files.
#[derive(Clone, Debug, Default)]
pub struct ReportInputs {
    /// page title
    pub title: String,
    /// the command line
    pub command: String,
    /// inputs as (name, value), e.g. options and their values
    pub inputs: Vec<(String, String)>,
    /// a source text shown verbatim (e.g. the case file)
    pub source: Option<(String, String)>,
    /// warnings found by the front door (shown first, highlighted)
    pub warnings: Vec<String>,
}

/// Escapes text for HTML.
pub fn escape(s: &str) -> String {
    let mut o = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => o.push_str("&amp;"),
            '<' => o.push_str("&lt;"),
            '>' => o.push_str("&gt;"),
            '"' => o.push_str("&quot;"),
            '\'' => o.push_str("&#39;"),
            _ => o.push(c),
        }
    }
    o
}

/// A number for a table: integers as such, others with 6 significant digits.
fn num(v: f64) -> String {
    if v.is_finite() && v == v.trunc() && v.abs() < 1e15 {
        format!("{}", v as i64)
    } else if v.is_finite() && v != 0.0 && (v.abs() >= 1e6 || v.abs() < 1e-3) {
        format!("{v:.6e}")
    } else {
        let s = format!("{v:.6}");
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s
        }
    }
}

/// Leaves of a JSON value as (path, text), arrays of more than 12 numbers summarised.
fn flatten(prefix: &str, v: &Value, out: &mut Vec<(String, String)>) {
    match v {
        Value::Object(m) => {
            for (k, x) in m {
                let p = if prefix.is_empty() {
                    k.clone()
                } else {
                    format!("{prefix}.{k}")
                };
                flatten(&p, x, out);
            }
        }
        Value::Array(a) => {
            if a.iter().all(Value::is_number) {
                let nums: Vec<f64> = a.iter().filter_map(Value::as_f64).collect();
                let text = if nums.len() <= 12 {
                    nums.iter().map(|&x| num(x)).collect::<Vec<_>>().join(", ")
                } else {
                    format!(
                        "{} values, {} … {}",
                        nums.len(),
                        num(nums[0]),
                        num(nums[nums.len() - 1])
                    )
                };
                out.push((prefix.to_string(), text));
            } else if a.iter().all(Value::is_string) {
                if !a.is_empty() {
                    let t: Vec<&str> = a.iter().filter_map(Value::as_str).collect();
                    out.push((prefix.to_string(), t.join("; ")));
                }
            } else {
                for (k, x) in a.iter().enumerate() {
                    flatten(&format!("{prefix}[{k}]"), x, out);
                }
            }
        }
        Value::Number(n) => out.push((prefix.to_string(), num(n.as_f64().unwrap_or(f64::NAN)))),
        Value::String(s) => out.push((prefix.to_string(), s.clone())),
        Value::Bool(b) => out.push((prefix.to_string(), b.to_string())),
        Value::Null => out.push((prefix.to_string(), "—".into())),
    }
}

/// Strings under keys named `notes` or `warnings` anywhere in the summary.
fn collect_notes(v: &Value, key: &str, out: &mut Vec<String>) {
    match v {
        Value::Object(m) => {
            for (k, x) in m {
                if k == key {
                    match x {
                        Value::Array(a) => {
                            out.extend(a.iter().filter_map(Value::as_str).map(String::from))
                        }
                        Value::String(s) => out.push(s.clone()),
                        _ => {}
                    }
                } else {
                    collect_notes(x, key, out);
                }
            }
        }
        Value::Array(a) => a.iter().for_each(|x| collect_notes(x, key, out)),
        _ => {}
    }
}

/// An SVG file made fit for inlining: from `<svg` on, with an accessible title.
fn inline_svg(text: &str, title: &str) -> Option<String> {
    let start = text.find("<svg")?;
    let body = &text[start..];
    let close = body.find('>')?;
    Some(format!(
        "{}><title>{}</title>{}",
        &body[..close],
        escape(title),
        &body[close + 1..]
    ))
}

/// A small CSV as an HTML table (quoted fields are read as such).
fn csv_table(text: &str) -> Option<String> {
    let parse = |line: &str| -> Vec<String> {
        let mut fields = Vec::new();
        let mut cur = String::new();
        let mut quoted = false;
        let mut chars = line.chars().peekable();
        while let Some(c) = chars.next() {
            match (c, quoted) {
                ('"', true) if chars.peek() == Some(&'"') => {
                    cur.push('"');
                    chars.next();
                }
                ('"', _) => quoted = !quoted,
                (',', false) => fields.push(std::mem::take(&mut cur)),
                _ => cur.push(c),
            }
        }
        fields.push(cur);
        fields
    };
    let mut lines = text.lines().filter(|l| !l.trim().is_empty());
    let header = parse(lines.next()?);
    let mut t = String::from("<table><thead><tr>");
    for h in &header {
        let _ = write!(t, "<th>{}</th>", escape(h));
    }
    t += "</tr></thead><tbody>";
    for l in lines {
        t += "<tr>";
        for f in parse(l) {
            let shown = f.parse::<f64>().map(num).unwrap_or(f);
            let _ = write!(t, "<td>{}</td>", escape(&shown));
        }
        t += "</tr>";
    }
    t += "</tbody></table>";
    Some(t)
}

const STYLE: &str = "body{font-family:system-ui,-apple-system,'Segoe UI',Roboto,'DejaVu Sans',sans-serif;margin:2em auto;max-width:1400px;padding:0 1.5em;color:#222;line-height:1.4}\
h1{font-size:1.6em;margin-bottom:.2em}h2{border-bottom:2px solid #ddd;padding-bottom:.2em;margin-top:2em}\
code,pre{font-family:'DejaVu Sans Mono',Menlo,Consolas,monospace;font-size:.9em}\
pre{background:#f6f6f6;padding:.8em;overflow-x:auto;white-space:pre-wrap;border-radius:4px}\
table{border-collapse:collapse;margin:.5em 0;font-size:.9em}td,th{border:1px solid #ccc;padding:.25em .6em;text-align:right}\
th{background:#f0f0f0}td:first-child,th:first-child{text-align:left}table.inputs td{text-align:left}\
.warn{background:#fff3cd;border-left:5px solid #e0a800;padding:.5em 1em;margin:.4em 0}\
.note{background:#eef5ff;border-left:5px solid #4a90d9;padding:.5em 1em;margin:.4em 0}\
figure{margin:1.5em 0;border:1px solid #ddd;padding:.5em;border-radius:4px}figure svg{max-width:100%;height:auto;display:block}\
figcaption{font-weight:600;margin-top:.3em}.muted{color:#666}";

/// The place of a figure in the page: the paper's figures by number
/// (fig6 before fig10), then the interface, the mesh study, the probes,
/// torsion's plots and anything else; numbers inside names compare as numbers.
pub fn reading_order(name: &str) -> (usize, Vec<(String, u64)>) {
    const GROUPS: [&str; 5] = ["fig", "interface", "study", "probes", "boundary"];
    let group = GROUPS
        .iter()
        .position(|g| name.starts_with(g))
        .unwrap_or(GROUPS.len());
    // alternating text and number pieces
    let mut key = Vec::new();
    let mut text = String::new();
    let mut digits = String::new();
    for ch in name.chars() {
        if ch.is_ascii_digit() {
            digits.push(ch);
        } else {
            if !digits.is_empty() {
                key.push((
                    std::mem::take(&mut text),
                    digits.parse().unwrap_or(u64::MAX),
                ));
                digits.clear();
            }
            text.push(ch);
        }
    }
    key.push((text, digits.parse().unwrap_or(0)));
    (group, key)
}

/// Builds the page for the output folder `dir`.
pub fn build(dir: &Path, r: &ReportInputs) -> std::io::Result<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)?
        .filter_map(|e| e.ok())
        .filter(|e| e.file_type().is_ok_and(|t| t.is_file()))
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    let summary: Option<Value> = std::fs::read_to_string(dir.join("summary.json"))
        .ok()
        .and_then(|t| serde_json::from_str(&t).ok());
    let mut h = String::new();
    let _ = write!(
        h,
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\
<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\
<meta http-equiv=\"Content-Security-Policy\" content=\"default-src 'none'; style-src 'unsafe-inline'; img-src data:\">\
<title>{}</title><style>{STYLE}</style></head><body>\n",
        escape(&r.title)
    );
    let _ = writeln!(
        h,
        "<h1>{}</h1><p class=\"muted\">tecon {} · <code>{}</code></p>",
        escape(&r.title),
        env!("CARGO_PKG_VERSION"),
        escape(&r.command)
    );

    // Warnings and notes first.
    let mut warnings = r.warnings.clone();
    let mut notes = Vec::new();
    if let Some(s) = &summary {
        collect_notes(s, "warnings", &mut warnings);
        collect_notes(s, "notes", &mut notes);
    }
    // the run's own warnings are in its summary too: each once, in order
    let mut seen = std::collections::HashSet::new();
    warnings.retain(|w| seen.insert(w.clone()));
    let mut seen = std::collections::HashSet::new();
    notes.retain(|n| seen.insert(n.clone()));
    h += "<h2 id=\"warnings\">Warnings and notes</h2>\n";
    if warnings.is_empty() && notes.is_empty() {
        h += "<p>None.</p>\n";
    }
    for w in &warnings {
        let _ = writeln!(h, "<div class=\"warn\">⚠ {}</div>", escape(w));
    }
    for n in &notes {
        let _ = writeln!(h, "<div class=\"note\">{}</div>", escape(n));
    }

    // Inputs.
    h += "<h2 id=\"inputs\">Inputs</h2>\n";
    if !r.inputs.is_empty() {
        h += "<table class=\"inputs\"><tbody>";
        for (k, v) in &r.inputs {
            let _ = write!(h, "<tr><td>{}</td><td>{}</td></tr>", escape(k), escape(v));
        }
        h += "</tbody></table>\n";
    }
    if let Some((name, text)) = &r.source {
        let _ = writeln!(
            h,
            "<p><code>{}</code>:</p><pre>{}</pre>",
            escape(name),
            escape(text)
        );
    }

    // The printed report.
    if let Ok(text) = std::fs::read_to_string(dir.join(REPORT_TEXT)) {
        let _ = writeln!(
            h,
            "<h2 id=\"report\">Report</h2><pre>{}</pre>",
            escape(&text)
        );
    }

    // Figures, in reading order.
    let mut svgs: Vec<&String> = names.iter().filter(|n| n.ends_with(".svg")).collect();
    svgs.sort_by_key(|n| reading_order(n));
    if !svgs.is_empty() {
        h += "<h2 id=\"figures\">Figures</h2>\n";
    }
    for n in &svgs {
        let stem = n.trim_end_matches(".svg");
        if let Some(svg) = std::fs::read_to_string(dir.join(n))
            .ok()
            .and_then(|t| inline_svg(&t, stem))
        {
            let _ = writeln!(
                h,
                "<figure id=\"fig-{0}\" class=\"figure\">{svg}<figcaption>{0} <span class=\"muted\">({0}.svg, {0}.png{1})</span></figcaption></figure>",
                escape(stem),
                if names.contains(&format!("{stem}.csv")) {
                    format!(", data {}.csv", escape(stem))
                } else {
                    String::new()
                }
            );
        }
    }

    // Key numbers.
    if let Some(s) = &summary {
        let mut rows = Vec::new();
        flatten("", s, &mut rows);
        rows.retain(|(k, _)| !k.ends_with("notes") && !k.ends_with("warnings"));
        h += "<h2 id=\"numbers\">Key numbers (summary.json, SI units)</h2>\n<table><thead><tr><th>key</th><th>value</th></tr></thead><tbody>";
        for (k, v) in rows {
            let _ = write!(h, "<tr><td>{}</td><td>{}</td></tr>", escape(&k), escape(&v));
        }
        h += "</tbody></table>\n";
    }

    // Small tables.
    let mut tables = String::new();
    for n in names.iter().filter(|n| n.ends_with(".csv")) {
        let Ok(text) = std::fs::read_to_string(dir.join(n)) else {
            continue;
        };
        let rows = text.lines().count().saturating_sub(1);
        if rows <= TABLE_ROWS
            && let Some(t) = csv_table(&text)
        {
            let _ = writeln!(tables, "<h3>{}</h3>{t}", escape(n));
        }
    }
    if !tables.is_empty() {
        h += "<h2 id=\"tables\">Tables</h2>\n";
        h += &tables;
    }

    // Files.
    h += "<h2 id=\"files\">Files in this folder</h2>\n<ul>";
    for n in &names {
        let detail = if n.ends_with(".csv") {
            std::fs::read_to_string(dir.join(n))
                .map(|t| format!(" ({} rows)", t.lines().count().saturating_sub(1)))
                .unwrap_or_default()
        } else {
            String::new()
        };
        let _ = write!(h, "<li><code>{}</code>{detail}</li>", escape(n));
    }
    if !names.iter().any(|n| n == REPORT) {
        let _ = write!(h, "<li><code>{REPORT}</code> (this page)</li>");
    }
    h += "</ul>\n";
    if names.iter().any(|n| n.ends_with(".pvd")) {
        h += "<p>3-D view: open the <code>.pvd</code> file in ParaView, then apply <em>Warp By Vector</em> on <code>displacement_m</code> (scale factor about 1000) and colour by <code>von_mises_Pa</code> or <code>temperature_C</code>.</p>\n";
    }
    h += "</body></html>\n";
    Ok(h)
}

/// Builds the page and writes it as `dir/report.html`.
pub fn write(dir: &Path, r: &ReportInputs) -> std::io::Result<std::path::PathBuf> {
    let html = build(dir, r)?;
    let p = dir.join(REPORT);
    std::fs::write(&p, html)?;
    Ok(p)
}

#[cfg(test)]
mod tests {
    //! Goal: the page holds every figure inline, the notes, and nothing remote.
    use super::*;

    #[test]
    fn figures_come_in_reading_order() {
        let mut v = vec![
            "study_mesh.svg",
            "interface_slip.svg",
            "fig11_hoop_fe_vs_analytical.svg",
            "probes_temperature.svg",
            "fig6_temperature_circumference.svg",
            "fig10_tangential_displacement.svg",
            "interface_contact_pressure.svg",
            "fig7_temperature_through_wall.svg",
        ];
        v.sort_by_key(|n| reading_order(n));
        assert_eq!(
            v,
            [
                "fig6_temperature_circumference.svg",
                "fig7_temperature_through_wall.svg",
                "fig10_tangential_displacement.svg",
                "fig11_hoop_fe_vs_analytical.svg",
                "interface_contact_pressure.svg",
                "interface_slip.svg",
                "study_mesh.svg",
                "probes_temperature.svg",
            ]
        );
    }

    #[test]
    fn the_page_is_self_contained_with_figures_numbers_and_warnings() {
        let d = tempfile::tempdir().unwrap();
        std::fs::write(
            d.path().join("summary.json"),
            r#"{"final":{"contact_pressure_mean":35240.5},"notes":["a <note>"],"warnings":["above yield"],"times":[1,10]}"#,
        )
        .unwrap();
        std::fs::write(
            d.path().join("fig.svg"),
            "<?xml version=\"1.0\"?>\n<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"10\" height=\"10\"><rect width=\"5\" height=\"5\"/></svg>",
        )
        .unwrap();
        std::fs::write(d.path().join("fig.csv"), "\"a, b\",c\n1,2.5\n").unwrap();
        let html = build(
            d.path(),
            &ReportInputs {
                title: "T".into(),
                command: "tecon vessel".into(),
                warnings: vec!["above yield".into()],
                ..Default::default()
            },
        )
        .unwrap();
        assert!(html.contains("<svg xmlns") && !html.contains("<?xml"));
        assert!(html.contains("<title>fig</title>"));
        assert!(html.contains("a &lt;note&gt;") && html.contains("above yield"));
        // a warning both passed in and in the summary is shown once
        assert_eq!(html.matches("⚠ above yield").count(), 1);
        assert!(html.contains("35240.5"));
        assert!(
            html.contains("<th>a, b</th>"),
            "quoted CSV header read as one field"
        );
        assert!(
            !html.contains("http://")
                || html.matches("http://").count()
                    == html.matches("xmlns=\"http://www.w3.org/2000/svg\"").count(),
            "no links but the SVG namespace"
        );
        assert!(!html.contains("<script src") && !html.contains("<link"));
    }
}
