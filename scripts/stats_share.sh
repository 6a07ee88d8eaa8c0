#!/usr/bin/env bash
# The statistics' share of the CPU time of the Fig. 5 sweep (the target: at most a quarter), from
# `perf record` samples of `patlab simulate experiments/fig5.toml`.
#
#   bash scripts/stats_share.sh [runs] [patlab binary] [threads]     (defaults: 3, build/patlab, 2)
#
# Every sample is attributed to the function it was taken in (perf's "self" time, which is
# robust to inlining into the caller and to TBB's work stealing, unlike inclusive times). A
# sample counts as statistics when its symbol is in patlab::stats (KS, Wilcoxon, moments, sorts)
# or is one of the runner's statistics stage functions (BlockStatistics and the tasks it spawns,
# BlockMoments, KsAgainstFast, Differences (the paired differences written from the moments'
# second pass, and its std::function thunk), PairedTest; Compare, its former name, for older
# binaries); everything else (the trials, TBB's scheduler, the kernel,
# start-up, memset of the sample arrays) counts as not. The largest symbols of each class are
# printed, so that the classification can be checked.
set -euo pipefail
runs=${1:-3}
patlab=${2:-build/patlab}
threads=${3:-2}
cd "$(dirname "$0")/.."
command -v perf >/dev/null || { echo "stats_share.sh: perf is not installed (apt-get install linux-perf)" >&2; exit 2; }
[[ -x $patlab ]] || { echo "stats_share.sh: $patlab is not an executable; build it first" >&2; exit 2; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
stats_regex='patlab::stats::|BlockStatistics|BlockMoments|KsAgainstFast|Differences|Compare\(|PairedTest'
echo "load: $(uptime | sed 's/.*load average: //')"
for ((r = 1; r <= runs; ++r)); do
  perf record -q -F 8000 -o "$work/perf.data" "$patlab" simulate experiments/fig5.toml -q \
    --threads "$threads" --out "$work/out" >/dev/null 2>&1
  perf report -i "$work/perf.data" --no-children --sort symbol --stdio -g none 2>/dev/null |
    grep -E '^ +[0-9]+\.[0-9]+%' >"$work/symbols.txt"
  awk -v re="$stats_regex" -v run="$r" '
    { pct = $1; sub(/%/, "", pct); sym = $0; sub(/^ +[0-9.]+% +\[[^]]*\] +/, "", sym)
      total += pct; if (sym ~ re) { stats += pct; ns++; if (ns <= 6) top_s = top_s sprintf("    %5.2f%% %s\n", pct, substr(sym, 1, 100)) }
      else { no++; if (no <= 4) top_o = top_o sprintf("    %5.2f%% %s\n", pct, substr(sym, 1, 100)) } }
    END { printf "run %d: statistics %.1f%% of %.1f%% sampled CPU\n", run, stats, total
          printf "  largest statistics symbols:\n%s  largest others:\n%s", top_s, top_o }' "$work/symbols.txt"
done
