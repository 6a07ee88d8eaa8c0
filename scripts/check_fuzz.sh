#!/usr/bin/env bash
# libFuzzer on every parser and image reader (docs/hardening.md): builds the harnesses of
# tests/fuzz/ with clang, ASan and UBSan in build-san/ (the build scripts/check_sanitizers.sh
# makes; CI runs that first, so nothing is rebuilt here), then runs each for a fixed time
# (PATLAB_FUZZ_SECONDS, default 20 s; CI uses the default), one per core at a time, starting from its committed seed
# corpus tests/fuzz/corpus/<name>/. New inputs go to a scratch folder, never into the repository.
# A crash, a sanitizer report, a leak, an exception other than patlab::InputError, a 10 s input
# or 2 GB of memory fails the run; the input that did it is left in build-san/findings/.
# Long runs: PATLAB_FUZZ_SECONDS=3600 bash scripts/check_fuzz.sh [harness...].
set -euo pipefail
cd "$(dirname "$0")/.."
build="${PATLAB_SANITIZER_BUILD_DIR:-build-san}"
seconds="${PATLAB_FUZZ_SECONDS:-20}"
launcher=()
if command -v ccache >/dev/null; then launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache); fi
start=$SECONDS
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_COMPILER=clang++ \
  -DPATLAB_FUZZ=ON "${launcher[@]}" >/dev/null
harnesses=("$@")
if [[ ${#harnesses[@]} -eq 0 ]]; then
  for f in tests/fuzz/*_fuzz.cpp; do harnesses+=("$(basename "$f" _fuzz.cpp)"); done
fi
cmake --build "$build" -j"$(nproc)" --target "${harnesses[@]/%/_fuzz}"
echo "check_fuzz: build $((SECONDS - start)) s"
fuzzing=$SECONDS
mkdir -p "$build/findings"
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
# One harness per core at a time; each one's summary is printed in the harnesses' order.
fuzz() {
  local name=$1 scratch="$build/corpus/$1" log="$build/findings/$1.log"
  rm -rf "$scratch" && mkdir -p "$scratch"
  if "$build/fuzz/${name}_fuzz" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 \
      -max_len=65536 -print_final_stats=1 -artifact_prefix="$build/findings/$name-" \
      "$scratch" "tests/fuzz/corpus/$name" >"$log" 2>&1; then
    runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log")
    echo "check_fuzz: $name ${seconds} s, ${runs:-?} executions, no finding" >"$log.summary"
  else
    echo "check_fuzz: $name FAILED (log: $log)" >"$log.summary"
  fi
}
rm -f "$build"/findings/*.summary
for name in "${harnesses[@]}"; do
  while [[ $(jobs -rp | wc -l) -ge $(nproc) ]]; do wait -n || true; done
  fuzz "$name" &
done
wait
status=0
for name in "${harnesses[@]}"; do
  summary="$build/findings/$name.log.summary"
  cat "$summary"
  if grep -q FAILED "$summary"; then
    tail -n 40 "$build/findings/$name.log"
    status=1
  fi
done
echo "check_fuzz: ${#harnesses[@]} harnesses in $((SECONDS - fuzzing)) s on $(nproc) cores"
exit $status
