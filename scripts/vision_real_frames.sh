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
# --debug writes an image per stage (<stem>.2_colour_lookup.png ... <stem>.6_detect.png); the
# committed picture of each frame is its last stage, the annotated detections.
DBG=$(mktemp -d)
trap 'rm -rf "$DBG"' EXIT

# SSL standard pattern sheet (800x800 PNG, 1 px = 1 mm): 16 robots, IDs 0-15.
"$PATLAB" detect "$F/ssl-standard-pattern-2010-16ids.png" -t "$D/ssl-standard-sheet.thresholds.toml" \
  -c "$D/ssl-standard-sheet.calibration.toml" -s experiments/detector.toml --debug "$DBG" \
  > "$R/ssl-standard-sheet.detections.csv"

# SSL field 2008 (780x580 JPEG): pre-2010 sector patterns (tests/data/vision/patterns/kiks-sectors.toml).
"$PATLAB" detect "$F/ssl-field-2008.jpg" -t "$D/ssl-2008.thresholds.toml" \
  -c "$D/ssl-2008.calibration.toml" -s "$D/ssl-2008.detector.toml" --debug "$DBG" \
  > "$R/ssl-field-2008.detections.csv" --timing
"$PATLAB" detect "$F/ssl-field-2008.jpg" -t "$D/ssl-2008.thresholds.toml" \
  -c "$D/ssl-2008.calibration.toml" --blobs > "$R/ssl-field-2008.blobs.csv"

# VSS test frame (765x613 PNG): two VSS designs (tests/data/vision/patterns/vss-*.toml).
"$PATLAB" detect "$F/vss-test-frame.png" -t "$D/vss.colors.txt" -c "$D/vss.calibration.toml" \
  -s "$D/vss.detector.toml" --debug "$DBG" > "$R/vss-test-frame.detections.csv" --timing
"$PATLAB" detect "$F/vss-test-frame.png" -t "$D/vss.colors.txt" -c "$D/vss.calibration.toml" \
  --blobs > "$R/vss-test-frame.blobs.csv"

# Settings that travel (docs/detect.md): every frame with the SHIPPED detector numbers -- the
# [detector] and [frame] tables of experiments/detector.toml, unchanged (frames fit a pattern
# with a patch missing) -- and only what the robots wear (palette, patterns, ID colours) from the
# frame's settings file; the SSL 2008 frame through the calibration patlab calibrate fits to its
# points (with its [[residual]] rows) and the pattern measured through that calibration. Each
# frame runs with the calibration as it is and with its [[residual]] tables removed (the residual
# term ignored), and again with [frame] missing_patch = "reject" (the [detector] policy the
# simulations keep), to show what each part does. Prints the table and writes
# results/vision/settings_travel.csv (ids_with: pattern:team-id of every detection, -1 = no ID).
table_of() { awk -v t="$2" '$0 == "[" t "]" {on=1; print; next} /^\[/{on=0} on' "$1"; }
SHIPPED="$(table_of experiments/detector.toml detector)
$(table_of experiments/detector.toml frame)"
wear() {  # settings file $1 with its [detector] and [frame] tables replaced by the shipped ones
  local dir
  dir=$(cd "$(dirname "$1")" && pwd)
  awk '/^\[(detector|frame)\]/{skip=1; next} /^\[/{skip=0} !skip' "$1" |
    sed -E "s#^(patterns_dir|codebook) = \"([^/].*)\"#\1 = \"$dir/\2\"#"
  echo "$SHIPPED"
}
reject() { sed 's/^missing_patch = "fit"/missing_patch = "reject"/' "$1"; }
without_residual() { awk '/^\[\[residual\]\]/{skip=1; next} /^\[/{skip=0} !skip' "$1"; }
"$PATLAB" calibrate "$D/ssl-2008.calibration-input.toml" --out "$DBG/fitted" >/dev/null
cp "$DBG/fitted/calibration.toml" "$DBG/ssl-2008.fitted.toml"
wear "$D/ssl-2008.detector.toml" | sed 's|^pattern = "kiks-sectors"|pattern = "kiks-sectors-fitted"|' \
  >"$DBG/ssl-2008.toml"
wear experiments/detector.toml >"$DBG/sheet.toml"
wear "$D/vss.detector.toml" >"$DBG/vss.toml"
for f in ssl-2008 sheet vss; do reject "$DBG/$f.toml" >"$DBG/$f-reject.toml"; done
# frame | expected robots | thresholds | calibration | settings | note
FRAMES=(
  "ssl-standard-pattern-2010-16ids.png|16|$D/ssl-standard-sheet.thresholds.toml|$D/ssl-standard-sheet.calibration.toml|$DBG/sheet.toml"
  "ssl-standard-pattern-2010-16ids.png|16|$D/ssl-standard-sheet.thresholds.toml|$D/ssl-standard-sheet.calibration.toml|$DBG/sheet-reject.toml|missing_patch = reject"
  "ssl-field-2008.jpg|6|$D/ssl-2008.thresholds.toml|$DBG/ssl-2008.fitted.toml|$DBG/ssl-2008.toml"
  "ssl-field-2008.jpg|6|$D/ssl-2008.thresholds.toml|$DBG/ssl-2008.fitted.toml|$DBG/ssl-2008-reject.toml|missing_patch = reject"
  "vss-test-frame.png|5|$D/vss.colors.txt|$D/vss.calibration.toml|$DBG/vss.toml"
  "vss-test-frame.png|5|$D/vss.colors.txt|$D/vss.calibration.toml|$DBG/vss-reject.toml|missing_patch = reject"
)
count() {  # detections of a CSV: all, and those with an ID
  tail -n +2 "$1" | awk -F, '{n++; if ($4 >= 0) k++} END {printf "%d,%d", n, k}'
}
ids() {  # pattern:team-id of every detection of a CSV (id -1: no ID), sorted, ';'-separated
  tail -n +2 "$1" | awk -F, '{print $2 ":" $3 "-" $4}' | sort -V | paste -sd';' -
}
residual_of() {  # rms_mm of the [[residual]] row nearest the default height, or 0
  awk -F'= *' '/^default_mm/{h=$2+0} /^\[\[residual\]\]/{r=1} r&&/^height_mm/{hh=$2+0}
    r&&/^rms_mm/{d=hh-h; if(d<0)d=-d; if(best==""||d<best){best=d; v=$2+0}}
    END {print (v=="" ? 0 : v)}' "$1"
}
echo "frame,note,robots,residual_mm,found_with,id_with,found_without,id_without,ids_with" \
  >"$R/settings_travel.csv"
for row in "${FRAMES[@]}"; do
  IFS='|' read -r frame robots thr cal set note <<<"$row"
  without_residual "$cal" >"$DBG/cal-without.toml"
  "$PATLAB" detect "$F/$frame" -t "$thr" -c "$cal" -s "$set" > "$DBG/with.csv"
  "$PATLAB" detect "$F/$frame" -t "$thr" -c "$DBG/cal-without.toml" -s "$set" > "$DBG/without.csv"
  echo "$frame,${note:-shipped},$robots,$(residual_of "$cal"),$(count "$DBG/with.csv"),$(count "$DBG/without.csv"),$(ids "$DBG/with.csv")" \
    >>"$R/settings_travel.csv"
done
echo "settings that travel: shipped [detector] and [frame] of experiments/detector.toml on every frame"
column -s, -t <"$R/settings_travel.csv"

for stem in ssl-standard-pattern-2010-16ids ssl-field-2008 vss-test-frame; do
  cp "$DBG/$stem.6_detect.png" "$R/$stem.png"
done

# Enlarged crops of the robots in the SSL 2008 debug image (the frame is 780x580 and a robot is
# ~35 px across): results/vision/ssl-field-2008.robots.png, 6 robots left to right in the order
# of docs/paper-reproduction.md (the 5 on the field, then the one held at the left edge).
if /usr/bin/python3 -c "import matplotlib, numpy" 2>/dev/null; then
  /usr/bin/python3 - "$R/ssl-field-2008.png" "$R/ssl-field-2008.robots.png" <<'PY'
import sys
import matplotlib
matplotlib.use("Agg")
import matplotlib.image as mpimg
import numpy as np
image = mpimg.imread(sys.argv[1])[..., :3]
centres = [(557, 200), (258, 82), (343, 58), (434, 559), (478, 564), (40, 445)]
half, scale = 40, 4
tiles = []
for x, y in centres:
    tile = np.zeros((2 * half, 2 * half, 3), dtype=image.dtype)
    y0, x0 = max(y - half, 0), max(x - half, 0)
    crop = image[y0:y + half, x0:x + half]
    tile[y0 - (y - half):y0 - (y - half) + crop.shape[0], x0 - (x - half):x0 - (x - half) + crop.shape[1]] = crop
    tiles.append(np.repeat(np.repeat(tile, scale, 0), scale, 1))
    tiles.append(np.ones((2 * half * scale, 6, 3), dtype=image.dtype))
mpimg.imsave(sys.argv[2], np.concatenate(tiles[:-1], 1))
PY
fi
echo "vision_real_frames: wrote $R"
