//! Unit tests of `src/updating/svd_solve.rs` through its public interface.

use faer::Mat;
use frfup::updating::svd_solve::*;

#[test]
fn full_rank_least_squares() {
    // Overdetermined, consistent: exact solution (1, -2).
    let a = Mat::from_fn(3, 2, |i, j| [[1.0, 0.0], [0.0, 1.0], [1.0, 1.0]][i][j]);
    let b = [1.0, -2.0, -1.0];
    let sol = solve_gap_rule(a.as_ref(), &b, 1e-4).unwrap();
    assert_eq!(sol.rank, 2);
    assert!((sol.step[0] - 1.0).abs() < 1e-12 && (sol.step[1] + 2.0).abs() < 1e-12);
    assert!(sol.null_space.is_empty());
}

#[test]
fn gap_rule_drops_dependent_column() {
    // Columns 0 and 1 identical: only their sum is determined.
    let a = Mat::from_fn(4, 3, |i, j| match j {
        0 | 1 => (i + 1) as f64,
        _ => ((i * i) as f64) - 1.0,
    });
    let b: Vec<f64> = (0..4)
        .map(|i| 2.0 * (i + 1) as f64 + 0.5 * ((i * i) as f64 - 1.0))
        .collect();
    let sol = solve_gap_rule(a.as_ref(), &b, 1e-4).unwrap();
    assert_eq!(sol.rank, 2);
    // Minimum-norm solution splits the sum equally.
    assert!((sol.step[0] - 1.0).abs() < 1e-10, "{:?}", sol.step);
    assert!((sol.step[1] - 1.0).abs() < 1e-10);
    assert!((sol.step[2] - 0.5).abs() < 1e-10);
    assert_eq!(sol.null_space.len(), 1);
    let nv = &sol.null_space[0];
    assert!((nv[0] + nv[1]).abs() < 1e-10 && nv[2].abs() < 1e-10);
}

#[test]
fn gap_rank_rules() {
    assert_eq!(gap_rank(&[1.0, 0.5, 1e-6], 1e-4), 2);
    assert_eq!(gap_rank(&[1.0, 0.5, 0.1], 1e-4), 3);
    assert_eq!(gap_rank(&[1.0, 1e-5, 1e-6], 1e-4), 1);
    assert_eq!(gap_rank(&[0.0, 0.0], 1e-4), 0);
    assert_eq!(gap_rank(&[], 1e-4), 0);
    assert_eq!(gap_rank(&[1.0, 1e-3, 1e-6, 1e-9, 1e-12, 1e-15], 1e-4), 5);
}

#[test]
fn underdetermined_has_full_null_space() {
    let a = Mat::from_fn(1, 3, |_, j| (j + 1) as f64);
    let sol = solve_gap_rule(a.as_ref(), &[14.0], 1e-4).unwrap();
    assert_eq!(sol.rank, 1);
    assert_eq!(sol.null_space.len(), 2);
    let r: f64 = sol
        .step
        .iter()
        .enumerate()
        .map(|(j, p)| (j + 1) as f64 * p)
        .sum();
    assert!((r - 14.0).abs() < 1e-10);
}

#[test]
fn rejects_non_finite_and_shape() {
    let a = Mat::from_fn(2, 1, |i, _| if i == 0 { f64::NAN } else { 1.0 });
    assert_eq!(
        solve_gap_rule(a.as_ref(), &[1.0, 1.0], 1e-4),
        Err(SvdSolveError::NonFinite)
    );
    let a = Mat::from_fn(2, 1, |_, _| 1.0);
    assert!(matches!(
        solve_gap_rule(a.as_ref(), &[1.0], 1e-4),
        Err(SvdSolveError::Shape { .. })
    ));
}

#[test]
fn truncated_inverse_of_rank_deficient() {
    // A = x xᵀ with x = (1, 2): pinv = x xᵀ / |x|⁴.
    let a = Mat::from_fn(2, 2, |i, j| ((i + 1) * (j + 1)) as f64);
    let p = truncated_pseudo_inverse(a.as_ref(), 1).unwrap();
    for i in 0..2 {
        for j in 0..2 {
            assert!((p[(i, j)] - ((i + 1) * (j + 1)) as f64 / 25.0).abs() < 1e-12);
        }
    }
}
