//! Modal identification of the test: natural frequencies, damping ratios and
//! real mode shapes at the sensors, fitted to single-reference FRFs. Used by
//! the diagnosis's channel checks only; the update takes its resonances from
//! [`crate::identification`] (the switch of the channel checks is measured
//! in docs/benchmarks.md).
//!
//! Peak picking on a summed indicator (see [`super::frequencies`]) misses weak
//! modes and merges close ones (the GARTEUR wing-torsion pair, 0.65 Hz apart
//! with 1 % damping, is one peak). This module fits instead, band by band, a
//! pole–residue model with poles common to all channels ("global" curve
//! fitting), receptance in m/N, ω in rad/s:
//!
//!   H_c(ω) = Σ_r [ A_cr/(iω − λ_r) + Ā_cr/(iω − λ̄_r) ] + U_c + L_c/ω²,
//!   λ_r = ω_r (−ζ_r + i√(1 − ζ_r²)),
//!
//! U_c and L_c (real) standing for the modes above and below the band. For
//! given poles the residues are linear: variable projection leaves the 2 R
//! pole parameters (ln f_r, ln ζ_r) to a Levenberg–Marquardt search on the
//! projected residual. Channel c is weighted by ω_band² / rms(accelerance_c):
//! test noise is a fraction of each channel's accelerance RMS, so every
//! channel's noise then weighs alike.
//!
//! Candidates are the local maxima of the indicator; each gets a band of
//! ±max(8 lines, 6 % of f) with every candidate inside it as a starting pole,
//! and keeps the poles in the band's middle half. A band whose residual a
//! further pole (placed at the largest residual) halves gets that pole: two
//! modes under one peak. A pole is kept when its largest contribution on a
//! measured line stands `significance` times above the band's residual RMS
//! per line and its half-power bandwidth lies between a fifth of a line and
//! half the band.
//!
//! Shapes: for real normal modes A_cr = φ_c φ_ref / (2iω_d m_r); the residues
//! are rotated by the phase that makes them most nearly real, and that real
//! part is the shape at the sensors (scaled to unit largest magnitude).

use faer::c64;

use faer::Mat;

use super::fullband::lm::{lm, LeastSquares, LmSettings};
use crate::identification::ColumnMode;

const TWO_PI: f64 = 2.0 * std::f64::consts::PI;
/// Indicator prominence of a candidate that starts a pole in its
/// neighbours' bands too.
const STRONG_CANDIDATE: f64 = 1.25;

/// Settings of the identification.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct IdentifyOptions {
    /// Minimum prominence of an indicator maximum to be a candidate (≥ 1).
    pub candidate_prominence: f64,
    /// Peak modal contribution ÷ residual RMS for a pole to be kept.
    pub significance: f64,
    /// Poles that may be added to a band beyond its candidates.
    pub max_extra_poles: usize,
}

impl Default for IdentifyOptions {
    fn default() -> Self {
        IdentifyOptions {
            candidate_prominence: 1.02,
            significance: 8.0,
            max_extra_poles: 2,
        }
    }
}

/// Modes of single-reference FRFs: `receptance[c][line]` (m/N) on the
/// ascending `lines_hz`; `indicator` per line (larger at resonances). Sorted
/// by frequency.
pub fn identify_modes(
    lines_hz: &[f64],
    receptance: &[Vec<c64>],
    indicator: &[f64],
    opts: &IdentifyOptions,
) -> Vec<ColumnMode> {
    let n = lines_hz.len();
    if n < 8 || receptance.is_empty() {
        return Vec::new();
    }
    let df = super::frequencies::line_spacing(lines_hz);
    if !(df > 0.0) {
        return Vec::new();
    }
    // Noise scale per channel: rms of the accelerance ω²|H| over the band.
    let acc_rms: Vec<f64> = receptance
        .iter()
        .map(|h| {
            let s: f64 = h
                .iter()
                .zip(lines_hz)
                .map(|(v, &f)| {
                    let w2 = (TWO_PI * f).powi(2);
                    let a = v.norm() * w2;
                    if a.is_finite() {
                        a * a
                    } else {
                        0.0
                    }
                })
                .sum();
            (s / n as f64).sqrt()
        })
        .collect();

    let candidates = candidates(lines_hz, indicator, opts.candidate_prominence);
    let start = first_positive(lines_hz) + 1;
    let mut modes: Vec<ColumnMode> = Vec::new();
    let mut covered_hi = f64::NEG_INFINITY;
    for &(k, _) in &candidates {
        // The band: ±max(8 lines, 6 % of f) around the candidate; starting
        // poles are the candidate and the clear peaks (prominence ≥
        // STRONG_CANDIDATE) inside the band; the poles kept are those in the
        // band's middle half, whose candidates need no band of their own.
        let f = lines_hz[k];
        if f <= covered_hi {
            continue;
        }
        let hw = ((0.06 * f / df).ceil() as usize).max(8);
        let lo = k.saturating_sub(hw).max(start);
        let hi = (k + hw).min(n - 1);
        if k < lo || hi <= lo + 4 {
            continue;
        }
        let freqs: Vec<f64> = candidates
            .iter()
            .filter(|&&(j, p)| j >= lo && j <= hi && (j == k || p >= STRONG_CANDIDATE))
            .map(|&(j, _)| lines_hz[j])
            .collect();
        let band = Band::new(lines_hz, receptance, &acc_rms, lo, hi);
        let (keep_lo, keep_hi) = (
            lines_hz[k.saturating_sub(hw / 2).max(lo)] - 0.5 * df,
            lines_hz[(k + hw / 2).min(hi)] + 0.5 * df,
        );
        covered_hi = keep_hi;
        modes.extend(
            band.identify(&freqs, opts, df)
                .into_iter()
                .filter(|m| m.frequency_hz >= keep_lo && m.frequency_hz <= keep_hi),
        );
    }
    modes.sort_by(|a, b| a.frequency_hz.total_cmp(&b.frequency_hz));
    // The same pole from two bands: keep the more significant.
    let mut out: Vec<ColumnMode> = Vec::new();
    for m in modes {
        match out.last_mut() {
            Some(prev) if (m.frequency_hz - prev.frequency_hz).abs() < 0.5 * df => {
                if m.significance > prev.significance {
                    *prev = m;
                }
            }
            _ => out.push(m),
        }
    }
    for m in &mut out {
        m.line = super::frequencies::nearest_line(lines_hz, m.frequency_hz);
    }
    out
}

fn first_positive(lines_hz: &[f64]) -> usize {
    lines_hz.iter().position(|&f| f > 0.0).unwrap_or(0)
}

/// Local maxima of the indicator with prominence ≥ `min_prominence` (above
/// 0 Hz).
fn candidates(lines_hz: &[f64], y: &[f64], min_prominence: f64) -> Vec<(usize, f64)> {
    let n = lines_hz.len().min(y.len());
    let mut out = Vec::new();
    for i in 1..n.saturating_sub(1) {
        if !(y[i] > y[i - 1] && y[i] >= y[i + 1]) || lines_hz[i] <= 0.0 {
            continue;
        }
        let valley = |dir: isize| {
            let mut m = y[i];
            let mut j = i as isize;
            loop {
                j += dir;
                if j < 0 || j as usize >= n || y[j as usize] > y[i] {
                    return m;
                }
                m = m.min(y[j as usize]);
            }
        };
        let base = valley(-1).max(valley(1));
        let prominence = if base > 0.0 {
            y[i] / base
        } else {
            f64::INFINITY
        };
        if prominence >= min_prominence {
            out.push((i, prominence));
        }
    }
    out
}

/// The weighted data of one band: rows are (Re, Im) per line.
struct Band {
    omega: Vec<f64>,
    /// (ω/ω_c)² per line, applied to data and basis alike.
    row_weight: Vec<f64>,
    /// data[c]: 2 × lines values (Re then Im per line), weighted.
    data: Vec<Vec<f64>>,
    weights: Vec<f64>,
    hz: Vec<f64>,
}

/// Pole parameters: (ln f, ln ζ).
type Pole = (f64, f64);

fn pole(p: Pole) -> c64 {
    let w = TWO_PI * p.0.exp();
    let z = p.1.exp().min(0.99);
    c64::new(-z * w, w * (1.0 - z * z).sqrt())
}

/// (ln f_1, ln ζ_1, ln f_2, …) as poles.
fn poles_of(x: &[f64]) -> Vec<Pole> {
    x.chunks(2).map(|c| (c[0], c[1])).collect()
}

/// The projected residual of a band as a least-squares problem in the
/// pole parameters (variable projection: the residues are eliminated).
struct PoleFit<'a> {
    band: &'a Band,
}

impl LeastSquares for PoleFit<'_> {
    fn residuals(&mut self, x: &[f64]) -> Option<Vec<f64>> {
        Some(self.band.residual(&poles_of(x)))
    }

    /// Forward differences with step 1e-6 in the log parameters.
    fn jacobian(&mut self, x: &[f64], r: &[f64], free: &[bool]) -> Option<Mat<f64>> {
        let h = 1e-6;
        let mut jac = Mat::<f64>::zeros(r.len(), x.len());
        for k in (0..x.len()).filter(|&k| free[k]) {
            let mut xp = x.to_vec();
            xp[k] += h;
            let rk = self.band.residual(&poles_of(&xp));
            for (row, (a, b)) in rk.iter().zip(r).enumerate() {
                jac[(row, k)] = (a - b) / h;
            }
        }
        Some(jac)
    }

    fn max_step(&self, i: usize) -> f64 {
        if i % 2 == 0 {
            0.05
        } else {
            1.0
        }
    }
}

impl Band {
    fn new(lines_hz: &[f64], h: &[Vec<c64>], acc_rms: &[f64], lo: usize, hi: usize) -> Band {
        let hz: Vec<f64> = lines_hz[lo..=hi].to_vec();
        let omega: Vec<f64> = hz.iter().map(|f| TWO_PI * f).collect();
        let wc = omega[omega.len() / 2].powi(2);
        // Row weight (ω/ω_c)²: noise on receptance falls like 1/ω².
        let row_weight: Vec<f64> = omega.iter().map(|w| (w * w) / wc).collect();
        let weights: Vec<f64> = acc_rms
            .iter()
            .map(|&r| {
                if r > 0.0 && r.is_finite() {
                    wc / r
                } else {
                    0.0
                }
            })
            .collect();
        let data = h
            .iter()
            .zip(&weights)
            .map(|(ch, &w)| {
                let mut v = Vec::with_capacity(2 * omega.len());
                for (x, rw) in ch[lo..=hi].iter().zip(&row_weight) {
                    let x = if x.re.is_finite() && x.im.is_finite() {
                        *x
                    } else {
                        c64::new(0.0, 0.0)
                    };
                    v.push(rw * w * x.re);
                    v.push(rw * w * x.im);
                }
                v
            })
            .collect();
        Band {
            omega,
            row_weight,
            data,
            weights,
            hz,
        }
    }

    fn rows(&self) -> usize {
        2 * self.omega.len()
    }

    /// Basis columns for the poles (2 per pole) and the residual terms.
    fn basis(&self, poles: &[Pole]) -> Vec<Vec<f64>> {
        let mut cols = Vec::with_capacity(2 * poles.len() + 2);
        for &p in poles {
            let l = pole(p);
            let mut g1 = Vec::with_capacity(self.rows());
            let mut g2 = Vec::with_capacity(self.rows());
            for (&w, &rw) in self.omega.iter().zip(&self.row_weight) {
                let s = c64::new(0.0, w);
                let a = (s - l).inv();
                let b = (s - l.conj()).inv();
                // A = a_r + i a_i: A/(s−λ) + Ā/(s−λ̄) = a_r (a + b) + a_i i (a − b).
                let u = (a + b) * rw;
                let v = c64::new(0.0, 1.0) * (a - b) * rw;
                g1.push(u.re);
                g1.push(u.im);
                g2.push(v.re);
                g2.push(v.im);
            }
            cols.push(g1);
            cols.push(g2);
        }
        let w0 = self.omega[self.omega.len() / 2];
        let mut up = Vec::with_capacity(self.rows());
        let mut low = Vec::with_capacity(self.rows());
        for (&w, &rw) in self.omega.iter().zip(&self.row_weight) {
            up.push(rw);
            up.push(0.0);
            low.push(rw * (w0 / w).powi(2));
            low.push(0.0);
        }
        cols.push(up);
        cols.push(low);
        cols
    }

    /// Residual vector (all channels) of the projection onto the basis.
    fn residual(&self, poles: &[Pole]) -> Vec<f64> {
        let q = orthonormal(self.basis(poles));
        let mut r = Vec::with_capacity(self.rows() * self.data.len());
        for y in &self.data {
            let mut e = y.clone();
            for qk in &q {
                let d = dot(qk, &e);
                axpy(-d, qk, &mut e);
            }
            r.extend(e);
        }
        r
    }

    /// Levenberg–Marquardt ([`lm`]) on the pole parameters (ln f_r, ln ζ_r),
    /// steps of at most 5 % in f and a factor e in ζ, ζ ≤ 0.5; returns the
    /// poles and S = Σr².
    fn fit(&self, poles: Vec<Pole>) -> (Vec<Pole>, f64) {
        let x0: Vec<f64> = poles.iter().flat_map(|p| [p.0, p.1]).collect();
        let lo = vec![f64::NEG_INFINITY; x0.len()];
        let hi: Vec<f64> = (0..x0.len())
            .map(|k| {
                if k % 2 == 0 {
                    f64::INFINITY
                } else {
                    0.5f64.ln()
                }
            })
            .collect();
        // Stop as the pole fit always has: on a relative gain below 1e-10,
        // after twelve increases of λ.
        let settings = LmSettings {
            max_iter: 60,
            relative_gain: 1e-10,
            min_move: 0.0,
            tries: 12,
            ..LmSettings::default()
        };
        match lm(&mut PoleFit { band: self }, &x0, &lo, &hi, settings) {
            Some(o) => (poles_of(&o.x), dot(&o.residuals, &o.residuals)),
            None => {
                let r = self.residual(&poles);
                let s = dot(&r, &r);
                (poles, s)
            }
        }
    }

    /// Residues (unweighted, per channel and pole) for the given poles.
    fn residues(&self, poles: &[Pole]) -> Vec<Vec<c64>> {
        let cols = self.basis(poles);
        let (q, r) = qr(cols);
        self.data
            .iter()
            .zip(&self.weights)
            .map(|(y, &w)| {
                let qty: Vec<f64> = q
                    .iter()
                    .map(|qk| qk.as_ref().map_or(0.0, |qk| dot(qk, y)))
                    .collect();
                let x = back_substitute(&r, &qty);
                (0..poles.len())
                    .map(|k| {
                        if w > 0.0 {
                            c64::new(x[2 * k], x[2 * k + 1]) / w
                        } else {
                            c64::new(0.0, 0.0)
                        }
                    })
                    .collect()
            })
            .collect()
    }

    /// Line (in the band) of the largest residual summed over channels.
    fn worst_line(&self, poles: &[Pole]) -> usize {
        let r = self.residual(poles);
        let rows = self.rows();
        let nl = self.omega.len();
        let mut best = (0.0, nl / 2);
        for l in 0..nl {
            let mut e = 0.0;
            for c in 0..self.data.len() {
                let o = c * rows + 2 * l;
                e += r[o] * r[o] + r[o + 1] * r[o + 1];
            }
            if e > best.0 {
                best = (e, l);
            }
        }
        best.1
    }

    fn identify(&self, freqs: &[f64], opts: &IdentifyOptions, df: f64) -> Vec<ColumnMode> {
        let z0 = (0.01f64).ln();
        let mut poles: Vec<Pole> = freqs.iter().map(|f| (f.ln(), z0)).collect();
        let (mut poles_fit, mut s) = self.fit(poles.clone());
        for _ in 0..opts.max_extra_poles {
            let l = self.worst_line(&poles_fit);
            let f = self.hz[l];
            if poles_fit.iter().any(|p| (p.0.exp() - f).abs() < 0.75 * df) {
                // The worst line is a fitted pole: nudge the new one beside it.
                poles = poles_fit.clone();
                poles.push(((f + df).ln(), z0));
            } else {
                poles = poles_fit.clone();
                poles.push((f.ln(), z0));
            }
            let (p2, s2) = self.fit(poles);
            let distinct = p2.iter().enumerate().all(|(i, a)| {
                p2.iter()
                    .skip(i + 1)
                    .all(|b| (a.0.exp() - b.0.exp()).abs() > 0.5 * df)
            });
            if s2 < 0.5 * s && distinct {
                poles_fit = p2;
                s = s2;
            } else {
                break;
            }
        }
        let res = self.residues(&poles_fit);
        // Residual RMS per line (all channels together).
        let rms = (s / self.omega.len() as f64).sqrt().max(1e-300);
        let (f_lo, f_hi) = (self.hz[0], self.hz[self.hz.len() - 1]);
        let mut out = Vec::new();
        for (k, &p) in poles_fit.iter().enumerate() {
            let f = p.0.exp();
            let z = p.1.exp();
            // A half-power bandwidth under a fifth of a line, or over half the
            // band, is not resolved by the band's data.
            let bandwidth = 2.0 * z * f;
            if !(f > f_lo && f < f_hi && bandwidth > 0.2 * df && bandwidth < 0.5 * (f_hi - f_lo)) {
                continue;
            }
            let a: Vec<c64> = res.iter().map(|rc| rc[k]).collect();
            // The mode's largest contribution on a measured line.
            let l = pole(p);
            let peak = self
                .omega
                .iter()
                .zip(&self.row_weight)
                .map(|(&w, &rw)| {
                    let s = c64::new(0.0, w);
                    let (ga, gb) = ((s - l).inv(), (s - l.conj()).inv());
                    a.iter()
                        .zip(&self.weights)
                        .map(|(x, wc)| (rw * wc * (x * ga + x.conj() * gb)).norm_sqr())
                        .sum::<f64>()
                        .sqrt()
                })
                .fold(0.0f64, f64::max);
            let significance = peak / rms;
            if significance < opts.significance {
                continue;
            }
            out.push(ColumnMode {
                frequency_hz: f,
                damping_ratio: z,
                shape: real_shape(&a),
                constant_sign: constant_sign(&a),
                significance,
                line: 0,
            });
        }
        out
    }
}

/// The sign that turns [`real_shape`] of the residues `a` into modal
/// constants: that of Σ_c shape_c·(−Im a_c).
fn constant_sign(a: &[c64]) -> f64 {
    let s: f64 = real_shape(a).iter().zip(a).map(|(v, x)| -v * x.im).sum();
    if s < 0.0 {
        -1.0
    } else {
        1.0
    }
}

/// The real part of the residues after the rotation that makes them most
/// nearly real, scaled to unit largest magnitude.
fn real_shape(a: &[c64]) -> Vec<f64> {
    let (mut sxx, mut sxy) = (0.0, 0.0);
    for x in a {
        sxx += x.re * x.re - x.im * x.im;
        sxy += 2.0 * x.re * x.im;
    }
    let theta = 0.5 * sxy.atan2(sxx);
    let rot = c64::new(theta.cos(), -theta.sin());
    let v: Vec<f64> = a.iter().map(|x| (x * rot).re).collect();
    let m = v
        .iter()
        .fold(0.0f64, |m, x| if x.abs() > m.abs() { *x } else { m });
    if m == 0.0 {
        v
    } else {
        v.iter().map(|x| x / m).collect()
    }
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

fn axpy(a: f64, x: &[f64], y: &mut [f64]) {
    for (yi, xi) in y.iter_mut().zip(x) {
        *yi += a * xi;
    }
}

/// Orthonormal basis of the columns' span (Gram–Schmidt applied twice;
/// columns dependent on earlier ones are dropped).
fn orthonormal(cols: Vec<Vec<f64>>) -> Vec<Vec<f64>> {
    qr(cols).0.into_iter().flatten().collect()
}

/// Thin QR by twice-applied Gram–Schmidt: Q's columns (None where a column
/// depends on the earlier ones) and the upper-triangular R (row-major).
#[allow(clippy::type_complexity)]
fn qr(cols: Vec<Vec<f64>>) -> (Vec<Option<Vec<f64>>>, Vec<Vec<f64>>) {
    let m = cols.len();
    let mut q: Vec<Option<Vec<f64>>> = Vec::with_capacity(m);
    let mut r = vec![vec![0.0; m]; m];
    for (j, mut v) in cols.into_iter().enumerate() {
        let norm0 = dot(&v, &v).sqrt();
        for _ in 0..2 {
            for (i, qi) in q.iter().enumerate() {
                if let Some(qi) = qi {
                    let d = dot(qi, &v);
                    r[i][j] += d;
                    axpy(-d, qi, &mut v);
                }
            }
        }
        let nv = dot(&v, &v).sqrt();
        if nv > 1e-10 * norm0 && nv > 0.0 {
            r[j][j] = nv;
            v.iter_mut().for_each(|x| *x /= nv);
            q.push(Some(v));
        } else {
            q.push(None);
        }
    }
    (q, r)
}

/// Solves R x = Qᵀy for the columns that have a Q column (others 0).
fn back_substitute(r: &[Vec<f64>], qty: &[f64]) -> Vec<f64> {
    let m = qty.len();
    let mut x = vec![0.0; m];
    for j in (0..m).rev() {
        if r[j][j] == 0.0 {
            continue;
        }
        let mut s = qty[j];
        for k in j + 1..m {
            s -= r[j][k] * x[k];
        }
        x[j] = s / r[j][j];
    }
    x
}
