#!/usr/bin/env bash
# patlab detect on the shared real frames (../shared/frames, GPL-3.0, not in this repository):
# writes results/vision/<frame>.png (annotated debug images), *.detections.csv and *.blobs.csv.
# Usage: scripts/vision_real_frames.sh [PATLAB] (default build/patlab). Skips cleanly (exit 0)
# when ../shared/frames is absent.
set -euo pipefail
cd "$(dirname "$0")/.."
PATLAB=${1:-build/patlab}
F=../shared/frames
D=tests/data/vision
R=results/vision
if [ ! -d "$F" ]; then
  echo "vision_real_frames: no $F; skipped"
  exit 0
fi
mkdir -p "$R"

# SSL standard pattern sheet (800x800 PNG, 1 px = 1 mm): 16 robots, IDs 0-15.
"$PATLAB" detect "$F/ssl-standard-pattern-2010-16ids.png" -t "$D/ssl-standard-sheet.thresholds.toml" \
  -c "$D/ssl-standard-sheet.calibration.toml" -s experiments/detector.toml --debug "$R" \
  --out "$R/ssl-standard-sheet.detections.csv"

# SSL field 2008 (780x580 JPEG): pre-2010 sector patterns (patterns/kiks-sectors.toml).
"$PATLAB" detect "$F/ssl-field-2008.jpg" -t "$D/ssl-2008.thresholds.toml" \
  -c "$D/ssl-2008.calibration.toml" -s "$D/ssl-2008.detector.toml" --debug "$R" \
  --out "$R/ssl-field-2008.detections.csv" --timing
"$PATLAB" detect "$F/ssl-field-2008.jpg" -t "$D/ssl-2008.thresholds.toml" \
  -c "$D/ssl-2008.calibration.toml" --blobs --out "$R/ssl-field-2008.blobs.csv"

# VSS test frame (765x613 PNG): two VSS designs (patterns/vss-*.toml).
"$PATLAB" detect "$F/vss-test-frame.png" -t "$D/vss.colors.txt" -c "$D/vss.calibration.toml" \
  -s "$D/vss.detector.toml" --debug "$R" --out "$R/vss-test-frame.detections.csv" --timing
"$PATLAB" detect "$F/vss-test-frame.png" -t "$D/vss.colors.txt" -c "$D/vss.calibration.toml" \
  --blobs --out "$R/vss-test-frame.blobs.csv"
echo "vision_real_frames: wrote $R"
