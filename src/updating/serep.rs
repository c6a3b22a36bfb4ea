//! SEREP reduction of the FE model onto the measured DOFs (§3.3, Eq. 32–34)
//! and inversion of the reduced dynamic stiffness (§3.3–3.4).
//!
//! With Ψ (N_fe × N_md) mass-normalised modes and Ψ_m their rows at the N_ex
//! measured DOFs, T = Ψ Ψ_m⁺ with Ψ_m⁺ = (Ψ_mᵀΨ_m)⁻¹Ψ_mᵀ (Eq. 32). Because
//! ΨᵀKΨ = Λ and ΨᵀMΨ = I, the reduced matrices never need T:
//! K̄ = TᵀKT = Ψ_m⁺ᵀ Λ Ψ_m⁺ (Eq. 33), M̄ = TᵀMT = Ψ_m⁺ᵀ Ψ_m⁺ (Eq. 34), and
//! Z̄(ω) = Ψ_m⁺ᵀ (Λ − ω²I) Ψ_m⁺ has rank N_md. Its rank-N_md pseudo-inverse
//! (the paper's truncated SVD) is exactly H̄(ω) = Ψ_m (Λ − ω²I)⁻¹ Ψ_mᵀ, the
//! receptance of the retained modes at the measured DOFs (m/N).
//!
//! Basis selection: modes that barely show at the measured DOFs (e.g. axial
//! modes of a frame measured transversally) would make Ψ_mᵀΨ_m singular. Modes
//! are taken in ascending frequency order and kept only if the part of their
//! measured partition ψ_m,r orthogonal to the already kept columns has a norm of
//! at least `tolerance` × the largest ‖ψ_m,s‖ among the candidates (an ordered
//! Gram–Schmidt rank test); the others are reported as dropped.

use faer::{Mat, MatRef};

use super::svd_solve::{truncated_pseudo_inverse, SvdSolveError};
use crate::solvers::dense::product;
use crate::solvers::eigen::Modes;

/// Why a SEREP basis could not be formed.
#[derive(Debug, Clone, PartialEq)]
pub enum SerepError {
    /// No computed mode is visible at the measured DOFs.
    NoVisibleModes,
    /// The mode shapes contain NaN or ±∞.
    NonFinite,
    /// A measured DOF index is outside the model.
    DofOutOfRange {
        index: usize,
        dofs: usize,
    },
    Svd(SvdSolveError),
}

impl std::fmt::Display for SerepError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            SerepError::NoVisibleModes => {
                write!(f, "no mode of the model shows at the measured DOFs")
            }
            SerepError::NonFinite => write!(f, "the mode shapes contain NaN or infinite values"),
            SerepError::DofOutOfRange { index, dofs } => {
                write!(
                    f,
                    "measured DOF index {index} is outside the model ({dofs} DOFs)"
                )
            }
            SerepError::Svd(e) => write!(f, "SEREP: {e}"),
        }
    }
}

impl std::error::Error for SerepError {}

/// How the reduced dynamic stiffness Z̄ is inverted (§3.3).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum InverseMethod {
    /// Truncated SVD at rank N_md (§3.4).
    Svd,
    /// (Z̄ + δI)⁻¹ with δ = `relative` × mean |diag Z̄|.
    Perturb { relative: f64 },
}

/// The retained modes and their measured partition.
#[derive(Clone, Debug)]
pub struct SerepBasis {
    /// Indices (into the computed modes) of the N_md retained modes, ascending.
    pub modes: Vec<usize>,
    /// Indices of computed modes dropped as invisible at the measured DOFs.
    pub dropped: Vec<usize>,
    /// λ_r = ω_r² (rad²/s²) of the retained modes.
    pub omega2: Vec<f64>,
    /// Ψ_m: N_ex × N_md.
    pub psi_m: Mat<f64>,
    /// Ψ_m⁺ = (Ψ_mᵀΨ_m)⁻¹Ψ_mᵀ: N_md × N_ex.
    pub psi_m_pinv: Mat<f64>,
}

impl SerepBasis {
    /// Select up to `count` modes visible at `measured` (equation indices) from
    /// the lowest computed `modes` (never more than N_ex).
    pub fn select(
        modes: &Modes,
        measured: &[usize],
        count: usize,
        tolerance: f64,
    ) -> Result<SerepBasis, SerepError> {
        let n = modes.shapes.nrows();
        if let Some(&index) = measured.iter().find(|&&i| i >= n) {
            return Err(SerepError::DofOutOfRange { index, dofs: n });
        }
        let n_ex = measured.len();
        let cols = modes.at(measured);
        if cols.iter().flatten().any(|v| !v.is_finite()) {
            return Err(SerepError::NonFinite);
        }
        let max_norm = cols.iter().map(|c| norm(c)).fold(0.0, f64::max);
        if !(max_norm > 0.0) {
            return Err(SerepError::NoVisibleModes);
        }
        let limit = count.min(n_ex);
        let mut kept = Vec::new();
        let mut dropped = Vec::new();
        let mut ortho: Vec<Vec<f64>> = Vec::new();
        for (r, col) in cols.iter().enumerate() {
            if kept.len() == limit {
                break;
            }
            // Two passes of modified Gram–Schmidt for a stable residual.
            let mut res = col.clone();
            for _ in 0..2 {
                for q in &ortho {
                    let d = dot(q, &res);
                    for (x, qi) in res.iter_mut().zip(q) {
                        *x -= d * qi;
                    }
                }
            }
            let rn = norm(&res);
            if rn >= tolerance * max_norm {
                res.iter_mut().for_each(|x| *x /= rn);
                ortho.push(res);
                kept.push(r);
            } else {
                dropped.push(r);
            }
        }
        if kept.is_empty() {
            return Err(SerepError::NoVisibleModes);
        }
        let psi_m = Mat::from_fn(n_ex, kept.len(), |i, k| cols[kept[k]][i]);
        let psi_m_pinv =
            truncated_pseudo_inverse(psi_m.as_ref(), kept.len()).map_err(SerepError::Svd)?;
        Ok(SerepBasis {
            omega2: kept.iter().map(|&r| modes.omega2[r]).collect(),
            modes: kept,
            dropped,
            psi_m,
            psi_m_pinv,
        })
    }

    /// N_md, the number of retained modes.
    pub fn len(&self) -> usize {
        self.modes.len()
    }

    pub fn is_empty(&self) -> bool {
        self.modes.is_empty()
    }

    /// N_ex, the number of measured DOFs.
    pub fn measured_len(&self) -> usize {
        self.psi_m.nrows()
    }

    /// T = Ψ Ψ_m⁺ (Eq. 32), N_fe × N_ex, for the retained columns of `shapes`.
    /// Dense: meant for checks on small models; the updating never forms it.
    pub fn transformation(&self, shapes: MatRef<'_, f64>) -> Mat<f64> {
        let psi = Mat::from_fn(shapes.nrows(), self.len(), |i, k| {
            shapes[(i, self.modes[k])]
        });
        product(psi.as_ref(), self.psi_m_pinv.as_ref())
    }

    /// K̄ = Ψ_m⁺ᵀ Λ Ψ_m⁺ (Eq. 33), N_ex × N_ex.
    pub fn reduced_stiffness(&self) -> Mat<f64> {
        self.reduced_dynamic_stiffness_with(|l| l)
    }

    /// M̄ = Ψ_m⁺ᵀ Ψ_m⁺ (Eq. 34), N_ex × N_ex.
    pub fn reduced_mass(&self) -> Mat<f64> {
        self.reduced_dynamic_stiffness_with(|_| 1.0)
    }

    /// Z̄(ω) = K̄ − ω²M̄ = Ψ_m⁺ᵀ (Λ − ω²I) Ψ_m⁺ (N/m).
    pub fn reduced_dynamic_stiffness(&self, omega2: f64) -> Mat<f64> {
        self.reduced_dynamic_stiffness_with(|l| l - omega2)
    }

    fn reduced_dynamic_stiffness_with(&self, f: impl Fn(f64) -> f64) -> Mat<f64> {
        let p = &self.psi_m_pinv;
        let d: Vec<f64> = self.omega2.iter().map(|&l| f(l)).collect();
        let scaled = Mat::from_fn(p.nrows(), p.ncols(), |k, j| d[k] * p[(k, j)]);
        product(p.transpose(), scaled.as_ref())
    }

    /// (λ_r − ω²)⁻¹ of the retained modes; `None` if ω² sits on an FE resonance.
    pub fn modal_factors(&self, omega2: f64) -> Option<Vec<f64>> {
        let mut out = Vec::with_capacity(self.len());
        for &l in &self.omega2 {
            let d = l - omega2;
            if d.abs() <= 1e-12 * l.abs().max(omega2.abs()) || !d.is_finite() {
                return None;
            }
            out.push(1.0 / d);
        }
        Some(out)
    }

    /// H̄(ω) = Ψ_m (Λ − ω²I)⁻¹ Ψ_mᵀ: the SEREP model's receptance between
    /// measured DOFs (m/N), identical to the rank-N_md SVD inverse of Z̄.
    pub fn modal_receptance(&self, omega2: f64) -> Option<Mat<f64>> {
        let d = self.modal_factors(omega2)?;
        let pm = &self.psi_m;
        let scaled = Mat::from_fn(pm.nrows(), pm.ncols(), |i, k| pm[(i, k)] * d[k]);
        Some(product(scaled.as_ref(), pm.transpose()))
    }

    /// H̄(ω) by literally inverting Z̄(ω) with `method` (§3.3–3.4).
    pub fn reduced_receptance(
        &self,
        omega2: f64,
        method: InverseMethod,
    ) -> Result<Mat<f64>, SerepError> {
        let z = self.reduced_dynamic_stiffness(omega2);
        match method {
            InverseMethod::Svd => {
                truncated_pseudo_inverse(z.as_ref(), self.len()).map_err(SerepError::Svd)
            }
            InverseMethod::Perturb { relative } => {
                let n = z.nrows();
                let scale = (0..n).map(|i| z[(i, i)].abs()).sum::<f64>() / n.max(1) as f64;
                let delta = relative * scale;
                let zp = Mat::from_fn(n, n, |i, j| z[(i, j)] + if i == j { delta } else { 0.0 });
                if (0..n).any(|j| (0..n).any(|i| !zp[(i, j)].is_finite())) {
                    return Err(SerepError::NonFinite);
                }
                let id = Mat::<f64>::identity(n, n);
                let h = crate::solvers::dense::lu_solve(zp.as_ref(), id.as_ref());
                if (0..n).any(|j| (0..n).any(|i| !h[(i, j)].is_finite())) {
                    return Err(SerepError::NonFinite);
                }
                Ok(h)
            }
        }
    }
}

pub(crate) fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

pub(crate) fn norm(a: &[f64]) -> f64 {
    dot(a, a).sqrt()
}
