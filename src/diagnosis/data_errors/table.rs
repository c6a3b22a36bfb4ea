//! The test's modes paired with the deck's, and the modal constants of each
//! pair at every channel: what the channel checks compare.
//!
//! Test modes come from the multi-channel pole fit
//! ([`crate::updating::identify::identify_modes`]) on the receptance of the
//! live channels (on a long record, from [`identify_column`] on the whole
//! record): a real shape s_k(c) per mode (largest magnitude 1), signed
//! as the modal constants φ_c,k φ_in,k. The deck's modal constants are
//! a_r(c) = φ_c,r φ_in,r ([`ModalModel::coeff`]). Both are free of the
//! arbitrary sign of a mode shape, so measured and predicted constants of a
//! mode are proportional with a positive factor, s_k(c) = α_k g_c a_r(c),
//! α_k > 0, where g_c = 1 for a sound channel.
//!
//! Pairing must not depend on the errors it is meant to find: a channel is
//! judged on pairs whose MAC is the best over its possible errors
//! ([`ModalTable::paired`]), computed on channel-normalised shapes (each
//! channel divided by its RMS over the modes, so that a channel's wrong
//! gain does not dominate), within ±[`WINDOW`] in frequency, greedily by
//! that MAC less half the log frequency ratio. Rigid-body modes (0 Hz) and
//! suspension modes (a few Hz) fall outside each other's window and that of
//! every elastic mode.

use super::super::data::TestData;
use super::super::fit::ModalModel;
use crate::identification::{identify_column, ColumnMode};
use crate::testdata::i_omega_power;
use crate::updating::frequencies::indicator;
use crate::updating::identify::{identify_modes, IdentifyOptions};

/// Largest relative frequency difference of a test mode and its FE partner.
pub const WINDOW: f64 = 0.3;
/// A pair's channel-normalised MAC must reach this.
pub const MIN_MAC: f64 = 0.3;
/// Entries where the deck predicts under this share of the mode's largest
/// constant are left out (near a nodal point the ratio means nothing).
pub const STRONG: f64 = 0.1;

/// The test's identified modes and the deck's modes near the band, at
/// every channel (`[mode][channel]`, 0 at channels that are not live).
pub struct ModalTable {
    test: Vec<Vec<f64>>,
    test_hz: Vec<f64>,
    fe: Vec<Vec<f64>>,
    fe_hz: Vec<f64>,
    live: Vec<bool>,
}

/// Modes paired for some judged channels, and their constants at every
/// channel (`[pair][channel]`; weight 0 where the entry is left out).
pub struct Paired {
    pub test: Vec<Vec<f64>>,
    pub fe: Vec<Vec<f64>>,
    pub weight: Vec<Vec<f64>>,
    /// (test, FE) natural frequency of each pair (Hz).
    pub frequencies_hz: Vec<(f64, f64)>,
}

/// The test's modes at channels `idx`: by the per-band pole fit on the
/// receptance, or, on a long record fitted on its informative lines, by
/// [`identify_column`] on the whole record (the pole fit's bands span
/// ±6 % of f, thousands of lines each on a fine axis: minutes per record).
fn test_modes(data: &TestData, idx: &[usize]) -> Vec<ColumnMode> {
    if data.record.is_some() {
        let (lines_hz, values) = data.whole_record();
        let values: Vec<Vec<_>> = idx.iter().map(|&c| values[c].clone()).collect();
        return identify_column(lines_hz, data.kind, &values).unwrap_or_default();
    }
    let values: Vec<Vec<_>> = idx.iter().map(|&c| data.values[c].clone()).collect();
    let receptance: Vec<Vec<_>> = values
        .iter()
        .map(|v| {
            v.iter()
                .zip(&data.omegas)
                .map(|(h, &w)| h / i_omega_power(w, data.kind.order()))
                .collect()
        })
        .collect();
    identify_modes(
        &data.lines_hz,
        &receptance,
        &indicator(&values),
        &IdentifyOptions::default(),
    )
}

impl ModalTable {
    /// Identify the test's modes on the `live` channels of `data` and take
    /// the modes of `mm` that may pair with them, each repeated mode as one
    /// ([`ModalModel::repeated_merged`]: its eigenspace's constants, the
    /// same in any basis of it, as the test sees it).
    pub fn new(data: &TestData, live: &[bool], mm: &ModalModel) -> ModalTable {
        let mm = &mm.repeated_merged();
        let idx: Vec<usize> = (0..data.channels.len()).filter(|&c| live[c]).collect();
        let modes = test_modes(data, &idx);
        let nc = data.channels.len();
        let test = modes
            .iter()
            .map(|m| {
                let mut full = vec![0.0; nc];
                for (&c, &x) in idx.iter().zip(&m.shape) {
                    full[c] = m.constant_sign * x;
                }
                full
            })
            .collect();
        let test_hz: Vec<f64> = modes.iter().map(|m| m.frequency_hz).collect();
        let (lo, hi) = test_hz
            .iter()
            .fold((f64::INFINITY, 0.0f64), |(l, h), f| (l.min(*f), h.max(*f)));
        let near: Vec<usize> = (0..mm.omega2.len())
            .filter(|&r| {
                let f = mm.frequencies_hz[r];
                f >= lo * (1.0 - WINDOW) && f <= hi * (1.0 + WINDOW)
            })
            .collect();
        ModalTable {
            test,
            test_hz,
            fe: near
                .iter()
                .map(|&r| {
                    (0..nc)
                        .map(|c| if live[c] { mm.coeff[c][r] } else { 0.0 })
                        .collect()
                })
                .collect(),
            fe_hz: near.iter().map(|&r| mm.frequencies_hz[r]).collect(),
            live: live.to_vec(),
        }
    }

    /// Number of channels (columns).
    pub fn channels(&self) -> usize {
        self.live.len()
    }

    /// Whether channel `c` takes part.
    pub fn is_live(&self, c: usize) -> bool {
        self.live[c]
    }

    /// The table with error `e` undone in the test's shapes.
    pub fn undo(&mut self, e: &super::DataError) {
        let c = e.channel;
        for s in &mut self.test {
            match e.kind {
                super::DataErrorKind::Dead { .. } => s[c] = 0.0,
                super::DataErrorKind::Reversed { .. } => s[c] = -s[c],
                super::DataErrorKind::Scale { factor, .. } => s[c] /= factor,
                // Each pair is listed for both channels: exchange once.
                super::DataErrorKind::Swapped { other } if c < other => s.swap(c, other),
                super::DataErrorKind::Swapped { .. } => {}
            }
        }
        if matches!(e.kind, super::DataErrorKind::Dead { .. }) {
            self.live[c] = false;
        }
    }

    /// The modes paired so that the channels under test (`judged`) cannot
    /// decide the pairing they are judged by: the pairing MAC is the best
    /// over the judged channels' possible errors (each sign, and for two
    /// channels their exchange; a scale cannot move a channel-normalised MAC).
    pub fn paired(&self, judged: &[usize]) -> Paired {
        let pairs = pair(&self.test, &self.test_hz, &self.fe, &self.fe_hz, judged);
        let mut out = Paired {
            test: Vec::new(),
            fe: Vec::new(),
            weight: Vec::new(),
            frequencies_hz: Vec::new(),
        };
        for (k, r) in pairs {
            let amax = self.fe[r].iter().fold(0.0f64, |a, x| a.max(x.abs()));
            let weight = self.fe[r]
                .iter()
                .zip(&self.test[k])
                .map(|(a, s)| {
                    let w = if amax > 0.0 { a.abs() / amax } else { 0.0 };
                    if w >= STRONG && *s != 0.0 && s.is_finite() {
                        w
                    } else {
                        0.0
                    }
                })
                .collect();
            out.test.push(self.test[k].clone());
            out.fe.push(self.fe[r].clone());
            out.weight.push(weight);
            out.frequencies_hz.push((self.test_hz[k], self.fe_hz[r]));
        }
        out
    }
}

impl Paired {
    /// Number of channels (columns).
    pub fn channels(&self) -> usize {
        self.weight.first().map_or(0, |w| w.len())
    }

    /// Summed weight of channel `c`'s entries.
    pub fn evidence(&self, c: usize) -> f64 {
        self.weight.iter().map(|w| w[c]).sum()
    }
}

/// Each channel divided by its RMS over the shapes.
fn channel_normalised(shapes: &[Vec<f64>]) -> Vec<Vec<f64>> {
    let nc = shapes.first().map_or(0, |s| s.len());
    let rms: Vec<f64> = (0..nc)
        .map(|c| (shapes.iter().map(|s| s[c] * s[c]).sum::<f64>() / shapes.len() as f64).sqrt())
        .collect();
    shapes
        .iter()
        .map(|s| {
            s.iter()
                .zip(&rms)
                .map(|(x, r)| if *r > 0.0 { x / r } else { 0.0 })
                .collect()
        })
        .collect()
}

fn mac(a: &[f64], b: &[f64]) -> f64 {
    let ab: f64 = a.iter().zip(b).map(|(x, y)| x * y).sum();
    let aa: f64 = a.iter().map(|x| x * x).sum();
    let bb: f64 = b.iter().map(|x| x * x).sum();
    if aa > 0.0 && bb > 0.0 {
        ab * ab / (aa * bb)
    } else {
        0.0
    }
}

/// The shape `t` as each error of the `judged` channels would leave it:
/// every sign combination, and for two channels also exchanged.
fn variants(t: &[f64], judged: &[usize]) -> Vec<Vec<f64>> {
    let mut out = vec![t.to_vec()];
    for &c in judged {
        let flipped: Vec<Vec<f64>> = out
            .iter()
            .map(|v| {
                let mut v = v.clone();
                v[c] = -v[c];
                v
            })
            .collect();
        out.extend(flipped);
    }
    if let [a, b] = judged {
        let swapped: Vec<Vec<f64>> = out
            .iter()
            .map(|v| {
                let mut v = v.clone();
                v.swap(*a, *b);
                v
            })
            .collect();
        out.extend(swapped);
    }
    out
}

/// Greedy pairs (test mode, FE mode) by channel-normalised MAC (the best
/// over the `judged` channels' errors) within the frequency window.
fn pair(
    test: &[Vec<f64>],
    test_hz: &[f64],
    fe: &[Vec<f64>],
    fe_hz: &[f64],
    judged: &[usize],
) -> Vec<(usize, usize)> {
    let tn = channel_normalised(test);
    let fnorm = channel_normalised(fe);
    let mut cand: Vec<(f64, usize, usize)> = Vec::new();
    for (k, t) in tn.iter().enumerate() {
        let forms = variants(t, judged);
        for (r, a) in fnorm.iter().enumerate() {
            let ratio = fe_hz[r] / test_hz[k];
            if !(ratio > 1.0 - WINDOW && ratio < 1.0 + WINDOW) {
                continue;
            }
            let m = forms.iter().map(|v| mac(v, a)).fold(0.0f64, f64::max);
            if m >= MIN_MAC {
                cand.push((m - 0.5 * ratio.ln().abs(), k, r));
            }
        }
    }
    cand.sort_by(|a, b| b.0.total_cmp(&a.0).then(a.1.cmp(&b.1)).then(a.2.cmp(&b.2)));
    let (mut used_k, mut used_r) = (vec![false; test.len()], vec![false; fe.len()]);
    let mut out = Vec::new();
    for (_, k, r) in cand {
        if !used_k[k] && !used_r[r] {
            used_k[k] = true;
            used_r[r] = true;
            out.push((k, r));
        }
    }
    out.sort();
    out
}
