//! Unit tests of `src/updating/identify.rs` through its public interface.

const TWO_PI: f64 = 2.0 * std::f64::consts::PI;
use faer::c64;

use crate::modal_synth::{close_and_weak_modes, synth};
use frfup::updating::correlation::mac;
use frfup::updating::identify::*;

fn indicator_of(lines: &[f64], h: &[Vec<c64>]) -> Vec<f64> {
    let mob: Vec<Vec<c64>> = h
        .iter()
        .map(|ch| {
            ch.iter()
                .zip(lines)
                .map(|(x, &f)| x * c64::new(0.0, TWO_PI * f))
                .collect()
        })
        .collect();
    frfup::updating::frequencies::indicator(&mob)
}

/// Two modes 0.65 Hz apart (1 % damping, one peak in the indicator), a
/// weak mode and a well separated one; 1.5 % noise. The fit must find all
/// four: frequencies within 0.05 %, damping within 15 %, MAC > 0.99.
#[test]
fn separates_close_modes_and_finds_weak_ones() {
    let lines: Vec<f64> = (0..=800).map(|i| i as f64 * 0.25).collect();
    let modes = close_and_weak_modes();
    let h = synth(&lines, &modes, 0, 0.015);
    let ind = indicator_of(&lines, &h);
    let found = identify_modes(&lines, &h, &ind, &IdentifyOptions::default());
    assert_eq!(found.len(), 4, "{found:#?}");
    for (m, (f, z, phi)) in found.iter().zip(&modes) {
        assert!((m.frequency_hz / f - 1.0).abs() < 5e-4, "{m:?} vs {f}");
        assert!((m.damping_ratio / z - 1.0).abs() < 0.15, "{m:?} vs {z}");
        let mac = mac(&m.shape, phi);
        assert!(mac > 0.99, "MAC {mac} for {f} Hz");
    }
}

/// Noise alone gives no modes.
#[test]
fn noise_alone_is_not_a_mode() {
    let lines: Vec<f64> = (0..=400).map(|i| i as f64 * 0.25).collect();
    let modes = vec![(40.0, 0.01, vec![1.0, 0.5, -0.5])];
    let h = synth(&lines, &modes, 0, 0.015);
    let ind = indicator_of(&lines, &h);
    let found = identify_modes(&lines, &h, &ind, &IdentifyOptions::default());
    assert_eq!(found.len(), 1, "{found:#?}");
    assert!((found[0].frequency_hz - 40.0).abs() < 0.02);
}
