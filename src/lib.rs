//! frfup: make a finite-element model agree with a vibration test.
//!
//! Data flows one way, one module per stage:
//!
//! `frfup_parsers` (UFF files, model decks) → [`testdata`] (measured FRFs) and
//! [`model`] (FE matrices) → [`solvers`] (modes, FRFs) → [`updating`]
//! (the FRF updating method of Yan & Golinval) → reports.
//!
//! The `frfup` binary is a thin layer over this library.

// Checks are written `!(x >= limit)` on purpose: a NaN must fail them.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

pub mod diagnosis;
pub mod fsio;
pub mod model;
pub mod report;
pub mod simulate;
pub mod solvers;
pub mod tasks;
pub mod testdata;
pub mod updating;

pub use frfup_parsers as parsers;
pub mod batch;
pub mod benchmark;
pub mod commands;
