//! Synthesised single-reference FRFs of known real modes, for the tests of
//! the modal identifications (`identification::identify_column` and the
//! band-wise pole fit of `updating::identify`).

use faer::c64;

const TWO_PI: f64 = 2.0 * std::f64::consts::PI;

/// (f Hz, ζ, shape) of each mode.
pub type RealMode = (f64, f64, Vec<f64>);

/// Receptance of real modes (f Hz, ζ, shape) driven at channel `reference`,
/// with complex noise `noise` × each channel's accelerance RMS.
pub fn synth(lines: &[f64], modes: &[RealMode], reference: usize, noise: f64) -> Vec<Vec<c64>> {
    let nch = modes[0].2.len();
    let mut seed = 0x2545_f491_4f6c_dd1du64;
    let mut gauss = move || {
        // Box–Muller on a xorshift generator.
        let mut u = || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        let (a, b) = (u().max(1e-300), u());
        (-2.0 * a.ln()).sqrt() * (TWO_PI * b).cos()
    };
    (0..nch)
        .map(|c| {
            let acc: Vec<c64> = lines
                .iter()
                .map(|&f| {
                    let w = TWO_PI * f;
                    let mut h = c64::new(0.0, 0.0);
                    for (fr, z, phi) in modes {
                        let wr = TWO_PI * fr;
                        h += c64::new(phi[c] * phi[reference], 0.0)
                            / c64::new(wr * wr - w * w, 2.0 * z * w * wr);
                    }
                    h * (-w * w)
                })
                .collect();
            let rms = (acc.iter().map(|v| v.norm_sqr()).sum::<f64>() / acc.len() as f64).sqrt();
            acc.iter()
                .zip(lines)
                .map(|(a, &f)| {
                    let w = TWO_PI * f;
                    let a = a + c64::new(gauss(), gauss()) * (noise * rms / 2f64.sqrt());
                    if w > 0.0 {
                        a / (-w * w)
                    } else {
                        c64::new(0.0, 0.0)
                    }
                })
                .collect()
        })
        .collect()
}

/// Two modes 0.65 Hz apart (1 % damping: one peak), a mode weak at the
/// reference (channel 0) and a well separated one, on six channels.
pub fn close_and_weak_modes() -> Vec<RealMode> {
    vec![
        (16.24, 0.010, vec![1.0, 0.8, 0.5, -0.3, 0.2, 0.1]),
        (36.78, 0.010, vec![1.0, 0.9, -0.7, -1.0, 0.3, 0.4]),
        (37.43, 0.010, vec![0.9, 0.8, 0.7, 1.0, -0.2, 0.5]),
        (60.75, 0.012, vec![0.1, -0.05, 0.08, 0.12, 1.0, -0.9]),
    ]
}
