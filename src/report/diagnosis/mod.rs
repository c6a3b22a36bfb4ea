//! The charts and the page of a diagnosis (`frfup diagnose`): the
//! localisation map on the model's geometry, the measured FRFs against the
//! model as given, after the parameter update and diagnosed, and a
//! self-contained `report.html` with the content of `report.md`.
//!
//! The model FRFs are the ones the diagnosis scored ([`crate::diagnosis::FitQuality::frfs`]:
//! its own predictor on the test data as it prepared them, same lines,
//! channels, excitation and FRF kind, with the damping fitted to the test).

use frfup_parsers::deck::{Analysis, Deck};
use num_complex::Complex64;

use super::charts::frf_overlay::{self, FrfChannel, FrfOverlay};
use super::charts::localisation::{self, LocalisationMap, MapFinding, MapNode};
use super::charts::ChartError;
use super::data::{pretty_units, resonance_marks};
use crate::diagnosis::data::TestData;
use crate::diagnosis::{describe_damping, Diagnosis};
use crate::identification::PairedModes;
use crate::testdata::MeasuredFrfs;

pub mod output;
pub mod page;

pub use output::write_outputs;
pub use page::{diagnosis_html, Embedded};

/// Names of the three models, in the order of the fit table.
pub const MODEL_NAMES: [&str; 3] = ["as given", "parameters updated", "diagnosed"];

/// What a diagnosis report is made of: the algorithms' results, the inputs
/// and their names.
pub struct DiagnosisReport<'a> {
    pub diagnosis: &'a Diagnosis,
    /// The analyst's deck, as given.
    pub deck: &'a Deck,
    /// The test as read (before any data-error correction).
    pub test: &'a MeasuredFrfs,
    pub deck_name: &'a str,
    pub test_name: &'a str,
    /// The test's modes paired with the diagnosed deck's
    /// ([`crate::identification::identify_and_pair`]), for the mode-shape
    /// viewer; why not, when they could not be.
    pub test_modes: &'a Result<PairedModes, String>,
    /// What the readers noticed in the inputs (data skipped or doubtful).
    pub notes: &'a [String],
}

/// The rendered files of a diagnosis report besides `diagnosis.json`,
/// `diagnosed.deck` and `report.md`: (path relative to the folder, bytes).
pub fn render_files(r: &DiagnosisReport) -> Result<Vec<(String, Vec<u8>)>, ChartError> {
    let (d, deck, test) = (r.diagnosis, r.deck, r.test);
    let (deck_name, test_name) = (r.deck_name, r.test_name);
    let map = localisation_map(d, deck, deck_name);
    let (overlay, frf_note) = overlay(d, deck, &d.data, test);
    let loc_svg = localisation::render(&map)?;
    let sheet = frf_overlay::render_contact_sheet(&overlay)?;
    let mut files = vec![
        ("localisation.svg".to_string(), loc_svg.clone().into_bytes()),
        ("frf-overlay.svg".to_string(), sheet.clone().into_bytes()),
    ];
    let mut channels = Vec::new();
    for (i, ch) in overlay.channels.iter().enumerate() {
        let name = super::channel_file(i, &ch.label);
        let svg = frf_overlay::render_channel(&overlay, i)?;
        files.push((name, svg.clone().into_bytes()));
        channels.push((ch.label.clone(), svg));
    }
    let (shapes, still) = super::viewer::diagnosis_section(&d.diagnosed_deck, r.test_modes);
    files.extend(still.map(|svg| (super::viewer::STILL_FILE.to_string(), svg.into_bytes())));
    let mut listed: Vec<String> = files.iter().map(|f| f.0.clone()).collect();
    listed.extend(
        [
            "diagnosis.json",
            "diagnosed.deck",
            "report.md",
            "report.html",
        ]
        .iter()
        .map(|s| s.to_string()),
    );
    listed.sort();
    let page = diagnosis_html(
        d,
        deck_name,
        test_name,
        &Embedded {
            localisation: loc_svg,
            frf_sheet: sheet,
            frf_channels: channels,
            frf_note,
            shapes: Some(shapes),
        },
        &listed,
    );
    files.push(("report.html".to_string(), page.into_bytes()));
    Ok(files)
}

// ---------------------------------------------------------------------------
// Localisation map

/// Axis indices (0 = x, 1 = y, 2 = z) of the plane the map shows: x–z for a
/// plane deck, else the two axes of largest extent (in x, y, z order).
pub fn map_axes(deck: &Deck) -> (usize, usize) {
    if deck.analysis == Analysis::Plane {
        return (0, 2);
    }
    let extent = |k: usize| {
        let (lo, hi) = deck
            .nodes
            .iter()
            .map(|n| n.xyz[k])
            .filter(|v| v.is_finite())
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
                (a.min(v), b.max(v))
            });
        if hi >= lo {
            hi - lo
        } else {
            0.0
        }
    };
    let mut order = [0usize, 1, 2];
    // Largest extent first; ties keep x, y, z order.
    order.sort_by(|&a, &b| extent(b).total_cmp(&extent(a)).then(a.cmp(&b)));
    let (a, b) = (order[0], order[1]);
    (a.min(b), a.max(b))
}

/// The map data of `d` on the geometry of `deck`.
pub fn localisation_map(d: &Diagnosis, deck: &Deck, deck_name: &str) -> LocalisationMap {
    let (ax, ay) = map_axes(deck);
    let names = ["x", "y", "z"];
    let measured: Vec<u32> = d
        .data
        .channels
        .iter()
        .map(|c| {
            deck.sensors
                .iter()
                .find(|s| s.test_node == c.node)
                .map_or(c.node, |s| s.node)
        })
        .collect();
    let fixed: Vec<u32> = deck.fixes.iter().map(|f| f.node).collect();
    let nodes: Vec<MapNode> = deck
        .nodes
        .iter()
        .map(|n| {
            let loc = d.localisation.iter().find(|l| l.0 == n.id);
            MapNode {
                id: n.id,
                x: n.xyz[ax],
                y: n.xyz[ay],
                score: loc.map(|l| l.1),
                candidate: loc.map(|l| l.2.clone()),
                measured: measured.contains(&n.id),
                fixed: fixed.contains(&n.id),
            }
        })
        .collect();
    let index = |id: u32| deck.nodes.iter().position(|n| n.id == id);
    let lines = deck
        .beams
        .iter()
        .filter_map(|b| Some((index(b.nodes[0])?, index(b.nodes[1])?)))
        .collect();
    let file = std::path::Path::new(deck_name)
        .file_name()
        .map_or(deck_name.into(), |f| f.to_string_lossy());
    let subtitle = if d.localisation.is_empty() {
        format!(
            "{file}, {}–{} plane; no node scored (no localisation round ran)",
            names[ax], names[ay]
        )
    } else {
        format!(
            "{file}, {}–{} plane; discs: share of the FRF error a small change at the node removes",
            names[ax], names[ay]
        )
    };
    let findings = d
        .findings
        .iter()
        .map(|f| MapFinding {
            label: f.label.clone(),
            nodes: f.nodes.iter().filter_map(|&id| index(id)).collect(),
        })
        .collect();
    LocalisationMap {
        title: "Where the model disagrees with the test".into(),
        subtitle: Some(subtitle),
        x_desc: format!("{} (m)", names[ax]),
        y_desc: format!("{} (m)", names[ay]),
        nodes,
        lines,
        labelled: 5,
        findings,
    }
}

// ---------------------------------------------------------------------------
// FRF overlay

fn empty_overlay(test: &MeasuredFrfs) -> FrfOverlay {
    FrfOverlay {
        title: "Measured and model FRFs".into(),
        subtitle: None,
        quantity: test.kind.name().into(),
        units: pretty_units(test.kind).into(),
        frequencies_hz: Vec::new(),
        series_labels: vec!["measured".into()],
        channels: Vec::new(),
        marks_hz: Vec::new(),
        mark_label: String::new(),
        resonances: Vec::new(),
    }
}

/// Measured FRFs (series 0) and the FRFs of the deck as given, after the
/// parameter update and diagnosed (series 1–3) at the lines and channels of
/// `data`, in the measured kind; the note says which model gave no FRF.
pub fn overlay(
    d: &Diagnosis,
    deck: &Deck,
    data: &TestData,
    test: &MeasuredFrfs,
) -> (FrfOverlay, Option<String>) {
    let mut o = empty_overlay(test);
    let input = crate::testdata::dof_label(data.input.0 as i64, data.input.1);
    o.subtitle = Some(format!(
        "{}, excitation {input}; damping: fitted to the test (as in the fit table)",
        test.kind.name()
    ));
    o.frequencies_hz = data.lines_hz.clone();
    o.resonances = resonance_marks(&data.resonances);
    let nan = vec![Complex64::new(f64::NAN, f64::NAN); data.lines_hz.len()];
    let same = d.updated_deck == *deck;
    let mut series: Vec<Vec<Vec<Complex64>>> = Vec::new();
    let mut notes = Vec::new();
    for (q, name) in [&d.initial, &d.updated, &d.diagnosed]
        .iter()
        .zip(&MODEL_NAMES)
    {
        if q.frfs.len() == data.channels.len() {
            let as_given = if *name == MODEL_NAMES[1] && same {
                "= as given, "
            } else {
                ""
            };
            o.series_labels.push(format!(
                "{name} ({as_given}{})",
                describe_damping(q.damping_model)
            ));
            series.push(
                q.frfs
                    .iter()
                    .map(|c| c.iter().map(|h| Complex64::new(h.re, h.im)).collect())
                    .collect(),
            );
        } else {
            o.series_labels.push(format!("{name} (no FRF)"));
            notes.push(format!("model {name}: no FRF at the test's channels"));
            series.push(vec![nan.clone(); data.channels.len()]);
        }
    }
    o.channels = data
        .channels
        .iter()
        .enumerate()
        .map(|(c, ch)| {
            let mut values = vec![data.values[c]
                .iter()
                .map(|h| Complex64::new(h.re, h.im))
                .collect::<Vec<_>>()];
            for s in &series {
                values.push(s.get(c).cloned().unwrap_or_else(|| nan.clone()));
            }
            FrfChannel {
                label: format!("{}/{input}", ch.label),
                values,
            }
        })
        .collect();
    let note = (!notes.is_empty()).then(|| notes.join("; "));
    (o, note)
}
