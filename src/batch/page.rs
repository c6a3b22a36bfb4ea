//! `summary.html` of a batch: the campaign's status box and one row per case,
//! in the status colours and words of the per-case reports (green "✔
//! passed"; red "✘ NOT CONVERGED", "✘ THRESHOLD FAILED", "✘ ERROR", each
//! with why), linking each case's `report.html`.

use std::fmt::Write as _;
use std::path::Path;

use super::{BatchSummary, CaseStatus};
use crate::report::html::{esc, CSS};

/// The class (`ok` or `fail`) and the words of a case's status.
pub fn status_words(status: &CaseStatus) -> (&'static str, String) {
    match status {
        CaseStatus::Passed => ("ok", "✔ passed".into()),
        CaseStatus::NotConverged(r) => ("fail", format!("✘ NOT CONVERGED — {r}")),
        CaseStatus::ThresholdFailed(r) => {
            ("fail", format!("✘ THRESHOLD FAILED — {}", r.join("; ")))
        }
        CaseStatus::Error(e) => ("fail", format!("✘ ERROR — {e}")),
    }
}

/// The page; `dir` is the batch folder (a case's report is linked when it
/// was written).
pub fn summary_html(s: &BatchSummary, dir: &Path) -> String {
    let mut h = format!(
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n<title>frfup batch summary</title>\n<style>{CSS}</style>\n</head>\n<body>\n<h1>frfup batch summary</h1>\n"
    );
    let (class, mark) = if s.exit_code() == 0 {
        ("ok", "✔ Status: every case passed")
    } else {
        ("fail", "✘ Status: FAILED")
    };
    let _ = writeln!(
        h,
        "<div class=\"status {class}\" role=\"status\"><b class=\"word\">{mark}</b><br>{}.</div>",
        esc(&s.totals())
    );
    h.push_str("<table>\n<tr><th class=\"l\">case</th><th class=\"l\">status</th><th>iterations</th><th>SFDAC mean before → after</th><th>mean |Δf/f| before → after (%)</th><th>wall time (s)</th></tr>\n");
    let opt = |x: Option<f64>, d: usize| x.map(|v| format!("{v:.d$}")).unwrap_or_default();
    for c in &s.cases {
        let (class, words) = status_words(&c.status);
        let name = if dir.join(&c.name).join("report.html").is_file() {
            format!("<a href=\"{0}/report.html\">{0}</a>", esc(&c.name))
        } else {
            esc(&c.name)
        };
        let _ = writeln!(
            h,
            "<tr><td class=\"l\">{name}</td><td class=\"l\"><span class=\"status {class}\">{}</span></td><td>{}</td><td>{} → {}</td><td>{} → {}</td><td>{:.2}</td></tr>",
            esc(&words),
            c.iterations.map(|n| n.to_string()).unwrap_or_default(),
            opt(c.sfdac_mean_before, 4),
            opt(c.sfdac_mean_after, 4),
            opt(c.freq_error_before_pct, 3),
            opt(c.freq_error_after_pct, 3),
            c.wall_time_s
        );
    }
    h.push_str("</table>\n</body>\n</html>\n");
    h
}
