//! `report.html` of a diagnosis: the content of `report.md` with the charts
//! inline, one function per section, under a status box that says in words
//! and colour whether the diagnosed model explains the test.

use std::fmt::Write as _;

use super::output::finding_values;
use super::MODEL_NAMES;
use crate::diagnosis::verdict::Verdict;
use crate::diagnosis::{sig, Diagnosis, FitQuality};
use crate::report::html::{chart, esc, frf_charts, CSS};

/// The rendered charts embedded in the page.
pub struct Embedded {
    pub localisation: String,
    pub frf_sheet: String,
    /// (channel label, SVG).
    pub frf_channels: Vec<(String, String)>,
    /// Why some model FRFs are missing, if they are.
    pub frf_note: Option<String>,
    /// The mode-shape viewer's section.
    pub shapes: Option<String>,
}

fn num(v: f64, d: usize) -> String {
    crate::report::charts::fmt_fixed(v, d)
}

fn quality_rows(d: &Diagnosis) -> [(&'static str, &FitQuality); 3] {
    [
        (MODEL_NAMES[0], &d.initial),
        (MODEL_NAMES[1], &d.updated),
        (MODEL_NAMES[2], &d.diagnosed),
    ]
}

/// The diagnosis' [`Verdict`] at a glance: (CSS class, mark, word,
/// sentence). Green only when conclusive (explained, nothing missing); amber
/// when physics may be missing (partly explained, absorbed by large
/// parameter changes); red when unexplained.
pub fn verdict(d: &Diagnosis) -> (&'static str, &'static str, String, String) {
    let v = Verdict::of(d);
    let (class, mark) = match v {
        Verdict::Explained | Verdict::NothingMissing => ("ok", "✔"),
        Verdict::PartlyExplained { .. }
        | Verdict::AbsorbedByParameters { .. }
        | Verdict::CannotTellApart { .. } => ("amber", "⚠"),
        Verdict::Unexplained { .. } => ("fail", "✘"),
    };
    (class, mark, v.status().to_uppercase(), v.sentence())
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
    header(&mut s, d, deck_name, test_name);
    disagreed(&mut s, d, charts);
    where_section(&mut s, d, charts);
    physics(&mut s, d);
    if let Some(shapes) = &charts.shapes {
        s.push_str(shapes);
    }
    improved(&mut s, d);
    rejected(&mut s, d);
    let _ = writeln!(s, "<h2 id=\"files\">Files</h2>\n<ul>");
    for f in files {
        let _ = writeln!(s, "<li><a href=\"{0}\">{0}</a></li>", esc(f));
    }
    s.push_str("</ul>\n</body>\n</html>\n");
    s
}

/// Inputs, status box, summary and the section links.
fn header(s: &mut String, d: &Diagnosis, deck_name: &str, test_name: &str) {
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
    let (class, mark, word, detail) = verdict(d);
    let _ = writeln!(
        s,
        "<div class=\"status {class}\" role=\"status\"><b class=\"word\">{mark} Status: {}</b><br>{}</div>",
        esc(&word),
        esc(&detail)
    );
    let found: Vec<String> = d
        .findings
        .iter()
        .map(|f| format!("<b>{}</b> ({})", esc(f.physics.name()), esc(&f.label)))
        .collect();
    let _ = writeln!(
        s,
        "<p class=\"summary\">{}<br>FRF error (1 = noise level): {} as given → {} after updating → <b>{}</b> diagnosed.</p>",
        if found.is_empty() {
            "Found: nothing the dictionary explains.".to_string()
        } else {
            format!("Found: {}.", found.join("; "))
        },
        num(d.initial.frf_error, 2),
        num(d.updated.frf_error, 2),
        num(d.diagnosed.frf_error, 2),
    );
    let links: Vec<String> = [
        ("disagreed", "what disagreed"),
        ("where", "where"),
        ("physics", "which physics"),
        ("shapes", "mode shapes"),
        ("improved", "improvement"),
        ("rejected", "rejected hypotheses"),
        ("files", "files"),
    ]
    .iter()
    .map(|(id, t)| format!("<a href=\"#{id}\">{t}</a>"))
    .collect();
    let _ = writeln!(s, "<p>{}</p>", links.join(" · "));
}

/// The fit table of the three models and the FRF charts.
fn disagreed(s: &mut String, d: &Diagnosis, charts: &Embedded) {
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
            "<p>The deck's parameters in the diagnosed model (relative changes from the deck as given): {}.</p>",
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
    frf_charts(s, &charts.frf_sheet, &charts.frf_channels);
}

/// The localisation scores and the map.
fn where_section(s: &mut String, d: &Diagnosis, charts: &Embedded) {
    let _ = writeln!(s, "<h2 id=\"where\">Where</h2>");
    if !d.findings.is_empty() {
        let found: Vec<String> = d
            .findings
            .iter()
            .map(|f| {
                let nodes: Vec<String> = f.nodes.iter().map(|n| n.to_string()).collect();
                format!(
                    "<b>{}</b> at node(s) {}",
                    esc(&f.label),
                    esc(&nodes.join(", "))
                )
            })
            .collect();
        let _ = writeln!(
            s,
            "<p>Accepted (ringed on the map): {}.</p>",
            found.join("; ")
        );
    }
    if d.localisation.is_empty() {
        s.push_str("<p>No node was scored: the search ran no localisation round (the model with its damping refitted was already at the noise level, or the evaluation budget was spent).</p>\n");
    } else {
        s.push_str("<p>First localisation round, before any hypothesis was fitted: nodes where a small change of the model would remove most of the remaining FRF error (share of the error a probe removes, best probe at the node; a probe is not a finding):</p>\n<ul>\n");
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
    chart(s, &charts.localisation);
}

/// The accepted findings with their fitted values.
fn physics(s: &mut String, d: &Diagnosis) {
    let _ = writeln!(s, "<h2 id=\"physics\">Which physics explains it</h2>");
    if d.findings.is_empty() {
        let _ = writeln!(s, "<p>{}</p>", esc(&Verdict::of(d).sentence()));
        return;
    }
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
    for f in d.findings.iter().filter(|f| !f.alternatives.is_empty()) {
        let _ = writeln!(
            s,
            "<p>The data cannot tell <b>{}</b> apart from: {}.</p>",
            esc(&f.label),
            esc(&f.indistinguishable_from().join("; "))
        );
        if let Some(t) = &f.tell_apart {
            let _ = writeln!(s, "<p>{}</p>", esc(&t.sentence(&f.label)));
        }
    }
}

fn improved(s: &mut String, d: &Diagnosis) {
    let _ = writeln!(s, "<h2 id=\"improved\">How much the fit improved</h2>");
    let _ = writeln!(
        s,
        "<p>FRF error (mean squared weighted log error over all lines and channels above the noise floor, 1 = noise level): {} as given, {} after updating, {} diagnosed. {}</p>",
        num(d.initial.frf_error, 2),
        num(d.updated.frf_error, 2),
        num(d.diagnosed.frf_error, 2),
        esc(&Verdict::of(d).sentence())
    );
    let _ = writeln!(
        s,
        "<p>SFDAC mean {} → {} → {}; mean frequency error {} → {} → {}.</p>",
        num(d.initial.sfdac_mean, 4),
        num(d.updated.sfdac_mean, 4),
        num(d.diagnosed.sfdac_mean, 4),
        percent(d.initial.freq_error_mean_pct),
        percent(d.updated.freq_error_mean_pct),
        percent(d.diagnosed.freq_error_mean_pct)
    );
}

/// A percentage with its sign "%", or "–" when there is none (no pairs).
pub fn percent(v: f64) -> String {
    if v.is_finite() {
        format!("{} %", num(v, 3))
    } else {
        "–".to_string()
    }
}

fn rejected(s: &mut String, d: &Diagnosis) {
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
}
