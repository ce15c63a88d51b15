#!/bin/bash
# tests/gui/make_screenshot.sh PATHVIEW OUT.png [SPP]: docs/screenshot.png from the real viewer under Xvfb. Opens
# the Cornell box, waits until the full-resolution accumulation has SPP samples (default 64; 90 s at most), then
# grabs the window with ImageMagick's import.
set -eu
if [ -z "${DISPLAY:-}" ]; then exec xvfb-run -a -s "-screen 0 1280x800x24" "$0" "$@"; fi
pathview=$1
png=$2
spp=${3:-64}
dir=$(mktemp -d)
"$pathview" view --width 640 --height 640 --log-file "$dir/view.log" --snapshot-dir "$dir" > "$dir/output.txt" 2>&1 &
pid=$!
deadline=$((SECONDS + 90))
until awk -v want="$spp" '/stats gen=[0-9]+ size=640x640/ { sub("spp=", "", $5); n = $5 + 0 } END { exit !(n >= want) }' \
    "$dir/view.log" 2> /dev/null; do
    [ $SECONDS -ge $deadline ] && break
    sleep 0.5
done
wid=$(xdotool search --onlyvisible --name '^pathview' | head -1)
import -window "$wid" "$png"
xdotool key ctrl+q
wait "$pid"
grep -E "stats" "$dir/view.log" | tail -1
rm -rf "$dir"
