//! Unit tests of `src/report/charts/frf_overlay.rs` through its public interface.

use crate::unit::report_charts::test_util::assert_svg;
use frfup::report::charts::frf_overlay::*;
use num_complex::Complex64;

fn sdof(f: f64, fr: f64, zeta: f64, scale: f64) -> Complex64 {
    let w = f / fr;
    Complex64::new(scale, 0.0) / Complex64::new(1.0 - w * w, 2.0 * zeta * w)
}

pub(crate) fn sample(channels: usize, lines: usize) -> FrfOverlay {
    let f: Vec<f64> = (0..lines)
        .map(|i| 200.0 * i as f64 / (lines.max(2) - 1) as f64)
        .collect();
    FrfOverlay {
        title: "Measured and model FRFs".into(),
        subtitle: Some("accelerance, excitation 112+z".into()),
        quantity: "accelerance".into(),
        units: "m/s²/N".into(),
        series_labels: vec![
            "measured".into(),
            "initial model".into(),
            "updated model".into(),
        ],
        channels: (0..channels)
            .map(|c| FrfChannel {
                label: format!("{}+z/112+z", 100 + c),
                values: [40.0, 44.0, 40.4]
                    .iter()
                    .map(|&fr| {
                        f.iter()
                            .map(|&x| {
                                sdof(x, fr, 0.02, 1e-3 * (c + 1) as f64)
                                    + sdof(x, 2.6 * fr, 0.01, 5e-4)
                            })
                            .collect()
                    })
                    .collect(),
            })
            .collect(),
        frequencies_hz: f,
        marks_hz: vec![37.0, 43.0, 97.0, 111.0],
        mark_label: "updating frequency".into(),
        resonances: vec![
            ResonanceMark {
                hz: 40.0,
                label: "R1".into(),
            },
            ResonanceMark {
                hz: 41.0,
                label: "R2".into(),
            },
            ResonanceMark {
                hz: 104.0,
                label: "R3".into(),
            },
        ],
    }
}

#[test]
fn channel_has_title_axes_legend_and_is_deterministic() {
    let o = sample(3, 801);
    let a = render_channel(&o, 1).unwrap();
    assert_svg(&a);
    for t in [
        "Measured and model FRFs — 101+z/112+z",
        "|accelerance| (m/s²/N, log scale)",
        "phase (°)",
        "frequency (Hz)",
        "measured",
        "initial model",
        "updated model",
        "updating frequency",
        "R3",
        "10⁻",
    ] {
        assert!(a.contains(t), "missing {t}");
    }
    assert_eq!(a, render_channel(&o, 1).unwrap());
}

#[test]
fn contact_sheet_has_every_channel() {
    let o = sample(26, 801);
    let a = render_contact_sheet(&o).unwrap();
    assert_svg(&a);
    for c in 0..26 {
        assert!(a.contains(&format!("{}+z/112+z", 100 + c)));
    }
    assert!(a.contains("|H| (m/s²/N)"));
    assert_eq!(a, render_contact_sheet(&o).unwrap());
}

#[test]
fn odd_data_does_not_panic() {
    let o = sample(0, 10);
    assert_svg(&render_contact_sheet(&o).unwrap());
    assert_svg(&render_channel(&o, 0).unwrap());
    let o = sample(1, 0);
    assert_svg(&render_channel(&o, 0).unwrap());
    assert_svg(&render_contact_sheet(&o).unwrap());
    let mut o = sample(1, 3);
    o.channels[0].values[0] = vec![Complex64::new(f64::NAN, 0.0); 3];
    o.channels[0].values[1] = vec![Complex64::new(0.0, 0.0); 3];
    o.channels[0].values[2].truncate(1);
    o.frequencies_hz = vec![0.0, 0.0, 0.0];
    assert_svg(&render_channel(&o, 0).unwrap());
    assert_svg(&render_contact_sheet(&o).unwrap());
    assert_eq!(file_stem("112+z/7-ry"), "112+z_7-ry");
}

#[test]
fn decimation_keeps_extremes() {
    let pts: Vec<(f64, f64)> = (0..10_000)
        .map(|i| (i as f64, if i == 5000 { 9.0 } else { 0.0 }))
        .collect();
    let d = decimate(pts, (0.0, 10_000.0), 100);
    assert!(d.len() <= 202);
    assert!(d.iter().any(|p| p.1 == 9.0));
}
