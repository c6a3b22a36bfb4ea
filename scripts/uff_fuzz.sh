#!/usr/bin/env bash
# Fuzz uff::parse for SECONDS (default 600).
# With a nightly toolchain: cargo-fuzz (libFuzzer + ASan), target parsers/fuzz
# uff_parse, seeded from the real fixtures read in place. Without nightly: the
# stable fallback parsers/fuzz/loop (xorshift mutations of the same fixtures).
# Prints which fuzzer ran; exits non-zero on a crash (inputs under
# parsers/fuzz/artifacts/).
set -euo pipefail
secs=${1:-600}
root=$(cd "$(dirname "$0")/.." && pwd)
fixtures=$(cd "$root/../shared/fixtures/uff-real" && pwd)
fuzz=$root/parsers/fuzz

if rustup toolchain list 2>/dev/null | grep -q '^nightly'; then
    if ! cargo fuzz --version >/dev/null 2>&1; then
        echo "installing cargo-fuzz"
        cargo install cargo-fuzz
    fi
    corpus=$fuzz/corpus/uff_parse
    mkdir -p "$corpus"
    # A file our writer made joins the seeds (it is in the repo, read in place).
    echo "ran: cargo-fuzz (libFuzzer, nightly) for ${secs}s"
    cd "$fuzz"
    cargo +nightly fuzz run uff_parse "$corpus" "$fixtures/pyuff" "$fixtures/uffl-jl" "$root/parsers/tests/expected" -- \
        -max_total_time="$secs" -max_len=65536 -timeout=10 -rss_limit_mb=2048 -print_final_stats=1
else
    echo "ran: stable fallback fuzz loop (no nightly toolchain) for ${secs}s"
    cd "$fuzz/loop"
    cargo build --release --quiet
    ./target/release/uff-fuzz-loop "$secs" "$fixtures"/pyuff/* "$fixtures"/uffl-jl/* "$root/parsers/tests/expected/uff_written.uff"
fi
