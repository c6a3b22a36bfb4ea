//! Conversions between receptance, mobility and accelerance, and the paper's
//! signed real FRF (Eq. 50 and §3.6).
//!
//! Per line, with ω = 2πf (rad/s): mobility = iω·receptance, accelerance =
//! (iω)²·receptance = −ω²·receptance. Going down in order divides by iω; at the
//! zero-frequency line that is undefined, so the converted value there is set to
//! 0 + 0i and [`Conversion::zeroed_lines`] says so (never NaN).

use faer::c64;

use super::{i_omega_power, FrfKind, MeasuredFrfs};

/// The outcome of a kind conversion.
#[derive(Clone, Debug, PartialEq)]
pub struct Conversion {
    pub frfs: MeasuredFrfs,
    /// Frequency lines (indices) set to zero because the conversion divides by ω = 0 there.
    pub zeroed_lines: Vec<usize>,
}

impl MeasuredFrfs {
    /// Convert every channel to `kind`, line by line.
    pub fn to_kind(&self, kind: FrfKind) -> Conversion {
        let power = kind.order() - self.kind.order();
        let mut zeroed_lines = Vec::new();
        let factors: Vec<Option<c64>> = self
            .frequencies_hz
            .iter()
            .enumerate()
            .map(|(line, &f)| {
                let omega = 2.0 * std::f64::consts::PI * f;
                if power < 0 && omega == 0.0 {
                    zeroed_lines.push(line);
                    None
                } else {
                    Some(i_omega_power(omega, power))
                }
            })
            .collect();
        let channels = self
            .channels
            .iter()
            .map(|ch| {
                let mut ch = ch.clone();
                for (v, fac) in ch.values.iter_mut().zip(&factors) {
                    *v = match fac {
                        Some(fac) => *v * fac,
                        None => c64::new(0.0, 0.0),
                    };
                }
                ch
            })
            .collect();
        Conversion {
            frfs: MeasuredFrfs {
                frequencies_hz: self.frequencies_hz.clone(),
                kind,
                channels,
            },
            zeroed_lines,
        }
    }
}

/// sign(x) with sign(0) = 0.
fn sign(x: f64) -> f64 {
    if x > 0.0 {
        1.0
    } else if x < 0.0 {
        -1.0
    } else {
        0.0
    }
}

/// §3.6: the signed real value of a receptance, h = sign(a)·|H| for H = a + ib.
pub fn signed_real(h: c64) -> f64 {
    sign(h.re) * h.norm()
}

/// Eq. 50 and §3.6: the signed real displacement FRF (m/N) of every channel,
/// `result[channel][line]`.
///
/// Accelerance H = a + ib: h = −sign(a)·√(a²+b²)/ω²; receptance: h = sign(a)·|H|;
/// mobility is first taken to receptance (÷ iω). Lines at ω = 0 give 0 for
/// accelerance and mobility (undefined there), never NaN.
pub fn signed_real_displacement(frfs: &MeasuredFrfs) -> Vec<Vec<f64>> {
    frfs.channels
        .iter()
        .map(|ch| {
            ch.values
                .iter()
                .zip(&frfs.frequencies_hz)
                .map(|(&h, &f)| {
                    let omega = 2.0 * std::f64::consts::PI * f;
                    match frfs.kind {
                        FrfKind::Receptance => signed_real(h),
                        _ if omega == 0.0 => 0.0,
                        // Eq. 50
                        FrfKind::Accelerance => -sign(h.re) * h.norm() / (omega * omega),
                        FrfKind::Mobility => signed_real(h * c64::new(0.0, -1.0 / omega)),
                    }
                })
                .collect()
        })
        .collect()
}
