//! Joint fits of several extensions at once.
//!
//! One extension at a time cannot find two effects that mask each other:
//! with the sensor masses missing, a softer clamp alone moves the peaks the
//! wrong way for some modes and its best fit is no clamp at all; with the
//! clamp missing, the masses alone run to their bound. Together they fit to
//! the noise. A joint fit of the log parameters x = (ln θ₁ … ln θ_p) runs in
//! two stages:
//!
//! 1. resonance frequencies: minimise Σ ln²(ω_model/ω_test) over the measured
//!    resonances ([`fit::frequency_residuals`]), from a grid of starts, by
//!    bounded Levenberg–Marquardt; this misfit is smooth in x where the FRF
//!    misfit is flat (peaks far apart) or rough (peaks crossing lines);
//! 2. FRFs: Levenberg–Marquardt on the weighted log-FRF residuals over x and
//!    the damping parameters together, from the best first-stage points and
//!    the given starts.
//!
//! The standard deviations come from the Jacobian of the second stage,
//! σ² (JᵀJ)⁻¹ (see [`fit::std_devs`]), on the log scale.
//!
//! The deck's own parameters (relative changes p̄, Eq. 26 of the paper)
//! can be fitted along, within their `param` bounds and with their priors
//! as prior rows √J₀·p̄_j/s_j ([`ParameterPrior`]): an update made while an
//! effect was missing has absorbed part of it into them.

use frfup_parsers::deck::Deck;

use crate::model::{self, FeModel, ParameterValues};
use crate::updating::fullband::lm::{self, LeastSquares, LmSettings};
use crate::updating::fullband::prior::ParameterPrior;
use crate::updating::fullband::ritz::RitzBasis;
use faer::Mat;

use super::fit::{self, DampingForm, DampingState, Mask, ModalModel};
use super::hypotheses::Hypothesis;
use super::select::Engine;

/// A joint fitting problem: extensions `hyps` on `base`, and optionally the
/// base deck's parameters. The unknowns are x = (ln θ of each hypothesis
/// with a parameter, in order; then p̄ of each deck parameter).
pub struct Joint<'a> {
    pub base: &'a Deck,
    pub hyps: Vec<&'a Hypothesis>,
    /// Names of the deck parameters fitted along (empty: none).
    pub deck_params: Vec<String>,
    /// Their bounds and priors, in the same order.
    pub deck_priors: Vec<ParameterPrior>,
}

impl<'a> Joint<'a> {
    /// Extensions only.
    pub fn new(base: &'a Deck, hyps: Vec<&'a Hypothesis>) -> Self {
        Joint {
            base,
            hyps,
            deck_params: Vec::new(),
            deck_priors: Vec::new(),
        }
    }

    /// Extensions and all of `base`'s own parameters.
    pub fn with_deck_parameters(base: &'a Deck, hyps: Vec<&'a Hypothesis>) -> Self {
        Joint {
            base,
            deck_params: model::parameter_names(base),
            deck_priors: ParameterPrior::of_deck(base),
            hyps,
        }
    }

    /// Number of log parameters (hypotheses with a parameter).
    pub fn n_logs(&self) -> usize {
        self.hyps.iter().filter(|h| h.param.is_some()).count()
    }

    /// Bounds of x.
    pub fn bounds(&self) -> (Vec<f64>, Vec<f64>) {
        let (mut lo, mut hi): (Vec<f64>, Vec<f64>) = self
            .hyps
            .iter()
            .filter_map(|h| h.param.as_ref())
            .map(|p| (p.lo.ln(), p.hi.ln()))
            .unzip();
        lo.extend(self.deck_priors.iter().map(|p| p.min));
        hi.extend(self.deck_priors.iter().map(|p| p.max));
        (lo, hi)
    }

    /// The deck parameters' values in x.
    pub fn deck_values(&self, x: &[f64]) -> ParameterValues {
        let k = self.n_logs();
        self.deck_params
            .iter()
            .cloned()
            .zip(x[k..].iter().copied())
            .collect()
    }

    /// The deck at x, the deck parameters' values multiplied out.
    pub fn deck_at(&self, x: &[f64]) -> Deck {
        let d = apply_all(self.base, &self.hyps, &x[..self.n_logs()]);
        if self.deck_params.is_empty() {
            d
        } else {
            model::updated_deck(&d, &self.deck_values(x))
        }
    }

    fn model(&self, engine: &Engine, x: &[f64]) -> Option<ModalModel> {
        engine.model(&self.deck_at(x)).ok()
    }

    /// [`Self::model`] and, when it was solved anew, its Ritz basis.
    fn model_with_basis(
        &self,
        engine: &Engine,
        x: &[f64],
    ) -> Option<(ModalModel, Option<RitzBasis>)> {
        engine.model_with_basis(&self.deck_at(x)).ok()
    }

    /// The FE model at x (not solved).
    fn fe_at(&self, x: &[f64]) -> Option<FeModel> {
        model::build(&self.deck_at(x), &ParameterValues::new()).ok()
    }

    /// The Ritz basis of the model at x ([`RitzBasis`]), for the
    /// differences of a Jacobian. Not counted as work: the columns are, one
    /// model solution each, as when each was solved in full.
    fn ritz_at(&self, engine: &Engine, x: &[f64]) -> Option<RitzBasis> {
        RitzBasis::at(&self.fe_at(x)?, engine.data).ok()
    }

    /// The modal model at x on `basis` (one model solution of work).
    fn ritz_model(&self, engine: &Engine, basis: &RitzBasis, x: &[f64]) -> Option<ModalModel> {
        let fe = self.fe_at(x)?;
        engine.spend_solution(fe.dofs.len());
        basis.modal_model(&fe)
    }
}

/// The deck with `hyps` applied: `logs` holds one log value per hypothesis
/// with a parameter, in order; the others are applied as they are.
pub fn apply_all(base: &Deck, hyps: &[&Hypothesis], logs: &[f64]) -> Deck {
    let mut d = base.clone();
    let mut k = 0;
    for h in hyps {
        if h.param.is_some() {
            d = h.apply(&d, logs.get(k).map(|s| s.exp()));
            k += 1;
        } else {
            d = h.apply(&d, None);
        }
    }
    d
}

/// Outcome of a joint fit.
#[derive(Clone, Debug)]
pub struct JointFit {
    /// Log parameter values, one per hypothesis with a parameter.
    pub logs: Vec<f64>,
    /// The deck parameters' relative changes (empty when not fitted).
    pub deck_values: ParameterValues,
    /// All unknowns x (logs, then deck parameters).
    pub x: Vec<f64>,
    pub damping: DampingState,
    /// Mean squared weighted residual on the fitted mask.
    pub cost: f64,
    /// Standard deviation of each log parameter (∞ when not determined).
    pub std_log: Vec<f64>,
    /// A log parameter within 2 % of its range from a bound.
    pub on_bound: Vec<bool>,
}

/// Starts of a problem whose last extension (after those `held`, as log
/// values) is new: the held values, the new one's log value on
/// `per_axis` points over its range and at `single` (its fit alone, when
/// given), the deck's parameters (if fitted along) at 0.
pub fn new_extension_starts(
    problem: &Joint,
    held: &[f64],
    single: Option<f64>,
    per_axis: usize,
) -> Vec<Vec<f64>> {
    let (lo, hi) = problem.bounds();
    let np = problem.deck_params.len();
    let mut fixed: Vec<Option<f64>> = held.iter().map(|&l| Some(l)).collect();
    fixed.push(None);
    fixed.extend(std::iter::repeat_n(Some(0.0), np));
    let mut starts = grid_starts(&lo, &hi, &fixed, per_axis);
    if let Some(s) = single {
        let mut x = held.to_vec();
        x.push(s);
        x.extend(std::iter::repeat_n(0.0, np));
        starts.push(x);
    }
    starts
}

/// Starts on a grid: entries of `fixed` that are `Some` stay, each `None`
/// takes `per_axis` values evenly spaced in its range [lo, hi] (inside by
/// half a step); the product of all.
pub fn grid_starts(
    lo: &[f64],
    hi: &[f64],
    fixed: &[Option<f64>],
    per_axis: usize,
) -> Vec<Vec<f64>> {
    let n = per_axis.max(1);
    let mut out = vec![Vec::new()];
    for (i, f) in fixed.iter().enumerate() {
        let axis: Vec<f64> = match f {
            Some(s) => vec![*s],
            None => (0..n)
                .map(|k| lo[i] + (hi[i] - lo[i]) * (k as f64 + 0.5) / n as f64)
                .collect(),
        };
        out = out
            .into_iter()
            .flat_map(|s| {
                axis.iter().map(move |a| {
                    let mut v = s.clone();
                    v.push(*a);
                    v
                })
            })
            .collect();
    }
    out
}

/// Settings of one joint fit.
#[derive(Clone, Copy, Debug)]
pub struct JointSettings {
    /// Run the resonance-frequency stage from the starts first.
    pub frequency_stage: bool,
    /// Levenberg–Marquardt iterations of each stage.
    pub iterations: usize,
}

/// Fit the unknowns of `problem` and the damping jointly on `mask`, from
/// `starts` (full x vectors). `None` if no start gives a model.
pub fn fit_joint(
    engine: &Engine,
    problem: &Joint,
    starts: &[Vec<f64>],
    damp: &DampingState,
    mask: &Mask,
    settings: JointSettings,
) -> Option<JointFit> {
    let data = engine.data;
    let (lo, hi) = problem.bounds();
    let n = lo.len();
    let k = problem.n_logs();
    let clamp = |s: &[f64]| -> Vec<f64> { (0..n).map(|i| s[i].clamp(lo[i], hi[i])).collect() };
    let freq_stage = settings.frequency_stage && n > 0 && !data.resonances.is_empty();
    // One model solution per start serves both stages: its resonance
    // misfit ranks the starts of the frequency stage, its damping-profiled
    // FRF cost ranks the starts of the FRF stage.
    let profile = |mm: &ModalModel| -> Option<(f64, DampingState)> {
        let (d, r) = fit::fit_damping(mm, damp, data, mask, 10);
        let c = fit::mean_sq(&r);
        c.is_finite().then_some((c, d))
    };
    let mut ranked: Vec<(f64, Vec<f64>)> = Vec::new();
    let mut profiled: Vec<(f64, Vec<f64>, DampingState)> = Vec::new();
    for s in starts.iter().filter(|s| s.len() == n) {
        let s = clamp(s);
        let Some(mm) = problem.model(engine, &s) else {
            continue;
        };
        if freq_stage {
            let r = fit::frequency_residuals(&mm, data);
            ranked.push((fit::mean_sq(&r), s.clone()));
        }
        if let Some((c, d)) = profile(&mm) {
            profiled.push((c, s, d));
        }
    }
    if freq_stage {
        ranked.sort_by(|a, b| a.0.total_cmp(&b.0));
        for (_, s) in ranked.into_iter().take(2) {
            let Some(o) = frequency_fit(engine, problem, &s, settings.iterations) else {
                continue;
            };
            if let Some((c, d)) = problem.model(engine, &o.x).as_ref().and_then(profile) {
                profiled.push((c, o.x, d));
            }
        }
    }
    // Second stage from the two best points by the damping-profiled FRF cost.
    profiled.sort_by(|a, b| a.0.total_cmp(&b.0));
    profiled.dedup_by(|a, b| a.1 == b.1);
    let mut best: Option<JointFit> = None;
    for (c0, s, d) in profiled.into_iter().take(2) {
        let (x, cost, dstate, sd) = frf_stage(engine, problem, &s, &d, mask, settings.iterations)
            .unwrap_or((s.clone(), c0, d.clone(), vec![f64::INFINITY; n]));
        if best.as_ref().is_none_or(|b| cost < b.cost) {
            let on_bound = (0..k)
                .map(|i| {
                    let span = hi[i] - lo[i];
                    x[i] - lo[i] < 0.02 * span || hi[i] - x[i] < 0.02 * span
                })
                .collect();
            best = Some(JointFit {
                logs: x[..k].to_vec(),
                deck_values: problem.deck_values(&x),
                x,
                damping: dstate,
                cost,
                std_log: sd[..k].to_vec(),
                on_bound,
            });
        }
    }
    best
}

/// Levenberg–Marquardt on the log-FRF residuals over (x, damping) from
/// (`x0`, `damp`); returns x, the cost, the damping and σ(x).
fn frf_stage(
    engine: &Engine,
    problem: &Joint,
    x0: &[f64],
    damp: &DampingState,
    mask: &Mask,
    iterations: usize,
) -> Option<(Vec<f64>, f64, DampingState, Vec<f64>)> {
    let data = engine.data;
    let (mut lo, mut hi) = problem.bounds();
    let n = lo.len();
    let (w_lo, w_hi) = data.band();
    let (dlo, dhi) = damp.form.bounds(w_lo, w_hi);
    lo.extend(dlo);
    hi.extend(dhi);
    let form = damp.form;
    let k = problem.n_logs();
    let prior_scale = ParameterPrior::row_scale(fit::noise_level(data, mask));
    let prior_rows = ParameterPrior::rows(&problem.deck_priors);
    let mut stage = FrfStage {
        engine,
        problem,
        mask,
        form,
        n,
        k,
        prior_scale,
        lo: lo.clone(),
        hi: hi.clone(),
        cache: None,
    };
    let mut start = x0.to_vec();
    start.extend(damp.x.iter().copied());
    let settings = LmSettings {
        max_iter: iterations,
        ..LmSettings::default()
    };
    let out = lm::lm(&mut stage, &start, &lo, &hi, settings)?;
    let jac = stage.jacobian(&out.x, &out.residuals, &vec![true; out.x.len()])?;
    let sd = fit::std_devs(jac.as_ref(), &out.residuals);
    Some((
        out.x[..n].to_vec(),
        fit::data_mean_sq(&out.residuals, prior_rows),
        DampingState {
            form,
            x: out.x[n..].to_vec(),
        },
        sd[..n].to_vec(),
    ))
}

/// The FRF stage's least-squares problem over (x, damping logs): the
/// model's unknowns by forward differences, the damping's columns exact
/// ([`fit::damping_jacobian`]) on the model at x, which damping steps reuse.
struct FrfStage<'a, 'b> {
    engine: &'a Engine<'a>,
    problem: &'a Joint<'b>,
    mask: &'a Mask,
    form: DampingForm,
    /// Unknowns of the model (x), then the damping's.
    n: usize,
    /// Log parameters of the hypotheses among x (the deck's p̄ follow).
    k: usize,
    prior_scale: f64,
    lo: Vec<f64>,
    hi: Vec<f64>,
    /// The model at the last x asked for, and its Ritz basis when it was
    /// solved anew for it.
    cache: Option<(Vec<f64>, ModalModel, Option<RitzBasis>)>,
}

impl FrfStage<'_, '_> {
    fn model_at(&mut self, x: &[f64]) -> Option<&ModalModel> {
        let key = &x[..self.n];
        if self
            .cache
            .as_ref()
            .is_none_or(|(k, _, _)| k.as_slice() != key)
        {
            let (mm, basis) = self.problem.model_with_basis(self.engine, key)?;
            self.cache = Some((key.to_vec(), mm, basis));
        }
        Some(&self.cache.as_ref()?.1)
    }

    /// The Ritz basis at x: kept from the model's solution at x, or solved.
    fn basis_at(&mut self, x: &[f64]) -> Option<RitzBasis> {
        let key = &x[..self.n];
        match self.cache.as_mut() {
            Some((k, _, basis)) if k.as_slice() == key && basis.is_some() => basis.take(),
            _ => self.problem.ritz_at(self.engine, key),
        }
    }

    /// The residuals at x of the model on `basis`.
    fn ritz_residuals(&self, basis: &RitzBasis, x: &[f64]) -> Option<Vec<f64>> {
        let mm = self.problem.ritz_model(self.engine, basis, &x[..self.n])?;
        Some(self.residuals_of(&mm, x))
    }

    /// The weighted log residuals of `mm` with the damping of x, and the
    /// prior rows of x's deck parameters.
    fn residuals_of(&self, mm: &ModalModel, x: &[f64]) -> Vec<f64> {
        let (n, k, form, mask) = (self.n, self.k, self.form, self.mask);
        let data = self.engine.data;
        let mut r = fit::residuals(
            &fit::predict(mm, form.damping(&x[n..]), data, mask),
            data,
            mask,
        );
        let priors = &self.problem.deck_priors;
        ParameterPrior::push_rows(priors, &x[k..n], self.prior_scale, &mut r);
        r
    }
}

impl LeastSquares for FrfStage<'_, '_> {
    fn residuals(&mut self, x: &[f64]) -> Option<Vec<f64>> {
        self.model_at(x)?;
        let mm = &self.cache.as_ref()?.1;
        Some(self.residuals_of(mm, x))
    }
    fn jacobian(&mut self, x: &[f64], r: &[f64], free: &[bool]) -> Option<Mat<f64>> {
        let n = self.n;
        // The damping's columns first, on the model at x (kept from the
        // residuals at x), then the model's by differences.
        let (form, mask, data) = (self.form, self.mask, self.engine.data);
        let damping = fit::damping_jacobian(self.model_at(x)?, form, &x[n..], data, mask);
        let model_free: Vec<bool> = (0..x.len()).map(|i| i < n && free[i]).collect();
        let (lo, hi) = (self.lo.clone(), self.hi.clone());
        let mut jac = match self.basis_at(x) {
            Some(basis) => {
                let mut f = |y: &[f64]| self.ritz_residuals(&basis, y);
                let r0 = f(x)?;
                lm::forward_differences(&mut f, x, &r0, &lo, &hi, &model_free)?
            }
            None => {
                let mut f = |y: &[f64]| self.residuals(y);
                lm::forward_differences(&mut f, x, r, &lo, &hi, &model_free)?
            }
        };
        // Prior rows (after the data rows) do not depend on the damping.
        for j in (0..damping.ncols()).filter(|&j| free[n + j]) {
            for i in 0..damping.nrows() {
                jac[(i, n + j)] = damping[(i, j)];
            }
        }
        Some(jac)
    }
}

/// Bounded Levenberg–Marquardt on `problem`'s resonance-frequency
/// residuals ([`fit::frequency_residuals`]) from `start`, within the
/// problem's bounds.
pub fn frequency_fit(
    engine: &Engine,
    problem: &Joint,
    start: &[f64],
    iterations: usize,
) -> Option<lm::LmOutcome> {
    let (lo, hi) = problem.bounds();
    let mut stage = FrequencyStage {
        engine,
        problem,
        lo: lo.clone(),
        hi: hi.clone(),
        basis: None,
    };
    let settings = LmSettings {
        max_iter: iterations,
        ..LmSettings::default()
    };
    lm::lm(&mut stage, start, &lo, &hi, settings)
}

/// The resonance-frequency stage's least-squares problem over x
/// ([`fit::frequency_residuals`]); its Jacobian by forward differences on
/// the Ritz basis at x.
struct FrequencyStage<'a, 'b> {
    engine: &'a Engine<'a>,
    problem: &'a Joint<'b>,
    lo: Vec<f64>,
    hi: Vec<f64>,
    /// The Ritz basis of the last x solved anew.
    basis: Option<(Vec<f64>, RitzBasis)>,
}

impl LeastSquares for FrequencyStage<'_, '_> {
    fn residuals(&mut self, x: &[f64]) -> Option<Vec<f64>> {
        let (mm, basis) = self.problem.model_with_basis(self.engine, x)?;
        if let Some(b) = basis {
            self.basis = Some((x.to_vec(), b));
        }
        Some(fit::frequency_residuals(&mm, self.engine.data))
    }
    fn jacobian(&mut self, x: &[f64], r: &[f64], free: &[bool]) -> Option<Mat<f64>> {
        let (engine, problem, data) = (self.engine, self.problem, self.engine.data);
        let (lo, hi) = (self.lo.clone(), self.hi.clone());
        let kept = match self.basis.take() {
            Some((k, b)) if k.as_slice() == x => Some(b),
            _ => None,
        };
        match kept.or_else(|| problem.ritz_at(engine, x)) {
            Some(basis) => {
                let mut f = |y: &[f64]| {
                    let mm = problem.ritz_model(engine, &basis, y)?;
                    Some(fit::frequency_residuals(&mm, data))
                };
                let r0 = f(x)?;
                lm::forward_differences(&mut f, x, &r0, &lo, &hi, free)
            }
            None => {
                let mut f = |y: &[f64]| self.residuals(y);
                lm::forward_differences(&mut f, x, r, &lo, &hi, free)
            }
        }
    }
}

/// Mean validation cost of a joint fit over the engine's folds: refit on
/// each training mask from the full-data optimum, predict the held-out one.
pub fn validate_joint(engine: &Engine, problem: &Joint, full: &JointFit) -> f64 {
    let settings = JointSettings {
        frequency_stage: false,
        iterations: 5,
    };
    engine.cross_validate(full.cost, |train| {
        let starts = std::slice::from_ref(&full.x);
        let f = fit_joint(engine, problem, starts, &full.damping, train, settings)?;
        Some((problem.model(engine, &f.x)?, f.damping.damping()))
    })
}
