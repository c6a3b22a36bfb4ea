#!/usr/bin/env bash
# Render report SVGs to PNG with rsvg-convert (installs librsvg2-bin via apt-get
# when missing), so charts can be looked at and checked by tests/report_render.rs.
#
#   scripts/render_png.sh                 # only make sure rsvg-convert exists
#   scripts/render_png.sh DIR [OUT_DIR]   # render every DIR/**/*.svg to OUT_DIR (default: next to the SVG)
set -euo pipefail

ensure_rsvg() {
    if command -v rsvg-convert >/dev/null 2>&1; then
        return 0
    fi
    if ! command -v apt-get >/dev/null 2>&1; then
        echo "render_png: rsvg-convert missing and no apt-get; install librsvg2-bin by hand" >&2
        return 1
    fi
    local sudo=""
    if [ "$(id -u)" -ne 0 ]; then
        sudo="sudo"
    fi
    echo "render_png: installing librsvg2-bin" >&2
    $sudo apt-get update -qq >/dev/null || true
    DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends librsvg2-bin >/dev/null
    command -v rsvg-convert >/dev/null 2>&1
}

ensure_rsvg

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
