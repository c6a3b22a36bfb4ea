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
//! (`param … min= max=`; default [`DEFAULT_MIN`], [`DEFAULT_MAX`]).
//! Minimised by bounded Levenberg–Marquardt ([`fit::lm`]), from the best of
//! the candidate starts, after a coarse stage on the resonance frequencies
//! alone when the start is far from the test ([`fit::frequency_residuals`]).
//!
//! Uncertainty: with H = JᵀJ at the optimum (prior rows included) and
//! B = Σ_i J_iᵀJ_i r_i² · N/(N − n) + Σ_j (J₀/s_j²)·J₀ e_j e_jᵀ (the observed
//! scatter of the residuals, and the prior's own), the covariance is the
//! sandwich H⁻¹BH⁻¹: it holds at the noise level the data show, whatever the
//! weights assumed. A parameter whose standard deviation exceeds
//! [`UNIDENTIFIED_SD`] (or its prior's s_j/√2: the data did not halve the
//! prior's variance) is *not identified by these data*; the directions of
//! parameter space the data do not see are the eigenvectors of the data's
//! information JᵀJ/ŝ² whose standard deviation 1/√λ exceeds the same limit.

use frfup_parsers::deck::Deck;
use nalgebra::{DMatrix, SymmetricEigen};

use super::data::TestData;
use super::fit::{self, DampingState, Mask, ModalModel};
use super::FitError;
use crate::model::{self, Damping, ParameterValues};

/// Default hard bounds of a relative change p̄ (a property between 0.1× and
/// 11× its deck value).
pub const DEFAULT_MIN: f64 = -0.9;
pub const DEFAULT_MAX: f64 = 10.0;
/// A parameter whose standard deviation exceeds this is not identified.
pub const UNIDENTIFIED_SD: f64 = 0.5;
/// Mean |ln(f_model/f_test)| above which the coarse frequency stage runs first.
const COARSE_THRESHOLD: f64 = 0.02;

/// Bounds and prior of one parameter (relative change p̄).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ParameterPrior {
    pub min: f64,
    pub max: f64,
    /// Prior standard deviation (None: no prior).
    pub sd: Option<f64>,
}

impl ParameterPrior {
    /// The deck's `param` bounds and priors, in deck order.
    pub fn of_deck(deck: &Deck) -> Vec<ParameterPrior> {
        deck.params
            .iter()
            .map(|p| ParameterPrior {
                min: p.min.unwrap_or(DEFAULT_MIN),
                max: p.max.unwrap_or(DEFAULT_MAX),
                sd: p.sd,
            })
            .collect()
    }
}

/// What to estimate.
pub struct EstimateRequest<'a> {
    pub deck: &'a Deck,
    pub data: &'a TestData,
    /// Candidate starting points p̄ (deck order); the one that fits best
    /// (after a damping fit) is used.
    pub starts: Vec<Vec<f64>>,
    /// Levenberg–Marquardt iteration limit.
    pub max_iter: usize,
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
    /// The estimate sits on `min` or `max`.
    pub at_bound: bool,
}

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
    /// Index of the start used (into the request's `starts`).
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

/// The residual function of F: data rows, then one prior row per parameter
/// with a prior. Caches the modal model of the last structural parameters
/// (damping columns of a Jacobian reuse it).
struct Objective<'a> {
    deck: &'a Deck,
    data: &'a TestData,
    mask: Mask,
    names: Vec<String>,
    priors: Vec<ParameterPrior>,
    form: fit::DampingForm,
    /// √J₀, the scale of a prior row.
    prior_scale: f64,
    cache: Option<(Vec<f64>, ModalModel)>,
    solutions: usize,
}

impl Objective<'_> {
    /// The modal model at structural parameters `p` (cached).
    fn modal(&mut self, p: &[f64]) -> Option<&ModalModel> {
        let fresh = self.cache.as_ref().is_none_or(|(k, _)| k.as_slice() != p);
        if fresh {
            let values: ParameterValues =
                self.names.iter().cloned().zip(p.iter().copied()).collect();
            self.solutions += 1;
            let d = model::updated_deck(self.deck, &values);
            let mm = fit::modal_model(&d, self.data).ok()?;
            self.cache = Some((p.to_vec(), mm));
        }
        self.cache.as_ref().map(|(_, mm)| mm)
    }

    fn residuals(&mut self, x: &[f64]) -> Option<Vec<f64>> {
        let np = self.names.len();
        self.modal(&x[..np])?;
        let mm = &self.cache.as_ref()?.1;
        let pred = fit::predict(mm, self.form.damping(&x[np..]), self.data, &self.mask);
        let mut r = fit::residuals(&pred, self.data, &self.mask);
        for (j, pr) in self.priors.iter().enumerate() {
            if let Some(sd) = pr.sd {
                r.push(self.prior_scale * x[j] / sd);
            }
        }
        Some(r)
    }

    /// Residual rows that come from the data (the rest are prior rows).
    fn data_rows(&self, total: usize) -> usize {
        total - self.priors.iter().filter(|p| p.sd.is_some()).count()
    }
}

/// Run the estimate.
pub fn estimate(req: &EstimateRequest) -> Result<FullBandEstimate, FitError> {
    let names = model::parameter_names(req.deck);
    let priors = ParameterPrior::of_deck(req.deck);
    let np = names.len();
    if np == 0 || req.starts.is_empty() {
        return Err(FitError::Data("no parameter to estimate".into()));
    }
    let mask = Mask::all(req.data);
    let j0 = fit::noise_level(req.data, &mask).max(1e-12);
    let deck_damping = Damping::of_deck(req.deck);
    let damp0 = fit::start_damping(deck_damping, req.data);
    let mut obj = Objective {
        deck: req.deck,
        data: req.data,
        mask: mask.clone(),
        names: names.clone(),
        priors: priors.clone(),
        form: damp0.form,
        prior_scale: j0.sqrt(),
        cache: None,
        solutions: 0,
    };
    // The best start, each with its damping fitted.
    let mut best: Option<(usize, Vec<f64>, DampingState, f64)> = None;
    for (k, s) in req.starts.iter().enumerate() {
        let p: Vec<f64> = s
            .iter()
            .zip(&priors)
            .map(|(v, pr)| v.clamp(pr.min, pr.max))
            .collect();
        let Some(mm) = obj.modal(&p) else { continue };
        let (d, r) = fit::fit_damping(mm, &damp0, req.data, &mask, 20);
        let c = fit::mean_sq(&r);
        if best.as_ref().is_none_or(|b| c < b.3) {
            best = Some((k, p, d, c));
        }
    }
    let Some((start, mut p, mut damp, _)) = best else {
        return Err(FitError::Eigen(
            "no starting point gives a usable model".into(),
        ));
    };
    let coarse_stage = coarse_frequencies(&mut obj, &mut p, &mut damp);
    let (lo, hi) = bounds(&priors, damp.form, req.data);
    let mut x0 = p.clone();
    x0.extend(damp.x.iter().copied());
    let out = fit::lm(|x| obj.residuals(x), &x0, &lo, &hi, req.max_iter)
        .ok_or_else(|| FitError::Eigen("the model could not be solved at the start".into()))?;
    let (sd, missing) = uncertainty(&mut obj, &out.x, &out.residuals, &lo, &hi, j0);
    let data_n = obj.data_rows(out.residuals.len());
    let misfit = fit::mean_sq(&out.residuals[..data_n]) / j0;
    let parameters = (0..np)
        .map(|j| {
            let v = out.x[j];
            let limit = priors[j]
                .sd
                .map_or(UNIDENTIFIED_SD, |s| (s / std::f64::consts::SQRT_2).min(UNIDENTIFIED_SD));
            let at_bound = v <= priors[j].min + 1e-9 || v >= priors[j].max - 1e-9;
            ParameterEstimate {
                name: names[j].clone(),
                value: v,
                sd: sd[j],
                prior: priors[j],
                identified: sd[j].is_finite() && sd[j] <= limit && !at_bound,
                at_bound,
            }
        })
        .collect();
    Ok(FullBandEstimate {
        parameters,
        damping: damp.form.damping(&out.x[np..]),
        misfit,
        converged: out.converged,
        iterations: out.iterations,
        start,
        coarse_stage,
        missing_directions: missing
            .into_iter()
            .map(|(v, s)| (named_direction(&names, &v), s))
            .collect(),
        model_solutions: obj.solutions,
    })
}

/// Hard bounds of x = [p̄, damping logs].
fn bounds(
    priors: &[ParameterPrior],
    form: fit::DampingForm,
    data: &TestData,
) -> (Vec<f64>, Vec<f64>) {
    let w_lo = data.omegas.first().copied().unwrap_or(1.0);
    let w_hi = data.omegas.last().copied().unwrap_or(1.0);
    let (dlo, dhi) = form.bounds(w_lo, w_hi);
    let mut lo: Vec<f64> = priors.iter().map(|p| p.min).collect();
    let mut hi: Vec<f64> = priors.iter().map(|p| p.max).collect();
    lo.extend(dlo);
    hi.extend(dhi);
    (lo, hi)
}

/// The coarse stage: when the model's resonances are on average more than
/// [`COARSE_THRESHOLD`] from the test's, fit p̄ to the resonance frequencies
/// alone (with the priors), then refit the damping; kept only if the
/// full-band cost falls. Returns whether it was kept.
fn coarse_frequencies(obj: &mut Objective, p: &mut Vec<f64>, damp: &mut DampingState) -> bool {
    let data = obj.data;
    let mask = obj.mask.clone();
    let Some(mm) = obj.modal(p) else { return false };
    let fr = fit::frequency_residuals(mm, data);
    if fr.is_empty() {
        return false;
    }
    let mean = fr.iter().map(|x| x.abs()).sum::<f64>() / fr.len() as f64;
    if mean <= COARSE_THRESHOLD {
        return false;
    }
    let before = fit::mean_sq(&fit::residuals(
        &fit::predict(mm, damp.damping(), data, &mask),
        data,
        &mask,
    ));
    let lo: Vec<f64> = obj.priors.iter().map(|q| q.min).collect();
    let hi: Vec<f64> = obj.priors.iter().map(|q| q.max).collect();
    let priors = obj.priors.clone();
    let f = |x: &[f64]| -> Option<Vec<f64>> {
        let mm = obj.modal(x)?;
        let mut r = fit::frequency_residuals(mm, data);
        // A prior row in frequency units: 1 % of frequency per prior sd.
        for (j, pr) in priors.iter().enumerate() {
            if let Some(sd) = pr.sd {
                r.push(0.01 * x[j] / sd);
            }
        }
        Some(r)
    };
    let Some(out) = fit::lm(f, p, &lo, &hi, 20) else {
        return false;
    };
    let Some(mm) = obj.modal(&out.x) else { return false };
    let (d, r) = fit::fit_damping(mm, damp, data, &mask, 20);
    if fit::mean_sq(&r) < before {
        *p = out.x;
        *damp = d;
        true
    } else {
        false
    }
}

/// Standard deviations of p̄ (sandwich covariance) and the unseen directions
/// (eigenvectors of the data information, with their standard deviation).
#[allow(clippy::type_complexity)]
fn uncertainty(
    obj: &mut Objective,
    x: &[f64],
    r: &[f64],
    lo: &[f64],
    hi: &[f64],
    j0: f64,
) -> (Vec<f64>, Vec<(Vec<f64>, f64)>) {
    let np = obj.names.len();
    let n = x.len();
    let nan = (vec![f64::INFINITY; np], Vec::new());
    let Some(jac) = fit::jacobian(&mut |y: &[f64]| obj.residuals(y), x, r, lo, hi) else {
        return nan;
    };
    let total = r.len();
    let data_n = obj.data_rows(total);
    let mut h = DMatrix::<f64>::zeros(n, n);
    let mut b = DMatrix::<f64>::zeros(n, n);
    let mut info = DMatrix::<f64>::zeros(n, n);
    let dof = (data_n as f64 - n as f64).max(1.0);
    let correction = data_n as f64 / dof;
    let s2 = r[..data_n].iter().map(|v| v * v).sum::<f64>() / dof;
    for i in 0..total {
        for a in 0..n {
            let ja = jac[a][i];
            if ja == 0.0 {
                continue;
            }
            for c in 0..n {
                let jc = jac[c][i];
                h[(a, c)] += ja * jc;
                if i < data_n {
                    b[(a, c)] += ja * jc * r[i] * r[i] * correction;
                    info[(a, c)] += ja * jc;
                } else {
                    // A prior row: expected r² from the prior itself is J₀.
                    b[(a, c)] += ja * jc * j0;
                }
            }
        }
    }
    let Some(hinv) = h.clone().try_inverse() else {
        return nan;
    };
    let cov = &hinv * b * &hinv;
    let sd: Vec<f64> = (0..np).map(|j| cov[(j, j)].max(0.0).sqrt()).collect();
    // Unseen directions: the structural block of the data information.
    let info_p = info.view((0, 0), (np, np)).into_owned() / s2.max(1e-300);
    let eig = SymmetricEigen::new(info_p);
    let mut missing = Vec::new();
    for (k, &lam) in eig.eigenvalues.iter().enumerate() {
        let s = if lam > 0.0 { 1.0 / lam.sqrt() } else { f64::INFINITY };
        if s > UNIDENTIFIED_SD {
            let v: Vec<f64> = eig.eigenvectors.column(k).iter().copied().collect();
            missing.push((v, s));
        }
    }
    missing.sort_by(|a, b| b.1.total_cmp(&a.1));
    (sd, missing)
}

/// A direction as (name, component) pairs, largest component +1, terms of
/// at least 0.1 of it.
fn named_direction(names: &[String], v: &[f64]) -> Vec<(String, f64)> {
    let (imax, vmax) = v
        .iter()
        .enumerate()
        .fold((0, 0.0f64), |a, (i, x)| if x.abs() > a.1.abs() { (i, *x) } else { a });
    let _ = imax;
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
