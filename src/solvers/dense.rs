//! Dense kernels on the calling thread, for the small and the tall, thin
//! matrices of the updating equations and of modal identification
//! (hundreds to 10⁵ rows, tens of columns). There, handing work to a
//! thread pool costs more than it saves: faer's pool spent a third of an
//! identification of 10 channels × 50,000 lines waiting at its barriers
//! (perf). faer's high-level `thin_svd`, `self_adjoint_eigen`, `llt`,
//! `partial_piv_lu`, `eigen`, `eigenvalues` and `*` use its process-wide
//! parallelism setting, and its parallel kernels sum in another order than
//! its sequential ones: results would depend on the machine's number of
//! cores. These take none, so no caller has to set
//! it and every machine gets the same bits.

use faer::diag::Diag;
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt::factor::{cholesky_in_place, cholesky_in_place_scratch};
use faer::linalg::evd::{
    evd_real, evd_scratch, self_adjoint_evd, self_adjoint_evd_scratch, ComputeEigenvectors,
    EvdError,
};
use faer::linalg::matmul::matmul;
use faer::linalg::svd::{svd, svd_scratch, ComputeSvdVectors, SvdError};
use faer::reborrow::ReborrowMut;
use faer::{c64, Accum, Mat, MatMut, MatRef, Par};

/// A = U diag(s) Vᵀ with min(M, N) columns in U and V, s non-increasing.
pub struct ThinSvd {
    pub s: Vec<f64>,
    pub u: Mat<f64>,
    pub v: Mat<f64>,
}

/// The thin singular value decomposition of `a` (M × N).
pub fn thin_svd(a: MatRef<'_, f64>) -> Result<ThinSvd, SvdError> {
    let (m, n) = a.shape();
    let size = m.min(n);
    let mut s = faer::diag::Diag::<f64>::zeros(size);
    let mut u = Mat::<f64>::zeros(m, size);
    let mut v = Mat::<f64>::zeros(n, size);
    let par = Par::Seq;
    let mut mem = MemBuffer::new(svd_scratch::<f64>(
        m,
        n,
        ComputeSvdVectors::Thin,
        ComputeSvdVectors::Thin,
        par,
        Default::default(),
    ));
    svd(
        a,
        s.as_mut(),
        Some(u.as_mut()),
        Some(v.as_mut()),
        par,
        MemStack::new(&mut mem),
        Default::default(),
    )?;
    Ok(ThinSvd {
        s: s.column_vector().iter().copied().collect(),
        u,
        v,
    })
}

/// A = U diag(λ) Uᵀ of a symmetric `a` (its lower triangle is read):
/// ascending λ, orthonormal U; `None` if the iteration fails.
pub fn symmetric_eigen(a: MatRef<'_, f64>) -> Option<(Vec<f64>, Mat<f64>)> {
    let n = a.nrows();
    let mut s = faer::diag::Diag::<f64>::zeros(n);
    let mut u = Mat::<f64>::zeros(n, n);
    let par = Par::Seq;
    let mut mem = MemBuffer::new(self_adjoint_evd_scratch::<f64>(
        n,
        ComputeEigenvectors::Yes,
        par,
        Default::default(),
    ));
    self_adjoint_evd(
        a,
        s.as_mut(),
        Some(u.as_mut()),
        par,
        MemStack::new(&mut mem),
        Default::default(),
    )
    .ok()?;
    Some((s.column_vector().iter().copied().collect(), u))
}

/// L of A = LLᵀ for a symmetric positive definite `a` (its lower triangle
/// is read); `None` if A is not numerically positive definite.
pub fn cholesky_lower(a: MatRef<'_, f64>) -> Option<Mat<f64>> {
    let mut l = a.to_owned();
    let par = Par::Seq;
    let mut mem = MemBuffer::new(cholesky_in_place_scratch::<f64>(
        a.nrows(),
        par,
        Default::default(),
    ));
    cholesky_lower_in_place(l.as_mut(), par, MemStack::new(&mut mem))?;
    Some(l)
}

/// A (symmetric positive definite, lower triangle read) overwritten by L of
/// A = LLᵀ, its strict upper triangle zeroed (faer's in-place Cholesky
/// writes into it too); `stack` from `cholesky_in_place_scratch`. `None`
/// if A is not numerically positive definite.
pub fn cholesky_lower_in_place(
    mut a: MatMut<'_, f64>,
    par: Par,
    stack: &mut MemStack,
) -> Option<()> {
    cholesky_in_place(
        a.rb_mut(),
        Default::default(),
        par,
        stack,
        Default::default(),
    )
    .ok()?;
    for j in 1..a.ncols() {
        a.rb_mut().col_mut(j).subrows_mut(0, j).fill(0.0);
    }
    Some(())
}

/// X = A⁻¹B for A = LLᵀ, `l` from [`cholesky_lower`]: two triangular solves.
pub fn cholesky_solve(l: MatRef<'_, f64>, b: MatRef<'_, f64>) -> Mat<f64> {
    use faer::linalg::triangular_solve::{
        solve_lower_triangular_in_place, solve_upper_triangular_in_place,
    };
    let mut x = b.to_owned();
    solve_lower_triangular_in_place(l, x.as_mut(), Par::Seq);
    solve_upper_triangular_in_place(l.transpose(), x.as_mut(), Par::Seq);
    x
}

/// X = A⁻¹B for a square `a` by LU with partial pivoting (PA = LU, then
/// two triangular solves). A singular `a` gives entries that are not
/// finite: the caller checks.
pub fn lu_solve(a: MatRef<'_, f64>, b: MatRef<'_, f64>) -> Mat<f64> {
    use faer::linalg::lu::partial_pivoting::{factor, solve};
    let n = a.nrows();
    let par = Par::Seq;
    let mut lu = a.to_owned();
    let mut x = b.to_owned();
    let (mut fwd, mut bwd) = (vec![0usize; n], vec![0usize; n]);
    let mut mem = MemBuffer::new(
        factor::lu_in_place_scratch::<usize, f64>(n, n, par, Default::default()).or(
            solve::solve_in_place_scratch::<usize, f64>(n, b.ncols(), par),
        ),
    );
    let stack = MemStack::new(&mut mem);
    let (_, perm) = factor::lu_in_place(
        lu.as_mut(),
        &mut fwd,
        &mut bwd,
        par,
        stack,
        Default::default(),
    );
    // L is the strict lower triangle (unit diagonal implied), U the upper.
    solve::solve_in_place(lu.as_ref(), lu.as_ref(), perm, x.as_mut(), par, stack);
    x
}

/// The eigenvalues λ of a real square `a` and, with `vectors`, its right
/// eigenvectors (column j for λ_j; a complex pair's vectors are each
/// other's conjugates), as faer's `eigen`/`eigenvalues` order them.
pub fn general_eigen(
    a: MatRef<'_, f64>,
    vectors: bool,
) -> Result<(Vec<c64>, Option<Mat<c64>>), EvdError> {
    let n = a.nrows();
    let par = Par::Seq;
    let (mut re, mut im) = (Diag::<f64>::zeros(n), Diag::<f64>::zeros(n));
    let mut u = vectors.then(|| Mat::<f64>::zeros(n, n));
    let want = if vectors {
        ComputeEigenvectors::Yes
    } else {
        ComputeEigenvectors::No
    };
    let mut mem = MemBuffer::new(evd_scratch::<f64>(
        n,
        ComputeEigenvectors::No,
        want,
        par,
        Default::default(),
    ));
    evd_real(
        a,
        re.as_mut(),
        im.as_mut(),
        None,
        u.as_mut().map(|u| u.as_mut()),
        par,
        MemStack::new(&mut mem),
        Default::default(),
    )?;
    let (re, im) = (re.column_vector(), im.column_vector());
    let mut lambda: Vec<c64> = (0..n).map(|j| c64::new(re[j], im[j])).collect();
    // A pair λ, λ̄ sits in columns j, j + 1 as Re v, Im v.
    let shapes = u.map(|u| {
        let mut v = Mat::<c64>::zeros(n, n);
        let mut j = 0;
        while j < n {
            if im[j] == 0.0 || j + 1 == n {
                for i in 0..n {
                    v[(i, j)] = c64::new(u[(i, j)], 0.0);
                }
                j += 1;
            } else {
                lambda[j + 1] = lambda[j].conj();
                for i in 0..n {
                    v[(i, j)] = c64::new(u[(i, j)], u[(i, j + 1)]);
                    v[(i, j + 1)] = c64::new(u[(i, j)], -u[(i, j + 1)]);
                }
                j += 2;
            }
        }
        v
    });
    Ok((lambda, shapes))
}

/// The product A·B.
pub fn product(a: MatRef<'_, f64>, b: MatRef<'_, f64>) -> Mat<f64> {
    let mut c = Mat::<f64>::zeros(a.nrows(), b.ncols());
    matmul(c.as_mut(), Accum::Replace, a, b, 1.0, Par::Seq);
    c
}
