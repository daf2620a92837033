//! Memory estimates before large allocations: a mesh too large for this
//! machine is refused with the estimate, before anything is built, instead
//! of an abort ("memory allocation … failed", exit 134) or minutes of
//! silence followed by the kernel's out-of-memory kill.
//!
//! The estimate of a thermoelastic contact analysis is fitted to the peak
//! resident size of `tecon vessel` (release build, plane strain, one-way,
//! the heat conduction running beside the contact solves): 55 MB at 8 704
//! triangles (level 3), 187 MB at 34 816 (level 4), 501 MB at 99 144
//! (`t1e5`), 683 MB at 139 264 (level 5) and 4.94 GB at 1 005 856 (`t1e6`);
//! at order 2, 667 MB at 44 672 (g2) and 5.15 GB at 251 464 (`t2.5e5
//! --order 2`). The sparse Cholesky factors grow like n log n on these
//! meshes, so the estimate is `16 MB + T · (3300 + 150 log₂ T)` bytes for T
//! three-node triangles (11–28 % over the measured peaks) and 4.5 times the
//! per-triangle part for six-node triangles (four times the unknowns; 32 %
//! over at `t2.5e5`, 70 % at g2).
//!
//! The memory available is the smaller of `MemAvailable` (/proc/meminfo)
//! and the address-space limit of the process (`ulimit -v`,
//! /proc/self/limits).

use tecon_mesh::VesselMeshSpec;

use crate::case::Case;

/// Estimated peak bytes of the whole analysis (mesh, heat conduction,
/// contact solves, outputs) on `triangles` triangles of order `order`.
pub fn analysis_bytes(triangles: usize, order: usize) -> u64 {
    let t = triangles.max(1) as f64;
    let per = (3300.0 + 150.0 * t.log2()) * if order == 2 { 4.5 } else { 1.0 };
    let b = 16e6 + t * per;
    if b.is_finite() && b < u64::MAX as f64 {
        b as u64
    } else {
        u64::MAX
    }
}

/// Bytes a new allocation can get now: the smaller of `MemAvailable` and the
/// address-space limit (`None` where neither can be read); the same reading
/// the torsion solver checks its dense sizes against.
pub fn available_bytes() -> Option<u64> {
    tecon_wavelet_bem::memory::available_bytes()
}

fn gb(b: u64) -> String {
    format!("{:.1} GB", b as f64 / 1e9)
}

/// Refuses an analysis of `triangles` triangles (of `order`) that needs
/// more than `available` bytes; `what` names the mesh in the message.
pub fn check_against(
    what: &str,
    triangles: usize,
    order: usize,
    available: u64,
) -> Result<(), String> {
    let need = analysis_bytes(triangles, order);
    if need > available {
        return Err(format!(
            "{what}: {triangles} triangles need about {} of memory to analyse, but only {} are available; choose a coarser mesh (the estimate grows like T log T: about {} per 10⁵ triangles)",
            gb(need),
            gb(available),
            gb(analysis_bytes(100_000, order))
        ));
    }
    Ok(())
}

/// [`check_against`] with the memory available now (no check where it cannot be read).
pub fn check(what: &str, triangles: usize, order: usize) -> Result<(), String> {
    match available_bytes() {
        Some(a) => check_against(what, triangles, order, a),
        None => Ok(()),
    }
}

/// The generator's own check (generation only) with the address-space limit too.
pub fn check_generation(spec: &VesselMeshSpec) -> Result<(), String> {
    match available_bytes() {
        Some(a) => tecon_mesh::check_memory(spec, a).map_err(|e| e.to_string()),
        None => Ok(()),
    }
}

/// Triangles a case's generator will make, known before the mesh is built
/// (`None` for a mesh file or a generator whose keys are checked later).
pub fn case_triangles(case: &Case) -> Option<(usize, usize)> {
    let m = &case.mesh;
    match m.generator.as_deref()? {
        "vessel" => {
            let spec = m.vessel_spec.or_else(|| match &m.preset {
                None => VesselMeshSpec::refined(2).ok(),
                Some(toml::Value::Integer(l)) => u32::try_from(*l)
                    .ok()
                    .and_then(|l| VesselMeshSpec::refined(l).ok()),
                Some(toml::Value::String(s)) if s == "paper" => Some(VesselMeshSpec::paper()),
                Some(toml::Value::String(s)) => s
                    .parse::<u32>()
                    .ok()
                    .and_then(|l| VesselMeshSpec::refined(l).ok()),
                Some(_) => None,
            })?;
            Some((spec.n_triangles(), spec.order))
        }
        "rectangle" => {
            let [nx, ny] = m.divisions?;
            Some((nx.checked_mul(ny)?.checked_mul(2)?, 1))
        }
        "annulus" => {
            let s = m.segments?;
            let rows = m
                .layer
                .iter()
                .try_fold(0usize, |a, l| a.checked_add(l.rows))?;
            Some((s.checked_mul(rows)?.checked_mul(2)?, 1))
        }
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    //! Goal: the estimate stays above the measured peaks and a size that
    //! does not fit is refused with the numbers.
    use super::*;

    #[test]
    fn the_estimate_covers_the_measured_peaks() {
        // measured peak resident sizes of `tecon vessel --mesh 3/4/t1e5/5/t1e6`
        // and, at order 2, g2 and `t2.5e5 --order 2`
        for (t, order, measured) in [
            (8_704, 1, 55.5e6),
            (34_816, 1, 187e6),
            (99_144, 1, 501e6),
            (139_264, 1, 683e6),
            (1_005_856, 1, 4.94e9),
            (44_672, 2, 667e6),
            (251_464, 2, 5.15e9),
        ] {
            let e = analysis_bytes(t, order) as f64;
            assert!(
                e > measured && e < 2.0 * measured,
                "{t} triangles of order {order}: estimate {e:.3e} against measured {measured:.3e}"
            );
        }
        assert!(analysis_bytes(1000, 2) > analysis_bytes(1000, 1));
        assert_eq!(analysis_bytes(usize::MAX, 2), u64::MAX);
    }

    #[test]
    fn level_nine_is_refused_with_the_estimate() {
        let spec = VesselMeshSpec::refined(9).unwrap();
        let e = check_against("--mesh 9", spec.n_triangles(), 1, 20_000_000_000).unwrap_err();
        assert!(
            e.contains("--mesh 9") && e.contains("35651584 triangles"),
            "{e}"
        );
        assert!(
            e.contains("GB of memory") && e.contains("20.0 GB are available"),
            "{e}"
        );
        check_against("--mesh 2", 2176, 1, 20_000_000_000).unwrap();
    }
}
