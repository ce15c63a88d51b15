#!/bin/bash
# tests/gui/measure_viewer.sh [SCENE [FLAGS...]]: input-to-first-frame latency of `pathview view` at 640x480 under
# Xvfb (Mesa llvmpipe). Not a test: it never fails on time. It opens SCENE (default: the built-in Cornell box) with
# FLAGS, waits for the first full-resolution frame, then makes MOVES (default 40) short orbit drags in the image,
# DELAY seconds apart (default 0.4), and reads the viewer's --log-file: each "frame ... reason=camera" line is the
# time from the input event that moved the camera to the first frame of the new accumulation on screen. Prints
# median / p90 / max of those, the first pass's size and time, and the load average.
# PATHVIEW=path/to/pathview (default build/pathview); KEEP_LOG=FILE keeps the log.
set -eu
if [ -z "${DISPLAY:-}" ]; then exec xvfb-run -a -s "-screen 0 1280x800x24" "$0" "$@"; fi
pathview=${PATHVIEW:-build/pathview}
moves=${MOVES:-40}
delay=${DELAY:-0.4}
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
log=$dir/view.log
"$pathview" view "$@" --width 640 --height 480 --log-file "$log" --snapshot-dir "$dir" > "$dir/output.txt" 2>&1 &
pid=$!
for _ in $(seq 600); do
    grep -q "frame gen=.* reason=refine size=640x480" "$log" 2> /dev/null && break
    kill -0 "$pid" 2> /dev/null || { cat "$dir/output.txt" >&2; exit 1; }
    sleep 0.2
done
grep -q "frame gen=.* reason=refine size=640x480" "$log" || { echo "no full-resolution frame after 120 s" >&2; kill "$pid"; exit 1; }
sleep 1
t0=$(awk 'END { print $1 }' "$log")
wid=$(xdotool search --onlyvisible --name '^pathview' | head -1)
eval "$(xdotool getwindowgeometry --shell "$wid")"
for i in $(seq "$moves"); do
    dx=$(((i % 2) * 2 - 1))  # alternate left and right: the view stays near the start view
    xdotool mousemove --sync $((X + 320)) $((Y + 240)) mousedown 1
    sleep 0.05
    xdotool mousemove $((X + 320 + 24 * dx)) $((Y + 240))  # one motion event past the click slop: one restart
    sleep 0.05
    xdotool mouseup 1
    sleep "$delay"
done
sleep 1
xdotool key ctrl+q
wait "$pid" || true
[ -n "${KEEP_LOG:-}" ] && cp "$log" "$KEEP_LOG"

echo "scene: $(awk '$2 == "start" { print $3, $4, $5 }' "$log" | head -1); load average $(cut -d' ' -f1-3 /proc/loadavg) (2 cores)"
awk -v a="$t0" '$1 > a && $2 == "frame" && / reason=camera/ { sub("latency_ms=", "", $5); print $5 }' "$log" | sort -n |
    awk '{ v[NR] = $1 } END { if (!NR) { print "no camera frames"; exit }
        printf "camera input -> first frame of the new accumulation: n=%d median %.0f ms, p90 %.0f ms, max %.0f ms\n",
            NR, v[int((NR + 1) / 2)], v[int(NR * 0.9 + 0.999)], v[NR] }'
# The first pass of each camera restart: its size (from the restart line) and ms/pass (first frame's snapshot).
awk -v a="$t0" '$1 > a && $2 == "restart" && / reason=camera/ { for (i = 3; i <= NF; i++) if ($i ~ /^size=/) n[$i]++ }
    END { s = ""; for (k in n) s = s " " substr(k, 6) " x" n[k]; print "first-pass sizes:" s }' "$log"
