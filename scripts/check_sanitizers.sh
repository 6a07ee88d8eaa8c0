#!/usr/bin/env bash
# The whole test suite under AddressSanitizer + UndefinedBehaviorSanitizer (docs/hardening.md).
# One clang build in build-san/ serves this check and the fuzzers (scripts/check_fuzz.sh):
# -DPATLAB_FUZZ=ON compiles every library, the tool, the tests and the harnesses with
# -fsanitize=fuzzer-no-link,address,undefined -fno-sanitize-recover=all, so the first report fails
# its test (leak checking on). Every test ctest knows runs, exactly as in the Release build.
# CI runs it from scripts/test.sh; locally after scripts/setup.sh. ccache is used when present.
# Other sanitizers (TSan, MSan) use -DPATLAB_SANITIZE=... in a build of their own: docs/hardening.md.
set -euo pipefail
cd "$(dirname "$0")/.."
build="${PATLAB_SANITIZER_BUILD_DIR:-build-san}"
launcher=()
if command -v ccache >/dev/null; then launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache); fi
start=$SECONDS
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_COMPILER=clang++ \
  -DPATLAB_FUZZ=ON "${launcher[@]}" >/dev/null
cmake --build "$build" -j"$(nproc)"
built=$SECONDS
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1:detect_stack_use_after_return=1:strict_string_checks=1"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
# Every test runs here, those whose numbers come from arithmetic that differs between compilers
# in the last bits included: reproduce --check's per-column rules accept another compiler's
# knife-edge cells (docs/reproduce.md), and the calibration tests check each fit against its own
# covariance (docs/calibrate.md).
tests=$(ctest --test-dir "$build" -N | sed -n 's/^Total Tests: //p')
ctest --test-dir "$build" --output-on-failure -j"$(nproc)"
echo "check_sanitizers: ${tests} tests clean under ASan + UBSan; build $((built - start)) s, tests $((SECONDS - built)) s"
