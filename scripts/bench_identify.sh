#!/usr/bin/env bash
# frfup identify against sdypy-EMA: accuracy on synthesised campaigns with
# known modes (close pairs, weak modes, 1-3 % noise) and speed on the
# GARTEUR-like fixture and a 10 x 50,000-line record. Needs python3 with
# numpy, pyuff and sdypy-ema (pip install sdypy-ema).
#
#   scripts/bench_identify.sh [CASES] [SEED]
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
cd "$root"
cargo build --release --quiet
bin="${CARGO_TARGET_DIR:-$root/target}/release/frfup"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
python3 scripts/bench_identify.py "$bin" "$work" --cases "${1:-30}" --seed "${2:-1}" \
    --garteur fixtures/garteur/campaign.uff
