#!/bin/bash
# tests/gui/gui_session.sh PATHVIEW OUTDIR: one viewer session on $DISPLAY. Drives the window with xdotool (a drag
# in the image, the F key, a click on the panel's "Russian roulette" checkbox, Ctrl+S) and checks each effect in
# the --log-file: the drag restarted accumulation (reason=camera), the click restarted with rr=off, Ctrl+S wrote
# an EXR that exrheader reads; then a screenshot: the image region is not black and the panel is drawn;
# Ctrl+Q closes the window and the program exits 0. Every wait polls the log with a timeout.
set -u
pathview=$1
out=$2
log=$out/view.log
pid=

fail() {
    echo "FAIL: $*"
    echo "--- log:"; tail -40 "$log" 2>/dev/null
    echo "--- program output:"; tail -20 "$out/output.txt" 2>/dev/null
    [ -n "$pid" ] && kill "$pid" 2> /dev/null
    exit 1
}

# Every wait is for an event (a log line, an exit) with one deadline long enough for a loaded machine (issue 26):
# nothing here asserts that the viewer is fast. PV_GUI_DEADLINE overrides it.
deadline_s=${PV_GUI_DEADLINE:-300}

# wait_for PATTERN: polls the log every 0.1 s until an extended regex matches.
wait_for() {
    local deadline=$((SECONDS + deadline_s))
    until grep -Eq -- "$1" "$log" 2> /dev/null; do
        kill -0 "$pid" 2> /dev/null || fail "the viewer exited while waiting for /$1/"
        [ $SECONDS -ge $deadline ] && fail "no /$1/ in the log after $deadline_s s"
        sleep 0.1
    done
}
count() { grep -Ec -- "$1" "$log" 2> /dev/null; }

# mean of a crop of the screenshot, 0..1
mean_of() { convert "$out/screen.png" -crop "$1" +repage -colorspace gray -format '%[fx:mean]' info:; }
stddev_of() { convert "$out/screen.png" -crop "$1" +repage -colorspace gray -format '%[fx:standard_deviation]' info:; }

start=$SECONDS
"$pathview" view --width 480 --height 640 --snapshot-dir "$out" --log-file "$log" > "$out/output.txt" 2>&1 &
pid=$!
wait_for "frame gen="
wid=$(xdotool search --sync --onlyvisible --name '^pathview' | head -1)
[ -n "$wid" ] || fail "no pathview window"
eval "$(xdotool getwindowgeometry --shell "$wid")"   # X Y WIDTH HEIGHT
xdotool windowfocus --sync "$wid" 2> /dev/null || true
echo "window $wid at $X,$Y size ${WIDTH}x$HEIGHT"

# 1. A drag in the image region orbits the camera: accumulation restarts with reason=camera.
x0=$((X + 200)); y0=$((Y + 280))
xdotool mousemove --sync $x0 $y0 mousedown 1
for i in 1 2 3 4 5 6 7 8; do
    xdotool mousemove --sync $((x0 + 12 * i)) $((y0 + 3 * i))
    sleep 0.03
done
xdotool mouseup 1
wait_for "restart gen=[0-9]+ reason=[a-z,]*camera"
echo "drag: restarted (reason=camera)"

# 2. A key: F frames the scene, which restarts the accumulation (reason=camera) after the logged action.
xdotool mousemove --sync $((X + 240)) $((Y + 280)) key f
wait_for "action frame-all"
deadline=$((SECONDS + deadline_s))
until sed -n '/action frame-all/,$p' "$log" | grep -Eq "restart gen=[0-9]+ reason=camera"; do
    [ $SECONDS -ge $deadline ] && fail "the F key did not restart the accumulation"
    sleep 0.1
done
echo "key F: restarted"

# 3. A click on the panel: the Russian roulette checkbox (position from the log) restarts with rr=off.
rr=$(grep -E "widget name=rr " "$log" | tail -1)
[ -n "$rr" ] || fail "the panel never logged the rr checkbox"
rx=$(echo "$rr" | sed -E 's/.* x=([0-9]+) y=([0-9]+).*/\1/')
ry=$(echo "$rr" | sed -E 's/.* x=([0-9]+) y=([0-9]+).*/\2/')
xdotool mousemove --sync $((X + rx)) $((Y + ry)) click 1
wait_for "restart gen=[0-9]+ reason=settings .* rr=off"
echo "panel click: restarted with rr=off"

# 4. Ctrl+S writes a FLOAT EXR with metadata into --snapshot-dir.
wait_for "frame gen=[0-9]+ shown_gen=[0-9]+ latency_ms=[0-9.]+ reason=refine size=480x640"
xdotool mousemove --sync $((X + 240)) $((Y + 280)) key ctrl+s
wait_for "snapshot path="
exr=$(grep -E "snapshot path=" "$log" | tail -1 | sed -E 's/.*snapshot path=([^ ]+).*/\1/')
exrheader "$exr" > "$out/exrheader.txt" 2>&1 || fail "exrheader cannot read $exr"
grep -q "pathview:spp" "$out/exrheader.txt" || fail "$exr has no pathview:spp metadata"
grep -Eq "R, 32-bit floating-point" "$out/exrheader.txt" || fail "$exr is not FLOAT"
echo "Ctrl+S: wrote $exr"

# 5. Screenshot: the image region is lit and the panel is drawn.
sleep 0.5
import -window root "$out/screen.png" || fail "import failed"
img_mean=$(mean_of "320x400+$((X + 80))+$((Y + 80))")
panel_mean=$(mean_of "360x$((HEIGHT - 20))+$((X + 490))+$((Y + 10))")
panel_sd=$(stddev_of "360x$((HEIGHT - 20))+$((X + 490))+$((Y + 10))")
echo "image mean $img_mean, panel mean $panel_mean, panel stddev $panel_sd"
awk -v m="$img_mean" 'BEGIN { exit !(m > 0.03) }' || fail "the image region is black (mean $img_mean)"
awk -v m="$panel_mean" -v s="$panel_sd" 'BEGIN { exit !(m > 0.02 && s > 0.05) }' ||
    fail "the panel is not drawn (mean $panel_mean, stddev $panel_sd)"

# 6. Ctrl+Q closes the window; the program joins its threads and exits 0.
xdotool key ctrl+q
deadline=$((SECONDS + deadline_s))
while kill -0 "$pid" 2> /dev/null; do
    [ $SECONDS -ge $deadline ] && fail "the viewer did not exit after Ctrl+Q"
    sleep 0.1
done
wait "$pid"
status=$?
pid=
[ $status -eq 0 ] || fail "exit status $status"
echo "PASS in $((SECONDS - start)) s"
