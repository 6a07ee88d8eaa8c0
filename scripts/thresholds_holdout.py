#!/usr/bin/env python3
"""Held-out measurement of `patlab thresholds --auto` (docs/thresholds.md, "Measured, held out").

Rendered frames: the thresholds are fitted on colour-camera frames of the golden scene
(tests/data/golden/ssl-frame.toml) and scored on frames of another scene of the same camera
(tests/data/vision/thresholds-holdout.scene.toml: other robots, poses and IDs) under other
exposures, read noise and sensor seeds, with `patlab detect` and the scene's own calibration and
detector settings. A robot counts as found when a detection has its team and ID; a false ID is a
detection whose (team, ID) is no robot of the frame.

Real frames: each is fitted on itself with no labels (the classes are its detector settings'
palette) and scored against the robots counted by eye (tests/vision/thresholds_auto_real_test.cpp
holds the same expected values with their pixel positions).

Usage: scripts/thresholds_holdout.py [PATLAB] (default build/patlab). Prints one table.
"""
import csv
import os
import subprocess
import sys
import tempfile

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
PATLAB = sys.argv[1] if len(sys.argv) > 1 else os.path.join(ROOT, "build", "patlab")
DATA = os.path.join(ROOT, "tests", "data")
FRAMES = os.path.join(ROOT, "..", "shared", "frames")

# Counted by eye (see the test named above): (team, id) of every robot of the frame whose
# pattern the detector settings describe.
REAL = {
    "ssl-field-2008.jpg": {
        "settings": "vision/ssl-2008.detector.toml",
        "calibration": "vision/ssl-2008.calibration.toml",
        "expected": [("yellow", 5), ("yellow", -1), ("yellow", -1), ("blue", 6), ("blue", 15)],
    },
    "vss-test-frame.png": {
        "settings": "vision/vss.detector.toml",
        "calibration": "vision/vss.calibration.toml",
        "expected": [("light-green", 2), ("blue", 1), ("light-green", 0), ("light-green", 1),
                     ("light-green", 2)],
    },
}


def run(args):
    return subprocess.run([PATLAB] + args, check=True, capture_output=True, text=True).stdout


def render(tmp, name, scene, frame, exposure, noise, seed):
    out = os.path.join(tmp, name)
    run(["render", scene, "--camera", "--frame", str(frame), "--exposure-gain", str(exposure),
         "--read-noise-levels", str(noise), "--sensor-seed", str(seed), "-o", out])
    return os.path.join(out, "frame.png"), os.path.join(out, "truth.csv")


def detect(frame, thresholds, calibration, settings):
    text = run(["detect", frame, "-t", thresholds, "-c", calibration, "-s", settings])
    return [(r["team"], int(r["id"]), r["status"]) for r in csv.DictReader(text.splitlines())]


def score(detections, expected):
    """(found, false IDs): expected is a list of (team, id); id -1 = a robot whose ID cannot be
    read in the frame, found by any detection of its team not matched otherwise."""
    remaining = list(detections)
    found = 0
    for team, rid in sorted(expected, key=lambda e: e[1] < 0):
        for d in remaining:
            if d[0] == team and (d[1] == rid or rid < 0):
                remaining.remove(d)
                found += 1
                break
    false_ids = sum(1 for d in remaining if d[1] >= 0)
    return found, false_ids


def main():
    golden = os.path.join(DATA, "golden", "ssl-frame.toml")
    holdout = os.path.join(DATA, "vision", "thresholds-holdout.scene.toml")
    settings = os.path.join(DATA, "golden", "ssl-frame.detector.toml")
    calibration = os.path.join(DATA, "golden", "ssl-frame.calibration.toml")
    print("fit on | scored on | robots found / expected | false IDs")
    with tempfile.TemporaryDirectory() as tmp:
        fits = {
            "golden, exposure 1": [(1.0, 2)],
            "golden, exposures 0.7 and 1.4": [(0.7, 2), (1.4, 2)],
        }
        for fit_name, conditions in fits.items():
            frames = [render(tmp, "fit%d" % k, golden, k, e, n, 1)[0]
                      for k, (e, n) in enumerate(conditions)]
            out = os.path.join(tmp, "t")
            run(["thresholds", "--auto"] + frames + ["--settings", settings, "-o", out])
            thresholds = os.path.join(out, "thresholds.toml")
            for exposure in (0.5, 0.7, 1.0, 1.3, 1.6):
                for noise in (2, 8):
                    frame, truth = render(tmp, "h", holdout, 5, exposure, noise, 7)
                    with open(truth) as f:
                        expected = [(r["team"], int(r["id"])) for r in csv.DictReader(f)]
                    found, false_ids = score(detect(frame, thresholds, calibration, settings),
                                             expected)
                    print("%s | holdout scene, exposure %g, read noise %d | %d / %d | %d"
                          % (fit_name, exposure, noise, found, len(expected), false_ids))
        for name, real in REAL.items():
            frame = os.path.join(FRAMES, name)
            if not os.path.exists(frame):
                print("%s | skipped: not found" % name)
                continue
            out = os.path.join(tmp, "real")
            s = os.path.join(DATA, real["settings"])
            run(["thresholds", "--auto", frame, "--settings", s, "-o", out])
            found, false_ids = score(
                detect(frame, os.path.join(out, "thresholds.toml"),
                       os.path.join(DATA, real["calibration"]), s), real["expected"])
            print("%s (itself, no labels) | %s | %d / %d | %d"
                  % (name, name, found, len(real["expected"]), false_ids))


if __name__ == "__main__":
    main()
