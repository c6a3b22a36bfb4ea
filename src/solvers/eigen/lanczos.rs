//! Sparse shift-and-invert block Lanczos with full reorthogonalisation and
//! thick restarts.
//!
//! P (K − σM) Pᵀ = L Lᵀ (supernodal Cholesky, AMD ordering P, σ < 0). The
//! operator C = L⁻¹ P M Pᵀ L⁻ᵀ is symmetric in the Euclidean inner product,
//! so a plain block Lanczos on it needs neither M-inner products nor a factor
//! of M. Its eigenvalues are μ = 1/(ω² − σ), eigenvectors y = Lᵀ P φ.
//!
//! The basis V (orthonormal, two-pass block Gram–Schmidt) is kept and
//! T = Vᵀ C V is updated one block at a time. Ritz pairs (θ, V s) have
//! residual ‖R s_last‖, R the triangular factor of the orthogonalised newest
//! block, so convergence checks are cheap. When the basis is full it restarts
//! from the leading Ritz vectors (thick restart), keeping the Krylov relation.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::matmul::matmul;
use faer::perm::PermRef;
use faer::reborrow::{Reborrow, ReborrowMut};
use faer::sparse::linalg::cholesky::supernodal::SupernodalLltRef;
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, CholeskySymbolicParams, SymbolicCholesky, SymbolicCholeskyRaw,
    SymmetricOrdering,
};
use faer::sparse::linalg::SupernodalThreshold;
use faer::sparse::SymbolicSparseColMat;
use faer::{Accum, Conj, Mat, MatMut, MatRef, Par, Side};

use super::{EigenError, EigenTuning};
use crate::model::SparseMatrix;
use crate::solvers::dense::product;
use crate::solvers::nested_dissection;
use crate::solvers::sparse_ops::{par, par_iter, PairPattern, RowMatrix};

/// P(K − σM)Pᵀ = L Lᵀ with access to the separate triangular solves. The
/// symbolic analysis is done once; [`ShiftedCholesky::refactor`] changes σ.
pub struct ShiftedCholesky {
    pattern: PairPattern,
    symbolic: SymbolicCholesky<usize>,
    values: Vec<f64>,
    /// (P v)_i = v_{fwd[i]}.
    fwd: Vec<usize>,
    /// The shift σ (rad²/s²).
    pub shift: f64,
    /// P M Pᵀ by rows, built by the first [`ShiftedCholesky::apply`] (solves
    /// alone, as for FRFs, never need it).
    permuted_mass: std::sync::OnceLock<RowMatrix>,
    /// Stored entries of the M given to `new`, to catch another M in `apply`.
    mass_nonzeros: usize,
}

impl ShiftedCholesky {
    /// Factors K − σM, retrying with 100σ (up to five times) if it is not
    /// numerically positive definite.
    pub fn new(k: &SparseMatrix, m: &SparseMatrix, shift: f64) -> Result<Self, EigenError> {
        Self::with_ordering(k, m, shift, FillOrdering::Best)
    }

    /// As [`ShiftedCholesky::new`] with a chosen fill-reducing ordering.
    pub fn with_ordering(
        k: &SparseMatrix,
        m: &SparseMatrix,
        shift: f64,
        ordering: FillOrdering,
    ) -> Result<Self, EigenError> {
        let pattern =
            PairPattern::new(k, m).map_err(|detail| EigenError::InvalidInput { detail })?;
        let symbolic = fill_reducing_symbolic(pattern.symbolic(), ordering)?;
        let n = k.nrows();
        let fwd = match symbolic.perm() {
            Some(p) => p.arrays().0.to_vec(),
            None => (0..n).collect(),
        };
        let values = vec![0.0; symbolic.len_val()];
        let mut this = ShiftedCholesky {
            pattern,
            symbolic,
            values,
            fwd,
            shift,
            permuted_mass: std::sync::OnceLock::new(),
            mass_nonzeros: m.compute_nnz(),
        };
        let mut sigma = shift;
        for _ in 0..6 {
            if this.refactor(sigma) {
                return Ok(this);
            }
            sigma *= 100.0;
        }
        Err(EigenError::InvalidInput {
            detail: format!(
                "K − σM is not positive definite even for σ = {sigma:e}: K has negative eigenvalues"
            ),
        })
    }

    /// Factors K − σM for a new σ; false (and an unusable factor) if it is not
    /// numerically positive definite, i.e. σ is not below the lowest ω².
    pub fn refactor(&mut self, sigma: f64) -> bool {
        let par = par();
        let mut mem = MemBuffer::new(
            self.symbolic
                .factorize_numeric_llt_scratch::<f64>(par, Default::default()),
        );
        let a = self.pattern.combine(1.0, -sigma);
        let ok = self
            .symbolic
            .factorize_numeric_llt(
                &mut self.values,
                a.as_ref(),
                Side::Lower,
                Default::default(),
                par,
                MemStack::new(&mut mem),
                Default::default(),
            )
            .is_ok();
        self.shift = sigma;
        ok
    }

    /// Nonzeros stored in L.
    pub fn factor_nonzeros(&self) -> usize {
        self.values.len()
    }

    fn supernodal(&self) -> SupernodalLltRef<'_, usize, f64> {
        match self.symbolic.raw() {
            SymbolicCholeskyRaw::Supernodal(s) => SupernodalLltRef::new(s, &self.values),
            SymbolicCholeskyRaw::Simplicial(_) => unreachable!("supernodal factorisation forced"),
        }
    }

    fn solve_scratch(&self, ncols: usize) -> MemBuffer {
        match self.symbolic.raw() {
            SymbolicCholeskyRaw::Supernodal(s) => {
                MemBuffer::new(s.solve_in_place_scratch::<f64>(ncols, par_iter()))
            }
            SymbolicCholeskyRaw::Simplicial(_) => unreachable!("supernodal factorisation forced"),
        }
    }

    /// out = C y = L⁻¹ P M Pᵀ L⁻ᵀ y. `m` must be the M of [`ShiftedCholesky::new`];
    /// P M Pᵀ is kept by rows on first use.
    pub fn apply(&self, m: &SparseMatrix, y: MatRef<'_, f64>) -> Mat<f64> {
        let par = par_iter();
        let mut mem = self.solve_scratch(y.ncols());
        let l = self.supernodal();
        let mut z = y.to_owned();
        l.l_transpose_solve_with_conj(Conj::No, z.as_mut(), par, MemStack::new(&mut mem));
        debug_assert_eq!(m.compute_nnz(), self.mass_nonzeros, "not the M of new()");
        let mass = self
            .permuted_mass
            .get_or_init(|| RowMatrix::permuted(m, &self.fwd));
        let mut w = mass.mul(z.as_ref());
        l.l_solve_with_conj(Conj::No, w.as_mut(), par, MemStack::new(&mut mem));
        w
    }

    /// Φ = Pᵀ L⁻ᵀ Y Z, the Rayleigh–Ritz vectors of (K, M) on the span of
    /// L⁻ᵀ Y: with Y orthonormal, (L⁻ᵀY)ᵀ(K − σM)(L⁻ᵀY) = I, so the projected
    /// pencil reduces to the symmetric A = (L⁻ᵀY)ᵀ M (L⁻ᵀY) = Z diag(μ) Zᵀ
    /// (μ = 1/(ω² − σ)). A is formed from M itself, not from the Krylov
    /// recurrence, so the returned shapes are M-orthogonal to rounding even
    /// when the smallest wanted Ritz pairs were accepted at the recurrence's
    /// rounding floor (cross terms φ_iᵀMφ_j were 1e-7 on a 1,176-DOF lattice
    /// wanting 100 modes; ~1e-14 after); used only then, so converged runs
    /// keep their bits. `m` must be the M of [`Self::new`].
    pub fn rayleigh_ritz(
        &self,
        m: &SparseMatrix,
        y: MatRef<'_, f64>,
    ) -> Result<Mat<f64>, EigenError> {
        debug_assert_eq!(m.compute_nnz(), self.mass_nonzeros, "not the M of new()");
        let count = y.ncols();
        let z = self.l_transpose_solve(y);
        let mass = self
            .permuted_mass
            .get_or_init(|| RowMatrix::permuted(m, &self.fwd));
        let mz = mass.mul(z.as_ref());
        let mut a = Mat::<f64>::zeros(count, count);
        matmul(
            a.as_mut(),
            Accum::Replace,
            z.transpose(),
            mz.as_ref(),
            1.0,
            par(),
        );
        // largest_eigenpairs reads A's lower triangle.
        let (_, rotation, _) = super::dense::largest_eigenpairs(a, count, Par::Seq, 0)?;
        let mut rotated = Mat::<f64>::zeros(z.nrows(), count);
        matmul(
            rotated.as_mut(),
            Accum::Replace,
            z.as_ref(),
            rotation.as_ref(),
            1.0,
            par(),
        );
        Ok(self.unpermute(rotated.as_ref()))
    }

    /// φ = Pᵀ L⁻ᵀ y.
    pub fn back_transform(&self, y: MatRef<'_, f64>) -> Mat<f64> {
        self.unpermute(self.l_transpose_solve(y).as_ref())
    }

    /// L⁻ᵀ y, in the factor's (permuted) order.
    fn l_transpose_solve(&self, y: MatRef<'_, f64>) -> Mat<f64> {
        let mut mem = self.solve_scratch(y.ncols());
        let mut z = y.to_owned();
        self.supernodal().l_transpose_solve_with_conj(
            Conj::No,
            z.as_mut(),
            par_iter(),
            MemStack::new(&mut mem),
        );
        z
    }

    /// x = (K − σM)⁻¹ b.
    pub fn solve(&self, b: MatRef<'_, f64>) -> Mat<f64> {
        let mut mem = self.solve_scratch(b.ncols());
        let l = self.supernodal();
        let mut w = self.permute(b);
        l.l_solve_with_conj(Conj::No, w.as_mut(), par_iter(), MemStack::new(&mut mem));
        l.l_transpose_solve_with_conj(Conj::No, w.as_mut(), par_iter(), MemStack::new(&mut mem));
        self.unpermute(w.as_ref())
    }

    fn permute(&self, v: MatRef<'_, f64>) -> Mat<f64> {
        Mat::from_fn(v.nrows(), v.ncols(), |i, j| v[(self.fwd[i], j)])
    }

    fn unpermute(&self, z: MatRef<'_, f64>) -> Mat<f64> {
        let mut u = Mat::<f64>::zeros(z.nrows(), z.ncols());
        for j in 0..z.ncols() {
            for (i, &f) in self.fwd.iter().enumerate() {
                u[(f, j)] = z[(i, j)];
            }
        }
        u
    }
}

/// Below this many unknowns [`FillOrdering::Best`] is AMD alone.
const ND_MIN_DOFS: usize = 2_000;

/// Fill-reducing ordering of the sparse Cholesky factor.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FillOrdering {
    /// Whichever of the two below gives fewer factor entries (AMD alone
    /// below 2,000 unknowns).
    Best,
    Amd,
    NestedDissection,
}

/// Symbolic Cholesky of the pattern. With [`FillOrdering::Best`], the better
/// (fewer factor entries) of nested dissection ([`nested_dissection`]) and
/// AMD: nested dissection wins by far on 3-D lattices (cube 26³: 93 M against
/// 224 M entries), AMD can win on thin or irregular models. Both analyses are
/// cheap next to the numeric factorisation.
fn fill_reducing_symbolic(
    pattern: &SymbolicSparseColMat<usize>,
    ordering: FillOrdering,
) -> Result<SymbolicCholesky<usize>, EigenError> {
    let params = || CholeskySymbolicParams {
        supernodal_flop_ratio_threshold: SupernodalThreshold::FORCE_SUPERNODAL,
        ..Default::default()
    };
    let analyse = |ordering| {
        factorize_symbolic_cholesky(pattern.as_ref(), Side::Lower, ordering, params()).map_err(
            |e| EigenError::InvalidInput {
                detail: format!("symbolic Cholesky: {e:?}"),
            },
        )
    };
    let n = pattern.nrows();
    // Small models (the static residual of every diagnosis model solution
    // comes here): AMD alone; a second analysis costs more than it saves.
    if ordering == FillOrdering::Amd || (ordering == FillOrdering::Best && n < ND_MIN_DOFS) {
        return analyse(SymmetricOrdering::Amd);
    }
    let fwd = nested_dissection::order(n, pattern.col_ptr(), pattern.row_idx());
    let mut inv = vec![0usize; n];
    for (i, &f) in fwd.iter().enumerate() {
        inv[f] = i;
    }
    let nd = analyse(SymmetricOrdering::Custom(PermRef::new_checked(
        &fwd, &inv, n,
    )))?;
    if ordering == FillOrdering::NestedDissection {
        return Ok(nd);
    }
    let amd = analyse(SymmetricOrdering::Amd)?;
    if std::env::var_os("FRFUP_EIGEN_TRACE").is_some() {
        eprintln!(
            "[sparse] nnz(L): nested dissection {}, AMD {}",
            nd.len_val(),
            amd.len_val()
        );
    }
    Ok(if nd.len_val() <= amd.len_val() {
        nd
    } else {
        amd
    })
}

/// Result of [`shift_invert`].
pub struct SparseOutcome {
    /// The lowest modes' shapes (unnormalised), n × count.
    pub vectors: Mat<f64>,
    pub shift: f64,
    pub operator_applications: usize,
    pub restarts: usize,
    pub factor_nonzeros: usize,
}

/// The `count` lowest modes of (K, M) by shift-invert block Lanczos.
pub fn shift_invert(
    k: &SparseMatrix,
    m: &SparseMatrix,
    count: usize,
    shift: f64,
    tuning: &EigenTuning,
) -> Result<SparseOutcome, EigenError> {
    let trace = std::env::var_os("FRFUP_EIGEN_TRACE").is_some();
    let t0 = std::time::Instant::now();
    let mut chol = ShiftedCholesky::new(k, m, shift)?;
    if trace {
        eprintln!(
            "[sparse] factor: {:.3} s, nnz(L) = {}",
            t0.elapsed().as_secs_f64(),
            chol.factor_nonzeros()
        );
    }
    if tuning.auto_shift {
        move_shift_up(&mut chol, m, tuning);
        if trace {
            eprintln!(
                "[sparse] shift {:e} after {:.3} s",
                chol.shift,
                t0.elapsed().as_secs_f64()
            );
        }
    }
    let op_time = std::cell::Cell::new(0.0);
    let op = |y: MatRef<'_, f64>| {
        let t = std::time::Instant::now();
        let r = chol.apply(m, y);
        op_time.set(op_time.get() + t.elapsed().as_secs_f64());
        r
    };
    let out = block_lanczos(&op, k.nrows(), count, tuning)?;
    if trace {
        eprintln!(
            "[sparse] lanczos: {:.3} s total, {:.3} s in the operator ({} applications, {} restarts{})",
            t0.elapsed().as_secs_f64(),
            op_time.get(),
            out.applications,
            out.restarts,
            if out.at_floor {
                ", some pairs at the rounding floor"
            } else {
                ""
            }
        );
    }
    Ok(SparseOutcome {
        // Pairs accepted at the floor: Rayleigh–Ritz on M restores M-orthogonality.
        vectors: if out.at_floor {
            chol.rayleigh_ritz(m, out.vectors.as_ref())?
        } else {
            chol.back_transform(out.vectors.as_ref())
        },
        shift: chol.shift,
        operator_applications: out.applications,
        restarts: out.restarts,
        factor_nonzeros: chol.factor_nonzeros(),
    })
}

/// Fractions of the estimated distance from σ₀ to the lowest ω² tried, in
/// order, as the new shift. The estimate is an upper bound, a few per cent
/// high on clustered spectra (2.4 % on the 101,400-DOF plate lattice), so
/// 0.97 usually factors; each failure costs a factorisation. Convergence is
/// steep in this fraction: on the plate 0.9 needs 264 operator applications
/// for 50 modes, 0.97 needs 216.
const SHIFT_FRACTIONS: [f64; 4] = [0.97, 0.85, 0.5, 0.25];

/// Moves σ up to just below the lowest ω² when the spectrum starts far above
/// the initial σ₀ (fixed structures): the relative gaps (ω²_{i+1} − ω²_i)/(ω²_i − σ)
/// that govern Krylov convergence grow by up to (ω²₁ − σ₀)/(ω²₁ − σ).
///
/// A short Lanczos run estimates ω²₁ ≈ σ₀ + 1/θ₁ (θ₁ ≤ μ₁, so this is an upper
/// bound); σ = σ₀ + f (ω²₁ − σ₀) for f in [`SHIFT_FRACTIONS`]. By Sylvester's law of inertia K − σM is
/// positive definite iff σ < ω²₁, so a failed Cholesky means σ was too high:
/// try the next fraction, and after the last return to σ₀.
fn move_shift_up(chol: &mut ShiftedCholesky, m: &SparseMatrix, tuning: &EigenTuning) {
    let sigma0 = chol.shift;
    let n = chol.fwd.len();
    // About five blocks: the estimate only has to be within a few per cent.
    let probe = EigenTuning {
        tolerance: 1e-2,
        max_basis: 4 * tuning.block_size.max(1),
        max_restarts: 1,
        ..tuning.clone()
    };
    let op = |y: MatRef<'_, f64>| chol.apply(m, y);
    let Ok(est) = block_lanczos_impl(&op, n, 1, &probe, true) else {
        return;
    };
    let theta = est.values[0];
    if !(theta > 0.0 && theta.is_finite()) {
        return;
    }
    let gap = 1.0 / theta;
    if gap < 100.0 * sigma0.abs() {
        return; // Zero-energy modes or a spectrum starting near σ₀: keep σ₀.
    }
    for fraction in SHIFT_FRACTIONS {
        if chol.refactor(sigma0 + fraction * gap) {
            return;
        }
    }
    // σ₀ factored before, so it does again.
    let _ = chol.refactor(sigma0);
}

/// Largest eigenpairs of a symmetric operator.
pub struct LanczosOutcome {
    /// Eigenvalues, descending.
    pub values: Vec<f64>,
    /// Orthonormal eigenvectors, n × count.
    pub vectors: Mat<f64>,
    pub applications: usize,
    pub restarts: usize,
    /// Some pairs were accepted at the rounding floor, not at the tolerance.
    pub at_floor: bool,
}

/// Deterministic pseudo-random numbers in (−1, 1) (xorshift64*).
pub struct Xorshift(pub u64);

impl Xorshift {
    /// The next number of the sequence.
    pub fn uniform(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        let r = self.0.wrapping_mul(0x2545_F491_4F6C_DD1D);
        (r >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    }
}

/// Below this ratio of a Cholesky-QR pivot to its column's norm the block is
/// too ill-conditioned for Cholesky QR (κ² ε would not be small after two
/// passes); modified Gram–Schmidt with breakdown handling takes over.
const CHOLESKY_QR_MIN_PIVOT: f64 = 1e-4;

/// Cholesky QR, twice ("CholQR2"): G = zᵀz = RᵀR, z ← z R⁻¹, repeated once
/// for orthogonality to working precision. Two passes over z with matrix
/// products instead of b² vector operations. Returns R (z_in = z_out R), or
/// `None`, with z unchanged, when a pivot is below [`CHOLESKY_QR_MIN_PIVOT`]
/// of its column's norm (near-dependent or vanishing columns).
pub fn cholesky_qr2(mut z: MatMut<'_, f64>, par: Par) -> Option<Mat<f64>> {
    let b = z.ncols();
    let original = z.rb().to_owned();
    let mut r_total = Mat::<f64>::identity(b, b);
    for _ in 0..2 {
        let mut g = Mat::<f64>::zeros(b, b);
        matmul(
            g.as_mut(),
            Accum::Replace,
            z.rb().transpose(),
            z.rb(),
            1.0,
            par,
        );
        // Upper-triangular R with RᵀR = G.
        let mut r = Mat::<f64>::zeros(b, b);
        for j in 0..b {
            let mut d = g[(j, j)];
            for k in 0..j {
                d -= r[(k, j)] * r[(k, j)];
            }
            let norm = g[(j, j)].sqrt();
            if !(d > 0.0 && d.sqrt() > CHOLESKY_QR_MIN_PIVOT * norm) {
                z.copy_from(&original);
                return None;
            }
            r[(j, j)] = d.sqrt();
            for i in j + 1..b {
                let mut e = g[(j, i)];
                for k in 0..j {
                    e -= r[(k, j)] * r[(k, i)];
                }
                r[(j, i)] = e / r[(j, j)];
            }
        }
        // R⁻¹ (upper triangular), column by column.
        let mut r_inv = Mat::<f64>::zeros(b, b);
        for j in 0..b {
            r_inv[(j, j)] = 1.0 / r[(j, j)];
            for i in (0..j).rev() {
                let mut acc = 0.0;
                for k in i + 1..=j {
                    acc += r[(i, k)] * r_inv[(k, j)];
                }
                r_inv[(i, j)] = -acc / r[(i, i)];
            }
        }
        let mut q = Mat::<f64>::zeros(z.nrows(), b);
        matmul(q.as_mut(), Accum::Replace, z.rb(), r_inv.as_ref(), 1.0, par);
        z.copy_from(&q);
        r_total = product(r.as_ref(), r_total.as_ref());
    }
    Some(r_total)
}

/// Orthonormalises the columns of `z` against `v` (two passes) and among
/// themselves (Cholesky QR twice, or modified Gram–Schmidt twice when the
/// block is near rank-deficient). Columns that vanish are replaced
/// by pseudo-random vectors. Returns R with z_in ⊥ v = z_out R.
pub fn orthonormalise(
    v: MatRef<'_, f64>,
    mut z: MatMut<'_, f64>,
    passes: usize,
    rng: &mut Xorshift,
) -> Mat<f64> {
    let par = par_iter();
    let b = z.ncols();
    let n = z.nrows();
    let mut r = Mat::<f64>::zeros(b, b);
    let project = |mut z: MatMut<'_, f64>, passes: usize, par: Par| {
        if v.ncols() == 0 {
            return;
        }
        for _ in 0..passes {
            let mut h = Mat::<f64>::zeros(v.ncols(), z.ncols());
            matmul(h.as_mut(), Accum::Replace, v.transpose(), z.rb(), 1.0, par);
            matmul(z.rb_mut(), Accum::Add, v, h.as_ref(), -1.0, par);
        }
    };
    project(z.rb_mut(), passes, par);
    if let Some(r) = cholesky_qr2(z.rb_mut(), par) {
        return r;
    }
    for j in 0..b {
        let before = z.rb().col(j).norm_l2();
        for _ in 0..2 {
            for i in 0..j {
                let d: f64 = z
                    .rb()
                    .col(i)
                    .iter()
                    .zip(z.rb().col(j).iter())
                    .map(|(a, b)| a * b)
                    .sum();
                r[(i, j)] += d;
                let (zi, zj) = z.rb_mut().two_cols_mut(i, j);
                zj.iter_mut().zip(zi.iter()).for_each(|(y, x)| *y -= d * x);
            }
        }
        let mut norm = z.rb().col(j).norm_l2();
        // NaN-safe: a NaN norm also counts as breakdown.
        let healthy = norm > 1e-10 * before && norm > 0.0;
        if !healthy {
            // Breakdown: the new direction is (numerically) in span(V, z_<j).
            r[(j, j)] = 0.0;
            for _ in 0..3 {
                let mut fresh = Mat::from_fn(n, 1, |_, _| rng.uniform());
                project(fresh.as_mut(), 2, par);
                for i in 0..j {
                    let d: f64 = z
                        .rb()
                        .col(i)
                        .iter()
                        .zip(fresh.col(0).iter())
                        .map(|(a, b)| a * b)
                        .sum();
                    fresh
                        .col_mut(0)
                        .iter_mut()
                        .zip(z.rb().col(i).iter())
                        .for_each(|(y, x)| *y -= d * x);
                }
                norm = fresh.col(0).norm_l2();
                z.rb_mut().col_mut(j).copy_from(fresh.col(0));
                if norm > 1e-3 {
                    break;
                }
            }
        } else {
            r[(j, j)] = norm;
        }
        let inv = 1.0 / norm;
        z.rb_mut().col_mut(j).iter_mut().for_each(|x| *x *= inv);
    }
    r
}

/// The `wanted` largest eigenpairs of the small projected matrix T, descending.
///
/// Only the wanted ones: bisection and inverse iteration on T's tridiagonal
/// form when they are at most half of T's order (see
/// [`super::dense::largest_eigenpairs`]); a full decomposition otherwise. On
/// a few-hundred-DOF model the projected problems were half of the time.
fn small_evd(t: MatRef<'_, f64>, wanted: usize) -> Result<(Vec<f64>, Mat<f64>), EigenError> {
    let wanted = wanted.min(t.nrows());
    super::dense::largest_eigenpairs(t.to_owned(), wanted, Par::Seq, PROJECTED_SUBSET_BELOW)
        .map(|(values, vectors, _)| (values, vectors))
}

/// The Ritz residual at which a pair that has stopped improving counts as
/// converged whatever the tolerance, in ulps of θ₁ (the largest Ritz value,
/// ≈ ‖C‖): ~4.5× the stall seen on a 5,400-DOF lattice wanting 300 modes.
const RESIDUAL_FLOOR_ULPS: f64 = 2e4;

/// A residual that fell by less than this factor between two checks has
/// stopped improving.
const STALL_RATIO: f64 = 0.5;

/// Flops of the projected eigenproblem per cols³ (tridiagonalisation and a
/// subset of the pairs), which Gram–Schmidt work must reach between checks.
const EVD_FLOPS_PER_CUBE: f64 = 9.0;

/// The subset path for the projected problem when at most 1/this of its
/// eigenpairs are wanted.
const PROJECTED_SUBSET_BELOW: usize = 2;

/// Block Lanczos (full reorthogonalisation, thick restart) for the `count`
/// largest eigenpairs of the symmetric positive semi-definite operator `op`
/// of dimension n.
pub fn block_lanczos(
    op: &dyn Fn(MatRef<'_, f64>) -> Mat<f64>,
    n: usize,
    count: usize,
    tuning: &EigenTuning,
) -> Result<LanczosOutcome, EigenError> {
    block_lanczos_impl(op, n, count, tuning, false)
}

/// With `best_effort`, running out of restarts returns the current Ritz pairs.
///
/// Each pass: apply C to the pending block and append it to the basis
/// ([`Krylov::extend`]); orthogonalise the result into the next block
/// ([`Krylov::next_block`]); when due ([`Plan::check_due`]), compute the Ritz
/// pairs and stop once `count` have converged ([`Krylov::converged`]); when
/// the basis is full, restart from the leading Ritz vectors
/// ([`Krylov::thick_restart`]).
fn block_lanczos_impl(
    op: &dyn Fn(MatRef<'_, f64>) -> Mat<f64>,
    n: usize,
    count: usize,
    tuning: &EigenTuning,
    best_effort: bool,
) -> Result<LanczosOutcome, EigenError> {
    let plan = Plan::new(n, count, tuning);
    let count = plan.count;
    let mut k = Krylov::start(n, &plan);
    loop {
        let (wq, h) = k.extend(op);
        let bq = h.ncols();
        if k.cols == n {
            let (theta, s) = small_evd(k.projected(), count)?;
            return Ok(k.ritz(&theta, s.as_ref(), count));
        }
        let next = k.next_block(wq, &h, plan.block);
        let restart = k.cols + next.z.ncols() > plan.max_basis;
        if !(restart || plan.check_due(&k, next.exact_relation)) {
            k.q = next.z;
            continue;
        }
        k.work = 0.0;
        // The check needs `count` Ritz pairs; a restart more (below).
        let (theta, s) = small_evd(k.projected(), count)?;
        let check = k.converged(&theta, s.as_ref(), next.r.as_ref(), bq, tuning.tolerance);
        if next.exact_relation && check.converged == count && k.cols >= count {
            let mut out = k.ritz(&theta, s.as_ref(), count);
            out.at_floor = check.at_floor > 0;
            return Ok(out);
        }
        k.q = next.z;
        if k.cols + k.q.ncols() > plan.max_basis {
            k.restarts += 1;
            if k.restarts > tuning.max_restarts {
                if best_effort {
                    return Ok(k.ritz(&theta, s.as_ref(), count));
                }
                return Err(EigenError::NoConvergence {
                    detail: format!(
                        "{} of {count} modes converged after {} restarts ({} operator applications)",
                        check.converged, k.restarts, k.applications
                    ),
                });
            }
            k.thick_restart(theta, s, plan.keep_target)?;
        }
    }
}

/// The sizes of a block Lanczos run.
struct Plan {
    /// Wanted pairs (at most n).
    count: usize,
    /// Block size b.
    block: usize,
    /// Largest basis: `tuning.max_basis`, or about 2·count + 4·b.
    max_basis: usize,
    /// Ritz vectors kept at a thick restart.
    keep_target: usize,
    /// Basis size of the first convergence check of the first cycle.
    first_check: usize,
}

impl Plan {
    fn new(n: usize, count: usize, tuning: &EigenTuning) -> Self {
        let count = count.min(n);
        let block = tuning.block_size.clamp(1, n.max(1));
        let max_basis = if tuning.max_basis > 0 {
            tuning.max_basis
        } else {
            (2 * count + 4 * block).max(40)
        }
        .max(count + 2 * block)
        .min(n);
        let keep_target = (count + (max_basis - count) / 2)
            .min(max_basis.saturating_sub(block))
            .max(count);
        // Krylov convergence of `count` pairs takes a basis of about three times
        // `count` (216 vectors for 50 modes on the plate lattice, 136 for 39 on
        // GARTEUR): no check before twice `count` in the first cycle (after a
        // restart the kept Ritz vectors already are most of the way).
        let first_check = (2 * count).min(max_basis.saturating_sub(block)).max(count);
        Plan {
            count,
            block,
            max_basis,
            keep_target,
            first_check,
        }
    }

    /// Whether to compute the Ritz pairs now (a restart always needs them).
    /// They come from a dense EVD of T (about 9 cols³ flops). On small
    /// operators that costs more than a block step (about 6 n·cols·b flops
    /// of Gram–Schmidt), so convergence is checked only once the steps since
    /// the last check have done as much work.
    fn check_due(&self, k: &Krylov, exact_relation: bool) -> bool {
        let evd_cost = EVD_FLOPS_PER_CUBE * (k.cols as f64).powi(3);
        let check_from = if k.restarts == 0 {
            self.first_check
        } else {
            self.count
        };
        exact_relation && k.cols >= check_from && k.work >= evd_cost
    }
}

/// The state of a block Lanczos run: the basis V (n × max_basis, `cols` in
/// use), T = Vᵀ C V, and the pending block q.
struct Krylov {
    n: usize,
    v: Mat<f64>,
    t: Mat<f64>,
    cols: usize,
    q: Mat<f64>,
    applications: usize,
    restarts: usize,
    /// Flops of Gram–Schmidt since the last convergence check.
    work: f64,
    /// Ritz residuals at the previous convergence check, by pair.
    previous_residuals: Vec<f64>,
    rng: Xorshift,
}

/// The block after the newest: z orthonormal to the basis, with z_in = z R.
struct NextBlock {
    z: Mat<f64>,
    r: Mat<f64>,
    /// z is a whole block (not shrunk near the full dimension), so the
    /// residual estimates of [`Krylov::converged`] hold.
    exact_relation: bool,
}

/// Outcome of a convergence check.
struct Convergence {
    converged: usize,
    /// Of which accepted at the rounding floor.
    at_floor: usize,
}

impl Krylov {
    /// An empty basis and a pseudo-random first block.
    fn start(n: usize, plan: &Plan) -> Self {
        let mut rng = Xorshift(0x9E37_79B9_7F4A_7C15);
        let v = Mat::<f64>::zeros(n, plan.max_basis);
        let t = Mat::<f64>::zeros(plan.max_basis, plan.max_basis);
        let mut q = Mat::from_fn(n, plan.block.min(n), |_, _| rng.uniform());
        orthonormalise(v.get(.., ..0), q.as_mut(), 0, &mut rng);
        Krylov {
            n,
            v,
            t,
            cols: 0,
            q,
            applications: 0,
            restarts: 0,
            work: 0.0,
            previous_residuals: Vec::new(),
            rng,
        }
    }

    /// T restricted to the basis in use.
    fn projected(&self) -> MatRef<'_, f64> {
        self.t.get(..self.cols, ..self.cols)
    }

    /// Applies the operator to the pending block q and appends q to the
    /// basis, with its column of T (h = Vᵀ C q, new diagonal block
    /// symmetrised). Returns C q and h.
    fn extend(&mut self, op: &dyn Fn(MatRef<'_, f64>) -> Mat<f64>) -> (Mat<f64>, Mat<f64>) {
        let (cols, bq) = (self.cols, self.q.ncols());
        let wq = op(self.q.as_ref());
        self.applications += bq;
        self.v.get_mut(.., cols..cols + bq).copy_from(&self.q);
        let mut h = Mat::<f64>::zeros(cols + bq, bq);
        matmul(
            h.as_mut(),
            Accum::Replace,
            self.v.get(.., ..cols + bq).transpose(),
            wq.as_ref(),
            1.0,
            par_iter(),
        );
        let t = &mut self.t;
        for i in 0..cols + bq {
            for j in 0..bq {
                t[(i, cols + j)] = h[(i, j)];
                t[(cols + j, i)] = h[(i, j)];
            }
        }
        // Symmetrise the new diagonal block.
        for i in 0..bq {
            for j in 0..i {
                let a = 0.5 * (t[(cols + i, cols + j)] + t[(cols + j, cols + i)]);
                t[(cols + i, cols + j)] = a;
                t[(cols + j, cols + i)] = a;
            }
        }
        self.cols += bq;
        self.work += 6.0 * (self.n * self.cols * bq) as f64;
        (wq, h)
    }

    /// The next block: C q orthogonalised against the basis (classical
    /// Gram–Schmidt twice, the first pass reusing h = Vᵀ C q). Near the full
    /// dimension the block shrinks; the residual estimate then no longer
    /// holds and the basis simply grows to n (exact).
    fn next_block(&mut self, mut wq: Mat<f64>, h: &Mat<f64>, block: usize) -> NextBlock {
        let bq = h.ncols();
        let next_b = block.min(self.n - self.cols);
        let exact_relation = next_b == bq;
        matmul(
            wq.as_mut(),
            Accum::Add,
            self.v.get(.., ..self.cols),
            h.as_ref(),
            -1.0,
            par_iter(),
        );
        let mut z = if exact_relation {
            wq
        } else {
            wq.get(.., ..next_b.min(bq)).to_owned()
        };
        let r = orthonormalise(self.v.get(.., ..self.cols), z.as_mut(), 1, &mut self.rng);
        NextBlock {
            z,
            r,
            exact_relation,
        }
    }

    /// How many of the Ritz pairs (θ, s) have converged.
    ///
    /// Residual of Ritz pair i: ‖R s_i[last block]‖, against tol·θ_i. The
    /// Krylov relation itself only holds to ~ε‖C‖ = ε θ₁ times a growth
    /// factor: when θ₁/θ_count is large (300 modes of a 5,400-DOF lattice,
    /// shift just below ω²₁: 1.4e3) the smallest wanted pairs stall at
    /// ~1e-12·θ₁ (~5e3 ε), above tol·θ_i, and a pair that met tol at one
    /// check missed it at the next (150 restarts). A pair whose residual
    /// is below the floor and fell by less than half since the previous
    /// check has stalled there and counts as converged.
    fn converged(
        &mut self,
        theta: &[f64],
        s: MatRef<'_, f64>,
        r: MatRef<'_, f64>,
        bq: usize,
        tolerance: f64,
    ) -> Convergence {
        let cols = self.cols;
        let floor = RESIDUAL_FLOOR_ULPS * f64::EPSILON * theta.first().map_or(0.0, |t| t.abs());
        let residuals: Vec<f64> = (0..theta.len().min(cols))
            .map(|i| {
                let mut res2 = 0.0;
                for row in 0..r.nrows() {
                    let mut acc = 0.0;
                    for c in 0..bq {
                        acc += r[(row, c)] * s[(cols - bq + c, i)];
                    }
                    res2 += acc * acc;
                }
                res2.sqrt()
            })
            .collect();
        let mut check = Convergence {
            converged: 0,
            at_floor: 0,
        };
        for (i, &res) in residuals.iter().enumerate() {
            if res <= tolerance * theta[i].abs() {
                check.converged += 1;
            } else if res <= floor
                && self
                    .previous_residuals
                    .get(i)
                    .is_some_and(|&before| res > STALL_RATIO * before)
            {
                check.converged += 1;
                check.at_floor += 1;
            }
        }
        self.previous_residuals = residuals;
        check
    }

    /// Thick restart from the leading Ritz vectors: the basis becomes the
    /// `keep_target` (at most cols) leading Ritz vectors and T their Ritz
    /// values. The pending block is orthogonal to the old basis, hence to
    /// the new one; its coupling to the kept vectors, Vᵀ C q, is computed
    /// when it is applied.
    fn thick_restart(
        &mut self,
        mut theta: Vec<f64>,
        mut s: Mat<f64>,
        keep_target: usize,
    ) -> Result<(), EigenError> {
        let cols = self.cols;
        let keep = keep_target.min(cols);
        if keep > theta.len() {
            (theta, s) = small_evd(self.projected(), keep)?;
        }
        let sk = s.get(.., ..keep);
        let mut nv = Mat::<f64>::zeros(self.n, keep);
        matmul(
            nv.as_mut(),
            Accum::Replace,
            self.v.get(.., ..cols),
            sk,
            1.0,
            par_iter(),
        );
        self.v.get_mut(.., ..keep).copy_from(&nv);
        drop(nv);
        self.t.fill(0.0);
        for (i, &value) in theta.iter().enumerate().take(keep) {
            self.t[(i, i)] = value;
        }
        self.cols = keep;
        Ok(())
    }

    /// The `count` Ritz pairs (θ, V s) of the basis in use.
    fn ritz(&self, theta: &[f64], s: MatRef<'_, f64>, count: usize) -> LanczosOutcome {
        ritz(
            self.v.get(.., ..self.cols),
            theta,
            s,
            count,
            self.applications,
            self.restarts,
        )
    }
}

fn ritz(
    v: MatRef<'_, f64>,
    theta: &[f64],
    s: MatRef<'_, f64>,
    count: usize,
    applications: usize,
    restarts: usize,
) -> LanczosOutcome {
    let mut y = Mat::<f64>::zeros(v.nrows(), count);
    matmul(
        y.as_mut(),
        Accum::Replace,
        v,
        s.get(.., ..count),
        1.0,
        par_iter(),
    );
    LanczosOutcome {
        values: theta[..count].to_vec(),
        vectors: y,
        applications,
        restarts,
        at_floor: false,
    }
}
