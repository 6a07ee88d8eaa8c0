#!/usr/bin/env bash
# patlab design on the SSL robot top: Ø180 mm, Ø50 key, four Ø40 dots, 2 ID
# colours (pink / green, as the SSL standard), 20 mm between patches, each design started from
# patterns/ssl-standard.toml among 32 seeded starts, then every design and the SSL standard
# compared with patlab compare (100,000 Monte-Carlo trials per design, 10,000 detect-mode frames
# per patch sigma). docs/design.md discusses the numbers.
# Usage: scripts/design_results.sh [PATLAB] (default build/patlab).
set -euo pipefail
cd "$(dirname "$0")/.."
PATLAB=${1:-build/patlab}
R=results/design
rm -f "$R"/*.toml "$R"/*.design.txt
SSL=(--outer-diameter-mm 180 --key-radius-mm 25 --id-patches 4 --id-radii-mm 20 --min-gap-mm 20
     --palette 2 --start ssl-standard --starts 32 --seed 1 -q)
# The most accurate angle at the SSL standard's robustness (its rotation onset is 3.766 mm).
"$PATLAB" design "${SSL[@]}" --name designed-accurate --min-rotation-onset-mm 3.77 --out "$R"
# The most robust rotation fix at the SSL standard's angle CRLB (7.76 mrad/mm).
"$PATLAB" design "${SSL[@]}" --name designed-robust --objective rotation_onset \
  --max-angle-crlb-mrad-per-mm 7.76 --out "$R"
# The same two inside the SSL standard's own envelope (Ø170: 5 mm from the rim), so that the
# gain of the layout is told apart from the gain of the 10 mm larger diameter.
"$PATLAB" design "${SSL[@]}" --name designed-accurate-170 --rim-gap-mm 5 \
  --min-rotation-onset-mm 3.77 --out "$R"
"$PATLAB" design "${SSL[@]}" --name designed-robust-170 --rim-gap-mm 5 \
  --objective rotation_onset --max-angle-crlb-mrad-per-mm 7.76 --out "$R"
"$PATLAB" compare ssl-standard "$R"/designed-accurate.toml "$R"/designed-robust.toml \
  "$R"/designed-accurate-170.toml "$R"/designed-robust-170.toml \
  --trials 100000 --frames 10000 --sigmas 2,3,4,5,6 --sort-by rotation_onset_mm --out "$R" -q
/usr/bin/python3 scripts/plot_compare.py "$R/compare.csv" "$R/compare.png"
