//! Shared plotting helpers (plotters): line plots of labelled series and
//! paths coloured by a value, each written as both SVG and PNG.
//!
//! ```ignore
//! let p = LinePlot {
//!     title: "Boundary shear stress".into(),
//!     x_label: "arc length s [m]".into(),
//!     y_label: "τ / (Gθ) [m]".into(),
//!     series: vec![Series { label: "τ".into(), points: vec![(0.0, 0.0), (1.0, 1.0)] }],
//! };
//! let (svg, png) = p.write_svg_png(std::path::Path::new("out/tau"))?;
//! ```
//!
//! PNG text needs a font: the bundled DejaVu Sans is registered once as
//! `sans-serif` (SVG output refers to the family by name and needs none).

use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::{Path, PathBuf};
use std::sync::Once;

/// Errors of the plotting helpers.
#[derive(Debug, thiserror::Error)]
pub enum PlotError {
    /// Drawing or encoding failed.
    #[error("plotting `{path}` failed: {message}")]
    Draw {
        /// target file
        path: String,
        /// backend message
        message: String,
    },
    /// Nothing to draw.
    #[error("plot `{0}` has no finite data")]
    Empty(String),
}

static FONT: Once = Once::new();

/// Registers the bundled DejaVu Sans as `sans-serif` (idempotent).
pub fn register_bundled_font() {
    FONT.call_once(|| {
        let bytes: &'static [u8] = include_bytes!("../assets/DejaVuSans.ttf");
        // a failure leaves PNG text unrendered but must not abort the program
        let _ = plotters::style::register_font("sans-serif", FontStyle::Normal, bytes);
    });
}

/// One labelled series of (x, y) points.
#[derive(Clone, Debug)]
pub struct Series {
    /// legend label
    pub label: String,
    /// points in drawing order
    pub points: Vec<(f64, f64)>,
}

/// A line plot of several labelled series (axis labels should carry units).
#[derive(Clone, Debug)]
pub struct LinePlot {
    /// title
    pub title: String,
    /// x-axis label with unit
    pub x_label: String,
    /// y-axis label with unit
    pub y_label: String,
    /// the series
    pub series: Vec<Series>,
}

/// A planar path whose segments are coloured by a scalar (e.g. a section boundary coloured by |q|).
#[derive(Clone, Debug)]
pub struct ColouredPath {
    /// title
    pub title: String,
    /// label of the colour scale, with unit
    pub value_label: String,
    /// (x, y, value) in drawing order; the path is closed when `closed`
    pub points: Vec<(f64, f64, f64)>,
    /// join the last point to the first
    pub closed: bool,
    /// further paths (e.g. the holes of a section), each closed, drawn on
    /// the same axes with the same colour scale as `points`; empty for one
    pub more_closed: Vec<Vec<(f64, f64, f64)>>,
}

/// Ten distinguishable colours (one per time or per quantity).
pub const PALETTE: [RGBColor; 10] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(255, 127, 14),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
    RGBColor(188, 189, 34),
    RGBColor(23, 190, 207),
];

fn err(path: &Path, e: impl std::fmt::Display) -> PlotError {
    PlotError::Draw {
        path: path.display().to_string(),
        message: e.to_string(),
    }
}

/// A tick label without a trailing ".0" or floating-point noise:
/// `2.0 → "2"`, `0.30000000000000004 → "0.3"`, `-0.0 → "0"`, `2.5e-7 → "2.5e-7"`.
pub fn fmt_tick(v: f64) -> String {
    if !v.is_finite() {
        return v.to_string();
    }
    let a = v.abs();
    if a == 0.0 || a < 1e-12 {
        return "0".into();
    }
    let trim = |s: String| -> String {
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s
        }
    };
    if !(1e-4..1e7).contains(&a) {
        // mantissa with at most 4 significant digits
        let s = format!("{v:.3e}");
        let (m, e) = s.split_once('e').unwrap_or((&s, "0"));
        return format!("{}e{}", trim(m.to_string()), e);
    }
    // six significant digits, then trimmed
    let decimals = (5 - a.log10().floor() as i32).clamp(0, 12) as usize;
    let s = trim(format!("{v:.decimals$}"));
    if s == "-0" { "0".into() } else { s }
}

/// A tick label of a logarithmic axis: the value at the tick rounded to two
/// significant digits (`0.00251189 → "0.0025"`, `0.0158489 → "0.016"`).
pub fn fmt_log_tick(v: f64) -> String {
    if !(v.is_finite() && v > 0.0) {
        return fmt_tick(v);
    }
    let scale = 10f64.powi(v.log10().floor() as i32 - 1);
    fmt_tick((v / scale).round() * scale)
}

/// A value for a legend or a title: like [`fmt_tick`] (`1 s`, `600 s`, `0.02 s`).
pub fn fmt_value(v: f64) -> String {
    fmt_tick(v)
}

/// Axis scale.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Scale {
    /// Linear.
    #[default]
    Linear,
    /// Base-10 logarithmic (non-positive values are left out).
    Log,
}

/// One axis of a panel.
#[derive(Clone, Debug, Default)]
pub struct Axis {
    /// label with unit
    pub label: String,
    /// linear or logarithmic
    pub scale: Scale,
    /// fixed range (data outside is clipped at the frame); `None`: fit the data
    pub range: Option<(f64, f64)>,
}

impl Axis {
    /// A linear axis fitted to the data.
    pub fn linear(label: impl Into<String>) -> Self {
        Axis {
            label: label.into(),
            ..Default::default()
        }
    }
    /// A logarithmic axis fitted to the data.
    pub fn log(label: impl Into<String>) -> Self {
        Axis {
            label: label.into(),
            scale: Scale::Log,
            range: None,
        }
    }
    /// The same axis with a fixed range.
    pub fn range(mut self, lo: f64, hi: f64) -> Self {
        self.range = Some((lo, hi));
        self
    }
}

/// One line of a panel.
#[derive(Clone, Debug, Default)]
pub struct Line {
    /// legend label (empty: not in the legend)
    pub label: String,
    /// points in drawing order (a non-finite point breaks the line)
    pub points: Vec<(f64, f64)>,
    /// index into [`PALETTE`]
    pub colour: usize,
    /// dashed instead of solid
    pub dashed: bool,
    /// a marker at every point
    pub markers: bool,
    /// no connecting line (markers only)
    pub no_line: bool,
}

impl Line {
    /// A solid line.
    pub fn solid(label: impl Into<String>, colour: usize, points: Vec<(f64, f64)>) -> Self {
        Line {
            label: label.into(),
            points,
            colour,
            ..Default::default()
        }
    }
    /// A dashed line.
    pub fn dashed(label: impl Into<String>, colour: usize, points: Vec<(f64, f64)>) -> Self {
        Line {
            dashed: true,
            ..Line::solid(label, colour, points)
        }
    }
    /// The same line with a marker at every point.
    pub fn with_markers(mut self) -> Self {
        self.markers = true;
        self
    }
    /// Markers only.
    pub fn points_only(mut self) -> Self {
        self.markers = true;
        self.no_line = true;
        self
    }
}

/// A value outside the frame, marked at the frame's edge with a label.
#[derive(Clone, Debug)]
pub struct OffScale {
    /// x of the value
    pub x: f64,
    /// the value (above or below the frame)
    pub y: f64,
    /// text beside the mark
    pub label: String,
}

/// Where the legend goes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum LegendAt {
    /// upper right corner (default)
    #[default]
    UpperRight,
    /// upper left corner
    UpperLeft,
    /// lower right corner
    LowerRight,
    /// lower left corner
    LowerLeft,
    /// no legend
    None,
}

/// One panel: axes, lines and marks.
#[derive(Clone, Debug, Default)]
pub struct Panel {
    /// panel title
    pub title: String,
    /// x axis
    pub x: Axis,
    /// y axis
    pub y: Axis,
    /// the lines
    pub lines: Vec<Line>,
    /// values outside the frame, marked at its edge
    pub off_scale: Vec<OffScale>,
    /// text lines written inside the frame (upper left)
    pub notes: Vec<String>,
    /// legend position
    pub legend: LegendAt,
}

/// A figure of one or more panels side by side.
#[derive(Clone, Debug)]
pub struct Figure {
    /// figure title
    pub title: String,
    /// panels, left to right
    pub panels: Vec<Panel>,
    /// size in pixels
    pub size: (u32, u32),
}

fn to_scale(v: f64, s: Scale) -> f64 {
    match s {
        Scale::Linear => v,
        Scale::Log => {
            if v > 0.0 {
                v.log10()
            } else {
                f64::NAN
            }
        }
    }
}

/// Drawing range of one axis (in scaled coordinates) from the data or the fixed range.
fn axis_range(axis: &Axis, values: impl Iterator<Item = f64>) -> Option<(f64, f64)> {
    if let Some((a, b)) = axis.range {
        let (a, b) = (to_scale(a, axis.scale), to_scale(b, axis.scale));
        if a.is_finite() && b.is_finite() && b > a {
            return Some((a, b));
        }
    }
    let mut r: Option<(f64, f64)> = None;
    for v in values
        .map(|v| to_scale(v, axis.scale))
        .filter(|v| v.is_finite())
    {
        r = Some(match r {
            None => (v, v),
            Some((a, b)) => (a.min(v), b.max(v)),
        });
    }
    r.map(|(a, b)| {
        let pad = if b > a {
            0.04 * (b - a)
        } else {
            0.5 * a.abs().max(1.0)
        };
        (a - pad, b + pad)
    })
}

/// Liang–Barsky: the part of segment p→q inside the box, if any.
fn clip_segment(
    p: (f64, f64),
    q: (f64, f64),
    (x0, x1): (f64, f64),
    (y0, y1): (f64, f64),
) -> Option<((f64, f64), (f64, f64))> {
    let (dx, dy) = (q.0 - p.0, q.1 - p.1);
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    for (pk, qk) in [
        (-dx, p.0 - x0),
        (dx, x1 - p.0),
        (-dy, p.1 - y0),
        (dy, y1 - p.1),
    ] {
        if pk == 0.0 {
            if qk < 0.0 {
                return None;
            }
        } else {
            let r = qk / pk;
            if pk < 0.0 {
                t0 = t0.max(r);
            } else {
                t1 = t1.min(r);
            }
        }
    }
    (t0 <= t1).then_some((
        (p.0 + t0 * dx, p.1 + t0 * dy),
        (p.0 + t1 * dx, p.1 + t1 * dy),
    ))
}

/// A polyline cut into the pieces that lie inside the box (non-finite points break it).
pub fn clip_polyline(
    points: &[(f64, f64)],
    xr: (f64, f64),
    yr: (f64, f64),
) -> Vec<Vec<(f64, f64)>> {
    let mut out: Vec<Vec<(f64, f64)>> = Vec::new();
    let mut cur: Vec<(f64, f64)> = Vec::new();
    let finite = |p: &(f64, f64)| p.0.is_finite() && p.1.is_finite();
    let inside = |p: (f64, f64)| p.0 >= xr.0 && p.0 <= xr.1 && p.1 >= yr.0 && p.1 <= yr.1;
    if points.len() == 1 && finite(&points[0]) && inside(points[0]) {
        return vec![points.to_vec()];
    }
    for w in points.windows(2) {
        if !(finite(&w[0]) && finite(&w[1])) {
            if cur.len() > 1 {
                out.push(std::mem::take(&mut cur));
            }
            cur.clear();
            continue;
        }
        match clip_segment(w[0], w[1], xr, yr) {
            Some((a, b)) => {
                if cur.last() != Some(&a) {
                    if cur.len() > 1 {
                        out.push(std::mem::take(&mut cur));
                    }
                    cur = vec![a];
                }
                cur.push(b);
            }
            None => {
                if cur.len() > 1 {
                    out.push(std::mem::take(&mut cur));
                }
                cur.clear();
            }
        }
    }
    if cur.len() > 1 {
        out.push(cur);
    }
    out
}

/// Legend entry of a line: solid or dashed, with a dot when it has markers.
fn label_series<'a, DB: DrawingBackend + 'a>(
    anno: &mut plotters::chart::SeriesAnno<'a, DB>,
    l: &Line,
    c: RGBColor,
) {
    let style = c.stroke_width(2);
    let gap = if l.dashed { 4 } else { 0 };
    let dot = if l.markers {
        c.filled()
    } else {
        c.mix(0.0).filled()
    };
    anno.label(l.label.clone()).legend(move |(x, y)| {
        EmptyElement::at((x, y))
            + PathElement::new(vec![(0, 0), (7, 0)], style)
            + PathElement::new(vec![(7 + gap, 0), (18, 0)], style)
            + Circle::new((9, 0), 3, dot)
    });
}

impl Panel {
    fn draw<DB: DrawingBackend>(
        &self,
        area: &DrawingArea<DB, Shift>,
        path: &Path,
    ) -> Result<(), PlotError> {
        let all = || self.lines.iter().flat_map(|l| l.points.iter().copied());
        let xr = axis_range(&self.x, all().filter(|p| p.1.is_finite()).map(|p| p.0));
        // the y range fitted to the points inside the x range
        let yr = axis_range(
            &self.y,
            all()
                .filter(|p| {
                    let x = to_scale(p.0, self.x.scale);
                    xr.is_some_and(|(a, b)| x >= a && x <= b)
                })
                .map(|p| p.1),
        );
        let (Some(xr), Some(yr)) = (xr, yr) else {
            return Err(PlotError::Empty(self.title.clone()));
        };
        let mut chart = ChartBuilder::on(area)
            .caption(&self.title, ("sans-serif", 18))
            .margin(10)
            .x_label_area_size(48)
            .y_label_area_size(72)
            .build_cartesian_2d(xr.0..xr.1, yr.0..yr.1)
            .map_err(|e| err(path, e))?;
        let fx = |v: &f64| match self.x.scale {
            Scale::Linear => fmt_tick(*v),
            Scale::Log => fmt_log_tick(10f64.powf(*v)),
        };
        let fy = |v: &f64| match self.y.scale {
            Scale::Linear => fmt_tick(*v),
            Scale::Log => fmt_log_tick(10f64.powf(*v)),
        };
        chart
            .configure_mesh()
            .x_desc(&self.x.label)
            .y_desc(&self.y.label)
            .x_label_formatter(&fx)
            .y_label_formatter(&fy)
            .x_labels(8)
            .y_labels(8)
            .label_style(("sans-serif", 14))
            .axis_desc_style(("sans-serif", 15))
            .light_line_style(RGBColor(235, 235, 235))
            .draw()
            .map_err(|e| err(path, e))?;
        let mut legend = false;
        for l in &self.lines {
            let c = PALETTE[l.colour % PALETTE.len()];
            let scaled: Vec<(f64, f64)> = l
                .points
                .iter()
                .map(|&(x, y)| (to_scale(x, self.x.scale), to_scale(y, self.y.scale)))
                .collect();
            let style = c.stroke_width(2);
            let pieces = if l.no_line {
                Vec::new()
            } else {
                clip_polyline(&scaled, xr, yr)
            };
            let mut first = true;
            for piece in pieces {
                let anno = if l.dashed {
                    chart
                        .draw_series(DashedLineSeries::new(piece, 7, 4, style))
                        .map_err(|e| err(path, e))?
                } else {
                    // one path per segment: plotters' bitmap backend joins a
                    // thick polyline with mitres, and a sharp reversal (a
                    // contact-pressure spike) then shoots a spike across the
                    // picture, out of the frame (plotters issue #549)
                    chart
                        .draw_series(
                            piece
                                .windows(2)
                                .map(|w| PathElement::new(vec![w[0], w[1]], style)),
                        )
                        .map_err(|e| err(path, e))?
                };
                if first {
                    if !l.label.is_empty() {
                        legend = true;
                        label_series(anno, l, c);
                    }
                    first = false;
                }
            }
            if l.markers {
                let inside: Vec<(f64, f64)> = scaled
                    .iter()
                    .copied()
                    .filter(|p| p.0 >= xr.0 && p.0 <= xr.1 && p.1 >= yr.0 && p.1 <= yr.1)
                    .collect();
                let anno = chart
                    .draw_series(inside.into_iter().map(|p| Circle::new(p, 4, c.filled())))
                    .map_err(|e| err(path, e))?;
                if first && !l.label.is_empty() {
                    legend = true;
                    label_series(anno, l, c);
                }
            }
        }
        // values beyond the frame: a triangle at the edge and a label
        for o in &self.off_scale {
            let x = to_scale(o.x, self.x.scale);
            let y = to_scale(o.y, self.y.scale);
            if !(x.is_finite() && x >= xr.0 && x <= xr.1) {
                continue;
            }
            let above = y > yr.1;
            let edge = if above { yr.1 } else { yr.0 };
            let red = RGBColor(200, 0, 0);
            chart
                .draw_series(std::iter::once(
                    EmptyElement::at((x, edge))
                        + Polygon::new(
                            if above {
                                vec![(0, 0), (-7, 12), (7, 12)]
                            } else {
                                vec![(0, 0), (-7, -12), (7, -12)]
                            },
                            red.filled(),
                        )
                        + Text::new(
                            o.label.clone(),
                            (10, if above { 4 } else { -20 }),
                            ("sans-serif", 14).into_font().color(&red),
                        ),
                ))
                .map_err(|e| err(path, e))?;
        }
        if !self.notes.is_empty() {
            let (px, py) = (xr.0 + 0.02 * (xr.1 - xr.0), yr.1);
            chart
                .draw_series(self.notes.iter().enumerate().map(|(k, n)| {
                    EmptyElement::at((px, py))
                        + Text::new(n.clone(), (0, 6 + 17 * k as i32), ("sans-serif", 14))
                }))
                .map_err(|e| err(path, e))?;
        }
        let pos = match self.legend {
            LegendAt::UpperRight => Some(SeriesLabelPosition::UpperRight),
            LegendAt::UpperLeft => Some(SeriesLabelPosition::UpperLeft),
            LegendAt::LowerRight => Some(SeriesLabelPosition::LowerRight),
            LegendAt::LowerLeft => Some(SeriesLabelPosition::LowerLeft),
            LegendAt::None => None,
        };
        if let (true, Some(pos)) = (legend, pos) {
            chart
                .configure_series_labels()
                .position(pos)
                .background_style(WHITE.mix(0.85))
                .border_style(BLACK)
                .label_font(("sans-serif", 13))
                .draw()
                .map_err(|e| err(path, e))?;
        }
        Ok(())
    }
}

impl Figure {
    /// A figure with one panel (900×600).
    pub fn single(panel: Panel) -> Self {
        Figure {
            title: String::new(),
            panels: vec![panel],
            size: (900, 600),
        }
    }

    fn draw<DB: DrawingBackend>(
        &self,
        root: DrawingArea<DB, Shift>,
        path: &Path,
    ) -> Result<(), PlotError> {
        root.fill(&WHITE).map_err(|e| err(path, e))?;
        let area = if self.title.is_empty() {
            root.clone()
        } else {
            root.titled(&self.title, ("sans-serif", 22))
                .map_err(|e| err(path, e))?
        };
        let n = self.panels.len().max(1);
        let cells = area.split_evenly((1, n));
        for (p, cell) in self.panels.iter().zip(&cells) {
            p.draw(cell, path)?;
        }
        root.present().map_err(|e| err(path, e))
    }

    /// The figure as an SVG document.
    pub fn to_svg(&self) -> Result<String, PlotError> {
        register_bundled_font();
        let mut s = String::new();
        self.draw(
            SVGBackend::with_string(&mut s, self.size).into_drawing_area(),
            Path::new("<svg>"),
        )?;
        Ok(s)
    }

    /// The figure as RGB pixels (row by row, 3 bytes each), as the PNG holds them.
    pub fn to_rgb(&self) -> Result<Vec<u8>, PlotError> {
        register_bundled_font();
        let mut buf = vec![0u8; 3 * self.size.0 as usize * self.size.1 as usize];
        self.draw(
            BitMapBackend::with_buffer(&mut buf, self.size).into_drawing_area(),
            Path::new("<png>"),
        )?;
        Ok(buf)
    }

    /// Writes `<stem>.svg` and `<stem>.png` and returns their paths.
    pub fn write_svg_png(&self, stem: &Path) -> Result<(PathBuf, PathBuf), PlotError> {
        register_bundled_font();
        let svg = stem.with_extension("svg");
        let png = stem.with_extension("png");
        let text = self.to_svg()?;
        std::fs::write(&svg, text).map_err(|e| err(&svg, e))?;
        self.draw(
            BitMapBackend::new(&png, self.size).into_drawing_area(),
            &png,
        )?;
        Ok((svg, png))
    }
}

impl LinePlot {
    /// The plot as a one-panel [`Figure`] (one colour per series, solid).
    pub fn figure(&self) -> Figure {
        Figure::single(Panel {
            title: self.title.clone(),
            x: Axis::linear(self.x_label.clone()),
            y: Axis::linear(self.y_label.clone()),
            lines: self
                .series
                .iter()
                .enumerate()
                .map(|(k, s)| Line::solid(s.label.clone(), k, s.points.clone()))
                .collect(),
            legend: if self.series.len() > 1 || self.series.iter().any(|s| !s.label.is_empty()) {
                LegendAt::UpperRight
            } else {
                LegendAt::None
            },
            ..Default::default()
        })
    }

    /// Writes `<stem>.svg` and `<stem>.png` (900×600) and returns their paths.
    pub fn write_svg_png(&self, stem: &Path) -> Result<(PathBuf, PathBuf), PlotError> {
        self.figure().write_svg_png(stem)
    }
}

fn bounds(it: impl Iterator<Item = (f64, f64)>) -> Option<((f64, f64), (f64, f64))> {
    let mut b: Option<((f64, f64), (f64, f64))> = None;
    for (x, y) in it.filter(|(x, y)| x.is_finite() && y.is_finite()) {
        b = Some(match b {
            None => ((x, x), (y, y)),
            Some(((x0, x1), (y0, y1))) => ((x0.min(x), x1.max(x)), (y0.min(y), y1.max(y))),
        });
    }
    b.map(|((x0, x1), (y0, y1))| {
        let px = if x1 > x0 {
            0.02 * (x1 - x0)
        } else {
            0.5 * x0.abs().max(1.0)
        };
        let py = if y1 > y0 {
            0.05 * (y1 - y0)
        } else {
            0.5 * y0.abs().max(1.0)
        };
        ((x0 - px, x1 + px), (y0 - py, y1 + py))
    })
}

/// Blue → red colour map on [0, 1].
pub fn colour_map(v: f64) -> RGBColor {
    let v = if v.is_finite() {
        v.clamp(0.0, 1.0)
    } else {
        0.0
    };
    let r = (255.0 * v.sqrt()) as u8;
    let g = (200.0 * (1.0 - (2.0 * v - 1.0).abs())) as u8;
    let b = (255.0 * (1.0 - v).sqrt()) as u8;
    RGBColor(r, g, b)
}

impl ColouredPath {
    fn draw<DB: DrawingBackend>(
        &self,
        root: DrawingArea<DB, Shift>,
        path: &Path,
        size: (u32, u32),
    ) -> Result<(), PlotError> {
        let all = || self.points.iter().chain(self.more_closed.iter().flatten());
        let ((x0, x1), (y0, y1)) = bounds(all().map(|p| (p.0, p.1)))
            .ok_or_else(|| PlotError::Empty(self.title.clone()))?;
        // equal aspect ratio
        let (cx, cy) = (0.5 * (x0 + x1), 0.5 * (y0 + y1));
        let span =
            (x1 - x0).max((y1 - y0) * (size.0 as f64 - 160.0) / (size.1 as f64 - 60.0)) * 0.5;
        let yspan = span * (size.1 as f64 - 60.0) / (size.0 as f64 - 160.0);
        let vmax = all()
            .map(|p| p.2)
            .filter(|v| v.is_finite())
            .fold(0.0f64, f64::max);
        let vmin = all()
            .map(|p| p.2)
            .filter(|v| v.is_finite())
            .fold(vmax, f64::min);
        let scale = |v: f64| {
            if vmax > vmin {
                (v - vmin) / (vmax - vmin)
            } else {
                1.0
            }
        };
        root.fill(&WHITE).map_err(|e| err(path, e))?;
        let (main, bar) = root.split_horizontally(size.0 - 110);
        let mut chart = ChartBuilder::on(&main)
            .caption(&self.title, ("sans-serif", 20))
            .margin(10)
            .x_label_area_size(35)
            .y_label_area_size(50)
            .build_cartesian_2d((cx - span)..(cx + span), (cy - yspan)..(cy + yspan))
            .map_err(|e| err(path, e))?;
        chart
            .configure_mesh()
            .x_desc("x")
            .y_desc("y")
            .label_style(("sans-serif", 12))
            .draw()
            .map_err(|e| err(path, e))?;
        let paths = std::iter::once((&self.points, self.closed))
            .chain(self.more_closed.iter().map(|p| (p, true)));
        for (pts, closed) in paths {
            let m = pts.len();
            let segs = if closed { m } else { m.saturating_sub(1) };
            chart
                .draw_series((0..segs).map(|k| {
                    let a = pts[k];
                    let b = pts[(k + 1) % m];
                    PathElement::new(
                        vec![(a.0, a.1), (b.0, b.1)],
                        colour_map(scale(0.5 * (a.2 + b.2))).stroke_width(4),
                    )
                }))
                .map_err(|e| err(path, e))?;
        }
        // colour bar
        let mut cb = ChartBuilder::on(&bar)
            .margin_top(40)
            .margin_bottom(40)
            .margin_right(10)
            .y_label_area_size(55)
            .build_cartesian_2d(0.0..1.0, vmin..vmax.max(vmin + f64::EPSILON))
            .map_err(|e| err(path, e))?;
        cb.configure_mesh()
            .disable_x_mesh()
            .disable_x_axis()
            .y_desc(&self.value_label)
            .label_style(("sans-serif", 12))
            .draw()
            .map_err(|e| err(path, e))?;
        let steps = 64;
        cb.draw_series((0..steps).map(|i| {
            let v0 = vmin + (vmax - vmin) * i as f64 / steps as f64;
            let v1 = vmin + (vmax - vmin) * (i + 1) as f64 / steps as f64;
            Rectangle::new(
                [(0.0, v0), (1.0, v1)],
                colour_map(i as f64 / (steps - 1) as f64).filled(),
            )
        }))
        .map_err(|e| err(path, e))?;
        root.present().map_err(|e| err(path, e))
    }

    /// Writes `<stem>.svg` and `<stem>.png` (800×640) and returns their paths.
    pub fn write_svg_png(&self, stem: &Path) -> Result<(PathBuf, PathBuf), PlotError> {
        register_bundled_font();
        let size = (800, 640);
        let svg = stem.with_extension("svg");
        let png = stem.with_extension("png");
        self.draw(SVGBackend::new(&svg, size).into_drawing_area(), &svg, size)?;
        self.draw(
            BitMapBackend::new(&png, size).into_drawing_area(),
            &png,
            size,
        )?;
        Ok((svg, png))
    }
}

#[cfg(test)]
mod tests {
    //! Goal: what is drawn stays inside its frame, in the PNG as in the SVG.
    use super::*;

    #[test]
    fn log_ticks_have_two_significant_digits() {
        assert_eq!(fmt_log_tick(0.00251189), "0.0025");
        assert_eq!(fmt_log_tick(0.0158489), "0.016");
        assert_eq!(fmt_log_tick(0.01), "0.01");
        assert_eq!(fmt_log_tick(1e-5), "1e-5");
        assert_eq!(fmt_log_tick(398107.0), "400000");
    }

    #[test]
    fn a_sharp_spike_stays_inside_the_frame_in_the_png() {
        // the vessel's contact pressure near the weld: 0, a spike, 0 again,
        // on a 0–180° axis (nearly vertical segments that reverse sharply)
        let mut pts = vec![(0.0, 0.0), (0.5, 0.0), (0.6, 0.365), (0.7, 0.0)];
        pts.extend((0..=60).map(|k| (2.0 + 3.0 * k as f64, 0.05 - 0.0002 * k as f64)));
        let fig = Figure::single(Panel {
            title: "spike".into(),
            x: Axis::linear("θ"),
            y: Axis::linear("p"),
            lines: vec![Line::solid("FE", 0, pts).with_markers()],
            legend: LegendAt::None,
            ..Default::default()
        });
        let (w, h) = fig.size;
        let rgb = fig.to_rgb().unwrap();
        let c = PALETTE[0];
        // below the x axis (frame bottom at h − 10 − 48 px) only labels are drawn
        let frame_bottom = h as usize - 10 - 48;
        let stray = (frame_bottom + 3..h as usize)
            .flat_map(|y| (0..w as usize).map(move |x| (x, y)))
            .filter(|&(x, y)| {
                let i = 3 * (y * w as usize + x);
                rgb[i] == c.0 && rgb[i + 1] == c.1 && rgb[i + 2] == c.2
            })
            .count();
        assert_eq!(stray, 0, "line pixels below the frame");
    }
}
