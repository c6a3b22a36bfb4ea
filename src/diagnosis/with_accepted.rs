//! A new extension fitted together with the accepted ones and the deck's
//! parameters, when no candidate passes with them held.
//!
//! Each round fits its candidates on the current model: the extensions
//! accepted so far stay at their values. An extension accepted alone
//! absorbs part of an effect still missing (seed-1 diagnosis benchmark
//! case 137: an added mass of 5.4 kg at node 22 and a flexible joint at
//! node 2; the mass, fitted first, ended at 5.06 kg and the deck's
//! `m_mass2` at −28 % (truth −16 %); held there, the joint fitted at
//! k = 5.1e6 N·m/rad (truth 7.2e5) and predicted no better than the deck's
//! parameters refitted alone, and the search stopped at 1.84× the noise
//! level). When no candidate of a round passes, the best few are fitted
//! again with the accepted extensions' values and the deck's parameters
//! free (x = ln θ of the accepted, ln θ of the new one, p̄), from the
//! accepted values, a grid over the new one's range and its single fit.
//! The best is judged (in `greedy.rs`) against the best the model without
//! it predicts: the current model, the deck's parameters refitted alone,
//! and the same joint fit without the new extension
//! ([`refitted_without`]), so that it competes with what re-estimating the
//! old ones achieves.

use frfup_parsers::deck::Deck;
use rayon::prelude::*;

use super::fit::DampingState;
use super::hypotheses::{Hypothesis, Physics};
use super::joint_screen::FULL_FIT;
use super::refit::{self, Joint, JointFit, JointSettings};
use super::select::{Engine, HypFit};

/// Candidates fitted again this way (two on large models).
const CANDIDATES: usize = 3;
/// Grid points over the new extension's log range.
const PER_AXIS: usize = 5;

/// A new extension fitted with the accepted ones and the deck's parameters.
pub(super) struct WithAccepted {
    pub hypothesis: Hypothesis,
    /// Logs in the order of the accepted extensions with a parameter, then
    /// the new one; the deck parameters' changes relative to the base deck.
    pub fit: JointFit,
    /// Its validation error (blocked cross-validation).
    pub v: f64,
}

/// The best (by validation error) of the round's fitted candidates
/// `fitted` (cost order) refitted with the accepted extensions `accepted`
/// (on `base`, their values) and the deck's parameters, of those well
/// determined and inside their bounds. `None` when nothing was accepted
/// with a value or no fit qualifies.
pub(super) fn best_with_accepted(
    engine: &Engine,
    base: &Deck,
    accepted: &[(Hypothesis, Option<f64>)],
    fitted: &[(Hypothesis, HypFit)],
    damp: &DampingState,
    large: bool,
) -> Option<WithAccepted> {
    if accepted.iter().all(|a| a.1.is_none()) {
        return None;
    }
    let logs = accepted_logs(accepted);
    let pool: Vec<&(Hypothesis, HypFit)> = fitted
        .iter()
        .filter(|(h, _)| h.param.is_some() && h.physics != Physics::Suspension)
        .take(if large { 2 } else { CANDIDATES })
        .collect();
    let fits: Vec<Option<WithAccepted>> = pool
        .par_iter()
        .map(|(h, f)| refit_with(engine, base, accepted, &logs, h, f, damp))
        .collect();
    fits.into_iter()
        .flatten()
        .min_by(|a, b| a.v.total_cmp(&b.v))
}

/// The log values of the accepted extensions with a parameter, in order
/// (the first unknowns of a [`Joint`] over them).
fn accepted_logs(accepted: &[(Hypothesis, Option<f64>)]) -> Vec<f64> {
    accepted
        .iter()
        .filter(|a| a.0.param.is_some())
        .map(|a| a.1.map_or(0.0, f64::ln))
        .collect()
}

/// The accepted extensions and the deck's parameters refitted without a new
/// extension, from the accepted values: its validation error (`None` when
/// no model results).
pub(super) fn refitted_without(
    engine: &Engine,
    base: &Deck,
    accepted: &[(Hypothesis, Option<f64>)],
    damp: &DampingState,
) -> Option<f64> {
    let problem = Joint::with_deck_parameters(base, accepted.iter().map(|a| &a.0).collect());
    let mut start = accepted_logs(accepted);
    start.extend(std::iter::repeat_n(0.0, problem.deck_params.len()));
    let settings = JointSettings {
        frequency_stage: false,
        ..FULL_FIT
    };
    let jf = refit::fit_joint(engine, &problem, &[start], damp, &engine.all, settings)?;
    Some(refit::validate_joint(engine, &problem, &jf))
}

/// `h` (its single fit `f`) fitted with the accepted extensions and the
/// deck's parameters; `None` when no start gives a model, or when its fit
/// ends on a bound or leaves its value undetermined (σ of ln θ ≥ 1).
fn refit_with(
    engine: &Engine,
    base: &Deck,
    accepted: &[(Hypothesis, Option<f64>)],
    logs: &[f64],
    h: &Hypothesis,
    f: &HypFit,
    damp: &DampingState,
) -> Option<WithAccepted> {
    let mut hyps: Vec<&Hypothesis> = accepted.iter().map(|a| &a.0).collect();
    hyps.push(h);
    let problem = Joint::with_deck_parameters(base, hyps);
    let starts = refit::new_extension_starts(&problem, logs, f.log_value, PER_AXIS);
    let jf = refit::fit_joint(engine, &problem, &starts, damp, &engine.all, FULL_FIT)?;
    let new = logs.len();
    if jf.on_bound[new] || !(jf.std_log[new] < 1.0) {
        return None;
    }
    let v = refit::validate_joint(engine, &problem, &jf);
    Some(WithAccepted {
        hypothesis: h.clone(),
        fit: jf,
        v,
    })
}
