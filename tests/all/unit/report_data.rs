//! Unit tests of `src/report/data.rs` through its public interface.

use frfup::report::data::*;

#[test]
fn mac_columns_keep_band_and_pairs() {
    let hz: Vec<f64> = (0..100).map(|i| i as f64).collect();
    let lines = [0.0, 10.0, 20.0];
    let c = mac_columns(&hz, &lines, &[50]);
    assert_eq!(c.first(), Some(&5));
    assert!(c.contains(&23) && !c.contains(&24) && c.contains(&50));
}
