//! `frfup::identification` against closed forms: FRFs synthesised from a
//! known modal model (real normal modes, viscous damping, unit modal
//! masses), H_o(ω) = (iω)ⁿ Σ_r φ_or φ_ref,r / (ω_r² − ω² + 2iζ_r ω_r ω),
//! which is exactly the pole–residue model the method fits.

use faer::c64;
use frfup::benchmark::Rng;
use frfup::identification::{identify, IdentifyOptions, ModeKind};
use frfup::testdata::{Channel, FrfKind, MeasuredFrfs};

const TWO_PI: f64 = 2.0 * std::f64::consts::PI;

/// A known modal model.
struct Truth {
    f_hz: Vec<f64>,
    zeta: Vec<f64>,
    /// shapes[r][o]; output 0 is the driving point.
    shapes: Vec<Vec<f64>>,
}

fn synthesise(t: &Truth, kind: FrfKind, lines: &[f64]) -> MeasuredFrfs {
    let n_out = t.shapes[0].len();
    let channels = (0..n_out)
        .map(|o| Channel {
            response_node: o as i64 + 1,
            response_direction: 3,
            reference_node: 1,
            reference_direction: 3,
            values: lines
                .iter()
                .map(|f| {
                    let w = TWO_PI * f;
                    let mut h = c64::new(0.0, 0.0);
                    for r in 0..t.f_hz.len() {
                        let wr = TWO_PI * t.f_hz[r];
                        let den = c64::new(wr * wr - w * w, 2.0 * t.zeta[r] * wr * w);
                        h += t.shapes[r][o] * t.shapes[r][0] / den;
                    }
                    h * kind.from_receptance(w)
                })
                .collect(),
        })
        .collect();
    MeasuredFrfs {
        frequencies_hz: lines.to_vec(),
        kind,
        channels,
    }
}

/// Adds complex Gaussian noise of `level` × each channel's RMS.
fn add_noise(frfs: &mut MeasuredFrfs, level: f64, seed: u64) {
    let mut rng = Rng::new(seed);
    let mut gauss = move || {
        let (u, v) = (rng.uniform().max(1e-300), rng.uniform());
        (-2.0 * u.ln()).sqrt() * (TWO_PI * v).cos()
    };
    for ch in &mut frfs.channels {
        let rms =
            (ch.values.iter().map(|v| v.norm_sqr()).sum::<f64>() / ch.values.len() as f64).sqrt();
        let s = level * rms / std::f64::consts::SQRT_2;
        for v in &mut ch.values {
            *v += c64::new(gauss() * s, gauss() * s);
        }
    }
}

fn mac(a: &[f64], b: &[f64]) -> f64 {
    let ab: f64 = a.iter().zip(b).map(|(x, y)| x * y).sum();
    ab * ab / (a.iter().map(|x| x * x).sum::<f64>() * b.iter().map(|x| x * x).sum::<f64>())
}

/// Three modes: two within each other's half-power bandwidth (20 and
/// 20.3 Hz, ζ = 1.5 %: bandwidth 0.6 Hz), one weak (its driving-point
/// residue 1/25 of the others').
fn three_modes() -> Truth {
    Truth {
        f_hz: vec![20.0, 20.3, 47.0],
        zeta: vec![0.015, 0.015, 0.008],
        shapes: vec![
            vec![1.0, 0.8, 0.3, -0.5, -1.0],
            vec![1.0, -0.6, -1.0, 0.4, 0.7],
            vec![0.2, 1.0, -0.8, 0.9, -0.4],
        ],
    }
}

fn lines(f0: f64, f1: f64, df: f64) -> Vec<f64> {
    let n = ((f1 - f0) / df).round() as usize;
    (0..=n).map(|k| f0 + k as f64 * df).collect()
}

/// Compares identified modes with the truth; returns the worst errors
/// (relative frequency, relative damping, 1 − MAC).
fn worst(t: &Truth, frfs: &MeasuredFrfs) -> (f64, f64, f64, usize) {
    let id = identify(frfs, &IdentifyOptions::default()).unwrap();
    let found: Vec<_> = id
        .modes
        .iter()
        .filter(|m| m.kind == ModeKind::Elastic)
        .collect();
    assert_eq!(
        found.len(),
        t.f_hz.len(),
        "modes found: {:?}",
        id.modes
            .iter()
            .map(|m| (m.frequency_hz, m.damping_ratio))
            .collect::<Vec<_>>()
    );
    let (mut ef, mut ez, mut em) = (0.0f64, 0.0f64, 0.0f64);
    for (r, m) in found.iter().enumerate() {
        ef = ef.max((m.frequency_hz / t.f_hz[r] - 1.0).abs());
        ez = ez.max((m.damping_ratio / t.zeta[r] - 1.0).abs());
        em = em.max(1.0 - mac(&m.real_shape(), &t.shapes[r]));
    }
    eprintln!("errors: f {ef:.2e} zeta {ez:.2e} 1-MAC {em:.2e}");
    (ef, ez, em, id.modes.len())
}

#[test]
fn noise_free_modes_are_exact() {
    // The data are the model: the fit is exact up to rounding (measured
    // errors ≤ 5e-15; the bounds leave room for other platforms' libm).
    for kind in [FrfKind::Receptance, FrfKind::Accelerance] {
        let frfs = synthesise(&three_modes(), kind, &lines(5.0, 60.0, 0.05));
        let (ef, ez, em, n) = worst(&three_modes(), &frfs);
        assert!(
            ef < 1e-10 && ez < 1e-9 && em < 1e-12,
            "{kind:?}: {ef:e} {ez:e} {em:e}"
        );
        assert_eq!(n, 3);
    }
}

#[test]
fn noisy_modes_within_targets() {
    // 2 % noise on every channel (about 1100 lines). The targets are
    // frequency 0.05 %, damping 5 %, MAC 0.995; the output-error fit does
    // far better: worst over these seeds 3.6e-5, 0.26 %, 1 − MAC 2.2e-5, for
    // the close pair and the weak mode alike. Bounds: about 4× those (the
    // scatter of a maximum-likelihood estimate over seeds).
    for seed in 1..=5 {
        let mut frfs = synthesise(
            &three_modes(),
            FrfKind::Accelerance,
            &lines(5.0, 60.0, 0.05),
        );
        add_noise(&mut frfs, 0.02, seed);
        let (ef, ez, em, n) = worst(&three_modes(), &frfs);
        assert!(
            ef < 1.5e-4 && ez < 0.01 && em < 1e-4,
            "seed {seed}: {ef:e} {ez:e} {em:e}"
        );
        assert_eq!(n, 3, "seed {seed}: a spurious mode");
    }
}

#[test]
fn suspension_mode_is_rigid_body() {
    let t = Truth {
        f_hz: vec![1.5, 18.0, 40.0],
        zeta: vec![0.03, 0.01, 0.01],
        shapes: vec![
            vec![1.0, 1.0, 1.0, 1.0],
            vec![1.0, 0.4, -0.4, -1.0],
            vec![1.0, -0.8, -0.8, 1.0],
        ],
    };
    let frfs = synthesise(&t, FrfKind::Accelerance, &lines(0.25, 50.0, 0.05));
    let id = identify(&frfs, &IdentifyOptions::default()).unwrap();
    let kinds: Vec<_> = id.modes.iter().map(|m| (m.frequency_hz, m.kind)).collect();
    assert_eq!(kinds.len(), 3, "{kinds:?}");
    assert_eq!(kinds[0].1, ModeKind::RigidBody, "{kinds:?}");
    assert!(
        kinds[1..].iter().all(|k| k.1 == ModeKind::Elastic),
        "{kinds:?}"
    );
}

/// The row of the FRF matrix a roving-hammer test gives (one sensor, the
/// hammer moved over the points): the same FRFs as the column by
/// reciprocity, with response and reference exchanged.
fn as_row(column: &MeasuredFrfs) -> MeasuredFrfs {
    let mut row = column.clone();
    for ch in &mut row.channels {
        std::mem::swap(&mut ch.response_node, &mut ch.reference_node);
        std::mem::swap(&mut ch.response_direction, &mut ch.reference_direction);
    }
    row
}

#[test]
fn roving_hammer_row_is_fitted_as_its_column() {
    // Fitted by reciprocity, a row gives the column's modes (one weight for
    // all FRFs instead of one per output: both within the identification's
    // 0.05 % target of the truth), and a hit point whose FRF is noise only
    // adds no mode (one sensor, one weight).
    let t = three_modes();
    let mut column = synthesise(&t, FrfKind::Accelerance, &lines(5.0, 60.0, 0.05));
    add_noise(&mut column, 0.01, 7);
    let row = as_row(&column);
    let a = identify(&column, &IdentifyOptions::default()).unwrap();
    let b = identify(&row, &IdentifyOptions::default()).unwrap();
    assert!(b.data.reciprocal && !a.data.reciprocal);
    assert_eq!(b.data.n_inputs(), 1);
    assert_eq!(a.modes.len(), 3);
    assert_eq!(a.modes.len(), b.modes.len());
    for ((x, y), f) in a.modes.iter().zip(&b.modes).zip(&t.f_hz) {
        assert!((x.frequency_hz / f - 1.0).abs() < 5e-4, "{x:?}");
        assert!((y.frequency_hz / f - 1.0).abs() < 5e-4, "{y:?}");
    }
    let mut dead = row.clone();
    let last = dead.channels.len() - 1;
    let tiny = 1e-4
        * dead.channels[0]
            .values
            .iter()
            .map(|v| v.norm())
            .fold(0.0, f64::max);
    let mut rng = Rng::new(11);
    for v in &mut dead.channels[last].values {
        *v = c64::new(rng.uniform() - 0.5, rng.uniform() - 0.5) * tiny;
    }
    let d = identify(&dead, &IdentifyOptions::default()).unwrap();
    let f: Vec<f64> = d.modes.iter().map(|m| m.frequency_hz).collect();
    assert_eq!(f.len(), 3, "{f:?}");
}
