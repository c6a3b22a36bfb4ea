#!/usr/bin/env bash
# Make the GARTEUR-like "measured" campaign from a hidden variant of the deck:
# stiffness errors on element groups (like the paper's Table 5), modal damping
# of 1 % (viscoelastic tape), bungee suspension (3 grounded z springs of
# 4000 N/m), 1.5 % complex noise, 26 accelerometers, 801 lines to 200 Hz,
# complex single-precision accelerance. The truth is kept in fixtures/garteur/.
#
# Usage: scripts/gen_garteur_campaign.sh [FRFUP_BINARY]
set -euo pipefail
cd "$(dirname "$0")/.."
FRFUP=${1:-target/release/frfup}
OUT=fixtures/garteur
python3 scripts/gen_garteur.py > "$OUT/garteur.deck"
# The deck `frfup demo` updates: the free-free model plus the bungee suspension
# the facts give (about 4000 N/m at 3 points), which an analyst models because
# it is known. It couples into the elastic modes (16.0 -> 16.2 Hz for the
# second one): a free-free model would have to absorb it into wrong stiffnesses.
{
  cat "$OUT/garteur.deck"
  echo "# bungee suspension (../shared/garteur/FACTS.md): 3 cords, about 4000 N/m each"
  echo "spring 1 104 z k=4000"
  echo "spring 2 204 z k=4000"
  echo "spring 3 10 z k=4000"
} > "$OUT/garteur_suspended.deck"
{
  cat "$OUT/garteur.deck"
  echo "# --- hidden variant: physics the analyst's deck leaves out ---"
  echo "damping modal 0.01"
  echo "spring 1 104 z k=4000"
  echo "spring 2 204 z k=4000"
  echo "spring 3 10 z k=4000"
} > "$OUT/truth.deck"
SETS=(
  --set fus_J=0.0 --set fus_Iy=0.0
  --set rw_Iy=0.105 --set rw_J=0.26 --set rw_Iz=-0.11
  --set lw_Iy=0.243 --set lw_J=0.251 --set lw_Iz=-0.02
  --set rroot_Iy=0.3 --set rroot_J=0.0 --set lroot_Iy=-0.2 --set lroot_J=0.1
  --set fin_Iz=-0.041 --set fin_J=-0.2
  --set tail_Iy=0.111 --set tail_Iz=0.0
  --set tp_Iy=0.0 --set finjoint_J=0.0
  --set wingbody_Iz=0.11 --set wingbody_J=0.0
)
SENSORS=104:+z,107:+z,111:+z,112:+z,114:+z,115:+z,113:+x,204:+z,207:+z,211:+z,212:+z,214:+z,215:+z,213:+x,1:+z,1:+y,7:+z,12:+z,16:+z,16:+y,302:+y,304:+y,304:+x,401:+z,405:+z,403:+z
"$FRFUP" simulate "$OUT/truth.deck" --input 112:+z --band 0:200:801 --sensors "$SENSORS" \
  --noise 0.015 --seed 19 --single --out "$OUT/campaign.uff" "${SETS[@]}"
# the truth as JSON (parameter name -> relative change)
printf '%s\n' "${SETS[@]}" | grep -v -- --set | python3 -c '
import json, sys
d = {}
for line in sys.stdin:
    k, v = line.strip().split("=")
    d[k] = float(v)
print(json.dumps({"parameters": d, "damping_modal_zeta": 0.01, "suspension_springs_n_per_m": {"104z": 4000, "204z": 4000, "10z": 4000}, "noise_fraction_of_rms": 0.015, "seed": 19}, indent=2, sort_keys=True))
' > "$OUT/truth.json"
echo "wrote $OUT/garteur.deck, $OUT/garteur_suspended.deck, $OUT/truth.deck, $OUT/truth.json, $OUT/campaign.uff"
