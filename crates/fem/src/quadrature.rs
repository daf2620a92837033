//! Gauss rules on the reference triangle and on the reference segment.
//!
//! Reference triangle `T̂ = {(ξ, η): ξ ≥ 0, η ≥ 0, ξ + η ≤ 1}` (area 1/2),
//! barycentric coordinates `L₁ = 1 − ξ − η`, `L₂ = ξ`, `L₃ = η`. A rule is a
//! list of points `(ξ, η)` and weights summing to 1/2:
//! `∫_T̂ f dξ dη ≈ Σ_q w_q f(ξ_q, η_q)`.
//!
//! | rule | points | exact for polynomials of degree | source of the formula |
//! |---|---|---|---|
//! | [`TriangleRule::Degree2`] | 3 | 2 | Strang & Fix (interior points `(2/3, 1/6, 1/6)`) |
//! | [`TriangleRule::Degree4`] | 6 | 4 | Dunavant (1985), table for p = 4 |
//! | [`TriangleRule::Degree5`] | 7 | 5 | Radon (1948): centroid and two orbits `(6 ∓ √15)/21` |
//!
//! All weights are positive and all points interior. Segment rules
//! ([`GaussLegendre`]) are Gauss–Legendre on `[−1, 1]`.

/// A Gauss rule on the reference triangle.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum TriangleRule {
    /// 3 points, exact to degree 2: mass matrices of linear triangles,
    /// stiffness of straight 6-node triangles.
    Degree2,
    /// 6 points, exact to degree 4: mass matrices of straight 6-node
    /// triangles; stiffness of curved ones to O(h⁴). The default.
    #[default]
    Degree4,
    /// 7 points, exact to degree 5.
    Degree5,
}

/// One point of a triangle rule.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TrianglePoint {
    /// Reference coordinates `(ξ, η)`.
    pub xi: [f64; 2],
    /// Weight (the weights of a rule sum to 1/2, the reference area).
    pub weight: f64,
}

/// Points of an orbit `(a, a, 1 − 2a)` of barycentric coordinates, as
/// `(ξ, η) = (L₂, L₃)`.
const fn orbit3(a: f64, w: f64) -> [TrianglePoint; 3] {
    let b = 1.0 - 2.0 * a;
    [
        TrianglePoint {
            xi: [a, a],
            weight: w,
        },
        TrianglePoint {
            xi: [b, a],
            weight: w,
        },
        TrianglePoint {
            xi: [a, b],
            weight: w,
        },
    ]
}

const fn join<const A: usize, const B: usize, const C: usize>(
    a: [TrianglePoint; A],
    b: [TrianglePoint; B],
) -> [TrianglePoint; C] {
    let mut out = [TrianglePoint {
        xi: [0.0, 0.0],
        weight: 0.0,
    }; C];
    let mut i = 0;
    while i < A {
        out[i] = a[i];
        i += 1;
    }
    let mut j = 0;
    while j < B {
        out[A + j] = b[j];
        j += 1;
    }
    out
}

/// Strang–Fix 3-point rule: barycentric `(2/3, 1/6, 1/6)` and permutations,
/// weight `1/6` each (1/3 of the area).
const DEGREE2: [TrianglePoint; 3] = orbit3(1.0 / 6.0, 1.0 / 6.0);

/// Dunavant's 6-point degree-4 rule (weights relative to the area, halved).
const DEGREE4: [TrianglePoint; 6] = join::<3, 3, 6>(
    orbit3(0.445_948_490_915_964_9, 0.5 * 0.223_381_589_678_011_47),
    orbit3(0.091_576_213_509_770_74, 0.5 * 0.109_951_743_655_321_87),
);

/// √15, written out so the table is a constant.
const SQRT15: f64 = 3.872_983_346_207_417;

/// Radon's 7-point degree-5 rule.
const DEGREE5: [TrianglePoint; 7] = join::<1, 6, 7>(
    [TrianglePoint {
        xi: [1.0 / 3.0, 1.0 / 3.0],
        weight: 0.5 * 9.0 / 40.0,
    }],
    join::<3, 3, 6>(
        orbit3((6.0 - SQRT15) / 21.0, 0.5 * (155.0 - SQRT15) / 1200.0),
        orbit3((6.0 + SQRT15) / 21.0, 0.5 * (155.0 + SQRT15) / 1200.0),
    ),
);

impl TriangleRule {
    /// The points and weights of the rule.
    #[inline]
    pub fn points(self) -> &'static [TrianglePoint] {
        match self {
            TriangleRule::Degree2 => &DEGREE2,
            TriangleRule::Degree4 => &DEGREE4,
            TriangleRule::Degree5 => &DEGREE5,
        }
    }

    /// The polynomial degree integrated exactly.
    pub fn degree(self) -> usize {
        match self {
            TriangleRule::Degree2 => 2,
            TriangleRule::Degree4 => 4,
            TriangleRule::Degree5 => 5,
        }
    }
}

/// Gauss–Legendre rules on `[−1, 1]` with 1 to 4 points (exact to degree
/// `2n − 1`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GaussLegendre {
    /// 1 point (degree 1).
    One,
    /// 2 points (degree 3).
    Two,
    /// 3 points (degree 5).
    Three,
    /// 4 points (degree 7).
    Four,
}

impl GaussLegendre {
    /// All rules, fewest points first.
    pub const ALL: [GaussLegendre; 4] = [
        GaussLegendre::One,
        GaussLegendre::Two,
        GaussLegendre::Three,
        GaussLegendre::Four,
    ];

    /// Number of points.
    pub fn n(self) -> usize {
        match self {
            GaussLegendre::One => 1,
            GaussLegendre::Two => 2,
            GaussLegendre::Three => 3,
            GaussLegendre::Four => 4,
        }
    }

    /// Points and weights `(s, w)`.
    pub fn points(self) -> &'static [(f64, f64)] {
        gauss_legendre_table(self)
    }
}

fn gauss_legendre_table(rule: GaussLegendre) -> &'static [(f64, f64)] {
    const G1: [(f64, f64); 1] = [(0.0, 2.0)];
    const G2: [(f64, f64); 2] = [
        (-0.577_350_269_189_625_8, 1.0),
        (0.577_350_269_189_625_8, 1.0),
    ];
    const G3: [(f64, f64); 3] = [
        (-0.774_596_669_241_483_4, 5.0 / 9.0),
        (0.0, 8.0 / 9.0),
        (0.774_596_669_241_483_4, 5.0 / 9.0),
    ];
    const G4: [(f64, f64); 4] = [
        (-0.861_136_311_594_052_6, 0.347_854_845_137_453_85),
        (-0.339_981_043_584_856_26, 0.652_145_154_862_546_1),
        (0.339_981_043_584_856_26, 0.652_145_154_862_546_1),
        (0.861_136_311_594_052_6, 0.347_854_845_137_453_85),
    ];
    match rule {
        GaussLegendre::One => &G1,
        GaussLegendre::Two => &G2,
        GaussLegendre::Three => &G3,
        GaussLegendre::Four => &G4,
    }
}

#[cfg(test)]
mod tests {
    //! Goal: every rule integrates all monomials ξ^a η^b of its degree exactly
    //! (∫_T̂ ξ^a η^b = a! b! / (a + b + 2)!) and fails at some monomial of
    //! the next degree (so the stated degree is the true one).
    use super::*;

    fn factorial(n: usize) -> f64 {
        (1..=n).map(|k| k as f64).product()
    }

    fn exact(a: usize, b: usize) -> f64 {
        factorial(a) * factorial(b) / factorial(a + b + 2)
    }

    fn integrate(rule: TriangleRule, a: usize, b: usize) -> f64 {
        rule.points()
            .iter()
            .map(|p| p.weight * p.xi[0].powi(a as i32) * p.xi[1].powi(b as i32))
            .sum()
    }

    #[test]
    fn triangle_rules_are_exact_to_their_degree_and_not_beyond() {
        for rule in [
            TriangleRule::Degree2,
            TriangleRule::Degree4,
            TriangleRule::Degree5,
        ] {
            let d = rule.degree();
            for total in 0..=d {
                for a in 0..=total {
                    let (q, e) = (integrate(rule, a, total - a), exact(a, total - a));
                    assert!(
                        (q - e).abs() < 1e-15,
                        "{rule:?}: ξ^{a} η^{} gives {q}, exact {e}",
                        total - a
                    );
                }
            }
            let worst = (0..=d + 1)
                .map(|a| (integrate(rule, a, d + 1 - a) - exact(a, d + 1 - a)).abs())
                .fold(0.0, f64::max);
            assert!(worst > 1e-6, "{rule:?} is exact beyond degree {d}");
            for p in rule.points() {
                assert!(p.weight > 0.0 && p.xi[0] > 0.0 && p.xi[1] > 0.0);
                assert!(p.xi[0] + p.xi[1] < 1.0);
            }
        }
    }

    #[test]
    fn gauss_legendre_is_exact_to_degree_2n_minus_1() {
        for rule in GaussLegendre::ALL {
            let n = rule.n();
            for k in 0..2 * n {
                let q: f64 = rule
                    .points()
                    .iter()
                    .map(|(x, w)| w * x.powi(k as i32))
                    .sum();
                let e = if k % 2 == 0 {
                    2.0 / (k as f64 + 1.0)
                } else {
                    0.0
                };
                assert!((q - e).abs() < 1e-15, "n = {n}, x^{k}: {q} vs {e}");
            }
            let k = 2 * n;
            let q: f64 = rule
                .points()
                .iter()
                .map(|(x, w)| w * x.powi(k as i32))
                .sum();
            assert!((q - 2.0 / (k as f64 + 1.0)).abs() > 1e-6);
        }
    }
}
