#!/usr/bin/env bash
# Installs patlab into build/install and builds the consumer examples against the installed
# package only, as another project would: examples/detect_blobs (patlab::detect with a settings
# file read by patlab::formats) must report, given the blobs `patlab detect --blobs` finds in the
# golden frame, the same robots (team and ID) as `patlab detect` itself; examples/detect_in_code
# links patlab::detect alone (its configure step fails if that reaches toml++, libpng, libjpeg or
# another room) and must find its one robot.
set -euo pipefail
cd "$(dirname "$0")/.."
prefix=$PWD/build/install
rm -rf "$prefix" build/example build/example-in-code
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

golden=tests/data/golden
frame_args=("$golden/ssl-frame.png" --thresholds "$golden/ssl-frame.thresholds.toml"
            --calibration "$golden/ssl-frame.calibration.toml")
"$prefix/bin/patlab" detect "${frame_args[@]}" --blobs --out build/example/blobs.csv
"$prefix/bin/patlab" detect "${frame_args[@]}" --settings "$golden/ssl-frame.detector.toml" \
  --out build/example/detections.csv
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
