//! Unit tests of `src/report/diagnosis/page.rs` through its public interface.

#[test]
fn a_missing_percentage_is_a_dash_without_its_unit() {
    assert_eq!(frfup::report::diagnosis::page::percent(f64::NAN), "–");
    assert_eq!(frfup::report::diagnosis::page::percent(0.009), "0.009 %");
}
