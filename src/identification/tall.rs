//! The LSFD over many lines (the whole band: up to 10⁵ lines, tens of
//! columns) by the normal equations, accumulated over fixed chunks of lines.
//!
//! With A the real design of [`design`] (2 rows per line) and B the
//! data of [`rhs`], D = diag(1/‖a_c‖) its column scaling:
//!
//!   x = D (D AᵀA D)⁻¹ D Aᵀ B,
//!
//! then one step of correction with the residual R = B − A x (the same
//! Cholesky factor reused). A and B are held as blocks of 4,096 lines
//! ([`CHUNK`]), built on both cores; the products AᵀA, AᵀB and AᵀR are
//! formed per block, each on cache-sized operands, and summed in block
//! order, so the result does not depend on the number of threads. No tall
//! matrix is formed or read row by row (the whole-band design of a
//! 50,000-line record is 13 MB: forming it, its residual twice and the
//! strided per-line sums cost more than the arithmetic). The per-line
//! residuals reuse the blocks. When the scaled
//! Gram matrix is ill-conditioned (κ above [`NORMAL_COND`]) the tall
//! design is formed and solved by the SVD ([`solve`]).

use faer::{c64, Mat};
use rayon::prelude::*;

use crate::solvers::dense::{cholesky_lower, cholesky_solve, product, symmetric_eigen};

use super::lsfd::{design, rhs, solve};
use super::prepare::Prepared;
use super::IdentifyError;

/// Lines per chunk: a chunk's design (2 × 4,096 rows × ≤ 40 columns) stays
/// in the second-level cache.
pub const CHUNK: usize = 4096;

/// Largest condition number of the column-scaled design for which the
/// normal equations are used. Their relative error, of order κ²ε (2e-6 at
/// κ = 1e5), shrinks by about that factor with one step of refinement on
/// the residual down to the limit κ²ε·‖r‖/(‖A‖‖x‖) a QR solution shares
/// when the fit leaves a residual (Björck, Numerical Methods for Least
/// Squares Problems, 1996, §2.9).
const NORMAL_COND: f64 = 1e5;

/// Least-squares coefficients (rows in [`design`] order, one column per
/// FRF) of the poles' model over `lines`, and, when `per_line` is asked,
/// Σ_j w_j² |residual_j(ω_k)|² at each of them.
pub struct LineFit {
    pub x: Mat<f64>,
    pub per_line: Vec<f64>,
}

/// Fits `poles` to the data at `lines` (see the module doc).
pub fn fit_lines(
    data: &Prepared,
    poles: &[c64],
    lines: &[usize],
    per_line: bool,
) -> Result<LineFit, IdentifyError> {
    let cols = 2 * poles.len() + 2;
    let chunk = |ls: &[usize]| Chunk {
        a: design(poles, &data.omega, ls, data.kind_order),
        b: rhs(data, ls),
    };
    let chunks: Vec<Chunk> = lines.par_chunks(CHUNK).map(chunk).collect();
    let x = match normal_solution(&chunks, cols) {
        Some(x) => x,
        None => solve(
            &design(poles, &data.omega, lines, data.kind_order),
            &rhs(data, lines),
        )?,
    };
    let per_line = if per_line {
        chunks
            .par_iter()
            .flat_map_iter(|c| line_residuals(data, &(&c.b - product(c.a.as_ref(), x.as_ref()))))
            .collect()
    } else {
        Vec::new()
    };
    Ok(LineFit { x, per_line })
}

/// One chunk's design rows and data rows.
struct Chunk {
    a: Mat<f64>,
    b: Mat<f64>,
}

/// Σ over the chunks of `f(chunk)` (rows × cols each), in chunk order.
fn chunk_sum(
    chunks: &[Chunk],
    rows: usize,
    cols: usize,
    f: impl Fn(&Chunk) -> Mat<f64> + Sync + Send,
) -> Mat<f64> {
    chunks
        .par_iter()
        .map(f)
        .collect::<Vec<_>>()
        .into_iter()
        .fold(Mat::<f64>::zeros(rows, cols), |s, m| s + m)
}

/// The refined normal-equation solution, or `None` when the scaled Gram
/// matrix is ill-conditioned, not positive definite or the result not
/// finite.
fn normal_solution(chunks: &[Chunk], cols: usize) -> Option<Mat<f64>> {
    let nj = chunks.first()?.b.ncols();
    let rows: usize = chunks.iter().map(|c| c.a.nrows()).sum();
    if cols == 0 || rows < 4 * cols {
        return None;
    }
    let mut gram = chunk_sum(chunks, cols, cols, |c| {
        product(c.a.transpose(), c.a.as_ref())
    });
    let scale: Vec<f64> = (0..cols).map(|i| gram[(i, i)].sqrt()).collect();
    if scale.iter().any(|v| !(*v > 0.0 && v.is_finite())) {
        return None;
    }
    for i in 0..cols {
        for j in 0..cols {
            gram[(i, j)] /= scale[i] * scale[j];
        }
    }
    let (values, _) = symmetric_eigen(gram.as_ref())?;
    let (lo, hi) = values
        .iter()
        .fold((f64::INFINITY, 0.0f64), |(l, h), &v| (l.min(v), h.max(v)));
    if !(lo > hi / (NORMAL_COND * NORMAL_COND)) {
        return None;
    }
    let l = cholesky_lower(gram.as_ref())?;
    // x = D (DAᵀAD)⁻¹ (D Aᵀ rhs), D = diag(1/scale).
    let step = |mut y: Mat<f64>| {
        for (i, s) in scale.iter().enumerate() {
            y.row_mut(i).iter_mut().for_each(|v| *v /= s);
        }
        let mut x = cholesky_solve(l.as_ref(), y.as_ref());
        for (i, s) in scale.iter().enumerate() {
            x.row_mut(i).iter_mut().for_each(|v| *v /= s);
        }
        x
    };
    let mut x = step(chunk_sum(chunks, cols, nj, |c| {
        product(c.a.transpose(), c.b.as_ref())
    }));
    let atr = chunk_sum(chunks, cols, nj, |c| {
        let r = &c.b - product(c.a.as_ref(), x.as_ref());
        product(c.a.transpose(), r.as_ref())
    });
    x += step(atr);
    let finite = x.col_iter().all(|c| c.iter().all(|v| v.is_finite()));
    finite.then_some(x)
}

/// Σ_j w_j² (r_{2k,j}² + r_{2k+1,j}²) per line k of the residual rows `r`.
fn line_residuals(data: &Prepared, r: &Mat<f64>) -> Vec<f64> {
    let m = data.n_inputs();
    let mut out = vec![0.0; r.nrows() / 2];
    for (j, col) in r.col_iter().enumerate() {
        let w2 = data.weights[j / m].powi(2);
        for (k, o) in out.iter_mut().enumerate() {
            *o += w2 * (col[2 * k].powi(2) + col[2 * k + 1].powi(2));
        }
    }
    out
}
