//! Built-in sections, the `--section` specification syntax and section files.
//!
//! ```text
//! circle:r=R   ellipse:a=A,b=B   rectangle:w=W,h=H   triangle:a=A
//! polygon:x1,y1;x2,y2;...   regular:n=N,r=R   groove:a=A,b=B   limacon:a=A,c=C
//! tube:ro=RO,ri=RI   box:w=W,h=H,t=T  (or box:w=W,h=H,tf=TF,tw=TW)
//! ```
//! Each key at most once. A file may add holes as `[[hole]]` tables, each
//! with `vertices` or its own `[[hole.piece]]` list.
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
//! and `kind = "ellipse"`: `center`, semi-axes `a` and `b`, optional
//! `rotation_deg` of the a axis, and the parameter angles `start_deg`,
//! `end_deg` of x = c + R (a cos t, b sin t).

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

/// Consecutive vertices closer than this fraction of the perimeter are merged
/// (the change of J is of the order of the square of the gap, far below any
/// tolerance; resolving a 1e-9 edge between two graded corners is not possible
/// at any affordable n).
pub const MERGE_FRACTION: f64 = 1e-7;

/// Merged vertex pairs named one by one in the notes; the rest are counted.
pub const MERGE_NOTES: usize = 5;

/// A vertex that lies between its neighbours and closer than this fraction
/// of the perimeter to the line through them is dropped: the sides on
/// either side of it are one straight side (a digitised outline often
/// carries such points). The area changes by less than this fraction times
/// the side's length, per vertex. Kept, such a vertex would be a "corner"
/// with graded nodes on both sides: a square given by 2000 points along
/// its sides asked for n ≥ 65 536 and came out flagged with J 3e-3 off.
pub const COLLINEAR_FRACTION: f64 = 1e-12;

/// Drops the vertices of the closed polygon `v` that lie between their
/// neighbours within `cut` of the line through them (see
/// [`COLLINEAR_FRACTION`]); returns how many. One pass with a stack (a run of
/// such vertices goes in linear time), then the vertices next to the
/// closing side. A polygon that would keep fewer than three is left as
/// given (its validation names the degeneracy).
fn drop_collinear(v: &mut Vec<V2>, cut: f64) -> usize {
    let on_line = |a: V2, p: V2, b: V2| {
        let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
        let len = dx.hypot(dy);
        let off = ((p[0] - a[0]) * dy - (p[1] - a[1]) * dx).abs() / len;
        let between = (p[0] - a[0]) * dx + (p[1] - a[1]) * dy > 0.0
            && (b[0] - p[0]) * dx + (b[1] - p[1]) * dy > 0.0;
        len > 0.0 && off < cut && between
    };
    let before = v.len();
    let mut out: Vec<V2> = Vec::with_capacity(before);
    for &p in v.iter() {
        while out.len() >= 2 && on_line(out[out.len() - 2], out[out.len() - 1], p) {
            out.pop();
        }
        out.push(p);
    }
    while out.len() > 3 {
        let m = out.len();
        if on_line(out[m - 2], out[m - 1], out[0]) {
            out.pop();
        } else if on_line(out[m - 1], out[0], out[1]) {
            out.remove(0);
        } else {
            break;
        }
    }
    if out.len() < 3 {
        // all on one line: left as given, for the validation to name
        return 0;
    }
    *v = out;
    before - v.len()
}

/// Polygon through `vertices` (either orientation), one segment per side.
/// Consecutive vertices closer than [`MERGE_FRACTION`] of the perimeter are
/// merged, and vertices on the straight line through their neighbours
/// dropped (see [`COLLINEAR_FRACTION`]), with a note.
pub fn polygon(vertices: &[V2]) -> Result<Section, GeometryError> {
    if vertices.len() < 3 {
        return Err(GeometryError::TooFewVertices(vertices.len()));
    }
    crate::memory::check_vertices(vertices.len(), crate::memory::available_bytes())?;
    let dist = |a: V2, b: V2| (a[0] - b[0]).hypot(a[1] - b[1]);
    let m0 = vertices.len();
    let perimeter: f64 = (0..m0)
        .map(|k| dist(vertices[k], vertices[(k + 1) % m0]))
        .sum();
    let cut = MERGE_FRACTION * perimeter;
    let mut kept: Vec<(usize, V2)> = Vec::with_capacity(m0);
    let mut notes = Vec::new();
    // a repeated vertex (a side of length 0) is merged too: outlines
    // exported from CAD or GIS tools often repeat the first vertex at the end
    let merged = |j: usize, k: usize, d: f64| {
        if d == 0.0 {
            format!("vertex {} repeats vertex {}: merged", k + 1, j + 1)
        } else {
            format!(
                "vertices {} and {} are {d:.1e} apart (< {MERGE_FRACTION:.0e} of the perimeter): merged",
                j + 1,
                k + 1
            )
        }
    };
    // the first few merges are named, the rest counted (a finely
    // digitised outline can merge millions of vertices)
    let mut merges = 0usize;
    let mut note_merge = |notes: &mut Vec<String>, j: usize, k: usize, d: f64| {
        if merges < MERGE_NOTES {
            notes.push(merged(j, k, d));
        }
        merges += 1;
    };
    for (k, &v) in vertices.iter().enumerate() {
        if let Some(&(j, last)) = kept.last() {
            let d = dist(last, v);
            if d < cut {
                note_merge(&mut notes, j, k, d);
                continue;
            }
        }
        kept.push((k, v));
    }
    while kept.len() >= 3 {
        let (j, last) = kept[kept.len() - 1];
        let d = dist(last, kept[0].1);
        if d < cut {
            note_merge(&mut notes, kept[0].0, j, d);
            kept.pop();
        } else {
            break;
        }
    }
    if merges > MERGE_NOTES {
        notes.push(format!(
            "{} more vertex pairs closer than {MERGE_FRACTION:.0e} of the perimeter merged ({merges} in all)",
            merges - MERGE_NOTES
        ));
    }
    if kept.len() < 3 {
        return Err(GeometryError::TooThin {
            given: m0,
            left: kept.len(),
            fraction: MERGE_FRACTION,
        });
    }
    let mut v: Vec<V2> = kept.into_iter().map(|(_, v)| v).collect();
    let dropped = drop_collinear(&mut v, COLLINEAR_FRACTION * perimeter);
    if dropped > 0 {
        notes.push(format!(
            "{dropped} vertices on the straight line through their neighbours (within {COLLINEAR_FRACTION:.0e} of the perimeter) dropped: their sides are one side"
        ));
    }
    if v.len() < 3 {
        return Err(GeometryError::TooFewVertices(v.len()));
    }
    let m = v.len();
    let pieces = (0..m)
        .map(|k| Piece::Segment {
            a: v[k],
            b: v[(k + 1) % m],
        })
        .collect();
    let mut sec = Section::new(format!("polygon ({m} vertices)"), pieces)?;
    sec.notes.extend(notes);
    Ok(sec)
}

/// Circular tube: outer radius `ro`, inner radius `ri` < `ro`, concentric at the origin.
pub fn tube(ro: f64, ri: f64) -> Result<Section, GeometryError> {
    if !(ri > 0.0 && ri < ro) {
        return Err(GeometryError::InvalidParameter { piece: 0 });
    }
    let mut s = Section::with_holes(circle(ro)?, vec![circle(ri)?])?;
    s.name = format!("tube ro={ro} ri={ri}");
    Ok(s)
}

/// Rectangular box (hollow rectangle) of outer width `w` (x) and height `h`
/// (y), centred at the origin, flanges (top and bottom walls) `tf` thick and
/// webs (side walls) `tw` thick.
pub fn hollow_rectangle(w: f64, h: f64, tf: f64, tw: f64) -> Result<Section, GeometryError> {
    if !(tf > 0.0 && tw > 0.0 && 2.0 * tw < w && 2.0 * tf < h) {
        return Err(GeometryError::InvalidParameter { piece: 0 });
    }
    let mut s = Section::with_holes(
        rectangle(w, h)?,
        vec![rectangle(w - 2.0 * tw, h - 2.0 * tf)?],
    )?;
    s.name = format!("box w={w} h={h} tf={tf} tw={tw}");
    Ok(s)
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
    // refused before its vertex list is built
    crate::memory::check_vertices(n, crate::memory::available_bytes())?;
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

/// A geometry error of the inside of a tube or a box (its one hole, which
/// the user did not give as a hole) as a bad value of the wall field
/// `field`: "hole[0]" would name nothing the user wrote.
fn inside_error(kind: &str, field: &str, value: &str, e: GeometryError) -> SpecError {
    let why = match e {
        GeometryError::HoleTouchesBoundary { near, .. } => format!(
            "the wall is too thin for double precision at this size: the inside touches the outside near ({:.6}, {:.6})",
            near[0], near[1]
        ),
        GeometryError::HoleOutside { .. } | GeometryError::HolesOverlap { .. } => {
            "the inside does not lie within the outside".to_string()
        }
        e => format!("the inside is not a valid section: {e}"),
    };
    bad(kind, field, value, &why)
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
        if out.iter().any(|(o, _): &(String, String)| *o == k) {
            return Err(bad(kind, &k, v, "given twice"));
        }
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
    let looks_like_path = spec.ends_with(".toml")
        || (!spec.contains(':')
            && (spec.contains('/') || spec.contains('\\') || spec.contains('.')));
    if looks_like_path {
        return Err(SpecError::NoSuchFile(spec.to_string()));
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
        "tube" => {
            let f = fields(kind, body, &["ro", "ri"])?;
            let ro = positive(kind, "ro", get(kind, &f, "ro")?)?;
            let ris = get(kind, &f, "ri")?;
            let ri = positive(kind, "ri", ris)?;
            if ri >= ro {
                return Err(bad(kind, "ri", ris, "the inner radius must be < ro"));
            }
            circle(ro)?;
            tube(ro, ri).map_err(|e| inside_error(kind, "ri", ris, e))
        }
        "box" => {
            let f = fields(kind, body, &["w", "h", "t", "tf", "tw"])?;
            let w = positive(kind, "w", get(kind, &f, "w")?)?;
            let h = positive(kind, "h", get(kind, &f, "h")?)?;
            let t = match get(kind, &f, "t") {
                Ok(v) => Some(positive(kind, "t", v)?),
                Err(_) => None,
            };
            let one = |key: &str| -> Result<f64, SpecError> {
                match get(kind, &f, key) {
                    Ok(v) => {
                        if t.is_some() {
                            return Err(bad(kind, key, v, "give either t or tf and tw"));
                        }
                        positive(kind, key, v)
                    }
                    Err(e) => t.ok_or(e),
                }
            };
            let (tf, tw) = (one("tf")?, one("tw")?);
            // name the field that was given: `t` when all walls are one
            let given = |key: &'static str| if t.is_some() { "t" } else { key };
            if 2.0 * tw >= w {
                return Err(bad(
                    kind,
                    given("tw"),
                    &tw.to_string(),
                    "the webs fill the width (2 tw ≥ w)",
                ));
            }
            if 2.0 * tf >= h {
                return Err(bad(
                    kind,
                    given("tf"),
                    &tf.to_string(),
                    "the flanges fill the height (2 tf ≥ h)",
                ));
            }
            // the outside's errors are those of a rectangle; the rest are
            // the inside's (the box's one hole), named by the thinner wall
            rectangle(w, h)?;
            let field = match t {
                Some(_) => "t",
                None if 1.0 - 2.0 * tw / w < 1.0 - 2.0 * tf / h => "tw",
                None => "tf",
            };
            let value = get(kind, &f, field)?;
            hollow_rectangle(w, h, tf, tw).map_err(|e| inside_error(kind, field, value, e))
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
    a: Option<f64>,
    b: Option<f64>,
    rotation_deg: Option<f64>,
}

#[derive(serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct SectionFile {
    name: Option<String>,
    vertices: Option<Vec<[f64; 2]>>,
    piece: Option<Vec<FilePiece>>,
    hole: Option<Vec<HoleFile>>,
}

#[derive(serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct HoleFile {
    vertices: Option<Vec<[f64; 2]>>,
    piece: Option<Vec<FilePiece>>,
}

/// Reads a TOML section file (polygon vertices or a chain of segments and
/// arcs, with optional `[[hole]]` chains).
pub fn read_section_file(path: &std::path::Path) -> Result<Section, SpecError> {
    let p = path.display().to_string();
    let text = std::fs::read_to_string(path).map_err(|e| SpecError::Io {
        path: p.clone(),
        source: e,
    })?;
    parse_section_toml(&text, &p)
}

/// One closed chain from `vertices` or `[[piece]]` of the section file
/// `origin`; `at` names it in errors ("" for the outer boundary, "hole[k]."
/// for a hole); `kind` prefixes the field errors.
fn chain(
    kind: &str,
    at: &str,
    origin: &str,
    vertices: Option<Vec<[f64; 2]>>,
    pieces: Option<Vec<FilePiece>>,
) -> Result<Section, SpecError> {
    // geometry errors name the file and the curve ("hole[2]: boundary is
    // self-intersecting near …")
    let geo = |e: GeometryError| -> SpecError {
        SpecError::FileGeometry {
            path: origin.into(),
            at: match at.strip_suffix('.') {
                Some(hole) => format!("{hole}: "),
                None => String::new(),
            },
            error: e,
        }
    };
    match (vertices, pieces) {
        (Some(v), None) => polygon(&v).map_err(geo),
        (None, Some(pieces)) => {
            let mut out = Vec::with_capacity(pieces.len());
            for (i, fp) in pieces.iter().enumerate() {
                let need = |o: Option<[f64; 2]>, f: &str| {
                    o.ok_or_else(|| SpecError::MissingField {
                        kind: kind.into(),
                        field: format!("{at}piece[{i}].{f}"),
                    })
                };
                let needf = |o: Option<f64>, f: &str| {
                    o.ok_or_else(|| SpecError::MissingField {
                        kind: kind.into(),
                        field: format!("{at}piece[{i}].{f}"),
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
                                kind,
                                &format!("{at}piece[{i}].radius"),
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
                    "ellipse" => {
                        let positive = |v: f64, f: &str| {
                            if v.is_finite() && v > 0.0 {
                                Ok(v)
                            } else {
                                Err(bad(
                                    kind,
                                    &format!("{at}piece[{i}].{f}"),
                                    &v.to_string(),
                                    "must be a positive length",
                                ))
                            }
                        };
                        out.push(Piece::Ellipse {
                            center: need(fp.center, "center")?,
                            a: positive(needf(fp.a, "a")?, "a")?,
                            b: positive(needf(fp.b, "b")?, "b")?,
                            rotation: fp.rotation_deg.unwrap_or(0.0).to_radians(),
                            t0: needf(fp.start_deg, "start_deg")?.to_radians(),
                            t1: needf(fp.end_deg, "end_deg")?.to_radians(),
                        })
                    }
                    other => {
                        return Err(bad(
                            kind,
                            &format!("{at}piece[{i}].kind"),
                            other,
                            "expected \"segment\", \"arc\" or \"ellipse\"",
                        ));
                    }
                }
            }
            Section::new(origin.to_string(), out).map_err(geo)
        }
        (Some(_), Some(_)) => Err(bad(
            kind,
            &format!("{at}vertices"),
            "",
            "give either `vertices` or `[[piece]]`, not both",
        )),
        (None, None) => Err(SpecError::MissingField {
            kind: kind.into(),
            field: format!("{at}vertices or {at}[[piece]]"),
        }),
    }
}

/// Parses the text of a section file; `origin` names it in errors.
pub fn parse_section_toml(text: &str, origin: &str) -> Result<Section, SpecError> {
    let file: SectionFile = toml::from_str(text).map_err(|e| SpecError::Toml {
        path: origin.into(),
        message: e.message().replace('\n', " ") + &span_hint(text, e.span()),
    })?;
    let kind = format!("section file `{origin}`");
    let mut sec = chain(&kind, "", origin, file.vertices, file.piece)?;
    if let Some(holes) = file.hole {
        let hs = holes
            .into_iter()
            .enumerate()
            .map(|(k, h)| chain(&kind, &format!("hole[{k}]."), origin, h.vertices, h.piece))
            .collect::<Result<Vec<_>, _>>()?;
        // the placement errors name the holes as hole[k] themselves
        sec = Section::with_holes(sec, hs).map_err(|e| SpecError::FileGeometry {
            path: origin.into(),
            at: String::new(),
            error: e,
        })?;
    }
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
