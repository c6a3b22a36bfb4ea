//! The linear system A p = b of one step: the FRF equations (Eq. 11–12),
//! optionally with the natural-frequency equations (Eq. 18–22), or, in the
//! frequencies-first stage, the natural-frequency equations alone with
//! mode-shape rows.

use faer::Mat;

use super::prepare::Problem;
use super::state::Iterate;
use super::{FREQUENCY_STAGE_MAC, SHAPE_ROW_WEIGHT, TWO_PI};
use crate::model::FeModel;
use crate::solvers::eigen::Modes;
use crate::updating::sensitivity::{frequency_equation, ModalSensitivities};
use crate::updating::{FrfWeighting, ModePair, ResonanceMethod, UpdateOptions};

/// The frequencies-first stage's system: the natural-frequency rows of the
/// clear pairs, and with fitted shapes ([`ResonanceMethod::ModalFit`]) their
/// mode-shape rows.
pub(super) fn frequency_system(
    it: &Iterate,
    problem: &Problem,
    opts: &UpdateOptions,
) -> (Mat<f64>, Vec<f64>) {
    let mut rows = frequency_rows(
        &it.fe,
        &it.modes,
        &it.pairs,
        &problem.test_hz,
        problem.r_used,
    );
    if opts.resonance_method == ResonanceMethod::ModalFit {
        append_shape_rows(&mut rows, it, problem);
    }
    rows
}

/// The natural-frequency equations alone (Eq. 18–20) for the paired
/// resonances, each row divided by ω̄_r² so that every mode counts alike:
/// (∂ω_r²/∂p / ω̄_r²) p = (ω̄_r² − ω_r²) / ω̄_r².
fn frequency_rows(
    fe: &FeModel,
    modes: &Modes,
    pairs: &[Option<ModePair>],
    test_hz: &[f64],
    r_used: usize,
) -> (Mat<f64>, Vec<f64>) {
    let mut rows: Vec<(Vec<f64>, f64)> = Vec::new();
    for (t, pair) in pairs.iter().enumerate().take(r_used) {
        // Only clear pairs: one wrong pair drives every parameter astray.
        if let Some(p) = pair.as_ref().filter(|p| p.mac >= FREQUENCY_STAGE_MAC) {
            let w2_test = (TWO_PI * test_hz[t]).powi(2);
            let (row, b) = frequency_equation(
                &fe.parameters,
                modes.shapes.as_ref(),
                p.fe,
                modes.omega2[p.fe],
                w2_test,
            );
            rows.push((row.iter().map(|x| x / w2_test).collect(), b / w2_test));
        }
    }
    let np = fe.parameters.len();
    let a = Mat::from_fn(rows.len(), np, |i, j| rows[i].0[j]);
    (a, rows.into_iter().map(|(_, b)| b).collect())
}

/// Mode-shape rows for the clear pairs (MAC ≥ [`FREQUENCY_STAGE_MAC`]):
/// −(∂φ_r/∂p) p = φ_r − MSF·φ̄_t at the sensors, scaled by 1/‖φ_r‖ and by
/// [`SHAPE_ROW_WEIGHT`]. ∂φ_r/∂p_j by Fox and Kapoor's modal expansion over
/// the computed modes: Σ_{s≠r} φ_s φ_sᵀ(∂K_j − λ_r ∂M_j)φ_r/(λ_r − λ_s)
/// − ½ (φ_rᵀ∂M_jφ_r) φ_r. Frequencies alone see the sum of symmetric
/// parameters (left and right wing); the shapes see their difference.
fn append_shape_rows(rows: &mut (Mat<f64>, Vec<f64>), it: &Iterate, problem: &Problem) {
    let (fe, modes) = (&it.fe, &it.modes);
    let equations = &problem.meas.equations;
    let all: Vec<usize> = (0..modes.len()).collect();
    let sens = ModalSensitivities::project(&fe.parameters, modes.shapes.as_ref(), &all);
    let np = fe.parameters.len();
    let mut extra: Vec<(Vec<f64>, f64)> = Vec::new();
    for (t, pair) in it.pairs.iter().enumerate().take(problem.r_used) {
        let Some(p) = pair.as_ref().filter(|p| p.mac >= FREQUENCY_STAGE_MAC) else {
            continue;
        };
        let r = p.fe;
        let lam = modes.omega2[r];
        let phi: Vec<f64> = equations.iter().map(|&i| modes.shapes[(i, r)]).collect();
        let test = &problem.test_shapes.shapes[t];
        let tt: f64 = test.iter().map(|x| x * x).sum();
        let nphi = phi.iter().map(|x| x * x).sum::<f64>().sqrt();
        if !(tt > 0.0 && nphi > 0.0) || test.len() != phi.len() {
            continue;
        }
        let msf = phi.iter().zip(test).map(|(a, b)| a * b).sum::<f64>() / tt;
        // d[j][e]: ∂φ_r/∂p_j at sensor e.
        let mut d = vec![vec![0.0; phi.len()]; np];
        for (j, dj) in d.iter_mut().enumerate() {
            for s in 0..modes.len() {
                let c = if s == r {
                    -0.5 * sens.dm[j][(r, r)]
                } else {
                    let gap = lam - modes.omega2[s];
                    if gap.abs() < 1e-6 * lam.abs().max(1e-12) {
                        continue;
                    }
                    (sens.dk[j][(s, r)] - lam * sens.dm[j][(s, r)]) / gap
                };
                for (e, &i) in equations.iter().enumerate() {
                    dj[e] += c * modes.shapes[(i, s)];
                }
            }
        }
        for e in 0..phi.len() {
            let w = SHAPE_ROW_WEIGHT / nphi;
            extra.push((
                (0..np).map(|j| -d[j][e] * w).collect(),
                (phi[e] - msf * test[e]) * w,
            ));
        }
    }
    if extra.is_empty() {
        return;
    }
    let (a, b) = rows;
    let m0 = a.nrows();
    let a2 = Mat::from_fn(m0 + extra.len(), np, |i, j| {
        if i < m0 {
            a[(i, j)]
        } else {
            extra[i - m0].0[j]
        }
    });
    b.extend(extra.iter().map(|(_, v)| *v));
    *a = a2;
}

/// The FRF stage's system: A_h, b_h (Eq. 11–12), each frequency block
/// divided by ‖h̄_i‖ under [`FrfWeighting::PerFrequency`], plus the
/// normalised natural-frequency rows when asked (Eq. 21–22).
pub(super) fn frf_system(
    it: &Iterate,
    problem: &Problem,
    opts: &UpdateOptions,
) -> (Mat<f64>, Vec<f64>) {
    let h_test = &problem.h_test;
    let mut a_h = it.eqs.a.clone();
    let mut b_h = it.eqs.b.clone();
    if opts.weighting == FrfWeighting::PerFrequency {
        let n_ex = h_test.first().map_or(0, |h| h.len());
        for (i, h) in h_test.iter().enumerate() {
            let nrm = h.iter().map(|x| x * x).sum::<f64>().sqrt();
            if !(nrm > 0.0 && nrm.is_finite()) {
                continue;
            }
            for e in i * n_ex..(i + 1) * n_ex {
                b_h[e] /= nrm;
                for j in 0..a_h.ncols() {
                    a_h[(e, j)] /= nrm;
                }
            }
        }
    }
    if !opts.with_frequencies {
        return (a_h, b_h);
    }
    let mut rows: Vec<(Vec<f64>, f64)> = Vec::new();
    for (t, pair) in it.pairs.iter().enumerate().take(problem.r_used) {
        // Only clear pairs: one wrong pair drives every parameter astray.
        if let Some(p) = pair.as_ref().filter(|p| p.mac >= FREQUENCY_STAGE_MAC) {
            let w2_test = (TWO_PI * problem.test_hz[t]).powi(2);
            rows.push(frequency_equation(
                &it.fe.parameters,
                it.modes.shapes.as_ref(),
                p.fe,
                it.modes.omega2[p.fe],
                w2_test,
            ));
        }
    }
    let np = a_h.ncols();
    let fro = |m: &Mat<f64>| -> f64 {
        let mut s = 0.0;
        for j in 0..m.ncols() {
            for i in 0..m.nrows() {
                s += m[(i, j)] * m[(i, j)];
            }
        }
        s.sqrt()
    };
    let nh = fro(&a_h);
    let sh = if nh > 0.0 { 1.0 / nh } else { 1.0 };
    let nw = rows
        .iter()
        .flat_map(|(r, _)| r.iter())
        .map(|x| x * x)
        .sum::<f64>()
        .sqrt();
    let sw = if nw > 0.0 { 1.0 / nw } else { 1.0 };
    let mh = a_h.nrows();
    let a = Mat::from_fn(mh + rows.len(), np, |i, j| {
        if i < mh {
            a_h[(i, j)] * sh
        } else {
            rows[i - mh].0[j] * sw
        }
    });
    let mut b: Vec<f64> = b_h.iter().map(|x| x * sh).collect();
    b.extend(rows.iter().map(|(_, x)| x * sw));
    (a, b)
}
