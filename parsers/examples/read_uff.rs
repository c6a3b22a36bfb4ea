//! Reads UFF files and prints dataset counts, timing and peak memory.
//!
//! `cargo run --release -p frfup-parsers --features bench --example read_uff -- [--whole] FILE...`
//!
//! Default: the streaming reader (`uff::parse_file`). `--whole`: read the file
//! into memory, then `uff::parse`. Per file one line:
//! `FILE: N datasets, ... decoded D MB; read+parse T s = R MB/s`; at exit
//! `peak RSS K kB` (VmHWM of /proc/self/status, Linux).

use std::time::Instant;

use frfup_parsers::uff::{self, Dataset};

/// Bytes of decoded data: 8 per real value, 16 per complex point, 8 per
/// uneven abscissa value.
fn decoded_bytes(file: &uff::UffFile) -> (usize, usize, usize) {
    let (mut functions, mut points, mut decoded) = (0, 0, 0);
    for d in &file.datasets {
        if let Dataset::Function(f) = d {
            functions += 1;
            points += f.len();
            decoded += f.ordinate.value_bytes();
            if let uff::Abscissa::Uneven(x) = &f.abscissa {
                decoded += x.len() * 8;
            }
        }
    }
    (functions, points, decoded)
}

fn peak_rss_kb() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    line.split_whitespace().nth(1)?.parse().ok()
}

fn main() {
    let mut failed = false;
    let mut whole = false;
    for path in std::env::args().skip(1) {
        if path == "--whole" {
            whole = true;
            continue;
        }
        let t0 = Instant::now();
        let size = std::fs::metadata(&path).map(|m| m.len()).unwrap_or(0);
        let parsed = if whole {
            std::fs::read(&path).map(|bytes| uff::parse(&bytes))
        } else {
            uff::parse_file(&path)
        };
        let seconds = t0.elapsed().as_secs_f64();
        match parsed {
            Err(e) => {
                eprintln!("{path}: {e}");
                failed = true;
            }
            Ok(Err(e)) => {
                println!("{path}: error: {e}");
                failed = true;
            }
            Ok(Ok(file)) => {
                let (functions, points, decoded) = decoded_bytes(&file);
                let mb = size as f64 / 1e6;
                println!(
                    "{path}: {} datasets, {functions} functions, {points} points, {} notes; {mb:.1} MB, decoded {:.1} MB; {} read+parse {seconds:.4} s = {:.0} MB/s",
                    file.datasets.len(),
                    file.notes.len(),
                    decoded as f64 / 1e6,
                    if whole { "whole" } else { "streaming" },
                    mb / seconds
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
        }
    }
    if let Some(kb) = peak_rss_kb() {
        println!("peak RSS {kb} kB");
    }
    if failed {
        std::process::exit(1);
    }
}
