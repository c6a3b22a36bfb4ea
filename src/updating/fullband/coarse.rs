//! The coarse stage of the full-band estimate: when the model's resonances
//! are on average more than [`COARSE_THRESHOLD`] from the test's (over the
//! test resonances that pair with a model mode: one with no partner within
//! the cap, e.g. a noise peak of a log-spaced axis at low frequency, says
//! nothing about how far the model is), fit p̄ to
//! the resonance frequencies alone ([`fit::frequency_residuals`], smooth
//! where the FRF misfit is flat or rough), with the priors (a parameter
//! without one is held near the start by a prior of sd [`COARSE_STAY`]),
//! then refit the damping; kept only if the full-band cost falls.

use faer::Mat;
use frfup_parsers::deck::Deck;

use super::data::TestData;
use super::fit::{self, DampingState, Mask, ModalSolution};
use super::lm::{self, LeastSquares, LmSettings};
use super::prior::ParameterPrior;
use crate::model::{self, FeModel, ParameterValues};
use crate::updating::sensitivity::ModalSensitivities;

/// Mean |ln(f_model/f_test)| above which the coarse frequency stage runs.
const COARSE_THRESHOLD: f64 = 0.02;
/// Scale of a prior row: 1 % of frequency per prior sd.
const COARSE_PRIOR: f64 = 0.01;
/// Prior sd, centred on the start, of a parameter without a prior of its
/// own: the resonance frequencies see few combinations of the parameters,
/// and a fit to them alone moves the others anywhere along the directions
/// they do not see (benchmark case 125 of seed 1: three section properties
/// a frequency fit takes to −63 %, +112 %, +199 % from every start, a
/// minimum the full-band fit cannot leave). Held near the start, they are
/// left to the full-band fit, which sees the shapes as well.
const COARSE_STAY: f64 = 0.3;
/// Levenberg–Marquardt iterations of the stage.
const COARSE_ITERATIONS: usize = 20;

/// Frequency residuals ln(ω_model/ω_test) per resonance, then the priors.
struct Frequencies<'a> {
    deck: &'a Deck,
    data: &'a TestData,
    names: &'a [String],
    priors: &'a [ParameterPrior],
    cache: Option<(Vec<f64>, FeModel, ModalSolution)>,
    solutions: usize,
}

impl Frequencies<'_> {
    fn solution(&mut self, p: &[f64]) -> Option<&(Vec<f64>, FeModel, ModalSolution)> {
        if self.cache.as_ref().is_none_or(|c| c.0.as_slice() != p) {
            let values: ParameterValues =
                self.names.iter().cloned().zip(p.iter().copied()).collect();
            self.solutions += 1;
            let d = model::updated_deck(self.deck, &values);
            let fe = model::build(&d, &ParameterValues::new()).ok()?;
            let sol = fit::modal_solution(&fe, self.data).ok()?;
            self.cache = Some((p.to_vec(), fe, sol));
        }
        self.cache.as_ref()
    }
}

impl LeastSquares for Frequencies<'_> {
    fn residuals(&mut self, p: &[f64]) -> Option<Vec<f64>> {
        let data = self.data;
        let mut r = fit::frequency_residuals(&self.solution(p)?.2.model, data);
        ParameterPrior::push_rows(self.priors, p, COARSE_PRIOR, &mut r);
        Some(r)
    }

    /// ∂ln ω_r = ∂λ_r / 2λ_r with ∂λ_r = φ_rᵀ(∂K − λ_r∂M)φ_r, times the chain
    /// factor 1/(1 + p̄).
    fn jacobian(&mut self, p: &[f64], r: &[f64], _free: &[bool]) -> Option<Mat<f64>> {
        let data = self.data;
        let (_, fe, sol) = self.solution(p)?;
        let align = fit::frequency_alignment(&sol.model, data);
        let paired: Vec<usize> = align.iter().filter_map(|a| a.1).collect();
        let sens = ModalSensitivities::project(&fe.parameters, sol.modes.shapes.as_ref(), &paired);
        let mut jac = Mat::<f64>::zeros(r.len(), p.len());
        for (j, &pj) in p.iter().enumerate() {
            let chain = 1.0 / (1.0 + pj);
            let mut k = 0;
            for (row, a) in align.iter().enumerate() {
                if let Some(mode) = a.1 {
                    let lam = sol.modes.omega2[mode];
                    let dl = sens.dk[j][(k, k)] - lam * sens.dm[j][(k, k)];
                    if lam > 0.0 {
                        jac[(row, j)] = chain * dl / (2.0 * lam);
                    }
                    k += 1;
                }
            }
        }
        ParameterPrior::fill_rows(self.priors, COARSE_PRIOR, &mut jac, align.len());
        Some(jac)
    }
}

/// Run the stage from `p` with damping `damp`; returns whether it was kept
/// (then `p` and `damp` are replaced) and the model solutions spent.
pub fn coarse_frequencies(
    deck: &Deck,
    data: &TestData,
    names: &[String],
    priors: &[ParameterPrior],
    p: &mut Vec<f64>,
    damp: &mut DampingState,
) -> (bool, usize) {
    let held: Vec<ParameterPrior> = priors
        .iter()
        .zip(p.iter())
        .map(|(pr, &start)| match pr.sd {
            Some(_) => *pr,
            None => ParameterPrior {
                sd: Some(COARSE_STAY),
                centre: start,
                ..*pr
            },
        })
        .collect();
    let mut problem = Frequencies {
        deck,
        data,
        names,
        priors: &held,
        cache: None,
        solutions: 0,
    };
    let kept = run(&mut problem, p, damp);
    (kept, problem.solutions)
}

fn run(problem: &mut Frequencies, p: &mut Vec<f64>, damp: &mut DampingState) -> bool {
    let (data, mask) = (problem.data, Mask::all(problem.data));
    let Some((_, _, sol)) = problem.solution(p) else {
        return false;
    };
    let aligned = fit::frequency_alignment(&sol.model, data);
    let paired: Vec<f64> = aligned
        .iter()
        .filter(|(_, mode)| mode.is_some())
        .map(|(r, _)| r.abs())
        .collect();
    let mean = if paired.is_empty() {
        f64::INFINITY
    } else {
        paired.iter().sum::<f64>() / paired.len() as f64
    };
    if aligned.is_empty() || mean <= COARSE_THRESHOLD {
        return false;
    }
    let pred = fit::predict(&sol.model, damp.damping(), data, &mask);
    let before = fit::mean_sq(&fit::residuals(&pred, data, &mask));
    let lo: Vec<f64> = problem.priors.iter().map(|q| q.min).collect();
    let hi: Vec<f64> = problem.priors.iter().map(|q| q.max).collect();
    let settings = LmSettings {
        max_iter: COARSE_ITERATIONS,
        negligible: 1e-10,
        ..LmSettings::default()
    };
    let Some(out) = lm::lm(problem, p, &lo, &hi, settings) else {
        return false;
    };
    let Some((_, _, sol)) = problem.solution(&out.x) else {
        return false;
    };
    let (d, r) = fit::fit_damping(&sol.model, damp, data, &mask, 20);
    if fit::mean_sq(&r) < before {
        *p = out.x;
        *damp = d;
        true
    } else {
        false
    }
}
