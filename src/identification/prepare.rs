//! The FRFs of the band arranged for the fit: outputs × inputs per line,
//! with one weight per output.

use faer::c64;

use super::IdentifyError;
use crate::testdata::{Channel, MeasuredFrfs};

const TWO_PI: f64 = 2.0 * std::f64::consts::PI;

/// A measured degree of freedom: node and UFF direction code ±1..±6.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct Dof {
    pub node: i64,
    pub direction: i32,
}

/// The FRFs of the band as an n_o × n_i matrix per line.
#[derive(Clone, Debug)]
pub struct Prepared {
    /// Lines of the band (Hz), ascending, all > 0.
    pub frequencies_hz: Vec<f64>,
    /// The same as ω = 2πf (rad/s).
    pub omega: Vec<f64>,
    /// Index in the test of the band's first line.
    pub first_line: usize,
    /// Power n of iω that turns receptance into the test's kind (0, 1, 2).
    pub kind_order: i32,
    pub outputs: Vec<Dof>,
    pub inputs: Vec<Dof>,
    /// Test channel of FRF (o, i), at `o * inputs.len() + i`.
    pub channels: Vec<usize>,
    /// FRF (o, i) over the band, at `o * inputs.len() + i`.
    pub h: Vec<Vec<c64>>,
    /// 1 / RMS of output o's FRFs over the band (of all FRFs when
    /// `reciprocal`).
    pub weights: Vec<f64>,
    /// Test channels left out (a reference that not every output has).
    pub left_out: Vec<usize>,
    /// A roving-hammer row fitted as a column by reciprocity (H_ij = H_ji):
    /// the outputs are the test's references (hit points), the one input its
    /// response DOF.
    pub reciprocal: bool,
}

impl Prepared {
    pub fn n_outputs(&self) -> usize {
        self.outputs.len()
    }
    pub fn n_inputs(&self) -> usize {
        self.inputs.len()
    }
    pub fn n_lines(&self) -> usize {
        self.omega.len()
    }
}

/// The output and input DOFs of a channel: response and reference, or the
/// other way round when `reciprocal` (H_ij = H_ji of a linear structure).
fn roles(ch: &Channel, reciprocal: bool) -> (Dof, Dof) {
    let response = Dof {
        node: ch.response_node,
        direction: ch.response_direction,
    };
    let reference = Dof {
        node: ch.reference_node,
        direction: ch.reference_direction,
    };
    if reciprocal {
        (reference, response)
    } else {
        (response, reference)
    }
}

/// The distinct output and input DOFs of `test`'s channels, in order of
/// first appearance.
fn distinct_dofs(test: &MeasuredFrfs, reciprocal: bool) -> (Vec<Dof>, Vec<Dof>) {
    let mut outputs: Vec<Dof> = Vec::new();
    let mut inputs: Vec<Dof> = Vec::new();
    for ch in &test.channels {
        let (o, i) = roles(ch, reciprocal);
        if !outputs.contains(&o) {
            outputs.push(o);
        }
        if !inputs.contains(&i) {
            inputs.push(i);
        }
    }
    (outputs, inputs)
}

/// A roving-hammer test: one response DOF and several references (a row of
/// the FRF matrix). It is fitted as a column by reciprocity: the hit points
/// become the outputs, one reference instead of many (the poly-reference
/// fit's cost grows with the square of the references).
fn is_row(test: &MeasuredFrfs) -> bool {
    let (responses, references) = distinct_dofs(test, false);
    responses.len() == 1 && references.len() > 1
}

/// The references to fit together: all of them when every response is
/// measured for each, else the one with most channels.
fn chosen_inputs(test: &MeasuredFrfs, reciprocal: bool) -> Vec<Dof> {
    let (outputs, inputs) = distinct_dofs(test, reciprocal);
    if test.channels.len() == inputs.len() * outputs.len() || inputs.len() <= 1 {
        return inputs;
    }
    let count = |d: &Dof| {
        test.channels
            .iter()
            .filter(|c| roles(c, reciprocal).1 == *d)
            .count()
    };
    let best = inputs
        .iter()
        .copied()
        .max_by_key(|d| (count(d), std::cmp::Reverse(*d)))
        .expect("at least one input");
    vec![best]
}

/// Arranges `test` for the fit over `band_hz` (all lines when `None`).
pub fn prepare(
    test: &MeasuredFrfs,
    band_hz: Option<(f64, f64)>,
) -> Result<Prepared, IdentifyError> {
    if test.channels.is_empty() {
        return Err(IdentifyError::NotEnoughData("the test has no FRF".into()));
    }
    let (f0, f1) = band_hz.unwrap_or((f64::MIN_POSITIVE, f64::INFINITY));
    if !(f0 < f1) {
        return Err(IdentifyError::BadOption(format!(
            "band {f0}:{f1} Hz is empty"
        )));
    }
    let lines: Vec<usize> = (0..test.frequencies_hz.len())
        .filter(|&k| {
            let f = test.frequencies_hz[k];
            f > 0.0 && f >= f0 && f <= f1
        })
        .collect();
    if lines.len() < 8 {
        return Err(IdentifyError::NotEnoughData(format!(
            "{} line(s) above 0 Hz in the band; the fit needs at least 8",
            lines.len()
        )));
    }
    let reciprocal = is_row(test);
    let inputs = chosen_inputs(test, reciprocal);
    let mut outputs: Vec<Dof> = Vec::new();
    let mut left_out = Vec::new();
    let mut by_dof: Vec<(Dof, Dof, usize)> = Vec::new();
    for (c, ch) in test.channels.iter().enumerate() {
        let (o, i) = roles(ch, reciprocal);
        if !inputs.contains(&i) || by_dof.iter().any(|(oo, ii, _)| *oo == o && *ii == i) {
            left_out.push(c);
            continue;
        }
        if !outputs.contains(&o) {
            outputs.push(o);
        }
        by_dof.push((o, i, c));
    }
    let m = inputs.len();
    let mut channels = vec![usize::MAX; outputs.len() * m];
    for (o, i, c) in by_dof {
        let oi = outputs.iter().position(|d| *d == o).unwrap();
        let ii = inputs.iter().position(|d| *d == i).unwrap();
        channels[oi * m + ii] = c;
    }
    let (lo, hi) = (lines[0], lines[lines.len() - 1]);
    if lines.len() != hi - lo + 1 {
        return Err(IdentifyError::NotEnoughData(
            "band lines are not contiguous".into(),
        ));
    }
    let h: Vec<Vec<c64>> = channels
        .iter()
        .map(|&c| test.channels[c].values[lo..=hi].to_vec())
        .collect();
    let weights = output_weights(&h, m, reciprocal);
    if weights.iter().all(|&w| w == 0.0) {
        return Err(IdentifyError::NotEnoughData(
            "every FRF is zero in the band".into(),
        ));
    }
    let frequencies_hz = test.frequencies_hz[lo..=hi].to_vec();
    Ok(Prepared {
        omega: frequencies_hz.iter().map(|f| TWO_PI * f).collect(),
        frequencies_hz,
        first_line: lo,
        kind_order: test.kind.order(),
        outputs,
        inputs,
        channels,
        h,
        weights,
        left_out,
        reciprocal,
    })
}

/// 1 / RMS of each output's FRFs (`h` at o·m + i), so that every sensor's
/// noise weighs alike; one common weight, 1 / RMS of all FRFs, for a
/// reciprocal row: its FRFs all come from one sensor, with one noise level,
/// and a hit point that only shows noise must not weigh like the others.
fn output_weights(h: &[Vec<c64>], m: usize, reciprocal: bool) -> Vec<f64> {
    let inverse_rms = |frfs: &[Vec<c64>]| {
        let (ss, n) = frfs.iter().fold((0.0, 0usize), |(s, n), v| {
            (s + v.iter().map(|x| x.norm_sqr()).sum::<f64>(), n + v.len())
        });
        let rms = (ss / n.max(1) as f64).sqrt();
        if rms > 0.0 && rms.is_finite() {
            1.0 / rms
        } else {
            0.0
        }
    };
    let outputs = h.len() / m.max(1);
    if reciprocal {
        vec![inverse_rms(h); outputs]
    } else {
        (0..outputs)
            .map(|o| inverse_rms(&h[o * m..(o + 1) * m]))
            .collect()
    }
}

/// The weighted sum of |H| over every FRF, per line: the mode indicator the
/// stabilisation chart is drawn over.
pub fn summed_magnitude(data: &Prepared) -> Vec<f64> {
    let m = data.n_inputs();
    let mut s = vec![0.0; data.n_lines()];
    for (j, h) in data.h.iter().enumerate() {
        let w = data.weights[j / m];
        for (sk, v) in s.iter_mut().zip(h) {
            // |v| without libm's hypot (no overflow at FRF magnitudes; 20×
            // cheaper once faer's kernels leave the vector registers wide).
            *sk += w * v.norm_sqr().sqrt();
        }
    }
    s
}

/// Highest model order by default: two poles per peak of the summed FRF
/// (a peak may hide two modes) twice over, plus 16 for the residual terms,
/// at least 64, per reference, between 24 and 100. At least 64 because the
/// computational poles that fit a band's mass and stiffness lines take
/// their share of the order first: in the benchmark (scripts/
/// bench_identify.sh) modes below 30 Hz of a 250 Hz band stabilised only
/// from order 25–30, too late to be kept at a maximum of 32, and all were
/// found at 64. A peak is the largest value within ±w
/// lines standing 25 % above the smallest within ±5w, by at least a fifth
/// of the median (noise ripples in anti-resonances do not); w = 3 lines, or
/// 1/300 of the band on long records.
pub fn default_max_order(data: &Prepared) -> usize {
    let s = summed_magnitude(data);
    let n = s.len();
    let mut sorted = s.clone();
    sorted.sort_by(f64::total_cmp);
    let median = sorted[n / 2];
    let w = (n / 300).max(3);
    let window = |k: usize, w: usize| &s[k.saturating_sub(w)..(k + w + 1).min(n)];
    let near = window_max(&s, w);
    let peaks = (0..n)
        .filter(|&k| {
            // The wide window only at the few local maxima (a long record
            // spent a tenth of its identification here otherwise).
            s[k] >= near[k] && {
                let low = window(k, 5 * w)
                    .iter()
                    .fold(f64::INFINITY, |a, &b| a.min(b));
                s[k] > 1.25 * low && s[k] - low > 0.2 * median
            }
        })
        .count();
    let m = data.n_inputs().max(1);
    ((4 * peaks + 16).max(64) / m).clamp(24, 100)
}

/// max(s[k−w ..= k+w]) (clipped to the ends) at every k, in O(n) by a
/// monotonic queue of candidate indices (values decreasing from the front).
pub fn window_max(s: &[f64], w: usize) -> Vec<f64> {
    let n = s.len();
    let mut queue = std::collections::VecDeque::with_capacity(2 * w + 1);
    let mut out = Vec::with_capacity(n);
    let mut next = 0;
    for k in 0..n {
        while next < n && next <= k + w {
            while queue.back().is_some_and(|&b: &usize| s[b] <= s[next]) {
                queue.pop_back();
            }
            queue.push_back(next);
            next += 1;
        }
        while queue.front().is_some_and(|&f| f + w < k) {
            queue.pop_front();
        }
        out.push(queue.front().map_or(f64::NEG_INFINITY, |&f| s[f]));
    }
    out
}
