//! Unit tests of the library's modules, one file per source file
//! (`src/a/b.rs` → `a_b.rs`), through their public interfaces: in the one
//! test binary, so that the library is compiled once for the tests.

mod batch_campaign;
mod diagnosis_discriminate;
mod diagnosis_folds;
mod diagnosis_prior;
mod diagnosis_suspension_placement;
mod diagnosis_verdict;
mod fsio;
mod identification_column;
mod model;
mod model_elements_beam;
mod report_charts;
mod report_charts_convergence;
mod report_charts_frequencies;
mod report_charts_frf_overlay;
mod report_charts_localisation;
mod report_charts_mac;
mod report_charts_sfdac;
mod report_data;
mod report_diagnosis;
mod report_diagnosis_page;
mod report_html;
mod report_prose;
mod report_tables;
mod report_viewer;
mod report_viewer_interpolate;
mod solvers_bandwidth;
mod solvers_eigen_dense;
mod solvers_eigen_lanczos;
mod solvers_eigen_tridiagonal;
mod solvers_nested_dissection;
mod solvers_sparse_ops;
mod testdata;
mod testdata_layout;
mod updating_correlation;
mod updating_frequencies;
mod updating_fullband_jacobian;
mod updating_fullband_lm;
mod updating_fullband_reduced;
mod updating_identify;
mod updating_model_states;
mod updating_options;
mod updating_sensitivity;
mod updating_serep;
mod updating_svd_solve;
