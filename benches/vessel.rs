//! The whole published case, `tecon vessel` without the output files: mesh,
//! transient heat conduction (292 Crank–Nicolson steps to 72 000 s) and the
//! thermoelastic contact solves at the six output times.
//!
//! ```text
//! cargo bench -p tecon --bench vessel
//! ```
//!
//! Sizes: the paper mesh (136 triangles; goal < 1 s) and the subdivision of
//! the paper mesh closest to 10⁵ triangles (every interval in 27 parts:
//! 99 144 triangles, 50 600 nodes, 459 interface elements; goal < 60 s).
//! Order 2: the graded P2 mesh `graded(0)` (2 784 six-node triangles, the
//! mesh of the accuracy study, docs/vessel.md §9) beside the linear level 2
//! (the current default, 2 176 triangles).
//! Before measuring, one run prints its Newton iterations and solves.

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use tecon::mesh::VesselMeshSpec;
use tecon_cli::vessel::{VesselOptions, analyse};

fn vessel(c: &mut Criterion) {
    let mut g = c.benchmark_group("vessel");
    g.sample_size(10);
    // the last: the same mesh with full Newton passes (no condensation onto
    // the interface dofs), for comparison
    for (name, spec, condensation) in [
        ("paper", Ok(VesselMeshSpec::paper()), true),
        ("level2_p1", VesselMeshSpec::refined(2), true),
        ("graded0_p2", VesselMeshSpec::graded(0), true),
        (
            "1e5_triangles",
            VesselMeshSpec::with_triangles(100_000),
            true,
        ),
        (
            "1e5_triangles_full_passes",
            VesselMeshSpec::with_triangles(100_000),
            false,
        ),
    ] {
        let spec = spec.expect("mesh spec");
        let o = VesselOptions {
            mesh: spec,
            quiet: true,
            condensation,
            ..Default::default()
        };
        let run = analyse(&o).expect("vessel run");
        eprintln!(
            "{name}: {} triangles, {} Newton iterations in {} increments, {:?}; heat conduction {:.2} s, contact {:.2} s",
            run.mesh.n_triangles(),
            run.newton.iterations,
            run.newton.increments,
            run.newton.solves,
            run.thermal_seconds,
            run.contact_seconds
        );
        g.bench_with_input(BenchmarkId::new("full_run", name), &o, |b, o| {
            b.iter(|| analyse(o).expect("vessel run"))
        });
    }
    g.finish();
}

/// One-way against staggered two-way coupling with the contact conductance
/// (`--conductance contact --coupling two-way`): paper mesh, level 2
/// (linear; the default mesh when the goal of issue 13, two-way at most 5×
/// one-way, was set) and the default g0 (order 2; about 2.4 s per two-way
/// run on 2026-11-30, so this group takes a few minutes).
/// Before measuring, one run of each prints its Newton iterations, solves,
/// contact solves and times.
fn vessel_two_way(c: &mut Criterion) {
    let mut g = c.benchmark_group("vessel_coupling");
    g.sample_size(10);
    for (name, spec) in [
        ("paper", VesselMeshSpec::paper()),
        ("level2", VesselMeshSpec::refined(2).expect("level 2")),
        ("g0", VesselMeshSpec::graded(0).expect("g0")),
    ] {
        let one = VesselOptions {
            mesh: spec,
            contact_conductance: true,
            quiet: true,
            ..Default::default()
        };
        let two = VesselOptions {
            two_way: Some(Default::default()),
            ..one.clone()
        };
        let mut seconds = [0.0; 2];
        for (k, (mode, o)) in [("one-way", &one), ("two-way", &two)]
            .into_iter()
            .enumerate()
        {
            let run = analyse(o).expect("vessel run");
            seconds[k] = run.thermal_seconds + run.contact_seconds;
            let coupling = run.coupling.map_or(String::new(), |c| {
                format!(
                    ", {} blocks, {} contact solves, {} rejected",
                    c.blocks, c.iterations, c.rejected
                )
            });
            eprintln!(
                "{name} {mode}: {} Newton iterations in {} increments, {:?}{coupling}; heat conduction {:.2} s, contact {:.2} s",
                run.newton.iterations,
                run.newton.increments,
                run.newton.solves,
                run.thermal_seconds,
                run.contact_seconds
            );
        }
        eprintln!(
            "{name}: two-way / one-way (heat + contact, one run each) {:.1}",
            seconds[1] / seconds[0]
        );
        g.bench_with_input(BenchmarkId::new("one_way", name), &one, |b, o| {
            b.iter(|| analyse(o).expect("vessel run"))
        });
        g.bench_with_input(BenchmarkId::new("two_way", name), &two, |b, o| {
            b.iter(|| analyse(o).expect("vessel run"))
        });
    }
    g.finish();
}

criterion_group!(benches, vessel, vessel_two_way);
criterion_main!(benches);
