//! Solvers on assembled models: the generalised eigenproblem ([`eigen`]) and
//! forced response ([`frf`]).
//!
//! CONTRACT (shared with `updating` and the CLI): items marked CONTRACT keep
//! their names and meaning; add freely around them.

pub(crate) mod bandwidth;
pub mod eigen;
pub mod frf;
pub(crate) mod nested_dissection;
pub(crate) mod sparse_ops;
