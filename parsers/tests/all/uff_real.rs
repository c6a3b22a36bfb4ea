//! Every real UFF file of `fixtures/uff-real` against values read by
//! pyuff (`scripts/uff_expected.py` → `tests/expected/uff_real.json`).

use std::path::PathBuf;

use frfup_parsers::uff::{self, Dataset, Function58, Ordinate, OtherKind};
use serde_json::Value;

fn fixtures() -> PathBuf {
    PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../fixtures/uff-real"))
}

fn expected() -> Value {
    let text = include_str!("../expected/uff_real.json");
    serde_json::from_str(text).expect("uff_real.json is valid JSON")
}

fn read(rel: &str) -> Result<uff::UffFile, uff::UffError> {
    let bytes = std::fs::read(fixtures().join(rel)).unwrap_or_else(|e| panic!("{rel}: {e}"));
    uff::parse(&bytes)
}

fn close(a: f64, b: f64, rel: f64) -> bool {
    (a - b).abs() <= rel * a.abs().max(b.abs()) + 1e-300
}

fn number(v: &Value) -> f64 {
    v.as_f64().unwrap_or(f64::NAN)
}

/// Compares our ordinate value i with pyuff's (a number or [re, im]).
fn check_value(f: &Function58, i: usize, want: &Value, rel: f64, what: &str) {
    let (re, im) = f.ordinate.at(i);
    match (f.ordinate.is_complex(), want) {
        (false, Value::Number(_)) => {
            assert!(
                close(re, number(want), rel),
                "{what}: ours {re} pyuff {want}"
            )
        }
        (true, Value::Array(a)) => {
            assert!(
                close(re, number(&a[0]), rel),
                "{what} re: ours {re} pyuff {}",
                a[0]
            );
            assert!(
                close(im, number(&a[1]), rel),
                "{what} im: ours {im} pyuff {}",
                a[1]
            );
        }
        _ => panic!("{what}: ordinate kind differs from pyuff ({want})"),
    }
}

/// Files whose 58b data pyuff cannot read: the uneven abscissa is stored in
/// single precision next to double-precision ordinates (UFFFiles.jl layout),
/// pyuff reads every value as double. They are checked against their ASCII twin.
const PYUFF_MISREADS: &[(&str, &str)] = &[
    (
        "uffl-jl/dataset58_case6_binary.unv",
        "uffl-jl/dataset58_case6_ascii.unv",
    ),
    (
        "uffl-jl/dataset58_case8_binary.unv",
        "uffl-jl/dataset58_case8_ascii.unv",
    ),
];

/// The truncated file: a clean error, not a panic and not a partial read.
const TRUNCATED: &str = "pyuff/dataset_milestone_in_header.uff";

fn check_function(rel: &str, f: &Function58, e: &Value, rel_tol: f64) {
    let n = f.len();
    assert_eq!(
        f.function_type as i64,
        e["func_type"].as_i64().unwrap_or(-1),
        "{rel}: function type"
    );
    assert_eq!(
        f.ordinate_type as i64,
        e["ord_data_type"].as_i64().unwrap_or(-1),
        "{rel}: ordinate type"
    );
    assert_eq!(
        n as i64,
        e["num_pts"].as_i64().unwrap_or(-1),
        "{rel}: declared points"
    );
    assert_eq!(
        f.response_node,
        e["rsp_node"].as_i64().unwrap_or(-1),
        "{rel}: response node"
    );
    assert_eq!(
        f.response_direction as i64,
        e["rsp_dir"].as_i64().unwrap_or(-1),
        "{rel}: response direction"
    );
    assert_eq!(
        f.reference_node,
        e["ref_node"].as_i64().unwrap_or(-1),
        "{rel}: reference node"
    );
    assert_eq!(
        f.reference_direction as i64,
        e["ref_dir"].as_i64().unwrap_or(-1),
        "{rel}: reference direction"
    );
    assert_eq!(
        f.numerator_axis.length_exponent as i64,
        e["ordinate_len_exp"].as_i64().unwrap_or(-99),
        "{rel}"
    );
    assert_eq!(
        f.denominator_axis.force_exponent as i64,
        e["orddenom_force_exp"].as_i64().unwrap_or(-99),
        "{rel}"
    );
    assert_eq!(
        f.id_lines[0].trim(),
        e["id1"].as_str().unwrap_or("?"),
        "{rel}: id line 1"
    );
    assert!(
        close(f.abscissa_at(0), number(&e["x_first"]), rel_tol),
        "{rel}: first abscissa {}",
        f.abscissa_at(0)
    );
    check_value(
        f,
        0,
        &e["y_first"],
        rel_tol,
        &format!("{rel}: first ordinate"),
    );
    let len_data = e["len_data"].as_u64().unwrap_or(0) as usize;
    let mid = e["mid_index"].as_u64().unwrap_or(0) as usize;
    if mid < n {
        check_value(
            f,
            mid,
            &e["y_mid"],
            rel_tol,
            &format!("{rel}: ordinate {mid}"),
        );
    }
    if len_data == n {
        // pyuff keeps zero padding of the last line as extra points; then its
        // last values are padding, not data.
        assert!(
            close(f.abscissa_at(n - 1), number(&e["x_last"]), rel_tol),
            "{rel}: last abscissa"
        );
        check_value(
            f,
            n - 1,
            &e["y_last"],
            rel_tol,
            &format!("{rel}: last ordinate"),
        );
    } else {
        assert!(
            len_data > n,
            "{rel}: pyuff read fewer points ({len_data}) than we did ({n})"
        );
    }
}

#[test]
fn every_fixture_matches_pyuff() {
    let expected = expected();
    let files = expected["files"].as_object().expect("files object");
    // Every fixture on disk has reference values.
    let mut on_disk = 0;
    for sub in ["pyuff", "uffl-jl"] {
        for entry in std::fs::read_dir(fixtures().join(sub)).expect("fixture folder") {
            let name = entry
                .expect("entry")
                .file_name()
                .to_string_lossy()
                .into_owned();
            assert!(
                files.contains_key(&format!("{sub}/{name}")),
                "no reference values for {sub}/{name}"
            );
            on_disk += 1;
        }
    }
    assert_eq!(on_disk, files.len());
    let mut checked_functions = 0;
    for (rel, e) in files {
        if rel == TRUNCATED {
            continue;
        }
        let file = read(rel).unwrap_or_else(|err| panic!("{rel}: {err}"));
        let types: Vec<u32> = file
            .datasets
            .iter()
            .map(|d| match d {
                Dataset::Function(_) => 58,
                Dataset::Other(o) => o.number,
            })
            .collect();
        let want: Vec<u32> = e["types"]
            .as_array()
            .expect("types")
            .iter()
            .map(|t| t.as_u64().unwrap_or(0) as u32)
            .collect();
        assert_eq!(types, want, "{rel}: dataset types");
        for (k, (d, de)) in file
            .datasets
            .iter()
            .zip(e["datasets"].as_array().expect("datasets"))
            .enumerate()
        {
            match d {
                Dataset::Function(f) => {
                    let twin = PYUFF_MISREADS
                        .iter()
                        .find(|(bin, _)| bin == rel)
                        .map(|(_, ascii)| *ascii);
                    match twin {
                        Some(ascii) => check_function(rel, f, &files[ascii]["datasets"][k], 1e-5),
                        None => check_function(rel, f, de, 1e-12),
                    }
                    checked_functions += 1;
                }
                Dataset::Other(o) => check_other(rel, &o.kind, de),
            }
        }
    }
    assert_eq!(checked_functions, 29);
}

fn check_other(rel: &str, kind: &OtherKind, e: &Value) {
    match kind {
        OtherKind::Units(u) => {
            assert_eq!(
                u.code as i64,
                e["units_code"].as_i64().unwrap_or(-1),
                "{rel}"
            );
            assert!(
                close(u.length, number(&e["length"]), 1e-15),
                "{rel}: length factor"
            );
            assert!(
                close(u.force, number(&e["force"]), 1e-15),
                "{rel}: force factor"
            );
            assert!(
                close(u.temperature, number(&e["temp"]), 1e-15),
                "{rel}: temperature factor"
            );
            assert!(
                close(u.temperature_offset, number(&e["temp_offset"]), 1e-15),
                "{rel}: offset"
            );
        }
        OtherKind::Nodes(n) => {
            assert_eq!(
                n.len() as u64,
                e["nodes"].as_u64().unwrap_or(0),
                "{rel}: nodes"
            );
            assert_eq!(n[0].label, e["first_node"].as_i64().unwrap_or(-1), "{rel}");
            for (c, w) in n[0]
                .coordinates
                .iter()
                .zip(e["first_xyz"].as_array().expect("xyz"))
            {
                assert!(close(*c, number(w), 1e-12), "{rel}: first node coordinates");
            }
        }
        OtherKind::TraceLine(t) => {
            assert_eq!(t.number, e["trace_num"].as_i64().unwrap_or(-1), "{rel}");
            assert_eq!(
                t.nodes.len() as i64,
                e["n_nodes"].as_i64().unwrap_or(-1),
                "{rel}"
            );
        }
        OtherKind::NodalData(d) => {
            assert_eq!(
                d.nodes.len() as u64,
                e["nodes"].as_u64().unwrap_or(0),
                "{rel}: 55 nodes"
            );
            assert_eq!(
                d.analysis_type,
                e["analysis_type"].as_i64().unwrap_or(-1),
                "{rel}"
            );
        }
        _ => {}
    }
}

#[test]
fn truncated_file_is_a_clean_error() {
    let err = read(TRUNCATED).expect_err("the file is truncated");
    assert_eq!(err.dataset_index, Some(0));
    assert_eq!(err.dataset_number, Some(58));
    assert_eq!(err.line, Some(21));
    assert!(
        err.message.contains("2508876 points") && err.message.contains("42 values"),
        "{err}"
    );
}

#[test]
fn latin1_units_label_decodes() {
    let file = read("pyuff/non_ascii_header.uff").expect("reads");
    let Dataset::Function(f) = &file.datasets[0] else {
        panic!("58 expected")
    };
    assert_eq!(f.numerator_axis.units_label, "(1/N)*(m/s²)");
    let file = read("pyuff/sample_dataset58_psd.uff").expect("reads");
    let Dataset::Function(f) = &file.datasets[0] else {
        panic!("58 expected")
    };
    assert_eq!(f.numerator_axis.units_label, "g²/Hz");
    assert!(matches!(f.abscissa, uff::Abscissa::Uneven(_)));
    assert_eq!(
        uff::units_label_si_factor(&f.numerator_axis.units_label),
        Some(uff::units::STANDARD_GRAVITY.powi(2))
    );
}

#[test]
fn binary_and_ascii_twins_agree() {
    // The UFFFiles.jl variant set stores the same FRF 8 ways.
    for case in 1..=8 {
        let a = read(&format!("uffl-jl/dataset58_case{case}_ascii.unv")).expect("ascii");
        let b = read(&format!("uffl-jl/dataset58_case{case}_binary.unv")).expect("binary");
        let (Dataset::Function(a), Dataset::Function(b)) = (&a.datasets[0], &b.datasets[0]) else {
            panic!("58")
        };
        assert!(b.binary && !a.binary);
        assert_eq!(
            (a.ordinate_type, a.len()),
            (b.ordinate_type, b.len()),
            "case {case}"
        );
        for i in 0..a.len() {
            assert!(
                close(a.abscissa_at(i), b.abscissa_at(i), 1e-5),
                "case {case} x {i}"
            );
        }
        let tol = if matches!(a.ordinate_type, 2 | 5) {
            1e-5
        } else {
            1e-11
        };
        assert_eq!(
            a.ordinate.is_complex(),
            b.ordinate.is_complex(),
            "case {case}: kinds differ"
        );
        for i in 0..a.len() {
            let (p, q) = (a.ordinate.at(i), b.ordinate.at(i));
            assert!(
                close(p.0, q.0, tol) && close(p.1, q.1, tol),
                "case {case}: {p:?} vs {q:?}"
            )
        }
    }
}

#[test]
fn units_factor_for_inch_pound_file() {
    let file = read("uffl-jl/dataset151_164_58_55.unv").expect("reads");
    let units = file
        .datasets
        .iter()
        .find_map(|d| match d {
            Dataset::Other(o) => match &o.kind {
                OtherKind::Units(u) => Some(u.clone()),
                _ => None,
            },
            _ => None,
        })
        .expect("164");
    assert_eq!(units.system, uff::UnitSystem::InchPoundForce);
    let f = file
        .datasets
        .iter()
        .find_map(|d| {
            if let Dataset::Function(f) = d {
                Some(f)
            } else {
                None
            }
        })
        .expect("58");
    // (in/s²)/lbf → (m/s²)/N: 0.0254 / 4.4482216152605.
    let factor = uff::ordinate_si_factor(f, &units);
    assert!(close(factor, 0.0254 / 4.4482216152605, 1e-9), "{factor}");
    assert_eq!(uff::abscissa_si_factor(f, &units), 1.0);
}

#[test]
fn geometry_and_modal_contents() {
    let file = read("pyuff/TestLab 161 164 18 15 82.uff").expect("reads");
    let OtherKind::CoordinateSystems { systems, part } = &other(&file, 2).kind else {
        panic!("18")
    };
    assert!(part.is_none());
    assert_eq!(systems[0].name, "SYS1");
    assert!(
        matches!(systems[0].definition, uff::CsDefinition::Points { origin: [x, _, _], .. } if x == -2.4)
    );
    let OtherKind::TraceLine(t) = &other(&file, 4).kind else {
        panic!("82")
    };
    assert_eq!(t.nodes, vec![2, 5, 6, 3, 4, 1, 2, 3, 0]);
    let OtherKind::Units(u) = &other(&file, 1).kind else {
        panic!("164")
    };
    assert_eq!((u.code, u.temperature_offset), (9, -273.15));

    let file = read("uffl-jl/dataset55.unv").expect("reads");
    let OtherKind::NodalData(d) = &other(&file, 0).kind else {
        panic!("55")
    };
    assert_eq!(
        (d.data_type, d.values_per_node, d.integers.as_slice()),
        (5, 3, &[1, 1][..])
    );
    assert_eq!(d.reals.len(), 6);
    assert!(matches!(&d.nodes[0].values, Ordinate::Complex(v) if v.len() == 3));

    let file = read("uffl-jl/dataset151.unv").expect("reads");
    let OtherKind::Header(h) = &other(&file, 0).kind else {
        panic!("151")
    };
    assert_eq!(
        h.file_program(),
        "PolyUFFExport 4.4.0.0 - Compatible to SDRC"
    );

    let file = read("pyuff/heat_engine_housing.uff").expect("reads");
    assert!(matches!(other(&file, 3).kind, OtherKind::Skipped));
    assert!(
        file.notes.iter().any(|n| n.contains("2412")),
        "{:?}",
        file.notes
    );
}

fn other(file: &uff::UffFile, k: usize) -> &uff::OtherDataset {
    match &file.datasets[k] {
        Dataset::Other(o) => o,
        Dataset::Function(_) => panic!("dataset {k} is a function"),
    }
}

/// Dataset 1858 (58 qualifiers) is kept: its seven records as text, in order
/// (trailing blanks trimmed), without a note.
#[test]
fn dataset_1858_qualifiers_are_kept() {
    let file = read("uffl-jl/dataset1858.unv").expect("reads");
    assert_eq!(file.datasets.len(), 1);
    assert!(file.notes.is_empty(), "{:?}", file.notes);
    let o = other(&file, 0);
    assert_eq!(o.number, 1858);
    let OtherKind::Qualifiers(records) = &o.kind else {
        panic!("1858 qualifiers expected: {:?}", o.kind)
    };
    assert_eq!(records.len(), 7, "{records:?}");
    assert!(records[3].ends_with("5.2706007E-02"), "{records:?}");
    assert_eq!(records[5].trim(), "X+    X+");
    assert_eq!(records[6].trim(), "NONE");
}
