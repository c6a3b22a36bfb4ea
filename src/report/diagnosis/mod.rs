//! The charts and the page of a diagnosis (`frfup diagnose`): the
//! localisation map on the model's geometry, the measured FRFs against the
//! model as given, after the parameter update and diagnosed, and a
//! self-contained `report.html` with the content of `report.md`.
//!
//! The model FRFs are the ones the diagnosis scored ([`FitQuality::frfs`]:
//! its own predictor on the test data as it prepared them, same lines,
//! channels, excitation and FRF kind, with the damping fitted to the test).

use std::fmt::Write as _;

use frfup_parsers::deck::{Analysis, Deck};
use num_complex::Complex64;

use super::charts::frf_overlay::{self, FrfChannel, FrfOverlay};
use super::charts::localisation::{self, LocalisationMap, MapNode};
use super::charts::ChartError;
use super::data::{pretty_units, resonance_marks};
use super::html::{chart, esc, frf_charts};
use crate::diagnosis::data::TestData;
use crate::diagnosis::{describe_damping, sig, Diagnosis, FitQuality};
use crate::testdata::MeasuredFrfs;
use output::finding_values;

pub mod output;

pub use output::{write_outputs, write_outputs_with_notes};

/// Names of the three models, in the order of the fit table.
pub const MODEL_NAMES: [&str; 3] = ["as given", "parameters updated", "diagnosed"];

/// The rendered files of a diagnosis report besides `diagnosis.json`,
/// `diagnosed.deck` and `report.md`: (path relative to the folder, bytes).
pub fn render_files(
    d: &Diagnosis,
    deck: &Deck,
    test: &MeasuredFrfs,
    deck_name: &str,
    test_name: &str,
) -> Result<Vec<(String, Vec<u8>)>, ChartError> {
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
    let subtitle = if d.localisation.is_empty() {
        format!(
            "{deck_name}, {}–{} plane: no node scored (the search ran no localisation round)",
            names[ax], names[ay]
        )
    } else {
        format!(
            "{deck_name}, {}–{} plane: share of the remaining FRF error that a small change at each node removes",
            names[ax], names[ay]
        )
    };
    LocalisationMap {
        title: "Where the model disagrees with the test".into(),
        subtitle: Some(subtitle),
        x_desc: format!("{} (m)", names[ax]),
        y_desc: format!("{} (m)", names[ay]),
        nodes,
        lines,
        labelled: 5,
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

// ---------------------------------------------------------------------------
// The page

/// The rendered charts embedded in the page.
pub struct Embedded {
    pub localisation: String,
    pub frf_sheet: String,
    /// (channel label, SVG).
    pub frf_channels: Vec<(String, String)>,
    /// Why some model FRFs are missing, if they are.
    pub frf_note: Option<String>,
}

const CSS: &str = "body{font-family:'DejaVu Sans',Arial,sans-serif;margin:2em auto;max-width:1300px;padding:0 1em;color:#222;line-height:1.4}\
h1{font-size:1.6em;margin-bottom:.2em}h2{border-bottom:1px solid #ccc;padding-bottom:.2em;margin-top:1.8em}\
table{border-collapse:collapse;margin:.6em 0;font-size:.92em}th,td{border:1px solid #ccc;padding:.25em .6em;text-align:right}\
th{background:#f2f2f2}td.l,th.l{text-align:left}\
.chart svg{max-width:100%;height:auto;border:1px solid #eee}.summary{background:#f7f7f7;padding:.6em 1em;border-left:4px solid #0064c8}\
.muted{color:#666}details{margin:.3em 0}summary{cursor:pointer}code{background:#f4f4f4;padding:0 .2em}li{margin:.2em 0}";

fn num(v: f64, d: usize) -> String {
    super::charts::fmt_fixed(v, d)
}

fn quality_rows(d: &Diagnosis) -> [(&'static str, &FitQuality); 3] {
    [
        (MODEL_NAMES[0], &d.initial),
        (MODEL_NAMES[1], &d.updated),
        (MODEL_NAMES[2], &d.diagnosed),
    ]
}

/// `report.html`: the content of `report.md` with the charts inline.
pub fn diagnosis_html(
    d: &Diagnosis,
    deck_name: &str,
    test_name: &str,
    charts: &Embedded,
    files: &[String],
) -> String {
    let mut s = String::new();
    let _ = write!(
        s,
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n<title>Model diagnosis</title>\n<style>{CSS}</style>\n</head>\n<body>\n<h1>Model diagnosis</h1>\n"
    );
    let _ = writeln!(
        s,
        "<p class=\"muted\">Model <code>{}</code> against test <code>{}</code> ({} channels{}).</p>",
        esc(deck_name),
        esc(test_name),
        d.channels.len(),
        if d.ignored_channels.is_empty() {
            String::new()
        } else {
            format!(
                "; not on a free DOF of the model, ignored: {}",
                esc(&d.ignored_channels.join(", "))
            )
        }
    );
    // Summary.
    let found: Vec<String> = d
        .findings
        .iter()
        .map(|f| format!("<b>{}</b> ({})", esc(f.physics.name()), esc(&f.label)))
        .collect();
    let _ = writeln!(
        s,
        "<p class=\"summary\">{}<br>FRF error (1 = noise level): {} as given → {} after updating → <b>{}</b> diagnosed. {}</p>",
        if found.is_empty() {
            "Nothing is missing: the deck's own parameters explain the test to the noise level.".to_string()
        } else {
            format!("Found: {}.", found.join("; "))
        },
        num(d.initial.frf_error, 2),
        num(d.updated.frf_error, 2),
        num(d.diagnosed.frf_error, 2),
        if d.at_noise_level {
            "The diagnosed model explains the test to the noise level."
        } else {
            "Some disagreement remains above the noise level."
        }
    );
    let links: Vec<String> = [
        ("disagreed", "what disagreed"),
        ("where", "where"),
        ("physics", "which physics"),
        ("improved", "improvement"),
        ("rejected", "rejected hypotheses"),
        ("files", "files"),
    ]
    .iter()
    .map(|(id, t)| format!("<a href=\"#{id}\">{t}</a>"))
    .collect();
    let _ = writeln!(s, "<p>{}</p>", links.join(" · "));

    // What disagreed.
    let _ = writeln!(s, "<h2 id=\"disagreed\">What disagreed</h2>");
    s.push_str("<table>\n<tr><th class=\"l\">model</th><th>SFDAC mean</th><th>SFDAC min</th><th>mean freq. error (%)</th><th>FRF error (1 = noise)</th><th>RMS log-magnitude error</th><th class=\"l\">damping used</th></tr>\n");
    for (name, q) in quality_rows(d) {
        let _ = writeln!(
            s,
            "<tr><td class=\"l\">{name}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td class=\"l\">{}</td></tr>",
            num(q.sfdac_mean, 4),
            num(q.sfdac_min, 4),
            num(q.freq_error_mean_pct, 3),
            num(q.frf_error, 2),
            num(q.frf_log_rms, 3),
            esc(&q.damping)
        );
    }
    s.push_str("</table>\n");
    if let Some(n) = &d.update_note {
        let _ = writeln!(s, "<p>Updating the deck's own parameters: {}.</p>", esc(n));
    }
    if !d.updated_parameters.is_empty() {
        let vals: Vec<String> = d
            .updated_parameters
            .iter()
            .map(|(k, v)| format!("<code>{}</code> = {}", esc(k), esc(&sig(*v))))
            .collect();
        let _ = writeln!(
            s,
            "<p>Updated parameter values (relative changes): {}.</p>",
            vals.join(", ")
        );
    }
    let _ = writeln!(
        s,
        "<p>Measured FRFs against the three models. The model FRFs of the deck as given and after updating use the damping fitted to the test (the fit table's); the diagnosed model uses the damping written in <code>diagnosed.deck</code>.</p>"
    );
    if let Some(n) = &charts.frf_note {
        let _ = writeln!(s, "<p class=\"muted\">{}</p>", esc(n));
    }
    frf_charts(&mut s, &charts.frf_sheet, &charts.frf_channels);

    // Where.
    let _ = writeln!(s, "<h2 id=\"where\">Where</h2>");
    if d.localisation.is_empty() {
        s.push_str("<p>No node was scored: the search ran no localisation round (the model with its damping refitted was already at the noise level, or the evaluation budget was spent).</p>\n");
    } else {
        s.push_str("<p>Nodes where a small change of the model would remove most of the remaining FRF error (share of the error a probe removes, best candidate at the node):</p>\n<ul>\n");
        for (n, sc, l) in d.localisation.iter().take(6) {
            let _ = writeln!(
                s,
                "<li>node {n}: {} % ({})</li>",
                num(100.0 * sc, 0),
                esc(l)
            );
        }
        s.push_str("</ul>\n");
    }
    chart(&mut s, &charts.localisation);

    // Which physics.
    let _ = writeln!(s, "<h2 id=\"physics\">Which physics explains it</h2>");
    if d.findings.is_empty() {
        s.push_str("<p>Nothing is missing: the deck's own parameters explain the test to the noise level.</p>\n");
    } else {
        s.push_str("<table>\n<tr><th class=\"l\">physics</th><th class=\"l\">hypothesis (where)</th><th class=\"l\">fitted values ± 1 standard deviation</th><th>held-out error before</th><th>after</th></tr>\n");
        for f in &d.findings {
            let vals: Vec<String> = finding_values(f).iter().map(|v| esc(v)).collect();
            let _ = writeln!(
                s,
                "<tr><td class=\"l\"><b>{}</b></td><td class=\"l\">{}</td><td class=\"l\">{}</td><td>{}</td><td>{}</td></tr>",
                esc(f.physics.name()),
                esc(&f.label),
                if vals.is_empty() {
                    "(no parameter)".to_string()
                } else {
                    vals.join("<br>")
                },
                esc(&sig(f.validation_error_before)),
                esc(&sig(f.validation_error_after))
            );
        }
        s.push_str("</table>\n");
        for f in d
            .findings
            .iter()
            .filter(|f| !f.indistinguishable_from.is_empty())
        {
            let _ = writeln!(
                s,
                "<p>The data cannot tell <b>{}</b> apart from: {}.</p>",
                esc(&f.label),
                esc(&f.indistinguishable_from.join("; "))
            );
        }
    }

    // Improvement.
    let _ = writeln!(s, "<h2 id=\"improved\">How much the fit improved</h2>");
    let _ = writeln!(
        s,
        "<p>FRF error (mean squared weighted log error over all lines and channels above the noise floor, 1 = noise level): {} as given, {} after updating, {} diagnosed. {}</p>",
        num(d.initial.frf_error, 2),
        num(d.updated.frf_error, 2),
        num(d.diagnosed.frf_error, 2),
        if d.at_noise_level {
            "The diagnosed model explains the test to the noise level."
        } else {
            "Some disagreement remains above the noise level: physics outside the dictionary, or effects too weak to separate."
        }
    );
    let _ = writeln!(
        s,
        "<p>SFDAC mean {} → {} → {}; mean frequency error {} % → {} % → {} %.</p>",
        num(d.initial.sfdac_mean, 4),
        num(d.updated.sfdac_mean, 4),
        num(d.diagnosed.sfdac_mean, 4),
        num(d.initial.freq_error_mean_pct, 3),
        num(d.updated.freq_error_mean_pct, 3),
        num(d.diagnosed.freq_error_mean_pct, 3)
    );

    // Rejected.
    let _ = writeln!(
        s,
        "<h2 id=\"rejected\">Hypotheses tried and not accepted</h2>"
    );
    if d.rejected.is_empty() {
        s.push_str("<p>None.</p>\n");
    } else {
        s.push_str("<table>\n<tr><th>round</th><th class=\"l\">hypothesis</th><th>value</th><th>held-out error</th><th class=\"l\">why not accepted</th></tr>\n");
        for r in &d.rejected {
            let _ = writeln!(
                s,
                "<tr><td>{}</td><td class=\"l\">{}</td><td>{}</td><td>{}</td><td class=\"l\">{}</td></tr>",
                r.round,
                esc(&r.label),
                r.value.map(|v| esc(&sig(v))).unwrap_or_else(|| "–".into()),
                esc(&sig(r.validation_error)),
                esc(&r.reason)
            );
        }
        s.push_str("</table>\n");
    }
    let _ = writeln!(
        s,
        "<p class=\"muted\">{} model evaluations. The diagnosed model is in <code>diagnosed.deck</code>.</p>",
        d.model_evaluations
    );
    let _ = writeln!(s, "<h2 id=\"files\">Files</h2>\n<ul>");
    for f in files {
        let _ = writeln!(s, "<li><a href=\"{0}\">{0}</a></li>", esc(f));
    }
    s.push_str("</ul>\n</body>\n</html>\n");
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    fn deck(text: &str) -> Deck {
        frfup_parsers::deck::parse(text).unwrap()
    }

    #[test]
    fn map_plane_is_x_z_for_plane_decks_else_the_largest_extent() {
        let plane = deck(
            "analysis plane\nmaterial s E=2e11 rho=7800\nsection c A=1e-4 Iy=1e-9\nnode 1 0 0 0\nnode 2 1 0 0\nbeam 1 1 2 s c\n",
        );
        assert_eq!(map_axes(&plane), (0, 2));
        // A space frame spread in y and z, thin in x.
        let space = deck(
            "material s E=2e11 rho=7800\nsection c A=1e-4 Iy=1e-9 Iz=1e-9 J=2e-9\nnode 1 0 0 0\nnode 2 0.1 2 0\nnode 3 0 2 1\nbeam 1 1 2 s c\nbeam 2 2 3 s c\n",
        );
        assert_eq!(map_axes(&space), (1, 2));
    }
}
