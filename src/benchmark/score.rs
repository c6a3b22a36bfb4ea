//! Scoring a case against its truth, and the summary of a run.
//!
//! A case is *within* when every identified parameter's estimate is within
//! [`TOLERANCE`] (absolute, in relative-change units) of its true value and
//! the fit explains the test (at most [`UNEXPLAINED_MISFIT`] times the
//! noise level, where the report gives it); a truth is *covered* when
//! |estimate − truth| ≤ 2 × reported sd.

use std::collections::BTreeMap;

use serde_json::Value;

/// Largest |p̂ − p| of an identified parameter for a case to count as within.
pub const TOLERANCE: f64 = 0.02;

/// Misfit (over the noise level) above which a parameter-only case is not
/// within, however close the identified parameters: the update's own
/// "the deck's parameters do not explain the test" warning. Parameters
/// held as not identified are not scored, so without this a case whose
/// held parameters leave the fit at hundreds of times the noise level
/// would count (seed 2, case 122: 386×).
pub const UNEXPLAINED_MISFIT: f64 = 4.0;

/// One parameter estimate as a report gives it.
#[derive(Clone, Debug, PartialEq)]
pub struct ReportEstimate {
    pub name: String,
    pub value: f64,
    /// One standard deviation, when the report gives it.
    pub sd: Option<f64>,
    /// False when the report says the data do not determine it.
    pub identified: bool,
}

/// The estimates of a `report.json`: `parameter_estimates` (`name`, `value`,
/// `sd`, `identified`) when present, else the `parameters` name → value map
/// (no sd, every parameter identified). `None` if neither is readable.
pub fn report_estimates(report: &Value) -> Option<Vec<ReportEstimate>> {
    if let Some(list) = report.get("parameter_estimates").and_then(Value::as_array) {
        let out: Vec<ReportEstimate> = list
            .iter()
            .filter_map(|e| {
                Some(ReportEstimate {
                    name: e.get("name")?.as_str()?.to_string(),
                    value: e.get("value")?.as_f64()?,
                    sd: e.get("sd").and_then(Value::as_f64),
                    identified: e.get("identified").and_then(Value::as_bool).unwrap_or(true),
                })
            })
            .collect();
        return Some(out);
    }
    let map = report.get("parameters")?.as_object()?;
    Some(
        map.iter()
            .filter_map(|(k, v)| {
                Some(ReportEstimate {
                    name: k.clone(),
                    value: v.as_f64()?,
                    sd: None,
                    identified: true,
                })
            })
            .collect(),
    )
}

/// How one case scored.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct CaseScore {
    /// Every identified parameter within [`TOLERANCE`] (None: no estimates).
    pub within: Option<bool>,
    /// Largest |p̂ − p| over identified parameters.
    pub max_error: Option<f64>,
    pub parameters: usize,
    pub identified: usize,
    /// Truths inside ±2 sd, out of the parameters with an sd.
    pub covered: usize,
    pub with_sd: usize,
    /// `converged` of the report (None: no report).
    pub converged: Option<bool>,
    pub stop: String,
}

/// Score estimates against the truth (name, true p). A true parameter with
/// no estimate counts as identified and missed.
pub fn score_estimates(truth: &[(String, f64)], estimates: &[ReportEstimate]) -> CaseScore {
    let mut s = CaseScore {
        parameters: truth.len(),
        ..CaseScore::default()
    };
    let mut worst = 0.0f64;
    for (name, p) in truth {
        let Some(e) = estimates.iter().find(|e| &e.name == name) else {
            worst = f64::INFINITY;
            s.identified += 1;
            continue;
        };
        let err = (e.value - p).abs();
        if let Some(sd) = e.sd.filter(|v| v.is_finite()) {
            s.with_sd += 1;
            s.covered += usize::from(err <= 2.0 * sd);
        }
        if e.identified {
            s.identified += 1;
            worst = worst.max(if err.is_finite() { err } else { f64::INFINITY });
        }
    }
    s.max_error = Some(worst);
    s.within = Some(worst <= TOLERANCE);
    s
}

/// Score a `report.json` against the truth.
pub fn score_report(truth: &[(String, f64)], report: &Value) -> CaseScore {
    let mut s = match report_estimates(report) {
        Some(e) => score_estimates(truth, &e),
        None => CaseScore {
            parameters: truth.len(),
            ..CaseScore::default()
        },
    };
    let misfit = report
        .get("estimate")
        .and_then(|e| e.get("misfit_over_noise"))
        .and_then(Value::as_f64);
    if misfit.is_some_and(|m| m > UNEXPLAINED_MISFIT) && s.within.is_some() {
        s.within = Some(false);
    }
    s.converged = report.get("converged").and_then(Value::as_bool);
    s.stop = report
        .get("stop")
        .and_then(Value::as_str)
        .unwrap_or_default()
        .to_string();
    s
}

/// One case of a run: what it was and how it went.
#[derive(Clone, Debug, Default)]
pub struct RunRecord {
    pub case: String,
    pub structure: String,
    pub layout: String,
    pub support: String,
    pub damping: String,
    pub format: String,
    pub axis: String,
    pub dofs: usize,
    pub channels: usize,
    pub noise: f64,
    /// Exit code of `frfup update` (None: killed or did not start).
    pub exit_code: Option<i32>,
    pub seconds: f64,
    pub score: CaseScore,
    /// The last stderr line of a failed run.
    pub message: String,
}

impl RunRecord {
    /// Exit 1, or a report that says not converged.
    pub fn not_converged(&self) -> bool {
        self.exit_code == Some(1)
            || (self.exit_code == Some(0) && self.score.converged == Some(false))
    }
    /// Column names of [`RunRecord::csv_fields`].
    pub const CSV_HEADER: [&'static str; 20] = [
        "case",
        "structure",
        "layout",
        "support",
        "damping",
        "format",
        "axis",
        "dofs",
        "channels",
        "noise",
        "exit_code",
        "seconds",
        "converged",
        "stop",
        "parameters",
        "identified",
        "max_error",
        "within",
        "covered_2sd",
        "message",
    ];
    /// The CSV row.
    pub fn csv_fields(&self) -> Vec<String> {
        let opt = |v: Option<String>| v.unwrap_or_default();
        vec![
            self.case.clone(),
            self.structure.clone(),
            self.layout.clone(),
            self.support.clone(),
            self.damping.clone(),
            self.format.clone(),
            self.axis.clone(),
            self.dofs.to_string(),
            self.channels.to_string(),
            format!("{}", self.noise),
            opt(self.exit_code.map(|c| c.to_string())),
            format!("{:.3}", self.seconds),
            opt(self.score.converged.map(|c| c.to_string())),
            self.score.stop.clone(),
            self.score.parameters.to_string(),
            self.score.identified.to_string(),
            opt(self.score.max_error.map(|e| format!("{e:.5}"))),
            opt(self.score.within.map(|w| w.to_string())),
            if self.score.with_sd > 0 {
                format!("{}/{}", self.score.covered, self.score.with_sd)
            } else {
                String::new()
            },
            self.message.clone(),
        ]
    }
}

/// A failure message without its file names and with every number written
/// `#`, so that the same failure on different cases groups together.
pub fn message_class(message: &str) -> String {
    let tail = message.rsplit_once(".uff: ").map_or(message, |(_, t)| t);
    let mut out = String::new();
    let mut in_number = false;
    for ch in tail.chars() {
        if ch.is_ascii_digit() {
            if !in_number {
                out.push('#');
            }
            in_number = true;
        } else {
            in_number = false;
            out.push(ch);
        }
    }
    out.chars().take(160).collect()
}

/// The row of a group in the summary table.
fn group_row(name: &str, rows: &[&RunRecord]) -> String {
    let n = rows.len();
    let within = rows.iter().filter(|r| r.score.within == Some(true)).count();
    let (cov, with_sd) = rows.iter().fold((0, 0), |a, r| {
        (a.0 + r.score.covered, a.1 + r.score.with_sd)
    });
    let coverage = if with_sd > 0 {
        format!(
            "{:.1} % ({cov}/{with_sd})",
            100.0 * cov as f64 / with_sd as f64
        )
    } else {
        "n/a".to_string()
    };
    let not_conv = rows.iter().filter(|r| r.not_converged()).count();
    let exit2 = rows.iter().filter(|r| r.exit_code == Some(2)).count();
    let other = rows
        .iter()
        .filter(|r| !matches!(r.exit_code, Some(0..=2)))
        .count();
    let mut t: Vec<f64> = rows.iter().map(|r| r.seconds).collect();
    t.sort_by(f64::total_cmp);
    let median = t.get(n / 2).copied().unwrap_or(0.0);
    let worst = t.last().copied().unwrap_or(0.0);
    format!(
        "| {name} | {n} | {:.1} % ({within}) | {coverage} | {not_conv} | {exit2} | {other} | {median:.2} s | {worst:.2} s |",
        100.0 * within as f64 / n.max(1) as f64
    )
}

/// The Markdown summary: all cases, then by structure kind and by layout,
/// then the most frequent failure messages.
pub fn summary_markdown(rows: &[RunRecord]) -> String {
    let mut s = String::new();
    s.push_str("| cases | n | every identified p within 0.02 | truths inside ±2 sd | not converged | exit 2 | crashed/timed out | median time | worst time |\n");
    s.push_str("|---|---|---|---|---|---|---|---|---|\n");
    let all: Vec<&RunRecord> = rows.iter().collect();
    s.push_str(&group_row("**all**", &all));
    s.push('\n');
    for key in [
        |r: &RunRecord| r.structure.clone(),
        |r: &RunRecord| r.layout.clone(),
        |r: &RunRecord| r.support.clone(),
        |r: &RunRecord| r.damping.clone(),
    ] {
        let mut groups: BTreeMap<String, Vec<&RunRecord>> = BTreeMap::new();
        for r in rows {
            groups.entry(key(r)).or_default().push(r);
        }
        for (name, g) in groups {
            s.push_str(&group_row(&name, &g));
            s.push('\n');
        }
    }
    let mut messages: BTreeMap<String, usize> = BTreeMap::new();
    for r in rows.iter().filter(|r| r.exit_code != Some(0)) {
        let code = r.exit_code.map_or("none".to_string(), |c| c.to_string());
        *messages
            .entry(format!("exit {code}: {}", message_class(&r.message)))
            .or_default() += 1;
    }
    if !messages.is_empty() {
        let mut list: Vec<(String, usize)> = messages.into_iter().collect();
        list.sort_by(|a, b| b.1.cmp(&a.1).then(a.0.cmp(&b.0)));
        s.push_str("\nMost frequent failures:\n\n");
        for (m, n) in list.iter().take(8) {
            s.push_str(&format!("- {n} × {m}\n"));
        }
    }
    s
}
