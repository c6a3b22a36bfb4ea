//! The full-band FRF fit: every line and channel above the noise floor,
//! weighted log-magnitude and phase residuals, damping identified along.
//! [`data`] prepares the measured FRFs (noise per channel, weights),
//! [`fit`] predicts model FRFs by modal superposition and fits a few
//! parameters by bounded Levenberg–Marquardt, and [`estimate`] is the final
//! stage of `frfup update`: the deck's parameters by maximum a posteriori
//! within their bounds, with their uncertainty. `frfup diagnose` fits its
//! hypotheses with the same pieces.

pub mod coarse;
pub mod data;
pub mod estimate;
pub mod fit;
pub mod jacobian;
pub mod lm;
pub mod objective;
pub mod reduced;
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

/// Wall-clock laps of the update's stages on stderr when the environment
/// variable `FRFUP_TIMING` is set (a profile without a profiler).
#[doc(hidden)]
pub fn lap(name: &str) {
    use std::sync::Mutex;
    use std::time::Instant;
    static LAST: Mutex<Option<Instant>> = Mutex::new(None);
    if std::env::var_os("FRFUP_TIMING").is_none() {
        return;
    }
    let now = Instant::now();
    if let Ok(mut last) = LAST.lock() {
        let since = last.map_or(0.0, |t| (now - t).as_secs_f64());
        eprintln!("timing {name:<30} {since:.3} s");
        *last = Some(now);
    }
}
