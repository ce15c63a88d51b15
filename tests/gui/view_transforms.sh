#!/bin/bash
# tests/gui/view_transforms.sh PATHVIEW OUTDIR: the view transforms in the real viewer on $DISPLAY (issue 37). Opens
# the Cornell box with clamp and a tiny OpenColorIO config this script writes, shows the raw accumulation (N), waits
# for full-resolution samples and pauses (P); then for each transform (T cycles clamp, reinhard, aces, agx,
# pbr-neutral, ocio) saves the image on screen as PNG (Ctrl+Shift+S) and checks that
#   - the PNG has the bytes `pathview render --spp <same> --view-transform <same> -o x.png` writes (cmp), and
#   - the display shader's own output, read back by the viewer, differs from them by at most 1 in any byte (the
#     GPU's float rounding; the log line says how many bytes differ),
# and that no transform restarted the accumulation. Screenshots of each transform are left in OUTDIR (screen-*.png).
set -u
pathview=$1
out=$2
log=$out/view.log
pid=
size_w=192
size_h=128

fail() {
    echo "FAIL: $*"
    echo "--- log:"; tail -30 "$log" 2>/dev/null
    echo "--- program output:"; tail -20 "$out/output.txt" 2>/dev/null
    [ -n "$pid" ] && kill "$pid" 2> /dev/null
    exit 1
}
deadline_s=${PV_GUI_DEADLINE:-300}
wait_for() {
    local deadline=$((SECONDS + deadline_s))
    until grep -Eq -- "$1" "$log" 2> /dev/null; do
        kill -0 "$pid" 2> /dev/null || fail "the viewer exited while waiting for /$1/"
        [ $SECONDS -ge $deadline ] && fail "no /$1/ in the log after $deadline_s s"
        sleep 0.1
    done
}
count() { grep -Ec -- "$1" "$log" 2> /dev/null; }

cat > "$out/config.ocio" <<'OCIO'
ocio_profile_version: 2
roles:
  scene_linear: linear
  default: linear
file_rules:
  - !<Rule> {name: Default, colorspace: default}
displays:
  sRGB:
    - !<View> {name: Gamma 2.2, colorspace: gamma22}
colorspaces:
  - !<ColorSpace> {name: linear, isdata: false}
  - !<ColorSpace>
    name: gamma22
    from_scene_reference: !<ExponentTransform> {value: 2.2, direction: inverse}
OCIO

start=$SECONDS
"$pathview" view --width $size_w --height $size_h --snapshot-dir "$out" --log-file "$log" \
    --view-transform clamp --ocio-config "$out/config.ocio" > "$out/output.txt" 2>&1 &
pid=$!
wait_for "frame gen="
wid=$(xdotool search --sync --onlyvisible --name '^pathview' | head -1)
[ -n "$wid" ] || fail "no pathview window"
eval "$(xdotool getwindowgeometry --shell "$wid")"
xdotool windowfocus --sync "$wid" 2> /dev/null || true
xdotool mousemove --sync $((X + 40)) $((Y + 40))

# The raw accumulation (the PNG of `render` is not denoised), at full resolution with a few samples, then paused.
xdotool key n
wait_for "action show raw"
wait_for "stats gen=[0-9]+ size=${size_w}x$size_h spp=([4-9]|[1-9][0-9]+) "
xdotool key p
sleep 1
restarts=$(count "restart gen=")

for t in clamp reinhard aces agx pbr-neutral ocio; do
    if [ "$t" != clamp ]; then
        before=$(count "action view-transform $t\$")
        xdotool key t
        deadline=$((SECONDS + deadline_s))
        until [ "$(count "action view-transform $t\$")" -gt "$before" ]; do
            [ $SECONDS -ge $deadline ] && fail "T did not select $t"
            sleep 0.1
        done
    fi
    sleep 0.5
    import -window "$wid" "$out/screen-$t.png" || fail "import failed"
    saved=$(count "snapshot path=.*\.png")
    xdotool key ctrl+shift+s
    deadline=$((SECONDS + deadline_s))
    until [ "$(count "snapshot path=.*\.png")" -gt "$saved" ]; do
        kill -0 "$pid" 2> /dev/null || fail "the viewer exited while saving"
        [ $SECONDS -ge $deadline ] && fail "no PNG snapshot for $t"
        sleep 0.1
    done
    line=$(grep -E "snapshot path=.*\.png" "$log" | tail -1)
    png=$(echo "$line" | sed -E 's/.*snapshot path=([^ ]+).*/\1/')
    spp=$(echo "$line" | sed -E 's/.* spp=([0-9]+).*/\1/')
    diff_bytes=$(echo "$line" | sed -E 's/.* screen_diff_bytes=([0-9]+\/[0-9]+).*/\1/')
    max_diff=$(echo "$line" | sed -E 's/.* screen_max_diff=([0-9]+).*/\1/')
    echo "$line" | grep -q "transform=$t " || fail "the PNG went through another transform: $line"
    flags="--view-transform $t"
    [ "$t" = ocio ] && flags="$flags --ocio-config $out/config.ocio"
    # shellcheck disable=SC2086
    "$pathview" render -q --width $size_w --height $size_h --spp "$spp" $flags -o "$out/render-$t.png" \
        > /dev/null 2>> "$out/output.txt" || fail "render $flags failed"
    cmp -s "$png" "$out/render-$t.png" || fail "$t: the viewer's PNG ($png, $spp spp) differs from render's"
    [ "$max_diff" -le 1 ] || fail "$t: the screen differs from the PNG by up to $max_diff in a byte"
    echo "$t: viewer PNG = render PNG at $spp spp; screen bytes differing by 1: $diff_bytes"
done
[ "$(count "restart gen=")" -eq "$restarts" ] || fail "a view transform restarted the accumulation"
echo "no restart while switching transforms"

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
