//! Unit tests of `src/report/viewer/mod.rs` through its public interface.

use frfup::model::Dof;
use frfup::model::ParameterValues;
use frfup::report::viewer::*;
use frfup::solvers::eigen::nodal;
use frfup::solvers::eigen::{lowest_modes, EigenOptions};

/// A plane cantilever of 4 beams, measured in z at nodes 3 and 5 with
/// the first mode's values scaled by −2: the drawn test shape is the
/// mode again (sign aligned, largest translation 1) at the measured
/// nodes, node 4 halfway between them, node 2 between the clamp (0) and
/// node 3; the FE shape's largest translation is 1; the drawn MAC is 1.
#[test]
fn shapes_are_scaled_aligned_and_filled_in() {
    let deck = frfup_parsers::deck::parse(
        "analysis plane\nmaterial s E=2e11 rho=7800\nsection c A=1e-4 Iy=1e-9\nnode 1 0 0 0\nnode 2 1 0 0\nnode 3 2 0 0\nnode 4 3 0 0\nnode 5 4 0 0\nbeam 1 1 2 s c\nbeam 2 2 3 s c\nbeam 3 3 4 s c\nbeam 4 4 5 s c\nfix 1 all\n",
    )
    .unwrap();
    let fe = frfup::model::build(&deck, &ParameterValues::new()).unwrap();
    let modes = lowest_modes(
        &fe.stiffness,
        &fe.mass,
        &EigenOptions {
            count: 3,
            ..EigenOptions::default()
        },
    )
    .unwrap();
    let shapes = nodal::fe_shapes(&deck, &fe, &modes);
    let points = [(3, Dof::Z), (5, Dof::Z)];
    let phi: Vec<f64> = [2, 4]
        .iter()
        .map(|&i| shapes.nodal.values[0][i][2])
        .collect();
    let pair = Partner {
        test_mode: 0,
        fe_mode: 0,
        test_hz: 1.0,
        mac: 1.0,
        test: phi.iter().map(|v| -2.0 * v).collect(),
    };
    let v = build(&deck, &shapes, &points, &[pair], ("t", "f"));
    let p = &v.pairs[0];
    assert_eq!(v.measured[2], [false, false, true]);
    assert_eq!(v.measured[3], [false; 3]);
    assert!(v.plane);
    let fe_max = p.fe.iter().flatten().fold(0.0f64, |m, x| m.max(x.abs()));
    assert!((fe_max - 1.0).abs() < 1e-12);
    let tip = p.fe[4][2];
    assert!((p.test[4][2] - tip.signum()).abs() < 1e-12, "{:?}", p.test);
    assert!((p.test[2][2] / p.test[4][2] - phi[0] / phi[1]).abs() < 1e-12);
    assert!((p.test[3][2] - 0.5 * (p.test[2][2] + p.test[4][2])).abs() < 1e-9);
    assert!((p.test[1][2] - 0.5 * p.test[2][2]).abs() < 1e-9);
    assert_eq!(p.test[0], [0.0; 3]);
    assert!((drawn_mac(&v, p) - 1.0).abs() < 1e-12);
}
