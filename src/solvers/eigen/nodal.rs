//! The modes at the nodes of a deck: the FE modes at every node (fixed
//! translations 0) and any shapes known at (node, DOF) points, arranged as
//! three translations per node in the global axes. What the reports draw and
//! `frfup modes` writes; computed here, beside the eigen solution.

use frfup_parsers::deck::Deck;

use crate::model::{Dof, FeModel};
use crate::solvers::eigen::Modes;

/// Modes as translations at nodes.
#[derive(Clone, Debug, PartialEq)]
pub struct NodalModes {
    /// What the modes are, e.g. "FE mode" or "test mode (fitted)".
    pub kind: String,
    /// Where they come from (a file name), for the UFF id lines.
    pub source: String,
    pub frequencies_hz: Vec<f64>,
    /// Viscous damping ratio of each mode, when known.
    pub damping_ratios: Option<Vec<f64>>,
    /// Node ids, ascending.
    pub nodes: Vec<u32>,
    /// [mode][node] translations (x, y, z); 0 where the shape is not known.
    pub values: Vec<Vec<[f64; 3]>>,
    /// [node]: which of x, y, z the shapes know (the CSV leaves the others
    /// empty; UFF 55 has no such mark and carries 0).
    pub known: Vec<[bool; 3]>,
}

fn axis(d: Dof) -> Option<usize> {
    match d {
        Dof::X => Some(0),
        Dof::Y => Some(1),
        Dof::Z => Some(2),
        _ => None,
    }
}

/// `shapes` ([mode][point]) at the translational `points` (node, FE DOF),
/// one entry per distinct node.
pub fn at_points(
    kind: &str,
    source: &str,
    frequencies_hz: &[f64],
    damping_ratios: Option<Vec<f64>>,
    points: &[(u32, Dof)],
    shapes: &[Vec<f64>],
) -> NodalModes {
    let mut nodes: Vec<u32> = points
        .iter()
        .filter(|(_, d)| axis(*d).is_some())
        .map(|(n, _)| *n)
        .collect();
    nodes.sort_unstable();
    nodes.dedup();
    let mut known = vec![[false; 3]; nodes.len()];
    for (n, d) in points {
        if let (Some(a), Ok(i)) = (axis(*d), nodes.binary_search(n)) {
            known[i][a] = true;
        }
    }
    let values = shapes
        .iter()
        .map(|shape| {
            let mut v = vec![[0.0; 3]; nodes.len()];
            for (k, (n, d)) in points.iter().enumerate() {
                if let (Some(a), Ok(i)) = (axis(*d), nodes.binary_search(n)) {
                    v[i][a] = shape.get(k).copied().unwrap_or(0.0);
                }
            }
            v
        })
        .collect();
    NodalModes {
        kind: kind.into(),
        source: source.into(),
        frequencies_hz: frequencies_hz[..shapes.len().min(frequencies_hz.len())].to_vec(),
        damping_ratios,
        nodes,
        values,
        known,
    }
}

/// The FE modes at every node of the deck (fixed DOFs 0), mass-normalised.
pub fn fe_modes(deck: &Deck, fe: &FeModel, modes: &Modes, source: &str) -> NodalModes {
    let points: Vec<(u32, Dof)> = fe.dofs.equations.clone();
    let eqs: Vec<usize> = (0..points.len()).collect();
    let mut set = at_points(
        "FE mode",
        source,
        &modes.frequencies_hz(),
        None,
        &points,
        &modes.at(&eqs),
    );
    // Nodes with no free translation (clamped) still belong to the picture.
    let mut all: Vec<u32> = deck.nodes.iter().map(|n| n.id).collect();
    all.sort_unstable();
    // A fixed translation is known: it is 0.
    set.known = vec![[true; 3]; all.len()];
    for v in &mut set.values {
        *v = all
            .iter()
            .map(|n| match set.nodes.binary_search(n) {
                Ok(i) => v[i],
                Err(_) => [0.0; 3],
            })
            .collect();
    }
    set.nodes = all;
    set
}

/// The FE modes at every node of a deck and which translations are free.
#[derive(Clone, Debug, PartialEq)]
pub struct FeShapes {
    /// Every node of the deck, ascending ids.
    pub nodal: NodalModes,
    /// [node] translation free (not fixed, in the analysis' plane).
    pub free: Vec<[bool; 3]>,
}

/// `modes` of `fe` (built from `deck`) at every node.
pub fn fe_shapes(deck: &Deck, fe: &FeModel, modes: &Modes) -> FeShapes {
    let nodal = fe_modes(deck, fe, modes, "");
    let free = nodal
        .nodes
        .iter()
        .map(|&n| [Dof::X, Dof::Y, Dof::Z].map(|d| fe.dofs.index(n, d).is_some()))
        .collect();
    FeShapes { nodal, free }
}
