//! Unit tests of `src/identification/prepare.rs`.

use frfup::identification::prepare::window_max;

/// Against the direct maximum over every clipped window, on a sequence
/// with plateaus, ties and both ends (the queue's edge cases).
#[test]
fn the_sliding_maximum_is_the_direct_one() {
    let s: Vec<f64> = (0..200)
        .map(|k| ((k * 37 % 23) as f64 * 0.5).floor() + if k % 17 == 0 { 9.0 } else { 0.0 })
        .collect();
    for w in [0, 1, 3, 10, 250] {
        let direct: Vec<f64> = (0..s.len())
            .map(|k| {
                s[k.saturating_sub(w)..(k + w + 1).min(s.len())]
                    .iter()
                    .fold(f64::NEG_INFINITY, |a, &b| a.max(b))
            })
            .collect();
        assert_eq!(window_max(&s, w), direct, "w = {w}");
    }
}
