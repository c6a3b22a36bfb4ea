//! Identified test modes paired with a deck's FE modes by MAC at the
//! measured DOFs, and the FE modes at every node for the reports' viewer.

use faer::c64;
use frfup_parsers::deck::Deck;

use crate::identification::stabilisation::mac;
use crate::identification::{identify, Identification, IdentifyOptions};
use crate::model::{self, Dof, ParameterValues};
use crate::solvers::eigen::nodal::{self, FeShapes};
use crate::solvers::eigen::{lowest_modes, EigenOptions};
use crate::testdata::MeasuredFrfs;

/// Least MAC of a pair.
pub const PAIR_MAC: f64 = 0.5;

/// The FE modes against the test modes.
#[derive(Clone, Debug, PartialEq)]
pub struct Pairing {
    pub fe_frequencies_hz: Vec<f64>,
    /// MAC[test mode][FE mode] at the DOFs both have.
    pub mac: Vec<Vec<f64>>,
    /// (test mode, FE mode), each used once, MAC ≥ [`PAIR_MAC`], best first.
    pub pairs: Vec<(usize, usize)>,
    /// Measured outputs the deck has.
    pub common_dofs: usize,
    /// (output, its FE node and DOF, sign of the output in the DOF's sense)
    /// of those outputs, in output order.
    pub measured: Vec<(usize, (u32, Dof), f64)>,
    /// The FE modes at every node, for the mode-shape viewer.
    pub fe_shapes: FeShapes,
}

/// Solves the deck's lowest modes and pairs them with `id`'s modes.
pub fn pair_with_deck(deck: &Deck, id: &Identification) -> Result<Pairing, String> {
    let fe = model::build(deck, &ParameterValues::new()).map_err(|e| e.to_string())?;
    model::check_mass(&fe).map_err(|e| e.to_string())?;
    let mut rows = Vec::new();
    let mut signs = Vec::new();
    let mut used = Vec::new();
    for (o, d) in id.data.outputs.iter().enumerate() {
        let node = u32::try_from(d.node).ok();
        if let Some((eq, sign)) = node.and_then(|n| fe.measured_dof(n, d.direction)) {
            rows.push(eq);
            signs.push(sign);
            used.push(o);
        }
    }
    if used.len() < 2 {
        return Err(format!(
            "the deck has {} of the {} measured DOFs; MAC needs at least 2",
            used.len(),
            id.data.outputs.len()
        ));
    }
    let count = (2 * id.modes.len() + 6).max(10);
    let modes = lowest_modes(
        &fe.stiffness,
        &fe.mass,
        &EigenOptions {
            count,
            expect_no_rigid_body_modes: fe.has_fixed_dofs,
            ..EigenOptions::default()
        },
    )
    .map_err(|e| e.to_string())?;
    let fe_shapes: Vec<Vec<c64>> = modes
        .at(&rows)
        .into_iter()
        .map(|v| {
            v.iter()
                .zip(&signs)
                .map(|(x, s)| c64::from(x * s))
                .collect()
        })
        .collect();
    let mac_m: Vec<Vec<f64>> = id
        .modes
        .iter()
        .map(|m| {
            let psi: Vec<c64> = used.iter().map(|&o| m.shape[o]).collect();
            fe_shapes.iter().map(|phi| mac(&psi, phi)).collect()
        })
        .collect();
    let mut cells: Vec<(usize, usize)> = (0..mac_m.len())
        .flat_map(|t| (0..fe_shapes.len()).map(move |f| (t, f)))
        .filter(|&(t, f)| mac_m[t][f] >= PAIR_MAC)
        .collect();
    cells.sort_by(|a, b| mac_m[b.0][b.1].total_cmp(&mac_m[a.0][a.1]));
    let mut pairs: Vec<(usize, usize)> = Vec::new();
    for (t, f) in cells {
        if pairs.iter().all(|p| p.0 != t && p.1 != f) {
            pairs.push((t, f));
        }
    }
    pairs.sort();
    let measured = used
        .iter()
        .zip(&rows)
        .zip(&signs)
        .map(|((&o, &eq), &s)| (o, fe.dofs.equations[eq], s))
        .collect();
    Ok(Pairing {
        fe_frequencies_hz: modes.frequencies_hz(),
        mac: mac_m,
        pairs,
        common_dofs: used.len(),
        measured,
        fe_shapes: nodal::fe_shapes(deck, &fe, &modes),
    })
}

/// A test's modes and their pairing with a deck's.
#[derive(Clone, Debug)]
pub struct PairedModes {
    pub identification: Identification,
    pub pairing: Pairing,
}

/// The modes of `test` identified as `frfup identify` does (whole band,
/// default orders), paired with the modes of `deck`; why not, when either
/// step fails.
pub fn identify_and_pair(deck: &Deck, test: &MeasuredFrfs) -> Result<PairedModes, String> {
    let identification = identify(test, &IdentifyOptions::default()).map_err(|e| e.to_string())?;
    let pairing = pair_with_deck(deck, &identification)?;
    Ok(PairedModes {
        identification,
        pairing,
    })
}
