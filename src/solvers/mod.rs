//! Solvers on assembled models: the generalised eigenproblem ([`eigen`]) and
//! forced response ([`frf`]).
//!
//! Used by `updating`, `diagnosis` and the command line.

pub(crate) mod bandwidth;
pub mod dense;
pub mod eigen;
pub mod frf;
pub(crate) mod nested_dissection;
pub(crate) mod sparse_ops;
