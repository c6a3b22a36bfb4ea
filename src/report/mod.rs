//! Reports people look at: SVG charts, extra CSV tables and a self-contained
//! `report.html` of an updating run.
//!
//! * [`charts`]: one module per chart, each a pure function from a plain data
//!   struct to SVG text (same input → same bytes);
//! * [`data`]: the adapter from an [`UpdateResult`] (+ deck + test data) to
//!   those structs, including the initial and updated model FRFs;
//! * [`output`]: the core files of an update (`report.json`, the paper's
//!   tables as CSV, `updated.deck`, `report.md`);
//! * [`tables`]: the CSV files [`output::write_outputs`] does not write;
//! * [`html`]: the page;
//! * [`diagnosis`]: the charts and page of `frfup diagnose`;
//! * [`viewer`]: the mode-shape viewer of the three reports.
//!
//! Entry points: [`output::write_outputs`] and [`write_report`].

pub mod charts;
pub mod data;
pub mod diagnosis;
pub mod html;
pub mod identification;
pub mod output;
pub mod prose;
pub mod shapes;
pub mod status;
pub mod tables;
pub mod viewer;

use std::fmt;
use std::path::{Path, PathBuf};

use frfup_parsers::deck::Deck;

pub use charts::ChartError;
pub use data::{report_data, ReportData, ReportInputs};

use crate::fsio::write_atomic;
use crate::solvers::eigen::nodal;
use crate::testdata::MeasuredFrfs;
use crate::updating::model_states::ModelStates;
use crate::updating::UpdateResult;

/// Folder (inside the report folder) of the per-channel FRF charts.
pub const FRF_DIR: &str = "frf";

/// Why a report could not be written.
#[derive(Debug)]
pub enum ReportError {
    /// Creating the folder or writing a file failed.
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
    /// A chart could not be drawn.
    Chart { file: String, source: ChartError },
}

impl fmt::Display for ReportError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ReportError::Io { path, source } => write!(f, "writing {}: {source}", path.display()),
            ReportError::Chart { file, source } => write!(f, "{file}: {source}"),
        }
    }
}

impl std::error::Error for ReportError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            ReportError::Io { source, .. } => Some(source),
            ReportError::Chart { source, .. } => Some(source),
        }
    }
}

/// The rendered files of a report, in writing order (path relative to the
/// report folder, bytes).
pub struct RenderedReport {
    pub files: Vec<(String, Vec<u8>)>,
    pub data: ReportData,
}

/// File name of the chart of channel `index` (0-based) labelled `label`.
pub fn channel_file(index: usize, label: &str) -> String {
    format!(
        "{FRF_DIR}/{:02}-{}.svg",
        index + 1,
        charts::frf_overlay::file_stem(label)
    )
}

fn chart(file: &str, r: Result<String, ChartError>) -> Result<String, ReportError> {
    r.map_err(|source| ReportError::Chart {
        file: file.to_string(),
        source,
    })
}

/// Render every report file in memory (no I/O).
pub fn render_report(
    result: &UpdateResult,
    states: &ModelStates,
    deck: &Deck,
    test: &MeasuredFrfs,
    inputs: &ReportInputs,
) -> Result<RenderedReport, ReportError> {
    let data = report_data(result, states, deck, test, inputs);
    let mut embedded = html::EmbeddedCharts {
        convergence: chart(
            "convergence.svg",
            charts::convergence::render(&data.convergence),
        )?,
        sfdac: chart("sfdac.svg", charts::sfdac::render(&data.sfdac))?,
        frequencies: chart(
            "frequencies.svg",
            charts::frequencies::render(&data.frequencies),
        )?,
        mac: chart("mac.svg", charts::mac::render(&data.mac))?,
        frf_sheet: chart(
            "frf-overlay.svg",
            charts::frf_overlay::render_contact_sheet(&data.frf),
        )?,
        frf_channels: Vec::new(),
        shapes: None,
    };
    let mut files: Vec<(String, Vec<u8>)> = vec![
        (
            "convergence.svg".into(),
            embedded.convergence.clone().into_bytes(),
        ),
        (
            "frf-overlay.svg".into(),
            embedded.frf_sheet.clone().into_bytes(),
        ),
        ("sfdac.svg".into(), embedded.sfdac.clone().into_bytes()),
        (
            "frequencies.svg".into(),
            embedded.frequencies.clone().into_bytes(),
        ),
        ("mac.svg".into(), embedded.mac.clone().into_bytes()),
    ];
    // One chart per channel, on every core, kept in channel order.
    let channel_charts: Vec<(String, String)> = {
        use rayon::prelude::*;
        data.frf
            .channels
            .par_iter()
            .enumerate()
            .map(|(i, ch)| {
                let name = channel_file(i, &ch.label);
                let svg = chart(&name, charts::frf_overlay::render_channel(&data.frf, i))?;
                Ok((name, svg))
            })
            .collect::<Result<_, ReportError>>()?
    };
    for ((name, svg), ch) in channel_charts.into_iter().zip(&data.frf.channels) {
        files.push((name, svg.clone().into_bytes()));
        embedded.frf_channels.push((ch.label.clone(), svg));
    }
    files.push((
        "iterations.csv".into(),
        tables::iterations_csv(result).into_bytes(),
    ));
    files.push((
        "resonances.csv".into(),
        tables::resonances_csv(result).into_bytes(),
    ));
    files.push((
        "updating-frequencies.csv".into(),
        tables::updating_frequencies_csv(result).into_bytes(),
    ));
    files.push(("mac.csv".into(), tables::mac_csv(&data).into_bytes()));
    files.push(("frf.csv".into(), tables::frf_csv(&data).into_bytes()));
    files.extend(shape_files(result, states, deck, inputs)?);
    let (section, still) = viewer::update_section(result, states, deck);
    embedded.shapes = Some(section);
    files.extend(still.map(|svg| (viewer::STILL_FILE.to_string(), svg.into_bytes())));
    let mut listed: Vec<String> = files.iter().map(|f| f.0.clone()).collect();
    listed.extend(
        [
            "report.json",
            "report.md",
            "parameters.csv",
            "frequencies.csv",
            "sfdac.csv",
            "updated.deck",
        ]
        .iter()
        .map(|s| s.to_string()),
    );
    listed.sort();
    let page = html::report_html(result, deck, test, inputs, &data, &embedded, &listed);
    files.push(("report.html".into(), page.into_bytes()));
    Ok(RenderedReport { files, data })
}

/// `shapes.csv` and `modes.uff` (geometry, then the test's modes and the
/// updated model's at the measured DOFs), when the test maps onto the model.
fn shape_files(
    result: &UpdateResult,
    states: &ModelStates,
    deck: &Deck,
    inputs: &ReportInputs,
) -> Result<Vec<(String, Vec<u8>)>, ReportError> {
    let Some(meas) = &states.measured else {
        return Ok(Vec::new());
    };
    let found = &result.test_resonances;
    let (kind, test_shapes) = match &found.shapes {
        Some(s) => ("test mode (fitted)", s.clone()),
        None => (
            "test ODS",
            found
                .peaks
                .iter()
                .map(|r| meas.deflection_shape(r.line))
                .collect(),
        ),
    };
    let test_hz: Vec<f64> = found.peaks.iter().map(|r| r.frequency_hz).collect();
    let zeta: Vec<f64> = found
        .peaks
        .iter()
        .map(|r| r.damping_ratio.unwrap_or(0.0))
        .collect();
    let test = nodal::at_points(
        kind,
        &inputs.test_path,
        &test_hz,
        Some(zeta),
        &meas.points,
        &test_shapes,
    );
    let fe = nodal::at_points(
        "updated FE mode",
        &inputs.deck_path,
        &states.updated.modes_hz,
        None,
        &meas.points,
        &states.updated.shapes,
    );
    let io = |name: &str, source| ReportError::Io {
        path: PathBuf::from(name),
        source,
    };
    let mut uff = shapes::geometry_uff(deck).map_err(|e| io("modes.uff", e))?;
    uff.extend(shapes::modes_uff(&test).map_err(|e| io("modes.uff", e))?);
    uff.extend(shapes::modes_uff(&fe).map_err(|e| io("modes.uff", e))?);
    Ok(vec![
        (
            "shapes.csv".into(),
            shapes::shapes_csv(&[&test, &fe]).into_bytes(),
        ),
        ("modes.uff".into(), uff),
    ])
}

/// Write the report of `result` into `dir` (created if missing): the charts
/// (`convergence.svg`, `frf-overlay.svg`, `frf/NN-CHANNEL.svg`, `sfdac.svg`,
/// `frequencies.svg`, `mac.svg`), the extra CSV tables and `report.html`, each
/// atomically. Per-channel charts of an earlier run that this run does not
/// write are removed, so the folder stays consistent. Returns the written paths.
pub fn write_report(
    dir: &Path,
    result: &UpdateResult,
    states: &ModelStates,
    deck: &Deck,
    test: &MeasuredFrfs,
    inputs: &ReportInputs,
) -> Result<Vec<PathBuf>, ReportError> {
    let rendered = render_report(result, states, deck, test, inputs)?;
    let frf_dir = dir.join(FRF_DIR);
    std::fs::create_dir_all(&frf_dir).map_err(|source| ReportError::Io {
        path: frf_dir.clone(),
        source,
    })?;
    let mut written = Vec::with_capacity(rendered.files.len());
    for (name, bytes) in &rendered.files {
        let path = dir.join(name);
        write_atomic(&path, bytes).map_err(|source| ReportError::Io {
            path: path.clone(),
            source,
        })?;
        written.push(path);
    }
    remove_stale_channels(&frf_dir, &written)?;
    Ok(written)
}

/// Remove `frf/NN-*.svg` files not in `keep`.
pub(crate) fn remove_stale_channels(frf_dir: &Path, keep: &[PathBuf]) -> Result<(), ReportError> {
    let entries = std::fs::read_dir(frf_dir).map_err(|source| ReportError::Io {
        path: frf_dir.to_path_buf(),
        source,
    })?;
    for e in entries.flatten() {
        let path = e.path();
        let name = e.file_name().to_string_lossy().into_owned();
        let ours = name.ends_with(".svg")
            && name.len() > 3
            && name.as_bytes()[..2].iter().all(u8::is_ascii_digit)
            && name.as_bytes()[2] == b'-';
        if ours && !keep.contains(&path) {
            std::fs::remove_file(&path).map_err(|source| ReportError::Io {
                path: path.clone(),
                source,
            })?;
        }
    }
    Ok(())
}
