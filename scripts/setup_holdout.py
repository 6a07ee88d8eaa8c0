#!/usr/bin/env python3
"""Holds each camera out in turn: the colour fit's constants chosen on the other cameras only.

`patlab setup`'s colour fit (vision/thresholds_blobs.h) has two constants that decide what it
sees: standout_delta_e (how far from the carpet a pixel must lie to be a candidate) and
segment_k (how readily the graph segmentation joins pixels into one region). Their defaults were
set while looking at real frames, so a score on those frames alone would not show that they
carry to a camera nobody looked at. Here every camera is scored on a grid of both constants:

  * the real VSS frame (../shared/frames/vss-test-frame.png, family `vss`, the shipped
    `vss.detector`, robots 0 mm above the floor);
  * the real SSL frame (../shared/frames/ssl-field-2008.jpg, family `ssl`, the settings of the
    robots' pattern as the team's sheet draws it, tests/data/vision/ssl-2008-sheet.detector.toml);
  * the rendered random cameras of scripts/setup_rendered.py (seeds 1-12 by default, each its own
    camera).

and then, for each camera in turn, the grid points with the best score on all the *other*
cameras (robots right minus ten times the false IDs) are the ones it is scored with: its held-out
score is its mean (and worst) score over those points. When the other cameras do not tell two
points apart, neither point is preferred -- a tie is not broken towards the defaults -- so a
camera whose result hangs on a constant its own frame chose shows it as a lower mean.

The real frames' truth is the robots counted by eye (tests/cli/setup_real_cli_test.cpp): each
robot's key patch centre in px, its team and ID (-1: team only), mapped to the floor through the
calibration setup wrote (patlab.pixel_to_floor) and matched within 60 mm.

Usage: scripts/setup_holdout.py [--patlab build/patlab] [--seeds 1-12] [--out results/setup]
(the patlab module from build/python, else an installed one)
Writes OUT/holdout_grid.csv (every camera at every grid point) and OUT/holdout.csv (each camera
held out), and prints the table docs/setup.md quotes.
"""
import argparse
import csv
import itertools
import math
import os
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "build", "python"))  # patlab's module, unless installed
import patlab  # noqa: E402
import setup_rendered  # noqa: E402

FRAMES = os.path.join(os.path.dirname(ROOT), "shared", "frames")
STANDOUT_DELTA_E = (14.0, 20.0, 28.0)
SEGMENT_K = (40.0, 60.0, 90.0)
DEFAULT = (20.0, 60.0)
MATCH_MM = 60.0
FALSE_ID_COST = 10

# The real frames: setup's flags and the robots counted by eye (u px, v px, team, id).
REAL = {
    "vss-real": ("vss-test-frame.png",
                 ["--field", "vss", "--robot-height", "0", "--settings", "vss.detector"],
                 [(145, 28, "blue", 1), (540, 598, "yellow", 2), (133, 413, "yellow", 0),
                  (276, 403, "yellow", 1), (209, 490, "yellow", 2)]),
    "ssl-real": ("ssl-field-2008.jpg",
                 ["--field", "ssl", "--settings",
                  os.path.join(ROOT, "tests", "data", "vision", "ssl-2008-sheet.detector.toml")],
                 [(557, 200, "yellow", 5), (343, 58, "yellow", -1), (258, 82, "yellow", -1),
                  (434, 559, "blue", 6), (478, 564, "blue", 15)]),
}


def score_real(cam_dir, detect_csv, robots):
    """(right, false IDs) of a real frame's detections against the robots counted by eye."""
    pixels = [(u, v) for u, v, _, _ in robots]
    floor = patlab.pixel_to_floor(os.path.join(cam_dir, "calibration.toml"), pixels)
    used = [False] * len(robots)
    right = false = 0
    for d in csv.DictReader(detect_csv.splitlines()):
        if "team" not in d:
            continue
        rid = int(d["id"])
        x, y = float(d["x_mm"]), float(d["y_mm"])
        near = [(math.hypot(fx - x, fy - y), i) for i, (fx, fy) in enumerate(floor)
                if not math.isnan(fx)]
        mm, i = min(near) if near else (math.inf, -1)
        ok = (mm <= MATCH_MM and not used[i] and robots[i][2] == d["team"]
              and robots[i][3] in (-1, rid))
        if ok:
            used[i] = True
            right += 1
        elif rid >= 0:
            false += 1
    return right, false


def colour_flags(point):
    return ["--colour-option", "standout_delta_e=%g" % point[0],
            "--colour-option", "segment_k=%g" % point[1]]


def run_real(patlab_bin, name, point, work, log):
    frame_name, flags, robots = REAL[name]
    frame = os.path.join(FRAMES, frame_name)
    cam_dir = os.path.join(work, "%s-%g-%g" % (name, *point))
    setup, _ = setup_rendered.run([patlab_bin, "setup", frame] + flags + colour_flags(point) +
                                  ["-o", cam_dir], log)
    if setup.returncode != 0:
        return 0, 0, len(robots)
    detect = subprocess.run([patlab_bin, "detect", frame, "--setup", cam_dir, "--format", "csv",
                             "-q"], stdout=subprocess.PIPE, text=True)
    right, false = score_real(cam_dir, detect.stdout, robots)
    return right, false, len(robots)


def choose(grid, cameras, held_out):
    """The grid points with the best score on every camera but `held_out` (all of them when
    those cameras do not tell the points apart)."""
    def total(point):
        return sum(grid[c, point][0] - FALSE_ID_COST * grid[c, point][1]
                   for c in cameras if c != held_out)
    best = max(total(p) for p in grid_points())
    return [p for p in grid_points() if total(p) == best]


def grid_points():
    return list(itertools.product(STANDOUT_DELTA_E, SEGMENT_K))


def write_csv(path, rows):
    with open(path + ".tmp", "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0].keys()), lineterminator="\n")
        writer.writeheader()
        writer.writerows(rows)
    os.replace(path + ".tmp", path)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--patlab", default=os.path.join(ROOT, "build", "patlab"))
    parser.add_argument("--seeds", default="1-12", help="rendered cameras, FIRST-LAST")
    parser.add_argument("--out", default=os.path.join(ROOT, "results", "setup"))
    args = parser.parse_args()
    patlab_bin = os.path.abspath(args.patlab)
    for frame_name, _, _ in REAL.values():
        if not os.path.exists(os.path.join(FRAMES, frame_name)):
            sys.exit("setup_holdout: %s not found; expected the shared frames at %s"
                     % (frame_name, FRAMES))
    work = tempfile.mkdtemp(prefix="setup_holdout.")
    log = os.path.join(work, "log.txt")
    rendered = {}
    for seed in setup_rendered.parse_seeds(args.seeds):
        row, frame, truth = setup_rendered.render_frame(patlab_bin, seed, work, log)
        if frame is None:
            sys.exit("setup_holdout: seed %d did not render (log: %s)" % (seed, log))
        rendered["seed%d" % seed] = (frame, truth, row["model"])
    cameras = list(REAL) + list(rendered)
    grid = {}
    for point in grid_points():
        for name in REAL:
            grid[name, point] = run_real(patlab_bin, name, point, work, log)
        for name, (frame, truth, model) in rendered.items():
            outcome, _ = setup_rendered.setup_and_score(
                patlab_bin, frame, truth, model, os.path.join(work, "%s-%g-%g" % (name, *point)),
                log, setup_flags=colour_flags(point))
            grid[name, point] = (outcome["right"], outcome["false_ids"], len(truth))
        print("standout_delta_e %g, segment_k %g: %s" % (point[0], point[1], ", ".join(
            "%s %d/%d%s" % (c, grid[c, point][0], grid[c, point][2],
                            " (%d false)" % grid[c, point][1] if grid[c, point][1] else "")
            for c in cameras)), flush=True)
    os.makedirs(args.out, exist_ok=True)
    write_csv(os.path.join(args.out, "holdout_grid.csv"), [
        {"camera": c, "standout_delta_e": p[0], "segment_k": p[1], "right": grid[c, p][0],
         "false_ids": grid[c, p][1], "robots": grid[c, p][2]}
        for p in grid_points() for c in cameras])
    rows = []
    for c in cameras:
        chosen = choose(grid, cameras, c)
        rights = [grid[c, p][0] for p in chosen]
        falses = [grid[c, p][1] for p in chosen]
        rows.append({"camera": c, "robots": grid[c, DEFAULT][2],
                     "points_chosen": " ".join("%g/%g" % p for p in chosen),
                     "right_mean": round(sum(rights) / len(rights), 2), "right_worst": min(rights),
                     "false_ids_mean": round(sum(falses) / len(falses), 2),
                     "false_ids_worst": max(falses),
                     "right_with_defaults": grid[c, DEFAULT][0],
                     "false_ids_with_defaults": grid[c, DEFAULT][1]})
    path = os.path.join(args.out, "holdout.csv")
    write_csv(path, rows)
    print("\n| camera held out | points chosen on the others (of %d) | right / shown: mean, worst "
          "| false IDs: mean, worst | with the defaults |" % len(grid_points()))
    print("|---|---|---|---|---|")
    for r in rows:
        print("| %s | %d | %.2f, %d / %d | %.2f, %d | %d / %d, %d false |" % (
            r["camera"], len(r["points_chosen"].split()), r["right_mean"], r["right_worst"],
            r["robots"], r["false_ids_mean"], r["false_ids_worst"], r["right_with_defaults"],
            r["robots"], r["false_ids_with_defaults"]))
    right = sum(r["right_mean"] for r in rows)
    worst = sum(r["right_worst"] for r in rows)
    shown = sum(r["robots"] for r in rows)
    false = sum(r["false_ids_mean"] for r in rows)
    print("held out: %.1f/%d robots right on average (%.1f%%; worst %d), %.1f false IDs; wrote %s"
          % (right, shown, 100.0 * right / max(shown, 1), worst, false, os.path.relpath(path)))
    subprocess.run(["rm", "-rf", work])
    return 0


if __name__ == "__main__":
    sys.exit(main())
