#!/usr/bin/env bash
# The merge step after scripts/slurm/simulate_array.sbatch (docs/cluster.md): joins the shard
# files of SHARD_DIR into OUT_DIR/<name>.csv and .json. Submit it to run after the array:
#
#   job=$(sbatch --parsable --array=1-N scripts/slurm/simulate_array.sbatch EXP.toml SHARDS)
#   sbatch --dependency=afterany:$job scripts/slurm/merge.sh SHARDS OUT_DIR
#
# afterany, not afterok: the merge then names every share that failed or is missing (and writes
# nothing) instead of never running. Exit status: patlab merge's (0 ok, 2 missing/bad shards).
#SBATCH --job-name=patlab-merge
#SBATCH --cpus-per-task=1
#SBATCH --output=patlab-merge-%j.out
set -euo pipefail
if [[ $# -lt 2 ]]; then
  echo "usage: $0 SHARD_DIR OUT_DIR [merge flags...]" >&2
  exit 2
fi
shard_dir=$1 out_dir=$2
shift 2
patlab=${PATLAB:-${SLURM_SUBMIT_DIR:-.}/build/patlab}
exec "$patlab" merge "$shard_dir" --out "$out_dir" "$@"
