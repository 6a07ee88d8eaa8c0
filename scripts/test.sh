#!/usr/bin/env bash
# Installs the dependencies, builds patlab and runs every check CI runs: the whole test suite
# (ctest), the main job leaving results/ unchanged (check_main_job.sh), the style guard rails
# (clang-format, clang-tidy limits), and the installed package
# with the consumer example built against it; then the test suite under ASan + UBSan and
# 20 s of libFuzzer per parser (docs/hardening.md).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
bash scripts/build.sh
ctest --test-dir build --output-on-failure -j"$(nproc)"
bash scripts/check_main_job.sh
bash scripts/check_install.sh
bash scripts/check_style.sh
bash scripts/check_cluster.sh
bash scripts/check_reproduce.sh
bash scripts/check_sanitizers.sh
bash scripts/check_fuzz.sh
