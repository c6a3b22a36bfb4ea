//! The stabilisation diagram: LSCF poles for every model order, each marked
//! by how it agrees with the nearest pole of the order below.

use faer::c64;
use rayon::prelude::*;

use super::lscf::{self, Sums};
use super::prepare::{self, Prepared};
use super::IdentifyError;

const TWO_PI: f64 = 2.0 * std::f64::consts::PI;

/// Relative tolerances between consecutive orders.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tolerances {
    /// |Δf| / f.
    pub frequency: f64,
    /// |Δζ| / ζ.
    pub damping: f64,
    /// Least MAC of the shape vectors.
    pub mac: f64,
    /// Largest damping ratio of a physical pole.
    pub max_damping: f64,
}

impl Default for Tolerances {
    /// PolyMAX's customary 1 % / 5 % / 98 % (Peeters et al. 2004), ζ ≤ 20 %.
    fn default() -> Self {
        Tolerances {
            frequency: 0.01,
            damping: 0.05,
            mac: 0.98,
            max_damping: 0.2,
        }
    }
}

/// How a pole compares with the order below.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stability {
    /// ζ ≤ 0 or above the physical limit.
    Unphysical,
    /// No pole of the order below within the frequency tolerance.
    New,
    /// Stable in frequency only.
    Frequency,
    /// Stable in frequency and damping.
    Damping,
    /// Stable in frequency and shape.
    Vector,
    /// Stable in frequency, damping and shape.
    Stable,
}

/// One pole of the diagram.
#[derive(Clone, Debug, PartialEq)]
pub struct DiagramPole {
    pub order: usize,
    /// λ (rad/s).
    pub pole: c64,
    pub frequency_hz: f64,
    pub damping_ratio: f64,
    pub stability: Stability,
    /// Shape up to a factor, per output.
    pub vector: Vec<c64>,
}

/// Poles per order over the band, with the summed FRF it is drawn over.
#[derive(Clone, Debug, PartialEq)]
pub struct Diagram {
    pub max_order: usize,
    /// Poles inside the band, by order then frequency.
    pub poles: Vec<DiagramPole>,
    /// Band lines (Hz) and the weighted sum of |H| on them.
    pub frequencies_hz: Vec<f64>,
    pub indicator: Vec<f64>,
}

/// MAC of two complex vectors, |aᴴb|² / (|a|²|b|²), 0 when either is zero.
pub fn mac(a: &[c64], b: &[c64]) -> f64 {
    let (mut ab, mut aa, mut bb) = (c64::new(0.0, 0.0), 0.0, 0.0);
    for (x, y) in a.iter().zip(b) {
        ab += x.conj() * y;
        aa += x.norm_sqr();
        bb += y.norm_sqr();
    }
    if aa > 0.0 && bb > 0.0 {
        ab.norm_sqr() / (aa * bb)
    } else {
        0.0
    }
}

fn stability(p: &DiagramPole, below: &[DiagramPole], tol: &Tolerances) -> Stability {
    if !(p.damping_ratio > 0.0 && p.damping_ratio <= tol.max_damping) {
        return Stability::Unphysical;
    }
    let Some(q) = below.iter().min_by(|a, b| {
        (a.pole - p.pole)
            .norm()
            .total_cmp(&(b.pole - p.pole).norm())
    }) else {
        return Stability::New;
    };
    if !((q.frequency_hz - p.frequency_hz).abs() <= tol.frequency * p.frequency_hz) {
        return Stability::New;
    }
    let damping = (q.damping_ratio - p.damping_ratio).abs() <= tol.damping * p.damping_ratio;
    let vector = mac(&q.vector, &p.vector) >= tol.mac;
    match (damping, vector) {
        (true, true) => Stability::Stable,
        (true, false) => Stability::Damping,
        (false, true) => Stability::Vector,
        (false, false) => Stability::Frequency,
    }
}

/// The diagram of orders 1..=max order.
pub fn diagram(data: &Prepared, sums: &Sums, tol: &Tolerances) -> Result<Diagram, IdentifyError> {
    let (f0, f1) = (
        data.frequencies_hz[0],
        data.frequencies_hz[data.n_lines() - 1],
    );
    // Every order's poles come from the same sums independently: computed
    // on all cores (each order's result does not depend on the thread),
    // then marked against the order below one after the other.
    // Collected whole first: the lowest failing order's error, not the
    // first a thread met.
    let per_order: Vec<Result<Vec<lscf::OrderPole>, IdentifyError>> = (1..=sums.max_order)
        .into_par_iter()
        .map(|order| lscf::poles(data, sums, order))
        .collect();
    let per_order: Vec<Vec<lscf::OrderPole>> = per_order.into_iter().collect::<Result<_, _>>()?;
    let mut all: Vec<DiagramPole> = Vec::new();
    let mut below: Vec<DiagramPole> = Vec::new();
    for (order, poles) in (1..=sums.max_order).zip(per_order) {
        let mut here: Vec<DiagramPole> = poles
            .into_iter()
            .map(|op| DiagramPole {
                order,
                pole: op.pole,
                frequency_hz: op.pole.norm() / TWO_PI,
                damping_ratio: -op.pole.re / op.pole.norm(),
                stability: Stability::New,
                vector: op.vector,
            })
            .filter(|p| p.frequency_hz >= f0 && p.frequency_hz <= f1)
            .collect();
        here.sort_by(|a, b| a.frequency_hz.total_cmp(&b.frequency_hz));
        for p in &mut here {
            p.stability = stability(p, &below, tol);
        }
        all.extend(here.iter().cloned());
        below = here;
    }
    Ok(Diagram {
        max_order: sums.max_order,
        poles: all,
        frequencies_hz: data.frequencies_hz.clone(),
        indicator: prepare::summed_magnitude(data),
    })
}
