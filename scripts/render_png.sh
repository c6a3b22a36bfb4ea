#!/usr/bin/env bash
# Render report SVGs to PNG with rsvg-convert (scripts/ensure_tool.sh installs
# librsvg2-bin when missing), so charts can be looked at and checked by tests/all/report_render.rs.
#
#   scripts/render_png.sh                 # only make sure rsvg-convert exists
#   scripts/render_png.sh DIR [OUT_DIR]   # render every DIR/**/*.svg to OUT_DIR (default: next to the SVG)
set -euo pipefail

"$(dirname "$0")/ensure_tool.sh" rsvg-convert librsvg2-bin

if [ $# -ge 1 ]; then
    src="$1"
    out="${2:-}"
    find "$src" -name '*.svg' -print0 | sort -z | while IFS= read -r -d '' svg; do
        if [ -n "$out" ]; then
            rel="${svg#"$src"/}"
            png="$out/${rel%.svg}.png"
            mkdir -p "$(dirname "$png")"
        else
            png="${svg%.svg}.png"
        fi
        rsvg-convert --background-color=white -o "$png" "$svg"
        echo "$png"
    done
fi
