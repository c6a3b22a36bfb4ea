//! `frfup modes` and `frfup simulate` end to end, against closed-form answers.

use crate::cli_support::{fixture, frfup, scratch};
use std::path::{Path, PathBuf};

fn tmp(name: &str) -> PathBuf {
    scratch("model", name)
}

/// Closed-form cantilever frequencies f_r = (β_r L)² / (2π L²) √(EI / ρA).
fn cantilever_hz(r: usize) -> f64 {
    let beta_l = [1.875_104_068_7, 4.694_091_132_9, 7.854_757_438_2][r];
    let (e, i, rho, a, l): (f64, f64, f64, f64, f64) = (2e11, 8.33e-10, 7800.0, 1e-4, 1.8);
    beta_l * beta_l / (2.0 * std::f64::consts::PI * l * l) * (e * i / (rho * a)).sqrt()
}

#[test]
fn modes_of_the_paper_cantilever_match_the_closed_form() {
    let csv = tmp("modes.csv");
    let out = frfup(&[
        "modes",
        &fixture("paper/cantilever.deck"),
        "--count",
        "3",
        "--csv",
        csv.to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = std::fs::read_to_string(&csv).unwrap();
    let mut lines = text.lines();
    assert!(lines.next().unwrap().starts_with("mode,frequency_hz"));
    for (r, line) in lines.enumerate() {
        let f: f64 = line.split(',').nth(1).unwrap().parse().unwrap();
        // 15 cubic elements: discretisation error ~ (h β)^4 — below 1e-4 relative for the first 3 modes
        let exact = cantilever_hz(r);
        assert!(
            (f - exact).abs() < 1e-4 * exact,
            "mode {}: {f} vs {exact}",
            r + 1
        );
    }
}

#[test]
fn a_bad_deck_names_file_line_and_column_and_exits_2() {
    let deck = tmp("bad.deck");
    std::fs::write(&deck, "material steel E=2e11 rho=7800\nsection s A=1e-4 Iy=1e-9 Iz=1e-9 J=1e-9\nnode 1 0 0 0\nnode 2 1 0 0\nbeam 1 1 3 steel s\n").unwrap();
    let out = frfup(&["modes", deck.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("bad.deck:5:"), "{err}");
    assert!(err.contains('3'), "names the undefined node: {err}");
}

#[test]
fn simulate_is_reproducible_and_its_noise_has_the_asked_level() {
    let deck = fixture("paper/cantilever.deck");
    let clean = tmp("clean.uff");
    let noisy_a = tmp("noisy-a.uff");
    let noisy_b = tmp("noisy-b.uff");
    let base = [
        "simulate",
        deck.as_str(),
        "--input",
        "16:+z",
        "--band",
        "1:200:400",
        "--sensors",
        "8:+z,16:+z",
    ];
    for (path, extra) in [
        (&clean, vec![]),
        (&noisy_a, vec!["--noise", "0.02", "--seed", "7"]),
        (&noisy_b, vec!["--noise", "0.02", "--seed", "7"]),
    ] {
        let mut args: Vec<&str> = base.to_vec();
        args.extend(["--out", path.to_str().unwrap()]);
        args.extend(extra);
        let out = frfup(&args);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
    assert_eq!(
        std::fs::read(&noisy_a).unwrap(),
        std::fs::read(&noisy_b).unwrap(),
        "same seed, same bytes"
    );
    let read = |p: &Path| frfup::testdata::load(p).unwrap();
    let (c, n) = (read(&clean), read(&noisy_a));
    assert_eq!(c.channels.len(), 2);
    for (cc, nc) in c.channels.iter().zip(&n.channels) {
        let rms =
            (cc.values.iter().map(|v| v.norm_sqr()).sum::<f64>() / cc.values.len() as f64).sqrt();
        let noise = (cc
            .values
            .iter()
            .zip(&nc.values)
            .map(|(a, b)| (a - b).norm_sqr())
            .sum::<f64>()
            / cc.values.len() as f64)
            .sqrt();
        // 400 complex samples: the sample RMS of the noise is within ~10 % of 0.02·RMS (3σ ≈ 3/√800)
        assert!(
            (noise / rms - 0.02).abs() < 0.002,
            "noise/rms = {}",
            noise / rms
        );
    }
}

#[test]
fn simulate_rejects_an_unknown_parameter_and_an_unknown_dof() {
    let deck = fixture("paper/cantilever.deck");
    let out_path = tmp("never.uff");
    let out = frfup(&[
        "simulate",
        &deck,
        "--input",
        "16:+z",
        "--band",
        "1:10:5",
        "--out",
        out_path.to_str().unwrap(),
        "--set",
        "nope=1",
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("nope"));
    let out = frfup(&[
        "simulate",
        &deck,
        "--input",
        "99:+z",
        "--band",
        "1:10:5",
        "--out",
        out_path.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("99"));
    assert!(!out_path.exists());
}

/// `diagnose` takes the update's options for its first step; the missing 2 %
/// modal damping is found (truth ζ = 0.02; measured 0.0200) and a bad option
/// value is a usage error.
#[test]
fn diagnose_takes_update_options_and_finds_the_damping() {
    let out_dir = tmp("diagnose-damping");
    let (deck, uff) = (
        fixture("diagnose/damping.deck"),
        fixture("diagnose/damping.uff"),
    );
    let run = |options: &[&str]| {
        let mut args = vec!["diagnose", &deck, &uff, "--out", out_dir.to_str().unwrap()];
        args.extend_from_slice(options);
        frfup(&args)
    };
    let out = run(&["--resonance-method", "fit", "--frequencies-first"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let d: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out_dir.join("diagnosis.json")).unwrap())
            .unwrap();
    let f = &d["findings"][0];
    assert_eq!(f["physics"], "damping");
    // The command writes the report and its charts too.
    for (name, min) in [
        ("report.md", 500),
        ("report.html", 20_000),
        ("localisation.svg", 5_000),
        ("frf-overlay.svg", 5_000),
    ] {
        let len = std::fs::metadata(out_dir.join(name)).map_or(0, |m| m.len());
        assert!(len > min, "{name}: {len} bytes");
    }
    // As diagnose_cases::missing_damping: within 3σ of the truth 0.02, σ as
    // written (measured ζ = 0.020014, σ = 1.7e-5).
    let zeta = f["parameters"]["zeta"].as_f64().unwrap();
    let sigma = f["uncertainty"]["zeta"].as_f64().unwrap();
    assert!((zeta - 0.02).abs() <= 3.0 * sigma, "zeta {zeta} ± {sigma}");
    assert!(sigma <= 1e-4, "σ {sigma}");
    assert_eq!(run(&["--resonance-method", "guess"]).status.code(), Some(2));
}
