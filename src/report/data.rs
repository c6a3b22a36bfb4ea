//! From an [`UpdateResult`] and its [`ModelStates`] (the initial and updated
//! models evaluated by `updating::model_states`) to the plain data of the
//! charts: the FRF overlay in the measured FRF kind, the MAC of the test
//! deflection shapes against the FE modes, and the chart structs.

use num_complex::Complex64;

use frfup_parsers::deck::Deck;

use super::charts::{
    ConvergenceChart, FrequencyChart, FrfChannel, FrfOverlay, MacChart, MacPanel, ModeFrequencies,
    NamedSeries, ResonanceMark, SfdacChart, StageMark,
};
use super::output::frequency_rows;
use crate::testdata::{FrfKind, MeasuredFrfs};
use crate::updating::measured::MeasuredDofs;
use crate::updating::model_states::{nearest, ModelStates, ModelView};
use crate::updating::MacMatrix;
use crate::updating::{ModePair, UpdateResult};

const TWO_PI: f64 = 2.0 * std::f64::consts::PI;

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

/// Everything the report shows beyond the [`UpdateResult`] itself.
#[derive(Clone, Debug)]
pub struct ReportData {
    pub title: String,
    pub convergence: ConvergenceChart,
    pub frf: FrfOverlay,
    pub sfdac: SfdacChart,
    pub frequencies: FrequencyChart,
    pub mac: MacChart,
    /// The test shapes of the MAC chart (those that paired the resonances).
    pub mac_source: crate::updating::ShapeSource,
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
    states: &ModelStates,
    deck: &Deck,
    test: &MeasuredFrfs,
    inputs: &ReportInputs,
) -> ReportData {
    let title = inputs
        .title
        .clone()
        .or_else(|| {
            let t = deck.title();
            (!t.trim().is_empty()).then(|| t.lines().next().unwrap_or_default().to_string())
        })
        .unwrap_or_else(|| "FRF model updating".to_string());

    let ModelStates {
        measured: meas,
        model_dofs,
        damping,
        initial,
        updated,
        first_pairs,
        last_pairs,
        mac_initial,
        mac_updated,
        notes,
    } = states.clone();
    let kind = test.kind;
    let frf = frf_overlay(result, meas.as_ref(), kind, &initial, &updated, &title);
    ReportData {
        convergence: convergence_chart(result, &title),
        sfdac: sfdac_chart(result),
        frequencies: frequency_chart(result),
        mac: mac_chart(
            result,
            meas.as_ref(),
            [(&initial, &mac_initial), (&updated, &mac_updated)],
            [&first_pairs, &last_pairs],
        ),
        mac_source: result.pairing_shapes.source,
        frf,
        kind,
        measured_labels: meas.as_ref().map(|m| m.labels.clone()).unwrap_or_default(),
        excitation: meas
            .as_ref()
            .map(|m| m.excitation_label.clone())
            .unwrap_or_else(|| result.excitation.clone()),
        model_dofs,
        damping: damping.describe(),
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
        not_identified: result
            .parameter_names
            .iter()
            .map(|n| {
                result
                    .estimate
                    .as_ref()
                    .is_some_and(|e| e.parameters.iter().any(|p| &p.name == n && !p.identified))
            })
            .collect(),
    }
}

/// Where the frequencies-first stage hands over to the FRF equations, and
/// the full-band estimate, when the run made one and kept it (the last
/// record): each marked as a stage of its own.
fn stage_marks(result: &UpdateResult) -> Vec<StageMark> {
    use crate::updating::IterationStage;
    let mut marks = Vec::new();
    let records = &result.iterations;
    let handover = records
        .windows(2)
        .find(|w| w[0].stage == IterationStage::Frequencies && w[1].stage == IterationStage::Frf);
    if let Some(w) = handover {
        marks.push(StageMark {
            at: w[1].index,
            label: "FRF stage after frequencies first".into(),
        });
    }
    let rejected = result
        .warnings
        .iter()
        .any(|w| matches!(w, crate::updating::UpdateWarning::EstimateRejected { .. }));
    match (&result.estimate, records.last()) {
        (Some(_), Some(last)) if !rejected && last.index > 0 => marks.push(StageMark {
            at: last.index,
            label: "full-band estimate".into(),
        }),
        _ => {}
    }
    marks
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
            .map(|(&v, &w)| v * kind.from_receptance(w))
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
pub fn mac_columns(modes_hz: &[f64], lines_hz: &[f64], paired: &[usize]) -> Vec<usize> {
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

/// One panel of the MAC chart: the columns of `mac` (computed on the
/// algorithm side) worth showing, the pairs outlined.
fn mac_panel(
    label: &str,
    view: &ModelView,
    mac: &MacMatrix,
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
        values: mac
            .values
            .iter()
            .map(|row| {
                cols.iter()
                    .map(|&r| row.get(r).copied().unwrap_or(f64::NAN))
                    .collect()
            })
            .collect(),
        pairs: paired
            .iter()
            .filter_map(|&(t, r)| Some((t, cols.iter().position(|&c| c == r)?)))
            .collect(),
    }
}

/// The MAC chart of the initial and updated models: the MAC matrices of
/// [`ModelStates`], titled with their shape source (the one that paired the
/// resonances, so the chart and the frequency table agree).
fn mac_chart(
    result: &UpdateResult,
    meas: Option<&MeasuredDofs>,
    models: [(&ModelView, &MacMatrix); 2],
    pairs: [&[Option<ModePair>]; 2],
) -> MacChart {
    let source = result.pairing_shapes.source;
    let mut c = MacChart {
        title: format!("MAC of the test's {} vs FE modes", source.name()),
        subtitle: Some(format!(
            "the shapes that paired the resonances; outlined: the pairs of the frequency table (same MAC, same {})",
            source.name()
        )),
        row_labels: result
            .resonances
            .iter()
            .enumerate()
            .map(|(i, r)| format!("R{} {}", i + 1, hz(r.frequency_hz)))
            .collect(),
        row_axis: "test resonance (Hz)".into(),
        column_axis: "FE mode (Hz)".into(),
        scale_label: format!("MAC of the {} (dimensionless)", source.short_name()),
        panels: Vec::new(),
    };
    let Some(meas) = meas else {
        return c;
    };
    c.panels = ["initial model", "updated model"]
        .iter()
        .zip(models)
        .zip(pairs)
        .map(|((label, (view, mac)), pairs)| mac_panel(label, view, mac, &meas.lines_hz, pairs))
        .collect();
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
