#!/usr/bin/env python3
"""Scores `patlab setup` + `patlab detect --setup` on rendered frames of random cameras.

Each seed draws a scene nobody tuned anything on: an SSL field model of the `ssl` family, a
camera 3-5 m up over a random point of it (random heading, a few degrees of tilt, focal length,
principal point and barrel distortion short of folding inside the frame), random lighting (the
scene's colours scaled by a brightness and a white balance, the carpet's shade), 6-10 robots in
the SSL standard pattern with random teams, IDs, positions and headings where the camera sees
them, a ball, and the colour camera of `patlab render --camera` (exposure, Bayer sensor noise,
demosaicing, YUV 4:2:2). Then, with nothing but the frame and the shipped settings
`ssl-frame.detector`:

    patlab setup FRAME --field ssl --settings ssl-frame.detector -o CAM
    patlab detect FRAME --setup CAM

and each frame is scored against the render's truth: robots found with the right team and ID
within 100 mm, false IDs (a team + ID the frame does not show there), and the position error of
the robots found. The field's half-turn symmetry gives two equally valid world frames (setup
picks one and says so): each frame is scored in the one that matches its truth.

Usage: scripts/setup_rendered.py [--patlab build/patlab] [--seeds 1-12] [--out results/setup]
                                  [--keep DIR] [--named-model] [--scale S]
  --named-model: pass the frame's own field model as `--field MODEL` instead of the family, as a
  team that knows the field it plays on would.
  --scale S: the same scenes seen by a camera of S times the resolution (780 S x 580 S px: the
  focal lengths and principal point scaled, the view the same), which setup bins back.
Writes OUT/rendered.csv (one row per frame: the scene drawn, the outcome, setup's held-out
mapping error and the true one -- where setup's camera and the true camera put the floor that
every 10th pixel shows inside the field's lines, RMS in mm -- and the camera setup wrote: its
centre's height over the floor, its focal length and what decided the height: the lines, the
robots, or neither) and prints the table docs/setup.md quotes.
"""
import argparse
import csv
import math
import os
import resource
import re
import subprocess
import sys
import tempfile
import tomllib

import numpy as np
from scipy.spatial.transform import Rotation

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
WIDTH, HEIGHT = 780, 580
ROBOT_TOP_MM = 140.0
BASE_COLOURS = {  # settings/ssl-half-field.toml's colours
    "field": (40, 100, 50), "body": (30, 30, 34), "blue": (35, 75, 210),
    "yellow": (235, 215, 45), "pink": (240, 95, 185), "green": (70, 215, 95),
    "orange": (250, 125, 25)}
MODELS = ["ssl-2008", "ssl-2009", "ssl-2012", "ssl-2014", "ssl-2015", "ssl-2018",
          "ssl-2019-div-b", "ssl-div-a", "ssl-div-b"]
MATCH_MM = 100.0
SCALE = 1.0  # --scale: the rendered frames' resolution over WIDTH x HEIGHT


def field_size(model):
    """(length, width) in mm from the model's file."""
    size = {}
    with open(os.path.join(ROOT, "experiments", "fields", model + ".toml")) as f:
        for line in f:
            key = line.split("=")[0].strip()
            if key in ("length_mm", "width_mm"):
                size[key] = float(line.split("=")[1].split("#")[0])
    return size["length_mm"], size["width_mm"]


def draw_camera(rng, length, width):
    """A downward camera over a random point of the field; returns its calibration values."""
    f = rng.uniform(480.0, 640.0)
    corner = math.hypot(WIDTH / 2, HEIGHT / 2) / f
    # r (1 + k1 r^2) stops growing at r^2 = 1 / (3 |k1|), where it is (2/3) / sqrt(3 |k1|): keep
    # that fold at least 10% beyond the frame's corner.
    k1_fold = (2.0 / (3.0 * 1.1 * corner)) ** 2 / 3.0
    k1 = -rng.uniform(0.02, 0.8 * k1_fold)
    centre = np.array([rng.uniform(-0.4, 0.4) * length, rng.uniform(-0.4, 0.4) * width,
                       rng.uniform(3000.0, 5000.0)])
    down = Rotation.from_rotvec([math.pi, 0.0, 0.0])
    heading = Rotation.from_rotvec([0.0, 0.0, rng.uniform(0.0, 2.0 * math.pi)])
    tilt = Rotation.from_rotvec(np.radians(rng.normal(0.0, 2.0, 3)))
    rotation = tilt * down * heading  # world -> camera
    return {"fx": f, "fy": f, "cx": WIDTH / 2 + rng.normal(0, 8), "cy": HEIGHT / 2 + rng.normal(0, 8),
            "k1": k1, "rotation": rotation, "centre": centre}


def floor_point(cam, u, v, z):
    """The point at height z seen at undistorted pixel (u, v)."""
    ray = np.array([(u - cam["cx"]) / cam["fx"], (v - cam["cy"]) / cam["fy"], 1.0])
    ray = cam["rotation"].inv().apply(ray)
    s = (z - cam["centre"][2]) / ray[2]
    return cam["centre"] + s * ray


def draw_robots(rng, cam, length, width):
    """6-10 robots where the camera sees them, inside the field lines, 300 mm apart."""
    count = int(rng.integers(6, 11))
    robots = []
    for _ in range(400):
        if len(robots) == count:
            break
        # Barrel distortion pulls every point towards the centre: an undistorted pixel in the
        # inner 80% of the frame is inside it.
        p = floor_point(cam, rng.uniform(0.1, 0.9) * WIDTH, rng.uniform(0.1, 0.9) * HEIGHT,
                        ROBOT_TOP_MM)
        if abs(p[0]) > length / 2 - 100 or abs(p[1]) > width / 2 - 100:
            continue
        if any(math.hypot(p[0] - r[1], p[1] - r[2]) < 300 for r in robots):
            continue
        robots.append((None, p[0], p[1], rng.uniform(-math.pi, math.pi)))
    teams = ["blue", "yellow"]
    ids = {t: list(rng.permutation(16)) for t in teams}
    out = []
    for i, (_, x, y, theta) in enumerate(robots):
        team = teams[i % 2]
        out.append((team, int(ids[team].pop()), x, y, theta))
    return out


def draw_colours(rng):
    """Lighting: brightness, white balance and the carpet's shade."""
    brightness = rng.uniform(0.75, 1.2)
    balance = rng.uniform(0.9, 1.1, 3)
    colours = {}
    for name, rgb in BASE_COLOURS.items():
        scale = brightness * balance * (rng.uniform(0.8, 1.25) if name == "field" else 1.0)
        colours[name] = [int(min(255, max(0, round(c * s)))) for c, s in zip(rgb, scale)]
    return brightness, colours


def write_scene(folder, model, cam, robots, colours, seed):
    rotvec = cam["rotation"].as_rotvec()
    translation = -cam["rotation"].apply(cam["centre"])
    # At --scale S the frame's pixel p sees what the drawn camera's (p + 0.5) / S - 0.5 sees.
    with open(os.path.join(folder, "camera.toml"), "w") as f:
        f.write('model = "pinhole"\nimage_size_px = [%d, %d]\n\n[pinhole]\n'
                % (round(WIDTH * SCALE), round(HEIGHT * SCALE)))
        f.write("fx_px = %.6f\nfy_px = %.6f\ncx_px = %.6f\ncy_px = %.6f\nk1 = %.6f\nk2 = 0.0\n"
                % (SCALE * cam["fx"], SCALE * cam["fy"], SCALE * (cam["cx"] + 0.5) - 0.5,
                   SCALE * (cam["cy"] + 0.5) - 0.5, cam["k1"]))
        f.write("rotation_rodrigues = [%.9f, %.9f, %.9f]\n" % tuple(rotvec))
        f.write("translation_mm = [%.6f, %.6f, %.6f]\n\n" % tuple(translation))
        f.write("[heights]\ndefault_mm = %.1f\norange = 21.5\n" % ROBOT_TOP_MM)
    with open(os.path.join(folder, "scene.toml"), "w") as f:
        f.write('calibration = "camera.toml"\n')
        f.write('field = "%s"\n' % os.path.join(ROOT, "experiments", "fields", model + ".toml"))
        f.write('pattern = "%s"\n' % os.path.join(ROOT, "patterns", "ssl-standard.toml"))
        f.write('codebook = "%s"\n\n' % os.path.join(ROOT, "patterns", "ssl-standard.codebook.toml"))
        f.write("[render]\nrobot_height_mm = %.1f\nseed = %d\n\n[colours]\n" % (ROBOT_TOP_MM, seed))
        for name, rgb in colours.items():
            f.write("%s = [%d, %d, %d]\n" % (name, *rgb))
        for team, rid, x, y, theta in robots:
            f.write('\n[[robot]]\nteam = "%s"\nid = %d\nx_mm = %.1f\ny_mm = %.1f\ntheta_rad = %.4f\n'
                    % (team, rid, x, y, theta))


def read_pinhole(path):
    """A calibration file's [pinhole] table, or None when it is missing or unreadable."""
    try:
        with open(path, "rb") as f:
            return tomllib.load(f)["pinhole"]
    except (OSError, KeyError, tomllib.TOMLDecodeError):
        return None


def floor_points(pinhole, pixels):
    """The floor (z = 0) points in mm that `pixels` (N x 2) see through a calibration's
    [pinhole] table, as src/patlab/camera/camera.cpp's PixelToWorld maps them (the radial
    distortion undone by Newton's method); NaN where a pixel does not reach the floor."""
    k1, k2 = pinhole.get("k1", 0.0), pinhole.get("k2", 0.0)
    xd = (pixels[:, 0] - pinhole["cx_px"]) / pinhole["fx_px"]
    yd = (pixels[:, 1] - pinhole["cy_px"]) / pinhole["fy_px"]
    rd = np.hypot(xd, yd)
    r = rd.copy()
    with np.errstate(invalid="ignore", divide="ignore"):
        for _ in range(20):
            r2 = r * r
            slope = 1.0 + 3.0 * k1 * r2 + 5.0 * k2 * r2 * r2
            r = r - (r * (1.0 + k1 * r2 + k2 * r2 * r2) - rd) / slope
        r2 = r * r
        valid = (r >= 0.0) & (1.0 + 3.0 * k1 * r2 + 5.0 * k2 * r2 * r2 > 0.0)
        scale = np.where(rd > 0.0, r / np.where(rd > 0.0, rd, 1.0), 1.0)
        rotation = Rotation.from_rotvec(pinhole["rotation_rodrigues"]).as_matrix()
        centre = -rotation.T @ np.array(pinhole["translation_mm"], dtype=float)
        rays = np.stack([xd * scale, yd * scale, np.ones_like(xd)], axis=1) @ rotation
        s = -centre[2] / rays[:, 2]
    valid &= np.isfinite(s) & (s > 0.0)
    points = centre[:2] + s[:, None] * rays[:, :2]
    points[~valid] = np.nan
    return points


def true_mapping_error(scene_dir, cam_dir, model):
    """The RMS distance in mm between where the true camera and setup's camera put the floor
    seen at every 10th pixel that shows the field (inside its lines), in the better of the two
    world frames (the field's half turn); inf where setup's camera misses part of it."""
    truth = read_pinhole(os.path.join(scene_dir, "camera.toml"))
    fitted = read_pinhole(os.path.join(cam_dir, "calibration.toml"))
    if truth is None or fitted is None:
        return ""
    u, v = np.meshgrid(np.arange(5, WIDTH, 10), np.arange(5, HEIGHT, 10))
    u, v = SCALE * (u + 0.5) - 0.5, SCALE * (v + 0.5) - 0.5  # the same floor at any --scale
    pixels = np.stack([u.ravel(), v.ravel()], axis=1).astype(float)
    length, width = field_size(model)
    a = floor_points(truth, pixels)
    inside = (np.abs(a[:, 0]) <= length / 2) & (np.abs(a[:, 1]) <= width / 2)
    a, b = a[inside], floor_points(fitted, pixels)[inside]
    if not len(a) or np.isnan(b).any():
        return "inf"
    return round(min(float(np.sqrt(np.mean(np.sum((a - sign * b) ** 2, axis=1))))
                     for sign in (1.0, -1.0)), 2)


def mapping_error(line):
    """The held-out mapping error of setup's report line: "0.72", or "<0.29" when it is below
    the line finder's resolution."""
    words = line.split()
    return "<" + words[3] if words[2] == "below" else words[2]


def run(arguments, log):
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    done = subprocess.run(arguments, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    with open(log, "a") as f:
        f.write("$ " + " ".join(arguments) + "\n" + done.stdout + "\n")
    return done, after.ru_utime - before.ru_utime


def score(truth, detections):
    """(right, false IDs, mean position error mm) in the better of the two world frames."""
    best = None
    for sign in (1.0, -1.0):  # identity or the half turn about the centre mark
        right, errors = 0, []
        for team, rid, x, y in truth:
            near = [math.hypot(sign * d[2] - x, sign * d[3] - y) for d in detections
                    if d[0] == team and d[1] == rid]
            if near and min(near) <= MATCH_MM:
                right += 1
                errors.append(min(near))
        false = sum(1 for d in detections if d[1] >= 0 and not any(
            t[0] == d[0] and t[1] == d[1] and math.hypot(sign * d[2] - t[2], sign * d[3] - t[3])
            <= MATCH_MM for t in truth))
        key = (right - false, right)
        if best is None or key > best[0]:
            best = (key, right, false, float(np.mean(errors)) if errors else float("nan"))
    return best[1:]


def render_frame(patlab, seed, work, log):
    """Draws seed's scene and renders it: (the row's scene columns, the frame, the truth as
    (team, id, x_mm, y_mm)), or (row, None, None) when the render fails."""
    rng = np.random.default_rng(seed)
    model = MODELS[int(rng.integers(len(MODELS)))]
    length, width = field_size(model)
    cam = draw_camera(rng, length, width)
    robots = draw_robots(rng, cam, length, width)
    brightness, colours = draw_colours(rng)
    exposure = rng.uniform(0.8, 1.25)
    noise = rng.uniform(1.0, 4.0)
    folder = os.path.join(work, "seed%d" % seed)
    os.makedirs(folder)
    write_scene(folder, model, cam, robots, colours, seed)
    row = {"seed": seed, "model": model, "height_mm": round(cam["centre"][2]),
           "f_px": round(SCALE * cam["fx"], 1), "k1": round(cam["k1"], 3),
           "brightness": round(brightness, 3), "exposure_gain": round(exposure, 3),
           "read_noise_levels": round(noise, 2), "robots": len(robots)}
    rendered, _ = run([patlab, "render", os.path.join(folder, "scene.toml"), "--camera",
                       "--exposure-gain", "%.3f" % exposure, "--read-noise-levels", "%.2f" % noise,
                       "--sensor-seed", str(seed), "-o", os.path.join(folder, "r")], log)
    if rendered.returncode != 0:
        return row, None, None
    truth = [(r["team"], int(r["id"]), float(r["x_mm"]), float(r["y_mm"]))
             for r in csv.DictReader(open(os.path.join(folder, "r", "truth.csv")))]
    return row, os.path.join(folder, "r", "frame.png"), truth


def camera_height(cam_dir, report):
    """(height of the camera's centre over the floor in mm, focal length in px, what decided the
    height: lines, robots, given or undetermined) from the calibration setup wrote and its
    report's `camera height:` line."""
    pinhole = read_pinhole(os.path.join(cam_dir, "calibration.toml"))
    if pinhole is None:
        return "", "", ""
    rotation = Rotation.from_rotvec(pinhole["rotation_rodrigues"]).as_matrix()
    centre = -rotation.T @ np.array(pinhole["translation_mm"])
    line = next((line for line in report.splitlines() if line.startswith("camera height:")), "")
    decided = re.search(r"\(the (\w+) decide", line)
    by = ("undetermined" if "undetermined" in line.split(",")[0] else
          decided.group(1) if decided else "given" if "given" in line else "")
    return round(float(centre[2])), round(float(pinhole["fx_px"]), 1), by


def setup_and_score(patlab, frame, truth, model, cam_dir, log, *, setup_flags=(), field="ssl"):
    """setup (with the shipped settings, `field` -- the family or a model -- and any further
    flags) and detect on one rendered frame, scored against its truth: (the row's outcome
    columns, setup's CPU seconds)."""
    setup, cpu = run([patlab, "setup", frame, "--field", field, "--settings", "ssl-frame.detector",
                      "-o", cam_dir] + list(setup_flags), log)
    kept = next((line.split()[2] for line in setup.stdout.splitlines()
                 if line.startswith("field model:")), "")
    mapping = next((mapping_error(line) for line in setup.stdout.splitlines()
                    if line.startswith("mapping error:")), "")
    if setup.returncode != 0:
        return dict(outcome="setup refused (exit %d)" % setup.returncode, model_kept=kept,
                    right=0, false_ids=0, position_error_mm="", mapping_error_mm=mapping,
                    true_mapping_error_mm="", setup_height_mm="", setup_f_px="",
                    height_decided_by=""), cpu
    height, focal, decided_by = camera_height(cam_dir, setup.stdout)
    true_mapping = true_mapping_error(os.path.dirname(os.path.dirname(frame)), cam_dir, model)
    detect, _ = run([patlab, "detect", frame, "--setup", cam_dir], log)
    detections = [(r["team"], int(r["id"]), float(r["x_mm"]), float(r["y_mm"]))
                  for r in csv.DictReader(detect.stdout.splitlines()) if "team" in r]
    right, false, error = score(truth, detections)
    return dict(outcome="detected" if detect.returncode == 0 else "detect failed",
                model_kept=kept, right=right, false_ids=false,
                position_error_mm="" if math.isnan(error) else round(error, 1),
                mapping_error_mm=mapping, true_mapping_error_mm=true_mapping,
                setup_height_mm=height, setup_f_px=focal, height_decided_by=decided_by), cpu


def one_frame(patlab, seed, work, log, named_model=False):
    row, frame, truth = render_frame(patlab, seed, work, log)
    if frame is None:
        return dict(row, outcome="render failed", model_kept="", right=0, false_ids=0,
                    position_error_mm="", mapping_error_mm="", true_mapping_error_mm="",
                    setup_height_mm="", setup_f_px="", height_decided_by=""), 0.0
    outcome, cpu = setup_and_score(patlab, frame, truth, row["model"],
                                   os.path.join(work, "seed%d" % seed, "cam"), log,
                                   field=row["model"] if named_model else "ssl")
    return dict(row, **outcome), cpu


def parse_seeds(text):
    first, _, last = text.partition("-")
    return range(int(first), int(last or first) + 1)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--patlab", default=os.path.join(ROOT, "build", "patlab"))
    parser.add_argument("--seeds", default="1-12", help="FIRST-LAST, default 1-12")
    parser.add_argument("--out", default=os.path.join(ROOT, "results", "setup"))
    parser.add_argument("--keep", help="keep the scenes, frames and logs in this folder")
    parser.add_argument("--named-model", action="store_true",
                        help="pass the frame's field model as --field MODEL, not the family")
    parser.add_argument("--scale", type=float, default=1.0,
                        help="render at this many times 780 x 580 px (default 1)")
    args = parser.parse_args()
    global SCALE
    SCALE = args.scale
    work = args.keep or tempfile.mkdtemp(prefix="setup_rendered.")
    os.makedirs(work, exist_ok=True)
    log = os.path.join(work, "log.txt")
    rows = []
    for seed in parse_seeds(args.seeds):
        row, cpu = one_frame(os.path.abspath(args.patlab), seed, work, log, args.named_model)
        rows.append(row)
        print("seed %d: %s %s, kept %s, %d/%d right, %d false IDs, setup %.1f s CPU" % (
            seed, row["model"], row["outcome"], row["model_kept"] or "-", row["right"],
            row["robots"], row["false_ids"], cpu), flush=True)
    os.makedirs(args.out, exist_ok=True)
    path = os.path.join(args.out, "rendered.csv")
    with open(path + ".tmp", "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0].keys()), lineterminator="\n")
        writer.writeheader()
        writer.writerows(rows)
    os.replace(path + ".tmp", path)
    shown = sum(r["robots"] for r in rows)
    right = sum(r["right"] for r in rows)
    false = sum(r["false_ids"] for r in rows)
    print("total: %d/%d robots right (%.1f%%), %d false IDs over %d frames; wrote %s" % (
        right, shown, 100.0 * right / max(shown, 1), false, len(rows), os.path.relpath(path)))
    if not args.keep:
        subprocess.run(["rm", "-rf", work])
    return 0


if __name__ == "__main__":
    sys.exit(main())
