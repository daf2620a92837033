//! The yield check: where the von Mises stress σ_vM of the elements exceeds
//! the yield stress σ_y of their material, and where the largest σ_vM is.
//!
//! The check is elastic: stresses above σ_y are not redistributed (the
//! solver has no plasticity), so an exceedance means the linear-elastic
//! result is not valid there — the report says so instead of staying silent.
//! Element values are used (constant in a linear triangle), not the
//! smoothed nodal ones, so no peak is averaged away.

use serde_json::{Value, json};
use tecon_elastic::{StressField, von_mises};
use tecon_mesh::Mesh;

/// The check in one region.
#[derive(Clone, Debug, PartialEq)]
pub struct RegionYield {
    /// region name
    pub region: String,
    /// yield stress of its material, Pa (None: not given)
    pub yield_stress: Option<f64>,
    /// largest element σ_vM, Pa
    pub peak: f64,
    /// centroid of the element with the peak, m
    pub peak_at: [f64; 2],
    /// index of that element
    pub peak_element: usize,
    /// that element as the report names it: "triangle 5", with its Gmsh
    /// element tag on a mesh read from a Gmsh file
    pub peak_label: String,
    /// elements with σ_vM > σ_y
    pub elements_above: usize,
    /// their area, m²
    pub area_above: f64,
    /// area of the region, m²
    pub area: f64,
}

/// The check over the mesh.
#[derive(Clone, Debug, PartialEq)]
pub struct YieldReport {
    /// one entry per region with elements, in the mesh's region order
    pub regions: Vec<RegionYield>,
}

fn centroid(mesh: &Mesh, e: usize) -> [f64; 2] {
    let t = mesh.triangles()[e];
    let p = |k: usize| mesh.nodes()[t[k]];
    [
        (p(0)[0] + p(1)[0] + p(2)[0]) / 3.0,
        (p(0)[1] + p(1)[1] + p(2)[1]) / 3.0,
    ]
}

/// Runs the check; `yield_of(region)` gives a region's yield stress.
pub fn check(
    mesh: &Mesh,
    stress: &StressField,
    yield_of: &dyn Fn(&str) -> Option<f64>,
) -> YieldReport {
    let areas = mesh.areas();
    let mut regions = Vec::new();
    for (r, name) in mesh.region_names().iter().enumerate() {
        let y = yield_of(name);
        let mut entry = RegionYield {
            region: name.clone(),
            yield_stress: y,
            peak: f64::NEG_INFINITY,
            peak_at: [f64::NAN; 2],
            peak_element: usize::MAX,
            peak_label: String::new(),
            elements_above: 0,
            area_above: 0.0,
            area: 0.0,
        };
        for (e, &reg) in mesh.element_regions().iter().enumerate() {
            if reg != r {
                continue;
            }
            let vm = von_mises(stress.element[e]);
            entry.area += areas[e];
            // ties go to the lower element index (deterministic)
            if vm > entry.peak {
                entry.peak = vm;
                entry.peak_element = e;
            }
            if y.is_some_and(|y| vm > y) {
                entry.elements_above += 1;
                entry.area_above += areas[e];
            }
        }
        if entry.peak_element != usize::MAX {
            entry.peak_at = centroid(mesh, entry.peak_element);
            entry.peak_label = mesh.triangle_label(entry.peak_element);
            regions.push(entry);
        }
    }
    YieldReport { regions }
}

impl YieldReport {
    /// Regions where σ_vM exceeds σ_y somewhere.
    pub fn exceeded(&self) -> Vec<&RegionYield> {
        self.regions
            .iter()
            .filter(|r| r.elements_above > 0)
            .collect()
    }

    /// The largest σ_vM of all regions.
    pub fn peak(&self) -> Option<&RegionYield> {
        self.regions.iter().max_by(|a, b| a.peak.total_cmp(&b.peak))
    }

    /// Report lines: one per region, then a warning per exceeded region.
    /// `polar` adds r and θ (about the origin) to positions.
    pub fn lines(&self, polar: bool) -> Vec<String> {
        let at = |p: [f64; 2]| {
            if polar {
                format!(
                    "(x, y) = ({:.4}, {:.4}) m, r = {:.4} m, θ = {:.2}°",
                    p[0],
                    p[1],
                    p[0].hypot(p[1]),
                    // in [0°, 360°), as the seam angles are given
                    p[1].atan2(p[0]).to_degrees().rem_euclid(360.0)
                )
            } else {
                format!("(x, y) = ({:.4e}, {:.4e}) m", p[0], p[1])
            }
        };
        let mut v = Vec::new();
        for r in &self.regions {
            match r.yield_stress {
                Some(y) => v.push(format!(
                    "region {}: peak von Mises {:.1} MPa at {} ({}); yield {:.1} MPa: {}",
                    r.region,
                    r.peak / 1e6,
                    at(r.peak_at),
                    r.peak_label,
                    y / 1e6,
                    if r.elements_above > 0 {
                        format!(
                            "EXCEEDED in {} elements, {:.3e} m² ({:.2} % of the region)",
                            r.elements_above,
                            r.area_above,
                            100.0 * r.area_above / r.area
                        )
                    } else {
                        format!(
                            "below everywhere (peak at {:.0} % of yield)",
                            100.0 * r.peak / y
                        )
                    }
                )),
                None => v.push(format!(
                    "region {}: peak von Mises {:.1} MPa at {} ({}); no yield stress given",
                    r.region,
                    r.peak / 1e6,
                    at(r.peak_at),
                    r.peak_label
                )),
            }
        }
        v
    }

    /// Warnings (one per region above yield) for reports.
    pub fn warnings(&self) -> Vec<String> {
        self.exceeded()
            .iter()
            .map(|r| {
                format!(
                    "von Mises stress above the yield stress ({:.1} MPa) in region {}: {} elements, {:.2} % of its area, peak {:.1} MPa at (x, y) = ({:.4}, {:.4}) m — the elastic result is not valid there",
                    r.yield_stress.unwrap_or(f64::NAN) / 1e6,
                    r.region,
                    r.elements_above,
                    100.0 * r.area_above / r.area,
                    r.peak / 1e6,
                    r.peak_at[0],
                    r.peak_at[1]
                )
            })
            .collect()
    }

    /// The check as JSON (SI units).
    pub fn to_json(&self) -> Value {
        Value::Array(
            self.regions
                .iter()
                .map(|r| {
                    json!({
                        "region": r.region,
                        "yield_stress": r.yield_stress,
                        "von_mises_max": r.peak,
                        "von_mises_max_at": r.peak_at,
                        "von_mises_max_element": r.peak_element,
                        "elements_above_yield": r.elements_above,
                        "area_above_yield": r.area_above,
                        "area": r.area,
                    })
                })
                .collect(),
        )
    }
}

/// Checks the `yield` keys of a case's materials: a stress > 0 in Pa.
pub fn check_case_keys(case: &crate::case::Case) -> Result<(), String> {
    for (i, m) in case.material.iter().enumerate() {
        if let Some(y) = m.yield_stress
            && !(y.is_finite() && y > 0.0)
        {
            return Err(format!(
                "material[{i}].yield (region '{}'): {y} is not a yield stress > 0 in Pa",
                m.region
            ));
        }
    }
    Ok(())
}

/// The check at every state: the JSON (one entry per output time), the
/// warnings (`t = … s: …`, one per time and region above yield) and the
/// report lines of the last state (a heading, then one line per region).
pub fn check_states(
    mesh: &Mesh,
    states: &[crate::driver::State],
    yield_of: &dyn Fn(&str) -> Option<f64>,
) -> (Value, Vec<String>, Vec<String>) {
    let mut all = Vec::new();
    let mut warnings = Vec::new();
    let mut last = Vec::new();
    for s in states {
        let r = check(mesh, &s.stress, yield_of);
        let when = format!("t = {} s", crate::plot::fmt_value(s.time));
        warnings.extend(r.warnings().into_iter().map(|w| format!("{when}: {w}")));
        all.push(json!({ "time": s.time, "regions": r.to_json() }));
        last = std::iter::once(format!("yield check at {when} (the last output):"))
            .chain(r.lines(false).into_iter().map(|l| format!("  {l}")))
            .collect();
    }
    (Value::Array(all), warnings, last)
}

#[cfg(test)]
mod tests {
    //! Goal: the check finds the element above yield and names its region.
    use super::*;
    use tecon_mesh::generators::rectangle;

    #[test]
    fn uniaxial_stress_above_yield_is_found_in_the_right_element() {
        let mesh = rectangle(0.0, 0.0, 2.0, 1.0, 2, 1).unwrap();
        let n = mesh.n_triangles();
        // uniaxial σ_xx: von Mises = |σ_xx| in plane stress (σ_zz = 0)
        let mut element = vec![[100e6, 0.0, 0.0, 0.0]; n];
        element[n - 1] = [300e6, 0.0, 0.0, 0.0];
        let s = StressField {
            element,
            nodal: vec![[0.0; 4]; mesh.n_nodes()],
            ..Default::default()
        };
        let rep = check(&mesh, &s, &|_| Some(250e6));
        assert_eq!(rep.regions.len(), 1);
        let r = &rep.regions[0];
        assert_eq!(r.elements_above, 1);
        assert_eq!(r.peak_element, n - 1);
        assert!((r.peak - 300e6).abs() < 1e-6);
        assert!((r.area - 2.0).abs() < 1e-12 && (r.area_above - 2.0 / n as f64).abs() < 1e-12);
        assert_eq!(rep.warnings().len(), 1);
        assert!(rep.lines(false)[0].contains("EXCEEDED"));
        let none = check(&mesh, &s, &|_| None);
        assert!(none.warnings().is_empty());
        assert!(none.lines(false)[0].contains("peak von Mises 300.0 MPa"));
    }
}
