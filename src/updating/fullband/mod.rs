//! The full-band FRF fit: every line and channel above the noise floor,
//! weighted log-magnitude and phase residuals, damping identified along.
//! [`data`] prepares the measured FRFs (noise per channel, weights; a long
//! record thinned to its informative [`lines`]),
//! [`fit`] predicts model FRFs by modal superposition and fits a few
//! parameters by bounded Levenberg–Marquardt, and [`estimate`] is the final
//! stage of `frfup update`: the deck's parameters by maximum a posteriori
//! within their bounds, with their uncertainty. `frfup diagnose` fits its
//! hypotheses with the same pieces.

pub mod coarse;
pub mod damping_fit;
pub mod data;
pub mod estimate;
pub mod fit;
pub mod jacobian;
pub mod lines;
pub mod lm;
pub mod objective;
pub mod prior;
pub mod reduced;
pub mod ritz;
pub mod uncertainty;

use std::fmt;

use crate::model::ModelError;

/// Why a full-band fit could not run.
#[derive(Debug)]
pub enum FitError {
    Model(ModelError),
    Eigen(String),
    Data(String),
}

impl fmt::Display for FitError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            FitError::Model(e) => write!(f, "model: {e}"),
            FitError::Eigen(e) => write!(f, "modes: {e}"),
            FitError::Data(e) => write!(f, "test data: {e}"),
        }
    }
}

impl std::error::Error for FitError {}
