//! Unit tests of `src/report/charts/convergence.rs` through its public interface.

use crate::unit::report_charts::test_util::assert_svg;
use frfup::report::charts::convergence::*;

fn sample() -> ConvergenceChart {
    ConvergenceChart {
        title: "Convergence of the updating parameters".into(),
        subtitle: Some("converged after 3 iterations".into()),
        parameter_names: vec!["EI_root".into(), "mass_tip".into(), "k_joint".into()],
        iterations: vec![0, 1, 2, 3],
        parameters: vec![
            vec![0.0, 0.0, 0.0],
            vec![0.3, -0.1, 0.05],
            vec![0.45, -0.12, f64::NAN],
            vec![0.5, -0.12, 0.02],
        ],
        sfdac_mean: vec![-0.35, 0.5, 0.85, 0.9995],
        sfdac_min: vec![-0.96, 0.1, 0.6, 0.67],
        selected: Some(3),
        stages: vec![StageMark {
            at: 3,
            label: "full-band estimate".into(),
        }],
        not_identified: vec![false, false, true],
    }
}

#[test]
fn has_title_axes_legend_and_is_deterministic() {
    let c = sample();
    let a = render(&c).unwrap();
    assert_svg(&a);
    for t in [
        "Convergence of the updating parameters",
        "iteration n",
        "SFDAC (scale of 1 − SFDAC, log)",
        "\n0.99\n",
        "\n0.999\n",
        "EI_root",
        "k_joint",
        "mean SFDAC",
        "minimum SFDAC",
        "returned model (iteration 3)",
        "full-band estimate from iteration 3",
    ] {
        assert!(a.contains(t), "missing {t}");
    }
    assert_eq!(a, render(&c).unwrap());
}

#[test]
fn tiny_ticks_are_compact() {
    let f = compact_tick_label((-2e-5, 1e-5), 3);
    assert_eq!(f(&-1e-5), "-1.0e-5");
    assert_eq!(f(&0.0), "0");
    assert!(!compact_tick_label((0.0, 0.3), 3)(&0.1).contains('e'));
}

#[test]
fn sfdac_scale() {
    assert_eq!(nines_label(&0.0), "0");
    assert_eq!(nines_label(&3.0), "0.999");
    assert_eq!(nines_label(&0.5), "");
    assert!((nines(0.99) - 2.0).abs() < 1e-9);
    assert_eq!(nines(1.0), 6.0);
}

#[test]
fn many_parameters_get_small_multiples() {
    let mut c = sample();
    c.parameter_names = (0..20).map(|i| format!("param_{i}")).collect();
    c.parameters = (0..4)
        .map(|n| (0..20).map(|j| 0.01 * (n * j) as f64).collect())
        .collect();
    let a = render(&c).unwrap();
    assert_svg(&a);
    assert!(a.contains("each on its own scale"));
    assert!(
        a.contains("param_19 = 0.5700"),
        "returned value in the title"
    );
}

#[test]
fn odd_data_does_not_panic() {
    let mut c = sample();
    c.iterations.clear();
    c.parameters.clear();
    assert!(render(&c).unwrap().contains("no iterations"));
    let mut c = sample();
    c.iterations = vec![0];
    c.parameters = vec![vec![f64::NAN, f64::INFINITY, 0.0]];
    c.sfdac_mean = vec![f64::NAN];
    c.sfdac_min = vec![];
    c.selected = None;
    assert_svg(&render(&c).unwrap());
    let mut c = sample();
    c.parameter_names = (0..40)
        .map(|i| format!("a rather long parameter name {i}"))
        .collect();
    assert_svg(&render(&c).unwrap());
}
