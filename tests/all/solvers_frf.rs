//! FRFs: direct solve vs modal superposition, reciprocity, poles.
//!
//! Tolerances: with all modes the modal sum is algebraically identical to the
//! direct solve for Rayleigh/hysteretic/no damping, so they agree to ~1e-8
//! relative (the conditioning of A(ω) near resonances times ε); reciprocity
//! holds to rounding (1e-10) because A(ω) is complex symmetric.

use crate::solvers_support::*;
use faer::c64;
use frfup::model::Damping;
use frfup::solvers::eigen::{lowest_modes, EigenOptions};
use frfup::solvers::frf::{
    direct_receptance, modal_receptance, static_residual, try_direct_receptance,
    try_modal_receptance, DirectFrf, FrfError,
};

fn max_rel(a: &faer::Mat<c64>, b: &faer::Mat<c64>) -> f64 {
    let mut e = 0.0f64;
    for j in 0..a.ncols() {
        for i in 0..a.nrows() {
            e = e.max((a[(i, j)] - b[(i, j)]).norm() / b[(i, j)].norm());
        }
    }
    e
}

fn all_modes(
    k: &frfup::model::SparseMatrix,
    m: &frfup::model::SparseMatrix,
) -> frfup::solvers::eigen::Modes {
    let n = k.nrows();
    lowest_modes(
        k,
        m,
        &EigenOptions {
            count: n,
            dense_limit: n,
            krylov_dofs_per_mode: 0,
            expect_no_rigid_body_modes: false,
            cover_omega2: None,
            grow_to_cover: false,
        },
    )
    .unwrap()
}

#[test]
fn direct_equals_modal_with_all_modes() {
    let (k, m) = eb_beam(30, 1.5, 2.0e3, 1.2, true);
    let modes = all_modes(&k, &m);
    let w1 = modes.omega2[0].sqrt();
    let omegas: Vec<f64> = (1..60).map(|i| 0.137 * i as f64 * w1).collect();
    let outputs = [0, 7, 20, k.nrows() - 2];
    let input = k.nrows() - 2;
    for damping in [
        Damping::None,
        Damping::Rayleigh {
            alpha: 0.5,
            beta: 1e-5,
        },
        Damping::Hysteretic { eta: 0.02 },
    ] {
        let d = try_direct_receptance(&k, &m, damping, &omegas, input, &outputs).unwrap();
        let s = modal_receptance(&modes, damping, &omegas, input, &outputs);
        let e = max_rel(&s, &d);
        assert!(e < 1e-8, "{damping:?}: {e:e}");
    }
}

#[test]
fn modal_damping_direct_path_uses_all_modes() {
    let (k, m) = chain(40, 1.0e4, 1.0, true);
    let modes = all_modes(&k, &m);
    let omegas: Vec<f64> = (1..50).map(|i| 4.0 * i as f64).collect();
    let damping = Damping::Modal { zeta: 0.03 };
    let d = direct_receptance(&k, &m, damping, &omegas, 39, &[0, 10, 39]);
    let s = modal_receptance(&modes, damping, &omegas, 39, &[0, 10, 39]);
    assert!(max_rel(&d, &s) < 1e-10);
    // Modal damping: the peak at mode r is 1/(2ζω_r²)·φ_jr φ_kr + others.
    assert!(d.col_iter().all(|c| c.iter().all(|v| v.re.is_finite())));
}

#[test]
fn reciprocity() {
    let (k0, m0) = random_pencil(60, 4, 11);
    let (k, m) = (from_dense(&k0), from_dense(&m0));
    let omegas = [0.3, 0.9, 1.7, 2.2];
    let damping = Damping::Rayleigh {
        alpha: 0.01,
        beta: 0.002,
    };
    let h_ij = direct_receptance(&k, &m, damping, &omegas, 5, &[17, 42]);
    let h_ji17 = direct_receptance(&k, &m, damping, &omegas, 17, &[5]);
    let h_ji42 = direct_receptance(&k, &m, damping, &omegas, 42, &[5]);
    for c in 0..omegas.len() {
        assert!((h_ij[(0, c)] - h_ji17[(0, c)]).norm() < 1e-10 * h_ij[(0, c)].norm());
        assert!((h_ij[(1, c)] - h_ji42[(0, c)]).norm() < 1e-10 * h_ij[(1, c)].norm());
    }
}

#[test]
fn undamped_frf_has_poles_at_eigenfrequencies() {
    let (n, kk, mm) = (25, 3.0e3, 0.2);
    let (k, m) = chain(n, kk, mm, true);
    let solver = DirectFrf::new(&k, &m, Damping::None).unwrap();
    for j in [1usize, 2, 5] {
        let w = fixed_free_omega(n, kk, mm, j);
        // |H| grows like 1/|ω − ω_j| approaching the pole from both sides.
        let near = |eps: f64| {
            solver
                .receptance(&[w * (1.0 + eps)], n - 1, &[n - 1])
                .unwrap()[(0, 0)]
                .norm()
        };
        let (a, b) = (near(1e-4), near(1e-6));
        assert!((b / a - 100.0).abs() < 1.0, "mode {j}: {a} {b}");
        let (a, b) = (near(-1e-4), near(-1e-6));
        assert!((b / a - 100.0).abs() < 1.0, "mode {j}: {a} {b}");
        // Sign change across the pole (real, undamped).
        let below = solver
            .receptance(&[w * (1.0 - 1e-6)], n - 1, &[n - 1])
            .unwrap()[(0, 0)]
            .re;
        let above = solver
            .receptance(&[w * (1.0 + 1e-6)], n - 1, &[n - 1])
            .unwrap()[(0, 0)]
            .re;
        assert!(below * above < 0.0);
    }
}

#[test]
fn residual_improves_truncated_superposition() {
    let (k, m) = eb_beam(60, 2.0, 1.0e4, 3.0, true);
    let n = k.nrows();
    let full = all_modes(&k, &m);
    let few = lowest_modes(
        &k,
        &m,
        &EigenOptions {
            count: 6,
            dense_limit: 0,
            krylov_dofs_per_mode: 0,
            expect_no_rigid_body_modes: true,
            cover_omega2: None,
            grow_to_cover: false,
        },
    )
    .unwrap();
    let w4 = few.omega2[3].sqrt();
    let omegas: Vec<f64> = (1..40).map(|i| w4 * i as f64 / 40.0 * 1.013).collect();
    let outputs = [n - 2, n / 2, 10];
    let damping = Damping::Hysteretic { eta: 0.01 };
    let exact = try_direct_receptance(&k, &m, damping, &omegas, n - 2, &outputs).unwrap();
    let all = modal_receptance(&full, damping, &omegas, n - 2, &outputs);
    // 60 beam elements: κ(K) ≈ 1e10, so the full modal sum carries ~κε.
    let e_all = max_rel(&all, &exact);
    assert!(e_all < 1e-7, "{e_all:e}");
    let plain = try_modal_receptance(&few, damping, &omegas, n - 2, &outputs, None).unwrap();
    let r = static_residual(&k, &m, &few, n - 2, &outputs).unwrap();
    let corrected =
        try_modal_receptance(&few, damping, &omegas, n - 2, &outputs, Some(&r)).unwrap();
    let (e0, e1) = (max_rel(&plain, &exact), max_rel(&corrected, &exact));
    assert!(e1 < 0.2 * e0, "without residual {e0:e}, with {e1:e}");
    // Statically exact: at ω → 0 the corrected sum is K⁻¹ (σ ≈ 0).
    let h0 = try_direct_receptance(&k, &m, Damping::None, &[0.0], n - 2, &outputs).unwrap();
    let c0 = try_modal_receptance(&few, Damping::None, &[0.0], n - 2, &outputs, Some(&r)).unwrap();
    assert!(max_rel(&c0, &h0) < 1e-6);
}

#[test]
fn bad_requests_are_errors() {
    let (k, m) = chain(5, 1.0, 1.0, true);
    assert!(matches!(
        try_direct_receptance(&k, &m, Damping::None, &[1.0], 5, &[0]),
        Err(FrfError::InvalidInput { .. })
    ));
    assert!(matches!(
        try_direct_receptance(&k, &m, Damping::None, &[f64::NAN], 0, &[0]),
        Err(FrfError::InvalidInput { .. })
    ));
    assert!(matches!(
        try_direct_receptance(&k, &m, Damping::Hysteretic { eta: -1.0 }, &[1.0], 0, &[0]),
        Err(FrfError::InvalidInput { .. })
    ));
    let h = direct_receptance(&k, &m, Damping::None, &[1.0], 9, &[0]);
    assert!(h[(0, 0)].re.is_nan());
}
