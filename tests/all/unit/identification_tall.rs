//! Unit tests of `src/identification/tall.rs`: the whole-band LSFD by
//! normal equations over blocks of lines.

use faer::c64;
use frfup::identification::lsfd::{design, evaluate, rhs, solve, Residual};
use frfup::identification::prepare::{Dof, Prepared};
use frfup::identification::tall::{fit_lines, CHUNK};
use frfup::solvers::dense::product;

/// A receptance record of `lines` lines over 1–200 Hz, three outputs of
/// one input, two modes, with a deterministic ripple of `noise` relative.
fn record(lines: usize, noise: f64) -> (Prepared, Vec<c64>, Vec<Vec<c64>>) {
    let poles = vec![c64::new(-3.0, 250.0), c64::new(-6.0, 750.0)];
    let residues = vec![
        vec![
            c64::new(0.0, -2.0),
            c64::new(0.5, -1.0),
            c64::new(-0.2, 1.5),
        ],
        vec![c64::new(0.1, -3.0), c64::new(0.0, 2.0), c64::new(0.3, -0.7)],
    ];
    let hz: Vec<f64> = (0..lines)
        .map(|k| 1.0 + 199.0 * k as f64 / (lines - 1) as f64)
        .collect();
    let omega: Vec<f64> = hz.iter().map(|f| 2.0 * std::f64::consts::PI * f).collect();
    let res = Residual {
        upper: 1e-3,
        lower: -2.0,
    };
    let h: Vec<Vec<c64>> = (0..3)
        .map(|j| {
            let a: Vec<c64> = residues.iter().map(|r| r[j]).collect();
            omega
                .iter()
                .enumerate()
                .map(|(k, &w)| {
                    let v = evaluate(&poles, &a, &res, w, 0);
                    v * (1.0 + noise * ((k * 7 + j * 3) as f64).sin())
                })
                .collect()
        })
        .collect();
    let dof = |node| Dof { node, direction: 3 };
    let data = Prepared {
        frequencies_hz: hz,
        omega,
        first_line: 0,
        kind_order: 0,
        outputs: vec![dof(1), dof(2), dof(3)],
        inputs: vec![dof(1)],
        channels: vec![0, 1, 2],
        h,
        weights: vec![1.0, 2.0, 0.5],
        left_out: Vec::new(),
        reciprocal: false,
    };
    (data, poles, residues)
}

/// Noise-free data over three chunks: the residues come back to 1e-9
/// (the normal equations' κ²ε after one refinement step), every line's
/// residual at rounding level.
#[test]
fn the_residues_of_noise_free_data_come_back() {
    let (data, poles, residues) = record(2 * CHUNK + 500, 0.0);
    let all: Vec<usize> = (0..data.n_lines()).collect();
    let fit = fit_lines(&data, &poles, &all, true).unwrap();
    for (r, row) in residues.iter().enumerate() {
        for (j, a) in row.iter().enumerate() {
            let got = c64::new(fit.x[(2 * r, j)], fit.x[(2 * r + 1, j)]);
            assert!(
                (got - a).norm() < 1e-9 * a.norm(),
                "mode {r} FRF {j}: {got} vs {a}"
            );
        }
    }
    assert_eq!(fit.per_line.len(), data.n_lines());
    let peak = data
        .h
        .iter()
        .flatten()
        .map(|v| v.norm_sqr())
        .fold(0.0, f64::max);
    assert!(fit.per_line.iter().all(|&e| e < 1e-20 * peak));
}

/// Noisy data on a subset of lines spanning chunks: the same solution
/// as the SVD of the whole design (lsfd::solve) to 1e-9, and the same
/// per-line residuals as the direct B − A x.
#[test]
fn the_chunked_normal_equations_agree_with_the_svd() {
    let (data, poles, _) = record(3 * CHUNK, 0.02);
    let lines: Vec<usize> = (0..data.n_lines()).step_by(2).collect();
    let fit = fit_lines(&data, &poles, &lines, true).unwrap();
    let a = design(&poles, &data.omega, &lines, 0);
    let b = rhs(&data, &lines);
    let svd = solve(&a, &b).unwrap();
    let scale = svd.norm_l2();
    assert!((&fit.x - &svd).norm_l2() < 1e-9 * scale);
    let r = &b - product(a.as_ref(), fit.x.as_ref());
    for (k, e) in fit.per_line.iter().enumerate() {
        let direct: f64 = (0..3)
            .map(|j| data.weights[j].powi(2) * (r[(2 * k, j)].powi(2) + r[(2 * k + 1, j)].powi(2)))
            .sum();
        assert!((e - direct).abs() <= 1e-12 * direct.max(1e-300), "line {k}");
    }
}
