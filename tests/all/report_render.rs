//! The report of a real update (the paper's cantilever, §4.1, simulated
//! accelerance with noise): every file written, byte-identical on re-runs,
//! a self-contained HTML page, and every SVG rendered to a non-trivial PNG with
//! `rsvg-convert` (skipped with a note when it is missing; `scripts/render_png.sh`
//! installs it).

use std::path::{Path, PathBuf};

use faer::c64;
use frfup::model::ParameterValues;
use frfup::parsers::deck::{parse, Deck};
use frfup::report::{write_report, ReportInputs};
use frfup::simulate::{simulate, Gaussian};
use frfup::testdata::MeasuredFrfs;
use frfup::updating::model_states::model_states;
use frfup::updating::{update, UpdateOptions, UpdateResult};

use crate::campaign_support::{band, z_campaign};
use crate::png_support::{fresh_dir, render_and_check, rsvg_available};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn out_dir(name: &str) -> PathBuf {
    fresh_dir("report_render", name)
}

fn cantilever_deck() -> Deck {
    let text = std::fs::read_to_string(root().join("fixtures/paper/cantilever.deck")).unwrap();
    parse(&text).unwrap()
}

/// Noise (fraction of each channel's RMS): small, as more makes the updater
/// find spurious resonances near 0 Hz.
const NOISE: f64 = 0.0005;

/// Accelerance at z of `channels` for a force at the tip, element group 3
/// twice as stiff as the deck says (the paper's Table 1 case), with NOISE.
fn cantilever_test(deck: &Deck, channels: &[u32]) -> MeasuredFrfs {
    let truth: ParameterValues = [("p3".to_string(), 1.0)].into_iter().collect();
    let campaign = z_campaign(16, channels, band(250.0, 2501));
    let mut test = simulate(deck, &truth, &campaign).unwrap();
    let mut g = Gaussian::new(7);
    for ch in &mut test.channels {
        let rms =
            (ch.values.iter().map(|v| v.norm_sqr()).sum::<f64>() / ch.values.len() as f64).sqrt();
        let sigma = NOISE * rms / std::f64::consts::SQRT_2;
        for v in &mut ch.values {
            *v += c64::new(sigma * g.next(), sigma * g.next());
        }
    }
    test
}

fn run(channels: &[u32]) -> (Deck, MeasuredFrfs, UpdateResult) {
    let deck = cantilever_deck();
    let test = cantilever_test(&deck, channels);
    let opts = UpdateOptions {
        resonances: Some(6),
        ..UpdateOptions::paper()
    };
    let result = update(&deck, &test, &opts).unwrap();
    (deck, test, result)
}

/// The report of `result` written into `dir`, its model states evaluated
/// as the update task does.
fn report_into(
    dir: &Path,
    result: &UpdateResult,
    deck: &Deck,
    test: &MeasuredFrfs,
    inputs: &ReportInputs,
) -> Result<Vec<PathBuf>, frfup::report::ReportError> {
    write_report(
        dir,
        result,
        &model_states(result, deck, test),
        deck,
        test,
        inputs,
    )
}

fn inputs() -> ReportInputs {
    ReportInputs {
        deck_path: "fixtures/paper/cantilever.deck".into(),
        test_path: "simulated (p3 = +1, 0.05 % noise)".into(),
        title: None,
        command: Some("frfup update fixtures/paper/cantilever.deck test.uff --out report".into()),
        input_notes: Vec::new(),
    }
}

fn read(dir: &Path, name: &str) -> Vec<u8> {
    std::fs::read(dir.join(name)).unwrap_or_else(|e| panic!("{name}: {e}"))
}

#[test]
fn report_files_are_complete_and_deterministic() {
    let (deck, test, result) = run(&(2..=16).collect::<Vec<_>>());
    let dir = out_dir("cantilever");
    // A channel chart of an earlier, larger run must not survive.
    std::fs::create_dir_all(dir.join("frf")).unwrap();
    std::fs::write(dir.join("frf/99-old.svg"), "<svg/>").unwrap();
    let files = report_into(&dir, &result, &deck, &test, &inputs()).unwrap();
    assert!(!dir.join("frf/99-old.svg").exists());
    for name in [
        "convergence.svg",
        "frf-overlay.svg",
        "sfdac.svg",
        "frequencies.svg",
        "mac.svg",
        "report.html",
        "iterations.csv",
        "resonances.csv",
        "updating-frequencies.csv",
        "mac.csv",
        "frf.csv",
        "frf/01-2+z_16+z.svg",
        "frf/15-16+z_16+z.svg",
    ] {
        assert!(
            files.contains(&dir.join(name)),
            "{name} not written: {files:?}"
        );
        assert!(dir.join(name).is_file(), "{name}");
    }
    let before: Vec<Vec<u8>> = files.iter().map(|p| std::fs::read(p).unwrap()).collect();
    let again = report_into(&dir, &result, &deck, &test, &inputs()).unwrap();
    assert_eq!(files, again);
    for (p, b) in again.iter().zip(&before) {
        assert_eq!(
            &std::fs::read(p).unwrap(),
            b,
            "{} changed on a re-run",
            p.display()
        );
    }
    // No temporary files left behind.
    for e in std::fs::read_dir(&dir).unwrap().flatten() {
        assert!(!e.file_name().to_string_lossy().ends_with(".tmp"));
    }

    let html = String::from_utf8(read(&dir, "report.html")).unwrap();
    for t in [
        "<!DOCTYPE html>",
        "What was measured",
        "accelerance",
        "16+z",
        "The model",
        "p3",
        "Options",
        "Convergence",
        "SFDAC before and after",
        "Resonance frequencies",
        "MAC",
        "Warnings",
    ] {
        assert!(html.contains(t), "report.html lacks {t}");
    }
    // The charts, the channels and the mode shapes' still images.
    assert_eq!(
        html.matches("<svg").count(),
        5 + 15 + 1,
        "every chart inline"
    );
    // The only scripts: the mode-shape viewer's data blob and code, inline.
    assert_eq!(html.matches("<script").count(), 2);
    for bad in [
        "<script src",
        "<link",
        "src=\"http",
        "href=\"http",
        "@import",
        "url(",
    ] {
        assert!(!html.contains(bad), "report.html not self-contained: {bad}");
    }
    let frf = String::from_utf8(read(&dir, "frf.csv")).unwrap();
    assert!(frf.starts_with(
        "channel,frequency_hz,measured_re[m/s^2/N],measured_im[m/s^2/N],initial_model_re"
    ));
    assert_eq!(frf.lines().count(), 1 + 15 * 2501);
    let res = String::from_utf8(read(&dir, "resonances.csv")).unwrap();
    assert!(res.starts_with("resonance,frequency_hz,damping_ratio"));
    assert!(res.lines().count() >= 6);
    eprintln!("report written to {}", dir.display());
}

#[test]
fn single_channel_and_degenerate_results_still_report() {
    // The driving point only: one channel, one measured DOF.
    let deck = cantilever_deck();
    let test = cantilever_test(&deck, &[16]);
    match update(&deck, &test, &UpdateOptions::paper()) {
        Ok(result) => {
            let dir = out_dir("single");
            report_into(&dir, &result, &deck, &test, &inputs()).unwrap();
            assert!(dir.join("frf/01-16+z_16+z.svg").is_file());
        }
        Err(e) => {
            eprintln!("note: one channel cannot be updated ({e}); degenerate result below instead")
        }
    }
    // A run cut to its initial model, with NaN correlation and no resonances.
    let (deck, test, mut result) = run(&[4, 8, 12, 16]);
    result.iterations.truncate(1);
    result.final_iteration = 0;
    result.iterations[0]
        .sfdac
        .values
        .iter_mut()
        .for_each(|v| *v = f64::NAN);
    result.iterations[0].sfdac.mean = f64::NAN;
    result.resonances.clear();
    let dir = out_dir("degenerate");
    report_into(&dir, &result, &deck, &test, &inputs()).unwrap();
    // No iterations at all.
    result.iterations.clear();
    report_into(&dir, &result, &deck, &test, &inputs()).unwrap();
    let html = String::from_utf8(read(&dir, "report.html")).unwrap();
    assert!(html.contains("no iteration"));
}

#[test]
fn every_chart_renders_to_a_png() {
    if !rsvg_available() {
        return;
    }
    let (deck, test, result) = run(&(2..=16).collect::<Vec<_>>());
    let dir = out_dir("png");
    let files = report_into(&dir, &result, &deck, &test, &inputs()).unwrap();
    let svgs: Vec<&PathBuf> = files
        .iter()
        .filter(|p| p.extension().is_some_and(|e| e == "svg"))
        .collect();
    // The charts, the channels and `mode-shapes.svg`.
    assert_eq!(svgs.len(), 5 + 15 + 1);
    for svg in svgs {
        render_and_check(svg, &svg.with_extension("png"));
    }
    eprintln!("PNGs in {}", dir.display());
}

/// The GARTEUR-like campaign (26 channels, 20 parameters, free-free): a large
/// report to look at. `cargo test --test all report_render:: -- --ignored`.
#[test]
#[ignore = "slow: a full GARTEUR update"]
fn garteur_report() {
    let deck_text = std::fs::read_to_string(root().join("fixtures/garteur/garteur.deck")).unwrap();
    let deck = parse(&deck_text).unwrap();
    let test = frfup::testdata::load(&root().join("fixtures/garteur/campaign.uff")).unwrap();
    let result = update(&deck, &test, &UpdateOptions::paper()).unwrap();
    let dir = out_dir("garteur");
    let inputs = ReportInputs {
        deck_path: "fixtures/garteur/garteur.deck".into(),
        test_path: "fixtures/garteur/campaign.uff".into(),
        title: None,
        command: None,
        input_notes: Vec::new(),
    };
    let files = report_into(&dir, &result, &deck, &test, &inputs).unwrap();
    if rsvg_available() {
        for svg in files
            .iter()
            .filter(|p| p.extension().is_some_and(|e| e == "svg"))
        {
            render_and_check(svg, &svg.with_extension("png"));
        }
    }
    eprintln!("GARTEUR report in {}", dir.display());
}
