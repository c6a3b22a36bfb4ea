//! Parameter values → the property of every element.
//!
//! A `param` scales a quantity of the listed elements by (1 + p). Several
//! parameters on the same quantity of the same element multiply. When a
//! material gives no `G`, G = E/(2(1+ν)) follows the (scaled) E.

use std::collections::HashMap;

use frfup_parsers::deck::{Deck, Material, Quantity, Section};

use super::elements::beam::{BeamProperties, Scalar};
use super::{ModelError, ParameterValues};

/// Index of a beam quantity in a factor array `[E, G, rho, A, Iy, Iz, J]`.
pub(crate) fn beam_slot(q: Quantity) -> Option<usize> {
    Some(match q {
        Quantity::E => 0,
        Quantity::G => 1,
        Quantity::Rho => 2,
        Quantity::A => 3,
        Quantity::Iy => 4,
        Quantity::Iz => 5,
        Quantity::J => 6,
        Quantity::M | Quantity::K => return None,
    })
}

/// Multiplicative factors (1 + p) of every element's quantities.
#[derive(Clone, Debug)]
pub(crate) struct Factors {
    /// Per beam (deck order): factors of E, G, rho, A, Iy, Iz, J.
    pub beam: Vec<[f64; 7]>,
    /// Per mass (deck order): factor of m.
    pub mass: Vec<f64>,
    /// Per spring (deck order): factor of k.
    pub spring: Vec<f64>,
}

/// ID → index in deck order, for beams, masses, springs.
pub(crate) struct Indices {
    pub beam: HashMap<u32, usize>,
    pub mass: HashMap<u32, usize>,
    pub spring: HashMap<u32, usize>,
}

impl Indices {
    pub fn new(deck: &Deck) -> Self {
        Indices {
            beam: deck
                .beams
                .iter()
                .enumerate()
                .map(|(i, b)| (b.id, i))
                .collect(),
            mass: deck
                .masses
                .iter()
                .enumerate()
                .map(|(i, m)| (m.id, i))
                .collect(),
            spring: deck
                .springs
                .iter()
                .enumerate()
                .map(|(i, s)| (s.id, i))
                .collect(),
        }
    }
    /// Indices (deck order) of the elements a `param` lists.
    pub fn targets(&self, quantity: Quantity, ids: impl Iterator<Item = u32>) -> Vec<usize> {
        let map = match quantity {
            Quantity::M => &self.mass,
            Quantity::K => &self.spring,
            _ => &self.beam,
        };
        let mut v: Vec<usize> = ids.filter_map(|id| map.get(&id).copied()).collect();
        v.sort_unstable();
        v.dedup();
        v
    }
}

/// Check `values` against the deck's parameters.
pub(crate) fn check_values(deck: &Deck, values: &ParameterValues) -> Result<(), ModelError> {
    for (name, &value) in values {
        let Some(p) = deck.param(name) else {
            return Err(ModelError::UnknownParameter { name: name.clone() });
        };
        if !value.is_finite() {
            return Err(ModelError::NonFiniteParameter {
                name: name.clone(),
                value,
            });
        }
        if 1.0 + value <= 0.0 {
            return Err(ModelError::NonPositiveProperty {
                name: name.clone(),
                value,
                pos: p.pos,
            });
        }
    }
    Ok(())
}

/// The factors of every element at `values` (unknown names are ignored here).
pub(crate) fn factors(deck: &Deck, idx: &Indices, values: &ParameterValues) -> Factors {
    let mut f = Factors {
        beam: vec![[1.0; 7]; deck.beams.len()],
        mass: vec![1.0; deck.masses.len()],
        spring: vec![1.0; deck.springs.len()],
    };
    for p in &deck.params {
        let v = values.get(&p.name).copied().unwrap_or(0.0);
        if v == 0.0 {
            continue;
        }
        let s = 1.0 + v;
        for i in idx.targets(p.quantity, p.ids()) {
            match p.quantity {
                Quantity::M => f.mass[i] *= s,
                Quantity::K => f.spring[i] *= s,
                q => {
                    if let Some(slot) = beam_slot(q) {
                        f.beam[i][slot] *= s;
                    }
                }
            }
        }
    }
    f
}

/// Properties of a beam with material `m`, section `s` and factors `f`
/// (possibly complex for complex-step derivatives).
pub(crate) fn beam_properties<T: Scalar>(
    m: &Material,
    s: &Section,
    f: [T; 7],
) -> BeamProperties<T> {
    let r = |x: f64| T::from_real(x);
    let e = r(m.e) * f[0];
    let g = match m.g {
        Some(g) => r(g) * f[1],
        None => e * r(1.0 / (2.0 * (1.0 + m.nu()))) * f[1],
    };
    // Iz and J are required in space; in a plane analysis they only reach
    // DOFs that are discarded, so any positive stand-in will do.
    let (iz, j) = (s.iz.unwrap_or(s.iy), s.j.unwrap_or(s.iy));
    BeamProperties {
        e,
        g,
        rho: r(m.rho) * f[2],
        a: r(s.a) * f[3],
        iy: r(s.iy) * f[4],
        iz: r(iz) * f[5],
        j: r(j) * f[6],
        ky: s.ky(),
        kz: s.kz(),
    }
}
