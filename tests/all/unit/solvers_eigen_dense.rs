//! Unit tests of `src/solvers/eigen/dense.rs` through its public interface.

use faer::linalg::triangular_solve::solve_lower_triangular_in_place;
use faer::linalg::triangular_solve::solve_upper_triangular_in_place;
use faer::sparse::Triplet;
use faer::Mat;
use faer::MatRef;
use faer::Par;
use frfup::model::SparseMatrix;
use frfup::solvers::eigen::dense::*;

/// A symmetric positive definite pencil with a narrow band plus a few
/// long-range couplings, in K alone and in M alone, so that the envelope
/// varies from block to block and reaches across blocks.
fn irregular_pencil(n: usize) -> (SparseMatrix, SparseMatrix) {
    let couple = |t: &mut Vec<Triplet<usize, usize, f64>>, i: usize, j: usize, v: f64| {
        t.push(Triplet::new(i, j, v));
        if i != j {
            t.push(Triplet::new(j, i, v));
        }
    };
    let (mut kt, mut mt) = (Vec::new(), Vec::new());
    for i in 0..n {
        couple(&mut kt, i, i, 10.0 + (i % 7) as f64);
        couple(&mut mt, i, i, 2.0 + (i % 3) as f64 * 0.1);
        if i >= 1 {
            couple(&mut kt, i, i - 1, -1.0);
            couple(&mut mt, i, i - 1, 0.3);
        }
        if i >= 2 {
            couple(&mut kt, i, i - 2, -0.5);
        }
    }
    for (i, j) in [(150, 3), (100, 70), (n - 1, 64)] {
        couple(&mut kt, i, j, -0.7);
    }
    for (i, j) in [(140, 10), (129, 60)] {
        couple(&mut mt, i, j, 0.2);
    }
    (
        SparseMatrix::try_new_from_triplets(n, n, &kt).unwrap(),
        SparseMatrix::try_new_from_triplets(n, n, &mt).unwrap(),
    )
}

fn dense(a: &SparseMatrix) -> Mat<f64> {
    let mut d = Mat::<f64>::zeros(a.nrows(), a.ncols());
    for j in 0..a.ncols() {
        for (&i, &v) in a
            .symbolic()
            .row_idx_of_col_raw(j)
            .iter()
            .zip(a.val_of_col(j))
        {
            d[(i, j)] += v;
        }
    }
    d
}

fn max_abs_difference(a: MatRef<'_, f64>, b: MatRef<'_, f64>) -> f64 {
    let mut worst = 0.0f64;
    for j in 0..a.ncols() {
        for i in 0..a.nrows() {
            worst = worst.max((a[(i, j)] - b[(i, j)]).abs());
        }
    }
    worst
}

#[test]
fn envelope_steps_match_full_triangular_solves() {
    // 170 rows: three blocks, the last one partial.
    let n = 170;
    let (k, m) = irregular_pencil(n);
    let sigma = -0.5;
    let envelope = Envelope::of(&k, &m);
    assert_eq!(envelope.first_col, [0, 62, 3]);
    assert_eq!(envelope.mass_first_row, [0, 63, 10]);
    assert_eq!(envelope.end_row, [151, 170, 170]);
    let (kd, md) = (dense(&k), dense(&m));
    let a = Mat::from_fn(n, n, |i, j| kd[(i, j)] - sigma * md[(i, j)]);

    let l = envelope_cholesky(&k, &m, sigma, &envelope, Par::Seq).unwrap();
    let llt = &l * l.transpose();
    assert!(max_abs_difference(llt.as_ref(), a.as_ref()) < 1e-12 * 20.0);
    assert!((0..n).all(|j| (0..j).all(|i| l[(i, j)] == 0.0)));

    // C = L⁻¹ M L⁻ᵀ by two full triangular solves.
    let c = reduce(l.as_ref(), &m, &envelope, Par::Seq);
    let mut w = md.clone();
    solve_lower_triangular_in_place(l.as_ref(), w.as_mut(), Par::Seq);
    let mut expected = w.transpose().to_owned();
    solve_lower_triangular_in_place(l.as_ref(), expected.as_mut(), Par::Seq);
    assert!(max_abs_difference(c.as_ref(), expected.as_ref()) < 1e-14);

    // φ = L⁻ᵀ y by a full triangular solve.
    let y = Mat::from_fn(n, 5, |i, j| ((i * 7 + j * 3) % 11) as f64 - 5.0);
    let mut phi = y.clone();
    back_substitute(l.as_ref(), &envelope, phi.as_mut(), Par::Seq);
    let mut expected = y;
    solve_upper_triangular_in_place(l.transpose(), expected.as_mut(), Par::Seq);
    assert!(max_abs_difference(phi.as_ref(), expected.as_ref()) < 1e-13);
}

#[test]
fn not_positive_definite_is_reported() {
    let (k, m) = irregular_pencil(170);
    let envelope = Envelope::of(&k, &m);
    // σ far above the spectrum (ω² ≤ ~10): K − σM is indefinite.
    assert!(envelope_cholesky(&k, &m, 1e3, &envelope, Par::Seq).is_none());
}

/// The subset path (a few of many eigenpairs of T) against the full
/// decomposition on the reduced C of a free-free chain (one rigid-body
/// mode, n = 200): the same vectors up to sign, to 1e-9 of their size (both are accurate
/// to ~ε‖T‖/gap, and the relative gaps here are above 1e-3).
#[test]
fn subset_of_eigenpairs_matches_full_decomposition() {
    let n = 200;
    let (mut kt, mut mt) = (Vec::new(), Vec::new());
    for i in 0..n {
        mt.push(Triplet::new(i, i, 1.0 + 0.3 * (i % 5) as f64));
        if i + 1 < n {
            let k = 1.0 + 0.1 * (i % 3) as f64;
            kt.push(Triplet::new(i, i, k));
            kt.push(Triplet::new(i + 1, i + 1, k));
            kt.push(Triplet::new(i, i + 1, -k));
            kt.push(Triplet::new(i + 1, i, -k));
        }
    }
    let k = SparseMatrix::try_new_from_triplets(n, n, &kt).unwrap();
    let m = SparseMatrix::try_new_from_triplets(n, n, &mt).unwrap();
    let envelope = Envelope::of(&k, &m);
    let l = envelope_cholesky(&k, &m, -1e-3, &envelope, Par::Seq).unwrap();
    let c = reduce(l.as_ref(), &m, &envelope, Par::Seq);
    let (mu_some, some, subset) =
        largest_eigenpairs(c.clone(), 12, Par::Seq, SUBSET_BELOW).unwrap();
    assert!(subset, "12 of 200: the subset path, and its checks passed");
    let (mu_all, all, full) = largest_eigenpairs(c, 12, Par::Seq, 0).unwrap();
    assert!(!full);
    for (a, b) in mu_some.iter().zip(&mu_all) {
        // Bisection to a few ulps of ‖C‖ against the QR algorithm.
        assert!((a - b).abs() <= 1e-13 * mu_all[0], "μ {a:e} vs {b:e}");
    }
    for j in 0..12 {
        let dot: f64 = some
            .col(j)
            .iter()
            .zip(all.col(j).iter())
            .map(|(a, b)| a * b)
            .sum();
        let size = all.col(j).iter().fold(0.0f64, |a, v| a.max(v.abs()));
        let worst = some
            .col(j)
            .iter()
            .zip(all.col(j).iter())
            .fold(0.0f64, |a, (x, y)| a.max((x - dot.signum() * y).abs()));
        assert!(worst <= 1e-9 * size, "mode {j}: {worst:e} of {size:e}");
    }
}

/// With a floor between the 5th and 6th largest μ, the pairs stop at the
/// first one below it (six), and they are the full decomposition's first six.
#[test]
fn a_floor_keeps_the_eigenvalues_above_it_and_the_next() {
    let (k, m) = irregular_pencil(160);
    let envelope = Envelope::of(&k, &m);
    let l = envelope_cholesky(&k, &m, -1e-3, &envelope, Par::Seq).unwrap();
    let c = reduce(l.as_ref(), &m, &envelope, Par::Seq);
    let (mu_all, all, _) = largest_eigenpairs(c.clone(), 20, Par::Seq, 0).unwrap();
    let floor = 0.5 * (mu_all[4] + mu_all[5]);
    let (mu, z, _) =
        largest_eigenpairs_down_to(c.clone(), 20, Some(floor), Par::Seq, SUBSET_BELOW).unwrap();
    assert_eq!(mu.len(), 6);
    assert_eq!(z.ncols(), 6);
    for j in 0..6 {
        assert!((mu[j] - mu_all[j]).abs() <= 1e-13 * mu_all[0], "μ{j}");
        let dot: f64 = z
            .col(j)
            .iter()
            .zip(all.col(j).iter())
            .map(|(a, b)| a * b)
            .sum();
        assert!(
            (dot.abs() - 1.0).abs() < 1e-9,
            "vector {j}: |cos| = {}",
            dot.abs()
        );
    }
    // A floor above every eigenvalue still gives the largest pair; no
    // floor gives the count asked for.
    let (mu, _, _) =
        largest_eigenpairs_down_to(c.clone(), 20, Some(2.0 * mu_all[0]), Par::Seq, 4).unwrap();
    assert_eq!(mu.len(), 1);
    let (mu, _, _) = largest_eigenpairs_down_to(c, 20, None, Par::Seq, 4).unwrap();
    assert_eq!(mu.len(), 20);
}

/// The count rule of a growing cover reproduces a caller that solves again
/// with twice the count: 40 asked, 48 wanted → 48; 90 wanted → 90 (40, 80,
/// 160 covers it); on 70 unknowns, 60 wanted → all 70 (40, then 70 = n, where
/// the caller asks without a cover); without growth at most the count.
#[test]
fn a_growing_cover_counts_as_a_doubling_caller_would() {
    assert_eq!(covering_count(40, 48, 336, true), 48);
    assert_eq!(covering_count(40, 90, 336, true), 90);
    assert_eq!(covering_count(40, 20, 336, true), 20);
    assert_eq!(covering_count(40, 40, 336, true), 40);
    assert_eq!(covering_count(40, 60, 70, true), 70);
    assert_eq!(covering_count(40, 70, 70, true), 70);
    assert_eq!(covering_count(80, 90, 70, true), 70);
    assert_eq!(covering_count(40, 48, 336, false), 40);
    assert_eq!(covering_count(40, 20, 336, false), 20);
}
