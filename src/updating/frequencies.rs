//! Measured resonances by peak picking and the choice of updating frequencies
//! around them (§3.5, Eq. 42).
//!
//! Peak indicator: per frequency line, I(f) = Σ_channels |Y_c(f)| / rms_c, the
//! sum over channels of the mobility magnitude (a viscous SDOF mobility peaks
//! exactly at ω_r), each channel scaled by its RMS over the band so that no
//! single channel dominates. A line is a resonance if it is a local maximum
//! whose prominence (peak ÷ the higher of the two valley minima separating it
//! from higher peaks or the band edges) is at least `min_prominence`. The peak
//! frequency is refined by a parabola through ln I at the three lines around
//! the maximum, and the half-power points (I = I_peak/√2, linear interpolation
//! between lines) give ξ = (f₂ − f₁)/(2 f_r).
//!
//! Updating frequencies (Eq. 42): ω = (1 ± cξ) ω̄_r for the first R resonances,
//! `offset` = cξ (the paper uses 5–10 %). A candidate is skipped when it falls
//! within the half-power band of another resonance (half-width max(ξ_s f_s,
//! 1.5 line spacings)) or outside the measured band. Each frequency is then
//! moved to the nearest measured line, so the measured FRF is used as recorded
//! (no interpolation) and the FE FRF is computed at exactly that line.

use faer::c64;

/// One measured resonance.
#[derive(Clone, Debug, PartialEq)]
pub struct Resonance {
    /// Refined resonance frequency f_r (Hz).
    pub frequency_hz: f64,
    /// The measured line nearest the peak.
    pub line: usize,
    /// Half-power damping ratio ξ, if both half-power points were found.
    pub damping_ratio: Option<f64>,
    /// Prominence of the peak (ratio ≥ 1).
    pub prominence: f64,
}

/// Peak-picking settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PeakOptions {
    /// Minimum peak-to-valley ratio of the indicator.
    pub min_prominence: f64,
}

impl Default for PeakOptions {
    fn default() -> Self {
        PeakOptions {
            min_prominence: 2.0,
        }
    }
}

/// The resonance indicator I(f) (see the module docs) from complex FRFs of any
/// kind given per channel; lines at 0 Hz are given 0.
pub fn indicator(channels: &[Vec<c64>]) -> Vec<f64> {
    let n = channels.iter().map(|c| c.len()).max().unwrap_or(0);
    let mut ind = vec![0.0; n];
    for ch in channels {
        let rms = (ch.iter().map(|v| v.norm_sqr()).sum::<f64>() / ch.len().max(1) as f64).sqrt();
        if !(rms > 0.0 && rms.is_finite()) {
            continue;
        }
        for (i, v) in ch.iter().enumerate() {
            let a = v.norm() / rms;
            if a.is_finite() {
                ind[i] += a;
            }
        }
    }
    ind
}

/// Resonances of `indicator` on the frequency `lines_hz`, ascending.
pub fn pick_peaks(lines_hz: &[f64], indicator: &[f64], opts: &PeakOptions) -> Vec<Resonance> {
    let n = lines_hz.len().min(indicator.len());
    let y = &indicator[..n];
    let mut out = Vec::new();
    if n < 3 {
        return out;
    }
    for i in 1..n - 1 {
        if !(y[i] > y[i - 1] && y[i] >= y[i + 1]) || lines_hz[i] <= 0.0 || !(y[i] > 0.0) {
            continue;
        }
        // Valley to the left: min over (last higher point, i).
        let mut left_min = y[i];
        let mut j = i;
        while j > 0 {
            j -= 1;
            if y[j] > y[i] {
                break;
            }
            left_min = left_min.min(y[j]);
        }
        let mut right_min = y[i];
        let mut j = i;
        while j + 1 < n {
            j += 1;
            if y[j] > y[i] {
                break;
            }
            right_min = right_min.min(y[j]);
        }
        let base = left_min.max(right_min);
        let prominence = if base > 0.0 {
            y[i] / base
        } else {
            f64::INFINITY
        };
        if prominence < opts.min_prominence {
            continue;
        }
        // Parabolic refinement on ln I.
        let (l, c, r) = (
            y[i - 1].max(1e-300).ln(),
            y[i].ln(),
            y[i + 1].max(1e-300).ln(),
        );
        let den = l - 2.0 * c + r;
        let (delta, peak_ln) = if den < 0.0 {
            let d = (0.5 * (l - r) / den).clamp(-0.5, 0.5);
            (d, c - 0.25 * (l - r) * d)
        } else {
            (0.0, c)
        };
        let step = if delta >= 0.0 {
            lines_hz[i + 1] - lines_hz[i]
        } else {
            lines_hz[i] - lines_hz[i - 1]
        };
        let f_r = lines_hz[i] + delta * step;
        let half = peak_ln.exp() / std::f64::consts::SQRT_2;
        let f1 = crossing(lines_hz, y, i, half, -1);
        let f2 = crossing(lines_hz, y, i, half, 1);
        let damping_ratio = match (f1, f2) {
            (Some(a), Some(b)) if b > a && f_r > 0.0 => Some((b - a) / (2.0 * f_r)),
            _ => None,
        };
        out.push(Resonance {
            frequency_hz: f_r,
            line: i,
            damping_ratio,
            prominence,
        });
    }
    out
}

/// Where the indicator falls to `level` walking from the peak `i` in direction
/// `dir`, interpolated linearly; `None` if it rises again (a valley) first or
/// the band ends.
fn crossing(x: &[f64], y: &[f64], i: usize, level: f64, dir: isize) -> Option<f64> {
    let mut j = i as isize;
    loop {
        let k = j + dir;
        if k < 0 || k as usize >= y.len() {
            return None;
        }
        let (yj, yk) = (y[j as usize], y[k as usize]);
        if yk > yj && j != i as isize {
            return None;
        }
        if yk <= level {
            let t = if yj != yk {
                (yj - level) / (yj - yk)
            } else {
                0.0
            };
            return Some(x[j as usize] + t * (x[k as usize] - x[j as usize]));
        }
        j = k;
    }
}

/// Where an updating frequency comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FrequencySource {
    /// Below (−1) or above (+1) test resonance `resonance` (Eq. 42).
    Resonance { resonance: usize, side: i8 },
    /// Given explicitly (Table 3's "chosen updating frequencies").
    Explicit,
}

/// One updating frequency, moved onto a measured line.
#[derive(Clone, Debug, PartialEq)]
pub struct UpdatingFrequency {
    /// The frequency asked for (Hz).
    pub requested_hz: f64,
    /// The measured line used (Hz): the updating frequency itself.
    pub hz: f64,
    pub line: usize,
    pub source: FrequencySource,
}

/// A candidate frequency that was not used, and why.
#[derive(Clone, Debug, PartialEq)]
pub struct SkippedFrequency {
    pub requested_hz: f64,
    pub reason: String,
}

/// The updating frequencies ω_i, i = 1..N_fr, ascending.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct UpdatingFrequencies {
    pub frequencies: Vec<UpdatingFrequency>,
    pub skipped: Vec<SkippedFrequency>,
}

impl UpdatingFrequencies {
    /// Eq. 42 around the first `count` resonances, `offset` = cξ.
    pub fn around_resonances(
        resonances: &[Resonance],
        count: usize,
        offset: f64,
        lines_hz: &[f64],
    ) -> Self {
        let spacing = line_spacing(lines_hz);
        let mut out = UpdatingFrequencies::default();
        for (r, res) in resonances.iter().take(count).enumerate() {
            for side in [-1i8, 1] {
                let f = res.frequency_hz * (1.0 + f64::from(side) * offset);
                let clash = resonances.iter().enumerate().find(|&(s, other)| {
                    s != r && {
                        let hb = (other.damping_ratio.unwrap_or(0.0) * other.frequency_hz)
                            .max(1.5 * spacing);
                        (f - other.frequency_hz).abs() <= hb
                    }
                });
                if let Some((s, other)) = clash {
                    out.skipped.push(SkippedFrequency {
                        requested_hz: f,
                        reason: format!(
                            "within the half-power band of resonance {} ({:.4} Hz)",
                            s + 1,
                            other.frequency_hz
                        ),
                    });
                    continue;
                }
                out.push(
                    f,
                    lines_hz,
                    FrequencySource::Resonance { resonance: r, side },
                );
            }
        }
        out.finish();
        out
    }

    /// Explicit frequencies (Hz), each moved to the nearest line.
    pub fn explicit(freqs_hz: &[f64], lines_hz: &[f64]) -> Self {
        let mut out = UpdatingFrequencies::default();
        for &f in freqs_hz {
            out.push(f, lines_hz, FrequencySource::Explicit);
        }
        out.finish();
        out
    }

    fn push(&mut self, f: f64, lines_hz: &[f64], source: FrequencySource) {
        let (Some(&lo), Some(&hi)) = (lines_hz.first(), lines_hz.last()) else {
            self.skipped.push(SkippedFrequency {
                requested_hz: f,
                reason: "no measured lines".into(),
            });
            return;
        };
        let spacing = line_spacing(lines_hz);
        if !f.is_finite() || f <= 0.0 || f < lo - 0.5 * spacing || f > hi + 0.5 * spacing {
            self.skipped.push(SkippedFrequency {
                requested_hz: f,
                reason: format!("outside the measured band {lo}–{hi} Hz"),
            });
            return;
        }
        let line = nearest_line(lines_hz, f);
        if lines_hz[line] <= 0.0 {
            self.skipped.push(SkippedFrequency {
                requested_hz: f,
                reason: "nearest line is 0 Hz".into(),
            });
            return;
        }
        if let Some(prev) = self.frequencies.iter().find(|u| u.line == line) {
            let reason = format!("same measured line as {:.4} Hz", prev.requested_hz);
            self.skipped.push(SkippedFrequency {
                requested_hz: f,
                reason,
            });
            return;
        }
        self.frequencies.push(UpdatingFrequency {
            requested_hz: f,
            hz: lines_hz[line],
            line,
            source,
        });
    }

    fn finish(&mut self) {
        self.frequencies.sort_by_key(|a| a.line);
    }

    pub fn len(&self) -> usize {
        self.frequencies.len()
    }

    pub fn is_empty(&self) -> bool {
        self.frequencies.is_empty()
    }

    /// The updating frequencies (Hz).
    pub fn hz(&self) -> Vec<f64> {
        self.frequencies.iter().map(|u| u.hz).collect()
    }
}

/// Index of the line nearest to `f` (lines ascending).
pub fn nearest_line(lines_hz: &[f64], f: f64) -> usize {
    let i = lines_hz.partition_point(|&x| x < f);
    if i == 0 {
        0
    } else if i >= lines_hz.len() {
        lines_hz.len() - 1
    } else if (f - lines_hz[i - 1]) <= (lines_hz[i] - f) {
        i - 1
    } else {
        i
    }
}

/// Median spacing of the lines (Hz).
pub(crate) fn line_spacing(lines_hz: &[f64]) -> f64 {
    let mut d: Vec<f64> = lines_hz.windows(2).map(|w| w[1] - w[0]).collect();
    if d.is_empty() {
        return 0.0;
    }
    d.sort_by(f64::total_cmp);
    d[d.len() / 2]
}
