//! `frfup modes MODEL.deck [--count N] [--csv FILE] [--shapes FILE] [--uff FILE]
//! [--set NAME=VALUE ...]`.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use crate::fsio::write_atomic;
use crate::model::{self, ParameterValues};
use crate::report::shapes;
use crate::solvers::eigen::nodal;
use crate::solvers::eigen::{lowest_modes, EigenOptions};
use crate::tasks::{eigen_error, model_error, read_deck, CommandError};

/// Options of `frfup modes`.
#[derive(Clone, Debug)]
pub struct ModesOptions {
    pub deck: PathBuf,
    pub count: usize,
    pub csv: Option<PathBuf>,
    /// `--shapes`: the shapes as CSV.
    pub shapes: Option<PathBuf>,
    /// `--uff`: geometry and modes as UFF 15, 82 and 55.
    pub uff: Option<PathBuf>,
    pub values: ParameterValues,
}

/// One row of the modes table (and of `--json`'s `modes`).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct ModeRow {
    pub mode: usize,
    pub frequency_hz: f64,
    /// Generalised mass φ̂ᵀMφ̂ (kg) of the shape scaled to a largest translation of 1.
    #[serde(rename = "generalised_mass_kg")]
    pub generalised_mass: f64,
}

/// Solve the deck's lowest modes.
pub fn solve(opts: &ModesOptions, stage: &dyn Fn(&str)) -> Result<Vec<ModeRow>, CommandError> {
    let deck = read_deck(&opts.deck)?;
    check_settings(&opts.deck, &deck, &opts.values)?;
    let fe = model::build(&deck, &opts.values).map_err(|e| model_error(&opts.deck, e))?;
    model::check_mass(&fe).map_err(|e| model_error(&opts.deck, e))?;
    stage(&format!(
        "computing {} mode(s) of a {}-DOF model",
        opts.count,
        fe.dofs.equations.len()
    ));
    let modes = lowest_modes(
        &fe.stiffness,
        &fe.mass,
        &EigenOptions {
            count: opts.count,
            expect_no_rigid_body_modes: fe.has_fixed_dofs,
            ..EigenOptions::default()
        },
    )
    .map_err(|e| eigen_error(&opts.deck, &fe, e))?;
    write_shapes(opts, &deck, &fe, &modes)?;
    let translational: Vec<bool> = fe
        .dofs
        .equations
        .iter()
        .map(|(_, d)| matches!(d, model::Dof::X | model::Dof::Y | model::Dof::Z))
        .collect();
    let freqs = modes.frequencies_hz();
    Ok((0..modes.len())
        .map(|r| {
            let col = modes.shapes.col(r);
            let mut peak = 0.0f64;
            for (i, &t) in translational.iter().enumerate() {
                if t {
                    peak = peak.max(col[i].abs());
                }
            }
            if peak == 0.0 {
                peak = (0..col.nrows()).fold(0.0f64, |a, i| a.max(col[i].abs()));
            }
            // Φ is mass-normalised (φᵀMφ = 1), so φ̂ = φ/peak has φ̂ᵀMφ̂ = 1/peak².
            ModeRow {
                mode: r + 1,
                frequency_hz: freqs[r],
                generalised_mass: if peak > 0.0 {
                    1.0 / (peak * peak)
                } else {
                    f64::NAN
                },
            }
        })
        .collect())
}

/// `--shapes` and `--uff`, if asked for.
fn write_shapes(
    opts: &ModesOptions,
    deck: &frfup_parsers::deck::Deck,
    fe: &model::FeModel,
    modes: &crate::solvers::eigen::Modes,
) -> Result<(), CommandError> {
    if opts.shapes.is_none() && opts.uff.is_none() {
        return Ok(());
    }
    let set = nodal::fe_modes(deck, fe, modes, &opts.deck.display().to_string());
    if let Some(path) = &opts.shapes {
        write_atomic(path, shapes::shapes_csv(&[&set]).as_bytes())
            .map_err(|e| CommandError::output(path, e))?;
    }
    if let Some(path) = &opts.uff {
        let mut bytes = shapes::geometry_uff(deck).map_err(|e| CommandError::output(path, e))?;
        bytes.extend(shapes::modes_uff(&set).map_err(|e| CommandError::output(path, e))?);
        write_atomic(path, &bytes).map_err(|e| CommandError::output(path, e))?;
    }
    Ok(())
}

/// The table printed by `frfup modes`.
pub fn table(rows: &[ModeRow]) -> String {
    let mut s = format!(
        "{:>5}  {:>14}  {:>20}\n",
        "mode", "frequency_hz", "generalised_mass_kg"
    );
    for r in rows {
        let _ = writeln!(
            s,
            "{:>5}  {:>14.6}  {:>20.6e}",
            r.mode, r.frequency_hz, r.generalised_mass
        );
    }
    s
}

/// The CSV written by `--csv`: `mode,frequency_hz,generalised_mass_kg`.
pub fn csv_text(rows: &[ModeRow]) -> String {
    let mut s = String::from("mode,frequency_hz,generalised_mass_kg\n");
    for r in rows {
        let _ = writeln!(
            s,
            "{},{},{}",
            r.mode,
            crate::fsio::csv_number(r.frequency_hz),
            crate::fsio::csv_number(r.generalised_mass)
        );
    }
    s
}

/// Run `frfup modes`, telling `stage` what it is doing: solve, write
/// `--csv` if asked; returns the rows to print ([`table`] or [`json`]).
pub fn run(opts: &ModesOptions, stage: &dyn Fn(&str)) -> Result<Vec<ModeRow>, CommandError> {
    let rows = solve(opts, stage)?;
    if let Some(csv) = &opts.csv {
        write_atomic(csv, csv_text(&rows).as_bytes()).map_err(|e| CommandError::output(csv, e))?;
    }
    Ok(rows)
}

/// The summary of `frfup modes --json`: the deck and its rows, keyed as the CSV's columns.
pub fn json(deck: &Path, rows: &[ModeRow]) -> serde_json::Value {
    serde_json::json!({ "deck": deck.display().to_string(), "modes": rows })
}

/// Parse `NAME=VALUE` settings of `--set` into parameter values.
pub fn parse_settings(settings: &[String]) -> Result<ParameterValues, CommandError> {
    let mut values = ParameterValues::new();
    for s in settings {
        let (name, value) = s.split_once('=').ok_or_else(|| {
            CommandError::input(format!(
                "--set {s:?}: expected NAME=VALUE (relative change, e.g. p3=1.0)"
            ))
        })?;
        let v: f64 = value
            .trim()
            .parse()
            .map_err(|_| CommandError::input(format!("--set {s:?}: {value:?} is not a number")))?;
        if !v.is_finite() || v <= -1.0 {
            return Err(CommandError::input(format!(
                "--set {s:?}: a relative change must be finite and > -1 (the value becomes (1 + p) x deck value)"
            )));
        }
        values.insert(name.trim().to_string(), v);
    }
    Ok(values)
}

/// Check that every `--set` name is a parameter of the deck.
pub fn check_settings(
    path: &Path,
    deck: &frfup_parsers::deck::Deck,
    values: &ParameterValues,
) -> Result<(), CommandError> {
    let names = model::parameter_names(deck);
    for name in values.keys() {
        if !names.iter().any(|n| n == name) {
            return Err(CommandError::input(format!(
                "{}: --set {name}: the deck has no parameter {name:?} (it has: {})",
                path.display(),
                if names.is_empty() {
                    "none".to_string()
                } else {
                    names.join(", ")
                }
            )));
        }
    }
    Ok(())
}
