//! Choosing extensions without over-fitting.
//!
//! Each candidate's parameter is fitted on all data (log grid, then golden
//! section on the damping-profiled cost), then validated by blocked
//! cross-validation: fit on alternate frequency blocks (8 blocks, 2 folds)
//! and on alternate channels (2 folds, [`folds`]), predict the held-out
//! data. A candidate is accepted if its mean validation cost is lower than the
//! current model's by more than the margin 3 %·V + 0.1·J0 (J0: noise level),
//! its fit does not end on a bound and its uncertainty is below its value.
//! Extensions are added greedily; the search stops when the cost is within
//! 25 % of the noise level.

use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Mutex, OnceLock};

use frfup_parsers::deck::Deck;
use rayon::prelude::*;

use super::data::TestData;
use super::fit::{self, DampingForm, DampingState, Mask, ModalModel};
use super::hypotheses::Hypothesis;
use super::model_cache::ModelCache;
use super::DiagnoseError;
use crate::model::{self, ParameterValues};
use crate::updating::fullband::ritz::RitzBasis;

/// Fitted hypothesis (or the current model alone when `value` is `None` and
/// the hypothesis has no parameter).
#[derive(Clone, Debug)]
pub struct HypFit {
    /// Parameter value (SI) and its log.
    pub value: Option<f64>,
    pub log_value: Option<f64>,
    pub damping: DampingState,
    /// Mean squared weighted residual.
    pub cost: f64,
    /// Standard deviation of the parameter (SI) and of the damping log-parameters.
    pub std: Option<f64>,
    pub damping_std_log: Vec<f64>,
    pub on_bound: bool,
    /// The deck's parameters' relative changes fitted along (empty: held).
    pub deck_values: crate::model::ParameterValues,
}

/// Folds of the blocked cross-validation: (train, validate) masks.
pub fn folds(data: &TestData) -> Vec<(Mask, Mask)> {
    let all = Mask::all(data);
    let nl = data.lines_hz.len();
    let blocks = 8usize;
    let mut out = Vec::new();
    for parity in 0..2 {
        let lines: Vec<bool> = (0..nl).map(|l| (l * blocks / nl) % 2 == parity).collect();
        let train = Mask {
            lines,
            channels: all.channels.clone(),
        };
        let val = train.complement();
        out.push((train, val));
    }
    let nc = data.channels.len();
    let live: Vec<bool> = (0..nc)
        .map(|c| data.weight[c].iter().any(|w| *w > 0.0))
        .collect();
    let (rank, both_live) = channel_ranks(data, &live);
    let enough = if both_live {
        nc >= 4
    } else {
        live.iter().filter(|l| **l).count() >= 4
    };
    if enough {
        for parity in 0..2 {
            let train = Mask {
                lines: all.lines.clone(),
                channels: (0..nc)
                    .map(|c| rank[c] % 2 == parity && (both_live || live[c]))
                    .collect(),
            };
            let val = train.complement();
            out.push((train, val));
        }
    }
    out
}

/// The rank of each channel whose parity picks its channel fold, and
/// whether both sides hold weighted channels by index alone. Channels
/// alternate by index; if one side would hold no weighted line (a plane
/// frame's axial channels, below the noise floor, in every other place),
/// the weighted channels alternate within each direction instead, or
/// among themselves if that still leaves a side empty.
fn channel_ranks(data: &TestData, live: &[bool]) -> (Vec<usize>, bool) {
    let nc = live.len();
    let both_sides = |rank: &[usize]| (0..2).all(|p| (0..nc).any(|c| live[c] && rank[c] % 2 == p));
    let by_index: Vec<usize> = (0..nc).collect();
    if both_sides(&by_index) {
        return (by_index, true);
    }
    let direction = |c: usize| data.channels[c].direction.abs();
    let within: Vec<usize> = (0..nc)
        .map(|c| {
            (0..c)
                .filter(|&b| live[b] && direction(b) == direction(c))
                .count()
        })
        .collect();
    if both_sides(&within) {
        return (within, false);
    }
    let among: Vec<usize> = (0..nc)
        .map(|c| (0..c).filter(|&b| live[b]).count())
        .collect();
    (among, false)
}

/// How the log parameter ln θ of a hypothesis is searched: `grid` evenly
/// spaced points over `bracket` (`None`: the parameter's bounds; always
/// clipped to them), then `golden` golden-section steps around the best.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LogSearch {
    pub bracket: Option<(f64, f64)>,
    pub grid: usize,
    pub golden: usize,
}

impl LogSearch {
    /// No search: for fits without a parameter (the damping alone, or an
    /// extension without a parameter).
    pub const NONE: LogSearch = LogSearch {
        bracket: None,
        grid: 0,
        golden: 0,
    };

    /// `grid` points over the parameter's bounds, then `golden` steps.
    pub fn over_bounds(grid: usize, golden: usize) -> LogSearch {
        LogSearch {
            bracket: None,
            grid,
            golden,
        }
    }
}

/// One fit by [`Engine::fit`].
#[derive(Clone, Copy)]
pub struct FitRequest<'r> {
    /// The extension fitted; `None`: the deck as it is (its damping only).
    pub hypothesis: Option<&'r Hypothesis>,
    /// The deck the extension is applied to.
    pub base: &'r Deck,
    /// Where the damping profile starts.
    pub damping: &'r DampingState,
    /// The lines and channels fitted.
    pub mask: &'r Mask,
    /// How the hypothesis's parameter is searched (ignored without one).
    pub search: LogSearch,
    /// Also compute the standard deviations (one Jacobian more).
    pub with_std: bool,
    /// Levenberg–Marquardt iterations of the damping profile
    /// ([`DAMPING_ITERATIONS`]; fewer while screening).
    pub damping_iterations: usize,
}

impl<'r> FitRequest<'r> {
    /// The damping of `base` alone on `mask`, without standard deviations.
    pub fn damping(base: &'r Deck, damping: &'r DampingState, mask: &'r Mask) -> Self {
        FitRequest {
            hypothesis: None,
            base,
            damping,
            mask,
            search: LogSearch::NONE,
            with_std: false,
            damping_iterations: DAMPING_ITERATIONS,
        }
    }
}

/// Levenberg–Marquardt iterations of a fit's damping profile (screens may
/// ask for fewer).
pub const DAMPING_ITERATIONS: usize = 10;

/// The fitting engine over one test.
pub struct Engine<'a> {
    pub data: &'a TestData,
    pub folds: Vec<(Mask, Mask)>,
    pub all: Mask,
    /// Work so far: model solutions asked for, weighted by size (one unit
    /// per 100 DOFs). A sum, whatever order threads add to it in.
    evaluations: AtomicUsize,
    /// The test's modes by the identification, found when first asked for.
    test_modes: OnceLock<Vec<crate::identification::ColumnMode>>,
    /// The modal models of the decks solved last.
    models: Mutex<ModelCache>,
}

impl<'a> Engine<'a> {
    pub fn new(data: &'a TestData) -> Self {
        Engine {
            data,
            folds: folds(data),
            all: Mask::all(data),
            evaluations: AtomicUsize::new(0),
            test_modes: OnceLock::new(),
            models: Mutex::new(ModelCache::default()),
        }
    }

    /// The test's modes (identified once, on the first call).
    pub fn test_modes(&self) -> &[crate::identification::ColumnMode] {
        self.test_modes
            .get_or_init(|| super::suspension_placement::identified_modes(self.data))
    }

    /// A copy of this engine with a work counter and a model cache of its
    /// own, for a search run beside another: each search's budget, and so
    /// its course, is then what it would be alone.
    pub fn beside(&self) -> Engine<'a> {
        Engine {
            data: self.data,
            folds: self.folds.clone(),
            all: self.all.clone(),
            evaluations: AtomicUsize::new(0),
            test_modes: self.test_modes.clone(),
            models: Mutex::new(ModelCache::default()),
        }
    }

    /// Count `spent` units of the work of `other` (an engine made by
    /// [`Self::beside`]) and its kept models as this one's.
    pub fn absorb(&self, other: Engine, spent: usize) {
        self.spend(spent);
        let kept = other.cache().hits();
        self.cache().hits += kept;
    }

    /// Model solutions asked for again and kept from before.
    pub fn models_kept(&self) -> usize {
        self.cache().hits()
    }

    fn cache(&self) -> std::sync::MutexGuard<'_, ModelCache> {
        // A thread that panicked while holding the lock left a whole cache:
        // every change to it is one call.
        self.models.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// Model-solution units spent so far.
    pub fn spent(&self) -> usize {
        self.evaluations.load(Ordering::Relaxed)
    }

    /// The counter of work spent, for fits that count their own model
    /// solutions.
    pub fn counter(&self) -> &AtomicUsize {
        &self.evaluations
    }

    /// Add `units` to the work spent.
    pub fn spend(&self, units: usize) {
        self.evaluations.fetch_add(units, Ordering::Relaxed);
    }

    /// Count one model solution of a model with `dofs` DOFs: one unit per
    /// 100 DOFs begun.
    pub fn spend_solution(&self, dofs: usize) {
        self.spend(dofs.div_ceil(100).max(1));
    }

    /// The modal model of `deck` (solved, or kept from an earlier call).
    pub fn model(&self, deck: &Deck) -> Result<ModalModel, DiagnoseError> {
        let kept = self.cache().get(deck);
        let mm = match kept {
            Some(mm) => mm,
            None => {
                let mm = fit::modal_model(deck, self.data)?;
                self.cache().keep(deck, &mm);
                mm
            }
        };
        // Work units: one per model solution asked for, more for models
        // above 100 DOFs. A kept model counts as well, so that the budget,
        // and with it the search's course, does not depend on the cache.
        self.spend_solution(mm.dofs);
        Ok(mm)
    }

    /// [`Self::model`], and when `deck` had to be solved, the Ritz basis of
    /// that solution ([`RitzBasis`]) for a Jacobian at this point.
    pub fn model_with_basis(
        &self,
        deck: &Deck,
    ) -> Result<(ModalModel, Option<RitzBasis>), DiagnoseError> {
        let kept = self.cache().get(deck);
        if let Some(mm) = kept {
            self.spend_solution(mm.dofs);
            return Ok((mm, None));
        }
        let fe = model::build(deck, &ParameterValues::new()).map_err(DiagnoseError::Model)?;
        let sol = fit::modal_solution(&fe, self.data)?;
        let basis = RitzBasis::of_solution(&fe, &sol).ok();
        self.cache().keep(deck, &sol.model);
        self.spend_solution(sol.model.dofs);
        Ok((sol.model, basis))
    }

    /// Damping-profiled cost of `req`'s hypothesis at log-parameter `s` (or
    /// with no parameter), the damping profile starting from `damp`.
    fn profile(
        &self,
        req: &FitRequest,
        s: Option<f64>,
        damp: &DampingState,
    ) -> Option<(f64, DampingState, ModalModel)> {
        let deck = match req.hypothesis {
            Some(h) => h.apply(req.base, s.map(f64::exp)),
            None => req.base.clone(),
        };
        let mm = self.model(&deck).ok()?;
        let (d, r) = fit::fit_damping(&mm, damp, self.data, req.mask, req.damping_iterations);
        let c = fit::mean_sq(&r);
        c.is_finite().then_some((c, d, mm))
    }

    /// Fit `req.hypothesis` (or only the damping of `req.base`) on
    /// `req.mask`: the damping profile alone when there is no parameter, else
    /// a grid over the log parameter's bracket refined by golden section.
    pub fn fit(&self, req: &FitRequest) -> Option<HypFit> {
        let Some(spec) = req.hypothesis.and_then(|h| h.param.as_ref()) else {
            return self.fit_damping_only(req);
        };
        let (blo, bhi) = (spec.lo.ln(), spec.hi.ln());
        let (s, cost, d) = self.search_log_parameter(req, blo, bhi)?;
        let span = bhi - blo;
        let on_bound = s - blo < 0.02 * span || bhi - s < 0.02 * span;
        let (std, damping_std_log) = if req.with_std {
            self.joint_std(req, s, &d)
                .unwrap_or((f64::INFINITY, vec![]))
        } else {
            (f64::NAN, vec![])
        };
        Some(HypFit {
            value: Some(s.exp()),
            log_value: Some(s),
            damping: d,
            cost,
            std: Some(std * s.exp()),
            damping_std_log,
            on_bound,
            deck_values: Default::default(),
        })
    }

    /// The fit of a request without a parameter: the damping profile of the
    /// deck (with the extension applied, if any).
    fn fit_damping_only(&self, req: &FitRequest) -> Option<HypFit> {
        let (cost, d, mm) = self.profile(req, None, req.damping)?;
        let damping_std_log = if req.with_std {
            self.damping_std(&mm, &d, req.mask)
        } else {
            vec![]
        };
        Some(HypFit {
            value: None,
            log_value: None,
            damping: d,
            cost,
            std: None,
            damping_std_log,
            on_bound: false,
            deck_values: Default::default(),
        })
    }

    /// The best log parameter in the bracket (within the bounds [blo, bhi]):
    /// `grid` evenly spaced points, then `golden` golden-section steps in the
    /// grid cells either side of the best point. Returns (s, cost, damping).
    fn search_log_parameter(
        &self,
        req: &FitRequest,
        blo: f64,
        bhi: f64,
    ) -> Option<(f64, f64, DampingState)> {
        let (lo, hi) = req
            .search
            .bracket
            .map(|(a, b)| (a.max(blo), b.min(bhi)))
            .unwrap_or((blo, bhi));
        let g = req.search.grid.max(2);
        let mut pts: Vec<(f64, f64, DampingState)> = Vec::new();
        for i in 0..g {
            let s = lo + (hi - lo) * i as f64 / (g - 1) as f64;
            if let Some((c, d, _)) = self.profile(req, Some(s), req.damping) {
                pts.push((s, c, d));
            }
        }
        let ibest = (0..pts.len()).min_by(|&a, &b| pts[a].1.total_cmp(&pts[b].1))?;
        let step = (hi - lo) / (g - 1) as f64;
        let (a, b) = (
            (pts[ibest].0 - step).max(blo),
            (pts[ibest].0 + step).min(bhi),
        );
        Some(self.golden_section(req, a, b, pts[ibest].clone()))
    }

    /// `req.search.golden` golden-section steps on [a, b] from the best
    /// point so far; the damping profile of each point starts from the best
    /// point's damping.
    fn golden_section(
        &self,
        req: &FitRequest,
        mut a: f64,
        mut b: f64,
        mut best: (f64, f64, DampingState),
    ) -> (f64, f64, DampingState) {
        let phi = 0.5 * (5f64.sqrt() - 1.0);
        let mut x1 = b - phi * (b - a);
        let mut x2 = a + phi * (b - a);
        let mut f1 = self.profile(req, Some(x1), &best.2);
        let mut f2 = self.profile(req, Some(x2), &best.2);
        for _ in 0..req.search.golden {
            let c1 = f1.as_ref().map_or(f64::INFINITY, |v| v.0);
            let c2 = f2.as_ref().map_or(f64::INFINITY, |v| v.0);
            if c1 < best.1 {
                best = (
                    x1,
                    c1,
                    f1.as_ref().map(|v| v.1.clone()).unwrap_or(best.2.clone()),
                );
            }
            if c2 < best.1 {
                best = (
                    x2,
                    c2,
                    f2.as_ref().map(|v| v.1.clone()).unwrap_or(best.2.clone()),
                );
            }
            if c1 <= c2 {
                b = x2;
                x2 = x1;
                f2 = f1;
                x1 = b - phi * (b - a);
                f1 = self.profile(req, Some(x1), &best.2);
            } else {
                a = x1;
                x1 = x2;
                f1 = f2;
                x2 = a + phi * (b - a);
                f2 = self.profile(req, Some(x2), &best.2);
            }
        }
        for f in [&f1, &f2] {
            if let Some(v) = f {
                if v.0 < best.1 {
                    best = (if std::ptr::eq(f, &f1) { x1 } else { x2 }, v.0, v.1.clone());
                }
            }
        }
        best
    }

    fn damping_std(&self, mm: &ModalModel, d: &DampingState, mask: &Mask) -> Vec<f64> {
        fit::damping_std(mm, d, self.data, mask)
    }

    /// Standard deviations from the joint Jacobian (log parameter, damping logs).
    fn joint_std(&self, req: &FitRequest, s: f64, d: &DampingState) -> Option<(f64, Vec<f64>)> {
        let (h, base, mask) = (req.hypothesis?, req.base, req.mask);
        let mm = self.model(&h.apply(base, Some(s.exp()))).ok()?;
        let r = fit::residuals(
            &fit::predict(&mm, d.damping(), self.data, mask),
            self.data,
            mask,
        );
        let step = 1e-3;
        let mm2 = self.model(&h.apply(base, Some((s + step).exp()))).ok()?;
        let r2 = fit::residuals(
            &fit::predict(&mm2, d.damping(), self.data, mask),
            self.data,
            mask,
        );
        if r2.len() != r.len() {
            return None;
        }
        let first: Vec<f64> = r2.iter().zip(&r).map(|(a, b)| (a - b) / step).collect();
        let damping = fit::damping_jacobian(&mm, d.form, &d.x, self.data, mask);
        let cols = faer::Mat::from_fn(r.len(), 1 + damping.ncols(), |i, j| match j {
            0 => first[i],
            _ => damping[(i, j - 1)],
        });
        let sd = fit::std_devs(cols.as_ref(), &r);
        Some((sd[0], sd[1..].to_vec()))
    }

    /// Mean validation cost over the folds: refit on each training mask
    /// (around the full-data optimum), predict the held-out mask.
    pub fn validate(&self, hyp: Option<&Hypothesis>, base: &Deck, full: &HypFit) -> f64 {
        self.cross_validate(full.cost, |train| {
            let bracket = full.log_value.map(|s| (s - 0.7, s + 0.7));
            let f = self.fit(&FitRequest {
                hypothesis: hyp,
                search: LogSearch {
                    bracket,
                    grid: 3,
                    golden: 5,
                },
                ..FitRequest::damping(base, &full.damping, train)
            })?;
            let deck = match hyp {
                Some(h) => h.apply(base, f.value),
                None => base.clone(),
            };
            Some((self.model(&deck).ok()?, f.damping.damping()))
        })
    }

    /// Blocked cross-validation: `refit` gives the model and damping fitted
    /// on a training mask; the mean cost of their predictions on the held-out
    /// masks (∞ if a refit fails, `no_folds` if there are no folds).
    /// The folds are refitted in parallel; their costs are summed in fold
    /// order.
    pub fn cross_validate<F>(&self, no_folds: f64, refit: F) -> f64
    where
        F: Fn(&Mask) -> Option<(ModalModel, crate::model::Damping)> + Sync,
    {
        let costs: Vec<Option<f64>> = self
            .folds
            .par_iter()
            .map(|(train, val)| {
                let (mm, damping) = refit(train)?;
                let r = fit::residuals(&fit::predict(&mm, damping, self.data, val), self.data, val);
                Some(fit::mean_sq(&r))
            })
            .collect();
        let mut sum = 0.0;
        for c in costs {
            let Some(c) = c else {
                return f64::INFINITY;
            };
            sum += c;
        }
        if self.folds.is_empty() {
            no_folds
        } else {
            sum / self.folds.len() as f64
        }
    }

    /// Validation cost with the damping held at `d` (no refit).
    pub fn validate_fixed_damping(&self, base: &Deck, d: &DampingState) -> f64 {
        let Ok(mm) = self.model(base) else {
            return f64::INFINITY;
        };
        let mut sum = 0.0;
        for (_, val) in &self.folds {
            sum += fit::mean_sq(&fit::residuals(
                &fit::predict(&mm, d.damping(), self.data, val),
                self.data,
                val,
            ));
        }
        sum / self.folds.len().max(1) as f64
    }

    /// Noise level J0 of all data.
    pub fn noise_level(&self) -> f64 {
        fit::noise_level(self.data, &self.all)
    }
}

/// Acceptance margin on the validation cost: 3 % of it plus 0.1·J0.
pub fn margin(v: f64, j0: f64) -> f64 {
    0.03 * v + 0.1 * j0
}

/// Choose the damping form on `base`: the deck's form (or modal) unless
/// another form lowers the cost by more than the margin.
pub fn choose_damping(
    engine: &Engine,
    base: &Deck,
    deck_form: Option<(DampingForm, Vec<f64>)>,
    zeta0: f64,
) -> Option<(DampingState, Vec<(DampingForm, f64)>)> {
    let w = engine.data.omegas.clone();
    let wc = (w.first()? * w.last()?).sqrt();
    let default_form = deck_form.as_ref().map_or(DampingForm::Modal, |d| d.0);
    let mut results = Vec::new();
    for form in super::hypotheses::damping::FORMS {
        let start = match &deck_form {
            Some((f, x)) if *f == form => x.clone(),
            _ => form.start(zeta0, wc),
        };
        let st = DampingState { form, x: start };
        if let Some(f) = engine.fit(&FitRequest::damping(base, &st, &engine.all)) {
            results.push((form, f.cost, f.damping));
        }
    }
    let j0 = engine.noise_level();
    let def = results.iter().find(|r| r.0 == default_form)?.clone();
    let mut chosen = def.clone();
    for r in &results {
        if r.1 < chosen.1 - margin(def.1, j0) {
            chosen = r.clone();
        }
    }
    Some((chosen.2, results.iter().map(|r| (r.0, r.1)).collect()))
}
