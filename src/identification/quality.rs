//! Shapes from residues, and the quality figures of a complex shape ψ.
//!
//! With S_xx = Re ψ·Re ψ, S_yy = Im ψ·Im ψ, S_xy = Re ψ·Im ψ, the 2 × 2
//! covariance of the points ψ_j in the complex plane has eigenvalues
//! e₁ ≥ e₂ and principal direction θ = ½ atan2(2S_xy, S_xx − S_yy):
//!
//! - MPC, modal phase collinearity (Pappa, Elliott & Schenk, J. Guidance 16
//!   (1993)): ((e₁ − e₂)/(e₁ + e₂))² = ((S_xx − S_yy)² + 4S_xy²)/(S_xx + S_yy)²,
//!   1 for a real (normal) mode;
//! - MPD, mean phase deviation (degrees): Σ_j |ψ_j| δ_j / Σ_j |ψ_j| with δ_j
//!   the angle between ψ_j and the line at θ (0 … 90°), 0 for a real mode;
//! - complexity: ‖Im ψ̃‖/‖ψ̃‖ of ψ rotated by −θ (√(e₂/(e₁+e₂)), 0 … 1/√2).

use faer::c64;

use super::prepare::Prepared;

/// Quality figures of one mode's shape.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Quality {
    pub mpc: f64,
    /// Degrees.
    pub mpd_deg: f64,
    pub complexity: f64,
}

fn moments(psi: &[c64]) -> (f64, f64, f64) {
    psi.iter().fold((0.0, 0.0, 0.0), |(xx, yy, xy), v| {
        (xx + v.re * v.re, yy + v.im * v.im, xy + v.re * v.im)
    })
}

impl Quality {
    /// The figures of `psi` (any scale or phase).
    pub fn of(psi: &[c64]) -> Quality {
        let (xx, yy, xy) = moments(psi);
        let tr = xx + yy;
        if !(tr > 0.0) {
            return Quality {
                mpc: 0.0,
                mpd_deg: 0.0,
                complexity: 0.0,
            };
        }
        let disc = ((xx - yy).powi(2) + 4.0 * xy * xy).sqrt();
        let mpc = (disc / tr).powi(2);
        let e2 = 0.5 * (tr - disc);
        let theta = 0.5 * (2.0 * xy).atan2(xx - yy);
        let (mut num, mut den) = (0.0, 0.0);
        for v in psi {
            let a = v.norm();
            if a > 0.0 {
                let d = (v.arg() - theta).rem_euclid(std::f64::consts::PI);
                num += a * d.min(std::f64::consts::PI - d);
                den += a;
            }
        }
        Quality {
            mpc,
            mpd_deg: (num / den.max(f64::MIN_POSITIVE)).to_degrees(),
            complexity: (e2.max(0.0) / tr).sqrt(),
        }
    }
}

/// ψ rotated by −θ (most nearly real), scaled so that its largest component
/// is 1 (real, positive).
pub fn rotate_real(psi: &[c64]) -> Vec<c64> {
    let Some(big) = psi
        .iter()
        .copied()
        .max_by(|a, b| a.norm().total_cmp(&b.norm()))
    else {
        return Vec::new();
    };
    if !(big.norm() > 0.0) {
        return psi.to_vec();
    }
    let (xx, yy, xy) = moments(psi);
    let theta = 0.5 * (2.0 * xy).atan2(xx - yy);
    let rot = c64::cis(-theta);
    let big_rot = big * rot;
    let sign = if big_rot.re < 0.0 { -1.0 } else { 1.0 };
    let scale = sign / big.norm();
    psi.iter().map(|v| v * rot * scale).collect()
}

/// Output shape and input participation from the residues of one mode: the
/// leading singular pair of the n_o × n_i residue matrix A = ψ Lᵀ (power
/// iteration on AᴴA; exact for one input). Participation scaled to largest
/// magnitude 1; the shape keeps the residues' scale.
pub fn shape_and_participation(data: &Prepared, residues: &[c64]) -> (Vec<c64>, Vec<c64>) {
    let m = data.n_inputs();
    let no = data.n_outputs();
    let a = |o: usize, i: usize| residues[o * m + i];
    let mut v: Vec<c64> = (0..m)
        .map(|i| (0..no).map(|o| a(o, i).norm_sqr()).sum::<f64>())
        .map(|x| c64::new(x.sqrt(), 0.0))
        .collect();
    for _ in 0..if m == 1 { 1 } else { 50 } {
        let u: Vec<c64> = (0..no)
            .map(|o| (0..m).map(|i| a(o, i) * v[i]).sum())
            .collect();
        let nv: Vec<c64> = (0..m)
            .map(|i| (0..no).map(|o| a(o, i).conj() * u[o]).sum::<c64>().conj())
            .collect();
        let norm = nv.iter().map(|x| x.norm_sqr()).sum::<f64>().sqrt();
        if !(norm > 0.0) {
            break;
        }
        v = nv.iter().map(|x| x / norm).collect();
    }
    // ψ = A v̄ / |v|², so that A ≈ ψ vᵀ.
    let vv: f64 = v
        .iter()
        .map(|x| x.norm_sqr())
        .sum::<f64>()
        .max(f64::MIN_POSITIVE);
    let shape: Vec<c64> = (0..no)
        .map(|o| (0..m).map(|i| a(o, i) * v[i].conj()).sum::<c64>() / vv)
        .collect();
    let vmax = v
        .iter()
        .map(|x| x.norm())
        .fold(0.0, f64::max)
        .max(f64::MIN_POSITIVE);
    let participation = v.iter().map(|x| x / vmax).collect();
    (shape, participation)
}
