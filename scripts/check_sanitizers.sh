#!/usr/bin/env bash
# Tests under AddressSanitizer + UndefinedBehaviorSanitizer (docs/hardening.md): a separate
# RelWithDebInfo build in build-asan/ (GCC, the same compiler as the Release build), every library,
# the tool and the tests compiled with -fsanitize=address,undefined and -fno-sanitize-recover=all,
# so the first report fails its test. CI runs the tests of the input paths: core, io and the
# malformed-input suite (which runs the sanitized tool on every input patlab reads); these are the
# ones run clean under the sanitizers so far. `scripts/check_sanitizers.sh --all` runs the whole
# suite (about 20 min on 2 cores; not yet run clean end to end: docs/hardening.md).
# CI runs it from scripts/test.sh; locally after scripts/setup.sh. ccache is used when present.
set -euo pipefail
cd "$(dirname "$0")/.."
build="${PATLAB_ASAN_BUILD_DIR:-build-asan}"
launcher=()
if command -v ccache >/dev/null; then launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache); fi
start=$SECONDS
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DPATLAB_SANITIZE=address,undefined \
  "${launcher[@]}" >/dev/null
targets=(patlab test_core test_io test_malformed)
if [[ "${1:-}" == "--all" ]]; then targets=(all); fi
cmake --build "$build" -j"$(nproc)" --target "${targets[@]}"
built=$SECONDS
# Leak checking stays on (LeakSanitizer is part of ASan); a report anywhere aborts the process.
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1:detect_stack_use_after_return=1:strict_string_checks=1"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
if [[ "${1:-}" == "--all" ]]; then
  ctest --test-dir "$build" --output-on-failure -j"$(nproc)"
else
  for t in test_core test_io test_malformed; do "$build/tests/$t" --gtest_brief=1; done
fi
echo "check_sanitizers: build $((built - start)) s, tests $((SECONDS - built)) s"
