//! Assembles and factorises a plane-strain system on 2·n² triangles and
//! prints the time of each phase; run under `/usr/bin/time -v` to read the
//! peak memory.
//!
//! ```text
//! cargo run --release -p tecon --example assemble_factorise -- 708
//! ```

use std::time::Instant;

use tecon::fem::reference::ElasticSet;
use tecon::fem::triangle::plane_strain_d;
use tecon::fem::{AssemblerBuilder, CholeskySolver, Dirichlet, Parallelism};
use tecon::mesh::rectangle;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let n: usize = std::env::args()
        .nth(1)
        .map(|s| s.parse())
        .transpose()?
        .unwrap_or(708);
    let t = Instant::now();
    let mesh = rectangle(0.0, 0.0, 1.0, 1.0, n, n)?;
    println!(
        "mesh: {} triangles, {} nodes ({:.2} s)",
        mesh.n_triangles(),
        mesh.n_nodes(),
        t.elapsed().as_secs_f64()
    );
    let set = ElasticSet {
        nodes: mesh.nodes(),
        triangles: mesh.triangles(),
        d: plane_strain_d(207e9, 0.3),
    };
    let t = Instant::now();
    let mut b = AssemblerBuilder::new(2 * mesh.n_nodes());
    let id = b.add_elements(&set);
    let asm = b.build()?;
    println!(
        "pattern: {} entries ({:.2} s)",
        asm.pattern().nnz(),
        t.elapsed().as_secs_f64()
    );
    let t = Instant::now();
    let mut k = asm.new_matrix();
    let mut f = vec![0.0; 2 * mesh.n_nodes()];
    asm.add(id, &set, &mut k, None, Parallelism::Rayon)?;
    println!("fill: {:.3} s", t.elapsed().as_secs_f64());
    let mut bc = Dirichlet::new();
    for &i in mesh.node_set("left")? {
        bc.set(2 * i, 0.0);
        bc.set(2 * i + 1, 0.0);
    }
    for &i in mesh.node_set("right")? {
        bc.set(2 * i, 1e-3);
    }
    bc.prepare(k.pattern())?.apply(&mut k, &mut f);
    let t = Instant::now();
    let mut ch = CholeskySolver::analyse(k.pattern().clone())?;
    println!(
        "symbolic: {:.2} s, factor entries {}",
        t.elapsed().as_secs_f64(),
        ch.factor_nnz()
    );
    let t = Instant::now();
    ch.factorise(&k)?;
    println!("numeric: {:.2} s", t.elapsed().as_secs_f64());
    let t = Instant::now();
    ch.solve(&mut f)?;
    println!(
        "solve: {:.3} s, u_x(max) = {:.6e}",
        t.elapsed().as_secs_f64(),
        f.iter().step_by(2).fold(0.0f64, |a, &b| a.max(b))
    );
    Ok(())
}
