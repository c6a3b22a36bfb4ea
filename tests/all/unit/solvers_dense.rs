//! `solvers::dense`: the kernels on the calling thread, checked against
//! closed forms.

use faer::{c64, Mat};
use frfup::solvers::dense::{general_eigen, lu_solve, product};

/// A well-conditioned matrix that needs pivoting (a zero leading entry).
fn pivoted(n: usize) -> Mat<f64> {
    Mat::from_fn(n, n, |i, j| {
        if i == j {
            if i == 0 {
                0.0
            } else {
                4.0 + i as f64
            }
        } else {
            1.0 / (1.0 + (i as f64 - j as f64).abs())
        }
    })
}

/// A X = B to round-off: the residual of the solution relative to ‖B‖ is
/// a few ε·cond(A) (cond ≈ 10 here), so 1e-13 leaves room for n = 40.
#[test]
fn lu_solve_solves_a_system_that_needs_pivoting() {
    let n = 40;
    let a = pivoted(n);
    let b = Mat::from_fn(n, 3, |i, j| ((i + 1) * (j + 2)) as f64);
    let x = lu_solve(a.as_ref(), b.as_ref());
    let r = product(a.as_ref(), x.as_ref()) - &b;
    let rel = r.norm_l2() / b.norm_l2();
    assert!(rel < 1e-13, "relative residual {rel}");
}

/// A singular matrix gives entries that are not finite (the callers' test).
#[test]
fn lu_solve_of_a_singular_matrix_is_not_finite() {
    let a = Mat::from_fn(3, 3, |i, _| i as f64 + 1.0);
    let b = Mat::from_fn(3, 1, |_, _| 1.0);
    let x = lu_solve(a.as_ref(), b.as_ref());
    assert!((0..3).any(|i| !x[(i, 0)].is_finite()), "{x:?}");
}

/// The companion matrix of (z² + 1)(z − 2)(z + 3) = z⁴ + z³ − 5z² + z − 6:
/// eigenvalues ±i, 2, −3 to round-off; each right eigenvector satisfies
/// A v = λ v, and a pair's vectors are each other's conjugates.
#[test]
fn general_eigen_gives_a_companion_matrix_roots_and_vectors() {
    let c = [-6.0, 1.0, -5.0, 1.0]; // c0..c3 of z⁴ + c3 z³ + ... + c0
    let a = Mat::from_fn(4, 4, |i, j| {
        if i == 3 {
            -c[j]
        } else if j == i + 1 {
            1.0
        } else {
            0.0
        }
    });
    let (lambda, vectors) = general_eigen(a.as_ref(), true).unwrap();
    let mut want = vec![
        c64::new(0.0, 1.0),
        c64::new(0.0, -1.0),
        c64::new(2.0, 0.0),
        c64::new(-3.0, 0.0),
    ];
    for l in &lambda {
        let k = (0..want.len())
            .min_by(|&x, &y| (want[x] - l).norm().total_cmp(&(want[y] - l).norm()))
            .unwrap();
        assert!((want[k] - l).norm() < 1e-12, "{l:?} among {lambda:?}");
        want.remove(k);
    }
    let v = vectors.unwrap();
    for (j, l) in lambda.iter().enumerate() {
        let av: Vec<c64> = (0..4)
            .map(|i| (0..4).map(|k| v[(k, j)] * a[(i, k)]).sum())
            .collect();
        let scale = (0..4).map(|i| v[(i, j)].norm()).fold(0.0, f64::max);
        for i in 0..4 {
            assert!((av[i] - v[(i, j)] * l).norm() < 1e-12 * scale, "mode {j}");
        }
        if l.im > 0.0 {
            for i in 0..4 {
                assert_eq!(v[(i, j + 1)], v[(i, j)].conj());
            }
            assert_eq!(lambda[j + 1], l.conj());
        }
    }
    let (alone, none) = general_eigen(a.as_ref(), false).unwrap();
    assert!(none.is_none());
    for (x, y) in alone.iter().zip(&lambda) {
        assert!((x - y).norm() < 1e-12);
    }
}
