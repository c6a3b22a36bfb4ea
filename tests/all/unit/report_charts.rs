//! Unit tests of `src/report/charts/mod.rs` through its public interface.

pub mod test_util {
    /// Loose well-formedness check: one `<svg` root, balanced tags.
    pub fn assert_svg(s: &str) {
        assert!(
            s.starts_with("<svg"),
            "not an SVG: {}",
            &s[..s.len().min(80)]
        );
        assert!(s.trim_end().ends_with("</svg>"));
        let mut depth = 0i64;
        let bytes = s.as_bytes();
        let mut i = 0;
        while let Some(off) = s[i..].find('<') {
            let start = i + off;
            let end = start + s[start..].find('>').expect("unclosed tag");
            let tag = &s[start..=end];
            if tag.starts_with("</") {
                depth -= 1;
            } else if !tag.ends_with("/>") && !tag.starts_with("<?") && !tag.starts_with("<!") {
                depth += 1;
            }
            assert!(depth >= 0, "unbalanced at {start}");
            i = end + 1;
            let _ = bytes;
        }
        assert_eq!(depth, 0, "unbalanced tags");
        assert!(
            !s.contains("NaN") && !s.contains("inf"),
            "non-finite number in SVG"
        );
    }
}

use frfup::report::charts::*;

#[test]
fn ticks_and_labels() {
    assert_eq!(nice_step(0.13), 0.2);
    assert_eq!(nice_step(7.0), 10.0);
    assert_eq!(decimals_for(0.25), 1);
    assert_eq!(decimals_for(0.2), 1);
    assert_eq!(decimals_for(5.0), 0);
    assert_eq!(fmt_fixed(-0.0001, 2), "0.00");
    assert_eq!(fmt_fixed(f64::NAN, 2), "–");
    assert_eq!(pow10_label(-6), "10⁻⁶");
    assert_eq!(pow10_label(3), "10³");
    assert_eq!(
        log_ticks(2.0, 200.0),
        vec![2.0, 5.0, 10.0, 20.0, 50.0, 100.0, 200.0]
    );
    assert_eq!(log_ticks(30.0, 80.0), vec![30.0, 50.0, 70.0]);
    assert!(log_ticks(0.0, 1.0).is_empty());
    assert_eq!(log_tick_label(0.05), "0.05");
    assert_eq!(log_tick_label(200.0), "200");
    let (a, b) = padded_range(0.0, 0.0, 0.05);
    assert!(a < b);
    let (a, b) = padded_range(f64::NAN, 1.0, 0.05);
    assert!(a < b);
}

#[test]
fn stagger_separates_close_labels() {
    let rows = stagger(&[(100.0, 30.0), (105.0, 30.0), (300.0, 30.0)], 2.0, 3);
    assert_eq!(rows, vec![0, 1, 0]);
    assert!(abbreviate("a very long parameter name", 12.0, 60.0).ends_with('…'));
    assert_eq!(abbreviate("short", 12.0, 200.0), "short");
}

#[test]
fn runs_break_at_nan() {
    let r = finite_runs(vec![(0.0, 1.0), (1.0, f64::NAN), (2.0, 3.0), (3.0, 4.0)]);
    assert_eq!(r.len(), 2);
    assert_eq!(r[1].len(), 2);
}
