//! The updating iteration (§3.1): at the current parameters p̄^n build the
//! model, compute its lowest modes, reduce by SEREP, form A p = b (Eq. 11–12,
//! optionally with Eq. 18–22), solve it by the truncated SVD (Eq. 41), and
//! compose p̄^{n+1} = p̄^n + p^{n+1} + p̄^n p^{n+1} (Eq. 29); stop when
//! max_j |p_j| < tol (Eq. 49).
//!
//! Safeguards: a step with 1 + p_j ≤ 0 (a property would become ≤ 0) is halved
//! until every 1 + p_j ≥ 0.1; if the SFDAC mean falls for two iterations in a
//! row, or a |p̄_j| exceeds `max_parameter`, the iteration stops and the best
//! iteration (highest SFDAC mean) is returned. When the iteration limit is hit
//! the best iteration is returned too.
//!
//! Combining the two kinds of equation (Eq. 21–22): each block is divided by
//! the Frobenius norm of its sensitivity matrix (A_h/‖A_h‖_F, b_h/‖A_h‖_F and
//! likewise for A_ω, b_ω), so neither dominates and each block's own solution
//! is unchanged. Before that, with `FrfWeighting::PerFrequency` (default),
//! each frequency block A_i, b_i is divided by ‖h̄_i‖ so that every updating
//! frequency counts alike; `FrfWeighting::None` keeps the paper's raw rows.
//!
//! One file per step of the iteration: `prepare` (the test's resonances,
//! the updating frequencies of Eq. 42 and the basis size), `state` (what
//! one iteration hands to the next, and the scoring of each iterate),
//! `equations` (A p = b, Eq. 11–12, 18–22), `step` (its solution, Eq. 41,
//! the safeguards and Eq. 29) and `stop` (Eq. 49 and the safeguards'
//! stopping rules).

mod equations;
mod prepare;
mod state;
mod step;
mod stop;

use frfup_parsers::deck::Deck;

use super::{StopReason, UpdateError, UpdateMethod, UpdateOptions, UpdateProgress, UpdateResult};
use crate::model::{self, FeModel, ModelError, ParameterValues};
use crate::testdata::MeasuredFrfs;
use state::IterationState;

pub use prepare::{eigen_count, MeasuredResonances};

const TWO_PI: f64 = 2.0 * std::f64::consts::PI;

/// Relative changes below which the frequency stage ends, and the largest
/// parameter step it takes.
const FREQUENCY_STAGE_EXIT: f64 = 0.01;
const FREQUENCY_STAGE_MAX_STEP: f64 = 0.3;
/// Weight of the mode-shape rows against the relative ω² rows.
const SHAPE_ROW_WEIGHT: f64 = 0.3;
/// Iterations after which the first stage ends even if its steps are not small.
const FREQUENCY_STAGE_ITERATIONS: usize = 12;
/// Tikhonov damping of the frequency stage, relative to the largest singular value.
const FREQUENCY_STAGE_DAMPING: f64 = 0.05;
/// MAC a pair needs to enter the frequency stage's equations.
const FREQUENCY_STAGE_MAC: f64 = 0.8;

/// Update the parameters of `deck` so that its FRFs match `test`.
pub fn update(
    deck: &Deck,
    test: &MeasuredFrfs,
    opts: &UpdateOptions,
) -> Result<UpdateResult, UpdateError> {
    update_with_progress(deck, test, opts, &mut |_| {})
}

/// [`update`], telling `progress` of every scored iteration and stage.
pub fn update_with_progress(
    deck: &Deck,
    test: &MeasuredFrfs,
    opts: &UpdateOptions,
    progress: &mut dyn FnMut(UpdateProgress),
) -> Result<UpdateResult, UpdateError> {
    match opts.method {
        UpdateMethod::Paper => update_model(
            &mut |values| model::build(deck, values),
            test,
            opts,
            progress,
            None,
        ),
        UpdateMethod::Robust => super::robust::update_robust(deck, test, opts, progress),
    }
}

/// The iteration on any model source: `build` assembles the FE model at the
/// given relative parameter changes (p̄, deck order names); `known`: the
/// test's resonances found by an earlier run on the same test and options.
///
/// Each pass scores the model at p̄^n (`IterationState::evaluate`), moves
/// out of the frequencies-first stage when its resonances are close, applies
/// the stopping rules, then forms and solves A p = b and composes p̄^{n+1}.
pub fn update_model(
    build: &mut dyn FnMut(&ParameterValues) -> Result<FeModel, ModelError>,
    test: &MeasuredFrfs,
    opts: &UpdateOptions,
    progress: &mut dyn FnMut(UpdateProgress),
    known: Option<&MeasuredResonances>,
) -> Result<UpdateResult, UpdateError> {
    prepare::check_options(opts)?;
    let (column, layout) = crate::testdata::layout::as_column(test);
    let mut warnings = Vec::new();
    let (problem, start) = prepare::prepare(build, &column, opts, known, &mut warnings)?;
    let mut state = IterationState::new(&problem, opts, start, warnings);
    let mut stop = StopReason::IterationLimit;
    for n in 0..=opts.max_iter {
        let iterate = state.evaluate(n, build, &problem, opts, progress)?;
        let was_frequency_stage = state.frequency_stage;
        if state.frequency_stage
            && stop::leaves_frequency_stage(n, &iterate.pairs, &state.step, &problem, opts)
        {
            state.frequency_stage = false;
        }
        if let Some(reason) = state.stopping_rule(n, was_frequency_stage, opts) {
            stop = reason;
            break;
        }
        let (a, b) = if state.frequency_stage {
            equations::frequency_system(&iterate, &problem, opts)
        } else {
            equations::frf_system(&iterate, &problem, opts)
        };
        let p = state.solve(n, &a, &b, &problem, opts)?;
        if let Some(reason) = state.take_step(n, p, &problem, opts) {
            stop = reason;
            break;
        }
    }
    Ok(state.finish(problem, opts, layout, stop))
}
