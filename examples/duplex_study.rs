//! The FE non-uniqueness study of the duplex tube (docs/coupling.md §2):
//! heat flowing from the outer tube into the inner one lowers the contact
//! pressure; with a steep conductance h = 100 + 1000 (p / 4 MPa)^6 there are
//! three steady states. Prints the one-dimensional states, the FE states
//! (roots of the FE map g_FE(h(p)) − p, with their slopes), and two-way
//! transients from several starting states.
//!
//! ```text
//! cargo run --release -p tecon --example duplex_study
//! ```

use tecon_cli::duplex::{DuplexTube, FeDuplex, Start, SteepLaw};

fn main() -> Result<(), Box<dyn std::error::Error + Send + Sync>> {
    let tube = DuplexTube {
        a: 0.05,
        c: 0.06,
        b: 0.08,
        conductivity: [40.0; 2],
        youngs_modulus: [200e9; 2],
        poisson_ratio: [0.3; 2],
        expansion: [12e-6; 2],
        t_inner: 20.0,
        t_outer: 60.0,
        t_ref: 20.0,
        interference: 40e-6,
    };
    let law = SteepLaw {
        h_base: 100.0,
        h0: 1000.0,
        p0: 4e6,
        exponent: 6.0,
    };
    let one_d = tube.steady_states(&|p| law.h(p), 40e6, 4000);
    for s in &one_d {
        println!(
            "1D: p = {:.5} MPa, h = {:.2}, slope {:.4}, stable {}",
            s.state.pressure / 1e6,
            s.conductance,
            s.slope,
            s.stable
        );
    }
    let rows: Vec<(usize, [usize; 2])> = std::env::args()
        .nth(1)
        .map(|s| s.parse::<usize>())
        .transpose()?
        .map(|k| vec![(12 * k, [3 * k, 4 * k])])
        .unwrap_or_else(|| vec![(12, [3, 4]), (24, [6, 8]), (48, [12, 16])]);
    for (segments, rows) in rows {
        let fe = FeDuplex {
            tube,
            law,
            segments,
            rows,
        };
        let t = std::time::Instant::now();
        for h in [100.0, 500.0, 2000.0] {
            let p = fe.pressure_at(h)?;
            let e = tube.at(h).pressure;
            println!(
                "segments {segments} rows {rows:?}: h = {h}: p FE {:.6} MPa, 1D {:.6} MPa ({:+.2e})",
                p / 1e6,
                e / 1e6,
                p / e - 1.0
            );
        }
        let states = fe.steady_states(12e6, 24, 1e-8)?;
        for (s, d) in states.iter().zip(&one_d) {
            println!(
                "FE: p = {:.5} MPa ({:+.2e} vs 1D), slope {:.4}, stable {}",
                s.pressure / 1e6,
                s.pressure / d.state.pressure - 1.0,
                s.slope,
                s.stable
            );
        }
        println!("  ({:.2} s)", t.elapsed().as_secs_f64());
    }
    let fe = FeDuplex {
        tube,
        law,
        segments: 12,
        rows: [3, 4],
    };
    let segments = [[10.0, 0.5], [100.0, 5.0], [1000.0, 20.0], [6000.0, 100.0]];
    let times = [10.0, 100.0, 300.0, 1000.0, 3000.0, 6000.0];
    let starts = [
        ("uniform 20 °C", Start::Uniform(20.0)),
        ("uniform 60 °C", Start::Uniform(60.0)),
        (
            "steady, outside at 40 °C",
            Start::Field(fe.steady_field(20.0, 40.0, law.h(9e6))?),
        ),
        (
            "steady, outside at 80 °C",
            Start::Field(fe.steady_field(20.0, 80.0, law.h(1e6))?),
        ),
    ];
    for (name, start) in &starts {
        let t = std::time::Instant::now();
        let run = fe.transient(start, &segments, &times, None)?;
        print!("transient from {name}:");
        for p in &run {
            print!(
                " t={}: {:.4} MPa ({:.2}/{:.2} °C, {} it)",
                p.time,
                p.pressure / 1e6,
                p.t_joint[0],
                p.t_joint[1],
                p.coupling_iterations
            );
        }
        println!("  ({:.2} s)", t.elapsed().as_secs_f64());
    }
    let s = fe.steady_two_way()?;
    println!(
        "two-way steady from the unloaded joint: {:.5} MPa",
        s.pressure / 1e6
    );
    Ok(())
}
