//! Detection of free rigid-body modes before a solve.
//!
//! Each body contributes its rigid modes v_k (constant temperature; x- and
//! y-translation and rotation about its centroid for plane displacement).
//! With the constraints applied, the normalised energy matrix
//! Ĝ_jk = v_jᵀ A v_k / √(s_j s_k), s_k = Σ_i |a_ii| v_k,i², has an eigenvalue
//! ≈ 0 exactly when some combination of modes is left free; the eigenvector
//! names the bodies and modes that take part. A mode held by one dof among
//! N has Ĝ ≈ 1/N, a truly free one ≈ 1e-16, so the threshold 1e-11 separates
//! them for any mesh up to 10⁹ dofs.

use nalgebra::DMatrix;

use crate::dofmap::DofMap;
use crate::error::FemError;
use crate::pattern::CsrMatrix;

/// Normalised energy below which a mode counts as free.
pub const FREE_MODE_TOLERANCE: f64 = 1e-11;

/// A named rigid mode of one body, as a sparse vector over the system's dofs.
#[derive(Debug, Clone, PartialEq)]
pub struct RigidMode {
    /// The body's name.
    pub body: String,
    /// The mode's name ("x-translation", "rotation", "uniform temperature").
    pub name: String,
    /// (dof, value) pairs.
    pub entries: Vec<(usize, f64)>,
}

/// The constant mode of a scalar field on a body's nodes.
pub fn scalar_mode(dofmap: &DofMap, body: &str, nodes: &[usize], name: &str) -> RigidMode {
    RigidMode {
        body: body.into(),
        name: name.into(),
        entries: nodes.iter().map(|&n| (dofmap.dof(n, 0), 1.0)).collect(),
    }
}

/// The three rigid modes of plane displacement on a body's nodes.
pub fn plane_rigid_modes(
    dofmap: &DofMap,
    body: &str,
    nodes: &[usize],
    coords: &[[f64; 2]],
) -> Vec<RigidMode> {
    let n = nodes.len().max(1) as f64;
    let (cx, cy) = nodes.iter().fold((0.0, 0.0), |(x, y), &i| {
        (x + coords[i][0] / n, y + coords[i][1] / n)
    });
    let tx = nodes.iter().map(|&i| (dofmap.dof(i, 0), 1.0)).collect();
    let ty = nodes.iter().map(|&i| (dofmap.dof(i, 1), 1.0)).collect();
    let mut rot = Vec::with_capacity(2 * nodes.len());
    for &i in nodes {
        rot.push((dofmap.dof(i, 0), -(coords[i][1] - cy)));
        rot.push((dofmap.dof(i, 1), coords[i][0] - cx));
    }
    vec![
        RigidMode {
            body: body.into(),
            name: "x-translation".into(),
            entries: tx,
        },
        RigidMode {
            body: body.into(),
            name: "y-translation".into(),
            entries: ty,
        },
        RigidMode {
            body: body.into(),
            name: "rotation".into(),
            entries: rot,
        },
    ]
}

/// Checks that no combination of `modes` is free in `matrix` (constraints
/// already applied). Returns the first free combination as
/// [`FemError::Unconstrained`].
pub fn check_rigid_modes(matrix: &CsrMatrix, modes: &[RigidMode]) -> Result<(), FemError> {
    let m = modes.len();
    if m == 0 {
        return Ok(());
    }
    let n = matrix.n();
    let diag: Vec<f64> = (0..n).map(|i| matrix.get(i, i).abs()).collect();
    let mut x = vec![0.0; n];
    let mut y = vec![0.0; n];
    let mut g = DMatrix::zeros(m, m);
    let mut s = vec![0.0; m];
    for (k, mk) in modes.iter().enumerate() {
        for &(d, v) in &mk.entries {
            if d >= n {
                return Err(FemError::DofOutOfRange {
                    what: format!("rigid mode '{}' of body '{}'", mk.name, mk.body),
                    dof: d,
                    n_dofs: n,
                });
            }
            x[d] = v;
            s[k] += diag[d] * v * v;
        }
        matrix.mul_vec(&x, &mut y);
        for (j, mj) in modes.iter().enumerate() {
            g[(j, k)] = mj.entries.iter().map(|&(d, v)| v * y[d]).sum::<f64>();
        }
        for &(d, _) in &mk.entries {
            x[d] = 0.0;
        }
    }
    let mut gn = DMatrix::zeros(m, m);
    for j in 0..m {
        for k in 0..m {
            let sc = (s[j] * s[k]).sqrt();
            gn[(j, k)] = if sc > 0.0 {
                0.5 * (g[(j, k)] + g[(k, j)]) / sc
            } else {
                0.0
            };
        }
    }
    // A mode with s = 0 touches only empty rows: it is free.
    if let Some(k) = (0..m).find(|&k| s[k] == 0.0) {
        return Err(unconstrained(modes, &[k], 0.0));
    }
    let eig = nalgebra::SymmetricEigen::new(gn);
    let mut order: Vec<usize> = (0..m).collect();
    order.sort_by(|&a, &b| eig.eigenvalues[a].total_cmp(&eig.eigenvalues[b]));
    let k0 = order[0];
    let lam = eig.eigenvalues[k0];
    if lam < FREE_MODE_TOLERANCE {
        let v = eig.eigenvectors.column(k0);
        let vmax = v.iter().fold(0.0f64, |a, x| a.max(x.abs()));
        let part: Vec<usize> = (0..m).filter(|&k| v[k].abs() > 0.2 * vmax).collect();
        return Err(unconstrained(modes, &part, lam));
    }
    Ok(())
}

fn unconstrained(modes: &[RigidMode], part: &[usize], energy: f64) -> FemError {
    let mut bodies: Vec<String> = Vec::new();
    for &k in part {
        if !bodies.contains(&modes[k].body) {
            bodies.push(modes[k].body.clone());
        }
    }
    let names: Vec<String> = part.iter().map(|&k| modes[k].name.clone()).collect();
    let description = if bodies.len() == 1 {
        let mut uniq = names.clone();
        uniq.dedup();
        format!("body '{}' ({})", bodies[0], uniq.join(" + "))
    } else {
        let parts: Vec<String> = part
            .iter()
            .map(|&k| format!("{} of '{}'", modes[k].name, modes[k].body))
            .collect();
        format!(
            "bodies {} together ({})",
            bodies
                .iter()
                .map(|b| format!("'{b}'"))
                .collect::<Vec<_>>()
                .join(" and "),
            parts.join(", ")
        )
    };
    FemError::Unconstrained {
        description,
        bodies,
        modes: names,
        energy,
    }
}
