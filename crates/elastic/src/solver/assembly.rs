//! Element loops: the bulk triangles (3- and 6-node) and the interface
//! elements (4-node linear and 6-node quadratic: tangent, internal force,
//! point responses), the external force and the residual. Kept apart from
//! the Newton / line-search logic so that other element types plug in here.

use nalgebra::{SMatrix, SVector};
use tecon_contact::{
    ContactStatus, FrictionBound, InterfaceElement, JointState, PointOutput,
    QuadraticInterfaceElement,
};
use tecon_fem::triangle::TriangleGeometry;
use tecon_fem::triangle6::Triangle6;
use tecon_fem::{CsrMatrix, Element, LocalSystem, Parallelism};

use crate::error::ElasticError;
use crate::joint::Joint;
use crate::kernels::{
    P2_RULE, gps_triangle, gps_triangle6, plane_triangle, plane_triangle6, plane_triangle6_load,
};
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

/// The 6-node (P2) bulk triangles. `delta_t` is empty (no temperature
/// change) or holds six values per element, element-major, in the node
/// order of `triangles` (each `T_a − T_ref,e`).
pub(super) struct Bulk6<'a> {
    pub(super) geometry: &'a [Triangle6],
    pub(super) triangles: &'a [[usize; 6]],
    pub(super) materials: &'a [Material],
    pub(super) analysis: Analysis,
    pub(super) delta_t: &'a [f64],
    pub(super) eps_zz: usize,
}

impl Bulk6<'_> {
    #[inline]
    fn element_delta_t(&self, e: usize) -> [f64; 6] {
        self.delta_t
            .get(6 * e..6 * e + 6)
            .map_or([0.0; 6], |s| std::array::from_fn(|a| s[a]))
    }
}

impl Element<12> for Bulk6<'_> {
    fn n_elements(&self) -> usize {
        self.triangles.len()
    }
    #[inline]
    fn dofs(&self, e: usize) -> [usize; 12] {
        PLANE.element_dofs(self.triangles[e])
    }
    #[inline]
    fn local(&self, e: usize) -> LocalSystem<12> {
        let m = &self.materials[e];
        let (matrix, vector) = plane_triangle6(
            &self.geometry[e],
            &self.analysis.d(m),
            self.analysis.in_plane_expansion(m),
            &self.element_delta_t(e),
        );
        LocalSystem { matrix, vector }
    }
    #[inline]
    fn local_vector(&self, e: usize) -> SVector<f64, 12> {
        let m = &self.materials[e];
        plane_triangle6_load(
            &self.geometry[e],
            &self.analysis.d(m),
            self.analysis.in_plane_expansion(m),
            &self.element_delta_t(e),
        )
    }
}

impl Element<13> for Bulk6<'_> {
    fn n_elements(&self) -> usize {
        self.triangles.len()
    }
    #[inline]
    fn dofs(&self, e: usize) -> [usize; 13] {
        let d: [usize; 12] = PLANE.element_dofs(self.triangles[e]);
        std::array::from_fn(|k| if k < 12 { d[k] } else { self.eps_zz })
    }
    #[inline]
    fn local(&self, e: usize) -> LocalSystem<13> {
        let (matrix, vector) = gps_triangle6(
            &self.geometry[e],
            &self.materials[e],
            &self.element_delta_t(e),
        );
        LocalSystem { matrix, vector }
    }
}

/// An interface element kernel of `N` dofs (`N / 2` nodes) and `P`
/// integration points: the linear 4-node element (8, 2) and the quadratic
/// 6-node one (12, 3).
pub(super) trait JointKernel<const N: usize, const P: usize> {
    /// Force, tangent and point outputs (see `InterfaceElement::evaluate`).
    fn respond(
        &self,
        law: &Joint,
        u: &SVector<f64, N>,
        committed: &[JointState; P],
    ) -> (
        SVector<f64, N>,
        SMatrix<f64, N, N>,
        [PointOutput<JointState>; P],
    );
    /// Augmented-Lagrangian update: new states, largest multiplier change.
    fn augment(
        &self,
        law: &Joint,
        u: &SVector<f64, N>,
        states: &[JointState; P],
    ) -> ([JointState; P], f64);
    /// Frozen friction-limit update: new states, largest change.
    fn update_friction(
        &self,
        law: &Joint,
        u: &SVector<f64, N>,
        states: &[JointState; P],
    ) -> ([JointState; P], f64);
    /// Position of point `q` on the bottom face, from the element's node
    /// coordinates (bottom nodes first).
    fn position(&self, q: usize, point: &PointOutput<JointState>, x: &[[f64; 2]]) -> [f64; 2];
}

impl JointKernel<8, 2> for InterfaceElement {
    #[inline]
    fn respond(
        &self,
        law: &Joint,
        u: &SVector<f64, 8>,
        committed: &[JointState; 2],
    ) -> (
        SVector<f64, 8>,
        SMatrix<f64, 8, 8>,
        [PointOutput<JointState>; 2],
    ) {
        let r = self.evaluate(law, u, committed);
        (r.force, r.tangent, r.points)
    }
    fn augment(
        &self,
        law: &Joint,
        u: &SVector<f64, 8>,
        states: &[JointState; 2],
    ) -> ([JointState; 2], f64) {
        InterfaceElement::augment(self, law, u, states)
    }
    fn update_friction(
        &self,
        law: &Joint,
        u: &SVector<f64, 8>,
        states: &[JointState; 2],
    ) -> ([JointState; 2], f64) {
        InterfaceElement::update_friction(self, law, u, states)
    }
    fn position(&self, _q: usize, p: &PointOutput<JointState>, x: &[[f64; 2]]) -> [f64; 2] {
        let s = p.zeta / self.geometry().length() + 0.5;
        [
            x[0][0] + s * (x[1][0] - x[0][0]),
            x[0][1] + s * (x[1][1] - x[0][1]),
        ]
    }
}

impl JointKernel<12, 3> for QuadraticInterfaceElement {
    #[inline]
    fn respond(
        &self,
        law: &Joint,
        u: &SVector<f64, 12>,
        committed: &[JointState; 3],
    ) -> (
        SVector<f64, 12>,
        SMatrix<f64, 12, 12>,
        [PointOutput<JointState>; 3],
    ) {
        let r = self.evaluate(law, u, committed);
        (r.force, r.tangent, r.points)
    }
    fn augment(
        &self,
        law: &Joint,
        u: &SVector<f64, 12>,
        states: &[JointState; 3],
    ) -> ([JointState; 3], f64) {
        QuadraticInterfaceElement::augment(self, law, u, states)
    }
    fn update_friction(
        &self,
        law: &Joint,
        u: &SVector<f64, 12>,
        states: &[JointState; 3],
    ) -> ([JointState; 3], f64) {
        QuadraticInterfaceElement::update_friction(self, law, u, states)
    }
    fn position(&self, q: usize, _p: &PointOutput<JointState>, _x: &[[f64; 2]]) -> [f64; 2] {
        self.geometry().bottom().position(self.points()[q].s)
    }
}

/// One interface's elements of one kernel type, with their nodes (`M`
/// per element, `N = 2M` dofs), at displacements `u` from `committed`
/// states.
pub(super) struct InterfaceSet<'a, K, const M: usize, const P: usize> {
    pub(super) nodes: &'a [[usize; M]],
    pub(super) elements: &'a [K],
    pub(super) law: &'a Joint,
    pub(super) u: &'a [f64],
    pub(super) committed: &'a PointStates,
    /// Reference displacements the jumps are measured from (staging).
    pub(super) reference: Option<&'a [f64]>,
}

impl<K, const M: usize, const P: usize> InterfaceSet<'_, K, M, P> {
    #[inline]
    pub(super) fn local_u<const N: usize>(&self, e: usize) -> SVector<f64, N> {
        local_u(&self.nodes[e], self.u, self.reference)
    }
}

/// Element dof values `u − u_ref` of the nodes `n` (x, y each).
#[inline]
fn local_u<const M: usize, const N: usize>(
    n: &[usize; M],
    u: &[f64],
    reference: Option<&[f64]>,
) -> SVector<f64, N> {
    match reference {
        None => SVector::<f64, N>::from_fn(|i, _| u[2 * n[i / 2] + i % 2]),
        Some(r) => SVector::<f64, N>::from_fn(|i, _| {
            let d = 2 * n[i / 2] + i % 2;
            u[d] - r[d]
        }),
    }
}

impl<K, const M: usize, const N: usize, const P: usize> Element<N> for InterfaceSet<'_, K, M, P>
where
    K: JointKernel<N, P> + Sync,
{
    fn n_elements(&self) -> usize {
        self.nodes.len()
    }
    #[inline]
    fn dofs(&self, e: usize) -> [usize; N] {
        let n = self.nodes[e];
        std::array::from_fn(|i| 2 * n[i / 2] + i % 2)
    }
    #[inline]
    fn local(&self, e: usize) -> LocalSystem<N> {
        let (vector, matrix, _) =
            self.elements[e].respond(self.law, &self.local_u(e), self.committed.element_array(e));
        LocalSystem { matrix, vector }
    }
}

/// Adds one interface set's forces (and tangent, if asked).
fn add_set<K, const M: usize, const N: usize, const P: usize>(
    assembler: &tecon_fem::Assembler,
    block: BlockId,
    set: &InterfaceSet<'_, K, M, P>,
    kt: Option<&mut CsrMatrix>,
    f_int: &mut [f64],
) -> Result<(), ElasticError>
where
    K: JointKernel<N, P> + Sync,
{
    match kt {
        Some(m) => assembler.add::<N, _>(block, set, m, Some(f_int), Parallelism::Rayon)?,
        None => assembler.add_vector::<N, _>(block, set, f_int)?,
    }
    Ok(())
}

/// Point outputs of one interface set, element-major.
fn set_points<K, const M: usize, const N: usize, const P: usize>(
    set: &InterfaceSet<'_, K, M, P>,
    out: &mut Vec<PointOutput<JointState>>,
) where
    K: JointKernel<N, P> + Sync,
{
    for (e, el) in set.elements.iter().enumerate() {
        let (_, _, points) = el.respond(set.law, &set.local_u(e), set.committed.element_array(e));
        out.extend(points);
    }
}

/// Between-passes updates of one interface set (frozen friction limits,
/// augmented-Lagrangian multipliers, as asked by `(frozen, augmented)`)
/// from the jumps at `u − u_ref`: the states are
/// updated in place; returns the largest friction-limit and multiplier
/// changes.
pub(super) fn update_set<K, const M: usize, const N: usize, const P: usize>(
    nodes: &[[usize; M]],
    elements: &[K],
    law: &Joint,
    u: &[f64],
    reference: Option<&[f64]>,
    states: &mut PointStates,
    (frozen, augmented): (bool, bool),
) -> (f64, f64)
where
    K: JointKernel<N, P>,
{
    let (mut friction, mut multiplier): (f64, f64) = (0.0, 0.0);
    for (e, (el, n)) in elements.iter().zip(nodes).enumerate() {
        let ue = local_u::<M, N>(n, u, reference);
        let st = states.element_array_mut::<P>(e);
        if frozen {
            let (new, change) = el.update_friction(law, &ue, st);
            *st = new;
            friction = friction.max(change);
        }
        if augmented {
            let (new, change) = el.augment(law, &ue, st);
            *st = new;
            multiplier = multiplier.max(change);
        }
    }
    (friction, multiplier)
}

impl StaticSolver<'_> {
    /// The outer updates of every interface from the jumps at `u` (see
    /// [`update_set`]): the largest friction-limit and multiplier changes.
    pub(super) fn update_outer(
        &self,
        u: &[f64],
        states: &mut [PointStates],
        flags: (bool, bool),
    ) -> (f64, f64) {
        let (mut friction, mut multiplier): (f64, f64) = (0.0, 0.0);
        for ((itf, law), set) in self
            .model
            .interfaces
            .iter()
            .zip(&self.laws)
            .zip(states.iter_mut())
        {
            let (f, m) = if itf.is_quadratic() {
                update_set(
                    &itf.quadratic_nodes,
                    &itf.quadratic,
                    law,
                    u,
                    itf.reference.as_deref(),
                    set,
                    flags,
                )
            } else {
                update_set(
                    &itf.nodes,
                    &itf.elements,
                    law,
                    u,
                    itf.reference.as_deref(),
                    set,
                    flags,
                )
            };
            friction = friction.max(f);
            multiplier = multiplier.max(m);
        }
        (friction, multiplier)
    }

    pub(super) fn external_force(&self, loads: &Loads) -> Result<Vec<f64>, ElasticError> {
        let mesh = self.model.mesh;
        let mut f = vec![0.0; self.model.n_dofs()];
        let gps = self.model.analysis == Analysis::GeneralisedPlaneStrain;
        let eps_zz = self.model.eps_zz_dof().unwrap_or(0);
        if !loads.delta_t.is_empty() {
            match &self.p2 {
                None => {
                    let set = Bulk {
                        nodes: mesh.nodes(),
                        triangles: mesh.triangles(),
                        materials: &self.materials,
                        analysis: self.model.analysis,
                        delta_t: &loads.delta_t,
                        eps_zz,
                    };
                    if gps {
                        self.assembler.add_vector::<7, _>(self.bulk, &set, &mut f)?;
                    } else {
                        self.assembler.add_vector::<6, _>(self.bulk, &set, &mut f)?;
                    }
                }
                Some(p2) => {
                    let set = p2.bulk(&self.materials, self.model.analysis, &loads.delta_t, eps_zz);
                    if gps {
                        self.assembler
                            .add_vector::<13, _>(self.bulk, &set, &mut f)?;
                    } else {
                        self.assembler
                            .add_vector::<12, _>(self.bulk, &set, &mut f)?;
                    }
                }
            }
        }
        let x = mesh.nodes();
        match &self.p2 {
            None => {
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
            }
            Some(p2) => {
                // Consistent load of a uniform pressure on a (curved) 3-node
                // edge: f_a = ∫ N_a p n_left ds (the traction −p n_out, with
                // the outward normal the right normal of a → b), 3-point
                // Gauss in the isoparametric arc length.
                for (nodes, edge, p) in &p2.pressure {
                    for q in edge.gauss_points(tecon_fem::quadrature::GaussLegendre::Three) {
                        for (k, &v) in nodes.iter().enumerate() {
                            let w = p * q.shape[k] * q.weight * loads.pressure;
                            f[2 * v] += w * q.normal.x;
                            f[2 * v + 1] += w * q.normal.y;
                        }
                    }
                }
            }
        }
        if loads.body_force != 0.0 {
            for (e, t) in mesh.triangles().iter().enumerate() {
                let bf = self.model.body_force[mesh.element_regions()[e]];
                if bf == [0.0; 2] {
                    continue;
                }
                match &self.p2 {
                    None => {
                        let area = TriangleGeometry::new(t.map(|v| x[v])).area;
                        for &v in t {
                            f[2 * v] += bf[0] * area / 3.0 * loads.body_force;
                            f[2 * v + 1] += bf[1] * area / 3.0 * loads.body_force;
                        }
                    }
                    Some(p2) => {
                        // f_a = ∫ N_a b dA
                        let t6 = p2.triangles[e];
                        for q in p2.geometry[e].points(P2_RULE) {
                            for (a, &v) in t6.iter().enumerate() {
                                let w = q.shape[a] * q.weight * loads.body_force;
                                f[2 * v] += bf[0] * w;
                                f[2 * v + 1] += bf[1] * w;
                            }
                        }
                    }
                }
            }
        }
        Ok(f)
    }

    /// Tangent and internal force at `u` from `committed` states.
    pub(super) fn tangent_and_force(
        &self,
        u: &[f64],
        committed: &[PointStates],
        with_matrix: bool,
    ) -> Result<(Option<CsrMatrix>, Vec<f64>), ElasticError> {
        self.tangent_and_force_from(u, &self.bulk_force(u), committed, with_matrix)
    }

    /// The bulk's internal force K u (the bulk is linear).
    pub(super) fn bulk_force(&self, u: &[f64]) -> Vec<f64> {
        let mut ku = vec![0.0; u.len()];
        self.k_bulk.mul_vec(u, &mut ku);
        ku
    }

    /// [`StaticSolver::tangent_and_force`] with the bulk force `ku` = K u
    /// already known (one sparse product less per Newton iteration).
    pub(super) fn tangent_and_force_from(
        &self,
        u: &[f64],
        ku: &[f64],
        committed: &[PointStates],
        with_matrix: bool,
    ) -> Result<(Option<CsrMatrix>, Vec<f64>), ElasticError> {
        let mut f_int = ku.to_vec();
        let mut kt = with_matrix.then(|| self.bulk_copy());
        self.add_interfaces(u, committed, kt.as_mut(), &mut f_int)?;
        Ok((kt, f_int))
    }

    /// A copy of K_bulk, in the storage of a tangent given back by
    /// [`StaticSolver::recycle`] when there is one: a fresh allocation of
    /// the tangent at every Newton iteration cost about 5 % of a two-way
    /// vessel run (the page faults of a new multi-megabyte block and the
    /// copy). A used tangent differs from K_bulk only where the interface
    /// elements added (the interface nodes' rows), where the rotations of
    /// skew supports turned it and where the constraints were applied, so
    /// only those slots are copied back: the whole copy was about 5 % of a
    /// two-way vessel run. Debug builds check that nothing else differs.
    pub(super) fn bulk_copy(&self) -> CsrMatrix {
        let spare = self.spare_tangents.lock().ok().and_then(|mut v| v.pop());
        match spare {
            Some(mut k) => {
                let ptr = self.k_bulk.pattern().indptr();
                let (from, to) = (self.k_bulk.values(), k.values_mut());
                let mut back = |r: std::ops::Range<usize>| {
                    to[r.clone()].copy_from_slice(&from[r]);
                };
                for &i in &self.interface_dofs {
                    back(ptr[i]..ptr[i + 1]);
                }
                self.rotations.for_each_touched(&mut back);
                self.prepared.for_each_touched(&mut back);
                debug_assert!(
                    k.values()
                        .iter()
                        .zip(self.k_bulk.values())
                        .all(|(x, y)| x.to_bits() == y.to_bits()),
                    "a recycled tangent differed from K_bulk outside the slots that the interfaces, rotations and constraints change"
                );
                k
            }
            None => self.k_bulk.clone(),
        }
    }

    /// Gives a tangent's storage back for [`StaticSolver::bulk_copy`] (at
    /// most two are kept; one of another pattern is dropped).
    pub(super) fn recycle(&self, k: CsrMatrix) {
        if std::sync::Arc::ptr_eq(k.pattern(), self.k_bulk.pattern())
            && let Ok(mut v) = self.spare_tangents.lock()
            && v.len() < 2
        {
            v.push(k);
        }
    }

    /// Adds the interface forces at `u` (and their tangent, if asked) to
    /// `f_int` (and `kt`).
    pub(super) fn add_interfaces(
        &self,
        u: &[f64],
        committed: &[PointStates],
        kt: Option<&mut CsrMatrix>,
        f_int: &mut [f64],
    ) -> Result<(), ElasticError> {
        self.add_interfaces_with(&self.laws, u, committed, kt, f_int)
    }

    /// The tangent at `u` with a shear stiffness `weight · k_s` added at
    /// every slipping Mohr–Coulomb point, `K_t + weight (K_stick − K_t)`
    /// (K_stick: every point sticking, the same normal law): the fallback
    /// Newton matrix when the true tangent has lost a body's rigid mode
    /// because every joint point holding the body slips (frozen limits
    /// give slipping points no shear stiffness) or is open. Positive
    /// definite wherever closed points hold the body, so its step is a
    /// descent direction of the energy; the residual and the line search
    /// stay on the true law, so the converged answer does not depend on it.
    pub(super) fn slip_stabilised_tangent(
        &self,
        u: &[f64],
        committed: &[PointStates],
        weight: f64,
    ) -> Result<CsrMatrix, ElasticError> {
        let mut f = vec![0.0; u.len()];
        let mut kt = self.k_bulk.clone();
        self.add_interfaces_with(&self.laws, u, committed, Some(&mut kt), &mut f)?;
        self.stabilise_slip(kt, u, committed, weight, false)
    }

    /// `kt + weight (K_stick − kt)`, K_stick the tangent at `u` with every
    /// Mohr–Coulomb point sticking (the same normal law; open points stay
    /// without stiffness); `with_limits_only`: only the joints with a slip
    /// limit (a friction coefficient or a cohesion) stick, a frictionless
    /// one keeps its tangent (it holds nothing along its faces).
    fn stabilise_slip(
        &self,
        mut kt: CsrMatrix,
        u: &[f64],
        committed: &[PointStates],
        weight: f64,
        with_limits_only: bool,
    ) -> Result<CsrMatrix, ElasticError> {
        let laws: Vec<Joint> = self
            .laws
            .iter()
            .map(|l| match l {
                Joint::Frictional(m)
                    if !with_limits_only || m.tan_phi() > 0.0 || m.cohesion() > 0.0 =>
                {
                    tecon_contact::ElasticJoint::new(*m.normal_law(), m.k_s())
                        .map(Joint::Sticking)
                        .map_err(|e| FemError::Solver(format!("stick tangent: {e}")).into())
                }
                other => Ok(other.clone()),
            })
            .collect::<Result<_, ElasticError>>()?;
        let mut f = vec![0.0; u.len()];
        let mut stick = self.k_bulk.clone();
        self.add_interfaces_with(&laws, u, committed, Some(&mut stick), &mut f)?;
        for (a, b) in kt.values_mut().iter_mut().zip(stick.values()) {
            *a += weight * (b - *a);
        }
        Ok(kt)
    }

    /// The frozen limits' tangent with the weak shear stiffness
    /// `weight · k_s` at every slipping point of a joint with a slip limit
    /// (a frictionless joint holds nothing along its faces; see
    /// [`StaticSolver::slip_stabilised_tangent`]): what the held check
    /// looks at once the plain tangent has lost a rigid mode (see
    /// `StaticSolver::check_held_or_sliding`).
    pub(super) fn sliding_held_tangent(
        &self,
        u: &[f64],
        committed: &[PointStates],
        weight: f64,
    ) -> Result<CsrMatrix, ElasticError> {
        let frozen = self.frozen_tangent(u, committed)?;
        self.stabilise_slip(frozen, u, committed, weight, true)
    }

    /// The tangent with every frictional law's slip limit frozen at its
    /// stored pressure (symmetric), whatever the options' bound.
    pub(super) fn frozen_tangent(
        &self,
        u: &[f64],
        committed: &[PointStates],
    ) -> Result<CsrMatrix, ElasticError> {
        let laws: Vec<Joint> = self
            .laws
            .iter()
            .map(|j| j.with_friction_bound(FrictionBound::Frozen))
            .collect();
        let mut f = vec![0.0; u.len()];
        let mut kt = self.k_bulk.clone();
        self.add_interfaces_with(&laws, u, committed, Some(&mut kt), &mut f)?;
        Ok(kt)
    }

    pub(super) fn add_interfaces_with(
        &self,
        laws: &[Joint],
        u: &[f64],
        committed: &[PointStates],
        mut kt: Option<&mut CsrMatrix>,
        f_int: &mut [f64],
    ) -> Result<(), ElasticError> {
        for (k, itf) in self.model.interfaces.iter().enumerate() {
            let block = self.interface_blocks[k];
            let law = &laws[k];
            if itf.is_quadratic() {
                let set = InterfaceSet::<_, 6, 3> {
                    nodes: &itf.quadratic_nodes,
                    elements: &itf.quadratic,
                    law,
                    u,
                    committed: &committed[k],
                    reference: itf.reference.as_deref(),
                };
                add_set(&self.assembler, block, &set, kt.as_deref_mut(), f_int)?;
            } else {
                let set = InterfaceSet::<_, 4, 2> {
                    nodes: &itf.nodes,
                    elements: &itf.elements,
                    law,
                    u,
                    committed: &committed[k],
                    reference: itf.reference.as_deref(),
                };
                add_set(&self.assembler, block, &set, kt.as_deref_mut(), f_int)?;
            }
        }
        Ok(())
    }

    /// Point outputs of every interface at `u` from `committed` states:
    /// per interface, element-major (`PointStates::per_element` points per
    /// element).
    pub(super) fn point_outputs(
        &self,
        u: &[f64],
        committed: &[PointStates],
    ) -> Vec<Vec<PointOutput<JointState>>> {
        self.model
            .interfaces
            .iter()
            .zip(&self.laws)
            .zip(committed)
            .map(|((itf, law), states)| {
                let mut out = Vec::with_capacity(states.as_slice().len());
                if itf.is_quadratic() {
                    let set = InterfaceSet::<_, 6, 3> {
                        nodes: &itf.quadratic_nodes,
                        elements: &itf.quadratic,
                        law,
                        u,
                        committed: states,
                        reference: itf.reference.as_deref(),
                    };
                    set_points(&set, &mut out);
                } else {
                    let set = InterfaceSet::<_, 4, 2> {
                        nodes: &itf.nodes,
                        elements: &itf.elements,
                        law,
                        u,
                        committed: states,
                        reference: itf.reference.as_deref(),
                    };
                    set_points(&set, &mut out);
                }
                out
            })
            .collect()
    }

    /// Status (with the slip direction) and traction magnitude |τ| + |σ| of
    /// every interface point.
    pub(super) fn statuses(&self, u: &[f64], committed: &[PointStates]) -> Vec<(PointStatus, f64)> {
        self.point_outputs(u, committed)
            .iter()
            .zip(committed)
            .flat_map(|(points, old)| points.iter().zip(old.as_slice()))
            .map(|(p, c)| {
                let sliding = match p.status {
                    ContactStatus::Slip => true,
                    // an open point under a frozen friction limit that slides
                    // on it (free sliding carries no traction)
                    ContactStatus::Open => p.traction.x != 0.0 && p.state.slip != c.slip,
                    ContactStatus::Stick => false,
                };
                let direction = match (sliding, p.traction.x < 0.0) {
                    (false, _) => 0,
                    (true, true) => -1,
                    (true, false) => 1,
                };
                (
                    (p.status, direction),
                    p.traction.x.abs() + p.traction.y.abs(),
                )
            })
            .collect()
    }

    pub(super) fn trial_states(&self, u: &[f64], committed: &[PointStates]) -> States {
        self.point_outputs(u, committed)
            .iter()
            .zip(committed)
            .map(|(points, old)| {
                PointStates::from_flat(old.per_element(), points.iter().map(|p| p.state).collect())
            })
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
        for (k, (itf, points)) in self
            .model
            .interfaces
            .iter()
            .zip(self.point_outputs(u, committed))
            .enumerate()
        {
            let per = committed[k].per_element();
            for (i, p) in points.iter().enumerate() {
                let (e, q) = (i / per, i % per);
                let position = if itf.is_quadratic() {
                    let n = itf.quadratic_nodes[e];
                    itf.quadratic[e].position(q, p, &[x[n[0]], x[n[1]]])
                } else {
                    let n = itf.nodes[e];
                    itf.elements[e].position(q, p, &[x[n[0]], x[n[1]]])
                };
                out.push(InterfacePointResult {
                    interface: k,
                    element: e,
                    point: q,
                    position,
                    jump: [p.jump.x, p.jump.y],
                    traction: [p.traction.x, p.traction.y],
                    status: p.status,
                    slip: p.slip,
                    debonded: p.state.cohesion_lost,
                });
            }
        }
        out
    }
}
