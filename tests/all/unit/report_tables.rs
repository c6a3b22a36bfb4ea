//! Unit tests of `src/report/tables.rs` through its public interface.

use frfup::report::tables::*;

#[test]
fn fields_and_numbers() {
    assert_eq!(
        csv_text([["a,b", "say \"x\"", ""], ["1", "2", "3"]]),
        "\"a,b\",\"say \"\"x\"\"\",\n1,2,3\n"
    );
    assert_eq!(e6(f64::NAN), "");
    assert_eq!(e6(-0.0), "0");
    assert_eq!(e6(0.0), "0");
    assert_eq!(e6(-1.5e-5), "-1.5e-5");
    assert_eq!(e6(0.01979010), "0.0197901");
    assert_eq!(f6(-0.0), "0.000000");
    assert_eq!(f6(1.5), "1.500000");
}
