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
//! Poles: eigenvalues z of the block companion matrix of D, λ = ln z / Δt
//! (rad/s); its eigenvector's first block is the participation vector L
//! (D(z)L = 0), and N_o(z)L is output o's shape up to a common factor.

use faer::linalg::solvers::Solve;
use faer::{c64, Mat, Side};

use super::prepare::Prepared;
use super::IdentifyError;
use crate::solvers::dense::product;

/// The Toeplitz sums of every order up to `max_order`.
#[derive(Clone, Debug)]
pub struct Sums {
    /// Sampling period of the z-domain model (s).
    pub dt: f64,
    pub max_order: usize,
    m: usize,
    /// Re Σ_k z_k^d, d = 0..=P.
    r: Vec<f64>,
    /// Re Σ_k z_k^d H_oi(k), d = −P..=P, per FRF (o, i).
    g: Vec<Vec<f64>>,
    /// Σ_o w_o² Re Σ_k z_k^d conj(H_oi) H_oj, d = −P..=P, per (i, j).
    t: Vec<Vec<f64>>,
}

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
        let width = 2 * p + 1;
        let mut r = vec![0.0; p + 1];
        let mut g = vec![vec![0.0; width]; data.h.len()];
        let mut t = vec![vec![0.0; width]; m * m];
        // Products conj(H_oi) H_oj summed over outputs with weights w_o².
        let mut q = vec![vec![c64::new(0.0, 0.0); n]; m * m];
        for (o, w) in data.weights.iter().enumerate() {
            let w2 = w * w;
            for i in 0..m {
                for j in 0..m {
                    let (hi, hj) = (&data.h[o * m + i], &data.h[o * m + j]);
                    for k in 0..n {
                        q[i * m + j][k] += hi[k].conj() * hj[k] * w2;
                    }
                }
            }
        }
        let theta: Vec<f64> = data.omega.iter().map(|w| w * dt).collect();
        for d in 0..=p {
            let zd: Vec<c64> = theta.iter().map(|th| c64::cis(th * d as f64)).collect();
            r[d] = zd.iter().map(|z| z.re).sum();
            // Re Σ z^{±d} x = Σ (Re z Re x ∓ Im z Im x).
            let sums = |x: &[c64]| -> (f64, f64) {
                let (mut a, mut b) = (0.0, 0.0);
                for (z, v) in zd.iter().zip(x) {
                    a += z.re * v.re;
                    b += z.im * v.im;
                }
                (a - b, a + b)
            };
            for (gj, h) in g.iter_mut().zip(&data.h) {
                let (plus, minus) = sums(h);
                gj[p + d] = plus;
                gj[p - d] = minus;
            }
            for (tj, qj) in t.iter_mut().zip(&q) {
                let (plus, minus) = sums(qj);
                tj[p + d] = plus;
                tj[p - d] = minus;
            }
        }
        Ok(Sums {
            dt,
            max_order,
            m,
            r,
            g,
            t,
        })
    }
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
    let r0 = Mat::<f64>::from_fn(n1, n1, |a, b| sums.r[a.abs_diff(b)]);
    let llt = r0
        .llt(Side::Lower)
        .map_err(|_| IdentifyError::Singular("LSCF R"))?;
    let mut mm = Mat::<f64>::from_fn(nc, nc, |a, b| {
        let (r, i) = (a / m, a % m);
        let (s, j) = (b / m, b % m);
        sums.t[i * m + j][big + s - r]
    });
    // Per output: S0_o and Z_o = R0⁻¹ S0_o (kept for the numerators).
    let mut zs: Vec<Mat<f64>> = Vec::with_capacity(data.n_outputs());
    for (o, w) in data.weights.iter().enumerate() {
        let s0 = Mat::<f64>::from_fn(n1, nc, |r, b| {
            let (s, i) = (b / m, b % m);
            -sums.g[o * m + i][big + s - r]
        });
        let z = llt.solve(s0.as_ref());
        mm -= product(s0.transpose(), z.as_ref()) * (w * w);
        zs.push(z);
    }
    let pm = p * m;
    let maa = mm.submatrix(0, 0, pm, pm).to_owned();
    let mab = mm.submatrix(0, pm, pm, m).to_owned();
    let lu = maa.partial_piv_lu();
    let alpha_a = lu.solve((-&mab).as_ref());
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
    let eig = companion
        .eigen()
        .map_err(|_| IdentifyError::Singular("LSCF companion eigenvalues"))?;
    let betas: Vec<Mat<f64>> = zs
        .iter()
        .map(|z| -product(z.as_ref(), alpha.as_ref()))
        .collect();
    let mut out = Vec::new();
    for e in 0..pm {
        let z = eig.S().column_vector()[e];
        if !(z.im > 0.0) || !(z.norm() > 0.0) || !z.re.is_finite() {
            continue;
        }
        let pole = c64::new(z.norm().ln(), z.arg()) / sums.dt;
        let participation: Vec<c64> = (0..m).map(|i| eig.U()[(i, e)]).collect();
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
