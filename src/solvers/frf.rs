//! Forced response: receptance H(ω) = x/f of the damped model.

use faer::c64;

use crate::model::{Damping, SparseMatrix};
use crate::solvers::eigen::Modes;

/// CONTRACT. Receptance (m/N) at `outputs` for a unit force at `input`, one
/// column per frequency: result is outputs.len() × omegas.len().
/// Direct complex solve of (K(1+iη) + iωC − ω²M) x = f.
pub fn direct_receptance(
    k: &SparseMatrix,
    m: &SparseMatrix,
    damping: Damping,
    omegas_rad_s: &[f64],
    input: usize,
    outputs: &[usize],
) -> faer::Mat<c64> {
    let _ = (k, m, damping, omegas_rad_s, input, outputs);
    todo!("solvers helper implements this")
}

/// CONTRACT. Same quantity by modal superposition over `modes`.
pub fn modal_receptance(
    modes: &Modes,
    damping: Damping,
    omegas_rad_s: &[f64],
    input: usize,
    outputs: &[usize],
) -> faer::Mat<c64> {
    let _ = (modes, damping, omegas_rad_s, input, outputs);
    todo!("solvers helper implements this")
}
