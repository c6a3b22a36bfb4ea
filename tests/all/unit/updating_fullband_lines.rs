//! The informative lines of a long record (`updating::fullband::lines`)
//! and the fitting data built on them (`TestData::new`): every line near a
//! resonance kept, a sparse background, the whole record kept beside for
//! the identification.

use faer::c64;
use frfup::diagnosis::data::TestData;
use frfup::diagnosis::suspension_placement::identified_modes;
use frfup::testdata::{Channel, FrfKind, MeasuredFrfs};
use frfup::updating::fullband::lines::{informative_lines, BACKGROUND, LINE_BUDGET};

/// Natural frequencies (Hz) of the long record: a free-free steel bar's
/// first three bending modes, damping 1e-4 (half-power half-width 0.03 to
/// 0.14 Hz, under the 0.125 Hz line spacing at the first).
const MODES_HZ: [f64; 3] = [266.13, 733.61, 1438.17];
const ZETA: f64 = 1e-4;
/// Lines and spacing: 40,000 lines of 0.125 Hz.
const LINES: usize = 40_000;
const DF: f64 = 0.125;

/// Accelerance of the three modes at four channels (mode shapes of a
/// free-free bar at four points), with 0.1 % relative noise from a fixed
/// linear congruential sequence.
fn long_record() -> MeasuredFrfs {
    let lines: Vec<f64> = (1..=LINES).map(|i| i as f64 * DF).collect();
    let shapes = [
        [1.0, -0.6, 0.3],
        [0.4, 0.9, -0.8],
        [-0.7, 0.2, 1.0],
        [0.9, 0.5, 0.6],
    ];
    let mut seed: u64 = 12345;
    let mut noise = move || {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((seed >> 11) as f64 / (1u64 << 53) as f64) - 0.5
    };
    let channels = shapes
        .iter()
        .enumerate()
        .map(|(c, phi)| {
            let values = lines
                .iter()
                .map(|&f| {
                    let w = 2.0 * std::f64::consts::PI * f;
                    let h: c64 = MODES_HZ
                        .iter()
                        .zip(phi)
                        .map(|(&fr, &a)| {
                            let wr = 2.0 * std::f64::consts::PI * fr;
                            let d = c64::new(wr * wr - w * w, 2.0 * ZETA * wr * w);
                            c64::new(-w * w * a, 0.0) / d
                        })
                        .sum();
                    h * c64::new(1.0 + 1e-3 * noise(), 1e-3 * noise())
                })
                .collect();
            Channel {
                response_node: c as i64 + 1,
                response_direction: 3,
                reference_node: 1,
                reference_direction: 3,
                values,
            }
        })
        .collect();
    MeasuredFrfs {
        frequencies_hz: lines,
        kind: FrfKind::Accelerance,
        channels,
    }
}

#[test]
fn a_record_within_the_budget_keeps_every_line() {
    let lines: Vec<f64> = (1..=LINE_BUDGET).map(|i| i as f64).collect();
    let kept = informative_lines(&lines, &[]);
    assert_eq!(kept, (0..LINE_BUDGET).collect::<Vec<_>>());
}

#[test]
fn a_long_record_keeps_its_resonances_and_a_sparse_background() {
    let test = long_record();
    let data = TestData::new(&test).unwrap();
    let n = data.lines_hz.len();
    // The background (BACKGROUND lines) plus a few hundred lines per peak.
    assert!(
        n > BACKGROUND && n < BACKGROUND + 3 * 250,
        "{n} lines kept of {LINES}"
    );
    let record = data.record.as_ref().expect("the whole record is kept");
    assert_eq!(record.lines_hz, test.frequencies_hz);
    assert_eq!(data.omegas.len(), n);
    for c in 0..data.channels.len() {
        assert_eq!((data.values[c].len(), data.weight[c].len()), (n, n));
    }
    assert_eq!(data.lines_hz.first(), test.frequencies_hz.first());
    assert_eq!(data.lines_hz.last(), test.frequencies_hz.last());
    // Every line within ±3 lines (±0.375 Hz) of each resonance is kept:
    // the peak and both half-power flanks at this spacing.
    for f in MODES_HZ {
        let near: Vec<f64> = test
            .frequencies_hz
            .iter()
            .copied()
            .filter(|x| (x - f).abs() <= 3.0 * DF + 1e-9)
            .collect();
        assert_eq!(near.len(), 6, "lines near {f} Hz");
        for x in near {
            assert!(
                data.lines_hz.contains(&x),
                "line {x} Hz beside the resonance at {f} Hz dropped"
            );
        }
    }
    // The picked resonances index the kept lines.
    for f in MODES_HZ {
        let r = data
            .resonances
            .iter()
            .find(|r| (r.frequency_hz - f).abs() < DF)
            .unwrap_or_else(|| panic!("no resonance picked at {f} Hz"));
        assert!((data.lines_hz[r.line] - f).abs() <= DF / 2.0 + 1e-9);
    }
}

#[test]
fn the_identification_runs_on_the_whole_record() {
    let data = TestData::new(&long_record()).unwrap();
    let modes = identified_modes(&data);
    for f in MODES_HZ {
        let m = modes
            .iter()
            .find(|m| (m.frequency_hz / f - 1.0).abs() < 1e-4)
            .unwrap_or_else(|| panic!("{f} Hz not identified: {modes:?}"));
        // Damping 1e-4 on 0.125 Hz lines: the peak is one line wide; the
        // fit on the even axis still finds ζ within 20 %.
        assert!(
            (m.damping_ratio / ZETA - 1.0).abs() < 0.2,
            "ζ {} at {f} Hz",
            m.damping_ratio
        );
        assert!((data.lines_hz[m.line] - m.frequency_hz).abs() <= DF / 2.0 + 1e-9);
    }
}
