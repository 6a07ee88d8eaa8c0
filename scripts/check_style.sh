#!/usr/bin/env bash
# The style guard rails (docs/contributing.md): the rooms' layering and file sizes
# (scripts/check_layering.sh), the source paths the docs mention (scripts/check_doc_paths.py),
# docs/setup.md's per-frame tables against results/setup (scripts/check_setup_tables.py),
# every C++ file formatted by the committed .clang-format, and the .clang-tidy limits (function size 80 lines, cognitive complexity 40) on every source file.
# Needs build/compile_commands.json (scripts/build.sh writes it).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/check_layering.sh  # the rooms' includes and links, cycles, no file over 500 lines
/usr/bin/python3 scripts/check_doc_paths.py  # every source path the docs mention exists
/usr/bin/python3 scripts/check_setup_tables.py  # docs/setup.md's per-frame rows are the CSVs'
mapfile -t files < <(git ls-files '*.cpp' '*.h')
echo "clang-format: ${#files[@]} files"
clang-format --dry-run -Werror "${files[@]}"
# Numbers as text do not depend on the locale (docs/architecture.md, "Numbers as text"): no
# printf-family floating-point conversion and no locale-bound number parsing in src/. A line may
# opt out with a comment "locale-independent: <why>".
locale_bound=$(git ls-files 'src/*.cpp' 'src/*.h' | /usr/bin/python3 scripts/check_locale_bound.py)
if [[ -n "$locale_bound" ]]; then
  echo "$locale_bound"
  echo "locale-bound number text above: use core/format.h (FormatFixed, StringPrintf...) and" \
       "std::from_chars / io::ParseDouble"
  exit 1
fi
# A room built as a unity build (PATLAB_UNITY_BUILD) is parsed as it compiles: its few generated
# units, each of which includes several of its sources (scripts/tidy_units.py; .clang-tidy's
# HeaderFilterRegex reports what is found in the sources they include).
mapfile -t sources < <(git ls-files 'src/*.cpp')
units=$(/usr/bin/python3 scripts/tidy_units.py "${sources[@]}")
echo "clang-tidy: ${#sources[@]} sources in $(wc -l <<< "$units") translation units"
mapfile -t units <<< "$units"
run-clang-tidy -quiet -p build -j"$(nproc)" "${units[@]}" > build/clang-tidy.log 2>&1 || {
  grep -E "warning:|error:" build/clang-tidy.log | sort -u
  echo "clang-tidy found problems (full log: build/clang-tidy.log)"
  exit 1
}
echo "style ok"
