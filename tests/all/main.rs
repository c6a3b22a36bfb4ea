//! The integration tests of `frfup`, one test binary (one link of the
//! numerical dependencies instead of one per file): each module is one
//! former `tests/*.rs` file, its tests named `module::test`. Run one module
//! with `cargo test --test all module::`.

mod campaign_doc;
mod campaign_support;
mod cli_support;
mod modal_synth;
mod model_common;
mod png_support;
mod solvers_support;
mod unit;

mod cli_batch;
mod cli_csv;
mod cli_demo;
mod cli_files;
mod cli_help;
mod cli_identify;
mod cli_json;
mod cli_layouts;
mod cli_mac;
mod cli_model;
mod cli_progress;
mod cli_shapes;
mod cli_uff;
mod data_error_lines;
mod data_errors;
mod diagnose_benchmark;
mod diagnose_cases;
mod diagnose_priors;
mod diagnose_tell_apart;
mod hostile_inputs;
mod identification_closed_form;
mod identification_records;
mod layering;
mod modal_predictor;
mod model_closed_form;
mod model_derivatives;
mod model_invariants;
mod random_benchmark;
mod report_browser;
mod report_render;
mod report_status;
mod report_viewer;
mod solvers_eigen;
mod solvers_frf;
mod updating_hard_cases;
mod updating_paper;
