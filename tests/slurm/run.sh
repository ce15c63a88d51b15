#!/bin/bash
# tests/slurm/run.sh PATHVIEW EXR_COMPARE: brings up a one-node Slurm cluster on this machine (root; Debian 12's
# slurm-wlm 22.05 and munge: munged, slurmctld, slurmd; proctrack/linuxproc, no cgroups; every file, socket and
# log in a temporary folder), submits deploy/slurm's array job for a small render and the dependent merge job,
# waits (bounded), checks the merged EXR against a single-process render (pathview_exr_compare, 1e-6 relative),
# prints both wall times, and tears everything down whatever happens. `make test-slurm` runs it.
# Environment: PV_TEST_SHARDS (4), PV_TEST_SPP (64), PV_TEST_FLAGS ("--width 96 --height 96"),
# PV_TEST_TIMEOUT (seconds for the jobs, 300).
set -euo pipefail
pathview=$(realpath "${1:?usage: run.sh PATHVIEW EXR_COMPARE}")
compare=$(realpath "${2:?usage: run.sh PATHVIEW EXR_COMPARE}")
deploy=$(cd "$(dirname "$0")/../../deploy/slurm" && pwd)
shards=${PV_TEST_SHARDS:-4}
spp=${PV_TEST_SPP:-64}
read -r -a flags <<< "${PV_TEST_FLAGS:---width 96 --height 96}"  # split at whitespace, no globbing
timeout=${PV_TEST_TIMEOUT:-300}

say() { echo "test-slurm: $*"; }
fail() {
  say "FAILED: $*"
  exit 1
}
[ "$(id -u)" = 0 ] || fail "needs root (munged, slurmctld and slurmd run as root here)"
for c in munged mungekey slurmctld slurmd sbatch scontrol sinfo; do
  command -v "$c" > /dev/null || fail "$c not found; install slurm-wlm and munge (make test-slurm does)"
done

# A live process (not a zombie waiting for its parent to reap it).
running() { [ -r "/proc/$1/stat" ] && ! grep -q '^[0-9]* (.*) Z' "/proc/$1/stat"; }
T=$(mktemp -d /tmp/pathview-slurm.XXXXXX)
chmod 755 "$T"  # munged wants its socket's folders searchable by all
cleanup() {
  local rc=$?
  trap - EXIT INT TERM
  export SLURM_CONF=$T/slurm.conf
  # Cancel whatever still runs on this test cluster, and give the job steps a few seconds to go.
  if [ -s "$T/slurmctld.pid" ]; then
    scancel --quiet --user=root 2> /dev/null || true
    for _ in $(seq 50); do
      [ -z "$(squeue -h -o %i 2> /dev/null)" ] && break
      sleep 0.2
    done
  fi
  # Stop the daemons this script started (by their pid files), then wait (bounded) for them to go.
  for d in slurmd slurmctld munged; do
    if [ -s "$T/$d.pid" ]; then kill "$(cat "$T/$d.pid")" 2> /dev/null || true; fi
  done
  for _ in $(seq 50); do
    alive=0
    for d in slurmd slurmctld munged; do
      if [ -s "$T/$d.pid" ] && running "$(cat "$T/$d.pid")"; then alive=1; fi
    done
    [ $alive = 0 ] && break
    sleep 0.1
  done
  for d in slurmd slurmctld munged; do
    if [ -s "$T/$d.pid" ] && running "$(cat "$T/$d.pid")"; then kill -9 "$(cat "$T/$d.pid")" 2> /dev/null || true; fi
  done
  if [ $rc != 0 ] && [ -d "$T" ]; then
    for f in "$T"/log/* "$T"/work/*.log; do
      [ -f "$f" ] && { echo "---- $f (last 20 lines)"; tail -n 20 "$f"; }
    done
  fi
  rm -rf "$T"
  exit $rc
}
trap cleanup EXIT
trap 'exit 130' INT TERM

# Two ports nothing listens on, for the controller and the node daemon.
listening() { (: < "/dev/tcp/127.0.0.1/$1") 2> /dev/null; }
while :; do
  ctld_port=$((20000 + RANDOM % 30000)) slurmd_port=$((ctld_port + 1))
  listening $ctld_port || listening $slurmd_port || break
done
now_ms() { echo $(($(date +%s%N) / 1000000)); }
seconds() { printf '%d.%02d' $(($1 / 1000)) $(($1 % 1000 / 10)); }
host=$(hostname -s)
cpus=$(nproc)
mkdir -p "$T/munge" "$T/state" "$T/spool" "$T/log" "$T/work/parts"
chmod 755 "$T/munge"

mungekey --create --keyfile="$T/munge.key"
munged --key-file="$T/munge.key" --socket="$T/munge/socket" --pid-file="$T/munged.pid" \
  --log-file="$T/log/munged.log" --seed-file="$T/munged.seed"

cat > "$T/slurm.conf" << EOF
ClusterName=pathview-test
SlurmctldHost=$host(127.0.0.1)
SlurmUser=root
SlurmdUser=root
SlurmctldPort=$ctld_port
SlurmdPort=$slurmd_port
AuthType=auth/munge
AuthInfo=socket=$T/munge/socket
CredType=cred/munge
StateSaveLocation=$T/state
SlurmdSpoolDir=$T/spool
SlurmctldPidFile=$T/slurmctld.pid
SlurmdPidFile=$T/slurmd.pid
SlurmctldLogFile=$T/log/slurmctld.log
SlurmdLogFile=$T/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
MpiDefault=none
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
ReturnToService=2
NodeName=$host NodeAddr=127.0.0.1 CPUs=$cpus State=UNKNOWN
PartitionName=test Nodes=ALL Default=YES MaxTime=30 State=UP
EOF
export SLURM_CONF=$T/slurm.conf
slurmctld -f "$SLURM_CONF"
slurmd -f "$SLURM_CONF" -N "$host"

# The node is up when sinfo says idle.
for _ in $(seq 150); do
  [ "$(sinfo -h -o %t 2> /dev/null)" = idle ] && break
  sleep 0.2
done
[ "$(sinfo -h -o %t)" = idle ] || fail "the node did not come up: sinfo says '$(sinfo -h -o %t)'"
say "one-node cluster up ($host, $cpus CPUs, Slurm $(sinfo -V | awk '{print $2}'))"

# The array job and its dependent merge, as a user would submit them.
cd "$T/work"
export PATHVIEW=$pathview PV_SPP=$spp PV_PARTS=$T/work/parts PV_OUT=$T/work/merged.exr PV_PNG=$T/work/merged.png
unset PV_FLAGS
t0=$(now_ms)
# The render flags after --, each argument whole (submit.sh passes them to every task).
read -r array merge <<< "$("$deploy/submit.sh" "$shards" -- "${flags[@]}")"
say "submitted array job $array ($shards tasks) and merge job $merge (afterok:$array)"
state=
deadline=$(($(date +%s) + timeout))
while [ "$(date +%s)" -lt "$deadline" ]; do
  state=$(scontrol show job "$merge" -o 2> /dev/null | grep -o 'JobState=[A-Z_]*' | cut -d= -f2 || true)
  case $state in
    COMPLETED | FAILED | CANCELLED | TIMEOUT | NODE_FAIL | OUT_OF_MEMORY | PREEMPTED | BOOT_FAIL | DEADLINE) break ;;
  esac
  sleep 0.2
done
t1=$(now_ms)
[ "$state" = COMPLETED ] || fail "merge job $merge: state '${state:-unknown}' (waited at most ${timeout}s)"
slurm_seconds=$(seconds $((t1 - t0)))
# When each job ran (whole seconds).
scontrol show job -o | grep -o 'JobId=[0-9]* \(ArrayJobId=[0-9]* ArrayTaskId=[0-9]* \)\?JobName=[^ ]*\|SubmitTime=[^ ]*\|StartTime=[^ ]*\|EndTime=[^ ]*' |
  paste -d' ' - - - - | sed 's/^/test-slurm:   /'

# The same render in one process on all cores, every pixel at every index as the shards (no adaptive sampling).
t0=$(now_ms)
"$pathview" render --spp "$spp" --adaptive off "${flags[@]}" -q -o "$T/work/single.exr" > /dev/null
t1=$(now_ms)
single_seconds=$(seconds $((t1 - t0)))

"$compare" "$T/work/single.exr" "$T/work/merged.exr" || fail "the merged EXR differs from the single-process render"
[ -s "$T/work/merged.png" ] || fail "no merged PNG"
say "$shards-shard Slurm render (submit to merged file): $slurm_seconds s; one process: $single_seconds s"
say "PASSED"
