#!/usr/bin/env bash
# The randomised benchmark of `frfup update` (issue 16, item 5): 200 random
# parameter-only cases (seed 1), `frfup update MODEL TEST --out DIR` with the
# defaults, two at a time; prints the Markdown summary table.
#   scripts/bench_random.sh [--cases N] [--seed S] [--out DIR] [--jobs J] [--bounds]
# Per-case results: DIR/cases.csv; each case's files and report: DIR/case-NNN/.
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build --release --quiet --features bench --bin frfup --example random_benchmark
target="${CARGO_TARGET_DIR:-target}"
exec "$target/release/examples/random_benchmark" --cases 200 --seed 1 --out random-benchmark --jobs 2 "$@"
