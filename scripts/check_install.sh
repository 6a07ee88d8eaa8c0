#!/usr/bin/env bash
# Installs patlab into build/install, runs README.md's example commands with the installed tool
# in an empty folder, and builds the consumer examples against the installed package only, as
# another project would: examples/detect_blobs (patlab::detect with a settings
# file read by patlab::formats) must report, given the blobs `patlab detect --blobs` finds in the
# golden frame, the same robots (team and ID) as `patlab detect` itself; examples/detect_in_code
# links patlab::detect alone (its configure step fails if that reaches toml++, libpng, libjpeg or
# another room) and must find its one robot.
set -euo pipefail
cd "$(dirname "$0")/.."
prefix=$PWD/build/install
rm -rf "$prefix" build/example build/example-in-code build/example-live
cmake --install build --prefix "$prefix" > build/install.log
cmake -S examples/detect_blobs -B build/example -DCMAKE_PREFIX_PATH="$prefix" > build/example-configure.log
cmake --build build/example 2>&1 | tail -n 1
cmake -S examples/detect_in_code -B build/example-in-code -DCMAKE_PREFIX_PATH="$prefix" \
  > build/example-in-code-configure.log || {
  cat build/example-in-code-configure.log
  exit 1
}
cmake --build build/example-in-code 2>&1 | tail -n 1
in_code=$(build/example-in-code/detect_in_code)
if [[ $(wc -l <<< "$in_code") != 1 || $in_code != "blue "*" ok 0.00 0.00 0.0000" ]]; then
  echo "examples/detect_in_code printed '$in_code'; expected one blue robot at (0, 0), theta 0"
  exit 1
fi

# The live room's public headers and the generated SSL-Vision classes from the installed prefix:
# examples/live_packet builds a detection packet with patlab::live and reads it back.
cmake -S examples/live_packet -B build/example-live -DCMAKE_PREFIX_PATH="$prefix" \
  > build/example-live-configure.log || {
  cat build/example-live-configure.log
  exit 1
}
cmake --build build/example-live 2>&1 | tail -n 1
live_packet=$(build/example-live/live_packet)
if [[ $live_packet != "robot 3 blue at 120 -40" ]]; then
  echo "examples/live_packet printed '$live_packet'; expected 'robot 3 blue at 120 -40'"
  exit 1
fi
echo "install ok: examples/live_packet included the live headers and the generated classes"

# README's examples, as a new user runs them: the installed tool, in an empty folder, shipped
# data by name, relative -o folders that do not exist yet. The commands are read from README.md's
# first example block (so they cannot drift from it), each line that starts with "patlab".
readme_examples=$(awk '/^## One example per command/ {on = 1}
  on && /^```sh/ {inside = 1; next}
  inside && /^```/ {exit}
  inside && /^patlab / {print}' README.md)
[[ -n $readme_examples ]] || { echo "no examples found in README.md"; exit 1; }
(
  cd "$(mktemp -d)"
  unset PATLAB_DATA
  while IFS= read -r example; do
    if ! eval "\"$prefix/bin/\"$example" > example.log 2>&1; then
      cat example.log
      echo "README example failed from an installed prefix in an empty folder: $example"
      exit 1
    fi
  done <<< "$readme_examples"
)
echo "install ok: README.md's $(wc -l <<< "$readme_examples") example commands ran from the installed prefix"
[[ -f $prefix/share/bash-completion/completions/patlab ]] ||
  { echo "no bash completion installed"; exit 1; }

golden=tests/data/golden
frame_args=("$golden/ssl-frame.png" --thresholds "$golden/ssl-frame.thresholds.toml"
            --calibration "$golden/ssl-frame.calibration.toml")
"$prefix/bin/patlab" detect "${frame_args[@]}" --blobs --out build/example
"$prefix/bin/patlab" detect "${frame_args[@]}" --settings "$golden/ssl-frame.detector.toml" \
  --out build/example
build/example/detect_blobs "$golden/ssl-frame.detector.toml" build/example/blobs.csv \
  > build/example/example.txt
# Columns: pattern team id status (the example prints poses from 2-decimal blobs, so poses are
# compared by the tests of the detector, not here).
tail -n +2 build/example/detections.csv | cut -d, -f2-5 | tr ',' ' ' | sort > build/example/cli.txt
cut -d' ' -f1-4 build/example/example.txt | sort > build/example/lib.txt
if ! diff -u build/example/cli.txt build/example/lib.txt; then
  echo "the installed library and the CLI disagree on the golden frame"
  exit 1
fi
echo "install ok: examples/detect_blobs found $(wc -l < build/example/lib.txt) robots, as patlab detect did;" \
  "examples/detect_in_code links patlab::detect alone and found: $in_code"

# The Python module, when it was built: `import patlab` from the installed prefix alone (its
# site-packages on PYTHONPATH, run in an empty folder, so neither the source nor the build tree is
# reachable), running the first example of docs/python.md.
if module=$(find "$prefix" -name '_patlab*.so' | head -n 1) && [[ -n $module ]]; then
  site=$(dirname "$(dirname "$module")")
  empty=$(mktemp -d)
  awk '/^```python$/ {inside = 1; next} inside && /^```$/ {exit} inside' docs/python.md \
    > "$empty/example.py"
  (cd "$empty" && env -u PATLAB_DATA PYTHONPATH="$site" PYTHONDONTWRITEBYTECODE=1 \
    /usr/bin/python3 example.py > python.txt) || { echo "docs/python.md's example failed"; exit 1; }
  echo "install ok: import patlab from ${site#"$prefix"/} ran docs/python.md's first example:" \
    "$(head -n 1 "$empty/python.txt")"
  rm -rf "$empty"
fi

# The same example through pkg-config (patlab.pc, relocatable), and a shared-library build of
# patlab (BUILD_SHARED_LIBS=ON: versioned SONAMEs) installed into its own prefix, with the example
# linked against it both ways and run from another folder: the installed tool and example must
# find their libraries by themselves (RUNPATH), and report the same robots. It builds no Python
# module (the one installed above is checked there) and compiles without optimisation (-O0, no
# debug information): it checks the packaging, not the code the Release build above tested, and
# an unoptimised build compiles in a fraction of the time.
pc_check() {  # $1: prefix, $2: output binary, $3: extra pkg-config flags
  local flags
  flags=$(PKG_CONFIG_PATH="$(dirname "$(find "$1" -name patlab.pc | head -n 1)")" \
    pkg-config $3 --cflags --libs patlab)
  # shellcheck disable=SC2086
  g++ -O1 examples/detect_blobs/main.cpp -o "$2" $flags -Wl,-rpath,"$(dirname "$(find "$1" -name 'libpatlab_core*' | head -n 1)")"
}
pc_check "$prefix" build/example/detect_blobs_pc --static
build/example/detect_blobs_pc "$golden/ssl-frame.detector.toml" build/example/blobs.csv |
  cut -d' ' -f1-4 | sort | diff -u build/example/lib.txt -
echo "install ok: the pkg-config build of the example (static libraries) agrees"

shared_prefix=$PWD/build/install-shared
rm -rf build/shared "$shared_prefix"
cmake -S . -B build/shared -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_FLAGS_DEBUG=-O0 \
  -DBUILD_SHARED_LIBS=ON -DPATLAB_BUILD_TESTS=OFF -DPATLAB_PYTHON=OFF > build/shared-configure.log
cmake --build build/shared -j"$(nproc)" > build/shared-build.log 2>&1 ||
  { tail -n 30 build/shared-build.log; exit 1; }
cmake --install build/shared --prefix "$shared_prefix" > build/shared-install.log
soname=$(objdump -p "$(find "$shared_prefix" -name 'libpatlab_detect.so.*.*.*' | head -n 1)" |
  awk '/SONAME/ {print $2}')
[[ "$soname" == libpatlab_detect.so.* ]] || { echo "no versioned SONAME: '$soname'"; exit 1; }
cmake -S examples/detect_blobs -B build/example-shared -DCMAKE_PREFIX_PATH="$shared_prefix" \
  > build/example-shared-configure.log
cmake --build build/example-shared 2>&1 | tail -n 1
pc_check "$shared_prefix" build/example-shared/detect_blobs_pc ""
(
  cd "$(mktemp -d)"
  for example in "$OLDPWD/build/example-shared/detect_blobs" "$OLDPWD/build/example-shared/detect_blobs_pc"; do
    "$example" "$OLDPWD/$golden/ssl-frame.detector.toml" "$OLDPWD/build/example/blobs.csv" |
      cut -d' ' -f1-4 | sort | diff -u "$OLDPWD/build/example/lib.txt" -
  done
  "$shared_prefix/bin/patlab" --help > /dev/null
)
echo "install ok: shared libraries ($soname), the example through find_package and pkg-config agree"
