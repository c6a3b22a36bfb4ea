//! `frfup info FILE... [--json]`: one line per dataset; with several files
//! each line starts with its file, and each JSON record has a `file` field.

use std::fmt::Write as _;
use std::path::PathBuf;

use frfup_parsers::uff::{Abscissa, Dataset, Function58, UffFile};
use serde_json::{json, Value};

use super::{progress::Progress, read_uff};
use crate::tasks::CommandError;
use crate::testdata::{entity_dof_label, function_type_name};

/// Name of a UFF ordinate data type (record 7, field 1).
pub fn ordinate_type_name(code: i32) -> &'static str {
    match code {
        2 => "real f32",
        4 => "real f64",
        5 => "complex f32",
        6 => "complex f64",
        _ => "unknown",
    }
}

/// The unit of a record's values from its axis labels (`m/s^2 / N`), `-`
/// when the file names none.
pub fn units(f: &Function58) -> String {
    let num = f.numerator_axis.units_label.trim();
    let den = f.denominator_axis.units_label.trim();
    let num = if num.is_empty() || num.eq_ignore_ascii_case("none") {
        ""
    } else {
        num
    };
    let den = if den.is_empty() || den.eq_ignore_ascii_case("none") {
        ""
    } else {
        den
    };
    match (num.is_empty(), den.is_empty()) {
        (true, true) => "-".to_string(),
        (false, true) => num.to_string(),
        (true, false) => format!("1/{den}"),
        (false, false) => format!("{num} / {den}"),
    }
}

fn band(f: &Function58) -> (f64, f64) {
    if f.is_empty() {
        return (f64::NAN, f64::NAN);
    }
    match &f.abscissa {
        Abscissa::Even { .. } => (f.abscissa_at(0), f.abscissa_at(f.len() - 1)),
        Abscissa::Uneven(x) => x
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &v| {
                (lo.min(v), hi.max(v))
            }),
    }
}

/// The table printed by `frfup info`.
pub fn table(file: &UffFile) -> String {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "{:>5}  {:<7} {:<11} {:<11} {:<20} {:<12} {:>8}  {:<24} units",
        "#", "dataset", "response", "reference", "function", "ordinate", "points", "band"
    );
    for (i, d) in file.datasets.iter().enumerate() {
        match d {
            Dataset::Function(f) => {
                let (lo, hi) = band(f);
                let label = f.abscissa_axis.units_label.trim();
                let unit = if label.is_empty() || label.eq_ignore_ascii_case("none") {
                    String::new()
                } else {
                    format!(" {}", f.abscissa_axis.units_label.trim())
                };
                let _ = writeln!(
                    out,
                    "{:>5}  {:<7} {:<11} {:<11} {:<20} {:<12} {:>8}  {:<24} {}",
                    i + 1,
                    if f.binary { "58b" } else { "58" },
                    entity_dof_label(&f.response_entity, f.response_node, f.response_direction),
                    entity_dof_label(&f.reference_entity, f.reference_node, f.reference_direction),
                    format!(
                        "{} {}",
                        f.function_type,
                        function_type_name(f.function_type)
                    ),
                    format!(
                        "{} {}",
                        f.ordinate_type,
                        ordinate_type_name(f.ordinate_type)
                    ),
                    f.len(),
                    format!("{}..{}{}", fmt_num(lo), fmt_num(hi), unit),
                    units(f)
                );
            }
            Dataset::Other(o) => {
                let _ = writeln!(out, "{:>5}  {:<7} {}", i + 1, o.number, o.summary);
            }
        }
    }
    for note in &file.notes {
        let _ = writeln!(out, "note: {note}");
    }
    out
}

fn fmt_num(x: f64) -> String {
    if x == 0.0 || (x.abs() >= 1e-3 && x.abs() < 1e6) {
        let s = format!("{x:.6}");
        let s = s.trim_end_matches('0').trim_end_matches('.');
        s.to_string()
    } else {
        format!("{x:.6e}")
    }
}

/// The JSON printed by `frfup info --json`.
pub fn json(file: &UffFile) -> Value {
    let records: Vec<Value> = file
        .datasets
        .iter()
        .enumerate()
        .map(|(i, d)| match d {
            Dataset::Function(f) => {
                let (lo, hi) = band(f);
                json!({
                    "index": i + 1,
                    "dataset": 58,
                    "binary": f.binary,
                    "response_node": f.response_node,
                    "response_dir": f.response_direction,
                    "reference_node": f.reference_node,
                    "reference_dir": f.reference_direction,
                    "response_entity": f.response_entity.trim(),
                    "reference_entity": f.reference_entity.trim(),
                    "response": entity_dof_label(&f.response_entity, f.response_node, f.response_direction),
                    "reference": entity_dof_label(&f.reference_entity, f.reference_node, f.reference_direction),
                    "function_type": f.function_type,
                    "function": function_type_name(f.function_type),
                    "ordinate_type": f.ordinate_type,
                    "points": f.len(),
                    "abscissa_min": finite_or_null(lo),
                    "abscissa_max": finite_or_null(hi),
                    "even": matches!(f.abscissa, Abscissa::Even { .. }),
                    "abscissa_units": f.abscissa_axis.units_label.trim(),
                    "units": units(f),
                    "numerator_data_type": f.numerator_axis.data_type,
                    "denominator_data_type": f.denominator_axis.data_type,
                })
            }
            Dataset::Other(o) => json!({
                "index": i + 1,
                "dataset": o.number,
                "line": o.line,
                "summary": o.summary,
            }),
        })
        .collect();
    json!({ "records": records, "notes": file.notes })
}

fn finite_or_null(x: f64) -> Value {
    if x.is_finite() {
        json!(x)
    } else {
        Value::Null
    }
}

/// Run `frfup info`: the text table or JSON of one or more files.
pub fn run(paths: &[PathBuf], as_json: bool, progress: Progress) -> Result<String, CommandError> {
    let mut tables = Vec::new();
    let mut records = Vec::new();
    let mut notes = Vec::new();
    for path in paths {
        let file = read_uff(path, progress)?;
        let name = path.display().to_string();
        if as_json {
            let v = json(&file);
            for mut r in v["records"].as_array().cloned().unwrap_or_default() {
                r["file"] = name.clone().into();
                records.push(r);
            }
            notes.extend(file.notes.iter().map(|n| match paths.len() {
                1 => n.clone(),
                _ => format!("{name}: {n}"),
            }));
        } else {
            tables.push((name, table(&file)));
        }
    }
    Ok(if as_json {
        let v = json!({ "records": records, "notes": notes });
        let mut s = serde_json::to_string_pretty(&v).unwrap_or_default();
        s.push('\n');
        s
    } else if tables.len() == 1 {
        tables.remove(0).1
    } else {
        with_file_column(&tables)
    })
}

/// The tables of several files as one, each line led by its file (the
/// header once, `file` first).
fn with_file_column(tables: &[(String, String)]) -> String {
    let width = tables
        .iter()
        .map(|(n, _)| n.len())
        .max()
        .unwrap_or(0)
        .max(4);
    let mut out = String::new();
    for (i, (name, table)) in tables.iter().enumerate() {
        for (k, line) in table.lines().enumerate() {
            match (k, i) {
                (0, 0) => {
                    let _ = writeln!(out, "{:<width$}  {line}", "file");
                }
                (0, _) => {}
                _ => {
                    let _ = writeln!(out, "{name:<width$}  {line}");
                }
            }
        }
    }
    out
}
