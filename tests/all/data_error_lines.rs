//! The line-by-line channel checks (`diagnosis::data_errors::lines`): each
//! measured FRF against a deck's prediction, and the diagnosis that runs
//! them after the modal checks.
//!
//! The prediction is that of each fixture's truth deck (what an update that
//! succeeded gives), so a clean campaign must be judged sound channel by
//! channel, and a corrupted one must show exactly its corruption.

use std::path::Path;

use faer::c64;
use frfup::diagnosis::data::TestData;
use frfup::diagnosis::data_errors::lines::{line_ratio, reconcile, verdicts, Verdict};
use frfup::diagnosis::data_errors::{DataError, DataErrorKind};
use frfup::diagnosis::fit::{modal_model, predict, Mask};
use frfup::model::Damping;
use frfup::testdata::MeasuredFrfs;

const CASES: [&str; 4] = ["control_beam", "control_portal", "joint", "two_effects"];

fn fixture(case: &str, which: &str) -> (frfup::parsers::deck::Deck, MeasuredFrfs) {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures/diagnose");
    let text = std::fs::read_to_string(root.join(format!("{case}.{which}deck"))).unwrap();
    let deck = frfup::parsers::deck::parse(&text).unwrap();
    (
        deck,
        frfup::testdata::load(&root.join(format!("{case}.uff"))).unwrap(),
    )
}

/// The truth deck's FRFs at the campaign's channels and lines.
fn truth_prediction(case: &str, data: &TestData) -> Vec<Vec<c64>> {
    let (truth, _) = fixture(case, "truth.");
    let mm = modal_model(&truth, data).unwrap();
    predict(&mm, Damping::of_deck(&truth), data, &Mask::all(data))
}

fn judged(case: &str, corrupt: impl Fn(&mut MeasuredFrfs)) -> (Vec<Verdict>, usize) {
    let (_, mut test) = fixture(case, "");
    let clean = TestData::new(&test).unwrap();
    let model = truth_prediction(case, &clean);
    corrupt(&mut test);
    let data = TestData::new(&test).unwrap();
    let n = data.channels.len();
    (verdicts(&data, &model, &vec![true; n]), n)
}

fn wrong(v: &[Verdict]) -> Vec<(usize, DataErrorKind)> {
    v.iter()
        .enumerate()
        .filter_map(|(c, v)| match v {
            Verdict::Wrong(k) => Some((c, k.clone())),
            _ => None,
        })
        .collect()
}

#[test]
fn a_clean_campaign_is_sound_on_every_channel_with_lines() {
    for case in CASES {
        let (v, n) = judged(case, |_| {});
        assert!(wrong(&v).is_empty(), "{case}: {v:?}");
        let sound = v.iter().filter(|v| **v == Verdict::Sound).count();
        // Every channel of these campaigns has lines above its noise.
        assert_eq!(sound, n, "{case}: {v:?}");
    }
}

#[test]
fn two_wrong_channels_are_each_found() {
    for case in CASES {
        let (v, n) = judged(case, |t| {
            let last = t.channels.len() - 1;
            t.channels[0].values.iter_mut().for_each(|z| *z = -*z);
            t.channels[last]
                .values
                .iter_mut()
                .for_each(|z| *z *= 9.80665);
        });
        let found = wrong(&v);
        assert_eq!(found.len(), 2, "{case}: {found:?}");
        assert!(
            matches!(found[0], (0, DataErrorKind::Reversed { agreement, .. }) if agreement < -0.9)
        );
        assert!(
            matches!(found[1], (c, DataErrorKind::Scale { factor, unit: Some(_) })
                if c == n - 1 && factor == 9.80665),
            "{case}: {found:?}"
        );
    }
}

#[test]
fn a_swapped_pair_is_found_whole() {
    for case in CASES {
        let (v, n) = judged(case, |t| {
            let (a, b) = (0, t.channels.len() / 2);
            let va = t.channels[a].values.clone();
            t.channels[a].values = t.channels[b].values.clone();
            t.channels[b].values = va;
        });
        let b = n / 2;
        assert_eq!(
            wrong(&v),
            vec![
                (0, DataErrorKind::Swapped { other: b }),
                (b, DataErrorKind::Swapped { other: 0 })
            ],
            "{case}"
        );
    }
}

#[test]
fn the_ratio_reads_gain_spread_and_opposition() {
    // H_test = −g·H_model on 30 lines: ln g, no spread, all opposed; the
    // misfit w²(ln²g + π²) with w = 2.
    let model: Vec<c64> = (1..=30).map(|k| c64::new(1.0 / k as f64, 0.3)).collect();
    let test: Vec<c64> = model.iter().map(|z| z * -3.0).collect();
    let r = line_ratio(&test, &model, &[2.0; 30]).unwrap();
    assert!((r.log_gain - 3f64.ln()).abs() < 1e-12);
    assert!(r.spread < 1e-12);
    assert_eq!(r.opposed, 1.0);
    let pi = std::f64::consts::PI;
    assert!((r.misfit - 4.0 * (3f64.ln().powi(2) + pi * pi)).abs() < 1e-9);
    // Fewer than 20 weighted lines: no verdict.
    let mut w = [0.0; 30];
    w[..19].iter_mut().for_each(|x| *x = 1.0);
    assert!(line_ratio(&test, &model, &w).is_none());
}

#[test]
fn reconcile_lets_decided_lines_overrule_the_modal_checks() {
    let scale = DataErrorKind::Scale {
        factor: 9.80665,
        unit: Some("g"),
    };
    let reversed = DataErrorKind::Reversed {
        agreement: -1.0,
        over: "its lines above the noise",
    };
    let at = |channel: usize, kind: &DataErrorKind| DataError {
        channel,
        kind: kind.clone(),
    };
    let swap = |a: usize, b: usize| at(a, &DataErrorKind::Swapped { other: b });
    let modal = vec![
        at(0, &DataErrorKind::Dead { snr: 2.0 }),
        at(1, &scale),
        at(2, &scale),
        swap(3, 4),
        swap(4, 3),
        swap(6, 7),
        swap(7, 6),
    ];
    let lines = vec![
        Verdict::Sound,                   // dead stays dead
        Verdict::Sound,                   // the modal scale is overruled
        Verdict::Undecided,               // the modal scale stays
        Verdict::Undecided,               // half a swap...
        Verdict::Wrong(reversed.clone()), // ...(the other reversed) is no swap
        Verdict::Wrong(scale.clone()),    // found by the lines alone
        Verdict::Sound,                   // sound does not overrule a swap
        Verdict::Sound,
    ];
    assert_eq!(
        reconcile(&modal, &lines),
        vec![
            modal[0].clone(),
            modal[2].clone(),
            at(4, &reversed),
            at(5, &scale),
            swap(6, 7),
            swap(7, 6),
        ]
    );
}
