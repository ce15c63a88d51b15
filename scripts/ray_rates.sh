#!/usr/bin/env bash
# scripts/ray_rates.sh: path-tracer ray rates of several pathview binaries, interleaved, for before/after ratios
# measured in one run (docs/ray-speed.md). Per round, per scene, each binary runs `pathview bench --rays-only` once,
# in an order rotated every round, and one line is printed:
#   ROUND SCENE NAME PATH_TRACER_MRAYS EMBREE_ON_ITS_MIX FRACTION MINIMAL_KERNEL_MRAYS ITS_FRACTION
# (the "| 2 | 1 |" row: 2 threads, CPU clock). scripts/paired_ratios.py turns the lines into medians of ratios.
#   ROUNDS=8 SCENES="sponza sibenik outside" scripts/ray_rates.sh before=/path/to/old/pathview after=build/pathview
# A binary given as NAME=PATH:plain gets no extra switches (a build older than --sky-guide and --adaptive); the
# others run with the sky guide and adaptive sampling off, so that every binary traces the plain path tracer.
# SAME="--rr off --max-depth 8" adds switches to every binary (the same estimator in all). The scenes come from
# ../shared/scenes (PATHVIEW_SCENES overrides), at their SOURCE.md cameras.
set -eu
S=${PATHVIEW_SCENES:-$(cd "$(dirname "$0")/../.." && pwd)/shared/scenes}
ROUNDS=${ROUNDS:-5}
SCENES=${SCENES:-"sponza sibenik"}
SECS=${SECS:-1.5}
SAME=${SAME:-}
declare -A ARGS=(
    [sponza]="$S/sponza-dabrovic/sponza.obj --eye -10,3,0 --target 10,5,0 --fov 60"
    [sibenik]="$S/sibenik/sibenik.obj --eye -17,-12.5,0 --target 0,-9,0 --fov 60"
    [outside]="$S/sponza-dabrovic/sponza.obj --eye 0,30,35 --target 0,5,0 --fov 45"
    [conference]="$S/conference/conference.obj --eye 1550,350,-194 --target 0,180,-194 --fov 60"
)
[ $# -gt 0 ] || { echo "usage: ray_rates.sh NAME=BINARY[:plain] ..." >&2; exit 2; }
for sc in $SCENES; do
    [ -n "${ARGS[$sc]:-}" ] || { echo "ray_rates.sh: unknown scene '$sc' (${!ARGS[*]})" >&2; exit 2; }
    f=${ARGS[$sc]%% *}
    [ -f "$f" ] || { echo "ray_rates.sh: $f: not found (set PATHVIEW_SCENES)" >&2; exit 2; }
done
bins=("$@")
n=${#bins[@]}
for r in $(seq 1 "$ROUNDS"); do
    for sc in $SCENES; do
        for k in $(seq 0 $((n - 1))); do
            spec=${bins[$(((k + r) % n))]}
            name=${spec%%=*}
            bin=${spec#*=}
            extra="--sky-guide off --adaptive off"
            if [[ $bin == *:plain ]]; then
                bin=${bin%:plain}
                extra=""
            fi
            # shellcheck disable=SC2086
            v=$("$bin" bench ${ARGS[$sc]} $extra $SAME --rays-only -q --rays-rounds 1 --rays-seconds "$SECS" \
                2>/dev/null | awk -F'|' '$2 ~ / 2 / && $3 ~ / 1 / {print $4, $8, $9, $10, $11; exit}')
            echo "$r $sc $name $v"
        done
    done
done
