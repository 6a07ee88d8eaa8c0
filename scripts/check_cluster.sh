#!/usr/bin/env bash
# Runs sweeps on real cluster engines and checks that each merged result is the single-process
# one, byte for byte (docs/cluster.md; CI runs it after the build). Two cases:
#   known:  EXP (default experiments/fig5.toml) --trials T, whole-point shares;
#   detect: experiments/id_confusion.toml --sigmas 2 --trials DETECT_FRAMES (default 2^14 + 300:
#           every point is two blocks of frames, so the shares are trial ranges within points,
#           docs/merge.md), 6 points, 12 blocks.
# For each case:
#   1. single process: patlab simulate EXP ARGS
#   2. GNU parallel:   the N shares with `parallel`, then patlab merge
#   3. Slurm:          a single-node cluster started here (munged, slurmctld, slurmd with a minimal
#                      slurm.conf in a scratch directory), the job array of
#                      scripts/slurm/simulate_array.sbatch and the merge step scripts/slurm/merge.sh
#                      submitted with --dependency=afterany; the daemons are stopped on exit.
# Needs the Debian packages parallel, slurm-wlm and munge (scripts/setup.sh). Run as root or as a
# user that may start munged and the Slurm daemons. Usage: check_cluster.sh [EXP]; T defaults to
# 20000 trials (TRIALS), N to 4 shares (SHARDS), PATLAB to build/patlab.
set -euo pipefail
cd "$(dirname "$0")/.."
P=${PATLAB:-$PWD/build/patlab}
EXP=${1:-experiments/fig5.toml}
TRIALS=${TRIALS:-20000}
N=${SHARDS:-4}
work=$(mktemp -d /tmp/patlab-cluster.XXXXXX)
pids=()
cleanup() {
  for pid in "${pids[@]}"; do kill "$pid" 2>/dev/null || true; done
  for pid in "${pids[@]}"; do
    for _ in $(seq 50); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
  done
  rm -rf "$work"
}
trap cleanup EXIT
start=$(date +%s)

DETECT_EXP=experiments/id_confusion.toml
DETECT_ARGS=(--sigmas 2 --trials "${DETECT_FRAMES:-16684}")
KNOWN_ARGS=(--trials "$TRIALS")

# single_and_parallel CASE EXP ARGS...: the single-process run and the GNU parallel shares,
# merged and compared; leaves the CSV's name in $work/CASE.name.
single_and_parallel() {
  local case=$1 exp=$2
  shift 2
  echo "== $case: single process: $exp $*"
  "$P" simulate "$exp" "$@" --out "$work/$case-single" -q
  local name
  name=$(basename "$(ls "$work/$case-single"/*.csv)" .csv)
  echo "$name" > "$work/$case.name"
  echo "== $case: GNU parallel: $N shares"
  parallel --will-cite --halt now,fail=1 -j2 "$P" simulate "$exp" "$@" --threads 1 \
    --shard {}/"$N" --out "$work/$case-parallel" -q ::: $(seq "$N")
  "$P" merge "$work/$case-parallel" --out "$work/$case-parallel-merged" -q
  cmp "$work/$case-single/$name.csv" "$work/$case-parallel-merged/$name.csv"
  cmp "$work/$case-single/$name.json" "$work/$case-parallel-merged/$name.json"
  echo "$case, GNU parallel: merged CSV and manifest identical to the single-process ones"
}
single_and_parallel known "$EXP" "${KNOWN_ARGS[@]}"
single_and_parallel detect "$DETECT_EXP" "${DETECT_ARGS[@]}"
# The detect case must really be trial-range shares: some share holds a block of a point.
if ! grep -q '"blocks_per_point": 2' "$work"/detect-parallel/*.shard-1-of-"$N".json; then
  echo "detect case: the shares are not trial ranges (expected blocks_per_point 2)" >&2
  exit 1
fi

echo "== Slurm: a single-node cluster in $work/slurm"
s=$work/slurm
mkdir -p "$s/state" "$s/spool" "$s/munge"
chmod 700 "$s/munge"
dd if=/dev/urandom of="$s/munge/munge.key" bs=1024 count=1 status=none
chmod 600 "$s/munge/munge.key"
munged --force --key-file="$s/munge/munge.key" --socket="$s/munge/munge.sock" \
  --pid-file="$s/munge/munged.pid" --log-file="$s/munge/munged.log" \
  --seed-file="$s/munge/munged.seed"
pids+=("$(cat "$s/munge/munged.pid")")
host=$(hostname -s)
cat > "$s/slurm.conf" <<CONF
ClusterName=patlabci
SlurmctldHost=$host(127.0.0.1)
SlurmctldPort=${SLURMCTLD_PORT:-16817}
SlurmdPort=${SLURMD_PORT:-16818}
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$s/munge/munge.sock
SlurmUser=$(id -un)
SlurmdUser=$(id -un)
StateSaveLocation=$s/state
SlurmdSpoolDir=$s/spool
SlurmctldPidFile=$s/slurmctld.pid
SlurmdPidFile=$s/slurmd.pid
SlurmctldLogFile=$s/slurmctld.log
SlurmdLogFile=$s/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
MpiDefault=none
ReturnToService=2
SchedulerType=sched/builtin
NodeName=$host NodeAddr=127.0.0.1 CPUs=$(nproc) State=UNKNOWN
PartitionName=ci Nodes=$host Default=YES MaxTime=INFINITE State=UP
CONF
export SLURM_CONF=$s/slurm.conf
slurmctld -f "$SLURM_CONF"
for _ in $(seq 100); do [[ -s $s/slurmctld.pid ]] && break; sleep 0.1; done
pids+=("$(cat "$s/slurmctld.pid")")
slurmd -f "$SLURM_CONF"
for _ in $(seq 100); do [[ -s $s/slurmd.pid ]] && break; sleep 0.1; done
pids+=("$(cat "$s/slurmd.pid")")
for _ in $(seq 300); do
  sinfo -h -o %t 2>/dev/null | grep -qx idle && break
  sleep 0.2
done
sinfo
# submit CASE EXP ARGS...: the array and its merge step; prints "ARRAY MERGE".
submit() {
  local case=$1 exp=$2
  shift 2
  local array merge
  array=$(sbatch --parsable --array=1-"$N" --chdir="$PWD" --output="$s/$case-shard-%a.out" \
    --export=ALL,PATLAB="$P" scripts/slurm/simulate_array.sbatch "$exp" "$s/$case-shards" "$@")
  merge=$(sbatch --parsable --dependency=afterany:"$array" --chdir="$PWD" \
    --output="$s/$case-merge.out" --export=ALL,PATLAB="$P" scripts/slurm/merge.sh \
    "$s/$case-shards" "$s/$case-merged" -q)
  echo "$array $merge"
}
read -r known_array known_merge < <(submit known "$EXP" "${KNOWN_ARGS[@]}")
read -r detect_array detect_merge < <(submit detect "$DETECT_EXP" "${DETECT_ARGS[@]}")
jobs="$known_array,$known_merge,$detect_array,$detect_merge"
echo "submitted array jobs $known_array (known) and $detect_array (detect), merge jobs" \
  "$known_merge and $detect_merge"
for _ in $(seq 1800); do
  [[ -z $(squeue -h -j "$jobs" 2>/dev/null) ]] && break
  sleep 0.2
done
for case in known detect; do
  name=$(cat "$work/$case.name")
  array_var=${case}_array
  if ! cmp "$work/$case-single/$name.csv" "$s/$case-merged/$name.csv" ||
     ! cmp "$work/$case-single/$name.json" "$s/$case-merged/$name.json"; then
    echo "Slurm, $case: the merged CSV or manifest differs or is missing; logs:" >&2
    tail -n 20 "$s"/*.out "$s"/*.log >&2 || true
    exit 1
  fi
  echo "$case, Slurm: merged CSV and manifest of array job ${!array_var} identical to the single-process ones"
done
echo "check_cluster: ok in $(($(date +%s) - start)) s"
