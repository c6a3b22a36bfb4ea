//! frfup: make a finite-element model agree with a vibration test.
//!
//! The library is layered and data flows one way: each module uses only the
//! modules of its own layer or of the layers before it (`tests/layering.rs`
//! checks every `crate::` path, and that no two modules import each other).
//!
//! 1. `frfup_parsers` (UFF files, model decks; its own crate) and [`fsio`]
//!    (bounded reads, atomic writes);
//! 2. [`testdata`] (measured FRFs) and [`model`] (FE matrices);
//! 3. [`solvers`] (modes, FRFs) and [`identification`] (modes identified
//!    from measured FRFs: LSCF poles, automatic selection, LSFD residues);
//! 4. [`simulate`] (measured-style FRFs computed from a model);
//! 5. [`benchmark`] (random updating cases with known truths);
//! 6. [`updating`] (the FRF updating method of Yan & Golinval, and the
//!    robust pipeline around it);
//! 7. [`diagnosis`] (the physics a model lacks);
//! 8. [`report`] (every file of an update or a diagnosis: JSON, CSV tables,
//!    the updated deck, Markdown, charts and pages);
//! 9. [`tasks`] (read the inputs, run, write a result folder; the error type
//!    with its exit code shared by the layers above);
//! 10. [`batch`] (campaigns of updates for CI);
//! 11. [`commands`] (the command line's other tasks).
//!
//! The `frfup` binary (`src/main.rs`) parses the command line and calls this
//! library; nothing here depends on it.

// Checks are written `!(x >= limit)` on purpose: a NaN must fail them.
#![allow(clippy::neg_cmp_op_on_partial_ord)]
// No unsafe code; a kernel of `solvers` that needs some allows it there,
// with the reason it is sound.
#![deny(unsafe_code)]

pub use frfup_parsers as parsers;

// In layer order (see above).
pub mod fsio;

pub mod model;
pub mod testdata;

pub mod solvers;

pub mod identification;

pub mod simulate;

pub mod benchmark;

pub mod updating;

pub mod diagnosis;

pub mod report;

pub mod tasks;

pub mod batch;

pub mod commands;
