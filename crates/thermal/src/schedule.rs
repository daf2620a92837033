//! Time schedules and the θ-method parameters.
//!
//! The time stepping is kept apart from the spatial operator: a
//! [`TimeSchedule`] is a list of step sizes Δt_n; the stepper factorises
//! `C/Δt + θK` once per distinct (Δt, θ) and reuses it, so schedules built
//! from blocks of equal steps ([`TimeSchedule::segments`],
//! [`TimeSchedule::geometric`]) need one factorisation per block.

use crate::error::ThermalError;

/// A sequence of time steps starting at `start`.
#[derive(Debug, Clone, PartialEq)]
pub struct TimeSchedule {
    start: f64,
    steps: Vec<f64>,
}

/// Largest number of steps a schedule may hold.
pub const MAX_STEPS: usize = 100_000_000;

fn check_count(steps: f64) -> Result<(), ThermalError> {
    if steps > MAX_STEPS as f64 {
        Err(ThermalError::TooManySteps {
            steps,
            limit: MAX_STEPS,
        })
    } else {
        Ok(())
    }
}

fn not_advancing(reason: String) -> ThermalError {
    ThermalError::ScheduleDoesNotAdvance { reason }
}

impl TimeSchedule {
    /// Explicit steps from t = 0. Every Δt must be positive and finite.
    pub fn from_steps(steps: Vec<f64>) -> Result<Self, ThermalError> {
        Self::from_steps_at(0.0, steps)
    }

    /// Explicit steps from t = `start`.
    pub fn from_steps_at(start: f64, steps: Vec<f64>) -> Result<Self, ThermalError> {
        if !start.is_finite() {
            return Err(not_advancing(format!("start time {start} is not finite")));
        }
        if steps.is_empty() {
            return Err(not_advancing("the schedule has no steps".into()));
        }
        for (k, &dt) in steps.iter().enumerate() {
            if !(dt > 0.0 && dt.is_finite()) {
                return Err(not_advancing(format!(
                    "step {k} has Δt = {dt} (must be positive and finite)"
                )));
            }
        }
        let end = start + steps.iter().sum::<f64>();
        if end <= start {
            return Err(not_advancing(format!(
                "the steps are too small to move t = {start} (end {end})"
            )));
        }
        Ok(TimeSchedule { start, steps })
    }

    /// `n` steps of size `dt` from t = 0.
    pub fn uniform(dt: f64, n: usize) -> Result<Self, ThermalError> {
        check_count(n as f64)?;
        Self::from_steps(vec![dt; n])
    }

    /// Piecewise-uniform steps from t = 0: segment `(t_end, dt)` steps from
    /// the previous end to `t_end` with equal steps no longer than `dt`
    /// (the step is shortened uniformly so the segment ends exactly on
    /// `t_end`). One distinct Δt per segment.
    pub fn segments(segments: &[(f64, f64)]) -> Result<Self, ThermalError> {
        if segments.is_empty() {
            return Err(not_advancing("no segments".into()));
        }
        let mut t = 0.0;
        let mut steps = Vec::new();
        for (s, &(t_end, dt)) in segments.iter().enumerate() {
            if !(t_end.is_finite() && t_end > t) {
                return Err(not_advancing(format!(
                    "segment {s} ends at t = {t_end}, not after the previous end {t}"
                )));
            }
            if !(dt > 0.0 && dt.is_finite()) {
                return Err(not_advancing(format!(
                    "segment {s} has Δt = {dt} (must be positive and finite)"
                )));
            }
            let span = t_end - t;
            let nf = ((span / dt) * (1.0 - 1e-12)).ceil().max(1.0);
            check_count(steps.len() as f64 + nf)?;
            let n = nf as usize;
            let h = span / n as f64;
            steps.extend(std::iter::repeat_n(h, n));
            t = t_end;
        }
        Self::from_steps(steps)
    }

    /// Growing steps from t = 0 to `t_end`: `per_level` steps of `dt0`, then
    /// `per_level` steps of `dt0·growth`, and so on; the last step is
    /// shortened to land on `t_end`. `growth ≥ 1`.
    pub fn geometric(
        dt0: f64,
        growth: f64,
        per_level: usize,
        t_end: f64,
    ) -> Result<Self, ThermalError> {
        if !(dt0 > 0.0 && dt0.is_finite()) {
            return Err(not_advancing(format!("first step Δt₀ = {dt0}")));
        }
        if !(growth >= 1.0 && growth.is_finite()) {
            return Err(not_advancing(format!(
                "growth factor {growth} must be ≥ 1 and finite"
            )));
        }
        if per_level == 0 {
            return Err(not_advancing("zero steps per level".into()));
        }
        if !(t_end > 0.0 && t_end.is_finite()) {
            return Err(not_advancing(format!("end time {t_end} is not after 0")));
        }
        // Steps needed: m·L with m·Δt₀·(g^L − 1)/(g − 1) ≥ t_end (checked
        // before anything is allocated).
        let m = per_level as f64;
        let estimate = if growth == 1.0 {
            t_end / dt0
        } else {
            m * ((t_end * (growth - 1.0) / (m * dt0) + 1.0).ln() / growth.ln()).ceil()
        };
        check_count(estimate)?;
        let mut steps = Vec::new();
        let mut t = 0.0;
        let mut dt = dt0;
        'outer: loop {
            for _ in 0..per_level {
                if t + dt >= t_end * (1.0 - 1e-12) {
                    steps.push(t_end - t);
                    break 'outer;
                }
                steps.push(dt);
                t += dt;
            }
            dt *= growth;
        }
        Self::from_steps(steps)
    }

    /// Start time.
    pub fn start(&self) -> f64 {
        self.start
    }

    /// End time (start + Σ Δt).
    pub fn end(&self) -> f64 {
        self.start + self.steps.iter().sum::<f64>()
    }

    /// The step sizes.
    pub fn steps(&self) -> &[f64] {
        &self.steps
    }

    /// Number of steps.
    pub fn len(&self) -> usize {
        self.steps.len()
    }

    /// Whether there are no steps (never true for a built schedule).
    pub fn is_empty(&self) -> bool {
        self.steps.is_empty()
    }

    /// Number of distinct step sizes (an upper bound of the factorisations
    /// per θ).
    pub fn distinct_steps(&self) -> usize {
        let mut b: Vec<u64> = self.steps.iter().map(|d| d.to_bits()).collect();
        b.sort_unstable();
        b.dedup();
        b.len()
    }
}

/// The θ-method `(C/Δt + θK) Tⁿ⁺¹ = (C/Δt − (1−θ)K) Tⁿ + F`, with a number
/// of backward-Euler (θ = 1) steps at the start.
///
/// Crank–Nicolson (θ = 1/2) damps the highest modes of a discontinuous
/// initial field only weakly (amplification → −1): the first steps are
/// taken with backward Euler, which damps them strongly (Rannacher's
/// start-up); a fixed number of first-order steps leaves the global order 2.
///
/// Optionally the first `restart_steps` steps after every growth of Δt are
/// backward Euler too: modes that a short step followed are left to the
/// longer one with an amplification near −1 by Crank–Nicolson, and on
/// strongly graded quadratic meshes the remnant of the initial jump then
/// rings at the weld edge for the rest of the run (a few mK below the
/// ambient at 72 000 s on the vessel).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ThetaScheme {
    theta: f64,
    startup_steps: usize,
    restart_steps: usize,
}

impl ThetaScheme {
    /// Backward Euler (θ = 1), first order, L-stable.
    pub fn backward_euler() -> Self {
        ThetaScheme {
            theta: 1.0,
            startup_steps: 0,
            restart_steps: 0,
        }
    }

    /// Crank–Nicolson (θ = 1/2) started with two backward-Euler steps.
    pub fn crank_nicolson() -> Self {
        ThetaScheme {
            theta: 0.5,
            startup_steps: 2,
            restart_steps: 0,
        }
    }

    /// A general θ ∈ [1/2, 1] with `startup_steps` backward-Euler steps first.
    pub fn new(theta: f64, startup_steps: usize) -> Result<Self, ThermalError> {
        if !(0.5..=1.0).contains(&theta) {
            return Err(ThermalError::InvalidTheta { theta });
        }
        Ok(ThetaScheme {
            theta,
            startup_steps,
            restart_steps: 0,
        })
    }

    /// The same scheme with `n` backward-Euler steps after every growth of
    /// the step size (see the type's documentation).
    pub fn with_restarts(self, n: usize) -> Self {
        ThetaScheme {
            restart_steps: n,
            ..self
        }
    }

    /// Backward-Euler steps after every growth of Δt.
    pub fn restart_steps(&self) -> usize {
        self.restart_steps
    }

    /// θ for step `k` of the step sizes `steps` (0-based): backward Euler
    /// for the start-up and, with restarts, for the first steps after each
    /// growth of Δt; else θ.
    pub fn theta_for(&self, k: usize, steps: &[f64]) -> f64 {
        if k < self.startup_steps {
            return 1.0;
        }
        if self.restart_steps > 0 {
            // the last growth of Δt at or before step k
            let mut j = k;
            while j > 0 && steps[j - 1] >= steps[j] {
                j -= 1;
            }
            if j > 0 && k - j < self.restart_steps {
                return 1.0;
            }
        }
        self.theta
    }

    /// θ after the start-up.
    pub fn theta(&self) -> f64 {
        self.theta
    }

    /// Number of backward-Euler steps at the start.
    pub fn startup_steps(&self) -> usize {
        self.startup_steps
    }

    /// θ used for schedule step `k` (0-based).
    pub fn theta_at(&self, k: usize) -> f64 {
        if k < self.startup_steps {
            1.0
        } else {
            self.theta
        }
    }
}

#[cfg(test)]
mod tests {
    //! Goal: schedules end exactly where asked, with one Δt per block.
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn segments_land_on_their_ends_with_one_step_size_each() {
        let s = TimeSchedule::segments(&[(1.0, 0.3), (60.0, 10.0), (3600.0, 600.0)]).unwrap();
        assert_relative_eq!(s.end(), 3600.0, epsilon = 1e-9);
        assert_eq!(s.distinct_steps(), 3);
        assert!(s.steps()[..4].iter().all(|&d| (d - 0.25).abs() < 1e-15));
        assert_eq!(s.len(), 4 + 6 + 6);
    }

    #[test]
    fn geometric_schedule_grows_per_level_and_ends_on_time() {
        let s = TimeSchedule::geometric(0.1, 2.0, 3, 10.0).unwrap();
        assert_relative_eq!(s.end(), 10.0, epsilon = 1e-12);
        assert_eq!(&s.steps()[..6], &[0.1, 0.1, 0.1, 0.2, 0.2, 0.2]);
        assert!(s.steps().windows(2).take(s.len() - 2).all(|w| w[1] >= w[0]));
    }

    #[test]
    fn absurd_step_counts_are_refused_before_allocating() {
        assert!(matches!(
            TimeSchedule::segments(&[(1e300, 1e-300)]),
            Err(ThermalError::TooManySteps { .. })
        ));
        assert!(matches!(
            TimeSchedule::geometric(1e-300, 1.0, 10, 1.0),
            Err(ThermalError::TooManySteps { .. })
        ));
        assert!(matches!(
            TimeSchedule::uniform(1.0, MAX_STEPS + 1),
            Err(ThermalError::TooManySteps { .. })
        ));
    }

    #[test]
    fn restarts_take_backward_euler_after_every_growth_of_the_step() {
        let steps = [0.1, 0.1, 0.1, 1.0, 1.0, 1.0, 1.0, 0.5, 0.5, 2.0, 2.0];
        let cn = ThetaScheme::crank_nicolson();
        let got: Vec<f64> = (0..steps.len()).map(|k| cn.theta_for(k, &steps)).collect();
        assert_eq!(got, [1.0, 1.0, 0.5, 0.5, 0.5, 0.5, 0.5, 0.5, 0.5, 0.5, 0.5]);
        let r = cn.with_restarts(2);
        assert_eq!(r.restart_steps(), 2);
        let got: Vec<f64> = (0..steps.len()).map(|k| r.theta_for(k, &steps)).collect();
        // growths at steps 3 and 9; the shrink at 7 is no restart
        assert_eq!(got, [1.0, 1.0, 0.5, 1.0, 1.0, 0.5, 0.5, 0.5, 0.5, 1.0, 1.0]);
    }

    #[test]
    fn theta_scheme_uses_backward_euler_for_the_start_up() {
        let cn = ThetaScheme::crank_nicolson();
        assert_eq!(
            (cn.theta_at(0), cn.theta_at(1), cn.theta_at(2)),
            (1.0, 1.0, 0.5)
        );
        assert_eq!(ThetaScheme::backward_euler().theta_at(0), 1.0);
        assert!(ThetaScheme::new(1.2, 0).is_err());
    }
}
