//! `frfup update` with its defaults on the test layouts of issue 16 item 4
//! whose driving point was not measured: a shaker with only a force gauge
//! at the tip, and a roving hammer that never hits the accelerometer's
//! point. The paper's cantilever (damped, 1 % noise) with two parameters
//! changed; the update must say that the driving point was not measured and
//! still recover them (measured when written: errors ≤ 1.2e-4 at a standard
//! deviation near 1e-4; the tolerance, 1e-3, is ten of them).

use std::path::Path;

use crate::cli_support::{csv_rows, fixture, frfup, frfup_ok, workdir};

/// The cantilever with modal damping, simulated with `layout` arguments;
/// returns (deck, test) paths.
fn campaign(dir: &Path, layout: &[&str]) -> (String, String) {
    let deck = dir.join("beam.deck");
    let text = std::fs::read_to_string(fixture("paper/cantilever.deck")).unwrap();
    std::fs::write(&deck, text + "damping modal 0.01\n").unwrap();
    let uff = dir.join("beam.uff");
    let (d, u) = (deck.to_str().unwrap(), uff.to_str().unwrap());
    let mut args = vec![
        "simulate",
        d,
        "--band",
        "1:300:1200",
        "--noise",
        "0.01",
        "--seed",
        "3",
        "--set",
        "p1=-0.2",
        "--set",
        "p3=0.3",
        "--out",
        u,
    ];
    args.extend_from_slice(layout);
    frfup_ok(&args);
    (d.to_string(), u.to_string())
}

/// Run the default update; check the warning, the exit code and p1, p3.
fn update_recovers(dir: &Path, deck: &str, test: &str, driving: &str) {
    let out = dir.join("out");
    let run = frfup(&["update", deck, test, "--out", out.to_str().unwrap()]);
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert_eq!(run.status.code(), Some(0), "{stderr}");
    assert!(
        stderr.contains(&format!("the driving point {driving} was not measured")),
        "{stderr}"
    );
    let rows = csv_rows(&out.join("estimates.csv"));
    let value = |name: &str| -> f64 {
        let r = rows.iter().find(|r| r[0] == name).expect(name);
        r[1].parse().unwrap()
    };
    for (name, truth) in [
        ("p1", -0.2),
        ("p2", 0.0),
        ("p3", 0.3),
        ("p4", 0.0),
        ("p5", 0.0),
    ] {
        let v = value(name);
        assert!((v - truth).abs() < 1e-3, "{name} = {v}, truth {truth}");
    }
}

#[test]
fn fixed_exciter_without_its_driving_point() {
    let dir = workdir("layout-no-driving-point");
    let sensors: Vec<String> = (2..=15).map(|n| format!("{n}:+z")).collect();
    let s = sensors.join(",");
    let (deck, test) = campaign(&dir, &["--input", "16:+z", "--sensors", &s]);
    update_recovers(&dir, &deck, &test, "16+z");
}

#[test]
fn roving_hammer_that_never_hits_the_sensor_point() {
    let dir = workdir("layout-hammer-off-sensor");
    let hits: Vec<String> = (2..=16)
        .filter(|&n| n != 12)
        .map(|n| format!("{n}:+z"))
        .collect();
    let s = hits.join(",");
    let (deck, test) = campaign(&dir, &["--response", "12:+z", "--sensors", &s]);
    update_recovers(&dir, &deck, &test, "12+z");
}
