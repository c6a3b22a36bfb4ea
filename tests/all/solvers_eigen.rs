//! Eigen solver against closed forms and an independent dense reference.
//!
//! Tolerances: closed-form chain/beam frequencies are exact for the discrete
//! models, so ω² agrees to ~1e-10 relative (a few hundred ε times the
//! condition of the pencil); mass normalisation to 1e-9; dense and sparse
//! paths to 1e-9 relative in ω² (both Rayleigh quotients of converged
//! vectors).

use crate::solvers_support::*;
use frfup::solvers::eigen::{
    lowest_modes, lowest_modes_with, EigenError, EigenOptions, EigenPath, EigenTuning,
};

fn opts(count: usize, dense: bool, fixed: bool) -> EigenOptions {
    EigenOptions {
        count,
        dense_limit: if dense { usize::MAX } else { 0 },
        krylov_dofs_per_mode: 0,
        expect_no_rigid_body_modes: fixed,
        cover_omega2: None,
        grow_to_cover: false,
    }
}

#[test]
fn fixed_free_chain_matches_closed_form_both_paths() {
    let (n, k, m) = (300, 1.0e4, 0.5);
    let (kk, mm) = chain(n, k, m, true);
    for dense in [true, false] {
        let modes = lowest_modes(&kk, &mm, &opts(20, dense, true)).unwrap();
        assert_eq!(modes.len(), 20);
        for j in 0..20 {
            let exact = fixed_free_omega(n, k, m, j + 1).powi(2);
            let rel = (modes.omega2[j] - exact).abs() / exact;
            assert!(
                rel < 1e-10,
                "dense={dense} mode {j}: {} vs {exact} ({rel:e})",
                modes.omega2[j]
            );
        }
        assert!(mass_orthonormality_error(&mm, &modes.shapes) < 1e-9);
    }
}

/// A chain numbered by a stride permutation (every neighbour 37 positions
/// away: the envelope spans the whole matrix) is renumbered internally by the
/// dense path; frequencies still match the closed form to 1e-10 and each mode
/// shape, read back in the scrambled numbering, equals the well numbered
/// chain's shape (up to sign) to 1e-9: a wrong un-permutation would fail.
#[test]
fn scrambled_numbering_gives_the_same_modes_on_the_dense_path() {
    let (n, k, m) = (301, 1.0e4, 0.5);
    let (kk, mm) = chain(n, k, m, true);
    let label = |i: usize| (i * 37) % n;
    let relabel = |a: &frfup::model::SparseMatrix| {
        let mut t = Vec::new();
        for j in 0..n {
            let rows = a.symbolic().row_idx_of_col_raw(j);
            for (&i, &v) in rows.iter().zip(a.val_of_col(j)) {
                t.push(faer::sparse::Triplet::new(label(i), label(j), v));
            }
        }
        faer::sparse::SparseColMat::try_new_from_triplets(n, n, &t).unwrap()
    };
    let (ks, ms) = (relabel(&kk), relabel(&mm));
    let plain = lowest_modes(&kk, &mm, &opts(15, true, true)).unwrap();
    let scrambled = lowest_modes(&ks, &ms, &opts(15, true, true)).unwrap();
    for j in 0..15 {
        let exact = fixed_free_omega(n, k, m, j + 1).powi(2);
        let rel = (scrambled.omega2[j] - exact).abs() / exact;
        assert!(rel < 1e-10, "mode {j}: {rel:e}");
        let sign = (0..n)
            .map(|i| plain.shapes[(i, j)] * scrambled.shapes[(label(i), j)])
            .sum::<f64>()
            .signum();
        let worst = (0..n)
            .map(|i| (plain.shapes[(i, j)] - sign * scrambled.shapes[(label(i), j)]).abs())
            .fold(0.0, f64::max);
        let size = (0..n)
            .map(|i| plain.shapes[(i, j)].abs())
            .fold(0.0, f64::max);
        assert!(worst < 1e-9 * size, "mode {j}: shape differs by {worst:e}");
    }
    assert!(mass_orthonormality_error(&ms, &scrambled.shapes) < 1e-9);
}

#[test]
fn free_free_chain_gives_rigid_body_mode_not_error() {
    let (n, k, m) = (200, 2.0e6, 1.5);
    let (kk, mm) = chain(n, k, m, false);
    let scale = k / m;
    for dense in [true, false] {
        let modes = lowest_modes(&kk, &mm, &opts(10, dense, false)).unwrap();
        // Rigid-body ω² is zero up to rounding relative to the stiffness scale.
        assert!(
            modes.omega2[0].abs() < 1e-10 * scale,
            "dense={dense}: {}",
            modes.omega2[0]
        );
        for j in 1..10 {
            let exact = free_free_omega(n, k, m, j + 1).powi(2);
            let rel = (modes.omega2[j] - exact).abs() / exact;
            assert!(rel < 1e-9, "dense={dense} mode {j}: {rel:e}");
        }
        assert!(mass_orthonormality_error(&mm, &modes.shapes) < 1e-9);
        // The rigid-body mode is uniform translation, mass-normalised: 1/√(n m).
        let v = 1.0 / ((n as f64) * m).sqrt();
        for i in 0..n {
            assert!((modes.shapes[(i, 0)].abs() - v).abs() < 1e-6 * v);
        }
    }
}

#[test]
fn mechanisms_are_counted_when_model_is_fixed() {
    // Grounded chain with the spring between masses 9 and 10 missing: masses
    // 10.. float freely → one zero-energy mode. Another break → two.
    let n = 60;
    for (breaks, expected) in [(vec![9], 1usize), (vec![9, 30], 2)] {
        let mut ke = vec![(0, 0, 1.0e5)];
        for i in 0..n - 1 {
            if breaks.contains(&i) {
                continue;
            }
            ke.push((i, i, 1.0e5));
            ke.push((i + 1, i + 1, 1.0e5));
            ke.push((i, i + 1, -1.0e5));
        }
        let kk = sym(n, &ke);
        let mm = sym(n, &(0..n).map(|i| (i, i, 2.0)).collect::<Vec<_>>());
        for dense in [true, false] {
            match lowest_modes(&kk, &mm, &opts(8, dense, true)) {
                Err(EigenError::Mechanisms { count, .. }) => {
                    assert_eq!(count, expected, "dense={dense}")
                }
                other => panic!("dense={dense}: expected mechanisms, got {other:?}"),
            }
            // The same model without the "fixed" flag returns the zero modes.
            let modes = lowest_modes(&kk, &mm, &opts(8, dense, false)).unwrap();
            assert!(modes.omega2[expected - 1].abs() < 1e-10 * 5.0e4);
            assert!(modes.omega2[expected] > 1e-6 * 5.0e4);
        }
    }
}

#[test]
fn cantilever_beam_matches_euler_bernoulli() {
    // 60 cubic elements: discretisation error of the first modes < 1e-8.
    let (len, ei, rho_a) = (2.0, 2.1e11 * 1e-8, 7850.0 * 1e-4);
    let (kk, mm) = eb_beam(60, len, ei, rho_a, true);
    let beta_l = [
        1.875_104_068_711_961,
        4.694_091_132_974_175,
        7.854_757_438_237_613,
    ];
    for dense in [true, false] {
        let modes = lowest_modes(&kk, &mm, &opts(3, dense, true)).unwrap();
        for (j, bl) in beta_l.iter().enumerate() {
            let exact = (bl / len).powi(4) * ei / rho_a;
            let rel = (modes.omega2[j] - exact).abs() / exact;
            assert!(rel < 1e-6, "dense={dense} mode {j}: {rel:e}");
        }
    }
}

#[test]
fn free_free_beam_has_two_rigid_modes_and_dense_sparse_agree() {
    let (kk, mm) = eb_beam(80, 3.0, 5.0e4, 2.0, false);
    let d = lowest_modes(&kk, &mm, &opts(12, true, false)).unwrap();
    let s = lowest_modes(&kk, &mm, &opts(12, false, false)).unwrap();
    let scale = d.omega2[11];
    for j in 0..12 {
        assert!(
            (d.omega2[j] - s.omega2[j]).abs() < 1e-9 * scale,
            "mode {j}: {} vs {}",
            d.omega2[j],
            s.omega2[j]
        );
    }
    assert!(d.omega2[1].abs() < 1e-9 * scale && d.omega2[2] > 1e-6 * scale);
    // Elastic shapes agree up to sign (rigid pair only up to rotation).
    for j in 2..12 {
        let dot: f64 = (0..kk.nrows())
            .map(|i| d.shapes[(i, j)] * s.shapes[(i, j)])
            .sum::<f64>();
        let nd: f64 = (0..kk.nrows())
            .map(|i| d.shapes[(i, j)].powi(2))
            .sum::<f64>();
        assert!((dot.abs() / nd - 1.0).abs() < 1e-7, "mode {j}");
    }
    assert!(mass_orthonormality_error(&mm, &s.shapes) < 1e-9);
}

#[test]
fn random_pencils_match_dense_reference() {
    for (n, band, seed) in [(40, 3, 1u64), (150, 6, 7), (400, 10, 42)] {
        let (k, m) = random_pencil(n, band, seed);
        let reference = reference_eigenvalues(&k, &m);
        let (kk, mm) = (from_dense(&k), from_dense(&m));
        let count = 25.min(n);
        for dense in [true, false] {
            let modes = lowest_modes(&kk, &mm, &opts(count, dense, true)).unwrap();
            for (j, (&got, &want)) in modes.omega2.iter().zip(&reference).take(count).enumerate() {
                let rel = (got - want).abs() / want;
                assert!(rel < 1e-9, "n={n} dense={dense} mode {j}: {rel:e}");
            }
            assert!(mass_orthonormality_error(&mm, &modes.shapes) < 1e-9);
        }
        // All modes by the dense path.
        let all = lowest_modes(&kk, &mm, &opts(n, true, true)).unwrap();
        for j in 0..n {
            assert!((all.omega2[j] - reference[j]).abs() < 1e-9 * reference[n - 1]);
        }
    }
}

#[test]
fn sparse_path_report_and_small_dimension_edge_cases() {
    // count ≥ n and a tiny model on the sparse path (Krylov space = whole space).
    let (kk, mm) = chain(5, 1.0, 1.0, true);
    let (modes, report) =
        lowest_modes_with(&kk, &mm, &opts(10, false, true), &EigenTuning::default()).unwrap();
    assert_eq!(report.path, EigenPath::Sparse);
    assert_eq!(modes.len(), 5);
    for j in 0..5 {
        let exact = fixed_free_omega(5, 1.0, 1.0, j + 1).powi(2);
        assert!((modes.omega2[j] - exact).abs() < 1e-12);
    }
    // σ may move up towards ω²₁ (fixed model) but stays below it.
    assert!(report.shift < modes.omega2[0]);
    let empty = lowest_modes(&kk, &mm, &opts(0, false, true)).unwrap();
    assert!(empty.is_empty());
}

#[test]
fn bad_input_is_an_error_not_a_panic() {
    let (kk, _) = chain(5, 1.0, 1.0, true);
    let (_, m4) = chain(4, 1.0, 1.0, true);
    assert!(matches!(
        lowest_modes(&kk, &m4, &opts(2, true, true)),
        Err(EigenError::InvalidInput { .. })
    ));
    let m0 = sym(
        5,
        &[
            (0, 0, 1.0),
            (1, 1, 1.0),
            (2, 2, 0.0),
            (3, 3, 1.0),
            (4, 4, 1.0),
        ],
    );
    assert!(matches!(
        lowest_modes(&kk, &m0, &opts(2, false, true)),
        Err(EigenError::MassNotPositive { .. })
    ));
    let knan = sym(5, &[(0, 0, f64::NAN)]);
    assert!(matches!(
        lowest_modes(&knan, &m0, &opts(2, true, true)),
        Err(EigenError::InvalidInput { .. })
    ));
}

#[test]
fn clustered_spectrum_auto_shift_matches_dense() {
    // Beam on a stiff elastic foundation: the lowest modes cluster just above
    // k_f/ρA, the case the automatic shift (σ moved up below ω²₁) is for.
    let (kb, mm) = eb_beam(150, 3.0, 50.0, 2.0, false);
    let n = kb.nrows();
    let mut extra: Vec<(usize, usize, f64)> = (0..n).step_by(2).map(|i| (i, i, 4.0e4)).collect();
    let sym_k = {
        let d = kb.to_dense();
        for j in 0..n {
            for i in 0..=j {
                if d[(i, j)] != 0.0 {
                    extra.push((i, j, d[(i, j)]));
                }
            }
        }
        sym(n, &extra)
    };
    let d = lowest_modes(&sym_k, &mm, &opts(30, true, true)).unwrap();
    let (s, report) =
        lowest_modes_with(&sym_k, &mm, &opts(30, false, true), &EigenTuning::default()).unwrap();
    assert!(report.shift > 0.0 && report.shift < d.omega2[0]);
    for j in 0..30 {
        let rel = (d.omega2[j] - s.omega2[j]).abs() / d.omega2[j];
        assert!(rel < 1e-10, "mode {j}: {rel:e}");
    }
    // A fixed negative shift (no auto shift) gives the same modes.
    let fixed = EigenTuning {
        shift: Some(-1.0),
        ..EigenTuning::default()
    };
    let (f, rf) = lowest_modes_with(&sym_k, &mm, &opts(30, false, true), &fixed).unwrap();
    assert_eq!(rf.shift, -1.0);
    for j in 0..30 {
        assert!((d.omega2[j] - f.omega2[j]).abs() / d.omega2[j] < 1e-10);
    }
}

/// With default options the path follows the model size and the count: a
/// 1,500-DOF chain wanting 20 modes (75 DOFs per mode) takes the Krylov path,
/// 100 modes of it (15 per mode) and 20 of a 900-DOF chain (below
/// `KRYLOV_MIN_DOFS`) the dense one. Either way ω² match the closed form to
/// 1e-10 relative, as on the 300-DOF chain above.
#[test]
fn few_modes_of_a_mid_size_model_take_the_krylov_path() {
    let (k, m) = (1.0e4, 0.5);
    for (n, count, path) in [
        (1500, 20, EigenPath::Sparse),
        (1500, 100, EigenPath::Dense),
        (900, 20, EigenPath::Dense),
    ] {
        let (kk, mm) = chain(n, k, m, true);
        let options = EigenOptions {
            count,
            expect_no_rigid_body_modes: true,
            ..EigenOptions::default()
        };
        let (modes, report) =
            lowest_modes_with(&kk, &mm, &options, &EigenTuning::default()).unwrap();
        assert_eq!(report.path, path, "n = {n}, {count} modes");
        for j in 0..count {
            let exact = fixed_free_omega(n, k, m, j + 1).powi(2);
            let rel = (modes.omega2[j] - exact).abs() / exact;
            assert!(rel < 1e-10, "n = {n} mode {j}: {rel:e}");
        }
        assert!(mass_orthonormality_error(&mm, &modes.shapes) < 1e-9);
    }
}

/// The GARTEUR-like deck has short, stiff elements with little rotary inertia:
/// its largest K_ii/M_ii is ~4e5 times the median. The sparse path's σ₀ is then
/// −1e-4·median, not −1e-8·max (which is far below the first elastic ω² and
/// makes all μ = 1/(ω² − σ) alike): the same 39 modes (to 1e-9 of ω²₃₉) with
/// at most 90 % of the operator applications that σ = −1e-8·max needs (136
/// against 176 when this was written).
#[test]
fn free_free_sparse_shift_starts_near_the_spectrum() {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/fixtures/garteur/garteur.deck"
    ))
    .unwrap();
    let deck = frfup::parsers::deck::parse(&text).unwrap();
    let fe = frfup::model::build(&deck, &Default::default()).unwrap();
    let (kk, mm) = (&fe.stiffness, &fe.mass);
    let n = kk.nrows();
    let diag = |a: &frfup::model::SparseMatrix, i: usize| {
        let rows = a.symbolic().row_idx_of_col_raw(i);
        rows.iter()
            .zip(a.val_of_col(i))
            .filter(|(r, _)| **r == i)
            .map(|(_, v)| *v)
            .sum::<f64>()
    };
    let mut ratios: Vec<f64> = (0..n).map(|i| diag(kk, i) / diag(mm, i)).collect();
    ratios.sort_by(f64::total_cmp);
    let (max, median) = (ratios[n - 1], ratios[n / 2]);
    assert!(max > 1e4 * median, "max/median = {:e}", max / median);

    let (auto, report) =
        lowest_modes_with(kk, mm, &opts(39, false, false), &EigenTuning::default()).unwrap();
    assert_eq!(report.path, EigenPath::Sparse);
    assert!(
        (report.initial_shift + 1e-4 * median).abs() <= 1e-12 * 1e-4 * median,
        "σ₀ = {:e}, −1e-4·median = {:e}",
        report.initial_shift,
        -1e-4 * median
    );
    let far = EigenTuning {
        shift: Some(-1e-8 * max),
        ..EigenTuning::default()
    };
    let (reference, far_report) = lowest_modes_with(kk, mm, &opts(39, false, false), &far).unwrap();
    let top = reference.omega2[38];
    for j in 0..39 {
        assert!(
            (auto.omega2[j] - reference.omega2[j]).abs() <= 1e-9 * top,
            "mode {j}: {} vs {}",
            auto.omega2[j],
            reference.omega2[j]
        );
    }
    assert!(
        10 * report.operator_applications <= 9 * far_report.operator_applications,
        "{} applications from σ₀, {} from −1e-8·max",
        report.operator_applications,
        far_report.operator_applications
    );
}

/// The n × n plate-like frame lattice of `scripts/gen_lattice.py plate n`:
/// 6n² free DOFs over a fixed layer, a spectrum with many close and double
/// modes.
fn plate_lattice(n: usize) -> frfup::model::FeModel {
    let mut deck = String::from(
        "title plate lattice\nanalysis space\nmaterial steel E=210e9 rho=7850 nu=0.3\n\
         section sq10 A=0.0001 Iy=8.33333e-10 Iz=8.33333e-10 J=1.406e-09\n",
    );
    let id = |i: usize, j: usize| 1 + i * n + j;
    let base = n * n;
    for layer in [0.0, -0.1] {
        for i in 0..n {
            for j in 0..n {
                let offset = if layer < 0.0 { base } else { 0 };
                deck += &format!(
                    "node {} {} {} {layer}\n",
                    offset + id(i, j),
                    i as f64 * 0.1,
                    j as f64 * 0.1
                );
            }
        }
    }
    let mut e = 0;
    for i in 0..n {
        for j in 0..n {
            let mut beam = |a: usize, b: usize| {
                e += 1;
                deck += &format!("beam {e} {a} {b} steel sq10\n");
            };
            if i + 1 < n {
                beam(id(i, j), id(i + 1, j));
            }
            if j + 1 < n {
                beam(id(i, j), id(i, j + 1));
            }
            beam(base + id(i, j), id(i, j));
        }
    }
    for k in 1..=base {
        deck += &format!("fix {} all\n", base + k);
    }
    let deck = frfup::parsers::deck::parse(&deck).unwrap();
    frfup::model::build(&deck, &Default::default()).unwrap()
}

/// 100 modes of the 14 × 14 lattice (1,176 DOF) by the Krylov path. With the
/// shift moved up to just below ω²₁, θ₁/θ₁₀₀ is large and the smallest wanted
/// Ritz pairs stall at the rounding floor of the Krylov relation, above
/// tol·θ_i: with a tolerance relative to θ_i only, pairs dropped in and out
/// of convergence across restarts (16 restarts, 1,256 operator
/// applications); with the floor at 2e4 ε θ₁, 4 and 488 when written. The
/// modes still match the dense path: ω² to 1e-9 relative.
#[test]
fn many_modes_by_krylov_do_not_stall_at_the_rounding_floor() {
    let fe = plate_lattice(14);
    let (kk, mm) = (&fe.stiffness, &fe.mass);
    let dense = lowest_modes(kk, mm, &opts(100, true, true)).unwrap();
    let (krylov, report) =
        lowest_modes_with(kk, mm, &opts(100, false, true), &EigenTuning::default()).unwrap();
    assert_eq!(report.path, EigenPath::Sparse);
    assert!(
        report.restarts <= 8,
        "{} restarts, {} applications",
        report.restarts,
        report.operator_applications
    );
    for j in 0..100 {
        let rel = (krylov.omega2[j] - dense.omega2[j]).abs() / dense.omega2[j];
        assert!(rel < 1e-9, "mode {j}: {rel:e}");
    }
    // The final Rayleigh–Ritz on M (lanczos::ShiftedCholesky::rayleigh_ritz)
    // keeps the shapes M-orthonormal (8e-15 when written; 1e-7 without it).
    assert!(mass_orthonormality_error(mm, &krylov.shapes) < 1e-12);
    // Pairs accepted at the rounding floor: residuals ‖Kφ − ω²Mφ‖/(s_max‖Mφ‖)
    // up to 4.6e-8 when written; the dense path's are ~1e-15.
    assert!(report.max_residual < 1e-6, "{:e}", report.max_residual);
}

/// A model the dense path could take falls back to it when the Krylov path
/// gives up: here after its first restart (`max_restarts: 0`), for 20 modes
/// of a 1,500-DOF chain (which needs restarts with the default basis). The
/// modes are the dense path's, to the closed form as above.
#[test]
fn krylov_failure_on_a_dense_size_model_falls_back_to_dense() {
    let (n, k, m) = (1500, 1.0e4, 0.5);
    let (kk, mm) = chain(n, k, m, true);
    let options = EigenOptions {
        count: 20,
        expect_no_rigid_body_modes: true,
        ..EigenOptions::default()
    };
    let (_, krylov) = lowest_modes_with(&kk, &mm, &options, &EigenTuning::default()).unwrap();
    assert_eq!(krylov.path, EigenPath::Sparse);
    assert!(krylov.restarts >= 1, "no restart: the test would not test");
    let no_restarts = EigenTuning {
        max_restarts: 0,
        ..EigenTuning::default()
    };
    let (modes, report) = lowest_modes_with(&kk, &mm, &options, &no_restarts).unwrap();
    assert_eq!(report.path, EigenPath::Dense);
    for j in 0..20 {
        let exact = fixed_free_omega(n, k, m, j + 1).powi(2);
        assert!((modes.omega2[j] - exact).abs() / exact < 1e-10, "mode {j}");
    }
    // A model above dense_limit has no fallback: the error comes through.
    let sparse_only = EigenOptions {
        dense_limit: 0,
        ..options
    };
    assert!(matches!(
        lowest_modes_with(&kk, &mm, &sparse_only, &no_restarts),
        Err(EigenError::NoConvergence { .. })
    ));
}

/// A growing cover (`grow_to_cover`) gives in one solution the modes a
/// caller doubling its count would get: on a 300-mass fixed–free chain with
/// ω²_top between the 56th and 57th closed-form modes, 40 asked give the 57
/// modes up to it and the one above, the same bits as asking 80 with the
/// cover (the caller's second solution); on a 60-mass chain whose 50 modes
/// lie below ω²_top, every mode, the same bits as asking 60 without a cover.
/// Without growth the 40 asked.
#[test]
fn a_growing_cover_solves_once_what_doubling_the_count_would() {
    let (k, m) = (1.0e4, 0.5);
    let cases = [(300, 56, 57, 80, true), (60, 50, 60, 60, false)];
    for (n, below, expect, again, cover_again) in cases {
        let (kk, mm) = chain(n, k, m, true);
        let w = |j: usize| fixed_free_omega(n, k, m, j).powi(2);
        let top = 0.5 * (w(below) + w(below + 1));
        let with = |count: usize, cover: bool, grow: bool| {
            let o = EigenOptions {
                cover_omega2: cover.then_some(top),
                grow_to_cover: grow,
                ..opts(count, true, true)
            };
            lowest_modes(&kk, &mm, &o).unwrap()
        };
        let grown = with(40, true, true);
        assert_eq!(grown.len(), expect, "n = {n}");
        let doubled = with(again, cover_again, false);
        assert_eq!(doubled.len(), expect, "n = {n}");
        assert_eq!(grown.omega2, doubled.omega2, "n = {n}");
        assert!(grown.shapes == doubled.shapes, "n = {n}: shapes differ");
        assert_eq!(with(40, true, false).len(), 40, "n = {n}");
    }
}
