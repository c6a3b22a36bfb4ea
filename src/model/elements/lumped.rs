//! Lumped masses and linear springs (deck spec: "Springs and masses add to
//! the assembled matrices as written").
//!
//! A `mass` adds m to the x, y, z diagonal terms of its node and Ixx, Iyy, Izz
//! to rx, ry, rz (kg, kg·m²). A grounded `spring` adds k to the diagonal of
//! its DOF; a two-node spring adds k·[1 −1; −1 1] on the same DOF of both
//! nodes (N/m or N·m/rad).

use frfup_parsers::deck::{DeckDof, Mass};

/// The diagonal mass terms of a lumped mass, as (DOF, value), zeros omitted.
pub fn mass_terms(mass: &Mass, m_factor: f64) -> Vec<(DeckDof, f64)> {
    let m = mass.m * m_factor;
    let mut out = Vec::with_capacity(6);
    if m != 0.0 {
        out.extend([(DeckDof::X, m), (DeckDof::Y, m), (DeckDof::Z, m)]);
    }
    for (dof, v) in [
        (DeckDof::Rx, mass.ixx),
        (DeckDof::Ry, mass.iyy),
        (DeckDof::Rz, mass.izz),
    ] {
        if let Some(v) = v.filter(|v| *v != 0.0) {
            out.push((dof, v));
        }
    }
    out
}

/// 2×2 stiffness of a two-node spring of stiffness k.
pub fn spring_pair(k: f64) -> [[f64; 2]; 2] {
    [[k, -k], [-k, k]]
}
