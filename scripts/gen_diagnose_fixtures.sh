#!/usr/bin/env bash
# Cases for `frfup diagnose`: each an analyst's deck (CASE.deck) and a test
# (CASE.uff) simulated with 1 % noise from a truth deck (CASE.truth.deck) that
# holds an effect the analyst's deck lacks. Controls: only the deck's own
# parameters are wrong (--set on the analyst's deck).
# Usage: scripts/gen_diagnose_fixtures.sh [path/to/frfup]
set -euo pipefail
cd "$(dirname "$0")/.."
FRFUP=${1:-target/release/frfup}
D=fixtures/diagnose
mkdir -p $D

beam() { # cantilever along x, 8 elements, 0.8 m, steel 20 x 10 mm
  cat <<'DECK'
analysis plane
material steel E=2.1e11 rho=7850
section bar A=2e-4 Iy=1.6667e-9
node 1 0.0 0 0
node 2 0.1 0 0
node 3 0.2 0 0
node 4 0.3 0 0
node 5 0.4 0 0
node 6 0.5 0 0
node 7 0.6 0 0
node 8 0.7 0 0
node 9 0.8 0 0
beam 1 1 2 steel bar
beam 2 2 3 steel bar
beam 3 3 4 steel bar
beam 4 4 5 steel bar
beam 5 5 6 steel bar
beam 6 6 7 steel bar
beam 7 7 8 steel bar
beam 8 8 9 steel bar
DECK
}
portal() { # plane portal frame: columns 1-4 and 9-12 (0.6 m), girder 4-9 (0.8 m), feet clamped
  cat <<'DECK'
analysis plane
material steel E=2.1e11 rho=7850
section col A=3e-4 Iy=2.5e-9
section gir A=3e-4 Iy=2.5e-9
node 1 0 0 0
node 2 0 0 0.2
node 3 0 0 0.4
node 4 0 0 0.6
node 5 0.16 0 0.6
node 6 0.32 0 0.6
node 7 0.48 0 0.6
node 8 0.64 0 0.6
node 9 0.8 0 0.6
node 10 0.8 0 0.4
node 11 0.8 0 0.2
node 12 0.8 0 0
beam 1 1 2 steel col
beam 2 2 3 steel col
beam 3 3 4 steel col
beam 4 4 5 steel gir
beam 5 5 6 steel gir
beam 6 6 7 steel gir
beam 7 7 8 steel gir
beam 8 8 9 steel gir
beam 9 9 10 steel col
beam 10 10 11 steel col
beam 11 11 12 steel col
fix 1 all
fix 12 all
DECK
}
freebeam() { # free-free beam 1.2 m, 12 elements
  echo "analysis plane"
  echo "material alu E=7e10 rho=2700"
  echo "section bar A=6e-4 Iy=1.8e-8"
  for i in $(seq 1 13); do echo "node $i $(awk "BEGIN{print ($i-1)*0.1}") 0 0"; done
  for i in $(seq 1 12); do echo "beam $i $i $((i+1)) alu bar"; done
}
stocky() { # stocky clamped-free beam (L/h = 5), 10 elements
  echo "analysis plane"
  echo "material steel E=2.1e11 rho=7850 nu=0.3"
  echo "section sq A=0.01 Iy=8.333e-6"
  for i in $(seq 1 11); do echo "node $i $(awk "BEGIN{print ($i-1)*0.05}") 0 0"; done
  for i in $(seq 1 10); do echo "beam $i $i $((i+1)) steel sq THEORY"; done
  echo "fix 1 all"
}
BEAM_SENS=3:3,5:3,7:3,9:3
sim() { # name input band sensors [extra args]
  local name=$1 input=$2 band=$3 sensors=$4; shift 4
  "$FRFUP" --quiet simulate "$D/$name.truth.deck" --input "$input" --band "$band" \
    --sensors "$sensors" --noise 0.01 --seed 7 --single --out "$D/$name.uff" "$@"
}

# 1. sensor mass: 25 g on each of the four accelerometers
{ echo "title cantilever, analyst's deck"; beam; echo "fix 1 all"; echo "damping modal 0.015"; echo "param EI Iy 1-8"; } > $D/sensor_mass.deck
{ echo "title cantilever with 25 g sensors"; beam; echo "fix 1 all"; echo "damping modal 0.015"; for n in 3 5 7 9; do echo "mass $n $n m=0.025"; done; } > $D/sensor_mass.truth.deck
sim sensor_mass 9:3 2:400:600 $BEAM_SENS

# 2. support flexibility: the clamp is a rotational spring 200 N·m/rad
{ echo "title cantilever, analyst's deck"; beam; echo "fix 1 all"; echo "damping modal 0.015"; } > $D/support.deck
{ echo "title cantilever on a flexible clamp"; beam; echo "fix 1 x,z"; echo "spring 1 1 ry k=200"; echo "damping modal 0.015"; } > $D/support.truth.deck
sim support 9:3 2:400:600 $BEAM_SENS

# 3. damping missing from the deck: 2 % modal
{ echo "title cantilever, analyst's deck (undamped)"; beam; echo "fix 1 all"; } > $D/damping.deck
{ echo "title cantilever, 2 % modal damping"; beam; echo "fix 1 all"; echo "damping modal 0.02"; } > $D/damping.truth.deck
sim damping 9:3 2:400:600 $BEAM_SENS

# 4. suspension: free-free beam hung on two bungees (z springs at nodes 3 and 11)
{ echo "title free-free beam, analyst's deck"; freebeam; echo "damping modal 0.01"; } > $D/suspension.deck
{ echo "title free-free beam on two bungees"; freebeam; echo "damping modal 0.01"; echo "spring 1 3 z k=800"; echo "spring 2 11 z k=800"; } > $D/suspension.truth.deck
sim suspension 13:3 0.5:250:500 1:3,4:3,7:3,10:3,13:3

# 5. added mass at node 6 (no sensor there)
{ echo "title cantilever, analyst's deck"; beam; echo "fix 1 all"; echo "damping modal 0.015"; } > $D/added_mass.deck
{ echo "title cantilever with a 0.12 kg mass at node 6"; beam; echo "fix 1 all"; echo "damping modal 0.015"; echo "mass 1 6 m=0.12"; } > $D/added_mass.truth.deck
sim added_mass 9:3 2:400:600 $BEAM_SENS

# 6. joint flexibility: the left girder-column corner (node 4) is a rotational spring
{ echo "title portal frame, analyst's deck"; portal; echo "damping modal 0.01"; } > $D/joint.deck
{ echo "title portal frame with a flexible corner at node 4"; portal | sed 's/^beam 4 4 5/beam 4 13 5/'; echo "node 13 0 0 0.6"; echo "spring 1 4 x k=1e9 to=13"; echo "spring 2 4 z k=1e9 to=13"; echo "spring 3 4 ry k=150 to=13"; echo "damping modal 0.01"; } > $D/joint.truth.deck
sim joint 6:3 2:300:600 2:1,4:1,6:3,7:3,9:1,11:1

# 7. shear deformation: a stocky beam, truth Timoshenko
{ echo "title stocky beam, analyst's deck (Euler-Bernoulli)"; stocky | sed 's/ THEORY//'; echo "damping modal 0.01"; } > $D/shear.deck
{ echo "title stocky beam, Timoshenko"; stocky | sed 's/THEORY/theory=timoshenko/'; echo "damping modal 0.01"; } > $D/shear.truth.deck
sim shear 11:3 20:20000:600 3:3,5:3,7:3,9:3,11:3

# 8. two effects: sensor masses and a flexible clamp
{ echo "title cantilever, analyst's deck"; beam; echo "fix 1 all"; echo "damping modal 0.015"; } > $D/two_effects.deck
{ echo "title cantilever with 20 g sensors on a flexible clamp"; beam; echo "fix 1 x,z"; echo "spring 1 1 ry k=300"; echo "damping modal 0.015"; for n in 3 5 7 9; do echo "mass $n $n m=0.02"; done; } > $D/two_effects.truth.deck
sim two_effects 9:3 2:400:600 $BEAM_SENS

# 9. support flexibility in translation: the clamp sits on a spring 2e4 N/m in z
{ echo "title cantilever, analyst's deck"; beam; echo "fix 1 all"; echo "damping modal 0.02"; } > $D/support_z.deck
{ echo "title cantilever whose clamp sits on a vertical spring"; beam; echo "fix 1 x,ry"; echo "spring 1 1 z k=2e4"; echo "damping modal 0.02"; } > $D/support_z.truth.deck
sim support_z 9:3 2:400:600 $BEAM_SENS

# 10. sensor masses (30 g on six accelerometers) and the deck's own parameters
# wrong too (girder -10 %, columns +6 %): the update absorbs part of the masses
{ echo "title portal frame, analyst's deck with params"; portal; echo "damping modal 0.01"; echo "param girder Iy 4-8"; echo "param columns Iy 1-3,9-11"; } > $D/sensor_mass_portal.deck
{ echo "title portal frame with 30 g sensors"; portal; echo "damping modal 0.01"; echo "param girder Iy 4-8"; echo "param columns Iy 1-3,9-11"; for n in 2 4 6 7 9 11; do echo "mass $n $n m=0.03"; done; } > $D/sensor_mass_portal.truth.deck
sim sensor_mass_portal 6:3 2:300:600 2:1,4:1,6:3,7:3,9:1,11:1 --set girder=-0.1 --set columns=0.06

# Controls: only the deck's own parameters are wrong.
{ echo "title cantilever, analyst's deck with params"; beam; echo "fix 1 all"; echo "damping modal 0.015"; echo "param EI_root Iy 1-4"; echo "param EI_tip Iy 5-8"; } > $D/control_beam.deck
cp $D/control_beam.deck $D/control_beam.truth.deck
sim control_beam 9:3 2:400:600 $BEAM_SENS --set EI_root=0.15 --set EI_tip=-0.1
{ echo "title portal frame, analyst's deck with params"; portal; echo "damping modal 0.01"; echo "param girder Iy 4-8"; echo "param columns Iy 1-3,9-11"; } > $D/control_portal.deck
cp $D/control_portal.deck $D/control_portal.truth.deck
sim control_portal 6:3 2:300:600 2:1,4:1,6:3,7:3,9:1,11:1 --set girder=-0.12 --set columns=0.08
ls -la $D
