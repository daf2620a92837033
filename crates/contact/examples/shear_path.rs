//! # Shear path of one interface element under normal pressure
//!
//! ```text
//! cargo run -p tecon-contact --example shear_path
//! ```
//!
//! One 4-node interface element (L = 0.1 m, horizontal), bottom face fixed.
//! The top face is pressed down by a normal pressure `p` (load controlled:
//! a Newton iteration on its normal displacement finds `σ = −p`) and driven
//! tangentially (displacement controlled) along the path
//!
//! ```text
//!   Δu_t : 0 ──► +s_max ──► −s_max ──► 0        (10 steps per leg)
//! ```
//!
//! through stick, forward slip, unloading (reverse stick), reverse slip and
//! reloading. Law: the paper's joint (smooth Ghaboussi normal law + Mohr–
//! Coulomb) with the default penalty `k_n = k_s = 10 E/h` for steel
//! (E = 207 GPa, h = L), cohesion c = 0.1 MPa, φ = 30°. States are committed
//! after each converged step, as a solver would.
//!
//! Prints the traction path `τ(Δu_t)`: it follows `τ = k_s (Δu_t − g_s)`
//! while sticking and stays on `±(c + p tan φ)` while slipping, and the slip
//! `g_s` left after unloading is permanent.

use tecon_contact::nalgebra::Point2;
use tecon_contact::{
    ContactError, ContactStatus, InterfaceElement, JointState, PaperJoint, Vector8,
};

/// Parameters of the shear path.
#[derive(Clone, Copy, Debug)]
pub struct ShearPath {
    /// Element length L (m).
    pub length: f64,
    /// Young's modulus for the default penalty (Pa).
    pub youngs_modulus: f64,
    /// Normal pressure p (Pa).
    pub pressure: f64,
    /// Cohesion c (Pa).
    pub cohesion: f64,
    /// Friction angle φ (degrees).
    pub friction_deg: f64,
    /// Peak tangential jump, as a multiple of the elastic slip `s/k_s`.
    pub peak_over_elastic: f64,
    /// Steps per leg of the path.
    pub steps_per_leg: usize,
}

impl Default for ShearPath {
    fn default() -> Self {
        Self {
            length: 0.1,
            youngs_modulus: 207.0e9,
            pressure: 2.0e6,
            cohesion: 0.1e6,
            friction_deg: 30.0,
            peak_over_elastic: 5.0,
            steps_per_leg: 10,
        }
    }
}

/// One converged step of the path (values at integration point 1).
#[derive(Clone, Copy, Debug)]
pub struct PathPoint {
    /// Tangential jump Δu_t (m).
    pub du_t: f64,
    /// Shear traction τ (Pa).
    pub tau: f64,
    /// Normal traction σ (Pa).
    pub sigma: f64,
    /// Status.
    pub status: ContactStatus,
    /// Committed state (slip, accumulated slip).
    pub state: JointState,
}

/// The law used by the example.
pub fn law(p: &ShearPath) -> Result<PaperJoint, ContactError> {
    Ok(PaperJoint::with_default_penalty(
        p.youngs_modulus,
        p.length,
        p.cohesion,
        p.friction_deg.to_radians(),
    )?)
}

/// Run the path; one [`PathPoint`] per step (the first is the unsheared,
/// pressed state).
pub fn shear_path(p: &ShearPath) -> Result<Vec<PathPoint>, ContactError> {
    let law = law(p)?;
    let nodes =
        [[0.0, 0.0], [p.length, 0.0], [p.length, 0.0], [0.0, 0.0]].map(|x| Point2::new(x[0], x[1]));
    let element = InterfaceElement::new(&nodes)?;
    let strength = law.strength(-p.pressure);
    let s_max = p.peak_over_elastic * strength / law.k_s();
    let n = p.steps_per_leg.max(1);
    // Tangential path: 0 → +s_max → −s_max → 0.
    let mut targets = vec![0.0];
    targets.extend((1..=n).map(|i| s_max * i as f64 / n as f64));
    targets.extend((1..=2 * n).map(|i| s_max - 2.0 * s_max * i as f64 / (2 * n) as f64));
    targets.extend((1..=n).map(|i| -s_max + s_max * i as f64 / n as f64));

    let mut committed = [JointState::default(); 2];
    // Normal displacement of the top face; start slightly closed so that the
    // first tangent is the contact stiffness (an open joint has none).
    let mut v = -1.0e-3 * p.pressure / law.normal_law().contact_stiffness();
    let mut path = Vec::with_capacity(targets.len());
    for &s in &targets {
        // Newton on v: Σ f_y(top nodes) = −p L (nodal rule, both top nodes
        // move alike; the normal law does not depend on Δu_t).
        let mut r = element.evaluate(&law, &displacement(s, v), &committed);
        for _ in 0..20 {
            let res = r.force[5] + r.force[7] + p.pressure * p.length;
            if res.abs() <= 1e-12 * p.pressure * p.length {
                break;
            }
            let k = r.tangent[(5, 5)] + r.tangent[(5, 7)] + r.tangent[(7, 5)] + r.tangent[(7, 7)];
            v -= res / k;
            r = element.evaluate(&law, &displacement(s, v), &committed);
        }
        committed = r.points.map(|q| q.state);
        let q = r.points[0];
        path.push(PathPoint {
            du_t: q.jump.x,
            tau: q.traction.x,
            sigma: q.traction.y,
            status: q.status,
            state: q.state,
        });
    }
    Ok(path)
}

/// Top face displaced by `(s, v)`, bottom fixed.
fn displacement(s: f64, v: f64) -> Vector8 {
    Vector8::from_column_slice(&[0.0, 0.0, 0.0, 0.0, s, v, s, v])
}

fn main() -> Result<(), ContactError> {
    let p = ShearPath::default();
    let law = law(&p)?;
    println!(
        "# one interface element, p = {:.2} MPa, c = {:.2} MPa, phi = {} deg, k_n = k_s = {:.3e} Pa/m",
        p.pressure / 1e6,
        p.cohesion / 1e6,
        p.friction_deg,
        law.k_s()
    );
    println!(
        "# slip limit c + p tan(phi) = {:.4} MPa",
        law.strength(-p.pressure) / 1e6
    );
    println!("step,du_t_um,tau_MPa,sigma_MPa,status,slip_um,accumulated_slip_um");
    for (i, q) in shear_path(&p)?.iter().enumerate() {
        println!(
            "{i},{:.5},{:.5},{:.5},{:?},{:.5},{:.5}",
            q.du_t * 1e6,
            q.tau / 1e6,
            q.sigma / 1e6,
            q.status,
            q.state.slip * 1e6,
            q.state.accumulated_slip * 1e6
        );
    }
    Ok(())
}
