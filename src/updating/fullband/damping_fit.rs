//! The damping fitted on one modal model, with its exact Jacobian.
//!
//! H_c(ω) = (iω)^k [f·(R0_c + ω²R1_c) + Σ_r a_cr / d_r(ω)] ([`fit::predict`])
//! with d_r = λ_r − ω² + i D(λ_r, ω) and f = 1/(1 + iη) for hysteretic
//! damping (1 otherwise). For the damping's log parameters x_k,
//! ∂d_r/∂x_k = i ∂D/∂x_k ([`DampingForm::term_derivatives`]) and
//! ∂f/∂ln η = −iη f², so
//!
//! ∂H_c/∂x_k = (iω)^k [∂f/∂x_k·(R0_c + ω²R1_c) − i Σ_r a_cr (∂D_r/∂x_k) / d_r²].
//!
//! A residual row is w·ln(H/H̄) (real and imaginary parts), so its
//! derivative is w·(∂H/∂x_k)/H, where the (iω)^k cancel. The sums over the
//! modes of every line and channel are one matrix product: the kernels
//! 1/d_r and −i(∂D_r/∂x_k)/d_r² (lines × modes, real and imaginary parts
//! stacked) times the coefficients a (modes × channels).
//!
//! Forward differences cost one prediction per damping parameter, each with
//! a complex logarithm per point; this costs one product and a complex
//! division per point. The damping profile of a candidate model is most of
//! a diagnosis's time.

use faer::{c64, Mat};

use super::data::TestData;
use super::fit::{self, DampingForm, DampingState, Mask, ModalModel};
use super::lm::{self, LeastSquares, LmSettings};

/// ∂r/∂x of [`fit::residuals`] of [`fit::predict`]`(mm, form.damping(x))`
/// on `mask`: one row per residual, one column per damping log parameter.
/// Rows where the residual is the fixed penalty (the model or its ratio to
/// the data not finite, or zero) are zero.
pub fn damping_jacobian(
    mm: &ModalModel,
    form: DampingForm,
    x: &[f64],
    data: &TestData,
    mask: &Mask,
) -> Mat<f64> {
    let nd = x.len();
    let damping = form.damping(x);
    let lines: Vec<usize> = (0..data.omegas.len()).filter(|&l| mask.lines[l]).collect();
    let channels: Vec<usize> = (0..data.channels.len())
        .filter(|&c| mask.channels[c])
        .collect();
    let sums = modal_sums(mm, form, x, data, &lines, &channels);
    let nl = lines.len();
    let rows: usize = channels
        .iter()
        .map(|&c| lines.iter().filter(|&&l| data.weight[c][l] != 0.0).count())
        .sum();
    // The static terms' damping factor of each used line, shared by the channels.
    let factors: Vec<(c64, c64, usize)> = lines
        .iter()
        .map(|&l| fit::static_factor(damping, data.omegas[l]))
        .collect();
    let mut jac = Mat::<f64>::zeros(2 * rows, nd);
    let mut row = 0;
    for (k, &c) in channels.iter().enumerate() {
        for (i, &l) in lines.iter().enumerate() {
            let weight = data.weight[c][l];
            if weight == 0.0 {
                continue;
            }
            let w = data.omegas[l];
            let (f, df, with) = factors[i];
            let stat = mm.residual[c] + w * w * mm.residual_mass[c];
            let h = f * stat + c64::new(sums[(i, k)], sums[(nl + i, k)]);
            let hm = h * crate::testdata::i_omega_power(w, data.kind.order());
            // The fixed penalty of fit::residuals does not depend on x.
            if !fit::has_log_ratio(hm / data.values[c][l]) {
                row += 2;
                continue;
            }
            let hinv = h.inv();
            for j in 0..nd {
                let block = 2 * (j + 1) * nl;
                let mut dh = c64::new(sums[(block + i, k)], sums[(block + nl + i, k)]);
                if j == with {
                    dh += df * stat;
                }
                let g = dh * hinv;
                jac[(row, j)] = weight * g.re;
                jac[(row + 1, j)] = weight * g.im;
            }
            row += 2;
        }
    }
    jac
}

/// Σ_r a_cr g_r(ω_l) for the kernels g = 1/d_r, then −i(∂D_r/∂x_k)/d_r² of
/// each damping parameter: rows (kernel b, real or imaginary part, line i)
/// at (2b + part)·lines + i, one column per channel of `channels`.
fn modal_sums(
    mm: &ModalModel,
    form: DampingForm,
    x: &[f64],
    data: &TestData,
    lines: &[usize],
    channels: &[usize],
) -> Mat<f64> {
    let damping = form.damping(x);
    let e = DampingForm::exp_parameters(x);
    let (nl, nm) = (lines.len(), mm.omega2.len());
    let blocks = 1 + x.len();
    let mut kernels = Mat::<f64>::zeros(2 * blocks * nl, nm);
    let omegas: Vec<f64> = lines.iter().map(|&l| data.omegas[l]).collect();
    let (mut inv_re, mut inv_im) = (vec![0.0; nl], vec![0.0; nl]);
    for (r, &lam) in mm.omega2.iter().enumerate() {
        fit::inverse_denominators(lam, damping, &omegas, &mut inv_re, &mut inv_im);
        for (i, &w) in omegas.iter().enumerate() {
            let inv = c64::new(inv_re[i], inv_im[i]);
            (kernels[(i, r)], kernels[(nl + i, r)]) = (inv_re[i], inv_im[i]);
            // D is evaluated at max(λ, 0) (Damping::modal_term).
            let dd = form.term_derivatives(e, lam.max(0.0), w);
            for (j, &d) in dd.iter().enumerate().take(x.len()) {
                let q = c64::new(0.0, -d) * inv * inv;
                let block = 2 * (j + 1) * nl;
                (kernels[(block + i, r)], kernels[(block + nl + i, r)]) = (q.re, q.im);
            }
        }
    }
    fit::coefficient_product(mm, channels, kernels)
}

/// The damping's log parameters as a least-squares problem on one modal
/// model.
struct DampingProblem<'a> {
    mm: &'a ModalModel,
    form: DampingForm,
    data: &'a TestData,
    mask: &'a Mask,
}

impl LeastSquares for DampingProblem<'_> {
    fn residuals(&mut self, x: &[f64]) -> Option<Vec<f64>> {
        let pred = fit::predict(self.mm, self.form.damping(x), self.data, self.mask);
        Some(fit::residuals(&pred, self.data, self.mask))
    }
    fn jacobian(&mut self, x: &[f64], _r: &[f64], _free: &[bool]) -> Option<Mat<f64>> {
        Some(damping_jacobian(
            self.mm, self.form, x, self.data, self.mask,
        ))
    }
}

/// Fit the damping parameters of `state.form` to the masked data on one
/// modal model (bounded Levenberg–Marquardt, at most `max_iter`
/// iterations); the fitted state and its residuals.
pub fn fit_damping(
    mm: &ModalModel,
    state: &DampingState,
    data: &TestData,
    mask: &Mask,
    max_iter: usize,
) -> (DampingState, Vec<f64>) {
    let (w_lo, w_hi) = data.band();
    let (lo, hi) = state.form.bounds(w_lo, w_hi);
    let form = state.form;
    let mut problem = DampingProblem {
        mm,
        form,
        data,
        mask,
    };
    let settings = LmSettings {
        max_iter,
        ..LmSettings::default()
    };
    match lm::lm(&mut problem, &state.x, &lo, &hi, settings) {
        Some(o) => (DampingState { form, x: o.x }, o.residuals),
        None => {
            let pred = fit::predict(mm, state.damping(), data, mask);
            (state.clone(), fit::residuals(&pred, data, mask))
        }
    }
}

/// σ of the damping's log parameters at `state` ([`lm::std_devs`] of the
/// exact Jacobian).
pub fn damping_std(
    mm: &ModalModel,
    state: &DampingState,
    data: &TestData,
    mask: &Mask,
) -> Vec<f64> {
    let pred = fit::predict(mm, state.damping(), data, mask);
    let r = fit::residuals(&pred, data, mask);
    let jac = damping_jacobian(mm, state.form, &state.x, data, mask);
    lm::std_devs(jac.as_ref(), &r)
}
