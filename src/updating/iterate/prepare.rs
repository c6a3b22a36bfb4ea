//! What the iteration works on, fixed from the first step to the last: the
//! measured DOFs, the test's resonances and mode shapes, the updating
//! frequencies (Eq. 42) with the measured FRFs h̄ there, the SEREP basis size
//! N_md and the number of modes computed per iteration.

use faer::c64;

use super::TWO_PI;
use crate::identification::{identify_column, ColumnMode};
use crate::model::{FeModel, ModelError, ParameterValues};
use crate::solvers::eigen::{lowest_modes, EigenOptions, Modes};
use crate::testdata::{i_omega_power, FrfKind, MeasuredFrfs};
use crate::updating::frequencies::{
    indicator, pick_peaks, PeakOptions, Resonance, UpdatingFrequencies,
};
use crate::updating::measured::MeasuredDofs;
use crate::updating::serep::InverseMethod;
use crate::updating::{
    ResonanceMethod, ShapeSource, TestShapes, UpdateError, UpdateOptions, UpdateWarning,
};

/// The test's resonances as found (before suspension modes are left out)
/// and, from the modal fit, their mode shapes at the measured DOFs (`None`:
/// peak picking). They depend on the test and the options only, so a later
/// run on the same test can be handed them instead of finding them again.
#[derive(Clone, Debug, Default)]
pub struct MeasuredResonances {
    pub peaks: Vec<Resonance>,
    pub shapes: Option<Vec<Vec<f64>>>,
}

/// The test side of the updating equations and the sizes of the model side.
pub(super) struct Problem {
    /// Parameter names in deck order; p̄ is aligned with them.
    pub names: Vec<String>,
    pub meas: MeasuredDofs,
    /// The measured resonances found (ascending, suspension modes left out).
    pub peaks: Vec<Resonance>,
    /// R, how many of `peaks` place the updating frequencies and pair modes.
    pub r_used: usize,
    pub updating: UpdatingFrequencies,
    /// ω_i (rad/s) of the updating frequencies and h̄(ω_i) at the measured DOFs.
    pub omegas: Vec<f64>,
    pub h_test: Vec<Vec<f64>>,
    /// Test mode shapes at the measured DOFs (fitted, else the operating
    /// deflection shapes at the peaks) and their frequencies (Hz), for pairing.
    pub test_shapes: TestShapes,
    pub test_hz: Vec<f64>,
    /// The resonances as found, for [`crate::updating::UpdateResult::test_resonances`].
    pub found: MeasuredResonances,
    /// N_md, the SEREP basis size asked for.
    pub n_md: usize,
    /// Modes computed per iteration ([`eigen_count`]).
    pub n_eig: usize,
}

/// The initial model and, when the suspension check computed them, its
/// lowest modes: iteration 0 reuses both.
pub(super) struct Start {
    pub model: FeModel,
    pub modes: Option<Modes>,
}

/// Build the initial model, map the test onto it and choose the updating
/// frequencies (from `known` resonances when given, else found in the test);
/// warnings about the test go to `warnings`.
pub(super) fn prepare(
    build: &mut dyn FnMut(&ParameterValues) -> Result<FeModel, ModelError>,
    test: &MeasuredFrfs,
    opts: &UpdateOptions,
    known: Option<&MeasuredResonances>,
    warnings: &mut Vec<UpdateWarning>,
) -> Result<(Problem, Start), UpdateError> {
    let model0 = build(&ParameterValues::new()).map_err(UpdateError::Model)?;
    let names: Vec<String> = model0.parameters.iter().map(|p| p.name.clone()).collect();
    if names.is_empty() {
        return Err(UpdateError::NoParameters);
    }
    let meas = MeasuredDofs::new(&model0, test, warnings)?;
    let n_ex = meas.len();
    let found = match known {
        Some(k) => k.clone(),
        None => measured_resonances(&meas, test.kind, opts),
    };
    let (mut peaks, mut fitted_shapes) = (found.peaks.clone(), found.shapes.clone());
    let mut modes0 = None;
    if !model0.has_fixed_dofs && !peaks.is_empty() {
        modes0 = Some(leave_out_suspension_modes(
            &model0,
            n_ex,
            opts,
            &mut peaks,
            &mut fitted_shapes,
            warnings,
        )?);
    }
    let r_used = resonances_used(opts, peaks.len(), n_ex);
    let updating = updating_frequencies(opts, &peaks, r_used, &meas, warnings)?;
    let omegas: Vec<f64> = updating.frequencies.iter().map(|u| TWO_PI * u.hz).collect();
    let h_test: Vec<Vec<f64>> = updating
        .frequencies
        .iter()
        .map(|u| meas.at_line(u.line))
        .collect();
    let test_shapes = match fitted_shapes {
        Some(shapes) => TestShapes {
            source: ShapeSource::Fitted,
            shapes,
        },
        None => TestShapes {
            source: ShapeSource::OperatingDeflection,
            shapes: peaks
                .iter()
                .map(|r| meas.deflection_shape(r.line))
                .collect(),
        },
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
    let problem = Problem {
        names,
        meas,
        peaks,
        r_used,
        updating,
        omegas,
        h_test,
        test_shapes,
        test_hz,
        found,
        n_md,
        n_eig,
    };
    let start = Start {
        model: model0,
        modes: modes0,
    };
    Ok((problem, start))
}

/// The measured resonances (Eq. 42's ω̄_r) and, from the modal fit, their
/// mode shapes at the measured DOFs (`None`: peak picking's deflection
/// shapes). The fit is [`identify_column`] on the FRFs in the test's own
/// `kind` (the identification that `frfup identify` runs).
fn measured_resonances(
    meas: &MeasuredDofs,
    kind: FrfKind,
    opts: &UpdateOptions,
) -> MeasuredResonances {
    let peaks = || MeasuredResonances {
        peaks: pick_peaks(
            &meas.lines_hz,
            &indicator(&meas.mobility),
            &PeakOptions {
                min_prominence: opts.min_prominence,
            },
        ),
        shapes: None,
    };
    if opts.resonance_method == ResonanceMethod::PeakPicking {
        return peaks();
    }
    let frfs: Vec<Vec<c64>> = meas
        .receptance
        .iter()
        .map(|h| {
            h.iter()
                .zip(&meas.lines_hz)
                .map(|(v, f)| v * i_omega_power(TWO_PI * f, kind.order()))
                .collect()
        })
        .collect();
    match identify_column(&meas.lines_hz, kind, &frfs) {
        // No pole fits (e.g. an undamped model's FRFs): the peaks.
        Ok(modes) if !modes.is_empty() => MeasuredResonances {
            peaks: modes.iter().map(resonance).collect(),
            shapes: Some(modes.into_iter().map(|m| m.shape).collect()),
        },
        _ => peaks(),
    }
}

/// An identified mode as a resonance (prominence ← significance).
fn resonance(m: &ColumnMode) -> Resonance {
    Resonance {
        frequency_hz: m.frequency_hz,
        line: m.line,
        damping_ratio: Some(m.damping_ratio),
        prominence: m.significance,
    }
}

/// A free-free model tested on a suspension: test resonances below half the
/// first elastic natural frequency of the initial model are suspension
/// (rigid-body) modes, which the FE model cannot reproduce; leave them out
/// of `peaks` (and of `fitted_shapes`). Returns the initial model's modes:
/// the probe solves for at least as many as iteration 0 needs (the basis
/// size only shrinks when peaks are left out), so that iteration reuses them.
fn leave_out_suspension_modes(
    model0: &FeModel,
    n_ex: usize,
    opts: &UpdateOptions,
    peaks: &mut Vec<Resonance>,
    fitted_shapes: &mut Option<Vec<Vec<f64>>>,
    warnings: &mut Vec<UpdateWarning>,
) -> Result<Modes, UpdateError> {
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
    let f_last = f.last().copied().unwrap_or(0.0);
    let Some(&f_elastic) = f.iter().find(|&&x| x > 0.1 && x > 1e-3 * f_last) else {
        return Ok(probe);
    };
    let suspension: Vec<f64> = peaks
        .iter()
        .map(|r| r.frequency_hz)
        .filter(|&x| x < 0.5 * f_elastic)
        .collect();
    if suspension.is_empty() {
        return Ok(probe);
    }
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
    Ok(probe)
}

/// The updating frequencies: `--freqs`, else (1 ± cξ) ω̄_r around the first R
/// resonances (Eq. 42); the candidates skipped are warned about.
fn updating_frequencies(
    opts: &UpdateOptions,
    peaks: &[Resonance],
    r_used: usize,
    meas: &MeasuredDofs,
    warnings: &mut Vec<UpdateWarning>,
) -> Result<UpdatingFrequencies, UpdateError> {
    let updating = match &opts.frequencies_hz {
        Some(f) => UpdatingFrequencies::explicit(f, &meas.lines_hz),
        None => {
            if peaks.is_empty() {
                return Err(UpdateError::NoResonances);
            }
            UpdatingFrequencies::around_resonances(peaks, r_used, opts.offset, &meas.lines_hz)
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
    Ok(updating)
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

/// The options' ranges, checked before anything is built.
pub(super) fn check_options(opts: &UpdateOptions) -> Result<(), UpdateError> {
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
