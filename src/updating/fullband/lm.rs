//! Bounded Levenberg–Marquardt: the one least-squares fitter of the full-band
//! fit, the diagnosis and the test's pole fit (`updating::identify`).
//!
//! Minimises Σ r_i(x)² within lo ≤ x ≤ hi. Step: (JᵀJ + λ·diag(JᵀJ)) δ = −Jᵀr
//! over the free unknowns (lo < hi), each component clamped to
//! ±[`LeastSquares::max_step`] ([`MAX_STEP`] unless the problem says otherwise) and the
//! new point to the bounds; a step is taken only if it lowers the cost (λ
//! then shrinks ×3), else λ grows ×10 (at most [`LmSettings::tries`] times). A problem that
//! approximates its residuals near an anchor (see [`LeastSquares::accepted`])
//! judges the step again on its re-linearised residuals; a step that is
//! worse there is undone and λ grows ×10, so the cost of the problem itself
//! never rises.

use faer::linalg::matmul::matmul;
use faer::{Accum, Mat, MatRef, Par};

use crate::solvers::dense::{cholesky_lower, cholesky_solve};

/// A least-squares problem: residuals r(x) and their Jacobian.
pub trait LeastSquares {
    /// r(x), or `None` where the model cannot be evaluated (the step is refused).
    fn residuals(&mut self, x: &[f64]) -> Option<Vec<f64>>;
    /// ∂r/∂x at `x` (rows of `r`, one column per unknown); columns of the
    /// unknowns with `free[i]` false are not used and may be left zero.
    fn jacobian(&mut self, x: &[f64], r: &[f64], free: &[bool]) -> Option<Mat<f64>>;
    /// `x` was accepted. A problem that re-linearises there (a reduced model
    /// moved to a new anchor) returns its residuals at `x`, which replace the
    /// old ones.
    fn accepted(&mut self, _x: &[f64]) -> Option<Vec<f64>> {
        None
    }
    /// The step to the point `accepted` was last called with is undone:
    /// return to the state at `x` (the point before it).
    fn rejected(&mut self, _x: &[f64]) {}
    /// The Jacobian is no longer needed: a problem may keep its storage for
    /// the next one (a long record's Jacobian is tens of megabytes, and
    /// fresh pages cost more than filling them).
    fn recycle(&mut self, _jac: Mat<f64>) {}
    /// Largest change of unknown `i` in one step (a trust region per unknown).
    fn max_step(&self, _i: usize) -> f64 {
        MAX_STEP
    }
}

/// The default largest change of an unknown in one step.
pub const MAX_STEP: f64 = 2.0;

/// Iteration limit and early stop of [`lm`].
#[derive(Clone, Copy, Debug)]
pub struct LmSettings {
    pub max_iter: usize,
    /// Stop once a step lowers Σr² by less than this (e.g. a small fraction
    /// of the noise variance of one residual: a change no data can tell).
    pub negligible: f64,
    /// Stop once a step lowers Σr² by less than this fraction of it.
    pub relative_gain: f64,
    /// Stop once no unknown moves by more than this.
    pub min_move: f64,
    /// Increases of λ tried before the point is taken as stationary.
    pub tries: usize,
}

impl Default for LmSettings {
    /// 100 iterations; stop at a relative gain below 1e-7 or a move below
    /// 1e-6; eight tries of λ.
    fn default() -> Self {
        LmSettings {
            max_iter: 100,
            negligible: 0.0,
            relative_gain: 1e-7,
            min_move: 1e-6,
            tries: 8,
        }
    }
}

/// Outcome of a Levenberg–Marquardt run.
#[derive(Clone, Debug)]
pub struct LmOutcome {
    pub x: Vec<f64>,
    pub residuals: Vec<f64>,
    /// The run stopped on its own criterion (relative cost change < 1e-7,
    /// a step < 1e-6, a gain below `negligible`, or no downhill step at any
    /// λ: a stationary point), not on the iteration limit.
    pub converged: bool,
    /// Jacobians evaluated.
    pub iterations: usize,
}

fn cost(r: &[f64]) -> f64 {
    r.iter().map(|v| v * v).sum()
}

/// Run bounded Levenberg–Marquardt from `x0` (clamped to the bounds).
pub fn lm(
    problem: &mut dyn LeastSquares,
    x0: &[f64],
    lo: &[f64],
    hi: &[f64],
    settings: LmSettings,
) -> Option<LmOutcome> {
    let n = x0.len();
    let free: Vec<bool> = (0..n).map(|i| lo[i] < hi[i]).collect();
    let idx: Vec<usize> = (0..n).filter(|&i| free[i]).collect();
    let mut x: Vec<f64> = (0..n).map(|i| x0[i].clamp(lo[i], hi[i])).collect();
    let mut r = problem.residuals(&x)?;
    let mut lambda = 1e-3;
    let outcome = |x, residuals, converged, iterations| {
        Some(LmOutcome {
            x,
            residuals,
            converged,
            iterations,
        })
    };
    for it in 0..settings.max_iter {
        if idx.is_empty() {
            return outcome(x, r, true, it);
        }
        let jac = problem.jacobian(&x, &r, &free)?;
        let (jtj, jtr) = normal_equations(jac.as_ref(), &r, &idx);
        problem.recycle(jac);
        let c0 = cost(&r);
        let mut accepted = None;
        for _ in 0..settings.tries {
            let mut a = jtj.clone();
            for k in 0..idx.len() {
                a[(k, k)] += lambda * jtj[(k, k)].max(1e-12);
            }
            let Some(step) = solve_spd(a.as_ref(), &jtr) else {
                lambda *= 10.0;
                continue;
            };
            let mut xn = x.clone();
            for (k, &i) in idx.iter().enumerate() {
                let limit = problem.max_step(i);
                xn[i] = (x[i] - step[k].clamp(-limit, limit)).clamp(lo[i], hi[i]);
            }
            let Some(rn) = problem.residuals(&xn).filter(|rn| cost(rn) < c0) else {
                lambda *= 10.0;
                continue;
            };
            // A problem that re-linearises at the new point judges the step
            // there; a step that is worse is undone and a shorter one tried
            // with the same Jacobian (it belongs to x, where the problem is
            // back).
            match problem.accepted(&xn) {
                Some(relinearised) if cost(&relinearised) >= c0 => {
                    problem.rejected(&x);
                    lambda *= 10.0;
                }
                Some(relinearised) => {
                    accepted = Some((xn, relinearised));
                    break;
                }
                None => {
                    accepted = Some((xn, rn));
                    break;
                }
            }
        }
        let Some((xn, rn)) = accepted else {
            return outcome(x, r, true, it + 1);
        };
        let cn = cost(&rn);
        let moved = idx
            .iter()
            .map(|&i| (xn[i] - x[i]).abs())
            .fold(0.0, f64::max);
        let small =
            (c0 - cn) / c0.max(1e-300) < settings.relative_gain || moved < settings.min_move;
        let negligible = c0 - cn < settings.negligible;
        x = xn;
        r = rn;
        lambda = (lambda / 3.0).max(1e-9);
        if small || negligible {
            return outcome(x, r, true, it + 1);
        }
    }
    outcome(x, r, false, settings.max_iter)
}

/// JᵀJ and Jᵀr over the columns `idx`.
pub fn normal_equations(jac: MatRef<'_, f64>, r: &[f64], idx: &[usize]) -> (Mat<f64>, Vec<f64>) {
    let every = idx.len() == jac.ncols() && idx.iter().enumerate().all(|(k, &i)| k == i);
    let gathered;
    let sub = if every {
        jac
    } else {
        gathered = Mat::from_fn(jac.nrows(), idx.len(), |i, k| jac[(i, idx[k])]);
        gathered.as_ref()
    };
    // JᵀJ and Jᵀr side by side on the pool's threads, each computed as it
    // would be alone.
    let gram = || {
        let mut jtj = Mat::<f64>::zeros(idx.len(), idx.len());
        matmul(
            jtj.as_mut(),
            Accum::Replace,
            sub.transpose(),
            sub,
            1.0,
            Par::Seq,
        );
        jtj
    };
    let gradient = || {
        (0..idx.len())
            .map(|k| {
                let col = sub.col(k);
                (0..r.len()).map(|i| col[i] * r[i]).sum()
            })
            .collect()
    };
    rayon::join(gram, gradient)
}

/// Solve A x = b for a symmetric positive definite A (Cholesky); `None` if
/// A is not numerically positive definite or the solution is not finite.
pub fn solve_spd(a: MatRef<'_, f64>, b: &[f64]) -> Option<Vec<f64>> {
    let l = cholesky_lower(a)?;
    let rhs = Mat::from_fn(b.len(), 1, |i, _| b[i]);
    let x = cholesky_solve(l.as_ref(), rhs.as_ref());
    let x: Vec<f64> = (0..b.len()).map(|i| x[(i, 0)]).collect();
    x.iter().all(|v| v.is_finite()).then_some(x)
}

/// The inverse of a symmetric positive definite matrix, if it has one.
pub fn inverse_spd(a: MatRef<'_, f64>) -> Option<Mat<f64>> {
    let l = cholesky_lower(a)?;
    let inv = cholesky_solve(
        l.as_ref(),
        Mat::<f64>::identity(a.nrows(), a.nrows()).as_ref(),
    );
    (0..inv.nrows())
        .all(|i| (0..inv.ncols()).all(|j| inv[(i, j)].is_finite()))
        .then_some(inv)
}

/// A residual function with its Jacobian by forward differences.
pub struct Differences<F> {
    pub f: F,
    pub lo: Vec<f64>,
    pub hi: Vec<f64>,
}

impl<F: FnMut(&[f64]) -> Option<Vec<f64>>> LeastSquares for Differences<F> {
    fn residuals(&mut self, x: &[f64]) -> Option<Vec<f64>> {
        (self.f)(x)
    }
    fn jacobian(&mut self, x: &[f64], r: &[f64], free: &[bool]) -> Option<Mat<f64>> {
        forward_differences(&mut self.f, x, r, &self.lo, &self.hi, free)
    }
}

/// Forward-difference Jacobian, step 1e-4 (backward at an upper bound); the
/// columns of unknowns that are not `free` are zero.
pub fn forward_differences<F>(
    f: &mut F,
    x: &[f64],
    r: &[f64],
    lo: &[f64],
    hi: &[f64],
    free: &[bool],
) -> Option<Mat<f64>>
where
    F: FnMut(&[f64]) -> Option<Vec<f64>>,
{
    let mut jac = Mat::<f64>::zeros(r.len(), x.len());
    for i in (0..x.len()).filter(|&i| free[i]) {
        let h = if x[i] + 1e-4 > hi[i] && x[i] - 1e-4 >= lo[i] {
            -1e-4
        } else {
            1e-4
        };
        let mut xp = x.to_vec();
        xp[i] += h;
        let rp = f(&xp)?;
        if rp.len() != r.len() {
            return None;
        }
        for (k, (a, b)) in rp.iter().zip(r).enumerate() {
            jac[(k, i)] = (a - b) / h;
        }
    }
    Some(jac)
}

/// Bounded Levenberg–Marquardt on `f` with forward differences (see [`lm`]).
pub fn lm_differences<F>(
    f: F,
    x0: &[f64],
    lo: &[f64],
    hi: &[f64],
    max_iter: usize,
) -> Option<LmOutcome>
where
    F: FnMut(&[f64]) -> Option<Vec<f64>>,
{
    let mut problem = Differences {
        f,
        lo: lo.to_vec(),
        hi: hi.to_vec(),
    };
    let settings = LmSettings {
        max_iter,
        ..LmSettings::default()
    };
    lm(&mut problem, x0, lo, hi, settings)
}

/// Standard deviations of x from σ²(JᵀJ)⁻¹ with σ² = Σr²/(N − p) (∞ when
/// JᵀJ is singular).
pub fn std_devs(jac: MatRef<'_, f64>, r: &[f64]) -> Vec<f64> {
    let p = jac.ncols();
    let idx: Vec<usize> = (0..p).collect();
    let (jtj, _) = normal_equations(jac, r, &idx);
    let dof = (r.len() as f64 - p as f64).max(1.0);
    let s2 = cost(r) / dof;
    match inverse_spd(jtj.as_ref()) {
        Some(inv) => (0..p).map(|i| (s2 * inv[(i, i)]).max(0.0).sqrt()).collect(),
        None => vec![f64::INFINITY; p],
    }
}
