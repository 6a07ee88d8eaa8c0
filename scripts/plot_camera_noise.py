#!/usr/bin/python3
"""Camera-level noise through the colour camera: merges DIR/camera/*.csv (patlab camtrack, one
file per mechanism setting and colour scheme) into DIR/camera.csv, computes the error-share
breakdown DIR/camera_shares.csv, and draws DIR/camera_shares.png. Run by scripts/camera_noise.sh.

usage: /usr/bin/python3 scripts/plot_camera_noise.py [DIR]   (default: results/camera-noise)

Shares: for a group (white patches, key, ID dots, the pattern's position and angle) the variance
with one mechanism on alone minus the quantisation-only variance is that mechanism's added
variance; its share is that over the variance with everything on. Quantisation's share is the
quantisation-only variance over everything-on. Shares need not add to 1 (the mechanisms interact:
the sum's gap is reported as 'interaction'). A missing or malformed input ends the script with one
line on stderr and exit status 2 (scripts/plotinput.py)."""
import csv
import glob
import io
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import plotinput  # noqa: E402

WHAT = "a CSV of `patlab camtrack` (scripts/camera_noise.sh writes DIR/camera/LABEL-SCHEME.csv)"
NUMBERS = ["sx_mm", "sx_lo", "sx_hi", "sy_mm", "sy_lo", "sy_hi", "stheta_rad", "stheta_lo",
           "stheta_hi"]
# (name, scheme, group, quantity)
TARGETS = [("white patch", "white", "all", "pos"), ("blue key", "colour", "key", "pos"),
           ("pink/green dot", "colour", "id", "pos"), ("pattern position", "colour", "pose", "pos"),
           ("pattern angle", "colour", "pose", "theta")]
MECHANISMS = ["colour", "noise", "jitter"]
LABELS = ["quantisation", "colour", "noise", "jitter", "all-but-jitter", "all", "read8",
          "roll0.004"]


def read(directory):
    """Every row of DIR/camera/*.csv with its scheme (white or colour, from the file name)."""
    paths = sorted(glob.glob(os.path.join(directory, "camera", "*.csv")))
    if not paths:
        plotinput.fail(os.path.join(directory, "camera"),
                       "no camtrack CSV files; expected camera/LABEL-SCHEME.csv from "
                       "scripts/camera_noise.sh")
    rows, header = [], None
    for path in paths:
        table = plotinput.read_csv(path, WHAT, columns=["label", "group"] + NUMBERS,
                                   numbers=NUMBERS)
        if header is not None and table.columns != header:
            plotinput.fail(path, f"its columns differ from those of {paths[0]}")
        header = table.columns
        scheme = "white" if path.endswith("-white.csv") else "colour"
        for r in table.rows:
            r["scheme"] = scheme
            rows.append(r)
    return rows


def merged_csv(rows):
    fields = ["label", "scheme"] + [k for k in rows[0] if k not in ("label", "scheme")]
    out = io.StringIO()
    w = csv.DictWriter(out, fieldnames=fields, lineterminator="\n")
    w.writeheader()
    w.writerows(rows)
    return out.getvalue()


def get(rows, label, scheme, group):
    for r in rows:
        if r["label"] == label and r["scheme"] == scheme and r["group"] == group:
            return r
    return None


def pooled(r):
    sx, sy = float(r["sx_mm"]), float(r["sy_mm"])
    return math.sqrt((sx * sx + sy * sy) / 2)


def ci(r, key):
    return float(r[key + "_lo"]), float(r[key + "_hi"])


def value(rows, label, scheme, group, q):
    r = get(rows, label, scheme, group)
    if r is None:
        return float("nan")
    return pooled(r) if q == "pos" else float(r["stheta_rad"])


def shares(rows, directory):
    """The share rows; fails when a track the breakdown needs is missing."""
    for label in ["all", "quantisation"] + MECHANISMS:
        for _, scheme, group, _ in TARGETS:
            if get(rows, label, scheme, group) is None:
                plotinput.fail(os.path.join(directory, "camera"),
                               f"no row label={label}, group={group} in {label}-{scheme}.csv; "
                               "expected every track of scripts/camera_noise.sh")
    share_rows = []
    for name, scheme, group, q in TARGETS:
        total = value(rows, "all", scheme, group, q) ** 2
        quant = value(rows, "quantisation", scheme, group, q) ** 2
        row = {"target": name, "std_all": f"{math.sqrt(total):.4g}",
               "quantisation": f"{quant / total:.3f}"}
        added = quant
        for m in MECHANISMS:
            v = value(rows, m, scheme, group, q) ** 2 - quant
            row[m] = f"{v / total:.3f}"
            added += v
        row["interaction"] = f"{1 - added / total:.3f}"
        share_rows.append(row)
    out = io.StringIO()
    w = csv.DictWriter(out, fieldnames=list(share_rows[0]), lineterminator="\n")
    w.writeheader()
    w.writerows(share_rows)
    return out.getvalue()


def position_panel(ax, rows):
    width = 0.2
    for k, (name, scheme, group, _) in enumerate(TARGETS[:4]):
        xs, ys, lo, hi = [], [], [], []
        for i, label in enumerate(LABELS):
            r = get(rows, label, scheme, group)
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
    ax.text(len(LABELS) - 0.5, 0.51, "Table I white ~0.5 mm", ha="right", fontsize=8,
            color="grey")
    ax.axhline(0.360, color="black", ls=":", lw=1)
    ax.text(len(LABELS) - 0.5, 0.37, "paper Butterfly 0.36 mm", ha="right", fontsize=8)
    ax.set_xticks(range(len(LABELS)), LABELS, rotation=30, ha="right")
    ax.set_ylabel("std per axis (mm), 95% CI")
    ax.set_title("Patch and pattern position error by camera mechanism")
    ax.legend(fontsize=8)


def angle_panel(ax, rows):
    xs, ys, lo, hi = [], [], [], []
    for i, label in enumerate(LABELS):
        r = get(rows, label, "colour", "pose")
        if r is None:
            continue
        v = float(r["stheta_rad"]) * 1e3
        xs.append(i)
        ys.append(v)
        lo.append(v - float(r["stheta_lo"]) * 1e3)
        hi.append(float(r["stheta_hi"]) * 1e3 - v)
    ax.bar(xs, ys, 0.6, yerr=[lo, hi], capsize=3, color="tab:purple")
    ax.axhline(7.0, color="black", ls=":", lw=1)
    ax.text(len(LABELS) - 0.5, 7.1, "paper Butterfly 7.0 mrad", ha="right", fontsize=8)
    ax.set_xticks(range(len(LABELS)), LABELS, rotation=30, ha="right")
    ax.set_ylabel("pattern angle std (mrad), 95% CI")
    ax.set_title("Coloured SSL pattern: angle error")


def main(argv):
    if len(argv) > 2:
        plotinput.usage("[DIR]")
    directory = argv[1] if len(argv) > 1 else "results/camera-noise"
    rows = read(directory)
    share_text = shares(rows, directory)
    plotinput.write_text(os.path.join(directory, "camera.csv"), merged_csv(rows))
    plotinput.write_text(os.path.join(directory, "camera_shares.csv"), share_text)
    fig, axes = plt.subplots(1, 2, figsize=(12, 4.8))
    position_panel(axes[0], rows)
    angle_panel(axes[1], rows)
    fig.tight_layout()
    plotinput.save(fig, os.path.join(directory, "camera_shares.png"), dpi=120)
    print(share_text, end="")


if __name__ == "__main__":
    main(sys.argv)
