//! The deck's `param` bounds and priors (`min=`, `max=`, `sd=`) in the fits
//! of the deck's parameters that `diagnose` runs besides the update: the
//! polish on all lines (`fit::fit_deck_parameters`) and the joint fits of a
//! hypothesis with the deck's parameters (`diagnosis::refit::Joint`). The
//! `control_portal` fixture: only the deck's parameters are wrong (girder
//! Iy −12 %, columns +8 %, 1 % noise; scripts/gen_diagnose_fixtures.sh).

use std::path::Path;
use std::sync::atomic::AtomicUsize;

use frfup::diagnosis::data::TestData;
use frfup::diagnosis::refit::Joint;
use frfup::model::ParameterValues;
use frfup::parsers::deck::{self, Deck};
use frfup::updating::fullband::fit::{fit_deck_parameters, DampingForm, DampingState, Mask};

fn case(girder_options: &str) -> (Deck, TestData) {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures/diagnose");
    let text = std::fs::read_to_string(dir.join("control_portal.deck")).unwrap();
    let edited = text.replace(
        "param girder Iy 4-8",
        &format!("param girder Iy 4-8 {girder_options}"),
    );
    let deck = deck::parse(&edited).unwrap();
    let test = frfup::testdata::load(&dir.join("control_portal.uff")).unwrap();
    (deck, TestData::new(&test).unwrap())
}

/// The polish from the truth, ζ = 0.01 (the deck's): the girder's value.
fn polished_girder(deck: &Deck, data: &TestData) -> f64 {
    let start: ParameterValues = [("girder".to_string(), -0.12), ("columns".to_string(), 0.08)]
        .into_iter()
        .collect();
    let damp = DampingState {
        form: DampingForm::Modal,
        x: vec![0.01f64.ln()],
    };
    let (values, _, _) = fit_deck_parameters(
        deck,
        &start,
        &damp,
        data,
        &Mask::all(data),
        8,
        &AtomicUsize::new(0),
    )
    .expect("the polish runs");
    values["girder"]
}

#[test]
fn polish_keeps_the_deck_bounds_and_priors() {
    let (deck, data) = case("");
    let free = polished_girder(&deck, &data);
    println!("girder without bound or prior: {free:+.6}");
    assert!((free + 0.12).abs() < 0.001, "girder {free}, truth −0.12");

    // A bound above the truth binds: the value stays on it.
    let (deck, data) = case("min=-0.05");
    let bounded = polished_girder(&deck, &data);
    println!("girder with min=-0.05: {bounded:+.6}");
    assert!((-0.05..-0.0499).contains(&bounded), "girder {bounded}");

    // A prior pulls towards the deck's value, the more the tighter it is,
    // as a linear-Gaussian MAP does: p(s) = p_free·σ⁻²/(σ⁻² + s⁻²) with σ
    // the data's standard deviation of p̄, so each prior implies
    // σ² = s²(p_free/p(s) − 1), and the two priors that move the value
    // measurably (s = 1e-3: −0.3 %, 1e-4: −26 %) must imply the same σ.
    // Measured: 5.65e-5 and 5.89e-5.
    let mut last = free;
    let mut implied = Vec::new();
    for sd in [0.01, 0.001, 0.0001] {
        let (deck, data) = case(&format!("sd={sd}"));
        let g = polished_girder(&deck, &data);
        let sigma = sd * (free / g - 1.0).sqrt();
        println!("girder with sd={sd}: {g:+.6}, implied data sd {sigma:.3e}");
        assert!(
            g < 0.0 && g >= last,
            "sd={sd}: girder {g}, looser prior {last}"
        );
        last = g;
        implied.push(sigma);
    }
    let (a, b) = (implied[1], implied[2]);
    assert!(
        (a / b - 1.0).abs() < 0.08,
        "implied data sd {a:.3e} vs {b:.3e}"
    );
}

/// On a deck updated in memory (as the diagnosis's later fits see it) the
/// prior still pulls towards the value written in the deck, not towards
/// the update's: a dominating prior (sd = 1e-6) brings the girder of the
/// deck updated by the truth (−12 %) back to the written value, +13.6 %
/// of the updated one.
#[test]
fn a_prior_keeps_its_centre_on_an_updated_deck() {
    let (deck, data) = case("sd=1e-6");
    let truth: ParameterValues = [("girder".to_string(), -0.12), ("columns".to_string(), 0.08)]
        .into_iter()
        .collect();
    let updated = frfup::model::updated_deck(&deck, &truth);
    let damp = DampingState {
        form: DampingForm::Modal,
        x: vec![0.01f64.ln()],
    };
    let (values, _, _) = fit_deck_parameters(
        &updated,
        &ParameterValues::new(),
        &damp,
        &data,
        &Mask::all(&data),
        8,
        &AtomicUsize::new(0),
    )
    .expect("the polish runs");
    let centre = 0.12 / 0.88;
    let g = values["girder"];
    println!("girder {g:+.6} on the updated deck, written value at {centre:+.6}");
    assert!(
        (g - centre).abs() < 1e-3 * centre,
        "girder {g}, prior centre {centre}"
    );
}

#[test]
fn joint_fits_take_the_deck_bounds() {
    let (deck, _) = case("min=-0.05 max=0.2");
    let joint = Joint::with_deck_parameters(&deck, Vec::new());
    let (lo, hi) = joint.bounds();
    assert_eq!(joint.deck_params, ["girder", "columns"]);
    assert_eq!((lo, hi), (vec![-0.05, -0.9], vec![0.2, 10.0]));
}
