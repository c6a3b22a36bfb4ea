//! `uff::parse` must never panic; the streaming `uff::parse_reader` must give
//! the same result and first error (any chunk size, 1 or 2 threads); whatever
//! is read must write and read back.
#![no_main]

use frfup_parsers::uff::{self, Dataset};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let whole = uff::parse(data);
    // Chunk size from the input length: boundaries fall everywhere over a run.
    let chunk = 1 + data.len() % 97;
    for (chunk, threads) in [(chunk, 1), (chunk + 13, 2), (1 << 20, 2)] {
        let streamed = uff::parse_reader_with(data, chunk, threads);
        assert_eq!(streamed, whole, "parse_reader (chunk {chunk}, {threads} threads) differs from parse");
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
        if uff::write_functions(&mut out, &functions).is_ok() {
            let _ = uff::parse(&out);
        }
    }
});
