#!/usr/bin/env python3
"""Scores `patlab setup` on rendered views that see one corner of a defence area and nothing
else of the field's lines: the lines match too few marks, and the robots' patterns place the
field (docs/setup.md, "When the lines alone do not fix the camera").

Each view i draws, as scripts/setup_rendered.py does (its camera noise, lighting and robots), a
model with rectangular defence areas, one of its four defence-area corners, and a camera 3-5 m
up looking nearly straight down at a point a few hundred mm from that corner into the field,
its focal length chosen so that the frame spans about 2.4 m of floor. Then

    patlab setup FRAME --field ssl --settings ssl-frame.detector -o CAM [--camera-height MM]
    patlab detect FRAME --setup CAM

and the robots are scored against the truth (scripts/setup_rendered.py's score).

Usage: scripts/setup_few_lines.py [--patlab build/patlab] [--views 1-8] [--measured-height]
                                  [--keep DIR]
  --measured-height: pass the camera's true height as --camera-height.
  --keep DIR: keep the scenes, frames, setup folders and the log in DIR.
"""
import argparse
import csv
import math
import os
import re
import sys
import tempfile

import numpy as np
from scipy.spatial.transform import Rotation

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import setup_rendered as rendered  # noqa: E402

MODELS = ["ssl-2018", "ssl-2019-div-b", "ssl-div-a", "ssl-div-b"]
SPAN_MM = 2400.0


def defence_corner(model, rng):
    """One of the model's defence-area corners (x, y) and the direction into the field."""
    lines = {}
    name = None
    with open(os.path.join(rendered.ROOT, "experiments", "fields", model + ".toml")) as f:
        for line in f:
            key = line.split("=")[0].strip()
            if key == "name":
                name = line.split("=")[1].strip().strip('"')
            elif key == "from_mm" and name:
                lines[name] = [float(v) for v in line.split("[")[1].split("]")[0].split(",")]
    front_x = lines["defense_front_pos"][0]
    half = abs(lines["defense_left_pos"][1])
    sx, sy = rng.choice([-1.0, 1.0]), rng.choice([-1.0, 1.0])
    return np.array([sx * front_x, sy * half]), np.array([-sx, sy])


def draw_camera(rng, corner, inward):
    height = rng.uniform(3000.0, 5000.0)
    f = rendered.WIDTH * height / SPAN_MM
    offset = inward * rng.uniform(200.0, 500.0, 2)
    centre = np.array([corner[0] + offset[0], corner[1] + offset[1], height])
    down = Rotation.from_rotvec([math.pi, 0.0, 0.0])
    heading = Rotation.from_rotvec([0.0, 0.0, rng.uniform(0.0, 2.0 * math.pi)])
    tilt = Rotation.from_rotvec(np.radians(rng.normal(0.0, 1.0, 3)))
    return {"fx": f, "fy": f, "cx": rendered.WIDTH / 2 + rng.normal(0, 4),
            "cy": rendered.HEIGHT / 2 + rng.normal(0, 4), "k1": -rng.uniform(0.0, 0.05),
            "rotation": tilt * down * heading, "centre": centre}


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--patlab", default=os.path.join(rendered.ROOT, "build", "patlab"))
    parser.add_argument("--views", default="1-8", help="FIRST-LAST or one view, default 1-8")
    parser.add_argument("--measured-height", action="store_true")
    parser.add_argument("--keep", help="keep the scenes, frames and logs in this folder")
    args = parser.parse_args()
    views = rendered.parse_seeds(args.views)
    patlab = os.path.abspath(args.patlab)
    kept = right = total = 0
    with tempfile.TemporaryDirectory(prefix="setup_few_lines.") as scratch:
        work = args.keep or scratch
        os.makedirs(work, exist_ok=True)
        log = os.path.join(work, "log.txt")
        open(log, "a").close()
        for view in views:
            rng = np.random.default_rng(1000 + view)
            model = MODELS[int(rng.integers(len(MODELS)))]
            length, width = rendered.field_size(model)
            corner, inward = defence_corner(model, rng)
            cam = draw_camera(rng, corner, inward)
            robots = rendered.draw_robots(rng, cam, length, width)
            _, colours = rendered.draw_colours(rng)
            folder = os.path.join(work, "view%d" % view)
            os.makedirs(folder, exist_ok=True)
            rendered.write_scene(folder, model, cam, robots, colours, view)
            rendered.run([patlab, "render", os.path.join(folder, "scene.toml"), "--camera",
                          "--sensor-seed", str(view), "-o", os.path.join(folder, "r")], log)
            frame = os.path.join(folder, "r", "frame.png")
            truth = [(r["team"], int(r["id"]), float(r["x_mm"]), float(r["y_mm"]))
                     for r in csv.DictReader(open(os.path.join(folder, "r", "truth.csv")))]
            flags = ["--camera-height", "%.0f" % cam["centre"][2]] if args.measured_height else []
            start = os.path.getsize(log)
            row, cpu = rendered.setup_and_score(patlab, frame, truth, model,
                                                os.path.join(folder, "cam"), log,
                                                setup_flags=flags)
            with open(log) as f:
                f.seek(start)
                text = f.read()
            stated = re.search(r"position is known to \+- ([\d.]+) mm", text)
            refused = re.search(r"patlab setup: (.*)", text)
            total += len(truth)
            head = "view %d: %s, %.2f m up, %d robots: " % (view, model, cam["centre"][2] / 1000,
                                                           len(truth))
            if not row["outcome"].startswith("detected"):
                print(head + row["outcome"] + (" -- " + refused.group(1)[-200:] if refused else "")
                      + ", setup %.1f s CPU" % cpu)
                continue
            kept += 1
            right += row["right"]
            print(head + "%d right, %d false IDs, mean error %s mm, stated +- %s mm, setup %.1f s "
                  "CPU" % (row["right"], row["false_ids"], row["position_error_mm"],
                           stated.group(1) if stated else "-", cpu))
    print("kept %d / %d views, %d / %d robots right" % (kept, len(views), right, total))


if __name__ == "__main__":
    main()
