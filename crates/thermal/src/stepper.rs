//! The θ-method time stepper, kept apart from the spatial operator.
//!
//! Each step solves for the increment ΔT = Tⁿ⁺¹ − Tⁿ:
//!
//! ```text
//!   (C/Δt + θK) ΔT = F − K Tⁿ          (ΔT = 0 at prescribed nodes)
//! ```
//!
//! which is the θ-method `(C/Δt + θK) Tⁿ⁺¹ = (C/Δt − (1−θ)K) Tⁿ + F`
//! rewritten. The right-hand side needs one sparse mat-vec with K (the
//! same for every Δt), the left-hand side one pair of triangular solves
//! with a factorisation of `C/Δt + θK` kept per distinct (Δt, θ). Solving
//! for the increment keeps the solve's round-off proportional to |ΔT|, not
//! to |T|, which is what lets the heat balance close to round-off.
//!
//! Factorisations live in a small pool (least recently used evicted; all
//! slots share one symbolic analysis, and an
//! evicted solver keeps its symbolic analysis and is refactorised
//! numerically for the new Δt).

use std::sync::Arc;

use rayon::prelude::*;
use tecon_fem::{CholeskySolver, CsrMatrix};

use crate::error::ThermalError;
use crate::output::{HeatBalance, Snapshot};
use crate::system::{BodyFlows, ThermalSystem};

/// Nodes per chunk of the parallel update (fixed: the summation order does
/// not depend on the thread count).
const UPDATE_CHUNK: usize = 16384;

/// Default number of factorisations kept by a stepper.
pub const DEFAULT_POOL: usize = 3;

#[derive(Debug)]
struct Factorised {
    key: (u64, u64),
    solver: CholeskySolver,
    last_used: u64,
}

fn weighted_mean(t: &[f64], w: &[f64]) -> f64 {
    let (s, ws) = t
        .iter()
        .zip(w)
        .fold((0.0, 0.0), |(s, ws), (t, w)| (s + w * t, ws + w));
    if ws > 0.0 { s / ws } else { 0.0 }
}

/// Counters of the work a stepper has done.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct StepperStats {
    /// Steps taken.
    pub steps: usize,
    /// Numeric factorisations of `C/Δt + θK`.
    pub factorisations: usize,
    /// Symbolic analyses (at most one: the pool's slots share it).
    pub analyses: usize,
}

/// Advances the temperature of a [`ThermalSystem`] by θ-method steps and
/// integrates the heat balance along the way.
#[derive(Debug)]
pub struct ThetaStepper<'s, 'm> {
    system: &'s ThermalSystem<'m>,
    temperature: Vec<f64>,
    initial: Vec<f64>,
    time: f64,
    pool: Vec<Factorised>,
    pool_size: usize,
    scratch: CsrMatrix,
    rhs: Vec<f64>,
    zero: Vec<f64>,
    saved: Vec<f64>,
    balance: HeatBalance,
    flows: BodyFlows,
    t_theta: Vec<f64>,
    shift: f64,
    stats: StepperStats,
    tick: u64,
    /// A solver analysed on this system's pattern whose ordering new pool
    /// slots share (no symbolic analysis of their own).
    symbolic: Option<CholeskySolver>,
}

impl<'s, 'm> ThetaStepper<'s, 'm> {
    /// A stepper starting from nodal temperatures `initial` at time `t0`.
    /// Prescribed temperatures are imposed on `initial`.
    pub fn new(
        system: &'s ThermalSystem<'m>,
        mut initial: Vec<f64>,
        t0: f64,
    ) -> Result<Self, ThermalError> {
        let n = system.n_nodes();
        if initial.len() != n {
            return Err(ThermalError::LengthMismatch {
                what: "initial temperature".into(),
                got: initial.len(),
                expected: n,
            });
        }
        if let Some(i) = initial.iter().position(|v| !v.is_finite()) {
            return Err(ThermalError::InvalidInitialTemperature {
                what: format!("node {i}"),
                value: initial[i],
            });
        }
        for (dof, v) in system.dirichlet.iter() {
            initial[dof] = v;
        }
        let shift = weighted_mean(&initial, &system.capacity_weights);
        Ok(ThetaStepper {
            system,
            temperature: initial.clone(),
            initial,
            time: t0,
            pool: Vec::new(),
            pool_size: DEFAULT_POOL,
            scratch: system.assembler.new_matrix(),
            rhs: vec![0.0; n],
            zero: vec![0.0; n],
            saved: vec![0.0; system.constrained.len()],
            balance: HeatBalance::default(),
            flows: BodyFlows::new(system.mesh.bodies().len()),
            t_theta: Vec::new(),
            shift,
            stats: StepperStats::default(),
            tick: 0,
            symbolic: None,
        })
    }

    /// New factorisations share the symbolic analysis (AMD ordering,
    /// elimination tree) of `analysed` instead of analysing the pattern
    /// again: for a sequence of systems of one mesh whose values change (a
    /// coupling loop re-assembling the interface conductances), the ordering
    /// is found once. `analysed` must be of this system's pattern (an equal
    /// one): a factorisation with another pattern fails with an error.
    pub fn share_symbolic(&mut self, analysed: &CholeskySolver) {
        self.symbolic = Some(analysed.share_symbolic());
    }

    /// Sets how many factorisations are kept (at least 1).
    pub fn set_pool_size(&mut self, size: usize) {
        self.pool_size = size.max(1);
        if self.pool.len() > self.pool_size {
            self.pool.sort_by_key(|f| std::cmp::Reverse(f.last_used));
            self.pool.truncate(self.pool_size);
        }
    }

    /// Drops the factorisations of the (Δt, θ) pairs for which `keep`
    /// (given the bits of Δt and θ) says no: a schedule that will not use
    /// them again need not hold their memory.
    pub fn retain_operators(&mut self, keep: impl Fn(u64, u64) -> bool) {
        self.pool.retain(|f| keep(f.key.0, f.key.1));
    }

    /// Current nodal temperatures.
    pub fn temperature(&self) -> &[f64] {
        &self.temperature
    }

    /// Current time.
    pub fn time(&self) -> f64 {
        self.time
    }

    /// Heat balance integrated since the start.
    pub fn balance(&self) -> HeatBalance {
        let gross_stored: f64 = self
            .temperature
            .iter()
            .zip(&self.initial)
            .zip(&self.system.capacity_weights)
            .map(|((t, t0), w)| (w * (t - t0)).abs())
            .sum();
        let mut b = self.balance;
        b.scale = b.scale.max(gross_stored);
        b.close()
    }

    /// Work counters.
    pub fn stats(&self) -> StepperStats {
        self.stats
    }

    /// The output at the current time.
    pub fn snapshot(&self) -> Snapshot {
        self.system.snapshot(
            self.time,
            self.stats.steps,
            self.temperature.clone(),
            self.balance(),
            &self.flows,
            Some(&self.initial),
        )
    }

    /// Index in the pool of the factorisation of `C/Δt + θK`, factorising
    /// it if needed.
    fn operator(&mut self, dt: f64, theta: f64) -> Result<usize, ThermalError> {
        self.tick += 1;
        let key = (dt.to_bits(), theta.to_bits());
        if let Some(i) = self.pool.iter().position(|f| f.key == key) {
            self.pool[i].last_used = self.tick;
            return Ok(i);
        }
        let sys = self.system;
        let inv = 1.0 / dt;
        self.scratch
            .values_mut()
            .par_iter_mut()
            .zip(sys.c.values().par_iter().zip(sys.k.values().par_iter()))
            .for_each(|(a, (c, k))| *a = c * inv + theta * k);
        self.zero.iter_mut().for_each(|v| *v = 0.0);
        sys.prepared
            .apply_scaled(&mut self.scratch, &mut self.zero, 0.0);
        let slot = if self.pool.len() < self.pool_size {
            let solver = match &self.symbolic {
                Some(a) => a.share_symbolic(),
                None => {
                    // analysed once: later slots (and slots refilled after
                    // a schedule dropped its factorisations) share it
                    self.stats.analyses += 1;
                    let solver = CholeskySolver::analyse(Arc::clone(sys.assembler.pattern()))?;
                    self.symbolic = Some(solver.share_symbolic());
                    solver
                }
            };
            self.pool.push(Factorised {
                key,
                solver,
                last_used: self.tick,
            });
            self.pool.len() - 1
        } else {
            let (i, _) = self
                .pool
                .iter()
                .enumerate()
                .min_by_key(|(_, f)| f.last_used)
                .ok_or_else(|| ThermalError::ScheduleDoesNotAdvance {
                    reason: "empty factorisation pool".into(),
                })?;
            self.pool[i].key = key;
            self.pool[i].last_used = self.tick;
            i
        };
        // A failed factorisation must not leave a stale entry under this key.
        if let Err(e) = self.pool[slot].solver.factorise(&self.scratch) {
            self.pool.swap_remove(slot);
            return Err(e.into());
        }
        self.stats.factorisations += 1;
        Ok(slot)
    }

    /// Adds the step's convective, flux and interface inflows per body,
    /// evaluated at `T_θ = Tⁿ + θΔT` (ΔT in `self.rhs`).
    fn per_body_flows(&mut self, dt: f64, theta: f64) {
        let sys = self.system;
        if sys.interface_elements.nodes.is_empty() && sys.mesh.bodies().len() == 1 {
            // One body: its flows are the global ones (added in `step`).
            return;
        }
        // A dense T_θ (one O(n) pass, only for meshes with several bodies
        // or interfaces).
        self.t_theta.clear();
        self.t_theta.extend(
            self.temperature
                .iter()
                .zip(&self.rhs)
                .map(|(t, d)| t + theta * d),
        );
        sys.add_body_flows(&mut self.flows, &self.t_theta, dt);
    }

    /// Takes one step of size `dt` with parameter `theta` ∈ [1/2, 1].
    pub fn step(&mut self, dt: f64, theta: f64) -> Result<(), ThermalError> {
        if !(dt > 0.0 && dt.is_finite()) || self.time + dt <= self.time {
            return Err(ThermalError::ScheduleDoesNotAdvance {
                reason: format!("step Δt = {dt} at t = {}", self.time),
            });
        }
        if !(0.5..=1.0).contains(&theta) {
            return Err(ThermalError::InvalidTheta { theta });
        }
        let slot = self.operator(dt, theta)?;
        let sys = self.system;
        // rhs = F − K Tⁿ (one mat-vec), evaluated as
        // F − c·(K1) − K (Tⁿ − c1) with c the capacity-weighted mean of Tⁿ:
        // K1 is the convective row sum exactly (conduction and interface
        // rows sum to zero), and the products see |Tⁿ − c| instead of |Tⁿ|.
        {
            let p = sys.k.pattern();
            let (indptr, indices) = (p.indptr(), p.indices());
            let kv = sys.k.values();
            let t = &self.temperature;
            let c = self.shift;
            self.rhs
                .par_iter_mut()
                .with_min_len(4096)
                .zip(sys.load.par_iter().zip(sys.row_sums.par_iter()))
                .enumerate()
                .for_each(|(i, (r, (f, g)))| {
                    let mut s = 0.0;
                    for q in indptr[i]..indptr[i + 1] {
                        s += kv[q] * (t[indices[q]] - c);
                    }
                    *r = (f - c * g) - s;
                });
        }
        for (s, row) in self.saved.iter_mut().zip(&sys.constrained) {
            *s = self.rhs[row.dof];
            self.rhs[row.dof] = 0.0;
        }
        self.pool[slot].solver.solve(&mut self.rhs)?;
        // Per-body flows: convection, fluxes and interfaces at T_θ.
        self.per_body_flows(dt, theta);
        let dtemp = &self.rhs;
        // Heat balance of the step, consistent with the θ-method.
        let (mut conv_in, mut gross) = (0.0, 0.0);
        for &(i, w, f) in &sys.convective_weights {
            let g = f - w * (self.temperature[i] + theta * dtemp[i]);
            conv_in += g;
            gross += g.abs();
        }
        gross += sys.flux_gross();
        let boundary_gross = gross;
        let mut prescribed = 0.0;
        let inv = 1.0 / dt;
        for (row, &s) in sys.constrained.iter().zip(&self.saved) {
            let mut r = 0.0;
            for q in 0..row.cols.len() {
                r += (row.c[q] * inv + theta * row.k[q]) * dtemp[row.cols[q]];
            }
            // Row c of C ΔT/Δt + K(Tⁿ + θΔT) − F; `s` holds F − K Tⁿ.
            prescribed += r - s;
            gross += (r - s).abs();
            let b = sys.mesh.node_bodies()[row.dof];
            self.flows.prescribed[b] += dt * (r - s);
            self.flows.gross[b] += dt * (r - s).abs();
        }
        // Tⁿ⁺¹ = Tⁿ + ΔT with the stored change w·ΔT and the content w·Tⁿ⁺¹,
        // summed per fixed chunk and then in chunk order: parallel, and
        // bitwise the same for any thread count.
        let (stored, content) = self
            .temperature
            .par_chunks_mut(UPDATE_CHUNK)
            .zip(dtemp.par_chunks(UPDATE_CHUNK))
            .zip(sys.capacity_weights.par_chunks(UPDATE_CHUNK))
            .map(|((t, d), w)| {
                let (mut s, mut c) = (0.0, 0.0);
                for ((t, d), w) in t.iter_mut().zip(d).zip(w) {
                    *t += d;
                    s += w * d;
                    c += w * *t;
                }
                (s, c)
            })
            .collect::<Vec<_>>()
            .into_iter()
            .fold((0.0, 0.0), |(s, c), (a, b)| (s + a, c + b));
        self.shift = content / sys.total_capacity;
        self.balance.stored_change += stored;
        if sys.interface_elements.nodes.is_empty() && sys.mesh.bodies().len() == 1 {
            self.flows.convection[0] += dt * conv_in;
            self.flows.flux[0] += dt * sys.flux_load;
            self.flows.gross[0] += dt * boundary_gross;
        }
        self.balance.convection_in += dt * conv_in;
        self.balance.scale += dt * gross;
        self.balance.flux_in += dt * sys.flux_load;
        self.balance.prescribed_in += dt * prescribed;
        self.time += dt;
        self.stats.steps += 1;
        Ok(())
    }
}
