#!/usr/bin/env bash
# Speed of `frfup update` (library) vs a straightforward NumPy/SciPy peer of the
# same equations (scripts/peer_update.py), on the same files in the same run;
# then one iteration on a ~100,000-DOF lattice (sparse eigen path).
#
# (a) GARTEUR-size: fixtures/garteur/garteur.deck (336 DOF, free-free, 20
#     parameters), 26 accelerometers, test simulated by `frfup simulate` at the
#     parameter changes of fixtures/garteur/truth.json (undamped, noise-free);
#     and the lead's realistic campaign fixtures/garteur/campaign.uff.
# (b) plate lattice 130x130 (101,400 DOF), 200 z sensors, 30 parameters.
#
# Usage: scripts/bench_update.sh [WORKDIR]   (default /tmp/frfup-bench-update)
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
work="${1:-/tmp/frfup-bench-update}"
mkdir -p "$work"
python3 -c "import numpy, scipy" 2>/dev/null || python3 -m pip install --quiet numpy scipy
(cd "$here" && cargo build --release --quiet && cargo build --release --features bench --example update_bench --quiet)
frfup="$here/target/release/frfup"
bench="$here/target/release/examples/update_bench"
deck="$here/fixtures/garteur/garteur.deck"
sensors=104:+z,107:+z,111:+z,112:+z,114:+z,115:+z,113:+x,204:+z,207:+z,211:+z,212:+z,214:+z,215:+z,213:+x,1:+z,1:+y,7:+z,12:+z,16:+z,16:+y,302:+y,304:+y,304:+x,401:+z,405:+z,403:+z
"$frfup" simulate "$deck" --input 112:+z --band 0:200:801 --sensors "$sensors" --noise 0 --out "$work/garteur_sim.uff" \
  --set rw_Iy=0.105 --set rw_J=0.26 --set rw_Iz=-0.11 --set lw_Iy=0.243 --set lw_J=0.251 --set lw_Iz=-0.02 \
  --set rroot_Iy=0.3 --set lroot_Iy=-0.2 --set lroot_J=0.1 --set fin_Iz=-0.041 --set fin_J=-0.2 \
  --set tail_Iy=0.111 --set wingbody_Iz=0.11 > /dev/null
echo "# machine: $(nproc) cores, load $(cut -d' ' -f1-3 /proc/loadavg)"
for case in garteur_sim campaign; do
  uff="$work/garteur_sim.uff"; [ "$case" = campaign ] && uff="$here/fixtures/garteur/campaign.uff"
  [ -f "$uff" ] || continue
  echo "# (a) GARTEUR-size, $case"
  ours=$("$bench" garteur "$deck" "$uff" "$work/export_$case" --repeat 5)
  peer=$(python3 "$here/scripts/peer_update.py" "$work/export_$case" --repeat 3)
  # The same peer with its BLAS on one thread: on this 2-core machine the
  # default (two OpenBLAS threads) is slower and far noisier at this size.
  peer1=$(OPENBLAS_NUM_THREADS=1 OMP_NUM_THREADS=1 MKL_NUM_THREADS=1 \
    python3 "$here/scripts/peer_update.py" "$work/export_$case" --repeat 3)
  echo "ours: $ours"
  echo "peer: $peer"
  echo "peer, one BLAS thread: $peer1"
  python3 - "$ours" "$peer" "$peer1" <<'PY'
import json, sys
a, b, c = (json.loads(x) for x in sys.argv[1:4])
print(f"iterations ours {a['iterations']} peer {b['iterations']}; SFDAC mean ours {a['sfdac_mean']} peer {b['sfdac_mean']}")
diff = max(abs(a['final_parameters'][k] - b['parameters_last'][k]) for k in a['final_parameters'])
print(f"converged ours {a['converged']} peer {b['stop']}; largest |p_ours - p_peer| = {diff:.2e}")
print(f"whole update: ours {a['update_s_best']*1e3:.1f} ms, NumPy/SciPy {b['update_s_best']*1e3:.1f} ms, ratio {b['update_s_best']/a['update_s_best']:.1f}x; "
      f"peer with one BLAS thread {c['update_s_best']*1e3:.1f} ms, ratio {c['update_s_best']/a['update_s_best']:.1f}x")
PY
done
echo "# (b) 101,400-DOF plate lattice, 200 sensors, 30 parameters: one iteration"
[ -f "$work/plate.deck" ] || python3 "$here/scripts/gen_lattice.py" plate 130 > "$work/plate.deck"
/usr/bin/time -f "peak RSS %M kB, wall %e s" "$bench" lattice "$work/plate.deck" --params 30 --sensors 200
