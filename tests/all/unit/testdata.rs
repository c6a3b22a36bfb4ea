//! Unit tests of `src/testdata/mod.rs` through its public interface.

use faer::c64;
use frfup::testdata::{i_omega_power, FrfKind};

/// (iω)^p against repeated multiplication by iω (or by 1/(iω)), and the
/// kinds' factors against their definitions.
#[test]
fn i_omega_powers_are_repeated_products() {
    let w = 3.7;
    let iw = c64::new(0.0, w);
    let mut up = c64::new(1.0, 0.0);
    let mut down = c64::new(1.0, 0.0);
    for p in 0..=2 {
        assert!((i_omega_power(w, p) - up).norm() <= 1e-15 * up.norm());
        assert!((i_omega_power(w, -p) - down).norm() <= 1e-15 * down.norm());
        up *= iw;
        down /= iw;
    }
    assert_eq!(FrfKind::Receptance.from_receptance(w), c64::new(1.0, 0.0));
    assert_eq!(FrfKind::Mobility.from_receptance(w), iw);
    assert_eq!(
        FrfKind::Accelerance.from_receptance(w),
        c64::new(-w * w, 0.0)
    );
}
