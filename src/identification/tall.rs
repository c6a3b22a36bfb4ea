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
//! residuals rebuild each block rather than keep them. When the scaled
//! Gram matrix is ill-conditioned (κ above [`NORMAL_COND`]) the tall
//! design is formed and solved by the SVD ([`solve`]).

use faer::linalg::solvers::Solve;
use faer::{c64, Mat, Side};
use rayon::prelude::*;

use crate::solvers::dense::product;

use super::lsfd::{design, rhs, solve};
use super::prepare::Prepared;
use super::IdentifyError;

/// Lines per chunk: a chunk's design (2 × 4,096 rows × ≤ 40 columns) stays
/// in the second-level cache.
const CHUNK: usize = 4096;

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
pub(super) struct LineFit {
    pub x: Mat<f64>,
    pub per_line: Vec<f64>,
}

/// Fits `poles` to the data at `lines` (see the module doc).
pub(super) fn fit_lines(
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
    let x = match normal_solution(
        &lines.par_chunks(CHUNK).map(chunk).collect::<Vec<_>>(),
        cols,
    ) {
        Some(x) => x,
        None => solve(
            &design(poles, &data.omega, lines, data.kind_order),
            &rhs(data, lines),
        )?,
    };
    let per_line = if per_line {
        lines
            .par_chunks(CHUNK)
            .flat_map_iter(|ls| {
                let c = chunk(ls);
                line_residuals(data, &(c.b - product(c.a.as_ref(), x.as_ref())))
            })
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
    let ev = gram.self_adjoint_eigen(Side::Lower).ok()?;
    let (lo, hi) = ev
        .S()
        .column_vector()
        .iter()
        .fold((f64::INFINITY, 0.0f64), |(l, h), &v| (l.min(v), h.max(v)));
    if !(lo > hi / (NORMAL_COND * NORMAL_COND)) {
        return None;
    }
    let llt = gram.llt(Side::Lower).ok()?;
    // x = D (DAᵀAD)⁻¹ (D Aᵀ rhs), D = diag(1/scale).
    let step = |mut y: Mat<f64>| {
        for (i, s) in scale.iter().enumerate() {
            y.row_mut(i).iter_mut().for_each(|v| *v /= s);
        }
        let mut x = llt.solve(&y);
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::identification::lsfd::evaluate;
    use crate::identification::lsfd::Residual;

    /// A receptance record of `lines` lines over 1–200 Hz, three outputs of
    /// one input, two modes, with a deterministic ripple of `noise` relative.
    fn record(lines: usize, noise: f64) -> (Prepared, Vec<c64>, Vec<Vec<c64>>) {
        let poles = vec![
            c64::new(-3.0, 2.0 * 3.1416 * 40.0),
            c64::new(-6.0, 2.0 * 3.1416 * 120.0),
        ];
        let residues = vec![
            vec![
                c64::new(0.0, -2.0),
                c64::new(0.5, -1.0),
                c64::new(-0.2, 1.5),
            ],
            vec![c64::new(0.1, -3.0), c64::new(0.0, 2.0), c64::new(0.3, -0.7)],
        ];
        let hz: Vec<f64> = (0..lines)
            .map(|k| 1.0 + 199.0 * k as f64 / (lines - 1) as f64)
            .collect();
        let omega: Vec<f64> = hz.iter().map(|f| 2.0 * std::f64::consts::PI * f).collect();
        let res = Residual {
            upper: 1e-3,
            lower: -2.0,
        };
        let h: Vec<Vec<c64>> = (0..3)
            .map(|j| {
                let a: Vec<c64> = residues.iter().map(|r| r[j]).collect();
                omega
                    .iter()
                    .enumerate()
                    .map(|(k, &w)| {
                        let v = evaluate(&poles, &a, &res, w, 0);
                        v * (1.0 + noise * ((k * 7 + j * 3) as f64).sin())
                    })
                    .collect()
            })
            .collect();
        let dof = |node| crate::identification::prepare::Dof { node, direction: 3 };
        let data = Prepared {
            frequencies_hz: hz,
            omega,
            first_line: 0,
            kind_order: 0,
            outputs: vec![dof(1), dof(2), dof(3)],
            inputs: vec![dof(1)],
            channels: vec![0, 1, 2],
            h,
            weights: vec![1.0, 2.0, 0.5],
            left_out: Vec::new(),
            reciprocal: false,
        };
        (data, poles, residues)
    }

    /// Noise-free data over three chunks: the residues come back to 1e-9
    /// (the normal equations' κ²ε after one refinement step), every line's
    /// residual at rounding level.
    #[test]
    fn the_residues_of_noise_free_data_come_back() {
        let (data, poles, residues) = record(2 * CHUNK + 500, 0.0);
        let all: Vec<usize> = (0..data.n_lines()).collect();
        let fit = fit_lines(&data, &poles, &all, true).unwrap();
        for (r, row) in residues.iter().enumerate() {
            for (j, a) in row.iter().enumerate() {
                let got = c64::new(fit.x[(2 * r, j)], fit.x[(2 * r + 1, j)]);
                assert!(
                    (got - a).norm() < 1e-9 * a.norm(),
                    "mode {r} FRF {j}: {got} vs {a}"
                );
            }
        }
        assert_eq!(fit.per_line.len(), data.n_lines());
        let peak = data
            .h
            .iter()
            .flatten()
            .map(|v| v.norm_sqr())
            .fold(0.0, f64::max);
        assert!(fit.per_line.iter().all(|&e| e < 1e-20 * peak));
    }

    /// Noisy data on a subset of lines spanning chunks: the same solution
    /// as the SVD of the whole design (lsfd::solve) to 1e-9, and the same
    /// per-line residuals as the direct B − A x.
    #[test]
    fn the_chunked_normal_equations_agree_with_the_svd() {
        let (data, poles, _) = record(3 * CHUNK, 0.02);
        let lines: Vec<usize> = (0..data.n_lines()).step_by(2).collect();
        let fit = fit_lines(&data, &poles, &lines, true).unwrap();
        let a = design(&poles, &data.omega, &lines, 0);
        let b = rhs(&data, &lines);
        let svd = solve(&a, &b).unwrap();
        let scale = svd.norm_l2();
        assert!((&fit.x - &svd).norm_l2() < 1e-9 * scale);
        let r = &b - product(a.as_ref(), fit.x.as_ref());
        for (k, e) in fit.per_line.iter().enumerate() {
            let direct: f64 = (0..3)
                .map(|j| {
                    data.weights[j].powi(2) * (r[(2 * k, j)].powi(2) + r[(2 * k + 1, j)].powi(2))
                })
                .sum();
            assert!((e - direct).abs() <= 1e-12 * direct.max(1e-300), "line {k}");
        }
    }
}
