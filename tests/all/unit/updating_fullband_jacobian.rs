//! Unit tests of `src/updating/fullband/jacobian.rs` through its public interface.

use crate::unit::updating_fullband_reduced::beam;
use frfup::model;
use frfup::updating::fullband::fit::{self, DampingForm, Mask};
use frfup::updating::fullband::jacobian::*;
use frfup::updating::fullband::reduced::ReducedModel;

/// |J_j − D_j| and |D_j| for the central difference D_j of `r_at` at `x0`
/// along unknown `j` with step `h`, J_j the analytic `column`: the check of
/// an exact Jacobian column.
pub fn central_difference_error<F: Fn(&[f64]) -> Vec<f64>>(
    r_at: &F,
    x0: &[f64],
    j: usize,
    column: faer::ColRef<'_, f64>,
    h: f64,
) -> (f64, f64) {
    let (mut xp, mut xm) = (x0.to_vec(), x0.to_vec());
    xp[j] += h;
    xm[j] -= h;
    let fd: Vec<f64> = r_at(&xp)
        .iter()
        .zip(r_at(&xm))
        .map(|(a, b)| (a - b) / (2.0 * h))
        .collect();
    let norm = fd.iter().map(|v| v * v).sum::<f64>().sqrt();
    let err = (0..fd.len())
        .map(|i| (fd[i] - column[i]).powi(2))
        .sum::<f64>()
        .sqrt();
    (err, norm)
}

/// The soft-sprung beam of [`beam`], its reduced model anchored at p̄ = 0
/// and solved at a point away from it, with modal damping.
struct BeamPoint {
    data: frfup::updating::fullband::data::TestData,
    mask: Mask,
    form: DampingForm,
    red: ReducedModel,
    x0: [f64; 5],
    modes: frfup::updating::fullband::reduced::ReducedModes,
    pred: Vec<Vec<faer::c64>>,
}

impl BeamPoint {
    fn new() -> BeamPoint {
        let (deck, data) = beam();
        let names = model::parameter_names(&deck);
        let mask = Mask::all(&data);
        let form = DampingForm::Modal;
        let red = ReducedModel::new(&deck, &names, &[0.0; 4], &data).unwrap();
        let x0 = [0.03, -0.02, 0.05, 0.1, 0.02f64.ln()];
        let modes = red.solve(&x0[..4]).unwrap();
        let pred = fit::predict(&modes.model, form.damping(&x0[4..]), &data, &mask);
        BeamPoint {
            data,
            mask,
            form,
            red,
            x0,
            modes,
            pred,
        }
    }

    fn point(&self) -> Point<'_> {
        Point {
            model: &self.red,
            modes: &self.modes,
            form: self.form,
            damping: &self.x0[4..],
            pred: &self.pred,
        }
    }
}

/// The analytic columns against central differences of the reduced
/// model (away from its anchor, so the expansion is exercised), and the
/// damping column.
#[test]
fn analytic_columns_match_central_differences() {
    let b = BeamPoint::new();
    let (data, mask, form, red, x0) = (&b.data, &b.mask, b.form, &b.red, b.x0);
    let r_at = |x: &[f64]| {
        let modes = red.solve(&x[..4]).unwrap();
        let pred = fit::predict(&modes.model, form.damping(&x[4..]), data, mask);
        fit::residuals(&pred, data, mask)
    };
    let pt = b.point();
    let jac = columns(&pt, data, mask, &[true; 5], 0, None);
    assert_eq!(jac.nrows(), r_at(&x0).len());
    // Written into the storage of an earlier Jacobian (stale values in
    // it, one column held and two rows left for the caller's prior rows,
    // whose zeros must come from the reset, as must those of every other
    // entry it does not compute): the same matrix, bit for bit.
    let rows = jac.nrows() + 2;
    let stale = faer::Mat::<f64>::from_fn(rows, jac.ncols(), |i, j| (i + 7 * j) as f64);
    let held = [true, false, true, true, true];
    let again = columns(&pt, data, mask, &held, 2, Some(stale));
    let fresh = columns(&pt, data, mask, &held, 2, None);
    assert!((0..rows).all(|i| again[(i, 1)] == 0.0));
    assert!((jac.nrows()..rows).all(|i| (0..5).all(|j| again[(i, j)] == 0.0)));
    assert!((0..rows).all(|i| (0..5).all(|j| again[(i, j)].to_bits() == fresh[(i, j)].to_bits())));
    for j in 0..5 {
        let (err, norm) = central_difference_error(&r_at, &x0, j, jac.col(j), 1e-4);
        // Exact but for the high modes' series (damping neglected); the
        // step is large enough to stay above the rounding of the lowest
        // eigenvalues (≈ ε·λ_max of the reduced pencil).
        assert!(
            err <= 2e-3 * norm,
            "unknown {j}: |analytic − fd| = {err:e} of {norm:e}"
        );
    }
}

/// The Jacobian's channel groups and parameters run on the threads there
/// are, each with the same operations: one, two and three threads give the
/// same matrix, bit for bit (the demo's bytes do not depend on the pool).
#[test]
fn the_same_columns_on_one_two_and_three_threads() {
    let b = BeamPoint::new();
    let (pt, data, mask) = (b.point(), &b.data, &b.mask);
    let on = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| columns(&pt, data, mask, &[true; 5], 0, None))
    };
    let one = on(1);
    for threads in [2, 3] {
        let other = on(threads);
        assert!(
            (0..one.nrows())
                .all(|i| (0..5).all(|j| one[(i, j)].to_bits() == other[(i, j)].to_bits())),
            "{threads} threads"
        );
    }
}
