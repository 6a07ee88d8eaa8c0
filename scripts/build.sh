#!/usr/bin/env bash
# Configures and builds patlab (Release) into build/: everything, or the targets given
# (e.g. `scripts/build.sh patlab`). With CI=true warnings are errors.
set -euo pipefail
cd "$(dirname "$0")/.."
werror=OFF
if [[ "${CI:-}" == "true" ]]; then werror=ON; fi
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DPATLAB_WERROR="$werror"
targets=()
for t in "$@"; do targets+=(--target "$t"); done
cmake --build build -j"$(nproc)" "${targets[@]}"
