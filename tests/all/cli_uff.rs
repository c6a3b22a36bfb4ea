//! The ingest commands end to end: `frfup info` and `frfup convert` on the real
//! fixtures in fixtures/uff-real, exit codes and messages on bad input, no partial output.

use std::path::{Path, PathBuf};

use crate::cli_support::{frfup, scratch};
use faer::c64;
use frfup::testdata::{self, Channel, FrfKind, MeasuredFrfs};

fn tmp(name: &str) -> PathBuf {
    scratch("uff", name)
}

fn shared(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("fixtures/uff-real")
        .join(rel)
}

#[test]
fn info_lists_every_dataset_of_a_mixed_file() {
    let out = frfup(&[
        "info",
        shared("uffl-jl/dataset151_164_58_55.unv").to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8(out.stdout).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    // header line + 151, 164, 58, 55
    assert_eq!(lines.len(), 5, "{text}");
    assert!(lines[1].contains("151"));
    assert!(lines[2].contains("164"));
    assert!(lines[3].contains("58") && lines[3].contains("1+x") && lines[3].contains("22+x"));
    assert!(lines[4].contains("55"));
}

#[test]
fn info_json_has_the_documented_fields() {
    let out = frfup(&[
        "info",
        shared("pyuff/measurement.uff").to_str().unwrap(),
        "--json",
    ]);
    assert!(out.status.success());
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let records = v["records"].as_array().unwrap();
    assert_eq!(records.len(), 3);
    for (i, r) in records.iter().enumerate() {
        assert_eq!(r["dataset"], 58);
        assert_eq!(r["function_type"], 4);
        assert_eq!(r["ordinate_type"], 6);
        assert_eq!(r["points"], 1001);
        assert_eq!(r["response_node"], 1);
        assert_eq!(r["reference_node"], i as i64 + 1);
        assert_eq!(r["abscissa_min"].as_f64(), Some(0.0));
        assert_eq!(r["abscissa_max"].as_f64(), Some(1000.0));
    }
}

#[test]
fn convert_to_csv_writes_one_row_per_line() {
    let out_path = tmp("measurement.csv");
    let out = frfup(&[
        "convert",
        shared("pyuff/measurement.uff").to_str().unwrap(),
        out_path.to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = std::fs::read_to_string(&out_path).unwrap();
    let mut lines = text.lines();
    assert_eq!(
        lines.next().unwrap(),
        "frequency_hz,1+x/1+x re,1+x/1+x im,1+x/2+x re,1+x/2+x im,1+x/3+x re,1+x/3+x im"
    );
    assert_eq!(lines.count(), 1001);
}

#[test]
fn convert_round_trips_through_58b_bit_exact() {
    let input = shared("uffl-jl/dataset58_case7_ascii.unv");
    let out_path = tmp("case7.uff");
    let out = frfup(&[
        "convert",
        input.to_str().unwrap(),
        out_path.to_str().unwrap(),
        "--binary",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let a = frfup_parsers::uff::parse(&std::fs::read(&input).unwrap()).unwrap();
    let b = frfup_parsers::uff::parse(&std::fs::read(&out_path).unwrap()).unwrap();
    let (frfup_parsers::uff::Dataset::Function(fa), frfup_parsers::uff::Dataset::Function(fb)) =
        (&a.datasets[0], &b.datasets[0])
    else {
        panic!("dataset 58 expected")
    };
    assert!(fb.binary);
    assert_eq!(
        fa.ordinate, fb.ordinate,
        "58b keeps every bit of the values"
    );
    assert_eq!(fa.response_node, fb.response_node);
    assert_eq!(fa.reference_node, fb.reference_node);
}

#[test]
fn bad_input_exits_2_names_the_file_and_line_and_writes_nothing() {
    let input = shared("pyuff/dataset_milestone_in_header.uff");
    let out_path = tmp("never.csv");
    let _ = std::fs::remove_file(&out_path);
    let out = frfup(&[
        "convert",
        input.to_str().unwrap(),
        out_path.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("dataset_milestone_in_header.uff"), "{err}");
    assert!(
        err.contains("line 21 (byte 1543)"),
        "line and byte offset: {err}"
    );
    assert!(err.contains("dataset #1 (type 58)"), "dataset index: {err}");
    assert!(err.contains("2508876"), "says what was declared: {err}");
    assert!(!out_path.exists(), "no partial output file");
    // The same for UFF output (58b).
    let uff_path = tmp("never.uff");
    let _ = std::fs::remove_file(&uff_path);
    let out = frfup(&[
        "convert",
        input.to_str().unwrap(),
        uff_path.to_str().unwrap(),
        "--binary",
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert!(!uff_path.exists(), "no partial 58b file");
    let dir = out_path.parent().unwrap();
    let leftovers: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .filter_map(|e| e.ok())
        .filter(|e| e.file_name().to_string_lossy().contains("never.csv"))
        .collect();
    assert!(leftovers.is_empty(), "no temporary file left behind");
}

#[test]
fn usage_errors_exit_2() {
    let out = frfup(&["convert", "a.uff"]);
    assert_eq!(out.status.code(), Some(2));
    let out = frfup(&[
        "convert",
        shared("pyuff/measurement.uff").to_str().unwrap(),
        "x.txt",
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains(".csv, .uff or .unv"));
}

/// One DOF oscillator m ẍ + c ẋ + k x = f: receptance R = 1/(k − ω²m + iωc).
fn oscillator(kind: FrfKind, freqs: &[f64]) -> MeasuredFrfs {
    let (m, c, k) = (2.0, 3.0, 8.0e4);
    let values = freqs
        .iter()
        .map(|&f| {
            let w = 2.0 * std::f64::consts::PI * f;
            let r = c64::new(1.0, 0.0) / c64::new(k - w * w * m, w * c);
            match kind {
                FrfKind::Receptance => r,
                FrfKind::Mobility => r * c64::new(0.0, w),
                FrfKind::Accelerance => r * c64::new(-w * w, 0.0),
            }
        })
        .collect();
    MeasuredFrfs {
        frequencies_hz: freqs.to_vec(),
        kind,
        channels: vec![Channel {
            response_node: 1,
            response_direction: 3,
            reference_node: 1,
            reference_direction: 3,
            values,
        }],
    }
}

#[test]
fn kind_conversions_match_the_closed_form_and_zero_line_is_explicit() {
    let freqs: Vec<f64> = (0..200).map(|i| i as f64 * 0.5).collect();
    let acc = oscillator(FrfKind::Accelerance, &freqs);
    for kind in [FrfKind::Receptance, FrfKind::Mobility] {
        let conv = acc.to_kind(kind);
        assert_eq!(
            conv.zeroed_lines,
            vec![0],
            "0 Hz is undefined when dividing by iω"
        );
        let exact = oscillator(kind, &freqs);
        for (line, (a, b)) in conv.frfs.channels[0]
            .values
            .iter()
            .zip(&exact.channels[0].values)
            .enumerate()
        {
            if line == 0 {
                assert_eq!(*a, c64::new(0.0, 0.0));
                continue;
            }
            // exact arithmetic up to a few roundings: 1e-12 relative
            assert!(
                (a - b).norm() <= 1e-12 * b.norm(),
                "{kind:?} line {line}: {a} vs {b}"
            );
        }
    }
    // multiplying up needs no special line
    let rec = oscillator(FrfKind::Receptance, &freqs);
    assert!(rec.to_kind(FrfKind::Accelerance).zeroed_lines.is_empty());
}

#[test]
fn eq50_signed_real_displacement_from_accelerance_equals_signed_receptance() {
    let freqs: Vec<f64> = (0..400).map(|i| i as f64 * 0.25).collect();
    let acc = oscillator(FrfKind::Accelerance, &freqs);
    let rec = oscillator(FrfKind::Receptance, &freqs);
    let h_acc = testdata::signed_real_displacement(&acc);
    let h_rec = testdata::signed_real_displacement(&rec);
    assert_eq!(h_acc[0][0], 0.0, "0 Hz line is 0, not NaN");
    for line in 1..freqs.len() {
        let (a, b) = (h_acc[0][line], h_rec[0][line]);
        assert!((a - b).abs() <= 1e-12 * b.abs(), "line {line}: {a} vs {b}");
    }
    // below resonance (≈ 31.8 Hz) the receptance is in phase: positive; above: negative
    assert!(h_rec[0][40] > 0.0 && h_rec[0][300] < 0.0);
    // Eq. 50 by hand at one line
    let w = 2.0 * std::f64::consts::PI * freqs[10];
    let a = acc.channels[0].values[10];
    let by_hand = -a.re.signum() * (a.re * a.re + a.im * a.im).sqrt() / (w * w);
    assert!((h_acc[0][10] - by_hand).abs() <= 1e-15 * by_hand.abs());
}

#[test]
fn g_based_accelerance_is_converted_to_si() {
    // Accelerance written in g/N (units label "g") reads back in m/s²/N.
    let freqs: Vec<f64> = (0..50).map(|i| i as f64).collect();
    let acc = oscillator(FrfKind::Accelerance, &freqs);
    let mut records = frfup::simulate::to_uff_records(&acc, "g test", true, false);
    let g = 9.80665;
    for r in &mut records {
        r.numerator_axis.units_label = "g".into();
        if let frfup_parsers::uff::Ordinate::Complex(v) = &mut r.ordinate {
            for p in v.iter_mut() {
                *p /= g;
            }
        }
    }
    let mut bytes = Vec::new();
    frfup_parsers::uff::write_functions(&mut bytes, &records).unwrap();
    let file = frfup_parsers::uff::parse(&bytes).unwrap();
    let back = testdata::from_uff(&file, Path::new("mem.uff")).unwrap();
    for (a, b) in back.channels[0].values.iter().zip(&acc.channels[0].values) {
        // ASCII E20.12 keeps 12-13 significant digits
        assert!((a - b).norm() <= 1e-10 * b.norm().max(1e-300), "{a} vs {b}");
    }
}

#[test]
fn dataset_164_inch_pound_units_are_converted_to_si() {
    // UFFFiles.jl's mixed file declares unit system 7 (inch, pound-force) before its FRF.
    let path = shared("uffl-jl/dataset151_164_58_55.unv");
    let file = frfup_parsers::uff::parse(&std::fs::read(&path).unwrap()).unwrap();
    let frfs = testdata::from_uff(&file, &path).unwrap();
    let frfup_parsers::uff::Dataset::Function(f) = &file.datasets[2] else {
        panic!()
    };
    assert!(f.ordinate.is_complex());
    let (n, d) = (&f.numerator_axis, &f.denominator_axis);
    // SI value = file value × length^-(Ln-Ld) × force^-(Fn-Fd), with 39.37 in/m and 0.2248 lbf/N
    let expected = 39.37007874015748f64.powi(-(n.length_exponent - d.length_exponent))
        * 0.2248089430997105f64.powi(-(n.force_exponent - d.force_exponent));
    let k = (0..f.len())
        .position(|i| f.ordinate.at(i).0 != 0.0)
        .unwrap();
    let got = frfs.channels[0].values[k].re / f.ordinate.at(k).0;
    assert!(
        (got - expected).abs() <= 1e-12 * expected.abs(),
        "{got} vs {expected}"
    );
}

/// `info --json` keys are pinned: the ten for a 58 record plus the
/// text line's index, name, band units and units (README, `frfup info`);
/// other datasets carry index, number, line and a summary.
#[test]
fn info_json_key_set_is_exact() {
    let out = frfup(&[
        "info",
        shared("uffl-jl/dataset151_164_58_55.unv").to_str().unwrap(),
        "--json",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let keys = |v: &serde_json::Value| -> Vec<String> {
        let mut k: Vec<String> = v.as_object().unwrap().keys().cloned().collect();
        k.sort();
        k
    };
    let sorted = |k: &[&str]| -> Vec<String> {
        let mut k: Vec<String> = k.iter().map(|s| s.to_string()).collect();
        k.sort();
        k
    };
    assert_eq!(keys(&v), sorted(&["records", "notes"]));
    let records = v["records"].as_array().unwrap();
    let numbers: Vec<i64> = records
        .iter()
        .map(|r| r["dataset"].as_i64().unwrap())
        .collect();
    assert_eq!(numbers, [151, 164, 58, 55]);
    let function58 = sorted(&[
        // the keys
        "dataset",
        "response_node",
        "response_dir",
        "reference_node",
        "reference_dir",
        "function_type",
        "ordinate_type",
        "points",
        "abscissa_min",
        "abscissa_max",
        // what the text line also shows
        "index",
        "binary",
        "function",
        "even",
        "abscissa_units",
        "units",
        "numerator_data_type",
        "denominator_data_type",
        // channels named by entity names only (node 0): the names, everywhere
        "response",
        "reference",
        "response_entity",
        "reference_entity",
        // which file the record comes from (info takes several)
        "file",
    ]);
    let other = sorted(&["index", "dataset", "line", "summary", "file"]);
    for (i, r) in records.iter().enumerate() {
        assert_eq!(r["index"], i as i64 + 1);
        let expected = if r["dataset"] == 58 {
            &function58
        } else {
            &other
        };
        assert_eq!(&keys(r), expected, "record {i}");
    }
    assert_eq!(records[2]["response_node"], 1);
    assert_eq!(records[2]["reference_node"], 22);
}

/// A file above the bar's 8 MB threshold read with stderr not a terminal (as
/// here), with and without `--quiet`: no bar, nothing at all on stderr, and
/// every dataset read.
#[test]
fn no_progress_output_off_a_terminal_or_with_quiet() {
    let one = std::fs::read(shared("pyuff/measurement.uff")).unwrap();
    let copies = (9 << 20) / one.len() + 1;
    let big = tmp("big_measurement.uff");
    std::fs::write(&big, one.repeat(copies)).unwrap();
    assert!(std::fs::metadata(&big).unwrap().len() > 8 << 20);
    for quiet in [false, true] {
        let mut args = vec!["info", big.to_str().unwrap()];
        if quiet {
            args.insert(0, "--quiet");
        }
        let out = frfup(&args);
        assert!(out.status.success(), "quiet {quiet}");
        assert!(
            out.stderr.is_empty(),
            "quiet {quiet}: {:?}",
            String::from_utf8_lossy(&out.stderr)
        );
        let rows = String::from_utf8(out.stdout).unwrap().lines().count();
        assert_eq!(
            rows,
            1 + 3 * copies,
            "quiet {quiet}: header + 3 datasets per copy"
        );
    }
    let _ = std::fs::remove_file(&big);
}

/// `convert --to displacement-real` to CSV: one column per channel (real
/// data), the 0 Hz line written as 0 with a note, and every other line equal
/// to Eq. 50 applied by hand to the accelerance read from the input (1e-12
/// relative: the CSV prints shortest round-trip decimals).
#[test]
fn convert_displacement_real_csv_has_one_column_per_channel() {
    let input = shared("pyuff/measurement.uff");
    let out_path = tmp("measurement_h.csv");
    let out = frfup(&[
        "convert",
        input.to_str().unwrap(),
        out_path.to_str().unwrap(),
        "--to",
        "displacement-real",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(String::from_utf8_lossy(&out.stderr).contains("0 Hz line is set to 0"));
    let text = std::fs::read_to_string(&out_path).unwrap();
    let rows: Vec<Vec<&str>> = text.lines().map(|l| l.split(',').collect()).collect();
    assert_eq!(
        rows[0],
        [
            "frequency_hz",
            "1+x/1+x[m/N]",
            "1+x/2+x[m/N]",
            "1+x/3+x[m/N]"
        ]
    );
    assert_eq!(rows.len(), 1 + 1001);
    let file = frfup_parsers::uff::parse(&std::fs::read(&input).unwrap()).unwrap();
    for (c, d) in file.datasets.iter().enumerate() {
        let frfup_parsers::uff::Dataset::Function(f) = d else {
            panic!("58 expected")
        };
        assert!(f.ordinate.is_complex(), "complex expected");
        assert_eq!(rows[1][c + 1].parse::<f64>().unwrap(), 0.0);
        for line in [1, 10, 500, 1000] {
            let hz: f64 = rows[line + 1][0].parse().unwrap();
            assert_eq!(hz, f.abscissa_at(line));
            let w = 2.0 * std::f64::consts::PI * hz;
            let (a, b) = f.ordinate.at(line);
            let expected = -a.signum() * (a * a + b * b).sqrt() / (w * w);
            let got: f64 = rows[line + 1][c + 1].parse().unwrap();
            assert!(
                (got - expected).abs() <= 1e-12 * expected.abs(),
                "channel {c} line {line}: {got} vs {expected}"
            );
        }
    }
}
