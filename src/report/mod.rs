//! Reports people look at: charts (SVG) and a self-contained HTML page of an
//! updating run.

pub mod charts;
