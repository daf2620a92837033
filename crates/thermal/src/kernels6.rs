//! Element kernels of heat conduction on quadratic (P2) elements, as
//! [`tecon_fem::Element`] sets.
//!
//! * conduction `K_e = ∫ k ∇N ∇Nᵀ dA` on the 6-node isoparametric triangle
//!   ([`tecon_fem::triangle6::Triangle6::laplace_matrix`], degree-4 rule),
//! * capacity `C_e = ∫ ρc N Nᵀ dA` consistent, or lumped by HRZ diagonal
//!   scaling (positive: `A/19` at corners, `16A/57` at mid nodes of a
//!   straight element; row sums would give zero corner capacities),
//! * convective 3-node edge `K_e = ∫ h N Nᵀ ds`, `f_e = ∫ h T∞ N ds` with the
//!   isoparametric arc length ([`tecon_fem::edge3::Edge3`]),
//! * thermal 3-pair interface `K_e = Σ_p w_p h_c,p b_p b_pᵀ`,
//!   `b = [−N₁, −N₂, N₂, N₁, −N₅, N₅]`
//!   ([`tecon_fem::interface3::Interface3Geometry`]): with the nodal rule
//!   `h_c L/6, 4L/6, L/6` per facing pair on a straight face.
//!
//! Node order of a triangle: corners 0, 1, 2, then the mid nodes of edges
//! (0,1), (1,2), (2,0). Edge order `[a, b, mid]`. Interface order
//! `[1, 2, 3, 4, 5, 6]` (corners as for the 4-node element, then the
//! bottom and top mid nodes).

use nalgebra::{Matrix3, SVector};
use tecon_fem::edge3::Edge3;
use tecon_fem::interface::InterfaceQuadrature;
use tecon_fem::interface3::{Interface3Geometry, Matrix6 as InterfaceMatrix6};
use tecon_fem::quadrature::TriangleRule;
use tecon_fem::triangle6::Triangle6;
use tecon_fem::{Element, LocalSystem};

use crate::material::CapacityKind;

/// Rule used by the P2 conduction and capacity kernels (exact for the
/// capacity of a straight element; O(h⁴) on curved ones).
pub const RULE: TriangleRule = TriangleRule::Degree4;

/// Conduction matrices of 6-node triangles, one conductivity per element;
/// the geometry is checked once by whoever builds the set.
#[derive(Debug, Clone, Copy)]
pub struct Conduction6Elements<'a> {
    /// Element geometries.
    pub geometry: &'a [Triangle6],
    /// Node numbers per element.
    pub triangles: &'a [[usize; 6]],
    /// k per element (W/(m K)).
    pub conductivity: &'a [f64],
}

impl Element<6> for Conduction6Elements<'_> {
    fn n_elements(&self) -> usize {
        self.triangles.len()
    }
    fn dofs(&self, e: usize) -> [usize; 6] {
        self.triangles[e]
    }
    fn local(&self, e: usize) -> LocalSystem<6> {
        LocalSystem {
            matrix: self.geometry[e].laplace_matrix(self.conductivity[e], RULE),
            vector: SVector::zeros(),
        }
    }
}

/// Capacity matrices of 6-node triangles with ρc per element.
#[derive(Debug, Clone, Copy)]
pub struct Capacity6Elements<'a> {
    /// Element geometries.
    pub geometry: &'a [Triangle6],
    /// Node numbers per element.
    pub triangles: &'a [[usize; 6]],
    /// ρc per element (J/(m³ K)).
    pub rho_c: &'a [f64],
    /// Consistent, or lumped (HRZ).
    pub kind: CapacityKind,
}

impl Element<6> for Capacity6Elements<'_> {
    fn n_elements(&self) -> usize {
        self.triangles.len()
    }
    fn dofs(&self, e: usize) -> [usize; 6] {
        self.triangles[e]
    }
    fn local(&self, e: usize) -> LocalSystem<6> {
        let g = &self.geometry[e];
        let matrix = match self.kind {
            CapacityKind::Consistent => g.mass_matrix(self.rho_c[e], RULE),
            CapacityKind::Lumped => g.lumped_mass_hrz(self.rho_c[e], RULE),
        };
        LocalSystem {
            matrix,
            vector: SVector::zeros(),
        }
    }
}

/// `K_e = ∫ h N Nᵀ ds`, `f_e = ∫ h T∞ N ds` on a 3-node edge `[a, b, mid]`.
#[inline]
pub fn convection_edge3(edge: &Edge3, h: f64, ambient: f64) -> LocalSystem<3> {
    LocalSystem {
        matrix: edge.mass_matrix(h),
        vector: edge.load_vector(h * ambient),
    }
}

/// Convective 3-node edges: film coefficient h and ambient T∞ per edge.
#[derive(Debug, Clone, Default)]
pub struct Convection3Edges {
    /// Nodes `[a, b, mid]` per edge.
    pub edges: Vec<[usize; 3]>,
    /// Edge geometry.
    pub geometry: Vec<Edge3>,
    /// Film coefficient h (W/(m² K)).
    pub h: Vec<f64>,
    /// Ambient temperature T∞.
    pub ambient: Vec<f64>,
}

impl Element<3> for Convection3Edges {
    fn n_elements(&self) -> usize {
        self.edges.len()
    }
    fn dofs(&self, e: usize) -> [usize; 3] {
        self.edges[e]
    }
    fn local(&self, e: usize) -> LocalSystem<3> {
        convection_edge3(&self.geometry[e], self.h[e], self.ambient[e])
    }
}

/// `K_e = Σ_p w_p h_c,p b_p b_pᵀ` over the three points of `rule`.
#[inline]
pub fn interface3_conductance(
    geometry: &Interface3Geometry,
    rule: InterfaceQuadrature,
    h_c: [f64; 3],
) -> InterfaceMatrix6 {
    let mut m = InterfaceMatrix6::zeros();
    for (p, h) in geometry.points(rule).iter().zip(h_c) {
        let b = p.jump_operator();
        m += b * b.transpose() * (p.weight * h);
    }
    m
}

/// Thermal 3-pair interface elements, flattened over interfaces.
#[derive(Debug, Clone, Default)]
pub struct Interface3Elements {
    /// Nodes `[1, 2, 3, 4, 5, 6]` per element.
    pub nodes: Vec<[usize; 6]>,
    /// Geometry per element.
    pub geometry: Vec<Interface3Geometry>,
    /// Integration rule per element.
    pub rule: Vec<InterfaceQuadrature>,
    /// h_c at the three integration points.
    pub h_c: Vec<[f64; 3]>,
}

impl Element<6> for Interface3Elements {
    fn n_elements(&self) -> usize {
        self.nodes.len()
    }
    fn dofs(&self, e: usize) -> [usize; 6] {
        self.nodes[e]
    }
    fn local(&self, e: usize) -> LocalSystem<6> {
        LocalSystem {
            matrix: interface3_conductance(&self.geometry[e], self.rule[e], self.h_c[e]),
            vector: SVector::zeros(),
        }
    }
}

/// Convective weights of a 3-node edge for the heat balance: `∫ h N ds`
/// per node (the column sums of `K_e`), order `[a, b, mid]`.
pub fn convective_weights3(edge: &Edge3, h: f64) -> [f64; 3] {
    let m: Matrix3<f64> = edge.mass_matrix(h);
    [0, 1, 2].map(|j| m.column(j).sum())
}

#[cfg(test)]
mod tests {
    //! Goal: the P2 kernels conserve heat (rows of conduction and
    //! interface matrices sum to zero, capacities sum to ρcA), lumping
    //! stays positive, and convection at ambient temperature carries no heat.
    use super::*;
    use nalgebra::Point2;

    fn straight(p: [[f64; 2]; 3]) -> [[f64; 2]; 6] {
        let m = |a: [f64; 2], b: [f64; 2]| [0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])];
        [
            p[0],
            p[1],
            p[2],
            m(p[0], p[1]),
            m(p[1], p[2]),
            m(p[2], p[0]),
        ]
    }

    #[test]
    fn conduction_and_capacity_conserve_heat_and_lumping_is_positive() {
        let mut x = straight([[0.0, 0.0], [0.3, 0.05], [0.1, 0.4]]);
        x[4] = [0.23, 0.26]; // curved edge (1,2)
        let g = [Triangle6::new(x).unwrap()];
        let tri = [[0usize, 1, 2, 3, 4, 5]];
        let k = Conduction6Elements {
            geometry: &g,
            triangles: &tri,
            conductivity: &[45.0],
        }
        .local(0)
        .matrix;
        for i in 0..6 {
            assert!(k.row(i).sum().abs() < 1e-12 * k[(i, i)]);
        }
        for kind in [CapacityKind::Consistent, CapacityKind::Lumped] {
            let c = Capacity6Elements {
                geometry: &g,
                triangles: &tri,
                rho_c: &[3.6e6],
                kind,
            }
            .local(0)
            .matrix;
            assert!((c.sum() - 3.6e6 * g[0].area()).abs() < 1e-9 * c.sum());
            if kind == CapacityKind::Lumped {
                assert!((0..6).all(|a| c[(a, a)] > 0.0));
            }
        }
    }

    #[test]
    fn convection_at_ambient_carries_no_heat_and_interface_rows_vanish() {
        let e = Edge3::new([[1.0, 0.0], [0.0, 1.0], [0.7, 0.7]]).unwrap();
        let ls = convection_edge3(&e, 10.25, 21.0);
        let r = ls.matrix * nalgebra::Vector3::repeat(21.0) - ls.vector;
        assert!(r.amax() < 1e-12);
        let w = convective_weights3(&e, 10.25);
        // The weights sum to h times the arc length of the rule (3-point
        // Gauss, the rule of K and f, so K·1 = f/T∞ exactly), which on this
        // curved edge is within 1e-3 of the 4-point length.
        let len3: f64 = e
            .gauss_points(tecon_fem::quadrature::GaussLegendre::Three)
            .map(|p| p.weight)
            .sum();
        assert!((w.iter().sum::<f64>() - 10.25 * len3).abs() < 1e-12);
        assert!((len3 - e.length()).abs() < 1e-3 * e.length());
        let p = |x: f64, y: f64| Point2::new(x, y);
        let g = Interface3Geometry::new(&[
            p(0.0, 0.0),
            p(1.0, 0.0),
            p(1.0, 0.0),
            p(0.0, 0.0),
            p(0.5, 0.0),
            p(0.5, 0.0),
        ])
        .unwrap();
        for rule in [InterfaceQuadrature::Nodal, InterfaceQuadrature::Gauss2] {
            let k = interface3_conductance(&g, rule, [850.0; 3]);
            assert!((k - g.jump_gram(rule) * 850.0).amax() < 1e-10);
            for i in 0..6 {
                assert!(k.row(i).sum().abs() < 1e-10);
            }
        }
        // Nodal: 850 · L/6 between nodes 1 and 4, 850 · 4L/6 between 5 and 6.
        let k = interface3_conductance(&g, InterfaceQuadrature::Nodal, [850.0; 3]);
        assert!((k[(0, 3)] + 850.0 / 6.0).abs() < 1e-10);
        assert!((k[(4, 5)] + 850.0 * 4.0 / 6.0).abs() < 1e-10);
    }
}
