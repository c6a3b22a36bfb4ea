//! Correlation of FE and test data: the modified FDAC (Eq. 44), the simplified
//! SFDAC (Eq. 45–46) on signed real displacement FRFs (m/N), the MAC, and the
//! pairing of test resonances with FE modes.

use super::serep::dot;

/// (xᵀy)|xᵀy| / ((xᵀx)(yᵀy)): the signed square of the cosine between x and y,
/// in [−1, 1]; 0 when either vector is zero.
fn signed_cos2(x: &[f64], y: &[f64]) -> f64 {
    let xy = dot(x, y);
    let d = dot(x, x) * dot(y, y);
    if d > 0.0 && d.is_finite() {
        (xy * xy.abs() / d).clamp(-1.0, 1.0)
    } else {
        0.0
    }
}

/// SFDAC_i (Eq. 45) of the FE FRF `fe` and the measured FRF `test` at one
/// updating frequency (same DOF order).
pub fn sfdac(fe: &[f64], test: &[f64]) -> f64 {
    signed_cos2(fe, test)
}

/// The SFDAC vector, its mean (Eq. 46) and minimum.
#[derive(Clone, Debug, PartialEq)]
pub struct SfdacSummary {
    pub values: Vec<f64>,
    pub mean: f64,
    pub min: f64,
}

impl SfdacSummary {
    pub fn new(fe: &[Vec<f64>], test: &[Vec<f64>]) -> SfdacSummary {
        let values: Vec<f64> = fe.iter().zip(test).map(|(h, t)| sfdac(h, t)).collect();
        let mean = if values.is_empty() {
            0.0
        } else {
            values.iter().sum::<f64>() / values.len() as f64
        };
        let min = values.iter().copied().fold(f64::INFINITY, f64::min);
        SfdacSummary {
            values,
            mean,
            min: if min.is_finite() { min } else { 0.0 },
        }
    }
}

/// FDAC(ω_i, ω̄_j) (Eq. 44): rows are FE frequencies, columns test frequencies.
pub fn fdac_matrix(fe: &[Vec<f64>], test: &[Vec<f64>]) -> Vec<Vec<f64>> {
    fe.iter()
        .map(|h| test.iter().map(|t| signed_cos2(h, t)).collect())
        .collect()
}

/// MAC(x, y) = (xᵀy)² / ((xᵀx)(yᵀy)).
pub fn mac(x: &[f64], y: &[f64]) -> f64 {
    signed_cos2(x, y).abs()
}

/// Where the test's mode shapes come from: what the MAC compares with the
/// FE modes, for pairing and in the report alike.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum ShapeSource {
    /// The multi-channel pole fit's residues (its deflection shape at the
    /// peak where no pole fits).
    Fitted,
    /// Operating deflection shapes: the measured FRFs at each resonance line.
    #[default]
    OperatingDeflection,
}

impl ShapeSource {
    /// "fitted mode shapes" or "operating deflection shapes (ODS)".
    pub fn name(self) -> &'static str {
        match self {
            ShapeSource::Fitted => "fitted mode shapes",
            ShapeSource::OperatingDeflection => "operating deflection shapes (ODS)",
        }
    }

    /// "fitted shapes" or "ODS", for labels with little room.
    pub fn short_name(self) -> &'static str {
        match self {
            ShapeSource::Fitted => "fitted shapes",
            ShapeSource::OperatingDeflection => "ODS",
        }
    }
}

/// The test's shape of each resonance at the measured DOFs, [resonance][DOF],
/// and where they come from.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TestShapes {
    pub source: ShapeSource,
    pub shapes: Vec<Vec<f64>>,
}

/// MAC of the test shapes against FE modes, [test resonance][FE mode]
/// (NaN where a shape is missing), and the shapes' source.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MacMatrix {
    pub source: ShapeSource,
    pub values: Vec<Vec<f64>>,
}

/// The MAC of every test shape against every FE mode shape (both at the
/// measured DOFs, in the same order).
pub fn mac_matrix(test: &TestShapes, fe_shapes: &[Vec<f64>]) -> MacMatrix {
    MacMatrix {
        source: test.source,
        values: test
            .shapes
            .iter()
            .map(|t| {
                fe_shapes
                    .iter()
                    .map(|f| {
                        if t.len() == f.len() {
                            mac(t, f)
                        } else {
                            f64::NAN
                        }
                    })
                    .collect()
            })
            .collect(),
    }
}

/// A test resonance paired with an FE mode.
#[derive(Clone, Debug, PartialEq)]
pub struct ModePair {
    /// Index of the test resonance.
    pub test: usize,
    /// Index of the FE mode (into the computed modes).
    pub fe: usize,
    pub mac: f64,
    pub fe_hz: f64,
}

/// Largest relative frequency difference of a pair.
pub const PAIR_FREQUENCY_WINDOW: f64 = 0.3;

/// Pair each test resonance with one FE mode within ±30 % in frequency
/// ([`PAIR_FREQUENCY_WINDOW`]): pairs are formed greedily in
/// order of decreasing MAC (ties: closer frequency, then lower indices), each FE
/// mode used once; a pair needs MAC ≥ `mac_min`. Resonances left over are
/// paired, if any FE mode is still free, with the free mode nearest in
/// frequency among those with MAC ≥ `mac_min`/2, else left unpaired (`None`).
pub fn pair_modes(
    test_shapes: &[Vec<f64>],
    test_hz: &[f64],
    fe_shapes: &[Vec<f64>],
    fe_hz: &[f64],
    mac_min: f64,
) -> Vec<Option<ModePair>> {
    let mut cands = Vec::new();
    for (t, ts) in test_shapes.iter().enumerate() {
        for (e, es) in fe_shapes.iter().enumerate() {
            let m = mac(ts, es);
            let df = ((fe_hz[e] - test_hz[t]) / test_hz[t].abs().max(1e-12)).abs();
            // A few sensors alias high modes onto low ones (GARTEUR: a 346 Hz
            // FE mode has MAC 0.98 with the 37 Hz test mode at 26 sensors).
            if df > PAIR_FREQUENCY_WINDOW {
                continue;
            }
            cands.push((m, df, t, e));
        }
    }
    cands.sort_by(|a, b| {
        b.0.total_cmp(&a.0)
            .then(a.1.total_cmp(&b.1))
            .then(a.2.cmp(&b.2))
            .then(a.3.cmp(&b.3))
    });
    let mut out: Vec<Option<ModePair>> = vec![None; test_shapes.len()];
    let mut used = vec![false; fe_shapes.len()];
    for &(m, _, t, e) in &cands {
        if m < mac_min {
            break;
        }
        if out[t].is_none() && !used[e] {
            out[t] = Some(ModePair {
                test: t,
                fe: e,
                mac: m,
                fe_hz: fe_hz[e],
            });
            used[e] = true;
        }
    }
    for (t, slot) in out.iter_mut().enumerate() {
        if slot.is_some() {
            continue;
        }
        let best = cands
            .iter()
            .filter(|c| c.2 == t && !used[c.3] && c.0 >= 0.5 * mac_min)
            .min_by(|a, b| a.1.total_cmp(&b.1).then(a.3.cmp(&b.3)));
        if let Some(&(m, _, _, e)) = best {
            *slot = Some(ModePair {
                test: t,
                fe: e,
                mac: m,
                fe_hz: fe_hz[e],
            });
            used[e] = true;
        }
    }
    out
}

/// Test resonances (Hz) paired one to one with model resonances (Hz) by
/// frequency alone: the closest pair first (|ln(f_model/f_test)|), then
/// the closest of the rest, each resonance in at most one pair, none
/// farther apart than a factor [`FREQUENCY_PAIR_RATIO`]. Returns (test,
/// model) index pairs in test order. Nearest-neighbour pairing lets two
/// test modes share one model peak (three close modes the model makes
/// one peak of) or a suspension mode take the first elastic mode's
/// partner, and their distance then counts as a frequency error.
pub fn pair_by_frequency(test_hz: &[f64], model_hz: &[f64]) -> Vec<(usize, usize)> {
    let mut candidates: Vec<(f64, usize, usize)> = Vec::new();
    for (t, &ft) in test_hz.iter().enumerate() {
        for (m, &fm) in model_hz.iter().enumerate() {
            let d = (fm / ft).ln().abs();
            if d.is_finite() && d < FREQUENCY_PAIR_RATIO.ln() {
                candidates.push((d, t, m));
            }
        }
    }
    candidates.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)).then(a.2.cmp(&b.2)));
    let (mut t_used, mut m_used) = (vec![false; test_hz.len()], vec![false; model_hz.len()]);
    let mut pairs = Vec::new();
    for (_, t, m) in candidates {
        if !t_used[t] && !m_used[m] {
            (t_used[t], m_used[m]) = (true, true);
            pairs.push((t, m));
        }
    }
    pairs.sort_unstable();
    pairs
}

/// Resonances farther apart than this factor are not paired by
/// [`pair_by_frequency`]: an initial model 40 % off in a stiffness is
/// within it (frequencies scale with its square root).
pub const FREQUENCY_PAIR_RATIO: f64 = 1.5;
