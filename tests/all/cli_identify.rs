//! `frfup identify` end to end on fixture campaigns simulated from decks
//! (`fixtures/diagnose/*.uff`, 1 % damping, noise added): the modes against
//! the truth deck's, the files, UFF 55 read back by our reader and by pyuff,
//! and bad input refused with exit 2.

use std::path::PathBuf;
use std::process::Command;

use crate::cli_support::{csv_rows, fixture, frfup, pyuff_available, scratch};
use frfup_parsers::uff::{self, Dataset, OtherKind};

fn tmp(name: &str) -> PathBuf {
    scratch("identify", name)
}

/// The `joint` campaign: 5 modes in band; the truth deck made it.
/// Each test its own folder (tests run in parallel).
fn identify_joint(name: &str) -> PathBuf {
    let out = tmp(name);
    let run = frfup(&[
        "identify",
        &fixture("diagnose/joint.uff"),
        "--out",
        out.to_str().unwrap(),
        "--deck",
        &fixture("diagnose/joint.truth.deck"),
    ]);
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    out
}

#[test]
fn joint_modes_match_the_truth_deck() {
    let out = identify_joint("match");
    for f in [
        "modes.csv",
        "shapes.csv",
        "modes.uff",
        "stabilisation.svg",
        "synthesis.svg",
        "report.html",
        "pairs.csv",
        "mac.svg",
    ] {
        assert!(out.join(f).is_file(), "{f} missing");
    }
    let modes = csv_rows(&out.join("modes.csv"));
    assert_eq!(modes[0][0..3], ["mode", "frequency_hz", "damping_ratio"]);
    assert_eq!(modes.len(), 6, "5 modes expected: {modes:?}");
    // Every mode pairs with the truth's: the campaign's noise (1 %) and
    // 0.25 Hz lines allow about 1e-4 in frequency (measured ≤ 5.2e-5) and
    // MAC 0.998 (measured ≥ 0.9988).
    let pairs = csv_rows(&out.join("pairs.csv"));
    assert_eq!(pairs.len(), 6, "{pairs:?}");
    for p in &pairs[1..] {
        let err: f64 = p[4].parse().unwrap();
        let mac: f64 = p[5].parse().unwrap();
        assert!(err.abs() < 0.01 && mac > 0.998, "{p:?}");
    }
    for m in &modes[1..] {
        let zeta: f64 = m[2].parse().unwrap();
        let mpc: f64 = m[4].parse().unwrap();
        assert!((zeta / 0.01 - 1.0).abs() < 0.01, "damping {m:?}");
        assert!(mpc > 0.99 && m[6] == "elastic", "{m:?}");
    }
    let shapes = csv_rows(&out.join("shapes.csv"));
    assert_eq!(shapes[0].len(), 3 + 3 * 5);
    let html = std::fs::read_to_string(out.join("report.html")).unwrap();
    assert!(html.contains("<svg") && html.contains("Pairing with"));
    // Self-contained: the viewer's inline scripts only, nothing fetched (the
    // SVG namespace is a name).
    assert_eq!(html.matches("<script").count(), 2);
    assert!(
        !html.contains("<script src")
            && !html.contains("src=\"http")
            && !html.contains("href=\"http")
    );
}

/// `--verbose` gives one `time:` line per stage, the identification's own
/// stages among them, and nothing of it reaches the output files.
#[test]
fn verbose_prints_the_stage_timings() {
    let (quiet, loud) = (tmp("timings-quiet"), tmp("timings-verbose"));
    let run = |out: &PathBuf, extra: &[&str]| {
        let mut args = vec![
            "identify",
            "--quiet",
            "--out",
            out.to_str().unwrap(),
            "--deck",
        ];
        let (campaign, deck) = (
            fixture("diagnose/joint.uff"),
            fixture("diagnose/joint.truth.deck"),
        );
        args.push(&deck);
        args.extend_from_slice(extra);
        args.push(&campaign);
        let o = frfup(&args);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        String::from_utf8_lossy(&o.stderr).into_owned()
    };
    assert!(!run(&quiet, &[]).contains("time:"));
    let stderr = run(&loud, &["--verbose"]);
    let stages: Vec<&str> = stderr.lines().filter(|l| l.starts_with("time: ")).collect();
    for name in [
        "read the inputs",
        "poles per order (diagram)",
        "residues, refinement (LSFD)",
        "write the folder",
    ] {
        assert!(
            stages.iter().any(|l| l.contains(name)),
            "{name} missing in {stderr}"
        );
    }
    assert_eq!(stages.len(), 8, "{stderr}");
    for file in ["modes.csv", "shapes.csv", "modes.uff", "report.html"] {
        assert_eq!(
            std::fs::read(quiet.join(file)).unwrap(),
            std::fs::read(loud.join(file)).unwrap(),
            "{file}"
        );
    }
}

#[test]
fn modes_uff_reads_back() {
    let out = identify_joint("readback");
    let file = uff::parse(&std::fs::read(out.join("modes.uff")).unwrap()).unwrap();
    let modes = csv_rows(&out.join("modes.csv"));
    let sets: Vec<_> = file
        .datasets
        .iter()
        .map(|d| match d {
            Dataset::Other(o) => match &o.kind {
                OtherKind::NodalData(n) => n.clone(),
                k => panic!("{k:?}"),
            },
            Dataset::Function(_) => panic!("no function expected"),
        })
        .collect();
    assert_eq!(sets.len(), modes.len() - 1);
    for (d, m) in sets.iter().zip(&modes[1..]) {
        let f: f64 = m[1].parse().unwrap();
        let z: f64 = m[2].parse().unwrap();
        assert_eq!(d.analysis_type, 2);
        // E13.5: 6 significant digits.
        assert!((d.reals[0] / f - 1.0).abs() < 1e-5 && (d.reals[2] / z - 1.0).abs() < 1e-5);
        assert!(!d.nodes.is_empty());
    }
}

#[test]
fn pyuff_reads_modes_uff() {
    if !pyuff_available() {
        return;
    }
    let out = identify_joint("pyuff");
    let script = "import sys, pyuff\n\
        u = pyuff.UFF(sys.argv[1])\n\
        for d in u.read_sets():\n\
        \x20   print(d['type'], d['mode_n'], repr(d['freq']), repr(d['modal_damp_vis']), len(d['node_nums']))\n";
    let run = Command::new("python3")
        .args(["-c", script, out.join("modes.uff").to_str().unwrap()])
        .output()
        .unwrap();
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let text = String::from_utf8(run.stdout).unwrap();
    let modes = csv_rows(&out.join("modes.csv"));
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines.len(), modes.len() - 1, "{text}");
    for (l, m) in lines.iter().zip(&modes[1..]) {
        let v: Vec<&str> = l.split_whitespace().collect();
        assert_eq!(v[0], "55");
        assert_eq!(v[1], m[0], "mode number");
        let f: f64 = v[2].parse().unwrap();
        let z: f64 = v[3].parse().unwrap();
        let want_f: f64 = m[1].parse().unwrap();
        let want_z: f64 = m[2].parse().unwrap();
        assert!(
            (f / want_f - 1.0).abs() < 1e-5 && (z / want_z - 1.0).abs() < 1e-5,
            "{l}"
        );
        assert!(v[4].parse::<usize>().unwrap() > 0);
    }
}

#[test]
fn bad_input_exits_2_with_a_message() {
    let out = tmp("bad");
    let o = out.to_str().unwrap();
    let cases: [(&[&str], &str); 4] = [
        (
            &["identify", "no-such-file.uff", "--out", o],
            "no-such-file.uff",
        ),
        (
            &[
                "identify",
                &fixture("diagnose/joint.uff"),
                "--out",
                o,
                "--band",
                "50:10",
            ],
            "--band",
        ),
        (
            &[
                "identify",
                &fixture("diagnose/joint.uff"),
                "--out",
                o,
                "--max-order",
                "2",
            ],
            "max order",
        ),
        (
            &[
                "identify",
                &fixture("diagnose/joint.uff"),
                "--out",
                o,
                "--band",
                "1000:2000",
            ],
            "line",
        ),
    ];
    for (args, needle) in cases {
        let run = frfup(args);
        let err = String::from_utf8_lossy(&run.stderr);
        assert_eq!(run.status.code(), Some(2), "{args:?}: {err}");
        assert!(err.contains(needle), "{args:?}: {err}");
    }
}

/// A record longer than two of the LSCF's fixed 4,096-line chunks (10,001
/// lines, 3 chunks) gives the same modes and shapes, byte for byte, on 1
/// thread as on 3: the chunks' sums are added in chunk order whatever
/// thread computed them.
#[test]
fn a_long_record_gives_the_same_modes_on_one_and_on_three_threads() {
    let uff = tmp("long-record.uff");
    crate::cli_support::frfup_ok(&[
        "simulate",
        &fixture("diagnose/joint.truth.deck"),
        "--input",
        "6:+z",
        "--band",
        "2:300:10001",
        "--noise",
        "0.01",
        "--out",
        uff.to_str().unwrap(),
        "--quiet",
    ]);
    let run = |threads: &str| {
        let out = tmp(&format!("long-record-t{threads}"));
        crate::cli_support::frfup_ok_on_threads(
            &[
                "identify",
                uff.to_str().unwrap(),
                "--out",
                out.to_str().unwrap(),
                "--quiet",
            ],
            threads,
        );
        out
    };
    let (one, three) = (run("1"), run("3"));
    for f in ["modes.csv", "shapes.csv"] {
        let a = std::fs::read(one.join(f)).unwrap();
        let b = std::fs::read(three.join(f)).unwrap();
        assert!(a == b, "{f} differs between 1 and 3 threads");
    }
    // Five modes in the band, as in the 600-line campaign.
    assert_eq!(csv_rows(&one.join("modes.csv")).len(), 6);
}
