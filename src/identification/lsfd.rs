//! Residues by least squares in the frequency domain (LSFD) with the poles
//! fixed, plus an upper and a lower residual per FRF.
//!
//! FRF j of kind order n (receptance 0, mobility 1, accelerance 2), s = iω:
//!
//!   H_j(ω) ≈ sⁿ [ Σ_r ( A_jr/(s − λ_r) + Ā_jr/(s − λ̄_r) ) + U_j + L_j/s² ],
//!
//! A_jr complex (receptance residue, m/N/s), U_j (m/N) and L_j (m/N·rad²/s²)
//! real: the modes above and below the band. With A = a + ib the model is
//! linear and real in (a, b, U, L); the real and imaginary parts of every line
//! are the rows of one design matrix shared by all FRFs (the poles are
//! common), so one factorisation solves every FRF: a thin SVD on a window
//! of lines ([`solve`]), the normal equations over the whole band
//! ([`super::tall`]).

use faer::{c64, Mat};

use crate::solvers::dense::{product, thin_svd};

use super::prepare::Prepared;
use super::select::{Picked, SelectOptions};
use super::tall::{fit_lines, LineFit};
use super::{refine, split, IdentifyError};

/// Upper and lower residual of one FRF (receptance terms).
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct Residual {
    /// U (m/N).
    pub upper: f64,
    /// L (m/N·rad²/s²), the term L/s² = −L/ω².
    pub lower: f64,
}

/// One fitted mode.
#[derive(Clone, Debug, PartialEq)]
pub struct FitMode {
    pub pole: c64,
    /// Per FRF (o, i) at o·m + i.
    pub residues: Vec<c64>,
    pub stable_orders: usize,
    /// Indices of its cluster's poles in the diagram.
    pub cluster: Vec<usize>,
    pub significance: f64,
}

/// The fit of the selected modes.
#[derive(Clone, Debug, PartialEq)]
pub struct Fit {
    pub modes: Vec<FitMode>,
    pub residuals: Vec<Residual>,
    /// RMS of the weighted residual ÷ RMS of the weighted data.
    pub relative_residual: f64,
}

fn s_pow(s: c64, n: i32) -> c64 {
    let mut v = c64::new(1.0, 0.0);
    for _ in 0..n.unsigned_abs() {
        v *= s;
    }
    if n < 0 {
        v.inv()
    } else {
        v
    }
}

/// The 2R + 2 complex basis functions at ω: (a, b) per pole, then U, L.
pub(super) fn basis(poles: &[c64], omega: f64, n: i32, out: &mut Vec<c64>) {
    out.clear();
    let s = c64::new(0.0, omega);
    let sn = s_pow(s, n);
    let i = c64::new(0.0, 1.0);
    for lam in poles {
        let (p, q) = ((s - lam).inv(), (s - lam.conj()).inv());
        out.push(sn * (p + q));
        out.push(sn * i * (p - q));
    }
    out.push(sn);
    out.push(sn / (s * s));
}

/// The real design matrix (rows Re, Im of each line in `lines`).
pub fn design(poles: &[c64], omega: &[f64], lines: &[usize], n: i32) -> Mat<f64> {
    let cols = 2 * poles.len() + 2;
    let mut a = Mat::<f64>::zeros(2 * lines.len(), cols);
    let mut b = Vec::with_capacity(cols);
    for (row, &k) in lines.iter().enumerate() {
        basis(poles, omega[k], n, &mut b);
        for (c, v) in b.iter().enumerate() {
            a[(2 * row, c)] = v.re;
            a[(2 * row + 1, c)] = v.im;
        }
    }
    a
}

/// The data of `lines` as real right-hand sides, one column per FRF.
pub fn rhs(data: &Prepared, lines: &[usize]) -> Mat<f64> {
    Mat::<f64>::from_fn(2 * lines.len(), data.h.len(), |r, j| {
        let v = data.h[j][lines[r / 2]];
        if r % 2 == 0 {
            v.re
        } else {
            v.im
        }
    })
}

/// Least-squares coefficients of every column of `b`: minimum-norm solution
/// by a thin SVD of `a` (columns scaled to unit norm), singular values below
/// 10⁻¹² of the largest dropped, so that nearly dependent columns (residual
/// terms over a narrow window) do not blow the residues up.
pub fn solve(a: &Mat<f64>, b: &Mat<f64>) -> Result<Mat<f64>, IdentifyError> {
    let scale: Vec<f64> = a
        .col_iter()
        .map(|c| {
            let n = c.norm_l2();
            if n > 0.0 {
                1.0 / n
            } else {
                1.0
            }
        })
        .collect();
    let an = Mat::<f64>::from_fn(a.nrows(), a.ncols(), |r, c| a[(r, c)] * scale[c]);
    let svd = thin_svd(an.as_ref()).map_err(|_| IdentifyError::Singular("LSFD"))?;
    let sv = &svd.s;
    let top = sv.iter().copied().fold(0.0, f64::max);
    let mut y = product(svd.u.transpose(), b.as_ref());
    for i in 0..y.nrows() {
        let si = sv[i];
        let inv = if si > 1e-12 * top { 1.0 / si } else { 0.0 };
        for j in 0..y.ncols() {
            y[(i, j)] *= inv;
        }
    }
    let mut x = product(svd.v.as_ref(), y.as_ref());
    for (c, s) in scale.iter().enumerate() {
        for j in 0..x.ncols() {
            x[(c, j)] *= s;
        }
    }
    if x.col_iter().all(|c| c.iter().all(|v| v.is_finite())) {
        Ok(x)
    } else {
        Err(IdentifyError::Singular("LSFD"))
    }
}

/// The fitted FRF at ω (the test's kind).
pub fn evaluate(poles: &[c64], residues: &[c64], res: &Residual, omega: f64, n: i32) -> c64 {
    let s = c64::new(0.0, omega);
    let mut v = c64::new(res.upper, 0.0) + res.lower / (s * s);
    for (lam, a) in poles.iter().zip(residues) {
        v += a / (s - lam) + a.conj() / (s - lam.conj());
    }
    v * s_pow(s, n)
}

struct Solved {
    x: Mat<f64>,
    significance: Vec<f64>,
    relative: f64,
}

/// Significance of mode r: its largest weighted contribution over FRFs and
/// lines ÷ the RMS of the weighted fit residual on the lines within
/// `WINDOW` half-bandwidths of it (where a spurious pole would fit noise,
/// and where a missing neighbour does not count against it).
const WINDOW: f64 = 8.0;

fn fit_once(data: &Prepared, poles: &[c64]) -> Result<Solved, IdentifyError> {
    let all: Vec<usize> = (0..data.n_lines()).collect();
    let LineFit { x, per_line } = fit_lines(data, poles, &all, true)?;
    let cost: f64 = per_line.iter().sum();
    let m = data.n_inputs();
    let nj = data.h.len() as f64;
    let total: f64 = data
        .h
        .iter()
        .enumerate()
        .map(|(j, h)| data.weights[j / m].powi(2) * h.iter().map(|v| v.norm_sqr()).sum::<f64>())
        .sum();
    let n = data.n_lines();
    let line = (data.omega[n - 1] - data.omega[0]) / (n - 1).max(1) as f64;
    let significance = (0..poles.len())
        .map(|r| {
            // The contribution peaks within its window: only those lines.
            let lam = poles[r];
            let half = WINDOW * (-lam.re).max(line);
            let near: Vec<usize> = (0..n)
                .filter(|&k| (data.omega[k] - lam.im).abs() <= half)
                .collect();
            let residues: Vec<(c64, f64)> = (0..data.h.len())
                .map(|j| {
                    (
                        c64::new(x[(2 * r, j)], x[(2 * r + 1, j)]),
                        data.weights[j / m],
                    )
                })
                .collect();
            // max over FRFs and lines of w_j |sⁿ (A_j/(s−λ) + Ā_j/(s−λ̄))|.
            let mut peak2: f64 = 0.0;
            for &k in &near {
                let s = c64::new(0.0, data.omega[k]);
                let (p, q) = ((s - lam).inv(), (s - lam.conj()).inv());
                let sn = s_pow(s, data.kind_order);
                for &(a, w) in &residues {
                    peak2 = peak2.max(w * w * (sn * (a * p + a.conj() * q)).norm_sqr());
                }
            }
            let peak = peak2.sqrt();
            let ss: f64 = near.iter().map(|&k| per_line[k]).sum();
            let rms = (ss / (near.len().max(1) as f64 * nj)).sqrt();
            peak / rms.max(f64::MIN_POSITIVE)
        })
        .collect();
    Ok(Solved {
        x,
        significance,
        relative: (cost / total.max(f64::MIN_POSITIVE)).sqrt(),
    })
}

/// The share of [`SelectOptions::min_significance`] a pole needs at its
/// LSCF value to be refined: refinement raises a true mode's significance
/// (a merged pair on the GARTEUR fixture: 9.8 → 397 once split), never a
/// computational pole's from ~0.1 to the threshold.
const PRESCREEN: f64 = 0.25;

/// Modes under this share of [`SelectOptions::min_significance`] are
/// dropped together; between it and the threshold, one at a time.
const CLEARLY_BELOW: f64 = 0.5;

/// Which modes stay after one step of backward elimination (`None`: all
/// reach `threshold`). Every mode clearly below it goes at once; else only
/// the weakest. A mode near the threshold is judged alone and last because
/// its significance depends on which neighbours stay: a pole fitting noise
/// in its window takes up part of the residual it is measured against, and
/// with all the weak ones dropped together a real mode just under the
/// threshold took its neighbour down with it (a real record's 22.2 Hz mode
/// fell from 7.1 to 3.9 when seventeen noise poles and the 41.9 Hz mode, at
/// 3.99, left at once).
fn eliminate(significance: &[f64], threshold: f64) -> Option<Vec<bool>> {
    let weakest = significance
        .iter()
        .enumerate()
        .min_by(|a, b| a.1.total_cmp(b.1))
        .filter(|(_, s)| **s < threshold)?
        .0;
    let clear: Vec<bool> = significance
        .iter()
        .map(|s| *s >= CLEARLY_BELOW * threshold)
        .collect();
    if clear.iter().any(|k| !k) {
        return Some(clear);
    }
    Some((0..significance.len()).map(|r| r != weakest).collect())
}

fn retain_by<T>(items: &mut Vec<T>, keep: &[bool]) {
    debug_assert_eq!(items.len(), keep.len());
    let mut k = keep.iter();
    items.retain(|_| *k.next().unwrap_or(&true));
}

/// Fits the picked poles (refined first when `refine`, merged ones split),
/// dropping modes below `opts.min_significance` ([`eliminate`]) and
/// refitting until none is.
pub fn fit_modes(
    data: &Prepared,
    picked: &[Picked],
    refine_poles: bool,
    opts: &SelectOptions,
) -> Result<Fit, IdentifyError> {
    let mut poles: Vec<c64> = picked.iter().map(|p| p.pole).collect();
    let mut orders: Vec<usize> = picked.iter().map(|p| p.stable_orders).collect();
    let mut clusters: Vec<Vec<usize>> = picked.iter().map(|p| p.cluster.clone()).collect();
    if refine_poles && !poles.is_empty() {
        // Poles whose contribution is far below the noise at their LSCF
        // values (computational poles fitting noise: significance ~0.1
        // where a mode has tens to hundreds) go before the refinement,
        // which would spend its iterations on their flat cost and couple
        // the windows of the true modes around them.
        let screened = fit_once(data, &poles)?;
        let keep: Vec<bool> = screened
            .significance
            .iter()
            .map(|s| *s >= opts.min_significance * PRESCREEN)
            .collect();
        retain_by(&mut poles, &keep);
        retain_by(&mut orders, &keep);
        retain_by(&mut clusters, &keep);
    }
    if refine_poles && !poles.is_empty() {
        poles = refine::refine(data, &poles)?;
        // Poles split off a merged one stand in no order of the diagram.
        let split = split::split_merged(data, &poles)?;
        orders.resize(split.len(), 0);
        clusters.resize(split.len(), Vec::new());
        poles = split;
    }
    loop {
        let solved = fit_once(data, &poles)?;
        if let Some(keep) = eliminate(&solved.significance, opts.min_significance) {
            retain_by(&mut poles, &keep);
            retain_by(&mut orders, &keep);
            retain_by(&mut clusters, &keep);
            continue;
        }
        let nr = poles.len();
        let x = &solved.x;
        let modes = (0..nr)
            .map(|r| FitMode {
                pole: poles[r],
                residues: (0..x.ncols())
                    .map(|j| c64::new(x[(2 * r, j)], x[(2 * r + 1, j)]))
                    .collect(),
                stable_orders: orders[r],
                cluster: clusters[r].clone(),
                significance: solved.significance[r],
            })
            .collect();
        let residuals = (0..x.ncols())
            .map(|j| Residual {
                upper: x[(2 * nr, j)],
                lower: x[(2 * nr + 1, j)],
            })
            .collect();
        return Ok(Fit {
            modes,
            residuals,
            relative_residual: solved.relative,
        });
    }
}
