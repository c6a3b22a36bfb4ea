#!/usr/bin/env bash
# A long record like a real roving-hammer test (issue 17, item 5): a
# free-free steel bar (1 m, 50 mm square, 20 Timoshenko elements) on two
# bungee cords (z springs of 9,700 N/m: bounce and pitch near 5 Hz),
# Rayleigh damping C = 0.6 M + 6e-9 K (ζ ≈ 1 % on the cords, 1.1e-4 to
# 1.9e-4 in the bending modes), hammer at 9 points, one accelerometer at
# node 3, 51,200 lines of 0.125 Hz to 6,400 Hz, 1 % noise. The analyst's
# deck is Euler–Bernoulli, free-free, damping 1e-3, with one parameter (Iy
# of every beam).
# Times `frfup update` and `frfup diagnose` with the defaults.
#   scripts/bench_long_record.sh [WORKDIR]
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build --release --quiet --bin frfup
target="${CARGO_TARGET_DIR:-target}"
case "$target" in /*) ;; *) target="$PWD/$target" ;; esac
frfup="$target/release/frfup"
work="${1:-random-benchmark/long-record}"
mkdir -p "$work"
cd "$work"

deck() { # $1: truth or model
    echo "title free-free steel bar on bungees ($1)"
    echo "analysis plane"
    echo "material steel E=2.1e11 rho=7850 nu=0.3"
    echo "section sq A=2.5e-3 Iy=5.208e-7"
    awk 'BEGIN { for (i = 0; i <= 20; i++) printf "node %d %.2f 0 0\n", i + 1, i * 0.05 }'
    for i in $(seq 1 20); do
        if [ "$1" = truth ]; then
            echo "beam $i $i $((i + 1)) steel sq theory=timoshenko"
        else
            echo "beam $i $i $((i + 1)) steel sq"
        fi
    done
    if [ "$1" = truth ]; then
        echo "spring 1 5 z k=9700"
        echo "spring 2 17 z k=9700"
        echo "damping rayleigh 0.6 6e-9"
    else
        echo "damping modal 0.001"
        echo "param EI Iy 1-20"
    fi
}
deck truth > truth.deck
deck model > model.deck
"$frfup" --quiet simulate truth.deck --response 3:+z \
    --sensors 1:+z,3:+z,5:+z,8:+z,11:+z,13:+z,15:+z,18:+z,21:+z \
    --band 0.125:6400:51200 --noise 0.01 --out record.uff
echo "== update (defaults)"
/usr/bin/time -f "wall %e s, max RSS %M kB" "$frfup" --verbose update model.deck record.uff \
    --out update 2>&1 | grep -E "^time:|^wall|full-band|converged|not converged" || true
echo "== diagnose (defaults)"
/usr/bin/time -f "wall %e s, max RSS %M kB" "$frfup" --verbose diagnose model.deck record.uff \
    --out diagnose 2>&1 | grep -E "^time:|^wall|explained|^[a-z-]+: |FRF error" || true
