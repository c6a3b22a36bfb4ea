//! The lines of a long record that carry information.
//!
//! A measured record of tens of thousands of lines (a fine resolution over a
//! wide band, damping near 10⁻⁴) has a few hundred lines where the
//! parameters and the damping show: around the resonances. The rest is
//! background whose shape a sparse, even subset describes as well. A record
//! of more than [`LINE_BUDGET`] lines is fitted on:
//!
//! - around each of the [`MAX_PEAKS`] most prominent resonances f_r with
//!   half-power half-width b_r = ζ_r f_r (one line where the peak is
//!   narrower than a line): every line within ±[`CORE`] b_r (at least ±3
//!   lines), then lines at distances growing by [`SKIRT_RATIO`] out to
//!   ±[`SKIRT`] b_r, so that the flanks, where a shifted model resonance
//!   shows, keep the peak's half-power resolution near it and a
//!   logarithmic one further away;
//! - every k-th line of the record, [`BACKGROUND`] in all.
//!
//! Each kept line keeps its own weight (its noise standard deviation is
//! estimated on the whole record), so the fit is a weighted least squares
//! on a subset of the same points, not a resampled record.

use crate::updating::frequencies::Resonance;

/// Records with more lines than this are thinned.
pub const LINE_BUDGET: usize = 4096;
/// Lines of the even background subset.
pub const BACKGROUND: usize = 1024;
/// Resonances (by prominence) whose neighbourhood is kept.
pub const MAX_PEAKS: usize = 200;
/// Every line within this many half-power half-widths of a peak is kept.
pub const CORE: f64 = 4.0;
/// Lines out to this many half-widths are kept at growing distances.
pub const SKIRT: f64 = 60.0;
/// Ratio of successive distances in the skirt.
pub const SKIRT_RATIO: f64 = 1.3;

/// The indices (ascending) of the lines of `lines_hz` to fit, given the
/// resonances picked on the whole record; all lines when there are at most
/// [`LINE_BUDGET`].
pub fn informative_lines(lines_hz: &[f64], resonances: &[Resonance]) -> Vec<usize> {
    let n = lines_hz.len();
    if n <= LINE_BUDGET {
        return (0..n).collect();
    }
    let mut keep = vec![false; n];
    let stride = n.div_ceil(BACKGROUND);
    for i in (0..n).step_by(stride) {
        keep[i] = true;
    }
    keep[n - 1] = true;
    let mut peaks: Vec<&Resonance> = resonances.iter().filter(|r| r.line < n).collect();
    peaks.sort_by(|a, b| {
        b.prominence
            .total_cmp(&a.prominence)
            .then(a.line.cmp(&b.line))
    });
    for r in peaks.into_iter().take(MAX_PEAKS) {
        for k in peak_offsets(lines_hz, r) {
            for i in [r.line.checked_sub(k), Some(r.line + k)]
                .into_iter()
                .flatten()
            {
                if i < n {
                    keep[i] = true;
                }
            }
        }
    }
    (0..n).filter(|&i| keep[i]).collect()
}

/// Distances in lines (0 first) kept on each side of resonance `r`.
fn peak_offsets(lines_hz: &[f64], r: &Resonance) -> Vec<usize> {
    let i = r.line;
    let df = if i + 1 < lines_hz.len() {
        lines_hz[i + 1] - lines_hz[i]
    } else {
        lines_hz[i] - lines_hz[i.saturating_sub(1)]
    };
    let b = r.damping_ratio.unwrap_or(0.0) * r.frequency_hz;
    // The half-width in lines, at least one line.
    let width = if df > 0.0 && b.is_finite() {
        (b / df).max(1.0)
    } else {
        1.0
    };
    let core = ((CORE * width).ceil() as usize).max(3);
    let outer = (SKIRT * width).ceil() as usize;
    let mut out: Vec<usize> = (0..=core).collect();
    let mut d = core as f64;
    loop {
        d *= SKIRT_RATIO;
        let k = d.round() as usize;
        if k > outer {
            break;
        }
        out.push(k);
    }
    out
}
