//! `frf_change`, the benchmark's measure of how visible an effect is (FRF
//! change in noise units), on hand-made FRFs.

use faer::c64;
use frfup::benchmark::frf_change;
use frfup::testdata::{Channel, FrfKind, MeasuredFrfs};

fn frfs(channels: &[[f64; 3]]) -> MeasuredFrfs {
    MeasuredFrfs {
        frequencies_hz: vec![1.0, 2.0, 3.0],
        kind: FrfKind::Receptance,
        channels: channels
            .iter()
            .enumerate()
            .map(|(i, v)| Channel {
                response_node: i as i64 + 1,
                response_direction: 3,
                reference_node: 1,
                reference_direction: 3,
                values: v.iter().map(|&x| c64::new(x, 0.0)).collect(),
            })
            .collect(),
    }
}

/// A change of 1 % on one of two channels at 1 % noise: one noise unit
/// on that channel's lines, so √(1/2) over the campaign.
#[test]
fn a_change_is_counted_in_noise_units_of_its_channel() {
    let reference = frfs(&[[1.0, 2.0, 2.0], [4.0, 4.0, 4.0]]);
    let other = frfs(&[[1.0, 2.0, 2.0], [4.04, 4.04, 4.04]]);
    let d = frf_change(&reference, &other, 0.01);
    assert!((d - 0.5f64.sqrt()).abs() < 1e-12, "{d}");
}

/// A channel the reference leaves at rounding level (zero by symmetry)
/// whose rounding changes by 100 % is no visible change (seed-1
/// diagnosis case 290 drew a support spring of 5.8e-5 relative frequency
/// shift as "3.2e125 noise units" this way); a response that appears
/// there at 1e-4 of the strongest channel is.
#[test]
fn rounding_on_a_silent_channel_is_not_a_change() {
    let reference = frfs(&[[1.0, 1.0, 1.0], [1e-17, -1e-17, 1e-17]]);
    let rounding = frfs(&[[1.0, 1.0, 1.0], [-1e-17, 1e-17, 2e-17]]);
    assert!(frf_change(&reference, &rounding, 0.01) < 1e-6);
    let visible = frfs(&[[1.0, 1.0, 1.0], [1e-4, 1e-4, 1e-4]]);
    let d = frf_change(&reference, &visible, 0.01);
    // 1e-4 / (0.01 × 1e-8) on half the lines.
    assert!((d - 1e6 * 0.5f64.sqrt()).abs() < 1.0, "{d}");
}
