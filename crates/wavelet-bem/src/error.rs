//! Typed errors of the crate.

use thiserror::Error;

/// Invalid boundary geometry.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum GeometryError {
    /// No pieces at all.
    #[error("the section has no boundary pieces")]
    Empty,
    /// A non-finite or out-of-range parameter.
    #[error(
        "piece {piece}: invalid parameter (non-finite, non-positive radius/axis, or limaçon c outside [0, 1/2])"
    )]
    InvalidParameter {
        /// piece index
        piece: usize,
    },
    /// A piece of (nearly) zero length.
    #[error("piece {piece} is degenerate (length {length:e})")]
    Degenerate {
        /// piece index
        piece: usize,
        /// its length
        length: f64,
    },
    /// Piece k does not end where piece k+1 starts.
    #[error(
        "boundary not closed: piece {piece} ends {gap:e} away from the start of the next piece"
    )]
    NotClosed {
        /// piece index
        piece: usize,
        /// gap length
        gap: f64,
    },
    /// The boundary crosses itself.
    #[error("boundary is self-intersecting near ({:.6}, {:.6})", near[0], near[1])]
    SelfIntersecting {
        /// a point near the crossing
        near: [f64; 2],
    },
    /// The enclosed area vanishes.
    #[error("the boundary encloses no area")]
    ZeroArea,
    /// Two consecutive pieces fold back on each other.
    #[error("junction {junction}: the boundary folds back on itself (zero interior angle)")]
    ZeroAngle {
        /// junction index
        junction: usize,
    },
    /// A hole lies outside the outer boundary.
    #[error("hole[{hole}] lies outside the outer boundary")]
    HoleOutside {
        /// hole index (0-based: the position in the list of holes, the
        /// `[[hole]]` tables of a section file in order)
        hole: usize,
    },
    /// A hole meets the outer boundary.
    #[error("hole[{hole}] touches or crosses the outer boundary near ({:.6}, {:.6})", near[0], near[1])]
    HoleTouchesBoundary {
        /// hole index (0-based)
        hole: usize,
        /// a point where the two boundaries meet (on the inscribed polygons
        /// that curved pieces are checked as)
        near: [f64; 2],
    },
    /// Two holes overlap or touch.
    #[error("hole[{a}] and hole[{b}] overlap or touch")]
    HolesOverlap {
        /// first hole (0-based)
        a: usize,
        /// second hole (0-based)
        b: usize,
    },
    /// A hole was given holes of its own.
    #[error("a hole cannot have holes of its own")]
    NestedHoles,
    /// Too few polygon vertices.
    #[error("a polygon needs at least 3 vertices, got {0}")]
    TooFewVertices(usize),
    /// Fewer than 3 vertices are left once those closer than
    /// [`crate::sections::MERGE_FRACTION`] of the perimeter are merged.
    #[error(
        "only {left} of the polygon's {given} vertices are more than {fraction:.0e} of the perimeter apart: the section is a line at this scale (thinner than {fraction:.0e} of its perimeter)"
    )]
    TooThin {
        /// vertices given
        given: usize,
        /// vertices left after merging
        left: usize,
        /// the merge distance as a fraction of the perimeter
        fraction: f64,
    },
    /// A polygon with more vertices than memory holds (refused before its
    /// vertex lists are built).
    #[error(
        "a polygon of {vertices} vertices needs about {:.1} GB to set up, more than the {:.1} GB available; give fewer vertices (a wavelet solve uses at most --max-n unknowns per curve, so an outline finer than that is not resolved anyway)",
        *needed as f64 / 1e9,
        *available as f64 / 1e9
    )]
    TooManyVertices {
        /// vertices given
        vertices: usize,
        /// estimated bytes
        needed: u64,
        /// bytes available
        available: u64,
    },
}

/// A bad `--section` specification or section file.
#[derive(Debug, Error)]
pub enum SpecError {
    /// Unknown section kind.
    #[error(
        "unknown section kind `{0}` (expected circle, ellipse, rectangle, triangle, polygon, regular, groove, limacon, tube, box, or a file path)"
    )]
    UnknownKind(String),
    /// A required field is missing.
    #[error("{kind}: missing field `{field}`")]
    MissingField {
        /// section kind
        kind: String,
        /// field name
        field: String,
    },
    /// A field does not parse or is out of range.
    #[error("{kind}: bad value `{value}` for field `{field}`: {reason}")]
    BadValue {
        /// section kind
        kind: String,
        /// field name
        field: String,
        /// the offending text
        value: String,
        /// why it is rejected
        reason: String,
    },
    /// The section names a file that does not exist.
    #[error("section file `{0}`: no such file")]
    NoSuchFile(String),
    /// The file cannot be read.
    #[error("cannot read section file `{path}`: {source}")]
    Io {
        /// file path
        path: String,
        /// underlying error
        source: std::io::Error,
    },
    /// The file is not valid TOML.
    #[error("section file `{path}`: {message}")]
    Toml {
        /// file path
        path: String,
        /// parser message (names the offending key/line)
        message: String,
    },
    /// The geometry is invalid.
    #[error("invalid section geometry: {0}")]
    Geometry(#[from] GeometryError),
    /// The geometry of a section file is invalid.
    #[error("section file `{path}`: invalid section geometry: {at}{error}")]
    FileGeometry {
        /// file path
        path: String,
        /// the curve at fault: "" (the outer boundary, or the holes'
        /// placement, which names them) or "hole[k]: " (0-based)
        at: String,
        /// what is wrong
        #[source]
        error: GeometryError,
    },
}

/// Failure of a solve.
#[derive(Debug, Error)]
pub enum SolveError {
    /// Unsupported number of unknowns.
    #[error("bad number of unknowns n = {n}: {reason}")]
    BadN {
        /// requested n
        n: usize,
        /// why
        reason: String,
    },
    /// Unsupported wavelet name.
    #[error("unknown wavelet `{0}` (expected db1 … db20)")]
    BadWavelet(String),
    /// Bad grading exponent.
    #[error("grading exponent must be an integer in 2..=12, got {0}")]
    BadGrading(f64),
    /// The linear system is (numerically) singular or the iteration failed.
    #[error("linear solve failed: {0}")]
    Linear(String),
    /// A combination the solver does not handle.
    #[error("not supported: {0}")]
    Unsupported(String),
    /// An evaluation point is not inside the section.
    #[error("point {index} ({}, {}) is {where_} the section", point[0], point[1])]
    PointOutside {
        /// 1-based index of the point
        index: usize,
        /// the point
        point: [f64; 2],
        /// "outside" or "on the boundary of"
        where_: &'static str,
    },
    /// The result is not finite.
    #[error("the solution is not finite (ill-posed geometry or too few unknowns)")]
    NonFinite,
    /// The section is so large or so small that J (∝ L⁴, about its polar
    /// moment) leaves the normal range of double precision.
    #[error(
        "the section's polar moment I_p = {polar_moment:e} (length⁴) is outside [1e-300, 1e300]: \
         J, of the same size, cannot be computed in double precision; give the lengths in units \
         nearer the section's size (e.g. mm instead of m)"
    )]
    Scale {
        /// the polar moment of the section about its centroid
        polar_moment: f64,
    },
    /// The boundary encloses, to round-off, no area (e.g. a tube whose
    /// wall is thinner than the rounding of its radii).
    #[error(
        "the section encloses, to round-off, no area: A = {area:e} against a perimeter of \
         {perimeter:e} (a wall thinner than the rounding of its coordinates?)"
    )]
    NoArea {
        /// the enclosed area
        area: f64,
        /// the total length of the boundary curves
        perimeter: f64,
    },
    /// The dense system would not fit in memory (refused before allocating).
    #[error(
        "n = {n} per curve on {curves} boundary curve(s) is {unknowns} unknowns: the dense solve \
         needs about {:.1} GB, more than the {:.1} GB available; use a smaller n \
         (--n, --max-n) or a section with fewer holes",
        *needed as f64 / 1e9,
        *available as f64 / 1e9
    )]
    TooLarge {
        /// unknowns per curve
        n: usize,
        /// boundary curves (1 + holes)
        curves: usize,
        /// total unknowns K n
        unknowns: usize,
        /// estimated peak bytes
        needed: u64,
        /// bytes available
        available: u64,
    },
}
