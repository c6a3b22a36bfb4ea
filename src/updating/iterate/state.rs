//! What one iteration hands to the next (p̄^n, the last step, the stage and
//! the records so far), and the scoring of the model at p̄^n: its modes, the
//! SEREP basis (Eq. 32–34), the FRF equations (Eq. 11–12), the SFDAC at the
//! updating frequencies (Eq. 45–46) and the test–FE mode pairs (MAC).

use super::prepare::{Problem, Start};
use super::stop::best_index;
use crate::model::{FeModel, ModelError, ParameterValues};
use crate::solvers::eigen::{lowest_modes, EigenOptions, Modes};
use crate::updating::correlation::{pair_modes, SfdacSummary};
use crate::updating::sensitivity::{frf_equations, FrfEquations, ModalSensitivities};
use crate::updating::serep::SerepBasis;
use crate::updating::{
    IterationRecord, IterationStage, ModePair, UpdateError, UpdateOptions, UpdateProgress,
    UpdateWarning,
};

/// The iteration's state between two passes.
pub(super) struct IterationState {
    /// p̄^n, the composed relative changes (Eq. 29), aligned with the names.
    pub p_bar: Vec<f64>,
    /// p^n, the step that produced p̄^n (after any scaling), the scale
    /// applied, and the rank and singular values of the system it solved.
    pub step: Vec<f64>,
    pub step_scale: f64,
    pub rank: usize,
    pub singular_values: Vec<f64>,
    pub records: Vec<IterationRecord>,
    /// FE FRFs at the updating frequencies of the initial model, of the last
    /// iterate and of the iterate with the highest mean SFDAC so far.
    pub fe_frfs_initial: Vec<Vec<f64>>,
    pub fe_frfs_last: Vec<Vec<f64>>,
    pub fe_frfs_best: Vec<Vec<f64>>,
    pub warnings: Vec<UpdateWarning>,
    /// The null-space and small-basis warnings are given once.
    pub warned_null: bool,
    pub warned_fewer: bool,
    /// Frequencies-first stage: while the paired resonances are far off, FRF
    /// equations at (1 ± cξ)ω̄ sit next to FE poles and mislead; solve the
    /// natural-frequency equations (Eq. 18) alone until they are close.
    pub frequency_stage: bool,
    /// Levenberg–Marquardt scale of the step damping: halved after a step
    /// that raised the mean SFDAC, quadrupled after one that lowered it.
    pub damping_scale: f64,
    /// The initial model and its modes, until iteration 0 takes them.
    start: Option<Start>,
}

/// The model at p̄^n and what the equations of the next step need from it.
pub(super) struct Iterate {
    pub fe: FeModel,
    pub modes: Modes,
    /// A_h p = b_h (Eq. 11–12) at the updating frequencies, and the FE FRFs.
    pub eqs: FrfEquations,
    /// Test resonance → FE mode pairs (MAC on the measured DOFs).
    pub pairs: Vec<Option<ModePair>>,
}

impl IterationState {
    /// p̄⁰ = 0, no step yet; `warnings` are those of the preparation.
    pub fn new(
        problem: &Problem,
        opts: &UpdateOptions,
        start: Start,
        warnings: Vec<UpdateWarning>,
    ) -> Self {
        let np = problem.names.len();
        IterationState {
            p_bar: vec![0.0; np],
            step: vec![0.0; np],
            step_scale: 1.0,
            rank: 0,
            singular_values: Vec::new(),
            records: Vec::new(),
            fe_frfs_initial: Vec::new(),
            fe_frfs_last: Vec::new(),
            fe_frfs_best: Vec::new(),
            warnings,
            warned_null: false,
            warned_fewer: false,
            frequency_stage: opts.frequencies_first,
            damping_scale: 1.0,
            start: Some(start),
        }
    }

    /// Build and score the model at p̄^n: record it (calling `progress`) and
    /// return what the next step's equations need.
    pub fn evaluate(
        &mut self,
        n: usize,
        build: &mut dyn FnMut(&ParameterValues) -> Result<FeModel, ModelError>,
        problem: &Problem,
        opts: &UpdateOptions,
        progress: &mut dyn FnMut(UpdateProgress),
    ) -> Result<Iterate, UpdateError> {
        let (fe, modes) = self.model_and_modes(build, problem)?;
        let fe_hz = modes.frequencies_hz();
        let meas = &problem.meas;
        let basis = SerepBasis::select(&modes, &meas.equations, problem.n_md, opts.basis_tolerance)
            .map_err(UpdateError::Serep)?;
        if n == 0 {
            self.warn_initial_basis(&basis, &fe_hz, problem);
        }
        if basis.len() < problem.n_md && !self.warned_fewer {
            self.warned_fewer = true;
            self.warnings.push(UpdateWarning::FewerModes {
                requested: problem.n_md,
                used: basis.len(),
            });
        }
        let sens = ModalSensitivities::project(&fe.parameters, modes.shapes.as_ref(), &basis.modes);
        let eqs = frf_equations(
            &basis,
            &sens,
            &problem.omegas,
            &problem.h_test,
            &basis
                .modes
                .iter()
                .map(|&r| modes.shapes[(meas.excitation_eq, r)])
                .collect::<Vec<_>>(),
            opts.inverse,
        )
        .map_err(UpdateError::Sensitivity)?;
        let sfdac = SfdacSummary::new(&eqs.fe_frf, &problem.h_test);
        let fe_shapes = modes.at(&meas.equations);
        let pairs = pair_modes(
            &problem.test_shapes.shapes,
            &problem.test_hz,
            &fe_shapes,
            &fe_hz,
            opts.mac_min,
        );
        if n == 0 {
            self.fe_frfs_initial = eqs.fe_frf.clone();
            self.warn_unpaired(&pairs, problem);
        }
        if self.records.is_empty()
            || sfdac.mean > self.records[best_index(&self.records)].sfdac.mean
        {
            self.fe_frfs_best = eqs.fe_frf.clone();
        }
        self.fe_frfs_last = eqs.fe_frf.clone();
        let record = IterationRecord {
            index: n,
            parameters: self.p_bar.clone(),
            step: self.step.clone(),
            step_scale: self.step_scale,
            rank: self.rank,
            singular_values: std::mem::take(&mut self.singular_values),
            sfdac,
            fe_frequencies_hz: fe_hz,
            basis_modes: basis.modes.clone(),
            pairs: pairs.clone(),
            // The stage flag still says which equations gave p^n: it changes
            // only after this evaluation.
            stage: match (n, self.frequency_stage) {
                (0, _) => IterationStage::Initial,
                (_, true) => IterationStage::Frequencies,
                (_, false) => IterationStage::Frf,
            },
        };
        progress(UpdateProgress::Iteration(&record));
        self.records.push(record);
        Ok(Iterate {
            fe,
            modes,
            eqs,
            pairs,
        })
    }

    /// The FE model at p̄^n and its lowest `n_eig` modes (iteration 0: the
    /// initial model, and its modes when the suspension check computed enough).
    fn model_and_modes(
        &mut self,
        build: &mut dyn FnMut(&ParameterValues) -> Result<FeModel, ModelError>,
        problem: &Problem,
    ) -> Result<(FeModel, Modes), UpdateError> {
        let (start_model, start_modes) = match self.start.take() {
            Some(s) => (Some(s.model), s.modes),
            None => (None, None),
        };
        let fe = match start_model {
            Some(m) => m,
            None => {
                let values: ParameterValues = problem
                    .names
                    .iter()
                    .cloned()
                    .zip(self.p_bar.iter().copied())
                    .collect();
                build(&values).map_err(UpdateError::Model)?
            }
        };
        let n_eig = problem.n_eig;
        let modes = match start_modes.filter(|m| m.len() >= n_eig) {
            Some(m) => leading_modes(m, n_eig),
            None => lowest_modes(
                &fe.stiffness,
                &fe.mass,
                &EigenOptions {
                    count: n_eig,
                    expect_no_rigid_body_modes: fe.has_fixed_dofs,
                    ..EigenOptions::default()
                },
            )
            .map_err(UpdateError::Eigen)?,
        };
        Ok((fe, modes))
    }

    /// Warnings on the initial model: computed modes below the basis's
    /// highest left out as invisible, and updating frequencies within 1 % of
    /// an FE natural frequency (the paper's rule 2).
    fn warn_initial_basis(&mut self, basis: &SerepBasis, fe_hz: &[f64], problem: &Problem) {
        let dropped: Vec<f64> = basis
            .dropped
            .iter()
            .filter(|&&r| r < *basis.modes.last().unwrap_or(&0))
            .map(|&r| fe_hz[r])
            .collect();
        if !dropped.is_empty() {
            self.warnings.push(UpdateWarning::DroppedModes {
                iteration: 0,
                modes_hz: dropped,
            });
        }
        for u in &problem.updating.frequencies {
            if let Some(f) = fe_hz.iter().find(|&&f| (f - u.hz).abs() <= 0.01 * u.hz) {
                self.warnings.push(UpdateWarning::NearFeResonance {
                    hz: u.hz,
                    fe_hz: *f,
                });
            }
        }
    }

    /// Test resonances used that the initial model pairs with no mode.
    fn warn_unpaired(&mut self, pairs: &[Option<ModePair>], problem: &Problem) {
        for (t, p) in pairs.iter().enumerate().take(problem.r_used.max(1)) {
            if p.is_none() {
                self.warnings.push(UpdateWarning::UnpairedResonance {
                    resonance: t,
                    hz: problem.test_hz[t],
                });
            }
        }
    }
}

/// The first `count` of `modes` (ascending frequency).
fn leading_modes(modes: Modes, count: usize) -> Modes {
    if modes.len() == count {
        return modes;
    }
    Modes {
        omega2: modes.omega2[..count].to_vec(),
        shapes: modes.shapes.get(.., ..count).to_owned(),
    }
}
