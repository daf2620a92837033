//! Interface conductance and coupling keys of case files:
//! `conductance = 850.0` or an `[interface.conductance]` table with
//! `law = "constant" | "power" | "mikic-yovanovich" | "gap"`, and the
//! `[coupling]` table (`mode = "one-way" | "two-way"`).

use std::path::Path;

use serde::Deserialize;
use tecon_thermal::{
    ContactPart, GasGap, JointConductance, MikicYovanovich, PowerLaw, Radiation, ThermalError,
};

use crate::case::{CliResult, err};
use crate::driver::{Coupling, TwoWay};

/// `[interface.conductance]`.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ConductanceSection {
    /// `"constant"`, `"power"`, `"mikic-yovanovich"` or `"gap"` (gas only).
    pub law: String,
    /// constant: h, W/(m² K).
    pub h: Option<f64>,
    /// power: h₀, W/(m² K) at p₀.
    pub h0: Option<f64>,
    /// power: p₀, Pa.
    pub p0: Option<f64>,
    /// power: exponent m.
    pub exponent: Option<f64>,
    /// mikic-yovanovich: combined RMS roughness σ, m.
    pub roughness: Option<f64>,
    /// mikic-yovanovich: combined asperity slope m.
    pub slope: Option<f64>,
    /// mikic-yovanovich: microhardness H_c, Pa.
    pub microhardness: Option<f64>,
    /// mikic-yovanovich: harmonic-mean conductivity k_s, W/(m K).
    pub harmonic_conductivity: Option<f64>,
    /// Gas in the gap: conductivity k_g, W/(m K) (adds k_g/(g + g₀)).
    pub gas_conductivity: Option<f64>,
    /// Gas in the gap: temperature-jump distance g₀, m.
    pub jump_distance: Option<f64>,
    /// Radiation across the gap: effective emissivity ε.
    pub emissivity: Option<f64>,
}

/// A parsed interface conductance.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Conductance {
    /// `conductance = h` (the constant law of one-way analyses).
    Constant(f64),
    /// A law that may read the contact state.
    Law(JointConductance),
}

/// Parses `conductance` of interface `key` (a number or a table).
pub fn parse(f: &Path, key: &str, v: &toml::Value) -> CliResult<Conductance> {
    let key = format!("{key}.conductance");
    let t = match v {
        toml::Value::Float(h) => return constant(f, &key, *h),
        toml::Value::Integer(h) => return constant(f, &key, *h as f64),
        toml::Value::Table(_) => v
            .clone()
            .try_into::<ConductanceSection>()
            .map_err(|e| err(f, format!("{key}: {}", e.message().replace('\n', " "))))?,
        other => {
            return Err(err(
                f,
                format!(
                    "{key} = {other}: give a number (W/(m² K)) or a table with law = \"constant\" | \"power\" | \"mikic-yovanovich\" | \"gap\""
                ),
            ));
        }
    };
    let law_err = |e: ThermalError| err(f, format!("{key}: {e}"));
    let need = |name: &str, v: Option<f64>| {
        v.ok_or_else(|| err(f, format!("{key}: law = \"{}\" needs {name}", t.law)))
    };
    let extra = |allowed: &[&str]| -> CliResult<()> {
        for (n, s) in [
            ("h", t.h),
            ("h0", t.h0),
            ("p0", t.p0),
            ("exponent", t.exponent),
            ("roughness", t.roughness),
            ("slope", t.slope),
            ("microhardness", t.microhardness),
            ("harmonic_conductivity", t.harmonic_conductivity),
        ] {
            if s.is_some() && !allowed.contains(&n) {
                return Err(err(
                    f,
                    format!("{key}.{n}: not a parameter of law = \"{}\"", t.law),
                ));
            }
        }
        Ok(())
    };
    let contact = match t.law.as_str() {
        "constant" => {
            extra(&["h"])?;
            let h = need("h", t.h)?;
            if !(h.is_finite() && h >= 0.0) {
                return Err(err(f, format!("{key}.h = {h}: must be non-negative")));
            }
            ContactPart::Constant(h)
        }
        "power" => {
            extra(&["h0", "p0", "exponent"])?;
            ContactPart::Power(
                PowerLaw::new(
                    need("h0", t.h0)?,
                    need("p0", t.p0)?,
                    need("exponent", t.exponent)?,
                )
                .map_err(law_err)?,
            )
        }
        "mikic-yovanovich" => {
            extra(&[
                "roughness",
                "slope",
                "microhardness",
                "harmonic_conductivity",
            ])?;
            ContactPart::MikicYovanovich(
                MikicYovanovich::new(
                    need("roughness", t.roughness)?,
                    need("slope", t.slope)?,
                    need("microhardness", t.microhardness)?,
                    need("harmonic_conductivity", t.harmonic_conductivity)?,
                )
                .map_err(law_err)?,
            )
        }
        "gap" => {
            extra(&[])?;
            if t.gas_conductivity.is_none() {
                return Err(err(
                    f,
                    format!(
                        "{key}: law = \"gap\" needs gas_conductivity (k_g, W/(m K)) and jump_distance (g₀, m)"
                    ),
                ));
            }
            ContactPart::None
        }
        other => {
            return Err(err(
                f,
                format!(
                    "{key}.law = \"{other}\": expected \"constant\", \"power\", \"mikic-yovanovich\" or \"gap\""
                ),
            ));
        }
    };
    let gas = match (t.gas_conductivity, t.jump_distance) {
        (None, None) => None,
        (Some(k), Some(g0)) => Some(GasGap::new(k, g0).map_err(law_err)?),
        (Some(_), None) => {
            return Err(err(
                f,
                format!("{key}: gas_conductivity needs jump_distance (g₀, m)"),
            ));
        }
        (None, Some(_)) => {
            return Err(err(
                f,
                format!("{key}.jump_distance: a gap law needs gas_conductivity (k_g, W/(m K))"),
            ));
        }
    };
    let radiation = t
        .emissivity
        .map(Radiation::new)
        .transpose()
        .map_err(law_err)?;
    Ok(Conductance::Law(JointConductance {
        contact,
        gas,
        radiation,
    }))
}

fn constant(f: &Path, key: &str, h: f64) -> CliResult<Conductance> {
    if h.is_finite() && h > 0.0 {
        Ok(Conductance::Constant(h))
    } else {
        Err(err(f, format!("{key} = {h}: must be positive")))
    }
}

/// `[coupling]`.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CouplingSection {
    /// `"one-way"` (default: heat conduction first, then contact) or
    /// `"two-way"` (staggered per time step).
    pub mode: Option<String>,
    /// two-way: thermal steps per contact solve (default 1).
    pub sync_interval: Option<usize>,
    /// two-way: settled when no conductance changes by more than this
    /// fraction of the largest (default 1e-4).
    pub tolerance: Option<f64>,
    /// two-way: most coupling iterations per block (default 30).
    pub max_iterations: Option<usize>,
    /// two-way: adaptive blocks with this largest relative conductance
    /// error per block (default 0.01; fixed blocks when only
    /// `sync_interval` is given).
    pub sync_tolerance: Option<f64>,
}

/// The coupling of `[coupling]` (absent: one-way).
pub fn coupling(f: &Path, c: Option<&CouplingSection>, has_thermal: bool) -> CliResult<Coupling> {
    let Some(c) = c else {
        return Ok(Coupling::OneWay);
    };
    match c.mode.as_deref().unwrap_or("one-way") {
        "one-way" => {
            for (n, s) in [
                ("sync_interval", c.sync_interval.is_some()),
                ("tolerance", c.tolerance.is_some()),
                ("max_iterations", c.max_iterations.is_some()),
                ("sync_tolerance", c.sync_tolerance.is_some()),
            ] {
                if s {
                    return Err(err(
                        f,
                        format!("coupling.{n}: only used with mode = \"two-way\""),
                    ));
                }
            }
            Ok(Coupling::OneWay)
        }
        "two-way" => {
            if !has_thermal {
                return Err(err(
                    f,
                    "coupling.mode = \"two-way\": needs heat conduction (a [thermal] section)",
                ));
            }
            let d = TwoWay::default();
            let sync_interval = c.sync_interval.unwrap_or(d.sync_interval);
            if sync_interval == 0 {
                return Err(err(f, "coupling.sync_interval: at least 1"));
            }
            let tolerance = c.tolerance.unwrap_or(d.tolerance);
            if !(tolerance.is_finite() && tolerance > 0.0) {
                return Err(err(
                    f,
                    format!("coupling.tolerance = {tolerance}: must be positive"),
                ));
            }
            let max_iterations = c.max_iterations.unwrap_or(d.max_iterations);
            if max_iterations == 0 {
                return Err(err(f, "coupling.max_iterations: at least 1"));
            }
            let sync_tolerance = match (c.sync_interval, c.sync_tolerance) {
                (Some(_), None) => None,
                (_, t) => t.or(d.sync_tolerance),
            };
            if let Some(t) = sync_tolerance
                && !(t.is_finite() && t > 0.0)
            {
                return Err(err(
                    f,
                    format!("coupling.sync_tolerance = {t}: must be positive"),
                ));
            }
            Ok(Coupling::TwoWay(TwoWay {
                sync_interval,
                tolerance,
                max_iterations,
                sync_tolerance,
            }))
        }
        other => Err(err(
            f,
            format!("coupling.mode = \"{other}\": expected \"one-way\" or \"two-way\""),
        )),
    }
}
