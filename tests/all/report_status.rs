//! The status box and the estimate of `report.md` / `report.html`: a run that
//! did not converge can never look like a success, and a converged one shows
//! its parameters with their uncertainty.

use std::path::{Path, PathBuf};

use crate::cli_support::{cantilever_case, frfup};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn workdir(name: &str) -> PathBuf {
    let dir = crate::cli_support::scratch_root()
        .join(format!("frfup-report-status-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn read(p: &Path) -> String {
    std::fs::read_to_string(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

#[test]
fn a_run_that_does_not_converge_has_a_red_status_that_says_why() {
    let dir = workdir("red");
    let out = dir.join("out");
    let o = frfup(&[
        "--quiet",
        "update",
        root()
            .join("fixtures/garteur/garteur.deck")
            .to_str()
            .unwrap(),
        root()
            .join("fixtures/garteur/campaign.uff")
            .to_str()
            .unwrap(),
        "--method",
        "paper",
        "--out",
        out.to_str().unwrap(),
    ]);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{stderr}");
    let md = read(&out.join("report.md"));
    let status = md.lines().nth(2).unwrap();
    assert!(
        status.starts_with("> **❌ Status: NOT CONVERGED — ") && status.contains("SFDAC mean fell"),
        "{md}"
    );
    assert!(!md.contains("✅"), "{md}");
    let html = read(&out.join("report.html"));
    assert!(
        html.contains("<div class=\"status fail\""),
        "red box missing"
    );
    assert!(html.contains("✘ Status: NOT CONVERGED — SFDAC mean fell"));
    assert!(!html.contains("status ok"), "a green box on a failed run");
    // the reason is the one the command prints
    assert!(stderr.contains("SFDAC mean fell"), "{stderr}");
}

#[test]
fn a_converged_run_has_a_green_status_and_its_estimate() {
    let dir = workdir("green");
    let (deck, uff) = cantilever_case(&dir);
    let out = dir.join("out");
    let o = frfup(&[
        "--quiet",
        "update",
        &deck,
        &uff,
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let md = read(&out.join("report.md"));
    assert_eq!(
        md.lines().nth(2).unwrap(),
        "> **✅ Status: converged**",
        "{md}"
    );
    assert!(
        md.contains("> Layout: fixed exciter at 16+z, 15 response channel(s)."),
        "{md}"
    );
    assert!(md.contains("## Estimated parameters"), "{md}");
    let p3 = md
        .lines()
        .find(|l| l.starts_with("| p3 |"))
        .unwrap_or_else(|| panic!("no p3 row: {md}"));
    let cells: Vec<&str> = p3.split('|').map(str::trim).collect();
    let value: f64 = cells[2].parse().unwrap();
    // p3 of the noise-free cantilever (exact 1.0), printed to four
    // decimals: measured 0.9999 ± 1.35e-4.
    assert!((value - 1.0).abs() <= 2e-4, "{p3}");
    assert!(cells[3].starts_with("± "), "{p3}");
    assert!(md.contains("damping identified along:"), "{md}");
    let html = read(&out.join("report.html"));
    assert!(html.contains("<div class=\"status ok\""));
    assert!(html.contains("✔ Status: converged"));
    assert!(!html.contains("status fail"));
    assert!(html.contains("Estimated parameters (full-band estimate)"));
}

#[test]
fn the_readers_notes_on_the_inputs_reach_every_report() {
    let dir = workdir("notes");
    let (deck, uff) = cantilever_case(&dir);
    let noted = dir.join("noted.uff");
    let text = format!("exported by hand\n{}", read(Path::new(&uff)));
    std::fs::write(&noted, text).unwrap();
    let out = dir.join("out");
    let o = frfup(&[
        "--quiet",
        "update",
        &deck,
        noted.to_str().unwrap(),
        "--method",
        "paper",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(
        o.status.code().unwrap() <= 1,
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let note = "line 1: 1 line(s) outside any dataset ignored";
    let md = read(&out.join("report.md"));
    assert!(
        md.contains(&format!("- input: {}: {note}", noted.display())),
        "{md}"
    );
    let html = read(&out.join("report.html"));
    assert!(html.contains("<h3>Input files</h3>") && html.contains(note));
    let json: serde_json::Value = serde_json::from_str(&read(&out.join("report.json"))).unwrap();
    assert!(
        json["input_notes"][0].as_str().unwrap().ends_with(note),
        "{json}"
    );
}

#[test]
fn the_readers_notes_reach_the_batch_summary() {
    let dir = workdir("batch-notes");
    let (deck, uff) = cantilever_case(&dir);
    let noted = dir.join("noted.uff");
    std::fs::write(
        &noted,
        format!("exported by hand\n{}", read(Path::new(&uff))),
    )
    .unwrap();
    let camp = dir.join("c.toml");
    std::fs::write(
        &camp,
        format!(
            "[[case]]\nname = \"noted\"\nmodel = \"{deck}\"\ntest = \"{}\"\nmethod = \"paper\"\n",
            noted.display()
        ),
    )
    .unwrap();
    let out = dir.join("out");
    let o = frfup(&[
        "--quiet",
        "batch",
        camp.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(
        o.status.code().unwrap() <= 1,
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let note = "line 1: 1 line(s) outside any dataset ignored";
    let md = read(&out.join("summary.md"));
    assert!(
        md.contains("## Warnings on the inputs") && md.contains(note),
        "{md}"
    );
    let json: serde_json::Value = serde_json::from_str(&read(&out.join("summary.json"))).unwrap();
    assert!(
        json["cases"][0]["input_notes"][0]
            .as_str()
            .unwrap()
            .ends_with(note),
        "{json}"
    );
}
