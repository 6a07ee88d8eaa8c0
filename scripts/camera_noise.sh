#!/usr/bin/env bash
# Camera-level noise through the colour camera: the section-II track (5 runs x 2570 frames) of
# the SSL standard pattern, coloured (blue key, pink/green dots) and all white, through patlab
# camtrack with each camera mechanism on alone and all together, then a sweep of sensor noise and
# camera roll for the fit to Table I and the section-IV Butterfly. Writes
# results/camera-noise/camera/*.csv, results/camera-noise/camera.csv (all rows) and
# results/camera-noise/camera_shares.png. ~19 CPU s per track (16 tracks); 2 at a time.
# Usage: bash scripts/camera_noise.sh [build/patlab]   (from the repository root)
set -euo pipefail
patlab=${1:-build/patlab}
out=results/camera-noise/camera
mkdir -p "$out"
scene=experiments/camera-noise/track-scene.toml
thr=experiments/camera-noise/track.thresholds.toml
quiet=(--read-noise-levels 0 --shot-noise-gain 0)
three=(--no-bayer --chroma-444)
# Jitter of the section-II fit (experiments/table1.toml: 0.09 px = 0.38 mm of shift) plus a
# 1 mm height bob (330 ppm) and 0.5 mrad of roll.
jit=(--shift-jitter-mm 0.38 --height-jitter-mm 1 --roll-jitter-rad 0.0005)
run() {  # label, then camtrack flags
  local label=$1; shift
  for colour in colour white; do
    local extra=()
    [[ $colour == white ]] && extra=(--white)
    # camtrack writes DIR/camtrack.csv; each run gets its own folder, renamed below.
    "$patlab" camtrack "$scene" --thresholds "$thr" --label "$label" "${extra[@]}" "$@" \
      --out "$out/.$label-$colour" -q &
  done
  wait  # the two schemes side by side (2 cores)
  for colour in colour white; do
    mv "$out/.$label-$colour/camtrack.csv" "$out/$label-$colour.csv"
    rmdir "$out/.$label-$colour"
  done
}
run quantisation "${quiet[@]}" "${three[@]}"
run colour "${quiet[@]}"
run noise "${three[@]}"
run jitter "${quiet[@]}" "${three[@]}" "${jit[@]}"
run all "${jit[@]}"
run all-but-jitter
# Sensor noise and roll: what the full camera needs to reach the paper's numbers.
run read8 --read-noise-levels 8 "${jit[@]}"
run roll0.004 --shift-jitter-mm 0.38 --height-jitter-mm 1 --roll-jitter-rad 0.004
/usr/bin/python3 scripts/plot_camera_noise.py
