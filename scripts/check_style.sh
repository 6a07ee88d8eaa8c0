#!/usr/bin/env bash
# The style guard rails (docs/contributing.md): the rooms' layering and file sizes
# (scripts/check_layering.sh), every C++ file formatted by the committed .clang-format, and the
# .clang-tidy limits (function size 80 lines, cognitive complexity 40) on every source file.
# Needs build/compile_commands.json (scripts/build.sh writes it).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/check_layering.sh  # the rooms' includes and links, cycles, no file over 500 lines
mapfile -t files < <(git ls-files '*.cpp' '*.h')
echo "clang-format: ${#files[@]} files"
clang-format --dry-run -Werror "${files[@]}"
mapfile -t sources < <(git ls-files 'src/*.cpp')
echo "clang-tidy: ${#sources[@]} sources"
run-clang-tidy -quiet -p build -j"$(nproc)" "${sources[@]/#/$PWD/}" > build/clang-tidy.log 2>&1 || {
  grep -E "warning:|error:" build/clang-tidy.log | sort -u
  echo "clang-tidy found problems (full log: build/clang-tidy.log)"
  exit 1
}
echo "style ok"
