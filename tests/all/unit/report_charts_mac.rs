//! Unit tests of `src/report/charts/mac.rs` through its public interface.

use crate::unit::report_charts::test_util::assert_svg;
use frfup::report::charts::mac::*;
use plotters::style::RGBColor;

fn sample(rows: usize, cols: usize) -> MacChart {
    let panel = |label: &str, off: usize| MacPanel {
        label: label.into(),
        column_labels: (0..cols)
            .map(|j| format!("{:.2}", 5.0 + 6.1 * j as f64))
            .collect(),
        values: (0..rows)
            .map(|i| {
                (0..cols)
                    .map(|j| {
                        if i + off == j {
                            0.95
                        } else {
                            0.05 * ((i + j) % 3) as f64
                        }
                    })
                    .collect()
            })
            .collect(),
        pairs: (0..rows)
            .filter(|i| i + off < cols)
            .map(|i| (i, i + off))
            .collect(),
    };
    MacChart {
        title: "MAC: test deflection shapes vs FE modes".into(),
        subtitle: None,
        row_labels: (0..rows)
            .map(|i| format!("{:.2}", 5.1 + 6.0 * i as f64))
            .collect(),
        row_axis: "test resonance (Hz)".into(),
        column_axis: "FE mode (Hz)".into(),
        scale_label: "MAC of the ODS (dimensionless)".into(),
        panels: vec![panel("initial model", 0), panel("updated model", 1)],
    }
}

#[test]
fn has_title_axes_scale_and_is_deterministic() {
    let c = sample(5, 7);
    let a = render(&c).unwrap();
    assert_svg(&a);
    for t in [
        "MAC: test deflection shapes vs FE modes",
        "test resonance (Hz)",
        "FE mode (Hz)",
        "MAC of the ODS (dimensionless)",
        "initial model",
        "updated model",
        "0.95",
    ] {
        assert!(a.contains(t), "missing {t}");
    }
    assert_eq!(a, render(&c).unwrap());
}

#[test]
fn colour_map_ends() {
    assert_eq!(mac_color(0.0), RGBColor(247, 251, 255));
    assert_eq!(mac_color(1.0), RGBColor(8, 48, 107));
    assert_eq!(mac_color(7.0), RGBColor(8, 48, 107));
    assert_eq!(mac_color(f64::NAN), RGBColor(220, 220, 220));
}

#[test]
fn odd_data_does_not_panic() {
    assert!(render(&sample(0, 3))
        .unwrap()
        .contains("no test resonances"));
    let mut c = sample(3, 40);
    c.panels[0].values[0][0] = f64::NAN;
    c.panels[1].values.pop();
    c.panels[1].pairs.push((99, 99));
    assert_svg(&render(&c).unwrap());
    assert_svg(&render(&sample(30, 2)).unwrap());
}
