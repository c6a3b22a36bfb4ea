//! FRF-based model updating (Yan & Golinval): SEREP reduction, FRF and
//! natural-frequency sensitivity equations, SVD solution, composed parameters.
//!
//! One module per step of the method:
//! [`measured`] (test channels → FE DOFs, Eq. 50), [`frequencies`] (peak
//! picking, Eq. 42), [`serep`] (Eq. 32–34, §3.3–3.4), [`sensitivity`]
//! (Eq. 7–12, 16–20), [`svd_solve`] (Eq. 35–41), [`correlation`] (Eq. 44–46,
//! MAC) and [`iterate`] (Eq. 26–29, 49). The files of an update are written
//! by `report::output` (the report layer, above this one).
//!
//! Entry points: [`update`] / [`update_with_progress`].

pub mod correlation;
pub mod frequencies;
pub mod fullband;
pub mod identify;
pub mod iterate;
pub mod measured;
pub mod model_states;
pub mod options;
pub mod robust;
pub mod sensitivity;
pub mod serep;
pub mod svd_solve;

use std::fmt;

use crate::model::{ModelError, ParameterValues};
use crate::solvers::eigen::EigenError;

pub use correlation::{
    fdac_matrix, mac, mac_matrix, sfdac, MacMatrix, ModePair, SfdacSummary, ShapeSource, TestShapes,
};
pub use frequencies::{Resonance, SkippedFrequency, UpdatingFrequencies, UpdatingFrequency};
pub use iterate::{update, update_model, update_with_progress};
pub use options::{
    Frequencies, FrfWeighting, InverseChoice, ResonanceMethod, UpdateMethod, UpdateOptions,
    UpdateSettings, DEFAULT_PERTURBATION,
};
pub use serep::{InverseMethod, SerepBasis};

/// Why an update could not run.
#[derive(Debug)]
pub enum UpdateError {
    /// The deck gave no FE model (at the initial or an updated parameter set).
    Model(ModelError),
    /// The eigen solution failed.
    Eigen(EigenError),
    /// The deck defines no `param`.
    NoParameters,
    /// The test data hold no channel.
    NoChannels,
    /// No test channel matches a DOF of the model.
    NoMatchingChannels {
        unmatched: Vec<String>,
    },
    /// The excitation DOF (reference of the records) is not a DOF of the model.
    UnknownExcitation {
        excitation: String,
    },
    /// A channel's value count differs from the frequency line count.
    ChannelLength {
        channel: String,
        values: usize,
        lines: usize,
    },
    /// No resonance could be found in the measured FRFs.
    NoResonances,
    /// No usable updating frequency remains.
    NoUpdatingFrequencies {
        skipped: Vec<SkippedFrequency>,
    },
    /// An option is out of range.
    InvalidOption(String),
    Serep(serep::SerepError),
    Sensitivity(sensitivity::SensitivityError),
    Svd(svd_solve::SvdSolveError),
    /// The full-band estimate could not run.
    Estimate(fullband::FitError),
}

impl fmt::Display for UpdateError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            UpdateError::Model(e) => write!(f, "model: {e}"),
            UpdateError::Eigen(e) => write!(f, "{e}"),
            UpdateError::NoParameters => {
                write!(f, "the deck defines no updating parameter (add `param NAME QTY IDS` statements)")
            }
            UpdateError::NoChannels => write!(f, "the test data hold no FRF"),
            UpdateError::NoMatchingChannels { unmatched } => write!(
                f,
                "no test channel matches a free DOF of the model (check node ids, `sensor` statements and the analysis type): {}",
                unmatched.join(", ")
            ),
            UpdateError::UnknownExcitation { excitation } => {
                write!(f, "the excitation DOF {excitation} is not a free DOF of the model")
            }
            UpdateError::ChannelLength { channel, values, lines } => {
                write!(f, "channel {channel} has {values} values but the test has {lines} frequency lines")
            }
            UpdateError::NoResonances => write!(
                f,
                "no resonance found in the measured FRFs; give the updating frequencies explicitly (--freqs)"
            ),
            UpdateError::NoUpdatingFrequencies { skipped } => {
                write!(f, "no usable updating frequency")?;
                for s in skipped {
                    write!(f, "; {:.4} Hz: {}", s.requested_hz, s.reason)?;
                }
                Ok(())
            }
            UpdateError::InvalidOption(s) => write!(f, "{s}"),
            UpdateError::Serep(e) => write!(f, "{e}"),
            UpdateError::Sensitivity(e) => write!(f, "{e}"),
            UpdateError::Svd(e) => write!(f, "solving the updating equations: {e}"),
            UpdateError::Estimate(e) => write!(f, "full-band estimate: {e}"),
        }
    }
}

impl std::error::Error for UpdateError {}

/// Something the user should know about a run that still produced a result.
#[derive(Clone, Debug, PartialEq)]
pub enum UpdateWarning {
    /// Test channels that match no free DOF of the model (ignored).
    UnmatchedChannels { labels: Vec<String> },
    /// Channels driven at another reference than the excitation (ignored).
    OtherReferences { excitation: String, ignored: usize },
    /// Two channels measure the same FE DOF; the later one is ignored.
    DuplicateChannel { label: String },
    /// The excitation DOF was not measured: the model's mode shapes at it
    /// stand in for the driving point in the updating equations.
    DrivingPointNotMeasured { excitation: String },
    /// A candidate updating frequency was not used.
    SkippedFrequency(SkippedFrequency),
    /// Test resonances of a free-free model below half its first elastic
    /// frequency, taken as suspension modes and not used.
    SuspensionModes {
        modes_hz: Vec<f64>,
        first_elastic_hz: f64,
    },
    /// An updating frequency lies within 1 % of a natural frequency of the
    /// initial model (the paper's rule 2 advises against it).
    NearFeResonance { hz: f64, fe_hz: f64 },
    /// Computed modes left out of the SEREP basis as invisible at the measured DOFs.
    DroppedModes {
        iteration: usize,
        modes_hz: Vec<f64>,
    },
    /// The basis holds fewer modes than asked for.
    FewerModes { requested: usize, used: usize },
    /// A test resonance has no FE mode partner.
    UnpairedResonance { resonance: usize, hz: f64 },
    /// The equations do not determine these parameter combinations (SVD null space).
    Indistinguishable {
        iteration: usize,
        combinations: Vec<Vec<(String, f64)>>,
    },
    /// The step would have made a property ≤ 0 (1 + p ≤ 0) and was scaled down.
    StepLimited {
        iteration: usize,
        scale: f64,
        parameters: Vec<String>,
    },
    /// The SFDAC mean fell for two iterations in a row: stopped.
    Diverged { iteration: usize, best: usize },
    /// A parameter left the admissible range: stopped.
    ParameterExploded {
        iteration: usize,
        name: String,
        value: f64,
        best: usize,
    },
    /// The iteration limit was reached before max |p| < tol.
    NotConverged { iterations: usize, last_step: f64 },
    /// The full-band estimate reached its iteration limit.
    EstimateNotConverged { iterations: usize },
    /// A step of the first stage gave no usable model; the full-band
    /// estimate started from the deck.
    FirstStageStopped { reason: String },
    /// The full-band estimate's parameters give no usable model; the first
    /// stage's result is returned.
    EstimateRejected { reason: String },
    /// Channels with no point above the noise floor, left out of the
    /// full-band estimate.
    SilentChannels { channels: Vec<String> },
    /// The final fit stays well above the noise level: the deck's parameters
    /// do not explain the test (missing physics, or a data error).
    Misfit { ratio: f64 },
    /// Parameters the data do not determine.
    NotIdentified {
        parameters: Vec<String>,
        directions: Vec<Vec<(String, f64)>>,
    },
}

impl fmt::Display for UpdateWarning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            UpdateWarning::UnmatchedChannels { labels } => {
                write!(f, "{} channel(s) match no free DOF of the model and are ignored: {}", labels.len(), labels.join(", "))
            }
            UpdateWarning::OtherReferences { excitation, ignored } => write!(
                f,
                "{ignored} channel(s) have another reference than the excitation {excitation} and are ignored"
            ),
            UpdateWarning::DuplicateChannel { label } => {
                write!(f, "channel {label} measures a DOF already measured; ignored")
            }
            UpdateWarning::DrivingPointNotMeasured { excitation } => write!(
                f,
                "the driving point {excitation} was not measured: the model's mode shapes at {excitation} stand in for it in the updating equations (SEREP expansion)"
            ),
            UpdateWarning::SkippedFrequency(s) => {
                write!(f, "updating frequency {:.4} Hz skipped: {}", s.requested_hz, s.reason)
            }
            UpdateWarning::SuspensionModes { modes_hz, first_elastic_hz } => write!(
                f,
                "test resonance(s) at {} Hz lie below half the first elastic frequency of the free-free model ({first_elastic_hz:.3} Hz): taken as suspension modes, not used",
                modes_hz.iter().map(|x| format!("{x:.3}")).collect::<Vec<_>>().join(", ")
            ),
            UpdateWarning::NearFeResonance { hz, fe_hz } => write!(
                f,
                "updating frequency {hz:.4} Hz is within 1 % of the initial model's natural frequency {fe_hz:.4} Hz"
            ),
            UpdateWarning::DroppedModes { iteration, modes_hz } => write!(
                f,
                "iteration {iteration}: {} mode(s) hardly visible at the measured DOFs left out of the SEREP basis ({} Hz)",
                modes_hz.len(),
                modes_hz.iter().map(|x| format!("{x:.3}")).collect::<Vec<_>>().join(", ")
            ),
            UpdateWarning::FewerModes { requested, used } => write!(
                f,
                "the SEREP basis holds {used} modes instead of {requested} (at most the number of measured DOFs, visible modes only)"
            ),
            UpdateWarning::UnpairedResonance { resonance, hz } => {
                write!(f, "test resonance {} ({hz:.4} Hz) has no FE mode partner (MAC)", resonance + 1)
            }
            UpdateWarning::Indistinguishable { iteration, combinations } => {
                write!(f, "iteration {iteration}: the equations cannot distinguish ")?;
                for (i, c) in combinations.iter().enumerate() {
                    if i > 0 {
                        write!(f, "; ")?;
                    }
                    let terms: Vec<String> = c.iter().map(|(n, v)| format!("{v:+.3}·{n}")).collect();
                    write!(f, "{}", terms.join(" "))?;
                }
                write!(f, " (SVD null space; these combinations keep their current values)")
            }
            UpdateWarning::StepLimited { iteration, scale, parameters } => write!(
                f,
                "iteration {iteration}: the step would make {} zero or negative; scaled by {scale}",
                parameters.join(", ")
            ),
            UpdateWarning::Diverged { iteration, best } => write!(
                f,
                "SFDAC mean fell for two iterations in a row at iteration {iteration}: stopped; keeping iteration {best} (best SFDAC mean)"
            ),
            UpdateWarning::ParameterExploded { iteration, name, value, best } => write!(
                f,
                "iteration {iteration}: parameter {name} reached {value:.4e}: diverging, stopped; keeping iteration {best} (best SFDAC mean)"
            ),
            UpdateWarning::NotConverged { iterations, last_step } => write!(
                f,
                "not converged after {iterations} iterations (last max |p| = {last_step:.3e})"
            ),
            UpdateWarning::EstimateNotConverged { iterations } => write!(
                f,
                "the full-band estimate did not converge in {iterations} Levenberg–Marquardt iterations; the best point found is returned"
            ),
            UpdateWarning::FirstStageStopped { reason } => write!(
                f,
                "the first stage stopped ({reason}); the full-band estimate started from the deck"
            ),
            UpdateWarning::EstimateRejected { reason } => write!(
                f,
                "the full-band estimate's parameters give no usable model ({reason}); the first stage's result is returned"
            ),
            UpdateWarning::SilentChannels { channels } => write!(
                f,
                "channel(s) {} carry no response above the noise floor (below 1e-9 of the largest channel, or zero): left out of the full-band estimate",
                channels.join(", ")
            ),
            UpdateWarning::Misfit { ratio } => write!(
                f,
                "the updated model fits the FRFs at {ratio:.1}× the noise level: the deck's parameters do not explain the test; run `frfup diagnose` to look for missing physics or data errors"
            ),
            UpdateWarning::NotIdentified { parameters, directions } => {
                write!(f, "not identified by these data: {}", parameters.join(", "))?;
                for d in directions {
                    let terms: Vec<String> = d.iter().map(|(n, v)| format!("{v:+.2}·{n}")).collect();
                    write!(f, "; unseen direction {}", terms.join(" "))?;
                }
                Ok(())
            }
        }
    }
}

/// Why the iteration stopped.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StopReason {
    /// max |p| < tol (Eq. 49).
    Converged,
    IterationLimit,
    Diverged,
    ParameterExploded,
}

impl StopReason {
    pub fn name(self) -> &'static str {
        match self {
            StopReason::Converged => "converged",
            StopReason::IterationLimit => "iteration limit",
            StopReason::Diverged => "diverged",
            StopReason::ParameterExploded => "parameter exploded",
        }
    }
}

/// One iteration: the model at p̄^n and how it correlates with the test.
#[derive(Clone, Debug, PartialEq)]
pub struct IterationRecord {
    /// n (0 = the initial model).
    pub index: usize,
    /// p̄^n, aligned with [`UpdateResult::parameter_names`].
    pub parameters: Vec<f64>,
    /// p^n, the step that produced p̄^n (zeros for n = 0), after any scaling.
    pub step: Vec<f64>,
    /// Factor the solved step was scaled by to keep properties positive (1 = none).
    pub step_scale: f64,
    /// Rank and singular values of the system that gave p^n (empty for n = 0).
    pub rank: usize,
    pub singular_values: Vec<f64>,
    /// SFDAC at the updating frequencies (Eq. 45–46).
    pub sfdac: SfdacSummary,
    /// Natural frequencies (Hz) of the computed modes of this model.
    pub fe_frequencies_hz: Vec<f64>,
    /// Indices of the modes in the SEREP basis (into `fe_frequencies_hz`).
    pub basis_modes: Vec<usize>,
    /// Test resonance → FE mode pairs (MAC on the measured DOFs).
    pub pairs: Vec<Option<ModePair>>,
    /// Which equations produced the step p^n.
    pub stage: IterationStage,
}

/// What an update reports as it runs, for a progress display: each scored
/// iteration, and the start of the full-band estimate, which scores nothing
/// until it ends (seconds on a large model).
#[derive(Clone, Copy, Debug)]
pub enum UpdateProgress<'a> {
    /// An iteration was scored.
    Iteration(&'a IterationRecord),
    /// The robust pipeline's full-band estimate starts.
    EstimateStarted,
}

/// Which equations produced an iteration's step: the convergence chart
/// marks where they change.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum IterationStage {
    /// Iteration 0, the initial model: no step.
    Initial,
    /// The frequencies-first stage: natural-frequency equations alone (Eq. 16–22).
    Frequencies,
    /// FRF equations at the updating frequencies (Eq. 11–12, solved by Eq. 35–41).
    Frf,
    /// The full-band estimate (the robust pipeline's last record).
    Estimate,
}

/// The outcome of an update.
#[derive(Clone, Debug)]
pub struct UpdateResult {
    pub converged: bool,
    pub stop: StopReason,
    /// Parameter names in deck order.
    pub parameter_names: Vec<String>,
    /// Index (into `iterations`) of the model returned as the updated one.
    pub final_iteration: usize,
    pub iterations: Vec<IterationRecord>,
    /// All measured resonances found (ascending); the first `resonances_used` drive Eq. 42.
    pub resonances: Vec<Resonance>,
    pub resonances_used: usize,
    pub updating_frequencies: UpdatingFrequencies,
    /// N_md asked for.
    pub modes: usize,
    /// Measured DOF labels (`NODE±dir`, FE node ids) in equation order, and the excitation.
    pub measured_dofs: Vec<String>,
    pub excitation: String,
    /// FDAC matrices (Eq. 44) of the initial and final models at the updating frequencies.
    pub fdac_initial: Vec<Vec<f64>>,
    pub fdac_final: Vec<Vec<f64>>,
    /// The test's resonances as found (suspension modes included), with
    /// their fitted shapes.
    pub test_resonances: iterate::MeasuredResonances,
    pub warnings: Vec<UpdateWarning>,
    pub options: UpdateOptions,
    /// What the campaign measured (a column, a row used by reciprocity, …).
    pub layout: crate::testdata::layout::Layout,
    /// The test shapes that paired resonances with FE modes (the MAC of
    /// `pairs`), and where they come from.
    pub pairing_shapes: TestShapes,
    /// The full-band estimate ([`UpdateMethod::Robust`]), whose parameters
    /// are those of the final record.
    pub estimate: Option<fullband::estimate::FullBandEstimate>,
}

impl UpdateResult {
    /// The updated p̄ of the returned model.
    pub fn parameters(&self) -> &[f64] {
        &self.iterations[self.final_iteration].parameters
    }

    /// The updated p̄ as a name → value map (for `model::build` / `updated_deck`).
    pub fn parameter_values(&self) -> ParameterValues {
        self.parameter_names
            .iter()
            .cloned()
            .zip(self.parameters().iter().copied())
            .collect()
    }

    /// The returned model's record.
    pub fn final_record(&self) -> &IterationRecord {
        &self.iterations[self.final_iteration]
    }
}
