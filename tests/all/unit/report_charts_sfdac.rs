//! Unit tests of `src/report/charts/sfdac.rs` through its public interface.

use crate::unit::report_charts::test_util::assert_svg;
use frfup::report::charts::sfdac::*;
use frfup::report::charts::NamedSeries;

fn sample(n: usize) -> SfdacChart {
    SfdacChart {
        title: "SFDAC at the updating frequencies".into(),
        subtitle: None,
        frequencies_hz: (0..n).map(|i| 5.0 + 7.3 * i as f64).collect(),
        series: vec![
            NamedSeries::new(
                "initial model",
                (0..n).map(|i| ((i as f64) * 0.7).sin()).collect(),
            ),
            NamedSeries::new(
                "updated model",
                (0..n).map(|i| 0.9 - 0.01 * i as f64).collect(),
            ),
        ],
    }
}

#[test]
fn frequency_labels_are_within_a_thousandth_of_their_value() {
    // The demo's first updating frequencies: 2.75 and 6.25 Hz read
    // "2.8" and "6.2" with the one decimal their spacing asks for.
    let labels = frequency_labels(&[2.5, 2.75, 6.25, 7.0, 37.4312]);
    assert_eq!(labels, ["2.50", "2.75", "6.25", "7.00", "37.43"]);
    assert_eq!(frequency_labels(&[10.0, 20.0]), ["10.0", "20.0"]);
}

#[test]
fn has_title_axes_legend_and_is_deterministic() {
    let c = sample(8);
    let a = render(&c).unwrap();
    assert_svg(&a);
    for t in [
        "SFDAC at the updating frequencies",
        "SFDAC_i (dimensionless)",
        "updating frequency (Hz)",
        "initial model (mean",
        "updated model (mean",
        "12.3",
    ] {
        assert!(a.contains(t), "missing {t}");
    }
    assert_eq!(a, render(&c).unwrap());
}

#[test]
fn many_frequencies_rotate_labels() {
    let a = render(&sample(40)).unwrap();
    assert_svg(&a);
    assert!(a.contains("rotate(270"));
}

#[test]
fn odd_data_does_not_panic() {
    assert!(render(&sample(0))
        .unwrap()
        .contains("no updating frequencies"));
    let mut c = sample(3);
    c.series[0].values = vec![f64::NAN, 2.0, -7.0];
    c.series[1].values.clear();
    assert_svg(&render(&c).unwrap());
    let mut c = sample(1);
    c.frequencies_hz = vec![0.0];
    assert_svg(&render(&c).unwrap());
}
