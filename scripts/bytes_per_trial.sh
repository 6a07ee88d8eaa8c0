#!/usr/bin/env bash
# Memory of a known-correspondence data point against its trial count (docs/hardening.md,
# "Bounded memory"): the peak resident set of `patlab simulate` on one Butterfly point (fast and
# ML, sigma 1 mm) at trial counts below and above the statistics block (2^20 trials), and the
# memory each trial adds per estimator below the block. Above the block the peak stays flat: a
# point runs block by block and keeps one block's samples.
#   bash scripts/bytes_per_trial.sh            # 100k, 500k, 1M (one block), 4M and 16M trials
#   COUNTS="100000 1000000" bash scripts/bytes_per_trial.sh
set -euo pipefail
cd "$(dirname "$0")/.."
P=${PATLAB:-build/patlab}
read -r -a counts <<< "${COUNTS:-100000 500000 1000000 4000000 16000000}"
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
cat > "$out/one.toml" <<TOML
name = "one"
patterns_dir = "$PWD/patterns"
patterns = ["${PATTERN:-butterfly}"]
estimators = ["fast", "ml"]
seed = 2003
[sigma]
values = [1.0]
TOML
rss_kb() {
  /usr/bin/time -f %M "$P" simulate "$out/one.toml" --trials "$1" --threads 2 --out "$out" -q 2>&1 |
    tail -1
}
block=1048576  # kStatisticsBlockTrials (src/patlab/sim/runner.h)
prev_n="" prev_kb="" low_n="" low_kb="" high_n="" high_kb="" cap_kb=0
for n in "${counts[@]}"; do
  kb=$(rss_kb "$n")
  line="trials ${n}: peak RSS ${kb} KB"
  if [[ -n "$prev_n" ]]; then
    line+=", $(awk -v a="$prev_kb" -v b="$kb" -v m="$prev_n" -v n="$n" \
      'BEGIN { printf "%.1f", (b - a) * 1024 / (n - m) / 2 }') bytes per added trial per estimator since ${prev_n}"
  fi
  echo "$line"
  # The slope below the block: between the two largest counts that fit in one block (past the
  # first, whose fixed costs dominate); the cap: the largest peak beyond one block.
  if (( n <= block )); then
    low_n=$high_n low_kb=$high_kb high_n=$n high_kb=$kb
  elif (( kb > cap_kb )); then
    cap_kb=$kb
  fi
  prev_n=$n prev_kb=$kb
done
if [[ -n "$low_n" ]]; then
  awk -v a="$low_kb" -v b="$high_kb" -v m="$low_n" -v n="$high_n" 'BEGIN {
    printf "slope below the block (%d..%d trials): %.1f bytes per trial per estimator\n", m, n,
      (b - a) * 1024 / (n - m) / 2 }'
fi
if (( cap_kb > 0 )); then
  echo "flat cap beyond ${block} trials: peak RSS $(( cap_kb / 1024 )) MB"
fi
