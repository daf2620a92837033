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
}

const PALETTE: [RGBColor; 6] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(255, 127, 14),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
];

fn err(path: &Path, e: impl std::fmt::Display) -> PlotError {
    PlotError::Draw {
        path: path.display().to_string(),
        message: e.to_string(),
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

impl LinePlot {
    fn draw<DB: DrawingBackend>(
        &self,
        root: DrawingArea<DB, Shift>,
        path: &Path,
    ) -> Result<(), PlotError> {
        let ((x0, x1), (y0, y1)) =
            bounds(self.series.iter().flat_map(|s| s.points.iter().copied()))
                .ok_or_else(|| PlotError::Empty(self.title.clone()))?;
        root.fill(&WHITE).map_err(|e| err(path, e))?;
        let mut chart = ChartBuilder::on(&root)
            .caption(&self.title, ("sans-serif", 22))
            .margin(12)
            .x_label_area_size(45)
            .y_label_area_size(70)
            .build_cartesian_2d(x0..x1, y0..y1)
            .map_err(|e| err(path, e))?;
        chart
            .configure_mesh()
            .x_desc(&self.x_label)
            .y_desc(&self.y_label)
            .label_style(("sans-serif", 14))
            .draw()
            .map_err(|e| err(path, e))?;
        for (k, s) in self.series.iter().enumerate() {
            let c = PALETTE[k % PALETTE.len()];
            chart
                .draw_series(LineSeries::new(
                    s.points
                        .iter()
                        .copied()
                        .filter(|(x, y)| x.is_finite() && y.is_finite()),
                    c.stroke_width(2),
                ))
                .map_err(|e| err(path, e))?
                .label(s.label.clone())
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 18, y)], c.stroke_width(2))
                });
        }
        if self.series.len() > 1 || self.series.iter().any(|s| !s.label.is_empty()) {
            chart
                .configure_series_labels()
                .background_style(WHITE.mix(0.85))
                .border_style(BLACK)
                .label_font(("sans-serif", 14))
                .draw()
                .map_err(|e| err(path, e))?;
        }
        root.present().map_err(|e| err(path, e))
    }

    /// Writes `<stem>.svg` and `<stem>.png` (900×600) and returns their paths.
    pub fn write_svg_png(&self, stem: &Path) -> Result<(PathBuf, PathBuf), PlotError> {
        register_bundled_font();
        let svg = stem.with_extension("svg");
        let png = stem.with_extension("png");
        self.draw(SVGBackend::new(&svg, (900, 600)).into_drawing_area(), &svg)?;
        self.draw(
            BitMapBackend::new(&png, (900, 600)).into_drawing_area(),
            &png,
        )?;
        Ok((svg, png))
    }
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
        let ((x0, x1), (y0, y1)) = bounds(self.points.iter().map(|p| (p.0, p.1)))
            .ok_or_else(|| PlotError::Empty(self.title.clone()))?;
        // equal aspect ratio
        let (cx, cy) = (0.5 * (x0 + x1), 0.5 * (y0 + y1));
        let span =
            (x1 - x0).max((y1 - y0) * (size.0 as f64 - 160.0) / (size.1 as f64 - 60.0)) * 0.5;
        let yspan = span * (size.1 as f64 - 60.0) / (size.0 as f64 - 160.0);
        let vmax = self
            .points
            .iter()
            .map(|p| p.2)
            .filter(|v| v.is_finite())
            .fold(0.0f64, f64::max);
        let vmin = self
            .points
            .iter()
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
        let m = self.points.len();
        let segs = if self.closed { m } else { m.saturating_sub(1) };
        chart
            .draw_series((0..segs).map(|k| {
                let a = self.points[k];
                let b = self.points[(k + 1) % m];
                PathElement::new(
                    vec![(a.0, a.1), (b.0, b.1)],
                    colour_map(scale(0.5 * (a.2 + b.2))).stroke_width(4),
                )
            }))
            .map_err(|e| err(path, e))?;
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
