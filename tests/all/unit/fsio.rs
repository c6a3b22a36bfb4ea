//! Unit tests of `src/fsio.rs` through its public interface.

mod csv_number_tests {
    use frfup::fsio::{csv_number, csv_number_sig};

    /// Seven significant digits, plain or scientific by magnitude, never 0e0.
    #[test]
    fn fixed_precision_numbers_follow_the_same_rule() {
        for (x, text) in [
            (0.0, "0"),
            (-0.0, "0"),
            (4.413691234e-3, "0.004413691"),
            (0.2270088, "0.2270088"),
            (-1.5e-5, "-1.5e-5"),
            (1.2345678e-7, "1.234568e-7"),
            (2.0, "2"),
            (123456.78, "123456.8"),
            (9.9999999e5, "1e6"),
            (3.0e7, "3e7"),
            (f64::NAN, ""),
        ] {
            assert_eq!(csv_number_sig(x, 7), text, "{x}");
        }
    }

    /// Plain or scientific by magnitude, and every one reads back exactly.
    #[test]
    fn numbers_read_back_and_never_say_0e0() {
        for (x, text) in [
            (0.0, "0"),
            (-0.0, "0"),
            (0.11431826140688388, "0.11431826140688388"),
            (-0.9, "-0.9"),
            (10.0, "10"),
            (1.5e-5, "1.5e-5"),
            (2.0e7, "2e7"),
            (f64::NAN, ""),
        ] {
            assert_eq!(csv_number(x), text);
            if x.is_finite() {
                assert_eq!(text.parse::<f64>().unwrap(), x);
            }
        }
    }
}
