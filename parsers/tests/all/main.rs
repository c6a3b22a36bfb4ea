//! The integration tests of `frfup-parsers`, one test binary: each module is
//! one former `tests/*.rs` file, its tests named `module::test`. Run one
//! module with `cargo test -p frfup-parsers --test all module::`.

mod deck_parse;
mod uff_errors;
mod uff_nodal;
mod uff_real;
mod uff_roundtrip;
mod uff_stream;
mod uff_stream_buffers;
