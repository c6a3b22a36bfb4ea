//! Dense shift-and-invert reduction for small models.
//!
//! K − σM = L Lᵀ (σ < 0), C = L⁻¹ M L⁻ᵀ (symmetric, n × n, dense),
//! C = Y diag(μ) Yᵀ with μ = 1/(ω² − σ): the `count` largest μ give the
//! lowest modes φ = L⁻ᵀ y (φᵀ(K − σM)φ = 1, not yet mass-normalised).
//!
//! Cholesky puts no entry outside the lower envelope of K − σM (row i of L is
//! zero left of the first nonzero of row i), and FE matrices in a sensible
//! node order have a narrow envelope (width w ≈ 110 for an 18 × 18 plate
//! lattice, n = 1944). The three triangular steps therefore work on blocks of
//! [`BLOCK`] rows and skip the zeros outside the envelope:
//!
//! - factorisation, block row R at a time (row-oriented Cholesky):
//!   L[R, F] = A[R, F] L[F, F]⁻ᵀ, L[R, R] = chol(A[R, R] − L[R, F] L[R, F]ᵀ),
//!   where A = K − σM and F are the envelope columns left of R;
//! - reduction, block row R at a time: with W = L⁻¹ M,
//!   C[R, :] = L[R, R]⁻¹ (Wᵀ[R, :] − L[R, F] C[F, :]). Only the columns up to
//!   R are formed (the lower triangle, which is all the eigensolver reads) and
//!   mirrored into the upper triangle, where later block rows read C[F, :].
//!   Wᵀ[R, :] up to R is (L⁻¹ M[:, R])ᵀ restricted to rows from the first
//!   nonzero row of M[:, R]: a triangular solve of envelope size.
//! - back-substitution φ = L⁻ᵀ y from the last block row up:
//!   φ_R = L[R, R]⁻ᵀ (y_R − L[B, R]ᵀ φ_B), B the rows below R whose envelope
//!   reaches R.
//!
//! These cost O(w n²) flops instead of the O(n³) of full triangular solves
//! (and degrade to that for a wide envelope). What remains O(n³) is the
//! symmetric eigendecomposition of C: Householder tridiagonalisation
//! C = Q T Qᵀ (in place), then T's wanted eigenvectors z (divide and conquer
//! for all of them, or [`tridiagonal`] bisection and inverse iteration when at
//! most a quarter are wanted), and y = Q z for the wanted columns only.

use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::linalg::cholesky::llt::factor::cholesky_in_place_scratch;
use faer::linalg::evd::tridiag::{tridiag_in_place, tridiag_in_place_scratch};
use faer::linalg::evd::{
    self_adjoint_evd_scratch, tridiagonal_self_adjoint_evd, ComputeEigenvectors,
};
use faer::linalg::householder::{
    apply_block_householder_sequence_on_the_left_in_place_scratch,
    apply_block_householder_sequence_on_the_left_in_place_with_conj,
};
use faer::linalg::matmul::matmul;
use faer::linalg::matmul::triangular::{self, BlockStructure};
use faer::linalg::qr::no_pivoting::factor::recommended_block_size;
use faer::linalg::triangular_solve::{
    solve_lower_triangular_in_place, solve_upper_triangular_in_place,
};
use faer::reborrow::{Reborrow, ReborrowMut};
use faer::sparse::Triplet;
use faer::{Accum, Col, Conj, Mat, MatMut, MatRef, Par};

use super::{tridiagonal, EigenError};
use crate::model::SparseMatrix;
use crate::solvers::bandwidth;
use crate::solvers::dense::cholesky_lower_in_place;
use crate::solvers::sparse_ops::{par, PairPattern};

/// Rows per block of the envelope steps: enough for efficient matrix
/// products, small next to the envelope width of lattice models.
const BLOCK: usize = 64;

/// Models smaller than this are solved on one thread: for the 336-DOF GARTEUR
/// model, waking the pool's threads for each block cost more than it saved.
const SEQUENTIAL_BELOW: usize = 600;

/// Tries σ, 100σ, 10⁴σ, … until K − σM is numerically positive definite.
/// Returns the `count` lowest (unnormalised) mode shapes, lowest first, and
/// the σ used; with `cover` = Some, the modes with ω² ≤ ω²_top and the one
/// above them (counted on T as the μ = 1/(ω² − σ) ≥ 1/(ω²_top − σ)), at most
/// `count` of them unless [`Cover::grow`].
///
/// When a reverse Cuthill–McKee renumbering of the unknowns shrinks the
/// envelope of K and M below [`RENUMBER_BELOW`] of the deck's own, the pencil
/// is solved renumbered and the shapes are put back in the deck's order.
pub fn shift_invert(
    k: &SparseMatrix,
    m: &SparseMatrix,
    count: usize,
    cover: Option<Cover>,
    shift: f64,
) -> Result<(Mat<f64>, f64), EigenError> {
    let Some(order) = narrower_order(k, m) else {
        return shift_invert_in_order(k, m, count, cover, shift);
    };
    let (y, sigma) = shift_invert_in_order(
        &renumbered(k, &order)?,
        &renumbered(m, &order)?,
        count,
        cover,
        shift,
    )?;
    // Row p of y is unknown order[p].
    let mut phi = Mat::zeros(y.nrows(), y.ncols());
    for j in 0..y.ncols() {
        for (p, &i) in order.iter().enumerate() {
            phi[(i, j)] = y[(p, j)];
        }
    }
    Ok((phi, sigma))
}

/// Renumber when the reverse Cuthill–McKee envelope is smaller than this
/// fraction of the deck's: a well numbered deck keeps its order.
const RENUMBER_BELOW: f64 = 0.8;

/// The reverse Cuthill–McKee order of the pencil's unknowns, if it narrows
/// the envelope enough to be worth a renumbered copy of K and M.
fn narrower_order(k: &SparseMatrix, m: &SparseMatrix) -> Option<Vec<usize>> {
    let n = k.nrows();
    // An unusable pair keeps its order; the factorisation reports why.
    let union = PairPattern::new(k, m).ok()?;
    let (col_ptr, row_idx) = (union.symbolic().col_ptr(), union.symbolic().row_idx());
    let identity: Vec<usize> = (0..n).collect();
    let order = bandwidth::reverse_cuthill_mckee(n, col_ptr, row_idx);
    let (before, after) = (
        bandwidth::profile(col_ptr, row_idx, &identity),
        bandwidth::profile(col_ptr, row_idx, &order),
    );
    ((after as f64) < RENUMBER_BELOW * before as f64).then_some(order)
}

/// P A Pᵀ: entry (p, q) is A[order[p], order[q]].
fn renumbered(a: &SparseMatrix, order: &[usize]) -> Result<SparseMatrix, EigenError> {
    let n = a.nrows();
    let mut position = vec![0; n];
    for (p, &i) in order.iter().enumerate() {
        position[i] = p;
    }
    let mut triplets = Vec::with_capacity(a.val().len());
    for j in 0..n {
        let rows = a.symbolic().row_idx_of_col_raw(j);
        for (&i, &v) in rows.iter().zip(a.val_of_col(j)) {
            triplets.push(Triplet::new(position[i], position[j], v));
        }
    }
    SparseMatrix::try_new_from_triplets(n, n, &triplets).map_err(|e| EigenError::InvalidInput {
        detail: format!("renumbering the unknowns: {e:?}"),
    })
}

/// [`shift_invert`] in the given numbering.
fn shift_invert_in_order(
    k: &SparseMatrix,
    m: &SparseMatrix,
    count: usize,
    cover: Option<Cover>,
    shift: f64,
) -> Result<(Mat<f64>, f64), EigenError> {
    let trace = std::env::var_os("FRFUP_EIGEN_TRACE").is_some();
    let t0 = std::time::Instant::now();
    let lap = |what: &str| {
        if trace {
            eprintln!("[dense] {what}: {:.3} s", t0.elapsed().as_secs_f64());
        }
    };
    let envelope = Envelope::of(k, m);
    let par = if k.nrows() < SEQUENTIAL_BELOW {
        Par::Seq
    } else {
        par()
    };
    let mut sigma = shift;
    let mut factor = None;
    for _ in 0..6 {
        factor = envelope_cholesky(k, m, sigma, &envelope, par);
        if factor.is_some() {
            break;
        }
        sigma *= 100.0;
    }
    let Some(l) = factor else {
        return Err(EigenError::InvalidInput {
            detail: format!(
                "K − σM is not positive definite even for σ = {sigma:e}: K has negative eigenvalues"
            ),
        });
    };
    lap("cholesky");
    let c = reduce(l.as_ref(), m, &envelope, par);
    lap("reduction");
    // ω² ≤ ω²_top ⟺ μ = 1/(ω² − σ) ≥ 1/(ω²_top − σ) (σ < 0 < ω²_top).
    let floor = cover
        .filter(|cv| cv.omega2 > sigma && cv.omega2.is_finite())
        .map(|cv| 1.0 / (cv.omega2 - sigma));
    let grow = cover.is_some_and(|cv| cv.grow);
    let (_, mut y, _) = largest_eigenpairs_covering(c, count, floor, grow, par, SUBSET_BELOW)?;
    lap("evd");
    back_substitute(l.as_ref(), &envelope, y.as_mut(), par);
    lap("back-substitution");
    Ok((y, sigma))
}

/// Lower envelope of K − σM (any σ) and of M, per block of [`BLOCK`] rows.
pub struct Envelope {
    pub n: usize,
    /// First column of the envelope of block row I (the least first nonzero
    /// column of its rows in K or M).
    pub first_col: Vec<usize>,
    /// First nonzero row of M's block column I (by symmetry, the least first
    /// nonzero column of M's rows in block I).
    pub mass_first_row: Vec<usize>,
    /// One past the last row whose envelope reaches block column I.
    pub end_row: Vec<usize>,
}

impl Envelope {
    /// The envelope of the pencil (K, M), by blocks of rows.
    pub fn of(k: &SparseMatrix, m: &SparseMatrix) -> Self {
        let n = k.nrows();
        let mut first = (0..n).collect::<Vec<_>>();
        let mut mass_first = first.clone();
        for j in 0..n {
            for (i, _) in lower_entries(k, j) {
                first[i] = first[i].min(j);
            }
            for (i, _) in lower_entries(m, j) {
                first[i] = first[i].min(j);
                mass_first[i] = mass_first[i].min(j);
            }
        }
        let blocks = n.div_ceil(BLOCK);
        let least = |v: &[usize], b: usize| {
            let rows = b * BLOCK..((b + 1) * BLOCK).min(n);
            v[rows].iter().copied().min().unwrap_or(0)
        };
        let first_col = (0..blocks).map(|b| least(&first, b)).collect();
        let mass_first_row = (0..blocks).map(|b| least(&mass_first, b)).collect();
        // Row i reaches block columns first[i] / BLOCK ..= i / BLOCK.
        let mut end_row = (0..blocks)
            .map(|b| ((b + 1) * BLOCK).min(n))
            .collect::<Vec<_>>();
        for (i, &f) in first.iter().enumerate() {
            for end in &mut end_row[f / BLOCK..=i / BLOCK] {
                *end = (*end).max(i + 1);
            }
        }
        Envelope {
            n,
            first_col,
            mass_first_row,
            end_row,
        }
    }

    /// Block rows as (index, first row, one past the last row).
    fn blocks(&self) -> impl DoubleEndedIterator<Item = (usize, usize, usize)> {
        let n = self.n;
        (0..self.first_col.len()).map(move |b| (b, b * BLOCK, ((b + 1) * BLOCK).min(n)))
    }
}

/// Entries (i, a_ij) of column j with i ≥ j: the lower triangle, which is
/// all the factorisation reads (as a dense Cholesky would).
fn lower_entries(a: &SparseMatrix, j: usize) -> impl Iterator<Item = (usize, f64)> + '_ {
    let rows = a.symbolic().row_idx_of_col_raw(j);
    rows.iter()
        .zip(a.val_of_col(j))
        .filter(move |(i, _)| **i >= j)
        .map(|(&i, &v)| (i, v))
}

/// K − σM = L Lᵀ inside the envelope (dense storage, zero outside it), or
/// None if K − σM is not numerically positive definite.
pub fn envelope_cholesky(
    k: &SparseMatrix,
    m: &SparseMatrix,
    sigma: f64,
    envelope: &Envelope,
    par: Par,
) -> Option<Mat<f64>> {
    let n = k.nrows();
    let mut l = Mat::<f64>::zeros(n, n);
    for j in 0..n {
        for (i, v) in lower_entries(k, j) {
            l[(i, j)] += v;
        }
        for (i, v) in lower_entries(m, j) {
            l[(i, j)] -= sigma * v;
        }
    }
    let mut mem = MemBuffer::new(cholesky_in_place_scratch::<f64>(
        BLOCK,
        par,
        Default::default(),
    ));
    for (b, r0, r1) in envelope.blocks() {
        let f = envelope.first_col[b];
        let h = r1 - r0;
        let (top, bottom) = l.as_mut().split_at_row_mut(r0);
        let (left, right) = bottom.split_at_col_mut(r0);
        let mut diagonal = right.submatrix_mut(0, 0, h, h);
        if f < r0 {
            // L[R, F] Lᵀ[F, F] = A[R, F], solved as L[F, F] L[R, F]ᵀ = A[R, F]ᵀ.
            let mut lrf = left.submatrix_mut(0, f, h, r0 - f);
            solve_lower_triangular_in_place(
                top.rb().submatrix(f, f, r0 - f, r0 - f),
                lrf.rb_mut().transpose_mut(),
                par,
            );
            triangular::matmul(
                diagonal.rb_mut(),
                BlockStructure::TriangularLower,
                Accum::Add,
                lrf.rb(),
                BlockStructure::Rectangular,
                lrf.rb().transpose(),
                BlockStructure::Rectangular,
                -1.0,
                par,
            );
        }
        cholesky_lower_in_place(diagonal.rb_mut(), par, MemStack::new(&mut mem))?;
    }
    Some(l)
}

/// The symmetric C = L⁻¹ M L⁻ᵀ, both triangles.
pub fn reduce(l: MatRef<'_, f64>, m: &SparseMatrix, envelope: &Envelope, par: Par) -> Mat<f64> {
    let n = l.nrows();
    let mut c = Mat::<f64>::zeros(n, n);
    for (b, r0, r1) in envelope.blocks() {
        let h = r1 - r0;
        let g = envelope.mass_first_row[b];
        let lrr = l.submatrix(r0, r0, h, h);
        // W[g..r1, R] = L[g..r1, g..r1]⁻¹ M[g..r1, R]; W is zero above g.
        let mut w = Mat::<f64>::zeros(r1 - g, h);
        for j in g..r1 {
            for (i, v) in lower_entries(m, j) {
                if i >= r1 {
                    continue;
                }
                // M[i, j] = M[j, i] with i ≥ j: place whichever lies in columns R.
                if i >= r0 {
                    w[(j - g, i - r0)] += v;
                }
                if j >= r0 && i > j {
                    w[(i - g, j - r0)] += v;
                }
            }
        }
        solve_lower_triangular_in_place(l.submatrix(g, g, r1 - g, r1 - g), w.as_mut(), par);
        let (mut top, mut bottom) = c.as_mut().split_at_row_mut(r0);
        bottom
            .rb_mut()
            .submatrix_mut(0, g, h, r1 - g)
            .copy_from(w.transpose());
        let f = envelope.first_col[b];
        let lrf = l.submatrix(r0, f, h, r0 - f);
        // Columns left of R, then mirrored above R.
        if r0 > 0 {
            let mut left = bottom.rb_mut().submatrix_mut(0, 0, h, r0);
            if f < r0 {
                matmul(
                    left.rb_mut(),
                    Accum::Add,
                    lrf,
                    top.rb().submatrix(f, 0, r0 - f, r0),
                    -1.0,
                    par,
                );
            }
            solve_lower_triangular_in_place(lrr, left.rb_mut(), par);
            top.rb_mut()
                .submatrix_mut(0, r0, r0, h)
                .copy_from(left.rb().transpose());
        }
        // The diagonal block, made exactly symmetric from its lower triangle.
        let mut diagonal = bottom.submatrix_mut(0, r0, h, h);
        if f < r0 {
            matmul(
                diagonal.rb_mut(),
                Accum::Add,
                lrf,
                top.rb().submatrix(f, r0, r0 - f, h),
                -1.0,
                par,
            );
        }
        solve_lower_triangular_in_place(lrr, diagonal.rb_mut(), par);
        for j in 0..h {
            for i in 0..j {
                diagonal[(i, j)] = diagonal[(j, i)];
            }
        }
    }
    c
}

/// [`tridiagonal::largest_pairs`] is used when at most 1/`SUBSET_BELOW` of the
/// eigenpairs are wanted and n ≥ 32 (the updater's ~40 of a few hundred; a
/// full decomposition for `modes` of all of them).
pub const SUBSET_BELOW: usize = 4;

/// The `count` largest eigenvalues of the symmetric C, largest first, their
/// orthonormal eigenvectors (C's lower triangle is read and overwritten), and
/// whether the subset path produced them: bisection and inverse iteration on
/// the tridiagonal form when count · `subset_below` ≤ n and n ≥ 32 (0: never).
pub fn largest_eigenpairs(
    c: Mat<f64>,
    count: usize,
    par: Par,
    subset_below: usize,
) -> Result<(Vec<f64>, Mat<f64>, bool), EigenError> {
    largest_eigenpairs_down_to(c, count, None, par, subset_below)
}

/// [`largest_eigenpairs`], but with `floor` = Some(μ_min) at most the
/// eigenvalues ≥ μ_min and the one below them (a Sturm count on the
/// tridiagonal form, before any eigenvector is computed).
pub fn largest_eigenpairs_down_to(
    c: Mat<f64>,
    count: usize,
    floor: Option<f64>,
    par: Par,
    subset_below: usize,
) -> Result<(Vec<f64>, Mat<f64>, bool), EigenError> {
    largest_eigenpairs_covering(c, count, floor, false, par, subset_below)
}

/// Which modes [`shift_invert`] returns besides its count: those with
/// ω² ≤ `omega2` and the one above them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cover {
    /// ω²_top (rad²/s²).
    pub omega2: f64,
    /// False: at most `count` of them. True: `count` is a first guess that
    /// doubles until the modes reach past ω²_top, every mode once it reaches
    /// n (then as if there were no cover): what a caller solving again with
    /// twice the count would get, in one solution ([`covering_count`]).
    pub grow: bool,
}

/// The number of eigenpairs returned for `count` asked when `wanted` (the
/// Sturm count above the floor, plus one) reach it, of `n`: at most `count`
/// without `grow`; with it, `count` doubled until it is at least `wanted`,
/// and all `n` once it reaches `n`.
pub fn covering_count(count: usize, wanted: usize, n: usize, grow: bool) -> usize {
    if !grow {
        return count.min(wanted).min(n);
    }
    let mut c = count.max(1);
    while c < wanted && c < n {
        c = (2 * c).min(n);
    }
    if c >= n {
        n
    } else {
        wanted
    }
}

/// [`largest_eigenpairs_down_to`], and with `grow` the count rule of
/// [`Cover::grow`] ([`covering_count`]) above the floor.
pub fn largest_eigenpairs_covering(
    mut c: Mat<f64>,
    count: usize,
    floor: Option<f64>,
    grow: bool,
    par: Par,
    subset_below: usize,
) -> Result<(Vec<f64>, Mat<f64>, bool), EigenError> {
    let n = c.nrows();
    let block = recommended_block_size::<f64>(n, n);
    let mut householder = Mat::<f64>::zeros(block, n.saturating_sub(1));
    let mut mem = MemBuffer::new(StackReq::any_of(&[
        tridiag_in_place_scratch::<f64>(n, par, Default::default()),
        self_adjoint_evd_scratch::<f64>(n, ComputeEigenvectors::Yes, par, Default::default()),
        apply_block_householder_sequence_on_the_left_in_place_scratch::<f64>(
            n.saturating_sub(1),
            block,
            count,
        ),
    ]));
    // C = Q T Qᵀ: T's diagonals and Q's reflectors overwrite C's lower triangle.
    tridiag_in_place(
        c.as_mut(),
        householder.as_mut(),
        par,
        MemStack::new(&mut mem),
        Default::default(),
    );
    let diag = Col::<f64>::from_fn(n, |i| c[(i, i)]);
    let subdiag = Col::<f64>::from_fn(n.saturating_sub(1), |i| c[(i + 1, i)]);
    let d: Vec<f64> = diag.iter().copied().collect();
    let e: Vec<f64> = subdiag.iter().copied().collect();
    let count = match floor {
        Some(mu) if n > 0 => {
            covering_count(count, tridiagonal::count_above(&d, &e, mu) + 1, n, grow)
        }
        _ => count,
    };
    // A few of many: bisection and inverse iteration on T (O(n·count²) at
    // most) instead of all n eigenvectors of T; a full decomposition if its
    // checks fail.
    let subset = if subset_below > 0 && count * subset_below <= n && n >= 32 {
        tridiagonal::largest_pairs(&d, &e, count)
            .map(|(values, vecs)| (values, Mat::from_fn(n, count, |i, j| vecs[j][i])))
    } else {
        None
    };
    let used_subset = subset.is_some();
    let (values, mut z) = match subset {
        Some(pairs) => pairs,
        None => {
            let mut mu = Col::<f64>::zeros(n);
            let mut z = Mat::<f64>::zeros(n, n);
            tridiagonal_self_adjoint_evd(
                diag.as_diagonal(),
                subdiag.as_diagonal(),
                mu.as_diagonal_mut(),
                Some(z.as_mut()),
                par,
                MemStack::new(&mut mem),
                Default::default(),
            )
            .map_err(|e| EigenError::NoConvergence {
                detail: format!("dense symmetric eigensolver: {e:?}"),
            })?;
            // μ ascending: reverse the column order in place and keep `count`.
            for j in 0..count.min(n / 2) {
                faer::perm::swap_cols_idx(z.as_mut(), j, n - 1 - j);
            }
            z.truncate(n, count);
            ((0..count).map(|j| mu[n - 1 - j]).collect(), z)
        }
    };
    if n > 1 {
        apply_block_householder_sequence_on_the_left_in_place_with_conj(
            c.as_ref().submatrix(1, 0, n - 1, n - 1),
            householder.as_ref(),
            Conj::No,
            z.as_mut().subrows_mut(1, n - 1),
            par,
            MemStack::new(&mut mem),
        );
    }
    Ok((values, z, used_subset))
}

/// y ← L⁻ᵀ y.
pub fn back_substitute(l: MatRef<'_, f64>, envelope: &Envelope, y: MatMut<'_, f64>, par: Par) {
    let mut y = y;
    for (b, r0, r1) in envelope.blocks().rev() {
        let h = r1 - r0;
        let end = envelope.end_row[b];
        let (top, bottom) = y.rb_mut().split_at_row_mut(r1);
        let mut yr = top.subrows_mut(r0, h);
        if end > r1 {
            matmul(
                yr.rb_mut(),
                Accum::Add,
                l.submatrix(r1, r0, end - r1, h).transpose(),
                bottom.rb().subrows(0, end - r1),
                -1.0,
                par,
            );
        }
        solve_upper_triangular_in_place(l.submatrix(r0, r0, h, h).transpose(), yr, par);
    }
}
