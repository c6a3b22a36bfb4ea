//! Least-squares solution of the updating equation A p = b (Eq. 12 / 21) by a
//! truncated SVD (§3.4, Eq. 35–41), and the rank-N pseudo-inverse used for the
//! reduced dynamic stiffness.
//!
//! Rank rule (Eq. 40): with σ₁ ≥ σ₂ ≥ … the rank r is the first index with
//! σ_{r+1}/σ_r < ε; singular values below σ₁·1e-13 (round-off level) are
//! dropped as well. Then p = V₁ Σ₁⁻¹ U₁ᵀ b (Eq. 41). The dropped right singular
//! vectors V₂ span the parameter combinations the equations cannot see.

use crate::solvers::dense::{thin_svd, ThinSvd};
use faer::{Mat, MatRef};

/// Singular values below this fraction of σ₁ count as zero whatever the gap.
const ROUND_OFF: f64 = 1e-13;

/// Why an SVD solve failed.
#[derive(Debug, Clone, PartialEq)]
pub enum SvdSolveError {
    /// A or b holds NaN or ±∞.
    NonFinite,
    /// The rows of A and the length of b differ.
    Shape { rows: usize, rhs: usize },
    /// The SVD iteration did not converge.
    NoConvergence,
}

impl std::fmt::Display for SvdSolveError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            SvdSolveError::NonFinite => {
                write!(f, "the updating equations contain NaN or infinite values")
            }
            SvdSolveError::Shape { rows, rhs } => {
                write!(
                    f,
                    "the sensitivity matrix has {rows} rows but the residual has {rhs}"
                )
            }
            SvdSolveError::NoConvergence => write!(f, "the SVD did not converge"),
        }
    }
}

impl std::error::Error for SvdSolveError {}

/// The truncated-SVD least-squares solution of A p = b.
#[derive(Clone, Debug, PartialEq)]
pub struct GapRuleSolution {
    /// p = A⁺ b (Eq. 41), one entry per column of A.
    pub step: Vec<f64>,
    /// Kept rank r (Eq. 40).
    pub rank: usize,
    /// All singular values σ₁ ≥ … ≥ σ_N of A.
    pub singular_values: Vec<f64>,
    /// Right singular vectors of the dropped singular values (each of length N):
    /// parameter combinations that the equations cannot distinguish.
    pub null_space: Vec<Vec<f64>>,
}

/// The rank kept by the gap rule σ_{r+1}/σ_r < ε (Eq. 40) on singular values in
/// non-increasing order.
pub fn gap_rank(singular_values: &[f64], eps: f64) -> usize {
    let Some(&s1) = singular_values.first() else {
        return 0;
    };
    if !(s1 > 0.0) {
        return 0;
    }
    for k in 0..singular_values.len() {
        if singular_values[k] < s1 * ROUND_OFF {
            return k;
        }
        if k + 1 < singular_values.len() && singular_values[k + 1] < eps * singular_values[k] {
            return k + 1;
        }
    }
    singular_values.len()
}

/// Solve A p ≈ b by the SVD with the gap rule (Eq. 39–41).
pub fn solve_gap_rule(
    a: MatRef<'_, f64>,
    b: &[f64],
    eps: f64,
) -> Result<GapRuleSolution, SvdSolveError> {
    let (m, n) = (a.nrows(), a.ncols());
    if m != b.len() {
        return Err(SvdSolveError::Shape {
            rows: m,
            rhs: b.len(),
        });
    }
    if b.iter().any(|v| !v.is_finite()) || (0..n).any(|j| (0..m).any(|i| !a[(i, j)].is_finite())) {
        return Err(SvdSolveError::NonFinite);
    }
    if n == 0 {
        return Ok(GapRuleSolution {
            step: vec![],
            rank: 0,
            singular_values: vec![],
            null_space: vec![],
        });
    }
    if m == 0 {
        return Ok(GapRuleSolution {
            step: vec![0.0; n],
            rank: 0,
            singular_values: vec![0.0; n],
            null_space: (0..n)
                .map(|j| (0..n).map(|i| f64::from(u8::from(i == j))).collect())
                .collect(),
        });
    }
    // Thin SVD of an M×N matrix with M ≥ N gives N singular values. When there
    // are fewer equations than parameters, pad with zero rows so that V is N×N
    // and the null space is complete.
    let padded;
    let a_eff = if m < n {
        padded = Mat::from_fn(n, n, |i, j| if i < m { a[(i, j)] } else { 0.0 });
        padded.as_ref()
    } else {
        a
    };
    let ThinSvd { s, u, v } = thin_svd(a_eff).map_err(|_| SvdSolveError::NoConvergence)?;
    let (u, v) = (u.as_ref(), v.as_ref());
    let rank = gap_rank(&s, eps);
    let mut step = vec![0.0; n];
    for k in 0..rank {
        let mut utb = 0.0;
        for i in 0..m {
            utb += u[(i, k)] * b[i];
        }
        let c = utb / s[k];
        for (j, p) in step.iter_mut().enumerate() {
            *p += v[(j, k)] * c;
        }
    }
    let null_space = (rank..n)
        .map(|k| {
            let mut col: Vec<f64> = (0..n).map(|j| v[(j, k)]).collect();
            canonical_sign(&mut col);
            col
        })
        .collect();
    Ok(GapRuleSolution {
        step,
        rank,
        singular_values: s,
        null_space,
    })
}

/// Flip a vector so that its largest-magnitude entry is positive (deterministic signs).
pub(crate) fn canonical_sign(v: &mut [f64]) {
    let mut best = 0.0f64;
    for &x in v.iter() {
        if x.abs() > best.abs() {
            best = x;
        }
    }
    if best < 0.0 {
        for x in v.iter_mut() {
            *x = -*x;
        }
    }
}

/// Rank-`rank` pseudo-inverse V₁ Σ₁⁻¹ U₁ᵀ of a square or rectangular matrix
/// (§3.4 applied to the reduced dynamic stiffness Z̄, whose rank is N_md).
pub fn truncated_pseudo_inverse(
    a: MatRef<'_, f64>,
    rank: usize,
) -> Result<Mat<f64>, SvdSolveError> {
    let (m, n) = (a.nrows(), a.ncols());
    if (0..n).any(|j| (0..m).any(|i| !a[(i, j)].is_finite())) {
        return Err(SvdSolveError::NonFinite);
    }
    let ThinSvd { s, u, v } = thin_svd(a).map_err(|_| SvdSolveError::NoConvergence)?;
    let (u, v) = (u.as_ref(), v.as_ref());
    let r = rank.min(s.len());
    let mut out = Mat::<f64>::zeros(n, m);
    for k in 0..r {
        if !(s[k] > 0.0) {
            break;
        }
        let inv = 1.0 / s[k];
        for i in 0..m {
            let ui = u[(i, k)] * inv;
            if ui == 0.0 {
                continue;
            }
            for j in 0..n {
                out[(j, i)] += v[(j, k)] * ui;
            }
        }
    }
    Ok(out)
}
