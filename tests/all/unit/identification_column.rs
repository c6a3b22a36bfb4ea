//! Unit tests of `src/identification/column.rs`: the identification as the
//! update calls it.

const TWO_PI: f64 = 2.0 * std::f64::consts::PI;
use faer::c64;

use crate::modal_synth::{close_and_weak_modes, synth};
use frfup::identification::identify_column;
use frfup::testdata::FrfKind;
use frfup::updating::correlation::mac;

/// The FRFs in the kind their noise was added in (−ω² × receptance).
fn accelerance(lines: &[f64], h: &[Vec<c64>]) -> Vec<Vec<c64>> {
    h.iter()
        .map(|ch| {
            ch.iter()
                .zip(lines)
                .map(|(x, &f)| x * -(TWO_PI * f).powi(2))
                .collect()
        })
        .collect()
}

/// Two modes 0.65 Hz apart (1 % damping, one peak in the indicator), a
/// weak mode and a well separated one; 1.5 % noise. The fit must find all
/// four: frequencies within 0.05 %, damping within 15 %, MAC > 0.99, and
/// the modal constants' signs.
#[test]
fn separates_close_modes_and_finds_weak_ones() {
    let lines: Vec<f64> = (0..=800).map(|i| i as f64 * 0.25).collect();
    let modes = close_and_weak_modes();
    let h = accelerance(&lines, &synth(&lines, &modes, 0, 0.015));
    let found = identify_column(&lines, FrfKind::Accelerance, &h).unwrap();
    assert_eq!(found.len(), 4, "{found:#?}");
    for (m, (f, z, phi)) in found.iter().zip(&modes) {
        assert!((m.frequency_hz / f - 1.0).abs() < 5e-4, "{m:?} vs {f}");
        assert!((m.damping_ratio / z - 1.0).abs() < 0.15, "{m:?} vs {z}");
        let mac = mac(&m.shape, phi);
        assert!(mac > 0.99, "MAC {mac} for {f} Hz");
        // Signed as the modal constants φ_c·φ_ref (reference: channel 0).
        for (c, s) in m.shape.iter().enumerate() {
            let q = phi[c] * phi[0];
            if q.abs() > 0.2 * phi[0].abs() {
                assert_eq!(
                    (m.constant_sign * s).signum(),
                    q.signum(),
                    "{f} Hz, channel {c}"
                );
            }
        }
    }
}

/// Noise alone gives no modes.
#[test]
fn noise_alone_is_not_a_mode() {
    let lines: Vec<f64> = (0..=400).map(|i| i as f64 * 0.25).collect();
    let modes = vec![(40.0, 0.01, vec![1.0, 0.5, -0.5])];
    let h = synth(&lines, &modes, 0, 0.015);
    let found = identify_column(&lines, FrfKind::Accelerance, &accelerance(&lines, &h)).unwrap();
    assert_eq!(found.len(), 1, "{found:#?}");
    assert!((found[0].frequency_hz - 40.0).abs() < 0.02);
}
