//! Lowest modes of K φ = ω² M φ, mass-normalised.
//!
//! Both paths work on the shifted pencil: with a shift σ < 0, K − σM = L Lᵀ is
//! positive definite even for free-free models, and the symmetric standard
//! problem L⁻¹ M L⁻ᵀ y = μ y has μ = 1/(ω² − σ): the largest μ give the lowest
//! ω², and φ = L⁻ᵀ y. Small models ([`dense`]) reduce and solve it densely;
//! large ones ([`lanczos`]) run a block Krylov method on a sparse supernodal
//! Cholesky factor. Every returned ω² is the Rayleigh quotient φᵀKφ of the
//! mass-normalised φ, which is accurate to O(ε) even for the lowest modes.

pub mod dense;
pub mod lanczos;
pub mod nodal;
pub mod tridiagonal;

use faer::reborrow::{Reborrow, ReborrowMut};
use faer::Mat;

use crate::model::SparseMatrix;
use crate::solvers::sparse_ops;

/// Modes in ascending frequency order.
#[derive(Clone, Debug)]
pub struct Modes {
    /// ω_r² (rad²/s²); rigid-body modes give values near 0 (may be slightly negative).
    pub omega2: Vec<f64>,
    /// Φ (n_dof × n_modes), mass-normalised: Φᵀ M Φ = I.
    pub shapes: faer::Mat<f64>,
}

impl Modes {
    /// f_r = √max(ω_r², 0) / 2π in Hz.
    pub fn frequencies_hz(&self) -> Vec<f64> {
        self.omega2
            .iter()
            .map(|w2| w2.max(0.0).sqrt() / (2.0 * std::f64::consts::PI))
            .collect()
    }
    /// The shapes at the equations `dofs`, [mode][dof]: what a sensor layout sees.
    pub fn at(&self, dofs: &[usize]) -> Vec<Vec<f64>> {
        (0..self.shapes.ncols().min(self.omega2.len()))
            .map(|r| dofs.iter().map(|&i| self.shapes[(i, r)]).collect())
            .collect()
    }
    pub fn len(&self) -> usize {
        self.omega2.len()
    }
    pub fn is_empty(&self) -> bool {
        self.omega2.is_empty()
    }
}

/// Smallest model for which [`EigenOptions::krylov_dofs_per_mode`] applies.
/// Below it the dense path costs a few milliseconds and, unlike the Krylov
/// method, never depends on how the spectrum clusters (a 384-DOF lattice
/// wanting 40 modes: dense 8 ms, Krylov 19 ms with five restarts).
pub const KRYLOV_MIN_DOFS: usize = 1000;

/// Restarts the Krylov path may take on a model below `dense_limit` before
/// the dense path takes over (a 1,176-DOF lattice wanting 100 modes needs 4).
const FEW_MODES_MAX_RESTARTS: usize = 20;

/// Default of [`EigenOptions::krylov_dofs_per_mode`]. Measured (one thread):
/// 2,400-DOF plate lattice, 10 modes: dense 1.34 s, Krylov 26 ms; 40 modes:
/// 1.37 s and 60 ms; 1,176-DOF lattice, 40 modes: 145 ms and 27 ms, 100
/// modes (12 DOFs a mode): 159 ms and 131 ms, about even; 20 keeps a margin.
pub const KRYLOV_DOFS_PER_MODE: usize = 20;

/// Options of [`lowest_modes`].
#[derive(Clone, Debug)]
pub struct EigenOptions {
    /// How many of the lowest modes (clamped to the number of DOFs).
    pub count: usize,
    /// Models with at most this many DOFs take the dense path, unless
    /// `krylov_dofs_per_mode` sends them to the Krylov one.
    pub dense_limit: usize,
    /// Models of at least [`KRYLOV_MIN_DOFS`] DOFs with at least this many DOFs
    /// per wanted mode take the sparse Krylov path even below `dense_limit`
    /// (0: never). Dense costs O(n³) whatever the count; the Krylov path about
    /// O(n·count²).
    pub krylov_dofs_per_mode: usize,
    /// True when the model has fixed DOFs: zero-energy modes are then reported as mechanisms.
    pub expect_no_rigid_body_modes: bool,
    /// With `Some(ω²_top)` (rad²/s²), fewer than `count` modes when fewer
    /// reach past it: the modes with ω² ≤ ω²_top and the one above them.
    /// The dense path counts them on its tridiagonal form (a Sturm count);
    /// the Krylov path returns `count`.
    pub cover_omega2: Option<f64>,
    /// With `cover_omega2`, the dense path returns every mode up to it and
    /// the one above even when they are more than `count`: `count` doubles
    /// until it covers them, all the modes once it reaches n (see
    /// [`dense::Cover::grow`]), so a caller that would solve again with
    /// twice the count gets the same modes from one solution. The Krylov
    /// path still returns `count`.
    pub grow_to_cover: bool,
}

impl Default for EigenOptions {
    fn default() -> Self {
        EigenOptions {
            count: 20,
            dense_limit: 2500,
            krylov_dofs_per_mode: KRYLOV_DOFS_PER_MODE,
            expect_no_rigid_body_modes: false,
            cover_omega2: None,
            grow_to_cover: false,
        }
    }
}

/// Why an eigen solve failed.
#[derive(Debug)]
pub enum EigenError {
    /// A fixed model has this many zero-energy modes (mechanisms); the
    /// equations (0-based) that move most in them.
    Mechanisms { count: usize, equations: Vec<usize> },
    /// M is not positive definite on the free DOFs (e.g. a DOF with no mass).
    MassNotPositive { detail: String },
    /// The iteration did not converge.
    NoConvergence { detail: String },
    /// K and M are not a usable pencil (shapes, non-finite entries, negative stiffness).
    InvalidInput { detail: String },
}

impl std::fmt::Display for EigenError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            EigenError::Mechanisms { count, equations } => write!(
                f,
                "the model has fixed DOFs but {count} zero-energy mode(s) (mechanisms) moving equation(s) {}: check fix, springs and element connectivity",
                equations.iter().map(|e| e.to_string()).collect::<Vec<_>>().join(", ")
            ),
            EigenError::MassNotPositive { detail } => {
                write!(f, "mass matrix is not positive definite: {detail}")
            }
            EigenError::NoConvergence { detail } => {
                write!(f, "eigen solver did not converge: {detail}")
            }
            EigenError::InvalidInput { detail } => {
                write!(f, "invalid stiffness/mass matrices: {detail}")
            }
        }
    }
}

impl std::error::Error for EigenError {}

/// Tuning knobs of [`lowest_modes_with`]; [`Default`] suits FE beam models.
#[derive(Clone, Debug)]
pub struct EigenTuning {
    /// Shift σ (rad²/s², must be < 0) instead of the automatic choice
    /// (dense: σ = −1e-4·s̃, sparse: σ = −min(1e-8·s_max, 1e-4·s̃), where s̃
    /// and s_max are the median and largest K_ii/M_ii).
    pub shift: Option<f64>,
    /// Modes with ω² < `zero_energy_tolerance` · s_max are zero-energy modes
    /// (rigid-body modes or mechanisms).
    pub zero_energy_tolerance: f64,
    /// Sparse path: a Ritz pair (μ, y) is converged when ‖C y − μ y‖ ≤ tol · μ,
    /// or when its residual has stalled below the rounding floor of the
    /// Krylov relation (2e4 ε μ₁; see `lanczos`), which only binds for the
    /// smallest wanted μ when μ₁/μ spans several decades.
    pub tolerance: f64,
    /// Sparse path: block size of the Krylov method (vectors per operator application).
    pub block_size: usize,
    /// Sparse path: largest Krylov basis (0 = automatic, about 2·count + 4·block).
    pub max_basis: usize,
    /// Sparse path: restarts before giving up.
    pub max_restarts: usize,
    /// Sparse path, automatic shift only: after a first factorisation, move σ
    /// up to 0.97 of the way to an estimate of the lowest ω² (see
    /// [`lanczos`]), which speeds up convergence on fixed structures.
    pub auto_shift: bool,
}

impl Default for EigenTuning {
    fn default() -> Self {
        EigenTuning {
            shift: None,
            zero_energy_tolerance: 1e-10,
            tolerance: 1e-9,
            block_size: 8,
            max_basis: 0,
            max_restarts: 300,
            auto_shift: true,
        }
    }
}

/// Which algorithm produced the modes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EigenPath {
    Dense,
    Sparse,
}

/// What [`lowest_modes_with`] did, for logs and benchmarks.
#[derive(Clone, Debug)]
pub struct EigenReport {
    pub path: EigenPath,
    /// The shift σ used (rad²/s², negative).
    pub shift: f64,
    /// The shift σ₀ asked for (rad²/s²): the dense path's before its ×100
    /// retries, the sparse path's before its probe moved it.
    pub initial_shift: f64,
    /// Largest K_ii/M_ii (rad²/s²): the stiffness scale of the tolerances.
    pub stiffness_scale: f64,
    /// Number of returned modes with ω² below the zero-energy tolerance.
    pub zero_energy_modes: usize,
    /// Largest ‖Kφ − ω²Mφ‖ / (s_max ‖Mφ‖) over the returned modes.
    pub max_residual: f64,
    /// Sparse path: vectors the operator (K − σM)⁻¹M was applied to.
    pub operator_applications: usize,
    /// Sparse path: restarts of the Krylov method.
    pub restarts: usize,
    /// Sparse path: nonzeros of the Cholesky factor.
    pub factor_nonzeros: usize,
}

/// The `opts.count` lowest modes of (K, M).
///
/// Errors instead of panics: shape/finiteness problems → `InvalidInput`, a
/// non-positive M_ii → `MassNotPositive`, zero-energy modes of a fixed model →
/// `Mechanisms`.
pub fn lowest_modes(
    k: &SparseMatrix,
    m: &SparseMatrix,
    opts: &EigenOptions,
) -> Result<Modes, EigenError> {
    lowest_modes_with(k, m, opts, &EigenTuning::default()).map(|(modes, _)| modes)
}

/// Scales of the pencil from its diagonals.
pub(crate) struct PencilScale {
    /// Largest K_ii/M_ii.
    pub max_ratio: f64,
    /// Median K_ii/M_ii.
    pub median_ratio: f64,
}

/// Checks shapes, finiteness and diagonals; returns the K/M diagonal ratios' scales.
pub(crate) fn pencil_scale(k: &SparseMatrix, m: &SparseMatrix) -> Result<PencilScale, EigenError> {
    sparse_ops::check_pair(k, m).map_err(|detail| EigenError::InvalidInput { detail })?;
    let dk = sparse_ops::diagonal(k);
    let dm = sparse_ops::diagonal(m);
    if let Some((i, v)) = dm.iter().enumerate().find(|(_, v)| **v <= 0.0) {
        return Err(EigenError::MassNotPositive {
            detail: format!("M[{i},{i}] = {v} at equation {i} (a DOF without mass?)"),
        });
    }
    if let Some((i, v)) = dk.iter().enumerate().find(|(_, v)| **v < 0.0) {
        return Err(EigenError::InvalidInput {
            detail: format!("K[{i},{i}] = {v} is negative"),
        });
    }
    let mut ratios: Vec<f64> = dk.iter().zip(&dm).map(|(k, m)| k / m).collect();
    ratios.sort_by(f64::total_cmp);
    let max_ratio = ratios.last().copied().unwrap_or(0.0);
    let positive: Vec<f64> = ratios.iter().copied().filter(|r| *r > 0.0).collect();
    let median_ratio = positive.get(positive.len() / 2).copied().unwrap_or(0.0);
    // A zero K gives only rigid-body modes; any positive scale then works.
    let max_ratio = if max_ratio > 0.0 { max_ratio } else { 1.0 };
    let median_ratio = if median_ratio > 0.0 {
        median_ratio
    } else {
        max_ratio
    };
    Ok(PencilScale {
        max_ratio,
        median_ratio,
    })
}

/// The lowest modes with explicit tuning, and a report of what was done.
pub fn lowest_modes_with(
    k: &SparseMatrix,
    m: &SparseMatrix,
    opts: &EigenOptions,
    tuning: &EigenTuning,
) -> Result<(Modes, EigenReport), EigenError> {
    let scale = pencil_scale(k, m)?;
    let n = k.nrows();
    let count = opts.count.min(n);
    if let Some(s) = tuning.shift {
        if !(s < 0.0 && s.is_finite()) {
            return Err(EigenError::InvalidInput {
                detail: format!("shift σ = {s} must be negative and finite"),
            });
        }
    }
    let few_modes = opts.krylov_dofs_per_mode > 0
        && n >= KRYLOV_MIN_DOFS
        && count.saturating_mul(opts.krylov_dofs_per_mode) <= n;
    let mut report = EigenReport {
        path: if n <= opts.dense_limit && !few_modes {
            EigenPath::Dense
        } else {
            EigenPath::Sparse
        },
        shift: 0.0,
        initial_shift: 0.0,
        stiffness_scale: scale.max_ratio,
        zero_energy_modes: 0,
        max_residual: 0.0,
        operator_applications: 0,
        restarts: 0,
        factor_nonzeros: 0,
    };
    if count == 0 {
        return Ok((
            Modes {
                omega2: Vec::new(),
                shapes: Mat::zeros(n, 0),
            },
            report,
        ));
    }
    let dense_path = |report: &mut EigenReport| -> Result<Mat<f64>, EigenError> {
        let shift = tuning.shift.unwrap_or(-1e-4 * scale.median_ratio);
        let cover = opts.cover_omega2.map(|omega2| dense::Cover {
            omega2,
            grow: opts.grow_to_cover,
        });
        let (phi, used) = dense::shift_invert(k, m, count, cover, shift)?;
        report.path = EigenPath::Dense;
        report.initial_shift = shift;
        report.shift = used;
        Ok(phi)
    };
    let shapes = match report.path {
        EigenPath::Dense => dense_path(&mut report)?,
        EigenPath::Sparse => {
            let (shift, tuning) = match tuning.shift {
                Some(s) => (
                    s,
                    &EigenTuning {
                        auto_shift: false,
                        ..tuning.clone()
                    },
                ),
                // Below the spectrum but not far: a huge K_ii/M_ii (a short,
                // stiff element with little rotary inertia) must not put σ₀
                // orders of magnitude below the wanted ω², where all
                // μ = 1/(ω² − σ) look alike and Krylov convergence stalls.
                None => (
                    -(1e-8 * scale.max_ratio).min(1e-4 * scale.median_ratio),
                    tuning,
                ),
            };
            report.initial_shift = shift;
            // A model the dense path could take gives the Krylov method a few
            // restarts only: dense costs at most ~1 s there.
            let capped;
            let tuning = if n <= opts.dense_limit {
                capped = EigenTuning {
                    max_restarts: tuning.max_restarts.min(FEW_MODES_MAX_RESTARTS),
                    ..tuning.clone()
                };
                &capped
            } else {
                tuning
            };
            match lanczos::shift_invert(k, m, count, shift, tuning) {
                Ok(out) => {
                    report.shift = out.shift;
                    report.operator_applications = out.operator_applications;
                    report.restarts = out.restarts;
                    report.factor_nonzeros = out.factor_nonzeros;
                    out.vectors
                }
                // A model small enough for the dense path gets it when the
                // Krylov method gives up.
                Err(EigenError::NoConvergence { .. }) if n <= opts.dense_limit => {
                    dense_path(&mut report)?
                }
                Err(e) => return Err(e),
            }
        }
    };
    let modes = finish(k, m, shapes, &scale, &mut report);
    let zero = tuning.zero_energy_tolerance * scale.max_ratio;
    let zero_energy = zero_energy_modes(k, m, &modes, zero);
    report.zero_energy_modes = zero_energy.len();
    if opts.expect_no_rigid_body_modes && !zero_energy.is_empty() {
        return Err(EigenError::Mechanisms {
            count: zero_energy.len(),
            equations: moving_equations(m, &modes, &zero_energy),
        });
    }
    Ok((modes, report))
}

/// Below this ratio of ω² to the stiffness of the DOFs a mode moves
/// (Σ K_ii φ_i², φ mass-normalised), a mode stores no strain energy.
const LOCAL_ZERO_ENERGY: f64 = 1e-6;

/// The modes that store no strain energy: ω² below `zero` (relative to the
/// stiffest DOF of the model) and also negligible against the stiffness of
/// the DOFs the mode moves. The second test keeps a stiff joint (1e10 N/m
/// springs on light nodes: a huge largest K_ii/M_ii) from turning a soft but
/// elastic mode elsewhere into a "mechanism".
fn zero_energy_modes(k: &SparseMatrix, m: &SparseMatrix, modes: &Modes, zero: f64) -> Vec<usize> {
    let dk = sparse_ops::diagonal(k);
    let _ = m;
    (0..modes.omega2.len())
        .filter(|&r| {
            let w2 = modes.omega2[r];
            if w2 >= zero {
                return false;
            }
            let col = modes.shapes.col(r);
            let local: f64 = (0..dk.len()).map(|i| dk[i] * col[i] * col[i]).sum();
            w2 < LOCAL_ZERO_ENERGY * local || local <= 0.0
        })
        .collect()
}

/// The equations (0-based) that carry most of the kinetic energy of the
/// zero-energy `modes` (φ_i² M_ii at least a quarter of the largest), at most 12.
fn moving_equations(m: &SparseMatrix, modes: &Modes, zero_energy: &[usize]) -> Vec<usize> {
    let dm = sparse_ops::diagonal(m);
    let mut out = Vec::new();
    for &r in zero_energy {
        let col = modes.shapes.col(r);
        let energy: Vec<f64> = (0..dm.len()).map(|i| dm[i] * col[i] * col[i]).collect();
        let top = energy.iter().fold(0.0f64, |a, &b| a.max(b));
        for (i, e) in energy.iter().enumerate() {
            if *e >= 0.25 * top && !out.contains(&i) {
                out.push(i);
            }
        }
    }
    out.sort_unstable();
    out.truncate(12);
    out
}

/// Below this many stored entries of K and M times modes, [`finish`] stays on
/// the calling thread.
const PARALLEL_FINISH_WORK: usize = 1 << 20;

/// Mass-normalises Φ, sets ω² to the Rayleigh quotients, sorts ascending, and
/// records the largest residual ‖Kφ − ω²Mφ‖ / (s_max ‖Mφ‖).
///
/// The columns are split between the threads of [`sparse_ops::par`], each
/// working through blocks of [`MODE_BLOCK`] modes (see [`ModeBlock`]).
fn finish(
    k: &SparseMatrix,
    m: &SparseMatrix,
    mut phi: Mat<f64>,
    scale: &PencilScale,
    report: &mut EigenReport,
) -> Modes {
    let count = phi.ncols();
    let mut omega2 = vec![0.0; count];
    let mut residuals = vec![0.0; count];
    let normalise = |mine: faer::MatMut<'_, f64>, w2: &mut [f64], res: &mut [f64]| {
        let mut block = ModeBlock::new(mine.nrows());
        let mut mine = mine;
        let pieces = w2.chunks_mut(MODE_BLOCK).zip(res.chunks_mut(MODE_BLOCK));
        for (b, (w2, res)) in pieces.enumerate() {
            let cols = mine.rb_mut().subcols_mut(b * MODE_BLOCK, w2.len());
            block.normalise(k, m, cols, w2, res, scale.max_ratio);
        }
    };
    // Two sparse products per mode: below about a millisecond of work a
    // thread start costs more than it saves (39 modes of 336 DOFs: ~0.5 Mflop).
    let work = count * (k.val().len() + m.val().len());
    if work < PARALLEL_FINISH_WORK {
        normalise(phi.as_mut(), &mut omega2, &mut residuals);
    } else {
        let threads = sparse_ops::par().degree().max(1);
        let per_thread = count
            .div_ceil(threads)
            .next_multiple_of(MODE_BLOCK)
            .max(MODE_BLOCK);
        std::thread::scope(|scope| {
            let mut rest = phi.as_mut();
            let chunks = omega2
                .chunks_mut(per_thread)
                .zip(residuals.chunks_mut(per_thread));
            for (w2, res) in chunks {
                let (mine, others) = rest.split_at_col_mut(w2.len());
                rest = others;
                scope.spawn(move || normalise(mine, w2, res));
            }
        });
    }
    report.max_residual = residuals.iter().copied().fold(0.0, f64::max);
    if omega2.is_sorted_by(|a, b| a.total_cmp(b).is_le()) {
        return Modes {
            omega2,
            shapes: phi,
        };
    }
    let mut order: Vec<usize> = (0..omega2.len()).collect();
    order.sort_by(|a, b| omega2[*a].total_cmp(&omega2[*b]));
    let shapes = Mat::from_fn(phi.nrows(), order.len(), |i, j| phi[(i, order[j])]);
    Modes {
        omega2: order.iter().map(|&j| omega2[j]).collect(),
        shapes,
    }
}

/// Modes per block of [`finish`]: K and M are read once per block, and the
/// products with a block vectorise across its modes.
const MODE_BLOCK: usize = 8;

/// Up to [`MODE_BLOCK`] mode shapes interleaved by DOF (x[i·B + c] = φ_c[i]),
/// with their products with M and K.
struct ModeBlock {
    x: Vec<f64>,
    mx: Vec<f64>,
    kx: Vec<f64>,
}

impl ModeBlock {
    fn new(n: usize) -> Self {
        let zeros = || vec![0.0; n * MODE_BLOCK];
        ModeBlock {
            x: zeros(),
            mx: zeros(),
            kx: zeros(),
        }
    }

    /// Scales the columns of `phi` to φᵀMφ = 1 and stores their Rayleigh
    /// quotients ω² = φᵀKφ and residuals ‖Kφ − ω²Mφ‖ / (s_max ‖Mφ‖).
    fn normalise(
        &mut self,
        k: &SparseMatrix,
        m: &SparseMatrix,
        mut phi: faer::MatMut<'_, f64>,
        omega2: &mut [f64],
        residuals: &mut [f64],
        max_ratio: f64,
    ) {
        let width = phi.ncols();
        self.x.fill(0.0);
        for c in 0..width {
            for (i, v) in phi.rb().col(c).iter().enumerate() {
                self.x[i * MODE_BLOCK + c] = *v;
            }
        }
        apply(m, &self.x, &mut self.mx);
        apply(k, &self.x, &mut self.kx);
        let rows = || {
            self.x
                .chunks_exact(MODE_BLOCK)
                .zip(self.mx.chunks_exact(MODE_BLOCK))
                .zip(self.kx.chunks_exact(MODE_BLOCK))
        };
        let mut norms = [0.0; MODE_BLOCK];
        for ((x, mx), _) in rows() {
            for c in 0..MODE_BLOCK {
                norms[c] += x[c] * mx[c];
            }
        }
        let factors = norms.map(|nc: f64| 1.0 / nc.max(f64::MIN_POSITIVE).sqrt());
        let mut w2 = [0.0; MODE_BLOCK];
        for ((x, _), kx) in rows() {
            for c in 0..MODE_BLOCK {
                w2[c] += (x[c] * factors[c]) * (kx[c] * factors[c]);
            }
        }
        let (mut r2, mut m2) = ([0.0; MODE_BLOCK], [0.0; MODE_BLOCK]);
        for ((_, mx), kx) in rows() {
            for c in 0..MODE_BLOCK {
                let (mv, kv) = (mx[c] * factors[c], kx[c] * factors[c]);
                r2[c] += (kv - w2[c] * mv).powi(2);
                m2[c] += mv * mv;
            }
        }
        for c in 0..width {
            phi.rb_mut()
                .col_mut(c)
                .iter_mut()
                .for_each(|v| *v *= factors[c]);
            omega2[c] = w2[c];
            residuals[c] = r2[c].sqrt() / (max_ratio * m2[c].sqrt().max(f64::MIN_POSITIVE));
        }
    }
}

/// y = A x for a block of [`MODE_BLOCK`] vectors interleaved by row.
fn apply(a: &SparseMatrix, x: &[f64], y: &mut [f64]) {
    y.fill(0.0);
    let sym = a.symbolic();
    for (j, xj) in x.chunks_exact(MODE_BLOCK).enumerate() {
        for (&i, &v) in sym.row_idx_of_col_raw(j).iter().zip(a.val_of_col(j)) {
            let yi = &mut y[i * MODE_BLOCK..(i + 1) * MODE_BLOCK];
            for (yc, xc) in yi.iter_mut().zip(xj) {
                *yc += v * xc;
            }
        }
    }
}
