#!/usr/bin/env bash
# Eigen benchmarks: (a) dense path, ~2,000-DOF lattice, all modes; (b) sparse
# path, 50 modes, on the ~100,000-DOF plate-like and cube lattices, peak RSS;
# (c) SciPy eigsh shift-invert on the same K, M, in the same run, once with
#     the initial σ₀ ≈ 0 frfup starts from (how a caller asks for the lowest
#     modes; the headline ratio) and once with the σ frfup's probe moved to
#     (SciPy handed frfup's shift for free; the conservative ratio);
# (d) a mid-size model wanting few modes (2,400-DOF lattice, 10 and 40
#     modes): the dense path against the Krylov path frfup now takes there,
#     and SciPy eigsh at σ₀;
# (e) many modes: 300 of a 5,400-DOF lattice, frfup against SciPy eigsh at σ₀.
#
# Usage: scripts/bench_eigen.sh [WORKDIR]   (default /tmp/frfup-bench)
# Env: LATTICES (default "plate cube"), PEER_SHIFTS (default "initial final"),
#      MID (default 1; 0 skips (d), (e) and (f)).
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
[ "${MID:-1}" = 0 ] && exit 0
[ -f "$work/mid.deck" ] || python3 "$gen" plate 20 > "$work/mid.deck"
for count in 10 40; do
  echo "# (d) mid-size model, $count modes: dense path, Krylov path, SciPy eigsh at sigma0"
  dense=$("$bin" "$work/mid.deck" --count "$count" --dense --repeat 3)
  krylov=$("$bin" "$work/mid.deck" --count "$count" --repeat 3 --export "$work/mid")
  ref=$(python3 "$here/scripts/bench_eigen_scipy.py" "$work/mid" "$count" initial)
  python3 - "$dense" "$krylov" "$ref" <<'PY'
import json, sys
d, k, s = (json.loads(x) for x in sys.argv[1:4])
print(f"# {k['deck']} ({k['n']} DOF), {k['count']} modes, best of 3: dense {d['eigen_s'] * 1e3:.1f} ms, "
      f"Krylov {k['eigen_s'] * 1e3:.1f} ms ({d['eigen_s'] / k['eigen_s']:.0f}x), "
      f"SciPy eigsh {s['scipy_s'] * 1e3:.1f} ms ({s['scipy_s'] / k['eigen_s']:.1f}x); "
      f"max rel. diff in ω² vs SciPy {s['max_rel_diff_omega2_vs_frfup']:.1e}")
PY
done
[ -f "$work/mid30.deck" ] || python3 "$gen" plate 30 > "$work/mid30.deck"
echo "# (e) many modes: 300 of a 5,400-DOF lattice, frfup vs SciPy eigsh at sigma0"
many=$("$bin" "$work/mid30.deck" --count 300 --export "$work/mid30")
ref=$(python3 "$here/scripts/bench_eigen_scipy.py" "$work/mid30" 300 initial)
python3 - "$many" "$ref" <<'PY'
import json, sys
k, s = (json.loads(x) for x in sys.argv[1:3])
print(f"# {k['deck']} ({k['n']} DOF), {k['count']} modes: frfup {k['eigen_s']:.2f} s "
      f"({k['applications']} applications, {k['restarts']} restarts, max residual {k['max_residual']:.1e}), "
      f"SciPy eigsh {s['scipy_s']:.2f} s ({s['scipy_s'] / k['eigen_s']:.1f}x); "
      f"max rel. diff in ω² vs SciPy {s['max_rel_diff_omega2_vs_frfup']:.1e}")
PY
echo "# (f) Krylov drivers on the same operator: block Lanczos (ours) vs faer partial_self_adjoint_eigen"
for spec in "mid 10" "mid 40" "mid30 300" "plate 50"; do
  set -- $spec
  [ -f "$work/$1.deck" ] || continue
  line=$("$bin" "$work/$1.deck" --count "$2" --faer | tail -1)
  python3 - "$line" "$1" <<'PY'
import json, sys
c = json.loads(sys.argv[1])
print(f"# {sys.argv[2]} ({c['n']} DOF), {c['count']} modes: ours {c['ours_s']:.3f} s ({c['ours_applications']} applications), "
      f"faer {c['faer_s']:.3f} s ({c['faer_applications']} applications, {c['faer_converged']} converged): "
      f"{c['faer_s'] / c['ours_s']:.1f}x; max rel. diff in ω² {c['max_rel_diff_omega2']:.1e}")
PY
done
