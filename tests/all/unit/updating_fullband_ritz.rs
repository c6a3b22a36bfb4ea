//! Unit tests of `src/updating/fullband/ritz.rs` through its public interface.

use frfup::model::{self, ParameterValues};
use frfup::updating::fullband::fit::{self, ModalModel};
use frfup::updating::fullband::ritz::RitzBasis;
use frfup_parsers::deck::{parse, Deck};

use super::updating_fullband_reduced::{beam_text_of, long_beam};

/// The long beam of the reduced model's tests with a tip mass and four
/// parameters.
fn beam() -> (Deck, frfup::updating::fullband::data::TestData) {
    long_beam("mass 1 41 m=0.3\nparam left E 1-20\nparam right Iy 21-40\nparam tip m 1\nparam sup k 1-2\n")
}

fn built(deck: &Deck, p: &[f64]) -> model::FeModel {
    let names = model::parameter_names(deck);
    let values: ParameterValues = names.iter().cloned().zip(p.iter().copied()).collect();
    model::build(&model::updated_deck(deck, &values), &ParameterValues::new()).unwrap()
}

/// The elastic modes' ω² (above 1 rad²/s²: the plane model's rigid-body
/// mode along x is round-off).
fn elastic(mm: &ModalModel) -> Vec<f64> {
    mm.omega2.iter().copied().filter(|w| *w > 1.0).collect()
}

/// On its own basis a model's modal model is its full one: the same modes
/// (elastic ω² to 1e-10, coefficients to 1e-8 of the largest: rounding of the
/// Rayleigh–Ritz solve) and the same static residual R0 at every channel
/// (the static responses are in the basis: 1e-6 of the largest). R1 is
/// exact only at the excitation (the channels' second Krylov vectors are
/// not in the basis): there to 1e-6, elsewhere within 20 %.
#[test]
fn a_model_on_its_own_basis_is_its_full_modal_model() {
    let (deck, data) = beam();
    let fe = built(&deck, &[0.0; 4]);
    let sol = fit::modal_solution(&fe, &data).unwrap();
    let basis = RitzBasis::of_solution(&fe, &sol).unwrap();
    let mm = basis.modal_model(&fe).unwrap();
    let full = &sol.model;
    assert_eq!(mm.omega2.len(), full.omega2.len());
    for (a, b) in elastic(&mm).iter().zip(elastic(full)) {
        // The two suspension modes (ω² 31 and 93) carry the full dense
        // solution's rounding on its shifted pencil (1.2e-9 measured).
        let tol = if b < 1e3 { 1e-8 } else { 1e-10 };
        assert!((a - b).abs() <= tol * b, "ω² {a} against {b}");
    }
    let top = full
        .coeff
        .iter()
        .flatten()
        .fold(0.0f64, |a, v| a.max(v.abs()));
    for (ca, cb) in mm.coeff.iter().zip(&full.coeff) {
        for (a, b) in ca.iter().zip(cb) {
            assert!((a - b).abs() <= 1e-8 * top, "coefficient {a} against {b}");
        }
    }
    let r0 = full.residual.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    for (a, b) in mm.residual.iter().zip(&full.residual) {
        assert!((a - b).abs() <= 1e-6 * r0, "R0 {a} against {b}");
    }
    // The last channel is the driving point (node 41).
    let (a, b) = (mm.residual_mass[3], full.residual_mass[3]);
    assert!(
        (a - b).abs() <= 1e-6 * b.abs(),
        "R1 at the excitation {a} against {b}"
    );
    for (a, b) in mm.residual_mass.iter().zip(&full.residual_mass) {
        assert!((a - b).abs() <= 0.2 * b.abs(), "R1 {a} against {b}");
    }
}

/// A model 1e-3 away (each parameter in turn) on the basis of the model
/// at the point: forward differences of the elastic modes' ω² over
/// h = 1e-3 agree with the full models' to 1e-4 of the derivative (the
/// Ritz error at x + h is second order in h, so first order in the
/// difference: 1.8e-5 measured; the diagnosis's steps are 1e-4). The two
/// suspension modes are left out: there the full solutions' rounding
/// (~1e-9 of ω², over h) is what differs. A model with other DOFs is
/// refused.
#[test]
fn nearby_models_on_the_basis_give_the_full_models_differences() {
    let (deck, data) = beam();
    let p0 = [0.1, -0.05, 0.2, 0.0];
    let fe = built(&deck, &p0);
    let basis = RitzBasis::at(&fe, &data).unwrap();
    let at = elastic(&basis.modal_model(&fe).unwrap());
    let full_at = elastic(&fit::modal_solution(&fe, &data).unwrap().model);
    let h = 1e-3;
    for j in 0..p0.len() {
        let mut p = p0;
        p[j] += h;
        let fe_j = built(&deck, &p);
        let ritz = elastic(&basis.modal_model(&fe_j).unwrap());
        let full = elastic(&fit::modal_solution(&fe_j, &data).unwrap().model);
        for r in 2..8 {
            let d_ritz = (ritz[r] - at[r]) / h;
            let d_full = (full[r] - full_at[r]) / h;
            assert!(
                (d_ritz - d_full).abs() <= 1e-4 * d_full.abs(),
                "parameter {j}, mode {r}: {d_ritz} against {d_full}"
            );
        }
    }
    let mut longer = beam_text_of(42);
    longer += "spring 1 1 z k=500\n";
    let other = model::build(&parse(&longer).unwrap(), &ParameterValues::new()).unwrap();
    assert!(basis.modal_model(&other).is_none());
}
