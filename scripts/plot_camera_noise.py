#!/usr/bin/env python3
"""Camera-level noise through the colour camera: merges results/camera-noise/camera/*.csv (patlab
camtrack, one file per mechanism setting and colour scheme) into results/camera-noise/camera.csv,
computes the error-share breakdown results/camera-noise/camera_shares.csv, and draws
results/camera-noise/camera_shares.png. Run by scripts/camera_noise.sh.

Shares: for a group (white patches, key, ID dots, the pattern's position and angle) the variance
with one mechanism on alone minus the quantisation-only variance is that mechanism's added
variance; its share is that over the variance with everything on. Quantisation's share is the
quantisation-only variance over everything-on. Shares need not add to 1 (the mechanisms interact:
the sum's gap is reported as 'interaction')."""
import csv
import glob
import math
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

root = "results/camera-noise"
rows = []
for path in sorted(glob.glob(os.path.join(root, "camera", "*.csv"))):
    scheme = "white" if path.endswith("-white.csv") else "colour"
    with open(path) as f:
        for r in csv.DictReader(f):
            r["scheme"] = scheme
            rows.append(r)
fields = ["label", "scheme"] + [k for k in rows[0] if k not in ("label", "scheme")]
with open(os.path.join(root, "camera.csv"), "w", newline="") as f:
    w = csv.DictWriter(f, fieldnames=fields, lineterminator="\n")
    w.writeheader()
    w.writerows(rows)


def get(label, scheme, group):
    for r in rows:
        if r["label"] == label and r["scheme"] == scheme and r["group"] == group:
            return r
    return None


def pooled(r):
    sx, sy = float(r["sx_mm"]), float(r["sy_mm"])
    return math.sqrt((sx * sx + sy * sy) / 2)


def ci(r, key):
    return float(r[key + "_lo"]), float(r[key + "_hi"])


# (name, scheme, group, quantity)
targets = [("white patch", "white", "all", "pos"), ("blue key", "colour", "key", "pos"),
           ("pink/green dot", "colour", "id", "pos"), ("pattern position", "colour", "pose", "pos"),
           ("pattern angle", "colour", "pose", "theta")]
mechs = ["colour", "noise", "jitter"]


def value(label, scheme, group, q):
    r = get(label, scheme, group)
    if r is None:
        return float("nan")
    return pooled(r) if q == "pos" else float(r["stheta_rad"])


share_rows = []
for name, scheme, group, q in targets:
    total = value("all", scheme, group, q) ** 2
    quant = value("quantisation", scheme, group, q) ** 2
    row = {"target": name, "std_all": f"{math.sqrt(total):.4g}",
           "quantisation": f"{quant / total:.3f}"}
    added = quant
    for m in mechs:
        v = value(m, scheme, group, q) ** 2 - quant
        row[m] = f"{v / total:.3f}"
        added += v
    row["interaction"] = f"{1 - added / total:.3f}"
    share_rows.append(row)
with open(os.path.join(root, "camera_shares.csv"), "w", newline="") as f:
    w = csv.DictWriter(f, fieldnames=list(share_rows[0]), lineterminator="\n")
    w.writeheader()
    w.writerows(share_rows)

labels = ["quantisation", "colour", "noise", "jitter", "all-but-jitter", "all", "read8",
          "roll0.004"]
fig, axes = plt.subplots(1, 2, figsize=(12, 4.8))
ax = axes[0]
width = 0.2
for k, (name, scheme, group, q) in enumerate(targets[:4]):
    xs, ys, lo, hi = [], [], [], []
    for i, label in enumerate(labels):
        r = get(label, scheme, group)
        if r is None:
            continue
        v = pooled(r)
        # the pooled std's interval from the two axes' intervals (conservative: the wider side)
        lx, hx = ci(r, "sx")
        ly, hy = ci(r, "sy")
        xs.append(i + (k - 1.5) * width)
        ys.append(v)
        lo.append(v - math.sqrt((lx * lx + ly * ly) / 2))
        hi.append(math.sqrt((hx * hx + hy * hy) / 2) - v)
    ax.bar(xs, ys, width, yerr=[lo, hi], capsize=2, label=name)
ax.axhline(0.5, color="grey", ls="--", lw=1)
ax.text(len(labels) - 0.5, 0.51, "Table I white ~0.5 mm", ha="right", fontsize=8, color="grey")
ax.axhline(0.360, color="black", ls=":", lw=1)
ax.text(len(labels) - 0.5, 0.37, "paper Butterfly 0.36 mm", ha="right", fontsize=8)
ax.set_xticks(range(len(labels)), labels, rotation=30, ha="right")
ax.set_ylabel("std per axis (mm), 95% CI")
ax.set_title("Patch and pattern position error by camera mechanism")
ax.legend(fontsize=8)
ax = axes[1]
ys, lo, hi = [], [], []
for label in labels:
    r = get(label, "colour", "pose")
    v = float(r["stheta_rad"]) * 1e3
    ys.append(v)
    lo.append(v - float(r["stheta_lo"]) * 1e3)
    hi.append(float(r["stheta_hi"]) * 1e3 - v)
ax.bar(range(len(labels)), ys, 0.6, yerr=[lo, hi], capsize=3, color="tab:purple")
ax.axhline(7.0, color="black", ls=":", lw=1)
ax.text(len(labels) - 0.5, 7.1, "paper Butterfly 7.0 mrad", ha="right", fontsize=8)
ax.set_xticks(range(len(labels)), labels, rotation=30, ha="right")
ax.set_ylabel("pattern angle std (mrad), 95% CI")
ax.set_title("Coloured SSL pattern: angle error")
fig.tight_layout()
fig.savefig(os.path.join(root, "camera_shares.png"), dpi=120)
print(open(os.path.join(root, "camera_shares.csv")).read())
