//! Dense LU (faer) and the projected preconditioned conjugate gradient method
//! used on the compressed wavelet-basis matrix.

use crate::error::SolveError;
use faer::Mat;
use faer::prelude::Solve;

/// Solves the dense row-major system A x = b of order n by partial-pivoting LU (faer).
pub fn dense_lu_solve(n: usize, a: &[f64], b: &[f64]) -> Result<Vec<f64>, SolveError> {
    let m = Mat::<f64>::from_fn(n, n, |i, j| a[i * n + j]);
    let lu = m.partial_piv_lu();
    let rhs = Mat::<f64>::from_fn(n, 1, |i, _| b[i]);
    let x = lu.solve(&rhs);
    clear_vector_upper_state();
    let out: Vec<f64> = (0..n).map(|i| x[(i, 0)]).collect();
    if out.iter().all(|v| v.is_finite()) {
        Ok(out)
    } else {
        Err(SolveError::Linear(
            "LU produced non-finite values (singular matrix)".into(),
        ))
    }
}

/// Solves the dense row-major symmetric (indefinite) system A x = b by the
/// Bunch–Kaufman LBLᵀ factorisation (faer; half the work of LU).
pub fn dense_symmetric_solve(n: usize, a: &[f64], b: &[f64]) -> Result<Vec<f64>, SolveError> {
    let m = Mat::<f64>::from_fn(n, n, |i, j| a[i * n + j]);
    let f = m.lblt(faer::Side::Lower);
    let rhs = Mat::<f64>::from_fn(n, 1, |i, _| b[i]);
    let x = f.solve(&rhs);
    clear_vector_upper_state();
    let out: Vec<f64> = (0..n).map(|i| x[(i, 0)]).collect();
    if out.iter().all(|v| v.is_finite()) {
        Ok(out)
    } else {
        Err(SolveError::Linear(
            "LBLᵀ produced non-finite values (singular matrix)".into(),
        ))
    }
}

/// A zeroed vector of `len` doubles for a dense matrix, backed by huge pages
/// where the kernel offers them on request (Linux, transparent huge pages
/// in `madvise` mode, the common default).
///
/// A dense order-2048 matrix is 32 MB: 8192 pages of 4 kB, each a page
/// fault on first touch and a TLB entry, while the column gathers and the
/// factorisation stride across all of them. With 2 MB pages the hollow box
/// of the speed bench (n = 1024 per curve) went from 0.22 s to 0.16 s
/// (medians of 10, 2 cores). The advice is only a hint: where it is refused
/// nothing changes but the speed.
pub(crate) fn dense_zeroed(len: usize) -> Vec<f64> {
    // calloc: fresh pages are not touched yet, so the advice applies to
    // their first fault
    let v = vec![0.0; len];
    advise_huge_pages(&v);
    v
}

#[cfg(target_os = "linux")]
fn advise_huge_pages(v: &[f64]) {
    const HUGE: usize = 2 << 20;
    let start = v.as_ptr() as usize;
    let end = start + std::mem::size_of_val(v);
    let first = start.next_multiple_of(HUGE);
    let last = end - end % HUGE;
    if last > first {
        // SAFETY: [first, last) lies inside the allocation of `v`, which
        // outlives the call; MADV_HUGEPAGE changes how the kernel backs the
        // pages, never their contents, and its failure is harmless.
        unsafe {
            libc::madvise(
                first as *mut libc::c_void,
                last - first,
                libc::MADV_HUGEPAGE,
            );
        }
    }
}

#[cfg(not(target_os = "linux"))]
fn advise_huge_pages(_: &[f64]) {}

/// Singular values (descending) of a dense row-major n×n matrix.
pub fn singular_values(n: usize, a: &[f64]) -> Result<Vec<f64>, SolveError> {
    let m = Mat::<f64>::from_fn(n, n, |i, j| a[i * n + j]);
    let s = m.singular_values();
    clear_vector_upper_state();
    s.map_err(|e| SolveError::Linear(format!("SVD failed: {e:?}")))
}

/// A compressed symmetric matrix in CSR form.
#[derive(Clone, Debug)]
pub struct Csr {
    /// order
    pub n: usize,
    /// row pointers
    pub indptr: Vec<usize>,
    /// column indices
    pub indices: Vec<usize>,
    /// values
    pub data: Vec<f64>,
}

impl Csr {
    /// y = A x (rows independent: deterministic for any thread count).
    pub fn matvec(&self, x: &[f64], y: &mut [f64]) {
        use rayon::prelude::*;
        y.par_iter_mut().enumerate().for_each(|(i, yi)| {
            let mut s = 0.0;
            for k in self.indptr[i]..self.indptr[i + 1] {
                s += self.data[k] * x[self.indices[k]];
            }
            *yi = s;
        });
    }
    /// Number of stored entries.
    pub fn nnz(&self) -> usize {
        self.data.len()
    }
}

/// Thresholds a dense row-major symmetric matrix: keeps |a_ij| ≥ ε·max|a|.
pub fn threshold(n: usize, a: &[f64], eps: f64) -> Csr {
    let amax = a.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let cut = eps * amax;
    let mut indptr = vec![0usize];
    let mut indices = Vec::new();
    let mut data = Vec::new();
    for i in 0..n {
        for j in 0..n {
            let v = a[i * n + j];
            if v.abs() >= cut {
                indices.push(j);
                data.push(v);
            }
        }
        indptr.push(indices.len());
    }
    Csr {
        n,
        indptr,
        indices,
        data,
    }
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// Projected preconditioned CG for `A x + c e = f, eᵀx = 0` with A symmetric
/// positive definite on e^⊥ (the single-layer operator is, on densities of
/// zero mean). The preconditioner is the diagonal `d` (level scaling), projected
/// onto e^⊥. Returns (x, c, iterations, relative residual).
pub fn projected_pcg(
    a: &Csr,
    e: &[f64],
    f: &[f64],
    d: &[f64],
    tol: f64,
    max_iter: usize,
) -> Result<(Vec<f64>, f64, usize, f64), SolveError> {
    let n = a.n;
    let ee = dot(e, e);
    let proj = |v: &mut [f64]| {
        let s = dot(e, v) / ee;
        for (vi, ei) in v.iter_mut().zip(e) {
            *vi -= s * ei;
        }
    };
    let mut x = vec![0.0; n];
    let mut r = f.to_vec();
    proj(&mut r);
    let bnorm = dot(&r, &r).sqrt().max(f64::MIN_POSITIVE);
    let mut z: Vec<f64> = r.iter().zip(d).map(|(ri, di)| ri / di).collect();
    proj(&mut z);
    let mut p = z.clone();
    let mut rz = dot(&r, &z);
    let mut ap = vec![0.0; n];
    let mut it = 0;
    let mut rel = dot(&r, &r).sqrt() / bnorm;
    while it < max_iter && rel > tol {
        a.matvec(&p, &mut ap);
        proj(&mut ap);
        let pap = dot(&p, &ap);
        if pap.is_nan() || pap <= 0.0 {
            return Err(SolveError::Linear(format!(
                "CG breakdown (pᵀAp = {pap:e}) at iteration {it}"
            )));
        }
        let alpha = rz / pap;
        for i in 0..n {
            x[i] += alpha * p[i];
            r[i] -= alpha * ap[i];
        }
        z = r.iter().zip(d).map(|(ri, di)| ri / di).collect();
        proj(&mut z);
        let rz2 = dot(&r, &z);
        let beta = rz2 / rz;
        rz = rz2;
        for i in 0..n {
            p[i] = z[i] + beta * p[i];
        }
        it += 1;
        rel = dot(&r, &r).sqrt() / bnorm;
    }
    // multiplier from the e-component of the residual: c = eᵀ(f − A x)/eᵀe
    let mut ax = vec![0.0; n];
    a.matvec(&x, &mut ax);
    let c = e
        .iter()
        .zip(f.iter().zip(&ax))
        .map(|(ei, (fi, ai))| ei * (fi - ai))
        .sum::<f64>()
        / ee;
    Ok((x, c, it, rel))
}

/// Solves the augmented symmetric system of K curves with `n` unknowns each
/// (order N = K n),
///
/// ```text
/// A x + Σ_k c_k E_k = f,   E_kᵀ x = 0   (k = 0 … K − 1),
/// ```
///
/// E_k the vector `e` on block k and zero elsewhere, without forming the
/// augmented matrix. Since Σ_k E_kᵀ x = 0, adding κ E Eᵀ (E = Σ_k E_k) to A
/// changes nothing at the solution; for the Galerkin matrix of the single
/// layer with the kernel −(1/2π) ln|x − y|, κ E Eᵀ with κ = ln(ρ)/2π is the
/// Galerkin matrix of the constant kernel ln(ρ)/2π, so B = A + κ E Eᵀ
/// discretises −(1/2π) ln(|x − y|/ρ), positive definite whenever the
/// logarithmic capacity of Γ is below ρ. On smooth boundaries
/// (`try_cholesky`) B is factorised by Cholesky (faer, blocked, in place).
/// The discrete matrix of a graded boundary can keep a few small negative
/// eigenvalues (the smooth kernel part is interpolated, and it is not smooth
/// at a graded corner: −0.08/n on the equilateral triangle), so there B is
/// factorised by LDLᵀ without pivoting (the same cost as Cholesky, half that
/// of LU; its pivots on polygons and thin-walled boxes are ≥ 1e-4 of ‖B‖
/// in size). Either way the backward error ‖f − B y‖ / (‖B‖ ‖y‖) of the
/// solves is checked against [`BACKWARD_ERROR_LIMIT`] on a kept copy of B,
/// and a failed or inaccurate factorisation is redone by partial-pivoting LU.
/// The K multipliers follow from the K × K
/// Schur complement S = Eᵀ B⁻¹ E: c = S⁻¹ Eᵀ B⁻¹ f, x = B⁻¹ (f − E c).
///
/// `a` (row-major N × N, symmetric) is overwritten; the copy of B is kept
/// in `spare` (resized to N × N if it is not: a work array whose pages are
/// already touched saves the page faults of a fresh one). Returns (x, c).
pub fn shifted_saddle_solve(
    a: &mut [f64],
    spare: &mut Vec<f64>,
    n: usize,
    e: &[f64],
    f: &[f64],
    kappa: f64,
    try_cholesky: bool,
) -> Result<(Vec<f64>, Vec<f64>), SolveError> {
    use rayon::prelude::*;
    let big = f.len();
    let kc = big / n;
    debug_assert_eq!(a.len(), big * big);
    debug_assert_eq!(e.len(), n);
    spare.resize(big * big, 0.0);
    // B = A + κ E Eᵀ, its copy, and the squares of its rows in one pass;
    // the row sums are added in row order (thread-count independent; the
    // entries are far from overflow, so the plain sum of squares serves:
    // faer's scaled norm took 14 % of a box solve)
    let squares: Vec<f64> = a
        .par_chunks_mut(big)
        .zip(spare.par_chunks_mut(big))
        .enumerate()
        .map(|(i, (row, copy))| {
            let ei = kappa * e[i % n];
            let mut sq = 0.0;
            for (j, (v, c)) in row.iter_mut().zip(copy.iter_mut()).enumerate() {
                *v += ei * e[j % n];
                *c = *v;
                sq += *v * *v;
            }
            sq
        })
        .collect();
    let norm_b = squares.iter().sum::<f64>().sqrt();
    let par = faer::get_global_parallelism();
    // right-hand sides: f, E_0, …, E_{K−1}
    let mut rhs = Mat::<f64>::zeros(big, kc + 1);
    for i in 0..big {
        rhs[(i, 0)] = f[i];
        rhs[(i, 1 + i / n)] = e[i % n];
    }
    // a symmetric row-major matrix is its own column-major storage
    let mut m = faer::MatMut::from_column_major_slice_mut(a, big, big);
    // kept for the backward-error check and the LU fallback
    let backup = faer::MatRef::from_column_major_slice(spare, big, big);
    let factored = if try_cholesky {
        cholesky_solve(m.as_mut(), &rhs, par)
    } else {
        ldlt_solve(m.as_mut(), &rhs, par)
    };
    let y = match factored {
        Some(y) if backward_error(backup, norm_b, &rhs, &y) <= BACKWARD_ERROR_LIMIT => y,
        _ => backup.partial_piv_lu().solve(&rhs),
    };
    // (after the K × K solve of the Schur complement, which runs faer too)
    let solution = schur(&y, n, e);
    clear_vector_upper_state();
    solution
}

/// Clears the upper halves of the vector registers (`vzeroupper`) on the
/// calling thread and on every thread of the rayon pool.
///
/// faer's dense kernels (the AVX-512 assembly micro-kernels it dispatches
/// to at run time) return without `vzeroupper`, leaving the upper register
/// state dirty on every thread that ran them. Code compiled for the
/// baseline x86-64 target (SSE encoding: the kernel fills, the warping
/// sums, the FFTs' scalar parts) then pays a state-transition penalty on
/// vector instructions: after a factorisation the kernel fill at N = 2048
/// took 245 ms instead of 15 ms, and the box section at 1e-10 ran 0.99 s
/// instead of 0.36 s (2 threads). Called after every dense factorisation.
pub fn clear_vector_upper_state() {
    #[cfg(target_arch = "x86_64")]
    if std::is_x86_feature_detected!("avx") {
        rayon::broadcast(|_| zero_upper_checked());
        zero_upper_checked();
    }
}

#[cfg(target_arch = "x86_64")]
fn zero_upper_checked() {
    // SAFETY: only called after `is_x86_feature_detected!("avx")` found the
    // instruction on this CPU; vzeroupper touches no memory, and the upper
    // register halves are dead at a function boundary.
    unsafe { zero_upper() }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx")]
fn zero_upper() {
    std::arch::x86_64::_mm256_zeroupper()
}

/// Largest accepted backward error ‖f − B y‖ / (‖B‖ ‖y‖) (Frobenius norms) of a
/// symmetric factorisation without pivoting; above it the solve is redone by
/// partial-pivoting LU. Both LLᵀ and LDLᵀ give about 3e-16 on every section
/// measured (the same as LU).
pub const BACKWARD_ERROR_LIMIT: f64 = 1e-12;

/// ‖f − B y‖_F / (‖B‖_F ‖y‖_F) with `norm_b` = ‖B‖_F, or +∞ when anything
/// is not finite.
fn backward_error(b: faer::MatRef<'_, f64>, norm_b: f64, f: &Mat<f64>, y: &Mat<f64>) -> f64 {
    let r = f - b * y;
    let e = r.norm_l2() / (norm_b * y.norm_l2()).max(f64::MIN_POSITIVE);
    if e.is_finite() { e } else { f64::INFINITY }
}

/// Cholesky LLᵀ in place (blocked, faer) and the solve of every column of
/// `rhs`; None when a pivot is not positive.
fn cholesky_solve(m: faer::MatMut<'_, f64>, rhs: &Mat<f64>, par: faer::Par) -> Option<Mat<f64>> {
    use faer::dyn_stack::{MemBuffer, MemStack};
    use faer::linalg::cholesky::llt;
    let big = m.nrows();
    let mut m = m;
    let scratch = llt::factor::cholesky_in_place_scratch::<f64>(big, par, Default::default());
    let mut buf = MemBuffer::new(scratch);
    llt::factor::cholesky_in_place(
        m.as_mut(),
        Default::default(),
        par,
        MemStack::new(&mut buf),
        Default::default(),
    )
    .ok()?;
    let mut y = rhs.clone();
    let mut sbuf = MemBuffer::new(llt::solve::solve_in_place_scratch::<f64>(
        big,
        rhs.ncols(),
        par,
    ));
    llt::solve::solve_in_place(m.as_ref(), y.as_mut(), par, MemStack::new(&mut sbuf));
    Some(y)
}

/// LDLᵀ without pivoting in place (blocked, faer: the cost of Cholesky, half
/// that of LU) and the solve of every column of `rhs`; None at a zero pivot.
/// Not backward stable in general; the caller checks the backward error.
fn ldlt_solve(m: faer::MatMut<'_, f64>, rhs: &Mat<f64>, par: faer::Par) -> Option<Mat<f64>> {
    use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
    use faer::linalg::cholesky::ldlt;
    let big = m.nrows();
    let mut m = m;
    let scratch = ldlt::factor::cholesky_in_place_scratch::<f64>(big, par, Default::default());
    let mut buf = MemBuffer::new(scratch);
    ldlt::factor::cholesky_in_place(
        m.as_mut(),
        Default::default(),
        par,
        MemStack::new(&mut buf),
        Default::default(),
    )
    .ok()?;
    let l = m.as_ref();
    let mut y = rhs.clone();
    ldlt::solve::solve_in_place_with_conj(
        l,
        l.diagonal(),
        faer::Conj::No,
        y.as_mut(),
        par,
        MemStack::new(&mut MemBuffer::new(StackReq::EMPTY)),
    );
    Some(y)
}

/// The multipliers and the solution from the solves Y = B⁻¹ [f, E_0, …, E_{K−1}].
fn schur(y: &Mat<f64>, n: usize, e: &[f64]) -> Result<(Vec<f64>, Vec<f64>), SolveError> {
    let big = y.nrows();
    let kc = big / n;
    // Schur complement S_kl = E_kᵀ B⁻¹ E_l and r_k = E_kᵀ B⁻¹ f
    let s = Mat::<f64>::from_fn(kc, kc, |k, l| {
        (0..n).map(|j| e[j] * y[(k * n + j, 1 + l)]).sum()
    });
    let r = Mat::<f64>::from_fn(kc, 1, |k, _| (0..n).map(|j| e[j] * y[(k * n + j, 0)]).sum());
    let c = s.partial_piv_lu().solve(&r);
    let c: Vec<f64> = (0..kc).map(|k| c[(k, 0)]).collect();
    let x: Vec<f64> = (0..big)
        .map(|i| y[(i, 0)] - (0..kc).map(|l| y[(i, 1 + l)] * c[l]).sum::<f64>())
        .collect();
    if x.iter().chain(&c).all(|v| v.is_finite()) {
        Ok((x, c))
    } else {
        Err(SolveError::Linear(
            "the shifted single-layer system is singular (non-finite solution)".into(),
        ))
    }
}
