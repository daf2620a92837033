//! Closed-form Saint-Venant torsion solutions (Gθ = 1), one struct per section.

use crate::quadrature::gauss_legendre_01;
use std::f64::consts::PI;

/// Circle of radius R: J = πR⁴/2, τ_max = R (uniform on Γ).
pub struct Circle {
    /// radius R
    pub r: f64,
}
impl Circle {
    /// J
    pub fn rigidity(&self) -> f64 {
        PI * self.r.powi(4) / 2.0
    }
    /// τ_max
    pub fn max_shear(&self) -> f64 {
        self.r
    }
}

/// Ellipse x = a cos t, y = b sin t.
pub struct Ellipse {
    /// semi-axis along x
    pub a: f64,
    /// semi-axis along y
    pub b: f64,
}
impl Ellipse {
    /// J = π a³ b³ / (a² + b²)
    pub fn rigidity(&self) -> f64 {
        PI * self.a.powi(3) * self.b.powi(3) / (self.a * self.a + self.b * self.b)
    }
    /// τ_max = 2 a² b / (a² + b²) (a ≥ b), at the ends of the minor axis
    pub fn max_shear(&self) -> f64 {
        let (a, b) = if self.a >= self.b {
            (self.a, self.b)
        } else {
            (self.b, self.a)
        };
        2.0 * a * a * b / (a * a + b * b)
    }
    /// |q|(t) = 2ab √(b² cos² t + a² sin² t) / (a² + b²)
    pub fn shear_at(&self, t: f64) -> f64 {
        let (a, b) = (self.a, self.b);
        2.0 * a * b * (b * b * t.cos().powi(2) + a * a * t.sin().powi(2)).sqrt() / (a * a + b * b)
    }
}

/// Equilateral triangle of side a.
pub struct EquilateralTriangle {
    /// side a
    pub a: f64,
}
impl EquilateralTriangle {
    /// J = √3 a⁴ / 80
    pub fn rigidity(&self) -> f64 {
        3f64.sqrt() * self.a.powi(4) / 80.0
    }
    /// τ_max = √3 a / 4 at the mid-sides
    pub fn max_shear(&self) -> f64 {
        3f64.sqrt() * self.a / 4.0
    }
    /// |q| = √3 s (a − s) / a at distance s from a vertex along a side
    pub fn shear_at(&self, s: f64) -> f64 {
        3f64.sqrt() * s * (self.a - s) / self.a
    }
}

/// Rectangle of width w and height h (series solution).
pub struct Rectangle {
    /// width
    pub w: f64,
    /// height
    pub h: f64,
}
impl Rectangle {
    fn ab(&self) -> (f64, f64) {
        let (a, b) = (0.5 * self.w.min(self.h), 0.5 * self.w.max(self.h));
        (a, b)
    }
    /// J = (16/3) a³ b [1 − (192/π⁵)(a/b) Σ_{n odd} tanh(nπb/2a)/n⁵], 2a ≤ 2b the sides
    pub fn rigidity(&self) -> f64 {
        let (a, b) = self.ab();
        // Σ_{odd} 1/n⁵ = (31/32) ζ(5); the tanh defect 1 − tanh x = 2/(e^{2x} + 1) decays fast
        let zeta5 = 1.036_927_755_143_37;
        let mut s = 31.0 / 32.0 * zeta5;
        let mut n = 1;
        loop {
            let x = n as f64 * PI * b / (2.0 * a);
            let defect = 2.0 / ((2.0 * x).exp() + 1.0) / (n as f64).powi(5);
            s -= defect;
            if defect < 1e-20 {
                break;
            }
            n += 2;
        }
        16.0 / 3.0 * a.powi(3) * b * (1.0 - 192.0 / PI.powi(5) * (a / b) * s)
    }
    /// τ_max = 2a [1 − (8/π²) Σ_{n odd} 1/(n² cosh(nπb/2a))] at the middle of the long sides
    pub fn max_shear(&self) -> f64 {
        let (a, b) = self.ab();
        let mut s = 0.0;
        let mut n = 1;
        loop {
            let term = 1.0 / ((n * n) as f64 * (n as f64 * PI * b / (2.0 * a)).cosh());
            s += term;
            if term < 1e-20 {
                break;
            }
            n += 2;
        }
        2.0 * a * (1.0 - 8.0 / (PI * PI) * s)
    }
    /// The warping constant Γ = ∫ ω² dA about the centre (ω the warping
    /// function, w along x), term by term: the terms decay like n⁻⁶.
    pub fn warping_constant(&self) -> f64 {
        let (a, b) = (0.5 * self.w, 0.5 * self.h);
        let mut g = 4.0 * a.powi(3) * b.powi(3) / 9.0;
        for n in 0..200_000 {
            let m = (2 * n + 1) as f64;
            let k = m * PI / (2.0 * a);
            let sg = if n % 2 == 0 { 1.0 } else { -1.0 };
            let c = -32.0 * a * a * sg / (m.powi(3) * PI.powi(3));
            let t = (k * b).tanh();
            // 2 ∫∫ xy φ: ∫x sin(kx) = 2(−1)ⁿ/k², ∫ y sinh(ky)/cosh(kb) = 2(b/k − tanh(kb)/k²)
            g += 2.0 * c * (2.0 * sg / (k * k)) * 2.0 * (b / k - t / (k * k));
            // ∫∫ φ²: ∫ sin² = a, ∫ sinh²(ky)/cosh²(kb) = tanh(kb)/k − b/cosh²(kb)
            let sech2 = 1.0 - t * t;
            g += c * c * a * (t / k - b * sech2);
        }
        g
    }
}

/// Limaçon z = A(e^{iθ} + c e^{2iθ}), 0 ≤ c ≤ ½ (image of the unit disc under a
/// univalent polynomial map): v = A²(1 + c² + 2c Re ζ)/2 in the ζ-disc gives
/// J = πA⁴(½ + 2c² + c⁴) and |q|(θ) = A(1 + 2c² + 2c cos θ)/√(1 + 4c² + 4c cos θ).
pub struct Limacon {
    /// scale A
    pub a: f64,
    /// shape c
    pub c: f64,
}
impl Limacon {
    /// J
    pub fn rigidity(&self) -> f64 {
        let c2 = self.c * self.c;
        PI * self.a.powi(4) * (0.5 + 2.0 * c2 + c2 * c2)
    }
    /// |q| at θ
    pub fn shear_at(&self, th: f64) -> f64 {
        let c = self.c;
        self.a * (1.0 + 2.0 * c * c + 2.0 * c * th.cos())
            / (1.0 + 4.0 * c * c + 4.0 * c * th.cos()).sqrt()
    }
    /// τ_max = A(1 + (1 − 2c)²)/(2(1 − 2c)) at θ = π (infinite for the cardioid)
    pub fn max_shear(&self) -> f64 {
        let d = 1.0 - 2.0 * self.c;
        self.a * (1.0 + d * d) / (2.0 * d)
    }
}

/// Grooved shaft: disc of radius a centred at (a, 0) minus the disc of radius
/// b centred at the origin. u = a x − r²/2 − a b² x / r² + b²/2.
pub struct Groove {
    /// shaft radius a
    pub a: f64,
    /// groove radius b < 2a
    pub b: f64,
}
impl Groove {
    /// u(x)
    pub fn u(&self, x: [f64; 2]) -> f64 {
        let r2 = x[0] * x[0] + x[1] * x[1];
        self.a * x[0] - 0.5 * r2 - self.a * self.b * self.b * x[0] / r2 + 0.5 * self.b * self.b
    }
    /// ∇u(x)
    pub fn grad(&self, x: [f64; 2]) -> [f64; 2] {
        let r2 = x[0] * x[0] + x[1] * x[1];
        let k = self.a * self.b * self.b;
        [
            self.a - x[0] - k * (r2 - 2.0 * x[0] * x[0]) / (r2 * r2),
            -x[1] + 2.0 * k * x[0] * x[1] / (r2 * r2),
        ]
    }
    /// τ_max = 2a − b at the bottom of the groove (b, 0)
    pub fn max_shear(&self) -> f64 {
        2.0 * self.a - self.b
    }
    /// J = 2∫u dA in polar coordinates (r analytic, θ by 64-point Gauss–Legendre)
    pub fn rigidity(&self) -> f64 {
        let (a, b) = (self.a, self.b);
        let thc = (b / (2.0 * a)).acos();
        let (x, w) = gauss_legendre_01(64);
        let mut s = 0.0;
        for (xi, wi) in x.iter().zip(&w) {
            let th = -thc + 2.0 * thc * xi;
            let c = th.cos();
            let r = 2.0 * a * c;
            let f = 0.5
                * (2.0 * a * c * (r.powi(3) - b.powi(3)) / 3.0
                    - (r.powi(4) - b.powi(4)) / 4.0
                    - 2.0 * a * b * b * c * (r - b)
                    + b * b * (r * r - b * b) / 2.0);
            s += wi * 2.0 * thc * f;
        }
        2.0 * s
    }
}
