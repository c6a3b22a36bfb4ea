//! Lowest modes of K φ = ω² M φ, mass-normalised.

use crate::model::SparseMatrix;

/// CONTRACT. Modes in ascending frequency order.
#[derive(Clone, Debug)]
pub struct Modes {
    /// ω_r² (rad²/s²); rigid-body modes give values near 0 (may be slightly negative).
    pub omega2: Vec<f64>,
    /// Φ (n_dof × n_modes), mass-normalised: Φᵀ M Φ = I.
    pub shapes: faer::Mat<f64>,
}

impl Modes {
    /// CONTRACT. f_r = √max(ω_r², 0) / 2π in Hz.
    pub fn frequencies_hz(&self) -> Vec<f64> {
        self.omega2
            .iter()
            .map(|w2| w2.max(0.0).sqrt() / (2.0 * std::f64::consts::PI))
            .collect()
    }
    pub fn len(&self) -> usize {
        self.omega2.len()
    }
    pub fn is_empty(&self) -> bool {
        self.omega2.is_empty()
    }
}

/// CONTRACT. Options of [`lowest_modes`].
#[derive(Clone, Debug)]
pub struct EigenOptions {
    /// How many of the lowest modes (clamped to the number of DOFs).
    pub count: usize,
    /// Models with at most this many DOFs take the dense path.
    pub dense_limit: usize,
    /// True when the model has fixed DOFs: zero-energy modes are then reported as mechanisms.
    pub expect_no_rigid_body_modes: bool,
}

impl Default for EigenOptions {
    fn default() -> Self {
        EigenOptions {
            count: 20,
            dense_limit: 2500,
            expect_no_rigid_body_modes: false,
        }
    }
}

/// CONTRACT. Why an eigen solve failed.
#[derive(Debug)]
pub enum EigenError {
    /// A fixed model has this many zero-energy modes (mechanisms).
    Mechanisms { count: usize },
    /// M is not positive definite on the free DOFs (e.g. a DOF with no mass).
    MassNotPositive { detail: String },
    /// The iteration did not converge.
    NoConvergence { detail: String },
}

impl std::fmt::Display for EigenError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            EigenError::Mechanisms { count } => write!(
                f,
                "the model has fixed DOFs but {count} zero-energy mode(s) (mechanisms): check fix, springs and element connectivity"
            ),
            EigenError::MassNotPositive { detail } => {
                write!(f, "mass matrix is not positive definite: {detail}")
            }
            EigenError::NoConvergence { detail } => {
                write!(f, "eigen solver did not converge: {detail}")
            }
        }
    }
}

impl std::error::Error for EigenError {}

/// CONTRACT. The `opts.count` lowest modes of (K, M).
pub fn lowest_modes(
    k: &SparseMatrix,
    m: &SparseMatrix,
    opts: &EigenOptions,
) -> Result<Modes, EigenError> {
    let _ = (k, m, opts);
    todo!("solvers helper implements this")
}
