#!/usr/bin/env bash
# The randomised benchmark of `frfup diagnose` (issue 17, item 6): 300 random
# cases (seed 1) — every physics class of the diagnosis dictionary and the
# data errors, alone and in pairs, and parameter-only controls, 1–3 % noise —
# each run as `frfup diagnose MODEL TEST --out DIR` with the defaults, two at
# a time; prints the Markdown summary (rates, confusion matrix, times).
#   scripts/bench_diagnose.sh [--cases N] [--seed S] [--out DIR] [--jobs J] [--timeout SECS]
# Per-case results: DIR/cases.csv; each case's files and diagnosis: DIR/case-NNN/.
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build --release --quiet --features bench --bin frfup --example random_benchmark
target="${CARGO_TARGET_DIR:-target}"
exec "$target/release/examples/random_benchmark" --diagnose --cases 300 --seed 1 \
    --out random-benchmark/diagnose --jobs 2 "$@"
