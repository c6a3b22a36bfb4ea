//! `frfup batch`: campaign file, per-case folders, summaries, shards, exit codes.

use std::path::{Path, PathBuf};

use crate::cli_support::{cantilever_case, frfup};

fn workdir(name: &str) -> PathBuf {
    let dir = crate::cli_support::scratch_root()
        .join(format!("frfup-cli-batch-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A campaign over the paper's cantilever: a good case, a case whose threshold
/// cannot be met, and a case whose test file is missing.
fn campaign(dir: &Path) -> PathBuf {
    cantilever_case(dir);
    let toml = r#"
fail_below_sfdac = 0.5

[[case]]
name = "good"
model = "beam.deck"
test = "beam.uff"
offset = 0.08
resonances = 6

[[case]]
name = "strict"
model = "beam.deck"
test = "beam.uff"
max-iter = 1
fail_below_sfdac = 1.01

[[case]]
name = "missing"
model = "beam.deck"
test = "nowhere.uff"
"#;
    let path = dir.join("campaign.toml");
    std::fs::write(&path, toml).unwrap();
    path
}

#[test]
fn a_campaign_runs_every_case_and_reports_each() {
    let dir = workdir("all");
    let camp = campaign(&dir);
    let out_dir = dir.join("out");
    let out = frfup(&[
        "batch",
        camp.to_str().unwrap(),
        "--out",
        out_dir.to_str().unwrap(),
        "--jobs",
        "2",
    ]);
    // a case could not run: exit 2 wins over the failed threshold
    assert_eq!(
        out.status.code(),
        Some(2),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out_dir.join("summary.json")).unwrap())
            .unwrap();
    let cases = summary["cases"].as_array().unwrap();
    let status: Vec<&str> = cases
        .iter()
        .map(|c| c["status"].as_str().unwrap())
        .collect();
    assert_eq!(status, ["passed", "threshold-failed", "error"]);
    assert!(cases[2]["detail"].as_str().unwrap().contains("nowhere.uff"));
    // the good case recovered the doubled stiffness: SFDAC to ~1
    assert!(cases[0]["sfdac_mean_after"].as_f64().unwrap() > 0.999);
    assert!(cases[0]["sfdac_mean_before"].as_f64().unwrap() < 0.7);
    assert!(
        out_dir.join("good/report.json").exists() && out_dir.join("good/updated.deck").exists()
    );
    let csv = std::fs::read_to_string(out_dir.join("summary.csv")).unwrap();
    assert_eq!(csv.lines().count(), 4, "header + 3 cases");
    assert!(std::fs::read_to_string(out_dir.join("summary.md"))
        .unwrap()
        .contains("| good | passed |"));
    // summary.html: the per-case reports' colours and words, failure in red.
    let html = std::fs::read_to_string(out_dir.join("summary.html")).unwrap();
    assert!(html.contains("class=\"status fail\""), "{html}");
    for (case, class, word) in [
        ("<a href=\"good/report.html\">good</a>", "ok", "✔ passed"),
        ("<a href=\"strict/report.html\">strict</a>", "fail", "✘ "),
        ("missing", "fail", "✘ ERROR — "),
    ] {
        let row = html
            .lines()
            .find(|l| l.starts_with(&format!("<tr><td class=\"l\">{case}</td>")))
            .unwrap_or_else(|| panic!("{case}: no row in\n{html}"));
        assert!(
            row.contains(&format!("<span class=\"status {class}\">{word}")),
            "{row}"
        );
    }
}

#[test]
fn shards_split_the_campaign_deterministically_and_thresholds_give_exit_1() {
    let dir = workdir("shard");
    let camp = campaign(&dir);
    // shard 2/3 holds case index 1 only: "strict", whose threshold fails → exit 1
    let out_dir = dir.join("out2");
    let out = frfup(&[
        "batch",
        camp.to_str().unwrap(),
        "--out",
        out_dir.to_str().unwrap(),
        "--shard",
        "2/3",
    ]);
    assert_eq!(
        out.status.code(),
        Some(1),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out_dir.join("summary.json")).unwrap())
            .unwrap();
    let names: Vec<&str> = summary["cases"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| c["name"].as_str().unwrap())
        .collect();
    assert_eq!(names, ["strict"]);
    assert_eq!(summary["skipped_by_shard"], 2);
    // shard 1/3 holds "good" only → exit 0
    let out = frfup(&[
        "batch",
        camp.to_str().unwrap(),
        "--out",
        dir.join("out1").to_str().unwrap(),
        "--shard",
        "1/3",
    ]);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    // a bad shard is a usage error
    let out = frfup(&[
        "batch",
        camp.to_str().unwrap(),
        "--out",
        dir.join("x").to_str().unwrap(),
        "--shard",
        "4/3",
    ]);
    assert_eq!(out.status.code(), Some(2));
}

#[test]
fn a_bad_campaign_file_names_file_and_line() {
    let dir = workdir("bad");
    let path = dir.join("c.toml");
    // Exit code and stderr of a batch run on the campaign `text`.
    let run = |text: &str| {
        std::fs::write(&path, text).unwrap();
        let out = frfup(&[
            "batch",
            path.to_str().unwrap(),
            "--out",
            dir.join("o").to_str().unwrap(),
        ]);
        (
            out.status.code(),
            String::from_utf8_lossy(&out.stderr).into_owned(),
        )
    };
    let (code, err) = run("[[case]]\nname = \"a\"\nmodel = \"m.deck\"\ntest = \n");
    assert_eq!(code, Some(2));
    assert!(err.contains("c.toml") && err.contains("line 4"), "{err}");
    let (code, err) =
        run("[[case]]\nname = \"a\"\nmodel = \"m.deck\"\ntest = \"t.uff\"\nmodez = 3\n");
    assert_eq!(code, Some(2));
    assert!(err.contains("modez"), "{err}");
    let (code, err) = run(
        "[[case]]\nname = \"a\"\nmodel = \"m.deck\"\ntest = \"t.uff\"\ndamping = 0.05\nresonance-method = \"magic\"\n",
    );
    assert_eq!(code, Some(2));
    assert!(
        err.contains("resonance-method") && err.contains("fit"),
        "{err}"
    );
}

#[test]
fn a_case_that_does_not_converge_is_its_own_failure() {
    let dir = workdir("not-converged");
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    // The paper's iteration on the GARTEUR-like deck, far from its test: it
    // stops on a falling SFDAC.
    let toml = format!(
        "[[case]]\nname = \"garteur\"\nmodel = \"{}\"\ntest = \"{}\"\nmethod = \"paper\"\n",
        root.join("fixtures/garteur/garteur.deck").display(),
        root.join("fixtures/garteur/campaign.uff").display()
    );
    let camp = dir.join("c.toml");
    std::fs::write(&camp, toml).unwrap();
    let out_dir = dir.join("out");
    let out = frfup(&[
        "--quiet",
        "batch",
        camp.to_str().unwrap(),
        "--out",
        out_dir.to_str().unwrap(),
    ]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stdout}{stderr}");
    assert!(
        stdout.contains("1 case(s) run: 0 passed, 1 not converged"),
        "{stdout}"
    );
    assert!(stderr.contains("1 case(s) did not converge"), "{stderr}");
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out_dir.join("summary.json")).unwrap())
            .unwrap();
    assert_eq!(summary["cases"][0]["status"], "not-converged");
    assert_eq!(summary["totals"]["not_converged"], 1);
    assert_eq!(summary["totals"]["failed"], 1);
    let md = std::fs::read_to_string(out_dir.join("summary.md")).unwrap();
    assert!(md.contains("| garteur | not-converged |"), "{md}");
    // As the per-case report says it: red, in capitals.
    let html = std::fs::read_to_string(out_dir.join("summary.html")).unwrap();
    assert!(
        html.contains("<span class=\"status fail\">✘ NOT CONVERGED — "),
        "{html}"
    );
    assert!(md.contains("0 passed, 1 not converged"), "{md}");
    let csv = std::fs::read_to_string(out_dir.join("summary.csv")).unwrap();
    assert!(
        csv.lines()
            .nth(1)
            .unwrap()
            .starts_with("garteur,not-converged,false,"),
        "{csv}"
    );
}
