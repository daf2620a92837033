//! Element loops: the bulk triangles and the interface elements (tangent,
//! internal force, point responses), the external force and the residual.
//! Kept apart from the Newton / line-search logic so that other element
//! types plug in here.

use tecon_contact::{ContactStatus, ElementResponse, InterfaceElement, JointState, Vector8};
use tecon_fem::triangle::TriangleGeometry;
use tecon_fem::{CsrMatrix, Element, LocalSystem, Parallelism};

use crate::error::ElasticError;
use crate::joint::Joint;
use crate::kernels::{gps_triangle, plane_triangle};
use crate::material::{Analysis, Material};

use super::*;

pub(super) struct Bulk<'a> {
    pub(super) nodes: &'a [[f64; 2]],
    pub(super) triangles: &'a [[usize; 3]],
    pub(super) materials: &'a [Material],
    pub(super) analysis: Analysis,
    pub(super) delta_t: &'a [f64],
    pub(super) eps_zz: usize,
}

impl Element<6> for Bulk<'_> {
    fn n_elements(&self) -> usize {
        self.triangles.len()
    }
    #[inline]
    fn dofs(&self, e: usize) -> [usize; 6] {
        PLANE.element_dofs(self.triangles[e])
    }
    #[inline]
    fn local(&self, e: usize) -> LocalSystem<6> {
        let g = TriangleGeometry::new(self.triangles[e].map(|v| self.nodes[v]));
        let m = &self.materials[e];
        let dt = self.delta_t.get(e).copied().unwrap_or(0.0);
        let (matrix, vector) = plane_triangle(
            &g,
            &self.analysis.d(m),
            self.analysis.in_plane_expansion(m) * dt,
        );
        LocalSystem { matrix, vector }
    }
}

impl Element<7> for Bulk<'_> {
    fn n_elements(&self) -> usize {
        self.triangles.len()
    }
    #[inline]
    fn dofs(&self, e: usize) -> [usize; 7] {
        let d: [usize; 6] = PLANE.element_dofs(self.triangles[e]);
        [d[0], d[1], d[2], d[3], d[4], d[5], self.eps_zz]
    }
    #[inline]
    fn local(&self, e: usize) -> LocalSystem<7> {
        let g = TriangleGeometry::new(self.triangles[e].map(|v| self.nodes[v]));
        let dt = self.delta_t.get(e).copied().unwrap_or(0.0);
        let (matrix, vector) = gps_triangle(&g, &self.materials[e], dt);
        LocalSystem { matrix, vector }
    }
}

pub(super) struct InterfaceSet<'a> {
    pub(super) nodes: &'a [[usize; 4]],
    pub(super) elements: &'a [InterfaceElement],
    pub(super) law: &'a Joint,
    pub(super) u: &'a [f64],
    pub(super) committed: &'a PointStates,
    /// Reference displacements the jumps are measured from (staging).
    pub(super) reference: Option<&'a [f64]>,
}

impl InterfaceSet<'_> {
    pub(super) fn local_u(&self, e: usize) -> Vector8 {
        let n = self.nodes[e];
        match self.reference {
            None => Vector8::from_fn(|i, _| self.u[2 * n[i / 2] + i % 2]),
            Some(r) => Vector8::from_fn(|i, _| {
                let d = 2 * n[i / 2] + i % 2;
                self.u[d] - r[d]
            }),
        }
    }
}

impl Element<8> for InterfaceSet<'_> {
    fn n_elements(&self) -> usize {
        self.nodes.len()
    }
    #[inline]
    fn dofs(&self, e: usize) -> [usize; 8] {
        PLANE.element_dofs(self.nodes[e])
    }
    #[inline]
    fn local(&self, e: usize) -> LocalSystem<8> {
        let r =
            self.elements[e].evaluate(self.law, &self.local_u(e), self.committed.element_array(e));
        LocalSystem {
            matrix: r.tangent,
            vector: r.force,
        }
    }
}

impl StaticSolver<'_> {
    pub(super) fn external_force(&self, loads: &Loads) -> Result<Vec<f64>, ElasticError> {
        let mesh = self.model.mesh;
        let mut f = vec![0.0; self.model.n_dofs()];
        if !loads.delta_t.is_empty() {
            let set = Bulk {
                nodes: mesh.nodes(),
                triangles: mesh.triangles(),
                materials: &self.materials,
                analysis: self.model.analysis,
                delta_t: &loads.delta_t,
                eps_zz: self.model.eps_zz_dof().unwrap_or(0),
            };
            if self.model.analysis == Analysis::GeneralisedPlaneStrain {
                self.assembler.add_vector::<7, _>(self.bulk, &set, &mut f)?;
            } else {
                self.assembler.add_vector::<6, _>(self.bulk, &set, &mut f)?;
            }
        }
        let x = mesh.nodes();
        for &([a, b], p) in &self.model.pressure {
            let (dx, dy) = (x[b][0] - x[a][0], x[b][1] - x[a][1]);
            // traction −p n, n L = (dy, −dx); half to each node
            let fx = -0.5 * p * dy * loads.pressure;
            let fy = 0.5 * p * dx * loads.pressure;
            for v in [a, b] {
                f[2 * v] += fx;
                f[2 * v + 1] += fy;
            }
        }
        if loads.body_force != 0.0 {
            for (e, t) in mesh.triangles().iter().enumerate() {
                let bf = self.model.body_force[mesh.element_regions()[e]];
                if bf == [0.0; 2] {
                    continue;
                }
                let area = TriangleGeometry::new(t.map(|v| x[v])).area;
                for &v in t {
                    f[2 * v] += bf[0] * area / 3.0 * loads.body_force;
                    f[2 * v + 1] += bf[1] * area / 3.0 * loads.body_force;
                }
            }
        }
        Ok(f)
    }

    /// Tangent and internal force at `u` from `committed` states; also the statuses.
    pub(super) fn tangent_and_force(
        &self,
        u: &[f64],
        committed: &[PointStates],
        with_matrix: bool,
    ) -> Result<(Option<CsrMatrix>, Vec<f64>), ElasticError> {
        let mut f_int = vec![0.0; u.len()];
        self.k_bulk.mul_vec(u, &mut f_int);
        let mut kt = with_matrix.then(|| self.k_bulk.clone());
        self.add_interfaces(u, committed, kt.as_mut(), &mut f_int)?;
        Ok((kt, f_int))
    }

    /// Adds the interface forces at `u` (and their tangent, if asked) to
    /// `f_int` (and `kt`).
    pub(super) fn add_interfaces(
        &self,
        u: &[f64],
        committed: &[PointStates],
        mut kt: Option<&mut CsrMatrix>,
        f_int: &mut [f64],
    ) -> Result<(), ElasticError> {
        for (k, itf) in self.model.interfaces.iter().enumerate() {
            let set = InterfaceSet {
                nodes: &itf.nodes,
                elements: &itf.elements,
                law: &self.laws[k],
                u,
                committed: &committed[k],
                reference: itf.reference.as_deref(),
            };
            match kt.as_deref_mut() {
                Some(m) => self.assembler.add::<8, _>(
                    self.interface_blocks[k],
                    &set,
                    m,
                    Some(&mut *f_int),
                    Parallelism::Rayon,
                )?,
                None => self
                    .assembler
                    .add_vector::<8, _>(self.interface_blocks[k], &set, f_int)?,
            }
        }
        Ok(())
    }

    /// Element responses of every interface at `u` from `committed` states.
    pub(super) fn responses(
        &self,
        u: &[f64],
        committed: &[PointStates],
    ) -> Vec<Vec<ElementResponse<JointState>>> {
        self.model
            .interfaces
            .iter()
            .zip(&self.laws)
            .zip(committed)
            .map(|((itf, law), states)| {
                itf.elements
                    .iter()
                    .enumerate()
                    .map(|(e, el)| el.evaluate(law, &itf.local_u(e, u), states.element_array(e)))
                    .collect()
            })
            .collect()
    }

    /// Status (with the slip direction) and traction magnitude |τ| + |σ| of
    /// every interface point.
    pub(super) fn statuses(&self, u: &[f64], committed: &[PointStates]) -> Vec<(PointStatus, f64)> {
        self.responses(u, committed)
            .iter()
            .flatten()
            .flat_map(|r| {
                r.points.map(|p| {
                    let backward = p.status == ContactStatus::Slip && p.traction.x < 0.0;
                    (
                        (p.status, backward),
                        p.traction.x.abs() + p.traction.y.abs(),
                    )
                })
            })
            .collect()
    }

    pub(super) fn trial_states(&self, u: &[f64], committed: &[PointStates]) -> States {
        self.responses(u, committed)
            .iter()
            .map(|v| PointStates::from_elements(v.iter().map(|r| r.points.map(|p| p.state))))
            .collect()
    }

    /// Residual in the rotated frame with constrained entries zeroed, and its norm.
    pub(super) fn residual(&self, f_ext: &[f64], f_int: &[f64]) -> Vec<f64> {
        let mut r: Vec<f64> = f_ext.iter().zip(f_int).map(|(a, b)| a - b).collect();
        self.rotations.rotate_vector(&mut r);
        self.prepared.zero(&mut r);
        r
    }

    pub(super) fn point_results(
        &self,
        u: &[f64],
        committed: &[PointStates],
    ) -> Vec<InterfacePointResult> {
        let x = self.model.mesh.nodes();
        let mut out = Vec::new();
        for (k, (itf, responses)) in self
            .model
            .interfaces
            .iter()
            .zip(self.responses(u, committed))
            .enumerate()
        {
            for (e, ((el, n), r)) in itf
                .elements
                .iter()
                .zip(&itf.nodes)
                .zip(&responses)
                .enumerate()
            {
                for (q, p) in r.points.iter().enumerate() {
                    let s = p.zeta / el.geometry().length() + 0.5;
                    let pos = [
                        x[n[0]][0] + s * (x[n[1]][0] - x[n[0]][0]),
                        x[n[0]][1] + s * (x[n[1]][1] - x[n[0]][1]),
                    ];
                    out.push(InterfacePointResult {
                        interface: k,
                        element: e,
                        point: q,
                        position: pos,
                        jump: [p.jump.x, p.jump.y],
                        traction: [p.traction.x, p.traction.y],
                        status: p.status,
                        slip: p.slip,
                    });
                }
            }
        }
        out
    }
}
