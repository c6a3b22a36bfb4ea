#!/usr/bin/env bash
# Fuzz deck::parse (and deck::write → deck::parse of what it accepts) for
# SECONDS (default 600) with cargo-fuzz (libFuzzer + ASan, nightly), target
# parsers/fuzz deck_parse, seeded from every deck under fixtures/. Nightly and
# cargo-fuzz are installed as in scripts/uff_fuzz.sh; unlike the UFF parser
# there is no stable fallback loop: without them the script says so and exits 3.
# Exits non-zero on a crash (inputs under parsers/fuzz/artifacts/deck_parse).
set -euo pipefail
secs=${1:-600}
root=$(cd "$(dirname "$0")/.." && pwd)
fuzz=$root/parsers/fuzz

if ! command -v rustup >/dev/null 2>&1; then
    echo "no rustup: cannot run cargo-fuzz"; exit 3
fi
if ! rustup toolchain list 2>/dev/null | grep -q '^nightly'; then
    echo "installing the nightly toolchain (for cargo-fuzz)"
    rustup toolchain install nightly --profile minimal >/dev/null 2>&1 || { echo "no nightly toolchain"; exit 3; }
fi
if ! cargo fuzz --version >/dev/null 2>&1; then
    echo "installing cargo-fuzz"
    cargo install cargo-fuzz >/dev/null 2>&1 || { echo "no cargo-fuzz"; exit 3; }
fi
corpus=$fuzz/corpus/deck_parse
seeds=$fuzz/corpus/deck_seeds
mkdir -p "$corpus" "$seeds"
find "$root/fixtures" -name '*.deck' -exec cp {} "$seeds/" \;
echo "ran: cargo-fuzz (libFuzzer, nightly) deck_parse for ${secs}s"
cd "$fuzz"
cargo +nightly fuzz run deck_parse "$corpus" "$seeds" -- \
    -max_total_time="$secs" -max_len=16384 -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 \
    -detect_leaks=0
