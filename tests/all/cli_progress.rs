//! Progress is for terminals: with stderr captured (a pipe, as here, and no
//! `CI` variable) a run prints no progress, only warnings, notes and the
//! one-line "wrote" summaries; `--progress` asks for it as plain lines.

use std::process::Command;

use crate::cli_support::{cantilever_case, fixture, workdir};

/// Run without `CI` set: only the terminal test decides.
fn run(args: &[&str]) -> (i32, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_frfup"))
        .args(args)
        .env_remove("CI")
        .output()
        .expect("run frfup");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

fn only_warnings(what: &str, stderr: &str) {
    for line in stderr.lines() {
        assert!(
            ["warning: ", "note: ", "wrote "]
                .iter()
                .any(|p| line.starts_with(p)),
            "{what}: {line:?} on stderr:\n{stderr}"
        );
    }
}

#[test]
fn no_progress_when_stderr_is_not_a_terminal() {
    let dir = workdir("progress");
    let (deck, uff) = cantilever_case(&dir);
    let out = |name: &str| dir.join(name).to_str().unwrap().to_string();
    let campaign = dir.join("campaign.toml");
    std::fs::write(
        &campaign,
        "[[case]]\nname = \"beam\"\nmodel = \"beam.deck\"\ntest = \"beam.uff\"\n",
    )
    .unwrap();
    let (ddeck, duff) = (
        fixture("diagnose/damping.deck"),
        fixture("diagnose/damping.uff"),
    );
    let runs: Vec<(&str, Vec<String>)> = vec![
        (
            "update",
            vec![
                "update".into(),
                deck.clone(),
                uff.clone(),
                "--out".into(),
                out("u"),
            ],
        ),
        (
            "diagnose",
            vec![
                "diagnose".into(),
                ddeck.clone(),
                duff.clone(),
                "--out".into(),
                out("d"),
            ],
        ),
        (
            "batch",
            vec![
                "batch".into(),
                campaign.to_str().unwrap().into(),
                "--out".into(),
                out("b"),
            ],
        ),
        ("convert", vec!["convert".into(), uff.clone(), out("c.csv")]),
        ("modes", vec!["modes".into(), deck.clone()]),
        ("info", vec!["info".into(), uff.clone()]),
        (
            "simulate",
            vec![
                "simulate".into(),
                deck.clone(),
                "--input".into(),
                "16:+z".into(),
                "--band".into(),
                "1:100:50".into(),
                "--out".into(),
                out("s.uff"),
            ],
        ),
    ];
    for (what, args) in &runs {
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let (code, stderr) = run(&args);
        assert!(code == 0 || code == 1, "{what}: exit {code}: {stderr}");
        only_warnings(what, &stderr);
    }
    // --progress (a global flag, after the command's own): one line per stage.
    let (code, stderr) = run(&["diagnose", &ddeck, &duff, "--out", &out("d2"), "--progress"]);
    assert_eq!(code, 0, "{stderr}");
    assert!(stderr.contains("searching for missing physics"), "{stderr}");
    assert!(stderr.contains("writing the report"), "{stderr}");
    let (code, stderr) = run(&["update", &deck, &uff, "--out", &out("u2"), "--progress"]);
    assert!(code == 0 || code == 1, "{stderr}");
    assert!(stderr.contains("iteration 1:"), "{stderr}");
    // The full-band estimate is named while it runs, and its record after.
    let started = stderr.find("full-band estimate: all lines");
    let scored = stderr.find("full-band estimate: SFDAC mean");
    assert!(
        started.is_some() && started < scored,
        "the estimate's stage is not shown: {stderr}"
    );
    let (code, stderr) = run(&["identify", &duff, "--out", &out("i"), "--progress"]);
    assert_eq!(code, 0, "{stderr}");
    assert!(stderr.contains("identifying modes: 4 FRF(s)"), "{stderr}");
    assert!(stderr.contains("writing the report"), "{stderr}");
    let (code, stderr) = run(&["modes", &deck, "--progress"]);
    assert_eq!(code, 0, "{stderr}");
    assert!(stderr.contains("mode(s) of a"), "{stderr}");
    let s2 = out("s2.uff");
    let args = ["simulate", &deck, "--input", "16:+z", "--band", "1:100:50"];
    let (code, stderr) = run(&[&args[..], &["--out", &s2, "--progress"]].concat());
    assert_eq!(code, 0, "{stderr}");
    assert!(stderr.contains("computing the FRFs of"), "{stderr}");
    assert!(stderr.contains(" record(s) to "), "{stderr}");
}
