#!/usr/bin/python3
"""Frames -> tracks -> section-II analysis, end to end, against known truth.

usage: /usr/bin/python3 scripts/analyze_chain.py [PATLAB [OUT_DIR [FRAMES]]]
       (defaults: build/patlab, results/analyze, 300)

1. Writes FRAMES scene files: three SSL robots of tests/data/golden (same camera, colours,
   thresholds, detector settings) driving straight lines at 7 mm/frame (210 mm/s at 30 Hz) while
   turning at 0.01 rad/frame, so their headings cross +-pi. Each frame has its own sensor-noise
   seed and its own camera jitter: the frame is rendered through the golden calibration with the
   camera translated by N(0, 1 mm) in x and y (about 0.2 px), while detection maps pixels back
   with the unjittered calibration, as a shaking camera would be seen.
2. `patlab render` each frame (PNG) and writes the true poses as a track CSV (truth.csv).
3. `patlab detect FRAMES... --out DIR --track`, which writes DIR/track.csv (the frame's position in
   the list is its index).
4. `patlab analyze track.csv --truth truth.csv --correct-bias --out OUT_DIR --name chain`:
   the paper's estimate (sample minus the sigma = 10 smoothed track) beside the true error
   (detected minus true pose) per robot and axis, each with its 95% interval.
5. Writes OUT_DIR/chain_check.csv: per robot and axis, whether the estimate's interval and the
   true std's interval overlap, and the ratio estimate / true; prints it.
Frames and scene files go to a temporary directory that is removed afterwards.
"""
import csv
import math
import os
import shutil
import subprocess
import sys
import tempfile

import numpy as np

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), ".."))
GOLDEN = os.path.join(ROOT, "tests", "data", "golden")
# (team, id, start x, start y, heading at frame 0, direction of travel in rad)
ROBOTS = [("blue", 3, -1050.0, 600.0, 2.0, 0.05),
          ("yellow", 5, -1050.0, -100.0, -1.0, -0.03),
          ("blue", 12, 1050.0, -650.0, 0.5, math.pi)]
SPEED_MM = 7.0
TURN_RAD = 0.01
JITTER_MM = 1.0


def pose(robot, frame):
    _, _, x0, y0, h0, travel = robot
    x = x0 + SPEED_MM * frame * math.cos(travel)
    y = y0 + SPEED_MM * frame * math.sin(travel)
    theta = math.remainder(h0 + TURN_RAD * frame, 2 * math.pi)
    return x, y, theta


def calibration_text(dx, dy):
    """The golden calibration with the camera's world->camera translation shifted by (dx, dy)."""
    out = []
    with open(os.path.join(GOLDEN, "ssl-frame.calibration.toml")) as f:
        for line in f:
            if line.startswith("translation_mm"):
                t = [float(v) for v in line.split("[")[1].split("]")[0].split(",")]
                line = f"translation_mm = [{t[0] + dx:.6f}, {t[1] + dy:.6f}, {t[2]:.6f}]\n"
            out.append(line)
    return "".join(out)


def scene_text(frame, calibration):
    head = []
    with open(os.path.join(GOLDEN, "ssl-frame.toml")) as f:
        for line in f:
            if line.startswith("[[robot]]") or line.startswith("[ball]"):
                break
            if line.startswith("calibration ="):
                line = f'calibration = "{calibration}"\n'
            elif line.startswith("pattern =") or line.startswith("codebook ="):
                key, value = line.split("=", 1)
                path = os.path.normpath(os.path.join(GOLDEN, value.strip().strip('"')))
                line = f'{key.strip()} = "{path}"\n'
            elif line.startswith("seed ="):
                line = f"seed = {1000 + frame}\n"
            head.append(line)
    for robot in ROBOTS:
        x, y, theta = pose(robot, frame)
        head.append(f'\n[[robot]]\nteam = "{robot[0]}"\nid = {robot[1]}\n'
                    f"x_mm = {x!r}\ny_mm = {y!r}\ntheta_rad = {theta!r}\n")
    return "".join(head)


def main():
    patlab = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else "build/patlab")
    out_dir = sys.argv[2] if len(sys.argv) > 2 else "results/analyze"
    frames = int(sys.argv[3]) if len(sys.argv) > 3 else 300
    rng = np.random.default_rng(2003)
    os.makedirs(out_dir, exist_ok=True)
    work = tempfile.mkdtemp(prefix="patlab-chain-")
    try:
        pngs = []
        truth = ["frame,subject,x_mm,y_mm,theta_rad"]
        for frame in range(frames):
            dx, dy = rng.normal(0.0, JITTER_MM, 2)
            cal = os.path.join(work, f"cal{frame:04d}.toml")
            with open(cal, "w") as f:
                f.write(calibration_text(dx, dy))
            scene = os.path.join(work, f"scene{frame:04d}.toml")
            with open(scene, "w") as f:
                f.write(scene_text(frame, cal))
            rendered = os.path.join(work, f"frame{frame:04d}")  # frame.png, truth.csv
            subprocess.run([patlab, "render", scene, "--out", rendered], check=True,
                           stdout=subprocess.DEVNULL)
            png = os.path.join(rendered, "frame.png")
            pngs.append(png)
            for robot in ROBOTS:
                x, y, theta = pose(robot, frame)
                truth.append(f"{frame},{robot[0]}-{robot[1]},{x!r},{y!r},{theta!r}")
        truth_csv = os.path.join(out_dir, "truth.csv")
        with open(truth_csv, "w") as f:
            f.write("\n".join(truth) + "\n")
        listing = os.path.join(work, "frames.txt")
        with open(listing, "w") as f:
            f.write("\n".join(pngs) + "\n")
        track_csv = os.path.join(out_dir, "track.csv")
        subprocess.run([patlab, "detect", listing,
                        "--thresholds", os.path.join(GOLDEN, "ssl-frame.thresholds.toml"),
                        "--calibration", os.path.join(GOLDEN, "ssl-frame.calibration.toml"),
                        "--settings", os.path.join(GOLDEN, "ssl-frame.detector.toml"),
                        "--out", work, "--track"], check=True)
        shutil.copyfile(os.path.join(work, "track.csv"), track_csv)
        subprocess.run([patlab, "analyze", track_csv, "--truth", truth_csv, "--correct-bias",
                        "--out", out_dir, "--name", "chain", "-q"], check=True)
    finally:
        shutil.rmtree(work)
    check(out_dir)


def check(out_dir):
    rows = list(csv.DictReader(open(os.path.join(out_dir, "chain.csv"))))
    lines = ["subject,axis,n,est_std,est_lo,est_hi,true_std,true_lo,true_hi,est_over_true,overlap"]
    for r in rows:
        for axis, est, tru in (("x", "sx_mm", "true_sx_mm"), ("y", "sy_mm", "true_sy_mm"),
                               ("theta", "stheta_rad", "true_stheta_rad")):
            e = [float(r[est]), float(r[est.replace("_mm", "").replace("_rad", "") + "_lo"]),
                 float(r[est.replace("_mm", "").replace("_rad", "") + "_hi"])]
            t = [float(r[tru]), float(r[tru.replace("_mm", "").replace("_rad", "") + "_lo"]),
                 float(r[tru.replace("_mm", "").replace("_rad", "") + "_hi"])]
            overlap = e[1] <= t[2] and t[1] <= e[2]
            lines.append(f"{r['subject']},{axis},{r['n']},{e[0]:.6g},{e[1]:.6g},{e[2]:.6g},"
                         f"{t[0]:.6g},{t[1]:.6g},{t[2]:.6g},{e[0] / t[0]:.3f},"
                         f"{'yes' if overlap else 'no'}")
    with open(os.path.join(out_dir, "chain_check.csv"), "w") as f:
        f.write("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
