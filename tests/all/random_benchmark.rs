//! The fixed-seed subset of the randomised benchmark (issue 16, item 5):
//! 12 small cases. The generator must be deterministic and every case valid;
//! the library update runs on each and its figures are printed. Only what
//! the default update must converge on all but one case and be within 0.02
//! on all but three (measured: 11 and 9 of 12).

use std::path::Path;
use std::time::Instant;

use frfup::benchmark::{
    case_seed, generate, score_estimates, score_report, Case, GenOptions, LayoutKind,
    ReportEstimate,
};
use frfup::model::{self, ParameterValues};
use frfup::parsers::deck;
use frfup::simulate::{self, Sensors};
use frfup::testdata;
use frfup::updating::{update, UpdateOptions};

const MASTER_SEED: u64 = 16;
const CASES: u64 = 12;

fn cases() -> Vec<Case> {
    (0..CASES)
        .map(|i| generate(case_seed(MASTER_SEED, i), &GenOptions::small()).expect("generate"))
        .collect()
}

/// Read back a case's UFF bytes as the updater would.
fn read_back(case: &Case) -> testdata::MeasuredFrfs {
    let bytes = case.uff_bytes().expect("uff");
    let file = frfup::parsers::uff::parse(&bytes).expect("UFF parses");
    testdata::from_uff(&file, Path::new("test.uff")).expect("FRFs load")
}

#[test]
fn same_seed_same_bytes() {
    for i in [0, 5] {
        let seed = case_seed(MASTER_SEED, i);
        let a = generate(seed, &GenOptions::small()).expect("generate");
        let b = generate(seed, &GenOptions::small()).expect("generate");
        assert_eq!(a.model_deck, b.model_deck);
        assert_eq!(a.truth_deck, b.truth_deck);
        assert_eq!(a.uff_bytes().unwrap(), b.uff_bytes().unwrap());
        assert_eq!(a.truth_json(), b.truth_json());
    }
    let other = generate(case_seed(MASTER_SEED + 1, 0), &GenOptions::small()).unwrap();
    assert_ne!(other.model_deck, cases()[0].model_deck);
}

/// Every case: the decks parse and build, the UFF reads back with one record
/// per point on the case's lines, and the layout is what the case says.
fn check_valid(case: &Case) {
    let model = deck::parse(&case.model_deck).expect("model deck parses");
    let fe = model::build(&model, &ParameterValues::new()).expect("model builds");
    assert_eq!(fe.dofs.len(), case.dofs);
    assert!((2..=6).contains(&case.params.len()));
    assert_eq!(model.params.len(), case.params.len());
    for p in &case.params {
        assert!(p.value.abs() >= 0.03 && p.value.abs() <= 0.4, "{p:?}");
        assert!(p.visibility >= 0.003, "{p:?}");
    }
    deck::parse(&case.truth_deck).expect("truth deck parses");
    assert!(case.noise >= 0.005 && case.noise <= 0.03);
    let frfs = read_back(case);
    assert_eq!(frfs.channels.len(), case.points.len());
    assert_eq!(frfs.frequencies_hz.len(), case.lines_hz.len());
    for (f, g) in frfs.frequencies_hz.iter().zip(&case.lines_hz) {
        assert!((f - g).abs() <= 2e-6 * g.abs(), "{f} vs {g}");
    }
    let last = *case.lines_hz.last().unwrap();
    assert!(case.elastic_modes_hz.iter().all(|f| *f < last));
    for (ch, p) in frfs.channels.iter().zip(&case.points) {
        let (resp, refr) = match case.layout {
            LayoutKind::FixedExciter => (p, &case.fixed),
            LayoutKind::RovingHammer => (&case.fixed, p),
        };
        assert_eq!(
            (ch.response_node, ch.response_direction),
            (resp.node as i64, resp.direction)
        );
        assert_eq!(
            (ch.reference_node, ch.reference_direction),
            (refr.node as i64, refr.direction)
        );
        assert!(ch
            .values
            .iter()
            .all(|v| v.re.is_finite() && v.im.is_finite()));
    }
    if case.layout == LayoutKind::RovingHammer {
        let refs: std::collections::BTreeSet<_> = frfs
            .channels
            .iter()
            .map(|c| (c.reference_node, c.reference_direction))
            .collect();
        assert_eq!(refs.len(), frfs.channels.len(), "every hit point differs");
    }
}

/// A roving-hammer record equals the fixed-exciter record with response and
/// reference swapped (reciprocity), noise-free.
fn check_reciprocity(case: &Case) {
    let truth = deck::parse(&case.truth_deck).unwrap();
    let values: ParameterValues = case
        .params
        .iter()
        .map(|p| (p.name.clone(), p.value))
        .collect();
    let mut row = case.campaign();
    row.noise = 0.0;
    row.response = Some(case.fixed);
    let mut column = row.clone();
    column.response = None;
    column.input = case.points[0];
    column.sensors = Sensors::List(vec![case.fixed]);
    let h_row = simulate::simulate(&truth, &values, &row).unwrap();
    let h_col = simulate::simulate(&truth, &values, &column).unwrap();
    let (a, b) = (&h_row.channels[0].values, &h_col.channels[0].values);
    let scale = a.iter().map(|v| v.norm()).fold(0.0, f64::max);
    for (x, y) in a.iter().zip(b) {
        assert!((x - y).norm() <= 1e-8 * scale, "{x} vs {y}");
    }
}

#[test]
fn fixed_seed_subset() {
    let t = Instant::now();
    let cases = cases();
    let gen_s = t.elapsed().as_secs_f64();
    let mut kinds = std::collections::BTreeSet::new();
    for case in &cases {
        check_valid(case);
        kinds.insert((case.structure, case.layout));
    }
    check_reciprocity(&cases[0]);
    assert!(
        kinds.len() >= 4,
        "the subset covers several kinds: {kinds:?}"
    );
    // Layouts whose driving point was not measured (cases 4, 6, 9).
    assert!(cases.iter().any(|c| !c.driving_point_measured()));
    let (mut within, mut ran, mut errors, mut converged) = (0, 0, 0, 0);
    for (i, case) in cases.iter().enumerate() {
        let model = deck::parse(&case.model_deck).unwrap();
        let test = read_back(case);
        let t = Instant::now();
        let truth: Vec<(String, f64)> = case
            .params
            .iter()
            .map(|p| (p.name.clone(), p.value))
            .collect();
        match update(&model, &test, &UpdateOptions::default()) {
            Ok(r) => {
                ran += 1;
                converged += usize::from(r.converged);
                let est: Vec<ReportEstimate> = r
                    .estimate
                    .as_ref()
                    .expect("the default update ends with the full-band estimate")
                    .parameters
                    .iter()
                    .map(|p| ReportEstimate {
                        name: p.name.clone(),
                        value: p.value,
                        sd: Some(p.sd),
                        identified: p.identified,
                    })
                    .collect();
                let s = score_estimates(&truth, &est);
                within += usize::from(s.within == Some(true));
                println!(
                    "case {i}: {} {} {} dofs {} params {} converged {} max error {:.4} ({:.2} s)",
                    case.structure.name(),
                    case.layout_label(),
                    case.support.name(),
                    case.dofs,
                    case.params.len(),
                    r.converged,
                    s.max_error.unwrap_or(f64::NAN),
                    t.elapsed().as_secs_f64()
                );
            }
            Err(e) => {
                errors += 1;
                println!(
                    "case {i}: {} {}: error {e}",
                    case.structure.name(),
                    case.layout.name()
                );
            }
        }
    }
    println!(
        "random subset: {} cases generated in {gen_s:.2} s; update ran on {ran}, refused {errors}; every parameter within 0.02 on {within}",
        cases.len()
    );
    // Every case runs: none refused.
    assert_eq!(errors, 0);
    assert_eq!(ran, cases.len());
    // Measured when fixed: 11 of 12 converged (case 8 stopped at the
    // estimate's iteration limit), 9 of 12 within 0.02; since a fifth of
    // the layouts lack the driving point (2026-11-28): 12 of 12 converged,
    // 10 within 0.02 (cases 8: 0.083, 11: 0.081; the three without a
    // driving point within 0.015).
    assert!(
        converged == cases.len(),
        "converged on {converged} of {}",
        cases.len()
    );
    assert!(
        within + 2 >= cases.len(),
        "within 0.02 on {within} of {}",
        cases.len()
    );
}

/// A case whose identified parameters are right but whose fit stays far
/// above the noise level (parameters held as not identified, seed 2's case
/// 122 at 386×) is not within; at 4× and below the parameters decide.
#[test]
fn a_fit_far_above_the_noise_level_is_not_within() {
    let truth = vec![("a".to_string(), 0.1), ("b".to_string(), -0.2)];
    let report = |misfit: f64| {
        serde_json::json!({
            "converged": true,
            "estimate": { "misfit_over_noise": misfit },
            "parameter_estimates": [
                { "name": "a", "value": 0.101, "sd": 0.001, "identified": true },
                { "name": "b", "value": 0.0, "sd": 50.0, "identified": false }
            ]
        })
    };
    assert_eq!(score_report(&truth, &report(0.8)).within, Some(true));
    assert_eq!(score_report(&truth, &report(4.0)).within, Some(true));
    let far = score_report(&truth, &report(386.4));
    assert_eq!(far.within, Some(false));
    assert_eq!(far.identified, 1, "b is still not scored as identified");
}
