//! Files of a diagnosis: `diagnosis.json`, `diagnosed.deck`, `report.md`,
//! `report.html`, `localisation.svg`, `frf-overlay.svg` and `frf/NN-CHANNEL.svg`
//! (charts and page from [`super`]), each written atomically
//! after all of them were rendered.

use std::path::Path;

use serde_json::{json, Map, Value};

use super::DiagnosisReport;
use crate::diagnosis::{sig, Diagnosis, Finding, FitQuality};
use crate::fsio::write_atomic;

fn num(x: f64) -> Value {
    if x.is_finite() {
        json!(x)
    } else {
        Value::Null
    }
}

fn quality_json(q: &FitQuality) -> Value {
    json!({
        "sfdac_mean": num(q.sfdac_mean),
        "sfdac_min": num(q.sfdac_min),
        "freq_error_mean_pct": num(q.freq_error_mean_pct),
        "frf_error": num(q.frf_error),
        "frf_log_rms": num(q.frf_log_rms),
        "damping": q.damping,
    })
}

/// Unit of a fitted parameter (` kg`, ` N/m`, …; empty if dimensionless):
/// a spring on a rotation DOF is in N·m/rad.
pub fn parameter_unit(name: &str, dofs: &[String]) -> &'static str {
    match name {
        "m" => " kg",
        "k" if dofs.iter().any(|d| d.starts_with('r')) => " N·m/rad",
        "k" => " N/m",
        "alpha" => " 1/s",
        "beta" => " s",
        _ => "",
    }
}

/// A finding's fitted values with one standard deviation and units,
/// e.g. `k = 300.0 ± 1.2 N·m/rad`.
pub fn finding_values(f: &Finding) -> Vec<String> {
    f.parameters
        .iter()
        .map(|(k, v)| {
            let u = f.uncertainty.get(k).copied().unwrap_or(f64::NAN);
            let unit = parameter_unit(k, &f.dofs);
            format!("{k} = {} ± {}{unit}", sig(*v), sig(u))
        })
        .collect()
}

/// `diagnosis.json` as a value.
pub fn diagnosis_json(d: &Diagnosis) -> Value {
    let findings: Vec<Value> = d
        .findings
        .iter()
        .map(|f| {
            let params: Map<String, Value> = f
                .parameters
                .iter()
                .map(|(k, v)| (k.clone(), num(*v)))
                .collect();
            let unc: Map<String, Value> = f
                .uncertainty
                .iter()
                .map(|(k, v)| (k.clone(), num(*v)))
                .collect();
            json!({
                "physics": f.physics.name(),
                "nodes": f.nodes,
                "dofs": f.dofs,
                "parameters": params,
                "uncertainty": unc,
                "evidence": {
                    "validation_error_before": num(f.validation_error_before),
                    "validation_error_after": num(f.validation_error_after),
                },
                "description": f.label,
                "indistinguishable_from": f.indistinguishable_from(),
                "alternatives": f.alternatives.iter().map(|a| json!({
                    "physics": a.physics.name(),
                    "nodes": a.nodes,
                })).collect::<Vec<_>>(),
                "tell_apart": f.tell_apart.as_ref().map(|t| json!({
                    "alternative": t.alternative,
                    "dof": t.dof,
                    "node": t.node,
                    "direction": t.direction,
                    "band_hz": [t.band_hz.0, t.band_hz.1],
                    "difference_db": num(t.difference_db),
                })),
            })
        })
        .collect();
    let rejected: Vec<Value> = d
        .rejected
        .iter()
        .map(|r| {
            json!({
                "hypothesis": r.label,
                "round": r.round,
                "value": r.value.map(num),
                "validation_error": num(r.validation_error),
                "reason": r.reason,
            })
        })
        .collect();
    json!({
        "findings": findings,
        "fit": {
            "initial": quality_json(&d.initial),
            "updated": quality_json(&d.updated),
            "diagnosed": quality_json(&d.diagnosed),
        },
        "noise_level": num(d.noise_level),
        "at_noise_level": d.at_noise_level,
        "updated_parameters": d.updated_parameters,
        "update": d.update_note,
        "localisation": d.localisation.iter().map(|(n, s, l)| json!({"node": n, "score": num(*s), "best_candidate": l})).collect::<Vec<_>>(),
        "rejected": rejected,
        "channels": d.channels,
        "ignored_channels": d.ignored_channels,
        "model_evaluations": d.model_evaluations,
    })
}

/// `report.md`: the diagnosis in plain words.
pub fn report_md(d: &Diagnosis, deck_name: &str, test_name: &str) -> String {
    let mut s = String::new();
    s.push_str("# Model diagnosis\n\n");
    s.push_str(&format!(
        "Model `{deck_name}` against test `{test_name}` ({} channels).\n\n",
        d.channels.len()
    ));
    let (_, mark, word, detail) = super::page::verdict(d);
    s.push_str(&format!("> **{mark} Status: {word}**: {detail}\n\n"));
    s.push_str("## What disagreed\n\n");
    s.push_str("| model | SFDAC mean | SFDAC min | mean freq. error (%) | FRF error (1 = noise) | damping used |\n|---|---|---|---|---|---|\n");
    for (name, q) in [
        ("as given", &d.initial),
        ("parameters updated", &d.updated),
        ("diagnosed", &d.diagnosed),
    ] {
        s.push_str(&format!(
            "| {name} | {:.4} | {:.4} | {:.3} | {:.2} | {} |\n",
            q.sfdac_mean, q.sfdac_min, q.freq_error_mean_pct, q.frf_error, q.damping
        ));
    }
    if let Some(n) = &d.update_note {
        s.push_str(&format!("\nUpdating the deck's own parameters: {n}.\n"));
    }
    s.push_str("\n![Measured FRFs against the model as given, after updating and diagnosed](frf-overlay.svg)\n\nOne chart per channel (magnitude and phase) in `frf/`; all of them in `report.html`.\n");
    if !d.localisation.is_empty() {
        s.push_str("\n## Where\n\nNodes where a small change of the model would remove most of the remaining FRF error (share of the error a probe removes):\n\n");
        for (n, sc, l) in d.localisation.iter().take(6) {
            s.push_str(&format!("- node {n}: {:.0} % ({l})\n", 100.0 * sc));
        }
        s.push_str("\n![Localisation map: the scores on the model's geometry](localisation.svg)\n");
    }
    s.push_str("\n## Which physics explains it\n\n");
    if d.findings.is_empty() {
        s.push_str(&crate::diagnosis::verdict::Verdict::of(d).sentence());
        s.push('\n');
    }
    for f in &d.findings {
        let vals = finding_values(f);
        s.push_str(&format!(
            "- **{}**: {}{}. Held-out prediction error {} → {}.\n",
            f.physics.name(),
            f.label,
            if vals.is_empty() {
                String::new()
            } else {
                format!(", {}", vals.join(", "))
            },
            sig(f.validation_error_before),
            sig(f.validation_error_after)
        ));
        if !f.alternatives.is_empty() {
            s.push_str(&format!(
                "  The data cannot tell this apart from: {}.\n",
                f.indistinguishable_from().join("; ")
            ));
        }
        if let Some(t) = &f.tell_apart {
            s.push_str(&format!("  {}\n", t.sentence(&f.label)));
        }
    }
    s.push_str(&format!(
        "\n## How much the fit improved\n\nFRF error (mean squared weighted log error over all lines and channels above the noise floor, 1 = noise level): {:.2} as given, {:.2} after updating, {:.2} diagnosed. {}\n",
        d.initial.frf_error,
        d.updated.frf_error,
        d.diagnosed.frf_error,
        crate::diagnosis::verdict::Verdict::of(d).sentence()
    ));
    if !d.rejected.is_empty() {
        s.push_str("\n## Hypotheses tried and not accepted\n\n");
        for r in &d.rejected {
            s.push_str(&format!(
                "- round {}: {}{}: {}\n",
                r.round,
                r.label,
                r.value
                    .map(|v| format!(" (value {})", sig(v)))
                    .unwrap_or_default(),
                r.reason
            ));
        }
    }
    s.push_str(&format!(
        "\n{} model evaluations. The diagnosed model is in `diagnosed.deck`.\n",
        d.model_evaluations
    ));
    s
}

/// The readers' notes on the inputs, as a Warnings section of `report.md`
/// and of the page (placed before its end).
fn notes_sections(notes: &[String]) -> (String, String) {
    if notes.is_empty() {
        return (String::new(), String::new());
    }
    let mut md = String::from("\n## Warnings\n\n");
    let mut html = String::from(
        "<h2 id=\"input-warnings\">Warnings</h2>\n<h3>Input files</h3>\n<ul class=\"warn\">\n",
    );
    for n in notes {
        md.push_str(&format!("- input: {}\n", n.replace('\n', " ")));
        html.push_str(&format!("<li>{}</li>\n", crate::report::html::esc(n)));
    }
    html.push_str("</ul>\n");
    (md, html)
}

/// Write the files of a diagnosis of `deck` (the analyst's deck, as given)
/// against `test` into `dir`: `diagnosis.json`, `diagnosed.deck`, `report.md`,
/// `report.html`, `localisation.svg`, `frf-overlay.svg` and
/// `frf/NN-CHANNEL.svg`. Everything is rendered before the first write, and
/// each file is written atomically; per-channel charts of an earlier run that
/// this run does not write are removed.
///
/// The readers' notes on the inputs ([`DiagnosisReport::notes`]) go into
/// `diagnosis.json` (`input_notes`), `report.md` and `report.html`.
pub fn write_outputs(r: &DiagnosisReport, dir: &Path) -> std::io::Result<()> {
    let d = r.diagnosis;
    let mut json = diagnosis_json(d);
    if let Some(o) = json.as_object_mut() {
        o.insert("input_notes".into(), serde_json::json!(r.notes));
    }
    let json = serde_json::to_string_pretty(&json).map_err(std::io::Error::other)?;
    let (notes_md, notes_html) = notes_sections(r.notes);

    let mut deck_text = String::from(
        "# written by frfup diagnose: the updated deck with the accepted extensions\n",
    );
    deck_text.push_str(&frfup_parsers::deck::write(&d.diagnosed_deck));
    let mut files: Vec<(String, Vec<u8>)> = vec![
        ("diagnosis.json".into(), format!("{json}\n").into_bytes()),
        ("diagnosed.deck".into(), deck_text.into_bytes()),
        (
            "report.md".into(),
            (report_md(d, r.deck_name, r.test_name) + &notes_md).into_bytes(),
        ),
    ];
    let mut rendered = super::render_files(r).map_err(std::io::Error::other)?;
    if let Some((_, page)) = rendered.iter_mut().find(|(n, _)| n == "report.html") {
        let text = String::from_utf8_lossy(page).into_owned();
        if let Some(at) = text.rfind("</body>") {
            *page = format!("{}{notes_html}{}", &text[..at], &text[at..]).into_bytes();
        }
    }
    files.extend(rendered);
    let frf_dir = dir.join(crate::report::FRF_DIR);
    std::fs::create_dir_all(&frf_dir)?;
    let mut written = Vec::with_capacity(files.len());
    for (name, bytes) in &files {
        let path = dir.join(name);
        write_atomic(&path, bytes)?;
        written.push(path);
    }
    crate::report::remove_stale_channels(&frf_dir, &written).map_err(std::io::Error::other)?;
    Ok(())
}
