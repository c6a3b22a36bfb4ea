//! The measured FRFs as the diagnosis uses them: one excitation, channels
//! on test node/direction pairs, a noise estimate per channel and the lines
//! that stand above the noise floor.

use std::sync::Arc;

use faer::c64;

use super::FitError as DiagnoseError;
use crate::testdata::{FrfKind, MeasuredFrfs};
use crate::updating::frequencies::{indicator, pick_peaks, PeakOptions, Resonance};

/// One measured channel (test node ids, UFF direction codes).
#[derive(Clone, Debug)]
pub struct ChannelInfo {
    pub node: u32,
    pub direction: i32,
    pub label: String,
}

/// Test data prepared for fitting.
#[derive(Clone, Debug)]
pub struct TestData {
    /// Frequency lines used (Hz, all > 0) and ω = 2πf (rad/s).
    pub lines_hz: Vec<f64>,
    pub omegas: Vec<f64>,
    /// The measured kind (its `order()`: the power of iω that turns
    /// receptance into it).
    pub kind: FrfKind,
    pub channels: Vec<ChannelInfo>,
    /// Measured FRF `values[channel][line]`, measured kind, SI units.
    pub values: Vec<Vec<c64>>,
    /// Noise standard deviation σ_c of each channel (E|n|² = σ_c²), same units.
    pub sigma: Vec<f64>,
    /// Per point (channel, line): 1/√(s² + f²) with s = σ_c/(√2|H|) the noise
    /// standard deviation of ln|H| (and of arg H), f the model floor; 0 where
    /// |H| < 3σ_c (below the noise floor).
    pub weight: Vec<Vec<f64>>,
    /// Expected squared weighted residual of each point from noise alone: s²/(s² + f²).
    pub noise_r2: Vec<Vec<f64>>,
    /// Excitation (test node, direction code).
    pub input: (u32, i32),
    /// Resonances picked on the measured FRFs (half-power damping where found).
    pub resonances: Vec<Resonance>,
    /// The sensors sit at the excitation's node, not at the channels' (a
    /// roving-hammer row used as a column by reciprocity: the channels are
    /// the hammer's points, the one accelerometer is at `input`).
    pub sensor_at_input: bool,
    /// The whole record when `lines_hz` holds only its informative lines
    /// (more than [`super::lines::LINE_BUDGET`] lines): the identification
    /// needs its even axis.
    pub record: Option<Arc<Record>>,
}

/// A whole measured record: its lines (Hz, ascending, > 0) and values
/// (`[channel][line]`, measured kind, SI units), channels as in [`TestData`].
#[derive(Clone, Debug)]
pub struct Record {
    pub lines_hz: Vec<f64>,
    pub values: Vec<Vec<c64>>,
}

/// Model tolerance floor of the relative error (1 %): keeps the sharpest
/// peak lines from dominating the fit.
pub const FLOOR: f64 = 0.01;

impl TestData {
    /// Keep the channels driven at the most common reference; estimate noise
    /// from second differences along frequency: Δ²n has variance 6σ², and the
    /// median of a Rayleigh magnitude is σ_Δ√(ln 2), so σ = med|Δ²H| / √(6 ln 2).
    pub fn new(test: &MeasuredFrfs) -> Result<TestData, DiagnoseError> {
        let mut refs: Vec<((i64, i32), usize)> = Vec::new();
        for ch in &test.channels {
            let key = (ch.reference_node, ch.reference_direction);
            match refs.iter_mut().find(|(k, _)| *k == key) {
                Some(e) => e.1 += 1,
                None => refs.push((key, 1)),
            }
        }
        let Some(&((rn, rd), _)) = refs.iter().max_by_key(|(_, n)| *n) else {
            return Err(DiagnoseError::Data("the test data hold no FRF".into()));
        };
        let input = (
            u32::try_from(rn).map_err(|_| DiagnoseError::Data(format!("reference node {rn}")))?,
            rd,
        );
        let keep: Vec<usize> = (0..test.frequencies_hz.len())
            .filter(|&i| test.frequencies_hz[i] > 0.0 && test.frequencies_hz[i].is_finite())
            .collect();
        if keep.len() < 8 {
            return Err(DiagnoseError::Data(
                "the test has fewer than 8 frequency lines above 0 Hz".into(),
            ));
        }
        let lines_hz: Vec<f64> = keep.iter().map(|&i| test.frequencies_hz[i]).collect();
        let omegas: Vec<f64> = lines_hz
            .iter()
            .map(|f| 2.0 * std::f64::consts::PI * f)
            .collect();
        let mut channels = Vec::new();
        let mut values = Vec::new();
        for ch in &test.channels {
            if (ch.reference_node, ch.reference_direction) != (rn, rd) {
                continue;
            }
            if ch.values.len() != test.frequencies_hz.len() {
                return Err(DiagnoseError::Data(format!(
                    "channel {} has {} values for {} lines",
                    ch.label(),
                    ch.values.len(),
                    test.frequencies_hz.len()
                )));
            }
            let Ok(node) = u32::try_from(ch.response_node) else {
                continue;
            };
            let v: Vec<c64> = keep.iter().map(|&i| ch.values[i]).collect();
            if v.iter().any(|z| !(z.re.is_finite() && z.im.is_finite())) {
                return Err(DiagnoseError::Data(format!(
                    "channel {} holds non-finite values",
                    ch.label()
                )));
            }
            channels.push(ChannelInfo {
                node,
                direction: ch.response_direction,
                label: crate::testdata::dof_label(ch.response_node, ch.response_direction),
            });
            values.push(v);
        }
        // Noise and resonances on the whole record (its even axis); the
        // fit on its informative lines.
        let sigma = acquisition_floor(values.iter().map(|v| noise_sigma(v)).collect(), &values);
        let mut peaks = pick_peaks(
            &lines_hz,
            &indicator(&values),
            &PeakOptions {
                min_prominence: 2.0,
            },
        );
        let keep = super::lines::informative_lines(&lines_hz, &peaks);
        let (lines_hz, omegas, values, record) = if keep.len() < lines_hz.len() {
            let pick = |v: &[f64]| keep.iter().map(|&i| v[i]).collect::<Vec<f64>>();
            let thin: Vec<Vec<c64>> = values
                .iter()
                .map(|v| keep.iter().map(|&i| v[i]).collect())
                .collect();
            for r in &mut peaks {
                r.line = keep.partition_point(|&i| i < r.line);
            }
            let record = Record { lines_hz, values };
            (
                pick(&record.lines_hz),
                pick(&omegas),
                thin,
                Some(Arc::new(record)),
            )
        } else {
            (lines_hz, omegas, values, None)
        };
        let (weight, noise_r2) = weights(&values, &sigma);
        Ok(TestData {
            lines_hz,
            omegas,
            kind: test.kind,
            channels,
            values,
            sigma,
            weight,
            noise_r2,
            input,
            resonances: peaks,
            sensor_at_input: false,
            record,
        })
    }

    /// The lines and values of the whole record (the identification's
    /// even axis): the record kept beside thinned lines, else these.
    pub fn whole_record(&self) -> (&[f64], &[Vec<c64>]) {
        match &self.record {
            Some(r) => (&r.lines_hz, &r.values),
            None => (&self.lines_hz, &self.values),
        }
    }

    /// Test nodes that carry a sensor: the channels' nodes, or the
    /// excitation's when the test was a roving hammer.
    pub fn sensor_nodes(&self) -> Vec<u32> {
        let mut nodes: Vec<u32> = if self.sensor_at_input {
            vec![self.input.0]
        } else {
            self.channels.iter().map(|c| c.node).collect()
        };
        nodes.sort_unstable();
        nodes.dedup();
        nodes
    }

    /// The band's first and last line ω (rad/s); (1, 1) without lines.
    pub fn band(&self) -> (f64, f64) {
        let w_lo = self.omegas.first().copied().unwrap_or(1.0);
        let w_hi = self.omegas.last().copied().unwrap_or(1.0);
        (w_lo, w_hi)
    }

    /// Median half-power damping ratio of the measured resonances (default 1 %).
    pub fn half_power_zeta(&self) -> f64 {
        let mut z: Vec<f64> = self
            .resonances
            .iter()
            .filter_map(|r| r.damping_ratio)
            .filter(|z| z.is_finite() && *z > 0.0)
            .collect();
        if z.is_empty() {
            return 0.01;
        }
        z.sort_by(|a, b| a.total_cmp(b));
        z[z.len() / 2].clamp(1e-4, 0.2)
    }

    /// Weights from the model FRFs `model` (`[channel][line]`, measured
    /// kind) instead of the measured ones: |H| in s = σ_c/(√2|H|) and in the
    /// noise-floor test is then free of the noise, so that neither the
    /// weight nor the choice of lines correlates with the residual it
    /// multiplies (a weight from the noisy |H̃| does: w·ln|H/H̃| then has a
    /// mean of order s, and Σ over many lines biases the estimate by
    /// several of its standard deviations).
    /// A point whose measured value is exactly zero (a channel the
    /// excitation does not reach, simulated without noise) stays out: its
    /// log residual is undefined.
    pub fn reweight(&mut self, model: &[Vec<c64>]) {
        let (mut w, mut n) = weights(model, &self.sigma);
        for (c, v) in self.values.iter().enumerate() {
            for (l, z) in v.iter().enumerate() {
                if z.norm() == 0.0 {
                    w[c][l] = 0.0;
                    n[c][l] = 0.0;
                }
            }
        }
        self.weight = w;
        self.noise_r2 = n;
    }

    /// Labels of the channels with no point above the noise floor (every
    /// weight 0): they take no part in a fit.
    pub fn silent_channels(&self) -> Vec<String> {
        self.channels
            .iter()
            .zip(&self.weight)
            .filter(|(_, w)| w.iter().all(|&v| v == 0.0))
            .map(|(c, _)| c.label.clone())
            .collect()
    }

    /// Drop channels (by index) that the model cannot place.
    pub fn retain_channels(&mut self, keep: &[bool]) {
        retain_flagged(&mut self.channels, keep);
        retain_flagged(&mut self.values, keep);
        retain_flagged(&mut self.sigma, keep);
        if let Some(r) = &mut self.record {
            retain_flagged(&mut Arc::make_mut(r).values, keep);
        }
        let (w, n) = weights(&self.values, &self.sigma);
        self.weight = w;
        self.noise_r2 = n;
    }
}

/// Keep the items of `v` whose flag in `keep` is set.
fn retain_flagged<T>(v: &mut Vec<T>, keep: &[bool]) {
    let mut flags = keep.iter();
    v.retain(|_| flags.next().copied().unwrap_or(false));
}

/// The dynamic range of an acquisition: no channel's noise σ_c is taken
/// below this fraction of the largest |H| of any channel (180 dB; 24-bit
/// converters reach about 140 dB). A channel the excitation does not reach
/// (a straight beam's out-of-plane DOFs simulated to rounding, 1e-26 of the
/// others) then lies below the noise floor and carries no weight, instead
/// of its rounding dominating the fit (update benchmark seed 2, case 035:
/// 16 of 24 channels so, fit at 3·10⁶× the noise level).
const DYNAMIC_RANGE: f64 = 1e-9;

/// σ_c raised to [`DYNAMIC_RANGE`] times the largest |H| of all channels.
fn acquisition_floor(sigma: Vec<f64>, values: &[Vec<c64>]) -> Vec<f64> {
    let peak = values.iter().flatten().fold(0.0f64, |a, z| {
        if z.norm().is_finite() {
            a.max(z.norm())
        } else {
            a
        }
    });
    let floor = DYNAMIC_RANGE * peak;
    sigma.into_iter().map(|s| s.max(floor)).collect()
}

fn noise_sigma(v: &[c64]) -> f64 {
    let mut d: Vec<f64> = v
        .windows(3)
        .map(|w| (w[2] - w[1] * 2.0 + w[0]).norm())
        .collect();
    let peak = v.iter().fold(0.0f64, |a, z| a.max(z.norm()));
    if d.is_empty() {
        return 1e-6 * peak;
    }
    d.sort_by(|a, b| a.total_cmp(b));
    let med = d[d.len() / 2];
    (med / (6.0 * std::f64::consts::LN_2).sqrt()).max(1e-9 * peak)
}

type Grid = Vec<Vec<f64>>;

fn weights(values: &[Vec<c64>], sigma: &[f64]) -> (Grid, Grid) {
    let mut w = Vec::with_capacity(values.len());
    let mut n = Vec::with_capacity(values.len());
    for (v, &s) in values.iter().zip(sigma) {
        let mut wc = Vec::with_capacity(v.len());
        let mut nc = Vec::with_capacity(v.len());
        for z in v {
            let a = z.norm();
            if a < 3.0 * s || a == 0.0 {
                wc.push(0.0);
                nc.push(0.0);
            } else {
                let sr = s / (std::f64::consts::SQRT_2 * a);
                let d = sr * sr + FLOOR * FLOOR;
                wc.push(1.0 / d.sqrt());
                nc.push(sr * sr / d);
            }
        }
        w.push(wc);
        n.push(nc);
    }
    (w, n)
}
