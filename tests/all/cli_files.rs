//! `convert IN -` (CSV on stdout) and several files in one `info` or
//! `convert`, each record naming its file.

use crate::cli_support::{fixture, frfup_ok, workdir};

#[test]
fn convert_to_stdout_writes_the_same_csv_as_to_a_file() {
    let dir = workdir("files-stdout");
    let input = fixture("uff-real/pyuff/measurement.uff");
    let path = dir.join("m.csv");
    frfup_ok(&["convert", &input, path.to_str().unwrap()]);
    let out = frfup_ok(&["convert", &input, "-"]);
    let written = std::fs::read(&path).unwrap();
    assert!(written.len() > 10_000);
    assert_eq!(out.stdout, written);
}

/// Two files in one CSV: the columns of each, named FILE:resp/ref, with the
/// values of the single-file CSV; `--channels` chooses in each file.
#[test]
fn convert_of_two_files_names_each_column_s_file() {
    let dir = workdir("files-two");
    let a = fixture("uff-real/pyuff/measurement.uff");
    let b = dir.join("part.uff");
    let b = b.to_str().unwrap();
    frfup_ok(&["convert", &a, b, "--channels", "2-3"]);
    let csv = |args: &[&str]| -> Vec<Vec<String>> {
        let out = frfup_ok(args);
        String::from_utf8(out.stdout)
            .unwrap()
            .lines()
            .map(|l| l.split(',').map(String::from).collect())
            .collect()
    };
    let both = csv(&["convert", &a, b, "-", "--channels", "1"]);
    let alone = csv(&["convert", &a, "-"]);
    assert_eq!(
        both[0],
        [
            "frequency_hz".to_string(),
            format!("{a}:1+x/1+x re"),
            format!("{a}:1+x/1+x im"),
            format!("{b}:1+x/2+x re"),
            format!("{b}:1+x/2+x im"),
        ]
    );
    assert_eq!(both.len(), alone.len());
    for (x, y) in both[1..].iter().zip(&alone[1..]) {
        assert_eq!(x[..], y[..5]);
    }
}

#[test]
fn info_of_two_files_says_which_file_each_record_comes_from() {
    let (a, b) = (
        fixture("uff-real/pyuff/measurement.uff"),
        fixture("uff-real/uffl-jl/dataset151_164_58_55.unv"),
    );
    let single = |f: &str| String::from_utf8(frfup_ok(&["info", f]).stdout).unwrap();
    let text = String::from_utf8(frfup_ok(&["info", &a, &b]).stdout).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    assert!(lines[0].starts_with("file "), "{text}");
    let body_a = single(&a).lines().count() - 1;
    let body_b = single(&b).lines().count() - 1;
    assert_eq!(lines.len(), 1 + body_a + body_b, "{text}");
    assert!(lines[1..=body_a].iter().all(|l| l.starts_with(a.as_str())));
    assert!(lines[1 + body_a..]
        .iter()
        .all(|l| l.starts_with(b.as_str())));
    let v: serde_json::Value =
        serde_json::from_slice(&frfup_ok(&["info", &a, &b, "--json"]).stdout).unwrap();
    let files: Vec<&str> = v["records"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| r["file"].as_str().unwrap())
        .collect();
    assert_eq!(files.len(), body_a + body_b);
    assert!(files[..body_a].iter().all(|f| *f == a));
    assert!(files[body_a..].iter().all(|f| *f == b));
}
