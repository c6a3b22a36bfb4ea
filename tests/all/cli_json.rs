//! `--json` of `update`, `modes`, `diagnose` and `batch`: stdout is one JSON
//! value, and its values are the ones the written files hold.

use crate::cli_support::{cantilever_case, fixture, frfup, frfup_ok, read_json, workdir};

/// stdout as JSON (fails the test when anything else is printed there).
fn stdout_json(out: &std::process::Output) -> serde_json::Value {
    serde_json::from_slice(&out.stdout).unwrap_or_else(|e| {
        panic!(
            "stdout is not one JSON value ({e}):\n{}",
            String::from_utf8_lossy(&out.stdout)
        )
    })
}

#[test]
fn update_json_repeats_report_json() {
    let dir = workdir("json-update");
    let (deck, uff) = cantilever_case(&dir);
    let out_dir = dir.join("out");
    let out = frfup_ok(&[
        "update",
        &deck,
        &uff,
        "--out",
        out_dir.to_str().unwrap(),
        "--offset",
        "0.08",
        "--resonances",
        "6",
        "--json",
    ]);
    let v = stdout_json(&out);
    let report = read_json(&out_dir.join("report.json"));
    for key in frfup::report::output::SUMMARY_KEYS {
        assert_eq!(v[key], report[key], "key {key}");
    }
    assert_eq!(v["converged"], true);
    let last = report["final_iteration"].as_u64().unwrap() as usize;
    let iterations = report["iterations"].as_array().unwrap();
    assert_eq!(v["sfdac_mean"]["initial"], iterations[0]["sfdac_mean"]);
    assert_eq!(v["sfdac_mean"]["updated"], iterations[last]["sfdac_mean"]);
    assert_eq!(v["sfdac_min"]["updated"], iterations[last]["sfdac_min"]);
    assert_eq!(v["out"], out_dir.to_str().unwrap());
    assert_eq!(v["threshold_failures"], serde_json::json!([]));
}

#[test]
fn modes_json_holds_the_csv_rows() {
    let dir = workdir("json-modes");
    let csv = dir.join("modes.csv");
    let out = frfup_ok(&[
        "modes",
        &fixture("paper/frame3d.deck"),
        "--count",
        "5",
        "--csv",
        csv.to_str().unwrap(),
        "--json",
    ]);
    let v = stdout_json(&out);
    let modes = v["modes"].as_array().unwrap();
    let text = std::fs::read_to_string(&csv).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    assert_eq!(modes.len(), 5);
    for (row, line) in modes.iter().zip(lines) {
        for (key, cell) in header.iter().zip(line.split(',')) {
            assert_eq!(
                row[*key].as_f64().unwrap(),
                cell.parse::<f64>().unwrap(),
                "{key}"
            );
        }
    }
}

/// `diagnose --json` on the missing-damping case, and `--fail-above-error`
/// on each side of the final error.
#[test]
fn diagnose_json_repeats_diagnosis_json_and_fail_above_error_gates() {
    let dir = workdir("json-diagnose");
    let (deck, uff) = (
        fixture("diagnose/damping.deck"),
        fixture("diagnose/damping.uff"),
    );
    let out_dir = dir.join("out");
    let out = frfup_ok(&[
        "diagnose",
        &deck,
        &uff,
        "--out",
        out_dir.to_str().unwrap(),
        "--json",
    ]);
    let v = stdout_json(&out);
    let d = read_json(&out_dir.join("diagnosis.json"));
    for (key, value) in d.as_object().unwrap() {
        if key != "input_notes" {
            assert_eq!(&v[key], value, "key {key}");
        }
    }
    assert_eq!(v["status"], "explained");
    let error = d["fit"]["diagnosed"]["frf_error"].as_f64().unwrap();
    for (x, code) in [(error * 0.9, 1), (error * 1.1, 0)] {
        let dir = workdir(&format!("json-diagnose-{code}"));
        let out = frfup(&[
            "diagnose",
            &deck,
            &uff,
            "--out",
            dir.join("out").to_str().unwrap(),
            "--fail-above-error",
            &x.to_string(),
        ]);
        assert_eq!(out.status.code(), Some(code), "X = {x}, error {error}");
    }
}

#[test]
fn batch_json_is_summary_json() {
    let dir = workdir("json-batch");
    cantilever_case(&dir);
    let campaign = dir.join("campaign.toml");
    std::fs::write(
        &campaign,
        "[[case]]\nname = \"beam\"\nmodel = \"beam.deck\"\ntest = \"beam.uff\"\noffset = 0.08\nresonances = 6\n",
    )
    .unwrap();
    let out_dir = dir.join("out");
    let out = frfup_ok(&[
        "batch",
        campaign.to_str().unwrap(),
        "--out",
        out_dir.to_str().unwrap(),
        "--json",
    ]);
    assert_eq!(stdout_json(&out), read_json(&out_dir.join("summary.json")));
}
