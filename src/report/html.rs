//! `report.html`: one self-contained page (inline SVG charts and CSS, no
//! network) with what was measured, the model, the options, the tables of
//! the run, the mode-shape viewer (the page's one script) and its warnings.

use std::fmt::Write as _;

use frfup_parsers::deck::Deck;

use super::data::{ReportData, ReportInputs};
use super::output::{frequency_rows, mean_abs_dev};
use crate::testdata::MeasuredFrfs;
use crate::updating::frequencies::FrequencySource;
use crate::updating::{InverseMethod, UpdateResult, UpdateWarning};

/// The rendered charts embedded in the page.
#[derive(Clone, Debug, Default)]
pub struct EmbeddedCharts {
    pub convergence: String,
    pub sfdac: String,
    pub frequencies: String,
    pub mac: String,
    pub frf_sheet: String,
    /// (channel label, SVG) per channel.
    pub frf_channels: Vec<(String, String)>,
    /// The mode-shape viewer's section.
    pub shapes: Option<String>,
}

/// Escape text for HTML.
pub fn esc(s: &str) -> String {
    let mut o = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => o.push_str("&amp;"),
            '<' => o.push_str("&lt;"),
            '>' => o.push_str("&gt;"),
            '"' => o.push_str("&quot;"),
            '\'' => o.push_str("&#39;"),
            c => o.push(c),
        }
    }
    o
}

fn fx(v: f64, d: usize) -> String {
    super::charts::fmt_fixed(v, d)
}

/// `v` with `d` decimals and its sign always shown (`+0.12`, `−0.12`), no
/// sign on a value that rounds to zero.
pub fn signed(v: f64, d: usize) -> String {
    if v.is_finite() {
        let s = format!("{v:+.d$}");
        if s.trim_start_matches(['+', '-'])
            .chars()
            .all(|c| c == '0' || c == '.')
        {
            s.trim_start_matches(['+', '-']).to_string()
        } else {
            s.replace('-', "−")
        }
    } else {
        "–".into()
    }
}

/// A step scale: 3 decimals, or 3 significant digits when small.
fn scale(v: f64) -> String {
    if v.is_finite() && v != 0.0 && v.abs() < 0.01 {
        format!("{v:.2e}")
    } else {
        fx(v, 3)
    }
}

/// The style of every page (update and diagnosis reports): tables scroll
/// inside their own box so the page is never wider than the window; status
/// boxes green (passed), red (failed) or amber (passed with a caveat), each
/// with its word and mark so colour is never the only signal.
pub(crate) const CSS: &str = "body{font-family:'DejaVu Sans',Arial,sans-serif;margin:2em auto;max-width:1300px;padding:0 1em;color:#222;line-height:1.4;overflow-wrap:anywhere}\
h1{font-size:1.6em;margin-bottom:.2em}h2{border-bottom:1px solid #ccc;padding-bottom:.2em;margin-top:1.8em}\
table{border-collapse:collapse;margin:.6em 0;font-size:.92em;display:block;max-width:100%;overflow-x:auto}\
th,td{border:1px solid #ccc;padding:.25em .6em;text-align:right;overflow-wrap:normal}\
th{background:#f2f2f2}td.l,th.l{text-align:left}tr.sel td{background:#eef5ff;font-weight:bold}\
.chart{max-width:100%}.chart svg{max-width:100%;height:auto;border:1px solid #eee}.summary{background:#f7f7f7;padding:.6em 1em;border-left:4px solid #888}\
.status{padding:.7em 1em;margin:.8em 0;border:2px solid;border-radius:4px;font-size:1.05em}\
.status b.word{font-size:1.25em;letter-spacing:.02em}.status.ok{background:#e6f4ea;border-color:#1e7e34;color:#0f4d1f}\
.status.fail{background:#fdecea;border-color:#c62828;color:#7f1010}.status.amber{background:#fff4e0;border-color:#e08a00;color:#6b4100}\
.warn li{margin:.2em 0}.muted{color:#666}details{margin:.3em 0}summary{cursor:pointer}code{background:#f4f4f4;padding:0 .2em;overflow-wrap:anywhere}li{margin:.2em 0}\
.viewer-pair{display:flex;flex-wrap:wrap;gap:1em}.viewer-pair figure{flex:1 1 280px;max-width:640px;margin:0}.viewer canvas{width:100%;height:auto;border:1px solid #eee;touch-action:pan-y;cursor:grab}\
figcaption{font-size:.92em;color:#444}.viewer-controls label{white-space:nowrap;margin-right:.8em}.viewer-controls label.pick{white-space:normal}.viewer-controls select{max-width:100%}.viewer-still{display:none}\
@media print{.viewer-live{display:none}.viewer-still{display:block}}";

fn row(s: &mut String, cells: &[(&str, String)]) {
    s.push_str("<tr>");
    for (class, c) in cells {
        if class.is_empty() {
            let _ = write!(s, "<td>{c}</td>");
        } else {
            let _ = write!(s, "<td class=\"{class}\">{c}</td>");
        }
    }
    s.push_str("</tr>\n");
}

fn kv(s: &mut String, rows: &[(&str, String)]) {
    s.push_str("<table>\n");
    for (k, v) in rows {
        let _ = writeln!(
            s,
            "<tr><th class=\"l\">{}</th><td class=\"l\">{v}</td></tr>",
            esc(k)
        );
    }
    s.push_str("</table>\n");
}

/// An inline SVG chart.
pub(crate) fn chart(s: &mut String, svg: &str) {
    let _ = writeln!(s, "<div class=\"chart\">{}</div>", svg.trim());
}

/// The FRF contact sheet, then each channel's chart folded under its label.
pub(crate) fn frf_charts(s: &mut String, sheet: &str, channels: &[(String, String)]) {
    chart(s, sheet);
    for (label, svg) in channels {
        let _ = writeln!(
            s,
            "<details><summary>{} (magnitude and phase)</summary>",
            esc(label)
        );
        chart(s, svg);
        s.push_str("</details>\n");
    }
}

/// The page.
pub fn report_html(
    result: &UpdateResult,
    deck: &Deck,
    test: &MeasuredFrfs,
    inputs: &ReportInputs,
    data: &ReportData,
    charts: &EmbeddedCharts,
    files: &[String],
) -> String {
    let mut s = String::new();
    let _ = write!(
        s,
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n<title>{}</title>\n<style>{CSS}</style>\n</head>\n<body>\n",
        esc(&data.title)
    );
    let _ = writeln!(s, "<h1>{}</h1>", esc(&data.title));
    let _ = writeln!(
        s,
        "<p class=\"muted\">FRF model updating (Yan &amp; Golinval): deck <code>{}</code>, test <code>{}</code></p>",
        esc(&inputs.deck_path),
        esc(&inputs.test_path)
    );
    status_box(&mut s, result);
    summary(&mut s, result);
    nav(&mut s);

    let _ = writeln!(s, "<h2 id=\"measured\">What was measured</h2>");
    measured(&mut s, test, inputs, data, result);
    let _ = writeln!(s, "<h2 id=\"model\">The model</h2>");
    model(&mut s, deck, inputs, data, result);
    let _ = writeln!(s, "<h2 id=\"options\">Options</h2>");
    options(&mut s, result, inputs);

    let _ = writeln!(s, "<h2 id=\"convergence\">Convergence</h2>");
    chart(&mut s, &charts.convergence);
    parameters_table(&mut s, result);
    estimate_section(&mut s, result, deck);

    let _ = writeln!(s, "<h2 id=\"sfdac\">SFDAC before and after</h2>");
    chart(&mut s, &charts.sfdac);
    sfdac_table(&mut s, result);

    let _ = writeln!(s, "<h2 id=\"frequencies\">Resonance frequencies</h2>");
    chart(&mut s, &charts.frequencies);
    frequency_table(&mut s, result);

    let _ = writeln!(s, "<h2 id=\"mac\">Mode shape correlation (MAC)</h2>");
    let _ = writeln!(s, "<p>{}</p>", super::prose::mac_sources(result).html());
    chart(&mut s, &charts.mac);
    if let Some(shapes) = &charts.shapes {
        s.push_str(shapes);
    }

    let _ = writeln!(
        s,
        "<h2 id=\"frf\">FRFs: measured, initial and updated model</h2>"
    );
    let _ = writeln!(s, "<p>Model FRFs damped with: {}.</p>", esc(&data.damping));
    frf_charts(&mut s, &charts.frf_sheet, &charts.frf_channels);

    let _ = writeln!(s, "<h2 id=\"warnings\">Warnings</h2>");
    warnings(&mut s, result, data, &inputs.input_notes);

    let _ = writeln!(s, "<h2 id=\"files\">Files</h2>\n<ul>");
    for f in files {
        let _ = writeln!(s, "<li><a href=\"{0}\">{0}</a></li>", esc(f));
    }
    s.push_str("</ul>\n</body>\n</html>\n");
    s
}

fn summary(s: &mut String, result: &UpdateResult) {
    let _ = writeln!(
        s,
        "<p class=\"summary\">{}</p>",
        super::prose::update_summary(result).html()
    );
}

/// The status box: green "converged" only when the run converged, red
/// "NOT CONVERGED — why" otherwise; an amber note when the estimate's misfit
/// says the deck's parameters do not explain the test. Colour is never the
/// only signal: the words say the same.
fn status_box(s: &mut String, result: &UpdateResult) {
    let st = super::status::status(result);
    let (class, mark) = if st.converged {
        ("ok", "✔")
    } else {
        ("fail", "✘")
    };
    let _ = writeln!(
        s,
        "<div class=\"status {class}\" role=\"status\"><b class=\"word\">{mark} Status: {}</b><br>Layout: {}.</div>",
        esc(&st.headline),
        esc(&result.layout.to_string())
    );
    if let Some(note) = &st.misfit_note {
        let _ = writeln!(
            s,
            "<div class=\"status amber\"><b>⚠ Note:</b> {}</div>",
            esc(note).replace("`frfup diagnose`", "<code>frfup diagnose</code>")
        );
    }
}

/// The full-band estimate: each parameter with ± 1 sd and its verdict, the
/// damping identified along and the directions the data do not determine.
fn estimate_section(s: &mut String, result: &UpdateResult, deck: &Deck) {
    use super::status;
    let Some(est) = &result.estimate else { return };
    let rows = status::estimate_rows(est, deck);
    let priors = rows.iter().any(|r| !r.prior.is_empty());
    let _ = writeln!(
        s,
        "<h3 id=\"estimate\">Estimated parameters (full-band estimate)</h3>\n<table>\n<tr><th class=\"l\">parameter</th><th>p̄</th><th>± 1 sd</th><th class=\"l\">verdict</th>{}</tr>",
        if priors { "<th class=\"l\">deck bounds / prior</th>" } else { "" }
    );
    for r in rows {
        let mut cells = vec![
            ("l", esc(&r.name)),
            ("", esc(&r.value)),
            ("", esc(&r.sd)),
            ("l", esc(&r.verdict)),
        ];
        if priors {
            cells.push(("l", esc(&r.prior)));
        }
        row(s, &cells);
    }
    s.push_str("</table>\n");
    if !priors {
        let _ = writeln!(
            s,
            "<p class=\"muted\">{}</p>",
            super::prose::no_priors().html()
        );
    }
    let _ = writeln!(s, "<p>{}</p>", super::prose::estimate_sentence(est).html());
    let unseen = status::unseen_directions(est);
    if !unseen.is_empty() {
        s.push_str("<p>Directions in parameter space these data do not determine:</p>\n<ul>\n");
        for d in unseen {
            let _ = writeln!(s, "<li>{}</li>", esc(&d));
        }
        s.push_str("</ul>\n");
    }
}

fn nav(s: &mut String) {
    s.push_str("<p>");
    let items = [
        ("measured", "measured"),
        ("model", "model"),
        ("options", "options"),
        ("convergence", "convergence"),
        ("sfdac", "SFDAC"),
        ("frequencies", "frequencies"),
        ("mac", "MAC"),
        ("shapes", "shapes"),
        ("frf", "FRFs"),
        ("warnings", "warnings"),
        ("files", "files"),
    ];
    let links: Vec<String> = items
        .iter()
        .map(|(id, t)| format!("<a href=\"#{id}\">{t}</a>"))
        .collect();
    s.push_str(&links.join(" · "));
    s.push_str("</p>\n");
}

fn measured(
    s: &mut String,
    test: &MeasuredFrfs,
    inputs: &ReportInputs,
    data: &ReportData,
    result: &UpdateResult,
) {
    let lines = &test.frequencies_hz;
    let band = match (lines.first(), lines.last()) {
        (Some(a), Some(b)) => format!("{} – {} Hz", fx(*a, 3), fx(*b, 3)),
        _ => "–".into(),
    };
    let spacing = if lines.len() > 1 {
        format!(
            "{} Hz",
            fx(
                (lines[lines.len() - 1] - lines[0]) / (lines.len() - 1) as f64,
                4
            )
        )
    } else {
        "–".into()
    };
    let used = if data.measured_labels.is_empty() {
        "none".to_string()
    } else {
        esc(&data.measured_labels.join(", "))
    };
    kv(
        s,
        &[
            (
                "test file",
                format!("<code>{}</code>", esc(&inputs.test_path)),
            ),
            (
                "FRF kind",
                format!("{} ({})", test.kind.name(), esc(test.kind.units())),
            ),
            ("channels in the file", test.channels.len().to_string()),
            (
                "channels used (response DOFs)",
                format!("{} : {used}", data.measured_labels.len()),
            ),
            ("excitation (reference DOF)", esc(&data.excitation)),
            ("frequency lines", lines.len().to_string()),
            ("band", band),
            ("line spacing", spacing),
            (
                "resonances found / used",
                format!("{} / {}", result.resonances.len(), result.resonances_used),
            ),
        ],
    );
    if !result.resonances.is_empty() {
        s.push_str("<table>\n<tr><th>resonance</th><th>frequency (Hz)</th><th>damping ζ (%)</th><th>prominence</th><th>used</th></tr>\n");
        for (i, r) in result.resonances.iter().enumerate() {
            row(
                s,
                &[
                    ("", format!("R{}", i + 1)),
                    ("", fx(r.frequency_hz, 3)),
                    (
                        "",
                        r.damping_ratio
                            .map(|z| fx(100.0 * z, 3))
                            .unwrap_or_else(|| "–".into()),
                    ),
                    ("", fx(r.prominence, 1)),
                    (
                        "",
                        if i < result.resonances_used {
                            "yes".into()
                        } else {
                            "no".into()
                        },
                    ),
                ],
            );
        }
        s.push_str("</table>\n");
    }
}

fn model(
    s: &mut String,
    deck: &Deck,
    inputs: &ReportInputs,
    data: &ReportData,
    result: &UpdateResult,
) {
    let deck_damping = match &deck.damping {
        None => "none".to_string(),
        Some(d) => format!("{:?}", d.model),
    };
    kv(
        s,
        &[
            (
                "deck file",
                format!("<code>{}</code>", esc(&inputs.deck_path)),
            ),
            ("title", esc(&deck.title())),
            ("analysis", deck.analysis.name().to_string()),
            (
                "nodes / beams / masses / springs / fixes",
                format!(
                    "{} / {} / {} / {} / {}",
                    deck.nodes.len(),
                    deck.beams.len(),
                    deck.masses.len(),
                    deck.springs.len(),
                    deck.fixes.len()
                ),
            ),
            ("free DOFs", data.model_dofs.to_string()),
            ("deck damping", esc(&deck_damping)),
            ("modes in the SEREP basis (N_md)", result.modes.to_string()),
        ],
    );
    s.push_str("<table>\n<tr><th class=\"l\">parameter</th><th class=\"l\">quantity</th><th class=\"l\">IDs</th><th>updated p̄</th><th>factor 1 + p̄</th></tr>\n");
    let values = result
        .iterations
        .get(result.final_iteration)
        .map(|r| r.parameters.clone())
        .unwrap_or_default();
    for (j, name) in result.parameter_names.iter().enumerate() {
        let (qty, ids) = match deck.param(name) {
            Some(p) => (
                format!("{} ({})", p.quantity.name(), p.quantity.target().name()),
                p.ids
                    .iter()
                    .map(|r| {
                        if r.first == r.last {
                            r.first.to_string()
                        } else {
                            format!("{}-{}", r.first, r.last)
                        }
                    })
                    .collect::<Vec<_>>()
                    .join(","),
            ),
            None => ("–".into(), "–".into()),
        };
        let p = values.get(j).copied().unwrap_or(f64::NAN);
        // A parameter the estimate could not determine keeps the deck's
        // value: say so instead of showing 0 as if it were a finding.
        let unidentified = result
            .estimate
            .as_ref()
            .and_then(|e| e.parameters.iter().find(|q| &q.name == name))
            .is_some_and(|q| !q.identified && q.held);
        let (value, factor) = if unidentified {
            ("not identified".to_string(), "1 (deck)".to_string())
        } else {
            (signed(p, 5), fx(1.0 + p, 4))
        };
        row(
            s,
            &[
                ("l", esc(name)),
                ("l", esc(&qty)),
                ("l", esc(&ids)),
                ("", value),
                ("", factor),
            ],
        );
    }
    s.push_str("</table>\n");
}

fn options(s: &mut String, result: &UpdateResult, inputs: &ReportInputs) {
    let o = &result.options;
    let opt = |v: Option<usize>| v.map(|x| x.to_string()).unwrap_or_else(|| "auto".into());
    let inverse = match o.inverse {
        InverseMethod::Svd => "SVD".to_string(),
        InverseMethod::Perturb { relative } => format!("diagonal perturbation ({relative:e})"),
    };
    let freqs = o
        .frequencies_hz
        .as_ref()
        .map(|f| f.iter().map(|x| fx(*x, 3)).collect::<Vec<_>>().join(", ") + " Hz")
        .unwrap_or_else(|| format!("around resonances, offset ±{} %", fx(100.0 * o.offset, 1)));
    let mut rows = vec![
        (
            "modes N_md",
            format!("{} (used {})", opt(o.modes), result.modes),
        ),
        (
            "resonances R",
            format!("{} (used {})", opt(o.resonances), result.resonances_used),
        ),
        ("updating frequencies", freqs),
        (
            "natural-frequency equations",
            if o.with_frequencies {
                "yes".into()
            } else {
                "no".into()
            },
        ),
        ("inverse of Z̄", inverse),
        ("SVD gap ε", format!("{:e}", o.svd_eps)),
        ("step damping μ/σ₁", format!("{}", o.damping)),
        ("stop when max |p| <", format!("{}", o.tol)),
        ("maximum iterations", o.max_iter.to_string()),
        ("basis tolerance", format!("{:e}", o.basis_tolerance)),
        ("resonances by", o.resonance_method.name().to_string()),
        ("minimum peak prominence", format!("{}", o.min_prominence)),
        ("minimum MAC for pairing", format!("{}", o.mac_min)),
        ("maximum |p̄|", format!("{}", o.max_parameter)),
    ];
    if let Some(c) = &inputs.command {
        rows.push(("command", format!("<code>{}</code>", esc(c))));
    }
    kv(s, &rows);
}

/// σ₁/σ_rank of an iteration's system, or "–".
fn condition(r: &crate::updating::IterationRecord) -> String {
    match (
        r.singular_values.first(),
        r.rank.checked_sub(1).and_then(|k| r.singular_values.get(k)),
    ) {
        (Some(a), Some(b)) if *b > 0.0 => format!("{:.3e}", a / b),
        _ => "–".into(),
    }
}

fn row_open(s: &mut String, selected: bool) {
    s.push_str(if selected {
        "<tr class=\"sel\">"
    } else {
        "<tr>"
    });
}

/// The iterations in a few columns (SFDAC, rank, conditioning, largest
/// step), then p̄ of every parameter at every iteration folded under a
/// summary: one row per parameter, so the table grows down, not sideways.
fn parameters_table(s: &mut String, result: &UpdateResult) {
    s.push_str("<table>\n<tr><th>iteration n</th><th>SFDAC mean</th><th>SFDAC min</th><th>rank</th><th>σ₁/σ_rank</th><th>step scale</th><th>max |p<sup>n</sup>| (step)</th></tr>\n");
    for (i, r) in result.iterations.iter().enumerate() {
        row_open(s, i == result.final_iteration);
        let max_step = r.step.iter().fold(0.0f64, |m, p| m.max(p.abs()));
        let _ =
            writeln!(
            s,
            "<td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>",
            r.index,
            fx(r.sfdac.mean, 4),
            fx(r.sfdac.min, 4),
            if r.index == 0 {
                "–".to_string()
            } else {
                format!("{} / {}", r.rank, result.parameter_names.len())
            },
            condition(r),
            scale(r.step_scale),
            if r.index == 0 { "–".into() } else { scale(max_step) }
        );
    }
    s.push_str("</table>\n<p class=\"muted\">The highlighted row is the returned model.</p>\n");
    let _ = writeln!(
        s,
        "<details><summary>p̄ of each parameter at each iteration ({} parameters × {} iterations; also in <code>parameters.csv</code>)</summary>",
        result.parameter_names.len(),
        result.iterations.len()
    );
    s.push_str("<table>\n<tr><th class=\"l\">parameter</th>");
    for (i, r) in result.iterations.iter().enumerate() {
        if i == result.final_iteration {
            let _ = write!(s, "<th>n = {} (returned)</th>", r.index);
        } else {
            let _ = write!(s, "<th>n = {}</th>", r.index);
        }
    }
    s.push_str("</tr>\n");
    for (j, name) in result.parameter_names.iter().enumerate() {
        let _ = write!(s, "<tr><td class=\"l\">{}</td>", esc(name));
        for r in &result.iterations {
            let p = r.parameters.get(j).copied().unwrap_or(f64::NAN);
            let _ = write!(s, "<td>{}</td>", signed(p, 4));
        }
        s.push_str("</tr>\n");
    }
    s.push_str("</table>\n</details>\n<p class=\"muted\">p̄: relative change of each parameter from its deck value (dimensionless).</p>\n");
}

fn sfdac_table(s: &mut String, result: &UpdateResult) {
    let (Some(first), Some(last)) = (
        result.iterations.first(),
        result.iterations.get(result.final_iteration),
    ) else {
        return;
    };
    s.push_str("<table>\n<tr><th>i</th><th>frequency (Hz)</th><th class=\"l\">chosen</th><th>SFDAC initial</th><th>SFDAC updated</th></tr>\n");
    for (i, u) in result.updating_frequencies.frequencies.iter().enumerate() {
        let source = match u.source {
            FrequencySource::Resonance { resonance, side } => {
                format!(
                    "{} R{}",
                    if side < 0 { "below" } else { "above" },
                    resonance + 1
                )
            }
            FrequencySource::Explicit => "explicit".into(),
        };
        let v = |x: &[f64]| x.get(i).map(|v| fx(*v, 4)).unwrap_or_else(|| "–".into());
        row(
            s,
            &[
                ("", (i + 1).to_string()),
                ("", fx(u.hz, 3)),
                ("l", source),
                ("", v(&first.sfdac.values)),
                ("", v(&last.sfdac.values)),
            ],
        );
    }
    let _ = writeln!(
        s,
        "<tr class=\"sel\"><td></td><td></td><td class=\"l\">mean</td><td>{}</td><td>{}</td></tr>\n<tr class=\"sel\"><td></td><td></td><td class=\"l\">minimum</td><td>{}</td><td>{}</td></tr>\n</table>",
        fx(first.sfdac.mean, 4),
        fx(last.sfdac.mean, 4),
        fx(first.sfdac.min, 4),
        fx(last.sfdac.min, 4)
    );
}

fn frequency_table(s: &mut String, result: &UpdateResult) {
    if result.iterations.get(result.final_iteration).is_none() {
        return;
    }
    let rows = frequency_rows(result);
    let mac = esc(super::prose::pairing_mac_header(result));
    let _ = writeln!(
        s,
        "<table>\n<tr><th>resonance</th><th>test (Hz)</th><th>initial (Hz)</th><th>deviation (%)</th><th>{mac}</th><th>updated (Hz)</th><th>deviation (%)</th><th>{mac}</th></tr>"
    );
    for (i, r) in rows.iter().enumerate() {
        let cells = |x: Option<(f64, f64)>| match x {
            Some((f, m)) => (
                fx(f, 3),
                signed(100.0 * (f - r.test_hz) / r.test_hz, 3),
                fx(m, 3),
            ),
            None => ("–".into(), "–".into(), "–".into()),
        };
        let (fi, di, mi) = cells(r.initial);
        let (fu, du, mu) = cells(r.updated);
        row(
            s,
            &[
                ("", format!("R{}", i + 1)),
                ("", fx(r.test_hz, 3)),
                ("", fi),
                ("", di),
                ("", mi),
                ("", fu),
                ("", du),
                ("", mu),
            ],
        );
    }
    let m = |u: bool| {
        mean_abs_dev(&rows, u)
            .map(|v| fx(v, 2))
            .unwrap_or_else(|| "–".into())
    };
    let _ = writeln!(
        s,
        "<tr class=\"sel\"><td class=\"l\" colspan=\"3\">mean |deviation|</td><td>{}</td><td></td><td></td><td>{}</td><td></td></tr>\n</table>",
        m(false),
        m(true)
    );
}

/// Warning groups shown in the page.
fn group(w: &UpdateWarning) -> &'static str {
    match w {
        UpdateWarning::Indistinguishable { .. } | UpdateWarning::StepLimited { .. } => {
            "Ill-conditioning and indistinguishable parameters"
        }
        UpdateWarning::UnmatchedChannels { .. }
        | UpdateWarning::OtherReferences { .. }
        | UpdateWarning::DuplicateChannel { .. }
        | UpdateWarning::SilentChannels { .. } => "Channels skipped",
        UpdateWarning::SkippedFrequency(_)
        | UpdateWarning::SuspensionModes { .. }
        | UpdateWarning::NearFeResonance { .. }
        | UpdateWarning::UnpairedResonance { .. } => "Frequencies and pairing",
        UpdateWarning::DroppedModes { .. } | UpdateWarning::FewerModes { .. } => "SEREP basis",
        UpdateWarning::Diverged { .. }
        | UpdateWarning::ParameterExploded { .. }
        | UpdateWarning::NotConverged { .. } => "Convergence",
        // Kinds added later still show up.
        #[allow(unreachable_patterns)]
        _ => "Other",
    }
}

fn warnings(s: &mut String, result: &UpdateResult, data: &ReportData, input_notes: &[String]) {
    const GROUPS: [&str; 6] = [
        "Convergence",
        "Ill-conditioning and indistinguishable parameters",
        "Channels skipped",
        "Frequencies and pairing",
        "SEREP basis",
        "Other",
    ];
    if result.warnings.is_empty() && data.notes.is_empty() && input_notes.is_empty() {
        s.push_str("<p>None.</p>\n");
        return;
    }
    if !input_notes.is_empty() {
        s.push_str("<h3>Input files</h3>\n<ul class=\"warn\">\n");
        for n in input_notes {
            let _ = writeln!(s, "<li>{}</li>", esc(n));
        }
        s.push_str("</ul>\n");
    }
    for g in GROUPS {
        let items: Vec<String> = result
            .warnings
            .iter()
            .filter(|w| group(w) == g)
            .map(|w| esc(&w.to_string()))
            .collect();
        if items.is_empty() {
            continue;
        }
        let _ = writeln!(s, "<h3>{g}</h3>\n<ul class=\"warn\">");
        for i in items {
            let _ = writeln!(s, "<li>{i}</li>");
        }
        s.push_str("</ul>\n");
    }
    if !data.notes.is_empty() {
        s.push_str("<h3>Report</h3>\n<ul class=\"warn\">\n");
        for n in &data.notes {
            let _ = writeln!(s, "<li>{}</li>", esc(n));
        }
        s.push_str("</ul>\n");
    }
}
