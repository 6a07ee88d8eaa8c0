#!/usr/bin/env bash
# Installs the dependencies, builds patlab and runs every check CI runs: the whole test suite
# (ctest), the main job leaving results/ unchanged (check_main_job.sh), the style guard rails
# (clang-format, clang-tidy limits), and the installed package
# with the consumer example built against it; then the test suite under ASan + UBSan and
# 20 s of libFuzzer per parser (docs/hardening.md).
set -euo pipefail
cd "$(dirname "$0")/.."
# Each step's wall time, printed when it ends (CI's time budget: docs/hardening.md).
step() {
  local start=$SECONDS
  "$@"
  echo "test.sh: '$*' took $((SECONDS - start)) s"
}
step bash scripts/setup.sh
step bash scripts/build.sh
step ctest --test-dir build --output-on-failure -j"$(nproc)"
step bash scripts/check_main_job.sh
step bash scripts/check_install.sh
step bash scripts/check_style.sh
step bash scripts/check_cluster.sh
step bash scripts/check_reproduce.sh
step bash scripts/check_sanitizers.sh
step bash scripts/check_fuzz.sh
echo "test.sh: every check passed in $SECONDS s"
