//! Dense shift-and-invert reduction for small models.
//!
//! K − σM = L Lᵀ (σ < 0), C = L⁻¹ M L⁻ᵀ (symmetric, n × n), C = Y diag(μ) Yᵀ,
//! μ = 1/(ω² − σ); the `count` largest μ give the lowest modes φ = L⁻ᵀ y
//! (not yet normalised). Cost ≈ (1/3 + 2) n³ for the reduction plus a dense
//! symmetric eigendecomposition.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt::factor::{cholesky_in_place, cholesky_in_place_scratch};
use faer::linalg::evd::{self_adjoint_evd, self_adjoint_evd_scratch, ComputeEigenvectors};
use faer::linalg::triangular_solve::{
    solve_lower_triangular_in_place, solve_upper_triangular_in_place,
};
use faer::Mat;

use super::EigenError;
use crate::model::SparseMatrix;
use crate::solvers::sparse_ops::{par, to_dense};

/// Tries σ, 100σ, 10⁴σ, … until K − σM is numerically positive definite.
/// Returns the `count` lowest (unnormalised) mode shapes and the σ used.
pub fn shift_invert(
    k: &SparseMatrix,
    m: &SparseMatrix,
    count: usize,
    shift: f64,
) -> Result<(Mat<f64>, f64), EigenError> {
    let n = k.nrows();
    let trace = std::env::var_os("FRFUP_EIGEN_TRACE").is_some();
    let t0 = std::time::Instant::now();
    let lap = |what: &str| {
        if trace {
            eprintln!("[dense] {what}: {:.3} s", t0.elapsed().as_secs_f64());
        }
    };
    let kd = to_dense(k);
    let md = to_dense(m);
    let par = par();
    let mut sigma = shift;
    let mut l = None;
    for _ in 0..6 {
        let mut a = Mat::from_fn(n, n, |i, j| kd[(i, j)] - sigma * md[(i, j)]);
        let mut mem = MemBuffer::new(cholesky_in_place_scratch::<f64>(n, par, Default::default()));
        let ok = cholesky_in_place(
            a.as_mut(),
            Default::default(),
            par,
            MemStack::new(&mut mem),
            Default::default(),
        )
        .is_ok();
        if ok {
            l = Some(a);
            break;
        }
        sigma *= 100.0;
    }
    let Some(l) = l else {
        return Err(EigenError::InvalidInput {
            detail: format!(
                "K − σM is not positive definite even for σ = {sigma:e}: K has negative eigenvalues"
            ),
        });
    };
    lap("cholesky");
    let l = l.as_ref();
    // W = L⁻¹ M, then C = L⁻¹ Wᵀ = L⁻¹ M L⁻ᵀ.
    let mut w = md;
    solve_lower_triangular_in_place(l, w.as_mut(), par);
    let mut c = w.transpose().to_owned();
    drop(w);
    solve_lower_triangular_in_place(l, c.as_mut(), par);
    lap("reduction");
    let mut s = faer::diag::Diag::<f64>::zeros(n);
    let mut u = Mat::<f64>::zeros(n, n);
    let mut mem = MemBuffer::new(self_adjoint_evd_scratch::<f64>(
        n,
        ComputeEigenvectors::Yes,
        par,
        Default::default(),
    ));
    self_adjoint_evd(
        c.as_ref(),
        s.as_mut(),
        Some(u.as_mut()),
        par,
        MemStack::new(&mut mem),
        Default::default(),
    )
    .map_err(|e| EigenError::NoConvergence {
        detail: format!("dense symmetric eigensolver: {e:?}"),
    })?;
    lap("evd");
    drop(c);
    // Ascending μ: the last `count` columns, largest μ first.
    let mut y = Mat::from_fn(n, count, |i, j| u[(i, n - 1 - j)]);
    solve_upper_triangular_in_place(l.transpose(), y.as_mut(), par);
    Ok((y, sigma))
}
