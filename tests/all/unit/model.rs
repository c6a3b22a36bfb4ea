//! Unit tests of `src/model/mod.rs` through its public interface.

use faer::c64;
use frfup::model::Damping;

/// d_r(ω) of a unit-mass oscillator with stiffness k = ω_r² is its
/// dynamic stiffness k − ω² + iω c (viscous, c = 2ζω_r or α + βk) or
/// k(1 + iη) − ω² (hysteretic), written out here independently.
#[test]
fn modal_denominator_is_the_oscillators_dynamic_stiffness() {
    let (k, w) = (400.0_f64, 17.0_f64);
    let cases = [
        (Damping::None, c64::new(k - w * w, 0.0)),
        (
            Damping::Modal { zeta: 0.02 },
            c64::new(k - w * w, 0.0) + c64::new(0.0, w) * (2.0 * 0.02 * 20.0),
        ),
        (
            Damping::Rayleigh {
                alpha: 0.3,
                beta: 1e-4,
            },
            c64::new(k - w * w, 0.0) + c64::new(0.0, w) * (0.3 + 1e-4 * k),
        ),
        (
            Damping::Hysteretic { eta: 0.05 },
            c64::new(k, 0.0) * c64::new(1.0, 0.05) - w * w,
        ),
    ];
    for (damping, expected) in cases {
        let d = damping.modal_denominator(k, w);
        assert!(
            (d - expected).norm() <= 1e-13 * k,
            "{damping:?}: {d} vs {expected}"
        );
    }
    // A rigid-body mode's round-off (ω_r² slightly below 0) adds no
    // negative damping.
    let d = Damping::Hysteretic { eta: 0.05 }.modal_denominator(-1e-9, w);
    assert_eq!(d.im, 0.0);
    assert_eq!(d.re, -1e-9 - w * w);
}

/// Four significant digits, also where rounding carries into the next
/// decade (0.0099998 reads 0.01000, not 0.010000; 999999.7 goes to e
/// notation as 1e6 does).
#[test]
fn four_significant_digits_across_a_decade() {
    use frfup::model::sig;
    assert_eq!(sig(0.0099998), "0.01000");
    assert_eq!(sig(0.0100006), "0.01000");
    assert_eq!(sig(0.012345), "0.01235");
    assert_eq!(sig(9999.7), "10000");
    assert_eq!(sig(999999.7), "1.000e6");
    assert_eq!(sig(0.00099996), "0.001000");
    assert_eq!(sig(3.1819963e-6), "3.182e-6");
    assert_eq!(sig(-0.0099998), "-0.01000");
}
