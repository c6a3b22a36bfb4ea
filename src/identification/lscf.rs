//! Poles by the poly-reference least-squares complex-frequency method
//! (PolyMAX; Peeters, Van der Auweraer, Guillaume & Leuridan, Shock and
//! Vibration 11 (2004) 395–409, eqs. 1–13).
//!
//! Right matrix-fraction model of output o's row of FRFs (1 × m), with
//! z_k = e^{iω_kΔt}, Δt = π/ω_max, real coefficients:
//!
//!   H_o(ω_k) ≈ N_o(z_k) D(z_k)⁻¹,  N_o(z) = Σ_{r=0}^{p} z^r β_{o,r} (1 × m),
//!   D(z) = Σ_{r=0}^{p} z^r α_r (m × m), α_p = I.
//!
//! The linearised error w_o [N_o(z_k) − H_o(ω_k) D(z_k)] summed in squares
//! over lines and outputs is a quadratic form in (β_o, α) with blocks
//! R_o = w_o² Re Σ_k X_kᴴX_k, S_o = −w_o² Re Σ_k X_kᴴ(X_k ⊗ H_o),
//! T_o = w_o² Re Σ_k (X_k ⊗ H_o)ᴴ(X_k ⊗ H_o), X_k = [z_k⁰ … z_kᵖ]. Eliminating
//! β_o = −R_o⁻¹S_o α leaves the reduced normal equations
//! M = Σ_o (T_o − S_oᵀR_o⁻¹S_o), M α = 0; with α_p = I the first p blocks
//! solve M_aa α_a = −M_ab. Every entry depends on s − r only (Toeplitz), so
//! one set of sums Σ_k z_k^d (·), |d| ≤ p_max, serves every order.
//!
//! One Cholesky factor R0 = LLᵀ at the highest order serves every order:
//! the factor of a leading block of R0 is the leading block of L, and the
//! first p+1 rows of Y_o = L⁻¹S0_o depend only on the first p+1 rows of
//! S0_o, so S_oᵀR_o⁻¹S_o of order p is Y_oᵀY_o over Y_o's leading
//! (p+1) × (p+1)m block, and β_o = −L_p⁻ᵀ Y_o α. The whole diagram costs one
//! triangular solve per output instead of one per output and order.
//!
//! Poles: eigenvalues z of the block companion matrix of D, λ = ln z / Δt
//! (rad/s); its eigenvector's first block is the participation vector L
//! (D(z)L = 0), and N_o(z)L is output o's shape up to a common factor.

use faer::linalg::matmul::matmul;
use faer::linalg::triangular_solve::{
    solve_lower_triangular_in_place, solve_upper_triangular_in_place,
};
use faer::{c64, Accum, Mat, Par};
use rayon::prelude::*;

use super::prepare::Prepared;
use super::IdentifyError;
use crate::solvers::dense::{cholesky_lower, general_eigen, lu_solve, product};

/// The Toeplitz sums of every order up to `max_order`.
#[derive(Clone, Debug)]
pub struct Sums {
    /// Sampling period of the z-domain model (s).
    pub dt: f64,
    pub max_order: usize,
    m: usize,
    /// Σ_o w_o² Re Σ_k z_k^d conj(H_oi) H_oj, d = −P..=P, per (i, j).
    t: Vec<Vec<f64>>,
    factored: Factored,
}

/// The numerator blocks at order P, factored once for every order.
#[derive(Clone, Debug)]
struct Factored {
    /// L of R0 = LLᵀ at order P ((P+1) × (P+1)).
    chol: Mat<f64>,
    /// Y_o = L⁻¹S0_o per output ((P+1) × (P+1)m).
    y: Vec<Mat<f64>>,
    /// w_o·Y_o stacked row by row: row r·outputs + o is w_o times Y_o's row
    /// r, so that order p's rows are the leading (p+1)·outputs.
    stack: Mat<f64>,
    /// Σ_o w_o² S_oᵀR⁻¹S_o of every order p ≥ 1 (index p − 1), the stack's
    /// leading (p+1)·outputs rows' Gram matrix: one running sum over the
    /// rows instead of a product per order (Σ_p p³ → P³); empty when they
    /// would take more than [`GRAM_MEMORY`] numbers.
    gram: Vec<Mat<f64>>,
}

/// Numbers kept for the per-order Gram matrices at most (128 MB).
const GRAM_MEMORY: usize = 16 << 20;

impl Sums {
    /// The sums for orders up to `max_order` (O(FRFs × lines × order)).
    pub fn new(data: &Prepared, max_order: usize) -> Result<Sums, IdentifyError> {
        let n = data.n_lines();
        let m = data.n_inputs();
        if 2 * n < (max_order + 1) * 2 {
            return Err(IdentifyError::NotEnoughData(format!(
                "{n} lines in the band cannot fit model order {max_order}"
            )));
        }
        let w_max = data.omega[n - 1];
        let dt = std::f64::consts::PI / w_max;
        let p = max_order;
        // Lines in fixed chunks, summed on all cores and added in chunk
        // order: the same sums whatever the number of threads.
        let parts: Vec<Partial> = (0..n.div_ceil(CHUNK))
            .into_par_iter()
            .map(|c| Partial::over(data, dt, p, c * CHUNK..((c + 1) * CHUNK).min(n)))
            .collect();
        let mut total = Partial::zeros(data.h.len(), m, p);
        for part in &parts {
            total.add(part);
        }
        let Partial { r, g, t } = total;
        let factored = factor(data, &r, &g, m, p)?;
        Ok(Sums {
            dt,
            max_order,
            m,
            t,
            factored,
        })
    }
}

/// Lines per chunk of the sums.
const CHUNK: usize = 4096;

/// The sums of [`Sums::new`] over some of the lines: Σ Re z^d per d,
/// and per FRF and per input pair Re Σ z^{±d}(·) at index P ± d.
struct Partial {
    r: Vec<f64>,
    g: Vec<Vec<f64>>,
    t: Vec<Vec<f64>>,
}

impl Partial {
    fn zeros(frfs: usize, m: usize, p: usize) -> Partial {
        Partial {
            r: vec![0.0; p + 1],
            g: vec![vec![0.0; 2 * p + 1]; frfs],
            t: vec![vec![0.0; 2 * p + 1]; m * m],
        }
    }

    fn add(&mut self, other: &Partial) {
        let pairs = [(&mut self.g, &other.g), (&mut self.t, &other.t)];
        for (mine, theirs) in pairs {
            for (a, b) in mine.iter_mut().zip(theirs) {
                a.iter_mut().zip(b).for_each(|(x, y)| *x += y);
            }
        }
        self.r.iter_mut().zip(&other.r).for_each(|(x, y)| *x += y);
    }

    fn over(data: &Prepared, dt: f64, p: usize, lines: std::ops::Range<usize>) -> Partial {
        let m = data.n_inputs();
        let mut out = Partial::zeros(data.h.len(), m, p);
        let h: Vec<&[c64]> = data.h.iter().map(|h| &h[lines.clone()]).collect();
        // Products conj(H_oi) H_oj summed over outputs with weights w_o².
        let mut q = vec![vec![c64::new(0.0, 0.0); lines.len()]; m * m];
        for (o, w) in data.weights.iter().enumerate() {
            let w2 = w * w;
            for i in 0..m {
                for j in 0..m {
                    let (hi, hj) = (h[o * m + i], h[o * m + j]);
                    for (qk, (a, b)) in q[i * m + j].iter_mut().zip(hi.iter().zip(hj)) {
                        *qk += a.conj() * b * w2;
                    }
                }
            }
        }
        crate::solvers::vector_state::clear(); // sin, cos per line
        let z1: Vec<c64> = data.omega[lines].iter().map(|w| c64::cis(w * dt)).collect();
        // z_k^d by repeated products (rounding grows as d·ε, 1e-14 at order
        // 100): a sine and cosine per line and order cost more than the sums.
        let mut zd = vec![c64::new(1.0, 0.0); z1.len()];
        for d in 0..=p {
            if d > 0 {
                for (z, step) in zd.iter_mut().zip(&z1) {
                    *z *= step;
                }
            }
            out.r[d] = zd.iter().map(|z| z.re).sum();
            // Re Σ z^{±d} x = Σ (Re z Re x ∓ Im z Im x).
            let sums = |x: &[c64]| -> (f64, f64) {
                let (mut a, mut b) = (0.0, 0.0);
                for (z, v) in zd.iter().zip(x) {
                    a += z.re * v.re;
                    b += z.im * v.im;
                }
                (a - b, a + b)
            };
            for (gj, hj) in out.g.iter_mut().zip(&h) {
                let (plus, minus) = sums(hj);
                gj[p + d] = plus;
                gj[p - d] = minus;
            }
            for (tj, qj) in out.t.iter_mut().zip(&q) {
                let (plus, minus) = sums(qj);
                tj[p + d] = plus;
                tj[p - d] = minus;
            }
        }
        out
    }
}

/// L of R0 at order `p`, Y_o = L⁻¹S0_o per output and their weighted stack
/// (see [`Sums`]).
fn factor(
    data: &Prepared,
    r: &[f64],
    g: &[Vec<f64>],
    m: usize,
    p: usize,
) -> Result<Factored, IdentifyError> {
    let (n1, nc, outputs) = (p + 1, (p + 1) * m, data.n_outputs());
    let r0 = Mat::<f64>::from_fn(n1, n1, |a, b| r[a.abs_diff(b)]);
    let chol = cholesky_lower(r0.as_ref()).ok_or(IdentifyError::Singular("LSCF R"))?;
    let mut stack = Mat::<f64>::zeros(n1 * outputs, nc);
    let mut y = Vec::with_capacity(outputs);
    for (o, w) in data.weights.iter().enumerate() {
        let mut yo = Mat::<f64>::from_fn(n1, nc, |row, b| {
            let (s, i) = (b / m, b % m);
            -g[o * m + i][p + s - row]
        });
        solve_lower_triangular_in_place(chol.as_ref(), yo.as_mut(), Par::Seq);
        for row in 0..n1 {
            for b in 0..nc {
                stack[(row * outputs + o, b)] = w * yo[(row, b)];
            }
        }
        y.push(yo);
    }
    let gram = running_gram(&stack, outputs, m, p);
    Ok(Factored {
        chol,
        y,
        stack,
        gram,
    })
}

/// The leading ((q+1)m)² block of the Gram matrix of `stack`'s first
/// (q+1)·`outputs` rows, for q = 1..=p (see [`Factored::gram`]).
fn running_gram(stack: &Mat<f64>, outputs: usize, m: usize, p: usize) -> Vec<Mat<f64>> {
    let size: usize = (1..=p).map(|q| ((q + 1) * m).pow(2)).sum();
    if size > GRAM_MEMORY {
        return Vec::new();
    }
    let nc = stack.ncols();
    let mut acc = Mat::<f64>::zeros(nc, nc);
    let mut out = Vec::with_capacity(p);
    for row in 0..=p {
        let rows = stack.submatrix(row * outputs, 0, outputs, nc);
        matmul(
            acc.as_mut(),
            Accum::Add,
            rows.transpose(),
            rows,
            1.0,
            Par::Seq,
        );
        if row >= 1 {
            let k = (row + 1) * m;
            out.push(acc.submatrix(0, 0, k, k).to_owned());
        }
    }
    out
}

/// A pole of one model order.
#[derive(Clone, Debug, PartialEq)]
pub struct OrderPole {
    /// λ (rad/s), Im λ > 0.
    pub pole: c64,
    /// N_o(z)L per output (shape up to a factor).
    pub vector: Vec<c64>,
    /// L, the participation of each input.
    pub participation: Vec<c64>,
}

/// The poles of model order `p` (1 ≤ p ≤ max order) with Im λ > 0.
pub fn poles(data: &Prepared, sums: &Sums, p: usize) -> Result<Vec<OrderPole>, IdentifyError> {
    assert!(p >= 1 && p <= sums.max_order);
    let m = sums.m;
    let big = sums.max_order;
    let n1 = p + 1;
    let nc = n1 * m;
    let mut mm = Mat::<f64>::from_fn(nc, nc, |a, b| {
        let (r, i) = (a / m, a % m);
        let (s, j) = (b / m, b % m);
        sums.t[i * m + j][big + s - r]
    });
    // Σ_o w_o² S_oᵀR⁻¹S_o = WᵀW over the stack's leading rows and columns.
    match sums.factored.gram.get(p - 1) {
        Some(g) => mm -= g,
        None => {
            let w = sums
                .factored
                .stack
                .submatrix(0, 0, n1 * data.n_outputs(), nc);
            matmul(mm.as_mut(), Accum::Add, w.transpose(), w, -1.0, Par::Seq);
        }
    }
    let pm = p * m;
    let maa = mm.submatrix(0, 0, pm, pm).to_owned();
    let mab = mm.submatrix(0, pm, pm, m).to_owned();
    let alpha_a = lu_solve(maa.as_ref(), (-&mab).as_ref());
    if !alpha_a.col_iter().all(|c| c.iter().all(|x| x.is_finite())) {
        return Err(IdentifyError::Singular("LSCF reduced normal equations"));
    }
    let mut alpha = Mat::<f64>::zeros(nc, m);
    alpha.submatrix_mut(0, 0, pm, m).copy_from(&alpha_a);
    for i in 0..m {
        alpha[(pm + i, i)] = 1.0;
    }
    let companion = Mat::<f64>::from_fn(pm, pm, |a, b| {
        if a < pm - m {
            if b == a + m {
                1.0
            } else {
                0.0
            }
        } else {
            -alpha[(b / m * m + a % m, b % m)]
        }
    });
    let singular = |_| IdentifyError::Singular("LSCF companion eigenvalues");
    // One input: L is a scalar, 1 (shapes are compared up to a factor), and
    // the eigenvalues alone cost a fraction of the full decomposition.
    let (zs, vecs) = general_eigen(companion.as_ref(), m > 1).map_err(singular)?;
    // β_o = −R⁻¹S_o α = −L_p⁻ᵀ (Y_o α) over the leading blocks.
    let lt = sums.factored.chol.submatrix(0, 0, n1, n1).transpose();
    let betas: Vec<Mat<f64>> = sums
        .factored
        .y
        .iter()
        .map(|yo| {
            let mut beta = -product(yo.submatrix(0, 0, n1, nc), alpha.as_ref());
            solve_upper_triangular_in_place(lt, beta.as_mut(), Par::Seq);
            beta
        })
        .collect();
    let mut out = Vec::new();
    for (e, &z) in zs.iter().enumerate() {
        if !(z.im > 0.0) || !(z.norm() > 0.0) || !z.re.is_finite() {
            continue;
        }
        let pole = c64::new(z.norm().ln(), z.arg()) / sums.dt;
        let participation: Vec<c64> = match &vecs {
            Some(u) => (0..m).map(|i| u[(i, e)]).collect(),
            None => vec![c64::new(1.0, 0.0)],
        };
        let vector = betas
            .iter()
            .map(|beta| numerator(beta, &participation, z))
            .collect();
        out.push(OrderPole {
            pole,
            vector,
            participation,
        });
    }
    Ok(out)
}

/// N(z)L = Σ_s z^s (β_s · L) for one output's β ((p+1) × m).
fn numerator(beta: &Mat<f64>, l: &[c64], z: c64) -> c64 {
    let mut acc = c64::new(0.0, 0.0);
    for s in (0..beta.nrows()).rev() {
        let mut bl = c64::new(0.0, 0.0);
        for (i, li) in l.iter().enumerate() {
            bl += li * beta[(s, i)];
        }
        acc = acc * z + bl;
    }
    acc
}
