//! The files of `frfup identify`: `modes.csv`, `shapes.csv`, `modes.uff`
//! (UFF 55), `stabilisation.svg`, `synthesis.svg`, `report.html`, and with a
//! deck `pairs.csv`, `mac.svg` and `mode-shapes.svg`.

pub mod page;
pub mod stabilisation;
pub mod tables;
pub mod uff;

use rayon::prelude::*;
use std::path::Path;

use super::charts::{self, FrfChannel, FrfOverlay, MacChart, MacPanel, ResonanceMark};
use super::viewer::{self, ViewerData};
use super::ReportError;
use crate::fsio::write_atomic;
use crate::identification::{Identification, Pairing};
use crate::testdata::{dof_label, MeasuredFrfs};

/// What the report is made of.
pub struct IdentifyReport<'a> {
    pub id: &'a Identification,
    pub test: &'a MeasuredFrfs,
    pub test_name: &'a str,
    /// The deck's name and the pairing with its modes.
    pub pairing: Option<(&'a str, &'a Pairing)>,
    /// Remarks on the inputs (skipped records, left-out channels).
    pub notes: &'a [String],
    /// The paired shapes on the deck's wireframe (with a deck).
    pub viewer: Option<&'a ViewerData>,
}

/// The rendered charts.
pub struct Charts {
    pub stabilisation: String,
    pub synthesis: String,
    pub mac: Option<String>,
    /// `mode-shapes.svg` (with a deck).
    pub shapes: Option<String>,
}

fn synthesis_overlay(r: &IdentifyReport) -> FrfOverlay {
    let id = r.id;
    let m = id.data.n_inputs();
    let channels = (0..id.data.h.len())
        .into_par_iter()
        .map(|j| {
            let (o, i) = (&id.data.outputs[j / m], &id.data.inputs[j % m]);
            FrfChannel {
                label: format!(
                    "{}/{}",
                    dof_label(o.node, o.direction),
                    dof_label(i.node, i.direction)
                ),
                values: vec![id.data.h[j].clone(), id.synthesise_lines(j, &id.data.omega)],
            }
        })
        .collect();
    FrfOverlay {
        title: "Measured and synthesised FRFs".into(),
        subtitle: Some(format!(
            "{} modes, upper and lower residuals; residual {:.2} % of the data (RMS, weighted)",
            id.modes.len(),
            100.0 * id.relative_residual
        )),
        quantity: r.test.kind.name().into(),
        units: r.test.kind.units().into(),
        frequencies_hz: id.data.frequencies_hz.clone(),
        series_labels: vec!["measured".into(), "identified modes".into()],
        channels,
        marks_hz: id.modes.iter().map(|m| m.frequency_hz).collect(),
        mark_label: "identified mode".into(),
        resonances: id
            .modes
            .iter()
            .enumerate()
            .map(|(k, m)| ResonanceMark {
                hz: m.frequency_hz,
                label: format!("{}", k + 1),
            })
            .collect(),
    }
}

fn mac_chart(id: &Identification, deck: &str, p: &Pairing) -> MacChart {
    MacChart {
        title: "MAC: test modes against FE modes".into(),
        subtitle: Some(format!("{deck}, {} measured DOFs in common", p.common_dofs)),
        row_labels: id
            .modes
            .iter()
            .map(|m| format!("{:.2}", m.frequency_hz))
            .collect(),
        row_axis: "test mode (Hz)".into(),
        column_axis: "FE mode (Hz)".into(),
        scale_label: "MAC of the identified mode shapes (dimensionless)".into(),
        panels: vec![MacPanel {
            label: "deck".into(),
            column_labels: p
                .fe_frequencies_hz
                .iter()
                .map(|f| format!("{f:.2}"))
                .collect(),
            values: p.mac.clone(),
            pairs: p.pairs.clone(),
        }],
    }
}

/// Renders the charts.
pub fn render_charts(r: &IdentifyReport) -> Result<Charts, ReportError> {
    let chart_err = |file: &str| {
        let file = file.to_string();
        move |source| ReportError::Chart { file, source }
    };
    let (stab, synthesis) = rayon::join(
        || stabilisation::render(r.id, &format!("Stabilisation diagram: {}", r.test_name)),
        || charts::frf_overlay::render_contact_sheet(&synthesis_overlay(r)),
    );
    let stab = stab.map_err(chart_err("stabilisation.svg"))?;
    let synthesis = synthesis.map_err(chart_err("synthesis.svg"))?;
    let mac = match r.pairing {
        Some((deck, p)) if !r.id.modes.is_empty() => {
            Some(charts::mac::render(&mac_chart(r.id, deck, p)).map_err(chart_err("mac.svg"))?)
        }
        _ => None,
    };
    Ok(Charts {
        stabilisation: stab,
        synthesis,
        mac,
        shapes: r.viewer.map(viewer::still_svg),
    })
}

/// Writes every file into `dir`.
pub fn write_outputs(r: &IdentifyReport, dir: &Path) -> Result<(), ReportError> {
    let write = |name: &str, bytes: &[u8]| {
        let path = dir.join(name);
        write_atomic(&path, bytes).map_err(|source| ReportError::Io { path, source })
    };
    write("modes.csv", tables::modes_csv(r.id).as_bytes())?;
    write("shapes.csv", tables::shapes_csv(r.id).as_bytes())?;
    let uff = uff::modes_uff(r.id, r.test_name).map_err(|source| ReportError::Io {
        path: dir.join("modes.uff"),
        source,
    })?;
    write("modes.uff", &uff)?;
    let charts = render_charts(r)?;
    write("stabilisation.svg", charts.stabilisation.as_bytes())?;
    write("synthesis.svg", charts.synthesis.as_bytes())?;
    if let Some((_, p)) = r.pairing {
        write("pairs.csv", tables::pairs_csv(r.id, p).as_bytes())?;
    }
    if let Some(mac) = &charts.mac {
        write("mac.svg", mac.as_bytes())?;
    }
    if let Some(svg) = &charts.shapes {
        write(viewer::STILL_FILE, svg.as_bytes())?;
    }
    write("report.html", page::html(r, &charts).as_bytes())?;
    Ok(())
}
