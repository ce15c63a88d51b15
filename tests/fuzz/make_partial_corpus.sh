#!/bin/bash
# tests/fuzz/make_partial_corpus.sh PATHVIEW: writes the seeds of fuzz_partial into tests/fuzz/corpus-partial:
# small valid partial renders (one range, odd sizes, another sampler and seed, a merge of two ranges). They depend
# on the pathview version (partial_version()); regenerate them when the partial format or the version changes.
set -euo pipefail
pathview=${1:?usage: make_partial_corpus.sh PATHVIEW}
out=$(cd "$(dirname "$0")" && pwd)/corpus-partial
mkdir -p "$out"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
common=(--threads 1 -q)
"$pathview" render --samples 0:2 --width 4 --height 3 "${common[@]}" -o "$out/seed_4x3_0-2.exr" > /dev/null
"$pathview" render --samples 3:1 --width 5 --height 2 --seed 7 --sampler independent "${common[@]}" \
    -o "$out/seed_5x2_independent_3-1.exr" > /dev/null
"$pathview" render --samples 0:1 --width 3 --height 3 "${common[@]}" -o "$tmp/a.exr" > /dev/null
"$pathview" render --samples 4:2 --width 3 --height 3 "${common[@]}" -o "$tmp/b.exr" > /dev/null
"$pathview" merge "$out/seed_3x3_merged_0-1_4-2.exr" "$tmp/a.exr" "$tmp/b.exr" > /dev/null
ls -l "$out"
