//! Refinement of the selected poles by nonlinear least squares on the LSFD
//! residual (variable projection: the residues and residuals are eliminated
//! for each trial set of poles; Golub & Pereyra, SIAM J. Numer. Anal. 10
//! (1973)).
//!
//! The LSCF poles minimise a linearised error, H·D − N, whose weighting by
//! |D| biases damping when the data are noisy; the minimiser of the true
//! output error Σ_j w_j² |H_j − Ĥ_j|² has no such bias (it is the maximum-
//! likelihood estimate for equal white noise per weighted FRF). Parameters
//! x_r = λ_r / σ_r⁰ with σ_r⁰ = max(−Re λ_r⁰, line spacing), so unit steps are
//! about a half-power half-bandwidth; Levenberg–Marquardt with a forward-
//! difference Jacobian. Poles whose windows (±8 half-bandwidths) overlap
//! are refined together (a close pair is coupled), each group on its own
//! window's lines, one group after the other: small problems, whatever the
//! number of lines. In a window only the group's residues and the residual
//! terms U, L are free; the other poles' FRFs are taken out with residues
//! fitted over the whole band. (With every residue free, a window of 30
//! lines had 30 nearly dependent columns and rounding moved the refined
//! poles by 0.1 %; with the others left to U and L, the tails of near
//! neighbours biased the pole.) The sweep over the windows is repeated with
//! the band's residues refitted at the new poles until no pole moves
//! ([`SETTLED`]), at most [`SWEEPS`] times. A pole that moves more than 1.5
//! units from its LSCF value (it drifted to another mode or into noise)
//! keeps its LSCF value.

use faer::{c64, Mat};
use rayon::prelude::*;

use super::prepare::Prepared;
use super::IdentifyError;
use super::{lsfd, tall};
use crate::solvers::dense::{cholesky_lower, cholesky_solve, product};

const MAX_ITERATIONS: usize = 40;
const WINDOW: f64 = 8.0;
const MAX_LINES: usize = 1000;
/// Lines of the whole-band fit of the residues the windows hold fixed.
const GLOBAL_LINES: usize = 4000;
/// Sweeps over the windows at most, each with the residues refitted at the
/// last sweep's poles (block coordinate descent on the joint problem).
const SWEEPS: usize = 3;
/// A sweep that moves no pole by more than this many half-bandwidths ends
/// the refinement.
const SETTLED: f64 = 1e-10;

pub(super) fn residual_vector(
    data: &Prepared,
    poles: &[c64],
    lines: &[usize],
    b: &Mat<f64>,
) -> Result<Vec<f64>, IdentifyError> {
    let a = lsfd::design(poles, &data.omega, lines, data.kind_order);
    let x = lsfd::solve(&a, b)?;
    let r = b - product(a.as_ref(), x.as_ref());
    let m = data.n_inputs();
    let mut out = Vec::with_capacity(r.nrows() * r.ncols());
    for j in 0..r.ncols() {
        let w = data.weights[j / m];
        out.extend(r.col(j).iter().map(|v| v * w));
    }
    Ok(out)
}

pub(super) fn cost(r: &[f64]) -> f64 {
    r.iter().map(|v| v * v).sum()
}

/// Groups of poles (indices, ascending Im λ) whose windows overlap.
fn groups(poles: &[c64], sigma: &[f64]) -> Vec<Vec<usize>> {
    let mut order: Vec<usize> = (0..poles.len()).collect();
    order.sort_by(|&a, &b| poles[a].im.total_cmp(&poles[b].im));
    let mut out: Vec<Vec<usize>> = Vec::new();
    for k in order {
        match out.last_mut() {
            Some(g)
                if g.iter().any(|&j| {
                    (poles[k].im - poles[j].im).abs() < WINDOW * (sigma[k] + sigma[j]) / 2.0
                }) =>
            {
                g.push(k)
            }
            _ => out.push(vec![k]),
        }
    }
    out
}

/// One LM step loop on the poles `group` of `poles` (scaled by `sigma`),
/// fitting `b` (the data of `lines`, real rows as [`lsfd::rhs`]); returns
/// the refined poles.
pub(super) fn refine_group(
    data: &Prepared,
    poles: &[c64],
    group: &[usize],
    sigma: &[f64],
    lines: &[usize],
    b: &Mat<f64>,
) -> Result<Vec<c64>, IdentifyError> {
    let with = |x: &[f64]| -> Vec<c64> {
        let mut p = poles.to_vec();
        for (q, &r) in group.iter().enumerate() {
            p[r] = c64::new(x[2 * q], x[2 * q + 1]) * sigma[r];
        }
        p
    };
    let mut x: Vec<f64> = group
        .iter()
        .flat_map(|&r| [poles[r].re / sigma[r], poles[r].im / sigma[r]])
        .collect();
    let np = x.len();
    let mut r = residual_vector(data, &with(&x), lines, b)?;
    let mut c = cost(&r);
    let mut mu = 1e-3;
    for _ in 0..MAX_ITERATIONS {
        let h = 1e-6;
        let mut jac = Mat::<f64>::zeros(r.len(), np);
        for q in 0..np {
            let mut xq = x.clone();
            xq[q] += h;
            let rq = residual_vector(data, &with(&xq), lines, b)?;
            for (i, (a, b0)) in rq.iter().zip(&r).enumerate() {
                jac[(i, q)] = (a - b0) / h;
            }
        }
        let jtj = product(jac.transpose(), jac.as_ref());
        let rv = Mat::<f64>::from_fn(r.len(), 1, |i, _| r[i]);
        let g = product(jac.transpose(), rv.as_ref());
        let mut improved = false;
        for _ in 0..8 {
            let mut a = jtj.clone();
            for d in 0..np {
                a[(d, d)] += mu * jtj[(d, d)].max(1e-12);
            }
            let Some(l) = cholesky_lower(a.as_ref()) else {
                mu *= 10.0;
                continue;
            };
            let step = cholesky_solve(l.as_ref(), (-&g).as_ref());
            let xt: Vec<f64> = (0..np).map(|d| x[d] + step[(d, 0)]).collect();
            if xt.chunks(2).any(|p| !(p[0] < 0.0)) {
                mu *= 10.0;
                continue;
            }
            let rt = residual_vector(data, &with(&xt), lines, b)?;
            let ct = cost(&rt);
            if ct < c {
                improved = (c - ct) / c > 1e-10;
                (x, r, c) = (xt, rt, ct);
                mu = (mu / 3.0).max(1e-9);
                break;
            }
            mu *= 4.0;
        }
        if !improved {
            break;
        }
    }
    Ok(with(&x))
}

/// The FRFs of the poles outside `group` with their `global` residues (rows
/// of [`lsfd::design`] order) at `lines`, as real rows of [`lsfd::rhs`].
fn others_part(
    data: &Prepared,
    poles: &[c64],
    global: &Mat<f64>,
    group: &[usize],
    lines: &[usize],
) -> Mat<f64> {
    let others: Vec<usize> = (0..poles.len()).filter(|r| !group.contains(r)).collect();
    let p: Vec<c64> = others.iter().map(|&r| poles[r]).collect();
    let a = lsfd::design(&p, &data.omega, lines, data.kind_order);
    let x = Mat::<f64>::from_fn(2 * others.len(), global.ncols(), |i, j| {
        global[(2 * others[i / 2] + i % 2, j)]
    });
    product(a.subcols(0, 2 * others.len()), x.as_ref())
}

/// The poles after refinement (the input's where refinement fails).
pub fn refine(data: &Prepared, poles0: &[c64]) -> Result<Vec<c64>, IdentifyError> {
    let n = data.n_lines();
    let line = (data.omega[n - 1] - data.omega[0]) / (n - 1).max(1) as f64;
    let sigma: Vec<f64> = poles0.iter().map(|p| (-p.re).max(line)).collect();
    let windows: Vec<(Vec<usize>, Vec<usize>)> = groups(poles0, &sigma)
        .into_iter()
        .filter_map(|group| {
            let lines: Vec<usize> = (0..n)
                .filter(|&k| {
                    group
                        .iter()
                        .any(|&r| (data.omega[k] - poles0[r].im).abs() <= WINDOW * sigma[r])
                })
                .collect();
            // Long records: every k-th line, at most MAX_LINES (still about
            // 60 lines per half-bandwidth).
            let stride = lines.len().div_ceil(MAX_LINES).max(1);
            let lines: Vec<usize> = lines.into_iter().step_by(stride).collect();
            (lines.len() >= 2 * (group.len() + 2)).then_some((group, lines))
        })
        .collect();
    let mut poles = poles0.to_vec();
    for _ in 0..SWEEPS {
        let global = band_residues(data, &poles)?;
        // The windows of a sweep depend only on the sweep's start: refined
        // on all cores, applied in order.
        let refined: Vec<Vec<c64>> = windows
            .par_iter()
            .map(|(group, lines)| {
                let b = lsfd::rhs(data, lines) - others_part(data, &poles, &global, group, lines);
                let local: Vec<c64> = group.iter().map(|&r| poles[r]).collect();
                let local_sigma: Vec<f64> = group.iter().map(|&r| sigma[r]).collect();
                let at: Vec<usize> = (0..group.len()).collect();
                refine_group(data, &local, &at, &local_sigma, lines, &b)
            })
            .collect::<Result<_, _>>()?;
        let mut next = poles.clone();
        for ((group, _), refined) in windows.iter().zip(&refined) {
            for (k, &r) in group.iter().enumerate() {
                if (refined[k] - poles0[r]).norm() <= 1.5 * sigma[r] {
                    next[r] = refined[k];
                }
            }
        }
        let moved = (0..poles.len())
            .map(|r| (next[r] - poles[r]).norm() / sigma[r])
            .fold(0.0, f64::max);
        poles = next;
        if moved < SETTLED {
            break;
        }
    }
    Ok(poles)
}

/// The residues of every pole (and U, L) fitted over the band, every k-th
/// line, at most [`GLOBAL_LINES`] (rows of [`lsfd::design`]).
fn band_residues(data: &Prepared, poles: &[c64]) -> Result<Mat<f64>, IdentifyError> {
    let n = data.n_lines();
    let all: Vec<usize> = (0..n).step_by(n.div_ceil(GLOBAL_LINES).max(1)).collect();
    Ok(tall::fit_lines(data, poles, &all, false)?.x)
}
