#!/bin/bash
# deploy/slurm/submit.sh N [sbatch options...]: submits render-array.sbatch as an N-task array and merge.sbatch
# depending on it (afterok: only if every task succeeded); prints the two job ids. The PV_* variables of
# render-array.sbatch come from this shell's environment. Extra options go to both sbatch calls
# (e.g. --partition=render --cpus-per-task=4).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
n=${1:?usage: submit.sh N [sbatch options...]}
shift
array=$(sbatch --parsable --array="0-$((n - 1))" "$@" "$here/render-array.sbatch")
array=${array%%;*}
merge=$(sbatch --parsable --dependency="afterok:$array" --kill-on-invalid-dep=yes "$@" "$here/merge.sbatch")
echo "$array ${merge%%;*}"
