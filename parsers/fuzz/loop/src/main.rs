//! Stable-Rust fuzz loop for `uff::parse` and `uff::parse_reader` (which must
//! agree): random mutations (xorshift) of the real fixtures and of a file we
//! write, for a given number of seconds.
//! A panic saves the input under `artifacts/` and fails the run.
//!
//! `uff-fuzz-loop SECONDS SEED_FILE...`

use std::panic;
use std::time::{Duration, Instant};

use frfup_parsers::uff::{self, Dataset};

struct XorShift(u64);

impl XorShift {
    fn next(&mut self) -> u64 {
        let mut x = self.0;
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        self.0 = x;
        x
    }
    fn below(&mut self, n: usize) -> usize {
        if n == 0 {
            0
        } else {
            (self.next() % n as u64) as usize
        }
    }
}

const INTERESTING: &[&[u8]] = &[
    b" ", b"\n", b"\r\n", b"-1", b"    -1\n", b"b", b"E", b"D", b"e+000", b"-", b"+", b".", b"0", b"1", b"2", b"5", b"6",
    b"9999999999", b"-2147483648", b"18446744073709551615", b"NaN", b"inf", b"1.0-100", b"\xff", b"\x00", b"\xc3\xa9",
    b"    58b     2     2          11", b"    58\n", b"  2411\n", b"    55\n", b"    82\n", b"   164\n", b"    18\n",
    b"  2420\n", b"    15\n", b"   151\n", b"  1858\n",
];

fn mutate(rng: &mut XorShift, seeds: &[Vec<u8>], input: &mut Vec<u8>) {
    let rounds = 1 + rng.below(8);
    for _ in 0..rounds {
        let len = input.len();
        match rng.below(9) {
            0 if len > 0 => {
                let i = rng.below(len);
                input[i] ^= 1 << rng.below(8);
            }
            1 if len > 0 => {
                let i = rng.below(len);
                input[i] = rng.next() as u8;
            }
            2 if len > 0 => {
                let a = rng.below(len);
                let b = (a + 1 + rng.below(64)).min(len);
                input.drain(a..b);
            }
            3 if len > 0 => {
                let a = rng.below(len);
                let b = (a + 1 + rng.below(256)).min(len);
                let chunk = input[a..b].to_vec();
                let at = rng.below(len);
                input.splice(at..at, chunk);
            }
            4 => {
                let word = INTERESTING[rng.below(INTERESTING.len())];
                let at = rng.below(len + 1);
                if rng.below(2) == 0 || at + word.len() > len {
                    input.splice(at..at, word.iter().copied());
                } else {
                    input[at..at + word.len()].copy_from_slice(word);
                }
            }
            5 if len > 0 => input.truncate(rng.below(len)),
            6 => {
                let other = &seeds[rng.below(seeds.len())];
                if !other.is_empty() {
                    let a = rng.below(other.len());
                    let b = (a + 1 + rng.below(4096)).min(other.len());
                    let at = rng.below(len + 1);
                    input.splice(at..at, other[a..b].iter().copied());
                }
            }
            7 if len > 0 => {
                // Overwrite a digit run with another number.
                let i = rng.below(len);
                if input[i].is_ascii_digit() {
                    let d = b'0' + rng.below(10) as u8;
                    let mut j = i;
                    while j < len && input[j].is_ascii_digit() {
                        input[j] = d;
                        j += 1;
                    }
                }
            }
            _ => {
                let at = rng.below(len + 1);
                let n = 1 + rng.below(16);
                let bytes: Vec<u8> = (0..n).map(|_| rng.next() as u8).collect();
                input.splice(at..at, bytes);
            }
        }
    }
}

fn exercise(data: &[u8]) {
    let whole = uff::parse(data);
    // The streaming reader must agree, wherever the chunks are cut.
    let chunk = 1 + data.len() % 97;
    for (chunk, threads) in [(chunk, 1), (chunk + 13, 2), (1 << 20, 2)] {
        let streamed = uff::parse_reader_with(data, chunk, threads);
        if streamed != whole {
            panic!("parse_reader (chunk {chunk}, {threads} threads) differs from parse: {streamed:?} vs {whole:?}");
        }
    }
    if let Ok(file) = whole {
        let functions: Vec<_> = file
            .datasets
            .iter()
            .filter_map(|d| match d {
                Dataset::Function(f) => Some((**f).clone()),
                Dataset::Other(_) => None,
            })
            .collect();
        let mut out = Vec::new();
        // No functions: nothing is written, and an empty file is no UFF file.
        if !functions.is_empty() && uff::write_functions(&mut out, &functions).is_ok() {
            if let Err(e) = uff::parse(&out) {
                panic!("our own output does not read back: {e}");
            }
        }
    }
}

fn main() {
    let mut args = std::env::args().skip(1);
    let seconds: u64 = args.next().and_then(|s| s.parse().ok()).unwrap_or(60);
    let seeds: Vec<Vec<u8>> = args.filter_map(|p| std::fs::read(p).ok()).filter(|s| s.len() < 400_000).collect();
    if seeds.is_empty() {
        eprintln!("no seed files");
        std::process::exit(2);
    }
    panic::set_hook(Box::new(|_| {}));
    let mut rng = XorShift(0x9e37_79b9_7f4a_7c15 ^ std::process::id() as u64);
    let deadline = Instant::now() + Duration::from_secs(seconds);
    let (mut runs, mut crashes) = (0u64, 0u64);
    std::fs::create_dir_all("artifacts").ok();
    while Instant::now() < deadline {
        let mut input = seeds[rng.below(seeds.len())].clone();
        mutate(&mut rng, &seeds, &mut input);
        runs += 1;
        let result = panic::catch_unwind(|| exercise(&input));
        if let Err(payload) = result {
            crashes += 1;
            let msg = payload
                .downcast_ref::<String>()
                .cloned()
                .or_else(|| payload.downcast_ref::<&str>().map(|s| s.to_string()))
                .unwrap_or_default();
            let path = format!("artifacts/crash-{runs}");
            std::fs::write(&path, &input).ok();
            println!("CRASH {path}: {msg}");
            if crashes >= 20 {
                break;
            }
        }
    }
    println!("uff-fuzz-loop: {runs} inputs in {seconds} s, {crashes} crash(es)");
    if crashes > 0 {
        std::process::exit(1);
    }
}
