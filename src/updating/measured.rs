//! The test as the method sees it: channels mapped to FE DOFs, the excitation
//! DOF, and the signed real displacement FRF h̄ (m/N, Eq. 50 / §3.6) at every
//! measured DOF and line.
//!
//! Test node ids are FE node ids unless a deck `sensor` maps them; a negative
//! UFF direction (response or reference) flips the sign. Only the records whose
//! reference is the excitation DOF are used: the excitation is the reference
//! shared by most channels (ties: the lowest node, then direction).

use faer::c64;

use super::{UpdateError, UpdateWarning};
use crate::model::FeModel;
use crate::testdata::{self, dof_label, FrfKind, MeasuredFrfs};

/// Measured data on FE DOFs.
#[derive(Clone, Debug)]
pub struct MeasuredDofs {
    /// FE equation index of each measured DOF, in channel order.
    pub equations: Vec<usize>,
    /// Labels `NODE±dir` of the test channels used.
    pub labels: Vec<String>,
    /// Node and FE DOF of each measured DOF (the values above are in the
    /// FE DOF's sense).
    pub points: Vec<(u32, crate::model::Dof)>,
    /// FE equation index of the excitation DOF (measured or not: the
    /// updating equations take the model's mode shapes there, §2.2 with the
    /// SEREP expansion, so a driving-point FRF is not required).
    pub excitation_eq: usize,
    pub excitation_label: String,
    /// Frequency lines (Hz).
    pub lines_hz: Vec<f64>,
    /// h̄[dof][line]: signed real displacement FRF in FE DOF sense (m/N).
    pub signed_real: Vec<Vec<f64>>,
    /// Complex receptance[dof][line] in FE DOF sense (m/N).
    pub receptance: Vec<Vec<c64>>,
    /// Complex mobility of the used channels (for peak picking).
    pub mobility: Vec<Vec<c64>>,
}

impl MeasuredDofs {
    /// Map `test` onto the DOFs of `model`, pushing warnings for ignored channels.
    pub fn new(
        model: &FeModel,
        test: &MeasuredFrfs,
        warnings: &mut Vec<UpdateWarning>,
    ) -> Result<Self, UpdateError> {
        if test.channels.is_empty() {
            return Err(UpdateError::NoChannels);
        }
        let lines = test.frequencies_hz.len();
        for ch in &test.channels {
            if ch.values.len() != lines {
                return Err(UpdateError::ChannelLength {
                    channel: ch.label(),
                    values: ch.values.len(),
                    lines,
                });
            }
        }
        // The excitation: the most common reference.
        let mut refs: Vec<((i64, i32), usize)> = Vec::new();
        for ch in &test.channels {
            let key = (ch.reference_node, ch.reference_direction);
            match refs.iter_mut().find(|(k, _)| *k == key) {
                Some((_, n)) => *n += 1,
                None => refs.push((key, 1)),
            }
        }
        refs.sort_by(|a, b| b.1.cmp(&a.1).then(a.0.cmp(&b.0)));
        let (ex_node, ex_dir) = refs[0].0;
        let excitation_label = dof_label(ex_node, ex_dir);
        let ignored = test.channels.len() - refs[0].1;
        if ignored > 0 {
            warnings.push(UpdateWarning::OtherReferences {
                excitation: excitation_label.clone(),
                ignored,
            });
        }
        let lookup = |node: i64, dir: i32| -> Option<(usize, f64)> {
            let node = u32::try_from(node).ok()?;
            model.measured_dof(node, dir)
        };
        let (ex_eq, ex_sign) = lookup(ex_node, ex_dir).ok_or(UpdateError::UnknownExcitation {
            excitation: excitation_label.clone(),
        })?;

        let real = testdata::signed_real_displacement(test);
        let receptance = test.to_kind(FrfKind::Receptance).frfs;
        let mobility = test.to_kind(FrfKind::Mobility).frfs;

        let mut out = MeasuredDofs {
            equations: Vec::new(),
            labels: Vec::new(),
            points: Vec::new(),
            excitation_eq: ex_eq,
            excitation_label: excitation_label.clone(),
            lines_hz: test.frequencies_hz.clone(),
            signed_real: Vec::new(),
            receptance: Vec::new(),
            mobility: Vec::new(),
        };
        let mut unmatched = Vec::new();
        for (c, ch) in test.channels.iter().enumerate() {
            if (ch.reference_node, ch.reference_direction) != (ex_node, ex_dir) {
                continue;
            }
            let label = dof_label(ch.response_node, ch.response_direction);
            let Some((eq, sign)) = lookup(ch.response_node, ch.response_direction) else {
                unmatched.push(label);
                continue;
            };
            if out.equations.contains(&eq) {
                warnings.push(UpdateWarning::DuplicateChannel { label });
                continue;
            }
            let s = sign * ex_sign;
            out.equations.push(eq);
            out.labels.push(label);
            out.points.push(model.dofs.equations[eq]);
            out.signed_real
                .push(real[c].iter().map(|v| s * v).collect());
            out.receptance.push(
                receptance.channels[c]
                    .values
                    .iter()
                    .map(|v| v * s)
                    .collect(),
            );
            out.mobility.push(mobility.channels[c].values.clone());
        }
        if out.equations.is_empty() {
            return Err(UpdateError::NoMatchingChannels { unmatched });
        }
        if !unmatched.is_empty() {
            warnings.push(UpdateWarning::UnmatchedChannels { labels: unmatched });
        }
        if !out.equations.contains(&ex_eq) {
            warnings.push(UpdateWarning::DrivingPointNotMeasured {
                excitation: excitation_label,
            });
        }
        Ok(out)
    }

    /// N_ex.
    pub fn len(&self) -> usize {
        self.equations.len()
    }

    pub fn is_empty(&self) -> bool {
        self.equations.is_empty()
    }

    /// h̄ at one line for every measured DOF (m/N).
    pub fn at_line(&self, line: usize) -> Vec<f64> {
        self.signed_real.iter().map(|h| h[line]).collect()
    }

    /// An operating deflection shape at `line` for MAC pairing: the quadrature
    /// (imaginary) part of the receptance, or its real part for undamped data,
    /// whichever has the larger norm.
    pub fn deflection_shape(&self, line: usize) -> Vec<f64> {
        let im: Vec<f64> = self.receptance.iter().map(|h| h[line].im).collect();
        let re: Vec<f64> = self.receptance.iter().map(|h| h[line].re).collect();
        let n = |v: &[f64]| v.iter().map(|x| x * x).sum::<f64>();
        if n(&im) >= n(&re) {
            im
        } else {
            re
        }
    }
}
