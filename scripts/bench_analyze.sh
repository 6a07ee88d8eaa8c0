#!/usr/bin/env bash
# Times `patlab analyze` on 1,000,000 samples (4 subjects x 5 runs x 50,000 frames of straight
# tracks with white noise, theta included) on one core: prints the tool's stage timings and the
# CPU time (user + sys) from /usr/bin/time. usage: scripts/bench_analyze.sh [PATLAB]
set -euo pipefail
P=$(realpath "${1:-build/patlab}")
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
/usr/bin/python3 - "$work/big.csv" <<'PY'
import sys
import numpy as np
rng = np.random.default_rng(1)
with open(sys.argv[1], "w") as f:
    f.write("frame,subject,run,x_mm,y_mm,theta_rad\n")
    for run in range(5):
        for s in range(4):
            n = 50000
            fr = np.arange(n)
            x = 0.77 * fr + rng.normal(0, 0.5, n)
            y = 100 * s + 0.1 * fr + rng.normal(0, 0.4, n)
            th = np.mod(0.01 * fr + rng.normal(0, 0.01, n) + np.pi, 2 * np.pi) - np.pi
            f.writelines(f"{a},r{s},{run},{b:.4f},{c:.4f},{d:.5f}\n" for a, b, c, d in zip(fr, x, y, th))
PY
uptime
taskset -c 0 /usr/bin/time -f "cpu: %U s user + %S s sys, %e s wall, %M KB max RSS, %R minor faults" \
  "$P" analyze "$work/big.csv" --out "$work/out"
# The same with glibc's malloc asking for transparent huge pages (this machine's THP mode is
# "madvise"): on the shared VM most of the sys time is minor page faults on fresh memory (~35,000
# of them for ~145 MB), which 2 MB pages cut to ~1,400. Same output.
GLIBC_TUNABLES=glibc.malloc.hugetlb=1 taskset -c 0 \
  /usr/bin/time -f "cpu (malloc huge pages): %U s user + %S s sys, %e s wall, %R minor faults" \
  "$P" analyze "$work/big.csv" --out "$work/out" -q
