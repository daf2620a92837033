//! Gauss–Legendre rules used for geometric integrals (area, centroid, I_p, lengths).

/// Nodes and weights of the `m`-point Gauss–Legendre rule on [0, 1].
///
/// Computed by Newton's method on the Legendre three-term recurrence; exact for
/// polynomials of degree ≤ 2m − 1.
pub fn gauss_legendre_01(m: usize) -> (Vec<f64>, Vec<f64>) {
    let mut x = vec![0.0; m];
    let mut w = vec![0.0; m];
    for i in 0..m {
        // Tricomi's initial guess for the i-th root on [-1, 1]
        let mut z = (std::f64::consts::PI * (i as f64 + 0.75) / (m as f64 + 0.5)).cos();
        let mut dp = 1.0;
        for _ in 0..100 {
            let (p, d) = legendre(m, z);
            dp = d;
            let dz = p / d;
            z -= dz;
            if dz.abs() < 1e-16 {
                break;
            }
        }
        let (_, d) = legendre(m, z);
        if d.is_finite() {
            dp = d;
        }
        x[i] = 0.5 * (1.0 - z);
        w[i] = 1.0 / ((1.0 - z * z) * dp * dp);
    }
    (x, w)
}

/// Legendre polynomial P_m(z) and its derivative.
fn legendre(m: usize, z: f64) -> (f64, f64) {
    let mut p0 = 1.0;
    let mut p1 = z;
    if m == 0 {
        return (1.0, 0.0);
    }
    for k in 2..=m {
        let kf = k as f64;
        let p2 = ((2.0 * kf - 1.0) * z * p1 - (kf - 1.0) * p0) / kf;
        p0 = p1;
        p1 = p2;
    }
    let d = m as f64 * (z * p1 - p0) / (z * z - 1.0);
    (p1, d)
}

/// Composite Gauss–Legendre rule on [0, 1]: `panels` equal panels of `m` points.
pub fn composite_gauss_01(panels: usize, m: usize) -> (Vec<f64>, Vec<f64>) {
    let (x, w) = gauss_legendre_01(m);
    let mut xs = Vec::with_capacity(panels * m);
    let mut ws = Vec::with_capacity(panels * m);
    let h = 1.0 / panels as f64;
    for p in 0..panels {
        for (xi, wi) in x.iter().zip(&w) {
            xs.push((p as f64 + xi) * h);
            ws.push(wi * h);
        }
    }
    (xs, ws)
}

#[cfg(test)]
mod tests {
    use super::*;
    #[test]
    fn gauss_is_exact_for_degree_2m_minus_1() {
        let (x, w) = gauss_legendre_01(10);
        for d in 0..20 {
            let s: f64 = x.iter().zip(&w).map(|(x, w)| w * x.powi(d)).sum();
            assert!(
                (s - 1.0 / (d as f64 + 1.0)).abs() < 1e-15,
                "degree {d}: {s}"
            );
        }
    }
}
