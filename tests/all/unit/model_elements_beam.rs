//! Unit tests of `src/model/elements/beam.rs` through its public interface.

use frfup::model::elements::beam::*;
use frfup_parsers::deck::Theory;

fn props() -> BeamProperties<f64> {
    BeamProperties {
        e: 2.0e11,
        g: 8.0e10,
        rho: 7800.0,
        a: 1e-3,
        iy: 2e-7,
        iz: 3e-7,
        j: 4e-7,
        ky: 5.0 / 6.0,
        kz: 5.0 / 6.0,
    }
}

#[test]
fn eb_matches_textbook_entries() {
    let p = props();
    let l = 0.5;
    let k = local_stiffness(&p, l, Theory::EulerBernoulli);
    let ei = p.e * p.iy;
    assert!((k[(2, 2)] - 12.0 * ei / l.powi(3)).abs() < 1e-6 * k[(2, 2)]);
    // θy = −dw/dx: coupling w1–θy1 is −6EI/L².
    assert!((k[(2, 4)] + 6.0 * ei / (l * l)).abs() < 1e-6 * k[(2, 2)]);
    assert!((k[(1, 5)] - 6.0 * p.e * p.iz / (l * l)).abs() < 1e-6 * k[(1, 1)]);
    let m = local_mass(&p, l, Theory::EulerBernoulli);
    let ml = p.rho * p.a * l;
    assert!((m[(1, 1)] - 156.0 * ml / 420.0).abs() < 1e-12);
    assert!((m[(2, 4)] + 22.0 * l * ml / 420.0).abs() < 1e-12);
    assert!((k - k.transpose()).amax() == 0.0);
    assert!((m - m.transpose()).amax() == 0.0);
}
