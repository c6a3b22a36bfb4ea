//! Unit tests of `src/updating/frequencies.rs` through its public interface.

use faer::c64;
use frfup::updating::frequencies::*;

/// Mobility of two SDOF modes (10 Hz, ζ 1 %; 25 Hz, ζ 2 %) on 0..40 Hz.
fn two_modes() -> (Vec<f64>, Vec<Vec<c64>>) {
    let lines: Vec<f64> = (0..=4000).map(|i| i as f64 * 0.01).collect();
    let modes = [(10.0, 0.01, 1.0), (25.0, 0.02, 0.5)];
    let ch: Vec<c64> = lines
        .iter()
        .map(|&f| {
            let w = 2.0 * std::f64::consts::PI * f;
            let mut h = c64::new(0.0, 0.0);
            for &(fr, z, a) in &modes {
                let wr = 2.0 * std::f64::consts::PI * fr;
                h += c64::new(a, 0.0) / c64::new(wr * wr - w * w, 2.0 * z * w * wr);
            }
            h * c64::new(0.0, w)
        })
        .collect();
    (lines, vec![ch])
}

#[test]
fn picks_two_modes_with_damping() {
    let (lines, ch) = two_modes();
    let res = pick_peaks(&lines, &indicator(&ch), &PeakOptions::default());
    assert_eq!(res.len(), 2, "{res:?}");
    assert!((res[0].frequency_hz - 10.0).abs() < 0.005, "{res:?}");
    // The first mode's tail shifts the summed-magnitude peak slightly.
    assert!((res[1].frequency_hz - 25.0).abs() < 0.06, "{res:?}");
    let z0 = res[0].damping_ratio.unwrap();
    let z1 = res[1].damping_ratio.unwrap();
    assert!((z0 - 0.01).abs() < 0.001, "{z0}");
    assert!((z1 - 0.02).abs() < 0.002, "{z1}");
}

#[test]
fn eq42_frequencies_on_lines() {
    let (lines, ch) = two_modes();
    let res = pick_peaks(&lines, &indicator(&ch), &PeakOptions::default());
    let u = UpdatingFrequencies::around_resonances(&res, 2, 0.08, &lines);
    let hz = u.hz();
    assert_eq!(hz.len(), 4);
    for (got, want) in hz.iter().zip([9.2, 10.8, 23.0, 27.0]) {
        assert!((got - want).abs() < 0.06, "{got} vs {want}");
    }
    // A frequency inside a neighbour's half-power band is skipped.
    let u = UpdatingFrequencies::around_resonances(&res, 2, 1.5, &lines);
    assert!(u.skipped.iter().any(|s| s.reason.contains("outside")));
    let close = [
        Resonance {
            frequency_hz: 10.0,
            line: 1000,
            damping_ratio: Some(0.01),
            prominence: 10.0,
        },
        Resonance {
            frequency_hz: 10.5,
            line: 1050,
            damping_ratio: Some(0.01),
            prominence: 10.0,
        },
    ];
    let u = UpdatingFrequencies::around_resonances(&close, 2, 0.05, &lines);
    // 10·1.05 sits on the second resonance, 10.5·0.95 inside the first's band.
    assert_eq!(u.len(), 2);
    assert_eq!(u.skipped.len(), 2);
    // Explicit frequencies snap and dedupe.
    let u = UpdatingFrequencies::explicit(&[6.004, 6.001, 50.0, 24.0], &lines);
    assert_eq!(u.hz(), vec![6.0, 24.0]);
    assert_eq!(u.skipped.len(), 2);
}

#[test]
fn no_peaks_in_flat_or_tiny_data() {
    assert!(pick_peaks(&[0.0, 1.0], &[1.0, 2.0], &PeakOptions::default()).is_empty());
    let lines: Vec<f64> = (0..100).map(f64::from).collect();
    assert!(pick_peaks(&lines, &vec![1.0; 100], &PeakOptions::default()).is_empty());
    assert_eq!(nearest_line(&lines, -3.0), 0);
    assert_eq!(nearest_line(&lines, 1e9), 99);
    assert_eq!(nearest_line(&lines, 4.6), 5);
}
