#!/usr/bin/env bash
# The GARTEUR-size update's wall time, two binaries alternated (A, B, A, B,
# ...) so that both see the same load: this machine's speed drifts by a
# third within a day, and a figure from another hour compares nothing.
# Prints, for each binary, the fastest, first-quartile and median time of
# the `update` stage of `frfup demo --verbose`.
#
# Usage: scripts/ab_demo_update.sh BINARY_A BINARY_B [RUNS]   (default 15)
# e.g. build the older commit in a worktree with its own --target-dir.
set -euo pipefail
a="$1"; b="$2"; runs="${3:-15}"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
for _ in $(seq "$runs"); do
  for x in A B; do
    bin="$a"; [ "$x" = B ] && bin="$b"
    rm -rf "$work/out"
    t=$("$bin" demo --out "$work/out" --verbose 2>&1 | awk '/time: update/ {print $3}')
    echo "$x $t"
  done
done > "$work/times"
for x in A B; do
  awk -v x="$x" '$1 == x {print $2}' "$work/times" | sort -g |
    awk -v x="$x" '{t[NR] = $1} END {printf "%s fastest %s s, first quartile %s s, median %s s (%d runs)\n", x, t[1], t[int(NR / 4) + 1], t[int((NR + 1) / 2)], NR}'
done
