//! `frfup batch`: run a campaign of updates for CI. Each case gets its own
//! folder; `summary.md`, `summary.csv`, `summary.json` and `summary.html` give one line per
//! case. A failing case never stops the others. Exit code: 2 if any case could
//! not run, else 1 if any threshold failed, else 0.

pub mod campaign;
pub mod page;

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;
use std::time::Instant;

use serde_json::json;

pub use campaign::{Campaign, Case, Shard};

use crate::fsio::write_atomic;
use crate::report::status::not_converged_reason;
use crate::tasks::update::{self as update_task, Thresholds, UpdateCommand};
use crate::tasks::CommandError;

/// Options of `frfup batch`.
#[derive(Clone, Debug)]
pub struct BatchOptions {
    pub campaign: PathBuf,
    pub out: PathBuf,
    /// Cases run at once (≥ 1).
    pub jobs: usize,
    pub shard: Option<Shard>,
    /// Thresholds from the command line: override the campaign file's, not a case's own.
    pub thresholds: Thresholds,
    /// `--strict`: a warning about a case's input makes the case an error.
    pub strict: bool,
}

/// How a case ended.
#[derive(Clone, Debug, PartialEq)]
pub enum CaseStatus {
    Passed,
    /// Ran, but did not converge (why it stopped): a failure.
    NotConverged(String),
    /// Ran, but a threshold failed (the reasons).
    ThresholdFailed(Vec<String>),
    /// Could not run (the error message).
    Error(String),
}

impl CaseStatus {
    pub fn name(&self) -> &'static str {
        match self {
            CaseStatus::Passed => "passed",
            CaseStatus::NotConverged(_) => "not-converged",
            CaseStatus::ThresholdFailed(_) => "threshold-failed",
            CaseStatus::Error(_) => "error",
        }
    }
    fn detail(&self) -> String {
        match self {
            CaseStatus::Passed => String::new(),
            CaseStatus::NotConverged(r) => r.clone(),
            CaseStatus::ThresholdFailed(r) => r.join("; "),
            CaseStatus::Error(e) => e.clone(),
        }
    }
}

/// One line of the summary.
#[derive(Clone, Debug, PartialEq)]
pub struct CaseSummary {
    pub name: String,
    pub status: CaseStatus,
    pub converged: Option<bool>,
    pub iterations: Option<usize>,
    pub sfdac_mean_before: Option<f64>,
    pub sfdac_mean_after: Option<f64>,
    pub sfdac_min_before: Option<f64>,
    pub sfdac_min_after: Option<f64>,
    /// Mean |Δf/f| (%) over paired resonances.
    pub freq_error_before_pct: Option<f64>,
    pub freq_error_after_pct: Option<f64>,
    pub wall_time_s: f64,
    /// What the readers noticed in the case's inputs (data skipped or doubtful).
    pub input_notes: Vec<String>,
}

/// The outcome of a batch.
#[derive(Clone, Debug, PartialEq)]
pub struct BatchSummary {
    pub cases: Vec<CaseSummary>,
    /// Cases of the campaign not in this shard.
    pub skipped_by_shard: usize,
}

impl BatchSummary {
    /// Cases with the status named `name` ("passed", "not-converged", …).
    pub fn count(&self, name: &str) -> usize {
        self.cases
            .iter()
            .filter(|c| c.status.name() == name)
            .count()
    }

    /// "4 case(s) run: 1 passed, 2 not converged, 1 threshold failed, 0 in error (3 failed)".
    pub fn totals(&self) -> String {
        let passed = self.count("passed");
        format!(
            "{} case(s) run: {} passed, {} not converged, {} threshold failed, {} in error ({} failed)",
            self.cases.len(),
            passed,
            self.count("not-converged"),
            self.count("threshold-failed"),
            self.count("error"),
            self.cases.len() - passed
        )
    }

    /// 2 if any case could not run, else 1 if any case did not converge or
    /// failed a threshold, else 0.
    pub fn exit_code(&self) -> i32 {
        if self
            .cases
            .iter()
            .any(|c| matches!(c.status, CaseStatus::Error(_)))
        {
            2
        } else if self.cases.iter().any(|c| {
            matches!(
                c.status,
                CaseStatus::ThresholdFailed(_) | CaseStatus::NotConverged(_)
            )
        }) {
            1
        } else {
            0
        }
    }
}

/// Run one case into `dir`.
pub fn run_case(case: &Case, dir: &Path, thresholds: Thresholds, strict: bool) -> CaseSummary {
    let start = Instant::now();
    let cmd = UpdateCommand {
        deck: case.model.clone(),
        test: case.test.clone(),
        out: dir.to_path_buf(),
        options: case.options.clone(),
        strict,
    };
    let outcome = std::panic::catch_unwind(|| update_task::run(&cmd, &mut |_| {}));
    let wall_time_s = start.elapsed().as_secs_f64();
    let empty = |status| CaseSummary {
        name: case.name.clone(),
        status,
        converged: None,
        iterations: None,
        sfdac_mean_before: None,
        sfdac_mean_after: None,
        sfdac_min_before: None,
        sfdac_min_after: None,
        freq_error_before_pct: None,
        freq_error_after_pct: None,
        wall_time_s,
        input_notes: Vec::new(),
    };
    let outcome = match outcome {
        Ok(Ok(o)) => o,
        Ok(Err(e)) => return empty(CaseStatus::Error(e.message)),
        Err(_) => {
            return empty(CaseStatus::Error(
                "internal error (panic) while updating; please report it".into(),
            ))
        }
    };
    let r = &outcome.result;
    let first = &r.iterations[0];
    let last = r.final_record();
    let reasons = update_task::threshold_failures(&outcome, thresholds);
    CaseSummary {
        name: case.name.clone(),
        status: if !r.converged {
            CaseStatus::NotConverged(not_converged_reason(r))
        } else if reasons.is_empty() {
            CaseStatus::Passed
        } else {
            CaseStatus::ThresholdFailed(reasons)
        },
        converged: Some(r.converged),
        iterations: Some(r.iterations.len() - 1),
        sfdac_mean_before: Some(first.sfdac.mean),
        sfdac_mean_after: Some(last.sfdac.mean),
        sfdac_min_before: Some(first.sfdac.min),
        sfdac_min_after: Some(last.sfdac.min),
        freq_error_before_pct: outcome.freq_error_initial_pct,
        freq_error_after_pct: outcome.freq_error_updated_pct,
        wall_time_s,
        input_notes: outcome.input_notes.clone(),
    }
}

/// Read the campaign and run this shard's cases, `jobs` at a time; writes the
/// summaries. `on_done` is called as each case finishes (from worker threads).
pub fn run(
    opts: &BatchOptions,
    on_done: &(dyn Fn(&CaseSummary, usize, usize) + Sync),
) -> Result<BatchSummary, CommandError> {
    let bytes = crate::fsio::read_input(&opts.campaign).map_err(CommandError::input)?;
    let text = String::from_utf8(bytes).map_err(|e| {
        CommandError::input(format!(
            "{}: not UTF-8 text (invalid byte at offset {})",
            opts.campaign.display(),
            e.utf8_error().valid_up_to()
        ))
    })?;
    let campaign =
        campaign::parse(&text, &opts.campaign).map_err(|e| CommandError::input(e.message))?;
    let cases: Vec<&Case> = campaign
        .cases
        .iter()
        .filter(|c| opts.shard.is_none_or(|s| s.contains(c.index)))
        .collect();
    let defaults = opts.thresholds.or(campaign.thresholds);
    // The case folders and the summaries land together (`fsio::write_folder`).
    crate::fsio::write_folder(&opts.out, |dir| -> Result<BatchSummary, CommandError> {
        let cases = run_cases(&cases, dir, defaults, opts, on_done);
        let summary = BatchSummary {
            skipped_by_shard: campaign.cases.len() - cases.len(),
            cases,
        };
        write_summaries(dir, &summary)?;
        Ok(summary)
    })
}

/// Run `cases` into `dir/NAME`, `jobs` at a time; summaries in campaign order.
fn run_cases(
    cases: &[&Case],
    dir: &Path,
    defaults: Thresholds,
    opts: &BatchOptions,
    on_done: &(dyn Fn(&CaseSummary, usize, usize) + Sync),
) -> Vec<CaseSummary> {
    let strict = opts.strict;
    let results: Mutex<Vec<Option<CaseSummary>>> = Mutex::new(vec![None; cases.len()]);
    let next = AtomicUsize::new(0);
    let done = AtomicUsize::new(0);
    let jobs = opts.jobs.clamp(1, cases.len().max(1));
    std::thread::scope(|s| {
        for _ in 0..jobs {
            s.spawn(|| loop {
                let i = next.fetch_add(1, Ordering::SeqCst);
                let Some(case) = cases.get(i) else { break };
                let summary = run_case(
                    case,
                    &dir.join(&case.name),
                    case.thresholds.or(defaults),
                    strict,
                );
                let n = done.fetch_add(1, Ordering::SeqCst) + 1;
                on_done(&summary, n, cases.len());
                if let Ok(mut r) = results.lock() {
                    r[i] = Some(summary);
                }
            });
        }
    });
    results
        .into_inner()
        .unwrap_or_default()
        .into_iter()
        .flatten()
        .collect()
}

fn opt(x: Option<f64>, digits: usize) -> String {
    x.map(|v| format!("{v:.digits$}")).unwrap_or_default()
}

/// `summary.md`, `summary.csv`, `summary.json` in `dir`.
pub fn write_summaries(dir: &Path, s: &BatchSummary) -> Result<(), CommandError> {
    let mut csv = String::from(
        "case,status,converged,iterations,sfdac_mean_before,sfdac_mean_after,sfdac_min_before,sfdac_min_after,freq_error_before_pct,freq_error_after_pct,wall_time_s,detail\n",
    );
    let mut w = csv::WriterBuilder::new()
        .has_headers(false)
        .from_writer(Vec::new());
    for c in &s.cases {
        let _ = w.write_record([
            c.name.clone(),
            c.status.name().to_string(),
            c.converged.map(|b| b.to_string()).unwrap_or_default(),
            c.iterations.map(|n| n.to_string()).unwrap_or_default(),
            opt(c.sfdac_mean_before, 6),
            opt(c.sfdac_mean_after, 6),
            opt(c.sfdac_min_before, 6),
            opt(c.sfdac_min_after, 6),
            opt(c.freq_error_before_pct, 4),
            opt(c.freq_error_after_pct, 4),
            format!("{:.3}", c.wall_time_s),
            c.status.detail(),
        ]);
    }
    csv.push_str(&String::from_utf8_lossy(
        &w.into_inner().unwrap_or_default(),
    ));

    let mut md = String::from("# frfup batch summary\n\n");
    let _ = writeln!(
        md,
        "{}{}.\n",
        s.totals(),
        if s.skipped_by_shard > 0 {
            format!(" ({} case(s) belong to other shards)", s.skipped_by_shard)
        } else {
            String::new()
        }
    );
    md.push_str("| case | status | iterations | SFDAC mean before → after | SFDAC min before → after | mean \\|Δf/f\\| before → after (%) | wall time (s) | detail |\n");
    md.push_str("|---|---|---:|---|---|---|---:|---|\n");
    for c in &s.cases {
        let _ = writeln!(
            md,
            "| {} | {} | {} | {} → {} | {} → {} | {} → {} | {:.2} | {} |",
            c.name,
            c.status.name(),
            c.iterations.map(|n| n.to_string()).unwrap_or_default(),
            opt(c.sfdac_mean_before, 4),
            opt(c.sfdac_mean_after, 4),
            opt(c.sfdac_min_before, 4),
            opt(c.sfdac_min_after, 4),
            opt(c.freq_error_before_pct, 3),
            opt(c.freq_error_after_pct, 3),
            c.wall_time_s,
            c.status.detail().replace('|', "\\|").replace('\n', " ")
        );
    }
    let noted: Vec<&CaseSummary> = s
        .cases
        .iter()
        .filter(|c| !c.input_notes.is_empty())
        .collect();
    if !noted.is_empty() {
        md.push_str("\n## Warnings on the inputs\n\n");
        for c in noted {
            for n in &c.input_notes {
                let _ = writeln!(md, "- {}: {}", c.name, n.replace('\n', " "));
            }
        }
    }
    let json = summary_json(s);
    let html = page::summary_html(s, dir);
    let json = serde_json::to_string_pretty(&json).unwrap_or_default() + "\n";
    for (name, body) in [
        ("summary.csv", csv),
        ("summary.md", md),
        ("summary.json", json),
        ("summary.html", html),
    ] {
        let p = dir.join(name);
        write_atomic(&p, body.as_bytes()).map_err(|e| CommandError::output(&p, e))?;
    }
    Ok(())
}

/// `summary.json` as a value (also `frfup batch --json`'s stdout).
pub fn summary_json(s: &BatchSummary) -> serde_json::Value {
    json!({
        "exit_code": s.exit_code(),
        "totals": {
            "cases": s.cases.len(),
            "passed": s.count("passed"),
            "not_converged": s.count("not-converged"),
            "threshold_failed": s.count("threshold-failed"),
            "error": s.count("error"),
            "failed": s.cases.len() - s.count("passed"),
        },
        "skipped_by_shard": s.skipped_by_shard,
        "cases": s.cases.iter().map(|c| json!({
            "name": c.name,
            "status": c.status.name(),
            "detail": c.status.detail(),
            "converged": c.converged,
            "iterations": c.iterations,
            "sfdac_mean_before": c.sfdac_mean_before,
            "sfdac_mean_after": c.sfdac_mean_after,
            "sfdac_min_before": c.sfdac_min_before,
            "sfdac_min_after": c.sfdac_min_after,
            "freq_error_before_pct": c.freq_error_before_pct,
            "freq_error_after_pct": c.freq_error_after_pct,
            "wall_time_s": c.wall_time_s,
            "input_notes": c.input_notes,
        })).collect::<Vec<_>>(),
    })
}
