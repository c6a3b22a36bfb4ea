//! The residual function of the full-band estimate and its minimisation.
//!
//! F(x) = Σ_i r_i(x)² + Σ_j J₀ (p̄_j / s_j)², x = [p̄, damping logs]: the
//! weighted log-FRF residuals of [`fit::residuals`] on the reduced model of
//! [`super::reduced`], then one prior row √J₀·p̄_j/s_j per parameter with a
//! prior. The reduced model is re-anchored once a step takes a property
//! more than [`ANCHOR_DRIFT`] from the anchor (the basis moved there from
//! the old one, [`ReducedModel::moved`]), and at the end of each
//! minimisation, from a new eigen solution of the full model, until the
//! anchor sits at the optimum: there the reduced model's FRFs and Jacobian
//! are the full model's.

use faer::{c64, Mat};
use frfup_parsers::deck::Deck;

use super::data::TestData;
use super::fit::{self, DampingForm, Mask};
use super::jacobian::{self, Point};
use super::lm::{self, LeastSquares, LmOutcome, LmSettings};
use super::prior::ParameterPrior;
use super::reduced::{ReducedModel, ReducedModes};
use super::FitError;

/// Largest relative change of a property from the anchor before the basis
/// is rebuilt.
pub const ANCHOR_DRIFT: f64 = 0.05;
/// Re-anchorings at the end of one minimisation, at most.
const MAX_ANCHORS: usize = 4;
/// Largest change of a structural unknown p̄_j in one Levenberg–Marquardt
/// step: the property changes by at most its deck value. A parameter the
/// data barely see at the start has a Gauss–Newton step far beyond where
/// its linearisation holds; with [`lm`]'s general limit of 2, the GARTEUR
/// demo's `tail_Iz` walked 0 → 8 → 0 in steps of 2, 12 of the first pass's
/// 26 iterations (10 with this limit, the same estimate to 1e-6). The
/// damping's log parameters keep the general limit.
pub const MAX_PARAMETER_STEP: f64 = 1.0;

/// The objective F on one data set.
pub struct Objective<'a> {
    pub deck: &'a Deck,
    pub data: &'a TestData,
    pub mask: Mask,
    pub names: Vec<String>,
    /// The priors in force (the first pass adds weak ones).
    pub priors: Vec<ParameterPrior>,
    pub form: DampingForm,
    /// √J₀, the scale of a prior row.
    pub prior_scale: f64,
    pub reduced: Option<ReducedModel>,
    /// The reduced model before the last re-anchoring, kept until the step
    /// that moved the anchor is judged on the new one.
    pub previous: Option<ReducedModel>,
    /// The reduced solution at the last structural parameters.
    pub cache: Option<(Vec<f64>, ReducedModes)>,
    /// The model FRFs at the last x.
    pub last: Option<(Vec<f64>, Vec<Vec<c64>>)>,
    /// Full models built and solved (one per anchor, moved or new).
    pub solutions: usize,
    /// The storage of the last Jacobian, for the next one.
    pub spare: Option<Mat<f64>>,
}

impl<'a> Objective<'a> {
    /// The objective of `names` (with their `priors`) on `data` within
    /// `mask`, damping of the given form, prior rows scaled by `prior_scale`
    /// (√J₀); nothing solved yet.
    pub fn new(
        deck: &'a Deck,
        data: &'a TestData,
        mask: Mask,
        (names, priors): (Vec<String>, Vec<ParameterPrior>),
        form: DampingForm,
        prior_scale: f64,
    ) -> Self {
        Objective {
            deck,
            data,
            mask,
            names,
            priors,
            form,
            prior_scale,
            reduced: None,
            previous: None,
            cache: None,
            last: None,
            solutions: 0,
            spare: None,
        }
    }

    /// The same objective with nothing solved yet.
    pub fn fresh(&self) -> Self {
        let parameters = (self.names.clone(), self.priors.clone());
        let mask = self.mask.clone();
        Objective::new(
            self.deck,
            self.data,
            mask,
            parameters,
            self.form,
            self.prior_scale,
        )
    }

    /// Number of structural parameters.
    pub fn np(&self) -> usize {
        self.names.len()
    }

    /// Take `other`'s anchor, its solution and model FRFs, and count its
    /// model solutions: the state `other`'s calls would have left here.
    pub fn take_anchor(&mut self, other: Objective) {
        self.solutions += other.solutions;
        self.reduced = other.reduced;
        self.cache = other.cache;
        self.last = other.last;
    }

    /// Build the reduced model at structural parameters `p`.
    pub fn anchor(&mut self, p: &[f64]) -> Result<(), FitError> {
        self.solutions += 1;
        self.cache = None;
        self.last = None;
        self.reduced = Some(ReducedModel::new(self.deck, &self.names, p, self.data)?);
        Ok(())
    }

    /// The reduced solution at `p` (cached).
    pub fn modes(&mut self, p: &[f64]) -> Option<&ReducedModes> {
        if self.cache.as_ref().is_none_or(|(k, _)| k.as_slice() != p) {
            let modes = self.reduced.as_ref()?.solve(p)?;
            self.cache = Some((p.to_vec(), modes));
        }
        self.cache.as_ref().map(|c| &c.1)
    }

    /// Model FRFs at x (cached).
    pub fn predict(&mut self, x: &[f64]) -> Option<&Vec<Vec<c64>>> {
        if self.last.as_ref().is_none_or(|(k, _)| k.as_slice() != x) {
            let np = self.np();
            let damping = self.form.damping(&x[np..]);
            let (data, mask) = (self.data, self.mask.clone());
            let modes = self.modes(&x[..np])?;
            let pred = fit::predict(&modes.model, damping, data, &mask);
            self.last = Some((x.to_vec(), pred));
        }
        self.last.as_ref().map(|l| &l.1)
    }

    /// Residual rows that come from the data (the rest are prior rows).
    pub fn data_rows(&self, total: usize) -> usize {
        total - ParameterPrior::rows(&self.priors)
    }
}

impl LeastSquares for Objective<'_> {
    fn residuals(&mut self, x: &[f64]) -> Option<Vec<f64>> {
        let data = self.data;
        self.predict(x)?;
        let pred = &self.last.as_ref()?.1;
        let mut r = fit::residuals(pred, data, &self.mask);
        ParameterPrior::push_rows(&self.priors, x, self.prior_scale, &mut r);
        Some(r)
    }

    /// Analytic columns of [`jacobian::columns`], then the prior rows.
    fn jacobian(&mut self, x: &[f64], r: &[f64], free: &[bool]) -> Option<Mat<f64>> {
        let np = self.np();
        self.predict(x)?;
        let pt = Point {
            model: self.reduced.as_ref()?,
            modes: &self.cache.as_ref()?.1,
            form: self.form,
            damping: &x[np..],
            pred: &self.last.as_ref()?.1,
        };
        let prior_rows = ParameterPrior::rows(&self.priors);
        let spare = self.spare.take();
        let mut jac = jacobian::columns(&pt, self.data, &self.mask, free, prior_rows, spare);
        let data_n = jac.nrows() - prior_rows;
        if self.data_rows(r.len()) != data_n || jac.ncols() != x.len() {
            return None;
        }
        ParameterPrior::fill_rows(&self.priors, self.prior_scale, &mut jac, data_n);
        Some(jac)
    }

    fn recycle(&mut self, jac: Mat<f64>) {
        self.spare = Some(jac);
    }

    fn max_step(&self, i: usize) -> f64 {
        if i < self.np() {
            MAX_PARAMETER_STEP
        } else {
            lm::MAX_STEP
        }
    }

    fn accepted(&mut self, x: &[f64]) -> Option<Vec<f64>> {
        let np = self.np();
        if self.reduced.as_ref()?.drift(&x[..np]) <= ANCHOR_DRIFT {
            return None;
        }
        self.modes(&x[..np])?;
        let moved = {
            let (model, at_p) = (self.reduced.as_ref()?, &self.cache.as_ref()?.1);
            model.moved(self.deck, &self.names, &x[..np], self.data, at_p)
        };
        let Ok(moved) = moved else {
            return None;
        };
        self.solutions += 1;
        self.previous = self.reduced.replace(moved);
        self.cache = None;
        self.last = None;
        self.residuals(x)
    }

    fn rejected(&mut self, _x: &[f64]) {
        if let Some(previous) = self.previous.take() {
            self.reduced = Some(previous);
            self.cache = None;
            self.last = None;
        }
    }
}

/// Minimise F from `x0` within [lo, hi] (an unknown with lo = hi is held):
/// Levenberg–Marquardt on the reduced model anchored at `x0`, then again
/// from each optimum with the anchor moved there, until a run no longer
/// lowers F by `negligible`.
pub fn minimise(
    obj: &mut Objective,
    x0: &[f64],
    lo: &[f64],
    hi: &[f64],
    max_iter: usize,
    negligible: f64,
) -> Result<LmOutcome, FitError> {
    let np = obj.np();
    let fresh = obj.reduced.as_ref().is_none_or(|m| m.anchor != x0[..np]);
    if fresh {
        obj.anchor(&x0[..np])?;
    }
    let settings = LmSettings {
        max_iter,
        negligible,
        ..LmSettings::default()
    };
    let failed = || FitError::Eigen("the reduced model could not be solved".into());
    let mut out = lm::lm(obj, x0, lo, hi, settings).ok_or_else(failed)?;
    for _ in 0..MAX_ANCHORS {
        let anchored = obj
            .reduced
            .as_ref()
            .is_some_and(|m| m.anchor == out.x[..np]);
        if anchored || out.iterations >= max_iter {
            break;
        }
        obj.anchor(&out.x[..np])?;
        let c0: f64 = obj
            .residuals(&out.x)
            .ok_or_else(failed)?
            .iter()
            .map(|v| v * v)
            .sum();
        let left = LmSettings {
            max_iter: max_iter - out.iterations,
            negligible,
            ..LmSettings::default()
        };
        let again = lm::lm(obj, &out.x, lo, hi, left).ok_or_else(failed)?;
        let gain = c0 - again.residuals.iter().map(|v| v * v).sum::<f64>();
        let iterations = out.iterations + again.iterations;
        out = LmOutcome {
            iterations,
            ..again
        };
        if gain < negligible {
            break;
        }
    }
    Ok(out)
}
