//! Dense kernels on the calling thread, for the small and the tall, thin
//! matrices of the updating equations and of modal identification
//! (hundreds to 10⁵ rows, tens of columns). There, handing work to a
//! thread pool costs more than it saves: faer's pool spent a third of an
//! identification of 10 channels × 50,000 lines waiting at its barriers
//! (perf). faer's high-level `thin_svd` and `*` use its process-wide
//! parallelism setting; these take none, so no caller has to set it.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::matmul::matmul;
use faer::linalg::svd::{svd, svd_scratch, ComputeSvdVectors, SvdError};
use faer::{Accum, Mat, MatRef, Par};

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

/// The product A·B.
pub fn product(a: MatRef<'_, f64>, b: MatRef<'_, f64>) -> Mat<f64> {
    let mut c = Mat::<f64>::zeros(a.nrows(), b.ncols());
    matmul(c.as_mut(), Accum::Replace, a, b, 1.0, Par::Seq);
    c
}
