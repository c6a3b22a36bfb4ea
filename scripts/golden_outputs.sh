#!/usr/bin/env bash
# Run a fixed set of commands on the checked-in fixtures and list the SHA-256
# of every file they write (and of their stdout), so that a structural change
# meant to change nothing can be shown to change nothing:
#
#   scripts/golden_outputs.sh target/release/frfup /tmp/before > before.txt
#   ... change ...
#   scripts/golden_outputs.sh target/release/frfup /tmp/after  > after.txt
#   diff before.txt after.txt
#
# Timings printed by the tool are not part of any file listed here.
set -uo pipefail
BIN=$(realpath "$1"); OUT=${2:-/tmp/frfup-golden}
cd "$(dirname "$0")/.."
rm -rf "$OUT"; mkdir -p "$OUT"
F=fixtures
run() { # name, command...
    local name=$1; shift
    "$@" >"$OUT/$name.stdout" 2>"$OUT/$name.stderr"
    echo "$?" >"$OUT/$name.rc"
}
run demo "$BIN" --quiet demo --out "$OUT/demo"
run update_garteur "$BIN" --quiet update $F/garteur/garteur.deck $F/garteur/campaign.uff --out "$OUT/update_garteur"
run update_paper "$BIN" --quiet update --method paper $F/garteur/garteur.deck $F/garteur/campaign.uff --out "$OUT/update_paper"
for c in added_mass control_beam shear; do
    run "diagnose_$c" "$BIN" --quiet diagnose $F/diagnose/$c.deck $F/diagnose/$c.uff --out "$OUT/diagnose_$c"
done
run modes "$BIN" modes $F/paper/frame3d.deck
run info "$BIN" info $F/uff-real/pyuff/Sample_UFF58b_bin.uff
run convert "$BIN" convert $F/uff-real/pyuff/Sample_UFF58_ascii.uff "$OUT/convert.csv"
run simulate "$BIN" --quiet simulate $F/paper/cantilever.deck --input 16:3 --band 1:200:200 --noise 0.01 --out "$OUT/simulate.uff"
cat >"$OUT/campaign.toml" <<TOML
[[case]]
name = "garteur"
model = "$(pwd)/$F/garteur/garteur.deck"
test = "$(pwd)/$F/garteur/campaign.uff"
TOML
run batch "$BIN" --quiet batch "$OUT/campaign.toml" --out "$OUT/batch"
# Hash every file but stderr (warnings and progress), with the output folder's
# path replaced by OUT, and wall-clock times (stdout, batch summaries) by T.
python3 - "$OUT" <<'PY'
import hashlib, os, re, sys
out = sys.argv[1]
for root, _, files in sorted(os.walk(out)):
    for f in sorted(files):
        if f.endswith(".stderr"):
            continue
        p = os.path.join(root, f)
        b = open(p, "rb").read().replace(out.encode(), b"OUT")
        if f.endswith(".stdout") or "/batch" in p and f.startswith("summary"):
            b = re.sub(rb"\b\d+\.\d+( s\b|,the |,[a-z]|,\n| \||</td></tr>)", rb"T\1", b)
            b = re.sub(rb'("wall_time_s": )[0-9.e+-]+', rb"\1T", b)
        print(hashlib.sha256(b).hexdigest(), os.path.relpath(p, out))
PY
