//! Unit tests of `src/updating/fullband/damping_fit.rs` through its public interface.

use crate::unit::updating_fullband_jacobian::central_difference_error;
use crate::unit::updating_fullband_reduced::{accelerances, beam_text, beam_text_of};
use faer::c64;
use frfup::updating::fullband::fit::{self, DampingForm, DampingState, Mask};
use frfup_parsers::deck::parse;

/// A free-free steel beam 2.4 m long on soft springs (25 nodes, 72 DOFs).
fn long_beam() -> frfup_parsers::deck::Deck {
    let mut text = beam_text_of(25);
    text += "mass 1 25 m=0.2\nspring 1 1 z k=500\nspring 2 25 z k=500\n";
    parse(&text).unwrap()
}

/// The exact damping columns against central differences of the residuals,
/// for each damping form, on a mask that leaves out a channel and every
/// third line (the row order must follow `fit::residuals`). The beam's
/// modal model carries static residual terms, so the hysteretic column
/// includes the derivative of their factor 1/(1 + iη).
#[test]
fn damping_columns_match_central_differences() {
    let deck = long_beam();
    // A band to 150 Hz: the modes above 375 Hz enter as residual terms.
    let lines: Vec<f64> = (1..=150).map(|i| i as f64).collect();
    let data = accelerances(
        &deck,
        lines,
        25,
        &[5, 9, 17, 25],
        0.02,
        c64::new(1.01, 0.005),
    );
    let mm = fit::modal_model(&deck, &data).unwrap();
    assert!(
        mm.residual.iter().any(|r| *r != 0.0),
        "residual terms present"
    );
    let mut mask = Mask::all(&data);
    mask.channels[1] = false;
    for (l, keep) in mask.lines.iter_mut().enumerate() {
        *keep = l % 3 != 0;
    }
    let points = [
        (DampingForm::Modal, vec![0.015f64.ln()]),
        (DampingForm::Rayleigh, vec![3.0f64.ln(), 2e-6f64.ln()]),
        (DampingForm::Hysteretic, vec![0.03f64.ln()]),
    ];
    for (form, x0) in points {
        let r_at = |x: &[f64]| {
            let pred = fit::predict(&mm, form.damping(x), &data, &mask);
            fit::residuals(&pred, &data, &mask)
        };
        let jac = fit::damping_jacobian(&mm, form, &x0, &data, &mask);
        assert_eq!((jac.nrows(), jac.ncols()), (r_at(&x0).len(), x0.len()));
        for j in 0..x0.len() {
            let (err, norm) = central_difference_error(&r_at, &x0, j, jac.col(j), 1e-5);
            // Central differences err by O(h²) ≈ 1e-10 of the column and
            // by rounding ≈ 1e-16/h; exact columns agree far inside 1e-7.
            assert!(
                err <= 1e-7 * norm,
                "{} column {j}: |exact − fd| = {err:e} of {norm:e}",
                form.name()
            );
        }
    }
}

/// The modal damping of accelerances computed directly (no modal
/// truncation, ζ = 0.02), fitted from ζ = 0.05 on the deck's own modal
/// model: ζ to 0.2 % (the static residual terms stand in for the modes
/// above the band, undamped), and its σ is small and finite.
#[test]
fn fit_damping_recovers_the_modal_damping_of_direct_accelerances() {
    let mut text = beam_text();
    text += "mass 1 9 m=0.2\nspring 1 1 z k=500\nspring 2 9 z k=500\n";
    let deck = parse(&text).unwrap();
    let lines: Vec<f64> = (1..=300).map(|i| i as f64 * 2.0).collect();
    let data = accelerances(&deck, lines, 9, &[3, 5, 7, 9], 0.02, c64::new(1.0, 0.0));
    let mm = fit::modal_model(&deck, &data).unwrap();
    let mask = Mask::all(&data);
    let start = DampingState {
        form: DampingForm::Modal,
        x: vec![0.05f64.ln()],
    };
    let (fitted, r) = fit::fit_damping(&mm, &start, &data, &mask, 20);
    let zeta = fitted.x[0].exp();
    assert!((zeta / 0.02 - 1.0).abs() < 2e-3, "ζ = {zeta}");
    let sd = fit::damping_std(&mm, &fitted, &data, &mask);
    assert!(
        sd[0].is_finite() && sd[0] > 0.0 && sd[0] < 0.01,
        "σ(ln ζ) = {}",
        sd[0]
    );
    assert_eq!(
        r.len(),
        fit::residuals(
            &fit::predict(&mm, fitted.damping(), &data, &mask),
            &data,
            &mask
        )
        .len()
    );
}

/// `has_log_ratio` is `log_ratio(..).is_some()` without the logarithm, on
/// ordinary, tiny (subnormal |z|²), huge (|z|² overflowing), zero and
/// non-finite ratios.
#[test]
fn has_log_ratio_is_whether_the_log_ratio_is_defined() {
    use frfup::updating::fullband::fit::{has_log_ratio, log_ratio};
    let values = [
        c64::new(1.5, -0.2),
        c64::new(1e-170, 0.0),
        c64::new(0.0, 1e-200),
        c64::new(1e200, -1e200),
        c64::new(0.0, 0.0),
        c64::new(f64::NAN, 1.0),
        c64::new(1.0, f64::INFINITY),
        c64::new(f64::MIN_POSITIVE, 0.0),
    ];
    let defined: Vec<bool> = values.iter().map(|&z| has_log_ratio(z)).collect();
    let expected: Vec<bool> = values.iter().map(|&z| log_ratio(z).is_some()).collect();
    assert_eq!(defined, expected);
    assert_eq!(defined, [true, true, true, true, false, false, false, true]);
}

/// A deck's Rayleigh damping with one coefficient 0 (proportional to the
/// stiffness or the mass alone) keeps its form: the zero coefficient starts
/// on its lower bound for the band, where its ζ is below 5e-7·ω_hi/ω_lo,
/// and the other keeps its value exactly. Before, such a deck was taken for
/// one without damping and fitted with a constant modal ζ.
#[test]
fn a_rayleigh_deck_with_one_zero_coefficient_keeps_its_form() {
    use frfup::model::Damping;
    let (w_lo, w_hi) = (2.0, 700.0);
    let (lo, _) = DampingForm::Rayleigh.bounds(w_lo, w_hi);
    let stiffness_only = Damping::Rayleigh {
        alpha: 0.0,
        beta: 4.651e-5,
    };
    let (form, x) = DampingForm::of(stiffness_only, w_lo, w_hi).expect("a form");
    assert_eq!(form, DampingForm::Rayleigh);
    assert_eq!(x, vec![lo[0], 4.651e-5f64.ln()]);
    let zeta_alpha = x[0].exp() / (2.0 * w_lo);
    assert!(
        zeta_alpha <= 5e-7 * w_hi / w_lo * (1.0 + 1e-12),
        "ζ_α = {zeta_alpha}"
    );
    let mass_only = Damping::Rayleigh {
        alpha: 3.633,
        beta: 0.0,
    };
    let (_, x) = DampingForm::of(mass_only, w_lo, w_hi).expect("a form");
    assert_eq!(x, vec![3.633f64.ln(), lo[1]]);
    let none = Damping::Rayleigh {
        alpha: 0.0,
        beta: 0.0,
    };
    assert_eq!(DampingForm::of(none, w_lo, w_hi), None);
}

/// `fit::kernel_column` (four lines at a time) is
/// `ModalDampingTerm::at(..).inv()` line by line, bit for bit, for every
/// damping form, over blocks and a tail, at 0 rad/s and on the resonance
/// of an undamped mode (0/0 there, NaN either way).
#[test]
fn kernel_columns_are_the_inverses_line_by_line() {
    use frfup::model::Damping;
    let w2: f64 = 3.7e4;
    let omegas: Vec<f64> = (0..11)
        .map(|i| match i {
            0 => 0.0,
            5 => w2.sqrt(),
            _ => 17.3 * i as f64 + 0.1,
        })
        .collect();
    let forms = [
        Damping::None,
        Damping::Modal { zeta: 0.013 },
        Damping::Rayleigh {
            alpha: 2.1,
            beta: 3.0e-6,
        },
        Damping::Hysteretic { eta: 0.02 },
    ];
    let same = |a: f64, b: f64| a.to_bits() == b.to_bits() || a.is_nan() && b.is_nan();
    for damping in forms {
        let t = damping.modal_term(w2);
        let (mut re, mut im) = (vec![0.0; 11], vec![0.0; 11]);
        fit::kernel_column(w2, t, &omegas, &mut re, &mut im);
        for (j, &w) in omegas.iter().enumerate() {
            let inv = t.at(w2, w).inv();
            assert!(
                same(re[j], inv.re) && same(im[j], inv.im),
                "{damping:?} line {j}: ({}, {}) against ({}, {})",
                re[j],
                im[j],
                inv.re,
                inv.im
            );
        }
    }
}
