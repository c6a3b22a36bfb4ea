//! Unit tests of `src/report/charts/frequencies.rs` through its public interface.

use crate::unit::report_charts::test_util::assert_svg;
use frfup::report::charts::frequencies::*;

fn sample() -> FrequencyChart {
    let test = [6.376, 16.104, 33.125, 33.531, 35.647];
    FrequencyChart {
        title: "Resonance frequencies: test vs models".into(),
        subtitle: None,
        reference_label: "test".into(),
        model_labels: vec!["initial model".into(), "updated model".into()],
        modes: test
            .iter()
            .enumerate()
            .map(|(i, &f)| ModeFrequencies {
                label: format!("R{}", i + 1),
                reference_hz: f,
                models_hz: vec![Some(f * 1.06), if i == 2 { None } else { Some(f * 0.999) }],
            })
            .collect(),
    }
}

#[test]
fn has_title_axes_legend_and_is_deterministic() {
    let c = sample();
    let a = render(&c).unwrap();
    assert_svg(&a);
    for t in [
        "Resonance frequencies: test vs models",
        "model frequency (Hz, log scale)",
        "test frequency (Hz, log scale)",
        "(%)",
        "initial model (mean |Δf| 6.00 %)",
        "updated model (mean |Δf| 0.10 %): deviation from the test",
        "model = test",
        "±5 %",
        "R5",
        "unpaired",
        "\n10\n",
        "\n20\n",
    ] {
        assert!(a.contains(t), "missing {t}");
    }
    assert_eq!(a, render(&c).unwrap());
    assert!((c.mean_abs_deviation_pct(1).unwrap() - 0.1).abs() < 1e-9);
}

#[test]
fn updated_deviations_get_their_own_scale() {
    let a = render(&sample()).unwrap();
    // The updated panel's axis is in tenths of a per cent, not ±6 %.
    assert!(a.contains("\n-0.10\n"), "no fine tick");
}

#[test]
fn outliers_are_clipped_and_labelled() {
    let mut c = sample();
    c.modes[0].reference_hz = 0.1;
    c.modes[0].models_hz = vec![Some(645.0), Some(645.0)];
    let a = render(&c).unwrap();
    assert_svg(&a);
    assert!(a.contains("+6.4e5 % (clipped)"), "clipped bar label");
    assert!(a.contains("645.0 Hz ↑"));
    assert_eq!(clip_limit(&[1.0, -2.0, 3.0]), 3.0);
    assert_eq!(clip_limit(&[1.0, 2.0, 5000.0]), 20.0);
    assert_eq!(clip_limit(&[f64::NAN]), 1.0);
}

#[test]
fn odd_data_does_not_panic() {
    let mut c = sample();
    c.modes.clear();
    assert!(render(&c).unwrap().contains("no test resonances"));
    let mut c = sample();
    c.modes[0].reference_hz = 0.0;
    c.modes[1].reference_hz = f64::NAN;
    c.modes[2].models_hz = vec![];
    assert_svg(&render(&c).unwrap());
    for r in &mut c.modes {
        r.reference_hz = 0.0;
    }
    assert_svg(&render(&c).unwrap());
}
