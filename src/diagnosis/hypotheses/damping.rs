//! `damping`: the global damping model (modal ζ, Rayleigh α/β or hysteretic
//! η). A model without damping has infinite peaks, so some damping is always
//! fitted along with every other hypothesis; this module chooses its form
//! and writes it into a deck.

use frfup_parsers::deck::{DampingModel, DampingStatement, Deck, Pos};

use crate::model::Damping;

use super::super::fit::DampingForm;

/// The forms tried, simplest first.
pub const FORMS: [DampingForm; 3] = [
    DampingForm::Modal,
    DampingForm::Hysteretic,
    DampingForm::Rayleigh,
];

/// The deck's damping as a model value.
pub fn of_deck(deck: &Deck) -> Damping {
    Damping::of_deck(deck)
}

/// `deck` with its `damping` statement replaced.
pub fn with_damping(deck: &Deck, d: Damping) -> Deck {
    let mut out = deck.clone();
    let model = match d {
        Damping::Modal { zeta } => Some(DampingModel::Modal { zeta }),
        Damping::Rayleigh { alpha, beta } => Some(DampingModel::Rayleigh { alpha, beta }),
        Damping::Hysteretic { eta } => Some(DampingModel::Hysteretic { eta }),
        Damping::None => None,
    };
    out.damping = model.map(|model| DampingStatement {
        model,
        pos: Pos::default(),
    });
    out
}
