//! Memory estimates of the dense solvers, checked before anything large is
//! allocated: a size that cannot fit is refused with the estimate
//! ([`SolveError::TooLarge`]) instead of an allocation abort or the kernel's
//! out-of-memory kill.
//!
//! All three methods store dense matrices of order N = K n (K boundary
//! curves, n unknowns per curve), so memory grows like K² n²: a section with
//! many holes reaches the limit at a small n. The peak, in doubles:
//!
//! * Daubechies Galerkin: 3 N² (kept as the bound; the assembly peaks at
//!   2 N², the kernel's upper triangle and the convolved rows, and the solve
//!   at 2 N², the factor in place and, in the assembly's second array, the
//!   copy kept for the backward-error check; the LU fallback adds its own);
//! * Nyström: 3 N² (kernel samples, the augmented matrix, its LU copy);
//! * Shannon: 6 N² (its 2n quadrature nodes per curve give a complex
//!   2N × N transform and a complex N × N kernel, then the real matrix and
//!   its factor copy).
//!
//! Add 64 MB for everything of size O(N) and the code itself.
//!
//! The memory available is the smaller of `MemAvailable` (/proc/meminfo) and
//! the address-space limit of the process (`ulimit -v`, /proc/self/limits);
//! where neither can be read (not Linux) nothing is refused.

use crate::error::SolveError;
use crate::solve::Method;

/// Fixed allowance for O(N) arrays, FFT plans and the program itself (bytes).
const BASE_BYTES: f64 = 64e6;

/// Estimated peak bytes of one dense solve with `curves` boundary curves of
/// `n` unknowns each by `method`.
pub fn dense_bytes(method: Method, curves: usize, n: usize) -> u64 {
    let big = curves as f64 * n as f64;
    let doubles = match method {
        Method::Daubechies | Method::Nystrom => 3.0 * big * big,
        Method::Shannon => 6.0 * big * big,
    };
    let b = BASE_BYTES + 8.0 * doubles;
    if b.is_finite() && b < u64::MAX as f64 {
        b as u64
    } else {
        u64::MAX
    }
}

/// Bytes per vertex of a polygon while it is set up: the vertex list
/// (16), the kept vertices with their indices (24), the vertices after the
/// collinear ones are dropped (16) and the side pieces (about 40), rounded
/// up. The caller's own list (16 more for a built-in regular polygon) is
/// included.
pub const POLYGON_BYTES_PER_VERTEX: u64 = 128;

/// Refuses a polygon of `vertices` vertices whose set-up needs more than
/// `available` bytes (`None`: unknown, nothing is refused).
pub fn check_vertices(
    vertices: usize,
    available: Option<u64>,
) -> Result<(), crate::error::GeometryError> {
    let needed = (vertices as u64).saturating_mul(POLYGON_BYTES_PER_VERTEX);
    match available {
        Some(avail) if needed > avail => Err(crate::error::GeometryError::TooManyVertices {
            vertices,
            needed,
            available: avail,
        }),
        _ => Ok(()),
    }
}

/// `MemAvailable` from /proc/meminfo in bytes.
fn mem_available() -> Option<u64> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = text.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb.saturating_mul(1024))
}

/// The process's address-space limit in bytes (`None`: unlimited or unknown).
fn address_space_limit() -> Option<u64> {
    let text = std::fs::read_to_string("/proc/self/limits").ok()?;
    let line = text.lines().find(|l| l.starts_with("Max address space"))?;
    let soft = line
        .trim_start_matches("Max address space")
        .split_whitespace()
        .next()?;
    soft.parse().ok()
}

/// Bytes a new allocation can get now: the smaller of `MemAvailable` and the
/// address-space limit (`None` where neither can be read).
pub fn available_bytes() -> Option<u64> {
    match (mem_available(), address_space_limit()) {
        (Some(a), Some(b)) => Some(a.min(b)),
        (a, b) => a.or(b),
    }
}

/// Refuses a dense solve whose estimate exceeds `available` bytes
/// (`None`: unknown, nothing is refused).
pub fn check_with(
    method: Method,
    curves: usize,
    n: usize,
    available: Option<u64>,
) -> Result<(), SolveError> {
    let needed = dense_bytes(method, curves, n);
    match available {
        Some(avail) if needed > avail => Err(SolveError::TooLarge {
            n,
            curves,
            unknowns: curves.saturating_mul(n),
            needed,
            available: avail,
        }),
        _ => Ok(()),
    }
}

/// [`check_with`] against the memory available now ([`available_bytes`]).
pub fn check(method: Method, curves: usize, n: usize) -> Result<(), SolveError> {
    check_with(method, curves, n, available_bytes())
}

#[cfg(test)]
mod tests {
    use super::*;
    #[test]
    fn estimate_grows_with_the_square_of_the_unknowns() {
        let a = dense_bytes(Method::Daubechies, 1, 1024) as f64 - BASE_BYTES;
        let b = dense_bytes(Method::Daubechies, 2, 1024) as f64 - BASE_BYTES;
        assert!((b / a - 4.0).abs() < 1e-12);
        // 1024 unknowns: 3 × 8 MB
        assert!((a - 3.0 * 8.0 * 1024.0 * 1024.0).abs() < 1.0);
        assert!(check_with(Method::Nystrom, 1, 64, Some(1 << 30)).is_ok());
        assert!(check_with(Method::Nystrom, 1, 64, None).is_ok());
        let e = check_with(Method::Daubechies, 1000, 8192, Some(1 << 34)).unwrap_err();
        let msg = e.to_string();
        assert!(msg.contains("8192000 unknowns"), "{msg}");
    }
}
