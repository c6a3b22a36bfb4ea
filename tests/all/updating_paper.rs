//! The benchmarks of Yan & Golinval §4.1–4.3 as integration tests: "measured"
//! FRFs are simulated (complex accelerance, as acquisition software writes it)
//! from the deck at the true parameter values, then the initial deck is updated.

use std::path::PathBuf;

use faer::c64;
use frfup::model::ParameterValues;
use frfup::parsers::deck::{parse, Deck};
use frfup::simulate::{simulate, Band, Gaussian};
use frfup::testdata::MeasuredFrfs;
use frfup::updating::{update, FrfWeighting, UpdateOptions, UpdateResult};

use crate::campaign_support::z_campaign;

fn fixture(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("fixtures/paper")
        .join(name)
}

fn deck(name: &str) -> Deck {
    parse(&std::fs::read_to_string(fixture(name)).unwrap()).unwrap()
}

fn values(v: &[(&str, f64)]) -> ParameterValues {
    v.iter().map(|(n, x)| (n.to_string(), *x)).collect()
}

/// Accelerance at z of `nodes` for a unit force at `input` z.
fn measure(
    deck: &Deck,
    truth: &ParameterValues,
    input: u32,
    nodes: &[u32],
    band: Band,
) -> MeasuredFrfs {
    let campaign = z_campaign(input, nodes, band);
    simulate(deck, truth, &campaign).unwrap()
}

/// Complex Gaussian noise as the paper states it ("% of RMS of FRF data in
/// chosen frequencies"), read per frequency line: at every line the standard
/// deviation is `fraction` × the RMS over channels of |H| at that line, so each
/// updating frequency has the stated signal-to-noise ratio; fixed seed.
fn add_noise(frfs: &mut MeasuredFrfs, fraction: f64, seed: u64) {
    let mut g = Gaussian::new(seed);
    let nch = frfs.channels.len() as f64;
    for l in 0..frfs.frequencies_hz.len() {
        let rms = (frfs
            .channels
            .iter()
            .map(|c| c.values[l].norm_sqr())
            .sum::<f64>()
            / nch)
            .sqrt();
        let sigma = fraction * rms / std::f64::consts::SQRT_2;
        for ch in &mut frfs.channels {
            ch.values[l] += c64::new(sigma * g.next(), sigma * g.next());
        }
    }
}

fn show(name: &str, r: &UpdateResult) {
    eprintln!(
        "== {name}: converged {} ({}), final {}",
        r.converged,
        r.stop.name(),
        r.final_iteration
    );
    eprintln!("updating frequencies {:?}", r.updating_frequencies.hz());
    for it in &r.iterations {
        let p: Vec<String> = it.parameters.iter().map(|x| format!("{x:+.5}")).collect();
        eprintln!(
            "  it {} [{}] sfdac mean {:.4} min {:.4} rank {} basis {}",
            it.index,
            p.join(" "),
            it.sfdac.mean,
            it.sfdac.min,
            it.rank,
            it.basis_modes.len()
        );
    }
    let rows = frfup::report::output::frequency_rows(r);
    for (i, row) in rows.iter().enumerate() {
        eprintln!(
            "  mode {} test {:.3} initial {:?} updated {:?}",
            i + 1,
            row.test_hz,
            row.initial.map(|x| x.0),
            row.updated.map(|x| x.0)
        );
    }
    for w in &r.warnings {
        eprintln!("  warning: {w}");
    }
}

fn band(end_hz: f64, step_hz: f64) -> Band {
    Band {
        start_hz: 0.0,
        end_hz,
        count: (end_hz / step_hz).round() as usize + 1,
    }
}

#[test]
fn cantilever_table1() {
    let d = deck("cantilever.deck");
    let truth = values(&[("p3", 1.0)]);
    let nodes: Vec<u32> = (2..=16).collect();
    let test = measure(&d, &truth, 16, &nodes, band(250.0, 0.05));
    let modes: Option<usize> = std::env::var("MODES").ok().map(|s| s.parse().unwrap());
    let opts = UpdateOptions {
        resonances: Some(6),
        offset: 0.08,
        modes,
        ..UpdateOptions::paper()
    };
    let r = update(&d, &test, &opts).unwrap();
    show("cantilever", &r);
    assert_eq!(r.updating_frequencies.len(), 12);
    assert!(r.converged);
    // Table 1 as printed: 3 iterations, final SFDAC ~1.0000 (ours 0.99997).
    assert_eq!(r.iterations.len() - 1, 3, "iterations");
    let last = r.final_record().sfdac.mean;
    assert!(last >= 0.99995, "final SFDAC {last}");
    // Noise-free data: what is left is the last step. The paper's iteration 3
    // is within 4.6e-4 of exact (p2); ours within 6.2e-4 (p5), p3 1.1e-4.
    let p = r.parameters();
    for (j, exact) in [0.0, 0.0, 1.0, 0.0, 0.0].into_iter().enumerate() {
        assert!((p[j] - exact).abs() <= 1e-3, "p{} in {p:?}", j + 1);
    }
    // The initial SFDAC is not the paper's 0.6409 to its digits (its twelve
    // frequencies are not printed; ours are ±8 % of our test resonances):
    // ours, 0.63317, is a fixed number of this deck and campaign (to 1e-4),
    // within 0.008 of the paper's.
    let first = r.iterations[0].sfdac.mean;
    assert!((first - 0.63317).abs() <= 1e-4, "initial SFDAC {first}");
    assert!((first - 0.6409).abs() <= 0.008, "initial SFDAC {first}");
}

#[test]
fn cantilever_element8_spreads_over_7_to_9() {
    let d = deck("cantilever15.deck");
    let truth = values(&[("e8", 1.0)]);
    let nodes: Vec<u32> = (2..=16).collect();
    let test = measure(&d, &truth, 16, &nodes, band(250.0, 0.05));
    let opts = UpdateOptions {
        resonances: Some(6),
        offset: 0.08,
        ..UpdateOptions::paper()
    };
    let r = update(&d, &test, &opts).unwrap();
    show("cantilever15", &r);
    // Nearly ill-conditioned (15 neighbouring elements): the defect must land on
    // elements 7-9; the weakly sensitive tip elements wander (measured after
    // the 20 iterations of the limit: element 8 at 1.032, sum 7-9 1.016;
    // elements 1-5 within 0.003, 11-13 within 0.045, 14-15 at 0.09, -0.23).
    let p = r.parameters();
    let pos: f64 = p.iter().map(|x| x.max(0.0)).sum();
    let centroid: f64 = p
        .iter()
        .enumerate()
        .map(|(j, x)| (j + 1) as f64 * x.max(0.0))
        .sum::<f64>()
        / pos;
    assert!((7.0..=9.0).contains(&centroid), "centroid {centroid}");
    let sum79: f64 = p[6..9].iter().sum();
    assert!((sum79 - 1.0).abs() < 0.05, "sum 7-9 {sum79}");
    for (j, bound) in (0..5).map(|j| (j, 0.01)).chain((10..13).map(|j| (j, 0.06))) {
        assert!(p[j].abs() < bound, "element {} {}", j + 1, p[j]);
    }
}

#[test]
fn framework_table2() {
    let d = deck("framework.deck");
    let truth = values(&[("p1", -0.2), ("p4", 1.0), ("p6", 1.0)]);
    let nodes: Vec<u32> = (2..=26).collect();
    let test = measure(&d, &truth, 26, &nodes, band(400.0, 0.05));
    let opts = UpdateOptions {
        modes: Some(8),
        resonances: Some(8),
        offset: 0.06,
        ..UpdateOptions::paper()
    };
    let r = update(&d, &test, &opts).unwrap();
    show("framework", &r);
    assert_eq!(r.updating_frequencies.len(), 16);
    assert!(r.converged);
    // Converged at iteration 5 (the paper: 8) within 0.011 of exact (p6; the
    // paper's largest is 0.025, p5): the stopping rule's last step.
    let exact = [-0.2, 0.0, 0.0, 1.0, 0.0, 1.0, 0.0];
    for (j, (p, e)) in r.parameters().iter().zip(exact).enumerate() {
        assert!((p - e).abs() <= 0.015, "p{} = {p}, exact {e}", j + 1);
    }
}

/// Our equivalents of Table 3's chosen frequencies (6, 24, 36, 59, 145, 166,
/// 190, 240 Hz for the paper's structure), by the paper's rule: 5-10 % from a
/// test resonance, not where the initial FE and test resonances differ much,
/// spread over the band.
const FRAME3D_FREQS: [f64; 8] = [1.6, 3.5, 13.0, 46.0, 80.0, 106.0, 163.0, 230.0];
const FRAME3D_EXACT: [f64; 6] = [-0.2, 0.2, 0.3, -0.1, 0.5, 0.6];

fn frame3d(noise: f64) -> UpdateResult {
    frame3d_seeded(noise, 2024)
}

fn frame3d_seeded(noise: f64, seed: u64) -> UpdateResult {
    frame3d_with(noise, seed, &|_| {})
}

fn frame3d_with(noise: f64, seed: u64, tweak: &dyn Fn(&mut UpdateOptions)) -> UpdateResult {
    let d = deck("frame3d.deck");
    let names = ["p1", "p2", "p3", "p4", "p5", "p6"];
    let truth: ParameterValues = names
        .iter()
        .map(|n| n.to_string())
        .zip(FRAME3D_EXACT)
        .collect();
    let nodes: Vec<u32> = (2..=30).collect();
    let mut test = measure(&d, &truth, 30, &nodes, band(400.0, 0.05));
    if noise > 0.0 {
        add_noise(&mut test, noise, seed);
    }
    // Noisy data: weight every updating frequency alike (the raw Eq. 11 rows
    // scale like 1/ω², so noise at the lowest frequency would drive the solution).
    let weighting = if noise > 0.0 {
        FrfWeighting::PerFrequency
    } else {
        FrfWeighting::None
    };
    let mut opts = UpdateOptions {
        frequencies_hz: Some(FRAME3D_FREQS.to_vec()),
        weighting,
        ..UpdateOptions::paper()
    };
    tweak(&mut opts);
    let r = update(&d, &test, &opts).unwrap();
    if seed == 2024 {
        show(&format!("frame3d noise {noise}"), &r);
    }
    r
}

#[test]
fn frame3d_table4_noise_free() {
    let r = frame3d(0.0);
    assert!(r.converged);
    // Within 0.0026 of exact (p6), as the paper's no-noise row (0.0027, p2).
    for (p, e) in r.parameters().iter().zip(FRAME3D_EXACT) {
        assert!((p - e).abs() <= 0.004, "{p} vs {e}");
    }
    assert!(r.final_record().sfdac.mean > 0.999);
}

/// Options for noisy data: the natural-frequency equations (Eq. 16–22) pin
/// the solution (1 % noise, 40 seeds: median largest error 0.083 with FRF
/// equations only, 0.029 with them; the paper's one realisation: 0.023); at
/// 5 % damped steps keep the bad realisations from diverging (median 0.24 →
/// 0.14, 90th percentile 4.5 → 0.42; paper 0.15). `frame3d_noise_statistics`
/// measures these.
fn noisy_options(noise: f64) -> impl Fn(&mut UpdateOptions) {
    move |o: &mut UpdateOptions| {
        o.with_frequencies = true;
        if noise >= 0.05 {
            o.damping = 0.05;
            o.tol = 0.001;
            o.max_iter = 40;
        }
    }
}

#[test]
fn frame3d_table4_noise_1_and_5_percent() {
    // One fixed realisation, as the paper's Table 4 (largest errors 0.023 at
    // 1 %, 0.15 at 5 %); ours measured 0.028 and 0.146. Bounds 25 % above
    // ours: deterministic but for rounding, which a noisy fit may amplify.
    for (noise, bound) in [(0.01, 0.035), (0.05, 0.18)] {
        let r = frame3d_with(noise, 2024, &noisy_options(noise));
        let err = r
            .parameters()
            .iter()
            .zip(FRAME3D_EXACT)
            .map(|(p, e)| (p - e).abs())
            .fold(0.0, f64::max);
        eprintln!("noise {noise}: max parameter error {err:.4}");
        assert!(err <= bound, "noise {noise}: max error {err}");
    }
}

/// The paper's Table 4 gives one noise realisation; this spreads ours over
/// 40 seeds: median and 90th percentile of the largest parameter error. Run
/// with `cargo test --release --test all updating_paper:: -- --ignored --nocapture`.
#[test]
#[ignore]
fn frame3d_noise_statistics() {
    type Tweak = Box<dyn Fn(&mut UpdateOptions)>;
    let variants: Vec<(&str, Tweak)> = vec![
        ("FRF equations only", Box::new(|_| {})),
        ("with frequencies", Box::new(|o| o.with_frequencies = true)),
        (
            "with frequencies, damping 0.05",
            Box::new(|o| noisy_options(0.05)(o)),
        ),
    ];
    for (name, tweak) in &variants {
        for noise in [0.01, 0.05] {
            let mut errs: Vec<f64> = (1..=40u64)
                .map(|seed| {
                    frame3d_with(noise, seed, tweak.as_ref())
                        .parameters()
                        .iter()
                        .zip(FRAME3D_EXACT)
                        .map(|(p, e)| (p - e).abs())
                        .fold(0.0, f64::max)
                })
                .collect();
            errs.sort_by(f64::total_cmp);
            eprintln!(
                "{name}, noise {noise}: largest parameter error over 40 seeds: min {:.4}, median {:.4}, 90th percentile {:.4}, max {:.4}",
                errs[0], errs[20], errs[36], errs[39]
            );
        }
    }
}
