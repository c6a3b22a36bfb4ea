//! Unit tests of `src/updating/fullband/lm.rs` through its public interface.

use faer::Mat;
use frfup::updating::fullband::lm::*;

/// y = a·exp(b·t) through exact data: LM finds (a, b) from a far start,
/// and holds a bound.
#[test]
fn fits_an_exponential_within_bounds() {
    let t: Vec<f64> = (0..20).map(|i| i as f64 * 0.1).collect();
    let f = |x: &[f64]| -> Option<Vec<f64>> {
        Some(
            t.iter()
                .map(|&ti| x[0] * (x[1] * ti).exp() - 2.0 * (-0.7 * ti).exp())
                .collect(),
        )
    };
    let out = lm_differences(f, &[1.0, 0.0], &[0.0, -5.0], &[10.0, 5.0], 100).unwrap();
    assert!(out.converged);
    assert!(
        (out.x[0] - 2.0).abs() < 1e-6 && (out.x[1] + 0.7).abs() < 1e-6,
        "{:?}",
        out.x
    );
    let out = lm_differences(f, &[1.0, 0.0], &[0.0, -0.5], &[10.0, 5.0], 100).unwrap();
    assert!(
        out.x[1] >= -0.5 && (out.x[1] + 0.5).abs() < 1e-12,
        "{:?}",
        out.x
    );
}

/// r(x) = x² − 0.01 seen through its linearisation at an anchor that
/// moves to each accepted point (as the full-band estimate's reduced
/// model does). From x = 0.005 the linear model's first step lands near
/// x = 1, where the true cost is 10⁴ times higher: that step must be
/// undone, and the true cost at the anchors kept must fall monotonically
/// to the root x = 0.1. The Jacobian at a point serves every step tried
/// from it, an undone one included: one Jacobian per point kept.
struct Linearised {
    anchor: f64,
    kept: Vec<f64>,
    undone: usize,
    jacobians: usize,
}

impl LeastSquares for Linearised {
    fn residuals(&mut self, x: &[f64]) -> Option<Vec<f64>> {
        let a = self.anchor;
        Some(vec![a * a - 0.01 + 2.0 * a * (x[0] - a)])
    }
    fn jacobian(&mut self, _x: &[f64], _r: &[f64], _free: &[bool]) -> Option<Mat<f64>> {
        self.jacobians += 1;
        Some(Mat::from_fn(1, 1, |_, _| 2.0 * self.anchor))
    }
    fn accepted(&mut self, x: &[f64]) -> Option<Vec<f64>> {
        self.anchor = x[0];
        self.kept.push(x[0]);
        Some(vec![x[0] * x[0] - 0.01])
    }
    fn rejected(&mut self, x: &[f64]) {
        self.kept.pop();
        self.anchor = x[0];
        self.undone += 1;
    }
}

#[test]
fn a_step_worse_on_the_relinearised_problem_is_undone() {
    let mut p = Linearised {
        anchor: 0.005,
        kept: vec![0.005],
        undone: 0,
        jacobians: 0,
    };
    let settings = LmSettings::default();
    let out = lm(&mut p, &[0.005], &[-10.0], &[10.0], settings).unwrap();
    assert!(p.undone >= 1, "no step was undone");
    assert!(
        p.jacobians <= p.kept.len(),
        "{} Jacobians for {} points",
        p.jacobians,
        p.kept.len()
    );
    let true_cost = |x: f64| (x * x - 0.01).powi(2);
    for w in p.kept.windows(2) {
        assert!(true_cost(w[1]) < true_cost(w[0]), "{:?}", p.kept);
    }
    assert!(
        out.converged && (out.x[0] - 0.1).abs() < 1e-6,
        "{:?}",
        out.x
    );
}

/// σ²(JᵀJ)⁻¹ of a straight-line fit: sd of the slope s/√Σ(t − t̄)² etc.
#[test]
fn straight_line_standard_deviations() {
    let jac = Mat::from_fn(4, 2, |i, j| if j == 0 { 1.0 } else { i as f64 });
    let r = [0.1, -0.1, -0.1, 0.1];
    let sd = std_devs(jac.as_ref(), &r);
    let s2: f64 = 0.04 / 2.0;
    assert!((sd[1] - (s2 / 5.0).sqrt()).abs() < 1e-12, "{sd:?}");
}
