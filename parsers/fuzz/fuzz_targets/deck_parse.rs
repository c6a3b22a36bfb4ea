//! `deck::parse` must never panic, on any text; whatever it accepts must
//! write back (`deck::write`) to text that parses again.
#![no_main]

use frfup_parsers::deck;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    // The CLI refuses non-UTF-8 decks before parsing; lossy text covers the rest.
    let text = String::from_utf8_lossy(data);
    if let Ok(parsed) = deck::parse(&text) {
        let written = deck::write(&parsed);
        if let Err(e) = deck::parse(&written) {
            panic!("a parsed deck writes back to text that does not parse: {e}\n{written}");
        }
    }
});
