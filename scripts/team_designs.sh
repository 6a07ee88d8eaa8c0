#!/usr/bin/env bash
# The real team pattern designs of c. 2009-2013: each SSL-Vision sheet in
# ../shared/frames/team-patterns (GPL-3.0 test data, not in this repository) imported with
# patlab import into results/team-designs/patterns/, then every imported design and the shipped
# SSL standard compared with patlab compare into results/team-designs/.
# Usage: scripts/team_designs.sh [PATLAB] (default build/patlab). Skips cleanly (exit 0) when
# ../shared/frames is absent.
set -euo pipefail
cd "$(dirname "$0")/.."
PATLAB=${1:-build/patlab}
F=../shared/frames/team-patterns
R=results/team-designs
if [ ! -d "$F" ]; then
  echo "team_designs: no $F; skipped"
  exit 0
fi
rm -rf "$R/patterns"
mkdir -p "$R"
# Every sheet, kiks.png included: its ring sectors are split by angle and modelled as disc
# patches at their centroids (docs/import.md, "Ring sectors").
mapfile -t sheets < <(ls "$F"/*.png)
"$PATLAB" import "${sheets[@]}" --out "$R/patterns" > "$R/import.txt"
# Every imported layout, and the shipped standard for reference.
mapfile -t designs < <(ls "$R"/patterns/*.toml | grep -v '\.codebook\.toml$')
"$PATLAB" compare "${designs[@]}" ssl-standard --sort-by rotation_onset_mm \
  --sigmas 2,3,4,5 --frames 2000 --out "$R" -q
/usr/bin/python3 scripts/plot_compare.py "$R/compare.csv" "$R/compare.png"
