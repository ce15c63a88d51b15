#!/bin/bash
# tests/gui/run_gui_test.sh PATHVIEW OUTDIR [SESSION]: runs SESSION (default gui_session.sh; view_transforms.sh)
# inside a fresh Xvfb display (xvfb-run -a, so parallel runs do not collide). Exit 77 (skip) only when xvfb-run is missing; any other missing tool fails.
set -u
pathview=$1
out=$2
session=${3:-gui_session.sh}
if ! command -v xvfb-run > /dev/null; then
    echo "SKIP: xvfb-run not found (Debian: apt-get install xvfb xauth)"
    exit 77
fi
for tool in xdotool exrheader import convert cmp; do
    command -v "$tool" > /dev/null || { echo "FAIL: $tool not found (see PLATFORM-NOTES / make deps)"; exit 1; }
done
rm -rf "$out"
mkdir -p "$out"
exec xvfb-run -a -s "-screen 0 1280x800x24" "$(dirname "$0")/$session" "$pathview" "$out"
