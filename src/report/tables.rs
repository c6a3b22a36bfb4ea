//! CSV tables of the report that [`super::output::write_outputs`] does not write
//! (it writes `parameters.csv`, `frequencies.csv`, `sfdac.csv`). Units are in
//! the column names; empty cells are missing values.
//!
//! * `iterations.csv`: rank, step scale and the step p^n of every iteration;
//! * `resonances.csv`: the measured resonances (peak picking);
//! * `updating-frequencies.csv`: the updating frequencies used and skipped;
//! * `mac.csv`: the MAC matrices of the MAC chart (long format): the test
//!   shapes that paired the resonances (`test_shapes`: `fitted` or `ods`)
//!   against the FE modes;
//! * `frf.csv`: measured, initial and updated FRFs (long format).

use super::data::ReportData;
use crate::updating::frequencies::FrequencySource;
use crate::updating::UpdateResult;

/// A finite number by `fmt`, −0 written as 0; empty otherwise.
fn num(v: f64, fmt: fn(f64) -> String) -> String {
    if v.is_finite() {
        fmt(v + 0.0)
    } else {
        String::new()
    }
}

/// Seven significant digits by the CSV rule of [`crate::fsio::csv_number`]:
/// plain decimal for 1e-4 ≤ |x| < 1e6, else `1.234568e-5`; zero is `0`.
pub fn e6(v: f64) -> String {
    crate::fsio::csv_number_sig(v, 7)
}

/// Six decimals, fixed point (an empty field when not finite).
pub fn f6(v: f64) -> String {
    num(v, |x| format!("{x:.6}"))
}

/// CSV text of `rows` (the header first), each field quoted where it needs
/// to be by the `csv` crate; lines end in `\n`.
pub fn csv_text<R, F>(rows: R) -> String
where
    R: IntoIterator,
    R::Item: IntoIterator<Item = F>,
    F: AsRef<[u8]>,
{
    let mut w = csv::WriterBuilder::new()
        .flexible(true)
        .from_writer(Vec::new());
    for row in rows {
        // Writing to memory cannot fail.
        let _ = w.write_record(row);
    }
    String::from_utf8(w.into_inner().unwrap_or_default()).unwrap_or_default()
}

fn header(names: &str) -> Vec<String> {
    names.split(',').map(String::from).collect()
}

/// `iterations.csv`.
pub fn iterations_csv(result: &UpdateResult) -> String {
    let head =
        header("iteration,rank,step_scale,max_abs_step,sfdac_mean,sfdac_min,basis_modes,returned")
            .into_iter()
            .chain(result.parameter_names.iter().map(|n| format!("step_{n}")));
    let rows = result.iterations.iter().enumerate().map(|(i, r)| {
        let max_step = r.step.iter().fold(0.0f64, |m, p| m.max(p.abs()));
        [
            r.index.to_string(),
            r.rank.to_string(),
            f6(r.step_scale),
            e6(max_step),
            f6(r.sfdac.mean),
            f6(r.sfdac.min),
            r.basis_modes.len().to_string(),
            (i == result.final_iteration).to_string(),
        ]
        .into_iter()
        .chain(r.step.iter().map(|p| e6(*p)))
        .collect::<Vec<_>>()
    });
    csv_text(std::iter::once(head.collect()).chain(rows))
}

/// `resonances.csv`.
pub fn resonances_csv(result: &UpdateResult) -> String {
    let rows = result.resonances.iter().enumerate().map(|(i, r)| {
        vec![
            (i + 1).to_string(),
            f6(r.frequency_hz),
            r.damping_ratio.map(f6).unwrap_or_default(),
            f6(r.prominence),
            r.line.to_string(),
            (i < result.resonances_used).to_string(),
        ]
    });
    csv_text(
        std::iter::once(header(
            "resonance,frequency_hz,damping_ratio,prominence,line,used",
        ))
        .chain(rows),
    )
}

/// `updating-frequencies.csv`.
pub fn updating_frequencies_csv(result: &UpdateResult) -> String {
    let used = result.updating_frequencies.frequencies.iter().map(|u| {
        let source = match u.source {
            FrequencySource::Resonance { resonance, side } => {
                format!(
                    "{} resonance {}",
                    if side < 0 { "below" } else { "above" },
                    resonance + 1
                )
            }
            FrequencySource::Explicit => "explicit".to_string(),
        };
        let (hz, requested) = (f6(u.hz), f6(u.requested_hz));
        vec![
            hz,
            requested,
            u.line.to_string(),
            source,
            "used".into(),
            String::new(),
        ]
    });
    let skipped = result.updating_frequencies.skipped.iter().map(|k| {
        let requested = f6(k.requested_hz);
        let reason = k.reason.clone();
        vec![
            String::new(),
            requested,
            String::new(),
            String::new(),
            "skipped".into(),
            reason,
        ]
    });
    csv_text(
        std::iter::once(header(
            "frequency_hz,requested_hz,line,source,status,reason",
        ))
        .chain(used)
        .chain(skipped),
    )
}

/// `mac.csv`.
pub fn mac_csv(data: &ReportData) -> String {
    let mut rows = vec![header(
        "model,test_resonance,test_label,fe_mode_hz,mac,paired,test_shapes",
    )];
    let shapes = match data.mac_source {
        crate::updating::ShapeSource::Fitted => "fitted",
        crate::updating::ShapeSource::OperatingDeflection => "ods",
    };
    for p in &data.mac.panels {
        for (t, row) in p.values.iter().enumerate() {
            for (c, v) in row.iter().enumerate() {
                rows.push(vec![
                    p.label.clone(),
                    (t + 1).to_string(),
                    data.mac.row_labels.get(t).cloned().unwrap_or_default(),
                    p.column_labels.get(c).cloned().unwrap_or_default(),
                    f6(*v),
                    p.pairs.contains(&(t, c)).to_string(),
                    shapes.to_string(),
                ]);
            }
        }
    }
    csv_text(rows)
}

/// `frf.csv`: one row per channel and line, real and imaginary parts of each
/// series in the measured FRF kind.
pub fn frf_csv(data: &ReportData) -> String {
    use rayon::prelude::*;
    let o = &data.frf;
    let units = data.kind.units();
    let mut head = header("channel,frequency_hz");
    for l in &o.series_labels {
        let key = l.replace(' ', "_");
        head.push(format!("{key}_re[{units}]"));
        head.push(format!("{key}_im[{units}]"));
    }
    let mut text = csv_text([head]);
    // One block of rows per channel, on every core, joined in order. Only
    // the label can need quoting (numbers and empty cells never do in a
    // record of several fields); it is quoted once, by the csv crate.
    let blocks: Vec<String> = o
        .channels
        .par_iter()
        .map(|ch| {
            let quoted = csv_text([[ch.label.as_str(), ""]]);
            let label = quoted.trim_end_matches('\n').trim_end_matches(',');
            let mut block = String::new();
            for (line, f) in o.frequencies_hz.iter().enumerate() {
                block.push_str(label);
                block.push(',');
                block.push_str(&f6(*f));
                for series in &ch.values {
                    block.push(',');
                    if let Some(v) = series.get(line) {
                        block.push_str(&e6(v.re));
                        block.push(',');
                        block.push_str(&e6(v.im));
                    } else {
                        block.push(',');
                    }
                }
                block.push('\n');
            }
            block
        })
        .collect();
    for b in blocks {
        text.push_str(&b);
    }
    text
}
