//! Solvers on assembled models: the generalised eigenproblem ([`eigen`]) and
//! forced response ([`frf`]).
//!
//! Used by `updating`, `diagnosis` and the command line.

pub mod bandwidth;
pub mod dense;
pub mod eigen;
pub mod frf;
pub mod nested_dissection;
pub mod sparse_ops;
pub mod vector_state;
