//! The updating iteration (§3.1): at the current parameters p̄^n build the
//! model, compute its lowest modes, reduce by SEREP, form A p = b (Eq. 11–12,
//! optionally with Eq. 18–22), solve it by the truncated SVD (Eq. 41), and
//! compose p̄^{n+1} = p̄^n + p^{n+1} + p̄^n p^{n+1} (Eq. 29); stop when
//! max_j |p_j| < tol (Eq. 49).
//!
//! Safeguards: a step with 1 + p_j ≤ 0 (a property would become ≤ 0) is halved
//! until every 1 + p_j ≥ 0.1; if the SFDAC mean falls for two iterations in a
//! row, or a |p̄_j| exceeds `max_parameter`, the iteration stops and the best
//! iteration (highest SFDAC mean) is returned. When the iteration limit is hit
//! the best iteration is returned too.
//!
//! Combining the two kinds of equation (Eq. 21–22): each block is divided by
//! the Frobenius norm of its sensitivity matrix (A_h/‖A_h‖_F, b_h/‖A_h‖_F and
//! likewise for A_ω, b_ω), so neither dominates and each block's own solution
//! is unchanged. Before that, with `FrfWeighting::PerFrequency` (default),
//! each frequency block A_i, b_i is divided by ‖h̄_i‖ so that every updating
//! frequency counts alike; `FrfWeighting::None` keeps the paper's raw rows.

use faer::Mat;
use frfup_parsers::deck::Deck;

use super::correlation::{fdac_matrix, pair_modes, SfdacSummary};
use super::frequencies::{indicator, pick_peaks, PeakOptions, Resonance, UpdatingFrequencies};
use super::identify::{identify_modes, IdentifyOptions};
use super::measured::MeasuredDofs;
use super::sensitivity::{frequency_equation, frf_equations, ModalSensitivities};
use super::serep::{InverseMethod, SerepBasis};
use super::svd_solve::solve_gap_rule;
use super::{
    FrfWeighting, IterationRecord, ResonanceMethod, StopReason, UpdateError, UpdateMethod,
    UpdateOptions, UpdateResult, UpdateWarning,
};
use crate::model::{self, FeModel, ModelError, ParameterValues};
use crate::solvers::eigen::{lowest_modes, EigenOptions, Modes};
use crate::testdata::MeasuredFrfs;

const TWO_PI: f64 = 2.0 * std::f64::consts::PI;

/// Update the parameters of `deck` so that its FRFs match `test`.
pub fn update(
    deck: &Deck,
    test: &MeasuredFrfs,
    opts: &UpdateOptions,
) -> Result<UpdateResult, UpdateError> {
    update_with_progress(deck, test, opts, &mut |_| {})
}

/// [`update`], calling `progress` after every scored iteration.
pub fn update_with_progress(
    deck: &Deck,
    test: &MeasuredFrfs,
    opts: &UpdateOptions,
    progress: &mut dyn FnMut(&IterationRecord),
) -> Result<UpdateResult, UpdateError> {
    match opts.method {
        UpdateMethod::Paper => update_model(
            &mut |values| model::build(deck, values),
            test,
            opts,
            progress,
        ),
        UpdateMethod::Robust => super::robust::update_robust(deck, test, opts, progress),
    }
}

/// The iteration on any model source: `build` assembles the FE model at the
/// given relative parameter changes (p̄, deck order names).
pub fn update_model(
    build: &mut dyn FnMut(&ParameterValues) -> Result<FeModel, ModelError>,
    test: &MeasuredFrfs,
    opts: &UpdateOptions,
    progress: &mut dyn FnMut(&IterationRecord),
) -> Result<UpdateResult, UpdateError> {
    check_options(opts)?;
    let (column, layout) = crate::testdata::layout::as_column(test);
    let test = &column;
    let mut warnings = Vec::new();
    let model0 = build(&ParameterValues::new()).map_err(UpdateError::Model)?;
    let names: Vec<String> = model0.parameters.iter().map(|p| p.name.clone()).collect();
    if names.is_empty() {
        return Err(UpdateError::NoParameters);
    }
    let np = names.len();
    let meas = MeasuredDofs::new(&model0, test, &mut warnings)?;
    let n_ex = meas.len();

    // Measured resonances and updating frequencies (Eq. 42).
    let ind = indicator(&meas.mobility);
    let (mut peaks, mut fitted_shapes): (Vec<Resonance>, Option<Vec<Vec<f64>>>) =
        match opts.resonance_method {
            ResonanceMethod::PeakPicking => (
                pick_peaks(
                    &meas.lines_hz,
                    &ind,
                    &PeakOptions {
                        min_prominence: opts.min_prominence,
                    },
                ),
                None,
            ),
            ResonanceMethod::ModalFit => {
                let modes = identify_modes(
                    &meas.lines_hz,
                    &meas.receptance,
                    &ind,
                    &IdentifyOptions::default(),
                );
                if modes.is_empty() {
                    // No pole fits (e.g. an undamped model's FRFs): the peaks.
                    let peaks = pick_peaks(
                        &meas.lines_hz,
                        &ind,
                        &PeakOptions {
                            min_prominence: opts.min_prominence,
                        },
                    );
                    (peaks, None)
                } else {
                    (
                        modes.iter().map(|m| m.resonance()).collect(),
                        Some(modes.into_iter().map(|m| m.shape).collect()),
                    )
                }
            }
        };
    // A free-free model tested on a suspension: test resonances below half the
    // first elastic natural frequency of the initial model are suspension
    // (rigid-body) modes, which the FE model cannot reproduce; leave them out.
    // The probe solves model0 for at least as many modes as iteration 0 needs
    // (the basis size only shrinks when peaks are left out), which reuses them.
    let mut modes0: Option<Modes> = None;
    if !model0.has_fixed_dofs && !peaks.is_empty() {
        let r_upper = resonances_used(opts, peaks.len(), n_ex);
        let explicit = opts.frequencies_hz.as_ref().map(|f| f.len());
        let n_eig_upper = eigen_count(
            basis_size(opts, r_upper, explicit, n_ex),
            peaks.len(),
            model0.dofs.len(),
        );
        let probe = lowest_modes(
            &model0.stiffness,
            &model0.mass,
            &EigenOptions {
                count: n_eig_upper.max(12).min(model0.dofs.len()),
                ..EigenOptions::default()
            },
        )
        .map_err(UpdateError::Eigen)?;
        // The first-elastic test looks at the 12 lowest modes, as before the
        // probe also served iteration 0.
        let f: Vec<f64> = probe.frequencies_hz().into_iter().take(12).collect();
        modes0 = Some(probe);
        let f_last = f.last().copied().unwrap_or(0.0);
        if let Some(&f_elastic) = f.iter().find(|&&x| x > 0.1 && x > 1e-3 * f_last) {
            let suspension: Vec<f64> = peaks
                .iter()
                .map(|r| r.frequency_hz)
                .filter(|&x| x < 0.5 * f_elastic)
                .collect();
            if !suspension.is_empty() {
                if let Some(shapes) = fitted_shapes.as_mut() {
                    let keep: Vec<bool> = peaks
                        .iter()
                        .map(|r| r.frequency_hz >= 0.5 * f_elastic)
                        .collect();
                    let mut k = keep.iter();
                    shapes.retain(|_| *k.next().unwrap_or(&true));
                }
                peaks.retain(|r| r.frequency_hz >= 0.5 * f_elastic);
                warnings.push(UpdateWarning::SuspensionModes {
                    modes_hz: suspension,
                    first_elastic_hz: f_elastic,
                });
            }
        }
    }
    let r_used = resonances_used(opts, peaks.len(), n_ex);
    let updating = match &opts.frequencies_hz {
        Some(f) => UpdatingFrequencies::explicit(f, &meas.lines_hz),
        None => {
            if peaks.is_empty() {
                return Err(UpdateError::NoResonances);
            }
            UpdatingFrequencies::around_resonances(&peaks, r_used, opts.offset, &meas.lines_hz)
        }
    };
    for s in &updating.skipped {
        warnings.push(UpdateWarning::SkippedFrequency(s.clone()));
    }
    if updating.is_empty() {
        return Err(UpdateError::NoUpdatingFrequencies {
            skipped: updating.skipped.clone(),
        });
    }
    let omegas: Vec<f64> = updating.frequencies.iter().map(|u| TWO_PI * u.hz).collect();
    let h_test: Vec<Vec<f64>> = updating
        .frequencies
        .iter()
        .map(|u| meas.at_line(u.line))
        .collect();
    let test_shapes: Vec<Vec<f64>> = match fitted_shapes {
        Some(shapes) => shapes,
        None => peaks
            .iter()
            .map(|r| meas.deflection_shape(r.line))
            .collect(),
    };
    let test_hz: Vec<f64> = peaks.iter().map(|r| r.frequency_hz).collect();

    let n_md = basis_size(
        opts,
        r_used,
        opts.frequencies_hz.as_ref().map(|_| updating.len()),
        n_ex,
    );
    if let Some(m) = opts.modes {
        if m > n_ex {
            warnings.push(UpdateWarning::FewerModes {
                requested: m,
                used: n_ex,
            });
        }
    }
    let n_eig = eigen_count(n_md, peaks.len(), model0.dofs.len());

    let mut records: Vec<IterationRecord> = Vec::new();
    let mut p_bar = vec![0.0; np];
    let mut step = vec![0.0; np];
    let mut step_scale = 1.0;
    let mut rank = 0;
    let mut singular_values = Vec::new();
    let mut model = Some(model0);
    let mut stop = StopReason::IterationLimit;
    let mut fe_frfs_initial = Vec::new();
    let mut fe_frfs_last = Vec::new();
    // FE FRFs of the iteration with the highest mean SFDAC so far (`best_index`).
    let mut fe_frfs_best = Vec::new();
    let mut warned_null = false;
    let mut warned_fewer = false;
    // Frequencies-first stage: while the paired resonances are far off, FRF
    // equations at (1 ± cξ)ω̄ sit next to FE poles and mislead; solve the
    // natural-frequency equations (Eq. 18) alone until they are close.
    let mut frequency_stage = opts.frequencies_first;
    // Levenberg–Marquardt scale of the step damping: halved after a step that
    // raised the mean SFDAC, quadrupled after one that lowered it.
    let mut damping_scale = 1.0f64;

    for n in 0..=opts.max_iter {
        let fe = match model.take() {
            Some(m) => m,
            None => {
                let values: ParameterValues =
                    names.iter().cloned().zip(p_bar.iter().copied()).collect();
                build(&values).map_err(UpdateError::Model)?
            }
        };
        let modes = match modes0.take().filter(|m| m.len() >= n_eig) {
            Some(m) => leading_modes(m, n_eig),
            None => lowest_modes(
                &fe.stiffness,
                &fe.mass,
                &EigenOptions {
                    count: n_eig,
                    expect_no_rigid_body_modes: fe.has_fixed_dofs,
                    ..EigenOptions::default()
                },
            )
            .map_err(UpdateError::Eigen)?,
        };
        let fe_hz = modes.frequencies_hz();
        let basis = SerepBasis::select(&modes, &meas.equations, n_md, opts.basis_tolerance)
            .map_err(UpdateError::Serep)?;
        if n == 0 {
            let dropped: Vec<f64> = basis
                .dropped
                .iter()
                .filter(|&&r| r < *basis.modes.last().unwrap_or(&0))
                .map(|&r| fe_hz[r])
                .collect();
            if !dropped.is_empty() {
                warnings.push(UpdateWarning::DroppedModes {
                    iteration: 0,
                    modes_hz: dropped,
                });
            }
            for u in &updating.frequencies {
                if let Some(f) = fe_hz.iter().find(|&&f| (f - u.hz).abs() <= 0.01 * u.hz) {
                    warnings.push(UpdateWarning::NearFeResonance {
                        hz: u.hz,
                        fe_hz: *f,
                    });
                }
            }
        }
        if basis.len() < n_md && !warned_fewer {
            warned_fewer = true;
            warnings.push(UpdateWarning::FewerModes {
                requested: n_md,
                used: basis.len(),
            });
        }
        let sens = ModalSensitivities::project(&fe.parameters, modes.shapes.as_ref(), &basis.modes);
        let eqs = frf_equations(
            &basis,
            &sens,
            &omegas,
            &h_test,
            meas.excitation_row,
            opts.inverse,
        )
        .map_err(UpdateError::Sensitivity)?;
        let sfdac = SfdacSummary::new(&eqs.fe_frf, &h_test);
        let fe_shapes: Vec<Vec<f64>> = (0..modes.len())
            .map(|r| {
                meas.equations
                    .iter()
                    .map(|&i| modes.shapes[(i, r)])
                    .collect()
            })
            .collect();
        let pairs = pair_modes(&test_shapes, &test_hz, &fe_shapes, &fe_hz, opts.mac_min);
        if n == 0 {
            fe_frfs_initial = eqs.fe_frf.clone();
            for (t, p) in pairs.iter().enumerate().take(r_used.max(1)) {
                if p.is_none() {
                    warnings.push(UpdateWarning::UnpairedResonance {
                        resonance: t,
                        hz: test_hz[t],
                    });
                }
            }
        }
        if records.is_empty() || sfdac.mean > records[best_index(&records)].sfdac.mean {
            fe_frfs_best = eqs.fe_frf.clone();
        }
        fe_frfs_last = eqs.fe_frf.clone();
        let record = IterationRecord {
            index: n,
            parameters: p_bar.clone(),
            step: step.clone(),
            step_scale,
            rank,
            singular_values: std::mem::take(&mut singular_values),
            sfdac,
            fe_frequencies_hz: fe_hz.clone(),
            basis_modes: basis.modes.clone(),
            pairs: pairs.clone(),
        };
        progress(&record);
        records.push(record);

        // Leave the frequency stage once every paired resonance used is within
        // `FREQUENCY_STAGE_EXIT` (relative).
        let was_frequency_stage = frequency_stage;
        if frequency_stage {
            let worst = pairs
                .iter()
                .take(r_used)
                .enumerate()
                .filter_map(|(t, p)| {
                    p.as_ref()
                        .filter(|p| p.mac >= FREQUENCY_STAGE_MAC)
                        .map(|p| ((p.fe_hz - test_hz[t]) / test_hz[t]).abs())
                })
                .fold(0.0f64, f64::max);
            // With fitted shapes the stage also matches mode shapes: stay until
            // its steps are small as well (at most FREQUENCY_STAGE_ITERATIONS).
            let settled = opts.resonance_method != ResonanceMethod::ModalFit
                || step.iter().fold(0.0f64, |a, p| a.max(p.abs())) < opts.tol.max(0.01)
                || n >= FREQUENCY_STAGE_ITERATIONS;
            if worst < FREQUENCY_STAGE_EXIT && (n > 0 && settled) {
                frequency_stage = false;
            }
        }

        // Stopping rules.
        let max_step = step.iter().fold(0.0f64, |a, p| a.max(p.abs()));
        if n > 0 && max_step < opts.tol && !was_frequency_stage {
            stop = StopReason::Converged;
            break;
        }
        if n >= 2 && !was_frequency_stage {
            let m: Vec<f64> = records[n - 2..=n].iter().map(|r| r.sfdac.mean).collect();
            if m[2] < m[1] - 1e-5 && m[1] < m[0] - 1e-5 {
                stop = StopReason::Diverged;
                warnings.push(UpdateWarning::Diverged {
                    iteration: n,
                    best: best_index(&records),
                });
                break;
            }
        }
        if n == opts.max_iter {
            warnings.push(UpdateWarning::NotConverged {
                iterations: n,
                last_step: max_step,
            });
            break;
        }

        // Assemble and solve A p = b.
        let (a, b) = if frequency_stage {
            let mut rows = frequency_rows(&fe, &modes, &pairs, &test_hz, r_used);
            if opts.resonance_method == ResonanceMethod::ModalFit {
                append_shape_rows(
                    &mut rows,
                    &fe,
                    &modes,
                    &pairs,
                    &test_shapes,
                    &meas.equations,
                    r_used,
                );
            }
            rows
        } else {
            assemble(
                &eqs.a, &eqs.b, &h_test, opts, &fe, &modes, &pairs, &test_hz, r_used,
            )
        };
        let mut sol = solve_gap_rule(a.as_ref(), &b, opts.svd_eps).map_err(UpdateError::Svd)?;
        if n > 0 {
            let (prev, now) = (records[n - 1].sfdac.mean, records[n].sfdac.mean);
            damping_scale = if now >= prev {
                (damping_scale * 0.5).max(0.01)
            } else {
                (damping_scale * 4.0).min(16.0)
            };
        }
        let damping = damping_scale
            * if frequency_stage {
                FREQUENCY_STAGE_DAMPING
            } else {
                opts.damping
            };
        if damping > 0.0 {
            // Damped least squares (rows μ I, μ = FREQUENCY_STAGE_DAMPING σ₁):
            // a resonance that no parameter moves much (a suspension mode, a
            // mode the parameters barely touch) must not buy its last per cent
            // with huge changes of insensitive parameters.
            let mu = damping * sol.singular_values.first().copied().unwrap_or(0.0);
            if mu > 0.0 {
                let (m, np_) = (a.nrows(), a.ncols());
                let aug = Mat::from_fn(m + np_, np_, |i, j| {
                    if i < m {
                        a[(i, j)]
                    } else if i - m == j {
                        mu
                    } else {
                        0.0
                    }
                });
                let mut b_aug = b.clone();
                b_aug.resize(m + np_, 0.0);
                let damped =
                    solve_gap_rule(aug.as_ref(), &b_aug, opts.svd_eps).map_err(UpdateError::Svd)?;
                sol.step = damped.step;
            }
        }
        if !sol.null_space.is_empty() && !warned_null {
            warned_null = true;
            let combinations = sol
                .null_space
                .iter()
                .map(|v| {
                    let vmax = v.iter().fold(0.0f64, |a, x| a.max(x.abs()));
                    names
                        .iter()
                        .zip(v)
                        .filter(|(_, x)| x.abs() >= 0.1 * vmax)
                        .map(|(nm, x)| (nm.clone(), *x))
                        .collect()
                })
                .collect();
            warnings.push(UpdateWarning::Indistinguishable {
                iteration: n,
                combinations,
            });
        }
        rank = sol.rank;
        singular_values = sol.singular_values;
        let mut p = sol.step;
        // Trust region of the frequency stage: the linearisation (Eq. 17) holds
        // for small changes only.
        if frequency_stage {
            let big = p.iter().fold(0.0f64, |a, x| a.max(x.abs()));
            if big > FREQUENCY_STAGE_MAX_STEP {
                p.iter_mut()
                    .for_each(|x| *x *= FREQUENCY_STAGE_MAX_STEP / big);
            }
        }
        // 1 + p ≤ 0 would make a property ≤ 0: halve the step.
        step_scale = 1.0;
        let bad: Vec<String> = names
            .iter()
            .zip(&p)
            .filter(|(_, &x)| 1.0 + x <= 0.0)
            .map(|(nm, _)| nm.clone())
            .collect();
        if !bad.is_empty() {
            while p.iter().any(|&x| 1.0 + step_scale * x < 0.1) && step_scale > 1e-12 {
                step_scale *= 0.5;
            }
            p.iter_mut().for_each(|x| *x *= step_scale);
            warnings.push(UpdateWarning::StepLimited {
                iteration: n + 1,
                scale: step_scale,
                parameters: bad,
            });
        }
        for (pb, x) in p_bar.iter_mut().zip(&p) {
            *pb = *pb + x + *pb * x; // Eq. 29
        }
        step = p;
        if let Some((j, v)) = p_bar
            .iter()
            .enumerate()
            .find(|(_, v)| !v.is_finite() || v.abs() > opts.max_parameter)
        {
            stop = StopReason::ParameterExploded;
            warnings.push(UpdateWarning::ParameterExploded {
                iteration: n + 1,
                name: names[j].clone(),
                value: *v,
                best: best_index(&records),
            });
            break;
        }
    }

    // The converged iterate (Eq. 49), else the best one (highest SFDAC mean).
    let final_iteration = match stop {
        StopReason::Converged => records.len() - 1,
        _ => best_index(&records),
    };
    let fdac_initial = fdac_matrix(&fe_frfs_initial, &h_test);
    let fdac_final = if final_iteration == records.len() - 1 {
        fdac_matrix(&fe_frfs_last, &h_test)
    } else {
        fdac_matrix(&fe_frfs_best, &h_test)
    };
    Ok(UpdateResult {
        converged: stop == StopReason::Converged,
        stop,
        parameter_names: names,
        final_iteration,
        iterations: records,
        resonances: peaks,
        resonances_used: r_used,
        updating_frequencies: updating,
        modes: n_md,
        measured_dofs: meas.labels.clone(),
        excitation: meas.excitation_label.clone(),
        fdac_initial,
        fdac_final,
        warnings,
        options: opts.clone(),
        layout,
        estimate: None,
    })
}

/// R, the measured resonances the updating frequencies are placed around:
/// `--resonances`, else all found up to the measured DOFs and at most 8.
fn resonances_used(opts: &UpdateOptions, peaks: usize, n_ex: usize) -> usize {
    match opts.resonances {
        Some(r) => r.min(peaks),
        None => peaks.min(n_ex).min(8),
    }
}

/// N_md, the SEREP basis size: `--modes`, else max(2R', R' + 4) with R' = R,
/// or with explicit frequencies max(R, their count / 2); at most the measured
/// DOFs. Monotone in both counts.
fn basis_size(
    opts: &UpdateOptions,
    r_used: usize,
    explicit_frequencies: Option<usize>,
    n_ex: usize,
) -> usize {
    let r_basis = match explicit_frequencies {
        Some(f) => r_used.max(f / 2),
        None => r_used,
    };
    opts.modes
        .unwrap_or_else(|| (2 * r_basis).max(r_basis + 4))
        .min(n_ex)
        .max(1)
}

/// How many of the lowest modes are computed per iteration: the N_md of the
/// basis plus max(N_md/2, 4) spare ones (invisible modes are skipped), and at
/// least two more than the measured resonances (for pairing).
pub fn eigen_count(n_md: usize, resonances: usize, dofs: usize) -> usize {
    (n_md + (n_md / 2).max(4)).max(resonances + 2).min(dofs)
}

/// The first `count` of `modes` (ascending frequency).
fn leading_modes(modes: Modes, count: usize) -> Modes {
    if modes.len() == count {
        return modes;
    }
    Modes {
        omega2: modes.omega2[..count].to_vec(),
        shapes: modes.shapes.get(.., ..count).to_owned(),
    }
}

/// Index of the record with the highest SFDAC mean (earliest on ties).
fn best_index(records: &[IterationRecord]) -> usize {
    let mut best = 0;
    for (i, r) in records.iter().enumerate() {
        if r.sfdac.mean > records[best].sfdac.mean {
            best = i;
        }
    }
    best
}

/// Relative changes below which the frequency stage ends, and the largest
/// parameter step it takes.
const FREQUENCY_STAGE_EXIT: f64 = 0.01;
const FREQUENCY_STAGE_MAX_STEP: f64 = 0.3;
/// Weight of the mode-shape rows against the relative ω² rows.
const SHAPE_ROW_WEIGHT: f64 = 0.3;
/// Iterations after which the first stage ends even if its steps are not small.
const FREQUENCY_STAGE_ITERATIONS: usize = 12;
/// Tikhonov damping of the frequency stage, relative to the largest singular value.
const FREQUENCY_STAGE_DAMPING: f64 = 0.05;
/// MAC a pair needs to enter the frequency stage's equations.
const FREQUENCY_STAGE_MAC: f64 = 0.8;

/// The natural-frequency equations alone (Eq. 18–20) for the paired
/// resonances, each row divided by ω̄_r² so that every mode counts alike:
/// (∂ω_r²/∂p / ω̄_r²) p = (ω̄_r² − ω_r²) / ω̄_r².
fn frequency_rows(
    fe: &FeModel,
    modes: &Modes,
    pairs: &[Option<super::ModePair>],
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
fn append_shape_rows(
    rows: &mut (Mat<f64>, Vec<f64>),
    fe: &FeModel,
    modes: &Modes,
    pairs: &[Option<super::ModePair>],
    test_shapes: &[Vec<f64>],
    equations: &[usize],
    r_used: usize,
) {
    let all: Vec<usize> = (0..modes.len()).collect();
    let sens = ModalSensitivities::project(&fe.parameters, modes.shapes.as_ref(), &all);
    let np = fe.parameters.len();
    let mut extra: Vec<(Vec<f64>, f64)> = Vec::new();
    for (t, pair) in pairs.iter().enumerate().take(r_used) {
        let Some(p) = pair.as_ref().filter(|p| p.mac >= FREQUENCY_STAGE_MAC) else {
            continue;
        };
        let r = p.fe;
        let lam = modes.omega2[r];
        let phi: Vec<f64> = equations.iter().map(|&i| modes.shapes[(i, r)]).collect();
        let test = &test_shapes[t];
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

/// A_h, b_h, plus the normalised frequency rows when asked (Eq. 21–22).
#[allow(clippy::too_many_arguments)]
fn assemble(
    a_h: &Mat<f64>,
    b_h: &[f64],
    h_test: &[Vec<f64>],
    opts: &UpdateOptions,
    fe: &FeModel,
    modes: &Modes,
    pairs: &[Option<super::ModePair>],
    test_hz: &[f64],
    r_used: usize,
) -> (Mat<f64>, Vec<f64>) {
    let mut a_h = a_h.clone();
    let mut b_h = b_h.to_vec();
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
    for (t, pair) in pairs.iter().enumerate().take(r_used) {
        // Only clear pairs: one wrong pair drives every parameter astray.
        if let Some(p) = pair.as_ref().filter(|p| p.mac >= FREQUENCY_STAGE_MAC) {
            let w2_test = (TWO_PI * test_hz[t]).powi(2);
            rows.push(frequency_equation(
                &fe.parameters,
                modes.shapes.as_ref(),
                p.fe,
                modes.omega2[p.fe],
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

fn check_options(opts: &UpdateOptions) -> Result<(), UpdateError> {
    let bad = |s: String| Err(UpdateError::InvalidOption(s));
    if !(opts.offset > 0.0 && opts.offset < 1.0) && opts.frequencies_hz.is_none() {
        return bad(format!(
            "--offset {} must be in (0, 1) (the paper uses 0.05–0.10)",
            opts.offset
        ));
    }
    if !(opts.svd_eps > 0.0 && opts.svd_eps < 1.0) {
        return bad(format!("--svd-eps {} must be in (0, 1)", opts.svd_eps));
    }
    if !(opts.tol > 0.0 && opts.tol.is_finite()) {
        return bad(format!("--tol {} must be > 0", opts.tol));
    }
    if opts.modes == Some(0) {
        return bad("--modes must be at least 1".into());
    }
    if opts.resonances == Some(0) {
        return bad("--resonances must be at least 1".into());
    }
    if let InverseMethod::Perturb { relative } = opts.inverse {
        if !(relative > 0.0 && relative.is_finite()) {
            return bad(format!("--perturbation {relative} must be > 0"));
        }
    }
    if let Some(f) = &opts.frequencies_hz {
        if f.is_empty() || f.iter().any(|x| !(x.is_finite() && *x > 0.0)) {
            return bad("--freqs needs positive frequencies in Hz".into());
        }
    }
    if !(opts.basis_tolerance >= 0.0 && opts.basis_tolerance < 1.0) {
        return bad(format!(
            "basis tolerance {} must be in [0, 1)",
            opts.basis_tolerance
        ));
    }
    if !(opts.max_parameter > 0.0) {
        return bad(format!("max parameter {} must be > 0", opts.max_parameter));
    }
    Ok(())
}
