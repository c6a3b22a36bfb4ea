//! `reversed-channel` and `channel-scale`: a channel's gain g_c in
//! s_k(c) = α_k g_c a_k(c) (see [`super::table`]).
//!
//! - Magnitude: ln|s_k(c)| − ln|a_k(c)| = ln|α_k| + ln|g_c| + e_kc, a
//!   two-way table fitted by median polish (rows = modes, columns =
//!   channels), so that one wrong channel or one badly paired mode does not
//!   move the others' effects. Column effects are centred on their median
//!   (most channels are sound). A channel is scaled when |ln g_c| ≥ ln 3 with
//!   a median residual under ln 1.6 (the same factor on every mode).
//! - Sign: S_kc = sgn s_k(c) · sgn a_k(c) = sgn g_c (α_k > 0); each
//!   channel's agreement A_c = Σ_k w_kc S_kc m_k / Σ_k w_kc ∈ [−1, 1], with
//!   m_k = 1 unless most other channels disagree on mode k. A channel is
//!   reversed when A_c ≤ −0.5 (three quarters of its weight disagrees).
//!
//! Each channel is judged against the others: the pairs are made without
//! it and the mode effects come from the other channels alone (a leave-one-
//! out fit), so a wrong channel cannot pull the reference it is compared
//! with. A channel needs entries of summed weight [`MIN_EVIDENCE`] (one
//! mode where it carries half the largest response), the others at least
//! three channels with entries.

use super::table::{ModalTable, Paired};
use super::{median, DataError, DataErrorKind};

/// Summed entry weight a channel needs to be judged.
pub const MIN_EVIDENCE: f64 = 0.5;
/// |ln g| at or above ln 3 is a scale error.
pub const SCALE: f64 = 3.0;
/// Median residual under ln 1.6: the same factor on every mode.
pub const CONSISTENT: f64 = 1.6;
/// Agreement at or below this is a reversed channel.
pub const REVERSED: f64 = -0.5;

/// Unit conversions a channel is commonly off by: (words, factor).
const UNITS: [(&str, f64); 7] = [
    ("g and m/s² (9.81)", 9.80665),
    ("mm and m (1000)", 1000.0),
    ("inch and mm (25.4)", 25.4),
    ("inch and m (39.37)", 39.3701),
    ("lbf and N (4.448)", 4.448222),
    ("ft and m (3.281)", 3.28084),
    ("µm and m (10⁶)", 1e6),
];

/// The table's row and column effects.
pub struct Effects {
    /// ln|α_k| per pair.
    pub row: Vec<f64>,
    /// ln|g_c| per channel (0 without entries), centred on the median.
    pub col: Vec<f64>,
    /// Median |residual| of each channel.
    pub spread: Vec<f64>,
    /// Sign of each mode (±1).
    pub mode_sign: Vec<f64>,
    /// Sign agreement A_c of each channel.
    pub agreement: Vec<f64>,
}

fn log_ratio(t: &Paired, k: usize, c: usize) -> Option<f64> {
    (t.weight[k][c] > 0.0).then(|| t.test[k][c].abs().ln() - t.fe[k][c].abs().ln())
}

/// Median polish of the log ratios and the sign majorities over the `used`
/// channels; the column effect, spread and agreement of every channel
/// against the modes' effects so found.
pub fn effects(t: &Paired, used: &[bool]) -> Effects {
    let (nk, nc) = (t.test.len(), t.channels());
    let mut row = vec![0.0; nk];
    let mut col = vec![0.0; nc];
    let column = |c: usize, row: &[f64]| -> f64 {
        let v: Vec<f64> = (0..nk)
            .filter_map(|k| log_ratio(t, k, c).map(|l| l - row[k]))
            .collect();
        median(&v).unwrap_or(0.0)
    };
    for _ in 0..4 {
        row = (0..nk)
            .map(|k| {
                let v: Vec<f64> = (0..nc)
                    .filter(|&c| used[c])
                    .filter_map(|c| log_ratio(t, k, c).map(|l| l - col[c]))
                    .collect();
                median(&v).unwrap_or(0.0)
            })
            .collect();
        col = (0..nc).map(|c| column(c, &row)).collect();
    }
    let judged: Vec<f64> = (0..nc)
        .filter(|&c| used[c] && t.evidence(c) > 0.0)
        .map(|c| col[c])
        .collect();
    let centre = median(&judged).unwrap_or(0.0);
    col.iter_mut().for_each(|x| *x -= centre);
    row.iter_mut().for_each(|x| *x += centre);
    let spread = (0..nc)
        .map(|c| {
            let v: Vec<f64> = (0..nk)
                .filter_map(|k| log_ratio(t, k, c).map(|l| (l - row[k] - col[c]).abs()))
                .collect();
            median(&v).unwrap_or(0.0)
        })
        .collect();
    let (mode_sign, agreement) = signs(t, used);
    Effects {
        row,
        col,
        spread,
        mode_sign,
        agreement,
    }
}

/// Mode signs and every channel's agreement with them. A mode's sign is
/// +1 (measured and predicted modal constants share their sign, see
/// [`super::table`]) unless three quarters of the `used` channels with an
/// entry, one vote each, say −1 (a pole whose residues are too complex to
/// sign).
fn signs(t: &Paired, used: &[bool]) -> (Vec<f64>, Vec<f64>) {
    let (nk, nc) = (t.test.len(), t.channels());
    let mode_sign: Vec<f64> = (0..nk)
        .map(|k| {
            let voters: Vec<f64> = (0..nc)
                .filter(|&c| used[c] && t.weight[k][c] > 0.0)
                .map(|c| sign(t, k, c))
                .collect();
            let votes: f64 = voters.iter().sum();
            if !voters.is_empty() && votes <= -0.5 * voters.len() as f64 {
                -1.0
            } else {
                1.0
            }
        })
        .collect();
    let agreement = (0..nc)
        .map(|c| {
            let (mut s, mut w) = (0.0, 0.0);
            for (k, m) in mode_sign.iter().enumerate() {
                s += t.weight[k][c] * sign(t, k, c) * m;
                w += t.weight[k][c];
            }
            if w > 0.0 {
                s / w
            } else {
                1.0
            }
        })
        .collect();
    (mode_sign, agreement)
}

/// sgn s_k(c) · sgn a_k(c).
pub fn sign(t: &Paired, k: usize, c: usize) -> f64 {
    if (t.test[k][c] < 0.0) == (t.fe[k][c] < 0.0) {
        1.0
    } else {
        -1.0
    }
}

/// The unit conversion nearest `factor` (> 0), if within 25 % (a factor
/// read from modal constants of a deck that is itself off), and its exact value
/// (inverted when the channel is too small).
pub fn unit_of(factor: f64) -> Option<(&'static str, f64)> {
    UNITS
        .iter()
        .flat_map(|&(words, f)| [(words, f), (words, 1.0 / f)])
        .map(|(words, f)| ((factor / f).ln().abs(), words, f))
        .filter(|(d, _, _)| *d < 0.25)
        .min_by(|a, b| a.0.total_cmp(&b.0))
        .map(|(_, words, f)| (words, f))
}

/// The error of channel `c` (if any) against the effects of the others.
fn judge(p: &Paired, e: &Effects, c: usize) -> Option<DataErrorKind> {
    if p.evidence(c) < MIN_EVIDENCE {
        return None;
    }
    let reversed = e.agreement[c] <= REVERSED;
    let scaled = e.col[c].abs() >= SCALE.ln() && e.spread[c] <= CONSISTENT.ln();
    if scaled {
        let magnitude = e.col[c].exp();
        let unit = unit_of(magnitude);
        let exact = unit.map_or(magnitude, |u| u.1);
        Some(DataErrorKind::Scale {
            factor: if reversed { -exact } else { exact },
            unit: unit.map(|u| u.0),
        })
    } else if reversed {
        Some(DataErrorKind::Reversed {
            agreement: e.agreement[c],
            over: "its modes' weight",
        })
    } else {
        None
    }
}

/// The clearest reversed or scaled channel, each judged against the
/// others: the largest |ln g|, else the lowest sign agreement.
pub fn clearest(t: &ModalTable) -> Option<DataError> {
    let nc = t.channels();
    let mut best: Option<(f64, DataError)> = None;
    for c in (0..nc).filter(|&c| t.is_live(c)) {
        let p = t.paired(&[c]);
        let used: Vec<bool> = (0..nc).map(|j| j != c && t.is_live(j)).collect();
        if (0..nc).filter(|&j| used[j] && p.evidence(j) > 0.0).count() < 3 {
            continue;
        }
        let e = effects(&p, &used);
        let Some(kind) = judge(&p, &e, c) else {
            continue;
        };
        let severity = match kind {
            DataErrorKind::Scale { factor, .. } => 1.0 + factor.abs().ln().abs(),
            _ => -e.agreement[c],
        };
        if best.as_ref().is_none_or(|b| severity > b.0) {
            best = Some((severity, DataError { channel: c, kind }));
        }
    }
    best.map(|b| b.1)
}
