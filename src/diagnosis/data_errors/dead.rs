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
//! at least [`MOVES`] of the median channel's. Both medians are over the
//! channels the deck predicts to move (largest constant at least [`MOVES`]
//! of the campaign's largest). A channel the deck itself predicts near zero
//! (a sensor across the plane of bending) is flagged only if the deck's FRF
//! there, set against the channel's own noise floor, would stand [`CLEAR`]
//! × above it: noise is the right measurement of a response below the
//! noise, not of one far above it.

use super::super::data::TestData;
use super::super::fit::ModalModel;
use super::{median, DataError, DataErrorKind};

/// A channel under this signal-to-noise ratio holds noise only.
pub const DEAD_SNR: f64 = 5.0;
/// The campaign's median signal-to-noise ratio must reach this.
pub const LIVE_SNR: f64 = 20.0;
/// Share of the median channel's predicted response a dead channel must have.
pub const MOVES: f64 = 0.05;
/// Or the signal-to-noise ratio the deck predicts for it must reach this
/// (a weak direction whose noise floor is far below its response).
pub const CLEAR: f64 = 50.0;
/// A channel whose largest predicted modal constant is under this share of
/// the campaign's largest does not move at all (a direction the deck
/// uncouples from the excitation: its noise floor is round-off).
pub const AT_ALL: f64 = 1e-3;

/// A channel the deck predicts silent holds a response when its
/// signal-to-noise ratio reaches this while the deck predicts under
/// [`DEAD_SNR`] there.
pub const LOUD_SNR: f64 = 20.0;
/// Largest factor between the level of a loud channel's data and the
/// level the deck predicts at a dead channel for the two to be one swap
/// (the factor 3 the modal checks allow a deck that is off).
pub const LEVEL_MATCH: f64 = 3.0;

/// Signal-to-noise ratio of each channel.
pub fn snr(data: &TestData) -> Vec<f64> {
    data.values
        .iter()
        .zip(&data.sigma)
        .map(|(v, &s)| channel_snr(v, s))
        .collect()
}

/// The 99th percentile over lines of |v| / `sigma`.
fn channel_snr(v: &[faer::c64], sigma: f64) -> f64 {
    let mut m: Vec<f64> = v.iter().map(|z| z.norm()).collect();
    m.sort_by(|a, b| a.total_cmp(b));
    let top = m.get((m.len() * 99) / 100).copied().unwrap_or(0.0);
    if sigma > 0.0 {
        top / sigma
    } else if top > 0.0 {
        f64::INFINITY
    } else {
        0.0
    }
}

/// Largest |modal constant| of each channel over the modes up to 1.2 × the
/// band's top line, a repeated mode's summed over its eigenspace
/// ([`ModalModel::repeated_merged`]: a tube's y and z bending pair mixed
/// at random would otherwise put a z-excited response at every y sensor).
pub fn predicted_strength(data: &TestData, mm: &ModalModel) -> Vec<f64> {
    let w_top = 1.2 * data.omegas.iter().fold(0.0f64, |a, w| a.max(*w));
    let mm = mm.repeated_merged();
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

/// The deck's FRFs at every channel and line of `data`, its modes damped
/// at the test's half-power damping ratio.
fn deck_frfs(data: &TestData, mm: &ModalModel) -> Vec<Vec<faer::c64>> {
    let damping = crate::model::Damping::Modal {
        zeta: data.half_power_zeta(),
    };
    super::super::fit::predict(mm, damping, data, &super::super::fit::Mask::all(data))
}

/// The signal-to-noise ratio of the deck's FRFs `model` (of
/// [`deck_frfs`]) at each channel: the 99th percentile over lines of
/// |H_model,c(l)| / σ_c, σ_c the channel's measured noise.
fn snr_of(model: &[Vec<faer::c64>], data: &TestData) -> Vec<f64> {
    model
        .iter()
        .zip(&data.sigma)
        .map(|(v, &s)| channel_snr(v, s))
        .collect()
}

/// The signal-to-noise ratio the deck predicts at each channel
/// ([`deck_frfs`] against each channel's measured noise).
pub fn predicted_snr(data: &TestData, mm: &ModalModel) -> Vec<f64> {
    snr_of(&deck_frfs(data, mm), data)
}

/// The dead channels of `data`.
pub fn dead_channels(data: &TestData, mm: &ModalModel) -> Vec<DataError> {
    if data.channels.len() < 3 {
        return Vec::new();
    }
    let snr = snr(data);
    let strength = predicted_strength(data, mm);
    // The medians are over the channels the deck predicts to move at all: a
    // campaign may measure directions that the excitation leaves still.
    let largest = strength.iter().fold(0.0f64, |a, p| a.max(*p));
    let moves = |c: usize| strength[c] >= MOVES * largest;
    let moving: Vec<usize> = (0..strength.len()).filter(|&c| moves(c)).collect();
    let over_moving = |v: &[f64]| median(&moving.iter().map(|&c| v[c]).collect::<Vec<_>>());
    let (Some(snr_mid), Some(strength_mid)) = (over_moving(&snr), over_moving(&strength)) else {
        return Vec::new();
    };
    if snr_mid < LIVE_SNR || !(strength_mid > 0.0) {
        return Vec::new();
    }
    // The deck's FRFs only when some channel holds noise.
    let expected = if snr.iter().any(|s| *s < DEAD_SNR) {
        predicted_snr(data, mm)
    } else {
        vec![0.0; snr.len()]
    };
    let clear = |c: usize| expected[c] >= CLEAR && strength[c] >= AT_ALL * largest;
    let dead: Vec<DataError> = (0..snr.len())
        .filter(|&c| snr[c] < DEAD_SNR && (strength[c] >= MOVES * strength_mid || clear(c)))
        .map(|c| DataError {
            channel: c,
            kind: DataErrorKind::Dead { snr: snr[c] },
        })
        .collect();
    // Most channels "dead" means the test, not a channel, is the problem.
    // Counted against every channel where the deck predicts a response
    // the test should show: those that move and those clear of their
    // noise (a driving point's accelerance can put every other channel
    // under MOVES of the largest, leaving two "moving" channels of six).
    let expected_live = (0..snr.len()).filter(|&c| moves(c) || clear(c)).count();
    if 2 * dead.len() >= expected_live {
        return Vec::new();
    }
    dead
}

/// Dead channels whose data sit at another sensor's place: a channel d
/// holds noise where the deck predicts a response, while a channel c
/// holds a clear response (signal-to-noise ratio ≥ [`LOUD_SNR`]) where
/// the deck predicts nothing above its noise (a y sensor's cable in the z
/// sensor's socket on a beam bent in y). When the level of c's data (99th
/// percentile of |H|) is within [`LEVEL_MATCH`] of the level the deck
/// predicts at d, the two channels are swapped, not d dead: each holds
/// what the deck predicts at the other. Of several such c, the closest in
/// level; each channel in one pair. The dead errors of `errors` so
/// explained become a swapped pair.
pub fn swaps_with_silent(
    data: &TestData,
    mm: &ModalModel,
    errors: Vec<DataError>,
) -> Vec<DataError> {
    let dead: Vec<usize> = errors
        .iter()
        .filter(|e| matches!(e.kind, DataErrorKind::Dead { .. }))
        .map(|e| e.channel)
        .collect();
    if dead.is_empty() {
        return errors;
    }
    let snr = snr(data);
    let model = deck_frfs(data, mm);
    let expected = snr_of(&model, data);
    let level = |v: &[faer::c64]| channel_snr(v, 1.0);
    let mut loud: Vec<usize> = (0..snr.len())
        .filter(|&c| !dead.contains(&c) && snr[c] >= LOUD_SNR && expected[c] < DEAD_SNR)
        .collect();
    let mut out: Vec<DataError> = errors
        .into_iter()
        .filter(|e| !matches!(e.kind, DataErrorKind::Dead { .. }))
        .collect();
    for d in dead {
        let want = level(&model[d]);
        let best = loud
            .iter()
            .map(|&c| ((level(&data.values[c]) / want).ln().abs(), c))
            .filter(|(m, _)| m.is_finite() && *m <= LEVEL_MATCH.ln())
            .min_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        match best {
            Some((_, c)) => {
                loud.retain(|&x| x != c);
                out.extend(super::swapped_pair(d, c));
            }
            None => out.push(DataError {
                channel: d,
                kind: DataErrorKind::Dead { snr: snr[d] },
            }),
        }
    }
    out.sort_by_key(|e| e.channel);
    out
}
