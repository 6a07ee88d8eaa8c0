#!/usr/bin/env bash
# patlab and the vectorised numpy reference (scripts/numpy_baseline.py --sweep) on the same sweep,
# timed in the same run, side by side:
#   bash scripts/bench_numpy.sh [TRIALS] [EXPERIMENT]   (defaults: the experiment's own trials a
#                                                        point, 100,000 for fig5; 0 = those)
# patlab runs the whole experiment (fast + ML, and every statistic and test of each point) on one
# thread and on two; numpy runs the estimators only (fast + 3 Newton steps, no statistics) in one
# process with its BLAS/OpenMP pools held to one thread. The ratios are trials per second of
# patlab over numpy's; with the benchmarks built (build/bench/sim_bench), the last two lines give
# patlab's kernel alone on one thread, the ceiling of the one-core ratio. The machines are shared:
# run it when `uptime` shows a low load, and read the load line it prints first.
set -euo pipefail
cd "$(dirname "$0")/.."
TRIALS=${1:-0}
EXPERIMENT=${2:-experiments/fig5.toml}
P=${PATLAB:-build/patlab}
OUT=$(mktemp -d)
trap 'rm -rf "$OUT"' EXIT
echo "load: $(uptime)"

# Seconds of wall time of the whole patlab run (process start to exit) with T threads.
patlab_seconds() {
  local start end
  start=$(date +%s.%N)
  local trials=()
  if [[ "$TRIALS" != 0 ]]; then trials=(--trials "$TRIALS"); fi
  "$P" simulate "$EXPERIMENT" "${trials[@]}" --threads "$1" --out "$OUT" -q
  end=$(date +%s.%N)
  awk -v a="$start" -v b="$end" 'BEGIN { print b - a }'
}

# CPU seconds (user + sys, /usr/bin/time) of a command, its own stdout to $OUT/cpu.out: on a
# shared machine the load inflates wall times unevenly (numpy's far more than patlab's), so the
# one-core ratio is also given in CPU time.
cpu_seconds() {
  /usr/bin/time -f "%U %S" -o "$OUT/cpu.txt" "$@" > "$OUT/cpu.out"
  awk '{ print $1 + $2 }' "$OUT/cpu.txt"
}
p1=$(patlab_seconds 1)
p2=$(patlab_seconds 2)
trials_args=()
if [[ "$TRIALS" != 0 ]]; then trials_args=(--trials "$TRIALS"); fi
p1_cpu=$(cpu_seconds "$P" simulate "$EXPERIMENT" "${trials_args[@]}" --threads 1 --out "$OUT" -q)
numpy_cpu=$(OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1 MKL_NUM_THREADS=1 \
  cpu_seconds /usr/bin/python3 scripts/numpy_baseline.py --sweep "$EXPERIMENT" "$TRIALS")
numpy_line=$(cat "$OUT/cpu.out")
echo "$numpy_line"
total=$(echo "$numpy_line" | sed -E 's/.* = ([0-9]+) trials .*/\1/')
numpy_s=$(echo "$numpy_line" | sed -E 's/.* in ([0-9.]+) s .*/\1/')
rate() { awk -v n="$total" -v s="$1" 'BEGIN { print n / s / 1e6 }'; }
ratio() { awk -v a="$1" -v b="$2" 'BEGIN { print a / b }'; }
printf '%-44s %10s %14s %8s\n' "run ($total trials)" "wall s" "M trials/s" "vs numpy"
printf '%-44s %10.3f %14.3f %7.1fx\n' "numpy, estimators only, 1 process" "$numpy_s" \
  "$(rate "$numpy_s")" 1
printf '%-44s %10.3f %14.3f %7.1fx\n' "patlab, everything, 1 thread" "$p1" "$(rate "$p1")" \
  "$(ratio "$numpy_s" "$p1")"
printf '%-44s %10.3f %14.3f %7.1fx\n' "patlab, everything, 2 threads" "$p2" "$(rate "$p2")" \
  "$(ratio "$numpy_s" "$p2")"
echo "same workload, one core each: patlab is $(ratio "$numpy_s" "$p1")x numpy's throughput"
echo "in CPU time (user + sys): numpy ${numpy_cpu} s, patlab 1 thread ${p1_cpu} s:" \
  "$(ratio "$numpy_cpu" "$p1_cpu")x"
# The core-for-core ceiling, when the benchmarks are built: patlab's kernel alone on one thread
# (noise, fast and ML; no statistics, no start-up, no output) and the noisy inputs alone (the
# floor every estimator adds to), in trials per second against numpy's estimators
# (docs/performance.md, "The Monte-Carlo engine and the numpy anchor").
bench=$(dirname "$P")/bench/sim_bench
if [[ -x $bench ]]; then
  "$bench" --benchmark_filter='butterfly_(inputs_only|fast_and_ml)/real_time/threads:1$' \
    --benchmark_format=csv 2>/dev/null > "$OUT/kernel.csv"
  # CSV columns: name, iterations, real_time, cpu_time, time_unit, bytes/s, items/s, ...
  numpy_rate=$(ratio "$total" "$numpy_s")
  awk -F, '/^"?Kernel/ { gsub(/"/, "", $1); sub(/^Kernel\/butterfly_/, "", $1);
                         sub(/\/real_time.*/, "", $1); print $1, $7 }' "$OUT/kernel.csv" |
    while read -r name per_second; do
      printf '%-44s %10s %14.3f %7.1fx\n' "patlab kernel only ($name), 1 thread" "-" \
        "$(ratio "$per_second" 1e6)" "$(ratio "$per_second" "$numpy_rate")"
    done
fi
