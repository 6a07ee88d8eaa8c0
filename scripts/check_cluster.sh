#!/usr/bin/env bash
# Runs a sweep on real cluster engines and checks that the merged result is the single-process
# one, byte for byte (docs/cluster.md; CI runs it after the build):
#   1. single process: patlab simulate EXP --trials T
#   2. GNU parallel:   the N shares with `parallel`, then patlab merge
#   3. Slurm:          a single-node cluster started here (munged, slurmctld, slurmd with a minimal
#                      slurm.conf in a scratch directory), the job array of
#                      scripts/slurm/simulate_array.sbatch and the merge step scripts/slurm/merge.sh
#                      submitted with --dependency=afterany; the daemons are stopped on exit.
# Needs the Debian packages parallel, slurm-wlm and munge (scripts/setup.sh). Run as root or as a
# user that may start munged and the Slurm daemons. EXP defaults to experiments/fig5.toml,
# T to 20000 trials, N to 4 shares.
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

echo "== single process: $EXP --trials $TRIALS"
"$P" simulate "$EXP" --trials "$TRIALS" --out "$work/single" -q
name=$(basename "$(ls "$work"/single/*.csv)" .csv)

echo "== GNU parallel: $N shares"
parallel --will-cite --halt now,fail=1 -j2 "$P" simulate "$EXP" --trials "$TRIALS" --threads 1 \
  --shard {}/"$N" --out "$work/parallel" -q ::: $(seq "$N")
"$P" merge "$work/parallel" --out "$work/parallel-merged" -q
cmp "$work/single/$name.csv" "$work/parallel-merged/$name.csv"
echo "GNU parallel: merged CSV identical to the single-process CSV"

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
array=$(sbatch --parsable --array=1-"$N" --chdir="$PWD" --output="$s/shard-%a.out" \
  --export=ALL,PATLAB="$P" scripts/slurm/simulate_array.sbatch "$EXP" "$s/shards" \
  --trials "$TRIALS")
merge=$(sbatch --parsable --dependency=afterany:"$array" --chdir="$PWD" --output="$s/merge.out" \
  --export=ALL,PATLAB="$P" scripts/slurm/merge.sh "$s/shards" "$s/merged" -q)
echo "submitted array job $array and merge job $merge"
for _ in $(seq 1800); do
  [[ -z $(squeue -h -j "$array,$merge" 2>/dev/null) ]] && break
  sleep 0.2
done
if ! cmp "$work/single/$name.csv" "$s/merged/$name.csv"; then
  echo "Slurm: the merged CSV differs or is missing; logs:" >&2
  tail -n 20 "$s"/*.out "$s"/*.log >&2 || true
  exit 1
fi
echo "Slurm: merged CSV of array job $array identical to the single-process CSV"
echo "check_cluster: ok in $(($(date +%s) - start)) s"
