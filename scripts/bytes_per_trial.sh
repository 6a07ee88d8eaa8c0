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
patterns = ["butterfly"]
estimators = ["fast", "ml"]
seed = 2003
[sigma]
values = [1.0]
TOML
rss_kb() {
  /usr/bin/time -f %M "$P" simulate "$out/one.toml" --trials "$1" --threads 2 --out "$out" -q 2>&1 |
    tail -1
}
prev_n="" prev_kb=""
for n in "${counts[@]}"; do
  kb=$(rss_kb "$n")
  line="trials ${n}: peak RSS ${kb} KB"
  if [[ -n "$prev_n" ]]; then
    slope=$(( (kb - prev_kb) * 1024 / (n - prev_n) ))
    line+=", $(( slope / 2 )) bytes per added trial per estimator since ${prev_n}"
  fi
  echo "$line"
  prev_n=$n prev_kb=$kb
done
