//! Unit tests of `src/updating/sensitivity.rs` through its public interface.

use faer::sparse::{SparseColMat, Triplet};
use faer::Mat;
use frfup::model::ParameterSensitivity;
use frfup::model::SparseMatrix;
use frfup::solvers::eigen::Modes;
use frfup::updating::sensitivity::*;
use frfup::updating::serep::InverseMethod;
use frfup::updating::serep::SerepBasis;

fn dense_to_sparse(m: &Mat<f64>) -> SparseMatrix {
    let mut t = Vec::new();
    for j in 0..m.ncols() {
        for i in 0..m.nrows() {
            if m[(i, j)] != 0.0 {
                t.push(Triplet::new(i, j, m[(i, j)]));
            }
        }
    }
    SparseColMat::try_new_from_triplets(m.nrows(), m.ncols(), &t).unwrap()
}

/// Springs k_e between DOFs (ground–0, 0–1, 1–2, 2–3), unit masses; one
/// parameter per spring.
fn chain(k: &[f64]) -> (Mat<f64>, Vec<Mat<f64>>) {
    let n = 4;
    let mut parts = Vec::new();
    for (e, &ke) in k.iter().enumerate() {
        let mut m = Mat::<f64>::zeros(n, n);
        if e == 0 {
            m[(0, 0)] = ke;
        } else {
            m[(e - 1, e - 1)] = ke;
            m[(e, e)] = ke;
            m[(e - 1, e)] = -ke;
            m[(e, e - 1)] = -ke;
        }
        parts.push(m);
    }
    let mut kk = Mat::<f64>::zeros(n, n);
    for p in &parts {
        kk += p;
    }
    (kk, parts)
}

fn modes_of(k: &Mat<f64>) -> Modes {
    // Unit masses: K φ = λ φ.
    let e = k.self_adjoint_eigen(faer::Side::Lower).unwrap();
    let s = e.S().column_vector();
    Modes {
        omega2: (0..k.nrows()).map(|i| s[i]).collect(),
        shapes: e.U().to_owned(),
    }
}

#[test]
fn frf_sensitivity_matches_finite_difference() {
    let kv = [3.0e4, 1.0e4, 2.0e4, 1.5e4];
    let (k, parts) = chain(&kv);
    let modes = modes_of(&k);
    let params: Vec<ParameterSensitivity> = parts
        .iter()
        .enumerate()
        .map(|(j, p)| ParameterSensitivity {
            name: format!("k{j}"),
            dk: dense_to_sparse(p),
            dm: dense_to_sparse(&Mat::zeros(4, 4)),
        })
        .collect();
    let all = [0, 1, 2, 3];
    let basis = SerepBasis::select(&modes, &all, 4, 1e-6).unwrap();
    let sens = ModalSensitivities::project(&params, modes.shapes.as_ref(), &basis.modes);
    // Modal projection equals the dense product.
    let psi = Mat::from_fn(4, 4, |i, k_| modes.shapes[(i, basis.modes[k_])]);
    let dense = psi.transpose() * &parts[2] * &psi;
    for i in 0..4 {
        for j in 0..4 {
            assert!((dense[(i, j)] - sens.dk[2][(i, j)]).abs() < 1e-9);
        }
    }
    // With the full basis and h̄ = current FRF, A p is the first-order change of h.
    let w = 0.5 * modes.omega2[1].sqrt() + 0.5 * modes.omega2[2].sqrt();
    let h0 = basis.modal_receptance(w * w).unwrap();
    let hbar: Vec<f64> = (0..4).map(|e| h0[(e, 3)]).collect();
    // ψ_k at the excitation DOF 3 (measured here: the row of Ψ_m).
    let psi_k: Vec<f64> = (0..basis.len()).map(|k_| basis.psi_m[(3, k_)]).collect();
    let eqs = frf_equations(
        &basis,
        &sens,
        &[w],
        std::slice::from_ref(&hbar),
        &psi_k,
        InverseMethod::Svd,
    )
    .unwrap();
    assert!(eqs.b.iter().all(|x| x.abs() < 1e-12));
    // Exact relation Eq. 4: H_n ΔZ h̄ = h_n − h̄ for h̄ the FRF of the perturbed model.
    let dp = 1e-3;
    let mut k2 = k.clone();
    k2 += &(&parts[1] * faer::Scale(dp));
    let h2 = modes_of(&k2);
    let b2 = SerepBasis::select(&h2, &all, 4, 1e-6).unwrap();
    let hp = b2.modal_receptance(w * w).unwrap();
    let hbar2: Vec<f64> = (0..4).map(|e| hp[(e, 3)]).collect();
    let eqs2 = frf_equations(
        &basis,
        &sens,
        &[w],
        std::slice::from_ref(&hbar2),
        &psi_k,
        InverseMethod::Svd,
    )
    .unwrap();
    for e in 0..4 {
        let lhs = eqs2.a[(e, 1)] * dp;
        assert!(
            (lhs - eqs2.b[e]).abs() < 1e-6 * eqs2.b[e].abs().max(1e-30) + 1e-18,
            "{lhs} {}",
            eqs2.b[e]
        );
    }
    // Perturbed inverse agrees when N_md = N_ex.
    let eqs3 = frf_equations(
        &basis,
        &sens,
        &[w],
        &[hbar2],
        &psi_k,
        InverseMethod::Perturb { relative: 1e-12 },
    )
    .unwrap();
    for e in 0..4 {
        assert!((eqs3.a[(e, 1)] - eqs2.a[(e, 1)]).abs() < 1e-6 * eqs2.a[(e, 1)].abs() + 1e-15);
    }
    // Natural-frequency row: −∂λ/∂p matches a finite difference.
    let (row, b) = frequency_equation(
        &params,
        modes.shapes.as_ref(),
        0,
        modes.omega2[0],
        modes.omega2[0],
    );
    assert_eq!(b, 0.0);
    let dl = (h2.omega2[0] - modes.omega2[0]) / dp;
    assert!((-row[1] - dl).abs() < 1e-2 * dl.abs(), "{} {dl}", -row[1]);
}
