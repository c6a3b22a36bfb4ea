//! The measurement that tells two explanations apart (item 2b of the
//! diagnosis: "X and Y explain the data equally well with these sensors").
//!
//! Both explained models are solved with the test's excitation and lines at
//! every translational DOF of the structure that was not measured. Their
//! predicted magnitudes are compared line by line,
//!
//!   d(j, f) = 20 log₁₀ |H_X(j, f)| / |H_Y(j, f)|   (dB),
//!
//! smoothed over [`SMOOTH_LINES`] lines (one line at an antiresonance is no
//! measurement plan) and only where both predictions stand above the test's
//! noise floor ([`FLOOR_SIGMAS`] × the median channel noise σ). The DOF j
//! with the largest |d| is where a sensor (or, by reciprocity, a hammer
//! point) tells X from Y; the band is the run of lines around the largest
//! difference where |d| stays above half of it.

use frfup_parsers::deck::Deck;

use super::data::{ChannelInfo, TestData};
use super::fit::{self, Mask};
use crate::model::{self, Damping, Dof, FeModel, ParameterValues};

/// Lines of the moving average of the dB difference.
pub const SMOOTH_LINES: usize = 5;
/// A prediction counts only above this many median noise σ of the test.
pub const FLOOR_SIGMAS: f64 = 3.0;
/// Most DOFs probed (nodes taken at a regular stride beyond it).
const MAX_PROBES: usize = 600;
/// Below this difference (dB) no sensor tells the two apart in practice.
pub const MEASURABLE_DB: f64 = 1.0;

/// Where and how to measure so that two explanations differ.
#[derive(Clone, Debug, PartialEq)]
pub struct TellApart {
    /// The other explanation (its label).
    pub alternative: String,
    /// The DOF to measure: test node, UFF direction code (1–3), label.
    pub node: u32,
    pub direction: i32,
    pub dof: String,
    /// The band (Hz) where the two differ by more than half the largest difference.
    pub band_hz: (f64, f64),
    /// The largest smoothed difference of the predicted magnitudes (dB, ≥ 0).
    pub difference_db: f64,
}

impl TellApart {
    /// One sentence for reports and the summary.
    pub fn sentence(&self, accepted: &str) -> String {
        if self.difference_db < MEASURABLE_DB {
            return format!(
                "{accepted} and {} explain the data equally well, and no unmeasured DOF in the test's band tells them apart by more than {MEASURABLE_DB} dB (largest {:.2} dB at {}).",
                self.alternative, self.difference_db, self.dof
            );
        }
        format!(
            "{accepted} and {} explain the data equally well with these sensors; to tell them apart, measure {} (a sensor, or a hammer point by reciprocity) at {}–{} Hz, where their predictions differ by {:.1} dB.",
            self.alternative,
            self.dof,
            crate::model::sig(self.band_hz.0),
            crate::model::sig(self.band_hz.1),
            self.difference_db
        )
    }
}

/// The measurement that tells the explanation `a` (deck and damping) from
/// `b`, on the lines and excitation of `data`; `None` when either model
/// cannot be solved or no DOF is left unmeasured.
pub fn tell_apart(
    a: (&Deck, Damping),
    b: (&Deck, Damping),
    alternative: &str,
    data: &TestData,
) -> Option<TellApart> {
    let fa = model::build(a.0, &ParameterValues::new()).ok()?;
    let fb = model::build(b.0, &ParameterValues::new()).ok()?;
    let probe = probe_data(&fa, &fb, data)?;
    let mask = Mask::all(&probe);
    let ha = fit::predict(
        &fit::modal_solution(&fa, &probe).ok()?.model,
        a.1,
        &probe,
        &mask,
    );
    let hb = fit::predict(
        &fit::modal_solution(&fb, &probe).ok()?.model,
        b.1,
        &probe,
        &mask,
    );
    let floor = FLOOR_SIGMAS * super::data_errors::median(&data.sigma).unwrap_or(0.0);
    let mut best: Option<(usize, usize, f64, Vec<f64>)> = None;
    for c in 0..probe.channels.len() {
        let d = smoothed_db(&ha[c], &hb[c], floor);
        let Some((l, v)) = d
            .iter()
            .enumerate()
            .max_by(|x, y| x.1.total_cmp(y.1))
            .map(|(l, v)| (l, *v))
        else {
            continue;
        };
        if best.as_ref().is_none_or(|b| v > b.2) {
            best = Some((c, l, v, d));
        }
    }
    let (c, l, v, d) = best?;
    let (lo, hi) = half_band(&d, l, v);
    let ch = &probe.channels[c];
    Some(TellApart {
        alternative: alternative.to_string(),
        node: ch.node,
        direction: ch.direction,
        dof: ch.label.clone(),
        band_hz: (probe.lines_hz[lo], probe.lines_hz[hi]),
        difference_db: v,
    })
}

/// `data` with its channels replaced by the translational DOFs of `fa`
/// that `fb` has too and the test did not measure.
fn probe_data(fa: &FeModel, fb: &FeModel, data: &TestData) -> Option<TestData> {
    let measured = |node: u32, dir: i32| {
        data.channels
            .iter()
            .any(|c| c.node == node && c.direction.abs() == dir)
    };
    let mut dofs: Vec<(u32, i32)> = fa
        .dofs
        .equations
        .iter()
        .filter_map(|&(node, dof)| {
            let dir = match dof {
                Dof::X => 1,
                Dof::Y => 2,
                Dof::Z => 3,
                _ => return None,
            };
            (fb.dofs.lookup.contains_key(&(node, dof)) && !measured(node, dir))
                .then_some((node, dir))
        })
        .collect();
    if dofs.len() > MAX_PROBES {
        let stride = dofs.len().div_ceil(MAX_PROBES);
        dofs = dofs.into_iter().step_by(stride).collect();
    }
    if dofs.is_empty() {
        return None;
    }
    let mut probe = data.clone();
    probe.channels = dofs
        .iter()
        .map(|&(node, direction)| ChannelInfo {
            node,
            direction,
            label: crate::testdata::dof_label(node as i64, direction),
        })
        .collect();
    Some(probe)
}

/// |20 log₁₀ |a|/|b||, averaged over [`SMOOTH_LINES`] lines; 0 where either
/// prediction is under `floor` or not finite.
pub fn smoothed_db(a: &[faer::c64], b: &[faer::c64], floor: f64) -> Vec<f64> {
    let raw: Vec<f64> = a
        .iter()
        .zip(b)
        .map(|(x, y)| {
            let (x, y) = (x.norm(), y.norm());
            if x.is_finite() && y.is_finite() && x > floor && y > floor {
                (20.0 * (x / y).log10()).abs()
            } else {
                0.0
            }
        })
        .collect();
    let h = SMOOTH_LINES / 2;
    (0..raw.len())
        .map(|l| {
            let w = &raw[l.saturating_sub(h)..(l + h + 1).min(raw.len())];
            w.iter().sum::<f64>() / w.len() as f64
        })
        .collect()
}

/// The run of lines around `peak` where `d` stays at or above half of `v`.
pub fn half_band(d: &[f64], peak: usize, v: f64) -> (usize, usize) {
    let (mut lo, mut hi) = (peak, peak);
    while lo > 0 && d[lo - 1] >= 0.5 * v {
        lo -= 1;
    }
    while hi + 1 < d.len() && d[hi + 1] >= 0.5 * v {
        hi += 1;
    }
    (lo, hi)
}
