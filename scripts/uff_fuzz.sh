#!/usr/bin/env bash
# Fuzz uff::parse and uff::parse_reader (which must agree) for SECONDS
# (default 600).
#
# Preferred: cargo-fuzz (libFuzzer + ASan, nightly), target parsers/fuzz
# uff_parse, seeded from the real fixtures read in place. If nightly is
# missing it is installed with `rustup toolchain install nightly`, and
# cargo-fuzz with `cargo install cargo-fuzz`; if either fails (offline, no
# rustup), the stable fallback parsers/fuzz/loop runs instead (xorshift
# mutations of the same fixtures). UFF_FUZZ=loop forces the fallback.
# Prints which fuzzer ran; exits non-zero on a crash (inputs under
# parsers/fuzz/artifacts/). Leak detection is off: the streaming reader's
# scoped threads are joined before their thread-locals (std's channel
# context) are freed, which LeakSanitizer's per-input check reports as a leak.
set -euo pipefail
secs=${1:-600}
root=$(cd "$(dirname "$0")/.." && pwd)
fixtures=$root/fixtures/uff-real
fuzz=$root/parsers/fuzz

have_nightly() {
    rustup toolchain list 2>/dev/null | grep -q '^nightly'
}

libfuzzer_ready() {
    [[ ${UFF_FUZZ:-} != loop ]] || return 1
    command -v rustup >/dev/null 2>&1 || return 1
    if ! have_nightly; then
        echo "installing the nightly toolchain (for cargo-fuzz)"
        rustup toolchain install nightly --profile minimal >/dev/null 2>&1 || return 1
    fi
    if ! cargo fuzz --version >/dev/null 2>&1; then
        echo "installing cargo-fuzz"
        cargo install cargo-fuzz >/dev/null 2>&1 || return 1
    fi
}

if libfuzzer_ready; then
    corpus=$fuzz/corpus/uff_parse
    mkdir -p "$corpus"
    echo "ran: cargo-fuzz (libFuzzer, nightly) for ${secs}s"
    cd "$fuzz"
    cargo +nightly fuzz run uff_parse "$corpus" "$fixtures/pyuff" "$fixtures/uffl-jl" "$root/parsers/tests/expected" -- \
        -max_total_time="$secs" -max_len=65536 -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 \
        -detect_leaks=0
else
    echo "ran: stable fallback fuzz loop (no nightly toolchain or cargo-fuzz) for ${secs}s"
    cd "$fuzz/loop"
    cargo build --release --quiet
    ./target/release/uff-fuzz-loop "$secs" "$fixtures"/pyuff/* "$fixtures"/uffl-jl/* "$root/parsers/tests/expected/uff_written.uff"
fi
