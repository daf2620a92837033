//! Where the time of the error-control ladder goes, per resolution.
//!
//! ```text
//! cargo run --release -p tecon-wavelet-bem --example ladder_profile -- SPEC [TOL]
//! ```
//!
//! Prints, for every n the error control visits, the times of assembly,
//! the full solve (assembly + factorisation), τ_max and the warping integrals,
//! then the total of `solve_to_tolerance` (wall and CPU seconds; stage times
//! are CPU seconds of all threads, which a loaded machine inflates less).

use std::time::Instant;
use tecon_wavelet_bem::daubechies::Daubechies;
use tecon_wavelet_bem::grading::Parametrisation;
use tecon_wavelet_bem::{Options, galerkin, sections, solve, solve_to_tolerance};

/// CPU time of all threads of this process so far (s), from
/// /proc/self/task/*/schedstat (0 where that cannot be read).
fn cpu() -> f64 {
    let Ok(dir) = std::fs::read_dir("/proc/self/task") else {
        return 0.0;
    };
    dir.flatten()
        .filter_map(|e| std::fs::read_to_string(e.path().join("schedstat")).ok())
        .filter_map(|s| s.split_whitespace().next()?.parse::<f64>().ok())
        .sum::<f64>()
        / 1e9
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let spec = args
        .get(1)
        .map(String::as_str)
        .unwrap_or("rectangle:w=1,h=2");
    let tol: f64 = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(1e-10);
    let sec = sections::parse_spec(spec).expect("section");
    let order: usize = args.get(3).and_then(|s| s.parse().ok()).unwrap_or(4);
    let grading: f64 = args.get(4).and_then(|s| s.parse().ok()).unwrap_or(8.0);
    let opts = Options {
        wavelet_order: order,
        grading,
        ..Options::default()
    };
    let t = Instant::now();
    let c0 = cpu();
    let c = solve_to_tolerance(&sec, &opts, tol, 4096).expect("solve");
    let total = t.elapsed().as_secs_f64();
    let ctot = cpu() - c0;
    println!(
        "{spec}: total {total:.3} s (cpu {ctot:.3} s), converged {}, J = {:.15e}, est J {:.1e} tau {:?} sc {:.1e} gamma {:.1e}",
        c.converged,
        c.solution.torsional_rigidity,
        c.j_error,
        c.tau_error,
        c.shear_centre_error,
        c.warping_error
    );
    for l in &c.levels {
        let o = Options { n: l.n, ..opts };
        let params: Vec<_> = sec
            .curves()
            .iter()
            .map(|cv| Parametrisation::new(cv, o.grading))
            .collect();
        let t0 = cpu();
        let _ = galerkin::assemble_with(
            &sec,
            &params,
            l.n,
            Daubechies::new(order).unwrap(),
            tecon_wavelet_bem::solve::symmetry_order(&sec, &o),
        )
        .unwrap();
        let ta = cpu() - t0;
        let t0 = cpu();
        let s = solve(&sec, &o).unwrap();
        let ts = cpu() - t0;
        let t0 = cpu();
        let _ = s.max_shear();
        let tm = cpu() - t0;
        let t0 = cpu();
        let _ = s.warping();
        let tw = cpu() - t0;
        println!(
            "  n = {:5}: assemble {ta:.3}  solve(total) {ts:.3}  tau_max {tm:.3}  warping {tw:.3}   J = {:.15e} tau {:?} G {:?}",
            l.n, l.torsional_rigidity, l.max_shear_stress, l.warping_constant
        );
    }
}
