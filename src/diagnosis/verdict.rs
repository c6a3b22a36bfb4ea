//! What a diagnosis concludes, in one place: every report, the command's
//! summary and its exit code read the same [`Verdict`].
//!
//! The FRF error is the mean squared weighted log error divided by its
//! noise-only value (1 = the noise level); the final model counts as at the
//! noise level below 1.25 of it ([`Diagnosis::at_noise_level`]). A parameter
//! the first stage moved by more than [`LARGE_CHANGE`] (relative) is itself
//! evidence of missing physics: such a change is reported, whatever else is
//! found.

use super::{sig, Diagnosis, Finding};

/// A relative change of a deck parameter above this (±30 %) is implausible
/// for a model a person built from drawings and handbook values.
pub const LARGE_CHANGE: f64 = 0.3;

/// The conclusion of a diagnosis.
#[derive(Clone, Debug, PartialEq)]
pub enum Verdict {
    /// Extensions were found and the extended model explains the test to the
    /// noise level.
    Explained,
    /// Extensions were found and explain the test to the noise level, but
    /// other hypotheses explain it as well with these sensors: one sentence
    /// per such finding, with the measurement that would tell them apart.
    CannotTellApart { pairs: Vec<String> },
    /// Extensions were found, but disagreement remains above the noise level.
    PartlyExplained { frf_error: f64 },
    /// No extension, and the deck's own parameters explain the test to the
    /// noise level with plausible changes.
    NothingMissing,
    /// No physical extension (data errors may have been undone); the
    /// parameters reach the noise level only with implausibly large
    /// changes, which may stand for missing physics.
    AbsorbedByParameters { large: Vec<(String, f64)> },
    /// No hypothesis explains the disagreement, which stays above the noise level.
    Unexplained { frf_error: f64 },
}

impl Verdict {
    /// The verdict of `d`.
    pub fn of(d: &Diagnosis) -> Verdict {
        Verdict::from_parts(
            &d.findings,
            d.at_noise_level,
            d.diagnosed.frf_error,
            &d.updated_parameters,
        )
    }

    /// The verdict of findings, whether the final model is at the noise
    /// level, its FRF error and the changes of the deck's parameters in the
    /// final model ([`super::Diagnosis::updated_parameters`]).
    pub fn from_parts(
        findings: &[Finding],
        at_noise_level: bool,
        frf_error: f64,
        updated_parameters: &crate::model::ParameterValues,
    ) -> Verdict {
        let mut large: Vec<(String, f64)> = updated_parameters
            .iter()
            .filter(|(_, p)| p.abs() > LARGE_CHANGE)
            .map(|(n, p)| (n.clone(), *p))
            .collect();
        large.sort_by(|a, b| b.1.abs().total_cmp(&a.1.abs()));
        let pairs: Vec<String> = findings
            .iter()
            .filter_map(|f| {
                let other = &f.alternatives.first()?.description;
                Some(f.tell_apart.as_ref().map_or_else(
                    || {
                        format!(
                            "{} and {other} explain the data equally well with these sensors.",
                            f.label
                        )
                    },
                    |t| t.sentence(&f.label),
                ))
            })
            .collect();
        // Data errors undone are corrections of the test, not explanations
        // of what the model lacks: with nothing else found, implausible
        // parameter changes still stand for missing physics.
        let physical = findings.iter().any(|f| !f.physics.is_data_error());
        match (findings.is_empty(), at_noise_level) {
            (false, true) if !physical && !large.is_empty() => {
                Verdict::AbsorbedByParameters { large }
            }
            (false, true) if pairs.is_empty() => Verdict::Explained,
            (false, true) => Verdict::CannotTellApart { pairs },
            (false, false) => Verdict::PartlyExplained { frf_error },
            (true, false) => Verdict::Unexplained { frf_error },
            (true, true) if large.is_empty() => Verdict::NothingMissing,
            (true, true) => Verdict::AbsorbedByParameters { large },
        }
    }

    /// Whether the diagnosis reached a conclusion it can stand behind
    /// (`frfup diagnose` exits 1 otherwise).
    pub fn is_conclusive(&self) -> bool {
        matches!(self, Verdict::Explained | Verdict::NothingMissing)
    }

    /// A short status word for summaries and the report's status box.
    pub fn status(&self) -> &'static str {
        match self {
            Verdict::Explained => "explained",
            Verdict::CannotTellApart { .. } => "cannot tell apart",
            Verdict::PartlyExplained { .. } => "partly explained",
            Verdict::NothingMissing => "nothing missing",
            Verdict::AbsorbedByParameters { .. } => "parameters absorb it",
            Verdict::Unexplained { .. } => "unexplained",
        }
    }

    /// The verdict in one or two sentences.
    pub fn sentence(&self) -> String {
        match self {
            Verdict::Explained => {
                "The extended model explains the test to the noise level.".into()
            }
            Verdict::CannotTellApart { pairs } => format!(
                "The extended model explains the test to the noise level, but not uniquely. {}",
                pairs.join(" ")
            ),
            Verdict::PartlyExplained { frf_error } => format!(
                "The findings improve the fit, but disagreement remains at {}× the noise level: physics outside the dictionary, a data error, or effects too weak to separate.",
                sig(*frf_error)
            ),
            Verdict::NothingMissing => {
                "Nothing is missing: the deck's own parameters, changed plausibly, explain the test to the noise level.".into()
            }
            Verdict::AbsorbedByParameters { large } => {
                let list: Vec<String> = large
                    .iter()
                    .map(|(n, p)| format!("{n} {:+.0} %", 100.0 * p))
                    .collect();
                format!(
                    "No physical extension was accepted, but the deck's parameters reach the noise level only with implausibly large changes ({}): these may stand for physics the deck lacks.",
                    list.join(", ")
                )
            }
            Verdict::Unexplained { frf_error } => format!(
                "Unexplained: no hypothesis was accepted and the model stays at {}× the noise level. Physics outside the dictionary, a data error, or effects too weak to separate.",
                sig(*frf_error)
            ),
        }
    }
}
