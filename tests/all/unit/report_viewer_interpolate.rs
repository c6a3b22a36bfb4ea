//! Unit tests of `src/report/viewer/interpolate.rs` through its public interface.

use frfup::report::viewer::interpolate::*;

/// A chain 0–1–2–3–4 on x at 0, 1, 3, 4, 6 m: measured at nodes 0 (1.0)
/// and 3 (−0.5): node 1 and 2 lie on the straight line between them
/// (arc length 1 and 3 of 4), node 4 beyond the last keeps −0.5.
#[test]
fn a_chain_interpolates_linearly_in_arc_length() {
    let xs = [0.0, 1.0, 3.0, 4.0, 6.0];
    let xyz: Vec<[f64; 3]> = xs.iter().map(|&x| [x, 0.0, 0.0]).collect();
    let beams = [[0, 1], [1, 2], [2, 3], [3, 4]];
    let g = Graph::new(&xyz, &beams);
    let mut v = vec![[0.0; 3]; 5];
    v[0][2] = 1.0;
    v[3][2] = -0.5;
    let mut measured = vec![[false; 3]; 5];
    measured[0][2] = true;
    measured[3][2] = true;
    let out = g.fill(&v, &measured, &[[true; 3]; 5]);
    let want = [1.0, 1.0 - 1.5 / 4.0, 1.0 - 1.5 * 3.0 / 4.0, -0.5, -0.5];
    for (o, w) in out.iter().zip(want) {
        assert!((o[2] - w).abs() < 1e-12, "{out:?}");
        assert_eq!((o[0], o[1]), (0.0, 0.0));
    }
    // A fixed node holds 0: node 4 clamped pulls nothing beyond node 3,
    // but a clamped node 2 splits the chain's values.
    let mut free = vec![[true; 3]; 5];
    free[2][2] = false;
    let out = g.fill(&v, &measured, &free);
    assert!((out[1][2] - 2.0 / 3.0).abs() < 1e-12, "{out:?}");
    assert_eq!(out[2][2], 0.0);
}
