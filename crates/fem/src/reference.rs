//! Reference element sets with one constant material: the Laplace (3×3) and
//! plane-strain (6×6) kernels over a list of triangles. Used by benchmarks,
//! verification tests and examples; the physics crates have their own,
//! richer element sets.

use nalgebra::{Matrix3, SVector};

use crate::assembler::{Element, LocalSystem};
use crate::triangle::{TriangleGeometry, elasticity_stiffness, laplace_matrix};

/// −∇·(k∇u) = s on linear triangles: matrix k∫∇N∇Nᵀ, vector s A/3.
#[derive(Debug, Clone, Copy)]
pub struct LaplaceSet<'a> {
    /// Node coordinates.
    pub nodes: &'a [[f64; 2]],
    /// Counter-clockwise triangles.
    pub triangles: &'a [[usize; 3]],
    /// Conductivity.
    pub k: f64,
    /// Uniform source.
    pub source: f64,
}

impl Element<3> for LaplaceSet<'_> {
    fn n_elements(&self) -> usize {
        self.triangles.len()
    }
    #[inline]
    fn dofs(&self, e: usize) -> [usize; 3] {
        self.triangles[e]
    }
    #[inline]
    fn local(&self, e: usize) -> LocalSystem<3> {
        let g = TriangleGeometry::new(self.triangles[e].map(|v| self.nodes[v]));
        LocalSystem {
            matrix: laplace_matrix(&g, self.k),
            vector: SVector::<f64, 3>::repeat(self.source * g.area / 3.0),
        }
    }
}

/// Plane elasticity with a constant D on linear triangles (dofs node·2 + c).
#[derive(Debug, Clone, Copy)]
pub struct ElasticSet<'a> {
    /// Node coordinates.
    pub nodes: &'a [[f64; 2]],
    /// Counter-clockwise triangles.
    pub triangles: &'a [[usize; 3]],
    /// Elasticity matrix.
    pub d: Matrix3<f64>,
}

impl Element<6> for ElasticSet<'_> {
    fn n_elements(&self) -> usize {
        self.triangles.len()
    }
    #[inline]
    fn dofs(&self, e: usize) -> [usize; 6] {
        crate::DofMap::new(0, 2).element_dofs(self.triangles[e])
    }
    #[inline]
    fn local(&self, e: usize) -> LocalSystem<6> {
        let g = TriangleGeometry::new(self.triangles[e].map(|v| self.nodes[v]));
        LocalSystem {
            matrix: elasticity_stiffness(&g, &self.d),
            vector: SVector::zeros(),
        }
    }
}
