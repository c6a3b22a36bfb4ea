#!/usr/bin/env bash
# Benchmark of the UFF reader: generates a campaign (256 channels x 6400 lines,
# complex single, ASCII ~40 MB and its 58b twin) with our writer, times a full
# read with our parser (release, best of 5 runs, page cache warm) and with
# pyuff (one run each, bounded by a timeout), prints MB/s, the ratio and peak
# RSS (/usr/bin/time -v, else VmHWM).
#
# Usage: scripts/bench_uff.sh [channels] [lines]
set -euo pipefail
channels=${1:-256}
lines=${2:-6400}
root=$(cd "$(dirname "$0")/.." && pwd)
dir=${BENCH_UFF_DIR:-$root/target/bench_uff}
mkdir -p "$dir"
cd "$root"
cargo build --release -p frfup-parsers --example gen_campaign --example read_uff --quiet
ascii=$dir/campaign_${channels}x${lines}_ascii.uff
binary=$dir/campaign_${channels}x${lines}_58b.uff
if [[ ! -s $ascii || ! -s $binary ]]; then
    ./target/release/examples/gen_campaign "$ascii" "$binary" "$channels" "$lines"
fi
python3 -c "import pyuff" 2>/dev/null || python3 -m pip install --quiet pyuff

peak_rss_kb() { # command... -> prints "max_rss_kb" on fd 3
    if [[ -x /usr/bin/time ]]; then
        /usr/bin/time -v "$@" 2> "$dir/time.txt" >/dev/null
        awk -F: '/Maximum resident set size/ {gsub(/ /, "", $2); print $2}' "$dir/time.txt"
    else
        "$@" >/dev/null & pid=$!
        hwm=0
        while kill -0 "$pid" 2>/dev/null; do
            v=$(awk '/VmHWM/ {print $2}' "/proc/$pid/status" 2>/dev/null || echo 0)
            (( v > hwm )) && hwm=$v
            sleep 0.005
        done
        wait "$pid"
        echo "$hwm"
    fi
}

ours() { # file -> best MB/s (parse only) and read+parse
    local best=0 best_total=0 line
    for _ in 1 2 3 4 5; do
        line=$(./target/release/examples/read_uff "$1")
        local mbs total
        mbs=$(sed -E 's/.*= ([0-9]+) MB\/s; read\+parse.*/\1/' <<<"$line")
        total=$(sed -E 's/.*read\+parse [0-9.]+ s = ([0-9]+) MB\/s.*/\1/' <<<"$line")
        (( mbs > best )) && best=$mbs
        (( total > best_total )) && best_total=$total
    done
    echo "$best $best_total"
}

pyuff_mbs() { # file -> MB/s of pyuff.UFF(path).read_sets()
    timeout 900 python3 - "$1" <<'PY' || echo "timeout"
import os, sys, time
import pyuff
p = sys.argv[1]
t = time.perf_counter()
sets = pyuff.UFF(p).read_sets()
dt = time.perf_counter() - t
n = len(sets) if isinstance(sets, list) else 1
print(f"{os.path.getsize(p) / 1e6 / dt:.1f} {n}")
PY
}

echo "cores: $(nproc); file sizes: ascii $(stat -c %s "$ascii") B, 58b $(stat -c %s "$binary") B"
./target/release/examples/read_uff "$ascii" "$binary"
for kind in ascii 58b; do
    f=$ascii; [[ $kind == 58b ]] && f=$binary
    read -r mbs total <<<"$(ours "$f")"
    rss=$(peak_rss_kb ./target/release/examples/read_uff "$f")
    read -r py n <<<"$(pyuff_mbs "$f")"
    ratio=$(python3 -c "print(f'{$mbs / $py:.0f}')" 2>/dev/null || echo "?")
    size_mb=$(python3 -c "print(f'{$(stat -c %s "$f") / 1e6:.1f}')")
    echo "$kind: ours ${mbs} MB/s parse (${total} MB/s read+parse), pyuff ${py} MB/s (${n} sets), ratio ${ratio}x, peak RSS ${rss} kB for a ${size_mb} MB file"
done
