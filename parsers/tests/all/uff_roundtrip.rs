//! Write → read round trips for every ordinate type × even/uneven ×
//! ASCII/binary, byte-exact output, and pyuff's reading of a file we write
//! (`tests/expected/uff_written.uff`, read by `scripts/uff_expected.py` into
//! `tests/expected/uff_written_pyuff.json`). Regenerate the file with
//! `UFF_BLESS=1 cargo test -p frfup-parsers --test all uff_roundtrip::`, then rerun
//! the script.

use frfup_parsers::uff::{
    self, Abscissa, AxisCharacteristics, ByteOrder, Complex64, Dataset, Function58, Ordinate,
    WriteOptions,
};
use serde_json::Value;

fn axis(data_type: i32, l: i32, f: i32, label: &str, units: &str) -> AxisCharacteristics {
    AxisCharacteristics {
        data_type,
        length_exponent: l,
        force_exponent: f,
        temperature_exponent: 0,
        label: label.into(),
        units_label: units.into(),
    }
}

/// Deterministic test values spanning magnitudes and signs.
fn value(i: usize, k: usize, double: bool) -> f64 {
    let base = ((i * 7 + k * 3) % 11) as f64 - 5.0;
    let scale = match (i + k) % 4 {
        0 => 1e-3,
        1 => 1.0,
        2 => 1e4,
        _ if double => 1e-120,
        _ => 1e-20,
    };
    (base + 0.123456789012345 * (k as f64 + 1.0)) * scale / 3.0
}

/// A function of `n` points with the given layout.
fn function(ordinate_type: i32, even: bool, binary: bool, n: usize) -> Function58 {
    let double = matches!(ordinate_type, 4 | 6);
    let ordinate = if matches!(ordinate_type, 2 | 4) {
        Ordinate::Real((0..n).map(|i| value(i, 0, double)).collect())
    } else {
        Ordinate::Complex(
            (0..n)
                .map(|i| Complex64::new(value(i, 0, double), value(i, 1, double)))
                .collect(),
        )
    };
    let abscissa = if even {
        Abscissa::Even {
            start: 1.25,
            step: 0.1953125,
        }
    } else {
        Abscissa::Uneven(
            (0..n)
                .map(|i| 10.0 * 1.0123456789f64.powi(i as i32))
                .collect(),
        )
    };
    Function58 {
        id_lines: [
            format!(
                "FRF type {ordinate_type} {} {}",
                if even { "even" } else { "uneven" },
                if binary { "58b" } else { "58" }
            ),
            "Mesure café".into(),
            "28-Jan-21 14:01:42".into(),
            String::new(),
            "NONE".into(),
        ],
        function_type: 4,
        function_id: 3,
        version: 1,
        load_case: 0,
        response_entity: "Mic 01".into(),
        response_node: 101,
        response_direction: -3,
        reference_entity: "NONE".into(),
        reference_node: 22,
        reference_direction: 1,
        ordinate_type,
        abscissa,
        z_axis_value: 0.0,
        abscissa_axis: axis(18, 0, 0, "Frequency", "Hz"),
        numerator_axis: axis(12, 1, 0, "Acceleration", "m/s²"),
        denominator_axis: axis(13, 0, 1, "Force", "N"),
        z_axis: axis(0, 0, 0, "NONE", "NONE"),
        ordinate,
        binary,
    }
}

/// All 16 layouts, n = 7 so that last data lines are short.
fn all_layouts() -> Vec<Function58> {
    let mut out = Vec::new();
    for binary in [false, true] {
        for t in [2, 4, 5, 6] {
            for even in [true, false] {
                out.push(function(t, even, binary, 7));
            }
        }
    }
    out
}

fn write(functions: &[Function58], options: &WriteOptions) -> Vec<u8> {
    let mut out = Vec::new();
    uff::write_functions_with(&mut out, functions, options).expect("writes");
    out
}

fn functions(file: &uff::UffFile) -> Vec<&Function58> {
    file.datasets
        .iter()
        .filter_map(|d| match d {
            Dataset::Function(f) => Some(f.as_ref()),
            Dataset::Other(_) => None,
        })
        .collect()
}

fn close(a: f64, b: f64, rel: f64) -> bool {
    (a - b).abs() <= rel * a.abs().max(b.abs())
}

/// Values as stored: binary single precision rounds to f32.
fn stored(v: f64, f: &Function58) -> f64 {
    if f.binary && matches!(f.ordinate_type, 2 | 5) {
        v as f32 as f64
    } else {
        v
    }
}

/// Relative tolerance of the printed precision: E13.5 → 5e-6, E20.12 → 5e-13.
fn tolerance(f: &Function58) -> (f64, f64) {
    if f.binary {
        (0.0, 0.0)
    } else if matches!(f.ordinate_type, 2 | 5) {
        (5.1e-6, 5.1e-6)
    } else {
        (5.1e-6, 5.1e-13) // uneven abscissa is E13.5 in ASCII
    }
}

fn assert_same(want: &Function58, got: &Function58) {
    let what = &want.id_lines[0];
    assert_eq!(want.binary, got.binary, "{what}");
    assert_eq!(want.ordinate_type, got.ordinate_type, "{what}");
    assert_eq!(want.len(), got.len(), "{what}");
    assert_eq!(want.id_lines[0..3], got.id_lines[0..3], "{what}");
    assert_eq!(
        got.id_lines[3], "NONE",
        "{what}: empty id lines are written as NONE"
    );
    assert_eq!(
        (
            want.function_type,
            want.function_id,
            want.version,
            want.load_case
        ),
        (
            got.function_type,
            got.function_id,
            got.version,
            got.load_case
        )
    );
    assert_eq!(
        (
            &want.response_entity,
            want.response_node,
            want.response_direction
        ),
        (
            &got.response_entity,
            got.response_node,
            got.response_direction
        )
    );
    assert_eq!(
        (
            &want.reference_entity,
            want.reference_node,
            want.reference_direction
        ),
        (
            &got.reference_entity,
            got.reference_node,
            got.reference_direction
        )
    );
    assert_eq!(want.abscissa_axis, got.abscissa_axis);
    assert_eq!(want.numerator_axis, got.numerator_axis);
    assert_eq!(want.denominator_axis, got.denominator_axis);
    assert_eq!(want.z_axis, got.z_axis);
    let (x_tol, y_tol) = tolerance(want);
    match (&want.abscissa, &got.abscissa) {
        // Record 7 keeps 7 significant digits (E13.5 columns, digits that fit).
        (Abscissa::Even { start: a, step: b }, Abscissa::Even { start: c, step: d }) => {
            assert!(
                close(*a, *c, 1e-7) && close(*b, *d, 1e-7),
                "{what}: {b} vs {d}"
            )
        }
        (Abscissa::Uneven(a), Abscissa::Uneven(b)) => a
            .iter()
            .zip(b)
            .for_each(|(p, q)| assert!(close(stored(*p, want), *q, x_tol), "{what}: x {p} vs {q}")),
        _ => panic!("{what}: spacing differs"),
    }
    assert_eq!(
        want.ordinate.is_complex(),
        got.ordinate.is_complex(),
        "{what}: ordinate kind differs"
    );
    assert_eq!(want.len(), got.len(), "{what}: points differ");
    // 58b single precision is kept as f32, exactly as stored.
    let single_kept = got.binary && matches!(got.ordinate_type, 2 | 5);
    assert_eq!(
        matches!(
            got.ordinate,
            Ordinate::RealSingle(_) | Ordinate::ComplexSingle(_)
        ),
        single_kept,
        "{what}: storage precision"
    );
    for i in 0..want.len() {
        let (p, q) = (want.ordinate.at(i), got.ordinate.at(i));
        let p = (stored(p.0, want), stored(p.1, want));
        let same = if want.binary {
            p.0.to_bits() == q.0.to_bits() && p.1.to_bits() == q.1.to_bits()
        } else {
            close(p.0, q.0, y_tol) && close(p.1, q.1, y_tol)
        };
        assert!(same, "{what}: point {i}: {p:?} vs {q:?}")
    }
}

#[test]
fn every_layout_round_trips() {
    for byte_order in [ByteOrder::Little, ByteOrder::Big] {
        let written = all_layouts();
        let bytes = write(&written, &WriteOptions { byte_order });
        let file = uff::parse(&bytes).unwrap_or_else(|e| panic!("{e}"));
        assert!(file.notes.is_empty(), "{:?}", file.notes);
        let read = functions(&file);
        assert_eq!(read.len(), written.len());
        for (w, r) in written.iter().zip(&read) {
            assert_same(w, r);
        }
        // Read → write → read gives the same values again, and the same bytes.
        let again: Vec<Function58> = read.iter().map(|f| (*f).clone()).collect();
        let bytes2 = write(&again, &WriteOptions { byte_order });
        let file2 = uff::parse(&bytes2).expect("reads back");
        assert_eq!(functions(&file2), read);
        assert_eq!(
            bytes2,
            write(&again, &WriteOptions { byte_order }),
            "writing is deterministic"
        );
    }
}

#[test]
fn long_functions_round_trip() {
    // Many lines, both spacings, point counts that leave short last lines.
    for t in [2, 4, 5, 6] {
        for even in [true, false] {
            for binary in [false, true] {
                let f = function(t, even, binary, 1001);
                let bytes = write(std::slice::from_ref(&f), &WriteOptions::default());
                let file = uff::parse(&bytes).expect("reads");
                assert_same(&f, functions(&file)[0]);
            }
        }
    }
}

#[test]
fn crlf_file_reads_like_lf() {
    let fs: Vec<Function58> = all_layouts().into_iter().filter(|f| !f.binary).collect();
    let lf = write(&fs, &WriteOptions::default());
    let crlf: Vec<u8> = lf
        .iter()
        .flat_map(|&b| {
            if b == b'\n' {
                vec![b'\r', b'\n']
            } else {
                vec![b]
            }
        })
        .collect();
    assert_eq!(
        uff::parse(&lf).expect("lf"),
        uff::parse(&crlf).expect("crlf")
    );
}

#[test]
fn parallel_parse_equals_one_by_one() {
    // > 1 MB so that blocks are parsed on several threads.
    let fs: Vec<Function58> = (0..64)
        .map(|k| function([2, 4, 5, 6][k % 4], k % 3 != 0, k % 5 == 0, 1500))
        .collect();
    let bytes = write(&fs, &WriteOptions::default());
    assert!(bytes.len() > 1 << 20);
    let whole = uff::parse(&bytes).expect("reads");
    let one_by_one: Vec<Function58> = fs
        .iter()
        .map(|f| {
            let b = write(std::slice::from_ref(f), &WriteOptions::default());
            functions(&uff::parse(&b).expect("reads"))[0].clone()
        })
        .collect();
    assert_eq!(
        functions(&whole).into_iter().cloned().collect::<Vec<_>>(),
        one_by_one
    );
    for _ in 0..3 {
        assert_eq!(uff::parse(&bytes).expect("reads"), whole);
    }
    // The first error in file order is reported whatever the threads do.
    let mut broken = bytes.clone();
    let cut = broken.len() / 2;
    let pos = cut
        + broken[cut..]
            .iter()
            .position(|&b| b == b'e')
            .expect("an exponent");
    broken[pos] = b'x';
    let e1 = uff::parse(&broken).expect_err("broken");
    for _ in 0..3 {
        assert_eq!(uff::parse(&broken).expect_err("broken"), e1);
    }
}

#[test]
fn writer_rejects_what_it_cannot_write() {
    let mut f = function(5, true, false, 3);
    f.ordinate = Ordinate::Complex(vec![Complex64::new(1.0, f64::NAN); 3]);
    assert!(uff::write_functions(&mut Vec::new(), &[f]).is_err());
    let mut f = function(2, true, false, 3);
    f.ordinate_type = 6;
    assert!(
        uff::write_functions(&mut Vec::new(), &[f]).is_err(),
        "real ordinate with type 6"
    );
    let mut f = function(2, false, false, 3);
    f.abscissa = Abscissa::Uneven(vec![1.0]);
    assert!(
        uff::write_functions(&mut Vec::new(), &[f]).is_err(),
        "abscissa length"
    );
    let mut f = function(2, true, true, 3);
    f.ordinate = Ordinate::Real(vec![1e300; 3]);
    assert!(
        uff::write_functions(&mut Vec::new(), &[f]).is_err(),
        "beyond single precision"
    );
    let mut f = function(2, true, false, 3);
    f.response_node = 12_345_678_901;
    assert!(
        uff::write_functions(&mut Vec::new(), &[f]).is_err(),
        "node wider than I10"
    );
}

const GOLDEN: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/tests/expected/uff_written.uff"
);

#[test]
fn golden_file() {
    let bytes = write(&all_layouts(), &WriteOptions::default());
    if std::env::var_os("UFF_BLESS").is_some() {
        std::fs::write(GOLDEN, &bytes).expect("bless");
    }
    let golden =
        std::fs::read(GOLDEN).expect("tests/expected/uff_written.uff (UFF_BLESS=1 to create)");
    assert!(
        golden == bytes,
        "writer output changed; if intended: UFF_BLESS=1 and rerun scripts/uff_expected.py"
    );
}

fn number(v: &Value) -> f64 {
    v.as_f64().unwrap_or(f64::NAN)
}

#[test]
fn pyuff_reads_our_file() {
    let text = include_str!("../expected/uff_written_pyuff.json");
    let pyuff: Value = serde_json::from_str(text).expect("json");
    let ours = all_layouts();
    let sets = pyuff["functions"].as_array().expect("functions");
    assert_eq!(sets.len(), ours.len());
    for (f, p) in ours.iter().zip(sets) {
        let what = &f.id_lines[0];
        assert_eq!(p["binary"].as_i64(), Some(i64::from(f.binary)), "{what}");
        assert_eq!(
            p["ord_data_type"].as_i64(),
            Some(i64::from(f.ordinate_type)),
            "{what}"
        );
        let (x_tol, y_tol) = tolerance(f);
        let xs = p["x"].as_array().expect("x");
        let ys = p["y"].as_array().expect("y");
        assert_eq!(ys.len(), f.len(), "{what}: pyuff point count");
        for (i, x) in xs.iter().enumerate() {
            // pyuff recomputes an even abscissa from record 7 (7 digits).
            let tol = if matches!(f.abscissa, Abscissa::Even { .. }) {
                1e-7
            } else {
                x_tol
            };
            assert!(
                close(stored(f.abscissa_at(i), f), number(x), tol),
                "{what}: x[{i}] {x}"
            );
        }
        for (i, y) in ys.iter().enumerate() {
            let (re, im) = f.ordinate.at(i);
            let want: Vec<f64> = if f.ordinate.is_complex() {
                vec![stored(re, f), stored(im, f)]
            } else {
                vec![stored(re, f)]
            };
            let got: Vec<f64> = match y {
                Value::Array(a) => a.iter().map(number).collect(),
                v => vec![number(v)],
            };
            assert_eq!(want.len(), got.len(), "{what}");
            for (a, b) in want.iter().zip(&got) {
                let ok = if f.binary {
                    a.to_bits() == b.to_bits()
                } else {
                    close(*a, *b, y_tol)
                };
                assert!(ok, "{what}: y[{i}] ours {a} pyuff {b}");
            }
        }
    }
}
