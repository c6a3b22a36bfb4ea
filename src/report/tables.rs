//! CSV tables of the report that [`super::output::write_outputs`] does not write
//! (it writes `parameters.csv`, `frequencies.csv`, `sfdac.csv`). Units are in
//! the column names; empty cells are missing values.
//!
//! * `iterations.csv`: rank, step scale and the step p^n of every iteration;
//! * `resonances.csv`: the measured resonances (peak picking);
//! * `updating-frequencies.csv`: the updating frequencies used and skipped;
//! * `mac.csv`: the MAC matrices of the MAC chart (long format): the test's
//!   operating deflection shapes against the FE modes, hence `mac_ods`;
//! * `frf.csv`: measured, initial and updated FRFs (long format).

use std::fmt::Write as _;

use super::data::ReportData;
use crate::updating::frequencies::FrequencySource;
use crate::updating::UpdateResult;

fn num(v: f64, fmt: fn(f64) -> String) -> String {
    if v.is_finite() {
        fmt(v)
    } else {
        String::new()
    }
}

fn e6(v: f64) -> String {
    num(v, |x| format!("{x:.6e}"))
}

fn f6(v: f64) -> String {
    num(v, |x| format!("{x:.6}"))
}

/// A CSV field, quoted when needed.
pub fn field(s: &str) -> String {
    if s.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

/// `iterations.csv`.
pub fn iterations_csv(result: &UpdateResult) -> String {
    let mut s = String::from(
        "iteration,rank,step_scale,max_abs_step,sfdac_mean,sfdac_min,basis_modes,returned",
    );
    for n in &result.parameter_names {
        s.push(',');
        s.push_str(&field(&format!("step_{n}")));
    }
    s.push('\n');
    for (i, r) in result.iterations.iter().enumerate() {
        let max_step = r.step.iter().fold(0.0f64, |m, p| m.max(p.abs()));
        let _ = write!(
            s,
            "{},{},{},{},{},{},{},{}",
            r.index,
            r.rank,
            f6(r.step_scale),
            e6(max_step),
            f6(r.sfdac.mean),
            f6(r.sfdac.min),
            r.basis_modes.len(),
            i == result.final_iteration
        );
        for p in &r.step {
            s.push(',');
            s.push_str(&e6(*p));
        }
        s.push('\n');
    }
    s
}

/// `resonances.csv`.
pub fn resonances_csv(result: &UpdateResult) -> String {
    let mut s = String::from("resonance,frequency_hz,damping_ratio,prominence,line,used\n");
    for (i, r) in result.resonances.iter().enumerate() {
        let _ = writeln!(
            s,
            "{},{},{},{},{},{}",
            i + 1,
            f6(r.frequency_hz),
            r.damping_ratio.map(f6).unwrap_or_default(),
            f6(r.prominence),
            r.line,
            i < result.resonances_used
        );
    }
    s
}

/// `updating-frequencies.csv`.
pub fn updating_frequencies_csv(result: &UpdateResult) -> String {
    let mut s = String::from("frequency_hz,requested_hz,line,source,status,reason\n");
    for u in &result.updating_frequencies.frequencies {
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
        let _ = writeln!(
            s,
            "{},{},{},{},used,",
            f6(u.hz),
            f6(u.requested_hz),
            u.line,
            source
        );
    }
    for k in &result.updating_frequencies.skipped {
        let _ = writeln!(s, ",{},,,skipped,{}", f6(k.requested_hz), field(&k.reason));
    }
    s
}

/// `mac.csv`.
pub fn mac_csv(data: &ReportData) -> String {
    let mut s = String::from("model,test_resonance,test_label,fe_mode_hz,mac_ods,paired\n");
    for p in &data.mac.panels {
        for (t, row) in p.values.iter().enumerate() {
            for (c, v) in row.iter().enumerate() {
                let _ = writeln!(
                    s,
                    "{},{},{},{},{},{}",
                    field(&p.label),
                    t + 1,
                    field(data.mac.row_labels.get(t).map(String::as_str).unwrap_or("")),
                    p.column_labels.get(c).map(|l| field(l)).unwrap_or_default(),
                    f6(*v),
                    p.pairs.contains(&(t, c))
                );
            }
        }
    }
    s
}

/// `frf.csv`: one row per channel and line, real and imaginary parts of each
/// series in the measured FRF kind.
pub fn frf_csv(data: &ReportData) -> String {
    let o = &data.frf;
    let units = data.kind.units();
    let mut s = String::from("channel,frequency_hz");
    for l in &o.series_labels {
        let key = l.replace(' ', "_");
        let _ = write!(s, ",{}", field(&format!("{key}_re[{units}]")));
        let _ = write!(s, ",{}", field(&format!("{key}_im[{units}]")));
    }
    s.push('\n');
    for ch in &o.channels {
        for (line, f) in o.frequencies_hz.iter().enumerate() {
            let _ = write!(s, "{},{}", field(&ch.label), f6(*f));
            for series in &ch.values {
                match series.get(line) {
                    Some(v) => {
                        let _ = write!(s, ",{},{}", e6(v.re), e6(v.im));
                    }
                    None => s.push_str(",,"),
                }
            }
            s.push('\n');
        }
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fields_and_numbers() {
        assert_eq!(field("a,b"), "\"a,b\"");
        assert_eq!(field("say \"x\""), "\"say \"\"x\"\"\"");
        assert_eq!(e6(f64::NAN), "");
        assert_eq!(f6(1.5), "1.500000");
    }
}
