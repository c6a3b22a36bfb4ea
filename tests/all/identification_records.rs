//! `frfup::identification` on recorded campaigns: the GARTEUR-like fixture
//! (26 channels, one reference, 0.25–200 Hz, 1.5 % noise) against the modes
//! of the model it was simulated from (`fixtures/garteur/truth.deck` at the
//! parameter values of `truth.json`), a measured roving-hammer record
//! against the closed-form mode series of its structure, and a noisy single
//! FRF in four formats against peak picking.

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

#[test]
fn a_noisy_single_frf_gives_its_two_resonances_in_either_format() {
    // fixtures/uff-real/uffl-jl/dataset58_case{3,7}_{ascii,binary}.unv (see
    // fixtures/uff-real/SOURCES.md): one FRF, 801 lines to 200 Hz, written
    // four ways (complex single and double, ASCII and 58b; the values agree
    // to 2e-11). Two resonances stand about ten times above their
    // surroundings near 22 and 42 Hz, the phase turning through each; above
    // 60 Hz the record is noise larger than either peak. Each mode must be
    // found, within one line (0.25 Hz) of the largest |H| near it (peak
    // picking, a second method), and nothing else. Before the weak modes
    // were eliminated one at a time, the double-precision 58b file gave no
    // mode and its ASCII twin both (their values differ in the last bit).
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures/uff-real/uffl-jl");
    for name in [
        "dataset58_case3_ascii.unv",
        "dataset58_case3_binary.unv",
        "dataset58_case7_ascii.unv",
        "dataset58_case7_binary.unv",
    ] {
        let test = frfup::testdata::load(&dir.join(name)).unwrap();
        let id = identify(&test, &IdentifyOptions::default()).unwrap();
        let found: Vec<f64> = id.modes.iter().map(|m| m.frequency_hz).collect();
        assert_eq!(found.len(), 2, "{name}: {found:?}");
        let h = &test.channels[0].values;
        let f = &test.frequencies_hz;
        for (mode, band) in found.iter().zip([20.0..25.0, 40.0..45.0]) {
            let peak = (0..f.len())
                .filter(|&l| band.contains(&f[l]))
                .max_by(|&a, &b| h[a].norm().total_cmp(&h[b].norm()))
                .map(|l| f[l])
                .unwrap();
            assert!(
                (mode - peak).abs() <= 0.25,
                "{name}: {mode} Hz, peak line {peak} Hz"
            );
        }
    }
}
