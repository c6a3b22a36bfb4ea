//! `uff::parse_reader` (streaming) against `uff::parse` (whole buffer): same
//! datasets, notes and first error, for every real fixture, cut anywhere,
//! whatever the chunk size and thread count.

use std::path::PathBuf;

use frfup_parsers::uff::{self, Abscissa, AxisCharacteristics, Complex64, Function58, Ordinate};

fn fixtures() -> Vec<PathBuf> {
    let root = PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../fixtures/uff-real"));
    let mut out = Vec::new();
    for dir in ["pyuff", "uffl-jl"] {
        for entry in std::fs::read_dir(root.join(dir)).expect("fixture directory") {
            out.push(entry.expect("entry").path());
        }
    }
    out.sort();
    assert!(out.len() > 30, "fixtures missing");
    out
}

/// A reader that returns at most `step` bytes per call, like a pipe: the end
/// of the file is only seen by a read returning 0.
struct Trickle<'a> {
    bytes: &'a [u8],
    step: usize,
}

impl std::io::Read for Trickle<'_> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        let n = buf.len().min(self.step).min(self.bytes.len());
        buf[..n].copy_from_slice(&self.bytes[..n]);
        self.bytes = &self.bytes[n..];
        Ok(n)
    }
}

fn same(bytes: &[u8], chunks: &[usize], what: &str) {
    let whole = uff::parse(bytes);
    for &chunk in chunks {
        for threads in [1, 2, 3] {
            let streamed = uff::parse_reader_with(bytes, chunk, threads);
            assert_eq!(streamed, whole, "{what}: chunk {chunk}, threads {threads}");
        }
        for step in [1, 7] {
            let streamed = uff::parse_reader_with(Trickle { bytes, step }, chunk, 2);
            assert_eq!(
                streamed, whole,
                "{what}: chunk {chunk}, reads of {step} bytes"
            );
        }
    }
    assert_eq!(uff::parse_reader(bytes), whole, "{what}: parse_reader");
}

#[test]
fn every_fixture_streams_the_same() {
    for path in fixtures() {
        let bytes = std::fs::read(&path).expect("fixture");
        let what = path.display().to_string();
        let small: &[usize] = if bytes.len() < 20_000 {
            &[1, 3, 7, 12, 64, 1000, 1 << 20]
        } else {
            &[997, 4096, 65536, 1 << 20]
        };
        same(&bytes, small, &what);
    }
}

#[test]
fn every_fixture_cut_streams_the_same() {
    for path in fixtures() {
        let bytes = std::fs::read(&path).expect("fixture");
        let step = (bytes.len() / 40).max(1);
        for cut in (0..bytes.len()).step_by(step) {
            same(
                &bytes[..cut],
                &[13, 4096],
                &format!("{} cut at {cut}", path.display()),
            );
        }
    }
}

#[test]
fn read_errors_are_reported() {
    struct Failing(usize);
    impl std::io::Read for Failing {
        fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
            if self.0 == 0 {
                return Err(std::io::Error::other("disk on fire"));
            }
            let n = buf.len().min(self.0);
            buf[..n].fill(b'\n');
            self.0 -= n;
            Ok(n)
        }
    }
    let e = uff::parse_reader(Failing(100)).expect_err("read error");
    assert!(
        e.message.starts_with("read error") && e.message.contains("disk on fire"),
        "{e}"
    );
    assert_eq!(e.byte_offset, 100);
}

fn function(k: usize, points: usize, binary: bool, ordinate_type: i32) -> Function58 {
    let axis = |t: i32| AxisCharacteristics {
        data_type: t,
        label: "L".into(),
        units_label: "U".into(),
        ..Default::default()
    };
    let v = |i: usize| ((i * 7 + k) as f64 * 0.37).sin() * 10f64.powi((i % 9) as i32 - 4);
    let ordinate = if matches!(ordinate_type, 5 | 6) {
        Ordinate::Complex(
            (0..points)
                .map(|i| Complex64::new(v(i), v(i + 1)))
                .collect(),
        )
    } else {
        Ordinate::Real((0..points).map(v).collect())
    };
    let abscissa = if k % 3 == 2 {
        Abscissa::Uneven((0..points).map(|i| i as f64 * 0.5 + 0.25).collect())
    } else {
        Abscissa::Even {
            start: 0.0,
            step: 0.25,
        }
    };
    Function58 {
        id_lines: [
            format!("f{k}"),
            "x".into(),
            "y".into(),
            "NONE".into(),
            "NONE".into(),
        ],
        function_type: 4,
        function_id: k as i32,
        version: 1,
        load_case: 0,
        response_entity: "NONE".into(),
        response_node: k as i64 + 1,
        response_direction: 3,
        reference_entity: "NONE".into(),
        reference_node: 1,
        reference_direction: 3,
        ordinate_type,
        abscissa,
        z_axis_value: 0.0,
        abscissa_axis: axis(18),
        numerator_axis: axis(12),
        denominator_axis: axis(13),
        z_axis: axis(0),
        ordinate,
        binary,
    }
}

/// Mixed ASCII/58b files of every ordinate type, and one big dataset that the
/// reader splits across threads.
#[test]
fn written_files_stream_the_same() {
    let mut functions = Vec::new();
    for k in 0..24 {
        functions.push(function(k, 50 + 37 * k, k % 2 == 1, [2, 4, 5, 6][k % 4]));
    }
    let mut bytes = Vec::new();
    uff::write_functions(&mut bytes, &functions).expect("write");
    let file = uff::parse(&bytes).expect("reads");
    assert_eq!(file.datasets.len(), functions.len());
    same(&bytes, &[1, 100, 4096, 65536], "mixed");

    for ordinate_type in [2, 4, 5, 6] {
        let big = function(3, 300_000, false, ordinate_type);
        let mut bytes = Vec::new();
        uff::write_functions(&mut bytes, std::slice::from_ref(&big)).expect("write");
        let file = uff::parse(&bytes).expect("reads big");
        let uff::Dataset::Function(f) = &file.datasets[0] else {
            panic!("58")
        };
        assert_eq!(f.len(), 300_000);
        same(&bytes, &[1 << 16, 1 << 20], "big");
        // A bad value in either half of the big dataset (read by two threads):
        // the line-by-line error, the same either way.
        for at in [bytes.len() / 3, bytes.len() - 200] {
            let mut bad = bytes.clone();
            let digit = at
                + bad[at..]
                    .iter()
                    .position(u8::is_ascii_digit)
                    .expect("digit");
            bad[digit] = b'x';
            let e = uff::parse(&bad).expect_err("bad value");
            let line = 1 + bad[..digit].iter().filter(|&&b| b == b'\n').count();
            assert_eq!(e.line, Some(line), "{e}");
            let line_start = bad[..digit]
                .iter()
                .rposition(|&b| b == b'\n')
                .map_or(0, |p| p + 1);
            assert_eq!(e.byte_offset, line_start, "{e}");
            same(&bad, &[1 << 20], "big with a bad value");
        }
        // Zero padding after the declared points: the note of the line-by-line read.
        let mut padded = bytes.clone();
        let close = padded.len() - "    -1\n".len();
        padded.splice(close..close, b"  0.00000E+00\n".iter().copied());
        same(&padded, &[1 << 20], "big with padding");
    }
}

/// Fuzz finding: text without any dataset, longer than a chunk; the error
/// offset is 0 (the file start), not the start of the last buffer.
#[test]
fn no_dataset_error_offset() {
    let bytes = "not a UFF line\n".repeat(100).into_bytes();
    let e = uff::parse(&bytes).expect_err("no dataset");
    assert_eq!(e.byte_offset, 0);
    same(&bytes, &[1, 16, 100], "stray text only");
}
