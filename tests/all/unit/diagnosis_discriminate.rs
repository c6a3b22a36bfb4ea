//! Unit tests of `src/diagnosis/discriminate.rs` through its public interface.

use frfup::diagnosis::discriminate::*;

#[test]
fn the_band_is_where_the_difference_stays_above_half() {
    let d = [0.0, 1.0, 3.0, 6.0, 4.0, 2.9, 3.5];
    assert_eq!(half_band(&d, 3, 6.0), (2, 4));
    let a = vec![faer::c64::new(10.0, 0.0); 9];
    let b = vec![faer::c64::new(1.0, 0.0); 9];
    // 20 dB everywhere above the floor; nothing under it.
    assert!(smoothed_db(&a, &b, 0.5)
        .iter()
        .all(|v| (v - 20.0).abs() < 1e-12));
    assert!(smoothed_db(&a, &b, 2.0).iter().all(|v| *v == 0.0));
}
