//! Mode shapes leave the program: `modes --shapes/--uff` (FE modes at every
//! node) and `update`'s `shapes.csv` and `modes.uff` (test and updated FE
//! modes at the measured DOFs), with the deck's geometry as UFF 15 and 82.
//! Checked against the Euler–Bernoulli cantilever's closed-form first mode,
//! read back by our UFF reader, and by pyuff when it is installed.

use std::path::{Path, PathBuf};
use std::process::Command;

use crate::cli_support::{csv_rows, fixture, frfup, pyuff_available, scratch};
use frfup_parsers::uff::{self, Dataset, NodalData55, OtherKind};

fn tmp(name: &str) -> PathBuf {
    scratch("shapes", name)
}

/// The datasets of a UFF file: (dataset number, its nodal data if 55).
fn datasets(path: &Path) -> Vec<(u32, Option<NodalData55>)> {
    let file = uff::parse(&std::fs::read(path).unwrap()).unwrap();
    file.datasets
        .iter()
        .map(|d| match d {
            Dataset::Other(o) => match &o.kind {
                OtherKind::NodalData(n) => (55, Some((**n).clone())),
                OtherKind::Nodes(_) => (15, None),
                OtherKind::TraceLine(_) => (82, None),
                k => panic!("unexpected dataset {k:?}"),
            },
            Dataset::Function(_) => panic!("no function expected"),
        })
        .collect()
}

/// φ₁(x) of a clamped-free Euler–Bernoulli beam (β₁L = 1.875104068711961,
/// σ₁ = (cosh βL + cos βL)/(sinh βL + sin βL)).
fn cantilever_first_mode(x_over_l: f64) -> f64 {
    let bl = 1.875_104_068_711_961_f64;
    let sigma = (bl.cosh() + bl.cos()) / (bl.sinh() + bl.sin());
    let b = bl * x_over_l;
    b.cosh() - b.cos() - sigma * (b.sinh() - b.sin())
}

/// The first FE mode of the 8-element cantilever at its nodes (z) against the
/// closed form, both scaled to the tip: cubic beam elements put the first
/// mode's nodal values within about 1e-5 of it; 1e-4 allows for the
/// shortest-round-trip CSV numbers and the solver's tolerance. The UFF file
/// holds the same values (E13.5: 6 significant digits), the clamped node 0.
#[test]
fn modes_write_shapes_matching_the_closed_form_and_uff() {
    let (csv, uff_path) = (tmp("modes-shapes.csv"), tmp("modes.uff"));
    let run = frfup(&[
        "modes",
        &fixture("diagnose/control_beam.truth.deck"),
        "--count",
        "3",
        "--shapes",
        csv.to_str().unwrap(),
        "--uff",
        uff_path.to_str().unwrap(),
    ]);
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let rows = csv_rows(&csv);
    assert_eq!(rows[0][..2], ["node", "direction"]);
    assert!(rows[0][2].starts_with("FE mode 1 ("), "{:?}", rows[0]);
    let z: Vec<(u32, f64)> = rows[1..]
        .iter()
        .filter(|r| r[1] == "z")
        .map(|r| (r[0].parse().unwrap(), r[2].parse().unwrap()))
        .collect();
    assert_eq!(z.len(), 9, "nine nodes");
    let tip = z[8].1;
    for (k, (node, v)) in z.iter().enumerate() {
        assert_eq!(*node as usize, k + 1);
        let want = cantilever_first_mode(k as f64 / 8.0) / cantilever_first_mode(1.0);
        assert!(
            (v / tip - want).abs() < 1e-4,
            "node {node}: {} vs {want}",
            v / tip
        );
    }
    let sets = datasets(&uff_path);
    let kinds: Vec<u32> = sets.iter().map(|s| s.0).collect();
    assert_eq!(kinds, [15, 82, 55, 55, 55]);
    let first = sets[2].1.as_ref().unwrap();
    assert_eq!((first.analysis_type, first.values_per_node), (2, 3));
    for (node, v) in &z {
        let nv = first
            .nodes
            .iter()
            .find(|n| n.node == i64::from(*node))
            .unwrap();
        let (uz, _) = nv.values.at(2);
        assert!(
            (uz - v).abs() <= 1e-5 * tip.abs(),
            "node {node}: {uz} vs {v}"
        );
    }
}

/// `update` writes the test's fitted shapes and the updated model's at the
/// measured DOFs; each test mode's shape has an FE partner with MAC ≥ 0.99
/// on this parameter-only campaign (the shapes are of the same structure),
/// and modes.uff holds the geometry, then one dataset 55 per shape column.
#[test]
fn update_writes_test_and_fe_shapes() {
    let out = tmp("update");
    let run = frfup(&[
        "update",
        &fixture("diagnose/control_beam.deck"),
        &fixture("diagnose/control_beam.uff"),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let rows = csv_rows(&out.join("shapes.csv"));
    let header = &rows[0];
    let test_cols: Vec<usize> = (2..header.len())
        .filter(|&c| header[c].starts_with("test mode"))
        .collect();
    let fe_cols: Vec<usize> = (2..header.len())
        .filter(|&c| header[c].starts_with("updated FE mode"))
        .collect();
    assert!(!test_cols.is_empty() && !fe_cols.is_empty(), "{header:?}");
    // Rows the test measured (z here); the others are empty.
    let measured: Vec<&Vec<String>> = rows[1..].iter().filter(|r| !r[2].is_empty()).collect();
    assert!(measured.iter().all(|r| r[1] == "z"));
    let col = |c: usize| -> Vec<f64> { measured.iter().map(|r| r[c].parse().unwrap()).collect() };
    let mac = |a: &[f64], b: &[f64]| {
        let ab: f64 = a.iter().zip(b).map(|(x, y)| x * y).sum();
        let aa: f64 = a.iter().map(|x| x * x).sum();
        let bb: f64 = b.iter().map(|x| x * x).sum();
        ab * ab / (aa * bb)
    };
    for &t in &test_cols {
        let best = fe_cols
            .iter()
            .map(|&f| mac(&col(t), &col(f)))
            .fold(0.0f64, f64::max);
        assert!(best >= 0.99, "{}: best MAC {best}", header[t]);
    }
    let sets = datasets(&out.join("modes.uff"));
    assert_eq!(sets[0].0, 15);
    assert_eq!(sets[1].0, 82);
    assert_eq!(sets.len() - 2, test_cols.len() + fe_cols.len());
}

/// pyuff reads the geometry and modes `modes --uff` writes.
#[test]
fn pyuff_reads_the_modes_uff() {
    if !pyuff_available() {
        return;
    }
    let path = tmp("pyuff-modes.uff");
    let run = frfup(&[
        "modes",
        &fixture("diagnose/control_beam.truth.deck"),
        "--count",
        "2",
        "--uff",
        path.to_str().unwrap(),
    ]);
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let script = "import sys, pyuff\n\
        for d in pyuff.UFF(sys.argv[1]).read_sets():\n\
        \x20   print(d['type'], len(d.get('node_nums', d.get('nodes', []))))\n";
    let py = Command::new("python3")
        .args(["-c", script, path.to_str().unwrap()])
        .output()
        .unwrap();
    assert!(
        py.status.success(),
        "{}",
        String::from_utf8_lossy(&py.stderr)
    );
    let text = String::from_utf8(py.stdout).unwrap();
    let types: Vec<&str> = text.lines().map(|l| l.split(' ').next().unwrap()).collect();
    assert_eq!(types, ["15", "82", "55", "55"], "{text}");
}
