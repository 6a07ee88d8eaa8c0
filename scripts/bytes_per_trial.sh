#!/usr/bin/env bash
# Memory per trial of a known-correspondence data point (issue 11, "bounded memory"): the peak
# resident set of `patlab simulate EXP --sigmas 1` with a pattern's one point at two trial counts,
# and the slope between them in bytes per trial and per estimator, on one line. Today every trial keeps its errors in memory (two point buffers of 3 doubles per estimator
# plus the statistics' temporaries), so the slope does not level off with N.
set -euo pipefail
cd "$(dirname "$0")/.."
P=${PATLAB:-build/patlab}
EXP=${1:-experiments/fig5.toml}
lo=${LO:-1000000} hi=${HI:-2000000}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
rss() { /usr/bin/time -f %M "$P" simulate "$EXP" --sigmas 1 --trials "$1" --threads 2 --out "$out" -q 2>&1 | tail -1; }
a=$(rss "$lo") b=$(rss "$hi")
estimators=$(cut -d, -f2 "$out"/*.csv | sed 1d | sort -u | wc -l)
per_trial=$(( (b - a) * 1024 / (hi - lo) ))
echo "peak RSS ${a} KB at ${lo} trials, ${b} KB at ${hi}: ${per_trial} bytes per trial of a point," \
  "$(( per_trial / estimators )) per trial per estimator (${estimators} estimators)"
