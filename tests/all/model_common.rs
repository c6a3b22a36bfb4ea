//! Shared helpers of the `model_*` test modules.
#![allow(dead_code)]

use frfup::model::{build, FeModel, ParameterValues, SparseMatrix};
use frfup::parsers::deck::{parse, Deck};
use nalgebra::DMatrix;

pub fn deck(text: &str) -> Deck {
    match parse(text) {
        Ok(d) => d,
        Err(e) => panic!("deck error {e}\n{text}"),
    }
}

pub fn model(text: &str) -> FeModel {
    model_at(text, &ParameterValues::new())
}

pub fn model_at(text: &str, values: &ParameterValues) -> FeModel {
    match build(&deck(text), values) {
        Ok(m) => m,
        Err(e) => panic!("model error {e}\n{text}"),
    }
}

/// Dense copy of a sparse matrix.
pub fn dense(a: &SparseMatrix) -> DMatrix<f64> {
    let d = a.to_dense();
    DMatrix::from_fn(d.nrows(), d.ncols(), |i, j| d[(i, j)])
}

/// Generalised eigenvalues λ = ω² of K x = λ M x (dense, via the Cholesky
/// factor of M: L⁻¹ K L⁻ᵀ), ascending. Independent of `frfup::solvers`.
pub fn eigenvalues(k: &DMatrix<f64>, m: &DMatrix<f64>) -> Vec<f64> {
    let l = m.clone().cholesky().expect("M positive definite").l();
    let x = l.solve_lower_triangular(k).expect("L invertible");
    let c = l
        .solve_lower_triangular(&x.transpose())
        .expect("L invertible");
    let c = (&c + c.transpose()) * 0.5;
    let mut ev: Vec<f64> = c.symmetric_eigenvalues().iter().copied().collect();
    ev.sort_by(|a, b| a.total_cmp(b));
    ev
}

/// Natural frequencies (Hz) of a model, ascending; negative λ (round-off of
/// rigid-body modes) map to −√|λ|/2π.
pub fn frequencies_hz(fe: &FeModel) -> Vec<f64> {
    eigenvalues(&dense(&fe.stiffness), &dense(&fe.mass))
        .into_iter()
        .map(|l| l.signum() * l.abs().sqrt() / (2.0 * std::f64::consts::PI))
        .collect()
}

/// Straight beam along +x from 0 to `length` with `n` elements, node ids
/// 1..=n+1, beam ids 1..=n; `extra` lines appended (materials, fixes, …).
pub fn line_deck(analysis: &str, n: usize, length: f64, beam_opts: &str, extra: &str) -> String {
    let mut s = format!("analysis {analysis}\n");
    for i in 0..=n {
        s += &format!("node {} {:e} 0 0\n", i + 1, length * i as f64 / n as f64);
    }
    for i in 1..=n {
        s += &format!("beam {i} {i} {} mat sec {beam_opts}\n", i + 1);
    }
    s += extra;
    s
}

/// Max-abs of a dense matrix.
pub fn amax(a: &DMatrix<f64>) -> f64 {
    a.iter().fold(0.0, |m, v| m.max(v.abs()))
}
