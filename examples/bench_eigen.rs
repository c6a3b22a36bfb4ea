//! Times `lowest_modes` on a deck and optionally exports K, M for SciPy.
//!
//! cargo run --release --example bench_eigen -- DECK [--count N] [--dense]
//!     [--export DIR] [--block B] [--basis B] [--shift S] [--tol T] [--repeat N]
//!
//! Prints one JSON line: sizes, path, seconds of the eigen solve, peak RSS
//! (VmHWM, MB) before and after it, and the frequencies. With --export, writes
//! DIR/K.mtx, DIR/M.mtx (Matrix Market, symmetric, lower triangle),
//! DIR/shift.txt (σ used), DIR/shift0.txt (the initial σ₀ = −min(1e-8·max, 1e-4·median K_ii/M_ii),
//! before the automatic move) and DIR/omega2.txt (our ω², one per line).

use std::io::Write;
use std::time::Instant;

use frfup::model::SparseMatrix;
use frfup::solvers::eigen::{lowest_modes_with, EigenOptions, EigenTuning};

fn peak_rss_mb() -> f64 {
    std::fs::read_to_string("/proc/self/status")
        .ok()
        .and_then(|s| {
            s.lines().find(|l| l.starts_with("VmHWM:")).and_then(|l| {
                l.split_whitespace()
                    .nth(1)
                    .and_then(|v| v.parse::<f64>().ok())
            })
        })
        .map(|kb| kb / 1024.0)
        .unwrap_or(f64::NAN)
}

fn write_mtx(path: &std::path::Path, a: &SparseMatrix) -> std::io::Result<()> {
    let mut lower = Vec::new();
    let sym = a.symbolic();
    for j in 0..a.ncols() {
        for (&i, &v) in sym.row_idx_of_col_raw(j).iter().zip(a.val_of_col(j)) {
            if i >= j {
                lower.push((i, j, v));
            }
        }
    }
    let mut f = std::io::BufWriter::new(std::fs::File::create(path)?);
    writeln!(f, "%%MatrixMarket matrix coordinate real symmetric")?;
    writeln!(f, "{} {} {}", a.nrows(), a.ncols(), lower.len())?;
    for (i, j, v) in lower {
        writeln!(f, "{} {} {:.17e}", i + 1, j + 1, v)?;
    }
    Ok(())
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let deck_path = args
        .first()
        .ok_or("usage: bench_eigen DECK [--count N] [--dense] [--export DIR]")?;
    let mut count = 50usize;
    let mut dense = false;
    let mut repeat = 1usize;
    let mut export: Option<std::path::PathBuf> = None;
    let mut tuning = EigenTuning::default();
    let mut i = 1;
    while i < args.len() {
        match args[i].as_str() {
            "--count" => {
                count = args.get(i + 1).ok_or("--count N")?.parse()?;
                i += 1;
            }
            "--dense" => dense = true,
            "--repeat" => {
                repeat = args.get(i + 1).ok_or("--repeat N")?.parse()?;
                i += 1;
            }
            "--shift" => {
                tuning.shift = Some(args.get(i + 1).ok_or("--shift S")?.parse()?);
                i += 1;
            }
            "--tol" => {
                tuning.tolerance = args.get(i + 1).ok_or("--tol T")?.parse()?;
                i += 1;
            }
            "--block" => {
                tuning.block_size = args.get(i + 1).ok_or("--block B")?.parse()?;
                i += 1;
            }
            "--basis" => {
                tuning.max_basis = args.get(i + 1).ok_or("--basis B")?.parse()?;
                i += 1;
            }
            "--export" => {
                export = Some(args.get(i + 1).ok_or("--export DIR")?.into());
                i += 1;
            }
            other => return Err(format!("unknown argument {other}").into()),
        }
        i += 1;
    }
    let t = Instant::now();
    let text = std::fs::read_to_string(deck_path)?;
    let deck = frfup::parsers::deck::parse(&text).map_err(|e| format!("{e:?}"))?;
    let fe = frfup::model::build(&deck, &Default::default()).map_err(|e| format!("{e:?}"))?;
    let build_s = t.elapsed().as_secs_f64();
    let n = fe.stiffness.nrows();
    let rss_before = peak_rss_mb();
    let opts = EigenOptions {
        count: if count == 0 { n } else { count },
        dense_limit: if dense { usize::MAX } else { 0 },
        krylov_dofs_per_mode: if dense { 0 } else { 1 },
        expect_no_rigid_body_modes: fe.has_fixed_dofs,
    };
    // Best of `--repeat` solves (the first pays for page faults and thread start-up).
    let mut eigen_s = f64::INFINITY;
    let mut solved = None;
    for _ in 0..repeat.max(1) {
        let t = Instant::now();
        solved = Some(lowest_modes_with(&fe.stiffness, &fe.mass, &opts, &tuning)?);
        eigen_s = eigen_s.min(t.elapsed().as_secs_f64());
    }
    let (modes, report) = solved.expect("at least one solve");
    let rss_after = peak_rss_mb();
    let f = modes.frequencies_hz();
    let show: Vec<String> = f
        .iter()
        .take(5)
        .chain(f.last())
        .map(|x| format!("{x:.6}"))
        .collect();
    println!(
        "{{\"deck\":\"{deck_path}\",\"n\":{n},\"nnz_k\":{},\"count\":{},\"path\":\"{:?}\",\"build_s\":{build_s:.3},\"eigen_s\":{eigen_s:.5},\"peak_rss_mb_before\":{rss_before:.0},\"peak_rss_mb\":{rss_after:.0},\"shift\":{:e},\"shift0\":{:e},\"factor_nnz\":{},\"applications\":{},\"restarts\":{},\"max_residual\":{:e},\"f_hz_first5_last\":[{}]}}",
        fe.stiffness.val().len(),
        modes.len(),
        report.path,
        report.shift,
        report.initial_shift,
        report.factor_nonzeros,
        report.operator_applications,
        report.restarts,
        report.max_residual,
        show.join(",")
    );
    if let Some(dir) = export {
        std::fs::create_dir_all(&dir)?;
        write_mtx(&dir.join("K.mtx"), &fe.stiffness)?;
        write_mtx(&dir.join("M.mtx"), &fe.mass)?;
        std::fs::write(dir.join("shift.txt"), format!("{:e}\n", report.shift))?;
        // The shift the sparse path starts from before it moves σ up (see
        // `EigenTuning::shift`): what a caller knows without our probe.
        let initial = report.initial_shift;
        std::fs::write(dir.join("shift0.txt"), format!("{initial:e}\n"))?;
        let w2: Vec<String> = modes.omega2.iter().map(|w| format!("{w:.17e}")).collect();
        std::fs::write(dir.join("omega2.txt"), w2.join("\n") + "\n")?;
    }
    Ok(())
}
