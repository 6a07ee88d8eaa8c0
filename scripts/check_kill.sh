#!/usr/bin/env bash
# Kills patlab's writing commands at random moments (SIGKILL or SIGTERM) and checks that every
# results folder holds the complete old or the complete new result set, never a mix, and no
# temporary after the next run into it (scripts/kill_harness.py; docs/hardening.md, "Results all
# or nothing"). CI (ctest kill_harness) runs COUNT=100 rounds of every command, reproduce included
# (a small root of the paper's experiments, a fraction of a second a run), two commands side by
# side (--jobs), then a SIGKILL placed at every fsync, rename and unlink of each command's run
# (--placed-calls fsync,rename,unlink; needs strace); locally, e.g.
#   COUNT=1000 bash scripts/check_kill.sh
#   COUNT=200 bash scripts/check_kill.sh --strace    # SIGKILL at each openat, fsync, rename, unlink
# Extra arguments go to the driver (--commands simulate,merge, --seed S, --jobs J).
set -euo pipefail
cd "$(dirname "$0")/.."
exec /usr/bin/python3 scripts/kill_harness.py --patlab "${PATLAB:-build/patlab}" --root . \
  --count "${COUNT:-100}" "$@"
