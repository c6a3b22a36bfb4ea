//! Derivatives of the full-band residuals, exact for the reduced model of
//! [`super::reduced`].
//!
//! H_c(ω) = (iω)^k Σ_r a_cr / d_r(ω) over the m reduced modes, with
//! a_cr = b_cr b_ir (b: the modes at the channels and the excitation) and
//! d_r = λ_r − ω² + i D(λ_r, ω). For a parameter j, with K_j, M_j the
//! reduced ∂K/∂p̄_j, ∂M/∂p̄_j:
//!
//! - ∂λ_r = ψ_rᵀ(K_j − λ_r M_j)ψ_r (Fox & Kapoor);
//! - ∂ψ_r = Σ_s ψ_s E_sr with E_sr = ψ_sᵀ(K_j − λ_r M_j)ψ_r / (λ_r − λ_s),
//!   and E_sr = −½ ψ_sᵀM_jψ_r for s = r or within a degenerate group (e.g.
//!   rigid-body modes): the expansion runs over every reduced mode, so it is
//!   exact for the reduced model;
//! - ∂a_cr = ∂b_cr b_ir + b_cr ∂b_ir with ∂b = b E;
//! - ∂d_r = ∂λ_r (1 + i ∂D/∂λ).
//!
//! The modes above 2·ω_max (most of them the basis's static part) enter
//! through their quasi-static series Σ_{k=0..2} ω^{2k} ∂(a_cr / λ_r^{k+1})
//! (damping neglected: at ω ≤ ω_max/2 of them the series is within 2 % of
//! their term, itself a small part of H): three columns instead of two per
//! mode. Damping (log parameters x): ∂d_r/∂x = i ∂D/∂x, over every mode.
//!
//! A residual row is w·ln(H/H̄) (real and imaginary parts), so its
//! derivative is w·(∂H/∂x)/H. Row order is that of [`fit::residuals`].

use faer::linalg::matmul::matmul;
use faer::{c64, Accum, Mat, MatRef, Par};

use super::data::TestData;
use super::fit::{self, DampingForm, Mask};
use super::reduced::{ReducedModel, ReducedModes};

/// What [`columns`] differentiates: the reduced model and its solution at
/// the point, the damping, and the model FRFs there.
pub struct Point<'a> {
    pub model: &'a ReducedModel,
    pub modes: &'a ReducedModes,
    pub form: DampingForm,
    /// The damping's log parameters.
    pub damping: &'a [f64],
    /// Model FRFs of [`fit::predict`] at the point (measured kind).
    pub pred: &'a [Vec<c64>],
}

/// ∂r/∂x over the data rows, x = [p̄ (deck order), damping logs], followed
/// by `extra_rows` zero rows for the caller (the prior rows: one allocation
/// of the whole Jacobian, which is tens of megabytes on long records),
/// written into `storage` when it has that shape; columns of unknowns that
/// are not `free` are zero.
pub fn columns(
    pt: &Point,
    data: &TestData,
    mask: &Mask,
    free: &[bool],
    extra_rows: usize,
    storage: Option<Mat<f64>>,
) -> Mat<f64> {
    let np = pt.model.anchor.len();
    let lines: Vec<usize> = (0..data.omegas.len()).filter(|&l| mask.lines[l]).collect();
    let params: Vec<usize> = (0..np).filter(|&j| free[j]).collect();
    let nc = data.channels.len();
    // ∂H_c(ω_l) of each free parameter: the kernels times the coefficients,
    // one channel's block of columns at a time into the same two buffers
    // (the whole product would be lines × channels·parameters twice over,
    // megabytes written once and read once).
    let (kernel, split) = kernels(pt, data, &lines);
    let coef = parameter_coefficients(pt, &params, split);
    let pairs = row_pairs(data, mask, &lines, pt.pred);
    let shape = (data_rows(data, mask) + extra_rows, free.len());
    let mut jac = match storage {
        Some(mut m) if (m.nrows(), m.ncols()) == shape => {
            m.fill(0.0);
            m
        }
        _ => Mat::<f64>::zeros(shape.0, shape.1),
    };
    let nf = params.len();
    let mut dh = (
        Mat::<f64>::zeros(lines.len(), nf),
        Mat::<f64>::zeros(lines.len(), nf),
    );
    for (c, pairs) in pairs.iter().enumerate().filter(|(_, p)| !p.is_empty()) {
        let block = coef.as_ref().subcols(c * nf, nf);
        complex_product_into(&mut dh, kernel.0.as_ref(), kernel.1.as_ref(), block);
        for (k, &j) in params.iter().enumerate() {
            fill(jac.col_as_slice_mut(j), &dh, k, pairs);
        }
    }
    // Damping: ∂H_c = Σ_r a_cr (−i ∂D_r/∂x) / d_r².
    let nd = pt.damping.len();
    let a = Mat::from_fn(pt.modes.model.omega2.len(), nc, |r, c| {
        pt.modes.model.coeff[c][r]
    });
    let mut dh = (
        Mat::<f64>::zeros(lines.len(), nc),
        Mat::<f64>::zeros(lines.len(), nc),
    );
    for k in (0..nd).filter(|&k| free[np + k]) {
        let (qr, qi) = damping_kernel(pt, data, &lines, k);
        complex_product_into(&mut dh, qr.as_ref(), qi.as_ref(), a.as_ref());
        for (c, pairs) in pairs.iter().enumerate() {
            fill(jac.col_as_slice_mut(np + k), &dh, c, pairs);
        }
    }
    jac
}

/// Number of data rows of [`fit::residuals`] for `mask`.
pub fn data_rows(data: &TestData, mask: &Mask) -> usize {
    let mut n = 0;
    for (c, w) in data.weight.iter().enumerate() {
        if mask.channels[c] {
            n += 2
                * (0..w.len())
                    .filter(|&l| mask.lines[l] && w[l] != 0.0)
                    .count();
        }
    }
    n
}

/// The per-line kernels [Re, Im] of [1/d_r | −(∂d_r/∂λ)/d_r² | ω^{2k}] over
/// the used lines, low modes (λ ≤ (2ω_max)²) one by one and the others by
/// their series; and the number of low modes.
fn kernels(pt: &Point, data: &TestData, lines: &[usize]) -> ((Mat<f64>, Mat<f64>), usize) {
    let lam = &pt.modes.model.omega2;
    let w_max = data.omegas.iter().fold(0.0f64, |a, w| a.max(*w));
    let nl = lam.iter().filter(|&&l| l <= (2.0 * w_max).powi(2)).count();
    let damping = pt.form.damping(pt.damping);
    let width = 2 * nl + 3;
    let mut gr = Mat::<f64>::zeros(lines.len(), width);
    let mut gi = Mat::<f64>::zeros(lines.len(), width);
    for (i, &l) in lines.iter().enumerate() {
        let w = data.omegas[l];
        for r in 0..nl {
            let (d, dd) = fit::denominator(lam[r], w, damping);
            let inv = d.inv();
            let h = -(dd * inv * inv);
            (gr[(i, r)], gi[(i, r)]) = (inv.re, inv.im);
            (gr[(i, nl + r)], gi[(i, nl + r)]) = (h.re, h.im);
        }
        for k in 0..3 {
            gr[(i, 2 * nl + k)] = (w * w).powi(k as i32);
        }
    }
    ((gr, gi), nl)
}

/// The coefficients the kernels multiply: rows [∂a_cr | a_cr ∂λ_r | series
/// terms], one column per (channel, free parameter).
fn parameter_coefficients(pt: &Point, params: &[usize], nl: usize) -> Mat<f64> {
    let psi = pt.modes.shapes.as_ref();
    let b = pt.modes.at_dofs.as_ref();
    let lam = &pt.modes.model.omega2;
    let a = &pt.modes.model.coeff;
    let (m, nc, nf) = (lam.len(), b.nrows() - 1, params.len());
    let scale = lam[..nl]
        .iter()
        .fold(0.0f64, |s, l| s.max(l.abs()))
        .max(1e-300);
    let mut coef = Mat::<f64>::zeros(2 * nl + 3, nc * nf);
    for (k, &j) in params.iter().enumerate() {
        let (dk, dm) = pt.model.derivative(j);
        let p = congruence(psi, dk);
        let q = congruence(psi, dm);
        let dl: Vec<f64> = (0..m).map(|r| p[(r, r)] - lam[r] * q[(r, r)]).collect();
        let e = Mat::from_fn(m, m, |s, r| {
            let gap = lam[r] - lam[s];
            let tie = 1e-8 * lam[r].abs().max(lam[s].abs()) + 1e-9 * scale;
            if s == r || gap.abs() <= tie {
                -0.5 * q[(s, r)]
            } else {
                (p[(s, r)] - lam[r] * q[(s, r)]) / gap
            }
        });
        let db = b * &e;
        for c in 0..nc {
            let col = c * nf + k;
            for r in 0..m {
                let da = db[(c, r)] * b[(nc, r)] + b[(c, r)] * db[(nc, r)];
                let adl = a[c][r] * dl[r];
                if r < nl {
                    coef[(r, col)] = da;
                    coef[(nl + r, col)] = adl;
                } else {
                    for t in 0..3 {
                        let n = t as i32 + 1;
                        coef[(2 * nl + t, col)] +=
                            da / lam[r].powi(n) - n as f64 * adl / lam[r].powi(n + 1);
                    }
                }
            }
        }
    }
    coef
}

/// ΨᵀSΨ.
fn congruence(psi: MatRef<'_, f64>, s: MatRef<'_, f64>) -> Mat<f64> {
    let mut sp = Mat::<f64>::zeros(s.nrows(), psi.ncols());
    matmul(sp.as_mut(), Accum::Replace, s, psi, 1.0, Par::Seq);
    let mut out = Mat::<f64>::zeros(psi.ncols(), psi.ncols());
    matmul(
        out.as_mut(),
        Accum::Replace,
        psi.transpose(),
        sp.as_ref(),
        1.0,
        Par::Seq,
    );
    out
}

/// [Re, Im] of −i (∂D_r/∂x_k) / d_r² over the used lines and every mode.
fn damping_kernel(pt: &Point, data: &TestData, lines: &[usize], k: usize) -> (Mat<f64>, Mat<f64>) {
    let lam = &pt.modes.model.omega2;
    let damping = pt.form.damping(pt.damping);
    let e = DampingForm::exp_parameters(pt.damping);
    let mut qr = Mat::<f64>::zeros(lines.len(), lam.len());
    let mut qi = Mat::<f64>::zeros(lines.len(), lam.len());
    for (i, &l) in lines.iter().enumerate() {
        let w = data.omegas[l];
        for (r, &lr) in lam.iter().enumerate() {
            let inv = fit::denominator(lr, w, damping).0.inv();
            let q = c64::new(0.0, -pt.form.term_derivatives(e, lr, w)[k]) * inv * inv;
            (qr[(i, r)], qi[(i, r)]) = (q.re, q.im);
        }
    }
    (qr, qi)
}

/// (G_r + iG_i)·C for a real C, its real and imaginary parts written into
/// `out` (shaped rows of G × columns of C).
fn complex_product_into(
    out: &mut (Mat<f64>, Mat<f64>),
    gr: MatRef<'_, f64>,
    gi: MatRef<'_, f64>,
    c: MatRef<'_, f64>,
) {
    let par = Par::Seq;
    matmul(out.0.as_mut(), Accum::Replace, gr, c, 1.0, par);
    matmul(out.1.as_mut(), Accum::Replace, gi, c, 1.0, par);
}

/// One pair of data rows (Re, Im) of the Jacobian: the index of its line
/// among the used ones, its first row, the weight w and (iω)^k / H of the
/// model there (`None`: the model or the ratio to the data is not finite or
/// vanishes, and the rows stay zero).
struct RowPair {
    line: usize,
    row: usize,
    weight: f64,
    factor: Option<c64>,
}

/// The row pairs of each channel (none for a channel left out by `mask`),
/// in the row order of [`fit::residuals`].
fn row_pairs(
    data: &TestData,
    mask: &Mask,
    lines: &[usize],
    pred: &[Vec<c64>],
) -> Vec<Vec<RowPair>> {
    let mut row = 0;
    let mut pairs: Vec<Vec<RowPair>> = (0..data.channels.len()).map(|_| Vec::new()).collect();
    for c in (0..data.channels.len()).filter(|&c| mask.channels[c]) {
        for (i, &l) in lines.iter().enumerate() {
            let weight = data.weight[c][l];
            if weight == 0.0 {
                continue;
            }
            let hm = pred[c][l];
            let ratio = hm / data.values[c][l];
            let factor = (ratio.re.is_finite() && ratio.im.is_finite() && ratio.norm() > 0.0)
                .then(|| crate::testdata::i_omega_power(data.omegas[l], data.kind.order()) / hm);
            pairs[c].push(RowPair {
                line: i,
                row,
                weight,
                factor,
            });
            row += 2;
        }
    }
    pairs
}

/// Write w·Re, w·Im of (iω)^k ∂H / H into one column of the Jacobian
/// (`col`): ∂H over the used lines is column `src` of `dh`, the rows are
/// one channel's `pairs`.
fn fill(col: &mut [f64], dh: &(Mat<f64>, Mat<f64>), src: usize, pairs: &[RowPair]) {
    let (re, im) = (dh.0.col_as_slice(src), dh.1.col_as_slice(src));
    for p in pairs {
        if let Some(factor) = p.factor {
            let d = c64::new(re[p.line], im[p.line]) * factor;
            col[p.row] = p.weight * d.re;
            col[p.row + 1] = p.weight * d.im;
        }
    }
}
