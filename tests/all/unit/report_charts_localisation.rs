//! Unit tests of `src/report/charts/localisation.rs` through its public interface.

use crate::unit::report_charts::test_util::assert_svg;
use frfup::report::charts::localisation::*;
use plotters::style::RGBColor;

pub(crate) fn sample() -> LocalisationMap {
    // A portal frame: two columns and a girder.
    let mut nodes = Vec::new();
    let pts = [
        (0.0, 0.0),
        (0.0, 0.3),
        (0.0, 0.6),
        (0.4, 0.6),
        (0.8, 0.6),
        (0.8, 0.3),
        (0.8, 0.0),
    ];
    for (i, &(x, y)) in pts.iter().enumerate() {
        nodes.push(MapNode {
            id: i as u32 + 1,
            x,
            y,
            score: match i {
                2 => Some(0.62),
                3 => Some(0.2),
                4 => Some(0.05),
                _ => None,
            },
            candidate: None,
            measured: i % 2 == 1,
            fixed: i == 0 || i == 6,
        });
    }
    LocalisationMap {
        title: "Localisation map".into(),
        subtitle: Some("test".into()),
        x_desc: "x (m)".into(),
        y_desc: "z (m)".into(),
        nodes,
        lines: (0..6).map(|i| (i, i + 1)).collect(),
        labelled: 3,
        findings: vec![MapFinding {
            label: "support-flexibility at node 1 (ry)".into(),
            nodes: vec![0],
        }],
    }
}

#[test]
fn map_has_title_axes_labels_and_is_deterministic() {
    let m = sample();
    let a = render(&m).unwrap();
    assert_svg(&a);
    assert_eq!(a, render(&m).unwrap());
    for t in [
        "Localisation map",
        "x (m)",
        "z (m)",
        "node 3: 62 %",
        "node 4: 20 %",
        "share of FRF error removed (%)",
        "fixed support",
    ] {
        assert!(a.contains(t), "lacks {t}");
    }
}

#[test]
fn accepted_findings_are_ringed_and_named() {
    let mut m = sample();
    m.findings.push(MapFinding {
        label: "sensor-mass at the 2 measured nodes".into(),
        nodes: vec![0, 1, 99],
    });
    let a = render(&m).unwrap();
    assert_svg(&a);
    assert!(a.contains("accepted: support-flexibility at node 1 (ry)"));
    assert!(a.contains("accepted: sensor-mass at the 2 measured nodes"));
    // Two rings at node 0 (one per finding), one at node 1.
    assert_eq!(
        a.matches("stroke=\"#005AC8\"").count() + a.matches("stroke=\"#008C46\"").count(),
        3 + 2
    );
}

#[test]
fn degenerate_maps_do_not_panic() {
    let mut m = sample();
    for n in &mut m.nodes {
        n.score = None;
        n.x = 0.0;
    }
    assert_svg(&render(&m).unwrap());
    m.nodes.truncate(1);
    m.lines.clear();
    assert_svg(&render(&m).unwrap());
    m.nodes.clear();
    assert_svg(&render(&m).unwrap());
    assert_eq!(score_color(0.0), RGBColor(255, 237, 160));
    assert_eq!(score_color(f64::NAN), RGBColor(255, 237, 160));
}
