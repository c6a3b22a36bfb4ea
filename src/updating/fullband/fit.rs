//! Model FRFs at the measured channels and the fit of a few parameters.
//!
//! Prediction: modal superposition over the lowest modes (up to 4·ω_max)
//! plus the residual of the others to second order in ω (R0 + ω²R1),
//! H_j(ω) = (iω)^k [Σ_r φ_jr φ_ir / d_r(ω) + R0 + ω²R1]
//! with d_r = ω_r² − ω² + i·(damping term). Residual of a point (channel c,
//! line l) above the noise floor: w_cl·ln(H_model/H_test), real part (log
//! magnitude) and imaginary part (phase), with w_cl from [`TestData`].
//! Cost = mean of the squared residuals; from noise alone it is J0 (≈ the
//! mean of s²/(s² + f²)), so J/J0 ≈ 1 is a fit at the noise level.
//!
//! Parameters are fitted on a log scale within physical bounds: damping by
//! Levenberg–Marquardt (1–2 parameters, cheap: the modes are reused), one
//! structural parameter by a log grid then golden-section search of the
//! damping-profiled cost. Uncertainty: σ²(JᵀJ)⁻¹ at the optimum, with
//! σ² = Σr²/(N − p).

use faer::{c64, Mat};
use frfup_parsers::deck::Deck;

use super::data::TestData;
use super::prior::ParameterPrior;
use super::FitError as DiagnoseError;
use crate::model::{self, Damping, FeModel, ModalDampingTerm, ParameterValues};
use crate::solvers::eigen::{self, EigenOptions, Modes};
use crate::solvers::frf;

/// Which points take part: lines and channels.
#[derive(Clone, Debug, PartialEq)]
pub struct Mask {
    pub lines: Vec<bool>,
    pub channels: Vec<bool>,
}

impl Mask {
    pub fn all(data: &TestData) -> Mask {
        Mask {
            lines: vec![true; data.lines_hz.len()],
            channels: vec![true; data.channels.len()],
        }
    }
    /// The complementary mask (held-out data) for a fold that holds out lines
    /// or channels.
    pub fn complement(&self) -> Mask {
        let lines_all = self.lines.iter().all(|&b| b);
        let ch_all = self.channels.iter().all(|&b| b);
        Mask {
            lines: if lines_all {
                self.lines.clone()
            } else {
                self.lines.iter().map(|b| !b).collect()
            },
            channels: if ch_all {
                self.channels.clone()
            } else {
                self.channels.iter().map(|b| !b).collect()
            },
        }
    }
}

/// The modes of one model and how they reach the measured channels.
#[derive(Clone, Debug)]
pub struct ModalModel {
    /// ω_r² (rad²/s²).
    pub omega2: Vec<f64>,
    /// a[c][r] = sign_c·φ_{j(c),r}·φ_{input,r} (1/kg).
    pub coeff: Vec<Vec<f64>>,
    /// Static residual of the modes left out, per channel (m/N).
    pub residual: Vec<f64>,
    /// Its first frequency correction R1 (m/N·s²): the modes left out add
    /// R0 + ω² R1 ([`frf::static_residual_terms`]).
    pub residual_mass: Vec<f64>,
    /// Lowest natural frequencies (Hz).
    pub frequencies_hz: Vec<f64>,
    /// Number of free DOFs of the model.
    pub dofs: usize,
}

/// Modes whose ω² differ by at most this share are one repeated mode for
/// [`ModalModel::repeated_merged`] (a tube's bending pair: equal to ~1e-13).
pub const REPEATED: f64 = 1e-6;

impl ModalModel {
    /// The same model with each repeated mode (ω² within [`REPEATED`]) as
    /// one: a[c] = Σ_r a[c][r] over its eigenspace, ω² their mean. The
    /// eigenvectors of a repeated mode are any basis of its eigenspace (a
    /// tube's y and z bending mixed at random), so one of them alone at a
    /// channel means nothing; the sum is the eigenspace's response to the
    /// excitation, the same in every basis and what a test identifies.
    /// The FRFs are unchanged.
    pub fn repeated_merged(&self) -> ModalModel {
        let mut groups: Vec<Vec<usize>> = Vec::new();
        for r in 0..self.omega2.len() {
            match groups.last_mut() {
                Some(g)
                    if (self.omega2[r] - self.omega2[g[0]]).abs()
                        <= REPEATED * self.omega2[r].abs().max(self.omega2[g[0]].abs()) =>
                {
                    g.push(r)
                }
                _ => groups.push(vec![r]),
            }
        }
        let mean = |v: &[f64], g: &[usize]| g.iter().map(|&r| v[r]).sum::<f64>() / g.len() as f64;
        ModalModel {
            omega2: groups.iter().map(|g| mean(&self.omega2, g)).collect(),
            coeff: self
                .coeff
                .iter()
                .map(|row| {
                    groups
                        .iter()
                        .map(|g| g.iter().map(|&r| row[r]).sum())
                        .collect()
                })
                .collect(),
            residual: self.residual.clone(),
            residual_mass: self.residual_mass.clone(),
            frequencies_hz: groups
                .iter()
                .map(|g| mean(&self.frequencies_hz, g))
                .collect(),
            dofs: self.dofs,
        }
    }
}

/// Build `deck` (values already multiplied in) and compute its modal model
/// at the channels of `data`.
pub fn modal_model(deck: &Deck, data: &TestData) -> Result<ModalModel, DiagnoseError> {
    let fe = model::build(deck, &ParameterValues::new()).map_err(DiagnoseError::Model)?;
    Ok(modal_solution(&fe, data)?.model)
}

/// A modal model with what its derivatives need: the modes and where the
/// channels and the excitation sit among the model's equations.
pub struct ModalSolution {
    pub model: ModalModel,
    pub modes: Modes,
    /// Equation of each channel's response DOF, and of the excitation.
    pub outputs: Vec<usize>,
    pub input: usize,
    /// sign_c of each channel (response sign × excitation sign).
    pub signs: Vec<f64>,
}

/// Where the test sits in a model: the excitation's equation, each channel's
/// equation and its sign (response sign × excitation sign).
pub struct Placement {
    pub input: usize,
    pub outputs: Vec<usize>,
    pub signs: Vec<f64>,
}

/// The equations of `data`'s excitation and channels in `fe`.
pub fn placement(fe: &FeModel, data: &TestData) -> Result<Placement, DiagnoseError> {
    let (input, in_sign) = fe.measured_dof(data.input.0, data.input.1).ok_or_else(|| {
        DiagnoseError::Data(format!(
            "the excitation {} is not a free DOF of the model",
            crate::testdata::dof_label(data.input.0 as i64, data.input.1)
        ))
    })?;
    let mut outputs = Vec::with_capacity(data.channels.len());
    let mut signs = Vec::with_capacity(data.channels.len());
    for ch in &data.channels {
        let (eq, s) = fe.measured_dof(ch.node, ch.direction).ok_or_else(|| {
            DiagnoseError::Data(format!(
                "channel {} is not a free DOF of the model",
                ch.label
            ))
        })?;
        outputs.push(eq);
        signs.push(s * in_sign);
    }
    Ok(Placement {
        input,
        outputs,
        signs,
    })
}

/// The modal model keeps the modes up to this multiple of ω_max (and the
/// one above): the static terms R0 + ω²R1 ([`static_factor`] damps them)
/// of each mode left out miss at most (ω/ω_r)⁴/(1 − (ω/ω_r)²) = 0.4 % of
/// its term in the band. Measured against the direct solution
/// (`tests/all/modal_predictor.rs`): 2.5·ω_max left 2.5e-5 of |H|
/// (hysteretic) and 2.3e-4 (Rayleigh, static terms undamped), and changed
/// 14 of the diagnosis benchmark's 300 findings; 4·ω_max leaves 1e-6 and
/// 7e-7.
pub const MODES_UP_TO: f64 = 4.0;

/// The lowest modes of `fe` up to [`MODES_UP_TO`]·ω_max of `data` and the
/// one above (every mode of a model of at most 40 DOFs): 40 asked, twice as
/// many until they reach past it, every mode once that is all of them. The
/// dense path does the doubling in one solution (`grow_to_cover`; the
/// GARTEUR model's 48 modes used to take two, 40 then 80); the Krylov path
/// solves again.
pub fn band_modes(fe: &FeModel, data: &TestData) -> Result<Modes, DiagnoseError> {
    let n = fe.dofs.len();
    let w_max = data.omegas.iter().fold(0.0f64, |a, w| a.max(*w));
    let top = (MODES_UP_TO * w_max).powi(2);
    let mut count = 40usize.min(n);
    loop {
        let opts = EigenOptions {
            count,
            expect_no_rigid_body_modes: fe.has_fixed_dofs,
            // A model that has no more DOFs than `count` keeps every mode.
            cover_omega2: (count < n).then_some(top),
            grow_to_cover: true,
            ..EigenOptions::default()
        };
        let modes = eigen::lowest_modes(&fe.stiffness, &fe.mass, &opts)
            .map_err(|e| DiagnoseError::Eigen(e.to_string()))?;
        let highest = modes.omega2.last().copied().unwrap_or(0.0);
        if highest >= top || count >= n || modes.len() < count || modes.len() >= n {
            return Ok(modes);
        }
        count = (2 * count).min(n);
    }
}

/// The modal model of `fe` at the channels of `data`: the lowest modes up to
/// 4·ω_max ([`band_modes`]) plus the static residual of the others.
pub fn modal_solution(fe: &FeModel, data: &TestData) -> Result<ModalSolution, DiagnoseError> {
    let Placement {
        input,
        outputs,
        signs,
    } = placement(fe, data)?;
    let n = fe.dofs.len();
    let modes = band_modes(fe, data)?;
    let (residual, residual_mass) = if modes.len() < n {
        frf::static_residual_terms(&fe.stiffness, &fe.mass, &modes, input, &outputs)
            .map_err(|e| DiagnoseError::Eigen(e.to_string()))?
    } else {
        (vec![0.0; outputs.len()], vec![0.0; outputs.len()])
    };
    let coeff = outputs
        .iter()
        .zip(&signs)
        .map(|(&j, &s)| {
            (0..modes.len())
                .map(|r| s * modes.shapes[(j, r)] * modes.shapes[(input, r)])
                .collect()
        })
        .collect();
    let residual = residual.iter().zip(&signs).map(|(r, s)| r * s).collect();
    let residual_mass = residual_mass
        .iter()
        .zip(&signs)
        .map(|(r, s)| r * s)
        .collect();
    Ok(ModalSolution {
        model: ModalModel {
            dofs: n,
            frequencies_hz: modes.frequencies_hz(),
            omega2: modes.omega2.clone(),
            coeff,
            residual,
            residual_mass,
        },
        modes,
        outputs,
        input,
        signs,
    })
}

/// Model FRFs in the measured kind, `[channel][line]`, masked channels left empty:
/// H_c(ω) = (iω)ⁿ [R0_c + ω² R1_c + Σ_r a_cr / d_r(ω)].
///
/// The sum runs mode by mode over all channels at once (coefficients stored
/// mode-major), so the inner loop is independent per channel and
/// vectorises; each channel still adds its terms in mode order, the same
/// sums as a per-channel loop.
pub fn predict(mm: &ModalModel, damping: Damping, data: &TestData, mask: &Mask) -> Vec<Vec<c64>> {
    let lines: Vec<usize> = (0..data.omegas.len()).filter(|&l| mask.lines[l]).collect();
    let active: Vec<usize> = (0..data.channels.len())
        .filter(|&c| mask.channels[c])
        .collect();
    let nl = lines.len();
    // 1/d_r(ω) of every mode at every used line, real parts above imaginary;
    // the lines' ω side by side, so that the divisions of several lines go
    // in one instruction.
    let omegas: Vec<f64> = lines.iter().map(|&l| data.omegas[l]).collect();
    let terms: Vec<_> = mm.omega2.iter().map(|&w2| damping.modal_term(w2)).collect();
    let mut kernels = Mat::<f64>::zeros(2 * nl, mm.omega2.len());
    for (r, (&w2, t)) in mm.omega2.iter().zip(&terms).enumerate() {
        let (re, im) = kernels.as_mut().col_mut(r).split_at_row_mut(nl);
        let (re, im) = (
            re.try_as_col_major_mut().unwrap(),
            im.try_as_col_major_mut().unwrap(),
        );
        kernel_column(w2, *t, &omegas, re.as_slice_mut(), im.as_slice_mut());
    }
    let sums = coefficient_product(mm, &active, kernels);
    // The static terms' damping factor of each line, shared by the channels.
    let factors: Vec<c64> = data
        .omegas
        .iter()
        .map(|&w| static_factor(damping, w).0)
        .collect();
    let mut out: Vec<Vec<c64>> = vec![Vec::new(); data.channels.len()];
    for (k, &c) in active.iter().enumerate() {
        let mut used = 0;
        out[c] = (0..data.omegas.len())
            .map(|l| {
                if !mask.lines[l] {
                    return c64::new(f64::NAN, f64::NAN);
                }
                let w = data.omegas[l];
                let stat = factors[l] * (mm.residual[c] + w * w * mm.residual_mass[c]);
                let h = stat + c64::new(sums[(used, k)], sums[(nl + used, k)]);
                used += 1;
                h * crate::testdata::i_omega_power(w, data.kind.order())
            })
            .collect();
    }
    out
}

/// 1/d_r(ω) of the mode of ω_r² = `lam` with `damping` at the lines
/// `omegas` (rad/s), as [`denominator`]'s first part inverted, written into
/// `re` and `im` ([`kernel_column`] with the mode's damping term).
pub fn inverse_denominators(
    lam: f64,
    damping: Damping,
    omegas: &[f64],
    re: &mut [f64],
    im: &mut [f64],
) {
    kernel_column(lam, damping.modal_term(lam), omegas, re, im);
}

/// 1/d_r(ω) of the mode of ω_r² = `w2` and damping term `t` at the lines
/// `omegas` (rad/s): real parts into `re`, imaginary parts into `im`. The
/// operations of [`ModalDampingTerm::at`] and `c64::inv`, in their order
/// (the same bits), four lines at a time: their divisions, most of a
/// prediction's own time, then share instructions.
pub fn kernel_column(w2: f64, t: ModalDampingTerm, omegas: &[f64], re: &mut [f64], im: &mut [f64]) {
    const LANES: usize = 4;
    let full = omegas.len() / LANES * LANES;
    for j0 in (0..full).step_by(LANES) {
        let w = &omegas[j0..j0 + LANES];
        let d_re: [f64; LANES] = std::array::from_fn(|k| w2 - w[k] * w[k]);
        let d_im: [f64; LANES] = std::array::from_fn(|k| t.slope * w[k] + t.constant);
        let n2: [f64; LANES] = std::array::from_fn(|k| d_re[k] * d_re[k] + d_im[k] * d_im[k]);
        let (re, im) = (&mut re[j0..j0 + LANES], &mut im[j0..j0 + LANES]);
        for k in 0..LANES {
            re[k] = d_re[k] / n2[k];
            im[k] = -d_im[k] / n2[k];
        }
    }
    for j in full..omegas.len() {
        let inv = t.at(w2, omegas[j]).inv();
        (re[j], im[j]) = (inv.re, inv.im);
    }
}

/// The damping of the modes the static terms R0 + ω²R1 stand for (all far
/// above ω, rad/s), as a factor f on them, with ∂f/∂x_j of the damping log
/// parameter x_j it depends on: hysteretic 1/(1 + iη) (j = 0, ∂ = −iη f²);
/// Rayleigh's stiffness part 1/(1 + iωβ) (d_r ≈ ω_r²(1 + iωβ) for
/// ω_r ≫ ω; its mass part αω/ω_r² is negligible there; j = 1,
/// ∂ = −iωβ f²); modal damping 2ζωω_r/ω_r² → 0: none.
pub fn static_factor(damping: Damping, w: f64) -> (c64, c64, usize) {
    let damped = |loss: f64| {
        let f = c64::new(1.0, loss).inv();
        (f, c64::new(0.0, -loss) * f * f)
    };
    match damping {
        Damping::Hysteretic { eta } => {
            let (f, df) = damped(eta);
            (f, df, 0)
        }
        Damping::Rayleigh { beta, .. } => {
            let (f, df) = damped(w * beta);
            (f, df, 1)
        }
        _ => (c64::new(1.0, 0.0), c64::new(0.0, 0.0), 0),
    }
}

/// Σ_r a_cr g_r for kernels g given as rows (any number of lines and
/// parts) × modes: `kernels` times the coefficients of `channels` (modes ×
/// channels), one matrix product.
pub fn coefficient_product(mm: &ModalModel, channels: &[usize], kernels: Mat<f64>) -> Mat<f64> {
    let nm = mm.omega2.len();
    let coeff = Mat::from_fn(nm, channels.len(), |r, k| mm.coeff[channels[k]][r]);
    let mut sums = Mat::<f64>::zeros(kernels.nrows(), channels.len());
    faer::linalg::matmul::matmul(
        sums.as_mut(),
        faer::Accum::Replace,
        kernels.as_ref(),
        coeff.as_ref(),
        1.0,
        faer::Par::Seq,
    );
    // libm's SSE-encoded functions follow (see vector_state).
    crate::solvers::vector_state::clear();
    sums
}

/// d_r(ω) of one mode ([`Damping::modal_denominator`], λ_r = ω_r²) and
/// ∂d_r/∂λ_r: modal ∂(2ζω_rω)/∂λ_r = ζω/ω_r, Rayleigh βω, hysteretic η (0
/// where λ_r ≤ 0, which the damping term counts as 0).
pub fn denominator(lam: f64, w: f64, damping: Damping) -> (c64, c64) {
    let wr = lam.max(0.0).sqrt();
    let slope = match damping {
        Damping::None => 0.0,
        Damping::Modal { zeta } if wr > 0.0 => zeta * w / wr,
        Damping::Rayleigh { beta, .. } if lam > 0.0 => beta * w,
        Damping::Hysteretic { eta } if lam > 0.0 => eta,
        _ => 0.0,
    };
    (damping.modal_denominator(lam, w), c64::new(1.0, slope))
}

/// Weighted log residuals (magnitude and phase) over the masked points.
pub fn residuals(pred: &[Vec<c64>], data: &TestData, mask: &Mask) -> Vec<f64> {
    let mut r = Vec::new();
    for (c, p) in pred.iter().enumerate() {
        if !mask.channels[c] {
            continue;
        }
        for (l, hm) in p.iter().enumerate() {
            let w = data.weight[c][l];
            if !mask.lines[l] || w == 0.0 {
                continue;
            }
            let (a, b) = log_ratio(*hm / data.values[c][l]).unwrap_or((10.0, std::f64::consts::PI));
            r.push(w * a);
            r.push(w * b);
        }
    }
    r
}

/// ln z = (ln|z|, arg z) of a model-to-data ratio, or `None` where it is
/// not finite or zero (the residual is then a fixed penalty that does not
/// depend on the model). ln|z| = ½ ln|z|² where |z|² is a normal number;
/// hypot's scaling only where it would under- or overflow.
pub fn log_ratio(ratio: c64) -> Option<(f64, f64)> {
    let n2 = ratio.norm_sqr();
    if n2.is_normal() {
        Some((0.5 * n2.ln(), ratio.arg()))
    } else if ratio.re.is_finite() && ratio.im.is_finite() && ratio.norm() > 0.0 {
        Some((ratio.norm().ln(), ratio.arg()))
    } else {
        None
    }
}

/// Whether [`log_ratio`] of `ratio` is defined (finite and not zero),
/// without the logarithm: the same conditions, in the same order.
pub fn has_log_ratio(ratio: c64) -> bool {
    ratio.norm_sqr().is_normal()
        || (ratio.re.is_finite() && ratio.im.is_finite() && ratio.norm() > 0.0)
}

/// Noise-level cost J0 of a mask: mean expected squared residual from noise.
pub fn noise_level(data: &TestData, mask: &Mask) -> f64 {
    let mut s = 0.0;
    let mut n = 0usize;
    for (c, nc) in data.noise_r2.iter().enumerate() {
        if !mask.channels[c] {
            continue;
        }
        for (l, &v) in nc.iter().enumerate() {
            if mask.lines[l] && data.weight[c][l] > 0.0 {
                s += 2.0 * v;
                n += 2;
            }
        }
    }
    if n == 0 {
        0.0
    } else {
        s / n as f64
    }
}

/// The mean squared residual of the data rows of `r`, which ends in
/// `prior_rows` prior rows ([`ParameterPrior::push_rows`]): the cost every
/// comparison of fits uses, with or without priors.
pub fn data_mean_sq(r: &[f64], prior_rows: usize) -> f64 {
    mean_sq(&r[..r.len().saturating_sub(prior_rows)])
}

pub fn mean_sq(r: &[f64]) -> f64 {
    if r.is_empty() {
        return f64::INFINITY;
    }
    r.iter().map(|x| x * x).sum::<f64>() / r.len() as f64
}

/// The damping model families and their log-scale parameters.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DampingForm {
    /// ζ (same ratio in every mode).
    Modal,
    /// α (1/s), β (s): C = αM + βK.
    Rayleigh,
    /// η: K(1 + iη).
    Hysteretic,
}

impl DampingForm {
    pub fn name(self) -> &'static str {
        match self {
            DampingForm::Modal => "modal",
            DampingForm::Rayleigh => "rayleigh",
            DampingForm::Hysteretic => "hysteretic",
        }
    }
    /// Parameter names as written in `diagnosis.json`.
    pub fn parameter_names(self) -> &'static [&'static str] {
        match self {
            DampingForm::Modal => &["zeta"],
            DampingForm::Rayleigh => &["alpha", "beta"],
            DampingForm::Hysteretic => &["eta"],
        }
    }
    /// Damping from log parameters.
    pub fn damping(self, x: &[f64]) -> Damping {
        match self {
            DampingForm::Modal => Damping::Modal { zeta: x[0].exp() },
            DampingForm::Rayleigh => Damping::Rayleigh {
                alpha: x[0].exp(),
                beta: x[1].exp(),
            },
            DampingForm::Hysteretic => Damping::Hysteretic { eta: x[0].exp() },
        }
    }
    /// ∂D/∂x_k of the damping term D(λ, ω) of [`denominator`] with respect
    /// to the log parameters x, given `e` = [`Self::exp_parameters`]`(x)`:
    /// modal D = 2ζ√λ·ω (∂/∂ln ζ = D), Rayleigh D = ω(α + βλ) (ωα, ωβλ),
    /// hysteretic D = ηλ (ηλ).
    pub fn term_derivatives(self, e: [f64; 2], lam: f64, w: f64) -> [f64; 2] {
        let l = lam.max(0.0);
        match self {
            DampingForm::Modal => [2.0 * e[0] * l.sqrt() * w, 0.0],
            DampingForm::Rayleigh => [w * e[0], w * e[1] * lam],
            DampingForm::Hysteretic => [e[0] * l, 0.0],
        }
    }
    /// The damping parameters e^x of the log parameters `x` (0 where there
    /// is no second one), computed once for loops over lines and modes.
    pub fn exp_parameters(x: &[f64]) -> [f64; 2] {
        [x[0].exp(), x.get(1).map_or(0.0, |v| v.exp())]
    }
    /// Log parameters giving about ζ at the centre of the band ω_c (rad/s).
    pub fn start(self, zeta: f64, w_c: f64) -> Vec<f64> {
        match self {
            DampingForm::Modal => vec![zeta.ln()],
            DampingForm::Rayleigh => vec![(zeta * w_c).ln(), (zeta / w_c).ln()],
            DampingForm::Hysteretic => vec![(2.0 * zeta).ln()],
        }
    }
    /// Log bounds for a band [ω_lo, ω_hi].
    pub fn bounds(self, w_lo: f64, w_hi: f64) -> (Vec<f64>, Vec<f64>) {
        match self {
            DampingForm::Modal => (vec![1e-4f64.ln()], vec![0.3f64.ln()]),
            DampingForm::Hysteretic => (vec![2e-4f64.ln()], vec![0.6f64.ln()]),
            DampingForm::Rayleigh => (
                vec![(1e-6 * w_hi).ln(), (1e-6 / w_hi).ln()],
                vec![(0.6 * w_hi).ln(), (0.6 / w_lo).ln()],
            ),
        }
    }
    /// The form and log parameters of a deck's damping, if any, for a test
    /// band [ω_lo, ω_hi] (rad/s). A Rayleigh coefficient of 0 (damping
    /// proportional to the mass or to the stiffness alone) starts at its
    /// lower bound of [`Self::bounds`], where it adds ζ ≤ 5e-7·ω_hi/ω_lo:
    /// a log parameter cannot hold 0, and taking such a deck for one
    /// without damping replaced its form by modal damping (a constant ζ
    /// cannot follow βω/2 from suspension modes at 1 Hz to elastic ones at
    /// 100 Hz: seed 12's update case 082 ended at 49× the noise level).
    pub fn of(d: Damping, w_lo: f64, w_hi: f64) -> Option<(DampingForm, Vec<f64>)> {
        match d {
            Damping::Modal { zeta } if zeta > 0.0 => Some((DampingForm::Modal, vec![zeta.ln()])),
            Damping::Hysteretic { eta } if eta > 0.0 => {
                Some((DampingForm::Hysteretic, vec![eta.ln()]))
            }
            Damping::Rayleigh { alpha, beta }
                if alpha >= 0.0 && beta >= 0.0 && alpha + beta > 0.0 =>
            {
                let (lo, _) = DampingForm::Rayleigh.bounds(w_lo, w_hi);
                let x = vec![alpha.ln().max(lo[0]), beta.ln().max(lo[1])];
                Some((DampingForm::Rayleigh, x))
            }
            _ => None,
        }
    }
}

pub use super::lm::{std_devs, LmOutcome};

/// Bounded Levenberg–Marquardt on `f` with forward differences
/// ([`super::lm::lm`]).
pub fn lm<F>(f: F, x0: &[f64], lo: &[f64], hi: &[f64], max_iter: usize) -> Option<LmOutcome>
where
    F: FnMut(&[f64]) -> Option<Vec<f64>>,
{
    super::lm::lm_differences(f, x0, lo, hi, max_iter)
}

/// Current damping model of a fit: its form and log parameters.
#[derive(Clone, Debug, PartialEq)]
pub struct DampingState {
    pub form: DampingForm,
    pub x: Vec<f64>,
}

impl DampingState {
    pub fn damping(&self) -> Damping {
        self.form.damping(&self.x)
    }
}

pub use super::damping_fit::{damping_jacobian, damping_std, fit_damping};

/// Fit the deck's own parameters (relative changes p̄, within the deck's
/// `param` bounds, with its priors as in [`super::estimate`]) and the
/// damping together by Levenberg–Marquardt on the log-FRF residuals: a
/// polish after the paper's update, which works on a few updating
/// frequencies only. Returns the values, the damping and the data's mean
/// squared residual at them ([`data_mean_sq`]: the prior shapes the fit,
/// costs compare data), or `None` if the deck has no parameter or nothing
/// improved.
pub fn fit_deck_parameters(
    deck: &Deck,
    start: &ParameterValues,
    damp: &DampingState,
    data: &TestData,
    mask: &Mask,
    max_iter: usize,
    evaluations: &std::sync::atomic::AtomicUsize,
) -> Option<(ParameterValues, DampingState, f64)> {
    let names = model::parameter_names(deck);
    if names.is_empty() {
        return None;
    }
    let np = names.len();
    let priors = ParameterPrior::of_deck(deck);
    let prior_scale = ParameterPrior::row_scale(noise_level(data, mask));
    let (w_lo, w_hi) = data.band();
    let (dlo, dhi) = damp.form.bounds(w_lo, w_hi);
    let mut x0: Vec<f64> = names
        .iter()
        .map(|n| start.get(n).copied().unwrap_or(0.0))
        .collect();
    x0.extend(damp.x.iter().copied());
    let mut lo: Vec<f64> = priors.iter().map(|p| p.min).collect();
    lo.extend(dlo);
    let mut hi: Vec<f64> = priors.iter().map(|p| p.max).collect();
    hi.extend(dhi);
    let form = damp.form;
    let mut cache: Option<(Vec<f64>, ModalModel)> = None;
    let f = |x: &[f64]| -> Option<Vec<f64>> {
        let p = &x[..np];
        let fresh = cache.as_ref().is_none_or(|(k, _)| k.as_slice() != p);
        if fresh {
            let values: ParameterValues = names.iter().cloned().zip(p.iter().copied()).collect();
            evaluations.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
            model::build(deck, &values).ok()?;
            let d = model::updated_deck(deck, &values);
            let mm = modal_model(&d, data).ok()?;
            cache = Some((p.to_vec(), mm));
        }
        let mm = &cache.as_ref()?.1;
        let mut r = residuals(&predict(mm, form.damping(&x[np..]), data, mask), data, mask);
        ParameterPrior::push_rows(&priors, p, prior_scale, &mut r);
        Some(r)
    };
    // Large parameter sets: fewer iterations (each Jacobian is np model solutions).
    let iters = if np > 8 { max_iter.min(3) } else { max_iter };
    let out = lm(f, &x0, &lo, &hi, iters)?;
    let values: ParameterValues = names
        .iter()
        .cloned()
        .zip(out.x[..np].iter().copied())
        .collect();
    Some((
        values,
        DampingState {
            form,
            x: out.x[np..].to_vec(),
        },
        data_mean_sq(&out.residuals, ParameterPrior::rows(&priors)),
    ))
}

/// Cap of one resonance's log frequency misfit: a resonance paired with a
/// model mode a factor 2 away counts as unpaired.
const FREQ_CAP: f64 = std::f64::consts::LN_2;

/// Natural frequencies (rad/s) of the modes that show in the measured
/// channels and lie near the measured band, ascending. A mode shows when its
/// peak in the measured kind, |a_cr|·ω_r^(order−2) for equal damping, reaches
/// 10⁻³ of the largest one (an axial mode under transverse sensors does not).
pub fn visible_omegas(mm: &ModalModel, data: &TestData) -> Vec<f64> {
    visible_modes(mm, data)
        .into_iter()
        .map(|(_, w)| w)
        .collect()
}

/// [`visible_omegas`] with each mode's index in `mm`.
pub fn visible_modes(mm: &ModalModel, data: &TestData) -> Vec<(usize, f64)> {
    let w_lo = 0.5 * data.omegas.first().copied().unwrap_or(0.0);
    let w_hi = 1.5 * data.omegas.last().copied().unwrap_or(0.0);
    let peaks: Vec<(usize, f64, f64)> = mm
        .omega2
        .iter()
        .enumerate()
        .filter_map(|(r, &w2)| {
            let w = w2.max(0.0).sqrt();
            if w < w_lo.max(1e-9) || w > w_hi {
                return None;
            }
            let a = mm.coeff.iter().map(|c| c[r].abs()).fold(0.0, f64::max);
            Some((r, w, a * w.powi(data.kind.order() - 2)))
        })
        .collect();
    let top = peaks.iter().map(|p| p.2).fold(0.0, f64::max);
    peaks
        .into_iter()
        .filter(|p| p.2 > 1e-3 * top)
        .map(|p| (p.0, p.1))
        .collect()
}

/// Resonance-frequency residuals ln(ω_model/ω_test), one per measured
/// resonance: visible model modes are paired with the measured resonances in
/// order, skipping model modes freely and measured ones at the cost of a
/// capped misfit (ln 2), by dynamic programming (a sequence alignment). The
/// squared sum is smooth in the model's parameters except where the pairing
/// changes, unlike the FRF misfit, which is flat or rough when peaks are far
/// apart: this is the coarse stage of a fit.
pub fn frequency_residuals(mm: &ModalModel, data: &TestData) -> Vec<f64> {
    frequency_alignment(mm, data)
        .into_iter()
        .map(|(r, _)| r)
        .collect()
}

/// [`frequency_residuals`] with the index (in `mm`) of the mode each
/// resonance is paired with (`None`: unpaired, or the misfit is capped).
pub fn frequency_alignment(mm: &ModalModel, data: &TestData) -> Vec<(f64, Option<usize>)> {
    let test: Vec<f64> = data
        .resonances
        .iter()
        .map(|r| 2.0 * std::f64::consts::PI * r.frequency_hz)
        .collect();
    let visible = visible_modes(mm, data);
    let model: Vec<f64> = visible.iter().map(|v| v.1).collect();
    let (n, k) = (test.len(), model.len());
    let cap2 = FREQ_CAP * FREQ_CAP;
    let pair = |i: usize, j: usize| (model[j] / test[i]).ln().clamp(-FREQ_CAP, FREQ_CAP);
    // cost[i][j]: best alignment of the first i resonances with the first j modes.
    let mut cost = vec![vec![0.0f64; k + 1]; n + 1];
    for i in 1..=n {
        cost[i][0] = cost[i - 1][0] + cap2;
        for j in 1..=k {
            let skip_mode = cost[i][j - 1];
            let skip_test = cost[i - 1][j] + cap2;
            let matched = cost[i - 1][j - 1] + pair(i - 1, j - 1).powi(2);
            cost[i][j] = skip_mode.min(skip_test).min(matched);
        }
    }
    let mut r = vec![(FREQ_CAP, None); n];
    let (mut i, mut j) = (n, k);
    while i > 0 && j > 0 {
        let here = cost[i][j];
        if here == cost[i - 1][j - 1] + pair(i - 1, j - 1).powi(2) {
            let v = pair(i - 1, j - 1);
            let capped = v.abs() >= FREQ_CAP;
            r[i - 1] = (v, (!capped).then_some(visible[j - 1].0));
            i -= 1;
            j -= 1;
        } else if here == cost[i][j - 1] {
            j -= 1;
        } else {
            i -= 1;
        }
    }
    r
}

/// Where a damping fit starts: the deck's damping model and values, or, when
/// the deck has none, modal damping at the median half-power ζ of the
/// measured resonances.
pub fn start_damping(deck_damping: Damping, data: &TestData) -> DampingState {
    let (w_lo, w_hi) = data.band();
    DampingForm::of(deck_damping, w_lo, w_hi)
        .map(|(form, x)| DampingState { form, x })
        .unwrap_or_else(|| {
            let wc = (w_lo * w_hi).sqrt();
            DampingState {
                form: DampingForm::Modal,
                x: DampingForm::Modal.start(data.half_power_zeta(), wc),
            }
        })
}
