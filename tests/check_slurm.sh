#!/usr/bin/env bash
# Runs examples/farm/slurm-array.sbatch on a single-node Slurm started here (Debian's slurm-wlm and
# munge), as a farm would: a job array of two shots, one stopped by SIGTERM mid-run, which tear
# answers with exit 4 and the task with a requeue; the resumed frames must equal a run never stopped.
#
#   check_slurm.sh TEAR_BINARY SOURCE_DIR
#
# Needs root (slurmd starts jobs) and the binaries of slurm-wlm and munge (apt-get install slurm-wlm
# munge). Exit 0 when every check holds, 1 when one fails, 77 (skipped, for ctest) with a message
# when Slurm cannot be run here, unless TEAR_REQUIRE_SLURM=1 (CI), where that fails instead. Everything lives in a temporary folder; the daemons are stopped
# and the folder removed at the end.
set -u
tear=$(realpath "$1")
source_dir=$(realpath "$2")

skip() {
  if [[ ${TEAR_REQUIRE_SLURM:-} == 1 ]]; then
    echo "FAIL: $*, and TEAR_REQUIRE_SLURM=1"
    exit 1
  fi
  echo "SKIP: $* (scripts/install-deps.sh does not install Slurm: apt-get install slurm-wlm munge, as root)"
  exit 77
}
for binary in slurmctld slurmd munged sbatch scontrol sinfo scancel; do
  command -v "$binary" >/dev/null || skip "no '$binary' on PATH: slurm-wlm and munge are not installed"
done
[[ $(id -u) == 0 ]] || skip "slurmd must run as root to start jobs"

work=$(mktemp -d /tmp/tear_slurm.XXXXXX)
chmod 700 "$work"
failures=0
fail() {
  echo "FAIL: $*"
  failures=$((failures + 1))
}
stop_daemons() {
  for name in slurmd slurmctld munged; do
    [[ -s "$work/$name.pid" ]] && kill "$(cat "$work/$name.pid")" 2>/dev/null
  done
  sleep 1
}
finish() {
  stop_daemons
  if ((failures)); then
    echo "check_slurm: $failures failed; logs kept in $work"
  else
    rm -rf "$work"
  fi
}
trap finish EXIT

# munge: a key of our own and a socket in the folder.
dd if=/dev/urandom of="$work/munge.key" bs=1024 count=1 status=none
chmod 400 "$work/munge.key"
munged --force --key-file="$work/munge.key" --socket="$work/munge.sock" --pid-file="$work/munged.pid" \
  --log-file="$work/munged.log" --seed-file="$work/munged.seed" || skip "munged does not start here"

host=$(hostname -s)
cpus=$(nproc)
memory=$(($(awk '/MemTotal/ {print $2}' /proc/meminfo) / 1024 / 2))
port=$((20000 + $$ % 20000))
mkdir -p "$work/state" "$work/spool" "$work/jobs"
cat >"$work/slurm.conf" <<CONF
ClusterName=teartest
SlurmctldHost=$host
SlurmctldPort=$port
SlurmdPort=$((port + 1))
SlurmUser=root
AuthType=auth/munge
AuthInfo=socket=$work/munge.sock
CredType=cred/munge
StateSaveLocation=$work/state
SlurmdSpoolDir=$work/spool
SlurmctldPidFile=$work/slurmctld.pid
SlurmdPidFile=$work/slurmd.pid
SlurmctldLogFile=$work/slurmctld.log
SlurmdLogFile=$work/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
SwitchType=switch/none
MpiDefault=none
JobCompType=jobcomp/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
ReturnToService=2
JobRequeue=1
NodeName=$host CPUs=$cpus RealMemory=$memory State=UNKNOWN
PartitionName=test Nodes=ALL Default=YES MaxTime=INFINITE State=UP
CONF
export SLURM_CONF="$work/slurm.conf"
slurmctld -c -i >/dev/null 2>&1 || skip "slurmctld does not start here"
slurmd >/dev/null 2>&1 || skip "slurmd does not start here"
for _ in $(seq 60); do
  [[ $(sinfo -h -o %T 2>/dev/null) == idle ]] && break
  sleep 1
done
[[ $(sinfo -h -o %T 2>/dev/null) == idle ]] || skip "the Slurm node did not come up (see $work/slurmd.log)"

# Two shots: a short one, and a hanging sheet cut while it falls (40 frames), stopped after a few.
mesh="$source_dir/examples/meshes/sheet_low.obj"
cat >"$work/long.json" <<'JSON'
{ "version": 1, "frames": 40,
  "cuts": [ { "frame": 3, "space": "rest-xy", "polyline": [[-0.1, 0.55], [0.6, 0.5]] },
            { "frame": 9, "space": "rest-xy", "polyline": [[1.1, 0.3], [0.3, 0.45]] } ],
  "simulation": { "iterations": 40, "pins": [ { "box": { "min": [-1, 0.99, -1], "max": [2, 2, 1] } } ] } }
JSON
cat >"$work/short.json" <<'JSON'
{ "version": 1, "frames": 3,
  "cuts": [ { "frame": 2, "space": "rest-xy", "polyline": [[-0.1, 0.5], [1.1, 0.5]] } ] }
JSON
cat >"$work/shots.txt" <<SHOTS
$mesh $work/short.json $work/out1/f.####.ply $work/out1/shot.ckpt
$mesh $work/long.json $work/out2/f.####.ply $work/out2/shot.ckpt
SHOTS
cd "$work/jobs" || exit 1
export TEAR="$tear"
job=$(sbatch --parsable --array=1-2 --cpus-per-task=1 --mem=100M \
  "$source_dir/examples/farm/slurm-array.sbatch" "$work/shots.txt") || { fail "sbatch refused the job"; exit 1; }
echo "check_slurm: job $job on a single-node Slurm ($host, $cpus CPUs)"

state() { scontrol show job -o "$1" 2>/dev/null | grep -o 'JobState=[A-Z_]*' | head -1 | cut -d= -f2; }
# Stop task 2 once it has written a few frames: SIGTERM to the batch shell, as Slurm sends it
# before a time limit (--signal=B:TERM@120).
for _ in $(seq 600); do
  [[ -e "$work/out2/f.0004.ply" ]] && break
  sleep 0.1
done
if [[ -e "$work/out2/f.0004.ply" && ! -e "$work/out2/f.0040.ply" ]]; then
  scancel --batch --signal=TERM "${job}_2"
  stopped=1
else
  fail "task 2 did not reach frame 4 in 60 s, or finished before it could be stopped"
  stopped=0
fi
for task in 1 2; do
  for _ in $(seq 300); do
    s=$(state "${job}_$task")
    [[ $s == COMPLETED || $s == FAILED || $s == CANCELLED ]] && break
    sleep 1
  done
  [[ $(state "${job}_$task") == COMPLETED ]] || fail "task $task ended $(state "${job}_$task")"
done

log1="$work/jobs/tear-${job}_1.log" log2="$work/jobs/tear-${job}_2.log"
grep -q "tear-array: ${job}_1 done" "$log1" || fail "task 1's log does not say it is done: $(cat "$log1")"
[[ $(ls "$work/out1" | grep -c '\.ply$') == 3 ]] || fail "task 1 wrote $(ls "$work/out1") "
if ((stopped)); then
  grep -q "requeued to resume" "$log2" || fail "task 2 was not requeued after exit 4: $(cat "$log2")"
  grep -q "stopped after frame" "$log2" || fail "tear did not say where it stopped: $(cat "$log2")"
  scontrol show job -o "${job}_2" | grep -q "Restarts=1" || fail "task 2 did not restart once"
fi
grep -q "Progress: 100%" "$log2" || fail "task 2's log has no 'Progress: 100%'"
# The resumed frames are those of a run never stopped.
"$tear" run "$mesh" "$work/long.json" -o "$work/whole/f.####.ply" --device cpu \
  --progress none >/dev/null 2>&1 || fail "the reference run failed"
"$tear" diff "$work/out2/f.####.ply" "$work/whole/f.####.ply" >"$work/diff.txt" 2>&1 ||
  fail "the resumed frames differ from a run never stopped: $(head -3 "$work/diff.txt")"
for frame in 0005 0020 0040; do
  cmp -s "$work/out2/f.$frame.ply" "$work/whole/f.$frame.ply" || fail "frame $frame's bytes differ from a run never stopped"
done

echo "check_slurm: $failures failed"
((failures == 0))
