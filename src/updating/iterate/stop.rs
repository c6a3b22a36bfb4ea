//! When the iteration ends, and what it returns: the stopping rule
//! max_j |p_j| < ε (Eq. 49), the safeguards' stops (SFDAC mean falling twice,
//! the iteration limit), the end of the frequencies-first stage, and the
//! result with the FDAC matrices (Eq. 44) of the initial and returned models.

use super::prepare::Problem;
use super::state::IterationState;
use super::{FREQUENCY_STAGE_EXIT, FREQUENCY_STAGE_ITERATIONS, FREQUENCY_STAGE_MAC};
use crate::testdata::layout::Layout;
use crate::updating::correlation::fdac_matrix;
use crate::updating::{
    IterationRecord, ModePair, ResonanceMethod, StopReason, UpdateOptions, UpdateResult,
    UpdateWarning,
};

/// Whether the frequencies-first stage ends after iteration `n`: every
/// clearly paired resonance used is within [`FREQUENCY_STAGE_EXIT`]
/// (relative), and, with fitted shapes (which the stage also matches), its
/// last step is small or it has run [`FREQUENCY_STAGE_ITERATIONS`].
pub(super) fn leaves_frequency_stage(
    n: usize,
    pairs: &[Option<ModePair>],
    step: &[f64],
    problem: &Problem,
    opts: &UpdateOptions,
) -> bool {
    let test_hz = &problem.test_hz;
    let worst = pairs
        .iter()
        .take(problem.r_used)
        .enumerate()
        .filter_map(|(t, p)| {
            p.as_ref()
                .filter(|p| p.mac >= FREQUENCY_STAGE_MAC)
                .map(|p| ((p.fe_hz - test_hz[t]) / test_hz[t]).abs())
        })
        .fold(0.0f64, f64::max);
    let settled = opts.resonance_method != ResonanceMethod::ModalFit
        || step.iter().fold(0.0f64, |a, p| a.max(p.abs())) < opts.tol.max(0.01)
        || n >= FREQUENCY_STAGE_ITERATIONS;
    worst < FREQUENCY_STAGE_EXIT && (n > 0 && settled)
}

impl IterationState {
    /// The stopping rules after scoring iteration `n` (none applies while the
    /// frequency stage ran): the last step below `tol` (Eq. 49), the SFDAC
    /// mean falling for two iterations in a row, the iteration limit.
    pub fn stopping_rule(
        &mut self,
        n: usize,
        was_frequency_stage: bool,
        opts: &UpdateOptions,
    ) -> Option<StopReason> {
        let max_step = self.step.iter().fold(0.0f64, |a, p| a.max(p.abs()));
        if n > 0 && max_step < opts.tol && !was_frequency_stage {
            return Some(StopReason::Converged);
        }
        if n >= 2 && !was_frequency_stage {
            let m: Vec<f64> = self.records[n - 2..=n]
                .iter()
                .map(|r| r.sfdac.mean)
                .collect();
            if m[2] < m[1] - 1e-5 && m[1] < m[0] - 1e-5 {
                self.warnings.push(UpdateWarning::Diverged {
                    iteration: n,
                    best: best_index(&self.records),
                });
                return Some(StopReason::Diverged);
            }
        }
        if n == opts.max_iter {
            self.warnings.push(UpdateWarning::NotConverged {
                iterations: n,
                last_step: max_step,
            });
            return Some(StopReason::IterationLimit);
        }
        None
    }

    /// The result: the converged iterate (Eq. 49), else the best one
    /// (highest SFDAC mean), with the FDAC matrices of the initial model and
    /// of the one returned.
    pub fn finish(
        self,
        problem: Problem,
        opts: &UpdateOptions,
        layout: Layout,
        stop: StopReason,
    ) -> UpdateResult {
        let records = self.records;
        let final_iteration = match stop {
            StopReason::Converged => records.len() - 1,
            _ => best_index(&records),
        };
        let fdac_initial = fdac_matrix(&self.fe_frfs_initial, &problem.h_test);
        let fdac_final = if final_iteration == records.len() - 1 {
            fdac_matrix(&self.fe_frfs_last, &problem.h_test)
        } else {
            fdac_matrix(&self.fe_frfs_best, &problem.h_test)
        };
        UpdateResult {
            converged: stop == StopReason::Converged,
            stop,
            parameter_names: problem.names,
            final_iteration,
            iterations: records,
            resonances: problem.peaks,
            resonances_used: problem.r_used,
            updating_frequencies: problem.updating,
            modes: problem.n_md,
            measured_dofs: problem.meas.labels,
            excitation: problem.meas.excitation_label,
            fdac_initial,
            fdac_final,
            test_resonances: problem.found,
            warnings: self.warnings,
            options: opts.clone(),
            layout,
            estimate: None,
        }
    }
}

/// Index of the record with the highest SFDAC mean (earliest on ties).
pub(super) fn best_index(records: &[IterationRecord]) -> usize {
    let mut best = 0;
    for (i, r) in records.iter().enumerate() {
        if r.sfdac.mean > records[best].sfdac.mean {
            best = i;
        }
    }
    best
}
