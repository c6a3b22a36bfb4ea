//! Unit tests of `src/report/html.rs` through its public interface.

use frfup::report::html::*;

#[test]
fn escaping_and_numbers() {
    assert_eq!(esc("<a & \"b\">"), "&lt;a &amp; &quot;b&quot;&gt;");
    assert_eq!(signed(-0.00001, 3), "0.000");
    assert_eq!(signed(-1.5, 1), "−1.5");
    assert_eq!(signed(1.5, 1), "+1.5");
    assert_eq!(signed(f64::NAN, 1), "–");
}
