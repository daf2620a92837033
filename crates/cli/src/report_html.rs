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

/// A leaf of the summary: a number, a list of numbers, or text.
#[derive(Clone, Debug, PartialEq)]
enum Leaf {
    Number(f64),
    Numbers(Vec<f64>),
    Text(String),
}

/// One leaf of the summary: its JSON key (`final.hoop_mean.core_inner`,
/// `times[2].time`), the path as read (an array's object by its name,
/// region or time instead of its index) and the value.
#[derive(Clone, Debug)]
struct KeyRow {
    key: String,
    path: Vec<String>,
    value: Leaf,
}

/// How an object of an array is called in a label: by its `name`,
/// `region`, `ring`, `interface` or `time`; else by its index.
fn element_name(x: &Value, k: usize) -> String {
    for f in ["name", "region", "ring", "interface"] {
        if let Some(n) = x.get(f).and_then(Value::as_str) {
            return n.to_string();
        }
    }
    if let Some(n) = x.get("stage").and_then(Value::as_u64) {
        return format!("stage {n}");
    }
    if let Some(t) = x.get("time").and_then(Value::as_f64) {
        return format!("t = {} s", crate::plot::fmt_value(t));
    }
    format!("[{k}]")
}

/// Leaves of a JSON value as [`KeyRow`]s.
fn flatten(key: &str, path: &[String], v: &Value, out: &mut Vec<KeyRow>) {
    let push = |out: &mut Vec<KeyRow>, value: Leaf| {
        out.push(KeyRow {
            key: key.to_string(),
            path: path.to_vec(),
            value,
        })
    };
    match v {
        Value::Object(m) => {
            for (k, x) in m {
                let p = if key.is_empty() {
                    k.clone()
                } else {
                    format!("{key}.{k}")
                };
                let mut path = path.to_vec();
                path.push(k.clone());
                flatten(&p, &path, x, out);
            }
        }
        Value::Array(a) => {
            if a.iter().all(Value::is_number) {
                push(
                    out,
                    Leaf::Numbers(a.iter().filter_map(Value::as_f64).collect()),
                );
            } else if a.iter().all(Value::is_string) {
                if !a.is_empty() {
                    let t: Vec<&str> = a.iter().filter_map(Value::as_str).collect();
                    push(out, Leaf::Text(t.join("; ")));
                }
            } else {
                for (k, x) in a.iter().enumerate() {
                    let mut path = path.to_vec();
                    path.push(element_name(x, k));
                    flatten(&format!("{key}[{k}]"), &path, x, out);
                }
            }
        }
        Value::Number(n) => push(out, Leaf::Number(n.as_f64().unwrap_or(f64::NAN))),
        Value::String(t) => push(out, Leaf::Text(t.clone())),
        Value::Bool(b) => push(out, Leaf::Text(b.to_string())),
        Value::Null => push(out, Leaf::Text("—".into())),
    }
}

/// The engineering unit of a summary number and its factor from the SI
/// value of `summary.json`: stresses and pressures in MPa, lengths in mm,
/// areas in mm², penalty stiffnesses in N/mm³, temperatures in °C (changes
/// in K), times in s; counts and ratios without a unit.
fn engineering_unit(path: &[String]) -> (&'static str, f64) {
    let leaf = path.last().map_or("", String::as_str);
    let parent = path.len().checked_sub(2).map_or("", |k| path[k].as_str());
    let in_history = path.iter().any(|p| p == "temperature_history");
    const LENGTHS: [&str; 10] = [
        "interference",
        "max_displacement",
        "position",
        "von_mises_max_at",
        "inner_radius",
        "outer_radius",
        "core_thickness",
        "layer_thickness",
        "thickness",
        "weld_half_width",
    ];
    const STRESS_PARENTS: [&str; 5] = [
        "hoop",
        "hoop_mean",
        "hoop_mean_with_prestress",
        "hoop_mean_pressure_only",
        "stress_mean",
    ];
    if leaf.ends_with("_deg") {
        ("°", 1.0)
    } else if leaf == "eta" && parent == "zz_error" {
        // the energy norm per unit thickness
        ("√(J/m)", 1.0)
    } else if leaf == "relative" && parent == "zz_error" {
        ("%", 100.0)
    } else if leaf.ends_with("_s") || ["time", "time_of_max", "output_times"].contains(&leaf) {
        ("s", 1.0)
    } else if ["bound_violation", "max_temperature_change"].contains(&leaf) {
        ("K", 1.0)
    } else if ["temperature_min", "temperature_max"].contains(&leaf)
        || (in_history && ["max", "last"].contains(&leaf))
    {
        ("°C", 1.0)
    } else if leaf.contains("relative") || leaf.contains("rel_error") || leaf.contains("ratio") {
        ("", 1.0)
    } else if leaf == "hoop_force_balance" {
        ("N/m", 1.0)
    } else if ["k_n", "k_s"].contains(&leaf) {
        ("N/mm³", 1e-9)
    } else if ["area", "area_above_yield"].contains(&leaf) {
        ("mm²", 1e6)
    } else if LENGTHS.contains(&leaf) {
        ("mm", 1e3)
    } else if STRESS_PARENTS.contains(&parent)
        || leaf.contains("pressure")
        || leaf.contains("hoop")
        || (leaf.contains("von_mises") && !leaf.ends_with("_element"))
        || ["cohesion", "yield_stress"].contains(&leaf)
    {
        ("MPa", 1e-6)
    } else {
        ("", 1.0)
    }
}

/// A readable name of one key of the summary.
fn readable(segment: &str, in_history: bool) -> String {
    let known = match segment {
        "final" => "after cooling",
        "hoop" | "hoop_mean" => "mean hoop stress σ_θθ",
        "core_inner" => "core, inner surface",
        "core_outer" => "core, outer surface",
        "layer_inner" => "layer, inner surface",
        "layer_outer" => "layer, outer surface",
        "analytical" => "analytical, δ = αΔTw/2π (plane strain)",
        "analytical_variants" => "analytical",
        "plane_strain_consistent" => "plane strain, δ = (1+ν)αΔTw/2π",
        "plane_stress_classical" => "plane stress (classical)",
        "contact_pressure" => "contact pressure",
        "contact_pressure_mean" => "mean contact pressure",
        "contact_pressure_max" => "largest contact pressure",
        "hoop_mean_with_prestress" => "mean hoop stress with the weld prestress",
        "hoop_mean_pressure_only" => "mean hoop stress, pressure alone",
        "pressure" => "internal pressure",
        "zz_error" => "ZZ error estimate",
        "eta" => "η",
        "coupling_delta" => "coupling parameter δ at ambient",
        "coupling_delta_at_weld_temperature" => "coupling parameter δ at the weld temperature",
        "heat_balance_max_rel_error" => "largest relative heat-balance error",
        "heat_balance_rel_error" => "relative heat-balance error",
        "bound_violation" => "temperature outside its physical bounds by",
        "max_temperature_change" => "largest temperature change",
        "hoop_force_balance" => "net hoop force of the half section",
        "hoop_force_balance_relative" => "net hoop force / ∫|σ_θθ| dr",
        "interface_points" => "interface integration points",
        "interface_nodes" => "interface positions",
        "temperature_history" => "temperature history",
        "time_of_max" => "time of the highest temperature",
        "max" if in_history => "highest temperature",
        "last" if in_history => "last temperature",
        "stress_mean" => "mean stress",
        "rr" => "σ_rr",
        "tt" => "σ_θθ",
        "rt" => "σ_rθ",
        "xx" => "σ_xx",
        "yy" => "σ_yy",
        "xy" => "σ_xy",
        "zz" => "σ_zz",
        "von_mises" => "von Mises",
        "eps_zz" => "ε_zz",
        "max_displacement" => "largest displacement",
        "max_von_mises" => "largest von Mises stress",
        "von_mises_max" => "peak von Mises stress",
        "von_mises_max_at" => "peak von Mises stress at (x, y)",
        "von_mises_max_element" => "element of the peak",
        "k_n" => "normal penalty stiffness k_n",
        "k_s" => "shear penalty stiffness k_s",
        "interference" => "interference δ",
        "temperature_min" => "lowest temperature",
        "temperature_max" => "highest temperature",
        "newton" => "Newton",
        "max_iterations_per_increment" => "most iterations in one increment",
        "max_iterations_per_pass" => "most iterations in one pass",
        "max_augmentations_per_increment" => "most outer updates in one increment",
        _ => "",
    };
    if known.is_empty() {
        segment.replace('_', " ")
    } else {
        known.to_string()
    }
}

/// The label of a row: its path in words, ` › ` between the levels.
fn row_label(path: &[String]) -> String {
    let in_history = path.iter().any(|p| p == "temperature_history");
    let words: Vec<String> = path.iter().map(|p| readable(p, in_history)).collect();
    let mut s = words.join(" › ");
    if let Some(c) = s.get(..1) {
        s = c.to_uppercase() + &s[1..];
    }
    s
}

/// A value in engineering units: 6 significant digits, integers as such.
fn engineering_value(v: f64) -> String {
    if v.is_finite() && v == v.trunc() && v.abs() < 1e15 {
        format!("{}", v as i64)
    } else {
        crate::plot::fmt_value(v)
    }
}

/// Top-level keys of the summaries in the order an engineer reads them:
/// the results first, then how they were obtained; other keys after these,
/// in the file's order.
const READING_ORDER: [&str; 9] = [
    "final",
    "operating",
    "times",
    "stages",
    "temperature_history",
    "analytical",
    "analytical_variants",
    "yield_check",
    "thermal",
];

/// The rows of the key-numbers table: (label, value, unit, JSON key).
fn key_numbers(summary: &Value) -> Vec<(String, String, String, String)> {
    let mut rows = Vec::new();
    flatten("", &[], summary, &mut rows);
    rows.retain(|r| !r.key.ends_with("notes") && !r.key.ends_with("warnings"));
    // (a stable sort: within a group the file's order)
    rows.sort_by_key(|r| {
        r.path.first().map_or(READING_ORDER.len(), |k| {
            READING_ORDER
                .iter()
                .position(|g| g == k)
                .unwrap_or(READING_ORDER.len())
        })
    });
    rows.into_iter()
        .map(|r| {
            let (unit, factor) = engineering_unit(&r.path);
            let value = match &r.value {
                Leaf::Number(v) => engineering_value(v * factor),
                Leaf::Numbers(v) if v.len() <= 12 => v
                    .iter()
                    .map(|x| engineering_value(x * factor))
                    .collect::<Vec<_>>()
                    .join(", "),
                Leaf::Numbers(v) => format!(
                    "{} values, {} … {}",
                    v.len(),
                    engineering_value(v[0] * factor),
                    engineering_value(v[v.len() - 1] * factor)
                ),
                Leaf::Text(t) => t.clone(),
            };
            let unit = if matches!(r.value, Leaf::Text(_)) {
                ""
            } else {
                unit
            };
            (row_label(&r.path), value, unit.to_string(), r.key)
        })
        .collect()
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
table.numbers td:first-child{min-width:24em}table.numbers td.text,table.numbers td:nth-child(3),table.numbers td:nth-child(4),table.numbers th{text-align:left}\
.warn{background:#fff3cd;border-left:5px solid #e0a800;padding:.5em 1em;margin:.4em 0}\
.note{background:#eef5ff;border-left:5px solid #4a90d9;padding:.5em 1em;margin:.4em 0}\
figure{margin:1.5em 0;border:1px solid #ddd;padding:.5em;border-radius:4px}figure svg{max-width:100%;height:auto;display:block}\
figcaption{font-weight:600;margin-top:.3em}.muted{color:#666}";

/// The place of a figure in the page: the temperature history first (how
/// the weld cools), the paper's figures by number (fig6 before fig10), then
/// the interface, the mesh study, the probes, torsion's plots and anything
/// else; numbers inside names compare as numbers.
pub fn reading_order(name: &str) -> (usize, Vec<(String, u64)>) {
    const GROUPS: [&str; 6] = [
        "temperature_history",
        "fig",
        "interface",
        "study",
        "probes",
        "boundary",
    ];
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

    // Key numbers, in engineering units (summary.json keeps SI).
    if let Some(s) = &summary {
        h += "<h2 id=\"numbers\">Key numbers</h2>\n<p class=\"muted\">From summary.json, in engineering units (MPa, mm, °C); the file itself keeps SI units (Pa, m), under the keys of the last column.</p>\n<table class=\"numbers\"><thead><tr><th>quantity</th><th>value</th><th>unit</th><th>summary.json key</th></tr></thead><tbody>";
        for (label, value, unit, key) in key_numbers(s) {
            // text (not a number, no unit) reads from the left
            let text = unit.is_empty() && value.parse::<f64>().is_err();
            let _ = write!(
                h,
                "<tr><td>{}</td><td{}>{}</td><td>{}</td><td><code class=\"muted\">{}</code></td></tr>",
                escape(&label),
                if text { " class=\"text\"" } else { "" },
                escape(&value),
                escape(&unit),
                escape(&key)
            );
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
            "temperature_history.svg",
        ];
        v.sort_by_key(|n| reading_order(n));
        assert_eq!(
            v,
            [
                "temperature_history.svg",
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

    /// Goal: the key numbers read in engineering units with readable
    /// labels, whatever summary they come from (vessel, case, multilayer),
    /// results first; the JSON keys stay as they are.
    #[test]
    fn key_numbers_are_in_engineering_units_with_readable_labels() {
        let v: Value = serde_json::from_str(
            r#"{
                "mesh": {"nodes": 108},
                "analytical": {"interference": 1.6811e-5, "hoop": {"core_inner": -1667657.2}},
                "final": {"hoop_mean": {"layer_outer": 4253401.8}, "hoop_force_balance": 21.3,
                          "zz_error": {"eta": 1.04, "relative": 0.0841}, "time": 72000.0},
                "joints": {"j": {"k_n": 1.2e15, "cohesion": 0.0, "law": "frictional"}},
                "times": [{"time": 60.0, "max_displacement": 2.5e-5, "temperature_max": 43.5,
                           "regions": {"core": {"area": 0.0306, "stress_mean": {"tt": -2.1e6}}}}],
                "temperature_history": {"probes": [{"name": "weld_centre", "max": 1132.0, "time_of_max": 0.0}]},
                "geometry": {"inner_radius": 0.762, "layers": [{"seam_angle_deg": 120.0}]},
                "stages": [{"stage": 1, "rings": [{"ring": "core", "mean_hoop_fe": -2.0e6, "relative_error": 2e-4}]}],
                "thermal": {"bound_violation": 3.916, "heat_balance_max_rel_error": 1.2e-12}
            }"#,
        )
        .unwrap();
        let rows = key_numbers(&v);
        let row = |key: &str| {
            rows.iter()
                .find(|r| r.3 == key)
                .map(|r| (r.0.as_str(), r.1.as_str(), r.2.as_str()))
                .unwrap_or_else(|| panic!("no row {key}: {rows:?}"))
        };
        assert_eq!(
            row("final.hoop_mean.layer_outer"),
            (
                "After cooling › mean hoop stress σ_θθ › layer, outer surface",
                "4.2534",
                "MPa"
            )
        );
        assert_eq!(row("analytical.interference").1, "0.016811");
        assert_eq!(row("analytical.interference").2, "mm");
        assert_eq!(row("analytical.hoop.core_inner").1, "-1.66766");
        assert_eq!(row("final.hoop_force_balance").2, "N/m");
        assert_eq!(row("final.zz_error.eta").2, "√(J/m)");
        assert_eq!(
            row("final.zz_error.relative"),
            ("After cooling › ZZ error estimate › relative", "8.41", "%")
        );
        assert_eq!(row("final.time"), ("After cooling › time", "72000", "s"));
        assert_eq!(
            row("joints.j.k_n"),
            (
                "Joints › j › normal penalty stiffness k_n",
                "1200000",
                "N/mm³"
            )
        );
        assert_eq!(row("joints.j.cohesion").2, "MPa");
        assert_eq!(row("joints.j.law"), ("Joints › j › law", "frictional", ""));
        assert_eq!(
            row("times[0].max_displacement"),
            ("Times › t = 60 s › largest displacement", "0.025", "mm")
        );
        assert_eq!(row("times[0].temperature_max").2, "°C");
        assert_eq!(
            row("times[0].regions.core.area"),
            ("Times › t = 60 s › regions › core › area", "30600", "mm²")
        );
        assert_eq!(row("times[0].regions.core.stress_mean.tt").1, "-2.1");
        assert_eq!(
            row("temperature_history.probes[0].max"),
            (
                "Temperature history › probes › weld centre › highest temperature",
                "1132",
                "°C"
            )
        );
        assert_eq!(
            row("geometry.inner_radius"),
            ("Geometry › inner radius", "762", "mm")
        );
        assert_eq!(row("geometry.layers[0].seam_angle_deg").2, "°");
        assert_eq!(
            row("stages[0].rings[0].mean_hoop_fe"),
            (
                "Stages › stage 1 › rings › core › mean hoop fe",
                "-2",
                "MPa"
            )
        );
        assert_eq!(row("stages[0].rings[0].relative_error").2, "");
        assert_eq!(row("thermal.bound_violation").2, "K");
        assert_eq!(row("mesh.nodes"), ("Mesh › nodes", "108", ""));
        // results first: after cooling, then the states, then the analytical model, the mesh last
        let first = |g: &str| rows.iter().position(|r| r.3.starts_with(g)).unwrap();
        assert!(first("final") < first("times") && first("times") < first("analytical"));
        assert!(first("thermal") < first("mesh"));
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
        // in MPa, with a readable label and its summary.json key
        assert!(
            html.contains("<td>After cooling › mean contact pressure</td><td>0.0352405</td><td>MPa</td><td><code class=\"muted\">final.contact_pressure_mean</code></td>"),
            "{html}"
        );
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
