//! What the data say about the parameters at the optimum of the full-band
//! estimate: the sandwich covariance and the directions the data do not see.
//!
//! With J the Jacobian over the free unknowns (prior rows included),
//! H = JᵀJ and B = Σ_i w_i J_iᵀJ_i, where w_i = r_i²/(1 − h_ii)² for a data
//! row (its observed scatter, inflated by its leverage h_ii = J_i H⁻¹ J_iᵀ
//! as HC3: a few lines at a sharp peak decide a frequency, and the fit
//! shrinks their residuals) and w_i = J₀ for a prior row (its expected r²
//! under the prior), the covariance is H⁻¹BH⁻¹: it holds at the noise level
//! the data show, whatever the weights assumed.
//!
//! The data's own information over the structural parameters is JᵀJ/ŝ²
//! (data rows, ŝ² = Σr²/(N − n)); its eigenvectors whose standard deviation
//! 1/√λ exceeds [`UNIDENTIFIED_SD`] are the directions the data miss.

use faer::linalg::matmul::matmul;
use faer::{Accum, Mat, Par};

use super::estimate::UNIDENTIFIED_SD;
use super::lm::{self, LeastSquares, LmOutcome};
use super::objective::Objective;
use crate::solvers::dense::{product, symmetric_eigen};

/// Standard deviations at a point and the unseen directions.
pub struct Uncertainty {
    /// Posterior standard deviation of each structural parameter (sandwich
    /// covariance over the free unknowns; ∞ for fixed ones).
    pub sd: Vec<f64>,
    /// Standard deviation from the data alone, ŝ²(JᵀJ)⁻¹ over the free
    /// unknowns' data rows (∞ where the data see nothing).
    pub sd_data: Vec<f64>,
    /// Eigenvectors of the data information over the free structural
    /// parameters whose standard deviation 1/√λ exceeds [`UNIDENTIFIED_SD`]
    /// (components over all parameters), with that standard deviation,
    /// largest first.
    pub missing: Vec<(Vec<f64>, f64)>,
}

/// The uncertainty at `out` over the unknowns with `free` set.
pub fn uncertainty(obj: &mut Objective, out: &LmOutcome, free: &[bool], j0: f64) -> Uncertainty {
    let np = obj.np();
    let mut u = Uncertainty {
        sd: vec![f64::INFINITY; np],
        sd_data: vec![f64::INFINITY; np],
        missing: Vec::new(),
    };
    let Some(jac) = obj.jacobian(&out.x, &out.residuals, free) else {
        return u;
    };
    let r = &out.residuals;
    let idx: Vec<usize> = (0..out.x.len()).filter(|&i| free[i]).collect();
    let n = idx.len();
    let data_n = obj.data_rows(r.len());
    let j = Mat::from_fn(r.len(), n, |i, k| jac[(i, idx[k])]);
    let (h, _) = lm::normal_equations(j.as_ref(), r, &(0..n).collect::<Vec<_>>());
    if let Some(hinv) = lm::inverse_spd(h.as_ref()) {
        let mut z = Mat::<f64>::zeros(r.len(), n);
        matmul(
            z.as_mut(),
            Accum::Replace,
            j.as_ref(),
            hinv.as_ref(),
            1.0,
            Par::Seq,
        );
        // √w_i per row (the leverage h_ii = Σ_c z_ic j_ic once per row).
        let mut lev = vec![0.0; data_n];
        for c in 0..n {
            let (zc, jc) = (z.col(c), j.col(c));
            for (i, l) in lev.iter_mut().enumerate() {
                *l += zc[i] * jc[i];
            }
        }
        let root_w: Vec<f64> = (0..r.len())
            .map(|i| match lev.get(i) {
                Some(&h) => r[i].abs() / (1.0 - h.clamp(0.0, 0.99)),
                None => j0.sqrt(),
            })
            .collect();
        let scaled = Mat::from_fn(r.len(), n, |i, k| root_w[i] * j[(i, k)]);
        let mut b = Mat::<f64>::zeros(n, n);
        matmul(
            b.as_mut(),
            Accum::Replace,
            scaled.transpose(),
            scaled.as_ref(),
            1.0,
            Par::Seq,
        );
        let cov = product(product(hinv.as_ref(), b.as_ref()).as_ref(), hinv.as_ref());
        for (a, &ia) in idx.iter().enumerate() {
            if ia < np {
                u.sd[ia] = cov[(a, a)].max(0.0).sqrt();
            }
        }
    }
    data_information(
        &mut u,
        j.as_ref().subrows(0, data_n),
        &r[..data_n],
        &idx,
        np,
        None,
    );
    u
}

/// The data-only standard deviations of the structural parameters at `x`
/// (the reduced model anchored there) and the directions the data miss
/// there, with the residual variance `s2` of another point (the optimum):
/// the information a far point would hold. [`Uncertainty::sd`] is not
/// computed (∞).
pub fn data_sd_at(obj: &mut Objective, x: &[f64], free: &[bool], s2: f64) -> Option<Uncertainty> {
    let np = obj.np();
    obj.anchor(&x[..np]).ok()?;
    let r = obj.residuals(x)?;
    let jac = obj.jacobian(x, &r, free)?;
    let idx: Vec<usize> = (0..x.len()).filter(|&i| free[i]).collect();
    let data_n = obj.data_rows(r.len());
    let j = Mat::from_fn(data_n, idx.len(), |i, k| jac[(i, idx[k])]);
    let mut u = Uncertainty {
        sd: vec![f64::INFINITY; np],
        sd_data: vec![f64::INFINITY; np],
        missing: Vec::new(),
    };
    data_information(&mut u, j.as_ref(), &r[..data_n], &idx, np, Some(s2));
    Some(u)
}

/// ŝ² = Σr²/(N − n) over the data rows of `out` with n free unknowns.
pub fn residual_variance(obj: &Objective, out: &LmOutcome, free: &[bool]) -> f64 {
    let data_n = obj.data_rows(out.residuals.len());
    let n = free.iter().filter(|&&f| f).count();
    let dof = (data_n as f64 - n as f64).max(1.0);
    (out.residuals[..data_n].iter().map(|v| v * v).sum::<f64>() / dof).max(1e-300)
}

/// sd_data and the missing directions from the data rows of J (columns `idx`).
fn data_information(
    u: &mut Uncertainty,
    j: faer::MatRef<'_, f64>,
    r: &[f64],
    idx: &[usize],
    np: usize,
    s2: Option<f64>,
) {
    let ip: Vec<usize> = (0..idx.len()).filter(|&a| idx[a] < np).collect();
    if ip.is_empty() {
        return;
    }
    let dof = (r.len() as f64 - idx.len() as f64).max(1.0);
    let s2 = s2.unwrap_or_else(|| (r.iter().map(|v| v * v).sum::<f64>() / dof).max(1e-300));
    let (info, _) = lm::normal_equations(j, r, &ip);
    let info = Mat::from_fn(ip.len(), ip.len(), |a, c| {
        0.5 * (info[(a, c)] + info[(c, a)]) / s2
    });
    let Some((lam, vecs)) = symmetric_eigen(info.as_ref()) else {
        return;
    };
    // Eigenvalues below 1e-14 of the largest are rounding: taken at that
    // floor, so that a parameter's variance is ∞ only when all information
    // is zero, and a direction the data miss (≈ 1/floor) does not leak into
    // the others through rounding-size components of its eigenvector.
    let floor = lam.iter().fold(0.0f64, |m, l| m.max(l.abs())) * 1e-14;
    let sd_of = |l: f64| {
        if floor > 0.0 {
            1.0 / l.max(floor).sqrt()
        } else {
            f64::INFINITY
        }
    };
    for (a, &pa) in ip.iter().enumerate() {
        // (info⁻¹)_aa by the eigen-decomposition.
        let var: f64 = (0..lam.len())
            .map(|k| vecs[(a, k)].powi(2) * sd_of(lam[k]).powi(2))
            .sum();
        u.sd_data[idx[pa]] = var.sqrt();
    }
    for (k, &l) in lam.iter().enumerate() {
        let sd = sd_of(l);
        if sd > UNIDENTIFIED_SD {
            let mut v = vec![0.0; np];
            for (a, &pa) in ip.iter().enumerate() {
                v[idx[pa]] = vecs[(a, k)];
            }
            u.missing.push((v, sd));
        }
    }
    u.missing.sort_by(|a, b| b.1.total_cmp(&a.1));
}
