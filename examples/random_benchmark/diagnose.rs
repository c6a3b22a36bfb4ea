//! `random_benchmark --diagnose`: the randomised benchmark of `frfup
//! diagnose` (issue 17, item 6). Cases from
//! [`frfup::benchmark::generate_diagnosis`] into DIR/case-NNN/, each run as
//! `frfup diagnose model.deck test.uff --out CASE/out` (no other flag),
//! scored from CASE/out/diagnosis.json against truth.json; DIR/cases.csv,
//! DIR/summary.md, and the summary printed. With `--score-only` the cases
//! already in DIR are scored again (after a change of the scoring) without
//! running anything.

use std::path::Path;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;

use frfup::benchmark::{
    case_seed, diagnosis_summary_markdown, generate_diagnosis, score_diagnosis, DiagRecord,
    GenOptions,
};

use super::{parallel, run_frfup, Args};

/// A written case: its record (before the run) and folder.
struct Written {
    record: DiagRecord,
    dir: std::path::PathBuf,
}

/// Case `i` of the run, written into DIR/case-NNN/ unless `score_only`
/// (then only its record is made: the files are already there).
fn write_case(args: &Args, i: usize) -> Result<Written, String> {
    let seed = case_seed(args.seed, i as u64);
    let case = generate_diagnosis(seed, &GenOptions::diagnosis()).map_err(|e| e.to_string())?;
    let dir = args.out.join(format!("case-{i:03}"));
    if !args.score_only {
        case.write(&dir).map_err(|e| e.to_string())?;
    }
    let record = DiagRecord {
        case: format!("case-{i:03}"),
        seed,
        structure: format!(
            "{} ({})",
            case.structure.name(),
            if case.plane { "plane" } else { "space" }
        ),
        support: case.support.name().to_string(),
        layout: case.layout_label(),
        dofs: case.dofs,
        channels: case.points.len(),
        lines: case.lines_hz.len(),
        noise: case.noise,
        ..DiagRecord::default()
    };
    Ok(Written { record, dir })
}

/// Run one case (its exit code, time and message kept in CASE/run.json),
/// or with `score_only` read them back; then score it.
fn run_case(bin: &Path, w: &Written, args: &Args) -> DiagRecord {
    let mut r = w.record.clone();
    let run_json = w.dir.join("run.json");
    if args.score_only {
        let run: Option<serde_json::Value> = std::fs::read_to_string(&run_json)
            .ok()
            .and_then(|t| serde_json::from_str(&t).ok());
        let run = run.unwrap_or_else(|| serde_json::json!({"message": "not run"}));
        r.exit_code = run["exit_code"].as_i64().map(|c| c as i32);
        r.seconds = run["seconds"].as_f64().unwrap_or(0.0);
        r.message = run["message"].as_str().unwrap_or_default().to_string();
    } else {
        let o = run_frfup(bin, &w.dir, "diagnose", args.timeout, &[]);
        (r.exit_code, r.seconds, r.message) = (o.exit_code, o.seconds, o.message);
        let run = serde_json::json!({
            "exit_code": r.exit_code, "seconds": r.seconds, "message": r.message,
        });
        let _ = std::fs::write(&run_json, format!("{run}\n"));
    }
    let read = |name: &str| std::fs::read_to_string(w.dir.join(name)).ok();
    let truth = read("truth.json").and_then(|t| serde_json::from_str(&t).ok());
    let deck = read("model.deck").and_then(|t| frfup::parsers::deck::parse(&t).ok());
    let diagnosis: Option<serde_json::Value> =
        read("out/diagnosis.json").and_then(|t| serde_json::from_str(&t).ok());
    if let (Some(truth), Some(deck)) = (truth, deck) {
        r.score = score_diagnosis(&truth, &deck, diagnosis.as_ref());
    }
    r
}

/// The whole run.
pub fn run(args: &Args, bin: &Path) -> Result<(), String> {
    std::fs::create_dir_all(&args.out).map_err(|e| format!("{}: {e}", args.out.display()))?;
    let t = Instant::now();
    let written = parallel(args.cases, args.jobs, |i| write_case(args, i));
    let mut cases = Vec::new();
    for (i, w) in written.into_iter().enumerate() {
        match w {
            Ok(w) => cases.push(w),
            Err(e) => eprintln!("case {i}: {e}"),
        }
    }
    let gen_s = t.elapsed().as_secs_f64();
    eprintln!(
        "generated {} case(s) in {gen_s:.1} s into {}",
        cases.len(),
        args.out.display()
    );
    if args.generate_only {
        return Ok(());
    }
    let done = AtomicUsize::new(0);
    let t = Instant::now();
    let rows = parallel(cases.len(), args.jobs, |i| {
        let r = run_case(bin, &cases[i], args);
        let k = done.fetch_add(1, Ordering::SeqCst) + 1;
        let f = r.csv_fields();
        eprintln!(
            "[{k}/{}] {} {} truth [{}] reported [{}] right {} exit {:?} {:.1} s",
            cases.len(),
            r.case,
            r.structure,
            f[9],
            f[10],
            f[11],
            r.exit_code,
            r.seconds
        );
        r
    });
    let run_s = t.elapsed().as_secs_f64();
    write_csv(&args.out.join("cases.csv"), &rows)?;
    let wall = if args.score_only {
        "Scored again from the files of an earlier run (times are that run's).".to_string()
    } else {
        format!(
            "Wall time: generation {gen_s:.0} s, diagnoses {run_s:.0} s ({} at a time).",
            args.jobs
        )
    };
    let summary = format!("{}\n{wall}\n", diagnosis_summary_markdown(&rows));
    std::fs::write(args.out.join("summary.md"), &summary)
        .map_err(|e| format!("{}: {e}", args.out.display()))?;
    println!("{summary}");
    Ok(())
}

fn write_csv(path: &Path, rows: &[DiagRecord]) -> Result<(), String> {
    let err = |e: csv::Error| format!("{}: {e}", path.display());
    let mut w = csv::Writer::from_path(path).map_err(err)?;
    w.write_record(DiagRecord::CSV_HEADER).map_err(err)?;
    for r in rows {
        let mut f = r.csv_fields();
        if !r.message.is_empty() {
            f[15] = format!("{} ({})", f[15], r.message);
        }
        w.write_record(f).map_err(err)?;
    }
    w.flush().map_err(|e| format!("{}: {e}", path.display()))
}
