//! `dead-channel`: a channel that holds noise only.
//!
//! The signal-to-noise ratio of a channel is the 99th percentile over lines
//! of |H_c(l)| / σ_c, with σ_c the noise estimated from second differences
//! along frequency ([`TestData::sigma`]). Complex white noise alone
//! (P(|n| > x) = exp(−x²/σ²)) gives √(ln 100) ≈ 2.15, whatever its level;
//! a live channel's resonances stand tens of σ above its noise even where
//! most lines are weak (a median would call such a channel dead). A channel
//! is dead when its ratio is under [`DEAD_SNR`] while the campaign's median
//! is at least [`LIVE_SNR`] (the test resolves its FRFs at all) and the deck
//! predicts the channel moves: its largest modal constant in the band is
//! at least [`MOVES`] of the median channel's. A channel the deck itself
//! predicts near zero (a sensor across the plane of bending) is not flagged:
//! noise there is the right measurement.

use super::super::data::TestData;
use super::super::fit::ModalModel;
use super::{median, DataError, DataErrorKind};

/// A channel under this signal-to-noise ratio holds noise only.
pub const DEAD_SNR: f64 = 5.0;
/// The campaign's median signal-to-noise ratio must reach this.
pub const LIVE_SNR: f64 = 20.0;
/// Share of the median channel's predicted response a dead channel must have.
pub const MOVES: f64 = 0.05;

/// Signal-to-noise ratio of each channel.
pub fn snr(data: &TestData) -> Vec<f64> {
    data.values
        .iter()
        .zip(&data.sigma)
        .map(|(v, &s)| {
            let mut m: Vec<f64> = v.iter().map(|z| z.norm()).collect();
            m.sort_by(|a, b| a.total_cmp(b));
            let top = m.get((m.len() * 99) / 100).copied().unwrap_or(0.0);
            if s > 0.0 {
                top / s
            } else if top > 0.0 {
                f64::INFINITY
            } else {
                0.0
            }
        })
        .collect()
}

/// Largest |modal constant| of each channel over the modes up to 1.2 × the
/// band's top line.
pub fn predicted_strength(data: &TestData, mm: &ModalModel) -> Vec<f64> {
    let w_top = 1.2 * data.omegas.iter().fold(0.0f64, |a, w| a.max(*w));
    mm.coeff
        .iter()
        .map(|row| {
            row.iter()
                .zip(&mm.omega2)
                .filter(|(_, w2)| **w2 <= w_top * w_top)
                .fold(0.0f64, |a, (x, _)| a.max(x.abs()))
        })
        .collect()
}

/// The dead channels of `data`.
pub fn dead_channels(data: &TestData, mm: &ModalModel) -> Vec<DataError> {
    if data.channels.len() < 3 {
        return Vec::new();
    }
    let snr = snr(data);
    let strength = predicted_strength(data, mm);
    let (Some(snr_mid), Some(strength_mid)) = (median(&snr), median(&strength)) else {
        return Vec::new();
    };
    if snr_mid < LIVE_SNR || !(strength_mid > 0.0) {
        return Vec::new();
    }
    let dead: Vec<DataError> = snr
        .iter()
        .zip(&strength)
        .enumerate()
        .filter(|(_, (s, p))| **s < DEAD_SNR && **p >= MOVES * strength_mid)
        .map(|(c, (s, _))| DataError {
            channel: c,
            kind: DataErrorKind::Dead { snr: *s },
        })
        .collect();
    // Most channels "dead" means the test, not a channel, is the problem.
    if 2 * dead.len() >= data.channels.len() {
        return Vec::new();
    }
    dead
}
