//! The folds of the diagnosis's blocked cross-validation
//! (`diagnosis::select::folds`): every training and validation mask holds
//! weighted data, also when every other channel carries none.

use std::path::Path;

use frfup::diagnosis::data::TestData;
use frfup::diagnosis::fit::Mask;
use frfup::diagnosis::select::folds;

fn data(file: &str) -> TestData {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(file);
    TestData::new(&frfup::testdata::load(&path).unwrap()).unwrap()
}

/// Weighted points of `data` under `mask`.
fn weighted(data: &TestData, mask: &Mask) -> usize {
    (0..data.channels.len())
        .filter(|&c| mask.channels[c])
        .map(|c| {
            (0..data.lines_hz.len())
                .filter(|&l| mask.lines[l] && data.weight[c][l] > 0.0)
                .count()
        })
        .sum()
}

#[test]
fn channels_alternate_by_index_when_both_sides_hold_data() {
    let data = data("fixtures/diagnose/control_portal.uff");
    let nc = data.channels.len();
    assert!(nc >= 4, "the fixture has {nc} channels");
    let f = folds(&data);
    assert_eq!(f.len(), 4, "two line folds and two channel folds");
    let by_index: Vec<bool> = (0..nc).map(|c| c % 2 == 0).collect();
    assert_eq!(f[2].0.channels, by_index);
}

#[test]
fn no_fold_is_empty_when_every_other_channel_carries_nothing() {
    for file in [
        "fixtures/diagnose/control_portal.uff",
        "fixtures/garteur/campaign.uff",
    ] {
        no_empty_fold(data(file));
    }
}

fn no_empty_fold(mut data: TestData) {
    let nc = data.channels.len();
    // Even channels below the noise floor everywhere (a plane frame's axial
    // channels between its transverse ones).
    for c in (0..nc).step_by(2) {
        data.weight[c].iter_mut().for_each(|w| *w = 0.0);
    }
    let live = nc / 2;
    let f = folds(&data);
    let expected = if live < 4 { 2 } else { 4 };
    assert_eq!(f.len(), expected, "{live} weighted channels");
    for (train, val) in &f {
        assert!(weighted(&data, train) > 0, "a training mask without data");
        assert!(weighted(&data, val) > 0, "a validation mask without data");
    }
}

#[test]
fn weighted_channels_in_as_many_directions_as_there_are_still_fill_both_sides() {
    // Four weighted channels, all at odd places, each in its own direction
    // (signed codes: -4 and 4 are one direction): alternation within each
    // direction would put all four on one side.
    let mut data = data("fixtures/garteur/campaign.uff");
    let nc = data.channels.len();
    let kept = [1usize, 3, 5, 7];
    for c in 0..nc {
        if !kept.contains(&c) {
            data.weight[c].iter_mut().for_each(|w| *w = 0.0);
        }
    }
    for (c, d) in kept.iter().zip([1, 2, 3, -4]) {
        data.channels[*c].direction = d;
    }
    let f = folds(&data);
    assert_eq!(f.len(), 4);
    for (train, val) in &f {
        assert!(weighted(&data, train) > 0, "a training mask without data");
        assert!(weighted(&data, val) > 0, "a validation mask without data");
    }
}
