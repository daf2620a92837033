//! Built-in sections, the `--section` specification syntax and section files.
//!
//! ```text
//! circle:r=R   ellipse:a=A,b=B   rectangle:w=W,h=H   triangle:a=A
//! polygon:x1,y1;x2,y2;...   regular:n=N,r=R   groove:a=A,b=B   limacon:a=A,c=C
//! ```
//! A file (TOML) holds either `vertices = [[x, y], ...]` or a list of pieces:
//! ```toml
//! [[piece]]
//! kind = "segment"
//! from = [0.0, 0.0]
//! to = [1.0, 0.0]
//! [[piece]]
//! kind = "arc"            # centre, radius, start/end angle in degrees (ccw if end > start)
//! center = [0.0, 0.0]
//! radius = 1.0
//! start_deg = 0.0
//! end_deg = 90.0
//! ```

use crate::error::{GeometryError, SpecError};
use crate::geometry::{Piece, Section, V2};
use std::f64::consts::{PI, TAU};

/// Circle of radius `r` centred at the origin (one closed arc).
pub fn circle(r: f64) -> Result<Section, GeometryError> {
    Section::new(
        format!("circle r={r}"),
        vec![Piece::Arc {
            center: [0.0, 0.0],
            radius: r,
            theta0: 0.0,
            theta1: TAU,
        }],
    )
}

/// Ellipse with semi-axes `a` (x) and `b` (y), centred at the origin.
pub fn ellipse(a: f64, b: f64) -> Result<Section, GeometryError> {
    Section::new(
        format!("ellipse a={a} b={b}"),
        vec![Piece::Ellipse {
            center: [0.0, 0.0],
            a,
            b,
            rotation: 0.0,
            t0: 0.0,
            t1: TAU,
        }],
    )
}

/// Polygon through `vertices` (either orientation), one segment per side.
pub fn polygon(vertices: &[V2]) -> Result<Section, GeometryError> {
    if vertices.len() < 3 {
        return Err(GeometryError::TooFewVertices(vertices.len()));
    }
    let m = vertices.len();
    let pieces = (0..m)
        .map(|k| Piece::Segment {
            a: vertices[k],
            b: vertices[(k + 1) % m],
        })
        .collect();
    Section::new(format!("polygon ({m} vertices)"), pieces)
}

/// Rectangle of width `w` (x) and height `h` (y) centred at the origin.
pub fn rectangle(w: f64, h: f64) -> Result<Section, GeometryError> {
    let (a, b) = (0.5 * w, 0.5 * h);
    let mut s = polygon(&[[-a, -b], [a, -b], [a, b], [-a, b]])?;
    s.name = format!("rectangle w={w} h={h}");
    Ok(s)
}

/// Equilateral triangle of side `a`, centroid at the origin, one side horizontal at the bottom.
pub fn triangle(a: f64) -> Result<Section, GeometryError> {
    let h = a * 3f64.sqrt() / 2.0;
    let mut s = polygon(&[
        [-0.5 * a, -h / 3.0],
        [0.5 * a, -h / 3.0],
        [0.0, 2.0 * h / 3.0],
    ])?;
    s.name = format!("triangle a={a}");
    Ok(s)
}

/// Regular polygon with `n` sides and circumradius `r`, centred at the origin.
pub fn regular_polygon(n: usize, r: f64) -> Result<Section, GeometryError> {
    let v: Vec<V2> = (0..n)
        .map(|k| {
            let th = -PI / 2.0 + PI / n as f64 + TAU * k as f64 / n as f64;
            [r * th.cos(), r * th.sin()]
        })
        .collect();
    let mut s = polygon(&v)?;
    s.name = format!("regular polygon n={n} r={r}");
    Ok(s)
}

/// Grooved shaft: the disc of radius `a` centred at (a, 0) minus the disc of
/// radius `b` < 2a centred at the origin (a semicircular-type groove).
pub fn groove(a: f64, b: f64) -> Result<Section, GeometryError> {
    if !(a > 0.0 && b > 0.0 && b < 2.0 * a) {
        return Err(GeometryError::InvalidParameter { piece: 0 });
    }
    let xp = b * b / (2.0 * a);
    let yp = (b * b - xp * xp).sqrt();
    let th = yp.atan2(xp - a); // angle of the upper meeting point about (a, 0)
    let beta = yp.atan2(xp); // same point about the origin
    Section::new(
        format!("groove a={a} b={b}"),
        vec![
            Piece::Arc {
                center: [a, 0.0],
                radius: a,
                theta0: -th,
                theta1: th,
            },
            Piece::Arc {
                center: [0.0, 0.0],
                radius: b,
                theta0: beta,
                theta1: -beta,
            },
        ],
    )
}

/// Limaçon z = A(e^{iθ} + c e^{2iθ}), 0 ≤ c ≤ ½ (c = ½: cardioid with an inward cusp at θ = π).
pub fn limacon(a: f64, c: f64) -> Result<Section, GeometryError> {
    Section::new(
        format!("limacon A={a} c={c}"),
        vec![Piece::Limacon {
            scale: a,
            c,
            shift: [0.0, 0.0],
            theta0: PI,
            reversed: false,
        }],
    )
}

fn bad(kind: &str, field: &str, value: &str, reason: &str) -> SpecError {
    SpecError::BadValue {
        kind: kind.into(),
        field: field.into(),
        value: value.into(),
        reason: reason.into(),
    }
}

fn parse_num(kind: &str, field: &str, value: &str) -> Result<f64, SpecError> {
    let v: f64 = value
        .trim()
        .parse()
        .map_err(|_| bad(kind, field, value, "not a number"))?;
    if !v.is_finite() {
        return Err(bad(kind, field, value, "not finite"));
    }
    Ok(v)
}

fn positive(kind: &str, field: &str, value: &str) -> Result<f64, SpecError> {
    let v = parse_num(kind, field, value)?;
    if v <= 0.0 {
        return Err(bad(kind, field, value, "must be positive"));
    }
    Ok(v)
}

/// key=value list → lookup closure
fn fields(kind: &str, body: &str, allowed: &[&str]) -> Result<Vec<(String, String)>, SpecError> {
    let mut out = Vec::new();
    for part in body.split(',').filter(|p| !p.trim().is_empty()) {
        let (k, v) = part
            .split_once('=')
            .ok_or_else(|| bad(kind, part.trim(), part, "expected key=value"))?;
        let k = k.trim().to_string();
        if !allowed.contains(&k.as_str()) {
            return Err(bad(
                kind,
                &k,
                v,
                &format!("unknown field (expected {})", allowed.join(", ")),
            ));
        }
        out.push((k, v.trim().to_string()));
    }
    Ok(out)
}

fn get<'a>(kind: &str, f: &'a [(String, String)], key: &str) -> Result<&'a str, SpecError> {
    f.iter()
        .find(|(k, _)| k == key)
        .map(|(_, v)| v.as_str())
        .ok_or_else(|| SpecError::MissingField {
            kind: kind.into(),
            field: key.into(),
        })
}

/// Parses a `--section` specification (see the module docs) or reads a section file.
pub fn parse_spec(spec: &str) -> Result<Section, SpecError> {
    let path = std::path::Path::new(spec);
    if path.is_file() {
        return read_section_file(path);
    }
    let (kind, body) = spec
        .split_once(':')
        .ok_or_else(|| SpecError::UnknownKind(spec.to_string()))?;
    let kind = kind.trim();
    match kind {
        "circle" => {
            let f = fields(kind, body, &["r"])?;
            Ok(circle(positive(kind, "r", get(kind, &f, "r")?)?)?)
        }
        "ellipse" => {
            let f = fields(kind, body, &["a", "b"])?;
            Ok(ellipse(
                positive(kind, "a", get(kind, &f, "a")?)?,
                positive(kind, "b", get(kind, &f, "b")?)?,
            )?)
        }
        "rectangle" => {
            let f = fields(kind, body, &["w", "h"])?;
            Ok(rectangle(
                positive(kind, "w", get(kind, &f, "w")?)?,
                positive(kind, "h", get(kind, &f, "h")?)?,
            )?)
        }
        "triangle" => {
            let f = fields(kind, body, &["a"])?;
            Ok(triangle(positive(kind, "a", get(kind, &f, "a")?)?)?)
        }
        "regular" => {
            let f = fields(kind, body, &["n", "r"])?;
            let ns = get(kind, &f, "n")?;
            let n: usize = ns
                .parse()
                .map_err(|_| bad(kind, "n", ns, "not an integer"))?;
            if n < 3 {
                return Err(bad(kind, "n", ns, "need at least 3 sides"));
            }
            Ok(regular_polygon(
                n,
                positive(kind, "r", get(kind, &f, "r")?)?,
            )?)
        }
        "groove" => {
            let f = fields(kind, body, &["a", "b"])?;
            let a = positive(kind, "a", get(kind, &f, "a")?)?;
            let bs = get(kind, &f, "b")?;
            let b = positive(kind, "b", bs)?;
            if b >= 2.0 * a {
                return Err(bad(kind, "b", bs, "groove radius must be < 2a"));
            }
            Ok(groove(a, b)?)
        }
        "limacon" => {
            let f = fields(kind, body, &["a", "c"])?;
            let a = positive(kind, "a", get(kind, &f, "a")?)?;
            let cs = get(kind, &f, "c")?;
            let c = parse_num(kind, "c", cs)?;
            if !(0.0..=0.5).contains(&c) {
                return Err(bad(kind, "c", cs, "must lie in [0, 0.5]"));
            }
            Ok(limacon(a, c)?)
        }
        "polygon" => {
            let mut v = Vec::new();
            for (i, pair) in body.split(';').filter(|p| !p.trim().is_empty()).enumerate() {
                let field = format!("vertex {}", i + 1);
                let (x, y) = pair
                    .split_once(',')
                    .ok_or_else(|| bad(kind, &field, pair, "expected x,y"))?;
                v.push([parse_num(kind, &field, x)?, parse_num(kind, &field, y)?]);
            }
            if v.len() < 3 {
                return Err(bad(kind, "vertices", body, "need at least 3 vertices"));
            }
            Ok(polygon(&v)?)
        }
        _ => Err(SpecError::UnknownKind(kind.to_string())),
    }
}

#[derive(serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct FilePiece {
    kind: String,
    from: Option<[f64; 2]>,
    to: Option<[f64; 2]>,
    center: Option<[f64; 2]>,
    radius: Option<f64>,
    start_deg: Option<f64>,
    end_deg: Option<f64>,
}

#[derive(serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct SectionFile {
    name: Option<String>,
    vertices: Option<Vec<[f64; 2]>>,
    piece: Option<Vec<FilePiece>>,
}

/// Reads a TOML section file (polygon vertices or a chain of segments and arcs).
pub fn read_section_file(path: &std::path::Path) -> Result<Section, SpecError> {
    let p = path.display().to_string();
    let text = std::fs::read_to_string(path).map_err(|e| SpecError::Io {
        path: p.clone(),
        source: e,
    })?;
    parse_section_toml(&text, &p)
}

/// Parses the text of a section file; `origin` names it in errors.
pub fn parse_section_toml(text: &str, origin: &str) -> Result<Section, SpecError> {
    let file: SectionFile = toml::from_str(text).map_err(|e| SpecError::Toml {
        path: origin.into(),
        message: e.message().replace('\n', " ") + &span_hint(text, e.span()),
    })?;
    let kind = format!("file {origin}");
    let mut sec = match (file.vertices, file.piece) {
        (Some(v), None) => polygon(&v)?,
        (None, Some(pieces)) => {
            let mut out = Vec::with_capacity(pieces.len());
            for (i, fp) in pieces.iter().enumerate() {
                let need = |o: Option<[f64; 2]>, f: &str| {
                    o.ok_or_else(|| SpecError::MissingField {
                        kind: kind.clone(),
                        field: format!("piece[{i}].{f}"),
                    })
                };
                let needf = |o: Option<f64>, f: &str| {
                    o.ok_or_else(|| SpecError::MissingField {
                        kind: kind.clone(),
                        field: format!("piece[{i}].{f}"),
                    })
                };
                match fp.kind.as_str() {
                    "segment" => out.push(Piece::Segment {
                        a: need(fp.from, "from")?,
                        b: need(fp.to, "to")?,
                    }),
                    "arc" => {
                        let r = needf(fp.radius, "radius")?;
                        if r.is_nan() || r <= 0.0 {
                            return Err(bad(
                                &kind,
                                &format!("piece[{i}].radius"),
                                &r.to_string(),
                                "must be positive",
                            ));
                        }
                        out.push(Piece::Arc {
                            center: need(fp.center, "center")?,
                            radius: r,
                            theta0: needf(fp.start_deg, "start_deg")?.to_radians(),
                            theta1: needf(fp.end_deg, "end_deg")?.to_radians(),
                        })
                    }
                    other => {
                        return Err(bad(
                            &kind,
                            &format!("piece[{i}].kind"),
                            other,
                            "expected \"segment\" or \"arc\"",
                        ));
                    }
                }
            }
            Section::new(origin.to_string(), out)?
        }
        (Some(_), Some(_)) => {
            return Err(bad(
                &kind,
                "vertices",
                "",
                "give either `vertices` or `[[piece]]`, not both",
            ));
        }
        (None, None) => {
            return Err(SpecError::MissingField {
                kind,
                field: "vertices or [[piece]]".into(),
            });
        }
    };
    if let Some(n) = file.name {
        sec.name = n;
    }
    Ok(sec)
}

fn span_hint(text: &str, span: Option<std::ops::Range<usize>>) -> String {
    match span {
        Some(r) => {
            let line = text[..r.start.min(text.len())].matches('\n').count() + 1;
            format!(" (line {line})")
        }
        None => String::new(),
    }
}
