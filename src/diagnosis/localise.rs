//! Localisation by sensitivity screening (forward selection): each candidate
//! extension is probed once at a typical value; with r₀ the current weighted
//! residual and Δr the change the probe makes, moving along Δr can lower
//! |r|² by at most (r₀·Δr)²/|Δr|² (only for r₀·Δr < 0, a physical step).
//! That fraction of |r₀|² is the candidate's score; node scores (the best
//! candidate at each node) say where the model disagrees. Candidates that
//! keep the deck's DOFs are probed on one Ritz basis of the deck
//! ([`RitzProbe`]), the others solved in full.
//!
//! The deck's own parameters compete on equal terms: their residual
//! changes span a subspace P, and r₀ and every Δr are projected onto its
//! orthogonal complement before scoring. A candidate then scores by what it
//! explains that no change of the deck's parameters explains (a parameter
//! error no longer lifts the extension that mimics it), and the score is
//! the fraction of the projected |r₀|².

use frfup_parsers::deck::Deck;
use rayon::prelude::*;

use super::data::TestData;
use super::fit::{self, DampingState, Mask, ModalModel};
use super::hypotheses::Hypothesis;
use crate::model::{self, ParameterValues};
use crate::updating::fullband::ritz::RitzBasis;

/// Residual change of one probed candidate.
pub struct Probe {
    pub index: usize,
    pub score: f64,
    pub delta: Vec<f64>,
}

/// Relative change p̄ of a deck parameter at which its residual change is
/// probed (5 %: inside the linear range of a stiffness or a density).
const PARAMETER_PROBE: f64 = 0.05;

/// Orthonormal basis of the residual changes of `base`'s own parameters
/// (each probed at p̄ = 5 %; directions within 1e-6 of the span of the
/// earlier ones dropped); empty when the deck has none.
pub fn parameter_directions(
    base: &Deck,
    r0: &[f64],
    damping: &DampingState,
    data: &TestData,
) -> Vec<Vec<f64>> {
    let mask = Mask::all(data);
    let mut basis: Vec<Vec<f64>> = Vec::new();
    for p in &base.params {
        let values = [(p.name.clone(), PARAMETER_PROBE)].into_iter().collect();
        let deck = crate::model::updated_deck(base, &values);
        let Ok(mm) = fit::modal_model(&deck, data) else {
            continue;
        };
        let mut d = residual_change(&mm, damping, data, &mask, r0);
        let n_before = dot(&d, &d);
        if d.is_empty() || !(n_before > 0.0) {
            continue;
        }
        for q in &basis {
            let a = dot(&d, q);
            d.iter_mut().zip(q).for_each(|(x, y)| *x -= a * y);
        }
        let n = dot(&d, &d);
        if n > 1e-6 * n_before {
            let s = n.sqrt();
            d.iter_mut().for_each(|x| *x /= s);
            basis.push(d);
        }
    }
    basis
}

/// `v` with its components along the orthonormal `basis` removed.
pub fn project_out(v: &[f64], basis: &[Vec<f64>]) -> Vec<f64> {
    let mut out = v.to_vec();
    for q in basis.iter().filter(|q| q.len() == v.len()) {
        let a = dot(&out, q);
        out.iter_mut().zip(q).for_each(|(x, y)| *x -= a * y);
    }
    out
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// Probe every candidate that has a free parameter; candidates whose deck
/// does not build get score 0. `r0` is the current residual; it and each
/// Δr are projected off `basis` (the deck parameters' directions, see
/// [`parameter_directions`]; empty: no projection) before scoring, and the
/// probes keep the projected Δr.
pub fn probe(
    base: &Deck,
    r0: &[f64],
    basis: &[Vec<f64>],
    damping: &DampingState,
    data: &TestData,
    candidates: &[Hypothesis],
) -> Vec<Probe> {
    let mask = Mask::all(data);
    let r0p = project_out(r0, basis);
    let n0: f64 = dot(&r0p, &r0p).max(1e-300);
    let ritz = RitzProbe::of(base, damping, data, &mask);
    candidates
        .par_iter()
        .enumerate()
        .map(|(index, h)| {
            let value = h.param.as_ref().map(|p| p.probe);
            let deck = h.apply(base, value);
            let fe = model::build(&deck, &ParameterValues::new()).ok();
            let on_basis = ritz.as_ref().zip(fe.as_ref()).and_then(|(rp, fe)| {
                let mm = rp.basis.modal_model(fe)?;
                Some(residual_change(&mm, damping, data, &mask, &rp.r0))
            });
            let delta =
                on_basis.unwrap_or_else(|| match fe.map(|fe| fit::modal_solution(&fe, data)) {
                    Some(Ok(sol)) => residual_change(&sol.model, damping, data, &mask, r0),
                    _ => Vec::new(),
                });
            let delta = project_out(&delta, basis);
            let score = reduction(&r0p, &delta) / n0;
            Probe {
                index,
                score,
                delta,
            }
        })
        .collect()
}

/// The base deck's Ritz basis ([`RitzBasis`]) and its residual on that
/// basis: a candidate that keeps the base's DOFs (a mass, a grounded spring
/// on a free DOF) is probed on the basis, its Δr taken against the base's
/// own residual there, like with like. One eigen solution for all of them
/// instead of one each; a candidate with other DOFs (a joint's new node, a
/// support unfixed) is solved in full.
struct RitzProbe {
    basis: RitzBasis,
    r0: Vec<f64>,
}

impl RitzProbe {
    fn of(base: &Deck, damping: &DampingState, data: &TestData, mask: &Mask) -> Option<Self> {
        let fe = model::build(base, &ParameterValues::new()).ok()?;
        let basis = RitzBasis::at(&fe, data).ok()?;
        let mm = basis.modal_model(&fe)?;
        let pred = fit::predict(&mm, damping.damping(), data, mask);
        let r0 = fit::residuals(&pred, data, mask);
        Some(RitzProbe { basis, r0 })
    }
}

fn residual_change(
    mm: &ModalModel,
    damping: &DampingState,
    data: &TestData,
    mask: &Mask,
    r0: &[f64],
) -> Vec<f64> {
    let pred = fit::predict(mm, damping.damping(), data, mask);
    let r = fit::residuals(&pred, data, mask);
    if r.len() != r0.len() {
        return Vec::new();
    }
    r.iter().zip(r0).map(|(a, b)| a - b).collect()
}

/// max over a > 0 of |r₀|² − |r₀ + aΔ|².
pub fn reduction(r0: &[f64], delta: &[f64]) -> f64 {
    if delta.len() != r0.len() || delta.is_empty() {
        return 0.0;
    }
    let dd: f64 = delta.iter().map(|v| v * v).sum();
    let rd: f64 = r0.iter().zip(delta).map(|(a, b)| a * b).sum();
    if dd > 0.0 && rd < 0.0 {
        rd * rd / dd
    } else {
        0.0
    }
}

/// Forward selection of a set of same-valued extensions (e.g. suspension
/// springs): add the probe whose Δr, summed with those chosen, lowers |r|²
/// most; stop after `max` or when the gain is below 2 % of |r₀|².
pub fn forward_select(r0: &[f64], probes: &[&Probe], max: usize) -> Vec<usize> {
    let n0: f64 = r0.iter().map(|v| v * v).sum::<f64>().max(1e-300);
    let mut chosen: Vec<usize> = Vec::new();
    let mut sum: Vec<f64> = vec![0.0; r0.len()];
    let mut best_red = 0.0;
    while chosen.len() < max {
        let mut best: Option<(usize, f64)> = None;
        for (i, p) in probes.iter().enumerate() {
            if chosen.contains(&i) || p.delta.len() != r0.len() {
                continue;
            }
            let trial: Vec<f64> = sum.iter().zip(&p.delta).map(|(a, b)| a + b).collect();
            let red = reduction(r0, &trial);
            if best.is_none_or(|(_, b)| red > b) {
                best = Some((i, red));
            }
        }
        match best {
            Some((i, red)) if red > best_red + 0.02 * n0 => {
                for (s, d) in sum.iter_mut().zip(&probes[i].delta) {
                    *s += d;
                }
                chosen.push(i);
                best_red = red;
            }
            _ => break,
        }
    }
    chosen
}
