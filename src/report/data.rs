//! From an [`UpdateResult`] (+ deck + test data) to the plain data of the
//! charts: the initial and updated model FRFs at the measured DOFs, the MAC of
//! the test deflection shapes against the FE modes, and the chart structs.
//!
//! Model FRFs: the model is built at p̄ = 0 and at the returned p̄, its modes
//! are computed up to at least twice the highest measured line, and the
//! receptance at the measured DOFs for the excitation DOF is summed over the
//! modes with a static residual for the modes left out. Damping: each FE
//! mode paired with a test resonance gets that resonance's half-power ζ, the
//! other modes the median measured ζ; without any half-power estimate the
//! deck's damping is used (direct solve), else ζ = 1 %. The result is then
//! converted to the measured FRF kind (× (iω)ⁿ).

use num_complex::Complex64;

use frfup_parsers::deck::Deck;

use super::charts::{
    ConvergenceChart, FrequencyChart, FrfChannel, FrfOverlay, MacChart, MacPanel, ModeFrequencies,
    NamedSeries, ResonanceMark, SfdacChart, StageMark,
};
use super::output::frequency_rows;
use crate::model::{self, Damping, FeModel, ParameterValues};
use crate::solvers::eigen::{lowest_modes, EigenOptions, Modes};
use crate::solvers::frf;
use crate::testdata::{FrfKind, MeasuredFrfs};
use crate::updating::measured::MeasuredDofs;
use crate::updating::{mac, ModePair, UpdateResult};

const TWO_PI: f64 = 2.0 * std::f64::consts::PI;

/// Damping used for the model FRFs when nothing was measured or given.
pub const DEFAULT_ZETA: f64 = 0.01;

/// Names and context of a report that the result does not carry.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ReportInputs {
    /// The deck file as the user gave it.
    pub deck_path: String,
    /// The test file as the user gave it.
    pub test_path: String,
    /// Report title; default: the deck's title, else "FRF model updating".
    pub title: Option<String>,
    /// The command line, recorded in the report.
    pub command: Option<String>,
    /// What the readers noticed in the inputs (data skipped or doubtful),
    /// shown under Warnings.
    pub input_notes: Vec<String>,
}

/// One model (initial or updated) evaluated for the report.
#[derive(Clone, Debug, Default)]
pub struct ModelView {
    /// e.g. "initial model (p̄ = 0)".
    pub label: String,
    /// Receptance (m/N, FE DOF sense) [measured DOF][line]; NaN if it failed.
    pub receptance: Vec<Vec<Complex64>>,
    /// Natural frequencies (Hz) of the computed modes.
    pub modes_hz: Vec<f64>,
    /// Mode shapes at the measured DOFs, [mode][measured DOF].
    pub shapes: Vec<Vec<f64>>,
    /// Why the FRFs or modes are missing, if they are.
    pub error: Option<String>,
}

/// Everything the report shows beyond the [`UpdateResult`] itself.
#[derive(Clone, Debug)]
pub struct ReportData {
    pub title: String,
    pub convergence: ConvergenceChart,
    pub frf: FrfOverlay,
    pub sfdac: SfdacChart,
    pub frequencies: FrequencyChart,
    pub mac: MacChart,
    /// The FRF kind of the test (the overlay is in this kind).
    pub kind: FrfKind,
    /// Labels of the measured DOFs used (test node ids), and the excitation.
    pub measured_labels: Vec<String>,
    pub excitation: String,
    /// Number of free DOFs of the model.
    pub model_dofs: usize,
    /// How the model FRFs were damped.
    pub damping: String,
    pub initial: ModelView,
    pub updated: ModelView,
    /// Things that went wrong while preparing the report (it still renders).
    pub notes: Vec<String>,
}

/// How the model FRFs are damped.
#[derive(Clone, Debug, PartialEq)]
enum DampingChoice {
    /// ζ per test resonance (half-power), and ζ for unpaired modes.
    Measured {
        by_resonance: Vec<Option<f64>>,
        other: f64,
    },
    /// The deck's own damping (direct solve).
    Deck(Damping),
    /// No information: one ζ for every mode.
    Uniform(f64),
}

impl DampingChoice {
    fn describe(&self) -> String {
        match self {
            DampingChoice::Measured { other, .. } => format!(
                "modal, ζ of each paired mode from the half-power bandwidth of its test resonance; other modes ζ = {:.3} % (median)",
                100.0 * other
            ),
            DampingChoice::Deck(d) => format!("the deck's damping ({})", damping_name(d)),
            DampingChoice::Uniform(z) => format!("modal ζ = {:.3} % for every mode (no measured or deck damping)", 100.0 * z),
        }
    }
}

/// A short description of a deck damping model.
pub fn damping_name(d: &Damping) -> String {
    match d {
        Damping::None => "none".into(),
        Damping::Modal { zeta } => format!("modal ζ = {zeta}"),
        Damping::Rayleigh { alpha, beta } => format!("Rayleigh α = {alpha}, β = {beta}"),
        Damping::Hysteretic { eta } => format!("hysteretic η = {eta}"),
    }
}

fn median(mut v: Vec<f64>) -> Option<f64> {
    v.retain(|x| x.is_finite());
    if v.is_empty() {
        return None;
    }
    v.sort_by(f64::total_cmp);
    let n = v.len();
    Some(if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    })
}

fn choose_damping(result: &UpdateResult, deck_damping: Damping) -> DampingChoice {
    let by_resonance: Vec<Option<f64>> = result
        .resonances
        .iter()
        .map(|r| r.damping_ratio.filter(|z| z.is_finite() && *z > 0.0))
        .collect();
    match median(by_resonance.iter().flatten().copied().collect()) {
        Some(other) => DampingChoice::Measured {
            by_resonance,
            other,
        },
        None if deck_damping != Damping::None => DampingChoice::Deck(deck_damping),
        None => DampingChoice::Uniform(DEFAULT_ZETA),
    }
}

/// The lowest modes up to at least `2 f_max` (or all of them).
fn modes_covering(model: &FeModel, f_max: f64, start: usize) -> Result<Modes, String> {
    let n = model.dofs.len();
    if n == 0 {
        return Err("the model has no free DOF".into());
    }
    let mut count = start.clamp(1, n);
    loop {
        let opts = EigenOptions {
            count,
            expect_no_rigid_body_modes: model.has_fixed_dofs,
            ..EigenOptions::default()
        };
        let modes =
            lowest_modes(&model.stiffness, &model.mass, &opts).map_err(|e| e.to_string())?;
        let top = modes.frequencies_hz().last().copied().unwrap_or(0.0);
        if count >= n || top >= 2.0 * f_max {
            return Ok(modes);
        }
        count = (2 * count).min(n);
    }
}

/// Evaluate `model` at the measured DOFs.
fn view(
    label: &str,
    model: Result<FeModel, String>,
    meas: &MeasuredDofs,
    choice: &DampingChoice,
    pairs: &[Option<ModePair>],
    start_modes: usize,
) -> ModelView {
    let lines = meas.lines_hz.len();
    let nan = vec![vec![Complex64::new(f64::NAN, f64::NAN); lines]; meas.len()];
    let fail = |e: String| ModelView {
        label: label.to_string(),
        receptance: nan.clone(),
        error: Some(e),
        ..ModelView::default()
    };
    let model = match model {
        Ok(m) => m,
        Err(e) => return fail(e),
    };
    let f_max = meas
        .lines_hz
        .iter()
        .copied()
        .filter(|f| f.is_finite())
        .fold(0.0, f64::max);
    let modes = match modes_covering(&model, f_max, start_modes) {
        Ok(m) => m,
        Err(e) => return fail(format!("modes: {e}")),
    };
    let modes_hz = modes.frequencies_hz();
    let shapes: Vec<Vec<f64>> = (0..modes.len())
        .map(|r| {
            meas.equations
                .iter()
                .map(|&j| modes.shapes[(j, r)])
                .collect()
        })
        .collect();
    let input = meas.equations[meas.excitation_row];
    let omegas: Vec<f64> = meas.lines_hz.iter().map(|f| TWO_PI * f).collect();
    let (receptance, error) = match choice {
        DampingChoice::Deck(d) => {
            match frf::try_direct_receptance(
                &model.stiffness,
                &model.mass,
                *d,
                &omegas,
                input,
                &meas.equations,
            ) {
                Ok(h) => (
                    (0..meas.len())
                        .map(|i| (0..lines).map(|l| h[(i, l)]).collect())
                        .collect(),
                    None,
                ),
                Err(e) => (nan.clone(), Some(format!("FRFs: {e}"))),
            }
        }
        _ => {
            let zetas = mode_zetas(choice, &modes_hz, pairs);
            let (residual, error) = match frf::static_residual(
                &model.stiffness,
                &model.mass,
                &modes,
                input,
                &meas.equations,
            ) {
                Ok(r) => (r, None),
                Err(e) => (
                    vec![0.0; meas.len()],
                    Some(format!("static residual left out: {e}")),
                ),
            };
            (
                modal_sum(&modes, &zetas, &omegas, input, &meas.equations, &residual),
                error,
            )
        }
    };
    ModelView {
        label: label.to_string(),
        receptance,
        modes_hz,
        shapes,
        error,
    }
}

/// ζ of each computed mode under `choice` (modes matched to pairs by frequency).
fn mode_zetas(choice: &DampingChoice, modes_hz: &[f64], pairs: &[Option<ModePair>]) -> Vec<f64> {
    match choice {
        DampingChoice::Measured {
            by_resonance,
            other,
        } => {
            let mut z = vec![*other; modes_hz.len()];
            for p in pairs.iter().flatten() {
                if let (Some(r), Some(Some(zeta))) =
                    (nearest(modes_hz, p.fe_hz), by_resonance.get(p.test))
                {
                    z[r] = *zeta;
                }
            }
            z
        }
        DampingChoice::Uniform(zeta) => vec![*zeta; modes_hz.len()],
        DampingChoice::Deck(_) => vec![DEFAULT_ZETA; modes_hz.len()],
    }
}

/// Index of the value of `hz` within 0.01 % of `f`.
fn nearest(hz: &[f64], f: f64) -> Option<usize> {
    let (i, d) = hz
        .iter()
        .enumerate()
        .map(|(i, h)| (i, (h - f).abs()))
        .min_by(|a, b| a.1.total_cmp(&b.1))?;
    (d <= 1e-4 * f.abs().max(1e-9)).then_some(i)
}

/// H_j(ω) = Σ_r φ_jr φ_kr / (ω_r² − ω² + 2iζ_r ω_r ω) + R_j.
fn modal_sum(
    modes: &Modes,
    zetas: &[f64],
    omegas: &[f64],
    input: usize,
    outputs: &[usize],
    residual: &[f64],
) -> Vec<Vec<Complex64>> {
    outputs
        .iter()
        .enumerate()
        .map(|(o, &j)| {
            omegas
                .iter()
                .map(|&w| {
                    let mut h = Complex64::new(residual.get(o).copied().unwrap_or(0.0), 0.0);
                    for (r, (&omega2, &zeta)) in modes.omega2.iter().zip(zetas).enumerate() {
                        let w2 = omega2.max(0.0);
                        let wr = w2.sqrt();
                        let d = Complex64::new(w2 - w * w, 2.0 * zeta * wr * w);
                        h += modes.shapes[(j, r)] * modes.shapes[(input, r)] / d;
                    }
                    h
                })
                .collect()
        })
        .collect()
}

/// (iω)ⁿ that turns receptance into `kind`.
fn to_kind(h: Complex64, omega: f64, kind: FrfKind) -> Complex64 {
    let iw = Complex64::new(0.0, omega);
    match kind.order() {
        0 => h,
        1 => h * iw,
        _ => h * iw * iw,
    }
}

/// Units with superscripts for display.
pub fn pretty_units(kind: FrfKind) -> &'static str {
    match kind {
        FrfKind::Receptance => "m/N",
        FrfKind::Mobility => "m/(s·N)",
        FrfKind::Accelerance => "m/(s²·N)",
    }
}

/// Short label of a frequency in Hz.
fn hz(f: f64) -> String {
    super::charts::fmt_fixed(f, if f.abs() >= 100.0 { 1 } else { 2 })
}

/// Build the report data. Never fails: problems become [`ReportData::notes`].
pub fn report_data(
    result: &UpdateResult,
    deck: &Deck,
    test: &MeasuredFrfs,
    inputs: &ReportInputs,
) -> ReportData {
    let mut notes = Vec::new();
    let title = inputs
        .title
        .clone()
        .or_else(|| {
            let t = deck.title();
            (!t.trim().is_empty()).then(|| t.lines().next().unwrap_or_default().to_string())
        })
        .unwrap_or_else(|| "FRF model updating".to_string());

    let model0 = model::build(deck, &ParameterValues::new()).map_err(|e| e.to_string());
    let model_dofs = model0.as_ref().map(|m| m.dofs.len()).unwrap_or(0);
    let deck_damping = model0.as_ref().map(|m| m.damping).unwrap_or_default();
    let mut ignored = Vec::new();
    let meas = match &model0 {
        Ok(m) => match MeasuredDofs::new(m, test, &mut ignored) {
            Ok(meas) => Some(meas),
            Err(e) => {
                notes.push(format!("the test data do not map onto the model: {e}"));
                None
            }
        },
        Err(e) => {
            notes.push(format!("the initial model could not be built: {e}"));
            None
        }
    };
    let choice = choose_damping(result, deck_damping);
    let start_modes = result
        .iterations
        .first()
        .map(|r| r.fe_frequencies_hz.len())
        .unwrap_or(0)
        .max(20);
    let first_pairs = result
        .iterations
        .first()
        .map(|r| r.pairs.clone())
        .unwrap_or_default();
    let last_pairs = result
        .iterations
        .get(result.final_iteration)
        .map(|r| r.pairs.clone())
        .unwrap_or_default();
    let (initial, updated) = match &meas {
        Some(meas) => {
            let initial = view(
                "initial model",
                model0,
                meas,
                &choice,
                &first_pairs,
                start_modes,
            );
            let updated_model = if result.iterations.get(result.final_iteration).is_none() {
                Err("no returned iteration".to_string())
            } else {
                model::build(deck, &result.parameter_values()).map_err(|e| e.to_string())
            };
            let updated = view(
                "updated model",
                updated_model,
                meas,
                &choice,
                &last_pairs,
                start_modes,
            );
            (initial, updated)
        }
        None => (ModelView::default(), ModelView::default()),
    };
    for v in [&initial, &updated] {
        if let Some(e) = &v.error {
            notes.push(format!("{}: {e}", v.label));
        }
    }

    let kind = test.kind;
    let frf = frf_overlay(result, meas.as_ref(), kind, &initial, &updated, &title);
    ReportData {
        convergence: convergence_chart(result, &title),
        sfdac: sfdac_chart(result),
        frequencies: frequency_chart(result),
        mac: mac_chart(
            result,
            meas.as_ref(),
            &initial,
            &updated,
            &first_pairs,
            &last_pairs,
        ),
        frf,
        kind,
        measured_labels: meas.as_ref().map(|m| m.labels.clone()).unwrap_or_default(),
        excitation: meas
            .as_ref()
            .map(|m| m.excitation_label.clone())
            .unwrap_or_else(|| result.excitation.clone()),
        model_dofs,
        damping: choice.describe(),
        initial,
        updated,
        notes,
        title,
    }
}

fn convergence_chart(result: &UpdateResult, title: &str) -> ConvergenceChart {
    let n = result.iterations.len().saturating_sub(1);
    let subtitle = format!(
        "{}: {} after {} iteration(s); returned iteration {}",
        title,
        if result.converged {
            "converged"
        } else {
            result.stop.name()
        },
        n,
        result.final_iteration
    );
    ConvergenceChart {
        title: "Convergence of the updating parameters and SFDAC".into(),
        subtitle: Some(subtitle),
        parameter_names: result.parameter_names.clone(),
        iterations: result.iterations.iter().map(|r| r.index).collect(),
        parameters: result
            .iterations
            .iter()
            .map(|r| r.parameters.clone())
            .collect(),
        sfdac_mean: result.iterations.iter().map(|r| r.sfdac.mean).collect(),
        sfdac_min: result.iterations.iter().map(|r| r.sfdac.min).collect(),
        selected: result
            .iterations
            .get(result.final_iteration)
            .map(|r| r.index),
        stages: stage_marks(result),
    }
}

/// The full-band estimate, when the run made one and kept it, is the last
/// record: marked as a stage of its own.
fn stage_marks(result: &UpdateResult) -> Vec<StageMark> {
    let rejected = result
        .warnings
        .iter()
        .any(|w| matches!(w, crate::updating::UpdateWarning::EstimateRejected { .. }));
    match (&result.estimate, result.iterations.last()) {
        (Some(_), Some(last)) if !rejected && last.index > 0 => vec![StageMark {
            at: last.index,
            label: "full-band estimate".into(),
        }],
        _ => Vec::new(),
    }
}

fn sfdac_chart(result: &UpdateResult) -> SfdacChart {
    let mut series = Vec::new();
    if let Some(first) = result.iterations.first() {
        series.push(NamedSeries::new(
            "initial model",
            first.sfdac.values.clone(),
        ));
    }
    if let Some(last) = result.iterations.get(result.final_iteration) {
        series.push(NamedSeries::new(
            format!("updated model (iteration {})", last.index),
            last.sfdac.values.clone(),
        ));
    }
    SfdacChart {
        title: "SFDAC at the updating frequencies".into(),
        subtitle: Some("signed FRF correlation on the measured DOFs (Eq. 45); 1 = FE and test FRF vectors parallel".into()),
        frequencies_hz: result.updating_frequencies.hz(),
        series,
    }
}

fn frequency_chart(result: &UpdateResult) -> FrequencyChart {
    let rows = if result.iterations.get(result.final_iteration).is_none() {
        Vec::new()
    } else {
        frequency_rows(result)
    };
    FrequencyChart {
        title: "Resonance frequencies: test vs initial and updated model".into(),
        subtitle: Some("FE partner of each test resonance by MAC pairing".into()),
        reference_label: "test".into(),
        model_labels: vec!["initial model".into(), "updated model".into()],
        modes: rows
            .iter()
            .enumerate()
            .map(|(i, r)| ModeFrequencies {
                label: format!("R{}", i + 1),
                reference_hz: r.test_hz,
                models_hz: vec![r.initial.map(|p| p.0), r.updated.map(|p| p.0)],
            })
            .collect(),
    }
}

fn frf_overlay(
    result: &UpdateResult,
    meas: Option<&MeasuredDofs>,
    kind: FrfKind,
    initial: &ModelView,
    updated: &ModelView,
    title: &str,
) -> FrfOverlay {
    let mut o = FrfOverlay {
        title: "Measured and model FRFs".into(),
        subtitle: None,
        quantity: kind.name().into(),
        units: pretty_units(kind).into(),
        frequencies_hz: Vec::new(),
        series_labels: vec![
            "measured".into(),
            "initial model".into(),
            "updated model".into(),
        ],
        channels: Vec::new(),
        marks_hz: result.updating_frequencies.hz(),
        mark_label: "updating frequency".into(),
        resonances: resonance_marks(&result.resonances),
    };
    let Some(meas) = meas else {
        return o;
    };
    o.subtitle = Some(format!(
        "{title}: {}, response / excitation {}",
        kind.name(),
        meas.excitation_label
    ));
    o.frequencies_hz = meas.lines_hz.clone();
    let omegas: Vec<f64> = meas.lines_hz.iter().map(|f| TWO_PI * f).collect();
    let convert = |h: &[Complex64]| -> Vec<Complex64> {
        h.iter()
            .zip(&omegas)
            .map(|(&v, &w)| to_kind(v, w, kind))
            .collect()
    };
    let empty = vec![Complex64::new(f64::NAN, f64::NAN); meas.lines_hz.len()];
    o.channels = meas
        .labels
        .iter()
        .enumerate()
        .map(|(i, label)| FrfChannel {
            label: format!("{label}/{}", meas.excitation_label),
            values: vec![
                convert(&meas.receptance[i]),
                convert(initial.receptance.get(i).unwrap_or(&empty)),
                convert(updated.receptance.get(i).unwrap_or(&empty)),
            ],
        })
        .collect();
    o
}

/// FE modes shown as MAC columns: those within [0.5 f_first, 1.15 f_last] of
/// the measured band (at most 40, nearest the band's centre kept), plus every
/// paired mode.
fn mac_columns(modes_hz: &[f64], lines_hz: &[f64], paired: &[usize]) -> Vec<usize> {
    let positive: Vec<f64> = lines_hz
        .iter()
        .copied()
        .filter(|f| *f > 0.0 && f.is_finite())
        .collect();
    let lo = positive.first().copied().unwrap_or(0.0) * 0.5;
    let hi = positive.last().copied().unwrap_or(f64::INFINITY) * 1.15;
    let mut cols: Vec<usize> = (0..modes_hz.len())
        .filter(|&r| (modes_hz[r] >= lo && modes_hz[r] <= hi) || paired.contains(&r))
        .collect();
    if cols.len() > 40 {
        let keep_paired: Vec<usize> = cols
            .iter()
            .copied()
            .filter(|r| paired.contains(r))
            .collect();
        let mut rest: Vec<usize> = cols
            .iter()
            .copied()
            .filter(|r| !paired.contains(r))
            .collect();
        rest.truncate(40usize.saturating_sub(keep_paired.len()));
        cols = keep_paired.into_iter().chain(rest).collect();
        cols.sort_unstable();
    }
    cols
}

fn mac_panel(
    label: &str,
    view: &ModelView,
    ods: &[Vec<f64>],
    lines_hz: &[f64],
    pairs: &[Option<ModePair>],
) -> MacPanel {
    let paired: Vec<(usize, usize)> = pairs
        .iter()
        .flatten()
        .filter_map(|p| Some((p.test, nearest(&view.modes_hz, p.fe_hz)?)))
        .collect();
    let paired_modes: Vec<usize> = paired.iter().map(|p| p.1).collect();
    let cols = mac_columns(&view.modes_hz, lines_hz, &paired_modes);
    let col_hz: Vec<f64> = cols.iter().map(|&r| view.modes_hz[r]).collect();
    MacPanel {
        label: label.to_string(),
        column_labels: super::charts::sfdac::frequency_labels(&col_hz),
        values: ods
            .iter()
            .map(|t| {
                cols.iter()
                    .map(|&r| view.shapes.get(r).map(|s| mac(t, s)).unwrap_or(f64::NAN))
                    .collect()
            })
            .collect(),
        pairs: paired
            .iter()
            .filter_map(|&(t, r)| Some((t, cols.iter().position(|&c| c == r)?)))
            .collect(),
    }
}

fn mac_chart(
    result: &UpdateResult,
    meas: Option<&MeasuredDofs>,
    initial: &ModelView,
    updated: &ModelView,
    first_pairs: &[Option<ModePair>],
    last_pairs: &[Option<ModePair>],
) -> MacChart {
    let mut c = MacChart {
        title: "MAC of the test's operating deflection shapes (ODS) vs FE modes".into(),
        subtitle: Some(format!(
            "ODS = measured FRFs at each resonance line; outlined: the frequency table's pairs (made with the {})",
            super::prose::pairing_shapes(result)
        )),
        row_labels: result
            .resonances
            .iter()
            .enumerate()
            .map(|(i, r)| format!("R{} {}", i + 1, hz(r.frequency_hz)))
            .collect(),
        row_axis: "test resonance (Hz)".into(),
        column_axis: "FE mode (Hz)".into(),
        panels: Vec::new(),
    };
    let Some(meas) = meas else {
        return c;
    };
    let ods: Vec<Vec<f64>> = result
        .resonances
        .iter()
        .map(|r| {
            if r.line < meas.lines_hz.len() {
                meas.deflection_shape(r.line)
            } else {
                vec![f64::NAN; meas.len()]
            }
        })
        .collect();
    c.panels = vec![
        mac_panel("initial model", initial, &ods, &meas.lines_hz, first_pairs),
        mac_panel("updated model", updated, &ods, &meas.lines_hz, last_pairs),
    ];
    c
}

/// The measured resonances as chart marks R1, R2, …
pub(crate) fn resonance_marks(
    resonances: &[crate::updating::frequencies::Resonance],
) -> Vec<ResonanceMark> {
    resonances
        .iter()
        .enumerate()
        .map(|(i, r)| ResonanceMark {
            hz: r.frequency_hz,
            label: format!("R{}", i + 1),
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn median_and_nearest() {
        assert_eq!(median(vec![3.0, f64::NAN, 1.0, 2.0]), Some(2.0));
        assert_eq!(median(vec![1.0, 2.0]), Some(1.5));
        assert_eq!(median(vec![]), None);
        assert_eq!(nearest(&[1.0, 2.0, 3.0], 2.0000001), Some(1));
        assert_eq!(nearest(&[1.0, 2.0], 2.5), None);
        assert_eq!(nearest(&[], 2.5), None);
    }

    #[test]
    fn mac_columns_keep_band_and_pairs() {
        let hz: Vec<f64> = (0..100).map(|i| i as f64).collect();
        let lines = [0.0, 10.0, 20.0];
        let c = mac_columns(&hz, &lines, &[50]);
        assert_eq!(c.first(), Some(&5));
        assert!(c.contains(&23) && !c.contains(&24) && c.contains(&50));
    }

    #[test]
    fn kinds() {
        let h = Complex64::new(1.0, 0.0);
        assert_eq!(
            to_kind(h, 2.0, FrfKind::Accelerance),
            Complex64::new(-4.0, 0.0)
        );
        assert_eq!(to_kind(h, 2.0, FrfKind::Mobility), Complex64::new(0.0, 2.0));
    }
}
