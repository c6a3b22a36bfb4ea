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
use super::fit::{self, DampingState, Mask, ModalModel, ModalSolution};
use super::jacobian;
use super::FitError;
use crate::model::{self, Damping, FeModel, ParameterValues};

/// Default hard bounds of a relative change p̄ (a property between 0.1× and
/// 11× its deck value).
pub const DEFAULT_MIN: f64 = -0.9;
pub const DEFAULT_MAX: f64 = 10.0;
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
    cache: Option<(Vec<f64>, FeModel, ModalSolution)>,
    solutions: usize,
}

impl Objective<'_> {
    /// The modal model at structural parameters `p` (cached).
    fn modal(&mut self, p: &[f64]) -> Option<&ModalModel> {
        let fresh = self
            .cache
            .as_ref()
            .is_none_or(|(k, _, _)| k.as_slice() != p);
        if fresh {
            let values: ParameterValues =
                self.names.iter().cloned().zip(p.iter().copied()).collect();
            self.solutions += 1;
            let d = model::updated_deck(self.deck, &values);
            let fe = model::build(&d, &ParameterValues::new()).ok()?;
            let sol = fit::modal_solution(&fe, self.data).ok()?;
            self.cache = Some((p.to_vec(), fe, sol));
        }
        self.cache.as_ref().map(|(_, _, s)| &s.model)
    }

    fn residuals(&mut self, x: &[f64]) -> Option<Vec<f64>> {
        let np = self.names.len();
        self.modal(&x[..np])?;
        let mm = &self.cache.as_ref()?.2.model;
        let pred = fit::predict(mm, self.form.damping(&x[np..]), self.data, &self.mask);
        let mut r = fit::residuals(&pred, self.data, &self.mask);
        for (j, pr) in self.priors.iter().enumerate() {
            if let Some(sd) = pr.sd {
                r.push(self.prior_scale * x[j] / sd);
            }
        }
        Some(r)
    }

    /// Columns ∂r/∂x: the parameters' analytically ([`jacobian`], one modal
    /// solution, chain rule ∂q/∂p̄ = 1/(1 + p̄) from the deck as built to the
    /// deck as given), the damping's by forward differences on the same modes.
    fn jacobian(&mut self, x: &[f64], r: &[f64], lo: &[f64], hi: &[f64]) -> Option<Vec<Vec<f64>>> {
        let np = self.names.len();
        self.modal(&x[..np])?;
        let damping = self.form.damping(&x[np..]);
        let (_, fe, sol) = self.cache.as_ref()?;
        let pred = fit::predict(&sol.model, damping, self.data, &self.mask);
        let mut cols = jacobian::parameter_columns(fe, sol, damping, self.data, &self.mask, &pred);
        let data_n = self.data_rows(r.len());
        if cols.iter().any(|c| c.len() != data_n) {
            return fit::jacobian(&mut |y: &[f64]| self.residuals(y), x, r, lo, hi);
        }
        for (j, col) in cols.iter_mut().enumerate() {
            let chain = 1.0 / (1.0 + x[j]);
            col.iter_mut().for_each(|v| *v *= chain);
            for (k, pr) in self.priors.iter().enumerate() {
                if let Some(sd) = pr.sd {
                    col.push(if k == j { self.prior_scale / sd } else { 0.0 });
                }
            }
        }
        for i in np..x.len() {
            cols.push(self.difference_column(x, r, i, 1e-4, lo, hi)?);
        }
        Some(cols)
    }

    /// ∂r/∂x_i by a forward difference of step `h` (backward at an upper bound).
    fn difference_column(
        &mut self,
        x: &[f64],
        r: &[f64],
        i: usize,
        h: f64,
        lo: &[f64],
        hi: &[f64],
    ) -> Option<Vec<f64>> {
        let h = if x[i] + h > hi[i] && x[i] - h >= lo[i] {
            -h
        } else {
            h
        };
        let mut xp = x.to_vec();
        xp[i] += h;
        let rp = self.residuals(&xp)?;
        (rp.len() == r.len()).then(|| rp.iter().zip(r).map(|(a, b)| (a - b) / h).collect())
    }

    /// ∂r/∂x by forward differences (step 1e-5 in p̄, 1e-4 in the damping's
    /// logs), zero columns for the fixed unknowns.
    fn exact_jacobian(
        &mut self,
        x: &[f64],
        r: &[f64],
        lo: &[f64],
        hi: &[f64],
        free: &[bool],
    ) -> Option<Vec<Vec<f64>>> {
        let np = self.names.len();
        let mut cols = Vec::with_capacity(x.len());
        for (i, &is_free) in free.iter().enumerate().take(x.len()) {
            if !is_free {
                cols.push(vec![0.0; r.len()]);
                continue;
            }
            let h = if i < np { 1e-5 } else { 1e-4 };
            cols.push(self.difference_column(x, r, i, h, lo, hi)?);
        }
        // Leave the model cached at x.
        self.residuals(x)?;
        Some(cols)
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
    // Parameters without a prior that the data do not determine keep the
    // deck's value (p̄ = 0 within the bounds); the others are estimated again
    // from there. Found at the optimum with every parameter free (at a far
    // start the linearisation says little).
    // Pass 1 with a weak prior (sd WEAK_PRIOR_SD) on the parameters that have
    // none: a direction the data cannot see then has a minimum instead of a
    // valley to creep along. The parameters whose data-only standard
    // deviation exceeds the limit are not identified: they keep the deck's
    // value (p̄ = 0 within the bounds). Pass 2, without the weak prior, from
    // there: the estimate and its uncertainty.
    let all_free = vec![true; x0.len()];
    let mut free = all_free.clone();
    obj.priors = priors
        .iter()
        .map(|p| ParameterPrior {
            sd: p.sd.or(Some(WEAK_PRIOR_SD)),
            ..*p
        })
        .collect();
    let first = minimise(&mut obj, &x0, &lo, &hi, req.max_iter, j0)?;
    let seen = uncertainty(&mut obj, &first, &lo, &hi, &all_free, j0);
    let missing = seen.missing.clone();
    let unseen = unidentified(&seen.sd_data, &priors, &free);
    obj.priors = priors.clone();
    let (mut lo2, mut hi2) = (lo.clone(), hi.clone());
    let mut x1 = first.x[..x0.len()].to_vec();
    for &j in &unseen {
        x1[j] = 0.0f64.clamp(lo[j], hi[j]);
        (lo2[j], hi2[j], free[j]) = (x1[j], x1[j], false);
    }
    let mut out = minimise(&mut obj, &x1, &lo2, &hi2, req.max_iter, j0)?;
    // The analytic Jacobian truncates the modal expansion of ∂φ; at the
    // optimum the exact one (finite differences, one model solution per free
    // parameter) makes a last Gauss–Newton step and gives the uncertainty.
    let exact = obj.exact_jacobian(&out.x, &out.residuals, &lo2, &hi2, &free);
    if let Some(jac) = &exact {
        polish(&mut obj, &mut out, jac, &lo2, &hi2, &free);
    }
    let mut sd = match &exact {
        Some(jac) => uncertainty_from(&mut obj, &out, jac, &free, j0).sd,
        None => uncertainty(&mut obj, &out, &lo2, &hi2, &free, j0).sd,
    };
    for &j in &unseen {
        sd[j] = seen.sd_data[j];
    }
    let iterations = first.iterations + out.iterations;
    out.iterations = iterations;
    let data_n = obj.data_rows(out.residuals.len());
    // Against the noise level, but never below that of 0.1 % noise: on
    // (nearly) noise-free data any model error would look enormous.
    let misfit = fit::mean_sq(&out.residuals[..data_n]) / j0.max(J0_FLOOR);
    let parameters = (0..np)
        .map(|j| {
            let v = out.x[j];
            let at_bound = free[j] && (v <= priors[j].min + 1e-9 || v >= priors[j].max - 1e-9);
            ParameterEstimate {
                name: names[j].clone(),
                value: v,
                sd: sd[j],
                prior: priors[j],
                identified: free[j] && sd[j] <= identification_limit(&priors[j]),
                at_bound,
            }
        })
        .collect();
    Ok(FullBandEstimate {
        parameters,
        damping: damp.form.damping(&out.x[np..]),
        misfit,
        converged: out.converged,
        iterations,
        start,
        coarse_stage,
        missing_directions: missing
            .into_iter()
            .map(|(v, s)| (named_direction(&names, &v), s))
            .collect(),
        model_solutions: obj.solutions,
    })
}

/// Free parameters without a prior whose standard deviation exceeds the limit.
fn unidentified(sd: &[f64], priors: &[ParameterPrior], free: &[bool]) -> Vec<usize> {
    (0..priors.len())
        .filter(|&j| {
            free[j] && priors[j].sd.is_none() && !(sd[j] <= identification_limit(&priors[j]))
        })
        .collect()
}

/// The standard deviation above which a parameter is not identified:
/// [`UNIDENTIFIED_SD`], or s/√2 for a prior of sd s (the data did not halve
/// the prior's variance).
fn identification_limit(prior: &ParameterPrior) -> f64 {
    prior.sd.map_or(UNIDENTIFIED_SD, |s| {
        (s / std::f64::consts::SQRT_2).min(UNIDENTIFIED_SD)
    })
}

/// Bounded Levenberg–Marquardt on F from `x0`, with the analytic Jacobian.
fn minimise(
    obj: &mut Objective,
    x0: &[f64],
    lo: &[f64],
    hi: &[f64],
    max_iter: usize,
    j0: f64,
) -> Result<fit::LmOutcome, FitError> {
    let cell = std::cell::RefCell::new(obj);
    let mut f = |x: &[f64]| cell.borrow_mut().residuals(x);
    let mut jac = |_: &mut _, x: &[f64], r: &[f64]| cell.borrow_mut().jacobian(x, r, lo, hi);
    fit::lm_with(&mut f, &mut jac, x0, lo, hi, max_iter, NEGLIGIBLE * j0)
        .ok_or_else(|| FitError::Eigen("the model could not be solved at the start".into()))
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
    let cell = std::cell::RefCell::new(&mut *obj);
    let mut f = |x: &[f64]| cell.borrow_mut().frequency_rows(x);
    let mut jac = |_: &mut _, x: &[f64], _: &[f64]| cell.borrow_mut().frequency_jacobian(x);
    let Some(out) = fit::lm_with(&mut f, &mut jac, p, &lo, &hi, 20, 1e-10) else {
        return false;
    };
    let Some(mm) = obj.modal(&out.x) else {
        return false;
    };
    let (d, r) = fit::fit_damping(mm, damp, data, &mask, 20);
    if fit::mean_sq(&r) < before {
        *p = out.x;
        *damp = d;
        true
    } else {
        false
    }
}

/// Scale of a prior row in the coarse stage: 1 % of frequency per prior sd.
const COARSE_PRIOR: f64 = 0.01;

impl Objective<'_> {
    /// Coarse-stage residuals: ln(ω_model/ω_test) per resonance, then the priors.
    fn frequency_rows(&mut self, p: &[f64]) -> Option<Vec<f64>> {
        let data = self.data;
        let mut r = fit::frequency_residuals(self.modal(p)?, data);
        for (j, pr) in self.priors.iter().enumerate() {
            if let Some(sd) = pr.sd {
                r.push(COARSE_PRIOR * p[j] / sd);
            }
        }
        Some(r)
    }

    /// ∂/∂p̄ of [`Self::frequency_rows`]: ∂ln ω_r = ∂λ_r / 2λ_r with
    /// ∂λ_r = φ_rᵀ(∂K − λ_r∂M)φ_r, times the chain factor 1/(1 + p̄).
    fn frequency_jacobian(&mut self, p: &[f64]) -> Option<Vec<Vec<f64>>> {
        let data = self.data;
        let align = fit::frequency_alignment(self.modal(p)?, data);
        let (_, fe, sol) = self.cache.as_ref()?;
        let paired: Vec<usize> = align.iter().filter_map(|a| a.1).collect();
        let sens = crate::updating::sensitivity::ModalSensitivities::project(
            &fe.parameters,
            sol.modes.shapes.as_ref(),
            &paired,
        );
        let mut cols = Vec::with_capacity(p.len());
        for (j, &pj) in p.iter().enumerate() {
            let chain = 1.0 / (1.0 + pj);
            let mut col = Vec::with_capacity(align.len());
            let mut k = 0;
            for a in &align {
                match a.1 {
                    Some(r) => {
                        let lam = sol.modes.omega2[r];
                        let dl = sens.dk[j][(k, k)] - lam * sens.dm[j][(k, k)];
                        col.push(if lam > 0.0 {
                            chain * dl / (2.0 * lam)
                        } else {
                            0.0
                        });
                        k += 1;
                    }
                    None => col.push(0.0),
                }
            }
            for (i, pr) in self.priors.iter().enumerate() {
                if let Some(sd) = pr.sd {
                    col.push(if i == j { COARSE_PRIOR / sd } else { 0.0 });
                }
            }
            cols.push(col);
        }
        Some(cols)
    }
}

/// What the data say about the parameters at a point.
struct Uncertainty {
    /// Posterior standard deviation (sandwich covariance over the free
    /// unknowns; ∞ for fixed ones).
    sd: Vec<f64>,
    /// Standard deviation from the data alone, ŝ²(JᵀJ)⁻¹ over the free
    /// unknowns' data rows (∞ where the data see nothing).
    sd_data: Vec<f64>,
    /// Eigenvectors of the data information over the free parameters whose
    /// standard deviation 1/√λ exceeds [`UNIDENTIFIED_SD`] (components over
    /// all parameters), with that standard deviation, largest first.
    missing: Vec<(Vec<f64>, f64)>,
}

fn uncertainty(
    obj: &mut Objective,
    out: &fit::LmOutcome,
    lo: &[f64],
    hi: &[f64],
    free: &[bool],
    j0: f64,
) -> Uncertainty {
    match obj.jacobian(&out.x, &out.residuals, lo, hi) {
        Some(jac) => uncertainty_from(obj, out, &jac, free, j0),
        None => {
            let np = obj.names.len();
            Uncertainty {
                sd: vec![f64::INFINITY; np],
                sd_data: vec![f64::INFINITY; np],
                missing: Vec::new(),
            }
        }
    }
}

/// One Gauss–Newton step over the free unknowns with the Jacobian `jac`,
/// clamped to the bounds, kept if it lowers F.
fn polish(
    obj: &mut Objective,
    out: &mut fit::LmOutcome,
    jac: &[Vec<f64>],
    lo: &[f64],
    hi: &[f64],
    free: &[bool],
) {
    let idx: Vec<usize> = (0..out.x.len()).filter(|&i| free[i]).collect();
    let n = idx.len();
    let mut a = DMatrix::<f64>::zeros(n, n);
    let mut g = nalgebra::DVector::<f64>::zeros(n);
    for (p, &ip) in idx.iter().enumerate() {
        for (q, &iq) in idx.iter().enumerate().take(p + 1) {
            let v: f64 = jac[ip].iter().zip(&jac[iq]).map(|(x, y)| x * y).sum();
            a[(p, q)] = v;
            a[(q, p)] = v;
        }
        g[p] = -jac[ip]
            .iter()
            .zip(&out.residuals)
            .map(|(x, y)| x * y)
            .sum::<f64>();
        a[(p, p)] *= 1.0 + 1e-9;
    }
    let Some(step) = a.cholesky().map(|c| c.solve(&g)) else {
        return;
    };
    let mut x = out.x.clone();
    for (p, &ip) in idx.iter().enumerate() {
        x[ip] = (x[ip] + step[p]).clamp(lo[ip], hi[ip]);
    }
    let cost = |r: &[f64]| r.iter().map(|v| v * v).sum::<f64>();
    if let Some(r) = obj.residuals(&x) {
        if cost(&r) < cost(&out.residuals) {
            out.x = x;
            out.residuals = r;
        }
    }
}

/// [`uncertainty`] with a given Jacobian (columns over every unknown).
fn uncertainty_from(
    obj: &mut Objective,
    out: &fit::LmOutcome,
    jac: &[Vec<f64>],
    free: &[bool],
    j0: f64,
) -> Uncertainty {
    let (x, r) = (&out.x, &out.residuals);
    let np = obj.names.len();
    let mut u = Uncertainty {
        sd: vec![f64::INFINITY; np],
        sd_data: vec![f64::INFINITY; np],
        missing: Vec::new(),
    };
    let idx: Vec<usize> = (0..x.len()).filter(|&i| free[i]).collect();
    let n = idx.len();
    let total = r.len();
    let data_n = obj.data_rows(total);
    let mut h = DMatrix::<f64>::zeros(n, n);
    let mut info = DMatrix::<f64>::zeros(n, n);
    let dof = (data_n as f64 - n as f64).max(1.0);
    let s2 = (r[..data_n].iter().map(|v| v * v).sum::<f64>() / dof).max(1e-300);
    let row = |i: usize| -> Vec<f64> { idx.iter().map(|&k| jac[k][i]).collect() };
    for i in 0..total {
        let ji = row(i);
        for a in 0..n {
            if ji[a] == 0.0 {
                continue;
            }
            for c in 0..n {
                h[(a, c)] += ji[a] * ji[c];
                if i < data_n {
                    info[(a, c)] += ji[a] * ji[c];
                }
            }
        }
    }
    if let Some(hinv) = h.clone().try_inverse() {
        // B: each data row's observed r², inflated by its leverage
        // h_ii = J_i H⁻¹ J_iᵀ as 1/(1 − h_ii)² (HC3: a few lines at a sharp
        // peak decide a frequency, and their residuals are shrunk by the fit);
        // a prior row's expected r² under the prior is J₀.
        let mut b = DMatrix::<f64>::zeros(n, n);
        for (i, &ri) in r.iter().enumerate() {
            let ji = nalgebra::DVector::from_vec(row(i));
            if ji.iter().all(|&v| v == 0.0) {
                continue;
            }
            let w = if i < data_n {
                let lev = (ji.transpose() * &hinv * &ji)[(0, 0)].clamp(0.0, 0.99);
                ri * ri / ((1.0 - lev) * (1.0 - lev))
            } else {
                j0
            };
            b += &ji * ji.transpose() * w;
        }
        let cov = &hinv * b * &hinv;
        for (a, &ia) in idx.iter().enumerate() {
            if ia < np {
                u.sd[ia] = cov[(a, a)].max(0.0).sqrt();
            }
        }
    }
    // The data's information over the free structural parameters.
    let ip: Vec<usize> = (0..n).filter(|&a| idx[a] < np).collect();
    if ip.is_empty() {
        return u;
    }
    let info_p = DMatrix::from_fn(ip.len(), ip.len(), |a, c| info[(ip[a], ip[c])]) / s2;
    let eig = SymmetricEigen::new(info_p);
    let floor = eig.eigenvalues.iter().fold(0.0f64, |m, l| m.max(l.abs())) * 1e-14;
    for (a, &pa) in ip.iter().enumerate() {
        // (info⁻¹)_aa by the eigen-decomposition, ∞ along null directions.
        let mut var = 0.0;
        for (k, &lam) in eig.eigenvalues.iter().enumerate() {
            let v = eig.eigenvectors[(a, k)];
            if v * v > 1e-20 {
                var += if lam > floor {
                    v * v / lam
                } else {
                    f64::INFINITY
                };
            }
        }
        u.sd_data[idx[pa]] = var.sqrt();
    }
    for (k, &lam) in eig.eigenvalues.iter().enumerate() {
        let sd = if lam > floor {
            1.0 / lam.sqrt()
        } else {
            f64::INFINITY
        };
        if sd > UNIDENTIFIED_SD {
            let mut v = vec![0.0; np];
            for (a, &pa) in ip.iter().enumerate() {
                v[idx[pa]] = eig.eigenvectors[(a, k)];
            }
            u.missing.push((v, sd));
        }
    }
    u.missing.sort_by(|a, b| b.1.total_cmp(&a.1));
    u
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
