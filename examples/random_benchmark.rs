//! The randomised benchmark of `frfup update` (issue 16, item 5), and with
//! `--diagnose` that of `frfup diagnose` (issue 17, item 6; see
//! `random_benchmark/diagnose.rs`).
//!
//!   random_benchmark --diagnose --cases 300 --seed 1 --out DIR [--jobs 2] [--timeout 600] [--score-only]
//!
//!   cargo run --release --features bench --example random_benchmark -- --cases 200 --seed 1 \
//!       --out DIR [--jobs 2] [--frfup PATH] [--timeout 600] [--bounds] [--generate-only]
//!       [--update-arg ARG]...
//!   random_benchmark --seed 1 --scatter 1 [--scatter 5]... --noise-seeds 20 [--noise F] --out DIR
//!
//! Generates the cases (frfup::benchmark) into DIR/case-NNN/ (model.deck,
//! truth.deck, test.uff, truth.json), runs the release `frfup` binary as a
//! user would — `frfup update model.deck test.uff --out CASE/out`, no other
//! flag (unless `--update-arg` adds some, for comparisons) — `--jobs` at a time, scores each CASE/out/report.json against
//! truth.json, writes DIR/cases.csv and DIR/summary.md and prints the summary.

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;
use std::time::{Duration, Instant};

#[path = "random_benchmark/diagnose.rs"]
mod diagnose;

use frfup::benchmark::{
    case_seed, generate, score_report, summary_markdown, GenOptions, RunRecord,
};

struct Args {
    cases: usize,
    seed: u64,
    out: PathBuf,
    jobs: usize,
    frfup: Option<PathBuf>,
    timeout: f64,
    bounds: bool,
    generate_only: bool,
    /// The diagnosis benchmark instead of the update benchmark.
    diagnose: bool,
    /// With `diagnose`: score the cases already in `out` again, run nothing.
    score_only: bool,
    /// Extra arguments of `frfup update` (none for the benchmark proper).
    update_args: Vec<String>,
    /// Scatter mode: these cases, each run on `noise_seeds` noise draws.
    scatter: Vec<usize>,
    noise_seeds: usize,
    /// Scatter mode: this noise fraction instead of the case's.
    noise: Option<f64>,
}

fn parse_args() -> Result<Args, String> {
    let mut a = Args {
        cases: 200,
        seed: 1,
        out: PathBuf::from("random-benchmark"),
        jobs: 2,
        frfup: None,
        timeout: 600.0,
        bounds: false,
        generate_only: false,
        diagnose: false,
        score_only: false,
        update_args: Vec::new(),
        scatter: Vec::new(),
        noise_seeds: 20,
        noise: None,
    };
    let mut it = std::env::args().skip(1);
    while let Some(flag) = it.next() {
        let mut value = || it.next().ok_or(format!("{flag} needs a value"));
        match flag.as_str() {
            "--cases" => a.cases = value()?.parse().map_err(|_| "--cases: a count")?,
            "--seed" => a.seed = value()?.parse().map_err(|_| "--seed: an integer")?,
            "--out" => a.out = PathBuf::from(value()?),
            "--jobs" => a.jobs = value()?.parse().map_err(|_| "--jobs: a count")?,
            "--frfup" => a.frfup = Some(PathBuf::from(value()?)),
            "--timeout" => a.timeout = value()?.parse().map_err(|_| "--timeout: seconds")?,
            "--bounds" => a.bounds = true,
            "--generate-only" => a.generate_only = true,
            "--diagnose" => a.diagnose = true,
            "--score-only" => a.score_only = true,
            "--update-arg" => a.update_args.push(value()?),
            "--scatter" => a
                .scatter
                .push(value()?.parse().map_err(|_| "--scatter: a case index")?),
            "--noise" => a.noise = Some(value()?.parse().map_err(|_| "--noise: a fraction")?),
            "--noise-seeds" => {
                a.noise_seeds = value()?.parse().map_err(|_| "--noise-seeds: a count")?
            }
            other => return Err(format!("unknown argument {other:?}")),
        }
    }
    a.jobs = a.jobs.max(1);
    Ok(a)
}

/// With several cases at a time, each `frfup` gets one thread (unless
/// RAYON_NUM_THREADS says otherwise): the cases already share the cores,
/// and a diagnosis's second start, run beside its first on a second
/// thread, would spend work that is thrown away when the first explains
/// the test.
fn one_thread_per_case(jobs: usize) {
    if jobs > 1 && std::env::var_os("RAYON_NUM_THREADS").is_none() {
        std::env::set_var("RAYON_NUM_THREADS", "1");
    }
}

fn main() {
    let args = match parse_args() {
        Ok(a) => a,
        Err(e) => {
            eprintln!("random_benchmark: {e}\nusage: random_benchmark [--cases N] [--seed S] [--out DIR] [--jobs J] [--frfup PATH] [--timeout SECS] [--bounds] [--generate-only] [--diagnose [--score-only]] [--update-arg ARG]... [--scatter CASE]... [--noise-seeds N] [--noise F]");
            std::process::exit(2);
        }
    };
    one_thread_per_case(args.jobs);
    if let Err(e) = run(&args) {
        eprintln!("random_benchmark: {e}");
        std::process::exit(2);
    }
}

/// The `frfup` binary beside this example's folder (target/release/frfup).
fn frfup_binary(args: &Args) -> Result<PathBuf, String> {
    if let Some(p) = &args.frfup {
        return Ok(p.clone());
    }
    let exe = std::env::current_exe().map_err(|e| e.to_string())?;
    let bin = exe
        .parent()
        .and_then(Path::parent)
        .map(|d| d.join("frfup"))
        .ok_or("cannot locate the frfup binary")?;
    if !bin.exists() {
        return Err(format!(
            "{} not found: build it first (cargo build --release) or pass --frfup PATH",
            bin.display()
        ));
    }
    Ok(bin)
}

/// Run `work(i)` for i in 0..n on `jobs` threads; results in index order.
fn parallel<T: Send>(n: usize, jobs: usize, work: impl Fn(usize) -> T + Sync) -> Vec<T> {
    let next = AtomicUsize::new(0);
    let out: Mutex<Vec<Option<T>>> = Mutex::new((0..n).map(|_| None).collect());
    std::thread::scope(|s| {
        for _ in 0..jobs.min(n.max(1)) {
            s.spawn(|| loop {
                let i = next.fetch_add(1, Ordering::SeqCst);
                if i >= n {
                    break;
                }
                let r = work(i);
                if let Ok(mut o) = out.lock() {
                    o[i] = Some(r);
                }
            });
        }
    });
    out.into_inner()
        .unwrap_or_default()
        .into_iter()
        .flatten()
        .collect()
}

/// What the runner keeps of a generated case.
struct Generated {
    record: RunRecord,
    truth: Vec<(String, f64)>,
    dir: PathBuf,
}

fn generate_case(args: &Args, i: usize) -> Result<Generated, String> {
    let case = draw_case(args, i)?;
    write_case(&case, &args.out.join(format!("case-{i:03}")), i)
}

/// Case `i` of the run.
fn draw_case(args: &Args, i: usize) -> Result<frfup::benchmark::Case, String> {
    let opts = GenOptions {
        bounds: args.bounds,
        ..GenOptions::default()
    };
    generate(case_seed(args.seed, i as u64), &opts).map_err(|e| e.to_string())
}

/// Write `case` (number `i`) into `dir`.
fn write_case(case: &frfup::benchmark::Case, dir: &Path, i: usize) -> Result<Generated, String> {
    let dir = dir.to_path_buf();
    case.write(&dir).map_err(|e| e.to_string())?;
    let record = RunRecord {
        case: format!("case-{i:03}"),
        structure: format!(
            "{} ({})",
            case.structure.name(),
            if case.plane { "plane" } else { "space" }
        ),
        layout: case.layout_label(),
        support: case.support.name().to_string(),
        damping: case.damping.name().to_string(),
        format: if case.binary { "58b" } else { "ascii" }.to_string(),
        axis: case.axis.name().to_string(),
        dofs: case.dofs,
        channels: case.points.len(),
        noise: case.noise,
        ..RunRecord::default()
    };
    let truth = case
        .params
        .iter()
        .map(|p| (p.name.clone(), p.value))
        .collect();
    Ok(Generated { record, truth, dir })
}

/// How a run of `frfup` went.
struct Outcome {
    exit_code: Option<i32>,
    seconds: f64,
    /// Why it failed: the last stderr line, or the runner's reason.
    message: String,
}

/// `frfup COMMAND model.deck test.uff --out DIR/out EXTRA...`, killed after
/// `timeout` s; stdout and stderr in DIR/COMMAND.stdout, DIR/COMMAND.stderr.
fn run_frfup(bin: &Path, dir: &Path, command: &str, timeout: f64, extra: &[String]) -> Outcome {
    let mut o = Outcome {
        exit_code: None,
        seconds: 0.0,
        message: String::new(),
    };
    let files = (
        std::fs::File::create(dir.join(format!("{command}.stdout"))),
        std::fs::File::create(dir.join(format!("{command}.stderr"))),
    );
    let (Ok(so), Ok(se)) = files else {
        o.message = "cannot create the log files".into();
        return o;
    };
    let start = Instant::now();
    let child = Command::new(bin)
        .arg(command)
        .arg(dir.join("model.deck"))
        .arg(dir.join("test.uff"))
        .arg("--out")
        .arg(dir.join("out"))
        .args(extra)
        .stdin(Stdio::null())
        .stdout(so)
        .stderr(se)
        .spawn();
    let mut child = match child {
        Ok(c) => c,
        Err(e) => {
            o.message = format!("cannot start {}: {e}", bin.display());
            return o;
        }
    };
    let status = loop {
        match child.try_wait() {
            Ok(Some(s)) => break Some(s),
            Ok(None) if start.elapsed().as_secs_f64() > timeout => {
                let _ = child.kill();
                let _ = child.wait();
                o.message = format!("timed out after {timeout} s");
                break None;
            }
            Ok(None) => std::thread::sleep(Duration::from_millis(20)),
            Err(e) => {
                o.message = e.to_string();
                break None;
            }
        }
    };
    o.seconds = start.elapsed().as_secs_f64();
    o.exit_code = status.and_then(|s| s.code());
    if o.exit_code != Some(0) && o.message.is_empty() {
        let err =
            std::fs::read_to_string(dir.join(format!("{command}.stderr"))).unwrap_or_default();
        o.message = err
            .lines()
            .rev()
            .find(|l| !l.trim().is_empty())
            .unwrap_or("")
            .trim()
            .to_string();
    }
    o
}

/// `frfup update model.deck test.uff --out DIR/out`, scored.
fn run_case(bin: &Path, g: &Generated, timeout: f64, extra: &[String]) -> RunRecord {
    let mut r = g.record.clone();
    let o = run_frfup(bin, &g.dir, "update", timeout, extra);
    (r.exit_code, r.seconds, r.message) = (o.exit_code, o.seconds, o.message);
    let report = std::fs::read_to_string(g.dir.join("out/report.json"))
        .ok()
        .and_then(|t| serde_json::from_str::<serde_json::Value>(&t).ok());
    if let Some(report) = report {
        r.score = score_report(&g.truth, &report);
    } else {
        r.score.parameters = g.truth.len();
    }
    r
}

/// The scatter diagnostic: each case of `args.scatter` simulated again with
/// `args.noise_seeds` noise draws (same structure, truth and layout), each
/// updated with the defaults; per parameter, the empirical standard
/// deviation of the estimates against the mean reported one, and the RMS
/// of the z-scores (estimate − truth)/sd (1 when the reported sd is right).
fn scatter(args: &Args, bin: &Path) -> Result<(), String> {
    println!("| case | parameter | truth | mean estimate | empirical sd | mean reported sd | ratio | RMS z | inside ±2 sd |");
    println!("|---|---|---|---|---|---|---|---|---|");
    for &i in &args.scatter {
        let base = draw_case(args, i)?;
        let runs = parallel(args.noise_seeds, args.jobs, |k| {
            let mut case = base.clone();
            case.seed = case_seed(base.seed, 1000 + k as u64);
            case.noise = args.noise.unwrap_or(case.noise);
            let dir = args.out.join(format!("case-{i:03}/noise-{k:02}"));
            let g = write_case(&case, &dir, i)?;
            run_case(bin, &g, args.timeout, &args.update_args);
            let text =
                std::fs::read_to_string(dir.join("out/report.json")).map_err(|e| e.to_string())?;
            let report: serde_json::Value =
                serde_json::from_str(&text).map_err(|e| e.to_string())?;
            frfup::benchmark::score::report_estimates(&report).ok_or("no estimates".to_string())
        });
        let runs: Vec<_> = runs.into_iter().filter_map(Result::ok).collect();
        for p in &base.params {
            let est: Vec<(f64, f64)> = runs
                .iter()
                .filter_map(|r| r.iter().find(|e| e.name == p.name && e.identified))
                .filter_map(|e| Some((e.value, e.sd?)))
                .collect();
            let n = est.len() as f64;
            if est.len() < 2 {
                continue;
            }
            let mean = est.iter().map(|e| e.0).sum::<f64>() / n;
            let emp = (est.iter().map(|e| (e.0 - mean).powi(2)).sum::<f64>() / (n - 1.0)).sqrt();
            let rep = est.iter().map(|e| e.1).sum::<f64>() / n;
            let z2 = est
                .iter()
                .map(|e| ((e.0 - p.value) / e.1).powi(2))
                .sum::<f64>()
                / n;
            let inside = est
                .iter()
                .filter(|e| (e.0 - p.value).abs() <= 2.0 * e.1)
                .count();
            println!(
                "| case-{i:03} | {} | {:.5} | {mean:.5} | {emp:.2e} | {rep:.2e} | {:.2} | {:.2} | {inside}/{} |",
                p.name, p.value, emp / rep, z2.sqrt(), est.len()
            );
        }
    }
    Ok(())
}

fn run(args: &Args) -> Result<(), String> {
    if !args.scatter.is_empty() {
        return scatter(args, &frfup_binary(args)?);
    }
    let bin = if args.generate_only || args.score_only {
        PathBuf::new()
    } else {
        frfup_binary(args)?
    };
    if args.diagnose {
        return diagnose::run(args, &bin);
    }
    std::fs::create_dir_all(&args.out).map_err(|e| format!("{}: {e}", args.out.display()))?;
    let t = Instant::now();
    let generated = parallel(args.cases, args.jobs, |i| generate_case(args, i));
    let mut cases = Vec::new();
    for (i, g) in generated.into_iter().enumerate() {
        match g {
            Ok(g) => cases.push(g),
            Err(e) => eprintln!("case {i}: {e}"),
        }
    }
    eprintln!(
        "generated {} case(s) in {:.1} s into {}",
        cases.len(),
        t.elapsed().as_secs_f64(),
        args.out.display()
    );
    if args.generate_only {
        return Ok(());
    }
    let done = AtomicUsize::new(0);
    let rows = parallel(cases.len(), args.jobs, |i| {
        let r = run_case(&bin, &cases[i], args.timeout, &args.update_args);
        let k = done.fetch_add(1, Ordering::SeqCst) + 1;
        eprintln!(
            "[{k}/{}] {} {} {} exit {:?} {:.2} s max error {}",
            cases.len(),
            r.case,
            r.structure,
            r.layout,
            r.exit_code,
            r.seconds,
            r.score
                .max_error
                .map(|e| format!("{e:.4}"))
                .unwrap_or_else(|| "-".into())
        );
        r
    });
    write_csv(&args.out.join("cases.csv"), &rows)?;
    let summary = summary_markdown(&rows);
    std::fs::write(args.out.join("summary.md"), &summary)
        .map_err(|e| format!("{}: {e}", args.out.display()))?;
    println!("{summary}");
    Ok(())
}

fn write_csv(path: &Path, rows: &[RunRecord]) -> Result<(), String> {
    let err = |e: csv::Error| format!("{}: {e}", path.display());
    let mut w = csv::Writer::from_path(path).map_err(err)?;
    w.write_record(RunRecord::CSV_HEADER).map_err(err)?;
    for r in rows {
        w.write_record(r.csv_fields()).map_err(err)?;
    }
    w.flush().map_err(|e| format!("{}: {e}", path.display()))
}
