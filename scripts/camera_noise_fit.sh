#!/usr/bin/env bash
# Which camera-level noise mechanisms, with which magnitudes, reproduce Table I and the
# section-IV Butterfly at once. patlab fitnoise (first-order model, profile likelihood, bootstrap,
# candidate models, the Butterfly-size sensitivity, the blob-level track check) into
# results/camera-noise/fit/, its figures, then the confirmation through the colour camera: patlab
# camtrack with the fitted camera jitter, white and coloured (the coloured one also through the
# detector), into results/camera-noise/fit/camtrack-*.csv. ~10 CPU s for the fit, ~20 CPU s per
# camtrack.
# Usage: bash scripts/camera_noise_fit.sh [build/patlab]   (from the repository root)
set -euo pipefail
patlab=${1:-build/patlab}
out=results/camera-noise/fit
mkdir -p "$out"
"$patlab" fitnoise --out "$out"
/usr/bin/python3 scripts/plot_camera_noise_fit.py "$out"
# The fitted common-mode jitter and roll as the camera's per-frame shift and roll (the fit finds
# both at or near 0; the camera's own sensor noise, Bayer and 4:2:2 stand in for the fitted
# per-patch terms).
shift=$(awk -F, '$1 == "common_mm" {print $3}' "$out/fit.csv")
roll=$(awk -F, '$1 == "roll_mrad" {print $3 / 1000}' "$out/fit.csv")
scene=experiments/camera-noise/track-scene.toml
thr=experiments/camera-noise/track.thresholds.toml
"$patlab" camtrack "$scene" --thresholds "$thr" --label fit-colour --detect \
  --shift-jitter-mm "$shift" --roll-jitter-rad "$roll" --out "$out/.camtrack-colour" &
"$patlab" camtrack "$scene" --thresholds "$thr" --label fit-white --white \
  --shift-jitter-mm "$shift" --roll-jitter-rad "$roll" --out "$out/.camtrack-white" &
wait
# camtrack writes DIR/camtrack.csv: the two runs' files under their result names.
for scheme in colour white; do
  mv "$out/.camtrack-$scheme/camtrack.csv" "$out/camtrack-$scheme.csv"
  rmdir "$out/.camtrack-$scheme"
done
