//! `swapped-channels`: two channels each holding the other's data.
//!
//! The misfit of channel c holding the values t_k (over the paired modes) is
//! C_c(t) = Σ_k w_kc [min(((ln|t_k| − ln|a_k(c)| − ln|α_k|)/0.5)², 16)
//! \+ 4·[sgn t_k · sgn a_k(c) · m_k < 0]] / Σ_k w_kc, with the mode
//! effects α_k and signs m_k of [`super::gains::effects`]: a 50 % magnitude
//! error costs 0.66, a wrong sign 4. Channels a and b are swapped when
//! C_a(s_b) + C_b(s_a) ≤ [`GAIN`] × (C_a(s_a) + C_b(s_b)) and the latter is
//! at least [`BAD`] (both channels clearly misfit as they are).

use super::gains::{effects, Effects, MIN_EVIDENCE};
use super::table::{ModalTable, Paired};
use super::DataError;

/// The swapped misfit must be at most this share of the misfit as measured.
pub const GAIN: f64 = 0.25;
/// The two channels' misfit as measured must reach this.
pub const BAD: f64 = 4.0;

fn misfit(t: &Paired, e: &Effects, c: usize, values: &[f64]) -> f64 {
    let (mut s, mut w) = (0.0, 0.0);
    for (k, &v) in values.iter().enumerate() {
        let wk = t.weight[k][c];
        if wk <= 0.0 || v == 0.0 {
            continue;
        }
        let a = t.fe[k][c];
        let l = (v.abs().ln() - a.abs().ln() - e.row[k]) / 0.5;
        let wrong_sign = (v < 0.0) != (a < 0.0);
        let flipped = if wrong_sign {
            -e.mode_sign[k]
        } else {
            e.mode_sign[k]
        };
        s += wk * ((l * l).min(16.0) + if flipped < 0.0 { 4.0 } else { 0.0 });
        w += wk;
    }
    if w > 0.0 {
        s / w
    } else {
        0.0
    }
}

/// Misfit of channels a and b as measured and swapped, judged on pairs
/// made without both and against the mode effects of the other channels.
fn misfits(t: &ModalTable, a: usize, b: usize) -> Option<(f64, f64)> {
    let nc = t.channels();
    let p = t.paired(&[a, b]);
    let used: Vec<bool> = (0..nc).map(|j| j != a && j != b && t.is_live(j)).collect();
    if p.evidence(a) < MIN_EVIDENCE
        || p.evidence(b) < MIN_EVIDENCE
        || (0..nc).filter(|&j| used[j] && p.evidence(j) > 0.0).count() < 2
    {
        return None;
    }
    let e = effects(&p, &used);
    let column = |c: usize| -> Vec<f64> { p.test.iter().map(|s| s[c]).collect() };
    let (sa, sb) = (column(a), column(b));
    Some((
        misfit(&p, &e, a, &sa) + misfit(&p, &e, b, &sb),
        misfit(&p, &e, a, &sb) + misfit(&p, &e, b, &sa),
    ))
}

/// The swapped pairs of the table, each reported for both channels.
pub fn swapped_pairs(t: &ModalTable) -> Vec<DataError> {
    let nc = t.channels();
    let live: Vec<usize> = (0..nc).filter(|&c| t.is_live(c)).collect();
    if live.len() < 4 {
        return Vec::new();
    }
    let mut cand: Vec<(f64, usize, usize)> = Vec::new();
    for (i, &a) in live.iter().enumerate() {
        for &b in &live[i + 1..] {
            if let Some((as_measured, swapped)) = misfits(t, a, b) {
                if as_measured >= BAD && swapped <= GAIN * as_measured {
                    cand.push((swapped / as_measured, a, b));
                }
            }
        }
    }
    cand.sort_by(|x, y| x.0.total_cmp(&y.0).then(x.1.cmp(&y.1)).then(x.2.cmp(&y.2)));
    let mut used = vec![false; nc];
    let mut out = Vec::new();
    for (_, a, b) in cand {
        if used[a] || used[b] {
            continue;
        }
        used[a] = true;
        used[b] = true;
        out.extend(super::swapped_pair(a, b));
    }
    // Several swaps at once are more likely a deck far from the test.
    if out.len() > 2 {
        return Vec::new();
    }
    out
}
