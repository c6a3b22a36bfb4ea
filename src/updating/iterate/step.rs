//! One updating step: solve A p = b by the SVD gap rule (Eq. 35–41), damped
//! when asked (Levenberg–Marquardt rows μ I), then the safeguards on p (the
//! frequency stage's trust region, 1 + p_j > 0) and the composition
//! p̄^{n+1} = p̄^n + p + p̄^n p (Eq. 29).

use faer::Mat;

use super::prepare::Problem;
use super::state::IterationState;
use super::stop::best_index;
use super::{FREQUENCY_STAGE_DAMPING, FREQUENCY_STAGE_MAX_STEP};
use crate::updating::svd_solve::solve_gap_rule;
use crate::updating::{StopReason, UpdateError, UpdateOptions, UpdateWarning};

impl IterationState {
    /// p^{n+1}, the solution of A p = b: the gap-rule SVD solution (Eq. 41),
    /// replaced by the damped one when the step damping is on. Keeps the
    /// rank and singular values for the next record and warns (once) about
    /// parameter combinations in the null space.
    pub fn solve(
        &mut self,
        n: usize,
        a: &Mat<f64>,
        b: &[f64],
        problem: &Problem,
        opts: &UpdateOptions,
    ) -> Result<Vec<f64>, UpdateError> {
        let mut sol = solve_gap_rule(a.as_ref(), b, opts.svd_eps).map_err(UpdateError::Svd)?;
        if n > 0 {
            let (prev, now) = (self.records[n - 1].sfdac.mean, self.records[n].sfdac.mean);
            self.damping_scale = if now >= prev {
                (self.damping_scale * 0.5).max(0.01)
            } else {
                (self.damping_scale * 4.0).min(16.0)
            };
        }
        let damping = self.damping_scale
            * if self.frequency_stage {
                FREQUENCY_STAGE_DAMPING
            } else {
                opts.damping
            };
        if damping > 0.0 {
            // Damped least squares (rows μ I, μ = FREQUENCY_STAGE_DAMPING σ₁):
            // a resonance that no parameter moves much (a suspension mode, a
            // mode the parameters barely touch) must not buy its last per cent
            // with huge changes of insensitive parameters.
            let mu = damping * sol.singular_values.first().copied().unwrap_or(0.0);
            if mu > 0.0 {
                sol.step = damped_step(a, b, mu, opts.svd_eps)?;
            }
        }
        if !sol.null_space.is_empty() && !self.warned_null {
            self.warned_null = true;
            self.warn_indistinguishable(n, &sol.null_space, problem);
        }
        self.rank = sol.rank;
        self.singular_values = sol.singular_values;
        Ok(sol.step)
    }

    /// The parameter combinations the equations do not determine (each SVD
    /// null-space vector's entries of at least a tenth of its largest).
    fn warn_indistinguishable(&mut self, n: usize, null_space: &[Vec<f64>], problem: &Problem) {
        let combinations = null_space
            .iter()
            .map(|v| {
                let vmax = v.iter().fold(0.0f64, |a, x| a.max(x.abs()));
                problem
                    .names
                    .iter()
                    .zip(v)
                    .filter(|(_, x)| x.abs() >= 0.1 * vmax)
                    .map(|(nm, x)| (nm.clone(), *x))
                    .collect()
            })
            .collect();
        self.warnings.push(UpdateWarning::Indistinguishable {
            iteration: n,
            combinations,
        });
    }

    /// Apply the safeguards to `p` and compose p̄^{n+1} (Eq. 29). Returns
    /// [`StopReason::ParameterExploded`] when a |p̄_j| leaves the admissible
    /// range (or is not finite).
    pub fn take_step(
        &mut self,
        n: usize,
        mut p: Vec<f64>,
        problem: &Problem,
        opts: &UpdateOptions,
    ) -> Option<StopReason> {
        // Trust region of the frequency stage: the linearisation (Eq. 17)
        // holds for small changes only.
        if self.frequency_stage {
            let big = p.iter().fold(0.0f64, |a, x| a.max(x.abs()));
            if big > FREQUENCY_STAGE_MAX_STEP {
                p.iter_mut()
                    .for_each(|x| *x *= FREQUENCY_STAGE_MAX_STEP / big);
            }
        }
        self.keep_properties_positive(n, &mut p, problem);
        for (pb, x) in self.p_bar.iter_mut().zip(&p) {
            *pb = *pb + x + *pb * x; // Eq. 29
        }
        self.step = p;
        let (j, v) = self
            .p_bar
            .iter()
            .enumerate()
            .find(|(_, v)| !v.is_finite() || v.abs() > opts.max_parameter)?;
        self.warnings.push(UpdateWarning::ParameterExploded {
            iteration: n + 1,
            name: problem.names[j].clone(),
            value: *v,
            best: best_index(&self.records),
        });
        Some(StopReason::ParameterExploded)
    }

    /// 1 + p_j ≤ 0 would make a property ≤ 0: halve the step until every
    /// 1 + p_j ≥ 0.1 (the scale is kept in `step_scale`).
    fn keep_properties_positive(&mut self, n: usize, p: &mut [f64], problem: &Problem) {
        self.step_scale = 1.0;
        let bad: Vec<String> = problem
            .names
            .iter()
            .zip(p.iter())
            .filter(|(_, &x)| 1.0 + x <= 0.0)
            .map(|(nm, _)| nm.clone())
            .collect();
        if bad.is_empty() {
            return;
        }
        while p.iter().any(|&x| 1.0 + self.step_scale * x < 0.1) && self.step_scale > 1e-12 {
            self.step_scale *= 0.5;
        }
        p.iter_mut().for_each(|x| *x *= self.step_scale);
        self.warnings.push(UpdateWarning::StepLimited {
            iteration: n + 1,
            scale: self.step_scale,
            parameters: bad,
        });
    }
}

/// The damped least-squares step: A p = b with the rows μ I (right-hand
/// side 0) appended, solved by the gap rule.
fn damped_step(a: &Mat<f64>, b: &[f64], mu: f64, svd_eps: f64) -> Result<Vec<f64>, UpdateError> {
    let (m, np_) = (a.nrows(), a.ncols());
    let aug = Mat::from_fn(m + np_, np_, |i, j| {
        if i < m {
            a[(i, j)]
        } else if i - m == j {
            mu
        } else {
            0.0
        }
    });
    let mut b_aug = b.to_vec();
    b_aug.resize(m + np_, 0.0);
    let damped = solve_gap_rule(aug.as_ref(), &b_aug, svd_eps).map_err(UpdateError::Svd)?;
    Ok(damped.step)
}
