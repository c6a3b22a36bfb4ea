//! Writes a synthetic measurement campaign through our writer: `channels`
//! FRFs (dataset 58, complex single, even 0..lines) as ASCII, and its 58b twin.
//!
//! `cargo run --release -p frfup-parsers --features bench --example gen_campaign -- OUT_ASCII OUT_BINARY [channels] [lines]`

use std::io::BufWriter;

use frfup_parsers::uff::{self, Abscissa, AxisCharacteristics, Complex64, Function58, Ordinate};

fn axis(data_type: i32, l: i32, f: i32, label: &str, units: &str) -> AxisCharacteristics {
    AxisCharacteristics {
        data_type,
        length_exponent: l,
        force_exponent: f,
        temperature_exponent: 0,
        label: label.into(),
        units_label: units.into(),
    }
}

/// An FRF with a few modes, deterministic.
fn channel(k: usize, lines: usize, binary: bool) -> Function58 {
    let modes = [(31.0, 0.02), (87.5, 0.015), (143.0, 0.01), (402.0, 0.02)];
    let ordinate: Vec<Complex64> = (0..lines)
        .map(|i| {
            let f = i as f64 * 0.25;
            let mut h = Complex64::new(0.0, 0.0);
            for (m, &(fm, z)) in modes.iter().enumerate() {
                let phi = ((k + 1) as f64 * (m + 1) as f64 * 0.37).sin();
                let (re, im) = (fm * fm - f * f, 2.0 * z * fm * f);
                let d = re * re + im * im;
                h.re += -f * f * phi * re / d;
                h.im += f * f * phi * im / d;
            }
            h
        })
        .collect();
    Function58 {
        id_lines: [
            format!("FRF {}", k + 1),
            "synthetic campaign".into(),
            "01-Jan-25 00:00:00".into(),
            "NONE".into(),
            "NONE".into(),
        ],
        function_type: 4,
        function_id: k as i32 + 1,
        version: 1,
        load_case: 0,
        response_entity: "NONE".into(),
        response_node: (k / 3 + 1) as i64,
        response_direction: (k % 3 + 1) as i32,
        reference_entity: "NONE".into(),
        reference_node: 1,
        reference_direction: 3,
        ordinate_type: 5,
        abscissa: Abscissa::Even {
            start: 0.0,
            step: 0.25,
        },
        z_axis_value: 0.0,
        abscissa_axis: axis(18, 0, 0, "Frequency", "Hz"),
        numerator_axis: axis(12, 1, 0, "Acceleration", "m/s^2"),
        denominator_axis: axis(13, 0, 1, "Force", "N"),
        z_axis: axis(0, 0, 0, "NONE", "NONE"),
        ordinate: Ordinate::Complex(ordinate),
        binary,
    }
}

fn main() -> std::io::Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.len() < 2 {
        eprintln!("usage: gen_campaign OUT_ASCII OUT_BINARY [channels=256] [lines=6400]");
        std::process::exit(2);
    }
    let channels: usize = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(256);
    let lines: usize = args.get(3).and_then(|s| s.parse().ok()).unwrap_or(6400);
    for (path, binary) in [(&args[0], false), (&args[1], true)] {
        let mut out = BufWriter::new(std::fs::File::create(path)?);
        for k in 0..channels {
            uff::write_functions(&mut out, &[channel(k, lines, binary)])?;
        }
        drop(out);
        println!("{path}: {} bytes", std::fs::metadata(path)?.len());
    }
    Ok(())
}
