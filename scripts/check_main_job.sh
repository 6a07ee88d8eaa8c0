#!/usr/bin/env bash
# The main job leaves the checkout as it found it: runs the README's first command
# (scripts/fig5.sh: set-up, build, the Fig. 5 sweep, the figure) and fails when any file under
# results/ differs from the committed one or is new. The committed results are the same bytes
# on every x86-64 CPU, at any thread count (docs/architecture.md, "Same bytes on every machine"),
# so a difference here is a bug, whatever machine CI runs on.
set -euo pipefail
cd "$(dirname "$0")/.."
if ! git rev-parse --is-inside-work-tree > /dev/null 2>&1; then
  echo "check_main_job: needs a git checkout (it compares results/ with the committed files)" >&2
  exit 2
fi
bash scripts/fig5.sh > build/main_job.log 2>&1 || {
  cat build/main_job.log >&2
  echo "check_main_job: scripts/fig5.sh failed (log above)" >&2
  exit 1
}
changed=$(git status --porcelain --untracked-files=all -- results/)
if [[ -n "$changed" ]]; then
  echo "check_main_job: the main job changed results/ on this machine ($(uname -m)," \
    "$(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs)):" >&2
  echo "$changed" >&2
  git --no-pager diff --stat -- results/ >&2
  git --no-pager diff -- results/fig5.csv | head -n 20 >&2
  exit 1
fi
echo "check_main_job: results/ unchanged after scripts/fig5.sh ($(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs))"
