//! The FE modes at every node of a deck, as the viewer draws them.

use frfup_parsers::deck::Deck;

use crate::model::{Dof, FeModel};
use crate::report::shapes::{self, NodalModes};
use crate::solvers::eigen::Modes;

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
    let nodal = shapes::fe_modes(deck, fe, modes, "");
    let free = nodal
        .nodes
        .iter()
        .map(|&n| [Dof::X, Dof::Y, Dof::Z].map(|d| fe.dofs.index(n, d).is_some()))
        .collect();
    FeShapes { nodal, free }
}
