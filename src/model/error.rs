//! Errors of model building.

use std::fmt;

use frfup_parsers::deck::{DeckError, Pos};

/// Why a deck could not be turned into an FE model. Errors tied to a
/// statement carry its position; Display gives `line:column: message` (the
/// caller prefixes the file name).
#[derive(Clone, Debug, PartialEq)]
pub enum ModelError {
    /// The deck fails the spec's checks (see `Deck::validate`).
    Deck(DeckError),
    /// A beam whose two nodes coincide.
    ZeroLength { beam: u32, pos: Pos, length: f64 },
    /// A beam whose `orient` vector is parallel to its axis.
    OrientParallel { beam: u32, pos: Pos },
    /// A parameter value names no `param` of the deck.
    UnknownParameter { name: String },
    /// A parameter value is not finite.
    NonFiniteParameter { name: String, value: f64 },
    /// Parameter values make a property zero or negative (p ≤ −1).
    NonPositiveProperty { name: String, value: f64, pos: Pos },
    /// No free DOF is left (no elements, or everything fixed).
    NoDofs,
    /// The sparse matrix could not be created (out of memory).
    Sparse(String),
    /// A value no structure has (a coordinate beyond 1e9 m, E beyond 1e15 Pa
    /// ...): a unit or typing error that would otherwise overflow.
    Implausible { pos: Pos, message: String },
    /// A free DOF without mass (M_ii ≤ 0): the eigenproblem is singular.
    NoMass { node: u32, dof: &'static str },
}

impl ModelError {
    /// The deck position of the statement at fault, if any.
    pub fn pos(&self) -> Option<Pos> {
        match self {
            ModelError::Deck(e) => Some(e.pos()),
            ModelError::ZeroLength { pos, .. }
            | ModelError::OrientParallel { pos, .. }
            | ModelError::NonPositiveProperty { pos, .. }
            | ModelError::Implausible { pos, .. } => Some(*pos),
            _ => None,
        }
    }
}

impl fmt::Display for ModelError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ModelError::Deck(e) => write!(f, "{e}"),
            ModelError::ZeroLength { beam, pos, length } => write!(
                f,
                "{pos}: beam {beam} has zero length ({length:e} m): its two nodes coincide"
            ),
            ModelError::OrientParallel { beam, pos } => write!(
                f,
                "{pos}: orient of beam {beam} is parallel to the beam axis; give a vector with a component normal to N1→N2"
            ),
            ModelError::UnknownParameter { name } => {
                write!(f, "parameter `{name}` is not defined by a `param` statement of the deck")
            }
            ModelError::NonFiniteParameter { name, value } => {
                write!(f, "parameter `{name}` has the non-finite value {value}")
            }
            ModelError::NonPositiveProperty { name, value, pos } => write!(
                f,
                "{pos}: parameter `{name}` = {value} makes a property zero or negative (relative changes must exceed −1)"
            ),
            ModelError::NoDofs => write!(f, "the model has no free degree of freedom"),
            ModelError::Sparse(s) => write!(f, "sparse assembly failed: {s}"),
            ModelError::Implausible { pos, message } => write!(f, "{pos}: {message}"),
            ModelError::NoMass { node, dof } => write!(
                f,
                "node {node} DOF {dof} is free but has no mass (M = 0): connect it to a beam, give it a `mass` (with rotary inertia for a rotation) or `fix` it"
            ),
        }
    }
}

impl std::error::Error for ModelError {}

impl From<DeckError> for ModelError {
    fn from(e: DeckError) -> Self {
        ModelError::Deck(e)
    }
}
