//! The updating equations: FRF sensitivities (Eq. 7–12) through the SEREP
//! model, and natural-frequency sensitivities (Eq. 16–20).
//!
//! The reduced parameter derivative is ∂Z̄/∂p_j = Tᵀ(∂K_j − ω²∂M_j)T
//! = Ψ_m⁺ᵀ C_j(ω) Ψ_m⁺ with the modal projection C_j = Ψᵀ∂K_jΨ − ω²Ψᵀ∂M_jΨ
//! (N_md × N_md), computed once per iteration from the sparse ∂K_j, ∂M_j
//! (cost ∝ nnz·N_md + support·N_md²), so T (N_fe × N_ex) is never formed.
//! At each updating frequency ω_i, with h̄_i the measured FRF at the measured
//! DOFs and u = Ψ_m⁺ h̄_i:
//!
//! * A_i = H̄_i ∂Z̄/∂p h̄_i (Eq. 8), column j = H̄_i Ψ_m⁺ᵀ C_j u. With the
//!   truncated-SVD inverse H̄_i = Ψ_m(Λ − ω²)⁻¹Ψ_mᵀ this is Ψ_m (Λ − ω²)⁻¹ C_j u;
//!   with the perturbed inverse, H̄_i = (Z̄ + δI)⁻¹ is applied literally.
//! * b_i = h_i^n − h̄_i (Eq. 9), h_i^n = Ψ_m(Λ − ω²)⁻¹ψ_kᵀ the SEREP model's
//!   receptance for a unit force at the excitation DOF k (for the SVD inverse
//!   and a measured k this is exactly the k-th column of H̄_i; the perturbed
//!   inverse is not used for h^n, whose null-space part would scale with
//!   1/δ). ψ_k is the FE mode shapes' row at k, so k need not be measured:
//!   the SEREP model's load Tᵀe_k = Ψ_m⁺ᵀψ_kᵀ gives the same h^n, and the
//!   derivation of A_i does not involve the load.
//!
//! Natural-frequency rows (Eq. 19–20), for an FE mode φ_r (mass-normalised)
//! paired with a test resonance ω̄_r: A_r,j = −φ_rᵀ(∂K_j − ω_r²∂M_j)φ_r,
//! b_r = ω_r² − ω̄_r² (rad²/s²).

use faer::{Mat, MatRef};

use super::serep::{InverseMethod, SerepBasis, SerepError};
use crate::model::{ParameterSensitivity, SparseMatrix};
use crate::solvers::dense::product;

/// Ψᵀ∂K_jΨ and Ψᵀ∂M_jΨ (N_md × N_md) of every parameter over the SEREP modes.
#[derive(Clone, Debug)]
pub struct ModalSensitivities {
    pub dk: Vec<Mat<f64>>,
    pub dm: Vec<Mat<f64>>,
}

impl ModalSensitivities {
    /// Project every parameter's ∂K, ∂M onto the columns `modes` of `shapes`.
    pub fn project(
        parameters: &[ParameterSensitivity],
        shapes: MatRef<'_, f64>,
        modes: &[usize],
    ) -> Self {
        let n = shapes.nrows();
        let nm = modes.len();
        let mut rows = vec![0.0; n * nm];
        for (k, &r) in modes.iter().enumerate() {
            for i in 0..n {
                rows[i * nm + k] = shapes[(i, r)];
            }
        }
        let mut pos = vec![usize::MAX; n];
        let mut dk = Vec::with_capacity(parameters.len());
        let mut dm = Vec::with_capacity(parameters.len());
        for p in parameters {
            dk.push(project_one(&p.dk, &rows, nm, &mut pos));
            dm.push(project_one(&p.dm, &rows, nm, &mut pos));
        }
        ModalSensitivities { dk, dm }
    }

    pub fn len(&self) -> usize {
        self.dk.len()
    }

    pub fn is_empty(&self) -> bool {
        self.dk.is_empty()
    }
}

/// Ψᵀ S Ψ for a sparse symmetric S, Ψ given row-major (n × nm).
fn project_one(s: &SparseMatrix, rows: &[f64], nm: usize, pos: &mut [usize]) -> Mat<f64> {
    let mut support: Vec<usize> = Vec::new();
    let mut y: Vec<f64> = Vec::new();
    let sym = s.symbolic();
    let ncols = s.ncols().min(pos.len());
    for c in 0..ncols {
        let vals = s.val_of_col(c);
        let ridx = sym.row_idx_of_col_raw(c);
        let pc = &rows[c * nm..(c + 1) * nm];
        for (&r, &v) in ridx.iter().zip(vals) {
            if v == 0.0 || r >= pos.len() {
                continue;
            }
            if pos[r] == usize::MAX {
                pos[r] = support.len();
                support.push(r);
                y.extend(std::iter::repeat_n(0.0, nm));
            }
            let slot = &mut y[pos[r] * nm..(pos[r] + 1) * nm];
            for (a, &b) in slot.iter_mut().zip(pc) {
                *a += v * b;
            }
        }
    }
    let ns = support.len();
    let psi_s = Mat::from_fn(ns, nm, |i, k| rows[support[i] * nm + k]);
    let y_s = Mat::from_fn(ns, nm, |i, k| y[i * nm + k]);
    for &r in &support {
        pos[r] = usize::MAX;
    }
    let out = product(psi_s.transpose(), y_s.as_ref());
    Mat::from_fn(nm, nm, |i, j| 0.5 * (out[(i, j)] + out[(j, i)]))
}

/// φᵀ S φ for one column `mode` of `shapes`.
pub fn quadratic_form(s: &SparseMatrix, shapes: MatRef<'_, f64>, mode: usize) -> f64 {
    let sym = s.symbolic();
    let n = shapes.nrows();
    let mut acc = 0.0;
    for c in 0..s.ncols().min(n) {
        let pc = shapes[(c, mode)];
        if pc == 0.0 {
            continue;
        }
        for (&r, &v) in sym.row_idx_of_col_raw(c).iter().zip(s.val_of_col(c)) {
            if r < n {
                acc += shapes[(r, mode)] * v * pc;
            }
        }
    }
    acc
}

/// Why the equations could not be formed.
#[derive(Debug, Clone, PartialEq)]
pub enum SensitivityError {
    /// An updating frequency coincides with a natural frequency of the current model.
    OnResonance {
        hz: f64,
    },
    Serep(SerepError),
}

impl std::fmt::Display for SensitivityError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            SensitivityError::OnResonance { hz } => write!(
                f,
                "updating frequency {hz} Hz coincides with a natural frequency of the current model; choose other frequencies"
            ),
            SensitivityError::Serep(e) => write!(f, "{e}"),
        }
    }
}

impl std::error::Error for SensitivityError {}

/// The stacked FRF equations A_h p = b_h (Eq. 11–12) and the current FE FRFs.
#[derive(Clone, Debug)]
pub struct FrfEquations {
    /// (N_fr·N_ex) × N_p, block i = A_i (m/N per unit relative change).
    pub a: Mat<f64>,
    /// b_h (m/N), block i = h_i^n − h̄_i.
    pub b: Vec<f64>,
    /// h_i^n at the measured DOFs (m/N), one vector per updating frequency.
    pub fe_frf: Vec<Vec<f64>>,
}

/// Form A_i, b_i at every updating frequency (ω_i in rad/s) and stack them.
/// `measured[i]` is h̄_i at the measured DOFs; `excitation` ψ_k, the basis
/// modes' values at the excitation DOF (N_md).
pub fn frf_equations(
    basis: &SerepBasis,
    sens: &ModalSensitivities,
    omegas: &[f64],
    measured: &[Vec<f64>],
    excitation: &[f64],
    method: InverseMethod,
) -> Result<FrfEquations, SensitivityError> {
    let n_ex = basis.measured_len();
    let nm = basis.len();
    let np = sens.len();
    let mut a = Mat::<f64>::zeros(omegas.len() * n_ex, np);
    let mut b = Vec::with_capacity(omegas.len() * n_ex);
    let mut fe_frf = Vec::with_capacity(omegas.len());
    let pm = &basis.psi_m;
    let pinv = &basis.psi_m_pinv;
    for (i, (&w, hbar)) in omegas.iter().zip(measured).enumerate() {
        let w2 = w * w;
        let d = basis
            .modal_factors(w2)
            .ok_or(SensitivityError::OnResonance {
                hz: w / (2.0 * std::f64::consts::PI),
            })?;
        // u = Ψ_m⁺ h̄
        let u: Vec<f64> = (0..nm)
            .map(|k| (0..n_ex).map(|e| pinv[(k, e)] * hbar[e]).sum())
            .collect();
        // V (N_md × N_p): v_j = C_j u
        let mut v = Mat::<f64>::zeros(nm, np);
        for j in 0..np {
            let (dk, dm) = (&sens.dk[j], &sens.dm[j]);
            for r in 0..nm {
                let mut acc = 0.0;
                for s in 0..nm {
                    acc += (dk[(r, s)] - w2 * dm[(r, s)]) * u[s];
                }
                v[(r, j)] = acc;
            }
        }
        let block = match method {
            InverseMethod::Svd => {
                let dv = Mat::from_fn(nm, np, |r, j| d[r] * v[(r, j)]);
                product(pm.as_ref(), dv.as_ref())
            }
            InverseMethod::Perturb { .. } => {
                let h = basis
                    .reduced_receptance(w2, method)
                    .map_err(SensitivityError::Serep)?;
                let wmat = product(pinv.transpose(), v.as_ref());
                product(h.as_ref(), wmat.as_ref())
            }
        };
        for e in 0..n_ex {
            for j in 0..np {
                a[(i * n_ex + e, j)] = block[(e, j)];
            }
        }
        let hn: Vec<f64> = (0..n_ex)
            .map(|e| (0..nm).map(|k| pm[(e, k)] * d[k] * excitation[k]).sum())
            .collect();
        for e in 0..n_ex {
            b.push(hn[e] - hbar[e]);
        }
        fe_frf.push(hn);
    }
    Ok(FrfEquations { a, b, fe_frf })
}

/// One natural-frequency equation row (Eq. 19–20) for the FE mode `mode` of
/// `shapes` with eigenvalue `omega2`, paired with the test ω̄² `test_omega2`.
pub fn frequency_equation(
    parameters: &[ParameterSensitivity],
    shapes: MatRef<'_, f64>,
    mode: usize,
    omega2: f64,
    test_omega2: f64,
) -> (Vec<f64>, f64) {
    let row = parameters
        .iter()
        .map(|p| {
            -(quadratic_form(&p.dk, shapes, mode) - omega2 * quadratic_form(&p.dm, shapes, mode))
        })
        .collect();
    (row, omega2 - test_omega2)
}
