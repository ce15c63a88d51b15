#!/bin/bash
# tests/gui/measure_settle.sh REFERENCE.exr [SCENE [FLAGS...]]: the viewer's settle time under Xvfb (Mesa llvmpipe).
# Not a test: it never fails on time. It opens SCENE (default: the built-in Cornell box) with FLAGS and B =
# REFERENCE (`--compare`: a converged render of the start view at the same size, e.g. `pathview render SCENE --time
# 600 -o ref.exr`), then TRIALS times (default 3) for each display (the denoised default (a-trous while rendering), then raw after N): orbits
# away with a short drag, waits, and presses R, which puts the camera back at the start view. The settle time is
# from that key press to the first shown pass whose image on screen is within relMSE LIMIT (default 2e-3) of B, read
# from the viewer's --log-file ("action reset-camera", then "error ... rel_mse_shown=" lines); "not within Ns" when
# none is before TIMEOUT seconds (default 60). Size: WIDTH x HEIGHT (default 640x480, REFERENCE's size).
# PATHVIEW=path/to/pathview (default build/pathview); KEEP_LOG=FILE keeps the log.
set -eu
if [ -z "${DISPLAY:-}" ]; then exec xvfb-run -a -s "-screen 0 1400x900x24" "$0" "$@"; fi
[ $# -ge 1 ] || { echo "usage: $0 REFERENCE.exr [SCENE [FLAGS...]]" >&2; exit 2; }
reference=$1
shift
pathview=${PATHVIEW:-build/pathview}
trials=${TRIALS:-3}
limit=${LIMIT:-2e-3}
timeout=${TIMEOUT:-60}
width=${WIDTH:-640}
height=${HEIGHT:-480}
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
log=$dir/view.log
"$pathview" view "$@" --width "$width" --height "$height" --compare "$reference" --log-file "$log" \
    --snapshot-dir "$dir" > "$dir/output.txt" 2>&1 &
pid=$!
for _ in $(seq 600); do
    grep -q "^[0-9.]* error " "$log" 2> /dev/null && break
    kill -0 "$pid" 2> /dev/null || { cat "$dir/output.txt" >&2; exit 1; }
    sleep 0.2
done
grep -q "^[0-9.]* error " "$log" || { echo "no pass compared with $reference after 120 s" >&2; kill "$pid"; exit 1; }
grep "^[0-9.]* compare " "$log" | head -1
wid=$(xdotool search --onlyvisible --name '^pathview' | head -1)
eval "$(xdotool getwindowgeometry --shell "$wid")"
cx=$((X + width / 2))
cy=$((Y + height / 2))

# Waits until the last reset-camera action has a settled pass (or TIMEOUT); prints the settle time in seconds.
settle() {
    local deadline=$((SECONDS + timeout + 2))
    while [ $SECONDS -lt $deadline ]; do
        local r
        r=$(awk -v lim="$limit" '$2 == "action" && $3 == "reset-camera" { t = $1; done = 0; next }
            t && !done && $2 == "error" { for (i = 3; i <= NF; i++) if ($i ~ /^rel_mse_shown=/) v = substr($i, 15) + 0;
                if (v <= lim) { s = $1 - t; done = 1 } }
            END { if (done) printf "%.2f", s }' "$log")
        if [ -n "$r" ]; then echo "$r"; return; fi
        sleep 0.25
    done
    echo "not within ${timeout}s"
}

for display in denoised raw; do
    if [ "$display" = raw ]; then
        xdotool mousemove --sync "$cx" "$cy"
        xdotool key n
        sleep 0.5
        grep -q "action show raw" "$log" || { echo "N did not switch to the raw image" >&2; kill "$pid"; exit 1; }
    fi
    times=""
    for _ in $(seq "$trials"); do
        xdotool mousemove --sync "$cx" "$cy" mousedown 1
        sleep 0.05
        xdotool mousemove $((cx + 40)) "$cy"
        sleep 0.05
        xdotool mousemove $((cx + 80)) "$cy"
        sleep 0.05
        xdotool mouseup 1
        sleep 0.5
        xdotool key r
        times="$times $(settle)"
        sleep 0.5
    done
    echo "settle to relMSE <= $limit, $display display: $times s"
done
xdotool key ctrl+q
wait "$pid" || true
[ -n "${KEEP_LOG:-}" ] && cp "$log" "$KEEP_LOG"
echo "load average $(cut -d' ' -f1-3 /proc/loadavg) (2 cores)"
