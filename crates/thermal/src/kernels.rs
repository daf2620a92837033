//! Element kernels of heat conduction, as [`tecon_fem::Element`] sets.
//!
//! Each kernel is a pure function of the element's coordinates and
//! properties, built on the shared geometry of `tecon-fem`:
//!
//! * conduction `K_e = ∫ k ∇N ∇Nᵀ dA = k A (b bᵀ + c cᵀ)/(4A²)`
//!   ([`tecon_fem::triangle::laplace_matrix`]),
//! * capacity `C_e = ∫ ρc N Nᵀ dA` consistent `ρcA/12 [2 1 1; 1 2 1; 1 1 2]`
//!   or lumped `ρcA/3 I`,
//! * convective edge `K_e = hL/6 [2 1; 1 2]`, `f_e = h T∞ L/2 [1 1]`,
//! * thermal interface `K_e = Σ_p w_p h_c(s_p) b_p b_pᵀ`, `b = [−N₁, −N₂, N₂, N₁]`
//!   from [`tecon_fem::interface::InterfaceGeometry`]; with the nodal rule
//!   this is `h_c L/2` per facing pair, with Gauss the consistent `h_c L/6`
//!   pattern.

use nalgebra::{Matrix2, Matrix4, SVector, Vector2};
use tecon_fem::interface::{InterfaceGeometry, InterfaceQuadrature};
use tecon_fem::triangle::{TriangleGeometry, consistent_mass, laplace_matrix, lumped_mass};
use tecon_fem::{Element, LocalSystem};

use crate::material::CapacityKind;

/// Geometry of a triangle computed from coordinates relative to its first
/// vertex (keeps the gradients accurate far from the origin).
#[inline]
pub(crate) fn triangle_geometry(nodes: &[[f64; 2]], t: [usize; 3]) -> TriangleGeometry {
    let o = nodes[t[0]];
    let rel = |p: [f64; 2]| [p[0] - o[0], p[1] - o[1]];
    TriangleGeometry::new([[0.0, 0.0], rel(nodes[t[1]]), rel(nodes[t[2]])])
}

/// Conduction matrices of linear triangles with a conductivity per element.
pub(crate) struct ConductionElements<'a> {
    pub nodes: &'a [[f64; 2]],
    pub triangles: &'a [[usize; 3]],
    pub conductivity: &'a [f64],
}

impl Element<3> for ConductionElements<'_> {
    fn n_elements(&self) -> usize {
        self.triangles.len()
    }
    fn dofs(&self, e: usize) -> [usize; 3] {
        self.triangles[e]
    }
    fn local(&self, e: usize) -> LocalSystem<3> {
        let g = triangle_geometry(self.nodes, self.triangles[e]);
        LocalSystem {
            matrix: laplace_matrix(&g, self.conductivity[e]),
            vector: SVector::zeros(),
        }
    }
}

/// Capacity matrices of linear triangles with ρc per element.
pub(crate) struct CapacityElements<'a> {
    pub nodes: &'a [[f64; 2]],
    pub triangles: &'a [[usize; 3]],
    pub rho_c: &'a [f64],
    pub kind: CapacityKind,
}

impl Element<3> for CapacityElements<'_> {
    fn n_elements(&self) -> usize {
        self.triangles.len()
    }
    fn dofs(&self, e: usize) -> [usize; 3] {
        self.triangles[e]
    }
    fn local(&self, e: usize) -> LocalSystem<3> {
        let g = triangle_geometry(self.nodes, self.triangles[e]);
        let matrix = match self.kind {
            CapacityKind::Consistent => consistent_mass(&g, self.rho_c[e]),
            CapacityKind::Lumped => lumped_mass(&g, self.rho_c[e]),
        };
        LocalSystem {
            matrix,
            vector: SVector::zeros(),
        }
    }
}

/// Convective edges: film coefficient h and ambient T∞ per edge.
#[derive(Debug, Clone, Default)]
pub(crate) struct ConvectionEdges {
    pub edges: Vec<[usize; 2]>,
    pub length: Vec<f64>,
    pub h: Vec<f64>,
    pub ambient: Vec<f64>,
}

/// `K_e = hL/6 [2 1; 1 2]`, `f_e = h T∞ L/2 [1, 1]`.
#[inline]
pub fn convection_edge(h: f64, ambient: f64, length: f64) -> LocalSystem<2> {
    let s = h * length / 6.0;
    let f = 0.5 * h * ambient * length;
    LocalSystem {
        matrix: Matrix2::new(2.0 * s, s, s, 2.0 * s),
        vector: Vector2::new(f, f),
    }
}

impl Element<2> for ConvectionEdges {
    fn n_elements(&self) -> usize {
        self.edges.len()
    }
    fn dofs(&self, e: usize) -> [usize; 2] {
        self.edges[e]
    }
    fn local(&self, e: usize) -> LocalSystem<2> {
        convection_edge(self.h[e], self.ambient[e], self.length[e])
    }
}

/// `K_e = Σ_p w_p h_c,p b_p b_pᵀ` over the two points of `rule`.
#[inline]
pub fn interface_conductance(
    geometry: &InterfaceGeometry,
    rule: InterfaceQuadrature,
    h_c: [f64; 2],
) -> Matrix4<f64> {
    let mut m = Matrix4::zeros();
    for (p, h) in geometry.points(rule).iter().zip(h_c) {
        let b = p.jump_operator();
        m += (b * b.transpose()) * (p.weight * h);
    }
    m
}

/// Thermal interface elements of all interfaces, flattened.
#[derive(Debug, Clone, Default)]
pub(crate) struct InterfaceElements {
    pub nodes: Vec<[usize; 4]>,
    pub geometry: Vec<InterfaceGeometry>,
    pub rule: Vec<InterfaceQuadrature>,
    /// h_c at the two integration points.
    pub h_c: Vec<[f64; 2]>,
}

impl Element<4> for InterfaceElements {
    fn n_elements(&self) -> usize {
        self.nodes.len()
    }
    fn dofs(&self, e: usize) -> [usize; 4] {
        self.nodes[e]
    }
    fn local(&self, e: usize) -> LocalSystem<4> {
        LocalSystem {
            matrix: interface_conductance(&self.geometry[e], self.rule[e], self.h_c[e]),
            vector: SVector::zeros(),
        }
    }
}

#[cfg(test)]
mod tests {
    //! Reference: DESIGN.md §2 "Heat conduction" (element formulas).
    //! Goal: the kernels equal the closed forms, conserve heat (row sums)
    //! and the interface kernel is the shared geometry's Gram matrix × h_c.
    use super::*;
    use approx::assert_relative_eq;
    use nalgebra::Point2;

    #[test]
    fn conduction_rows_sum_to_zero_and_match_the_formula() {
        let nodes = [[1000.0, 2000.0], [1000.3, 2000.1], [1000.05, 2000.4]];
        let g = triangle_geometry(&nodes, [0, 1, 2]);
        let k = laplace_matrix(&g, 63.9);
        for i in 0..3 {
            let s: f64 = (0..3).map(|j| k[(i, j)]).sum();
            assert!(s.abs() < 1e-12 * k[(i, i)].abs(), "row {i} sums to {s}");
        }
        // k A (b bᵀ + c cᵀ)/(4A²) with b, c from the coordinates.
        let p = nodes;
        let b = [p[1][1] - p[2][1], p[2][1] - p[0][1], p[0][1] - p[1][1]];
        let c = [p[2][0] - p[1][0], p[0][0] - p[2][0], p[1][0] - p[0][0]];
        let area = 0.5
            * ((p[1][0] - p[0][0]) * (p[2][1] - p[0][1])
                - (p[2][0] - p[0][0]) * (p[1][1] - p[0][1]));
        for i in 0..3 {
            for j in 0..3 {
                let e = 63.9 * (b[i] * b[j] + c[i] * c[j]) / (4.0 * area);
                assert_relative_eq!(k[(i, j)], e, max_relative = 1e-9);
            }
        }
    }

    #[test]
    fn capacity_totals_are_rho_c_area_for_both_kinds() {
        let nodes = [[0.0, 0.0], [2.0, 0.0], [0.5, 1.5]];
        let tris = [[0usize, 1, 2]];
        for kind in [CapacityKind::Consistent, CapacityKind::Lumped] {
            let set = CapacityElements {
                nodes: &nodes,
                triangles: &tris,
                rho_c: &[7.0],
                kind,
            };
            let m = set.local(0).matrix;
            assert_relative_eq!(m.sum(), 7.0 * 1.5, epsilon = 1e-12);
        }
    }

    #[test]
    fn convection_edge_matches_closed_form() {
        let ls = convection_edge(10.25, 21.0, 0.3);
        let s = 10.25 * 0.3 / 6.0;
        assert_relative_eq!(
            ls.matrix,
            Matrix2::new(2.0 * s, s, s, 2.0 * s),
            epsilon = 1e-15
        );
        assert_relative_eq!(
            ls.vector,
            Vector2::new(1.0, 1.0) * (10.25 * 21.0 * 0.15),
            epsilon = 1e-12
        );
        // K·[T∞, T∞] = f: no heat flows at ambient temperature.
        assert_relative_eq!(
            ls.matrix * Vector2::new(21.0, 21.0),
            ls.vector,
            epsilon = 1e-12
        );
    }

    #[test]
    fn interface_kernel_is_h_c_times_the_jump_gram() {
        let g = InterfaceGeometry::new(&[
            Point2::new(0.0, 0.0),
            Point2::new(0.6, 0.8),
            Point2::new(0.6, 0.8),
            Point2::new(0.0, 0.0),
        ])
        .unwrap();
        for rule in [InterfaceQuadrature::Nodal, InterfaceQuadrature::Gauss2] {
            let k = interface_conductance(&g, rule, [850.0, 850.0]);
            assert_relative_eq!(k, g.jump_gram(rule) * 850.0, epsilon = 1e-10);
            // Rows sum to zero: no heat is created across the interface.
            for i in 0..4 {
                assert!(k.row(i).sum().abs() < 1e-10);
            }
        }
        // Nodal: h_c L/2 per facing pair, point 1 sees pair (1, 4) only.
        let k = interface_conductance(&g, InterfaceQuadrature::Nodal, [2.0, 0.0]);
        assert_relative_eq!(k[(0, 0)], 2.0 * 0.5, epsilon = 1e-14);
        assert_relative_eq!(k[(0, 3)], -2.0 * 0.5, epsilon = 1e-14);
        assert_eq!(k[(1, 1)], 0.0);
    }
}
