//! Screening by joint fits: every candidate extension fitted together with
//! the deck's own parameters, so that it competes with the parameter-only
//! explanation on equal terms (small models only).
//!
//! A linear probe at a typical value misjudges an effect far larger than the
//! probe (a heavy added mass, a very soft joint), and a probe or a fit with
//! the deck's parameters held misjudges a candidate whenever those are
//! wrong too: the parameter error dominates the residual. Here each
//! candidate's log parameter ln θ and the deck's relative changes p̄ are
//! fitted on the measured resonance frequencies (Σ ln²(ω_model/ω_test),
//! bounded Levenberg–Marquardt from a 5-point grid in ln θ, p̄ = 0), and the
//! candidates are ranked by the damping-profiled FRF cost at that point. The
//! best few are then fitted in full on the FRFs ([`refit::fit_joint`]).

use frfup_parsers::deck::Deck;

use super::fit::{self, DampingState};
use super::hypotheses::{Hypothesis, Physics};
use super::refit::{self, Joint, JointSettings};
use super::select::{Engine, HypFit};

/// Levenberg–Marquardt iterations of the frequency stage of the screen.
const SCREEN_ITERATIONS: usize = 8;

/// A full joint fit: resonance-frequency stage, then the FRFs, 10
/// Levenberg–Marquardt iterations each.
pub(super) const FULL_FIT: JointSettings = JointSettings {
    frequency_stage: true,
    iterations: 10,
};

/// The `take` candidates of `candidates` (those with a parameter, no
/// suspension springs) that the joint screen ranks best on `base`, each
/// fitted in full with the deck's parameters along; best cost first.
pub(super) fn best_joint_fits(
    engine: &Engine,
    base: &Deck,
    damp: &DampingState,
    candidates: &[Hypothesis],
    take: usize,
) -> Vec<(Hypothesis, HypFit)> {
    let mut ranked: Vec<(f64, usize)> = candidates
        .iter()
        .enumerate()
        .filter(|(_, h)| h.param.is_some() && h.physics != Physics::Suspension)
        .filter_map(|(i, h)| screen_cost(engine, base, damp, h).map(|c| (c, i)))
        .collect();
    ranked.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    let mut out: Vec<(Hypothesis, HypFit)> = ranked
        .into_iter()
        .take(take)
        .filter_map(|(_, i)| {
            let h = &candidates[i];
            let problem = Joint::with_deck_parameters(base, vec![h]);
            frequency_seeded_with(engine, &problem, damp, None).map(|f| (h.clone(), f))
        })
        .collect();
    out.sort_by(|a, b| a.1.cost.total_cmp(&b.1.cost));
    out
}

/// The damping-profiled FRF cost (3 damping iterations) of `h` on `base`
/// after the joint frequency fit; `None` when no start gives a model.
fn screen_cost(engine: &Engine, base: &Deck, damp: &DampingState, h: &Hypothesis) -> Option<f64> {
    let data = engine.data;
    let problem = Joint::with_deck_parameters(base, vec![h]);
    let (lo, hi) = problem.bounds();
    let mut fixed = vec![None];
    fixed.extend(std::iter::repeat_n(Some(0.0), problem.deck_params.len()));
    let starts = refit::grid_starts(&lo, &hi, &fixed, 5);
    let model = |x: &[f64]| engine.model(&problem.deck_at(x)).ok();
    let profiled = |x: &[f64]| -> Option<f64> {
        let mm = model(x)?;
        let (_, r) = fit::fit_damping(&mm, damp, data, &engine.all, 3);
        let c = fit::mean_sq(&r);
        c.is_finite().then_some(c)
    };
    if data.resonances.is_empty() {
        return starts
            .iter()
            .filter_map(|s| profiled(s))
            .min_by(f64::total_cmp);
    }
    let misfit = |x: &[f64]| model(x).map(|mm| fit::frequency_residuals(&mm, data));
    let best_start = starts
        .iter()
        .filter_map(|s| misfit(s).map(|r| (fit::mean_sq(&r), s)))
        .min_by(|a, b| a.0.total_cmp(&b.0))?
        .1
        .clone();
    let x = refit::frequency_fit(engine, &problem, &best_start, SCREEN_ITERATIONS)
        .map_or(best_start, |o| o.x);
    profiled(&x)
}

/// A one-extension problem (the deck's parameters along, starting at 0)
/// fitted through [`refit::fit_joint`]: 7 starts across the extension's
/// bounds (and the log value of `grid`, a fit with the parameters held),
/// resonance-frequency stage, then the FRFs with the damping.
pub(super) fn frequency_seeded_with(
    engine: &Engine,
    problem: &Joint,
    damp: &DampingState,
    grid: Option<&HypFit>,
) -> Option<HypFit> {
    let starts = refit::new_extension_starts(problem, &[], grid.and_then(|g| g.log_value), 7);
    let jf = refit::fit_joint(engine, problem, &starts, damp, &engine.all, FULL_FIT)?;
    let value = jf.logs[0].exp();
    Some(HypFit {
        value: Some(value),
        log_value: Some(jf.logs[0]),
        damping: jf.damping.clone(),
        cost: jf.cost,
        std: Some(jf.std_log[0] * value),
        damping_std_log: vec![],
        on_bound: jf.on_bound[0],
        deck_values: jf.deck_values.clone(),
    })
}

/// A hypothesis without a parameter (shear deformation) on `base`, with the
/// deck's parameters fitted along from 0 (resonance stage, then the FRFs):
/// without them, a model whose parameters are also wrong leaves the
/// hypothesis no chance against one that has a parameter to absorb them.
pub(super) fn parameterless_with_deck(
    engine: &Engine,
    base: &Deck,
    h: &Hypothesis,
    damp: &DampingState,
) -> Option<HypFit> {
    let problem = Joint::with_deck_parameters(base, vec![h]);
    if h.param.is_some() || problem.deck_params.is_empty() {
        return None;
    }
    let jf = deck_parameters_fit(engine, &problem, damp)?;
    Some(HypFit {
        value: None,
        log_value: None,
        damping: jf.damping.clone(),
        cost: jf.cost,
        std: None,
        damping_std_log: vec![],
        on_bound: false,
        deck_values: jf.deck_values.clone(),
    })
}

/// The validation cost of `base` with only the deck's parameters refitted
/// (no extension), or `None` when the deck has none: what a candidate
/// fitted along with those parameters has to beat, so that it competes
/// with the parameter-only explanation on equal terms.
pub(super) fn parameters_only_validation(
    engine: &Engine,
    base: &Deck,
    damp: &DampingState,
) -> Option<f64> {
    let problem = Joint::with_deck_parameters(base, vec![]);
    if problem.deck_params.is_empty() {
        return None;
    }
    let jf = deck_parameters_fit(engine, &problem, damp)?;
    Some(refit::validate_joint(engine, &problem, &jf))
}

/// `base` with only the deck's parameters fitted, from the values `start`
/// (a candidate's joint fit) and from p̄ = 0, the better; `None` when the
/// deck has none. A candidate fitted along with the parameters may have
/// won only because the parameter-only fit stopped short of its optimum:
/// from the values the joint fit found, the parameters alone may reach it.
pub(super) fn parameters_only_from(
    engine: &Engine,
    base: &Deck,
    damp: &DampingState,
    start: &crate::model::ParameterValues,
) -> Option<refit::JointFit> {
    let problem = Joint::with_deck_parameters(base, vec![]);
    if problem.deck_params.is_empty() {
        return None;
    }
    let from: Vec<f64> = problem
        .deck_params
        .iter()
        .map(|n| start.get(n).copied().unwrap_or(0.0))
        .collect();
    let starts = vec![from, vec![0.0; problem.deck_params.len()]];
    refit::fit_joint(engine, &problem, &starts, damp, &engine.all, FULL_FIT)
}

/// The deck's parameters of `problem` (no extension parameter) fitted from
/// p̄ = 0: resonance stage, then the FRFs with the damping.
fn deck_parameters_fit(
    engine: &Engine,
    problem: &Joint,
    damp: &DampingState,
) -> Option<refit::JointFit> {
    let starts = vec![vec![0.0; problem.deck_params.len()]];
    refit::fit_joint(engine, problem, &starts, damp, &engine.all, FULL_FIT)
}
