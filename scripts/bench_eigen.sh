#!/usr/bin/env bash
# Eigen benchmarks: (a) dense path, ~2,000-DOF lattice, all modes; (b) sparse
# path, 50 modes, on the ~100,000-DOF plate-like and cube lattices, peak RSS;
# (c) SciPy eigsh shift-invert on the same K, M, in the same run, once with
#     the initial σ₀ ≈ 0 frfup starts from (how a caller asks for the lowest
#     modes; the headline ratio) and once with the σ frfup's probe moved to
#     (SciPy handed frfup's shift for free; the conservative ratio).
#
# Usage: scripts/bench_eigen.sh [WORKDIR]   (default /tmp/frfup-bench)
# Env: LATTICES (default "plate cube"), PEER_SHIFTS (default "initial final").
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
work="${1:-/tmp/frfup-bench}"
mkdir -p "$work"
python3 -c "import scipy" 2>/dev/null || python3 -m pip install --quiet scipy
(cd "$here" && cargo build --release --example bench_eigen --quiet)
bin="$here/target/release/examples/bench_eigen"
gen="$here/scripts/gen_lattice.py"
[ -f "$work/small.deck" ] || python3 "$gen" plate 18 > "$work/small.deck"
[ -f "$work/plate.deck" ] || python3 "$gen" plate 130 > "$work/plate.deck"
[ -f "$work/cube.deck" ] || python3 "$gen" cube 26 > "$work/cube.deck"
echo "# machine: $(nproc) cores, load $(cut -d' ' -f1-3 /proc/loadavg)"
echo "# (a) dense path, all modes"
"$bin" "$work/small.deck" --count 0 --dense
for name in ${LATTICES:-plate cube}; do
  echo "# (b) sparse path, 50 modes: $name"
  out=$("$bin" "$work/$name.deck" --count 50 --export "$work/$name")
  echo "$out"
  for shift in ${PEER_SHIFTS:-initial final}; do
    echo "# (c) SciPy eigsh, same K, M, $shift sigma: $name"
    ref=$(python3 "$here/scripts/bench_eigen_scipy.py" "$work/$name" 50 "$shift")
    echo "$ref"
    python3 - "$out" "$ref" <<'PY'
import json, sys
a, b = json.loads(sys.argv[1]), json.loads(sys.argv[2])
print(f"# {a['deck']}: frfup {a['eigen_s']:.2f} s (peak RSS {a['peak_rss_mb']:.0f} MB), "
      f"SciPy at the {b['shift']} sigma {b['sigma']:.4g} {b['scipy_s']:.2f} s (peak RSS {b['scipy_peak_rss_mb']} MB): "
      f"{b['scipy_s'] / a['eigen_s']:.1f}x; max rel. diff in ω² {b['max_rel_diff_omega2_vs_frfup']:.1e}")
PY
  done
done
