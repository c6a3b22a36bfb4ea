//! Bad input gives an `UffError` naming line (or byte offset), dataset index
//! and number, and what was expected; real-world quirks are read.

use frfup_parsers::uff::{self, Dataset, UffError};

const HEADER: &str = "    -1
    58
Quirk test
NONE
01-Jan-25 00:00:00
NONE
NONE
    4         1    1         0 NONE               7   3 NONE               1   3
";

const AXES: &str = "        18    0    0    0 Frequency            Hz
        12    1    0    0 Acceleration         m/s^2
        13    0    1    0 Force                N
         0    0    0    0 NONE                 NONE
";

/// An ASCII 58 with the given record 7 and data lines.
fn ascii58(record7: &str, data: &str) -> Vec<u8> {
    format!("{HEADER}{record7}\n{AXES}{data}    -1\n").into_bytes()
}

/// `uff::parse`, checked against the streaming reader with tiny and normal
/// chunks, on one and two threads: same result, same first error.
fn read(bytes: &[u8]) -> Result<uff::UffFile, UffError> {
    let whole = uff::parse(bytes);
    for chunk in [1, 2, 5, 16, 100, 1 << 20] {
        for threads in [1, 2] {
            let streamed = uff::parse_reader_with(bytes, chunk, threads);
            assert_eq!(streamed, whole, "chunk {chunk}, threads {threads}");
            // One byte per read: the end of input is only seen at the end.
            let trickle =
                std::io::Read::chain(&bytes[..bytes.len() / 2], &bytes[bytes.len() / 2..]);
            let streamed = uff::parse_reader_with(trickle, chunk, threads);
            assert_eq!(
                streamed, whole,
                "chained reader, chunk {chunk}, threads {threads}"
            );
        }
    }
    whole
}

fn error(bytes: &[u8]) -> UffError {
    match read(bytes) {
        Ok(f) => panic!("expected an error, read {} datasets", f.datasets.len()),
        Err(e) => e,
    }
}

fn real(bytes: &[u8]) -> Vec<f64> {
    let file = read(bytes).unwrap_or_else(|e| panic!("{e}"));
    match &file.datasets[0] {
        Dataset::Function(f) => (0..f.len())
            .flat_map(|i| {
                let (re, im) = f.ordinate.at(i);
                if f.ordinate.is_complex() {
                    vec![re, im]
                } else {
                    vec![re]
                }
            })
            .collect(),
        Dataset::Other(_) => panic!("58 expected"),
    }
}

const R7_REAL4: &str = "         2         4         1  0.00000E+00  1.00000E+00  0.00000E+00";

#[test]
fn fortran_number_forms() {
    // D exponent, 3-digit exponent, exponent without E, plain.
    let v = real(&ascii58(
        R7_REAL4,
        "  1.50000D+01  2.50000E+000    1.00000-100  4.00000E-01\n",
    ));
    assert_eq!(v, vec![15.0, 2.5, 1.0e-100, 0.4]);
}

#[test]
fn run_together_and_whitespace_separated_lines() {
    // Fixed columns without blanks between fields.
    let v = real(&ascii58(
        R7_REAL4,
        "-1.111111E-01-2.111111E+01 4.111111E+03-3.111111E+03\n",
    ));
    assert_eq!(v, vec![-0.1111111, -21.11111, 4111.111, -3111.111]);
    // Other widths, separated by blanks: read by whitespace.
    let v = real(&ascii58(R7_REAL4, "1.0 2.0\n   3.0e0    4\n"));
    assert_eq!(v, vec![1.0, 2.0, 3.0, 4.0]);
}

#[test]
fn short_last_line_and_padding() {
    let r7 = "         2         5         1  0.00000E+00  1.00000E+00  0.00000E+00";
    let v = real(&ascii58(
        r7,
        "  1.00000E+00  2.00000E+00  3.00000E+00  4.00000E+00\n  5.00000E+00\n",
    ));
    assert_eq!(v.len(), 5);
    // Zero padding of the last line is dropped with a note.
    let file = read(&ascii58(
        r7,
        "  1.00000E+00  2.00000E+00  3.00000E+00  4.00000E+00  5.00000E+00  0.00000E+00\n",
    ))
    .expect("reads");
    assert_eq!(file.notes.len(), 1, "{:?}", file.notes);
}

#[test]
fn fewer_points_than_declared() {
    let e = error(&ascii58(
        R7_REAL4,
        "  1.00000E+00  2.00000E+00  3.00000E+00\n",
    ));
    assert_eq!(
        (e.dataset_index, e.dataset_number, e.line),
        (Some(0), Some(58), Some(15))
    );
    assert!(
        e.message.contains("4 points") && e.message.contains("3 values"),
        "{e}"
    );
}

#[test]
fn more_points_than_declared() {
    let e = error(&ascii58(
        R7_REAL4,
        "  1.00000E+00  2.00000E+00  3.00000E+00  4.00000E+00  5.00000E+00\n",
    ));
    assert_eq!(e.line, Some(14));
    assert!(e.message.contains("more values"), "{e}");
}

#[test]
fn non_numeric_field() {
    let e = error(&ascii58(
        R7_REAL4,
        "  1.00000E+00  2.0000XE+00  3.00000E+00  4.00000E+00\n",
    ));
    assert_eq!((e.line, e.dataset_number), (Some(14), Some(58)));
    assert!(e.message.contains("2.0000XE+00"), "{e}");
    let e = error(&ascii58(
        "         2         X         1  0.00000E+00  1.00000E+00  0.00000E+00",
        "",
    ));
    assert_eq!(e.line, Some(9));
    assert!(e.message.contains("record 7"), "{e}");
}

#[test]
fn nan_and_infinity() {
    let e = error(&ascii58(
        R7_REAL4,
        "  1.00000E+00          NaN  3.00000E+00  4.00000E+00\n",
    ));
    assert_eq!(e.line, Some(14));
    assert!(
        e.message.contains("NaN") && e.message.contains("finite"),
        "{e}"
    );
    let e = error(&ascii58(
        R7_REAL4,
        "  1.00000E+00  1.00000E+99999 3.00000E+00  4.00000E+00\n",
    ));
    assert!(
        e.message.contains("finite") || e.message.contains("expected a number"),
        "{e}"
    );
}

#[test]
fn truncated_file() {
    let bytes = ascii58(
        R7_REAL4,
        "  1.00000E+00  2.00000E+00  3.00000E+00  4.00000E+00\n",
    );
    for cut in [bytes.len() - 3, 200, 40, 12] {
        let e = error(&bytes[..cut]);
        assert_eq!(e.dataset_index, Some(0), "cut {cut}: {e}");
        assert!(e.line.is_some(), "cut {cut}: {e}");
    }
}

/// A 58b function, real single, 4 points; `declared` bytes in its header.
fn binary58(declared: usize, data: &[u8], after: &[u8]) -> Vec<u8> {
    let mut out = format!("    -1\n    58b     1     2          11{declared:>12}     0     0           0           0\n").into_bytes();
    out.extend_from_slice(
        HEADER
            .split_once("    58\n")
            .map_or("", |(_, rest)| rest)
            .as_bytes(),
    );
    out.extend_from_slice(R7_REAL4.as_bytes());
    out.push(b'\n');
    out.extend_from_slice(AXES.as_bytes());
    out.extend_from_slice(data);
    out.extend_from_slice(after);
    out
}

fn f32s(v: &[f32]) -> Vec<u8> {
    v.iter().flat_map(|x| x.to_le_bytes()).collect()
}

#[test]
fn binary_quirks() {
    let data = f32s(&[1.0, 2.0, 3.0, 4.0]);
    // Closing -1 right after the data, on its own line, after CRLF.
    for after in [
        &b"    -1\n"[..],
        b"\n    -1\n",
        b"\r\n    -1\r\n",
        b"\n\n    -1",
    ] {
        assert_eq!(real(&binary58(16, &data, after)), vec![1.0, 2.0, 3.0, 4.0]);
    }
    // Header fields with non-standard widths.
    let standard = binary58(16, &data, b"    -1\n");
    let line_end = 7 + standard[7..]
        .iter()
        .position(|&b| b == b'\n')
        .expect("header line");
    let mut odd = b"    -1\n    58b 1 2 11 16 0 0 0 0".to_vec();
    odd.extend_from_slice(&standard[line_end..]);
    assert_eq!(real(&odd), vec![1.0, 2.0, 3.0, 4.0]);
}

#[test]
fn binary_wrong_byte_count() {
    let data = f32s(&[1.0, 2.0, 3.0, 4.0]);
    // Header says 12 bytes, the data has 16: record 7 decides, with a note.
    let file = read(&binary58(12, &data, b"    -1\n")).expect("record 7 length accepted");
    assert_eq!(file.notes.len(), 1);
    // Fewer bytes than record 7 needs.
    let e = error(&binary58(12, &data[..12], b"    -1\n"));
    assert_eq!((e.dataset_index, e.dataset_number), (Some(0), Some(58)));
    assert!(e.message.contains("58b") && e.message.contains("16"), "{e}");
    // Truncated inside the data.
    let e = error(&binary58(16, &data[..10], b""));
    assert!(e.message.contains("truncated"), "{e}");
    assert!(e.byte_offset > 0);
}

#[test]
fn binary_non_finite() {
    let data = f32s(&[1.0, f32::NAN, 3.0, 4.0]);
    let bytes = binary58(16, &data, b"    -1\n");
    let e = error(&bytes);
    assert_eq!(e.line, None);
    assert_eq!(e.byte_offset, bytes.len() - 7 - 12);
    assert!(e.message.contains("point 2"), "{e}");
}

#[test]
fn big_endian_binary() {
    let data: Vec<u8> = [1.0f32, 2.0, 3.0, 4.0]
        .iter()
        .flat_map(|x| x.to_be_bytes())
        .collect();
    let mut bytes = binary58(16, &data, b"    -1\n");
    // Byte order field: 2 = big-endian.
    let pos = bytes
        .windows(6)
        .position(|w| w == b"     1")
        .expect("byte order field");
    bytes[pos + 5] = b'2';
    assert_eq!(real(&bytes), vec![1.0, 2.0, 3.0, 4.0]);
}

#[test]
fn unknown_dataset_is_skipped_with_a_note() {
    let mut bytes = b"    -1\n  9999\nwhatever 1 2 3\n    -1\n".to_vec();
    bytes.extend(ascii58(
        R7_REAL4,
        "  1.00000E+00  2.00000E+00  3.00000E+00  4.00000E+00\n",
    ));
    let file = read(&bytes).expect("reads");
    assert_eq!(file.datasets.len(), 2);
    assert!(
        file.notes
            .iter()
            .any(|n| n.contains("9999") && n.starts_with("line 2")),
        "{:?}",
        file.notes
    );
}

#[test]
fn latin1_and_utf8_headers() {
    let mut bytes = ascii58(
        R7_REAL4,
        "  1.00000E+00  2.00000E+00  3.00000E+00  4.00000E+00\n",
    );
    let pos = bytes
        .windows(10)
        .position(|w| w == b"Quirk test")
        .expect("id line");
    bytes[pos + 5] = 0xe9; // Latin-1 é
    let file = read(&bytes).expect("reads");
    let Dataset::Function(f) = &file.datasets[0] else {
        panic!("58")
    };
    assert_eq!(f.id_lines[0], "Quirkétest");
}

#[test]
fn not_a_uff_file() {
    let e = error(b"hello world\n");
    assert!(e.message.contains("no UFF dataset"), "{e}");
    let e = error(b"");
    assert_eq!(e.byte_offset, 0);
    let e = error(b"    -1\n  abc\n    -1\n");
    assert_eq!(e.line, Some(2));
}

/// Dataset 2420 text: part UID 7 "Part seven"; systems 5 (cartesian, color 8)
/// and 12 (cylindrical, color 2), each with four `1P3D25.16` rows.
fn dataset2420(row9: Option<&str>) -> Vec<u8> {
    let row = |v: [&str; 3]| format!("{:>25}{:>25}{:>25}\n", v[0], v[1], v[2]);
    let (one, zero) = ("1.0000000000000000D+00", "0.0000000000000000D+00");
    let mut s = String::from("    -1\n  2420\n         7\nPart seven\n");
    s += "         5         0         8\nCS five\n";
    s += &row([one, zero, zero]);
    s += &row([zero, one, zero]);
    s += &row9.map_or_else(|| row([zero, zero, one]), |t| format!("{t}\n"));
    s += &row([
        "2.5000000000000000D-01",
        "-1.5000000000000000D+00",
        "3.0E+000",
    ]);
    s += "        12         1         2\nCyl twelve\n";
    s += &row([zero, "-1.0000000000000000D+00", zero]);
    s += &row([one, zero, zero]);
    s += &row([zero, zero, one]);
    s += &row(["1.0000000000000000D+01", zero, "-2.0000000000000000D-03"]);
    s += "    -1\n";
    s.into_bytes()
}

/// 2420 has no real fixture: the part, both systems' labels, types, colors,
/// names and transformation rows (axes then origin) are read exactly (the
/// values are exact in binary), and a bad row names file line and dataset.
#[test]
fn dataset_2420_coordinate_systems() {
    let file = read(&dataset2420(None)).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(file.datasets.len(), 1);
    let Dataset::Other(o) = &file.datasets[0] else {
        panic!("2420 expected")
    };
    assert_eq!(o.number, 2420);
    let uff::OtherKind::CoordinateSystems { part, systems } = &o.kind else {
        panic!("coordinate systems expected: {:?}", o.kind)
    };
    let part = part.as_ref().expect("2420 has a part");
    assert_eq!((part.uid, part.name.as_str()), (7, "Part seven"));
    assert_eq!(systems.len(), 2);
    let summary: Vec<_> = systems
        .iter()
        .map(|c| (c.label, c.cs_type, c.reference_cs, c.color, c.name.as_str()))
        .collect();
    assert_eq!(
        summary,
        [(5, 0, 0, 8, "CS five"), (12, 1, 0, 2, "Cyl twelve")]
    );
    assert_eq!(
        systems[0].definition,
        uff::CsDefinition::Matrix([
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
            [0.25, -1.5, 3.0]
        ])
    );
    assert_eq!(
        systems[1].definition,
        uff::CsDefinition::Matrix([
            [0.0, -1.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 0.0, 1.0],
            [10.0, 0.0, -2e-3]
        ])
    );

    let e = error(&dataset2420(Some("  not a number")));
    assert_eq!(
        (e.dataset_index, e.dataset_number, e.line),
        (Some(0), Some(2420), Some(9)),
        "{e}"
    );
    assert!(e.message.contains("1P3D25.16"), "{e}");
}
