#!/usr/bin/env bash
# Make sure a command the tests (or a script) call exists: when it is missing,
# install its Debian package with apt-get (as root, or through sudo), quietly.
# Fails when the command is still missing afterwards.
#
#   scripts/ensure_tool.sh COMMAND PACKAGE     # e.g. rsvg-convert librsvg2-bin
set -euo pipefail
cmd=$1
pkg=$2
if command -v "$cmd" >/dev/null 2>&1; then
    exit 0
fi
if ! command -v apt-get >/dev/null 2>&1; then
    echo "ensure_tool: $cmd missing and no apt-get; install $pkg by hand" >&2
    exit 1
fi
sudo=""
if [ "$(id -u)" -ne 0 ]; then
    sudo="sudo"
fi
echo "ensure_tool: installing $pkg for $cmd" >&2
install() {
    DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "$pkg" >/dev/null 2>&1
}
# The package lists of a fresh container may be empty: update only if needed.
install || { $sudo apt-get update -qq >/dev/null && install; }
if ! command -v "$cmd" >/dev/null 2>&1; then
    echo "ensure_tool: $pkg installed but $cmd still missing" >&2
    exit 1
fi
