//! `uff::parse` must never panic; whatever it reads must write and read back.
#![no_main]

use frfup_parsers::uff::{self, Dataset};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Ok(file) = uff::parse(data) {
        let functions: Vec<_> = file
            .datasets
            .iter()
            .filter_map(|d| match d {
                Dataset::Function(f) => Some((**f).clone()),
                Dataset::Other(_) => None,
            })
            .collect();
        let mut out = Vec::new();
        if uff::write_functions(&mut out, &functions).is_ok() {
            let _ = uff::parse(&out);
        }
    }
});
