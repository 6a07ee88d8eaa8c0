#!/usr/bin/env bash
# Installs patlab into build/install and builds the consumer example (examples/detect_blobs)
# against the installed package only, as another project would; then checks that the example,
# given the blobs `patlab detect --blobs` finds in the golden frame, reports the same robots
# (team and ID) as `patlab detect` itself.
set -euo pipefail
cd "$(dirname "$0")/.."
prefix=$PWD/build/install
rm -rf "$prefix" build/example
cmake --install build --prefix "$prefix" > build/install.log
cmake -S examples/detect_blobs -B build/example -DCMAKE_PREFIX_PATH="$prefix" > build/example-configure.log
cmake --build build/example 2>&1 | tail -n 1

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
echo "install ok: examples/detect_blobs found $(wc -l < build/example/lib.txt) robots, as patlab detect did"
