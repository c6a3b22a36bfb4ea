//! Unit tests of `src/solvers/eigen/lanczos.rs` through its public interface.

use faer::sparse::Triplet;
use faer::Mat;
use faer::MatRef;
use faer::Par;
use frfup::model::SparseMatrix;
use frfup::solvers::eigen::lanczos::*;
use frfup::solvers::eigen::EigenTuning;

/// A k × k × k grid pencil: K = 7-point Laplacian + 0.01 I, M = I.
fn grid_pencil(k: usize) -> (SparseMatrix, SparseMatrix) {
    let n = k * k * k;
    let id = |x: usize, y: usize, z: usize| (z * k + y) * k + x;
    let mut kt = Vec::new();
    for z in 0..k {
        for y in 0..k {
            for x in 0..k {
                let i = id(x, y, z);
                kt.push(Triplet::new(i, i, 6.01));
                for (dx, dy, dz) in [(1, 0, 0), (0, 1, 0), (0, 0, 1)] {
                    let (a, b, c) = (x + dx, y + dy, z + dz);
                    if a < k && b < k && c < k {
                        let j = id(a, b, c);
                        kt.push(Triplet::new(i, j, -1.0));
                        kt.push(Triplet::new(j, i, -1.0));
                    }
                }
            }
        }
    }
    let mt: Vec<_> = (0..n).map(|i| Triplet::new(i, i, 1.0)).collect();
    (
        SparseMatrix::try_new_from_triplets(n, n, &kt).unwrap(),
        SparseMatrix::try_new_from_triplets(n, n, &mt).unwrap(),
    )
}

#[test]
fn nested_dissection_matches_amd_eigenvalues() {
    let (k, m) = grid_pencil(14);
    let tuning = EigenTuning::default();
    let run = |ordering| {
        let chol = ShiftedCholesky::with_ordering(&k, &m, -1e-3, ordering).unwrap();
        let op = |y: MatRef<'_, f64>| chol.apply(&m, y);
        let out = block_lanczos(&op, k.nrows(), 12, &tuning).unwrap();
        let omega2: Vec<f64> = out.values.iter().map(|mu| chol.shift + 1.0 / mu).collect();
        (omega2, chol.factor_nonzeros())
    };
    let (nd, nd_fill) = run(FillOrdering::NestedDissection);
    let (amd, amd_fill) = run(FillOrdering::Amd);
    for (a, b) in nd.iter().zip(&amd) {
        assert!((a - b).abs() <= 1e-9 * b.abs(), "ω²: ND {a}, AMD {b}");
    }
    // On so small a grid the level-set separators (diagonal planes) do not
    // pay off yet (14³: ND 239 k, AMD 218 k); on the 101,400-DOF cube
    // lattice ND gives 93 M against AMD's 224 M.
    assert!(
        (nd_fill as f64) < 1.5 * amd_fill as f64,
        "nnz(L): ND {nd_fill}, AMD {amd_fill}"
    );
    let best = ShiftedCholesky::new(&k, &m, -1e-3).unwrap();
    assert_eq!(best.factor_nonzeros(), nd_fill.min(amd_fill));
}

/// ‖QᵀQ − I‖_max and ‖Q R − Z‖_max / ‖Z‖_max.
fn qr_errors(z: &Mat<f64>, q: &Mat<f64>, r: &Mat<f64>) -> (f64, f64) {
    let b = q.ncols();
    let g = q.transpose() * q;
    let orth = (0..b)
        .flat_map(|i| (0..b).map(move |j| (i, j)))
        .map(|(i, j)| (g[(i, j)] - if i == j { 1.0 } else { 0.0 }).abs())
        .fold(0.0, f64::max);
    let qr = q * r;
    let scale = z
        .col_iter()
        .flat_map(|c| c.iter().copied())
        .fold(0.0, |a: f64, v| a.max(v.abs()));
    let diff = (0..z.nrows())
        .flat_map(|i| (0..b).map(move |j| (i, j)))
        .map(|(i, j)| (qr[(i, j)] - z[(i, j)]).abs())
        .fold(0.0, f64::max);
    (orth, diff / scale)
}

/// Cholesky QR twice on a well-conditioned block, and the Gram–Schmidt
/// fallback on a block with a repeated column: both give Q with
/// QᵀQ = I and Z = Q R to ~1e-14 (a few hundred ulps of accumulated
/// rounding over 500-long dot products).
#[test]
fn block_orthonormalisation_is_exact_and_handles_dependent_columns() {
    let mut rng = Xorshift(7);
    let n = 500;
    let z = Mat::from_fn(n, 8, |_, _| rng.uniform());
    let mut q = z.clone();
    let r = cholesky_qr2(q.as_mut(), Par::Seq).expect("well-conditioned block");
    let (orth, diff) = qr_errors(&z, &q, &r);
    assert!(orth < 1e-14 && diff < 1e-14, "CholQR2: {orth:e}, {diff:e}");
    for i in 1..8 {
        for j in 0..i {
            assert_eq!(r[(i, j)], 0.0, "R is upper triangular");
        }
    }

    // Column 5 = column 2: Cholesky QR must decline, and orthonormalise
    // replaces the vanished direction by a fresh orthonormal one.
    let mut dep = z.clone();
    let c2 = dep.col(2).to_owned();
    dep.col_mut(5).copy_from(&c2);
    let mut q = dep.clone();
    assert!(cholesky_qr2(q.as_mut(), Par::Seq).is_none());
    assert_eq!(q, dep, "a declined block is left unchanged");
    let empty = Mat::<f64>::zeros(n, 0);
    let r = orthonormalise(empty.as_ref(), q.as_mut(), 0, &mut rng);
    assert_eq!(r[(5, 5)], 0.0, "breakdown recorded in R");
    let (orth, diff) = qr_errors(&dep, &q, &r);
    assert!(
        orth < 1e-13 && diff < 1e-13,
        "MGS fallback: {orth:e}, {diff:e}"
    );
}
