//! Times `lowest_modes` on a deck and optionally exports K, M for SciPy.
//!
//! cargo run --release --features bench --example bench_eigen -- DECK [--count N] [--dense]
//!     [--export DIR] [--block B] [--basis B] [--shift S] [--tol T] [--repeat N]
//!     [--faer]
//!
//! Prints one JSON line: sizes, path, seconds of the eigen solve, peak RSS
//! (VmHWM, MB) before and after it, and the frequencies. With --export, writes
//! DIR/K.mtx, DIR/M.mtx (Matrix Market, symmetric, lower triangle),
//! DIR/shift.txt (σ used), DIR/shift0.txt (the initial σ₀ = −min(1e-8·max, 1e-4·median K_ii/M_ii),
//! before the automatic move) and DIR/omega2.txt (our ω², one per line).
//!
//! With --faer, a second JSON line compares the two Krylov drivers on the
//! same shift-invert operator C = L⁻¹ P M Pᵀ L⁻ᵀ at the σ our solve ended at
//! (factorisation shared, not timed): our block Lanczos
//! (`lanczos::block_lanczos`) against faer's restarted Lanczos
//! (`faer::matrix_free::eigen::partial_self_adjoint_eigen`). Ours converges
//! a pair at ‖C y − μ y‖ ≤ tol·μ, faer's at ‖C y − μ y‖ ≤ tol_abs; tol_abs is
//! set to tol·μ_count (the smallest wanted μ), so faer is held to at least
//! our accuracy on every pair.

use std::io::Write;
use std::time::Instant;

use std::sync::atomic::{AtomicUsize, Ordering};

use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::matrix_free::eigen::{partial_self_adjoint_eigen, partial_self_adjoint_eigen_scratch};
use faer::matrix_free::LinOp;
use faer::{Col, Mat, MatMut, MatRef, Par};
use frfup::model::SparseMatrix;
use frfup::solvers::eigen::lanczos::{block_lanczos, ShiftedCholesky};
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
    let mut compare_faer = false;
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
            "--faer" => compare_faer = true,
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
        cover_omega2: None,
        grow_to_cover: false,
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
    if compare_faer {
        compare_krylov_drivers(&fe.stiffness, &fe.mass, count, report.shift, &tuning)?;
    }
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

/// C = L⁻¹ P M Pᵀ L⁻ᵀ as faer's matrix-free operator, counting applications
/// (one per column).
struct ShiftInvert<'a> {
    chol: &'a ShiftedCholesky,
    mass: &'a SparseMatrix,
    columns: AtomicUsize,
}

impl std::fmt::Debug for ShiftInvert<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "ShiftInvert(n = {})", self.mass.nrows())
    }
}

impl LinOp<f64> for ShiftInvert<'_> {
    fn apply_scratch(&self, _rhs_ncols: usize, _par: Par) -> StackReq {
        StackReq::EMPTY
    }
    fn nrows(&self) -> usize {
        self.mass.nrows()
    }
    fn ncols(&self) -> usize {
        self.mass.nrows()
    }
    fn apply(&self, out: MatMut<'_, f64>, rhs: MatRef<'_, f64>, _par: Par, _stack: &mut MemStack) {
        self.columns.fetch_add(rhs.ncols(), Ordering::Relaxed);
        let mut out = out;
        out.copy_from(self.chol.apply(self.mass, rhs));
    }
    fn conj_apply(
        &self,
        out: MatMut<'_, f64>,
        rhs: MatRef<'_, f64>,
        par: Par,
        stack: &mut MemStack,
    ) {
        // Real symmetric: C̄ = C.
        self.apply(out, rhs, par, stack)
    }
}

/// Our block Lanczos and faer's partial self-adjoint eigensolver on the same
/// operator; prints one JSON line with both times and the largest relative
/// difference in ω² = σ + 1/μ.
fn compare_krylov_drivers(
    k: &SparseMatrix,
    m: &SparseMatrix,
    count: usize,
    shift: f64,
    tuning: &EigenTuning,
) -> Result<(), Box<dyn std::error::Error>> {
    let n = k.nrows();
    let count = count.min(n);
    let chol = ShiftedCholesky::new(k, m, shift)?;
    let op = ShiftInvert {
        chol: &chol,
        mass: m,
        columns: AtomicUsize::new(0),
    };
    let t = Instant::now();
    let ours = block_lanczos(&|y| chol.apply(m, y), n, count, tuning)?;
    let ours_s = t.elapsed().as_secs_f64();
    let mu_min = ours.values[count - 1];
    let tol_abs = tuning.tolerance * mu_min;
    // A deterministic start vector with every component nonzero.
    let v0 = Col::<f64>::from_fn(n, |i| 1.0 + ((i * 7919) % 104729) as f64 / 104729.0);
    let mut vectors = Mat::<f64>::zeros(n, count);
    let mut values = vec![0.0; count];
    let params = Default::default();
    let mut mem = MemBuffer::new(partial_self_adjoint_eigen_scratch(
        &op,
        count,
        Par::Seq,
        params,
    ));
    let t = Instant::now();
    let info = partial_self_adjoint_eigen(
        vectors.as_mut(),
        &mut values,
        &op,
        v0.as_ref(),
        tol_abs,
        Par::Seq,
        MemStack::new(&mut mem),
        params,
    );
    let faer_s = t.elapsed().as_secs_f64();
    let omega2 = |mu: &[f64]| {
        let mut w: Vec<f64> = mu.iter().map(|m| shift + 1.0 / m).collect();
        w.sort_by(f64::total_cmp);
        w
    };
    let (a, b) = (
        omega2(&ours.values[..count]),
        omega2(&values[..info.n_converged_eigen]),
    );
    let max_rel = a
        .iter()
        .zip(&b)
        .map(|(x, y)| ((x - y) / x.abs().max(1e-300)).abs())
        .fold(0.0, f64::max);
    println!(
        "{{\"compare\":\"krylov drivers\",\"n\":{n},\"count\":{count},\"shift\":{shift:e},\"ours_s\":{ours_s:.5},\"ours_applications\":{},\"ours_restarts\":{},\"faer_s\":{faer_s:.5},\"faer_applications\":{},\"faer_converged\":{},\"tol_abs\":{tol_abs:e},\"max_rel_diff_omega2\":{max_rel:e}}}",
        ours.applications,
        ours.restarts,
        op.columns.load(Ordering::Relaxed),
        info.n_converged_eigen,
    );
    Ok(())
}
