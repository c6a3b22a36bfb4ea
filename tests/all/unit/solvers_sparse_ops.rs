//! Unit tests of `src/solvers/sparse_ops.rs` through its public interface.

use faer::sparse::Triplet;
use faer::Mat;
use frfup::model::SparseMatrix;
use frfup::solvers::sparse_ops::*;

/// P A Pᵀ X by rows against the dense product, for the specialised block
/// widths (8, 4) and the general one (3), on an unsymmetric pattern so
/// that rows and columns cannot be confused. Same operations in the same
/// order per entry up to the summation order of each row: 1e-13 relative.
#[test]
fn permuted_row_product_matches_dense() {
    let n = 37;
    let mut t = Vec::new();
    for i in 0..n {
        t.push(Triplet::new(i, i, 2.0 + i as f64));
        t.push(Triplet::new(i, (i * 7 + 3) % n, 0.5 - 0.01 * i as f64));
        t.push(Triplet::new((i * 5 + 1) % n, i, -0.25 * (i % 4) as f64));
    }
    let a = SparseMatrix::try_new_from_triplets(n, n, &t).unwrap();
    let dense = a.to_dense();
    let fwd: Vec<usize> = (0..n).map(|i| (i * 11 + 4) % n).collect();
    let rows = RowMatrix::permuted(&a, &fwd);
    for b in [8, 4, 3] {
        let x = Mat::from_fn(n, b, |i, j| ((i * 3 + j * 17) % 13) as f64 - 6.0);
        let y = rows.mul(x.as_ref());
        for c in 0..b {
            for i in 0..n {
                let expect: f64 = (0..n).map(|j| dense[(fwd[i], fwd[j])] * x[(j, c)]).sum();
                let got = y[(i, c)];
                assert!(
                    (got - expect).abs() <= 1e-13 * expect.abs().max(1.0),
                    "b = {b}, ({i}, {c}): {got} vs {expect}"
                );
            }
        }
    }
}
