//! Unit tests of `src/solvers/eigen/tridiagonal.rs` through its public interface.

use frfup::solvers::eigen::tridiagonal::*;

/// The 1-D Laplacian tridiag(−1, 2, −1) of order n has eigenvalues
/// 2 − 2 cos(jπ/(n+1)) and eigenvectors sin(ijπ/(n+1)): closed form.
#[test]
fn laplacian_matches_closed_form() {
    let n = 200;
    let d = vec![2.0; n];
    let e = vec![-1.0; n - 1];
    let (values, vectors) = largest_pairs(&d, &e, 12).expect("well separated");
    let h = std::f64::consts::PI / (n + 1) as f64;
    for (r, (lambda, z)) in values.iter().zip(&vectors).enumerate() {
        let j = (n - r) as f64;
        let exact = 2.0 - 2.0 * (j * h).cos();
        // Bisection to 4 ulps of ‖T‖ = 4.
        assert!(
            (lambda - exact).abs() < 1e-14 * 4.0,
            "λ{r}: {lambda} vs {exact}"
        );
        let norm = (0.5 * (n + 1) as f64).sqrt();
        let dot: f64 = (0..n)
            .map(|i| z[i] * ((i + 1) as f64 * j * h).sin() / norm)
            .sum();
        // Gap 2.4e-4 relative: the vector is accurate to ~ε‖T‖/gap.
        assert!(
            (dot.abs() - 1.0).abs() < 1e-10,
            "vector {r}: |cos| = {}",
            dot.abs()
        );
    }
}

/// A direct sum of three copies of the same block (a zero off-diagonal
/// splits T): every eigenvalue is triple, as for rigid-body modes. The
/// vectors must still be orthonormal and span the right subspaces.
#[test]
fn multiple_eigenvalues_give_orthonormal_vectors() {
    let block_d = [4.0, 1.0, 3.0, 2.0];
    let block_e = [0.5, -0.7, 0.2];
    let mut d = Vec::new();
    let mut e = Vec::new();
    for copy in 0..3 {
        d.extend_from_slice(&block_d);
        e.extend_from_slice(&block_e);
        if copy < 2 {
            e.push(0.0);
        }
    }
    let (values, vectors) = largest_pairs(&d, &e, 6).expect("checked pairs");
    assert!((values[0] - values[2]).abs() < 1e-13 && (values[3] - values[5]).abs() < 1e-13);
    assert!(values[2] - values[3] > 0.1);
    for (i, zi) in vectors.iter().enumerate() {
        for (j, zj) in vectors.iter().enumerate() {
            let dot: f64 = zi.iter().zip(zj).map(|(a, b)| a * b).sum();
            let expect = if i == j { 1.0 } else { 0.0 };
            assert!((dot - expect).abs() < 1e-12, "z{i}·z{j} = {dot}");
        }
    }
}

/// The Sturm count of the 1-D Laplacian against its closed-form spectrum
/// 2 − 2 cos(jπ/(n+1)): at a point between two eigenvalues it counts
/// exactly those above, at every gap of the spectrum.
#[test]
fn count_above_matches_the_closed_form_spectrum() {
    let n = 60;
    let d = vec![2.0; n];
    let e = vec![-1.0; n - 1];
    let h = std::f64::consts::PI / (n + 1) as f64;
    let eig = |j: usize| 2.0 - 2.0 * (j as f64 * h).cos();
    for j in 1..n {
        let between = 0.5 * (eig(j) + eig(j + 1));
        assert_eq!(
            count_above(&d, &e, between),
            n - j,
            "between λ{j} and λ{}",
            j + 1
        );
    }
    assert_eq!(count_above(&d, &e, -1.0), n);
    assert_eq!(count_above(&d, &e, 5.0), 0);
}
