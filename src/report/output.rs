//! Report files of an update, each written atomically; the same result gives
//! the same bytes.
//!
//! * `report.json`: everything (keys sorted, iteration 0 = initial model);
//! * `parameters.csv`: p̄ per iteration (the paper's Tables 1, 2, 4);
//! * `frequencies.csv`: test vs initial vs updated natural frequencies (Tables 3, 7);
//! * `sfdac.csv`: SFDAC per updating frequency, initial and updated (Table 6);
//! * `updated.deck`: the deck at the updated parameter values;
//! * `report.md`: a short human summary.

use std::fmt::Write as _;
use std::path::Path;

use frfup_parsers::deck::{self, Deck};
use serde_json::{json, Map, Value};

use super::tables::csv_text;
use crate::fsio::{csv_number, csv_number_sig, write_atomic};
use crate::model;
use crate::updating::{IterationRecord, UpdateResult};

/// Write the report files of `result` (for `deck`) into `dir` (created if missing).
pub fn write_outputs(result: &UpdateResult, deck: &Deck, dir: &Path) -> std::io::Result<()> {
    write_outputs_with_notes(result, deck, dir, &[])
}

/// [`write_outputs`], with what the readers noticed in the inputs (skipped
/// or doubtful data: `testdata::LoadedTest::notes`) in `report.json`
/// (`input_notes`) and under Warnings in `report.md`.
pub fn write_outputs_with_notes(
    result: &UpdateResult,
    deck: &Deck,
    dir: &Path,
    notes: &[String],
) -> std::io::Result<()> {
    std::fs::create_dir_all(dir)?;
    let mut json = report_json(result);
    if let Some(o) = json.as_object_mut() {
        o.insert("input_notes".into(), json!(notes));
    }
    let json = serde_json::to_string_pretty(&json).map_err(std::io::Error::other)?;
    write_atomic(&dir.join("report.json"), (json + "\n").as_bytes())?;
    write_atomic(
        &dir.join("parameters.csv"),
        parameters_csv(result).as_bytes(),
    )?;
    write_atomic(
        &dir.join("frequencies.csv"),
        frequencies_csv(result).as_bytes(),
    )?;
    write_atomic(&dir.join("sfdac.csv"), sfdac_csv(result).as_bytes())?;
    if let Some(est) = &result.estimate {
        write_atomic(&dir.join("estimates.csv"), estimates_csv(est).as_bytes())?;
    }
    let updated = model::updated_deck(deck, &result.parameter_values());
    write_atomic(&dir.join("updated.deck"), deck::write(&updated).as_bytes())?;
    write_atomic(
        &dir.join("report.md"),
        report_md_with_notes(result, deck, notes).as_bytes(),
    )?;
    Ok(())
}

fn finite_or_null(x: f64) -> Value {
    if x.is_finite() {
        json!(x)
    } else {
        Value::Null
    }
}

fn named(names: &[String], values: &[f64]) -> Value {
    let mut m = Map::new();
    for (n, v) in names.iter().zip(values) {
        m.insert(n.clone(), json!(v));
    }
    Value::Object(m)
}

/// One row of the frequency table: test Hz, initial/updated FE Hz and MAC.
pub struct FrequencyRow {
    pub test_hz: f64,
    pub initial: Option<(f64, f64)>,
    pub updated: Option<(f64, f64)>,
}

/// Test resonances with their initial and updated FE partners.
pub fn frequency_rows(result: &UpdateResult) -> Vec<FrequencyRow> {
    let first = &result.iterations[0];
    let last = result.final_record();
    result
        .resonances
        .iter()
        .enumerate()
        .map(|(t, r)| FrequencyRow {
            test_hz: r.frequency_hz,
            initial: first
                .pairs
                .get(t)
                .cloned()
                .flatten()
                .map(|p| (p.fe_hz, p.mac)),
            updated: last
                .pairs
                .get(t)
                .cloned()
                .flatten()
                .map(|p| (p.fe_hz, p.mac)),
        })
        .collect()
}

fn dev_pct(fe: f64, test: f64) -> f64 {
    100.0 * (fe - test) / test
}

/// Mean |f_fe/f_test − 1| in % over the paired rows (Table 3's last line).
pub fn mean_abs_dev(rows: &[FrequencyRow], updated: bool) -> Option<f64> {
    let devs: Vec<f64> = rows
        .iter()
        .filter_map(|r| {
            if updated { r.updated } else { r.initial }.map(|(f, _)| dev_pct(f, r.test_hz).abs())
        })
        .collect();
    (!devs.is_empty()).then(|| devs.iter().sum::<f64>() / devs.len() as f64)
}

fn iteration_json(names: &[String], r: &IterationRecord) -> Value {
    json!({
        "index": r.index,
        "parameters": named(names, &r.parameters),
        "step": named(names, &r.step),
        "step_scale": r.step_scale,
        "rank": r.rank,
        "singular_values": r.singular_values,
        "sfdac_mean": r.sfdac.mean,
        "sfdac_min": r.sfdac.min,
        "sfdac": r.sfdac.values,
        "fe_frequencies_hz": r.fe_frequencies_hz,
        "basis_modes": r.basis_modes,
    })
}

/// The content of `report.json`.
pub fn report_json(result: &UpdateResult) -> Value {
    let names = &result.parameter_names;
    let rows = frequency_rows(result);
    let opt = |x: Option<(f64, f64)>, i: usize| match x {
        Some(v) => json!(if i == 0 { v.0 } else { v.1 }),
        None => Value::Null,
    };
    let o = &result.options;
    let estimate = result.estimate.as_ref();
    json!({
        "converged": result.converged,
        "stop": result.stop.name(),
        "method": o.method.name(),
        "layout": result.layout.to_string(),
        "parameter_estimates": estimate.map(|e| e.parameters.iter().map(|p| json!({
            "name": p.name,
            "value": p.value,
            "sd": finite_or_null(p.sd),
            "identified": p.identified,
            "at_bound": p.at_bound,
            "min": p.prior.min,
            "max": p.prior.max,
            "prior_sd": p.prior.sd,
        })).collect::<Vec<_>>()),
        "estimate": estimate.map(|e| json!({
            "converged": e.converged,
            "iterations": e.iterations,
            "misfit_over_noise": e.misfit,
            "damping": crate::model::describe_damping(e.damping),
            "start": match e.start {
                0 => "deck",
                s if s >= crate::updating::fullband::estimate::SPREAD_START => "spread",
                _ => "first stage",
            },
            "coarse_frequency_stage": e.coarse_stage,
            "model_solutions": e.model_solutions,
            "unseen_directions": e.missing_directions.iter().map(|(d, sd)| json!({
                "sd": finite_or_null(*sd),
                "direction": d.iter().map(|(n, v)| json!({"name": n, "component": v})).collect::<Vec<_>>(),
            })).collect::<Vec<_>>(),
        })),
        "final_iteration": result.final_iteration,
        "parameter_order": names,
        "parameters": named(names, result.parameters()),
        "iterations": result.iterations.iter().map(|r| iteration_json(names, r)).collect::<Vec<_>>(),
        "updating_frequencies_hz": result.updating_frequencies.hz(),
        "resonances": result.resonances.iter().enumerate().map(|(i, r)| json!({
            "frequency_hz": r.frequency_hz,
            "damping_ratio": r.damping_ratio,
            "used": i < result.resonances_used,
        })).collect::<Vec<_>>(),
        "frequencies": {
            "test": rows.iter().map(|r| r.test_hz).collect::<Vec<_>>(),
            "initial": rows.iter().map(|r| opt(r.initial, 0)).collect::<Vec<_>>(),
            "updated": rows.iter().map(|r| opt(r.updated, 0)).collect::<Vec<_>>(),
            "initial_mac": rows.iter().map(|r| opt(r.initial, 1)).collect::<Vec<_>>(),
            "updated_mac": rows.iter().map(|r| opt(r.updated, 1)).collect::<Vec<_>>(),
            "initial_mean_abs_dev_pct": mean_abs_dev(&rows, false),
            "updated_mean_abs_dev_pct": mean_abs_dev(&rows, true),
        },
        "fdac": {"initial": result.fdac_initial, "updated": result.fdac_final},
        "measured_dofs": result.measured_dofs,
        "excitation": result.excitation,
        "modes": result.modes,
        "warnings": result.warnings.iter().map(|w| w.to_string()).collect::<Vec<_>>(),
        // Every field of UpdateOptions but the method (above): one definition.
        "options": serde_json::to_value(o).unwrap_or_default(),
    })
}

/// The keys of `report.json` that `--json` prints on stdout (all but the
/// per-iteration history, the resonance list and the echo of the inputs).
pub const SUMMARY_KEYS: [&str; 11] = [
    "converged",
    "stop",
    "method",
    "layout",
    "parameter_estimates",
    "estimate",
    "final_iteration",
    "parameter_order",
    "parameters",
    "frequencies",
    "warnings",
];

/// The summary of `frfup update --json`: [`SUMMARY_KEYS`] of
/// [`report_json`], the same values `report.json` holds, plus the initial
/// and final SFDAC (`sfdac_mean`, `sfdac_min`: first and last iteration).
pub fn summary_json(result: &UpdateResult) -> Value {
    let full = report_json(result);
    let mut m: Map<String, Value> = SUMMARY_KEYS
        .iter()
        .filter_map(|k| full.get(*k).map(|v| (k.to_string(), v.clone())))
        .collect();
    let (first, last) = (&result.iterations[0], result.final_record());
    m.insert(
        "sfdac_mean".into(),
        json!({"initial": first.sfdac.mean, "updated": last.sfdac.mean}),
    );
    m.insert(
        "sfdac_min".into(),
        json!({"initial": first.sfdac.min, "updated": last.sfdac.min}),
    );
    Value::Object(m)
}

/// `parameters.csv`: iteration, p̄ per parameter, SFDAC mean and min.
pub fn parameters_csv(result: &UpdateResult) -> String {
    let header = std::iter::once("iteration".to_string())
        .chain(result.parameter_names.iter().cloned())
        .chain(["sfdac_mean".into(), "sfdac_min".into()]);
    let rows = result.iterations.iter().map(|r| {
        std::iter::once(r.index.to_string())
            .chain(r.parameters.iter().map(|p| csv_number_sig(*p, 7)))
            .chain([
                format!("{:.6}", r.sfdac.mean),
                format!("{:.6}", r.sfdac.min),
            ])
            .collect::<Vec<_>>()
    });
    csv_text(std::iter::once(header.collect()).chain(rows))
}

/// `frequencies.csv`: Table 3 / Table 7 layout.
pub fn frequencies_csv(result: &UpdateResult) -> String {
    let rows = frequency_rows(result);
    let header = "mode,test_hz,initial_hz,initial_dev_pct,updated_hz,updated_dev_pct,initial_mac,updated_mac";
    let cell = |x: Option<(f64, f64)>, t: f64| match x {
        Some((f, _)) => [format!("{f:.4}"), format!("{:.3}", dev_pct(f, t))],
        None => [String::new(), String::new()],
    };
    let mac = |x: Option<(f64, f64)>| x.map(|v| format!("{:.4}", v.1)).unwrap_or_default();
    let body = rows.iter().enumerate().map(|(i, r)| {
        let [fi, di] = cell(r.initial, r.test_hz);
        let [fu, du] = cell(r.updated, r.test_hz);
        let test = format!("{:.4}", r.test_hz);
        vec![
            (i + 1).to_string(),
            test,
            fi,
            di,
            fu,
            du,
            mac(r.initial),
            mac(r.updated),
        ]
    });
    let m = |x: Option<f64>| x.map(|v| format!("{v:.3}")).unwrap_or_default();
    let (before, after) = (m(mean_abs_dev(&rows, false)), m(mean_abs_dev(&rows, true)));
    let mean = ["mean_abs", "", "", &before, "", &after, "", ""].map(String::from);
    csv_text(
        std::iter::once(header.split(',').map(String::from).collect())
            .chain(body)
            .chain([mean.to_vec()]),
    )
}

/// `sfdac.csv`: SFDAC_i of the initial and the returned model (Table 6).
pub fn sfdac_csv(result: &UpdateResult) -> String {
    let first = &result.iterations[0].sfdac;
    let last = &result.final_record().sfdac;
    let row = |label: String, a: f64, b: f64| vec![label, format!("{a:.6}"), format!("{b:.6}")];
    let hz = result.updating_frequencies.hz();
    let body = hz
        .iter()
        .enumerate()
        .map(|(i, f)| row(format!("{f:.4}"), first.values[i], last.values[i]));
    csv_text(
        std::iter::once(
            ["frequency_hz", "initial", "updated"]
                .map(String::from)
                .to_vec(),
        )
        .chain(body)
        .chain([
            row("mean".into(), first.mean, last.mean),
            row("min".into(), first.min, last.min),
        ]),
    )
}

/// `report.md`: a short summary for people.
pub fn report_md(result: &UpdateResult, deck: &Deck) -> String {
    report_md_with_notes(result, deck, &[])
}

/// The status box of `report.md`: a quoted block that opens with the status
/// in capitals, then the misfit note when the estimate fits badly.
fn status_md(s: &mut String, result: &UpdateResult) {
    let st = super::status::status(result);
    if st.converged {
        let _ = writeln!(s, "> **✅ Status: {}**", st.headline);
    } else {
        let _ = writeln!(s, "> **❌ Status: {}**", st.headline);
    }
    if let Some(note) = &st.misfit_note {
        let _ = writeln!(s, ">\n> **⚠ Note:** {note}");
    }
    let _ = writeln!(s, ">\n> Layout: {}.\n", result.layout);
}

/// `## Estimated parameters`: the full-band estimate, if the run made one.
fn estimate_md(s: &mut String, result: &UpdateResult, deck: &Deck) {
    use super::status;
    let Some(est) = &result.estimate else { return };
    s.push_str("## Estimated parameters (full-band estimate, relative change p̄)\n\n| parameter | value | ± 1 sd | verdict | deck bounds / prior |\n|---|---:|---:|---|---|\n");
    for r in status::estimate_rows(est, deck) {
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {} |",
            r.name, r.value, r.sd, r.verdict, r.prior
        );
    }
    let _ = writeln!(s, "\n{}\n", super::prose::estimate_sentence(est).markdown());
    let unseen = status::unseen_directions(est);
    if !unseen.is_empty() {
        s.push_str("Directions in parameter space these data do not determine:\n\n");
        for d in unseen {
            let _ = writeln!(s, "- {d}");
        }
        s.push('\n');
    }
}

/// [`report_md`] with the readers' notes on the inputs under Warnings.
pub fn report_md_with_notes(result: &UpdateResult, deck: &Deck, notes: &[String]) -> String {
    let mut s = String::from("# FRF model updating report\n\n");
    status_md(&mut s, result);
    let _ = writeln!(s, "{}\n", super::prose::update_summary(result).markdown());

    let _ = writeln!(
        s,
        "{} measured DOFs, excitation {}, {} modes in the SEREP basis, {} updating frequencies (Hz): {}.\n",
        result.measured_dofs.len(),
        result.excitation,
        result.modes,
        result.updating_frequencies.len(),
        result.updating_frequencies.hz().iter().map(|f| format!("{f:.3}")).collect::<Vec<_>>().join(", ")
    );
    estimate_md(&mut s, result, deck);
    let title = deck.title();
    let _ = writeln!(
        s,
        "## Model\n\n{}{} parameter(s):\n\n| parameter | quantity | IDs |\n|---|---|---|",
        if title.is_empty() {
            String::new()
        } else {
            format!("{}. ", title.replace('\n', " "))
        },
        deck.params.len()
    );
    for p in &deck.params {
        let ids: Vec<String> = p
            .ids
            .iter()
            .map(|r| {
                if r.first == r.last {
                    r.first.to_string()
                } else {
                    format!("{}-{}", r.first, r.last)
                }
            })
            .collect();
        let _ = writeln!(
            s,
            "| {} | {} | {} |",
            p.name,
            p.quantity.name(),
            ids.join(",")
        );
    }
    s.push_str("\n## Options\n\n");
    if let Some(opts) = report_json(result)
        .get("options")
        .and_then(|o| o.as_object())
    {
        for (k, v) in opts {
            let _ = writeln!(s, "- {k}: {v}");
        }
    }
    s.push('\n');
    s.push_str("## Parameters (relative change p̄)\n\n| iteration |");
    for n in &result.parameter_names {
        let _ = write!(s, " {n} |");
    }
    s.push_str(" SFDAC mean |\n|---|");
    for _ in &result.parameter_names {
        s.push_str("---|");
    }
    s.push_str("---|\n");
    for r in &result.iterations {
        let _ = write!(s, "| {} |", r.index);
        for p in &r.parameters {
            let _ = write!(s, " {p:.5} |");
        }
        let _ = writeln!(s, " {:.4} |", r.sfdac.mean);
    }
    s.push_str("\n## Natural frequencies (Hz)\n\n| mode | test | initial | dev % | updated | dev % |\n|---|---|---|---|---|---|\n");
    let rows = frequency_rows(result);
    for (i, r) in rows.iter().enumerate() {
        let c = |x: Option<(f64, f64)>| match x {
            Some((f, _)) => format!("{f:.3} | {:+.2}", dev_pct(f, r.test_hz)),
            None => "– | –".to_string(),
        };
        let _ = writeln!(
            s,
            "| {} | {:.3} | {} | {} |",
            i + 1,
            r.test_hz,
            c(r.initial),
            c(r.updated)
        );
    }
    if let (Some(a), Some(b)) = (mean_abs_dev(&rows, false), mean_abs_dev(&rows, true)) {
        let _ = writeln!(s, "| mean \\|dev\\| | | | {a:.2} | | {b:.2} |");
    }
    let _ = writeln!(s, "\n{}", super::prose::mac_sources(result).markdown());
    if !result.warnings.is_empty() || !notes.is_empty() {
        s.push_str("\n## Warnings\n\n");
        for w in &result.warnings {
            let _ = writeln!(s, "- {w}");
        }
        for n in notes {
            let _ = writeln!(s, "- input: {}", n.replace('\n', " "));
        }
    }
    s
}

/// `estimates.csv`: the full-band estimate of each parameter with its
/// uncertainty, bounds and prior.
fn estimates_csv(est: &crate::updating::fullband::estimate::FullBandEstimate) -> String {
    let header = "parameter,value,sd,identified,at_bound,min,max,prior_sd";
    let rows = est.parameters.iter().map(|p| {
        vec![
            p.name.clone(),
            csv_number(p.value),
            csv_number(p.sd),
            p.identified.to_string(),
            p.at_bound.to_string(),
            csv_number(p.prior.min),
            csv_number(p.prior.max),
            p.prior.sd.map(csv_number).unwrap_or_default(),
        ]
    });
    csv_text(std::iter::once(header.split(',').map(String::from).collect()).chain(rows))
}
