//! ∂K/∂p and ∂M/∂p of every `param` (paper, Eq. 30–31), p being the relative
//! change about the current value (X = (1 + p)·X_current) at p = 0.
//!
//! Beams: the element matrices are differentiated by **complex step**:
//! with X → X·(1 + i·h), ∂K_e/∂p = Im K_e / h (h = 1e-20), exact to rounding
//! (no subtractive cancellation). For Euler–Bernoulli beams every quantity
//! enters linearly, so this is exactly the part of K_e (M_e) proportional to
//! the quantity (Eq. 31); for Timoshenko beams it also carries the
//! dependence through Φ = 12EI/(κGAL²). When a material gives no `G`, G
//! follows E, so ∂/∂E includes the torsion and shear terms.
//! Masses: ∂M/∂p = the current m on the x, y, z terms (inertias unchanged).
//! Springs: ∂K/∂p = the current spring matrix.

use faer::sparse::Triplet;
use frfup_parsers::deck::{Deck, DeckDof, Quantity};
use nalgebra::Complex;

use super::assembly::{from_triplets, spring_entries, Layout, NONE};
use super::elements::beam::{local_mass, local_stiffness, Matrix12};
use super::elements::frame::to_global;
use super::properties::{beam_properties, beam_slot};
use super::{ModelError, ParameterSensitivity};

/// Complex-step size (relative).
pub const COMPLEX_STEP: f64 = 1e-20;

/// Global ∂K_e/∂p, ∂M_e/∂p of beam `b` for a relative change of quantity slot `slot`.
pub(crate) fn beam_derivative(
    deck: &Deck,
    layout: &Layout,
    b: usize,
    slot: usize,
) -> (Matrix12<f64>, Matrix12<f64>) {
    let beam = &deck.beams[b];
    let frame = &layout.frames[b];
    let (Some(mat), Some(sec)) = (deck.material(&beam.material), deck.section(&beam.section))
    else {
        return (Matrix12::zeros(), Matrix12::zeros());
    };
    let mut f = layout.factors.beam[b].map(|v| Complex::new(v, 0.0));
    f[slot] *= Complex::new(1.0, COMPLEX_STEP);
    let p = beam_properties::<Complex<f64>>(mat, sec, f);
    let k = local_stiffness(&p, frame.length, beam.theory()).map(|z| z.im / COMPLEX_STEP);
    let m = local_mass(&p, frame.length, beam.theory()).map(|z| z.im / COMPLEX_STEP);
    (
        to_global(&k, &frame.rotation),
        to_global(&m, &frame.rotation),
    )
}

/// One [`ParameterSensitivity`] per deck `param`, in deck order.
pub(crate) fn derivatives(
    deck: &Deck,
    layout: &Layout,
    n: usize,
) -> Result<Vec<ParameterSensitivity>, ModelError> {
    let mut out = Vec::with_capacity(deck.params.len());
    for p in &deck.params {
        let targets = layout.indices.targets(p.quantity, p.ids());
        let mut dk: Vec<Triplet<usize, usize, f64>> = Vec::new();
        let mut dm: Vec<Triplet<usize, usize, f64>> = Vec::new();
        match p.quantity {
            Quantity::M => {
                for i in targets {
                    let mass = &deck.masses[i];
                    let m = mass.m * layout.factors.mass[i];
                    for d in [DeckDof::X, DeckDof::Y, DeckDof::Z] {
                        let eq = layout.equation(mass.node, d);
                        if eq != NONE && m != 0.0 {
                            dm.push(Triplet::new(eq, eq, m));
                        }
                    }
                }
            }
            Quantity::K => {
                for i in targets {
                    let s = &deck.springs[i];
                    let k = s.k * layout.factors.spring[i];
                    for (r, c, v) in spring_entries(layout, s, k) {
                        dk.push(Triplet::new(r, c, v));
                    }
                }
            }
            q => {
                let Some(slot) = beam_slot(q) else { continue };
                for b in targets {
                    let (k, m) = beam_derivative(deck, layout, b, slot);
                    let eqs = layout.beam_equations(deck, b);
                    for &(ri, row) in &eqs {
                        for &(ci, col) in &eqs {
                            if k[(ri, ci)] != 0.0 {
                                dk.push(Triplet::new(row, col, k[(ri, ci)]));
                            }
                            if m[(ri, ci)] != 0.0 {
                                dm.push(Triplet::new(row, col, m[(ri, ci)]));
                            }
                        }
                    }
                }
            }
        }
        out.push(ParameterSensitivity {
            name: p.name.clone(),
            dk: from_triplets(n, &dk)?,
            dm: from_triplets(n, &dm)?,
        });
    }
    Ok(out)
}
