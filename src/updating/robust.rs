//! The default pipeline ([`UpdateMethod::Robust`]).
//!
//! 1. The paper's iteration as a first stage ([`update_model`]) with the
//!    robust options: resonances by the multi-channel pole fit, the
//!    frequencies-first stage, damped steps. It brings the model near the
//!    test cheaply; its result is one of the starts of stage 2.
//! 2. The full-band estimate ([`estimate`]): every line and channel, the
//!    damping fitted along, bounds and priors, from the better of the deck
//!    (p̄ = 0) and stage 1's best iteration, and from the other too when the
//!    better ends above the noise level; when all of them end clearly above
//!    it (1.1×), from up to `spread_starts` points spread over ±0.3 too. Its
//!    parameters are the result, with their uncertainty; the update has
//!    converged when this stage has.
//! 3. The final parameters are scored like an iteration (SFDAC at the
//!    updating frequencies, pairs, FDAC) and appended as the last record,
//!    so that every table and chart shows the model returned.

use frfup_parsers::deck::Deck;

use super::fullband::data::TestData;
use super::fullband::estimate::{
    estimate, fit_start, EstimateRequest, FullBandEstimate, StartFit, SPREAD_START,
};
use super::fullband::FitError;
use super::iterate::update_model;
use super::{
    IterationRecord, IterationStage, StopReason, UpdateError, UpdateMethod, UpdateOptions,
    UpdateProgress, UpdateResult, UpdateWarning,
};
use crate::model::{self, ParameterValues};
use crate::testdata::MeasuredFrfs;

/// Misfit (mean squared residual over its noise-level value) above which the
/// update warns that its parameters do not explain the test.
pub const MISFIT_WARNING: f64 = 4.0;
/// Misfit above which the estimate is run again from the other starts: the
/// noise level itself. The noise level's estimate runs high (at the truth
/// the fits of the update benchmark sit at 0.94× it; the median of its 200
/// cases is 0.935×, 8 are above 1), so a minimum at or above it may be a
/// local one: case 147 of seed 1 ended at 1.017× from the first stage's
/// result with two parameters 0.07 from the truth, 100 standard deviations,
/// where the deck's start reaches the truth at 0.955×.
const RESTART_MISFIT: f64 = 1.0;
/// Misfit above which the fit is not at the noise level, whatever the
/// scatter of the noise level's estimate: at the truth, the 600 cases of
/// the update benchmark's seeds 1, 2 and 11 end at 1.02× it at most. Above
/// it the estimate is run from `spread_starts` further starts (each a whole
/// estimate), which stop once one fits below it. Seed 11's case 058 (a
/// T-frame's two crossbar arms' Iy changed +0.35 and −0.25, sensors in x
/// alone) ended at 1.31× with both 0.4 from the truth and standard
/// deviations of 0.0005: a local minimum that looks certain.
const SPREAD_MISFIT: f64 = 1.1;

/// Run the robust pipeline.
pub fn update_robust(
    deck: &Deck,
    test: &MeasuredFrfs,
    opts: &UpdateOptions,
    progress: &mut dyn FnMut(UpdateProgress),
) -> Result<UpdateResult, UpdateError> {
    // The deck's own start of the estimate needs nothing of the first
    // stage, which leaves a core idle most of its time: fitted beside it,
    // as a task of the pool (a thread of its own would deadlock a pool of
    // one thread when the update itself runs on it, as in `diagnose`: the
    // pool's thread would wait for a thread that waits for the pool).
    let (column, _) = crate::testdata::layout::as_column(test);
    let mut side = None;
    let first = rayon::in_place_scope(|scope| {
        scope.spawn(|_| {
            side = Some(test_data(deck, &column).map(|data| {
                let np = model::parameter_names(deck).len();
                let fitted = (np > 0)
                    .then(|| fit_start(deck, &data, &vec![0.0; np]))
                    .flatten();
                (data, fitted)
            }));
        });
        first_stage(deck, test, opts, progress)
    });
    let mut result = first?;
    let (data, fitted) = side.expect("the scope ran its task")?;
    let silent = data.silent_channels();
    if !silent.is_empty() {
        result
            .warnings
            .push(UpdateWarning::SilentChannels { channels: silent });
    }
    let np = result.parameter_names.len();
    progress(UpdateProgress::EstimateStarted);
    let est = best_estimate(deck, &data, starts(&result, np), opts, fitted)?;
    let values = est.values();
    let p_final: Vec<f64> = result
        .parameter_names
        .iter()
        .map(|n| values.get(n).copied().unwrap_or(0.0))
        .collect();
    match score(deck, test, &values, &p_final, &result) {
        Ok((record, fdac)) => {
            append_final(&mut result, record, fdac, &p_final);
            progress(UpdateProgress::Iteration(result.final_record()));
        }
        // The estimate's parameters give no usable model (e.g. a mechanism
        // once a stiffness sits at its lower bound): keep the first stage's
        // result and say that the update did not converge.
        Err(e) => {
            result.converged = false;
            result.stop = StopReason::Diverged;
            result.warnings.push(UpdateWarning::EstimateRejected {
                reason: e.to_string(),
            });
            result.estimate = Some(est);
            return Ok(result);
        }
    }
    result.converged = est.converged;
    result.stop = if est.converged {
        StopReason::Converged
    } else {
        StopReason::IterationLimit
    };
    estimate_warnings(&mut result.warnings, &est);
    result.estimate = Some(est);
    debug_assert_eq!(result.options.method, UpdateMethod::Robust);
    Ok(result)
}

/// The full-band estimate from the best of `starts`; when it ends above the
/// noise level ([`RESTART_MISFIT`]), from each other start too, keeping the
/// lowest misfit. The best start before the estimate (lowest cost after a
/// damping fit) can lie in the basin of a local minimum, e.g. a first stage
/// that settled on a wrong pairing; only a fit at the noise level shows
/// that the minimum is the one the data support.
/// The further starts are independent estimates, run on the pool's threads
/// ([`try_starts`]).
fn best_estimate(
    deck: &Deck,
    data: &TestData,
    starts: Vec<Vec<f64>>,
    opts: &UpdateOptions,
    fitted: Option<StartFit>,
) -> Result<FullBandEstimate, UpdateError> {
    let max_iter = opts.estimate_iterations;
    let request = |starts: Vec<Vec<f64>>, fitted: Option<StartFit>| EstimateRequest {
        deck,
        data,
        starts,
        max_iter,
        fitted,
    };
    let run = |starts: Vec<Vec<f64>>| estimate(request(starts, None));
    let mut best = estimate(request(starts.clone(), fitted)).map_err(UpdateError::Estimate)?;
    if best.misfit <= RESTART_MISFIT {
        return Ok(best);
    }
    let (chosen, mut solutions) = (best.start, best.model_solutions);
    let others = starts
        .into_iter()
        .enumerate()
        .filter(|&(k, _)| k != chosen)
        .collect();
    try_starts(&mut best, &mut solutions, others, f64::NEG_INFINITY, &run);
    // Every start ended in the basin of a minimum that leaves the test
    // unexplained: starts spread over the plausible range, independent of
    // the first stage (which can itself have settled on a wrong pairing).
    if best.misfit > SPREAD_MISFIT {
        let spread = spread_starts(best.parameters.len(), opts.spread_starts)
            .into_iter()
            .enumerate()
            .map(|(i, s)| (SPREAD_START + i, s))
            .collect();
        try_starts(&mut best, &mut solutions, spread, SPREAD_MISFIT, &run);
    }
    best.model_solutions = solutions;
    Ok(best)
}

/// The estimate from each of `starts` (its index, p̄), kept in `best` when
/// its misfit is lower, in the order of the starts, until `best` reaches
/// `stop`; the model solutions of those taken added to `solutions`. The
/// starts run on the pool's threads, a batch of as many as it has at a
/// time; one computed after the stop is discarded and not counted, so the
/// outcome is the same on any number of threads.
fn try_starts(
    best: &mut FullBandEstimate,
    solutions: &mut usize,
    starts: Vec<(usize, Vec<f64>)>,
    stop: f64,
    run: &(impl Fn(Vec<Vec<f64>>) -> Result<FullBandEstimate, FitError> + Sync),
) {
    use rayon::prelude::*;
    let batch = rayon::current_num_threads().max(1);
    for these in starts.chunks(batch) {
        let outcomes: Vec<_> = these
            .par_iter()
            .map(|(k, s)| (*k, run(vec![s.clone()])))
            .collect();
        for (k, outcome) in outcomes {
            if let Ok(mut other) = outcome {
                *solutions += other.model_solutions;
                if other.misfit < best.misfit {
                    other.start = k;
                    *best = other;
                }
            }
            if best.misfit <= stop {
                return;
            }
        }
    }
}

/// Half-range of the spread starts in p̄ (relative change).
const SPREAD: f64 = 0.3;

/// `count` points of the Halton sequence in [−SPREAD, SPREAD]^np (bases the
/// first primes, index from 1): deterministic, evenly spread in every
/// dimension however many parameters there are.
fn spread_starts(np: usize, count: usize) -> Vec<Vec<f64>> {
    const PRIMES: [u64; 16] = [2, 3, 5, 7, 11, 13, 17, 19, 23, 29, 31, 37, 41, 43, 47, 53];
    let radical_inverse = |mut i: u64, base: u64| {
        let (mut f, mut r) = (1.0, 0.0);
        while i > 0 {
            f /= base as f64;
            r += f * (i % base) as f64;
            i /= base;
        }
        r
    };
    (1..=count as u64)
        .map(|i| {
            (0..np)
                .map(|j| {
                    let base = PRIMES[j % PRIMES.len()];
                    SPREAD * (2.0 * radical_inverse(i, base) - 1.0)
                })
                .collect()
        })
        .collect()
}

/// The paper's iteration with the robust options, falling back when it
/// cannot run (see the arms).
fn first_stage(
    deck: &Deck,
    test: &MeasuredFrfs,
    opts: &UpdateOptions,
    progress: &mut dyn FnMut(UpdateProgress),
) -> Result<UpdateResult, UpdateError> {
    match update_model(&mut |v| model::build(deck, v), test, opts, progress, None) {
        // No resonance stands out of the test's FRFs (heavy damping, a
        // sparse axis): place the first stage's updating frequencies around
        // the deck's own natural frequencies instead; the full-band estimate
        // does not need resonances.
        Err(e @ (UpdateError::NoResonances | UpdateError::NoUpdatingFrequencies { .. })) => {
            let Some(freqs) = deck_frequencies(deck, test, opts.offset) else {
                return Err(e);
            };
            let o = UpdateOptions {
                frequencies_hz: Some(freqs),
                ..opts.clone()
            };
            update_model(&mut |v| model::build(deck, v), test, &o, progress, None)
        }
        // A step of the first stage gave no usable model (a mechanism, a
        // failed eigen solution): the estimate starts from the deck alone.
        Err(e @ (UpdateError::Eigen(_) | UpdateError::Model(_))) => {
            let o = UpdateOptions {
                max_iter: 0,
                frequencies_first: false,
                ..opts.clone()
            };
            let mut r = update_model(&mut |v| model::build(deck, v), test, &o, progress, None)?;
            r.warnings.push(UpdateWarning::FirstStageStopped {
                reason: e.to_string(),
            });
            Ok(r)
        }
        r => r,
    }
}

/// Append the final parameters' record (with the step from the first
/// stage's result, Eq. 29 inverted) and make it the returned iteration.
fn append_final(
    result: &mut UpdateResult,
    mut record: IterationRecord,
    fdac: Vec<Vec<f64>>,
    p_final: &[f64],
) {
    let prev = &result.final_record().parameters;
    record.step = p_final
        .iter()
        .zip(prev)
        .map(|(f, p)| (f - p) / (1.0 + p))
        .collect();
    record.stage = IterationStage::Estimate;
    result.iterations.push(record);
    result.final_iteration = result.iterations.len() - 1;
    result.fdac_final = fdac;
}

/// The warnings of the estimate, in place of the first stage's own stopping
/// warnings (they describe an intermediate result).
fn estimate_warnings(warnings: &mut Vec<UpdateWarning>, est: &FullBandEstimate) {
    warnings.retain(|w| {
        !matches!(
            w,
            UpdateWarning::NotConverged { .. }
                | UpdateWarning::Diverged { .. }
                | UpdateWarning::ParameterExploded { .. }
        )
    });
    if !est.converged {
        warnings.push(UpdateWarning::EstimateNotConverged {
            iterations: est.iterations,
        });
    }
    if est.misfit > MISFIT_WARNING {
        warnings.push(UpdateWarning::Misfit { ratio: est.misfit });
    }
    let unidentified: Vec<String> = est
        .parameters
        .iter()
        .filter(|p| !p.identified && !p.at_bound)
        .map(|p| p.name.clone())
        .collect();
    if !unidentified.is_empty() {
        warnings.push(UpdateWarning::NotIdentified {
            parameters: unidentified,
            directions: est
                .missing_directions
                .iter()
                .map(|(d, _)| d.clone())
                .collect(),
        });
    }
}

/// (1 ± offset)·f_r for the deck's natural frequencies f_r inside the test's
/// band (rigid-body modes left out), or `None` if there is none.
fn deck_frequencies(deck: &Deck, test: &MeasuredFrfs, offset: f64) -> Option<Vec<f64>> {
    let fe = model::build(deck, &ParameterValues::new()).ok()?;
    let (lo, hi) = (
        test.frequencies_hz.first().copied()?,
        test.frequencies_hz.last().copied()?,
    );
    let modes = crate::solvers::eigen::lowest_modes(
        &fe.stiffness,
        &fe.mass,
        &crate::solvers::eigen::EigenOptions {
            count: 16.min(fe.dofs.len()),
            expect_no_rigid_body_modes: fe.has_fixed_dofs,
            ..Default::default()
        },
    )
    .ok()?;
    let mut f: Vec<f64> = modes
        .frequencies_hz()
        .into_iter()
        .filter(|&x| x > 1e-3 * hi && x > lo)
        .take(8)
        .flat_map(|x| [(1.0 - offset) * x, (1.0 + offset) * x])
        .filter(|&x| x > lo && x < hi)
        .collect();
    f.dedup();
    (!f.is_empty()).then_some(f)
}

/// Where the full-band estimate may start: the deck, the first stage's
/// returned iterate and its best one by SFDAC mean (a converged iterate can
/// fit worse than an earlier one).
fn starts(result: &UpdateResult, np: usize) -> Vec<Vec<f64>> {
    let best = result
        .iterations
        .iter()
        .max_by(|a, b| a.sfdac.mean.total_cmp(&b.sfdac.mean))
        .map(|r| r.parameters.clone());
    let mut s = vec![vec![0.0; np]];
    for c in std::iter::once(result.parameters().to_vec()).chain(best) {
        if !s.contains(&c) {
            s.push(c);
        }
    }
    s
}

/// The measured FRFs for the full-band fit, restricted to the channels the
/// model can place (the others are already reported by the first stage).
fn test_data(deck: &Deck, test: &MeasuredFrfs) -> Result<TestData, UpdateError> {
    let mut data = TestData::new(test).map_err(UpdateError::Estimate)?;
    let fe = model::build(deck, &ParameterValues::new()).map_err(UpdateError::Model)?;
    let keep: Vec<bool> = data
        .channels
        .iter()
        .map(|c| fe.measured_dof(c.node, c.direction).is_some())
        .collect();
    data.retain_channels(&keep);
    Ok(data)
}

/// The record of the final parameters: the first stage's machinery run for
/// zero iterations on the deck with the values multiplied out (on the test
/// resonances the first stage found), relabelled.
fn score(
    deck: &Deck,
    test: &MeasuredFrfs,
    values: &ParameterValues,
    p_final: &[f64],
    stage1: &UpdateResult,
) -> Result<(IterationRecord, Vec<Vec<f64>>), UpdateError> {
    let final_deck = model::updated_deck(deck, values);
    // The first stage's own options: the same updating frequencies.
    let once = UpdateOptions {
        max_iter: 0,
        frequencies_first: false,
        ..stage1.options.clone()
    };
    let scored = update_model(
        &mut |v| model::build(&final_deck, v),
        test,
        &once,
        &mut |_| {},
        Some(&stage1.test_resonances),
    )?;
    let mut rec = scored.iterations[0].clone();
    rec.index = stage1.iterations.len();
    rec.parameters = p_final.to_vec();
    rec.step_scale = 1.0;
    Ok((rec, scored.fdac_initial))
}
