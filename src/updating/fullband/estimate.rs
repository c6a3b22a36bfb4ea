//! The final stage of `frfup update`: the deck's parameters estimated on
//! every line and channel, with their uncertainty.
//!
//! Objective (maximum a posteriori, Gaussian noise and priors):
//!
//!   F(p̄, d) = Σ_i r_i(p̄, d)² + Σ_j J₀ (p̄_j / s_j)²
//!
//! r_i the weighted log-FRF residuals of [`fit::residuals`] (log magnitude
//! and phase of every point above the noise floor), d the damping's log
//! parameters (fitted along), J₀ the noise-level value of a mean squared
//! residual ([`fit::noise_level`]), s_j the prior standard deviation of p̄_j
//! (`param … sd=S`; no term without it). Hard bounds min_j ≤ p̄_j ≤ max_j
//! (`param … min= max=`; default [`super::prior::DEFAULT_MIN`], [`super::prior::DEFAULT_MAX`]).
//! Minimised by bounded Levenberg–Marquardt with the exact Jacobian of a
//! reduced model that follows the estimate ([`objective`]), from the best of
//! the candidate starts, after a coarse stage on the resonance frequencies
//! alone when the start is far from the test ([`coarse`]).
//!
//! Two passes. The first, with a weak prior (sd [`WEAK_PRIOR_SD`]) on the
//! parameters that have none, finds the optimum's neighbourhood (a
//! direction the data cannot see then has a minimum instead of a valley to
//! creep along) and the parameters the data do not determine. The second,
//! without the weak prior, starts there with those parameters held at the
//! deck's value (a parameter is identified when its data-only standard
//! deviation is below the limit both at the first pass's optimum and at the
//! deck's values), and with the weights of the first pass's model FRFs
//! ([`TestData::reweight`]): a weight taken from the noisy measured |H|
//! correlates with the residual it multiplies, which biases the estimate by
//! several standard deviations when many lines are fitted.
//!
//! Uncertainty: the sandwich covariance of [`uncertainty`]. A parameter whose
//! standard deviation exceeds [`UNIDENTIFIED_SD`] (or its prior's s_j/√2:
//! the data did not halve the prior's variance) is *not identified by these
//! data*, with the directions of parameter space the data do not see.

use frfup_parsers::deck::Deck;

use super::coarse;
use super::data::TestData;
use super::fit::{self, DampingState, Mask};
use super::lm::{self, LeastSquares, LmOutcome, LmSettings};
use super::objective::{minimise, Objective};
use super::prior::ParameterPrior;
use super::reduced::ReducedModel;
use super::uncertainty::{data_sd_at, residual_variance, uncertainty, Uncertainty};
use super::FitError;
use crate::model::{self, Damping, ParameterValues};
use crate::solvers::dense::symmetric_eigen;
use crate::updating::serep::dot;

/// A parameter whose standard deviation exceeds this is not identified.
pub const UNIDENTIFIED_SD: f64 = 0.5;
/// J₀ of 0.1 % relative noise under the 1 % model floor of the weights
/// (s²/(s² + f²) with s = 1e-3/√2, f = 1e-2): the smallest noise level a
/// misfit is measured against.
const J0_FLOOR: f64 = 0.005;
/// The weak prior of the first pass on parameters without one (see [`estimate`]).
const WEAK_PRIOR_SD: f64 = 1.0;
/// A decrease of Σr² below this many noise variances (J₀) ends the estimate:
/// it would move no parameter by a noticeable fraction of its uncertainty.
const NEGLIGIBLE: f64 = 0.05;
/// Levenberg–Marquardt iterations of the damping fit at each start.
const START_ITERATIONS: usize = 20;
/// Relative gain of the cost below which a start's damping fit stops.
const START_GAIN: f64 = 1e-5;

/// What to estimate.
pub struct EstimateRequest<'a> {
    pub deck: &'a Deck,
    pub data: &'a TestData,
    /// Candidate starting points p̄ (deck order); the one that fits best
    /// (after a damping fit) is used.
    pub starts: Vec<Vec<f64>>,
    /// Levenberg–Marquardt iteration limit of the first pass; the second
    /// pass, whose optimum is the result, may take twice as many (on a long
    /// curved valley it is still descending at the noise level when the
    /// first pass's budget would stop it).
    pub max_iter: usize,
    /// A start's damping fit done beforehand ([`fit_start`]), used for the
    /// start it was done at.
    pub fitted: Option<StartFit>,
}

/// A start's damping fit: the structural unknowns held at `p`, the
/// damping alone fitted by Levenberg–Marquardt, and the reduced model
/// anchored at `p`.
pub struct StartFit {
    /// The mean squared data residual after the fit.
    cost: f64,
    p: Vec<f64>,
    damping: DampingState,
    reduced: Option<ReducedModel>,
    /// Model solutions spent.
    solutions: usize,
}

/// The damping fit at `start` (clamped to the bounds) on its own, as
/// [`estimate`] does it for each of its starts; `None` where the model
/// cannot be solved there. It needs nothing but the deck and the data, so
/// `update` runs it for the deck's own start beside its first stage.
pub fn fit_start(deck: &Deck, data: &TestData, start: &[f64]) -> Option<StartFit> {
    let (mut obj, damp0, _) = objective(deck, data);
    let (dlo, dhi) = bounds(&obj.priors, damp0.form, data);
    let p = clamped_start(start, &dlo, &dhi);
    let fit = damping_fit(&mut obj, p, &damp0, &dlo, &dhi);
    fit.map(|f| StartFit {
        solutions: obj.solutions,
        ..f
    })
}

/// One parameter's estimate.
#[derive(Clone, Debug, PartialEq)]
pub struct ParameterEstimate {
    pub name: String,
    /// p̄ (relative change).
    pub value: f64,
    /// One standard deviation of p̄ (sandwich covariance).
    pub sd: f64,
    pub prior: ParameterPrior,
    /// False: the data do not determine it (see the module doc).
    pub identified: bool,
    /// Held at the deck's value. A parameter not identified and not held
    /// takes part in a combination whose mirror image fits the data as well
    /// (two like members' changes swapped): its value fits, but the data do
    /// not say it rather than its mirror's.
    pub held: bool,
    /// The estimate sits on `min` or `max`.
    pub at_bound: bool,
}

/// [`FullBandEstimate::start`] of the first start spread over the
/// plausible range (see `updating::robust`).
pub const SPREAD_START: usize = 1000;

/// The outcome of the full-band estimate.
#[derive(Clone, Debug)]
pub struct FullBandEstimate {
    pub parameters: Vec<ParameterEstimate>,
    /// The damping identified along.
    pub damping: Damping,
    /// Mean squared residual over its noise-level value J₀ (1: the fit is at
    /// the noise level).
    pub misfit: f64,
    /// Levenberg–Marquardt stopped on its criterion (not its iteration limit).
    pub converged: bool,
    pub iterations: usize,
    /// Index of the start used (into the request's `starts`; the robust
    /// pipeline numbers its spread starts from [`SPREAD_START`]).
    pub start: usize,
    /// The coarse stage on resonance frequencies ran first.
    pub coarse_stage: bool,
    /// Directions in parameter space the data do not determine (name,
    /// component; largest component 1), with their standard deviation.
    pub missing_directions: Vec<(Vec<(String, f64)>, f64)>,
    /// Model solutions (eigen problems) spent.
    pub model_solutions: usize,
}

impl FullBandEstimate {
    /// p̄ as a name → value map.
    pub fn values(&self) -> ParameterValues {
        self.parameters
            .iter()
            .map(|p| (p.name.clone(), p.value))
            .collect()
    }
}

/// Run the estimate.
pub fn estimate(req: EstimateRequest) -> Result<FullBandEstimate, FitError> {
    if req.starts.is_empty() || model::parameter_names(req.deck).is_empty() {
        return Err(FitError::Data("no parameter to estimate".into()));
    }
    let (mut obj, damp0, j0) = objective(req.deck, req.data);
    let (names, priors, mask) = (obj.names.clone(), obj.priors.clone(), obj.mask.clone());
    let (start, mut p, mut damp) = best_start(&mut obj, &req.starts, &damp0, req.fitted)?;
    let (coarse_stage, spent) =
        coarse::coarse_frequencies(req.deck, req.data, &names, &priors, &mut p, &mut damp);
    obj.solutions += spent;
    let (lo, hi) = bounds(&priors, damp.form, req.data);
    let x0 = [p, damp.x].concat();
    let mut first = first_pass(&mut obj, &x0, &lo, &hi, req.max_iter, j0)?;
    if !first.mirror.is_empty() {
        first = mirror_test(&mut obj, first, &lo, &hi, req.max_iter, j0);
    }
    let mut weighted = req.data.clone();
    let pred = obj
        .predict(&first.out.x)
        .ok_or_else(|| FitError::Eigen("the first pass's model could not be solved".into()))?;
    weighted.reweight(pred);
    let j0 = fit::noise_level(&weighted, &mask).max(1e-12);
    let mut obj = Objective {
        data: &weighted,
        prior_scale: ParameterPrior::row_scale(j0),
        ..obj
    };
    let mut second = second_pass(&mut obj, &first, &lo, &hi, 2 * req.max_iter, j0)?;
    // A parameter left free that still ends above its identification limit
    // is not identified either: it is held at the deck's value and the pass
    // repeated (a number the data do not support never reaches updated.deck).
    for _ in 0..3 {
        let np = names.len();
        let newly: Vec<usize> = (0..np)
            .filter(|&j| second.free[j] && second.sd[j] > identification_limit(&priors[j]))
            .collect();
        if newly.is_empty() {
            break;
        }
        for &j in &newly {
            first.seen.sd_data[j] = first.seen.sd_data[j].max(second.sd[j]);
        }
        first.unseen.extend(newly);
        second = second_pass(&mut obj, &first, &lo, &hi, 2 * req.max_iter, j0)?;
    }
    let data_n = obj.data_rows(second.out.residuals.len());
    // Against the noise level, but never below that of 0.1 % noise: on
    // (nearly) noise-free data any model error would look enormous.
    let misfit = fit::mean_sq(&second.out.residuals[..data_n]) / j0.max(J0_FLOOR);
    let np = names.len();
    let parameters = (0..np)
        .map(|j| {
            let (v, mut sd, free) = (second.out.x[j], second.sd[j], second.free[j]);
            let mirrored = first.mirror.iter().any(|(d, _)| in_direction(d, j));
            if mirrored && free {
                // Either value or its mirror's: half their distance.
                sd = sd.max(first.mirror_spread.get(j).copied().unwrap_or(0.0));
            }
            ParameterEstimate {
                name: names[j].clone(),
                value: v,
                sd,
                prior: priors[j],
                identified: free && !mirrored && sd <= identification_limit(&priors[j]),
                held: !free,
                at_bound: free && (v <= priors[j].min + 1e-9 || v >= priors[j].max - 1e-9),
            }
        })
        .collect();
    Ok(FullBandEstimate {
        parameters,
        damping: damp.form.damping(&second.out.x[np..]),
        misfit,
        converged: second.out.converged,
        iterations: first.out.iterations + second.out.iterations,
        start,
        coarse_stage,
        missing_directions: first
            .seen
            .missing
            .iter()
            .chain(&first.mirror)
            .map(|(v, s)| (named_direction(&names, v), *s))
            .collect(),
        model_solutions: obj.solutions,
    })
}

/// The objective on the deck's parameters and all the data, with the
/// deck's priors and the noise level's prior scale, the damping it starts
/// from, and the noise level J₀ of a mean squared residual.
fn objective<'a>(deck: &'a Deck, data: &'a TestData) -> (Objective<'a>, DampingState, f64) {
    let mask = Mask::all(data);
    let j0 = fit::noise_level(data, &mask).max(1e-12);
    let damp0 = fit::start_damping(Damping::of_deck(deck), data);
    let parameters = (model::parameter_names(deck), ParameterPrior::of_deck(deck));
    let scale = ParameterPrior::row_scale(j0);
    let obj = Objective::new(deck, data, mask, parameters, damp0.form, scale);
    (obj, damp0, j0)
}

/// A start's p̄ within the bounds.
fn clamped_start(start: &[f64], lo: &[f64], hi: &[f64]) -> Vec<f64> {
    (0..start.len())
        .map(|j| start[j].clamp(lo[j], hi[j]))
        .collect()
}

/// The start (index, p̄ within the bounds, damping) whose damping-fitted
/// data cost is lowest; the objective is left anchored there. A start that
/// `fitted` holds is not fitted again.
fn best_start(
    obj: &mut Objective,
    starts: &[Vec<f64>],
    damp0: &DampingState,
    mut fitted: Option<StartFit>,
) -> Result<(usize, Vec<f64>, DampingState), FitError> {
    let np = obj.np();
    let (dlo, dhi) = bounds(&obj.priors, damp0.form, obj.data);
    let mut best: Option<(usize, StartFit)> = None;
    for (k, s) in starts.iter().enumerate() {
        let p = clamped_start(&s[..np], &dlo, &dhi);
        let fit = match fitted.take_if(|f| f.p == p) {
            Some(f) => {
                obj.solutions += f.solutions;
                Some(f)
            }
            None => damping_fit(obj, p, damp0, &dlo, &dhi),
        };
        let Some(fit) = fit else {
            continue;
        };
        if best.as_ref().is_none_or(|b| fit.cost < b.1.cost) {
            best = Some((k, fit));
        }
    }
    let Some((k, fit)) = best else {
        return Err(FitError::Eigen(
            "no starting point gives a usable model".into(),
        ));
    };
    obj.reduced = fit.reduced;
    obj.cache = None;
    obj.last = None;
    Ok((k, fit.p, fit.damping))
}

/// The damping alone fitted at `p` (the structural unknowns held: lo = hi),
/// from `damp0`; the reduced model anchored at `p` is taken out of `obj`.
fn damping_fit(
    obj: &mut Objective,
    p: Vec<f64>,
    damp0: &DampingState,
    dlo: &[f64],
    dhi: &[f64],
) -> Option<StartFit> {
    let np = obj.np();
    obj.anchor(&p).ok()?;
    let (mut lo, mut hi) = (dlo.to_vec(), dhi.to_vec());
    lo[..np].copy_from_slice(&p);
    hi[..np].copy_from_slice(&p);
    let x = [p.clone(), damp0.x.clone()].concat();
    let r0 = obj.residuals(&x)?;
    // The starts' costs differ by orders of magnitude where the choice
    // matters: a gain below START_GAIN of the cost cannot change it.
    let settings = LmSettings {
        max_iter: START_ITERATIONS,
        negligible: START_GAIN * r0.iter().map(|v| v * v).sum::<f64>(),
        ..LmSettings::default()
    };
    let out = lm::lm(obj, &x, &lo, &hi, settings)?;
    let cost = fit::mean_sq(&out.residuals[..obj.data_rows(out.residuals.len())]);
    Some(StartFit {
        cost,
        p,
        damping: DampingState {
            form: damp0.form,
            x: out.x[np..].to_vec(),
        },
        reduced: obj.reduced.take(),
        solutions: 0,
    })
}

/// The first pass's optimum, its uncertainty and the parameters (without
/// a prior) it leaves unidentified.
struct FirstPass {
    out: LmOutcome,
    seen: Uncertainty,
    /// Parameters held at the deck's value.
    unseen: Vec<usize>,
    /// Directions (unit, over the parameters) that mix several parameters,
    /// unseen at the deck or here, with their standard deviation there:
    /// candidates for [`mirror_test`], then those whose mirror fits as well.
    mirror: Vec<(Vec<f64>, f64)>,
    /// Half the distance between this optimum and its mirror's, per
    /// parameter, once [`mirror_test`] found them alike (else empty).
    mirror_spread: Vec<f64>,
}

/// Minimise with the weak prior on the parameters that have none.
fn first_pass(
    obj: &mut Objective,
    x0: &[f64],
    lo: &[f64],
    hi: &[f64],
    max_iter: usize,
    j0: f64,
) -> Result<FirstPass, FitError> {
    let priors = obj.priors.clone();
    obj.priors = priors
        .iter()
        .map(|p| ParameterPrior {
            sd: p.sd.or(Some(WEAK_PRIOR_SD)),
            ..*p
        })
        .collect();
    let out = minimise(obj, x0, lo, hi, max_iter, NEGLIGIBLE * j0)?;
    let all = vec![true; x0.len()];
    // The information at the deck's values (p̄ = 0, the optimum's damping
    // and noise level) too: a parameter the data see only far from its deck
    // value (a joint made much softer, traded against a neighbour) is seen
    // through a linearisation that does not hold back to where the data
    // lose it; its standard deviation there is not an honest one. It is
    // computed on a fresh objective beside the optimum's (one anchored at
    // the deck, which `obj` then takes over, as if it had anchored there
    // itself after the optimum's uncertainty).
    let np = obj.np();
    let mut x_deck = out.x.clone();
    for (j, v) in x_deck[..np].iter_mut().enumerate() {
        *v = 0.0f64.clamp(lo[j], hi[j]);
    }
    let s2 = residual_variance(obj, &out, &all);
    let mut beside = obj.fresh();
    let (seen, at_deck) = rayon::join(
        || uncertainty(obj, &out, &all, j0),
        || data_sd_at(&mut beside, &x_deck, &all, s2),
    );
    obj.take_anchor(beside);
    obj.priors = priors;
    let without_prior: Vec<bool> = obj.priors.iter().map(|p| p.sd.is_none()).collect();
    let directions = seen
        .missing
        .iter()
        .chain(at_deck.iter().flat_map(|u| u.missing.iter()))
        .map(|(v, _)| v.as_slice());
    let (mut unseen, mixed_directions) = unseen_subspace(directions, &without_prior);
    let at_deck_sd = at_deck
        .as_ref()
        .map(|u| u.missing.clone())
        .unwrap_or_default();
    let at_deck = at_deck.map_or_else(|| seen.sd_data.clone(), |u| u.sd_data);
    // A parameter above its limit at either point that no direction
    // accounts for (its variance spread over several directions, each seen
    // a little) is held too.
    let mixed = |j: usize| mixed_directions.iter().any(|v| in_direction(v, j));
    for j in 0..np {
        let limit = identification_limit(&obj.priors[j]);
        let seen_both = seen.sd_data[j] <= limit && at_deck[j] <= limit;
        if without_prior[j] && !seen_both && !mixed(j) && !unseen.contains(&j) {
            unseen.push(j);
        }
    }
    unseen.sort_unstable();
    let mut seen = seen;
    for j in (0..np).filter(|&j| unseen.contains(&j) || mixed(j)) {
        // Report the larger of the two: the one that decided.
        seen.sd_data[j] = seen.sd_data[j].max(at_deck[j]);
    }
    let mirror = mixed_directions
        .into_iter()
        .map(|v| {
            let sd = at_deck_sd
                .iter()
                .chain(&seen.missing)
                .filter(|(u, _)| dot(&v, u).abs() > 0.7)
                .fold(0.0f64, |m, (_, s)| m.max(*s));
            (v, sd)
        })
        .collect();
    Ok(FirstPass {
        out,
        seen,
        unseen,
        mirror,
        mirror_spread: Vec::new(),
    })
}

/// Two data costs Σr² closer than this many noise variances (J₀, times the
/// misfit when the fit is above the noise level) cannot be told apart: a
/// Δχ² of 9, three standard deviations along one direction.
const AMBIGUITY: f64 = 9.0;

/// The first pass again from its optimum mirrored across the deck's value
/// along its mixed unseen directions (x − 2(vᵀx)v): where the data do not
/// see a combination at the deck (two like members of a symmetric
/// structure), the optimum found and its mirror image are both candidates,
/// and the one pass cannot tell which basin it started in. The lower cost
/// is kept; when the two are within [`AMBIGUITY`], the directions stay in
/// `mirror` and their parameters are reported as not identified, else
/// `mirror` is emptied and they are judged by their uncertainty alone.
fn mirror_test(
    obj: &mut Objective,
    first: FirstPass,
    lo: &[f64],
    hi: &[f64],
    max_iter: usize,
    j0: f64,
) -> FirstPass {
    let mut x = first.out.x.clone();
    for (v, _) in &first.mirror {
        let along = dot(v, &x);
        for (j, vj) in v.iter().enumerate() {
            x[j] = (x[j] - 2.0 * along * vj).clamp(lo[j], hi[j]);
        }
    }
    let Ok(other) = first_pass(obj, &x, lo, hi, max_iter, j0) else {
        return first;
    };
    let data_cost = |p: &FirstPass| {
        let r = &p.out.residuals[..obj.data_rows(p.out.residuals.len())];
        (r.iter().map(|v| v * v).sum::<f64>(), r.len())
    };
    let ((c1, n), (c2, _)) = (data_cost(&first), data_cost(&other));
    let misfit = (c1.min(c2) / (n.max(1) as f64 * j0)).max(1.0);
    let ambiguous = (c1 - c2).abs() < AMBIGUITY * j0 * misfit;
    let mirror = first.mirror.clone();
    let spread: Vec<f64> = (0..obj.np())
        .map(|j| 0.5 * (first.out.x[j] - other.out.x[j]).abs())
        .collect();
    let mut best = if c2 < c1 { other } else { first };
    (best.mirror, best.mirror_spread) = if ambiguous {
        (mirror, spread)
    } else {
        (Vec::new(), Vec::new())
    };
    best
}

/// The subspace the data do not see, from the directions missed at the
/// optimum and at the deck (unit vectors over the parameters), over the
/// parameters without a prior of their own (a prior decides the others):
/// an orthonormal basis of the span of those directions (eigenvectors of
/// Σ v vᵀ with eigenvalue above ½: two directions within 60° count once).
/// A basis vector along one parameter (component above [`COORDINATE`]) is
/// returned as that parameter, to be held at the deck's value; the others
/// as directions that mix parameters (two like members whose sum the data
/// determine at the deck but not their difference), for [`mirror_test`].
fn unseen_subspace<'a>(
    directions: impl Iterator<Item = &'a [f64]>,
    without_prior: &[bool],
) -> (Vec<usize>, Vec<Vec<f64>>) {
    let np = without_prior.len();
    let mut gram = faer::Mat::<f64>::zeros(np, np);
    for v in directions {
        let u: Vec<f64> = (0..np)
            .map(|j| if without_prior[j] { v[j] } else { 0.0 })
            .collect();
        let norm2: f64 = u.iter().map(|x| x * x).sum();
        if norm2 < 0.25 {
            continue;
        }
        for a in 0..np {
            for b in 0..np {
                gram[(a, b)] += u[a] * u[b] / norm2;
            }
        }
    }
    let (mut held, mut mixed) = (Vec::new(), Vec::new());
    let Some((values, vectors)) = symmetric_eigen(gram.as_ref()) else {
        return (held, mixed);
    };
    for k in (0..np).rev().filter(|&k| values[k] > 0.5) {
        let v: Vec<f64> = (0..np).map(|j| vectors[(j, k)]).collect();
        let (jmax, vmax) =
            v.iter().enumerate().fold(
                (0, 0.0f64),
                |a, (j, x)| if x.abs() > a.1 { (j, x.abs()) } else { a },
            );
        if vmax > COORDINATE {
            held.push(jmax);
        } else {
            mixed.push(v);
        }
    }
    (held, mixed)
}

/// A unit direction whose largest component exceeds this is along that
/// parameter alone.
const COORDINATE: f64 = 0.99;

/// Parameter `j` takes part in direction `v` (a component of at least 0.1
/// of its largest, as [`named_direction`] names them).
fn in_direction(v: &[f64], j: usize) -> bool {
    let vmax = v.iter().fold(0.0f64, |a, x| a.max(x.abs()));
    vmax > 0.0 && v[j].abs() >= 0.1 * vmax
}

/// The second pass's optimum, which unknowns it left free, and the
/// structural parameters' standard deviations (the first pass's data-only
/// ones for those it held).
struct SecondPass {
    out: LmOutcome,
    free: Vec<bool>,
    sd: Vec<f64>,
}

/// Minimise from the first pass's optimum with its unidentified parameters
/// held at the deck's value (p̄ = 0 within the bounds).
fn second_pass(
    obj: &mut Objective,
    first: &FirstPass,
    lo: &[f64],
    hi: &[f64],
    max_iter: usize,
    j0: f64,
) -> Result<SecondPass, FitError> {
    let (mut lo2, mut hi2, mut x1) = (lo.to_vec(), hi.to_vec(), first.out.x.clone());
    let mut free = vec![true; x1.len()];
    for &j in &first.unseen {
        x1[j] = 0.0f64.clamp(lo[j], hi[j]);
        (lo2[j], hi2[j], free[j]) = (x1[j], x1[j], false);
    }
    let out = minimise(obj, &x1, &lo2, &hi2, max_iter, NEGLIGIBLE * j0)?;
    let mut sd = uncertainty(obj, &out, &free, j0).sd;
    let np = obj.np();
    for j in (0..np).filter(|&j| !free[j]) {
        sd[j] = first.seen.sd_data[j];
    }
    Ok(SecondPass { out, free, sd })
}

/// The standard deviation above which a parameter is not identified:
/// [`UNIDENTIFIED_SD`], or s/√2 for a prior of sd s (the data did not halve
/// the prior's variance).
fn identification_limit(prior: &ParameterPrior) -> f64 {
    prior.sd.map_or(UNIDENTIFIED_SD, |s| {
        (s / std::f64::consts::SQRT_2).min(UNIDENTIFIED_SD)
    })
}

/// Hard bounds of x = [p̄, damping logs].
fn bounds(
    priors: &[ParameterPrior],
    form: fit::DampingForm,
    data: &TestData,
) -> (Vec<f64>, Vec<f64>) {
    let (w_lo, w_hi) = data.band();
    let (dlo, dhi) = form.bounds(w_lo, w_hi);
    let mut lo: Vec<f64> = priors.iter().map(|p| p.min).collect();
    let mut hi: Vec<f64> = priors.iter().map(|p| p.max).collect();
    lo.extend(dlo);
    hi.extend(dhi);
    (lo, hi)
}

/// A direction as (name, component) pairs, largest component +1, terms of
/// at least 0.1 of it.
fn named_direction(names: &[String], v: &[f64]) -> Vec<(String, f64)> {
    let vmax = v
        .iter()
        .fold(0.0f64, |a, &x| if x.abs() > a.abs() { x } else { a });
    if vmax == 0.0 {
        return Vec::new();
    }
    names
        .iter()
        .zip(v)
        .filter(|(_, x)| x.abs() >= 0.1 * vmax.abs())
        .map(|(n, x)| (n.clone(), x / vmax))
        .collect()
}
