//! The steady duplex tube: one-dimensional solution of two concentric tubes
//! in contact, heat flowing radially through a pressure-dependent joint
//! conductance (it couples heat conduction and elasticity, so it lives in
//! the command layer rather than in `tecon-thermal` or `tecon-elastic`).
//!
//! ```text
//!   r = a ── inner tube ── r = c (joint, h(p)) ── outer tube ── r = b
//!   T(a) = T_a                                                T(b) = T_b
//! ```
//!
//! For a given conductance h the temperatures are logarithmic in each tube,
//! `T = A + B ln r`, with one heat rate per unit length
//! `Q = (T_a − T_b) / (R₁ + R_c + R₂)`, `R₁ = ln(c/a)/(2πk₁)`,
//! `R_c = 1/(2πc h)`, `R₂ = ln(b/c)/(2πk₂)` and the jump `T₁(c) − T₂(c) = Q R_c`.
//! In plane strain with ΔT = T − T_ref and `β = (1+ν)α/(1−ν)`:
//!
//! ```text
//!   u(r)  = β I(r)/r + C₁ r + C₂/r,       I(r) = ∫_{r₀}^{r} ΔT s ds
//!   σ_rr = 2(λ+μ) C₁ − 2μ β I(r)/r² − 2μ C₂/r²
//! ```
//!
//! (r₀ the tube's inner radius). Free surfaces σ_rr(a) = σ_rr(b) = 0, the
//! joint σ_rr(c) = −p on both sides and closed, `u₂(c) − u₁(c) = δ` (δ the
//! radial interference, the inner tube oversize), give five linear
//! equations for C₁, C₂ of each tube and p: the contact pressure g(h) for a
//! given conductance. With h = h(p) the steady state is a scalar fixed
//! point p = g(h(p)). A fixed point is stable under the thermal transient
//! when the map's slope g'(p) < 1 (a small pressure rise returns).

use std::f64::consts::PI;

use nalgebra::{Matrix5, Vector5};

/// Data of the duplex tube (SI units, temperatures in °C).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DuplexTube {
    /// Inner radius a.
    pub a: f64,
    /// Joint radius c.
    pub c: f64,
    /// Outer radius b.
    pub b: f64,
    /// Conductivities k₁, k₂.
    pub conductivity: [f64; 2],
    /// Young's moduli E₁, E₂.
    pub youngs_modulus: [f64; 2],
    /// Poisson's ratios ν₁, ν₂.
    pub poisson_ratio: [f64; 2],
    /// Expansion coefficients α₁, α₂.
    pub expansion: [f64; 2],
    /// Prescribed temperature of the bore, T_a.
    pub t_inner: f64,
    /// Prescribed temperature of the outside, T_b.
    pub t_outer: f64,
    /// Stress-free temperature T_ref.
    pub t_ref: f64,
    /// Radial interference δ (m): inner tube oversize at T_ref.
    pub interference: f64,
}

/// The state for one conductance.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DuplexState {
    /// Contact pressure p (Pa); negative: the joint would open.
    pub pressure: f64,
    /// Temperature of the inner tube at the joint, T₁(c).
    pub t_joint_inner: f64,
    /// Temperature of the outer tube at the joint, T₂(c).
    pub t_joint_outer: f64,
    /// Heat rate from inside out per unit length, W/m.
    pub heat_rate: f64,
}

/// A steady state of the coupled problem.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SteadyState {
    /// The state.
    pub state: DuplexState,
    /// Conductance h(p).
    pub conductance: f64,
    /// Slope g'(p) of the fixed-point map.
    pub slope: f64,
    /// Stable: g'(p) < 1.
    pub stable: bool,
}

impl DuplexTube {
    /// The temperatures and the contact pressure for a conductance `h`.
    pub fn at(&self, h: f64) -> DuplexState {
        let (a, b, c) = (self.a, self.b, self.c);
        let [k1, k2] = self.conductivity;
        let r1 = (c / a).ln() / (2.0 * PI * k1);
        let rc = 1.0 / (2.0 * PI * c * h);
        let r2 = (b / c).ln() / (2.0 * PI * k2);
        let q = (self.t_inner - self.t_outer) / (r1 + rc + r2);
        // T = A + B ln r in each tube
        let b1 = -q / (2.0 * PI * k1);
        let a1 = self.t_inner - b1 * a.ln();
        let b2 = -q / (2.0 * PI * k2);
        let a2 = self.t_outer - b2 * b.ln();
        let tr = self.t_ref;
        let integral = |aa: f64, bb: f64, r0: f64, r: f64| {
            let f = |s: f64| (aa - tr) * s * s / 2.0 + bb * (s * s / 2.0 * s.ln() - s * s / 4.0);
            f(r) - f(r0)
        };
        let lame = |k: usize| {
            let (e, nu) = (self.youngs_modulus[k], self.poisson_ratio[k]);
            let lambda = e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
            let mu = e / (2.0 * (1.0 + nu));
            let beta = (1.0 + nu) * self.expansion[k] / (1.0 - nu);
            (lambda, mu, beta)
        };
        let (l1, m1, be1) = lame(0);
        let (l2, m2, be2) = lame(1);
        let i1c = integral(a1, b1, a, c);
        let i2b = integral(a2, b2, c, b);
        // unknowns C₁ᵃ, C₂ᵃ (inner), C₁ᵇ, C₂ᵇ (outer), p
        #[rustfmt::skip]
        let m = Matrix5::new(
            2.0 * (l1 + m1), -2.0 * m1 / (a * a), 0.0, 0.0, 0.0,
            0.0, 0.0, 2.0 * (l2 + m2), -2.0 * m2 / (b * b), 0.0,
            2.0 * (l1 + m1), -2.0 * m1 / (c * c), 0.0, 0.0, 1.0,
            0.0, 0.0, 2.0 * (l2 + m2), -2.0 * m2 / (c * c), 1.0,
            c, 1.0 / c, -c, -1.0 / c, 0.0,
        );
        let rhs = Vector5::new(
            0.0,
            2.0 * m2 * be2 * i2b / (b * b),
            2.0 * m1 * be1 * i1c / (c * c),
            0.0,
            -be1 * i1c / c - self.interference,
        );
        let x = m
            .lu()
            .solve(&rhs)
            .unwrap_or_else(|| Vector5::repeat(f64::NAN));
        DuplexState {
            pressure: x[4],
            t_joint_inner: a1 + b1 * c.ln(),
            t_joint_outer: a2 + b2 * c.ln(),
            heat_rate: q,
        }
    }

    /// Every steady state with p in (0, p_max] for the conductance law
    /// `h(p)`: sign changes of g(h(p)) − p on `n` intervals, each refined
    /// by bisection to 1e-12 relative. (An open state, p = 0, exists
    /// besides when g(h(0)) ≤ 0.)
    pub fn steady_states(&self, h: &dyn Fn(f64) -> f64, p_max: f64, n: usize) -> Vec<SteadyState> {
        let f = |p: f64| self.at(h(p)).pressure - p;
        let mut out = Vec::new();
        let mut p0 = p_max * 1e-9;
        let mut f0 = f(p0);
        for k in 1..=n {
            let p1 = p_max * k as f64 / n as f64;
            let f1 = f(p1);
            if f0 * f1 <= 0.0 && f0 != f1 {
                let (mut lo, mut hi, mut flo) = (p0, p1, f0);
                for _ in 0..200 {
                    let mid = 0.5 * (lo + hi);
                    let fm = f(mid);
                    if fm * flo > 0.0 {
                        lo = mid;
                        flo = fm;
                    } else {
                        hi = mid;
                    }
                    if hi - lo <= 1e-12 * hi {
                        break;
                    }
                }
                let p = 0.5 * (lo + hi);
                let dp = 1e-6 * p;
                let slope =
                    (self.at(h(p + dp)).pressure - self.at(h(p - dp)).pressure) / (2.0 * dp);
                out.push(SteadyState {
                    state: self.at(h(p)),
                    conductance: h(p),
                    slope,
                    stable: slope < 1.0,
                });
            }
            p0 = p1;
            f0 = f1;
        }
        out
    }
}

// ---------------------------------------------------------------------------
// The FE study: the same tubes by finite elements through the one driver
// ---------------------------------------------------------------------------

/// Conductance `h(p) = h_base + h₀ (p/p₀)^m` of the study. The FE joint
/// carries it as a power law plus a gas gap `k_g/(max(g, 0) + g₀)` with
/// `k_g = h_base g₀`: equal to h(p) while the joint is closed (g ≤ 0).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SteepLaw {
    /// Conductance of the unloaded closed joint, W/(m² K).
    pub h_base: f64,
    /// h₀, W/(m² K).
    pub h0: f64,
    /// p₀, Pa.
    pub p0: f64,
    /// m.
    pub exponent: f64,
}

impl SteepLaw {
    /// h(p) (p ≤ 0: h_base).
    pub fn h(&self, p: f64) -> f64 {
        self.h_base + self.h0 * (p.max(0.0) / self.p0).powf(self.exponent)
    }
}

/// Temperature-jump distance g₀ of the FE gas part, m (only `k_g / g₀`
/// matters while the joint is closed).
const JUMP_DISTANCE: f64 = 1e-4;

/// The duplex tube by finite elements: a quarter ring of linear triangles
/// (symmetry on both cut edges), the interference as an eigenstrain.
///
/// A uniform temperature rise ΔT₀ of the inner tube alone expands it
/// freely by `u = (1+ν)α ΔT₀ r` in plane strain without stress: the inner
/// tube's reference temperature is set `ΔT₀ = δ / ((1+ν) α c)` below the
/// rest, which is exactly a radial interference δ at r = c.
#[derive(Debug, Clone, PartialEq)]
pub struct FeDuplex {
    /// Geometry, materials, boundary temperatures and interference (the
    /// density and specific heat of the transient are 7800 kg/m³ and
    /// 460 J/(kg K)).
    pub tube: DuplexTube,
    /// The joint conductance.
    pub law: SteepLaw,
    /// Intervals around the quarter.
    pub segments: usize,
    /// Element rows across the inner and the outer tube.
    pub rows: [usize; 2],
}

/// Where a transient of the FE duplex tube starts.
#[derive(Debug, Clone, PartialEq)]
pub enum Start {
    /// The same temperature everywhere.
    Uniform(f64),
    /// Nodal temperatures (from [`FeDuplex::steady_field`] on the same mesh).
    Field(Vec<f64>),
}

/// One output time of an FE transient.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FePoint {
    /// Time, s.
    pub time: f64,
    /// Mean contact pressure of the joint, Pa.
    pub pressure: f64,
    /// Mean nodal temperature of the inner / outer tube at the joint.
    pub t_joint: [f64; 2],
    /// Coupling iterations (contact solves) up to this output.
    pub coupling_iterations: usize,
}

/// A steady state of the FE duplex tube.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FeSteadyState {
    /// Mean contact pressure, Pa.
    pub pressure: f64,
    /// Conductance h(p).
    pub conductance: f64,
    /// Slope of the FE map p ↦ g_FE(h(p)) (stable below 1).
    pub slope: f64,
    /// g′ < 1.
    pub stable: bool,
}

impl FeDuplex {
    /// The case text: steady (no schedule) or a transient over `segments`
    /// (`[t_end, Δt]`) with output `times`; `h`: a constant conductance
    /// (one-way), else the law with two-way coupling.
    fn case_text(&self, h: Option<f64>, schedule: Option<(&[[f64; 2]], &[f64])>) -> String {
        let t = &self.tube;
        let mut s = format!(
            "[mesh]\ngenerator = \"annulus\"\ntheta0 = 0.0\ntheta1 = 90.0\nsegments = {}\n\
             [[mesh.layer]]\nname = \"tube_in\"\nr_in = {:e}\nr_out = {:e}\nrows = {}\n\
             [[mesh.layer]]\nname = \"tube_out\"\nr_in = {:e}\nr_out = {:e}\nrows = {}\n",
            self.segments, t.a, t.c, self.rows[0], t.c, t.b, self.rows[1]
        );
        for (k, region) in ["tube_in", "tube_out"].iter().enumerate() {
            s += &format!(
                "[[material]]\nregion = \"{region}\"\nconductivity = {:e}\ndensity = 7800.0\n\
                 specific_heat = 460.0\nyoungs_modulus = {:e}\npoisson_ratio = {:e}\nexpansion = {:e}\n",
                t.conductivity[k], t.youngs_modulus[k], t.poisson_ratio[k], t.expansion[k]
            );
        }
        s += "[[interface]]\nname = \"tube_in_tube_out\"\n";
        match h {
            Some(h) => s += &format!("conductance = {h:e}\n"),
            None => {
                let l = &self.law;
                s += &format!(
                    "[interface.conductance]\nlaw = \"power\"\nh0 = {:e}\np0 = {:e}\nexponent = {:e}\n\
                     gas_conductivity = {:e}\njump_distance = {:e}\n",
                    l.h0,
                    l.p0,
                    l.exponent,
                    l.h_base * JUMP_DISTANCE,
                    JUMP_DISTANCE
                );
            }
        }
        s += "[interface.joint]\nlaw = \"frictional\"\nfriction = 0.3\n";
        s += &format!(
            "[[thermal.bc]]\nedges = \"inner\"\ntype = \"temperature\"\nvalue = {:e}\n\
             [[thermal.bc]]\nedges = \"outer\"\ntype = \"temperature\"\nvalue = {:e}\n\
             [thermal.initial]\ndefault = {:e}\n",
            t.t_inner, t.t_outer, t.t_ref
        );
        if let Some((segments, times)) = schedule {
            let seg: Vec<String> = segments
                .iter()
                .map(|[a, b]| format!("[{a:e}, {b:e}]"))
                .collect();
            s += &format!("[thermal.schedule]\nsegments = [{}]\n", seg.join(", "));
            let times: Vec<String> = times.iter().map(|t| format!("{t:e}")).collect();
            s += &format!("[output]\ntimes = [{}]\n", times.join(", "));
        }
        s += &format!(
            "[mechanical]\nanalysis = \"plane-strain\"\nreference_temperature = {:e}\n\
             [[mechanical.symmetry]]\nedges = \"start\"\n[[mechanical.symmetry]]\nedges = \"end\"\n",
            t.t_ref
        );
        if h.is_none() {
            s += "[coupling]\nmode = \"two-way\"\n";
        }
        s
    }

    /// Runs a case text through the driver with the interference as the
    /// inner tube's lower reference temperature and an optional start.
    fn run(
        &self,
        text: &str,
        start: Option<&Start>,
        two_way: Option<crate::driver::TwoWay>,
    ) -> crate::writers::CliResult<(tecon_mesh::Mesh, crate::driver::Outcome)> {
        use crate::driver::{Coupling, Reference};
        let file = std::path::Path::new("duplex study");
        let case = crate::case::parse(text, file)?;
        let mut mesh = crate::setup::build_mesh(&case, std::path::Path::new("."))?;
        crate::setup::declare_interfaces(&case, &mut mesh)?;
        let outcome = {
            let mut p = crate::setup::prepare(&case, &mesh, None)?;
            let t = &self.tube;
            let dt0 = t.interference / ((1.0 + t.poisson_ratio[0]) * t.expansion[0] * t.c);
            let inner = mesh
                .region_names()
                .iter()
                .position(|r| r == "tube_in")
                .ok_or("duplex study: no region tube_in")?;
            let reference = mesh
                .element_regions()
                .iter()
                .map(|&r| if r == inner { t.t_ref - dt0 } else { t.t_ref })
                .collect();
            if let (Some(c), Coupling::TwoWay(_)) = (two_way, p.setup.coupling) {
                p.setup.coupling = Coupling::TwoWay(c);
            }
            let th = p
                .setup
                .thermal
                .as_mut()
                .ok_or("duplex study: no heat conduction")?;
            th.reference_temperature = Reference::Elements(reference);
            match start {
                Some(Start::Uniform(v)) => {
                    th.model.set_initial_default(*v)?;
                }
                Some(Start::Field(f)) => {
                    if f.len() != mesh.n_nodes() {
                        return Err(format!(
                            "duplex study: a start field of {} values for {} nodes",
                            f.len(),
                            mesh.n_nodes()
                        )
                        .into());
                    }
                    for (i, v) in f.iter().enumerate() {
                        th.model.set_initial_node(i, *v)?;
                    }
                }
                None => {}
            }
            crate::driver::run(&p.setup).map_err(|e| format!("duplex study: {e}"))?
        };
        Ok((mesh, outcome))
    }

    /// Mean contact pressure and joint temperatures of a state.
    fn point(&self, mesh: &tecon_mesh::Mesh, s: &crate::driver::State) -> FePoint {
        let (mut sum, mut n) = (0.0, 0);
        for p in s.interface.iter().filter(|p| p.interface == 0) {
            sum += (-p.traction[1]).max(0.0);
            n += 1;
        }
        let mut t_joint = [0.0; 2];
        if let Some(t) = &s.temperature {
            let mut acc = [(0.0, 0usize); 2];
            let inner_body = mesh.node_bodies()[0];
            for (i, x) in mesh.nodes().iter().enumerate() {
                if (x[0].hypot(x[1]) - self.tube.c).abs() < 1e-9 * self.tube.c {
                    let k = usize::from(mesh.node_bodies()[i] != inner_body);
                    acc[k].0 += t[i];
                    acc[k].1 += 1;
                }
            }
            t_joint = acc.map(|(s, n)| if n > 0 { s / n as f64 } else { f64::NAN });
        }
        FePoint {
            time: s.time,
            pressure: if n > 0 { sum / n as f64 } else { 0.0 },
            t_joint,
            coupling_iterations: s.coupling_iterations,
        }
    }

    /// The FE map g_FE(h): the steady mean contact pressure with a constant
    /// joint conductance `h` (one-way).
    pub fn pressure_at(&self, h: f64) -> crate::writers::CliResult<f64> {
        let (mesh, o) = self.run(&self.case_text(Some(h), None), None, None)?;
        let s = o.states.first().ok_or("duplex study: no state")?;
        Ok(self.point(&mesh, s).pressure)
    }

    /// Steady nodal temperatures with boundary temperatures `t_inner`,
    /// `t_outer` and a constant conductance `h` (a starting state).
    pub fn steady_field(
        &self,
        t_inner: f64,
        t_outer: f64,
        h: f64,
    ) -> crate::writers::CliResult<Vec<f64>> {
        let other = FeDuplex {
            tube: DuplexTube {
                t_inner,
                t_outer,
                ..self.tube
            },
            ..self.clone()
        };
        let (_, o) = other.run(&other.case_text(Some(h), None), None, None)?;
        o.states
            .first()
            .and_then(|s| s.temperature.clone())
            .ok_or_else(|| "duplex study: no temperature".into())
    }

    /// Every FE steady state with p in (0, p_max]: sign changes of
    /// g_FE(h(p)) − p on `n` intervals, each refined by the Illinois
    /// method to `rel_tol` relative; the slope g′ by central differences.
    pub fn steady_states(
        &self,
        p_max: f64,
        n: usize,
        rel_tol: f64,
    ) -> crate::writers::CliResult<Vec<FeSteadyState>> {
        let law = self.law;
        let f = |p: f64| -> crate::writers::CliResult<f64> { Ok(self.pressure_at(law.h(p))? - p) };
        let mut out = Vec::new();
        let mut p0 = p_max / n as f64;
        let mut f0 = f(p0)?;
        for k in 2..=n {
            let p1 = p_max * k as f64 / n as f64;
            let f1 = f(p1)?;
            if f0 * f1 < 0.0 {
                let (mut a, mut b, mut fa, mut fb) = (p0, p1, f0, f1);
                let mut side = 0;
                for _ in 0..60 {
                    let x = (a * fb - b * fa) / (fb - fa);
                    let fx = f(x)?;
                    if fx * fb < 0.0 {
                        (a, fa) = (b, fb);
                        side = 0;
                    } else {
                        fa *= if side == 1 { 0.5 } else { 1.0 };
                        side = 1;
                    }
                    (b, fb) = (x, fx);
                    if (b - a).abs() <= rel_tol * b.abs() || fx == 0.0 {
                        break;
                    }
                }
                let p = b;
                let dp = 1e-3 * p;
                let slope = (self.pressure_at(law.h(p + dp))? - self.pressure_at(law.h(p - dp))?)
                    / (2.0 * dp);
                out.push(FeSteadyState {
                    pressure: p,
                    conductance: law.h(p),
                    slope,
                    stable: slope < 1.0,
                });
            }
            p0 = p1;
            f0 = f1;
        }
        Ok(out)
    }

    /// A two-way transient from `start` with the boundary temperatures of
    /// [`FeDuplex::tube`]: the state at every output time.
    pub fn transient(
        &self,
        start: &Start,
        segments: &[[f64; 2]],
        times: &[f64],
        two_way: Option<crate::driver::TwoWay>,
    ) -> crate::writers::CliResult<Vec<FePoint>> {
        let (mesh, o) = self.run(
            &self.case_text(None, Some((segments, times))),
            Some(start),
            two_way,
        )?;
        Ok(o.states.iter().map(|s| self.point(&mesh, s)).collect())
    }

    /// A two-way steady analysis (fixed point from the unloaded joint).
    pub fn steady_two_way(&self) -> crate::writers::CliResult<FePoint> {
        let (mesh, o) = self.run(&self.case_text(None, None), None, None)?;
        let s = o.states.first().ok_or("duplex study: no state")?;
        Ok(self.point(&mesh, s))
    }
}
