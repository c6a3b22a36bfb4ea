//! `random_benchmark --diagnose`: the randomised benchmark of `frfup
//! diagnose` (issue 17, item 6). Cases from
//! [`frfup::benchmark::generate_diagnosis`] into DIR/case-NNN/, each run as
//! `frfup diagnose model.deck test.uff --out CASE/out` (no other flag),
//! scored from CASE/out/diagnosis.json against truth.json; DIR/cases.csv,
//! DIR/summary.md, and the summary printed.

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

fn write_case(args: &Args, i: usize) -> Result<Written, String> {
    let seed = case_seed(args.seed, i as u64);
    let case = generate_diagnosis(seed, &GenOptions::diagnosis()).map_err(|e| e.to_string())?;
    let dir = args.out.join(format!("case-{i:03}"));
    case.write(&dir).map_err(|e| e.to_string())?;
    let record = DiagRecord {
        case: format!("case-{i:03}"),
        seed,
        structure: format!(
            "{} ({})",
            case.structure.name(),
            if case.plane { "plane" } else { "space" }
        ),
        support: case.support.name().to_string(),
        layout: case.layout.name().to_string(),
        dofs: case.dofs,
        channels: case.points.len(),
        lines: case.lines_hz.len(),
        noise: case.noise,
        ..DiagRecord::default()
    };
    Ok(Written { record, dir })
}

/// Run and score one case.
fn run_case(bin: &Path, w: &Written, timeout: f64) -> DiagRecord {
    let mut r = w.record.clone();
    let o = run_frfup(bin, &w.dir, "diagnose", timeout, &[]);
    (r.exit_code, r.seconds, r.message) = (o.exit_code, o.seconds, o.message);
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
        let r = run_case(bin, &cases[i], args.timeout);
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
    let summary = format!(
        "{}\nWall time: generation {gen_s:.0} s, diagnoses {run_s:.0} s ({} at a time).\n",
        diagnosis_summary_markdown(&rows),
        args.jobs
    );
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
