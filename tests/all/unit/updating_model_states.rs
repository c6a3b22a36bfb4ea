//! Unit tests of `src/updating/model_states.rs` through its public interface.

use frfup::updating::model_states::*;

#[test]
fn median_and_nearest() {
    assert_eq!(median(vec![3.0, f64::NAN, 1.0, 2.0]), Some(2.0));
    assert_eq!(median(vec![1.0, 2.0]), Some(1.5));
    assert_eq!(median(vec![]), None);
    assert_eq!(nearest(&[1.0, 2.0, 3.0], 2.0000001), Some(1));
    assert_eq!(nearest(&[1.0, 2.0], 2.5), None);
    assert_eq!(nearest(&[], 2.5), None);
}
