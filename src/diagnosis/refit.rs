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

use frfup_parsers::deck::Deck;

use super::fit::{self, DampingState, Mask, ModalModel};
use super::hypotheses::Hypothesis;
use super::select::Engine;

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

/// Log bounds of the hypotheses with a parameter.
pub fn log_bounds(hyps: &[&Hypothesis]) -> (Vec<f64>, Vec<f64>) {
    hyps.iter()
        .filter_map(|h| h.param.as_ref())
        .map(|p| (p.lo.ln(), p.hi.ln()))
        .unzip()
}

/// Outcome of a joint fit.
#[derive(Clone, Debug)]
pub struct JointFit {
    /// Log parameter values, one per hypothesis with a parameter.
    pub logs: Vec<f64>,
    pub damping: DampingState,
    /// Mean squared weighted residual on the fitted mask.
    pub cost: f64,
    /// Standard deviation of each log parameter (∞ when not determined).
    pub std_log: Vec<f64>,
    /// A parameter within 2 % of its log range from a bound.
    pub on_bound: Vec<bool>,
}

impl JointFit {
    /// Parameter values (SI).
    pub fn values(&self) -> Vec<f64> {
        self.logs.iter().map(|s| s.exp()).collect()
    }
}

/// Starts on a grid: entries of `fixed` that are `Some` stay, each `None`
/// takes `per_axis` values evenly spaced in its log range (inside the
/// bounds by half a step); the product of all.
pub fn grid_starts(hyps: &[&Hypothesis], fixed: &[Option<f64>], per_axis: usize) -> Vec<Vec<f64>> {
    let (lo, hi) = log_bounds(hyps);
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

/// Fit the parameters of `hyps` (applied on `base`) and the damping jointly
/// on `mask`, from `starts` (log values). `None` if no start gives a model.
pub fn fit_joint(
    engine: &Engine,
    base: &Deck,
    hyps: &[&Hypothesis],
    starts: &[Vec<f64>],
    damp: &DampingState,
    mask: &Mask,
    settings: JointSettings,
) -> Option<JointFit> {
    let data = engine.data;
    let (lo, hi) = log_bounds(hyps);
    let p = lo.len();
    let clamp = |s: &[f64]| -> Vec<f64> { (0..p).map(|i| s[i].clamp(lo[i], hi[i])).collect() };
    let mut seeds: Vec<Vec<f64>> = starts.iter().map(|s| clamp(s)).collect();
    if settings.frequency_stage && p > 0 && !data.resonances.is_empty() {
        let freq = |x: &[f64]| -> Option<Vec<f64>> {
            let mm = engine.model(&apply_all(base, hyps, x)).ok()?;
            Some(fit::frequency_residuals(&mm, data))
        };
        let mut ranked: Vec<(f64, Vec<f64>)> = seeds
            .iter()
            .filter_map(|s| freq(s).map(|r| (fit::mean_sq(&r), s.clone())))
            .collect();
        ranked.sort_by(|a, b| a.0.total_cmp(&b.0));
        for (_, s) in ranked.into_iter().take(2) {
            if let Some(o) = fit::lm(freq, &s, &lo, &hi, settings.iterations) {
                seeds.push(o.x);
            }
        }
    }
    // Second stage from the two best seeds by the damping-profiled FRF cost.
    let mut profiled: Vec<(f64, Vec<f64>, DampingState)> = seeds
        .iter()
        .filter_map(|s| {
            let mm = engine.model(&apply_all(base, hyps, s)).ok()?;
            let (d, r) = fit::fit_damping(&mm, damp, data, mask, 10);
            let c = fit::mean_sq(&r);
            c.is_finite().then(|| (c, s.clone(), d))
        })
        .collect();
    profiled.sort_by(|a, b| a.0.total_cmp(&b.0));
    profiled.dedup_by(|a, b| a.1 == b.1);
    let mut best: Option<JointFit> = None;
    for (c0, s, d) in profiled.into_iter().take(2) {
        let (x, cost, dstate, jac_std) =
            frf_stage(engine, base, hyps, &s, &d, mask, settings.iterations).unwrap_or((
                s.clone(),
                c0,
                d.clone(),
                vec![f64::INFINITY; p],
            ));
        if best.as_ref().is_none_or(|b| cost < b.cost) {
            let on_bound = (0..p)
                .map(|i| {
                    let span = hi[i] - lo[i];
                    x[i] - lo[i] < 0.02 * span || hi[i] - x[i] < 0.02 * span
                })
                .collect();
            best = Some(JointFit {
                logs: x,
                damping: dstate,
                cost,
                std_log: jac_std,
                on_bound,
            });
        }
    }
    best
}

/// Levenberg–Marquardt on the log-FRF residuals over (x, damping) from
/// (`x0`, `damp`); returns x, the cost, the damping and σ(x) on the log scale.
fn frf_stage(
    engine: &Engine,
    base: &Deck,
    hyps: &[&Hypothesis],
    x0: &[f64],
    damp: &DampingState,
    mask: &Mask,
    iterations: usize,
) -> Option<(Vec<f64>, f64, DampingState, Vec<f64>)> {
    let data = engine.data;
    let (mut lo, mut hi) = log_bounds(hyps);
    let p = lo.len();
    let w_lo = data.omegas.first().copied().unwrap_or(1.0);
    let w_hi = data.omegas.last().copied().unwrap_or(1.0);
    let (dlo, dhi) = damp.form.bounds(w_lo, w_hi);
    lo.extend(dlo);
    hi.extend(dhi);
    let form = damp.form;
    // The model depends on x only: damping steps reuse it.
    let mut cache: Option<(Vec<f64>, ModalModel)> = None;
    let mut f = |x: &[f64]| -> Option<Vec<f64>> {
        let key = &x[..p];
        if cache.as_ref().is_none_or(|(k, _)| k.as_slice() != key) {
            let mm = engine.model(&apply_all(base, hyps, key)).ok()?;
            cache = Some((key.to_vec(), mm));
        }
        let mm = &cache.as_ref()?.1;
        Some(fit::residuals(
            &fit::predict(mm, form.damping(&x[p..]), data, mask),
            data,
            mask,
        ))
    };
    let mut start = x0.to_vec();
    start.extend(damp.x.iter().copied());
    let out = fit::lm(&mut f, &start, &lo, &hi, iterations)?;
    let jac = fit::jacobian(&mut f, &out.x, &out.residuals, &lo, &hi)?;
    let sd = fit::std_devs(&jac, &out.residuals);
    Some((
        out.x[..p].to_vec(),
        fit::mean_sq(&out.residuals),
        DampingState {
            form,
            x: out.x[p..].to_vec(),
        },
        sd[..p].to_vec(),
    ))
}

/// Mean validation cost of a joint fit over the engine's folds: refit on
/// each training mask from the full-data optimum, predict the held-out one.
pub fn validate_joint(engine: &Engine, base: &Deck, hyps: &[&Hypothesis], full: &JointFit) -> f64 {
    let mut sum = 0.0;
    let mut n = 0usize;
    for (train, val) in &engine.folds {
        let settings = JointSettings {
            frequency_stage: false,
            iterations: 5,
        };
        let Some(f) = fit_joint(
            engine,
            base,
            hyps,
            std::slice::from_ref(&full.logs),
            &full.damping,
            train,
            settings,
        ) else {
            return f64::INFINITY;
        };
        let Ok(mm) = engine.model(&apply_all(base, hyps, &f.logs)) else {
            return f64::INFINITY;
        };
        let r = fit::residuals(
            &fit::predict(&mm, f.damping.damping(), engine.data, val),
            engine.data,
            val,
        );
        sum += fit::mean_sq(&r);
        n += 1;
    }
    if n == 0 {
        full.cost
    } else {
        sum / n as f64
    }
}
