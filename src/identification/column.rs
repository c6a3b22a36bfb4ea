//! One column of the FRF matrix given as arrays: the entry point of the
//! update, which holds the test as FRFs per measured DOF for one excitation
//! (a roving-hammer row already turned into a column by reciprocity).

use faer::c64;

use super::{identify, Identification, IdentifyError, IdentifyOptions, Mode};
use crate::testdata::{Channel, FrfKind, MeasuredFrfs};

/// A test mode at the DOFs of one column, as the update (from
/// [`identify_column`]) and the diagnosis's channel checks (from the pole fit
/// of `updating::identify`) use it.
#[derive(Clone, Debug, PartialEq)]
pub struct ColumnMode {
    /// Undamped natural frequency |λ|/2π (Hz).
    pub frequency_hz: f64,
    /// Viscous damping ratio −Re λ/|λ|.
    pub damping_ratio: f64,
    /// Real mode shape at the DOFs (the real part of the shape rotated to be
    /// most nearly real), largest magnitude 1, arbitrary sign.
    pub shape: Vec<f64>,
    /// ±1: `shape` × this has the signs of the modal constants
    /// Q_c = φ_c·φ_ref themselves (for a real mode the residue is
    /// A_c = Q_c/(2iω_d), so Q_c ∝ −Im A_c).
    pub constant_sign: f64,
    /// Peak modal contribution ÷ RMS of the fit residual.
    pub significance: f64,
    /// Index in `lines_hz` of the line nearest the natural frequency.
    pub line: usize,
}

/// The modes of `frfs[dof][line]`, FRFs of `kind` on the ascending
/// `lines_hz` for one excitation, by [`identify`] with its defaults; sorted
/// by frequency.
pub fn identify_column(
    lines_hz: &[f64],
    kind: FrfKind,
    frfs: &[Vec<c64>],
) -> Result<Vec<ColumnMode>, IdentifyError> {
    let id = identify(&as_test(lines_hz, kind, frfs), &IdentifyOptions::default())?;
    Ok(column_modes(&id, lines_hz))
}

/// `frfs` as a test: DOF c is node c + 1, the excitation node 0 (names that
/// only keep the DOFs apart; the fit never reads geometry).
fn as_test(lines_hz: &[f64], kind: FrfKind, frfs: &[Vec<c64>]) -> MeasuredFrfs {
    MeasuredFrfs {
        frequencies_hz: lines_hz.to_vec(),
        kind,
        channels: frfs
            .iter()
            .enumerate()
            .map(|(c, values)| Channel {
                response_node: c as i64 + 1,
                response_direction: 1,
                reference_node: 0,
                reference_direction: 1,
                values: values.clone(),
            })
            .collect(),
    }
}

fn column_modes(id: &Identification, lines_hz: &[f64]) -> Vec<ColumnMode> {
    id.modes
        .iter()
        .map(|m| ColumnMode {
            frequency_hz: m.frequency_hz,
            damping_ratio: m.damping_ratio,
            shape: m.real_shape(),
            constant_sign: constant_sign(m),
            significance: m.significance,
            line: nearest_line(lines_hz, m.frequency_hz),
        })
        .collect()
}

/// The sign of the projection Σ_c shape_c·(−Im A_c).
fn constant_sign(m: &Mode) -> f64 {
    let projection: f64 = m
        .shape
        .iter()
        .zip(&m.residues)
        .map(|(s, a)| s.re * -a.im)
        .sum();
    if projection < 0.0 {
        -1.0
    } else {
        1.0
    }
}

fn nearest_line(lines_hz: &[f64], f: f64) -> usize {
    let k = lines_hz.partition_point(|&x| x < f);
    match (k.checked_sub(1), lines_hz.get(k)) {
        (Some(lo), Some(&hi)) if f - lines_hz[lo] <= hi - f => lo,
        (Some(lo), None) => lo,
        _ => k,
    }
}
