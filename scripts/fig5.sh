#!/usr/bin/env bash
# The main job from a fresh machine: installs the dependencies, builds patlab, runs the default
# experiment (the paper's Fig. 5) and draws the figure:
#   results/fig5.csv, results/fig5.json, results/fig5.png
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
bash scripts/build.sh patlab
./build/patlab simulate experiments/fig5.toml --out results
/usr/bin/python3 scripts/plot_fig5.py results/fig5.csv results/fig5.png
echo "wrote results/fig5.png"
