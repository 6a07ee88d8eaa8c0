#!/usr/bin/env bash
# CI: every number the paper prints, regenerated and judged against results/paper.md and the
# committed result files (docs/reproduce.md). Fails with a line per failing number or file.
set -euo pipefail
cd "$(dirname "$0")/.."
start=$(date +%s)
build/patlab reproduce --check
echo "check_reproduce: ok in $(($(date +%s) - start)) s"
