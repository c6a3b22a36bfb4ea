//! One CSV convention in every CSV frfup writes: a header of unique,
//! non-empty names, frequencies and times named with their unit, numbers as
//! plain decimals or `1.234e-5` (never `0e0`, `NaN` or `inf`: a missing value
//! is an empty cell).

use std::path::{Path, PathBuf};

use crate::cli_support::{cantilever_case, fixture, frfup, frfup_ok, workdir};

/// Every `.csv` under `dir`.
fn csv_files(dir: &Path, found: &mut Vec<PathBuf>) {
    for e in std::fs::read_dir(dir).unwrap().flatten() {
        let p = e.path();
        if p.is_dir() {
            csv_files(&p, found);
        } else if p.extension().is_some_and(|x| x == "csv") {
            found.push(p);
        }
    }
}

/// A number cell in the convention: `-?D+(.D+)?` or `-?D(.D+)?e-?D+` with a
/// non-zero mantissa.
fn well_written_number(cell: &str) -> bool {
    let body = cell.strip_prefix('-').unwrap_or(cell);
    let digits = |s: &str| !s.is_empty() && s.bytes().all(|b| b.is_ascii_digit());
    let decimal = |s: &str| match s.split_once('.') {
        Some((i, f)) => digits(i) && digits(f),
        None => digits(s),
    };
    match body.split_once('e') {
        None => decimal(body),
        Some((m, e)) => {
            let e = e.strip_prefix('-').unwrap_or(e);
            let m_ok = decimal(m) && m.len() <= 1 + 1 + 16 && m.as_bytes()[0] != b'0';
            m_ok && digits(e) && m.split_once('.').is_none_or(|(i, _)| i.len() == 1)
        }
    }
}

fn check(path: &Path) {
    let mut r = csv::ReaderBuilder::new()
        .flexible(true)
        .from_path(path)
        .unwrap();
    let header: Vec<String> = r.headers().unwrap().iter().map(String::from).collect();
    let name = path.display();
    for (i, h) in header.iter().enumerate() {
        assert!(!h.trim().is_empty(), "{name}: column {i} has no name");
        assert!(!header[..i].contains(h), "{name}: column name {h:?} twice");
        let l = h.to_ascii_lowercase();
        if l.contains("frequency") || l.starts_with("f_") {
            assert!(l.contains("hz"), "{name}: {h:?} without its unit");
        }
        if l.starts_with("time") {
            assert!(
                l.ends_with("_s") || l.contains("[s]"),
                "{name}: {h:?} without its unit"
            );
        }
    }
    for (row, rec) in r.records().enumerate() {
        for (c, cell) in rec.unwrap().iter().enumerate() {
            let looks_numeric = cell.parse::<f64>().is_ok();
            if looks_numeric {
                assert!(
                    well_written_number(cell),
                    "{name}: row {} column {:?}: {cell:?}",
                    row + 2,
                    header.get(c)
                );
            }
        }
    }
}

#[test]
fn every_csv_follows_one_convention() {
    let dir = workdir("csv");
    let (deck, uff) = cantilever_case(&dir);
    let d = |n: &str| dir.join(n).to_str().unwrap().to_string();
    crate::cli_support::copy_dir(crate::cli_support::demo_dir(), &dir.join("demo"));
    let out = frfup(&["update", &deck, &uff, "--out", &d("update")]);
    assert!(matches!(out.status.code(), Some(0 | 1)));
    let out = frfup(&[
        "update",
        "--method",
        "paper",
        &deck,
        &uff,
        "--out",
        &d("paper"),
    ]);
    assert!(matches!(out.status.code(), Some(0 | 1)));
    frfup_ok(&[
        "diagnose",
        &fixture("diagnose/damping.deck"),
        &fixture("diagnose/damping.uff"),
        "--out",
        &d("diagnose"),
    ]);
    frfup_ok(&[
        "modes",
        &fixture("paper/frame3d.deck"),
        "--csv",
        &d("modes.csv"),
    ]);
    for (i, (input, extra)) in [
        ("uff-real/pyuff/measurement.uff", None),
        ("uff-real/pyuff/measurement.uff", Some("displacement-real")),
        ("uff-real/pyuff/measurement.uff", Some("receptance")),
        ("uff-real/pyuff/Sample_UFF58_ascii.uff", None),
        ("uff-real/pyuff/Sample_UFF58b_bin.uff", None),
    ]
    .into_iter()
    .enumerate()
    {
        let target = d(&format!("convert{i}.csv"));
        let mut args = vec!["convert".to_string(), fixture(input), target];
        if let Some(kind) = extra {
            args.extend(["--to".to_string(), kind.to_string()]);
        }
        frfup_ok(&args.iter().map(String::as_str).collect::<Vec<_>>());
    }
    let campaign = dir.join("campaign.toml");
    std::fs::write(
        &campaign,
        "[[case]]\nname = \"beam\"\nmodel = \"beam.deck\"\ntest = \"beam.uff\"\n",
    )
    .unwrap();
    let out = frfup(&["batch", campaign.to_str().unwrap(), "--out", &d("batch")]);
    assert!(matches!(out.status.code(), Some(0 | 1)));
    let mut found = Vec::new();
    csv_files(&dir, &mut found);
    assert!(found.len() >= 35, "{} CSV files", found.len());
    for path in &found {
        check(path);
    }
}

#[test]
fn the_number_rule_itself() {
    for ok in ["0", "-0.5", "12", "1.5e-5", "-2.345e7", "1e6"] {
        assert!(well_written_number(ok), "{ok}");
    }
    for bad in [
        "0e0",
        "0.000000e0",
        "NaN",
        "inf",
        "+1",
        "1.",
        ".5",
        "12.5e3",
        "1E5",
    ] {
        assert!(!well_written_number(bad), "{bad}");
    }
}
