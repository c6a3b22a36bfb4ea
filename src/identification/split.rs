//! Modes closer than their half-power bandwidths that the stabilisation
//! diagram gave as one pole.
//!
//! With one reference a close pair is one peak of every FRF (the GARTEUR
//! wing-torsion pair, 36.78 and 37.43 Hz at 1 % damping), and the diagram
//! can stabilise a single pole between the two. That pole leaves a residual
//! in its window (±[`WINDOW`] half-bandwidths) far above the noise. For
//! each selected pole whose window residual exceeds [`MERGED`] of the
//! window's data (weighted, as in [`super::lsfd`]), a second pole is placed
//! at the line of largest residual with the same damping, both are refined
//! together on the window ([`refine::refine_group`], the other poles held,
//! every residue free), and the pair is kept when the window's residual
//! falls to [`KEEP`] of what it was or less. Noise alone cannot do that: a
//! pole adds 2 + 2·(FRFs) unknowns against 2·(window lines)·(FRFs) data, so
//! fitting noise with it lowers the residual by a few percent.

use faer::c64;

use super::prepare::Prepared;
use super::refine::{cost, refine_group, residual_vector};
use super::{lsfd, IdentifyError};

/// Half-width of a pole's window in half-power half-bandwidths.
pub const WINDOW: f64 = 8.0;
/// A pole whose window residual is above this share of the window's data
/// (weighted squares) is tried as two.
pub const MERGED: f64 = 1e-2;
/// The split is kept when the window residual falls to this share or less.
pub const KEEP: f64 = 0.5;
/// Lines of a window at most (longer windows are strided).
const MAX_LINES: usize = 1000;

/// `poles` with every merged pole split in two (each selected pole tried
/// once; the new poles at the end).
pub fn split_merged(data: &Prepared, poles: &[c64]) -> Result<Vec<c64>, IdentifyError> {
    let n = data.n_lines();
    let line = (data.omega[n - 1] - data.omega[0]) / (n - 1).max(1) as f64;
    let selected = poles.len();
    let mut poles = poles.to_vec();
    for r in 0..selected {
        if let Some(split) = try_split(data, &poles, r, line)? {
            poles = split;
        }
    }
    // Two merged neighbours can each give a pole to the mode between them
    // (three close modes, two diagram poles): a new pole within a quarter
    // half-bandwidth of a pole already kept is the same mode, and goes.
    let sigma_of = |p: &c64| (-p.re).max(line);
    let mut kept: Vec<c64> = poles[..selected].to_vec();
    for &p in &poles[selected..] {
        if kept
            .iter()
            .all(|q| (p - q).norm() > 0.25 * sigma_of(q).max(sigma_of(&p)))
        {
            kept.push(p);
        }
    }
    Ok(kept)
}

/// The poles with pole `r` split, when that halves its window's residual.
/// The window is fitted with the poles whose windows overlap it and the
/// residual terms U, L for the others.
fn try_split(
    data: &Prepared,
    poles: &[c64],
    r: usize,
    line: f64,
) -> Result<Option<Vec<c64>>, IdentifyError> {
    let sigma_of = |p: &c64| (-p.re).max(line);
    let sigma_r = sigma_of(&poles[r]);
    let near: Vec<usize> = (0..poles.len())
        .filter(|&s| (poles[s].im - poles[r].im).abs() <= WINDOW * (sigma_r + sigma_of(&poles[s])))
        .collect();
    let window: Vec<usize> = (0..data.n_lines())
        .filter(|&k| (data.omega[k] - poles[r].im).abs() <= WINDOW * sigma_r)
        .collect();
    let stride = window.len().div_ceil(MAX_LINES).max(1);
    let lines: Vec<usize> = window.into_iter().step_by(stride).collect();
    // Per FRF: 2 unknowns per pole and U, L, with the new pole; the window
    // must hold twice as many data.
    if lines.len() < 2 * (2 * (near.len() + 1) + 2) {
        return Ok(None);
    }
    let local: Vec<c64> = near.iter().map(|&s| poles[s]).collect();
    let b = lsfd::rhs(data, &lines);
    let residual = residual_vector(data, &local, &lines, &b)?;
    let before = cost(&residual);
    let m = data.n_inputs();
    let energy: f64 = (0..data.h.len())
        .map(|j| data.weights[j / m].powi(2) * b.col(j).squared_norm_l2())
        .sum();
    if !(before > MERGED * energy) {
        return Ok(None);
    }
    let im = new_frequency(data, &residual, &lines, poles[r], sigma_r);
    let mut trial = local.clone();
    trial.push(c64::new(poles[r].re, im));
    let (lr, q) = (
        near.iter().position(|&s| s == r).unwrap_or(0),
        trial.len() - 1,
    );
    let sigma: Vec<f64> = trial.iter().map(sigma_of).collect();
    let refined = refine_group(data, &trial, &[lr, q], &sigma, &lines, &b)?;
    let after = cost(&residual_vector(data, &refined, &lines, &b)?);
    let inside = |p: c64| p.re < 0.0 && (p.im - poles[r].im).abs() <= WINDOW * sigma_r;
    let apart = (refined[lr] - refined[q]).norm() > 0.25 * sigma_r;
    let kept = after <= KEEP * before && inside(refined[lr]) && inside(refined[q]) && apart;
    if !kept {
        return Ok(None);
    }
    let mut out = poles.to_vec();
    out[r] = refined[lr];
    out.push(refined[q]);
    Ok(Some(out))
}

/// ω (rad/s) of the second pole: the window line of largest residual, kept
/// at least a half-bandwidth from the merged pole (on the side whose
/// residual is larger).
fn new_frequency(data: &Prepared, residual: &[f64], lines: &[usize], pole: c64, sigma: f64) -> f64 {
    let nl = lines.len();
    let per_line: Vec<f64> = (0..nl)
        .map(|k| {
            residual
                .chunks(2 * nl)
                .map(|col| col[2 * k].powi(2) + col[2 * k + 1].powi(2))
                .sum()
        })
        .collect();
    let (mut best, mut above, mut below) = (0, 0.0, 0.0);
    for (k, &v) in per_line.iter().enumerate() {
        if v > per_line[best] {
            best = k;
        }
        if data.omega[lines[k]] > pole.im {
            above += v;
        } else {
            below += v;
        }
    }
    let w = data.omega[lines[best]];
    if (w - pole.im).abs() >= sigma {
        w
    } else if above >= below {
        pole.im + sigma
    } else {
        pole.im - sigma
    }
}
