//! The model states an update compares with the test, evaluated for display:
//! the initial and the updated model's FRFs and modes at the measured DOFs,
//! and the updated model's modes at every node (for the mode-shape viewer).
//!
//! Model FRFs: the model is built at p̄ = 0 and at the returned p̄, its modes
//! are computed up to at least twice the highest measured line, and the
//! receptance at the measured DOFs for the excitation DOF is summed over the
//! modes with a static residual for the modes left out. Damping: each FE
//! mode paired with a test resonance gets that resonance's half-power ζ, the
//! other modes the median measured ζ; without any half-power estimate the
//! deck's damping is used (direct solve), else ζ = 1 %.

use frfup_parsers::deck::Deck;
use num_complex::Complex64;

use super::measured::MeasuredDofs;
use super::{mac_matrix, MacMatrix, ModePair, UpdateResult};
use crate::model::{self, Damping, FeModel, ParameterValues};
use crate::solvers::eigen::nodal::{fe_shapes, FeShapes};
use crate::solvers::eigen::{lowest_modes, EigenOptions, Modes};
use crate::solvers::frf;
use crate::testdata::MeasuredFrfs;

const TWO_PI: f64 = 2.0 * std::f64::consts::PI;

/// Damping used for the model FRFs when nothing was measured or given.
pub const DEFAULT_ZETA: f64 = 0.01;

/// One model state (initial or updated) evaluated at the measured DOFs.
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
    /// The same modes at every node of the deck (the updated model's only,
    /// for the report's mode-shape viewer).
    pub nodal: Option<FeShapes>,
    /// Why the FRFs or modes are missing, if they are.
    pub error: Option<String>,
}

/// The initial and updated models at the measured DOFs, and how they were
/// damped: what a report draws beside the test.
#[derive(Clone, Debug)]
pub struct ModelStates {
    /// The test mapped onto the model's DOFs (`None` if it does not map).
    pub measured: Option<MeasuredDofs>,
    /// Free DOFs of the model.
    pub model_dofs: usize,
    pub damping: DampingChoice,
    pub initial: ModelView,
    pub updated: ModelView,
    /// Test–FE pairs of the first and of the returned iteration.
    pub first_pairs: Vec<Option<ModePair>>,
    pub last_pairs: Vec<Option<ModePair>>,
    /// MAC of the test shapes that made the pairs (`UpdateResult::
    /// pairing_shapes`) against every computed mode of the initial and of
    /// the updated model: the pairs' MAC are entries of these.
    pub mac_initial: MacMatrix,
    pub mac_updated: MacMatrix,
    /// What could not be evaluated, and why.
    pub notes: Vec<String>,
}

/// The models of `result`'s first and returned iterations evaluated at the
/// test's measured DOFs, damped as [`DampingChoice`] says. Never fails:
/// what could not be evaluated is NaN, and [`ModelStates::notes`] says why.
pub fn model_states(result: &UpdateResult, deck: &Deck, test: &MeasuredFrfs) -> ModelStates {
    let mut notes = Vec::new();
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
                ("initial model", None),
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
                ("updated model", Some(deck)),
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

    ModelStates {
        measured: meas,
        model_dofs,
        damping: choice,
        mac_initial: mac_matrix(&result.pairing_shapes, &initial.shapes),
        mac_updated: mac_matrix(&result.pairing_shapes, &updated.shapes),
        initial,
        updated,
        first_pairs,
        last_pairs,
        notes,
    }
}

/// How the model FRFs are damped.
#[derive(Clone, Debug, PartialEq)]
pub enum DampingChoice {
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
    /// In words, for the report.
    pub fn describe(&self) -> String {
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

pub fn median(mut v: Vec<f64>) -> Option<f64> {
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

/// Evaluate `model` at the measured DOFs (and, given its deck, its modes
/// at every node).
fn view(
    (label, deck): (&str, Option<&Deck>),
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
    let shapes = modes.at(&meas.equations);
    let input = meas.excitation_eq;
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
        nodal: deck.map(|d| fe_shapes(d, &model, &modes)),
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
pub fn nearest(hz: &[f64], f: f64) -> Option<usize> {
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
                        let d = Damping::Modal { zeta }.modal_denominator(omega2, w);
                        h += modes.shapes[(j, r)] * modes.shapes[(input, r)] / d;
                    }
                    h
                })
                .collect()
        })
        .collect()
}
