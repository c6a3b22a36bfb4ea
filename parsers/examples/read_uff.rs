//! Reads UFF files and prints dataset counts and timing.
//!
//! `cargo run --release -p frfup-parsers --example read_uff -- FILE...`

use std::time::Instant;

use frfup_parsers::uff::{self, Dataset, Ordinate};

fn main() {
    let mut failed = false;
    for path in std::env::args().skip(1) {
        let t0 = Instant::now();
        let bytes = match std::fs::read(&path) {
            Ok(b) => b,
            Err(e) => {
                eprintln!("{path}: {e}");
                failed = true;
                continue;
            }
        };
        let t1 = Instant::now();
        match uff::parse(&bytes) {
            Ok(file) => {
                let t2 = Instant::now();
                let mut functions = 0;
                let mut points = 0;
                let mut decoded = 0usize;
                for d in &file.datasets {
                    if let Dataset::Function(f) = d {
                        functions += 1;
                        points += f.len();
                        decoded += match &f.ordinate {
                            Ordinate::Real(v) => v.len() * 8,
                            Ordinate::Complex(v) => v.len() * 16,
                        };
                        if let uff::Abscissa::Uneven(x) = &f.abscissa {
                            decoded += x.len() * 8;
                        }
                    }
                }
                let mb = bytes.len() as f64 / 1e6;
                let parse_s = (t2 - t1).as_secs_f64();
                let total_s = (t2 - t0).as_secs_f64();
                println!(
                    "{path}: {} datasets, {functions} functions, {points} points, {} notes; {:.1} MB, decoded {:.1} MB; parse {:.4} s = {:.0} MB/s; read+parse {:.4} s = {:.0} MB/s",
                    file.datasets.len(),
                    file.notes.len(),
                    mb,
                    decoded as f64 / 1e6,
                    parse_s,
                    mb / parse_s,
                    total_s,
                    mb / total_s
                );
                if std::env::var_os("READ_UFF_VERBOSE").is_some() {
                    for n in &file.notes {
                        println!("  note: {n}");
                    }
                    for (i, d) in file.datasets.iter().enumerate() {
                        match d {
                            Dataset::Function(f) => println!(
                                "  {i}: 58{} ft={} ord={} n={} {:?}..",
                                if f.binary { "b" } else { "" },
                                f.function_type,
                                f.ordinate_type,
                                f.len(),
                                f.abscissa_at(0)
                            ),
                            Dataset::Other(o) => println!("  {i}: {}", o.summary),
                        }
                    }
                }
            }
            Err(e) => {
                println!("{path}: error: {e}");
                failed = true;
            }
        }
    }
    if failed {
        std::process::exit(1);
    }
}
