#!/bin/bash
# tests/gui/measure_viewer.sh PATHVIEW [SECONDS]: the viewer's figures on the 512x512 Cornell box under Xvfb,
# from its --log-file. Not a test (it never fails on time); prints:
#   - spp/s at full resolution while idle (no input; the UI redraws only when a pass lands),
#   - UI frame time while rendering, with input (the pointer hovering the panel at ~50 events/s),
#   - latency from a camera-moving input event to the first frame showing the new accumulation (orbit drags),
#   - `pathview render` spp/s on the same image right after, for comparison (same load).
set -eu
if [ -z "${DISPLAY:-}" ]; then exec xvfb-run -a -s "-screen 0 1280x800x24" "$0" "$@"; fi
pathview=$1
idle=${2:-10}
dir=$(mktemp -d)
log=$dir/view.log
"$pathview" view --width 512 --height 512 --log-file "$log" --snapshot-dir "$dir" > "$dir/output.txt" 2>&1 &
pid=$!
until grep -q "frame gen=[0-9]* shown_gen=[0-9]* latency_ms=[0-9.]* reason=refine size=512x512" "$log" 2> /dev/null; do
    sleep 0.2
done
t0=$(awk 'END { print $1 }' "$log")
sleep "$idle"
t1=$(awk 'END { print $1 }' "$log")
wid=$(xdotool search --onlyvisible --name '^pathview' | head -1)
eval "$(xdotool getwindowgeometry --shell "$wid")"
for i in $(seq 100); do xdotool mousemove $((X + 600 + (i % 2) * 40)) $((Y + 300 + i)); sleep 0.02; done
t2=$(awk 'END { print $1 }' "$log")
for k in 1 2 3 4 5; do
    xdotool mousemove --sync $((X + 150)) $((Y + 250)) mousedown 1
    for i in $(seq 15); do xdotool mousemove $((X + 150 + 5 * i)) $((Y + 250)); sleep 0.03; done
    xdotool mouseup 1
    sleep 1.5
done
xdotool key ctrl+q
wait "$pid"
load=$(cut -d' ' -f1-3 /proc/loadavg)

echo "load average: $load (2 cores)"
awk -v a="$t0" -v b="$t1" '$2 == "stats" && $1 > a && $1 <= b && $4 == "size=512x512" { for (i = 3; i <= NF; i++) { split($i, kv, "="); v[kv[1]] = kv[2] } last = v["spp"]; rs = v["render_s"]; fr += v["frames"]; fs += v["frames"] * v["frame_ms_avg"] }
    END { printf "idle, full resolution: %d spp in %.2f s of rendering = %.2f spp/s; %d UI frames, %.1f ms each\n", last, rs, last / rs, fr, fr ? fs / fr : 0 }' "$log"
awk -v a="$t1" -v b="$t2" '$2 == "stats" && $1 > a && $1 <= b + 1 { for (i = 3; i <= NF; i++) { split($i, kv, "="); v[kv[1]] = kv[2] } fr += v["frames"]; fs += v["frames"] * v["frame_ms_avg"]; fc += v["frames"] * v["frame_cpu_ms_avg"]; if (v["frame_ms_max"] > mx) mx = v["frame_ms_max"] }
    END { printf "hovering the panel while rendering: %d UI frames, mean %.1f ms (UI thread CPU %.1f ms), max %.1f ms\n", fr, fr ? fs / fr : 0, fr ? fc / fr : 0, mx }' "$log"
grep -E "frame gen=.*reason=camera" "$log" | sed -E 's/.*latency_ms=([0-9.]+).*/\1/' | sort -n |
    awk '{ a[NR] = $1 } END { printf "camera input -> first frame of the new accumulation: n=%d median %.0f ms, p90 %.0f ms, max %.0f ms\n", NR, a[int((NR + 1) / 2)], a[int(NR * 0.9 + 0.5)], a[NR] }'
"$pathview" render --width 512 --height 512 --time "$idle" -q -o "$dir/render.exr" | sed -E 's/^pathview: ([0-9]+) spp in ([0-9.]+) s.*/\1 \2/' |
    awk '{ printf "pathview render, same size, right after: %d spp in %.2f s = %.2f spp/s\n", $1, $2, $1 / $2 }'
rm -rf "$dir"
