#!/bin/bash
# deploy/slurm/submit.sh N [sbatch options...] [-- render flags...]: submits render-array.sbatch as an N-task array
# and merge.sbatch depending on it (afterok: only if every task succeeded); prints the two job ids.
#   N                a positive integer (decimal digits, no sign): the number of shards
#   sbatch options   go to both sbatch calls (e.g. --partition=render --cpus-per-task=4)
#   render flags     after `--`, passed to every task's `pathview render` as arguments, each kept whole (a path
#                    with spaces or a `*` stays one argument, never split or expanded here or in the job)
# The PV_* variables of render-array.sbatch come from this shell's environment.
#   deploy/slurm/submit.sh 16 --cpus-per-task=4 -- --width 1920 --height 1080 --environment "/shared/my sky.exr"
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
usage="usage: submit.sh N [sbatch options...] [-- render flags...]"
[ $# -ge 1 ] || { echo "$usage" >&2; exit 2; }
n=$1
shift
# Checked as text before any arithmetic: $(( )) would evaluate an expression such as 'x[$(cmd)]'.
if ! [[ $n =~ ^[1-9][0-9]{0,8}$ ]]; then
    echo "submit.sh: shard count '$n' is not a positive integer (1 to 999999999, decimal digits); $usage" >&2
    exit 2
fi
sbatch_opts=()
while [ $# -gt 0 ] && [ "$1" != "--" ]; do
    sbatch_opts+=("$1")
    shift
done
render_flags=()
if [ $# -gt 0 ]; then
    shift  # the --
    render_flags=("$@")
fi
# sbatch hands the arguments after the script to the script, whole.
array=$(sbatch --parsable --array="0-$((n - 1))" "${sbatch_opts[@]}" "$here/render-array.sbatch" "${render_flags[@]}")
array=${array%%;*}
merge=$(sbatch --parsable --dependency="afterok:$array" --kill-on-invalid-dep=yes "${sbatch_opts[@]}" "$here/merge.sbatch")
echo "$array ${merge%%;*}"
