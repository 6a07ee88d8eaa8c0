#!/usr/bin/env bash
# Configures and builds patlab (Release) into build/. With CI=true warnings are errors.
set -euo pipefail
cd "$(dirname "$0")/.."
werror=OFF
if [[ "${CI:-}" == "true" ]]; then werror=ON; fi
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DPATLAB_WERROR="$werror"
cmake --build build -j"$(nproc)"
