//! Unit tests of `src/updating/serep.rs` through its public interface.

use faer::Mat;
use frfup::solvers::eigen::Modes;
use frfup::updating::serep::*;

/// A 4-DOF chain K = tridiag(-k, 2k, -k), M = m I; exact modes.
fn chain_modes() -> (Mat<f64>, Mat<f64>, Modes) {
    let n = 4;
    let k = Mat::from_fn(n, n, |i, j| {
        if i == j {
            2.0e4
        } else if i.abs_diff(j) == 1 {
            -1.0e4
        } else {
            0.0
        }
    });
    let m = Mat::from_fn(n, n, |i, j| if i == j { 2.0 } else { 0.0 });
    // Analytic: φ_r(i) = sin((i+1) r π/(n+1)), λ_r = (2k − 2k cos(rπ/(n+1)))/m.
    let mut omega2 = Vec::new();
    let mut shapes = Mat::<f64>::zeros(n, n);
    for r in 1..=n {
        let th = r as f64 * std::f64::consts::PI / (n + 1) as f64;
        omega2.push((2.0e4 - 2.0e4 * th.cos()) / 2.0);
        let v: Vec<f64> = (0..n).map(|i| ((i + 1) as f64 * th).sin()).collect();
        let mm: f64 = v.iter().map(|x| 2.0 * x * x).sum();
        for i in 0..n {
            shapes[(i, r - 1)] = v[i] / mm.sqrt();
        }
    }
    (k, m, Modes { omega2, shapes })
}

#[test]
fn reduced_matrices_match_explicit_transformation() {
    let (k, m, modes) = chain_modes();
    let measured = [0, 1, 3];
    let basis = SerepBasis::select(&modes, &measured, 2, 1e-3).unwrap();
    assert_eq!(basis.modes, vec![0, 1]);
    let t = basis.transformation(modes.shapes.as_ref());
    let kbar = t.transpose() * &k * &t;
    let mbar = t.transpose() * &m * &t;
    let (k2, m2) = (basis.reduced_stiffness(), basis.reduced_mass());
    for i in 0..3 {
        for j in 0..3 {
            assert!((kbar[(i, j)] - k2[(i, j)]).abs() < 1e-8 * 2e4, "K {i}{j}");
            assert!((mbar[(i, j)] - m2[(i, j)]).abs() < 1e-10, "M {i}{j}");
        }
    }
    // T reproduces the retained modes at all DOFs from their measured part.
    for (k_, &r) in basis.modes.iter().enumerate() {
        let col: Vec<f64> = (0..3).map(|i| basis.psi_m[(i, k_)]).collect();
        for i in 0..4 {
            let v: f64 = (0..3).map(|j| t[(i, j)] * col[j]).sum();
            assert!((v - modes.shapes[(i, r)]).abs() < 1e-12);
        }
    }
}

#[test]
fn svd_inverse_equals_modal_receptance() {
    let (_, _, modes) = chain_modes();
    let basis = SerepBasis::select(&modes, &[0, 1, 3], 2, 1e-3).unwrap();
    let w2 = 0.7 * modes.omega2[1];
    let h1 = basis.reduced_receptance(w2, InverseMethod::Svd).unwrap();
    let h2 = basis.modal_receptance(w2).unwrap();
    let scale = (0..3).map(|i| h2[(i, i)].abs()).fold(0.0, f64::max);
    for i in 0..3 {
        for j in 0..3 {
            assert!((h1[(i, j)] - h2[(i, j)]).abs() < 1e-9 * scale);
        }
    }
    // Full basis: the perturbed inverse tends to the exact inverse.
    let basis = SerepBasis::select(&modes, &[0, 1, 2, 3], 4, 1e-3).unwrap();
    let h3 = basis
        .reduced_receptance(w2, InverseMethod::Perturb { relative: 1e-10 })
        .unwrap();
    let h4 = basis.modal_receptance(w2).unwrap();
    for i in 0..4 {
        for j in 0..4 {
            assert!((h3[(i, j)] - h4[(i, j)]).abs() < 1e-6 * scale);
        }
    }
}

#[test]
fn invisible_modes_are_dropped() {
    let (_, _, mut modes) = chain_modes();
    // Make mode 1 vanish at the measured DOFs 0 and 3; mode 2 is symmetric
    // like mode 0, so at these two DOFs it adds nothing new either.
    for i in [0, 3] {
        modes.shapes[(i, 1)] = 0.0;
    }
    let basis = SerepBasis::select(&modes, &[0, 3], 3, 1e-3).unwrap();
    assert_eq!(basis.modes, vec![0, 3]);
    assert_eq!(basis.dropped, vec![1, 2]);
    assert!(basis.modal_factors(modes.omega2[0]).is_none());
}
