//! Forced response: receptance H(ω) = x/f of the damped model.
//!
//! Direct: A(ω) x = f with A(ω) = K(1 + iη) + iωC − ω²M, C = αM + βK
//! (Rayleigh), factorised by a complex sparse LU whose symbolic analysis (on
//! the union pattern of K and M) is shared by all frequencies.
//!
//! Modal superposition: H_jk(ω) = Σ_r φ_jr φ_kr / d_r(ω) + R_jk with
//! d_r = ω_r² − ω² (undamped), ω_r² − ω² + 2iζω_rω (modal),
//! ω_r² − ω² + iω(α + βω_r²) (Rayleigh), ω_r²(1 + iη) − ω² (hysteretic), and
//! an optional static residual R_jk = [(K − σM)⁻¹]_jk − Σ_r φ_jr φ_kr/(ω_r² − σ)
//! standing for the modes left out (divided by 1 + iη for hysteretic damping).
//!
//! Modal damping has no C for the direct solve: [`try_direct_receptance`]
//! computes it by modal superposition over all modes (n ≤ 2500, exact: that is
//! C = MΦ diag(2ζω_r) ΦᵀM) or, for larger models, over the modes up to at
//! least 2·max ω plus the static residual.

use faer::linalg::solvers::SolveCore;
use faer::sparse::linalg::solvers::{Lu, SymbolicLu};
use faer::sparse::SparseColMatRef;
use faer::{c64, Conj, Mat};

use crate::model::{Damping, SparseMatrix};
use crate::solvers::eigen::lanczos::ShiftedCholesky;
use crate::solvers::eigen::{self, EigenError, EigenOptions, Modes};
use crate::solvers::sparse_ops::{self, PairPattern};

/// Why a forced response could not be computed.
#[derive(Debug)]
pub enum FrfError {
    /// Bad indices, shapes, damping values or frequencies.
    InvalidInput { detail: String },
    /// A(ω) is singular (an undamped model driven at an eigenfrequency).
    Singular { omega_rad_s: f64, detail: String },
    /// Computing the modes (modal damping, residual terms) failed.
    Eigen(EigenError),
}

impl std::fmt::Display for FrfError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            FrfError::InvalidInput { detail } => write!(f, "invalid FRF request: {detail}"),
            FrfError::Singular {
                omega_rad_s,
                detail,
            } => write!(
                f,
                "dynamic stiffness is singular at ω = {omega_rad_s} rad/s (an undamped resonance?): {detail}"
            ),
            FrfError::Eigen(e) => write!(f, "modes for the FRF: {e}"),
        }
    }
}

impl std::error::Error for FrfError {}

impl From<EigenError> for FrfError {
    fn from(e: EigenError) -> Self {
        FrfError::Eigen(e)
    }
}

fn invalid(detail: impl Into<String>) -> FrfError {
    FrfError::InvalidInput {
        detail: detail.into(),
    }
}

fn check_damping(damping: Damping) -> Result<(), FrfError> {
    let ok = match damping {
        Damping::None => true,
        Damping::Modal { zeta } => zeta.is_finite() && zeta >= 0.0,
        Damping::Rayleigh { alpha, beta } => {
            alpha.is_finite() && beta.is_finite() && alpha >= 0.0 && beta >= 0.0
        }
        Damping::Hysteretic { eta } => eta.is_finite() && eta >= 0.0,
    };
    if ok {
        Ok(())
    } else {
        Err(invalid(format!(
            "damping {damping:?} must be finite and non-negative"
        )))
    }
}

fn check_request(
    n: usize,
    omegas: &[f64],
    input: usize,
    outputs: &[usize],
) -> Result<(), FrfError> {
    if input >= n {
        return Err(invalid(format!(
            "input equation {input} ≥ number of DOFs {n}"
        )));
    }
    if let Some(o) = outputs.iter().find(|o| **o >= n) {
        return Err(invalid(format!("output equation {o} ≥ number of DOFs {n}")));
    }
    if let Some(w) = omegas.iter().find(|w| !w.is_finite()) {
        return Err(invalid(format!("frequency {w} rad/s is not finite")));
    }
    Ok(())
}

fn nan_matrix(rows: usize, cols: usize) -> Mat<c64> {
    Mat::from_fn(rows, cols, |_, _| c64::new(f64::NAN, f64::NAN))
}

/// Direct frequency-response solver of one model, reusable across
/// frequencies and right-hand sides.
pub struct DirectFrf {
    pattern: PairPattern,
    damping: Damping,
    symbolic: SymbolicLu<usize>,
    n: usize,
}

impl DirectFrf {
    /// Analyses the pattern of K + M once. Modal damping has no direct form:
    /// use [`try_direct_receptance`] or [`modal_receptance`].
    pub fn new(k: &SparseMatrix, m: &SparseMatrix, damping: Damping) -> Result<Self, FrfError> {
        check_damping(damping)?;
        if let Damping::Modal { .. } = damping {
            return Err(invalid(
                "modal damping has no damping matrix for a direct solve; use modal superposition",
            ));
        }
        let pattern = PairPattern::new(k, m).map_err(invalid)?;
        let symbolic = SymbolicLu::try_new(pattern.symbolic().as_ref())
            .map_err(|e| invalid(format!("symbolic LU: {e:?}")))?;
        Ok(DirectFrf {
            pattern,
            damping,
            symbolic,
            n: k.nrows(),
        })
    }

    /// Number of DOFs.
    pub fn n(&self) -> usize {
        self.n
    }

    /// Values of A(ω) = K(1 + iη) + iω(αM + βK) − ω²M on the union pattern.
    fn values(&self, omega: f64) -> Vec<c64> {
        let (eta, alpha, beta) = match self.damping {
            Damping::Hysteretic { eta } => (eta, 0.0, 0.0),
            Damping::Rayleigh { alpha, beta } => (0.0, alpha, beta),
            Damping::None | Damping::Modal { .. } => (0.0, 0.0, 0.0),
        };
        let ki = eta + omega * beta;
        let w2 = omega * omega;
        self.pattern.values_with(
            |k| c64::new(k, k * ki),
            |m| c64::new(-w2 * m, omega * alpha * m),
        )
    }

    /// x = A(ω)⁻¹ F for every column of F (n × r).
    pub fn solve(&self, omega_rad_s: f64, rhs: &Mat<c64>) -> Result<Mat<c64>, FrfError> {
        if rhs.nrows() != self.n {
            return Err(invalid(format!(
                "right-hand side has {} rows, model has {} DOFs",
                rhs.nrows(),
                self.n
            )));
        }
        let vals = self.values(omega_rad_s);
        let a = SparseColMatRef::new(self.pattern.symbolic().as_ref(), &vals);
        let singular = |detail: String| FrfError::Singular {
            omega_rad_s,
            detail,
        };
        let lu = Lu::try_new_with_symbolic(self.symbolic.clone(), a)
            .map_err(|e| singular(format!("{e:?}")))?;
        let mut x = rhs.clone();
        lu.solve_in_place_with_conj(Conj::No, x.as_mut());
        if x.col_iter()
            .any(|c| c.iter().any(|v| !(v.re.is_finite() && v.im.is_finite())))
        {
            return Err(singular("non-finite solution".into()));
        }
        Ok(x)
    }

    /// Receptance at `outputs` for a unit force at `input`: outputs × omegas.
    /// Frequencies are spread over the available threads.
    pub fn receptance(
        &self,
        omegas_rad_s: &[f64],
        input: usize,
        outputs: &[usize],
    ) -> Result<Mat<c64>, FrfError> {
        check_request(self.n, omegas_rad_s, input, outputs)?;
        let mut f = Mat::<c64>::zeros(self.n, 1);
        f[(input, 0)] = c64::new(1.0, 0.0);
        let threads = std::thread::available_parallelism()
            .map(|t| t.get())
            .unwrap_or(1)
            .min(omegas_rad_s.len())
            .max(1);
        let chunk = omegas_rad_s.len().div_ceil(threads).max(1);
        let columns: Vec<Result<Vec<Vec<c64>>, FrfError>> = std::thread::scope(|s| {
            let handles: Vec<_> = omegas_rad_s
                .chunks(chunk)
                .map(|ws| {
                    let f = &f;
                    s.spawn(move || {
                        ws.iter()
                            .map(|&w| {
                                let x = self.solve(w, f)?;
                                Ok(outputs.iter().map(|&o| x[(o, 0)]).collect())
                            })
                            .collect::<Result<Vec<_>, FrfError>>()
                    })
                })
                .collect();
            handles
                .into_iter()
                .map(|h| {
                    h.join()
                        .unwrap_or_else(|_| Err(invalid("FRF worker thread panicked")))
                })
                .collect()
        });
        let mut out = Mat::<c64>::zeros(outputs.len(), omegas_rad_s.len());
        let mut col = 0;
        for part in columns {
            for c in part? {
                for (r, v) in c.into_iter().enumerate() {
                    out[(r, col)] = v;
                }
                col += 1;
            }
        }
        Ok(out)
    }
}

/// Receptance (m/N) at `outputs` for a unit force at `input`, one
/// column per frequency: result is outputs.len() × omegas.len().
/// Direct complex solve of (K(1+iη) + iωC − ω²M) x = f.
///
/// On invalid input or a singular A(ω) every entry is NaN; use
/// [`try_direct_receptance`] for the reason.
pub fn direct_receptance(
    k: &SparseMatrix,
    m: &SparseMatrix,
    damping: Damping,
    omegas_rad_s: &[f64],
    input: usize,
    outputs: &[usize],
) -> faer::Mat<c64> {
    try_direct_receptance(k, m, damping, omegas_rad_s, input, outputs)
        .unwrap_or_else(|_| nan_matrix(outputs.len(), omegas_rad_s.len()))
}

/// [`direct_receptance`] with errors as values. Modal damping goes through
/// modal superposition (see the module notes).
pub fn try_direct_receptance(
    k: &SparseMatrix,
    m: &SparseMatrix,
    damping: Damping,
    omegas_rad_s: &[f64],
    input: usize,
    outputs: &[usize],
) -> Result<Mat<c64>, FrfError> {
    check_damping(damping)?;
    sparse_ops::check_pair(k, m).map_err(invalid)?;
    check_request(k.nrows(), omegas_rad_s, input, outputs)?;
    if let Damping::Modal { .. } = damping {
        return modal_damping_receptance(k, m, damping, omegas_rad_s, input, outputs);
    }
    DirectFrf::new(k, m, damping)?.receptance(omegas_rad_s, input, outputs)
}

/// Modal damping: all modes when the dense path applies, else the modes up to
/// at least 2·max ω (doubling the count) plus the static residual.
fn modal_damping_receptance(
    k: &SparseMatrix,
    m: &SparseMatrix,
    damping: Damping,
    omegas_rad_s: &[f64],
    input: usize,
    outputs: &[usize],
) -> Result<Mat<c64>, FrfError> {
    let n = k.nrows();
    let dense_limit = EigenOptions::default().dense_limit;
    if n <= dense_limit {
        let opts = EigenOptions {
            count: n,
            dense_limit,
            ..EigenOptions::default()
        };
        let modes = eigen::lowest_modes(k, m, &opts)?;
        return try_modal_receptance(&modes, damping, omegas_rad_s, input, outputs, None);
    }
    let w_max = omegas_rad_s.iter().fold(0.0f64, |a, w| a.max(w.abs()));
    let mut count = 50usize.min(n);
    loop {
        let opts = EigenOptions {
            count,
            dense_limit,
            ..EigenOptions::default()
        };
        let modes = eigen::lowest_modes(k, m, &opts)?;
        let top = modes.omega2.last().copied().unwrap_or(0.0);
        if top >= (2.0 * w_max).powi(2) || count >= n || count >= 800 {
            let residual = static_residual(k, m, &modes, input, outputs)?;
            return try_modal_receptance(
                &modes,
                damping,
                omegas_rad_s,
                input,
                outputs,
                Some(&residual),
            );
        }
        count = (2 * count).min(n);
    }
}

/// Static residual of the modes *not* in `modes`, for the given input and
/// outputs: R_j = [(K − σM)⁻¹]_{j,input} − Σ_r φ_jr φ_input,r / (ω_r² − σ),
/// with a small σ < 0 (−1e-8·max K_ii/M_ii) so free-free models work too.
/// Units m/N.
pub fn static_residual(
    k: &SparseMatrix,
    m: &SparseMatrix,
    modes: &Modes,
    input: usize,
    outputs: &[usize],
) -> Result<Vec<f64>, FrfError> {
    let n = k.nrows();
    let chol = residual_factor(k, m, modes, input, outputs)?;
    let sigma = chol.shift;
    let mut e = Mat::<f64>::zeros(n, 1);
    e[(input, 0)] = 1.0;
    let x = chol.solve(e.as_ref());
    Ok(outputs
        .iter()
        .map(|&j| {
            let modal: f64 = (0..modes.len())
                .map(|r| {
                    modes.shapes[(j, r)] * modes.shapes[(input, r)] / (modes.omega2[r] - sigma)
                })
                .sum();
            x[(j, 0)] - modal
        })
        .collect())
}

/// Checks of a residual request and the factor of K − σM with the small
/// shift σ < 0 (−1e-8·max K_ii/M_ii) that keeps free-free models regular.
fn residual_factor(
    k: &SparseMatrix,
    m: &SparseMatrix,
    modes: &Modes,
    input: usize,
    outputs: &[usize],
) -> Result<ShiftedCholesky, FrfError> {
    let scale = eigen::pencil_scale(k, m)?;
    let n = k.nrows();
    check_request(n, &[], input, outputs)?;
    if modes.shapes.nrows() != n {
        return Err(invalid(format!(
            "mode shapes have {} rows, model has {n} DOFs",
            modes.shapes.nrows()
        )));
    }
    Ok(ShiftedCholesky::new(k, m, -1e-8 * scale.max_ratio)?)
}

/// The static residual of [`static_residual`] and its first correction in
/// frequency: the modes left out contribute
/// Σ_high φ_jr φ_ir / (λ_r − ω²) ≈ R0_j + ω² R1_j with
/// R1_j = Σ_high φ_jr φ_ir / λ_r² (σ-shifted as R0). Computed as
/// x = (K − σM)⁻¹e_i and v = (K − σM)⁻¹M x̄, each M-orthogonally deflated of
/// the computed modes (x̄ = x − ΦΦᵀMx), so rigid-body modes cancel exactly.
/// Units m/N and m/N·s².
pub fn static_residual_terms(
    k: &SparseMatrix,
    m: &SparseMatrix,
    modes: &Modes,
    input: usize,
    outputs: &[usize],
) -> Result<(Vec<f64>, Vec<f64>), FrfError> {
    let n = k.nrows();
    let chol = residual_factor(k, m, modes, input, outputs)?;
    let mass_times = |x: &Mat<f64>| -> Mat<f64> {
        let mut y = Mat::<f64>::zeros(n, 1);
        let sym = m.symbolic();
        for c in 0..n {
            let xc = x[(c, 0)];
            if xc == 0.0 {
                continue;
            }
            for (&r, &v) in sym.row_idx_of_col_raw(c).iter().zip(m.val_of_col(c)) {
                y[(r, 0)] += v * xc;
            }
        }
        y
    };
    let deflate = |x: &mut Mat<f64>| {
        let mx = mass_times(x);
        for r in 0..modes.len() {
            let c: f64 = (0..n).map(|i| modes.shapes[(i, r)] * mx[(i, 0)]).sum();
            for i in 0..n {
                x[(i, 0)] -= c * modes.shapes[(i, r)];
            }
        }
    };
    let mut e = Mat::<f64>::zeros(n, 1);
    e[(input, 0)] = 1.0;
    let mut x = chol.solve(e.as_ref());
    deflate(&mut x);
    let mut v = chol.solve(mass_times(&x).as_ref());
    deflate(&mut v);
    Ok((
        outputs.iter().map(|&j| x[(j, 0)]).collect(),
        outputs.iter().map(|&j| v[(j, 0)]).collect(),
    ))
}

/// Same quantity by modal superposition over `modes`.
///
/// On invalid input every entry is NaN; use [`try_modal_receptance`] for the
/// reason and for the residual term.
pub fn modal_receptance(
    modes: &Modes,
    damping: Damping,
    omegas_rad_s: &[f64],
    input: usize,
    outputs: &[usize],
) -> faer::Mat<c64> {
    try_modal_receptance(modes, damping, omegas_rad_s, input, outputs, None)
        .unwrap_or_else(|_| nan_matrix(outputs.len(), omegas_rad_s.len()))
}

/// Modal superposition with an optional residual (one value per output, m/N,
/// e.g. from [`static_residual`]).
pub fn try_modal_receptance(
    modes: &Modes,
    damping: Damping,
    omegas_rad_s: &[f64],
    input: usize,
    outputs: &[usize],
    residual: Option<&[f64]>,
) -> Result<Mat<c64>, FrfError> {
    check_damping(damping)?;
    let n = modes.shapes.nrows();
    check_request(n, omegas_rad_s, input, outputs)?;
    if modes.shapes.ncols() != modes.omega2.len() {
        return Err(invalid("mode shapes and ω² have different counts"));
    }
    if let Some(r) = residual {
        if r.len() != outputs.len() {
            return Err(invalid(format!(
                "{} residual values for {} outputs",
                r.len(),
                outputs.len()
            )));
        }
    }
    let residual_factor = match damping {
        Damping::Hysteretic { eta } => c64::new(1.0, eta).inv(),
        _ => c64::new(1.0, 0.0),
    };
    let mut out = Mat::<c64>::zeros(outputs.len(), omegas_rad_s.len());
    for (c, &w) in omegas_rad_s.iter().enumerate() {
        let inv_d: Vec<c64> = modes
            .omega2
            .iter()
            .map(|&w2| damping.modal_denominator(w2, w).inv())
            .collect();
        for (row, &j) in outputs.iter().enumerate() {
            let mut h = c64::new(0.0, 0.0);
            for (r, id) in inv_d.iter().enumerate() {
                h += id * (modes.shapes[(j, r)] * modes.shapes[(input, r)]);
            }
            if let Some(res) = residual {
                h += residual_factor * res[row];
            }
            out[(row, c)] = h;
        }
    }
    Ok(out)
}
