//! `frfup::identification` on recorded campaigns: the GARTEUR-like fixture
//! (26 channels, one reference, 0.25–200 Hz, 1.5 % noise) against the modes
//! of the model it was simulated from (`fixtures/garteur/truth.deck` at the
//! parameter values of `truth.json`), and a measured roving-hammer record
//! against the closed-form mode series of its structure.

use std::path::Path;

use frfup::identification::{identify, IdentifyOptions};
use frfup::model::{self, ParameterValues};
use frfup::solvers::eigen::{lowest_modes, EigenOptions};

#[test]
fn wing_torsion_pair_is_separated() {
    // The wing-torsion pair (36.78 and 37.43 Hz at 1 % damping) is one peak
    // of every FRF, and the diagram stabilises one pole between the two;
    // the split of a merged pole (identification::split) must give both,
    // within the identification's 0.05 % target. Measured: 16 modes, the
    // pair within 0.0015 % and 0.037 %, fit residual 4.78 % (10.4 % while
    // every residue was free in every refinement window, 24.9 % with the
    // pair merged; what remains is the 2.53/2.58 Hz pair, 0.05 Hz apart on
    // 0.25 Hz lines, and weak modes). The third mode of the group, 38.73 Hz,
    // within 1.3e-5 (9.4e-4 then); no mode twice (both merged poles of the
    // group once split one off at 37.42 Hz).
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures/garteur");
    let test = frfup::testdata::load(&root.join("campaign.uff")).unwrap();
    let id = identify(&test, &IdentifyOptions::default()).unwrap();
    let text = std::fs::read_to_string(root.join("truth.deck")).unwrap();
    let deck = frfup::parsers::deck::parse(&text).unwrap();
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(root.join("truth.json")).unwrap()).unwrap();
    let values: ParameterValues = json["parameters"]
        .as_object()
        .unwrap()
        .iter()
        .map(|(k, v)| (k.clone(), v.as_f64().unwrap()))
        .collect();
    let fe = model::build(&deck, &values).unwrap();
    let opts = EigenOptions {
        count: 30,
        ..EigenOptions::default()
    };
    let truth = lowest_modes(&fe.stiffness, &fe.mass, &opts)
        .unwrap()
        .frequencies_hz();
    let pair: Vec<f64> = truth
        .into_iter()
        .filter(|f| (36.0..38.0).contains(f))
        .collect();
    assert_eq!(pair.len(), 2, "{pair:?}");
    for f in &pair {
        let err = id
            .modes
            .iter()
            .map(|m| (m.frequency_hz / f - 1.0).abs())
            .fold(f64::INFINITY, f64::min);
        assert!(err < 5e-4, "{f} Hz: nearest identified mode off by {err:e}");
    }
    let third = truth_near(&fe, 38.0..40.0);
    let err = id
        .modes
        .iter()
        .map(|m| (m.frequency_hz / third - 1.0).abs())
        .fold(f64::INFINITY, f64::min);
    assert!(
        err < 1e-4,
        "{third} Hz: nearest identified mode off by {err:e}"
    );
    // The same mode twice: closer than a quarter of a half-power half-width.
    for (k, a) in id.modes.iter().enumerate() {
        for b in &id.modes[k + 1..] {
            let gap = (a.frequency_hz - b.frequency_hz).abs();
            let half = a.damping_ratio * a.frequency_hz;
            assert!(
                gap > 0.25 * half,
                "{} and {} Hz",
                a.frequency_hz,
                b.frequency_hz
            );
        }
    }
    assert!(id.modes.len() >= 16, "{} modes", id.modes.len());
    assert!(id.relative_residual < 0.06, "{}", id.relative_residual);
}

/// The one natural frequency of `fe` in `band` (Hz).
fn truth_near(fe: &model::FeModel, band: std::ops::Range<f64>) -> f64 {
    let opts = EigenOptions {
        count: 30,
        ..EigenOptions::default()
    };
    let f: Vec<f64> = lowest_modes(&fe.stiffness, &fe.mass, &opts)
        .unwrap()
        .frequencies_hz()
        .into_iter()
        .filter(|f| band.contains(f))
        .collect();
    assert_eq!(f.len(), 1, "{f:?}");
    f[0]
}

#[test]
fn measured_roving_hammer_beam_gives_its_bending_series() {
    // fixtures/uff-real/pyuff/measurement.uff (pyuff's repository, see
    // fixtures/uff-real/SOURCES.md): 3 measured accelerance FRFs, one
    // accelerometer (1+x) and three hit points, 1001 lines to 1000 Hz, very
    // light damping. Fitted as a column by reciprocity. Its modes follow a
    // free-free beam's bending series, f_n = f_1 (β_n L / β_1 L)² with
    // β_n L = 4.7300, 7.8532, 10.9956, 14.1372, 17.2788 (Euler–Bernoulli):
    // every one must be found within 0.5 % of the series scaled to the
    // first (measured: 0.02–0.2 %, the highest lowest from shear and rotary
    // inertia). Fitted as three references (before reciprocity) the third,
    // 278.7 Hz, was missed and the fit residual was 23 %.
    let path =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures/uff-real/pyuff/measurement.uff");
    let test = frfup::testdata::load(&path).unwrap();
    let id = identify(&test, &IdentifyOptions::default()).unwrap();
    assert!(id.data.reciprocal && id.data.n_inputs() == 1);
    let beta = [4.7300f64, 7.8532, 10.9956, 14.1372, 17.2788];
    let f1 = id.modes[0].frequency_hz;
    assert!((f1 - 51.52).abs() < 0.05, "first mode {f1}");
    for b in &beta[1..] {
        let f = f1 * (b / beta[0]).powi(2);
        let err = id
            .modes
            .iter()
            .map(|m| (m.frequency_hz / f - 1.0).abs())
            .fold(f64::INFINITY, f64::min);
        assert!(
            err < 5e-3,
            "bending mode near {f:.1} Hz: nearest off by {err:e}"
        );
    }
    assert!(id.relative_residual < 0.05, "{}", id.relative_residual);
}
