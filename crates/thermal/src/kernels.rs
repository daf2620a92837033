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
use tecon_fem::triangle::{
    TriangleGeometry, consistent_mass, laplace_matrix, lumped_mass,
};
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
