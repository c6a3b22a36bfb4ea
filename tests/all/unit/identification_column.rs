//! Unit tests of `src/identification/column.rs`: the identification as the
//! update and the diagnosis call it.

const TWO_PI: f64 = 2.0 * std::f64::consts::PI;
use faer::c64;
use frfup::identification::identify_column;
use frfup::testdata::FrfKind;
use frfup::updating::correlation::mac;

/// Receptance of real modes (f Hz, ζ, shape) driven at channel `reference`,
/// with complex noise `noise` × each channel's accelerance RMS.
fn synth(
    lines: &[f64],
    modes: &[(f64, f64, Vec<f64>)],
    reference: usize,
    noise: f64,
) -> Vec<Vec<c64>> {
    let nch = modes[0].2.len();
    let mut seed = 0x2545_f491_4f6c_dd1du64;
    let mut gauss = move || {
        // Box–Muller on a xorshift generator.
        let mut u = || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        let (a, b) = (u().max(1e-300), u());
        (-2.0 * a.ln()).sqrt() * (TWO_PI * b).cos()
    };
    (0..nch)
        .map(|c| {
            let acc: Vec<c64> = lines
                .iter()
                .map(|&f| {
                    let w = TWO_PI * f;
                    let mut h = c64::new(0.0, 0.0);
                    for (fr, z, phi) in modes {
                        let wr = TWO_PI * fr;
                        h += c64::new(phi[c] * phi[reference], 0.0)
                            / c64::new(wr * wr - w * w, 2.0 * z * w * wr);
                    }
                    h * (-w * w)
                })
                .collect();
            let rms = (acc.iter().map(|v| v.norm_sqr()).sum::<f64>() / acc.len() as f64).sqrt();
            acc.iter()
                .zip(lines)
                .map(|(a, &f)| {
                    let w = TWO_PI * f;
                    let a = a + c64::new(gauss(), gauss()) * (noise * rms / 2f64.sqrt());
                    if w > 0.0 {
                        a / (-w * w)
                    } else {
                        c64::new(0.0, 0.0)
                    }
                })
                .collect()
        })
        .collect()
}

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
    let modes = vec![
        (16.24, 0.010, vec![1.0, 0.8, 0.5, -0.3, 0.2, 0.1]),
        (36.78, 0.010, vec![1.0, 0.9, -0.7, -1.0, 0.3, 0.4]),
        (37.43, 0.010, vec![0.9, 0.8, 0.7, 1.0, -0.2, 0.5]),
        (60.75, 0.012, vec![0.1, -0.05, 0.08, 0.12, 1.0, -0.9]),
    ];
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
